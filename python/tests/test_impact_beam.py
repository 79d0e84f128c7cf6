"""impact_beam against the command line: the same library must give the same numbers.

The command line is run as `cargo xtask ...` from the repository (set IMPACT_XTASK to a built
binary to skip cargo). Every comparison is exact: the report's floats to the last bit (both
are serde_json's shortest round-trip text of the same f64), the CSVs' cells to their printed
digits. Only wall times differ between two runs.
"""

import csv
import io
import json
import os
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import impact_beam as ib

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "validation" / "scenes"
TIP = SCENES / "paper-tip.toml"
HALF_SPACE = SCENES / "half-space-r10.toml"


def cli(*args, check=True):
    """`cargo --quiet xtask ARGS` (or $IMPACT_XTASK ARGS) in the repository: (stdout, stderr)."""
    # cargo's own lines ("Finished", "Running") kept off stderr, which the tests read.
    command = [os.environ["IMPACT_XTASK"]] if "IMPACT_XTASK" in os.environ else ["cargo", "--quiet", "xtask"]
    done = subprocess.run(command + [str(a) for a in args], cwd=REPO, capture_output=True, text=True)
    if check:
        assert done.returncode == 0, done.stderr
    return done.stdout, done.stderr


def timeless(report):
    """A report without its wall time (the one value two runs of a scene do not share)."""
    return {k: v for k, v in report.items() if k != "wall_time"}


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def printed(values, digits=9):
    """Values as the CSVs print them (`{:.9e}` in Rust; NaN as an empty cell), in Python's
    spelling: the CSV's cells are read back through `float` to compare."""
    return ["" if np.isnan(v) else f"{v:.{digits}e}" for v in values]


def cells(rows, name, digits=9):
    return ["" if r[name] == "" else f"{float(r[name]):.{digits}e}" for r in rows]


def scene_dict(path):
    """A scene file as the dict a notebook would write (tomllib, Python 3.11+)."""
    tomllib = pytest.importorskip("tomllib")
    with open(path, "rb") as f:
        return tomllib.load(f)


def test_the_version_is_the_packages_and_the_crates():
    # A result is recorded with what computed it: the compiled crates' version, which the
    # package's metadata repeats (python/pyproject.toml against the workspace's Cargo.toml).
    with open(REPO / "Cargo.toml", encoding="utf-8") as f:
        workspace = next(line.split('"')[1] for line in f if line.startswith("version = "))
    assert ib.__version__ == workspace
    from importlib.metadata import version

    assert version("impact-beam") == workspace


def test_the_report_equals_the_command_lines_json_to_the_last_digit():
    for scene in (TIP, HALF_SPACE):
        stdout, _ = cli("simulate", scene, "--json")
        expected = json.loads(stdout)
        got = ib.simulate(scene).report
        assert timeless(got) == timeless(expected)
        assert got["wall_time"] > 0


def test_an_off_centre_strike_reports_its_twist_as_the_command_line_does():
    # validation/scenes/paper-tip-offset.toml: 10 mm off the centreline (validation/REFERENCES.md
    # 1.9, 491.921 N by the independent reference); the same scene centred has no twist.
    offset = SCENES / "paper-tip-offset.toml"
    stdout, _ = cli("simulate", offset, "--json")
    got = ib.simulate(offset).report
    assert timeless(got) == timeless(json.loads(stdout))
    assert got["max_twist"] > 0
    assert got["contacts"][0]["peak_force"] == pytest.approx(491.921, rel=1e-4)
    centred = scene_dict(offset)
    centred["impact"]["offset"] = 0.0
    centred["solver"]["end_time"] = 2e-4
    report = ib.simulate(centred).report
    assert "max_twist" not in report
    assert report["contacts"][0]["peak_force"] == pytest.approx(781.6675, rel=1e-4)


