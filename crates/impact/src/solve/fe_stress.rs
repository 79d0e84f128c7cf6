//! The finite-element method's bending stress, from the elements' section strains.
//!
//! Each element's rotation is linear, so its curvature kappa = (theta_2 - theta_1)/l_e and its
//! extension are constant over it: their mean, most accurate at the element's midpoint, where
//! the stress is recovered. On the struck face (+z at rest, the ball's side; w = -z), the fibre
//! strain is extension - (h/2) kappa, so sigma = E (extension - (h/2) kappa): the bending stress
//! M (h/2)/I with tension positive on the struck face, plus the axial stress N/A of the same
//! fibre. A clamped end's stress is extrapolated linearly from its two nearest midpoints; a
//! pinned end holds no moment and reports its zero (its axial stress aside); an interior
//! support (a structure's) reports the larger of the extrapolations from its two sides (a
//! clamp's moment jumps there). The envelope is observed at every accepted step. The field,
//! when asked, holds every envelope point (the midpoints, the supports, the impact point) and
//! the nodes between them (their elements' mean; a free end no moment), so that the
//! report's largest stress is a point of it.
//!
//! **Under the ball.** The midpoints alone miss the peak of a moment with a kink: under the
//! ball the moment's slope jumps by the contact force, and the midpoints on either side are
//! h/2 of the shear below the peak, a first-order error (the frame of
//! validation/scenes/frame-impact.toml: 3.56, 3.97, 4.27, 4.57, 4.72, 4.80e7 Pa at 80 to 2560
//! elements, toward 4.88e7 Pa). So the impact point is a point of the envelope too, where it
//! lies between the ends, its value the larger of the linear extrapolations from the two
//! nearest midpoints on each side that do not hold it (each exact for a moment linear on its
//! side, second order for a smooth one): 4.57, 4.87, 4.89, 4.886, 4.883, 4.882e7 Pa on the
//! same meshes. Only there: near a smooth peak a one-sided extrapolation overshoots (its
//! error (3/8) h^2 sigma'' against the midpoints' h^2 sigma''/8; on the paper's tip, whose
//! largest stress is a short bending wave's crest 2.4 cm from the struck end, extrapolating
//! to every node gave 60.7, 57.3, 55.5 MPa at 128, 256, 512 elements against the midpoints'
//! 50.9, 53.8, 54.6 and the limit 54.9); likewise where the ball strikes inside an element, so
//! that a side reaches up to 1.5 elements (+1.7 % at 256 uniform elements on the paper's beam
//! struck at 1.10 m, against the midpoints' -16 %; a node at the impact point, as the default
//! meshes have, 2.3e-3). An extrapolation never reaches over a `break`: a node
//! where the stress may jump (a corner, a step of section, an interior support or a
//! rotational spring).
//!
//! A node that carries a point mass or a spring is a point of the envelope too, read as a
//! support is (its one side at an end, the larger of its two sides inside): a mass's rotary
//! inertia gives a free end a moment, and a mass or a spring kinks the moment where it sits,
//! both at the node, which the midpoints reach only at first order (a review's cantilever
//! with a tip mass of rotary inertia 2e-5 kg m^2: 4.7 % low at the default mesh, 2.3 % after
//! a tolerance's refinement, whose second-order estimate claimed 0.8 %).

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
    /// For each support, in the order of its envelope point after the midpoints: its node and
    /// how its stress is read.
    supports: Vec<(usize, AtSupport)>,
    /// The impact point's envelope point (after the supports), if it has one: its two sides.
    impact_point: Option<[Option<Side>; 2]>,
    /// The nodes that carry a mass or a spring, in the order of their envelope points (after
    /// the impact point's), and how their stress is read.
    attached: Vec<(usize, AtSupport)>,
    /// The impact point (element, local coordinate), and the ends that hold no moment.
    impact: (usize, f64),
    free_ends: Vec<usize>,
    stresses: Vec<f64>,
    /// Each element's stress in parts at its struck face's corner: [E eps (the extension),
    /// -E (t/2) kappa (the bending about the width axis), the lateral bending's] (Pa), which
    /// are linear in the strains and so are extrapolated to a support or the impact point one
    /// by one before they are combined into its worst corner.
    parts: Vec<[f64; 3]>,
    /// The time of the last instant in the envelope (s).
    observed: Option<f64>,
    envelope: Envelope,
    /// EI (N m^2), set with the field (the moment is only the field's).
    flexural_rigidity: f64,
    /// The field at the nodes, the midpoints and the impact point, when asked, and what each
    /// of its points is.
    field: Option<Field>,
    field_points: Vec<FieldPoint>,
}

