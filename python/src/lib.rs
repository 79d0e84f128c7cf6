//! `impact_beam._native`: the Python front end's bridge to the `impact` library.
//!
//! Every function here converts Python's arguments, calls the same library code as the
//! command line (`cargo xtask simulate | sweep | accuracy | compare`), and converts the
//! answer back; nothing is computed twice. The package `impact_beam` (python/impact_beam)
//! wraps these functions with typed signatures and docstrings; see there for units.
//!
//! - A scene is a path to a TOML file (read by [`impact::study::read_input`], as the command
//!   line reads it) or a dict with the file's tables and keys (turned into the same TOML table
//!   and read by [`impact::Scene::from_table`]).
//! - Runs release the GIL; a sweep and a comparison run on every core (rayon).
//! - A scene or an option the command line refuses raises `ValueError` with the command
//!   line's message (for a file, "in PATH: ..." as it prints); a failed run raises
//!   `RuntimeError`; a panic, which the library should never raise, is caught here and
//!   raised as `RuntimeError` too, never as pyo3's `PanicException`.
//! - Long calls stop early: the calling thread checks Python's signals every
//!   `SIGNAL_POLL` (20 ms) while the work runs on others, so Ctrl-C (KeyboardInterrupt) is raised
//!   within a fraction of a second; a progress callback that raises stops the work the same
//!   way and is not called again. A run in progress stops at its next progress report (a
//!   thousandth of its window), a sweep's points in progress too (not finished, they are not
//!   kept), and a sweep with a `journal` keeps every finished point there (resumable).
//! - A progress callback is called with the GIL held.

use impact::study::{self, Axis, Grid, Shard, COLUMNS};
use impact::{ImpactError, Outcome, Scene};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::Mutex;

/// The library's allocations through mimalloc, as in the command line (`xtask/src/main.rs`:
/// huge pages, far fewer first-touch page faults a run); Python's own objects keep Python's
/// allocator.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// A scene as given: where it came from (for messages) and its table.
struct SceneInput {
    /// `Some(path)` for a file: errors read "in PATH: ...", as on the command line.
    path: Option<PathBuf>,
    table: toml::Table,
    scene: Scene,
}

impl SceneInput {
    /// `error` (with its causes) as the command line words it for this scene.
    fn refuse(&self, error: &ImpactError) -> PyErr {
        let text = chain(error);
        match &self.path {
            Some(p) => PyValueError::new_err(format!("in {}: {text}", p.display())),
            None => PyValueError::new_err(for_a_dict(&text)),
        }
    }
}

/// A message about a scene given as a dict, in Python's words: it is no file.
fn for_a_dict(text: &str) -> String {
    text.replace("scene file: ", "scene: ").replace("the scene file", "the scene")
}

/// `value` (a Python object from a scene dict, at `key`) as a TOML value.
fn to_toml(value: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        return value.extract::<i64>().map(toml::Value::Integer).map_err(|_| {
            PyValueError::new_err(format!("{key} = {value}: an integer must fit in 64 bits"))
        });
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract::<f64>()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract::<String>()?));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        return to_table(d, key).map(toml::Value::Table);
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<toml::Value>> = value
            .try_iter()?
            .enumerate()
            .map(|(i, item)| to_toml(&item?, &format!("{key}[{i}]")))
            .collect();
        return items.map(toml::Value::Array);
    }
    if value.is_none() {
        return Err(PyValueError::new_err(format!(
            "{key} = None: a scene has no empty value; leave the key out for its default"
        )));
    }
    // numpy scalars and arrays: their Python equivalents.
    if value.hasattr("tolist")? {
        let plain = value.call_method0("tolist")?;
        if !plain.is(value) {
            return to_toml(&plain, key);
        }
    }
    Err(PyTypeError::new_err(format!(
        "{key}: a value of type {} is not a scene value (allowed: bool, int, float, str, list, dict)",
        value.get_type().name()?
    )))
}