def test_a_structure_reports_as_the_command_line_does():
    # validation/scenes/frame-impact.toml (validation/REFERENCES.md 1.11): an L-frame struck out
    # of its plane by the fe method's 3D beam; its static stiffness 446.467 N/m against the
    # members-in-series closed form 446.424, the clamped member's twist reported.
    frame = SCENES / "frame-impact.toml"
    stdout, _ = cli("simulate", frame, "--json")
    got = ib.simulate(frame).report
    assert timeless(got) == timeless(json.loads(stdout))
    assert got["static_stiffness"] == pytest.approx(446.424, rel=5e-4)
    assert got["largest_twist"]["position"] <= 0.5
    assert got["torsion_shear"]["max"] > 0


def test_a_structure_by_its_own_modes_meets_the_fe_method(tmp_path):
    # The same frame by Goldsmith's method on its 3D beam's modes (validation/REFERENCES.md
    # 1.13): the first contact within 1e-3 of the fe method's (measured 1.5e-4), the same
    # static stiffness (one static solve of the same mesh), the command line's report.
    scene = scene_dict(SCENES / "frame-impact.toml")
    scene["solver"]["method"] = "modal"
    modal = ib.simulate(scene).report
    fe = ib.simulate(SCENES / "frame-impact.toml").report
    # 240 modes below the cutoff; the 145 that move the struck face are kept (the frame's
    # in-plane modes never are excited).
    assert modal["plan"]["method"] == "modal" and modal["plan"]["modes"] == 145
    first, reference = modal["contacts"][0], fe["contacts"][0]
    assert first["peak_force"] == pytest.approx(reference["peak_force"], rel=1e-3)
    assert first["duration"] == pytest.approx(reference["duration"], rel=1e-3)
    assert modal["static_stiffness"] == pytest.approx(fe["static_stiffness"], rel=1e-9)
    path = tmp_path / "frame-modal.toml"
    path.write_text((SCENES / "frame-impact.toml").read_text().replace('method = "fe"', 'method = "modal"'))
    stdout, _ = cli("simulate", path, "--json")
    assert timeless(modal) == timeless(json.loads(stdout))


def test_a_simulation_prints_its_headline_not_its_arrays():
    run = ib.simulate(TIP)
    text = repr(run)
    first = run.first_contact
    assert text.startswith(f"Simulation('barrientos-tip': modal, {run.report['contact_count']} contact(s)")
    assert f"first {first['duration'] * 1e6:.2f} µs, {first['peak_force']:.1f} N" in text
    assert len(text) < 300


def test_the_history_holds_the_csv_columns_as_float64_arrays(tmp_path):
    history_csv = tmp_path / "history.csv"
    cli("simulate", TIP, "--history", history_csv)
    rows = read_csv(history_csv)
    run = ib.simulate(TIP)
    assert list(run.history) == list(rows[0])
    for name, values in run.history.items():
        assert values.dtype == np.float64 and values.ndim == 1 and len(values) == len(rows)
        # The CSV prints 10 significant digits: the arrays print to the same cells.
        assert printed(values) == cells(rows, name), name
    # The ball's energy at the start is the impact energy of the report.
    assert run.history["ball_energy_j"][0] == pytest.approx(run.report["energy"]["initial"], rel=1e-12)


def test_the_field_is_two_dimensional_and_matches_the_command_lines(tmp_path):
    field_csv = tmp_path / "field.csv"
    cli("simulate", TIP, "--field", field_csv)
    rows = read_csv(field_csv)
    field = ib.simulate(TIP, field=True).field
    n_t, n_x = len(field["time_s"]), len(field["x_m"])
    assert n_t * n_x == len(rows)
    for name in ("displacement_m", "slope_rad", "moment_n_m", "stress_pa"):
        assert field[name].shape == (n_t, n_x)
        assert printed(field[name].ravel()) == cells(rows, name), name
    assert ib.simulate(TIP).field is None


