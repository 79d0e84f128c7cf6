"""impact_beam: a hard ball striking a flexible beam, from Python.

The same library as the command line (``cargo xtask simulate | sweep | accuracy | compare``),
compiled from this repository's Rust crates: every number here is the number the command line
prints. SI units throughout (s, m, N, Pa, J, kg), in the keys' names where they are columns
(``time_s``, ``force_n``).

A *scene* is a path to a TOML scene file (str or os.PathLike) or a dict with the file's tables
and keys (``{"beam": {...}, "ball": {...}, "impact": {...}, "contact": {...}, "solver": {...}}``;
see docs/scene.md in the repository). A scene the command line refuses raises ``ValueError`` with
its message, which names the key, the value and what is allowed.

>>> import impact_beam as ib
>>> run = ib.simulate("validation/scenes/paper-tip.toml")        # doctest: +SKIP
>>> run.report["contacts"][0]["peak_force"]                       # doctest: +SKIP
788.115...
>>> run.history["force_n"].max()                                   # doctest: +SKIP
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native

__all__ = [
    "__version__",
    "Simulation",
    "simulate",
    "sweep",
    "accuracy",
    "compare",
    "SWEEP_COLUMNS",
    "SUMMARY_COLUMNS",
    "ACCURACY_COLUMNS",
]

Scene = Union[str, "os.PathLike[str]", Mapping[str, Any]]


def _flag(name: str, value: Any) -> bool:
    """``value`` as a flag, or a TypeError naming the argument."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected True or False, got {value!r} ({type(value).__name__})")
    return bool(value)


def _callback(name: str, value: Any) -> Any:
    """``value`` if it can be called (or None), else a TypeError naming the argument."""
    if value is not None and not callable(value):
        raise TypeError(
            f"{name}: expected a function (called with the progress) or None, got {value!r} ({type(value).__name__})"
        )
    return value


def _counts(name: str, values: Any) -> List[int]:
    """``values`` as whole numbers >= 1, or an error naming the argument."""
    try:
        items = list(values)
    except TypeError:
        raise TypeError(f"{name}: expected a list of whole numbers, got {values!r}") from None
    out = []
    for v in items:
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise TypeError(f"{name}: expected whole numbers, got {v!r} ({type(v).__name__})")
        if v < 1:
            raise ValueError(f"{name}: {v} is not allowed: each must be at least 1")
        out.append(int(v))
    return out


def _shard(value: Any) -> Optional[str]:
    """``(k, n)`` or ``"k/n"`` as the native ``"k/n"``, or an error naming ``shard``."""
    if value is None:
        return None
    if isinstance(value, str):
        return value
    try:
        k, n = value
    except (TypeError, ValueError):
        raise TypeError(f"shard: expected (k, n) or \"k/n\", got {value!r}") from None
    for v in (k, n):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise TypeError(f"shard: expected whole numbers (k, n), got {value!r}")
    if not 1 <= k <= n:
        raise ValueError(f"shard: {tuple(value)!r} is not allowed: 1 <= k <= n")
    return f"{k}/{n}"

#: The report's scalars in a sweep's table, with their units in the names (as sweep.csv).
#: The version of the compiled crates (the workspace's; ``pip show impact-beam`` says the same).
__version__: str = _native.__version__

SWEEP_COLUMNS: List[str] = list(_native.SWEEP_COLUMNS)
#: The columns of a comparison's table (as compare's summary.csv).
SUMMARY_COLUMNS: List[str] = list(_native.SUMMARY_COLUMNS)
#: The numeric columns of the work-precision table (as work_precision.csv).
ACCURACY_COLUMNS: List[str] = list(_native.ACCURACY_COLUMNS)


# eq=False: fields of numpy arrays make a generated `==` raise ("the truth value of an array
# is ambiguous", a review's); two runs compare by identity, and hash by it.
@dataclass(frozen=True, repr=False, eq=False)
class Simulation:
    """One run of a scene.

    Attributes:
        report: the report, a dict equal to ``cargo xtask simulate SCENE --json``: the plan and
            the reasons for each choice, warnings, every contact (start, duration, peak force,
            impulse, print radius, contact pressure and stresses under the ball), restitution,
            largest displacement, bending stress, energy ledger, estimated error, wall time.
            SI units; ball velocities positive toward the beam.
        history: the run's history as 1-D float64 arrays keyed by the history CSV's columns
            (``simulate --history``): ``time_s``, ``force_n``, ``approach_m``,
            ``ball_position_m``, ``ball_velocity_m_s``, ``beam_displacement_m``,
            ``contact_point_m``, ``ball_energy_j``, ``beam_energy_j``, ``contact_energy_j``,
            ``dissipated_energy_j``.
        field: with ``field=True``, the beam along its length (``simulate --field``):
            ``time_s`` (n_t,), ``x_m`` (n_x,), and ``displacement_m``, ``slope_rad``,
            ``moment_n_m``, ``stress_pa`` as (n_t, n_x) arrays (stress on the struck face,
            tension positive); else None.
    """

    report: Dict[str, Any]
    history: Dict[str, np.ndarray]
    field: Optional[Dict[str, np.ndarray]] = None

    @property
    def first_contact(self) -> Optional[Dict[str, Any]]:
        """The first contact's entry of the report (None without a contact)."""
        contacts = self.report["contacts"]
        return contacts[0] if contacts else None

    def __repr__(self) -> str:
        # A notebook shows this: the headline numbers, not thousands of samples.
        r, plan = self.report, self.report["plan"]
        first = self.first_contact
        # A contact the window cut is marked as the command line marks it.
        contact = (
            f"first {first['duration'] * 1e6:.2f}{'' if first['complete'] else '+'} µs"
            f"{'' if first['complete'] else ' (not ended)'}, {first['peak_force']:.1f} N"
            if first
            else "no contact"
        )
        field = "none" if self.field is None else f"{len(self.field['time_s'])} x {len(self.field['x_m'])}"
        return (
            f"Simulation({r['name']!r}: {plan['method']}, {r['contact_count']} contact(s), {contact}; "
            f"max displacement {r['max_displacement'] * 1e3:.4f} mm; {len(r['warnings'])} warning(s); "
            f"history {len(self.history['time_s'])} samples; field {field})"
        )