/// A dict of a scene (or of a table in it, at `at`) as a TOML table.
fn to_table(dict: &Bound<'_, PyDict>, at: &str) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    for (k, v) in dict.iter() {
        let name: String = k.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "{at}: a key must be a str, not {}",
                k.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            ))
        })?;
        let key = if at.is_empty() { name.clone() } else { format!("{at}.{name}") };
        table.insert(name, to_toml(&v, &key)?);
    }
    Ok(table)
}

/// Reads `scene`: a path (str or os.PathLike) to a TOML file, or a dict of its tables.
fn scene_input(scene: &Bound<'_, PyAny>) -> PyResult<SceneInput> {
    if let Ok(dict) = scene.cast::<PyDict>() {
        let table = to_table(dict, "")?;
        let parsed = Scene::from_table(table.clone())
            .map_err(|e| PyValueError::new_err(for_a_dict(&chain(&e))))?;
        return Ok(SceneInput { path: None, table, scene: parsed });
    }
    let path: PathBuf = scene.extract().map_err(|_| {
        PyTypeError::new_err(
            "scene: a path to a TOML scene file (str or os.PathLike) or a dict of its tables",
        )
    })?;
    let text =
        study::read_input(&path, "scene file").map_err(|e| PyValueError::new_err(chain(&e)))?;
    let refuse =
        |e: &dyn std::fmt::Display| PyValueError::new_err(format!("in {}: {e}", path.display()));
    let parsed = Scene::from_toml(&text).map_err(|e| refuse(&e))?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| refuse(&e))?;
    Ok(SceneInput { path: Some(path), table, scene: parsed })
}

/// An error and its causes on one line, as the command line prints them ("a: b: c").
fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut cause = error.source();
    while let Some(c) = cause {
        text.push_str(": ");
        text.push_str(&c.to_string());
        cause = c.source();
    }
    text
}

/// How often the calling thread checks Python's signals while work runs.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(20);

/// Why a call stopped early: the first interrupt or callback exception; the work checks
/// [`Stop::stopped`] before each point and at each progress report.
#[derive(Default)]
struct Stop {
    flag: std::sync::atomic::AtomicBool,
    error: Mutex<Option<PyErr>>,
}

/// The payload with which a run in progress unwinds when its call stops (never a panic's
/// message: [`std::panic::resume_unwind`] does not run the panic hook).
struct Stopped;

impl Stop {
    fn stopped(&self) -> bool {
        self.flag.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Stops the call with `error` (the first one is kept).
    fn stop(&self, error: PyErr) {
        if let Ok(mut slot) = self.error.lock() {
            slot.get_or_insert(error);
        }
        self.flag.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Ends a run in progress when the call has stopped (its progress report calls this).
    fn unwind_if_stopped(&self) {
        if self.stopped() {
            std::panic::resume_unwind(Box::new(Stopped));
        }
    }

    /// The reason the call stopped, if it did.
    fn take(&self) -> Option<PyErr> {
        self.error.lock().ok().and_then(|mut e| e.take())
    }
}

/// `work` on this thread with a panic turned into `RuntimeError` (the plan is made here,
/// before the run goes to its own thread: a panic in it had reached Python as pyo3's
/// `PanicException`, which `except Exception` does not catch).
fn unpanicked<T>(work: impl FnOnce() -> T) -> PyResult<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).map_err(|panic| {
        PyRuntimeError::new_err(ImpactError::from_panic(panic.as_ref()).to_string())
    })
}

/// Runs `work` on another thread without the GIL while this thread checks Python's signals
/// every [`SIGNAL_POLL`] (an interrupt stops the call: `stop`); a panic is caught and turned
/// into an error, a run unwound by [`Stop`] into the reason it stopped.
fn detached<T: Send>(py: Python<'_>, stop: &Stop, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let result = py.detach(|| {
        std::thread::scope(|scope| {
            let worker =
                scope.spawn(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)));
            while !worker.is_finished() {
                std::thread::sleep(SIGNAL_POLL);
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    stop.stop(e);
                }
            }
            worker.join().unwrap_or_else(Err)
        })
    });
    let value = result.map_err(|panic| {
        if panic.is::<Stopped>() {
            return stop.take().unwrap_or_else(|| PyRuntimeError::new_err("the call was stopped"));
        }
        PyRuntimeError::new_err(ImpactError::from_panic(panic.as_ref()).to_string())
    })?;
    // An interrupt that came as the work ended still counts.
    Python::attach(|py| py.check_signals())?;
    Ok(value)
}