def test_sweep_rows_equal_the_command_lines_sweep_csv(tmp_path):
    axes = {"impact.speed": [0.5, 1.0, 2.0], "ball.radius": [0.005, 0.01]}
    cli("sweep", HALF_SPACE, "--set", "impact.speed=0.5,1,2", "--set", "ball.radius=0.005,0.01", "--out", tmp_path)
    rows = read_csv(tmp_path / "sweep.csv")
    table = ib.sweep(HALF_SPACE, axes)
    assert list(table) == list(rows[0])
    assert list(table["point"]) == [int(r["point"]) for r in rows]
    for name in ["impact.speed", "ball.radius"]:
        assert list(table[name]) == [float(r[name]) for r in rows], name
    for name in ib.SWEEP_COLUMNS:
        if name != "wall_time_s":
            assert printed(table[name]) == cells(rows, name), name
    assert table["error"] == [""] * 6
    # A shard holds the points K-1, K-1+N, ... of the whole.
    half = ib.sweep(HALF_SPACE, axes, shard="2/2")
    assert list(half["point"]) == [1, 3, 5]
    assert list(half["first_peak_force_n"]) == list(table["first_peak_force_n"][1::2])


def test_a_dict_scene_equals_its_toml_twin():
    scene = scene_dict(TIP)
    assert timeless(ib.simulate(scene).report) == timeless(ib.simulate(TIP).report)
    # numpy values are scene values too.
    scene["impact"]["drop_height"] = np.float64(0.1)
    scene["solver"]["modes"] = np.int64(64)
    report = ib.simulate(scene).report
    assert report["plan"]["modes"] == 64 and report["impact_speed"] == pytest.approx((2 * 9.81 * 0.1) ** 0.5, rel=1e-3)


def test_a_refused_scene_raises_value_error_with_the_command_lines_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(TIP.read_text().replace("length = 1.15", "length = -1.0"))
    _, stderr = cli("simulate", bad, check=False)
    with pytest.raises(ValueError) as refused:
        ib.simulate(bad)
    assert stderr.strip() == f"error: {refused.value}"
    assert "beam.length = -1" in str(refused.value)
    # The same scene as a dict: the same words without the file's name.
    scene = scene_dict(TIP)
    scene["beam"]["length"] = float("nan")
    with pytest.raises(ValueError, match="beam.length = NaN"):
        ib.simulate(scene)
    del scene["beam"]["length"]
    with pytest.raises(ValueError, match="length"):
        ib.simulate(scene)
    scene["beam"]["length"] = None
    with pytest.raises(ValueError, match="beam.length = None"):
        ib.simulate(scene)
    scene["beam"]["length"] = object()
    with pytest.raises(TypeError, match="beam.length"):
        ib.simulate(scene)


def test_files_and_options_the_command_line_refuses_are_refused_alike(tmp_path):
    for path, words in [
        (tmp_path / "missing.toml", "cannot read the scene file"),
        (tmp_path, "is not a regular file"),
    ]:
        _, stderr = cli("simulate", path, check=False)
        with pytest.raises(ValueError) as refused:
            ib.simulate(path)
        assert words in str(refused.value) and stderr.strip() == f"error: {refused.value}"
    with pytest.raises(ValueError, match="impact.sped"):
        ib.sweep(HALF_SPACE, {"impact.sped": [1.0]})
    with pytest.raises(ValueError, match="no values"):
        ib.sweep(HALF_SPACE, {"impact.speed": []})
    with pytest.raises(ValueError, match="3/2"):
        ib.sweep(HALF_SPACE, {"impact.speed": [1.0]}, shard="3/2")
    _, stderr = cli("sweep", HALF_SPACE, "--set", "impact.speed=1.0,-1.0", "--out", tmp_path / "bad-sweep", check=False)
    with pytest.raises(ValueError, match=r"point 1 \(impact.speed = -1") as refused:
        ib.sweep(HALF_SPACE, {"impact.speed": [1.0, -1.0]})
    assert stderr.strip() == f"error: {refused.value}"
    with pytest.raises(ValueError, match=r"compare needs a \[beam\] or a \[structure\]"):
        ib.compare(HALF_SPACE)
    with pytest.raises(TypeError, match="scene"):
        ib.simulate(42)


