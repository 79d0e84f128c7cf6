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
//! - A progress callback is called with the GIL held; an exception it raises is raised once
//!   the work is done (the run is not stopped halfway).

use impact::study::{self, Axis, Grid, Shard, COLUMNS};
use impact::{ImpactError, Outcome, Scene};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::Mutex;

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
            None => PyValueError::new_err(text),
        }
    }
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
        let parsed =
            Scene::from_table(table.clone()).map_err(|e| PyValueError::new_err(chain(&e)))?;
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

/// Runs `work` without the GIL, a panic caught and turned into an error.
fn detached<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(work))).map_err(|panic| {
        let what = panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_string()))
            .unwrap_or_default();
        PyRuntimeError::new_err(format!("internal error (please report it): {what}"))
    })
}

/// A progress callback shared by the worker threads: each call takes the GIL; the first
/// exception is kept for [`Callback::finish`].
struct Callback {
    function: Option<Py<PyAny>>,
    failed: Mutex<Option<PyErr>>,
}

impl Callback {
    fn new(function: Option<Py<PyAny>>) -> Self {
        Self { function, failed: Mutex::new(None) }
    }

    fn call<A: for<'py> pyo3::call::PyCallArgs<'py>>(&self, args: A) {
        let Some(f) = &self.function else { return };
        Python::attach(|py| {
            if let Err(e) = f.call1(py, args) {
                if let Ok(mut slot) = self.failed.lock() {
                    slot.get_or_insert(e);
                }
            }
        });
    }

    /// The callback's first exception, if any.
    fn finish(self) -> PyResult<()> {
        match self.failed.into_inner() {
            Ok(Some(e)) => Err(e),
            _ => Ok(()),
        }
    }
}

/// A run's failure as Python sees it: `ValueError` for a scene the plan refuses,
/// `RuntimeError` for a solver that failed.
fn run_error(input: &SceneInput, e: &ImpactError) -> PyErr {
    match e {
        ImpactError::SolverFailed { .. } | ImpactError::Integrator { .. } => {
            PyRuntimeError::new_err(chain(e))
        }
        _ => input.refuse(e),
    }
}

/// Runs `scenes` on every core without the GIL, telling `progress` (points done, points)
/// after each: the reports (or errors) in the scenes' order.
fn simulate_all(
    py: Python<'_>,
    scenes: &[Scene],
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Result<impact::Report, ImpactError>>> {
    let callback = Callback::new(progress);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let reports = detached(py, || {
        scenes
            .par_iter()
            .map(|s| {
                let report = impact::simulate(s).map(|o| o.report);
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                callback.call((n, scenes.len()));
                report
            })
            .collect()
    })?;
    callback.finish()?;
    Ok(reports)
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
    let mut plan = impact::Plan::new(&input.scene).map_err(|e| input.refuse(&e))?;
    if field {
        plan = plan.with_field().map_err(|e| input.refuse(&e))?;
    }
    let callback = Callback::new(progress);
    let outcome: Result<Outcome, ImpactError> =
        detached(py, || impact::run_with_progress(&plan, &|fraction| callback.call((fraction,))))?;
    callback.finish()?;
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

/// The value of a swept key at each point, as numbers when they all are, else as text.
fn key_column<'py>(py: Python<'py>, values: &[&toml::Value]) -> PyResult<Bound<'py, PyAny>> {
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

/// `sweep`: the columns of the command line's sweep.csv over the points of `shard`.
#[pyfunction]
#[pyo3(signature = (scene, axes, shard = None, progress = None))]
fn sweep<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    axes: &Bound<'py, PyDict>,
    shard: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let input = scene_input(scene)?;
    let refuse = |e: ImpactError| PyValueError::new_err(chain(&e));
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
    let mine: Vec<usize> = shard.points(grid.len()).collect();
    // Every point's scene before any run, as the command line does: a bad point stops the
    // sweep before it costs anything (the message names the point and its values).
    let scenes: Vec<Scene> = mine
        .iter()
        .map(|&i| grid.scene(&input.table, i))
        .collect::<Result<_, _>>()
        .map_err(refuse)?;
    let results: Vec<Result<impact::Report, String>> = simulate_all(py, &scenes, progress)?
        .into_iter()
        .map(|r| r.map_err(|e| chain(&e)))
        .collect();
    let out = PyDict::new(py);
    out.set_item("point", PyArray1::from_vec(py, mine.iter().map(|&i| i as i64).collect()))?;
    for (a, key) in grid.keys().iter().enumerate() {
        let values: Vec<&toml::Value> = mine.iter().map(|&i| grid.point(i)[a].1).collect();
        out.set_item(key, key_column(py, &values)?)?;
    }
    let scalars: Vec<[Option<f64>; COLUMNS.len()]> = results
        .iter()
        .map(|r| r.as_ref().map_or([None; COLUMNS.len()], study::grid::scalars))
        .collect();
    for (c, name) in COLUMNS.iter().enumerate() {
        let values: Vec<f64> = scalars.iter().map(|row| row[c].unwrap_or(f64::NAN)).collect();
        out.set_item(name, column(py, &values))?;
    }
    let errors: Vec<String> = results
        .iter()
        .map(|r| r.as_ref().err().map_or_else(String::new, |e| study::printable(e)))
        .collect();
    out.set_item("error", errors)?;
    Ok(out)
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
    let callback = Callback::new(progress);
    let study =
        detached(py, || run(&input.scene, &ladders, &|done, total| callback.call((done, total))))?;
    callback.finish()?;
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
    let reports: Vec<impact::Report> = simulate_all(py, &scenes, progress)?
        .into_iter()
        .collect::<Result<_, _>>()
        .map_err(|e| run_error(&input, &e))?;
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
    Ok(())
}