/// A progress callback shared by the worker threads: each call takes the GIL; an exception
/// stops the call (`stop`), and the callback is not called again.
struct Callback<'a> {
    function: Option<Py<PyAny>>,
    stop: &'a Stop,
}

impl<'a> Callback<'a> {
    /// `function` (None: no calls), after checking that it can be called.
    fn new(function: Option<Py<PyAny>>, stop: &'a Stop) -> PyResult<Self> {
        if let Some(f) = &function {
            let callable = Python::attach(|py| f.bind(py).is_callable());
            if !callable {
                return Err(PyTypeError::new_err(
                    "progress: expected a function (callable) or None",
                ));
            }
        }
        Ok(Self { function, stop })
    }

    fn call<A: for<'py> pyo3::call::PyCallArgs<'py>>(&self, args: A) {
        let Some(f) = &self.function else { return };
        Python::attach(|py| {
            // Checked with the GIL held: a call that raised on another thread set it while it
            // held the GIL, so no call waiting for the GIL follows one that raised.
            if self.stop.stopped() {
                return;
            }
            if let Err(e) = f.call1(py, args) {
                self.stop.stop(e);
            }
        });
    }
}

/// A run's failure as Python sees it: `ValueError` for a scene the plan refuses,
/// `RuntimeError` for a solver that failed.
fn run_error(input: &SceneInput, e: &ImpactError) -> PyErr {
    // A refinement's run fails as that run's error does (its message the whole chain).
    let mut cause = e;
    while let ImpactError::Refinement { source, .. } = cause {
        cause = source;
    }
    match cause {
        ImpactError::SolverFailed { .. }
        | ImpactError::Integrator { .. }
        | ImpactError::Internal(_) => PyRuntimeError::new_err(chain(e)),
        _ => input.refuse(e),
    }
}

/// Runs `scenes` on every core without the GIL: each finished one handed to `finished` (its
/// index and report) and counted to `callback` (points done, points); a point not started
/// when the call stopped is `None`.
fn simulate_all(
    py: Python<'_>,
    scenes: &[Scene],
    (stop, callback): (&Stop, &Callback<'_>),
    finished: &(dyn Fn(usize, &Result<impact::Report, ImpactError>) + Sync),
) -> PyResult<Vec<Option<Result<impact::Report, ImpactError>>>> {
    // A progress callback runs on one of the pool's workers: a sweep or a comparison called
    // from it would wait for workers that wait for it (it hung, past Ctrl-C, a review's).
    if rayon::current_thread_index().is_some() {
        return Err(PyRuntimeError::new_err(
            "sweep and compare cannot be called from inside a sweep's or a comparison's progress callback: the callback runs on one of the worker threads the inner call would wait for; call them after the outer call returns (simulate may be called there)",
        ));
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    detached(py, stop, || {
        scenes
            .par_iter()
            .enumerate()
            .map(|(k, s)| {
                if stop.stopped() {
                    return None;
                }
                // A point in progress stops at its next progress report when the call stops
                // (it had run to its end: a Ctrl-C waited 9.5 s for 10 s points, a review's);
                // it is not finished, so it is not kept and runs again with the journal.
                let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    impact::simulate_with_progress(s, &|_| stop.unwind_if_stopped())
                }));
                // A point that panics is its own error row, not the sweep's end (a review's
                // degenerate beam had taken every point of a journaled sweep with it).
                let report = match run {
                    Ok(outcome) => outcome.map(|o| o.report),
                    Err(payload) if payload.is::<Stopped>() => return None,
                    Err(payload) => Err(ImpactError::from_panic(payload.as_ref())),
                };
                finished(k, &report);
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                callback.call((n, scenes.len()));
                Some(report)
            })
            .collect()
    })
}