def test_progress_is_reported_and_a_failing_callback_raises():
    seen = []
    ib.simulate(TIP, progress=seen.append)
    assert seen and seen == sorted(seen) and seen[-1] == pytest.approx(1.0)
    counts = []
    ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0, 1.5]}, progress=lambda done, total: counts.append((done, total)))
    assert sorted(counts) == [(1, 3), (2, 3), (3, 3)]

    def stop(_fraction):
        raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        ib.simulate(TIP, progress=stop)


def test_a_sweep_releases_the_gil():
    """Python code runs while a sweep computes: the sweep does not hold the GIL."""
    # Long enough (half a second or more) that the scheduler's own pauses of this thread, with the
    # sweep on every core, stay a small part of it (94 ms of a 0.26 s sweep on 2 busy cores).
    heights = {"solver.end_time": [0.16], "impact.drop_height": list(np.linspace(0.05, 0.5, 48 * os.cpu_count()))}
    span = []

    def work():
        start = time.perf_counter()
        ib.sweep(TIP, heights)
        span.append(time.perf_counter() - start)

    worker = threading.Thread(target=work)
    worker.start()
    gaps, last = [], time.perf_counter()
    while worker.is_alive():
        time.sleep(0)
        now = time.perf_counter()
        gaps.append(now - last)
        last = now
    worker.join()
    # Held through the sweep, the GIL would stop this loop for the sweep's whole duration (a
    # control that holds it stalled the loop for 1.4 s of a 1.9 s sweep); released, the loop
    # waits only for a switch interval (5 ms) or the scheduler, with the sweep on every core.
    assert span[0] > 0.2, "the sweep is too short to tell"
    assert max(gaps) < span[0] / 3, (max(gaps), span[0])


def test_compare_equals_the_command_lines_summary(tmp_path):
    cli("compare", TIP, "--modes", "16", "--elements", "20", "--out", tmp_path)
    rows = read_csv(tmp_path / "summary.csv")
    table = ib.compare(TIP, modes=[16], elements=[20])
    assert list(table)[: len(ib.SUMMARY_COLUMNS)] == ib.SUMMARY_COLUMNS == list(rows[0])
    assert table["run"] == [r["run"] for r in rows]
    # Beyond summary.csv: each run's estimated error and warnings (the reference's tolerance
    # met or not, which the command line prints and a notebook had not seen).
    assert len(table["estimated_error"]) == len(table["warnings"]) == len(rows)
    assert table["estimated_error"][0] > 0.0 and np.isnan(table["estimated_error"][-1])
    for name in ib.SUMMARY_COLUMNS[1:-1]:
        if name == "contact_count":
            assert list(table[name]) == [int(r[name]) for r in rows]
        else:
            assert printed(table[name]) == cells(rows, name), name


def test_a_structure_is_compared_on_its_own_mesh():
    # The frame by both methods on its 80 elements against its own modes at tolerance 1e-3
    # (640 elements; validation/REFERENCES.md 1.14: the first contact within 1 % of it).
    table = ib.compare(SCENES / "frame-impact.toml")
    assert [r.split(",")[0] for r in table["run"]] == ["reference: modal", "fe", "modal"]
    reference, fe, modal = table["peak_force_n"]
    assert fe == pytest.approx(reference, rel=1.5e-2) and modal == pytest.approx(fe, rel=1e-3)
    with pytest.raises(Exception, match="segments' `elements`"):
        ib.compare(SCENES / "frame-impact.toml", modes=[16])


def test_accuracy_quick_equals_the_command_lines_table(tmp_path):
    cli("accuracy", TIP, "--quick", "--out", tmp_path)
    rows = read_csv(tmp_path / "work_precision.csv")
    study = ib.accuracy(TIP, quick=True)
    table = study["rows"]
    assert table["method"] == [r["method"] for r in rows]
    assert table["setting"] == [r["setting"] for r in rows]
    for name in ib.ACCURACY_COLUMNS[1:]:
        assert printed(table[name], 3) == cells(rows, name, 3), name
    assert [r["method"] for r in study["references"]] == ["modal", "fe"]


