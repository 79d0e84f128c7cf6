//! Speed against error: the settings of a work-precision study and the errors of its runs.
//!
//! A beam scene is run by the modal method over a ladder of mode counts, with and without the
//! residual flexibility (and with two looser energy tolerances of its adaptive contact step),
//! and by the finite-element method over a ladder of uniform meshes (and other contact steps
//! and HHT alphas). Each method's errors are measured from its own converged run, at four times
//! the finest resolution of its ladder (the modal one with the residual flexibility, which
//! converges fastest: validation/REFERENCES.md 1.4); that reference is checked against a run at
//! half its resolution, and the check says how far the reference itself may be off (a third of
//! their difference: Richardson at second order, the fe element's order and below the modal
//! series'). Where both references are converged they differ by the models (the modal
//! method's linear beam with the load on its centre line against the geometrically exact beam
//! struck on its face), which no setting of either method removes.
//!
//! Unless the scene asks for Euler-Bernoulli modes, the modal method also runs its ladder with
//! Euler-Bernoulli modes (and the residual flexibility), measured from the same (Timoshenko)
//! reference: its curve levels off at what that beam theory leaves out on the scene.
//!
//! Errors are relative (-), as [`Report::differences_from`] measures them: the first contact's
//! duration and peak force, the contact sequence (the worst relative error in start, duration
//! and peak force over the significant contacts, those with a peak of at least
//! [`crate::SIGNIFICANT_PEAK`] of the first's, a missing one counting 1), the largest
//! displacement at the impact point; and the energy balance error over the impact energy.
//!
//! The references and their checks come first in [`settings`], so that a study stopped part
//! way has what its finished rows are measured against.

use crate::error::ImpactError;
use crate::outcome::{Differences, Report};
use crate::scene::{MethodName, Scene, TheoryName};
use crate::study::variant;

/// The figure's curve of the modal runs with the residual flexibility.
pub const RESIDUAL: &str = "modal, residual flexibility";

/// The figure's curve of the modal runs with Euler-Bernoulli modes (and the residual
/// flexibility), when the scene's modal runs have Timoshenko's.
pub const EULER_BERNOULLI: &str = "modal, Euler-Bernoulli modes";

/// The label's mark of a run with Euler-Bernoulli modes.
const EULER_BERNOULLI_MARK: &str = "Euler-Bernoulli modes";

/// The resolutions of a study.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ladders {
    /// The modal method's mode counts.
    pub modes: Vec<usize>,
    /// The modal reference's mode count (with the residual flexibility).
    pub modal_reference: usize,
    /// The fe method's numbers of equal elements.
    pub elements: Vec<usize>,
    /// The fe reference's number of elements.
    pub fe_reference: usize,
    /// The mode count the modal variants (energy tolerances) are run at.
    pub modal_variant: usize,
    /// The element count the fe variants (steps per pulse, alphas) are run at.
    pub fe_variant: usize,
    /// A `[structure]`'s ladder, both methods: factors on every segment's `elements`.
    pub mesh_factors: Vec<usize>,
    /// A `[structure]`'s references' factor (both methods; their checks at half of it).
    pub mesh_reference: usize,
}

impl Ladders {
    /// The full ladders: 32 to 1024 modes (reference 4096), 32 to 512 elements (reference
    /// 2048); a structure's meshes 1 to 8 times its own (reference 32).
    pub fn full() -> Self {
        Self {
            modes: vec![32, 64, 128, 256, 512, 1024],
            modal_reference: 4096,
            elements: vec![32, 64, 128, 256, 512],
            fe_reference: 2048,
            modal_variant: 512,
            fe_variant: 256,
            mesh_factors: vec![1, 2, 4, 8],
            mesh_reference: 32,
        }
    }

    /// Reduced ladders for CI: 16 to 128 modes and elements, references at 512; a structure's
    /// meshes 1 and 2 times its own (reference 8).
    pub fn quick() -> Self {
        Self {
            modes: vec![16, 32, 64, 128],
            modal_reference: 512,
            elements: vec![16, 32, 64, 128],
            fe_reference: 512,
            modal_variant: 64,
            fe_variant: 64,
            mesh_factors: vec![1, 2],
            mesh_reference: 8,
        }
    }
}

/// What a setting is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// A setting whose errors are measured.
    Run,
    /// The run at half the reference's resolution that says how far the reference may be off.
    Check,
    /// The method's converged run that errors are measured from.
    Reference,
}

