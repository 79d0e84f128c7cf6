//! The finite-element method's bending stress, from the elements' section strains.
//!
//! Each element's rotation is linear, so its curvature kappa = (theta_2 - theta_1)/l_e and its
//! extension are constant over it: their mean, most accurate at the element's midpoint, where
//! the stress is recovered. On the struck face (+z at rest, the ball's side; w = -z), the fibre
//! strain is extension - (h/2) kappa, so sigma = E (extension - (h/2) kappa): the bending stress
//! M (h/2)/I with tension positive on the struck face, plus the axial stress N/A of the same
//! fibre. A clamp's stress is extrapolated linearly from its two nearest midpoints; a pinned
//! end holds no moment and reports its zero (its axial stress aside). The envelope is observed
//! at every accepted step.

use super::observe::{BeamRecorder, BeamView, Instant};
use crate::outcome::{BendingStress, Envelope, Field};
use simo_beam::{PlanarState, Support};

/// The fe beam seen as a stress field.
pub(crate) struct FeStress {
    /// E (Pa) and h/2 (m).
    youngs_modulus: f64,
    half_thickness: f64,
    /// Each element's (E, h/2, EI) where they differ (a stepped structure); empty otherwise.
    sections: Vec<(f64, f64, f64)>,
    /// Element count; the envelope's points are the midpoints, then the supports.
    elements: usize,
    /// For each support, in the order of its envelope point after the midpoints: whether it
    /// is a clamp, its two nearest elements and the extrapolation weight.
    supports: Vec<(bool, [usize; 2], f64)>,
    stresses: Vec<f64>,
    /// The time of the last instant in the envelope (s).
    observed: Option<f64>,
    envelope: Envelope,
    /// EI (N m^2), set with the field (the moment is only the field's).
    flexural_rigidity: f64,
    /// The field at the nodes, when asked.
    field: Option<Field>,
}

impl FeStress {
    /// The stress field of a beam on `nodes` (reference x, m) held at its ends by `ends`.
    pub(crate) fn new(
        nodes: &[f64],
        ends: (Support, Support),
        youngs_modulus: f64,
        thickness: f64,
    ) -> Self {
        let elements = nodes.len() - 1;
        let mid: Vec<f64> = nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
        let mut points = mid.clone();
        let mut supports = Vec::new();
        let mut positions = Vec::new();
        let last = nodes.len() - 1;
        for (support, at, near) in [
            (ends.0, nodes[0], [0, 1]),
            (ends.1, nodes[last], [elements - 1, elements.saturating_sub(2)]),
        ] {
            if support == Support::Free {
                continue;
            }
            // Linear through the two midpoints, at the end: sigma_0 + w (sigma_0 - sigma_1).
            let weight = if elements > 1 {
                (at - mid[near[0]]) / (mid[near[0]] - mid[near[1]])
            } else {
                0.0
            };
            supports.push((support == Support::Clamped, near, weight));
            points.push(at);
            positions.push(at);
        }
        let count = points.len();
        Self {
            youngs_modulus,
            half_thickness: 0.5 * thickness,
            sections: Vec::new(),
            elements,
            supports,
            stresses: vec![0.0; count],
            observed: None,
            envelope: Envelope::new(points, &positions),
            flexural_rigidity: 0.0,
            field: None,
        }
    }

    /// Records the field at the nodes at every [`FeStress::record_field`] call: w = -z (the
    /// impact direction), slope -theta, and the moment and stress averaged over the node's
    /// elements (an end node takes its one element's); `width` (m) gives EI.
    pub(crate) fn with_field(mut self, nodes: &[f64], width: f64) -> Self {
        let thickness = 2.0 * self.half_thickness;
        self.flexural_rigidity = self.youngs_modulus * width * thickness.powi(3) / 12.0;
        self.field = Some(Field::new(nodes.to_vec()));
        self
    }