fn column<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, values)
}

/// `simulate`: the report as the command line's JSON, the history's columns, and the field's.
#[pyfunction]
#[pyo3(signature = (scene, field = false, progress = None))]
fn simulate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    field: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<(String, Bound<'py, PyDict>, Option<Bound<'py, PyDict>>)> {
    let input = scene_input(scene)?;
    let mut plan = unpanicked(|| impact::Plan::new(&input.scene))?.map_err(|e| input.refuse(&e))?;
    if field {
        plan = unpanicked(|| plan.with_field())?.map_err(|e| input.refuse(&e))?;
    }
    let stop = Stop::default();
    let callback = Callback::new(progress, &stop)?;
    let outcome: Result<Outcome, ImpactError> = detached(py, &stop, || {
        impact::run_with_progress(&plan, &|fraction| {
            callback.call((fraction,));
            stop.unwind_if_stopped();
        })
    })?;
    if let Some(e) = stop.take() {
        return Err(e);
    }
    let outcome = outcome.map_err(|e| run_error(&input, &e))?;
    let report = serde_json::to_string(&outcome.report)
        .map_err(|e| PyRuntimeError::new_err(format!("the report does not serialise: {e}")))?;
    let history = PyDict::new(py);
    for (name, values) in outcome.history.columns() {
        history.set_item(name, column(py, values))?;
    }
    let field = match &outcome.field {
        Some(f) => {
            let out = PyDict::new(py);
            out.set_item("time_s", column(py, &f.time))?;
            out.set_item("x_m", column(py, &f.points))?;
            let shape = [f.time.len(), f.points.len()];
            for (name, values) in f.quantities() {
                out.set_item(name, column(py, values).reshape(shape)?)?;
            }
            Some(out)
        }
        None => None,
    };
    Ok((report, history, field))
}

/// The value of a swept key at each point: integers (int64) or booleans when they all are
/// (a bool axis had come back as the strings 'true' and 'false', and 'false' is truthy),
/// numbers (float64) when they all are, else text.
fn key_column<'py>(py: Python<'py>, values: &[&toml::Value]) -> PyResult<Bound<'py, PyAny>> {
    let integers = values.iter().map(|v| v.as_integer()).collect::<Option<Vec<i64>>>();
    if let Some(n) = integers {
        return Ok(numpy::PyArray1::from_vec(py, n).into_any());
    }
    if let Some(b) = values.iter().map(|v| v.as_bool()).collect::<Option<Vec<bool>>>() {
        return Ok(numpy::PyArray1::from_vec(py, b).into_any());
    }
    let numbers: Option<Vec<f64>> = values
        .iter()
        .map(|v| match v {
            toml::Value::Float(x) => Some(*x),
            toml::Value::Integer(n) => Some(*n as f64),
            _ => None,
        })
        .collect();
    Ok(match numbers {
        Some(n) => column(py, &n).into_any(),
        None => PyList::new(
            py,
            values.iter().map(|v| match v {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            }),
        )?
        .into_any(),
    })
}

/// The first line of a sweep's journal: what it is, then the sweep's fingerprint and shard.
const JOURNAL_TAG: &str = "# impact-beam sweep journal";

/// A sweep's journal (`journal=PATH`): the tag line, the table's header, then a table row a
/// finished point, appended (and flushed) as each finishes, so an interrupted sweep keeps
/// them; a sweep given the same journal again runs only the points it lacks.
struct Journal {
    path: PathBuf,
    file: Mutex<std::fs::File>,
    /// The rows it held when opened, by point (each checked against the sweep's grid).
    kept: std::collections::BTreeMap<usize, Vec<String>>,
    /// The first write that failed, and how many rows were not written: the call raises it
    /// (a journal cut by a full disk or a file-size limit had returned as if every point
    /// were kept, a review's; the command line stops on it too).
    failed: Mutex<Option<(String, usize)>>,
}