/// One run of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// "modal" or "fe".
    pub method: &'static str,
    /// The figure's curve it belongs to (the method, or [`RESIDUAL`]).
    pub series: &'static str,
    /// What was set, e.g. "256 modes" or "128 elements; alpha -0.2"; unique in a study.
    pub label: String,
    /// Whether it is on the method's main ladder (mode or element counts): the figure's curves.
    pub ladder: bool,
    /// What it is for.
    pub role: Role,
    /// The scene it runs.
    pub scene: Scene,
}

/// The settings of the study of `scene`: each method's reference and check first, then the
/// ladders and the variants.
///
/// # Errors
/// `Study` when `scene` has no `[beam]` (a half-space has one model, exact to round-off).
pub fn settings(scene: &Scene, l: &Ladders) -> Result<Vec<Setting>, ImpactError> {
    if scene.structure.is_some() {
        return Ok(structure_settings(scene, l));
    }
    if scene.beam.is_none() {
        return Err(ImpactError::Study(
            "accuracy needs a [beam] or a [structure] (a [half_space] has one model, exact to round-off)"
                .into(),
        ));
    }
    let modal = |n: usize| variant(scene, MethodName::Modal, Some(n));
    let residual = |n: usize| {
        let mut s = modal(n);
        s.solver.residual_flexibility = Some(true);
        s
    };
    let fe = |n: usize| variant(scene, MethodName::Fe, Some(n));
    let mut out = Vec::new();
    let mut add = |method, label: String, ladder, role, scene| {
        let series = if label.contains(EULER_BERNOULLI_MARK) {
            EULER_BERNOULLI
        } else if label.contains("residual flexibility") {
            RESIDUAL
        } else {
            method
        };
        out.push(Setting { method, series, label, ladder, role, scene });
    };
    // The modal reference with the residual flexibility: the same beam model as the ladder,
    // converged far faster (validation/REFERENCES.md 1.4).
    for (n, role) in [(l.modal_reference, Role::Reference), (l.modal_reference / 2, Role::Check)] {
        let tag = if role == Role::Reference { "reference" } else { "check" };
        add("modal", format!("{n} modes; residual flexibility ({tag})"), false, role, residual(n));
    }
    for (n, role) in [(l.fe_reference, Role::Reference), (l.fe_reference / 2, Role::Check)] {
        let tag = if role == Role::Reference { "reference" } else { "check" };
        add("fe", format!("{n} elements ({tag})"), false, role, fe(n));
    }
    for &n in &l.modes {
        add("modal", format!("{n} modes"), true, Role::Run, modal(n));
    }
    for &n in &l.modes {
        add("modal", format!("{n} modes; residual flexibility"), true, Role::Run, residual(n));
    }
    if scene.solver.beam_theory != Some(TheoryName::EulerBernoulli) {
        for &n in &l.modes {
            let mut s = residual(n);
            s.solver.beam_theory = Some(TheoryName::EulerBernoulli);
            let label = format!("{n} modes; residual flexibility; {EULER_BERNOULLI_MARK}");
            add("modal", label, true, Role::Run, s);
        }
    }
    for tol in [1e-4, 1e-5] {
        let mut s = modal(l.modal_variant);
        s.solver.energy_tolerance = Some(tol);
        let label = format!("{} modes; energy tolerance {tol:e}", l.modal_variant);
        add("modal", label, false, Role::Run, s);
    }
    for &n in &l.elements {
        add("fe", format!("{n} elements"), true, Role::Run, fe(n));
    }
    for samples in [100, 400] {
        let mut s = fe(l.fe_variant);
        s.solver.samples_per_pulse = Some(samples);
        let label = format!("{} elements; {samples} steps per pulse", l.fe_variant);
        add("fe", label, false, Role::Run, s);
    }
    for alpha in [0.0, -0.2] {
        let mut s = fe(l.fe_variant);
        s.solver.alpha = Some(alpha);
        add("fe", format!("{} elements; alpha {alpha}", l.fe_variant), false, Role::Run, s);
    }
    Ok(out)
}

