#!/usr/bin/env python3
"""Interleaved timing of our `simulate` against a peer script, for the speed figures of the notes.

    python3 validation/peers/interleave.py --scene SCENE.toml --pairs 31 \
        --peer "/tmp/peers/bin/python validation/peers/exudyn_tip.py --elements 256 --end-time 0.001 --step 1e-6"

Each round runs our binary on the scene (its report's `wall_time`, the solve without start-up and
reading) and then the peer (the `wall time X s` it prints), and with `--base BINARY` an older
build of ours first (a before/after in the same rounds). Interleaving keeps the ratios meaningful
while the machine's speed drifts: a 2-core cloud machine moves a 40 ms run by +-15 % from one run
to the next. Prints each time's median and minimum and the peer/ours ratio pair by pair (median,
range) and median to median. Standard library only; nothing here is part of the build or tests.
"""

import argparse
import json
import re
import shlex
import statistics
import subprocess
import sys


def ours(binary, scene):
    out = subprocess.run(
        [binary, "simulate", scene, "--json"], capture_output=True, text=True, check=True
    ).stdout
    return float(json.loads(out)["wall_time"])


def peer(command):
    out = subprocess.run(shlex.split(command), capture_output=True, text=True, check=True).stdout
    # Exudyn's scripts print "solve wall time X s", scipy_modal_tip.py "wall time X s".
    match = re.search(r"wall time ([0-9.eE+-]+) s", out)
    if not match:
        sys.exit(f"the peer printed no 'wall time ... s': {out[-400:]}")
    return float(match.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True, help="the scene our binary simulates")
    parser.add_argument("--peer", required=True, help="the peer's command line")
    parser.add_argument("--binary", default="target/release/xtask", help="our xtask binary")
    parser.add_argument("--base", help="an older build of ours, run first in each round")
    parser.add_argument("--pairs", type=int, default=15, help="rounds (at least 15 for a claim)")
    args = parser.parse_args()
    if args.pairs < 1:
        sys.exit(f"--pairs must be at least 1, got {args.pairs}")
    rows = []
    for k in range(args.pairs):
        base = ours(args.base, args.scene) if args.base else None
        row = (base, ours(args.binary, args.scene), peer(args.peer))
        rows.append(row)
        print(f"round {k + 1}: " + " ".join("-" if x is None else f"{x:.4f}" for x in row),
              file=sys.stderr)
    median = statistics.median
    for name, j in (("base", 0), ("ours", 1), ("peer", 2)):
        values = [r[j] for r in rows if r[j] is not None]
        if values:
            print(f"{name}: median {median(values):.4f} s, min {min(values):.4f} s")
    for name, j in (("ours", 1), ("base", 0)):
        ratios = [r[2] / r[j] for r in rows if r[j] is not None]
        if ratios:
            whole = median([r[2] for r in rows]) / median([r[j] for r in rows])
            print(f"peer/{name}: {median(ratios):.2f}x pair by pair ({min(ratios):.2f}-"
                  f"{max(ratios):.2f}), {whole:.2f}x median to median, {len(rows)} rounds")
    if args.base:
        ratios = [r[1] / r[0] for r in rows]
        print(f"ours/base: {median(ratios):.3f} pair by pair")


if __name__ == "__main__":
    main()