/// One CSV line of `cells`.
fn csv_line(cells: &[String]) -> PyResult<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(cells).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    w.into_inner().map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

impl Journal {
    /// Opens `path` for the sweep of `manifest`: a new file with its tag and header, or an
    /// existing one of the same sweep, whose rows are checked ([`study::Manifest::check_row`])
    /// and kept; another sweep's, or a damaged one, is refused naming the line.
    fn open(path: PathBuf, manifest: &study::Manifest) -> PyResult<Self> {
        let tag = format!(
            "{JOURNAL_TAG} {} shard {}/{}",
            manifest.fingerprint, manifest.shard.k, manifest.shard.n
        );
        let shown = path.display().to_string();
        let refuse = |line: usize, why: String| {
            PyValueError::new_err(format!("journal {shown}, line {line}: {why}"))
        };
        let mut kept = std::collections::BTreeMap::new();
        if path.exists() {
            let text = std::fs::read_to_string(&path)
                .map_err(|e| PyValueError::new_err(format!("journal {shown}: {e}")))?;
            let mut lines = text.split_inclusive('\n');
            if lines.next().map(str::trim_end) != Some(tag.as_str()) {
                return Err(refuse(1, "the journal of another sweep (scene, axes or shard differ), or not a journal: give another path".into()));
            }
            let header = csv_line(&manifest.header)?;
            if lines.next().map(str::as_bytes) != Some(header.as_slice()) {
                return Err(refuse(2, "its columns are not the sweep's".into()));
            }
            // A last line without its end (a write cut short) is left out: that point runs.
            for (k, line) in lines.enumerate().filter(|(_, l)| l.ends_with('\n')) {
                let mut reader =
                    csv::ReaderBuilder::new().has_headers(false).from_reader(line.as_bytes());
                let record = reader
                    .records()
                    .next()
                    .and_then(Result::ok)
                    .ok_or_else(|| refuse(k + 3, "not a table row".into()))?;
                let cells: Vec<String> = record.iter().map(str::to_string).collect();
                if cells.len() != manifest.header.len() {
                    return Err(refuse(
                        k + 3,
                        format!(
                            "{} fields where the header has {}",
                            cells.len(),
                            manifest.header.len()
                        ),
                    ));
                }
                let point = manifest.check_row(&cells).map_err(|e| refuse(k + 3, chain(&e)))?;
                kept.insert(point, cells);
            }
        }
        let mut text = tag.into_bytes();
        text.push(b'\n');
        text.extend(csv_line(&manifest.header)?);
        for row in kept.values() {
            text.extend(csv_line(row)?);
        }
        // Rewritten whole (a cut last line dropped), then appended to.
        // Synced before the rename (else a machine that stops may leave the new name on an
        // empty file) and after it.
        let tmp = path.with_extension("journal-tmp");
        let synced = |p: &std::path::Path| std::fs::File::open(p).and_then(|f| f.sync_all());
        std::fs::write(&tmp, &text)
            .and_then(|()| synced(&tmp))
            .and_then(|()| std::fs::rename(&tmp, &path))
            .and_then(|()| path.parent().map_or(Ok(()), |d| synced(d).or(Ok(()))))
            .map_err(|e| PyValueError::new_err(format!("journal {shown}: cannot write it: {e}")))?;
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| PyValueError::new_err(format!("journal {shown}: cannot write it: {e}")))?;
        Ok(Self { path, file: Mutex::new(file), kept, failed: Mutex::new(None) })
    }

    /// Appends a finished point's row; a failure is kept for [`Journal::check`].
    fn append(&self, cells: &[String]) {
        use std::io::Write;
        let written = match (csv_line(cells), self.file.lock()) {
            (Ok(line), Ok(mut f)) => {
                // Synced: a machine that stops keeps the finished rows too.
                f.write_all(&line)
                    .and_then(|()| f.flush())
                    .and_then(|()| f.sync_data())
                    .map_err(|e| e.to_string())
            }
            (Err(e), _) => Err(e.to_string()),
            (_, Err(_)) => Err("a run stopped while writing it".to_string()),
        };
        if let Err(why) = written {
            let mut failed = self.failed.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            match failed.as_mut() {
                Some((_, missed)) => *missed += 1,
                None => *failed = Some((why, 1)),
            }
        }
    }

    /// An `OSError` naming the journal, the first write that failed and how many rows were
    /// not kept, if any was not.
    fn check(&self) -> PyResult<()> {
        let failed = self.failed.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        match &*failed {
            Some((why, missed)) => Err(pyo3::exceptions::PyOSError::new_err(format!(
                "journal {}: cannot write it: {why}; {missed} finished point(s) are not kept there (a row cut short is run again when the journal is reused)",
                self.path.display()
            ))),
            None => Ok(()),
        }
    }
}

