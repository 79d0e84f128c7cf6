"""Type stubs of the compiled module (python/src/lib.rs); use the wrappers in impact_beam."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np

_Scene = Union[str, os.PathLike[str], Mapping[str, Any]]

__version__: str
SWEEP_COLUMNS: List[str]
SUMMARY_COLUMNS: List[str]
ACCURACY_COLUMNS: List[str]

def simulate(
    scene: _Scene, field: bool = ..., progress: Optional[Callable[[float], Any]] = ...
) -> Tuple[str, Dict[str, np.ndarray], Optional[Dict[str, np.ndarray]]]: ...
def sweep(
    scene: _Scene,
    axes: Dict[str, Any],
    shard: Optional[str] = ...,
    progress: Optional[Callable[[int, int], Any]] = ...,
    journal: Optional[Union[str, os.PathLike[str]]] = ...,
) -> Dict[str, Any]: ...
def accuracy(
    scene: _Scene, quick: bool = ..., progress: Optional[Callable[[int, int], Any]] = ...
) -> Dict[str, Any]: ...
def compare(
    scene: _Scene,
    modes: List[int] = ...,
    elements: List[int] = ...,
    progress: Optional[Callable[[int, int], Any]] = ...,
) -> Dict[str, Any]: ...