/// A point of the fe field.
#[derive(Debug, Clone, Copy, PartialEq)]
enum FieldPoint {
    /// A node: its displacement and slope; the stress and moment of a support's or the impact
    /// point's envelope point there, else averaged over its elements.
    Node(usize),
    /// An element's midpoint: its own stress and moment (the element's only ones), the mean
    /// of its nodes' displacement and slope (its linear interpolation).
    Middle(usize),
    /// The impact point inside an element: its envelope point's stress.
    Impact,
}

/// One side of an extrapolation: its two elements (the nearer first) and the weight `w` of
/// `sigma_near + w (sigma_near - sigma_far)`.
type Side = ([usize; 2], f64);

/// How a support's stress is read.
#[derive(Debug, Clone, Copy)]
enum AtSupport {
    /// A pinned end: no moment, 0.
    Zero,
    /// Extrapolated from the midpoints on each side that has two (the larger of the two): a
    /// clamped end from its one side, an interior support from both (a clamp's moment jumps
    /// there, a pin's does not).
    Sides([Option<Side>; 2]),
}

impl FeStress {
    /// The stress field of a beam on `nodes` (reference x, m) held at the nodes `held` (node,
    /// how; `Free` an end that holds no moment: the field's zero there), struck at `impact`
    /// (element, local coordinate), whose stress may jump at the nodes `breaks` (see the
    /// module text).
    pub(crate) fn new(
        nodes: &[f64],
        held: &[(usize, Support)],
        (youngs_modulus, thickness): (f64, f64),
        (impact, breaks, attached): ((usize, f64), &[usize], &[usize]),
    ) -> Self {
        let elements = nodes.len() - 1;
        let mid: Vec<f64> = nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
        let mut points = mid.clone();
        let mut supports = Vec::new();
        let mut positions = Vec::new();
        let last = nodes.len() - 1;
        let free_ends = held.iter().filter(|(_, s)| *s == Support::Free).map(|h| h.0).collect();
        for &(node, support) in held.iter().filter(|(_, s)| *s != Support::Free) {
            let at = nodes[node];
            let end = node == 0 || node == last;
            let read = if end && support == Support::Pinned {
                AtSupport::Zero
            } else {
                at_node(nodes, &mid, node, breaks)
            };
            supports.push((node, read));
            points.push(at);
            positions.push(at);
        }
        let impact_point = impact_sides(nodes, &mid, impact, breaks);
        if impact_point.is_some() {
            let (e, xi) = impact;
            points.push(nodes[e] + xi * (nodes[e + 1] - nodes[e]));
        }
        let attached: Vec<(usize, AtSupport)> = attached
            .iter()
            .filter(|node| !supports.iter().any(|s| s.0 == **node))
            .map(|&node| (node, at_node(nodes, &mid, node, breaks)))
            .collect();
        points.extend(attached.iter().map(|(node, _)| nodes[*node]));
        let count = points.len();
        Self {
            youngs_modulus,
            half_thickness: 0.5 * thickness,
            sections: Vec::new(),
            elements,
            supports,
            impact_point,
            attached,
            impact,
            free_ends,
            stresses: vec![0.0; count],
            parts: Vec::new(),
            observed: None,
            envelope: Envelope::new(points, &positions),
            flexural_rigidity: 0.0,
            field: None,
            field_points: Vec::new(),
        }
    }