/// A sweep table's rows as the Python columns: `point`, the swept keys, the scalars (the
/// runs' own values where this call ran them, else the journal's printed ones; NaN where
/// blank), `error`.
fn sweep_columns<'py>(
    py: Python<'py>,
    grid: &Grid,
    rows: &std::collections::BTreeMap<usize, Vec<String>>,
    exact: &std::collections::BTreeMap<usize, [Option<f64>; COLUMNS.len()]>,
) -> PyResult<Bound<'py, PyDict>> {
    let points: Vec<usize> = rows.keys().copied().collect();
    let out = PyDict::new(py);
    out.set_item("point", PyArray1::from_vec(py, points.iter().map(|&i| i as i64).collect()))?;
    let keys = grid.keys();
    for (a, key) in keys.iter().enumerate() {
        let values: Vec<&toml::Value> = points.iter().map(|&i| grid.point(i)[a].1).collect();
        out.set_item(key, key_column(py, &values)?)?;
    }
    for (c, name) in COLUMNS.iter().enumerate() {
        let values: Vec<f64> = rows
            .iter()
            .map(|(point, cells)| match exact.get(point) {
                Some(row) => row[c].unwrap_or(f64::NAN),
                None => cells[1 + keys.len() + c].parse().unwrap_or(f64::NAN),
            })
            .collect();
        out.set_item(name, column(py, &values))?;
    }
    let errors: Vec<String> =
        rows.values().map(|c| c.last().cloned().unwrap_or_default()).collect();
    out.set_item("error", errors)?;
    Ok(out)
}