/// The settings of a `[structure]`: both methods on the same meshes, every segment's
/// `elements` times each of `l.mesh_factors` (the modal method on each mesh's own modes, its
/// residual flexibility on), the references at `l.mesh_reference` times, their checks at half
/// that; the variants (the modal method's energy tolerances, the fe method's steps per pulse and
/// alphas) on twice the scene's mesh.
fn structure_settings(scene: &Scene, l: &Ladders) -> Vec<Setting> {
    let elements: usize =
        scene.structure.as_ref().map_or(0, |st| st.segments.iter().map(|s| s.elements).sum());
    let on = |method: MethodName, factor: usize| {
        let mut s = variant(scene, method, None);
        s.solver.tolerance = None;
        if let Some(st) = s.structure.as_mut() {
            for seg in &mut st.segments {
                seg.elements *= factor;
            }
        }
        s
    };
    let label = |method: &str, factor: usize| {
        let own = if method == "modal" { "; own modes" } else { "" };
        format!("{} elements{own}", elements * factor)
    };
    let mut out = Vec::new();
    for (method, name) in [(MethodName::Modal, "modal"), (MethodName::Fe, "fe")] {
        for (factor, role) in
            [(l.mesh_reference, Role::Reference), (l.mesh_reference / 2, Role::Check)]
        {
            let tag = if role == Role::Reference { "reference" } else { "check" };
            let scene = on(method, factor);
            out.push(Setting {
                method: name,
                series: name,
                label: format!("{} ({tag})", label(name, factor)),
                ladder: false,
                role,
                scene,
            });
        }
    }
    for (method, name) in [(MethodName::Modal, "modal"), (MethodName::Fe, "fe")] {
        for &factor in &l.mesh_factors {
            out.push(Setting {
                method: name,
                series: name,
                label: label(name, factor),
                ladder: true,
                role: Role::Run,
                scene: on(method, factor),
            });
        }
    }
    for tol in [1e-4, 1e-5] {
        let mut s = on(MethodName::Modal, 2);
        s.solver.energy_tolerance = Some(tol);
        let label = format!("{}; energy tolerance {tol:e}", label("modal", 2));
        out.push(Setting {
            method: "modal",
            series: "modal",
            label,
            ladder: false,
            role: Role::Run,
            scene: s,
        });
    }
    for samples in [100, 400] {
        let mut s = on(MethodName::Fe, 2);
        s.solver.samples_per_pulse = Some(samples);
        let label = format!("{}; {samples} steps per pulse", label("fe", 2));
        out.push(Setting {
            method: "fe",
            series: "fe",
            label,
            ladder: false,
            role: Role::Run,
            scene: s,
        });
    }
    for alpha in [0.0, -0.2] {
        let mut s = on(MethodName::Fe, 2);
        s.solver.alpha = Some(alpha);
        let label = format!("{}; alpha {alpha}", label("fe", 2));
        out.push(Setting {
            method: "fe",
            series: "fe",
            label,
            ladder: false,
            role: Role::Run,
            scene: s,
        });
    }
    out
}

/// One measured setting.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// "modal" or "fe".
    pub method: &'static str,
    /// The figure's curve.
    pub series: &'static str,
    /// What was set.
    pub setting: String,
    /// Whether it is on the main ladder.
    pub ladder: bool,
    /// Whether it is its method's check run.
    pub check: bool,
    /// Its wall time (s).
    pub wall_time: f64,
    /// Its errors from its method's reference.
    pub errors: Differences,
    /// Its energy balance error over the impact energy (-).
    pub energy_balance: f64,
}

/// The numeric columns of the study's table (`work_precision.csv`, after `method` and
/// `setting`), in [`Row::values`]'s order.
pub const ROW_COLUMNS: [&str; 7] = [
    "wall_time_s",
    "error_first_duration",
    "error_first_peak_force",
    "error_contact_sequence",
    "error_max_displacement",
    "error_max_stress",
    "energy_balance",
];

impl Row {
    /// The error a setting is judged by: the worst of the four.
    pub fn worst(&self) -> f64 {
        self.errors.worst()
    }

    /// The wall time, the five relative errors and the energy balance, as [`ROW_COLUMNS`].
    pub fn values(&self) -> [f64; 7] {
        let e = &self.errors;
        [
            self.wall_time,
            e.first_duration,
            e.first_peak_force,
            e.contact_sequence,
            e.max_displacement,
            e.max_stress,
            self.energy_balance,
        ]
    }
}

/// Runs the study of `scene` over `ladders`: every setting one after another (a wall time
/// shared with another run on the same cores is not the setting's cost), `progress(done,
/// total)` after each; the study of their reports.
///
/// # Errors
/// What [`settings`] refuses; a run's error, naming its setting; what [`Study::new`] refuses.
pub fn run(
    scene: &Scene,
    ladders: &Ladders,
    progress: &dyn Fn(usize, usize),
) -> Result<Study, ImpactError> {
    let all = settings(scene, ladders)?;
    let mut reports = Vec::with_capacity(all.len());
    for (i, s) in all.iter().enumerate() {
        let outcome = crate::simulate(&s.scene)
            .map_err(|e| ImpactError::Study(format!("setting {}: {e}", s.label)))?;
        reports.push(outcome.report);
        progress(i + 1, all.len());
    }
    Study::new(&scene.name, &all, &reports)
}