def simulate(
    scene: Scene,
    *,
    field: bool = False,
    progress: Optional[Callable[[float], Any]] = None,
) -> Simulation:
    """Plan and run one scene.

    Args:
        scene: a path to a TOML scene file or a dict with its tables and keys.
        field: also record the beam along its length (displacement, slope, moment, stress).
        progress: called with the fraction of the simulated window done (0 to 1; with
            ``solver.tolerance`` from 0 again for every run of the refinement), at most a
            thousand times a run, on a worker thread with the GIL held; an exception it raises
            stops the run and is raised.

    Returns:
        The report, the history's arrays and (with ``field``) the field's.

    Raises:
        ValueError: the scene is refused (the message names the key, the value and what is
            allowed) or the file cannot be read.
        RuntimeError: the solver failed (the message says when and what to try).
    """
    field = _flag("field", field)
    progress = _callback("progress", progress)
    report, history, recorded = _native.simulate(scene, field, progress)
    return Simulation(json.loads(report), dict(history), None if recorded is None else dict(recorded))


def sweep(
    scene: Scene,
    axes: Mapping[str, Union[Sequence[Any], np.ndarray]],
    *,
    shard: Union[None, str, Sequence[int]] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    journal: Union[None, str, "os.PathLike[str]"] = None,
) -> Dict[str, Union[np.ndarray, List[str]]]:
    """Run a scene over the grid of ``axes`` on every core (the GIL released).

    Ctrl-C (KeyboardInterrupt) stops a sweep within a fraction of a second (the points in
    progress stop too, unfinished, and are run again next time); with ``journal``, every finished point is kept there as it finishes, and
    a sweep given the same journal again runs only the points it lacks.

    Args:
        scene: a path to a TOML scene file or a dict with its tables and keys.
        axes: dotted scene keys and their values, ``{"impact.drop_height": [0.1, 0.2]}``; two
            or more keys make a grid (the last key varies fastest, as on the command line).
        shard: ``(k, n)`` (or ``"k/n"``) runs points k-1, k-1+n, ... of the grid (as
            ``sweep --shard k/n``).
        progress: called with (points done, points) after each point; an exception it raises
            stops the sweep (no point starts after it) and is raised.
        journal: a file that keeps the finished points (a table with the sweep's fingerprint
            on its first line); an existing one of the same sweep is resumed, one of another
            sweep refused.

    Returns:
        The columns of the command line's sweep.csv: ``point`` (int64), each swept key
        (float64, or a list of str for names), the report's scalars of ``SWEEP_COLUMNS``
        (float64; NaN where a quantity does not exist, e.g. the restitution of a contact that
        had not ended) and ``error`` (a list of str, empty where the run succeeded).

    Raises:
        ValueError: an axis, the shard or a point's scene is refused (naming the point), or
            the journal is another sweep's.
        KeyboardInterrupt: interrupted; the message says how many points were kept.
    """
    shard = _shard(shard)
    progress = _callback("progress", progress)
    if journal is not None:
        journal = os.fspath(journal)
    return dict(_native.sweep(scene, dict(axes), shard, progress, journal))


def accuracy(
    scene: Scene,
    *,
    quick: bool = False,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Any]:
    """Speed against error (``cargo xtask accuracy``): both methods over ladders of settings.

    The settings run one after another (a wall time shared with another run on the same cores
    is not the setting's cost); each error is relative to its method's converged reference.

    Args:
        scene: a beam scene (path or dict).
        quick: the short ladders (seconds instead of minutes).
        progress: called with (settings done, settings) after each.

    Returns:
        ``rows``: the table of work_precision.csv (``method``, ``setting`` as lists of str; the
        numeric ``ACCURACY_COLUMNS`` as float64 arrays: wall time (s), the five relative errors,
        the energy balance over the impact energy); ``references``: each method's reference with
        its estimated error and check; ``model_difference``: the modal reference's differences
        from the fe one's; ``theory_difference``: what Euler-Bernoulli modes leave out (or None);
        ``name``: the scene's name.
    """
    quick = _flag("quick", quick)
    progress = _callback("progress", progress)
    return dict(_native.accuracy(scene, quick, progress))


def compare(
    scene: Scene,
    *,
    modes: Sequence[int] = (),
    elements: Sequence[int] = (),
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Union[np.ndarray, List[str]]]:
    """Both methods side by side (``cargo xtask compare``), against a converged reference.

    Runs the modal reference (``solver.tolerance`` = 1e-3), each method at the scene's own or
    default resolution, and the modal method at each of ``modes`` and the fe method at each of
    ``elements`` (uniform meshes), on every core.

    Returns:
        The columns of compare's summary.csv (``SUMMARY_COLUMNS``): ``run`` (list of str), the
        first contact's duration (s) and peak force (N), the contact count (int64), the largest
        displacement (m), the largest bending stress (Pa; NaN where the method does not recover
        it) and the wall time (s); and each run's ``estimated_error`` (NaN without one) and
        ``warnings`` (list of lists of str: whether the reference met its tolerance, too).

    Raises:
        ValueError: the scene is refused, or has no beam.
    """
    modes, elements = _counts("modes", modes), _counts("elements", elements)
    progress = _callback("progress", progress)
    return dict(_native.compare(scene, modes, elements, progress))