/// `sweep`: the columns of the command line's sweep.csv over the points of `shard`; with a
/// `journal`, every finished point kept there as it finishes, and the points it already holds
/// not run again.
#[pyfunction]
#[pyo3(signature = (scene, axes, shard = None, progress = None, journal = None))]
fn sweep<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    axes: &Bound<'py, PyDict>,
    shard: Option<&str>,
    progress: Option<Py<PyAny>>,
    journal: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let input = scene_input(scene)?;
    // The library's messages name the command line's options: in Python they are arguments.
    let refuse = |e: ImpactError| {
        PyValueError::new_err(
            chain(&e)
                .replace(
                    "give at least one --set KEY=START:STOP:COUNT or KEY=v1,v2,...",
                    "axes: give at least one key and its values",
                )
                .replace("--set ", "axes: ")
                .replace("--shard ", "shard: "),
        )
    };
    let mut parsed = Vec::new();
    for (k, v) in axes.iter() {
        let key: String = k
            .extract()
            .map_err(|_| PyTypeError::new_err("axes: each key is a dotted scene key (str)"))?;
        let values = match to_toml(&v, &key)? {
            toml::Value::Array(a) => a,
            single => vec![single],
        };
        parsed.push(Axis::new(&key, values).map_err(refuse)?);
    }
    let grid = Grid::new(parsed).map_err(refuse)?;
    let shard = shard.map(Shard::parse).transpose().map_err(refuse)?.unwrap_or(Shard::WHOLE);
    let manifest = study::Manifest::new(&input.table, &grid, shard);
    let journal = journal.map(|p| Journal::open(p, &manifest)).transpose()?;
    let mine: Vec<usize> = shard
        .points(grid.len())
        .filter(|i| journal.as_ref().is_none_or(|j| !j.kept.contains_key(i)))
        .collect();
    // Every point's scene before any run, as the command line does: a bad point stops the
    // sweep before it costs anything (the message names the point and its values).
    let scenes: Vec<Scene> = mine
        .iter()
        .map(|&i| grid.scene(&input.table, i))
        .collect::<Result<_, _>>()
        .map_err(refuse)?;
    let row = |k: usize, r: &Result<impact::Report, ImpactError>| {
        let why = r.as_ref().err().map(|e| chain(e));
        grid.row(mine[k], r.as_ref().map_err(|_| why.as_deref().unwrap_or("")))
    };
    let stop = Stop::default();
    let callback = Callback::new(progress, &stop)?;
    let results = simulate_all(py, &scenes, (&stop, &callback), &|k, r| {
        if let Some(j) = &journal {
            j.append(&row(k, r));
        }
    })?;
    if let Some(j) = &journal {
        j.check()?;
    }
    let mut rows = journal.as_ref().map(|j| j.kept.clone()).unwrap_or_default();
    let mut exact = std::collections::BTreeMap::new();
    for (k, r) in results.iter().enumerate() {
        if let Some(r) = r {
            rows.insert(mine[k], row(k, r));
            let scalars = r.as_ref().map_or([None; COLUMNS.len()], study::grid::scalars);
            exact.insert(mine[k], scalars);
        }
    }
    if let Some(e) = stop.take() {
        let total = shard.points(grid.len()).count();
        let kept = match &journal {
            Some(j) => format!(
                "{} of {total} points are kept in {}: call sweep again with the same journal to finish",
                rows.len(),
                j.path.display()
            ),
            None => format!(
                "{} of {total} points had finished and are lost: pass journal=PATH to keep them",
                rows.len()
            ),
        };
        return Err(if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
            pyo3::exceptions::PyKeyboardInterrupt::new_err(format!("sweep interrupted: {kept}"))
        } else {
            e
        });
    }
    sweep_columns(py, &grid, &rows, &exact)
}

/// `accuracy`: the work-precision study's table, references and the models' differences.
#[pyfunction]
#[pyo3(signature = (scene, quick = false, progress = None))]
fn accuracy<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    quick: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use study::accuracy::{run, Ladders, ROW_COLUMNS};
    let input = scene_input(scene)?;
    let ladders = if quick { Ladders::quick() } else { Ladders::full() };
    let stop = Stop::default();
    let callback = Callback::new(progress, &stop)?;
    let study = detached(py, &stop, || {
        run(&input.scene, &ladders, &|done, total| {
            callback.call((done, total));
            stop.unwind_if_stopped();
        })
    })?;
    if let Some(e) = stop.take() {
        return Err(e);
    }
    let study = study.map_err(|e| run_error(&input, &e))?;
    let rows = PyDict::new(py);
    rows.set_item("method", study.rows.iter().map(|r| r.method).collect::<Vec<_>>())?;
    rows.set_item("setting", study.rows.iter().map(|r| r.setting.clone()).collect::<Vec<_>>())?;
    let values: Vec<[f64; ROW_COLUMNS.len()]> = study.rows.iter().map(|r| r.values()).collect();
    for (c, name) in ROW_COLUMNS.iter().enumerate() {
        rows.set_item(name, column(py, &values.iter().map(|v| v[c]).collect::<Vec<_>>()))?;
    }
    let differences = |d: &impact::Differences| -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        out.set_item("first_duration", d.first_duration)?;
        out.set_item("first_peak_force", d.first_peak_force)?;
        out.set_item("contact_sequence", d.contact_sequence)?;
        out.set_item("max_displacement", d.max_displacement)?;
        out.set_item("max_stress", d.max_stress)?;
        out.set_item("same_contacts", d.same_contacts)?;
        Ok(out)
    };
    let references = PyList::empty(py);
    for r in &study.references {
        let entry = PyDict::new(py);
        entry.set_item("method", r.method)?;
        entry.set_item("setting", &r.setting)?;
        entry.set_item("estimated_error", r.estimated_error)?;
        entry.set_item("check", &r.check)?;
        references.append(entry)?;
    }
    let out = PyDict::new(py);
    out.set_item("name", &study.name)?;
    out.set_item("rows", rows)?;
    out.set_item("references", references)?;
    out.set_item("model_difference", differences(&study.model_difference)?)?;
    out.set_item(
        "theory_difference",
        study.theory_difference.as_ref().map(differences).transpose()?,
    )?;
    Ok(out)
}

