//! `cargo xtask validate`: every case of validation/cases.toml against its reference.

use crate::files::say;
use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Cases {
    case: Vec<Case>,
}

/// One validation case as written in validation/cases.toml.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    id: String,
    /// `scene` (run a scene, read a report value by JSON pointer), `cantilever-eigenvalue`,
    /// `tip-compliance-sum`, `mode-shape`.
    kind: String,
    /// A number, or a list for vector quantities; omitted where the kind computes it (the
    /// closed-form Euler-Bernoulli frequencies).
    reference: Option<Value>,
    tolerance: f64,
    source: String,
    scene: Option<String>,
    quantity: Option<String>,
    mode: Option<usize>,
    file: Option<String>,
    /// Beam benchmarks: number of elements (per leg for the right-angle frame).
    elements: Option<usize>,
    /// Beam benchmarks: the load parameter (turns, k = PL^2/EI, or P).
    load: Option<f64>,
    /// Beam benchmarks: equal load increments.
    load_steps: Option<usize>,
    /// HHT cases: alpha and Omega = omega h.
    alpha: Option<f64>,
    omega_h: Option<f64>,
    /// Hard cases: KEY=VALUE settings applied to `scene` (as `sweep --set` takes them).
    set: Option<Vec<String>>,
}

/// A scalar or a vector quantity.
#[derive(Deserialize, Serialize, Clone, Debug)]
#[serde(untagged)]
enum Value {
    Scalar(f64),
    Vector(Vec<f64>),
}

impl Value {
    fn as_vec(&self) -> Vec<f64> {
        match self {
            Value::Scalar(x) => vec![*x],
            Value::Vector(v) => v.clone(),
        }
    }
}

/// One result row (the JSON output of `--json`).
#[derive(Serialize)]
struct Outcome {
    id: String,
    reference: Value,
    computed: Value,
    rel_error: f64,
    tolerance: f64,
    pass: bool,
    source: String,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../validation")
}

/// Euler-Bernoulli frequencies (Hz) of the paper's cantilever, validation/REFERENCES.md 1.1, from the
/// modal crate's eigenvalues.
fn euler_bernoulli_frequencies(count: usize) -> anyhow::Result<Vec<f64>> {
    let beam =
        modal::Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, modal::Support::ClampedFree)?;
    Ok(beam.modes(count)?.iter().map(|m| m.omega / (2.0 * std::f64::consts::PI)).collect())
}

/// Computes the case's quantity, and its reference where the kind derives it.
fn compute_value(case: &Case) -> anyhow::Result<(Value, Option<Value>)> {
    use simo_beam::benchmarks as b;
    let elements = || case.elements.with_context(|| format!("case {} needs `elements`", case.id));
    let load = || case.load.with_context(|| format!("case {} needs `load`", case.id));
    let steps = || case.load_steps.with_context(|| format!("case {} needs `load_steps`", case.id));
    let alpha = || case.alpha.with_context(|| format!("case {} needs `alpha`", case.id));
    let omega_h = || case.omega_h.with_context(|| format!("case {} needs `omega_h`", case.id));
    let v = |x: Vec<f64>| Ok((Value::Vector(x), None));
    match case.kind.as_str() {
        "rollup" => {
            let (tip, rotation, _) = b::roll_up(load()?, elements()?)?;
            v(vec![tip.x, tip.z, rotation])
        }
        "mattiasson" => v(b::mattiasson(load()?, elements()?, steps()?)?.to_vec()),
        "bend45" => v(b::bend45(load()?, elements()?, steps()?)?.iter().copied().collect()),
        "bend45-path" => {
            let a = b::bend45(load()?, elements()?, 8)?;
            let c = b::bend45(load()?, elements()?, 10)?;
            Ok((Value::Scalar((a - c).norm()), None))
        }
        "shear-locking" => Ok((Value::Scalar(b::shear_locking_ratio(elements()?)?), None)),
        "cantilever-frequencies" => {
            let fe = b::paper_cantilever_flexural_frequencies(elements()?, 10)?;
            Ok((Value::Vector(fe), Some(Value::Vector(euler_bernoulli_frequencies(10)?))))
        }
        "hht-spectral-radius" => {
            let s = hht::spectrum(hht::Scheme::hht(alpha()?)?, omega_h()?);
            // Beyond the bifurcation there is no oscillating pair; the radius still exists.
            let radius = match s {
                Ok(s) => s.radius,
                Err(_) => hht::amplification(hht::Scheme::hht(alpha()?)?, omega_h()?)?
                    .complex_eigenvalues()
                    .iter()
                    .map(|z| z.norm())
                    .fold(0.0, f64::max),
            };
            Ok((Value::Scalar(radius), None))
        }
        "hht-damping-ratio" => Ok((
            Value::Scalar(hht::spectrum(hht::Scheme::hht(alpha()?)?, omega_h()?)?.damping_ratio),
            None,
        )),
        "hht-period-error" => Ok((
            Value::Scalar(hht::spectrum(hht::Scheme::hht(alpha()?)?, omega_h()?)?.period_error),
            None,
        )),
        "right-angle-cantilever" => {
            let (tip, _) = b::right_angle_cantilever(elements()?, 0.05, 30.0)?;
            let peak = tip.iter().filter(|s| s.0 < 10.0).map(|s| s.1).fold(f64::MIN, f64::max);
            let trough = tip
                .iter()
                .filter(|s| s.0 > 10.0 && s.0 < 20.0)
                .map(|s| s.1)
                .fold(f64::MAX, f64::min);
            v(vec![peak, trough])
        }
        _ => Ok((Value::Scalar(compute(case)?), None)),
    }
}

