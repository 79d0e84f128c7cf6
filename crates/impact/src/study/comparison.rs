//! The runs of `compare`: one beam scene by both methods, against a converged reference.

use crate::error::ImpactError;
use crate::outcome::Report;
use crate::scene::{MethodName, Scene};
use crate::study::variant;

/// The reference's `solver.tolerance`: the modal method, its modes doubled until two
/// successive runs agree within it (on a `[structure]`, on its own modes, every segment's
/// elements doubled: on the frame of validation/scenes/frame-impact.toml it ends at 640
/// elements in about a second; before the stress under the ball was read at the impact point
/// (validation/REFERENCES.md 1.14) a structure's reference took 1e-2, which the first-order
/// stress brought to 2560 elements).
pub const REFERENCE_TOLERANCE: f64 = 1e-3;

/// The runs of a comparison of `scene`, each with its label: `reference` (the modal method at
/// [`REFERENCE_TOLERANCE`]), `fe` and
/// `modal` (each method at the scene's own resolution or its default), then `modal, N modes`
/// for each of `modes` and `fe, N equal elements` for each of `elements` (a `[beam]` only),
/// sorted, once each, leaving out a resolution the scene's own run already has.
///
/// # Errors
/// `Study` for a half-space (one model only), and for mode or element counts with a
/// `[structure]` (its resolution is its segments' elements).
pub fn runs(
    scene: &Scene,
    modes: &[usize],
    elements: &[usize],
) -> Result<Vec<(String, Scene)>, ImpactError> {
    if scene.structure.is_some() {
        if !(modes.is_empty() && elements.is_empty()) {
            return Err(ImpactError::Study("compare on a [structure] runs its own mesh by both methods: mode and element counts set a [beam]'s resolution, a structure's is its segments' `elements` (give another mesh as another scene file)".into()));
        }
        let mut reference = variant(scene, MethodName::Modal, None);
        reference.solver.tolerance = Some(REFERENCE_TOLERANCE);
        let mut modal = variant(scene, MethodName::Modal, None);
        modal.solver.tolerance = None;
        return Ok(vec![
            ("reference".to_string(), reference),
            ("fe".to_string(), variant(scene, MethodName::Fe, None)),
            ("modal".to_string(), modal),
        ]);
    }
    if scene.beam.is_none() {
        return Err(ImpactError::Study(
            "compare needs a [beam] or a [structure] (a [half_space] has one model only)".into(),
        ));
    }
    let fe = |n: Option<usize>| variant(scene, MethodName::Fe, n);
    let modal = |n: Option<usize>| variant(scene, MethodName::Modal, n);
    let mut modes: Vec<usize> =
        modes.iter().copied().filter(|n| scene.solver.modes != Some(*n)).collect();
    let mut elements: Vec<usize> =
        elements.iter().copied().filter(|n| scene.solver.elements != Some(*n)).collect();
    modes.sort_unstable();
    modes.dedup();
    elements.sort_unstable();
    elements.dedup();
    let mut reference = modal(None);
    reference.solver.modes = None;
    reference.solver.tolerance = Some(REFERENCE_TOLERANCE);
    // The modal method's default: the scene's own modes, else the plan's choice.
    let mut default_modal = modal(None);
    default_modal.solver.tolerance = None;
    let mut runs = vec![
        ("reference".to_string(), reference),
        ("fe".to_string(), fe(None)),
        ("modal".to_string(), default_modal),
    ];
    runs.extend(modes.iter().map(|&n| (format!("modal, {n} modes"), modal(Some(n)))));
    runs.extend(elements.iter().map(|&n| (format!("fe, {n} equal elements"), fe(Some(n)))));
    Ok(runs)
}

/// One run of a comparison as its table (`summary.csv`) shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryRow {
    /// The run, with its resolution: "reference: modal, 424 modes", "fe, 58 elements
    /// (default)", "modal, 16 modes".
    pub run: String,
    /// The first contact's duration (s); `None` without a contact.
    pub first_duration: Option<f64>,
    /// The first contact's peak force (N); `None` without a contact.
    pub peak_force: Option<f64>,
    /// The number of contacts.
    pub contact_count: usize,
    /// The largest displacement at the impact point (m).
    pub max_displacement: f64,
    /// The largest bending stress in the beam (Pa), where the method recovers it.
    pub max_bending_stress: Option<f64>,
    /// The run's wall time (s).
    pub wall_time: f64,
}

/// The columns of `summary.csv`, with their units, in [`SummaryRow`]'s order.
pub const SUMMARY_COLUMNS: [&str; 7] = [
    "run",
    "first_contact_duration_s",
    "peak_force_n",
    "contact_count",
    "max_displacement_m",
    "max_bending_stress_pa",
    "wall_time_s",
];

/// The table of a comparison: the runs of [`runs`] (their labels) with their reports, in order.
pub fn summary<'a>(runs: impl IntoIterator<Item = (&'a str, &'a Report)>) -> Vec<SummaryRow> {
    runs.into_iter()
        .map(|(label, r)| {
            let p = &r.plan;
            let first = r.contacts.first();
            SummaryRow {
                // The modal method on a structure's own modes has a mesh too.
                run: match (label, p.elements > 0) {
                    ("reference", false) => format!("reference: modal, {} modes", p.modes),
                    ("reference", true) => {
                        format!("reference: modal, {} elements, {} modes", p.elements, p.modes)
                    }
                    ("fe", _) => format!("fe, {} elements (default)", p.elements),
                    ("modal", false) => format!("modal, {} modes (default)", p.modes),
                    ("modal", true) => {
                        format!("modal, {} elements, {} modes (default)", p.elements, p.modes)
                    }
                    _ => label.to_string(),
                },
                first_duration: first.map(|c| c.duration),
                peak_force: first.map(|c| c.peak_force),
                contact_count: r.contact_count,
                max_displacement: r.max_displacement,
                max_bending_stress: r.bending_stress.as_ref().map(|b| b.max),
                wall_time: r.wall_time,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::plan::{Method, Plan};

    #[test]
    fn a_structure_is_compared_on_its_own_mesh_against_its_modal_ladder() {
        let text = include_str!("../../../../validation/scenes/frame-impact.toml");
        let scene = Scene::from_toml(text).unwrap();
        let compared = runs(&scene, &[], &[]).unwrap();
        let labels: Vec<&str> = compared.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(labels, ["reference", "fe", "modal"]);
        let plans: Vec<Plan> = compared.iter().map(|(_, s)| Plan::new(s).unwrap()).collect();
        assert!(
            matches!(&plans[0].method, Method::Modal(m) if m.tolerance == Some(REFERENCE_TOLERANCE))
        );
        assert!(matches!(plans[1].method, Method::Fe(_)));
        assert!(matches!(&plans[2].method, Method::Modal(m) if m.tolerance.is_none()));
        let err = runs(&scene, &[64], &[]).unwrap_err().to_string();
        assert!(err.contains("segments' `elements`"), "{err}");
    }
}