/// `compare`: the columns of the command line's summary.csv.
#[pyfunction]
#[pyo3(signature = (scene, modes = Vec::new(), elements = Vec::new(), progress = None))]
fn compare<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    modes: Vec<usize>,
    elements: Vec<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use study::comparison::{runs, summary, SummaryRow, SUMMARY_COLUMNS};
    let input = scene_input(scene)?;
    let runs = runs(&input.scene, &modes, &elements).map_err(|e| input.refuse(&e))?;
    let scenes: Vec<Scene> = runs.iter().map(|(_, s)| s.clone()).collect();
    let stop = Stop::default();
    let callback = Callback::new(progress, &stop)?;
    let all = simulate_all(py, &scenes, (&stop, &callback), &|_, _| {})?;
    if let Some(e) = stop.take() {
        return Err(e);
    }
    let reports: Vec<impact::Report> =
        all.into_iter().flatten().collect::<Result<_, _>>().map_err(|e| run_error(&input, &e))?;
    let rows = summary(runs.iter().map(|(l, _)| l.as_str()).zip(&reports));
    let floats = |value: fn(&SummaryRow) -> Option<f64>| {
        column(py, &rows.iter().map(|r| value(r).unwrap_or(f64::NAN)).collect::<Vec<_>>())
    };
    let [run, duration, peak, count, displacement, stress, wall] = SUMMARY_COLUMNS;
    let out = PyDict::new(py);
    out.set_item(run, rows.iter().map(|r| r.run.clone()).collect::<Vec<_>>())?;
    out.set_item(duration, floats(|r| r.first_duration))?;
    out.set_item(peak, floats(|r| r.peak_force))?;
    out.set_item(
        count,
        PyArray1::from_vec(py, rows.iter().map(|r| r.contact_count as i64).collect()),
    )?;
    out.set_item(displacement, floats(|r| Some(r.max_displacement)))?;
    out.set_item(stress, floats(|r| r.max_bending_stress))?;
    out.set_item(wall, floats(|r| Some(r.wall_time)))?;
    // Beyond summary.csv: each run's estimated error (NaN without one) and warnings, which
    // say whether the reference met its tolerance (the command line prints it; a notebook had
    // compared against a reference flagged unconverged without knowing, a review's).
    let estimated: Vec<f64> =
        reports.iter().map(|r| r.estimated_error.unwrap_or(f64::NAN)).collect();
    out.set_item("estimated_error", column(py, &estimated))?;
    out.set_item("warnings", reports.iter().map(|r| r.warnings.clone()).collect::<Vec<_>>())?;
    Ok(out)
}

/// The native module: `simulate`, `sweep`, `accuracy`, `compare` and the sweep's columns.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add("SWEEP_COLUMNS", COLUMNS.to_vec())?;
    m.add("SUMMARY_COLUMNS", study::comparison::SUMMARY_COLUMNS.to_vec())?;
    m.add("ACCURACY_COLUMNS", study::accuracy::ROW_COLUMNS.to_vec())?;
    // The crates' version (the workspace's, which python/pyproject.toml repeats): what a
    // result was computed with, for a user's records.
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