    /// Records the field at every [`FeStress::record_field`] call, at the nodes, the elements'
    /// midpoints and the impact point (every point of the envelope, so that the field holds
    /// the report's largest stress where it is): w = -z (the impact direction), slope -theta,
    /// the moment and the stress of each [`FieldPoint`]; `width` (m) gives EI.
    pub(crate) fn with_field(mut self, nodes: &[f64], width: f64) -> Self {
        let thickness = 2.0 * self.half_thickness;
        self.flexural_rigidity = self.youngs_modulus * width * thickness.powi(3) / 12.0;
        let mut points: Vec<(f64, FieldPoint)> = nodes
            .iter()
            .enumerate()
            .map(|(i, x)| (*x, FieldPoint::Node(i)))
            .chain(
                nodes
                    .windows(2)
                    .enumerate()
                    .map(|(e, w)| (0.5 * (w[0] + w[1]), FieldPoint::Middle(e))),
            )
            .collect();
        let (e, xi) = self.impact;
        if self.impact_point.is_some() && xi > 0.0 && xi < 1.0 {
            let at = nodes[e] + xi * (nodes[e + 1] - nodes[e]);
            // Struck at the midpoint itself: the impact point's value stands for it.
            if (xi - 0.5).abs() <= 1e-12 {
                points.retain(|p| p.1 != FieldPoint::Middle(e));
            }
            points.push((at, FieldPoint::Impact));
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        self.field = Some(Field::new(points.iter().map(|p| p.0).collect()));
        self.field_points = points.into_iter().map(|p| p.1).collect();
        self
    }

    /// Each element's own section, `[E, G, width, thickness]` (Pa, Pa, m, m): a structure whose
    /// members differ.
    pub(crate) fn with_sections(mut self, sections: &[[f64; 4]]) -> Self {
        self.sections =
            sections.iter().map(|[e, _, w, t]| (*e, 0.5 * t, e * w * t.powi(3) / 12.0)).collect();
        self
    }

    /// Adds the field of configuration `q` with section strains `strains` at `t` (s), if asked;
    /// the stresses are those [`FeStress::observe_strains`] left for the same instant.
    pub(crate) fn record_field(&mut self, t: f64, q: &PlanarState, strains: &[(f64, f64, f64)]) {
        let Some(field) = &mut self.field else { return };
        field.push_instant(t);
        let moment = |e: usize| {
            let ei = self.sections.get(e).map_or(self.flexural_rigidity, |s| s.2);
            -ei * strains[e].2
        };
        // A point's moment and stress from the side whose stress extrapolation is the larger
        // (as `observe_strains` chose it), the moment extrapolated alike.
        let sided = |sides: &[Option<Side>; 2]| {
            let (k, stress) = larger_side(&self.parts, sides);
            let m = k
                .and_then(|k| sides[k])
                .map_or(0.0, |([near, far], w)| moment(near) + w * (moment(near) - moment(far)));
            (m, stress)
        };
        let at_impact = || self.impact_point.as_ref().map_or((0.0, 0.0), &sided);
        let (e, xi) = self.impact;
        let impact_node = self.impact_point.is_some().then_some(match xi {
            0.0 => Some(e),
            1.0 => Some(e + 1),
            _ => None,
        });
        let last = self.elements - 1;
        let at_node = |i: usize| {
            let held = self.supports.iter().chain(&self.attached).find(|s| s.0 == i);
            if let Some((_, read)) = held {
                return match read {
                    AtSupport::Zero => (0.0, 0.0),
                    AtSupport::Sides(sides) => sided(sides),
                };
            }
            if impact_node.flatten() == Some(i) {
                return at_impact();
            }
            // An end that holds no moment: none there, and its element's axial stress (its
            // own value, half an element in, had shown up to a third of the largest stress,
            // shrinking as the mesh refines).
            if self.free_ends.contains(&i) {
                let e = i.min(last);
                let youngs = self.sections.get(e).map_or(self.youngs_modulus, |s| s.0);
                return (0.0, youngs * strains[e].0);
            }
            let (a, b) = (i.saturating_sub(1), i.min(last));
            (0.5 * (moment(a) + moment(b)), 0.5 * (self.stresses[a] + self.stresses[b]))
        };
        let n = q.z.len();
        for point in &self.field_points {
            let ((w, slope), (m, s)) = match *point {
                FieldPoint::Node(i) => ((-q.z[i], -q.theta[i]), at_node(i)),
                FieldPoint::Middle(e) => {
                    let (w, slope) =
                        (0.5 * (q.z[e] + q.z[e + 1]), 0.5 * (q.theta[e] + q.theta[e + 1]));
                    ((-w, -slope), (moment(e), self.stresses[e]))
                }
                FieldPoint::Impact => {
                    let (a, b) = (e, (e + 1).min(n - 1));
                    let w = q.z[a] + xi * (q.z[b] - q.z[a]);
                    let slope = q.theta[a] + xi * (q.theta[b] - q.theta[a]);
                    ((-w, -slope), at_impact())
                }
            };
            field.displacement.push(w);
            field.slope.push(slope);
            field.moment.push(m);
            field.stress.push(s);
        }
    }

    /// Observes the beam at time `t` (s), given each element's section strains and (the 3D
    /// beam; empty in the plane) the stress its bending about the thickness axis adds at a
    /// corner (Pa). Each element's stress is its section's worst corner, |E eps| + E (t/2)
    /// |kappa| + the lateral term, signed as the struck face's bending stress: the extension's
    /// share adds to whichever face it loads more. (It had been the struck face's own, so a
    /// member's support read the face its `thickness_direction` happened to name: a symmetric
    /// portal's feet 4.98 and 5.62 MPa, the same foot 5.62 or 4.98 with that direction
    /// reversed, 11 % apart; a review's.)
    pub(crate) fn observe_strains(&mut self, t: f64, strains: &[(f64, f64, f64)], lateral: &[f64]) {
        self.observed = Some(t);
        self.parts.resize(strains.len(), [0.0; 3]);
        // The beam's own section where no element has its own (a `[structure]`'s elements
        // each have theirs), no lateral stress where none is given (the plane): one zipped
        // loop, no index looked up an element.
        let own = (self.youngs_modulus, self.half_thickness, 0.0);
        let sections = self.sections.iter().copied().chain(std::iter::repeat(own));
        let laterals = lateral.iter().copied().chain(std::iter::repeat(0.0));
        let each = self.parts.iter_mut().zip(strains).zip(sections).zip(laterals);
        for (((part, (extension, _, curvature)), (e, half, _)), lateral) in each {
            *part = [e * extension, -e * half * curvature, lateral];
        }
        for (stress, part) in self.stresses.iter_mut().zip(&self.parts) {
            *stress = worst_corner(*part);
        }
        for k in 0..self.supports.len() {
            self.stresses[self.elements + k] = match self.supports[k].1 {
                AtSupport::Zero => 0.0,
                AtSupport::Sides(sides) => larger_side(&self.parts, &sides).1,
            };
        }
        let mut next = self.elements + self.supports.len();
        if let Some(sides) = &self.impact_point {
            self.stresses[next] = larger_side(&self.parts, sides).1;
            next += 1;
        }
        for (k, (_, read)) in self.attached.iter().enumerate() {
            if let AtSupport::Sides(sides) = read {
                self.stresses[next + k] = larger_side(&self.parts, sides).1;
            }
        }
        self.envelope.observe(t, &self.stresses);
    }
}

/// How the stress at `node` of a beam of `nodes` with midpoints `mid` is read where the moment
/// may jump or kink there (a clamp, an interior support, a mass or a spring): at an end,
/// linear through the two midpoints, `sigma_0 + w (sigma_0 - sigma_1)` (one element: its own
/// twice; a single element's [0, 1] had read past the elements, a review's panic); inside,
/// from each side's two midpoints that no `break` separates from it ([`impact_sides`]).
fn at_node(nodes: &[f64], mid: &[f64], node: usize, breaks: &[usize]) -> AtSupport {
    let elements = mid.len();
    if node == 0 || node == elements {
        let near = if node == 0 {
            [0, 1.min(elements - 1)]
        } else {
            [elements - 1, elements.saturating_sub(2)]
        };
        let weight = if elements > 1 {
            (nodes[node] - mid[near[0]]) / (mid[near[0]] - mid[near[1]])
        } else {
            0.0
        };
        return AtSupport::Sides([Some((near, weight)), None]);
    }
    AtSupport::Sides(impact_sides(nodes, mid, (node, 0.0), breaks).unwrap_or([None, None]))
}

/// A section's worst corner from its stress's `parts` at the struck face's corner (see
/// `FeStress::parts`): |E eps| + E (t/2) |kappa| + |lateral|, the four corners taking every
/// sign of the two bendings, signed as the struck face's stress.
fn worst_corner([extension, bending, lateral]: [f64; 3]) -> f64 {
    (extension.abs() + bending.abs() + lateral.abs()).copysign(extension + bending)
}

/// Of a point's extrapolation `sides`, which one's worst corner from the elements' stress
/// `parts`, each part extrapolated from the two midpoints, is the larger, and that value (0
/// with neither). (The signed corners themselves had been extrapolated: where the extension
/// outweighs the bending at the farther midpoint its sign flips, and a symmetric portal's feet
/// read 5.82 and 6.15 MPa.)
fn larger_side(parts: &[[f64; 3]], sides: &[Option<Side>; 2]) -> (Option<usize>, f64) {
    let mut best = (None, 0.0_f64);
    for (k, side) in sides.iter().enumerate() {
        if let Some(([near, far], w)) = *side {
            let (a, b) = (parts[near], parts[far]);
            let v = worst_corner(std::array::from_fn(|i| a[i] + w * (a[i] - b[i])));
            if v.abs() > best.1.abs() {
                best = (Some(k), v);
            }
        }
    }
    best
}

/// The impact point's extrapolation sides (`FeStress`'s `impact_point`) on a beam of
/// `nodes` with midpoints `mid`, struck at `(e, xi)`: on each side the two nearest elements
/// that do not hold the point (a node's own two elements are on either side of it; an
/// element's inside holds it), where no break lies between the farther midpoint and the point.
/// `None` at an end (a free end holds no moment; a support's is extrapolated already) or
/// where neither side has two such elements.
fn impact_sides(
    nodes: &[f64],
    mid: &[f64],
    (e, xi): (usize, f64),
    breaks: &[usize],
) -> Option<[Option<Side>; 2]> {
    let elements = mid.len();
    let at = nodes[e] + xi * (nodes[e + 1] - nodes[e]);
    if at <= nodes[0] || at >= nodes[elements] {
        return None;
    }
    // The elements wholly before and after the point.
    let (before, after) = if xi <= 0.0 {
        (e.checked_sub(1), Some(e))
    } else if xi >= 1.0 {
        (Some(e), Some(e + 1))
    } else {
        (e.checked_sub(1), Some(e + 1))
    };
    let clear = |from: f64, to: f64| {
        let (lo, hi) = (from.min(to), from.max(to));
        !breaks.iter().any(|&b| nodes[b] > lo && nodes[b] < hi)
    };
    let side = |near: usize, far: usize| {
        clear(mid[far], at)
            .then(|| ([near, far], (at - mid[near]).abs() / (mid[near] - mid[far]).abs()))
    };
    let left = before.and_then(|n| n.checked_sub(1).map(|f| (n, f))).and_then(|(n, f)| side(n, f));
    let right = after.filter(|n| n + 1 < elements).and_then(|n| side(n, n + 1));
    (left.is_some() || right.is_some()).then_some([left, right])
}

/// Per element `[E, G, width, thickness]`, what turns the 3D beam's strains out of its plane
/// into stresses at a section's corner: E w/2 (Pa m) a lateral curvature, and
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
            if let Some(state) = state.filter(|_| at.sample.is_some()) {
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