/// A method's reference and how far it may itself be off.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// "modal" or "fe".
    pub method: &'static str,
    /// Its setting.
    pub setting: String,
    /// A third of its worst difference from the check run (half its resolution).
    pub estimated_error: f64,
    /// The check's setting.
    pub check: String,
}

/// The study of one scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// The scene's name.
    pub name: String,
    /// The measured settings, each method's ladder and variants, then its check.
    pub rows: Vec<Row>,
    /// Each method's reference.
    pub references: Vec<Reference>,
    /// The differences between the two methods' references (the modal one's from the fe one's).
    pub model_difference: Differences,
    /// The beam theory of the modal reference.
    pub modal_theory: Option<TheoryName>,
    /// The errors of the finest run with Euler-Bernoulli modes (from the modal reference),
    /// when there are such runs: what that theory leaves out on the scene.
    pub theory_difference: Option<Differences>,
    /// Whether the scene is a `[structure]` (both methods on its 3D beam: the modal one
    /// linearised at rest, the fe one geometrically exact).
    pub structure: bool,
}

impl Study {
    /// The study of `name` from the reports of `settings` (one each, in order).
    ///
    /// # Errors
    /// `Study` when the counts differ or a method's reference or check is missing.
    pub fn new(name: &str, settings: &[Setting], reports: &[Report]) -> Result<Self, ImpactError> {
        if settings.len() != reports.len() {
            return Err(ImpactError::Study(format!(
                "{} settings but {} reports",
                settings.len(),
                reports.len()
            )));
        }
        let find = |method: &str, role: Role| {
            settings.iter().position(|s| s.method == method && s.role == role).ok_or_else(|| {
                ImpactError::Study(format!("the {method} method has no {role:?} setting"))
            })
        };
        let mut rows = Vec::new();
        let mut references = Vec::new();
        for method in ["modal", "fe"] {
            let (reference, check) = (find(method, Role::Reference)?, find(method, Role::Check)?);
            let r = &reports[reference];
            references.push(Reference {
                method,
                setting: settings[reference].label.clone(),
                estimated_error: reports[check].differences_from(r).worst() / 3.0,
                check: settings[check].label.clone(),
            });
            let mut measured: Vec<Row> = settings
                .iter()
                .zip(reports)
                .filter(|(s, _)| s.method == method && s.role != Role::Reference)
                .map(|(s, report)| {
                    let e = &report.energy;
                    Row {
                        method,
                        series: s.series,
                        setting: s.label.clone(),
                        ladder: s.ladder,
                        check: s.role == Role::Check,
                        wall_time: report.wall_time,
                        errors: report.differences_from(r),
                        energy_balance: if e.initial > 0.0 {
                            e.balance_error.abs() / e.initial
                        } else {
                            0.0
                        },
                    }
                })
                .collect();
            // The check after the settings it says something about.
            measured.sort_by_key(|row| row.check);
            rows.extend(measured);
        }
        let modal_reference = &reports[find("modal", Role::Reference)?];
        let model_difference =
            modal_reference.differences_from(&reports[find("fe", Role::Reference)?]);
        // The ladder's rows come in increasing resolution: the last is the finest.
        let theory_difference =
            rows.iter().rev().find(|r| r.series == EULER_BERNOULLI && r.ladder).map(|r| r.errors);
        Ok(Self {
            name: name.to_string(),
            rows,
            references,
            model_difference,
            modal_theory: modal_reference.plan.beam_theory,
            theory_difference,
            structure: settings.iter().any(|s| s.scene.structure.is_some()),
        })
    }