/// A hard case: the scene with the case's settings, run; the result is the energy ledger's
/// balance error relative to the energy that moved (initial kinetic, gravity's work, beam,
/// dissipated, numerical), or infinity for a report with a non-finite number or against plain
/// physics (no contact at all, a negative largest displacement, an elastic bounce that gives
/// back more than it got).
fn hard_case(scene: &Path, case: &Case) -> anyhow::Result<f64> {
    use impact::study::{Axis, Grid};
    let text = std::fs::read_to_string(scene)
        .with_context(|| format!("cannot read {}", scene.display()))?;
    let base: toml::Table = toml::from_str(&text)?;
    let axes =
        case.set.iter().flatten().map(|s| Axis::parse(s, &[])).collect::<Result<Vec<_>, _>>()?;
    let scene = if axes.is_empty() {
        impact::Scene::from_toml(&text)?
    } else {
        Grid::new(axes)?.scene(&base, 0)?
    };
    let report = impact::simulate(&scene)?.report;
    let json = serde_json::to_value(&report)?;
    let finite = |v: &serde_json::Value| -> bool {
        fn walk(v: &serde_json::Value) -> bool {
            match v {
                serde_json::Value::Number(n) => n.as_f64().is_some_and(f64::is_finite),
                serde_json::Value::Array(a) => a.iter().all(walk),
                serde_json::Value::Object(o) => o.values().all(walk),
                _ => true,
            }
        }
        walk(v)
    };
    let e = &report.energy;
    let elastic = report.plan.contact_law == impact::LawName::Hertz;
    let on_a_block = report.plan.method == impact::MethodKind::HalfSpace;
    let gives_back_more =
        elastic && on_a_block && report.restitution.is_some_and(|r| r > 1.0 + 1e-6);
    if !finite(&json)
        || report.contact_count == 0
        || report.max_displacement < 0.0
        || gives_back_more
    {
        return Ok(f64::INFINITY);
    }
    let moved =
        e.initial + e.ball_potential.abs() + e.beam + e.dissipated + e.numerical_dissipation.abs();
    Ok(e.balance_error.abs() / moved)
}