def test_the_example_runs_and_prints_the_first_contact(tmp_path):
    done = subprocess.run(
        [sys.executable, str(REPO / "python" / "examples" / "paper_tip.py"), "--quick", "--out", str(tmp_path)],
        capture_output=True, text=True, env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert done.returncode == 0, done.stderr
    first = ib.simulate(TIP).first_contact
    assert f"first contact: {first['duration'] * 1e6:.3f} µs, peak force {first['peak_force']:.1f} N" in done.stdout
    assert (tmp_path / "drop_height_sweep.png").stat().st_size > 10_000
    assert "modal reference" in done.stdout and "fe reference" in done.stdout


def long_sweep_axes(points):
    """A sweep of `points` points of the paper's tip, each a few milliseconds."""
    return {"solver.end_time": [2e-4], "impact.drop_height": list(np.linspace(0.05, 0.5, points))}


def test_an_interrupted_sweep_raises_promptly_and_its_journal_keeps_the_finished_points(tmp_path):
    """Ctrl-C (SIGINT) half a second into a long sweep: KeyboardInterrupt within half a second
    more, saying how many points were kept; the journal holds them, and the same call with the
    same journal runs only the rest (before: the interrupt waited for every point, then a
    PanicException, and every finished point was lost)."""
    import signal

    journal = tmp_path / "journal.csv"
    axes = long_sweep_axes(1500)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt, match="points are kept in") as caught:
        ib.sweep(TIP, axes, journal=journal)
    late = time.perf_counter() - start - 0.5
    assert late < 0.5, f"KeyboardInterrupt {late:.3f} s after the signal"
    kept = journal.read_text().splitlines()[2:]
    assert 0 < len(kept) < 1500, len(kept)
    assert f"{len(kept)} of 1500" in str(caught.value)
    # Resumed: the kept points are not run again.
    ran = []
    table = ib.sweep(TIP, axes, journal=journal, progress=lambda done, total: ran.append(total))
    assert list(table["point"]) == list(range(1500))
    assert ran and ran[0] == 1500 - len(kept)


def test_an_interrupt_stops_a_sweep_s_points_in_progress(tmp_path):
    """Ctrl-C half a second into a sweep of two long fe runs (seconds each): KeyboardInterrupt
    within half a second more, neither point kept (the interrupt had waited for the points in
    progress to finish, 9.5 s for 10 s points, a review's)."""
    import signal

    scene = scene_dict(TIP)
    scene["solver"] = {"method": "fe", "elements": 256, "end_time": 0.2}
    journal = tmp_path / "journal.csv"
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt, match="0 of 2 points are kept"):
        ib.sweep(scene, {"impact.drop_height": [0.1, 0.2]}, journal=journal)
    late = time.perf_counter() - start - 0.5
    assert late < 0.5, f"KeyboardInterrupt {late:.3f} s after the signal"
    assert journal.read_text().splitlines()[2:] == []


def test_a_raising_progress_callback_stops_a_sweep_after_one_call():
    calls = []

    def fail(done, total):
        calls.append(done)
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        ib.sweep(TIP, long_sweep_axes(400), progress=fail)
    assert len(calls) == 1, calls


def test_a_journal_of_another_sweep_is_refused(tmp_path):
    journal = tmp_path / "journal.csv"
    ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0]}, journal=journal)
    with pytest.raises(ValueError, match="line 1: the journal of another sweep"):
        ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 2.0]}, journal=journal)
    # An edited row: refused by its line.
    lines = journal.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("1,1.0,"))
    lines[at] = lines[at].replace("1,1.0,", "1,1.5,", 1)
    journal.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=f"line {at + 1}: point 1 has impact.speed = 1.5"):
        ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0]}, journal=journal)