    /// The cheapest setting of `method` whose worst error is within `target`.
    pub fn cheapest(&self, method: &str, target: f64) -> Option<&Row> {
        // Not the check run: its errors define the reference's own (a third of them), so
        // naming it the cheapest setting was circular (a review's); the chart leaves it out too.
        self.rows
            .iter()
            .filter(|r| r.method == method && !r.check && r.worst() <= target)
            .min_by(|a, b| a.wall_time.total_cmp(&b.wall_time))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::Plan;

    fn scene() -> Scene {
        let mut s =
            Scene::from_toml(include_str!("../../../../validation/scenes/paper-tip.toml")).unwrap();
        // Modal-only keys that the fe settings must drop.
        s.solver.residual_flexibility = Some(false);
        s.solver.adaptive_step = Some(true);
        s
    }

    #[test]
    fn every_setting_is_a_valid_scene_with_a_unique_label_and_references_come_first() {
        let all = settings(&scene(), &Ladders::quick()).unwrap();
        for s in &all {
            Plan::new(&s.scene).unwrap_or_else(|e| panic!("{}: {e}", s.label));
            assert_eq!(all.iter().filter(|t| t.label == s.label).count(), 1, "{}", s.label);
            assert!(!s.label.contains(','), "a CSV field: {}", s.label);
        }
        assert!(all[..4].iter().all(|s| s.role != Role::Run));
        assert!(all[4..].iter().all(|s| s.role == Role::Run));
        // The Euler-Bernoulli ladder runs Euler-Bernoulli modes, and only where the scene's
        // modal runs may have Timoshenko's.
        let theory = |s: &Setting| Plan::new(&s.scene).unwrap().summary().beam_theory;
        let euler_bernoulli: Vec<&Setting> =
            all.iter().filter(|s| s.series == EULER_BERNOULLI).collect();
        assert_eq!(euler_bernoulli.len(), Ladders::quick().modes.len());
        assert!(euler_bernoulli
            .iter()
            .all(|s| s.ladder && theory(s) == Some(TheoryName::EulerBernoulli)));
        let reference = all.iter().find(|s| s.method == "modal" && s.role == Role::Reference);
        assert_eq!(reference.map(theory), Some(Some(TheoryName::Timoshenko)));
        let mut asked = scene();
        asked.solver.beam_theory = Some(TheoryName::EulerBernoulli);
        let asked = settings(&asked, &Ladders::quick()).unwrap();
        assert!(asked.iter().all(|s| s.series != EULER_BERNOULLI));
        let mut half = scene();
        half.beam = None;
        assert!(settings(&half, &Ladders::quick()).is_err());
    }

    #[test]
    fn a_structure_is_studied_on_its_meshes_by_both_methods() {
        // The frame (80 elements): both methods on 80 and 160 elements, the references on 640,
        // their checks on 320; each setting a valid scene with its own label.
        let text = include_str!("../../../../validation/scenes/frame-impact.toml");
        let frame = Scene::from_toml(text).unwrap();
        let all = settings(&frame, &Ladders::quick()).unwrap();
        for s in &all {
            let plan = Plan::new(&s.scene).unwrap_or_else(|e| panic!("{}: {e}", s.label));
            assert_eq!(plan.summary().method.to_string(), s.method, "{}", s.label);
            assert_eq!(all.iter().filter(|t| t.label == s.label).count(), 1, "{}", s.label);
            assert!(!s.label.contains(','), "a CSV field: {}", s.label);
        }
        let labels: Vec<&str> = all.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(
            labels[..8],
            [
                "640 elements; own modes (reference)",
                "320 elements; own modes (check)",
                "640 elements (reference)",
                "320 elements (check)",
                "80 elements; own modes",
                "160 elements; own modes",
                "80 elements",
                "160 elements",
            ]
        );
        assert!(all[4..].iter().all(|s| s.role == Role::Run));
    }

    #[test]
    fn the_cheapest_setting_meets_every_error() {
        let row = |setting: &str, wall_time: f64, worst: f64| Row {
            method: "modal",
            series: "modal",
            setting: setting.into(),
            ladder: true,
            check: false,
            wall_time,
            errors: Differences {
                first_duration: worst / 10.0,
                first_peak_force: worst,
                contact_sequence: worst / 2.0,
                max_displacement: 0.0,
                max_stress: worst / 4.0,
                same_contacts: true,
            },
            energy_balance: 1e-7,
        };
        let study = Study {
            name: "test".into(),
            rows: vec![
                row("16 modes", 0.001, 3e-2),
                row("64 modes", 0.002, 5e-3),
                row("256 modes", 0.004, 4e-4),
            ],
            references: vec![],
            model_difference: row("reference", 0.0, 1e-3).errors,
            modal_theory: None,
            theory_difference: None,
            structure: false,
        };
        // Within 1e-2: 64 modes (16 fails on its peak force); within 1e-3: 256.
        assert_eq!(study.cheapest("modal", 1e-2).map(|r| r.setting.as_str()), Some("64 modes"));
        assert_eq!(study.cheapest("modal", 1e-3).map(|r| r.setting.as_str()), Some("256 modes"));
        assert!(study.cheapest("fe", 1e-2).is_none());
    }
}
