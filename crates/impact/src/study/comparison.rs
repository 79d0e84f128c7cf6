//! The runs of `compare`: one beam scene by both methods, against a converged reference.

use crate::scene::{MethodName, Scene};
use crate::study::variant;

/// The reference's `solver.tolerance`: the modal method, its modes doubled until two
/// successive runs agree within it.
pub const REFERENCE_TOLERANCE: f64 = 1e-3;

/// The runs of a comparison of `scene`, each with its label: `reference` (the modal method at
/// [`REFERENCE_TOLERANCE`]), `fe` and `modal` (each method at the scene's own resolution or its
/// default), then `modal, N modes` for each of `modes` and `fe, N equal elements` for each of
/// `elements`, sorted, once each, leaving out a resolution the scene's own run already has.
pub fn runs(scene: &Scene, modes: &[usize], elements: &[usize]) -> Vec<(String, Scene)> {
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
    runs
}