def test_arguments_are_refused_in_pythons_words():
    with pytest.raises(TypeError, match="field: expected True or False, got 'yes'"):
        ib.simulate(TIP, field="yes")
    started = time.perf_counter()
    with pytest.raises(TypeError, match="progress: expected a function"):
        ib.sweep(TIP, long_sweep_axes(400), progress=5)
    assert time.perf_counter() - started < 0.2, "refused only after the run"
    with pytest.raises(ValueError, match="modes: -1 is not allowed"):
        ib.compare(TIP, modes=[-1])
    with pytest.raises(ValueError, match=r"shard: \(3, 2\) is not allowed"):
        ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0]}, shard=(3, 2))
    half = ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0, 1.5]}, shard=(2, 2))
    assert list(half["point"]) == [1]
    with pytest.raises(ValueError, match="axes: give at least one key") as caught:
        ib.sweep(HALF_SPACE, {})
    assert "--set" not in str(caught.value)
    with pytest.raises(ValueError) as caught:
        ib.simulate({"beam": {"length": 1.0}, "nonsense": 1})
    assert "scene file" not in str(caught.value), caught.value


def test_a_journal_that_cannot_be_written_raises(tmp_path):
    """A journal cut by a file-size limit (a full disk alike) had let the call return as if
    every point were kept (a review's); it raises OSError naming the journal and how many
    finished points it does not hold. In a child process: the limit is the process's."""
    journal = tmp_path / "journal.csv"
    script = f"""
import resource, signal
import impact_beam as ib
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (1500, 1500))
try:
    ib.sweep({str(HALF_SPACE)!r}, {{"impact.speed": [0.5 + 0.1 * k for k in range(12)]}}, journal={str(journal)!r})
    print("returned")
except OSError as e:
    print("raised:", e)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert out.stdout.startswith("raised: journal") and "are not kept there" in out.stdout, out


def test_a_sweep_called_from_a_sweep_s_progress_callback_is_refused():
    # The callback runs on one of the sweep's workers: a sweep or a comparison called there
    # waited for workers waiting for it, and hung past Ctrl-C (a review's). Refused at once;
    # simulate, which needs no worker, still runs there.
    seen = []

    def nested(done, total):
        seen.append(ib.simulate(HALF_SPACE).report["impact_speed"])
        ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0]})

    with pytest.raises(RuntimeError, match="cannot be called from inside a sweep's"):
        ib.sweep(HALF_SPACE, {"impact.speed": [0.5, 1.0]}, progress=nested)
    assert seen and all(speed > 0.0 for speed in seen)


def test_a_degenerate_beam_is_refused_as_a_value_error():
    # A micrometre strip of the paper's section: the plan had panicked, and pyo3's
    # PanicException (not an Exception) had escaped a sweep loop's `except Exception`.
    scene = scene_dict(TIP)
    scene["beam"]["length"] = 1e-6
    scene["impact"]["position"] = 0.0
    with pytest.raises(ValueError, match="not a beam"):
        ib.simulate(scene)


def test_swept_integers_and_booleans_keep_their_kind():
    # A bool axis had come back as the strings 'true' and 'false' ('false' is truthy) and an
    # integer axis as floats.
    table = ib.sweep(TIP, {"solver.modes": [8, 16], "impact.gravity": [True, False]})
    assert table["solver.modes"].dtype == np.int64 and list(table["solver.modes"]) == [8, 8, 16, 16]
    assert table["impact.gravity"].dtype == np.bool_ and list(table["impact.gravity"]) == [True, False, True, False]


def test_a_contact_the_window_cut_is_marked_in_the_headline():
    scene = scene_dict(TIP)
    scene["solver"] = {"method": "modal", "modes": 16, "end_time": 2e-5}
    run = ib.simulate(scene)
    assert not run.first_contact["complete"]
    assert "+ µs (not ended)" in repr(run), repr(run)


def test_two_runs_compare_and_hash_without_raising():
    # A generated == over numpy fields had raised ValueError; hash had raised TypeError.
    a, b = ib.simulate(HALF_SPACE), ib.simulate(HALF_SPACE)
    assert a == a and a != b
    assert len({a, b}) == 2
