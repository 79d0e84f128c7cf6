//! The text summary of `simulate`: positions named as the scene names them, and no lines for
//! quantities a run did not have.
#![allow(clippy::unwrap_used)] // a test stops on a broken fixture

use std::process::Command;

const XTASK: &str = env!("CARGO_BIN_EXE_xtask");

/// `simulate` on `scene` (TOML text), run from a scratch file named after `test`.
fn simulate(test: &str, scene: &str) -> std::process::Output {
    let dir = std::env::temp_dir().join(format!("xtask-summary-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let out = Command::new(XTASK).args(["simulate", path.to_str().unwrap()]).output().unwrap();
    std::fs::remove_dir_all(&dir).ok();
    out
}

/// The summary of `scene` (TOML text), run from a scratch file named after `test`.
fn summary(test: &str, scene: &str) -> String {
    let out = simulate(test, scene);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// The paper's strip (1.15 m cantilever) struck at 1.10 m over 0.1 ms by the modal method,
/// with `extra` in its [beam] and `offset` (m) across the width.
fn strip(extra: &str, offset: f64) -> String {
    format!(
        "name = \"strip\"\n[beam]\nlength = 1.15\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
         youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n{extra}\
         [ball]\nradius = 0.005\nmass = 0.009\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
         [impact]\nposition = 1.10\noffset = {offset}\ndrop_height = 0.2\ngravity = false\n\
         [solver]\nmethod = \"modal\"\nend_time = 1e-4\n"
    )
}

#[test]
fn twist_lines_name_a_beams_positions_x_and_a_structures_s_by_arc_length() {
    let beam = summary("beam", &strip("", 0.01));
    let twist = beam.lines().filter(|l| l.contains("twist") || l.contains("torsion shear"));
    let twist: Vec<&str> = twist.filter(|l| !l.trim_start().starts_with('-')).collect();
    assert!(twist.iter().any(|l| l.starts_with("largest torsion shear stress")), "{beam}");
    assert!(twist.iter().all(|l| !l.contains(" s = ") && !l.contains("arc length")), "{twist:?}");
    let frame = std::fs::read_to_string(format!(
        "{}/../validation/scenes/frame-impact.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("gravity = false", "gravity = false\noffset = 0.005")
    .replace("method = \"fe\"", "method = \"modal\"")
    .replace("end_time = 0.002", "end_time = 1e-4");
    let frame = summary("frame", &frame);
    let anywhere = frame.lines().find(|l| l.starts_with("largest twist anywhere")).unwrap();
    assert!(anywhere.contains(" at s = ") && anywhere.contains("m (arc length)"), "{anywhere}");
}

#[test]
fn a_centred_strike_on_a_beams_own_modes_prints_no_twist() {
    // A [beam] carrying a sensor runs on its 3D finite elements' modes, which report the
    // twist and the torsion shear: exact zeros on a centred strike, not printed.
    let text = summary("centred", &strip("[[beam.mass]]\nat = 0.9\nmass = 0.02\n", 0.0));
    assert!(text.contains("largest bending stress"), "{text}");
    let said = text.lines().filter(|l| !l.trim_start().starts_with('-'));
    assert!(said.clone().all(|l| !l.contains("twist") && !l.contains("torsion shear")), "{text}");
}

#[test]
fn a_failed_run_prints_the_plan_it_failed_on() {
    // A run that fails prints no report, and its plan (the steps, their warnings) had gone
    // unsaid: the paper's strip struck at mid-span by a 100 kg ball at 200 steps a pulse (the
    // default takes more, from the contact's local frequency; validation/REFERENCES.md 1.5), whose Newton
    // iteration diverges in the first contact.
    let scene = strip("", 0.0)
        .replace("position = 1.10", "position = 0.575")
        .replace("mass = 0.009", "mass = 100.0")
        .replace("method = \"modal\"", "method = \"fe\"\nsamples_per_pulse = 200")
        .replace("end_time = 1e-4", "end_time = 2e-4");
    let out = simulate("failed", &scene);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    let plan = err.find("the plan the run failed on").unwrap();
    let error = err.find("error: ").unwrap();
    assert!(plan < error, "{err}");
    assert!(err[plan..error].contains("200 per estimated contact duration"), "{err}");
    assert!(err[plan..error].contains("warning: the contact step"), "{err}");
}
