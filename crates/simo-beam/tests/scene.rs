//! Beam-only scene files: the standard benchmarks through the file format, and bad input.
#![allow(clippy::unwrap_used, clippy::float_cmp)] // helpers stop on bad fixtures; exact zeros are part of the contract

use simo_beam::scene::{BeamScene, SceneError};

fn scene_text(path: &str) -> String {
    std::fs::read_to_string(format!(
        "{}/../../validation/scenes/{path}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

fn scene(path: &str) -> BeamScene {
    BeamScene::from_toml(&scene_text(path)).unwrap()
}

#[test]
fn mattiasson_scene_file_matches_the_elastica() {
    // validation/REFERENCES.md 3.3, k = 10, reference from validation/reference/mattiasson.csv (elliptic
    // integrals). With 32 elements the discretisation error is ~4x the 64-element one
    // (second order; 3e-5..5e-5 at 64, see the validate cases), so 5e-4 absolute on u/L, w/L
    // and the rotation (rad) leaves margin while still catching a wrong load or support.
    let run = scene("beam-mattiasson-k10.toml").run(|_| {}).unwrap();
    let last = run.history.last().unwrap();
    assert_eq!(last.time_or_load, 1.0);
    let [x, _, z] = last.position;
    let reference = [0.554995597753751, 0.810609024880296, 1.43028553880386];
    let computed = [1.0 - x, -z, last.rotation[1]];
    for (c, r) in computed.iter().zip(reference) {
        assert!((c - r).abs() < 5e-4, "{computed:?} vs {reference:?}");
    }
    // The load path is monotone in the load factor and ends at 1.
    assert_eq!(run.history.len(), 11);
    assert!(run.history.windows(2).all(|w| w[1].time_or_load > w[0].time_or_load));
    assert_eq!(run.shape.len(), 33);
    assert_eq!(run.shape[32].position, last.position);
    // The history's first column is named with its unit: a load factor here.
    let mut csv = Vec::new();
    run.write_history_csv(&mut csv).unwrap();
    assert!(String::from_utf8(csv).unwrap().starts_with("load_factor_-,x_m,"));
}

#[test]
fn bend45_scene_file_is_the_benchmark_model() {
    // The arc, its true arc length for the load position and the stiffness form must build
    // exactly the model of simo_beam::benchmarks::bend45, so the two tips agree to round-off;
    // against Simo & Vu-Quoc (15.79, 47.23, 53.37) the 8-element mesh is within 1e-3
    // (validation/REFERENCES.md 3.2; the validate case bend45-p600 measures 8.3e-4).
    let run = scene("beam-bend45.toml").run(|_| {}).unwrap();
    let tip = run.history.last().unwrap().position;
    let bench = simo_beam::benchmarks::bend45(600.0, 8, 6).unwrap();
    for k in 0..3 {
        assert!((tip[k] - bench[k]).abs() < 1e-9 * bench.norm(), "{tip:?} vs {bench:?}");
    }
    let svq = [15.79, 47.23, 53.37];
    let err = (0..3).map(|k| (tip[k] - svq[k]).powi(2)).sum::<f64>().sqrt();
    let size = svq.iter().map(|v| v * v).sum::<f64>().sqrt();
    assert!(err / size < 1e-3, "{tip:?}");
    assert!((run.tracked_arc_length - 25.0 * std::f64::consts::PI).abs() < 1e-12);
}

#[test]
fn right_angle_scene_file_is_the_benchmark_model() {
    // The dynamic path (two joined legs, a profiled load at the elbow, trapezoidal rule) must
    // reproduce simo_beam::benchmarks::right_angle_cantilever step for step; 4 s covers the
    // loading and the first swing. After the load ends (t = 2 s) the energy stays bounded: the
    // trapezoidal rule conserves it exactly only for a linear system, and on this large swing
    // it wanders by 8e-6 relative at h = 0.05 (measured); 1e-4 catches any drift or blow-up.
    let mut s = scene("beam-right-angle.toml");
    s.dynamic.as_mut().unwrap().duration = 4.0;
    let run = s.run(|_| {}).unwrap();
    let (bench, _) = simo_beam::benchmarks::right_angle_cantilever(10, 0.05, 4.0).unwrap();
    let mut csv = Vec::new();
    run.write_history_csv(&mut csv).unwrap();
    assert!(String::from_utf8(csv).unwrap().starts_with("time_s,x_m,"));
    assert_eq!(run.history.len(), bench.len());
    for (a, (t, z)) in run.history.iter().zip(&bench) {
        assert!((a.time_or_load - t).abs() < 1e-12);
        assert!((a.position[2] - z).abs() < 1e-9, "t = {t}: {} vs {z}", a.position[2]);
    }
    let energy: Vec<f64> = run
        .history
        .iter()
        .filter(|h| h.time_or_load > 2.0 + 1e-9)
        .map(|h| h.strain_energy + h.kinetic_energy)
        .collect();
    let e0 = energy[0];
    assert!(e0 > 0.0);
    assert!(energy.iter().all(|e| (e - e0).abs() < 1e-4 * e0), "{energy:?}");
}

fn error_of(text: &str) -> String {
    let scene = match BeamScene::from_toml(text) {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    match scene.run(|_| {}) {
        Ok(_) => panic!("the scene should be refused:\n{text}"),
        Err(e) => {
            assert!(
                !matches!(e, SceneError::StaticFailed { .. } | SceneError::DynamicFailed { .. }),
                "{e}"
            );
            e.to_string()
        }
    }
}

#[test]
fn a_sharp_hairpin_whose_members_do_not_lie_in_each_other_is_a_structure() {
    // 0.57 degrees between two 1 m members 1.1e-3 m deep (sqrt(3 EI / EA) each side): they
    // overlap over 0.11 m from the joint, not over a whole member.
    let text = scene_text("beam-mattiasson-k10.toml").replacen(
        "elements = 32",
        "elements = 32\n[[segment]]\nend = [0.0, 0.01, 0.0]\nelements = 8",
        1,
    );
    let model = BeamScene::from_toml(&text).unwrap().model().unwrap();
    assert_eq!(model.mesh().elements.len(), 40);
}

#[test]
fn bad_beam_scenes_name_the_field() {
    let good = scene_text("beam-mattiasson-k10.toml");
    let cases = [
        ("elements = 32", "elements = 0", "segment[0].elements"),
        ("elements = 32", "elements = -3", "elements"),
        ("end = [1.0, 0.0, 0.0]", "end = [nan, 0.0, 0.0]", "segment[0].end"),
        ("end = [1.0, 0.0, 0.0]", "end = [0.0, 0.0, 0.0]", "segment[0].end"),
        ("axial_stiffness = 1e7 ", "axial_stiffness = -1e7", "section.axial_stiffness"),
        ("axial_stiffness = 1e7 ", "", "section.axial_stiffness is missing"),
        ("bending_stiffness = 1.0 ", "youngs_modulus = 2e11", "not both"),
        ("at = 0.0", "at = 0.01", "support[0].at"),
        ("at = 1.0\n", "at = 1.5\n", "load[0].at"),
        ("force = [0.0, 0.0, -10.0]", "force = [0.0, inf, -10.0]", "load[0].force"),
        ("load_steps = 10", "load_steps = 0", "static.load_steps"),
        ("load_steps = 10", "load_steps = 1000000000", "static.load_steps = 1000000000"),
        ("elements = 32", "elements = 1000000000", "segment[0].elements = 1000000000"),
        ("analysis = \"static\"", "analysis = \"quasi\"", "analysis"),
        ("kind = \"clamped\"", "kind = \"welded\"", "kind"),
        ("[static]", "[static]\nload_step = 3", "load_step"),
        ("analysis = \"static\"", "analysis = \"dynamic\"", "[dynamic]"),
        ("kind = \"clamped\"", "kind = \"pinned\"", "mechanism at load factor"),
        ("bending_stiffness = 1.0 ", "bending_stiffness = nan ", "section.bending_stiffness = NaN"),
        // A segment too short to mesh: refused for its length, not for its direction.
        ("end = [1.0, 0.0, 0.0]", "end = [1e-200, 0.0, 0.0]", "at least 1e-9 m from the start"),
        // A vector with a fourth number: refused, not read as its first three.
        (
            "end = [1.0, 0.0, 0.0]",
            "end = [1.0, 0.0, 0.0, 7.0]",
            "invalid length 4, expected an array of 3 numbers",
        ),
        ("force = [0.0, 0.0, -10.0]", "force = [0.0, 0.0, -10.0, \"junk\"]", "expected a number"),
        // The reader's Rust type names in words: a count is a whole number, a value a number.
        ("elements = 32", "elements = 2.5", "floating point `2.5`, expected a whole number (a count)"),
        ("elements = 32", "elements = 99999999999999999999", "(more than 64 bits), expected a whole"),
        ("load_steps = 10", "load_steps = \"ten\"", "string \"ten\", expected a whole number"),
        ("at = 0.0", "at = [0.0]", "invalid type: an array, expected a number"),
        // Points as written, [x, y, z] (nalgebra's column had printed [[1.0, 0.0, 0.0]]).
        ("end = [1.0, 0.0, 0.0]", "end = [0.0, 0.0, 0.0]", "segment[0].end = [0, 0, 0]: a point"),
        ("end = [1.0, 0.0, 0.0]", "end = [1.0, 0.0, 0.0]\ncentre = [0.0, 1.0, 0.0]", "(arc), not both"),
        // No nearest node to infinity.
        ("at = 0.0", "at = inf", "support[0].at = inf: the arc length of a node, from 0 to 1 m"),
        ("end = [1.0, 0.0, 0.0]", "end = \"far\"", "expected an array"),
        // An arc too short to mesh (radius 1e-12 m): refused for its length too (it ran, with a
        // stress 570 times the frame's at the corner).
        (
            "end = [1.0, 0.0, 0.0]",
            "centre = [0.0, 1e-12, 0.0]\nnormal = [0.0, 0.0, 1.0]\nangle_degrees = 90.0",
            "makes the arc at least 1e-9 m long",
        ),
        // A segment straight back along the one before (the members inside each other): it
        // ran, its Newton matrices refactored at most steps and its struck face barely moved.
        (
            "elements = 32",
            "elements = 32\n[[segment]]\nend = [0.0, 0.0, 0.0]\nelements = 8",
            "segment[1].end = [0.0, 0.0, 0.0]: a segment that does not fold back onto segment[0]: it runs straight back along it; here the angle between them must exceed 0.063 degrees",
        ),
        // Nearly so: sections sqrt(3 EI / EA) = 5.5e-4 m deep overlap over 11 m.
        (
            "elements = 32",
            "elements = 32\n[[segment]]\nend = [0.0, 1e-4, 0.0]\nelements = 8",
            "they meet at 0.006 degrees, so sections 0.0005477 m deep on each side of the axis overlap over 10.95 m",
        ),
        // Two supports at one node: refused, not one silently kept.
        (
            "kind = \"clamped\"",
            "kind = \"clamped\"\n[[support]]\nat = 0.0\nkind = \"pinned\"",
            "support[1].at = 0",
        ),
        // A time profile in a static analysis: refused, not ignored.
        (
            "force = [0.0, 0.0, -10.0]",
            "force = [0.0, 0.0, -10.0]\nprofile = [[0.0, 0.0], [1.0, 1.0]]",
            "load[0].profile: a static analysis",
        ),
    ];
    for (from, to, expect) in cases {
        assert!(good.contains(from), "fixture changed: {from}");
        let text = good.replacen(from, to, 1);
        let message = error_of(&text);
        assert!(message.contains(expect), "{to}: {message}");
    }
    let dynamic = scene_text("beam-right-angle.toml");
    for (from, to, expect) in [
        ("alpha = 0.0", "alpha = 0.2", "dynamic.alpha"),
        ("time_step = 0.05", "time_step = -0.05", "dynamic.time_step"),
        // Longer than the duration: it had taken one step cut to the duration, silently.
        (
            "time_step = 0.05",
            "time_step = 31.0",
            "dynamic.time_step = 31: at most dynamic.duration (30 s)",
        ),
        ("duration = 30.0", "duration = nan", "dynamic.duration"),
        ("mass_per_length = 1.0", "mass_per_length = 0.0", "section.mass_per_length"),
        (
            "profile = [[0.0, 0.0], [1.0, 50.0], [2.0, 0.0]]",
            "profile = [[1.0, 0.0], [0.0, 1.0]]",
            "load[0].profile",
        ),
        (
            "end = [10.0, 0.0, 0.0]",
            "start = [1.0, 1.0, 1.0]\nend = [10.0, 0.0, 0.0]",
            "segment[1].start",
        ),
        ("track = 20.0", "track = 20.5", "output.track"),
    ] {
        assert!(dynamic.contains(from), "fixture changed: {from}");
        let message = error_of(&dynamic.replacen(from, to, 1));
        assert!(message.contains(expect), "{to}: {message}");
    }
}

#[test]
fn hostile_beam_scenes_are_refused_by_name_or_run_clean() {
    // The hostile tour on beam scenes: one value replaced by NaN, an infinity, -0, 0, a huge
    // or tiny number, a negative one or the wrong type, or a line dropped, from a fixed
    // pseudo-random sequence. No panic; a refusal names a key of the file; a run that
    // finishes has finite positions.
    let hostile = [
        "nan", "inf", "-inf", "-0.0", "0", "1e308", "1e-300", "-1.0", "1e9", "\"x\"", "true", "[]",
    ];
    let mut seed: u64 = 99;
    let mut next = move || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (seed >> 33) as usize
    };
    let bases = [scene_text("beam-mattiasson-k10.toml"), scene_text("beam-bend45.toml")];
    let (mut refused, mut ran) = (0, 0);
    for case in 0..120 {
        let lines: Vec<&str> = bases[case % 2].lines().collect();
        let editable: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].contains(" = ") && !lines[i].trim_start().starts_with('#'))
            .collect();
        let at = editable[next() % editable.len()];
        let mut text: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        let pick = next() % (hostile.len() + 1);
        if pick == hostile.len() {
            text.remove(at);
        } else {
            let key = lines[at].split(" = ").next().unwrap_or_default();
            text[at] = format!("{key} = {}", hostile[pick]);
        }
        let text = text.join("\n");
        let keys: Vec<&str> = text
            .lines()
            .filter_map(|l| l.split_once(" = ").map(|(k, _)| k.trim()))
            .chain(["segment", "support", "load", "section", "static", "dynamic", "analysis"])
            .collect();
        let result = BeamScene::from_toml(&text).and_then(|s| s.run(|_| {}));
        match result {
            Err(e) => {
                let message = e.to_string();
                assert!(
                    keys.iter().any(|k| message.contains(k)),
                    "case {case}: no key named: {message}\n{text}"
                );
                refused += 1;
            }
            Ok(run) => {
                assert!(run.shape.iter().all(|n| n.position.iter().all(|x| x.is_finite())));
                ran += 1;
            }
        }
    }
    // Measured: 110 refused, 10 ran, of 120.
    assert!(refused > 30 && ran >= 5, "{refused} refused, {ran} ran");
}

#[test]
fn a_profile_holds_its_first_factor_before_its_first_time() {
    // The documented convention (simo_beam::Profile::Table): constant beyond both ends.
    let p = simo_beam::Profile::Table(vec![(0.5, 2.0), (1.0, 4.0)]);
    assert_eq!(p.factor(0.0), 2.0);
    assert_eq!(p.factor(0.5), 2.0);
    assert_eq!(p.factor(0.75), 3.0);
    assert_eq!(p.factor(7.0), 4.0);
    // A scene whose profile starts later with a factor other than 0 says so; one that starts
    // at [0, 0] (the right-angle cantilever's) does not.
    let late = scene_text("beam-right-angle.toml").replacen(
        "profile = [[0.0, 0.0], [1.0, 50.0], [2.0, 0.0]]",
        "profile = [[0.5, 50.0], [2.0, 0.0]]",
        1,
    );
    let mut late = BeamScene::from_toml(&late).unwrap();
    late.dynamic.as_mut().unwrap().duration = 0.05;
    let run = late.run(|_| {}).unwrap();
    assert!(
        run.warnings.iter().any(|w| w.contains("load[0].profile starts at t = 5.0000e-1 s")),
        "{:?}",
        run.warnings
    );
    let mut on_time = scene("beam-right-angle.toml");
    on_time.dynamic.as_mut().unwrap().duration = 0.05;
    assert!(on_time.run(|_| {}).unwrap().warnings.iter().all(|w| !w.contains("profile")));
}

#[test]
fn strains_beyond_the_small_strain_range_are_reported() {
    // Mattiasson's cantilever with EA = 10 N instead of 1e7: the tip force 10 N stretches it
    // by about a hundred per cent (P / EA at the clamp, less the bending's share).
    let soft = scene_text("beam-mattiasson-k10.toml").replacen(
        "axial_stiffness = 1e7",
        "axial_stiffness = 10.0",
        1,
    );
    let run = BeamScene::from_toml(&soft).unwrap().run(|_| {}).unwrap();
    assert!(
        run.warnings
            .iter()
            .any(|w| w.contains("largest axial strain") && w.contains("at load factor")),
        "{:?}",
        run.warnings
    );
    // The slender original stays within it: no warning.
    assert!(scene("beam-mattiasson-k10.toml").run(|_| {}).unwrap().warnings.is_empty());
}

#[test]
fn a_stepped_cantilever_bends_as_its_two_sections_say() {
    // A steel strip 25 mm wide, 0.6 m at 8 mm thick then 0.5 m at 4 mm (its own section),
    // clamped, 1 N down at the tip: delta = P ((L^3 - L2^3)/(3 EI1) + L2^3/(3 EI2)) (the
    // moment P (L - x) over each part's EI), 1.0445e-3 m; shear adds P (L1/GA1 + L2/GA2)
    // (below 1e-6 of it). Within 1e-3 at 32 elements a part (the one-point element's
    // 1/(4 n^2)).
    let text = r#"
name = "stepped"
analysis = "static"
[section]
youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0
width = 0.025
thickness = 0.008
[[segment]]
start = [0.0, 0.0, 0.0]
end = [0.6, 0.0, 0.0]
elements = 32
[[segment]]
end = [1.1, 0.0, 0.0]
elements = 32
[segment.section]
youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0
width = 0.025
thickness = 0.004
[[support]]
at = 0.0
kind = "clamped"
[[load]]
at = 1.1
force = [0.0, 0.0, -1.0]
"#;
    let run = BeamScene::from_toml(text).unwrap().run(|_| {}).unwrap();
    let z = -run.history.last().unwrap().position[2];
    let (e, b) = (2.1e11, 0.025);
    let (ei1, ei2) = (e * b * 0.008f64.powi(3) / 12.0, e * b * 0.004f64.powi(3) / 12.0);
    let (l, l2): (f64, f64) = (1.1, 0.5);
    let expected = (l.powi(3) - l2.powi(3)) / (3.0 * ei1) + l2.powi(3) / (3.0 * ei2);
    assert!((z / expected - 1.0).abs() < 1e-3, "{z} vs {expected}");
    // A bad key of the segment's own section is named under the segment.
    let err = BeamScene::from_toml(&text.replace("thickness = 0.004", "thickness = -0.004"))
        .unwrap()
        .run(|_| {})
        .unwrap_err()
        .to_string();
    assert!(err.contains("segment[1].section.thickness"), "{err}");
}

#[test]
fn a_beam_scene_s_modes_are_its_cantilever_s() {
    // Mattiasson's cantilever (EI = 1 N m^2 both ways, rho A = 1 kg/m by default, L = 1 m,
    // 64 elements): its lowest bending frequency 1.8751041^2 sqrt(EI / rho A) / L^2 =
    // 3.5160 rad/s, double (the same stiffness both ways), within 5e-3 (the scene's default
    // rotary inertia, 1e-3 of rho A, lowers it by about 1.8e-3). The loads play no part.
    let s = scene("beam-mattiasson-k10.toml");
    let modes = s.modes_below(5.0).unwrap();
    assert_eq!(modes.len(), 2, "{:?}", modes.iter().map(|m| m.omega).collect::<Vec<_>>());
    assert!((modes[1].omega / modes[0].omega - 1.0).abs() < 1e-10);
    let exact = 1.875_104_1_f64.powi(2);
    assert!((modes[0].omega / exact - 1.0).abs() < 5e-3, "{} vs {exact}", modes[0].omega);
    let e = s.modes_below(-1.0).unwrap_err().to_string();
    assert!(e.contains("omega_max = -1"), "{e}");
}

#[test]
fn a_segment_lowered_with_its_nodes_is_meshed_on_them() {
    // `SegmentSpec::nodes` (set by a lowering, not read from files): a straight piece's nodes
    // at the fractions given, their arc lengths the fractions times its length; a count that
    // is not elements + 1, fractions that do not rise from 0 to 1, or nodes on an arc are
    // refused.
    use simo_beam::scene::{structure, SectionSpec, SegmentSpec};
    let section = SectionSpec {
        youngs_modulus: Some(2.1e11),
        poisson_ratio: Some(0.3),
        density: Some(7850.0),
        width: Some(0.025),
        thickness: Some(0.005),
        ..Default::default()
    };
    let straight = |nodes: Vec<f64>, elements: usize| SegmentSpec {
        nodes: Some(nodes),
        ..SegmentSpec::straight(Some([0.0; 3]), [2.0, 0.0, 0.0], elements)
    };
    let (model, stations) =
        structure(&section, &[straight(vec![0.0, 0.5, 0.75, 1.0], 3)], &[]).unwrap();
    assert_eq!(stations, vec![0.0, 1.0, 1.5, 2.0]);
    let x: Vec<f64> = model.mesh().positions.iter().map(|p| p.x).collect();
    assert_eq!(x, vec![0.0, 1.0, 1.5, 2.0]);
    for (nodes, elements) in [(vec![0.0, 0.5, 1.0], 3), (vec![0.0, 0.6, 0.5, 1.0], 3)] {
        assert!(structure(&section, &[straight(nodes, elements)], &[]).is_err());
    }
    let arc = SegmentSpec {
        end: None,
        centre: Some([0.0, 1.0, 0.0]),
        normal: Some([0.0, 0.0, 1.0]),
        angle_degrees: Some(90.0),
        ..straight(vec![0.0, 0.5, 1.0], 2)
    };
    let err = structure(&section, &[arc], &[]).unwrap_err().to_string();
    assert!(err.contains("segment[0]") && err.contains("equally spaced"), "{err}");
}

#[test]
fn a_static_equilibrium_past_buckling_is_said_to_be_unstable() {
    // A cantilever (EI = 1 N m^2, L = 1 m, the Mattiasson section) under a dead axial tip
    // load: Euler's P_cr = pi^2 EI / (4 L^2) = 2.4674 N. Past it the straight beam is still an
    // equilibrium, and the load path from the unloaded beam stays on it: at 30 N (12 P_cr) the
    // tip stayed at x = 0.999997 m where the stable elastica turns it through 178 degrees to
    // x = -0.635 m (Timoshenko & Gere, Theory of Elastic Stability, sec. 2.7; a review's), with
    // no word. The tangent stiffness there has negative eigenvalues (two: both bending planes);
    // the run now says from which load factor on. At 3 N in 10 steps: 2.4 N (0.8) is stable,
    // 2.7 N (0.9) is not; at 2.4 N throughout, nothing is said.
    let run = |force: f64| {
        let text = scene_text("beam-mattiasson-k10.toml")
            .replace("force = [0.0, 0.0, -10.0]", &format!("force = [-{force}, 0.0, 0.0]"));
        assert!(text.contains(&format!("force = [-{force}, 0.0, 0.0]")), "the load was not set");
        BeamScene::from_toml(&text).unwrap().run(|_| {}).unwrap()
    };
    let said =
        |r: &simo_beam::scene::BeamRun| r.warnings.iter().find(|w| w.contains("unstable")).cloned();
    let past = said(&run(3.0)).expect("a warning past buckling");
    assert!(past.contains("from load factor 9.0000e-1") && past.contains("2 negative"), "{past}");
    assert_eq!(said(&run(2.4)), None);
}