fn compute(case: &Case) -> anyhow::Result<f64> {
    let need = |o: &Option<String>, what: &str| {
        o.clone().with_context(|| format!("case {}: kind {} needs `{what}`", case.id, case.kind))
    };
    match case.kind.as_str() {
        "scene" => {
            let outcome = crate::simulate::load_and_run(&root().join(need(&case.scene, "scene")?))?;
            let json = serde_json::to_value(&outcome.report)?;
            let pointer = need(&case.quantity, "quantity")?;
            json.pointer(&pointer)
                .and_then(serde_json::Value::as_f64)
                .with_context(|| format!("case {}: no number at {pointer} in the report", case.id))
        }
        "hard-case" => hard_case(&root().join(need(&case.scene, "scene")?), case),
        "cantilever-eigenvalue" => {
            Ok(modal::Support::ClampedFree.eigenvalue(case.mode.context("needs `mode`")?)?)
        }
        "tip-compliance-sum" => {
            let n = case.mode.context("needs `mode` (number of modes)")?;
            (1..=n).map(|k| Ok(4.0 / modal::Support::ClampedFree.eigenvalue(k)?.powi(4))).sum()
        }
        "mode-shape" => {
            // Largest |phi_computed - phi_reference| over the reference file's points (textbook
            // scaling, so values are O(1) and the error is absolute); reference 0.
            let n = case.mode.context("needs `mode`")?;
            let text = std::fs::read_to_string(root().join(need(&case.file, "file")?))?;
            let beam = modal::Beam::new(1.0, 1.0, 1.0, modal::Support::ClampedFree)?;
            let shape = beam.modes(n)?[n - 1].shape;
            let mut worst: f64 = 0.0;
            for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
                let v: Vec<f64> = line.split(',').map(str::parse).collect::<Result<_, _>>()?;
                worst = worst.max((shape.value(v[0]) - v[1]).abs());
            }
            Ok(worst)
        }
        other => anyhow::bail!("case {}: unknown kind {other}", case.id),
    }
}

pub(crate) fn run(json: bool) -> anyhow::Result<bool> {
    let path = root().join("cases.toml");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let cases: Cases = toml::from_str(&text).with_context(|| format!("in {}", path.display()))?;
    let mut rows = Vec::new();
    for case in &cases.case {
        let (computed, derived) = compute_value(case)?;
        let reference = derived
            .or_else(|| case.reference.clone())
            .with_context(|| format!("case {} has no reference", case.id))?;
        let (c, r) = (computed.as_vec(), reference.as_vec());
        anyhow::ensure!(
            c.len() == r.len(),
            "case {}: {} values against {} references",
            case.id,
            c.len(),
            r.len()
        );
        // Relative error of the vector (2-norm); absolute where the reference is zero.
        let error = c.iter().zip(&r).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
        let size = r.iter().map(|x| x * x).sum::<f64>().sqrt();
        let rel_error = if size == 0.0 { error } else { error / size };
        rows.push(Outcome {
            id: case.id.clone(),
            reference,
            computed: computed.clone(),
            rel_error,
            tolerance: case.tolerance,
            pass: rel_error <= case.tolerance && c.iter().all(|x| x.is_finite()),
            source: case.source.clone(),
        });
    }
    let all = rows.iter().all(|r| r.pass);
    if json {
        say!("{}", serde_json::to_string_pretty(&rows)?)?;
    } else {
        say!(
            "{:<32} {:>15} {:>15} {:>10} {:>9}  {:<4}  source",
            "id",
            "reference",
            "computed",
            "rel error",
            "tolerance",
            ""
        )?;
        let show = |v: &Value| match v {
            Value::Scalar(x) => format!("{x:.8e}"),
            Value::Vector(x) if x.len() <= 3 => {
                format!("[{}]", x.iter().map(|y| format!("{y:.6}")).collect::<Vec<_>>().join(", "))
            }
            Value::Vector(x) => format!("[{:.6}, ... {} values]", x[0], x.len()),
        };
        for r in &rows {
            say!(
                "{:<32} {:>15} {:>15} {:>10.2e} {:>9.0e}  {:<4}  {}",
                r.id,
                show(&r.reference),
                show(&r.computed),
                r.rel_error,
                r.tolerance,
                if r.pass { "pass" } else { "FAIL" },
                r.source
            )?;
        }
        say!("{} of {} cases pass", rows.iter().filter(|r| r.pass).count(), rows.len())?;
    }
    Ok(all)
}
