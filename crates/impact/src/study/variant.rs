//! The scene of one method at one resolution.

use crate::scene::{MethodName, Scene};

/// `scene` run by `method` (modal or fe), at `resolution` (modes or equal elements) when
/// given, else at the scene's own resolution of that method (its modes or mesh, or its
/// `solver.tolerance`). The other method's keys are dropped, so that any valid beam scene
/// gives valid variants: the modal method's `modes`, `residual_flexibility`,
/// `plain_stress_series`, `adaptive_step`, `energy_tolerance`, `beam_theory` and
/// `modal_basis`; the fe method's `elements`, `element_size`, `alpha` and
/// `time_step`. A given resolution replaces `solver.tolerance` (which would choose its own)
/// and a graded mesh. Shared keys (`end_time`, `samples_per_pulse`, `output_interval`) stay.
///
/// [`MethodName::Auto`] keeps the scene as written.
pub fn variant(scene: &Scene, method: MethodName, resolution: Option<usize>) -> Scene {
    let mut s = scene.clone();
    let solver = &mut s.solver;
    match method {
        MethodName::Auto => return s,
        MethodName::Modal => {
            solver.elements = None;
            solver.element_size = None;
            solver.alpha = None;
            solver.fe_model = None;
            solver.time_step = None;
            if resolution.is_some() {
                solver.modes = resolution;
                solver.tolerance = None;
            }
        }
        MethodName::Fe => {
            solver.modes = None;
            solver.residual_flexibility = None;
            solver.plain_stress_series = None;
            solver.adaptive_step = None;
            solver.energy_tolerance = None;
            solver.beam_theory = None;
            solver.modal_basis = None;
            if resolution.is_some() {
                solver.elements = resolution;
                solver.element_size = None;
                solver.tolerance = None;
            }
        }
    }
    solver.method = method;
    s
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::Plan;

    #[test]
    fn variants_of_a_scene_with_either_methods_keys_are_valid() {
        let text = include_str!("../../../../validation/scenes/paper-tip.toml");
        let mut modal = Scene::from_toml(text).unwrap();
        modal.solver.method = MethodName::Modal;
        modal.solver.residual_flexibility = Some(true);
        modal.solver.energy_tolerance = Some(1e-4);
        modal.solver.beam_theory = Some(crate::TheoryName::EulerBernoulli);
        modal.solver.modal_basis = Some(crate::ModalBasisName::Analytic);
        let mut fe = variant(&modal, MethodName::Fe, None);
        fe.solver.alpha = Some(-0.1);
        fe.solver.element_size = Some(0.02);
        for (from, method, resolution) in [
            (&modal, MethodName::Fe, None),
            (&modal, MethodName::Fe, Some(16)),
            (&fe, MethodName::Modal, None),
            (&fe, MethodName::Modal, Some(32)),
            (&fe, MethodName::Fe, Some(16)),
        ] {
            let v = variant(from, method, resolution);
            Plan::new(&v).unwrap_or_else(|e| panic!("{method:?} {resolution:?}: {e}"));
        }
        let v = variant(&fe, MethodName::Fe, Some(16));
        assert_eq!((v.solver.elements, v.solver.element_size), (Some(16), None));
        assert_eq!(v.solver.alpha, Some(-0.1), "the fe keys stay in an fe variant");
        assert_eq!(variant(&modal, MethodName::Modal, None).solver.modes, modal.solver.modes);
    }
}