    /// Each element's own section, `[E, G, width, thickness]` (Pa, Pa, m, m): a structure whose
    /// members differ.
    pub(crate) fn with_sections(mut self, sections: &[[f64; 4]]) -> Self {
        self.sections =
            sections.iter().map(|[e, _, w, t]| (*e, 0.5 * t, e * w * t.powi(3) / 12.0)).collect();
        self
    }

    /// Adds the field of configuration `q` with section strains `strains` at `t` (s), if asked.
    pub(crate) fn record_field(&mut self, t: f64, q: &PlanarState, strains: &[(f64, f64, f64)]) {
        let Some(field) = &mut self.field else { return };
        field.push_instant(t);
        let element = |e: usize| {
            let (extension, _, curvature) = strains[e];
            let (youngs, half, ei) = self.sections.get(e).copied().unwrap_or((
                self.youngs_modulus,
                self.half_thickness,
                self.flexural_rigidity,
            ));
            (-ei * curvature, youngs * (extension - half * curvature))
        };
        let last = self.elements - 1;
        for i in 0..=self.elements {
            let (m, s) = match i {
                0 => element(0),
                _ if i > last => element(last),
                _ => {
                    let (a, b) = (element(i - 1), element(i));
                    (0.5 * (a.0 + b.0), 0.5 * (a.1 + b.1))
                }
            };
            field.displacement.push(-q.z[i]);
            field.slope.push(-q.theta[i]);
            field.moment.push(m);
            field.stress.push(s);
        }
    }

    /// Observes the beam at time `t` (s), given each element's section strains and (the 3D
    /// beam; empty in the plane) the stress its bending about the thickness axis adds at the
    /// worst corner of the struck face's edge (Pa).
    pub(crate) fn observe_strains(&mut self, t: f64, strains: &[(f64, f64, f64)], lateral: &[f64]) {
        self.observed = Some(t);
        for (stress, (extension, _, curvature)) in self.stresses.iter_mut().zip(strains) {
            *stress = self.youngs_modulus * (extension - self.half_thickness * curvature);
        }
        for (stress, ((extension, _, curvature), (e, half, _))) in
            self.stresses.iter_mut().zip(strains.iter().zip(&self.sections))
        {
            *stress = e * (extension - half * curvature);
        }
        for (stress, extra) in self.stresses.iter_mut().zip(lateral) {
            *stress += extra.copysign(*stress);
        }
        for (k, &(clamped, [a, b], weight)) in self.supports.iter().enumerate() {
            let (sa, sb) = (self.stresses[a], self.stresses[b]);
            self.stresses[self.elements + k] = if clamped { sa + weight * (sa - sb) } else { 0.0 };
        }
        self.envelope.observe(t, &self.stresses);
    }
}

/// Per element `[E, G, width, thickness]`, what turns the 3D beam's strains out of its plane
/// into stresses at the struck face's worst corner: E w/2 (Pa m) a lateral curvature, and
/// k G t (Pa m) a twist rate into the largest Saint-Venant shear stress (k of the rectangle,
/// t its thinner side).
pub(crate) fn out_of_plane_factors(sections: &[[f64; 4]]) -> (Vec<f64>, Vec<f64>) {
    let lateral = sections.iter().map(|[e, _, w, _]| 0.5 * e * w).collect();
    let shear = sections
        .iter()
        .map(|[_, g, w, t]| modal::rectangle_torsion(*w, *t).1 * g * w.min(*t))
        .collect();
    (lateral, shear)
}

impl BeamRecorder for FeStress {
    /// The envelope at every instant handed over (every accepted step), the field at the
    /// recorded ones.
    fn observe(&mut self, at: &Instant<'_>) {
        if let BeamView::Fe { state, strains, lateral } = at.beam {
            // A recorded instant is usually the step just accepted, already in the envelope.
            if self.observed != Some(at.t) {
                self.observe_strains(at.t, strains, lateral);
            }
            if at.sample.is_some() {
                self.record_field(at.t, state, strains);
            }
        }
    }

    fn finish(&mut self, yield_stress: Option<f64>) -> BendingStress {
        self.envelope.finish(None, yield_stress)
    }

    fn take_field(&mut self) -> Option<Field> {
        self.field.take()
    }
}
