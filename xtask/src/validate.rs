//! `cargo xtask validate`: every case of validation/cases.toml against its reference.

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
    reference: f64,
    tolerance: f64,
    source: String,
    scene: Option<String>,
    quantity: Option<String>,
    mode: Option<usize>,
    file: Option<String>,
}

/// One result row (the JSON output of `--json`).
#[derive(Serialize)]
struct Outcome {
    id: String,
    reference: f64,
    computed: f64,
    rel_error: f64,
    tolerance: f64,
    pass: bool,
    source: String,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../validation")
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

#[allow(clippy::print_stdout)]
pub fn run(json: bool) -> anyhow::Result<bool> {
    let path = root().join("cases.toml");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let cases: Cases = toml::from_str(&text).with_context(|| format!("in {}", path.display()))?;
    let mut rows = Vec::new();
    for case in &cases.case {
        let computed = compute(case)?;
        let error = (computed - case.reference).abs();
        let rel_error = if case.reference == 0.0 { error } else { error / case.reference.abs() };
        rows.push(Outcome {
            id: case.id.clone(),
            reference: case.reference,
            computed,
            rel_error,
            tolerance: case.tolerance,
            pass: rel_error <= case.tolerance && computed.is_finite(),
            source: case.source.clone(),
        });
    }
    let all = rows.iter().all(|r| r.pass);
    if json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        println!(
            "{:<32} {:>15} {:>15} {:>10} {:>9}  {:<4}  source",
            "id", "reference", "computed", "rel error", "tolerance", ""
        );
        for r in &rows {
            println!(
                "{:<32} {:>15.8e} {:>15.8e} {:>10.2e} {:>9.0e}  {:<4}  {}",
                r.id,
                r.reference,
                r.computed,
                r.rel_error,
                r.tolerance,
                if r.pass { "pass" } else { "FAIL" },
                r.source
            );
        }
        println!("{} of {} cases pass", rows.iter().filter(|r| r.pass).count(), rows.len());
    }
    Ok(all)
}
