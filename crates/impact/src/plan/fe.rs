//! The finite-element method's plan: the mesh, HHT's alpha and the steps.

use super::modal::MODE_CUTOFF;
use super::Pulse;
use crate::error::{invalid, positive, ImpactError};
use crate::scene::{BeamSpec, FeModelName, SolverSpec};
use simo_beam::Support;
use std::f64::consts::PI;

/// Default steps per estimated contact duration for the finite-element method (each step is a
/// Newton solve of the whole beam; see the convergence table in the FE tests).
pub const FE_SAMPLES_PER_PULSE: usize = 200;
/// Default HHT alpha of the finite-element method: a little numerical damping of the
/// frequencies above the mesh's resolution (the contact excites them), spectral radius 0.9 at
/// infinity, period and damping errors O((omega h)^2) below.
pub const FE_ALPHA: f64 = -0.05;
/// Default largest step, in contact steps: 1, every step the contact step, in contact and out
/// of it. Out of contact the beam carries the bending waves of the last impacts: they come back
/// from the clamp and their arrival decides when later contacts start and how long they last,
/// and HHT moves them by its dispersion, a relative period error of about (omega h)^2 / 12 over
/// every period of their travel. On the paper's tip (512 elements, gravity off, 5 ms) flights of
/// up to 8 contact steps (adapted to the local error at the impact point, the default until
/// then) made the fourth contact 159.6 us long against 141.7 us at 1 contact step, and no local
/// error control on the impact point alone found it (validation/REFERENCES.md 1.7); at 1 the
/// first 8 contacts are within 6e-4 (start) and 4e-3 (duration) of half the step. A scene may
/// set `solver.time_step` longer: the steps out of contact (and in a long, quasi-static contact)
/// then adapt up to it, faster and not converged in time.
pub const FE_FREE_STEP_RATIO: f64 = 1.0;
/// Elements per flexural wavelength at the impact point in the default graded mesh.
pub const FE_ELEMENTS_PER_WAVELENGTH: f64 = 16.0;
/// Growth of the element size away from the impact point in the default graded mesh.
pub const FE_GROWTH: f64 = 1.15;
/// The largest mesh a scene may ask for.
const MAX_ELEMENTS: usize = 100_000;
/// The first mesh of the refinement to a tolerance: 64 equal elements, coarse enough to cost
/// little (a tenth of the 512 the paper's tip needs for 1 %), fine enough that the next mesh
/// is in the asymptotic range (the paper's tip: successive differences fall 4x a halving).
pub const FE_LADDER_START: usize = 64;
/// The refinement to a tolerance stops at this many elements, tolerance met or not.
pub const FE_LADDER_END: usize = 8192;

/// The finite-element model of a struck beam.
#[derive(Debug, Clone, PartialEq)]
pub struct FePlan {
    /// The same beam as a uniform Timoshenko beam (shear and rotary inertia, as the fe beam
    /// has): its static stiffness defines the equivalent static force (as in the modal
    /// method), its first mode the swing's period, its wavelengths the mesh.
    pub(crate) analytic: Option<modal::Beam>,
    /// Beam material.
    pub(crate) material: simo_beam::Material,
    /// Section width (m), along y.
    pub(crate) width: f64,
    /// Section thickness (m), along z (the direction of impact).
    pub(crate) thickness: f64,
    /// How the first (x = 0) and the last node (x = L) are held.
    pub(crate) ends: (Support, Support),
    /// Impact point (m) from x = 0.
    pub(crate) position: f64,
    /// Node positions along x (m), from 0 to L.
    pub(crate) nodes: Vec<f64>,
    /// HHT alpha in [-1/3, 0].
    pub(crate) alpha: f64,
    /// Largest step out of contact (s).
    pub(crate) free_time_step: f64,
    /// Steps per estimated contact duration.
    pub(crate) samples_per_pulse: usize,
    /// The contact's local frequency at the struck section (rad/s; `None` where the struck
    /// section has no density to take it from), which the default steps resolve.
    pub(crate) local_frequency: Option<f64>,
    /// Largest approach on a rigid support (m): the scale of the event tolerance.
    pub(crate) approach_scale: f64,
    /// The pulse's duration the meshes are sized for (s): omega t_c = 20 at the fastest
    /// frequency the impact excites (`Pulse::sized`).
    pub(crate) sized_duration: f64,
    /// The relative error to refine the uniform mesh to, if asked (`solver.tolerance`).
    pub(crate) tolerance: Option<f64>,
    /// Point masses and elastic supports, each at a node of the mesh.
    pub(crate) attachments: Vec<Attachment>,
    /// The strike's offset across the width (m), and the beam in torsion when it is not 0 (its
    /// static twist enters the equivalent static force).
    pub(crate) offset: f64,
    pub(crate) torsion: Option<modal::Torsion>,
    /// The 3D beam and the strike: a `[structure]`'s (then `analytic` is `None` and `nodes` are
    /// the nodes' arc lengths), or the structure a 3D `[beam]` lowers onto
    /// ([`super::structure::of_beam`]); `None` for the planar beam.
    pub(crate) structure: Option<Box<super::structure::StructurePlan>>,
}

/// A point mass and an elastic support at one place of the fe beam (either may be 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Attachment {
    /// Where (m from x = 0): a node of every mesh.
    pub(crate) at: f64,
    /// Mass (kg) and its rotary inertia about the section's axes E1 (the beam's), E2 (the
    /// width's: the planar beam's too) and E3 (kg m^2).
    pub(crate) mass: f64,
    pub(crate) rotary_inertia: [f64; 3],
    /// Stiffness along the impact direction (N/m) and against the bending rotation (N m/rad).
    pub(crate) stiffness: f64,
    pub(crate) rotational_stiffness: f64,
}

/// Two positions closer than this fraction of the beam's length are one node.
const SAME_NODE: f64 = 1e-9;

/// `nodes` with a node at every attachment (an existing node within [`SAME_NODE`] of the
/// beam's length moved onto it, else a node added).
pub(crate) fn with_nodes_at(nodes: Vec<f64>, attachments: &[Attachment]) -> Vec<f64> {
    with_points(nodes, attachments.iter().map(|a| a.at))
}

/// `nodes` with a node at each of `points` (m), as [`with_nodes_at`].
fn with_points(mut nodes: Vec<f64>, points: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let length = nodes.last().copied().unwrap_or(0.0);
    for at in points {
        let k = nodes.partition_point(|x| *x < at);
        let near = [k.checked_sub(1), Some(k)]
            .into_iter()
            .flatten()
            .filter(|&i| i < nodes.len())
            .find(|&i| (nodes[i] - at).abs() <= SAME_NODE * length);
        match near {
            Some(i) => nodes[i] = at,
            None => nodes.insert(k, at),
        }
    }
    nodes
}

/// `nodes` with a node at the impact point `position` (m), as the default meshes have (the
/// stress under the ball and the contact are read best there: validation/REFERENCES.md 1.5),
/// and `pieces` (at least two) equal elements, not one, between it and an end it lies one
/// element from: an end's stress is extrapolated from its two nearest midpoints, which must
/// not straddle the moment's kink under the ball, and a ladder that doubles its elements
/// doubles `pieces` too, so that its difference measures the error there as well (with two
/// on every rung the deflection under a ball 4 mm from a clamp had stayed 3 % low, its
/// estimate 4.6e-3, a review's).
fn with_ball_node(nodes: Vec<f64>, position: f64, pieces: usize) -> Vec<f64> {
    let mut nodes = with_points(nodes, [position]);
    let n = nodes.len() - 1;
    let k = node_at(&nodes, position);
    // No shorter than MIN_ELEMENT of the beam (a ladder 1 um from a clamp had split it into
    // 4 nm elements beside 140 um ones, and Newton's iteration diverged, a review's).
    let length = nodes[n] - nodes[0];
    let span = if k == 1 { nodes[1] - nodes[0] } else { nodes[n] - nodes[n - 1] };
    let most = (span / (MIN_ELEMENT * length)).floor().max(2.0) as usize;
    let pieces = pieces.clamp(2, most);
    let split = |a: f64, b: f64| (1..pieces).map(move |i| a + (b - a) * i as f64 / pieces as f64);
    if n >= 2 && k == 1 {
        let inner: Vec<f64> = split(nodes[0], nodes[1]).collect();
        nodes.splice(1..1, inner);
    } else if n >= 2 && k == n - 1 {
        let inner: Vec<f64> = split(nodes[n - 1], nodes[n]).collect();
        nodes.splice(n..n, inner);
    }
    nodes
}

/// The node of `nodes` at `at` (m), as [`with_nodes_at`] placed it.
pub(crate) fn node_at(nodes: &[f64], at: f64) -> usize {
    let k = nodes.partition_point(|x| *x < at).min(nodes.len() - 1);
    match k.checked_sub(1) {
        Some(j) if (nodes[j] - at).abs() < (nodes[k] - at).abs() => j,
        _ => k,
    }
}

impl FePlan {
    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.nodes.len() - 1
    }

    /// The struck element and the impact point's local coordinate on it (0 at its first
    /// node, 1 at its second): the first element whose end is at or beyond the point.
    pub(crate) fn impact_site(&self) -> (usize, f64) {
        let nodes = &self.nodes;
        let i = nodes.windows(2).position(|w| self.position <= w[1]).unwrap_or(0);
        (i, (self.position - nodes[i]) / (nodes[i + 1] - nodes[i]))
    }

    /// Node positions along the beam (m), from 0 to L.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// HHT alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The planar beam of the plan: straight along x, thickness along z, its ends held, its
    /// masses and springs attached.
    ///
    /// # Errors
    /// From `simo_beam` for a section or mesh it refuses (checked before, not expected).
    pub(crate) fn beam(&self) -> Result<simo_beam::PlanarBeam, ImpactError> {
        let section = simo_beam::Section::rectangle(&self.material, self.width, self.thickness)?;
        let last = self.nodes.len() - 1;
        let (first, end) = self.ends;
        let mut beam = simo_beam::PlanarBeam::new(&self.nodes, &section)?
            .support(0, first)?
            .support(last, end)?;
        for a in &self.attachments {
            let node = node_at(&self.nodes, a.at);
            if a.mass > 0.0 || a.rotary_inertia[1] > 0.0 {
                beam = beam.attach_mass(node, a.mass, a.rotary_inertia[1])?;
            }
            if a.stiffness > 0.0 || a.rotational_stiffness > 0.0 {
                beam = beam.attach_spring(node, a.stiffness, a.rotational_stiffness)?;
            }
        }
        Ok(beam)
    }

    /// The 3D beam of the plan: a `[structure]`'s, or the one a 3D `[beam]` is lowered onto
    /// ([`super::structure::of_beam`]: straight along x, width along y, thickness along z, its
    /// ends held, its masses and springs attached).
    ///
    /// # Errors
    /// `Inconsistent` for a plan without a 3D beam (a planar one).
    pub(crate) fn beam3d(&self) -> Result<simo_beam::BeamModel, ImpactError> {
        match &self.structure {
            Some(s) => Ok(s.model.clone()),
            None => Err(ImpactError::Inconsistent("a planar fe plan has no 3D beam".into())),
        }
    }

    /// Whether the beam is the 3D one (a `[structure]`, or a `[beam]` by `solver.fe_model` or
    /// an off-centre strike): the one with a structure.
    pub(crate) fn three_d(&self) -> bool {
        self.structure.is_some()
    }

    /// A `[structure]` scene's plan; `None` for a `[beam]` (also when lowered onto a structure
    /// for its 3D beam: its mesh, static flexibility and ladder stay the beam's).
    pub(crate) fn scene_structure(&self) -> Option<&super::structure::StructurePlan> {
        self.structure.as_deref().filter(|_| self.analytic.is_none())
    }

    /// Each element's section as the struck face sees it: E (Pa), G (Pa), its size across the
    /// face and its depth along the strike (m) ([`super::structure::StructurePlan::struck_sections`]),
    /// or the beam's uniform width and thickness.
    pub(crate) fn element_sections(&self) -> Vec<[f64; 4]> {
        match &self.structure {
            Some(st) => st.struck_sections(),
            None => {
                let m = &self.material;
                vec![
                    [m.youngs_modulus, m.shear_modulus, self.width, self.thickness];
                    self.elements()
                ]
            }
        }
    }

    /// The held nodes and how: a structure's (and a `[beam]`'s lowered onto one) as its model
    /// holds them ([`super::structure::StructurePlan::supports`]), else the beam's ends; and
    /// as `Free` each end held by nothing, not even a rotational spring (its moment is zero).
    pub(crate) fn supports(&self) -> Vec<(usize, Support)> {
        let last = self.nodes.len() - 1;
        let (mut held, springs): (Vec<(usize, Support)>, Vec<usize>) = match &self.structure {
            Some(st) => (st.supports(), st.model.rotational_spring_nodes().collect()),
            None => (
                [(0, self.ends.0), (last, self.ends.1)]
                    .into_iter()
                    .filter(|(_, s)| *s != Support::Free)
                    .collect(),
                self.attachments
                    .iter()
                    .filter(|a| a.rotational_stiffness > 0.0)
                    .map(|a| node_at(&self.nodes, a.at))
                    .collect(),
            ),
        };
        for end in [0, last] {
            if !held.iter().any(|h| h.0 == end) && !springs.contains(&end) {
                held.push((end, Support::Free));
            }
        }
        held
    }

    /// The interior nodes where the bending stress may jump (`solve::fe_stress`): a
    /// rotational spring's on a beam (its moment), a structure's joints and interior supports
    /// ([`super::structure::StructurePlan::joints`]).
    pub(crate) fn stress_breaks(&self) -> Vec<usize> {
        match &self.structure {
            Some(st) => st.joints(),
            None => self
                .attachments
                .iter()
                .filter(|a| a.rotational_stiffness > 0.0)
                .map(|a| node_at(&self.nodes, a.at))
                .collect(),
        }
    }

    /// The nodes that carry a point mass or a spring (a structure's, or a beam's
    /// attachments'), where the bending moment may kink or jump: their stress is extrapolated
    /// to them as a support's (`solve::fe_stress`).
    pub(crate) fn attachment_nodes(&self) -> Vec<usize> {
        match &self.structure {
            Some(st) => st.model.attachment_nodes(),
            None => {
                let mut nodes: Vec<usize> =
                    self.attachments.iter().map(|a| node_at(&self.nodes, a.at)).collect();
                nodes.sort_unstable();
                nodes.dedup();
                nodes
            }
        }
    }

    /// The struck face's static flexibility at the impact point (m/N): the analytic
    /// Timoshenko beam's, plus offset^2 times the static twist per torque off the centre.
    pub(crate) fn static_flexibility(&self) -> Option<f64> {
        let bending = self.analytic.as_ref()?.static_flexibility(self.position)?;
        match &self.torsion {
            Some(t) => {
                Some(bending + self.offset * self.offset * t.static_flexibility(self.position)?)
            }
            None => Some(bending),
        }
    }

    /// The first elastic mode's period (s): a structure's, of its 3D beam at the plan's mesh
    /// ([`super::structure::StructurePlan::first_frequency`]); the analytic beam's; or where
    /// masses and springs change it, the planar beam's on 32 elements (a dense eigen-solution
    /// of 99 unknowns; the swing's period to about 1e-3, all a window's warning needs).
    pub(crate) fn first_period(&self) -> Option<f64> {
        let omega = if let Some(st) = self.scene_structure() {
            st.first_frequency()?
        } else if self.attachments.is_empty() {
            let beam = self.analytic.as_ref()?;
            beam.modes(3).ok()?.into_iter().map(|m| m.omega).find(|w| *w > 0.0)?
        } else {
            let beam = self.remeshed(32).ok()?.beam().ok()?;
            let modes = simo_beam::planar_modes(&beam, 8).ok()?;
            // Rigid-body modes (a free beam) sit at round-off's scale of the highest.
            let top = modes.iter().fold(0.0, |m: f64, x| m.max(x.omega));
            modes.into_iter().map(|m| m.omega).find(|w| *w > 1e-6 * top)?
        };
        Some(2.0 * std::f64::consts::PI / omega)
    }

    /// The same plan on `elements` equal elements (and a node at each attachment and at the
    /// impact point, with 2 x `elements` / [`FE_LADDER_START`] elements between it and a near
    /// end: [`with_ball_node`]); a structure's with every segment's elements times `elements`
    /// over its own.
    ///
    /// # Errors
    /// From rebuilding a structure (not expected: it was built once).
    pub(crate) fn remeshed(&self, elements: usize) -> Result<FePlan, ImpactError> {
        if let Some(st) = self.scene_structure() {
            let factor = (elements / st.base_elements).max(1);
            let mut refined = st.refined(factor)?;
            refined.free_time_step = self.free_time_step;
            refined.samples_per_pulse = self.samples_per_pulse;
            return Ok(refined);
        }
        let length = self.nodes.last().copied().unwrap_or(0.0);
        let nodes = with_ball_node(
            with_nodes_at(uniform(length, elements), &self.attachments),
            self.position,
            2 * elements / FE_LADDER_START,
        );
        let mut remeshed = FePlan { nodes, ..self.clone() };
        if let Some(st) = &self.structure {
            // A 3D [beam]: lowered again, onto the new mesh.
            let (scene, pulse) = st.source();
            remeshed.structure =
                Some(Box::new(super::structure::of_beam(&remeshed, scene, pulse)?));
        }
        Ok(remeshed)
    }
}

/// Contact steps a period of the contact's local frequency below which a plan warns, and which
/// the default steps take at least: the paper's tip struck by heavier balls at 200 steps a
/// rigid-support pulse (a review's) had its first contact 0.5 % long at 3 kg, 5 % at 10 kg, 11 %
/// at 30 kg and 30 % at 100 kg, against runs refined in space and time, with no word; at 100 kg
/// on its mid-span (5.3 steps a period) Newton's iteration diverged in the first contact.
const LOCAL_STEPS: f64 = 40.0;

/// Warns where the contact step takes fewer than [`LOCAL_STEPS`] over a period of the
/// contact's `local` frequency (rad/s; a ball heavy against the beam, whose local response
/// then sets the force's time scale: [`super::modal::local_frequency`]): where
/// `solver.samples_per_pulse` or `time_step` set the steps (the default takes that many),
/// unless a tolerance refines them.
pub(super) fn local_steps(local: f64, steps: &Steps, s: &SolverSpec, warnings: &mut Vec<String>) {
    if s.tolerance.is_some() {
        return;
    }
    let per_period = 2.0 * PI / local / steps.contact_step;
    if per_period < LOCAL_STEPS {
        let needed = (steps.samples as f64 * LOCAL_STEPS / per_period).ceil();
        warnings.push(format!("the contact step {:.3e} s takes {per_period:.1} steps over a period of the contact's local frequency {local:.4e} rad/s (the ball is heavy against the beam, whose local response sets the force's time scale, not the rigid-support pulse the step is sized by): the first contact is not converged in time (a review's, the paper's tip struck by heavier balls at 200 steps a rigid-support pulse: 0.5 % long at 3 kg, 5 % at 10 kg, 30 % at 100 kg; at 100 kg on its mid-span Newton's iteration diverged); set solver.samples_per_pulse = {needed} or more, or solver.tolerance", steps.contact_step));
    }
}

/// The fe method's time stepping, checked: HHT alpha, steps per contact, the steps' lengths.
#[derive(Debug, Clone, Copy)]
pub(super) struct Steps {
    pub(super) alpha: f64,
    pub(super) samples: usize,
    pub(super) contact_step: f64,
    pub(super) free_time_step: f64,
    /// The default steps a pulse, where the contact's local frequency raised them (to take
    /// [`LOCAL_STEPS`] a period of it).
    pub(super) raised_from: Option<usize>,
}

impl Steps {
    /// From `solver.samples_per_pulse`, `alpha` and `time_step`, for the pulse's duration; by
    /// default at least [`LOCAL_STEPS`] a period of the contact's `local` frequency (rad/s),
    /// where it is known (a `[beam]`'s, or a structure's at its struck section).
    pub(super) fn new(
        s: &SolverSpec,
        pulse: &Pulse,
        local: Option<f64>,
    ) -> Result<Self, ImpactError> {
        let mut samples = s.samples_per_pulse.unwrap_or(FE_SAMPLES_PER_PULSE);
        let mut raised_from = None;
        if let (None, None, Some(local)) = (s.samples_per_pulse, s.time_step, local) {
            let needed = (LOCAL_STEPS * pulse.duration * local / (2.0 * PI)).ceil();
            if needed > samples as f64 && needed.is_finite() {
                raised_from = Some(samples);
                samples = (needed as usize).min(super::MAX_SAMPLES_PER_PULSE);
            }
        }
        if samples < 10 {
            return Err(invalid("solver.samples_per_pulse", samples, "must be at least 10"));
        }
        let alpha = s.alpha.unwrap_or(FE_ALPHA);
        if !(alpha.is_finite() && (-1.0 / 3.0..=0.0).contains(&alpha)) {
            return Err(invalid(
                "solver.alpha",
                alpha,
                "must be in [-1/3, 0] (HHT, the paper's eq. 9)",
            ));
        }
        let estimated_duration = pulse.duration;
        let time_step = s.time_step.map(|h| positive("solver.time_step", h, "s")).transpose()?;
        let mut shorter = false;
        if let Some(h) = time_step {
            // The largest step, in contact too: a time_step shorter than the contact step sets
            // every step (it had been raised to the contact step without a word).
            let needed = (estimated_duration / h).ceil();
            if needed > samples as f64 {
                samples = if needed < 1e12 { needed as usize } else { usize::MAX };
                shorter = true;
            }
        }
        let contact_step = estimated_duration / samples as f64;
        let free_time_step = match time_step {
            Some(h) if !shorter => h.max(contact_step),
            _ => FE_FREE_STEP_RATIO * contact_step,
        };
        Ok(Self { alpha, samples, contact_step, free_time_step, raised_from })
    }

    /// The reasons for the steps and for how the maxima are sampled.
    pub(super) fn reasons(
        &self,
        s: &SolverSpec,
        estimated_duration: f64,
        reasons: &mut Vec<String>,
    ) {
        let Steps { alpha, samples, contact_step, free_time_step, raised_from } = *self;
        if let Some(from) = raised_from {
            reasons.push(format!("{samples} contact steps per estimated contact duration, not {from}: the ball is heavy against the beam, whose local response sets the force's time scale (the contact's local frequency), and a period of it takes {LOCAL_STEPS} steps (at 5.3 a period, the paper's beam struck at mid-span by a 100 kg ball, Newton's iteration had diverged in the first contact; at 10 kg on its tip the first contact came out 5 % long)"));
        }
        if free_time_step > contact_step * (1.0 + 1e-9) {
            reasons.push(format!("HHT alpha = {alpha}; steps of {contact_step:.4e} s in contact ({samples} per estimated contact duration {estimated_duration:.4e} s), up to {free_time_step:.4e} s out of contact (solver.time_step): the waves the impacts leave in the beam are then integrated with HHT's dispersion at the longer steps, and the contacts after the first few are not converged in time (validation/REFERENCES.md 1.7)"));
        } else {
            reasons.push(format!("HHT alpha = {alpha}; every step {contact_step:.4e} s ({samples} per estimated contact duration {estimated_duration:.4e} s), in contact and out of it: the bending waves an impact sends along the beam decide when later contacts start and end, and longer steps out of contact move them (validation/REFERENCES.md 1.7)"));
        }
        reasons.push(format!("maxima: the bending stress at each element's midpoint (one-point integration: the element's only stress) and at the impact point, extrapolated there from the two midpoints on each side (the moment's kink under the ball, which the midpoints miss by h/2 of the shear), at every accepted step ({contact_step:.4e} s apart in contact, up to {free_time_step:.4e} s out of it; HHT defines no value between its steps); the largest displacement between steps too, by the cubic through each step's ends and rates; neither depends on solver.output_interval"));
        if s.alpha.is_none() {
            reasons.push(format!("alpha = {FE_ALPHA} by default: it damps the vibration the impacts put into frequencies the mesh does not resolve, and energy.numerical_dissipation says how much (at the default steps, on the paper's tip 3e-5 of the ball's energy over 1 ms; on the heavy ball 1.5-2 % over 0.4 s, and 0.2 % and 2.2 % with -0.01 and -0.1: its chattering keeps feeding the high frequencies; longer steps out of contact damp more, 7 % and 12 % at 8 contact steps); set alpha = 0 for an undamped energy study: it conserves energy to 1e-6 on the tip, moves the first three contacts by less than 1e-3 and the heavy ball's largest displacement by 0.6 %, but keeps that unresolved vibration"));
        }
    }
}

/// The finite-element model of `beam` (whose analytic Timoshenko twin is `analytic`) struck at
/// `position` (m): the mesh asked for or graded from the impact point, alpha and the steps.
#[allow(clippy::too_many_arguments)] // the scene's parts a plan is made of, each checked before
pub(super) fn plan(
    beam: &BeamSpec,
    s: &SolverSpec,
    analytic: modal::Beam,
    position: f64,
    damping: f64,
    attachments: Vec<Attachment>,
    pulse: &Pulse,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<FePlan, ImpactError> {
    if damping > 0.0 {
        return Err(invalid("beam.modal_damping", damping, "must be 0 or absent with method = \"fe\" (the finite-element beam is undamped; HHT alpha adds numerical damping of high frequencies)"));
    }
    let local = super::modal::local_frequency(
        &analytic,
        (pulse.ball_mass, pulse.speed, pulse.max_approach),
    );
    let steps = Steps::new(s, pulse, Some(local))?;
    let Steps { alpha, samples, free_time_step, .. } = steps;
    reasons.push("planar geometrically exact beam (Reissner-Simo, 3 unknowns a node): the ball strikes the face along the thickness and nothing moves the beam or the ball out of that plane, so the 3D beam's other 3 unknowns a node would stay zero (and it takes about 4.5x the time: validation/REFERENCES.md 1.9; solver.fe_model = \"3d\" forces it)".into());
    let bar = (beam.youngs_modulus / beam.density).sqrt();
    let nodes = with_nodes_at(mesh(s, (&analytic, bar), position, pulse, reasons)?, &attachments);
    if !attachments.is_empty() {
        let places: Vec<String> = attachments
            .iter()
            .map(|a| {
                let mut what = Vec::new();
                if a.mass > 0.0 {
                    what.push(format!("{} kg", a.mass));
                }
                if a.stiffness > 0.0 || a.rotational_stiffness > 0.0 {
                    what.push(format!("{} N/m, {} N m/rad", a.stiffness, a.rotational_stiffness));
                }
                format!("{} at x = {} m", what.join(" and "), a.at)
            })
            .collect();
        reasons.push(format!("a node at each point mass and spring ({}): a mass moves with its node in x and z, a spring holds its node's z and section rotation", places.join("; ")));
    }
    let [first, last] = beam.support.ends();
    let ends = (first, last);
    let sized = pulse.sized(analytic.flexural_rigidity(), analytic.mass_per_length());
    resolution(s, (&analytic, bar), (&nodes, ends, position), sized, (reasons, warnings))?;
    steps.reasons(s, pulse.duration, reasons);
    local_steps(local, &steps, s, warnings);
    Ok(FePlan {
        material: simo_beam::Material::new(beam.youngs_modulus, beam.poisson_ratio, beam.density)?,
        analytic: Some(analytic),
        width: beam.width,
        thickness: beam.thickness,
        ends,
        position,
        nodes,
        alpha,
        free_time_step,
        samples_per_pulse: samples,
        local_frequency: Some(local),
        approach_scale: pulse.max_approach,
        sized_duration: sized,
        tolerance: s.tolerance,
        attachments,
        offset: 0.0,
        torsion: None,
        structure: None,
    })
}

/// The beam model of an fe plan: planar unless asked (`solver.fe_model`) or the strike is off
/// the centreline (a planar beam cannot twist), with the reason; whether it is the 3D one.
pub(super) fn model(
    fe: &mut FePlan,
    asked: Option<FeModelName>,
    offset: f64,
    torsion: Option<modal::Torsion>,
    reasons: &mut Vec<String>,
) -> Result<bool, ImpactError> {
    let three_d = match asked {
        Some(FeModelName::Planar) if offset != 0.0 => {
            return Err(ImpactError::Inconsistent(format!(
                "solver.fe_model = \"planar\" with impact.offset = {offset} m: a planar beam cannot twist; use fe_model = \"3d\" (the default off the centreline)"
            )));
        }
        Some(FeModelName::ThreeD) => true,
        Some(FeModelName::Planar) => false,
        None => offset != 0.0,
    };
    if three_d {
        // The planar model's reason gives way to the 3D one's.
        reasons.retain(|r| !r.starts_with("planar geometrically exact beam"));
        reasons.push(match asked {
            Some(_) => "3D geometrically exact beam (Simo's rod, 6 unknowns a node: extension, both shears and bendings, twist), as asked (solver.fe_model)".into(),
            None => format!("3D geometrically exact beam (Simo's rod, 6 unknowns a node): struck {offset} m off the centreline, the contact force twists the beam, which a planar beam cannot"),
        });
        reasons.push("3D: the bending stress is the section's worst corner's (the extension and the bending about both axes, in magnitude) and torsion_shear the Saint-Venant shear stress k G t theta', each at the elements' midpoints and every accepted step; the twist (the struck section's and the largest anywhere) at every accepted step".into());
    }
    fe.offset = offset;
    fe.torsion = torsion;
    Ok(three_d)
}

/// The node positions (m): `solver.elements` equal elements, or elements of `solver.element_size`
/// or of 1/16 of the flexural wavelength the pulse excites wherever its waves reach within the
/// window, growing beyond (see [`FE_GROWTH`]).
fn mesh(
    s: &SolverSpec,
    (beam, bar): (&modal::Beam, f64),
    position: f64,
    pulse: &Pulse,
    reasons: &mut Vec<String>,
) -> Result<Vec<f64>, ImpactError> {
    let length = beam.length();
    // The shortest wave the pulse excites (omega t_c = MODE_CUTOFF, as for the modes).
    let (rigidity, mass) = (beam.flexural_rigidity(), beam.mass_per_length());
    let (wavelength, group_velocity) =
        shortest_wave(rigidity, mass, pulse.sized(rigidity, mass), bar);
    if s.elements.is_some() && s.element_size.is_some() {
        return Err(ImpactError::Inconsistent("solver: give elements (a uniform mesh) or element_size (a mesh graded from the impact point), not both".into()));
    }
    if let Some(tolerance) = s.tolerance {
        if s.elements.is_some() || s.element_size.is_some() {
            return Err(ImpactError::Inconsistent(
                "solver.tolerance chooses the mesh: give it without elements or element_size"
                    .into(),
            ));
        }
        let tolerance = super::checked_tolerance(tolerance)?;
        reasons.push(format!("uniform meshes (with a node at the impact point, and 2, 4, 8, ... elements between it and an end it lies one element from) from {FE_LADDER_START} elements, doubled until two successive ones agree within solver.tolerance = {tolerance} on every significant contact's start, duration and peak force and on the largest displacement (the finer mesh's error a third of their difference, Richardson at second order; the largest displacement's their whole difference, its mesh error swinging in sign with the waves' dispersion); then, on that mesh, uniform steps of the contact step divided by 2, 4, ... until two runs agree again (the steps' error is their whole difference), the estimated error being the mesh's plus the steps'"));
        return Ok(with_ball_node(uniform(length, FE_LADDER_START), position, 2));
    }
    match s.elements {
        Some(0) => Err(invalid("solver.elements", 0, "must be at least 1")),
        Some(n) if n > MAX_ELEMENTS => Err(invalid("solver.elements", n, "must be at most 100000")),
        Some(n) => {
            reasons.push(format!("{n} equal elements, as asked"));
            Ok(uniform(length, n))
        }
        None => {
            let h0 = match s.element_size {
                Some(h) if positive("solver.element_size", h, "m")? < MIN_ELEMENT * length => {
                    return Err(invalid(
                        "solver.element_size",
                        format!("{h:e}"),
                        "at least 1e-7 of beam.length: shorter elements put nodes the same to round-off",
                    ));
                }
                Some(h) => h.min(length),
                None => (wavelength / FE_ELEMENTS_PER_WAVELENGTH).min(length / 16.0),
            };
            // The waves the mesh is sized for (omega t_c <= MODE_CUTOFF) travel at most at their
            // group velocity at the cutoff: within the window they reach no further from the
            // ball, and no reflection of them either. Elements stay h0 long there; beyond they
            // grow, where nothing the pulse sends arrives before the window ends.
            let reach = reach(s, group_velocity);
            let window = reach / group_velocity;
            // Elements needed: those within the reach, and about log(1 + L (r - 1) / h0) / log(r)
            // per side beyond.
            let estimate = (2.0 * reach).min(length) / h0
                + 2.0 * (1.0 + length * (FE_GROWTH - 1.0) / h0).ln() / FE_GROWTH.ln()
                + 32.0;
            if estimate > MAX_ELEMENTS as f64 && s.element_size.is_some() {
                return Err(invalid(
                    "solver.element_size",
                    h0,
                    "too small: the mesh would exceed 100000 elements",
                ));
            }
            if estimate > MAX_ELEMENTS as f64 {
                return Err(ImpactError::Inconsistent(format!(
                    "the default mesh would need about {estimate:.0} elements, more than 100000: elements of {h0:.3e} m (a sixteenth of the shortest wave the impact excites, {wavelength:.3e} m) over the {:.3e} m its waves reach from the ball in the {window:.3e} s window; a shorter solver.end_time shortens the reach, and solver.elements or solver.element_size sets a coarser mesh (its resolution then stated and warned of)",
                    (2.0 * reach).min(length)
                )));
            }
            let nodes = graded_nodes(length, position, (h0, reach), FE_GROWTH, length / 16.0);
            let why = if s.element_size.is_some() {
                "as asked".to_string()
            } else {
                format!("1/{FE_ELEMENTS_PER_WAVELENGTH} of the flexural wavelength {wavelength:.3e} m at {:.4e} rad/s, the fastest the impact excites: omega t_c = {MODE_CUTOFF}, or {} times the contact's local frequency where higher (a ball heavy against the beam)", MODE_CUTOFF / pulse.sized(rigidity, mass), super::modal::LOCAL_CUTOFF)
            };
            let grading = if position - reach <= 0.0 && position + reach >= length {
                format!("everywhere: the waves reach the whole beam within the window (at {group_velocity:.4e} m/s, the group velocity at that frequency or the bar velocity sqrt(E/rho) if lower, {reach:.3e} m in {window:.3e} s)")
            } else {
                format!("within {reach:.3e} m of the impact point, as far as the waves reach in the window ({group_velocity:.4e} m/s, the group velocity at that frequency or the bar velocity sqrt(E/rho) if lower, for {window:.3e} s), growing by {FE_GROWTH} per element beyond to at most L/16")
            };
            reasons.push(format!("{} elements of {h0:.3e} m ({why}) {grading}", nodes.len() - 1));
            Ok(nodes)
        }
    }
}

/// The shortest element, as a fraction of the beam's length: a node's position has 16
/// significant digits, so elements of 1e-7 L still have 9.
const MIN_ELEMENT: f64 = 1e-7;

/// The largest stress near the ball is low by about this times (h/lambda)^2 on a mesh of
/// elements h long at the impact point, lambda the flexural wavelength at omega t_c =
/// MODE_CUTOFF: on the paper's tip (validation/REFERENCES.md 1.5, uniform meshes) 21, 7.2,
/// 2.1 and 0.5 % at 18, 9, 4.5 and 2.25 mm (lambda = 24.5 mm): 0.39, 0.53, 0.60, 0.60.
pub(super) const STRESS_MESH_ERROR: f64 = 0.6;

/// A mesh whose largest stress would be this much low or more is warned about.
pub(super) const STRESS_MESH_WARNING: f64 = 0.05;

/// A clamped end's stress and an interior support's are extrapolated from the two nearest
/// midpoints (`solve::fe_stress`), whose error on a wave of length lambda is (3/8) h^2 sigma''
/// = (3/8) (2 pi h/lambda)^2 = 14.8 (h/lambda)^2 of its amplitude. Measured where the shortest
/// waves the pulse excites (lambda at omega t_c = 20) carry the support's largest: a 1 m strip
/// clamped at 0 and pinned at 1 m struck at 0.3 m over 2 ms, its clamp's largest against the
/// analytic modes' 36.84 MPa, +16, +5.0, +2.2 and +1.2 % at h/lambda = 0.20, 0.051, 0.034 and
/// 0.025: about this times (h/lambda)^2 on the fine meshes. Where longer waves carry it, less:
/// the frame of validation/scenes/frame-impact.toml, its clamp against 16.23 MPa at 640
/// elements a member, +0.9, +5.8, -7.7 and -0.6 % at 0.51, 0.25, 0.13 and 0.064
/// (validation/REFERENCES.md 1.5).
pub(super) const SUPPORT_MESH_ERROR: f64 = 20.0;

/// A support read on elements longer than this share of the shortest wave is warned about
/// (an eighth: twice the default meshes' sixteenth; the strip's clamp +16 % at 0.2).
pub(super) const SUPPORT_MESH_WARNING: f64 = 0.125;

/// A torsion front (Saint-Venant torsion does not disperse: the twist the pulse's torque puts
/// into the beam travels as a step of rise c_t t_c) crosses the mesh's elements, whose lumped
/// rotary inertia disperses it (omega = (2 c_t/h) sin(k h/2)): after a distance D it trails
/// oscillations of width sigma = (h^2 D/8)^(1/3) that overshoot its step by about
/// `a exp(-b / r)`, r = sigma / (c_t t_c), t_c the plan's estimated duration. Fitted on the
/// paper's strip pinned at both ends, struck at 0.4 m 10 mm off its centre line (t_c 41.2 us
/// estimated, 47.1 us in the run), the struck section's twist against the exact wave
/// solution's plateau e m dv / (2 sqrt(G J rho Ip)) = 1.602e-3 rad: 15, 3.4, 0.5 % at
/// r = 0.32, 0.20, 0.13 (a front that travelled 1.5 m, 256 to 1024 elements), 7.2 and 1.1 % of
/// a double step at 0.23 and 0.15 (2.3 m): validation/REFERENCES.md 1.9.
pub(super) const TORSION_OVERSHOOT: (f64, f64) = (1.39, 0.713);

/// A twist whose front may overshoot by this much or more is warned about: the fit is the
/// strip's, and a 20 x 10 mm beam pinned at both ends over 4 ms measured +4.3 % where it
/// estimated 1.8 % (a review's, against four refinements and the modal method).
pub(super) const TORSION_WARNING: f64 = 0.01;

/// How far the fit may understate a section's overshoot (that 20 x 10 mm beam's 4.3 against
/// 1.8 %): the mesh a warning advises is sized for TORSION_WARNING divided by it.
const TORSION_SPREAD: f64 = 2.4;

/// The torsion shear's front is sharper than the twist's: the twist rate travels with the
/// torque e F(t) itself, which rises from zero to its peak in about half the contact (a Hertz
/// pulse) or less (struck off the centre line, the strip's twist softens the contact after
/// its peak: the paper's tip 10 mm off peaks at 12 us of an 0.97 ms contact, 0.3 of the
/// estimated t_c), where the twist integrates it over the whole contact. So the shear's rise is
/// taken as c_t t_c / 4 in the same fit, an upper estimate. Measured against the exact
/// Saint-Venant solution by images (validation/peers/twist_images.py --rate-at), each with the
/// run's own force: that tip's clamp, +6.3, +9.6 and +4.4 % at elements of 1.54, 0.77 and
/// 0.385 mm, where this estimates 41, 20 and 6.3 % (before the cap); the pinned strip of
/// [`TORSION_OVERSHOOT`] over 2 ms, its largest, -3.0 and +7.2 % at 4.49 and 1.12 mm (a front
/// narrower than the spread is smeared low), estimated 86 and 42 %: validation/REFERENCES.md
/// 1.9.
const TORSION_SHEAR_RISE: f64 = 0.25;

/// Where the estimate reaches this share the elements are too long for the front: it is
/// then said as "this or more", high or low (a front sharper than the elements' spread
/// overshoots by about 27 % of its step, the semi-discrete chain's Airy front, and a pulse
/// narrower than the spread is smeared low: a review measured the paper's tip 10 mm off at 100
/// and 250 elements -43 and -23.5 %, at 400 -7.5 %).
const SHARP_FRONT_OVERSHOOT: f64 = 0.3;

/// The plan's word on the twist and torsion shear of `what` (a 3D run that twists) on elements
/// up to `h` long (m), of a section whose torsion waves travel at `speed` (m/s), struck by a
/// pulse of `duration` (s), over the window of `s`: the sizes into the reasons, a warning with
/// the element length that would bring them under [`TORSION_WARNING`] (`advice` says how).
pub(super) fn torsion_mesh(
    (what, advice): (&str, &dyn Fn(f64) -> String),
    (h, speed, duration): (f64, f64, f64),
    s: &SolverSpec,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) {
    let (a, b) = TORSION_OVERSHOOT;
    let travel = reach(s, speed);
    let rise = speed * duration;
    let spread = (h * h * travel / 8.0).cbrt();
    let overshoot = |rise: f64| (a * (-b * rise / spread).exp()).min(SHARP_FRONT_OVERSHOOT);
    let (twist, shear) = (overshoot(rise), overshoot(TORSION_SHEAR_RISE * rise));
    // The size as said (`bound` for the shear's upper estimate): at the cap, that much or more.
    let size = |x: f64, bound: bool| {
        if x >= SHARP_FRONT_OVERSHOOT {
            format!("{:.0} % or more", 100.0 * x)
        } else if bound {
            format!("up to about {:.1} %", 100.0 * x)
        } else {
            format!("about {:.1} %", 100.0 * x)
        }
    };
    reasons.push(format!(
        "{what}: torsion fronts (rise {rise:.3e} m, c_t t_c) travel up to {travel:.3e} m in the window over elements of up to {h:.3e} m, whose dispersion makes them overshoot their step by {} (the twist; fitted on a strip, up to 2.4 times that measured on a thicker section) and moves the torsion shear by {} (its front is the torque's own rise, about a quarter of that: an upper estimate below the cap, measured 1.4 to 6.5 times below it; high where the front overshoots, low where elements too long smear it: validation/REFERENCES.md 1.9)",
        size(twist, false),
        size(shear, true)
    ));
    if shear >= TORSION_WARNING {
        // sigma = r* rise' with a exp(-b / r*) = TORSION_WARNING / TORSION_SPREAD, rise' the
        // shear's (the twist's is four times longer: that mesh holds both).
        let r = b / (a * TORSION_SPREAD / TORSION_WARNING).ln();
        let enough = (8.0 * (r * TORSION_SHEAR_RISE * rise).powi(3) / travel).sqrt();
        warnings.push(format!(
            "{what}: where torsion fronts have travelled far, the torsion shear may be off by {} (high where the front overshoots, low where elements too long smear it) and the twist by {} of a front's step: a front of rise {rise:.3e} m (c_t t_c; the shear's a quarter of it) travels up to {travel:.3e} m in the window over elements of up to {h:.3e} m, whose dispersion moves it (validation/REFERENCES.md 1.9); {} would bring both under {:.0} % even where the fit understates the twist's {TORSION_SPREAD} times (a shorter window too)",
            size(shear, true),
            size(twist, false),
            advice(enough),
            100.0 * TORSION_WARNING
        ));
    }
}

/// The flexural wavelength (m) at the fastest frequency the pulse of `duration` (s) excites
/// (omega t_c = MODE_CUTOFF), and the fastest its waves travel (m/s), on a section of
/// `rigidity` EI (N m^2) and `mass` rho A (kg/m) of a material whose bar velocity sqrt(E/rho)
/// is `bar`: lambda = 2 pi (EI / rho A)^(1/4) / sqrt(omega), and the group velocity there,
/// 2 sqrt(omega) (EI / rho A)^(1/4) (Euler-Bernoulli's, above the Timoshenko beam's), but no
/// more than the bar velocity, which bounds every wave in a Timoshenko beam (its bending
/// branch tends to it and to the shear velocity, both lower).
pub(super) fn shortest_wave(rigidity: f64, mass: f64, duration: f64, bar: f64) -> (f64, f64) {
    let omega = MODE_CUTOFF / duration;
    let scale = (rigidity / mass).powf(0.25);
    (2.0 * PI * scale / omega.sqrt(), (2.0 * omega.sqrt() * scale).min(bar))
}

/// How far (m) the waves the meshes are sized for reach from the ball within the window:
/// their group velocity `speed` at the cutoff times `solver.end_time` (its default when
/// absent or invalid, which the plan refuses later). No reflection of them reaches further.
pub(super) fn reach(s: &SolverSpec, speed: f64) -> f64 {
    let window =
        s.end_time.filter(|t| t.is_finite() && *t > 0.0).unwrap_or(super::DEFAULT_END_TIME);
    speed * window
}

/// The plan's word on a support's stress read on elements `h` long (m) against the shortest
/// wave `wavelength` (m): its size into the reasons, and a warning naming `key` and how many
/// elements would do where they are longer than [`SUPPORT_MESH_WARNING`] of the wave.
pub(super) fn support_mesh(
    (what, key, elements): (&str, &str, usize),
    (h, wavelength): (f64, f64),
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) {
    let ratio = h / wavelength;
    let measured = "(measured, validation/REFERENCES.md 1.5: +16 % on a strip's clamp at h/lambda = 0.2, +1.2 % at 0.025; where longer waves carry it, less)";
    let size = if ratio <= SUPPORT_MESH_WARNING {
        format!(
            "can be off by up to about {SUPPORT_MESH_ERROR} (h/lambda)^2 = {:.1} %",
            100.0 * SUPPORT_MESH_ERROR * ratio * ratio
        )
    } else {
        "does not resolve them".to_string()
    };
    reasons.push(format!(
        "{what}: its stress is extrapolated from the two nearest elements' midpoints ({h:.3e} m, {ratio:.3} of the shortest wave the impact excites, {wavelength:.3e} m), which {size} {measured}"
    ));
    if ratio > SUPPORT_MESH_WARNING {
        let enough = (elements as f64 * ratio * FE_ELEMENTS_PER_WAVELENGTH).ceil();
        warnings.push(format!(
            "{what}: its stress is not resolved: it is extrapolated from the two nearest elements' midpoints, {h:.3e} m long, {ratio:.2} of the shortest wave the pulse excites ({wavelength:.3e} m), where it can be off by several per cent to tens of per cent {measured}; {key} = {enough} or more (a sixteenth of the wave, as the default meshes), or set solver.tolerance"
        ));
    }
}

/// Elements at least per half-wave of the first mode, below which the first mode (the
/// swing: the largest displacement, the equivalent static force, the stress at the supports)
/// is not resolved.
const FIRST_MODE_ELEMENTS: f64 = 4.0;

/// Whether the mesh can say what the report prints: refuses one whose impact point cannot
/// move along the strike (both nodes of its element held by supports, or on a held node), and
/// warns, with the size, where the elements at the impact point are too long for the pulse's
/// waves (STRESS_MESH_ERROR (h/lambda)^2 above STRESS_MESH_WARNING) or the longest ones for
/// the first mode (fewer than FIRST_MODE_ELEMENTS per half-wave); the criterion goes into the
/// reasons.
fn resolution(
    s: &SolverSpec,
    (beam, bar): (&modal::Beam, f64),
    (nodes, (first, last), position): (&[f64], (Support, Support), f64),
    estimated_duration: f64,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<(), ImpactError> {
    let n = nodes.len() - 1;
    let held = |k: usize| (k == 0 && first != Support::Free) || (k == n && last != Support::Free);
    // The element holding the impact point (the last one for the end).
    let element = nodes.partition_point(|x| *x <= position).saturating_sub(1).min(n - 1);
    let on_node = [element, element + 1]
        .into_iter()
        .find(|k| (nodes[*k] - position).abs() <= 1e-12 * beam.length());
    let fixed = match on_node {
        Some(k) => held(k),
        None => held(element) && held(element + 1),
    };
    let key = if s.elements.is_some() { "solver.elements" } else { "solver.element_size" };
    if fixed {
        return Err(ImpactError::Inconsistent(format!(
            "{key}: the mesh of {n} element(s) holds the impact point (x = {position} m) still: {}; the ball would meet a rigid support. Use more elements (the impact point then lies between free nodes)",
            if on_node.is_some() { "it is a supported node" } else { "both nodes of its element are supports" }
        )));
    }
    if s.tolerance.is_some() {
        // The refinement chooses the meshes and checks them against each other.
        return Ok(());
    }
    let (wavelength, group_velocity) =
        shortest_wave(beam.flexural_rigidity(), beam.mass_per_length(), estimated_duration, bar);
    let at_impact = nodes[element + 1] - nodes[element];
    let stress_error = STRESS_MESH_ERROR * (at_impact / wavelength).powi(2);
    let longest = nodes.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    let half_wave = PI * beam.length() / beam.support().eigenvalue(1).unwrap_or(PI);
    let per_half_wave = half_wave / longest;
    reasons.push(format!(
        "mesh check: elements of {at_impact:.3e} m at the impact point against the flexural wavelength {wavelength:.3e} m at the fastest frequency the impact excites (the largest stress near the ball is low by about {STRESS_MESH_ERROR} (h/lambda)^2, measured on the paper's tip, validation/REFERENCES.md 1.5: {:.1e} here; warned above {STRESS_MESH_WARNING}); {per_half_wave:.1} of the longest elements per half-wave of the first mode (warned below {FIRST_MODE_ELEMENTS})",
        stress_error
    ));
    if stress_error > STRESS_MESH_WARNING {
        let size = if at_impact > wavelength {
            "several times off".to_string()
        } else {
            format!("about {:.0} % low", 100.0 * stress_error)
        };
        warnings.push(format!(
            "{key}: elements of {at_impact:.3e} m at the impact point, {:.2} of the flexural wavelength the pulse excites ({wavelength:.3e} m): the contact force and the stress near the ball are not resolved (the largest stress {size}); the default mesh has elements of {:.3e} m there, or set solver.tolerance",
            at_impact / wavelength,
            wavelength / FE_ELEMENTS_PER_WAVELENGTH
        ));
    }
    if per_half_wave < FIRST_MODE_ELEMENTS {
        warnings.push(format!(
            "{key}: {per_half_wave:.1} elements per half-wave of the first mode ({half_wave:.3e} m), below {FIRST_MODE_ELEMENTS}: the beam's swing is not resolved (the largest displacement, the equivalent static force and the stress at the supports)"
        ));
    }
    clamped_ends(
        (nodes, (first, last), position),
        (wavelength, reach(s, group_velocity)),
        (reasons, warnings),
    );
    Ok(())
}

/// The stress of a clamped end of the beam of `nodes` struck at `position` (m), where the
/// pulse's waves (the shortest `wavelength`, m) reach it `within` (m) of the ball: the plan's
/// word on how well its elements resolve it ([`support_mesh`]).
fn clamped_ends(
    (nodes, (first, last), position): (&[f64], (Support, Support), f64),
    (wavelength, within): (f64, f64),
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) {
    let n = nodes.len() - 1;
    for (end, support, h) in [(0, first, nodes[1] - nodes[0]), (n, last, nodes[n] - nodes[n - 1])] {
        if support != Support::Clamped {
            continue;
        }
        let what = format!("the clamped end at x = {} m", nodes[end]);
        let distance = (nodes[end] - position).abs();
        if distance <= within {
            support_mesh((&what, "solver.elements", n), (h, wavelength), (reasons, warnings));
        }
        kink_beside(
            (nodes, end, position),
            (
                &what,
                &format!(
                    "solver.elements = {} or more, or the default mesh, which puts two elements between the ball and an end",
                    (2.0 * nodes[n] / distance).ceil()
                ),
            ),
            warnings,
        );
    }
}

/// Warns where the ball's load reaches the mesh (its node, or both nodes of the element it
/// strikes inside) between the support at `node` of `stations` (positions along the chain, m)
/// and the farther of the two midpoints its stress is extrapolated from on either side (the
/// one element's own where a side has only one): the moment's kink under the ball then lies
/// in the extrapolation, which takes the moment as linear there. `advice` names the elements
/// that would not.
pub(super) fn kink_beside(
    (stations, node, position): (&[f64], usize, f64),
    (what, advice): (&str, &str),
    warnings: &mut Vec<String>,
) {
    let n = stations.len() - 1;
    if n == 0 {
        return;
    }
    let at = stations[node];
    // Each side's reach (its direction along the chain, m).
    let mut reaches = Vec::new();
    if node >= 1 {
        let far = match node {
            1 => at - stations[0],
            _ => at - 0.5 * (stations[node - 1] + stations[node - 2]),
        };
        reaches.push((-1.0, far));
    }
    if node < n {
        let far = match n - node {
            1 => stations[n] - at,
            _ => 0.5 * (stations[node + 1] + stations[node + 2]) - at,
        };
        reaches.push((1.0, far));
    }
    // Each node the ball's load reaches is a kink of the discrete moment (a ball inside the
    // second element, between 1.5 and 2 elements from the clamp, had read it 11 % low).
    let k = stations.partition_point(|x| *x < position).min(n);
    let on_node = (stations[k] - position).abs() <= SAME_NODE * (stations[n] - stations[0]);
    let kinks =
        if on_node || k == 0 { vec![stations[k]] } else { vec![stations[k - 1], stations[k]] };
    let inside = |x: f64| {
        reaches.iter().any(|(direction, far)| {
            let d = (x - at) * direction;
            d > 0.0 && d < *far
        })
    };
    let distance = (at - position).abs();
    let far = reaches.iter().fold(0.0, |a: f64, r| a.max(r.1));
    if distance > 0.0 && kinks.into_iter().any(inside) {
        warnings.push(format!(
            "{what}: the ball strikes {distance:.3e} m from it, and its load reaches the mesh within the elements its stress is extrapolated from (their midpoints out to {far:.3e} m): the moment's kink under the ball lies between them, and the support's stress can be tens of per cent off, as can the displacement under the ball inside the support's first element (the paper's cantilever struck 1 mm from its clamp on elements of 1.54 mm: the clamp's stress 28 % low, the displacement 33 %, validation/REFERENCES.md 1.5); elements of at most half that distance there ({advice})"
        ));
    }
}

impl FePlan {
    /// The clamped ends' word ([`clamped_ends`]) on this plan's mesh over a window of
    /// `end_time` (s): (reasons, warnings). For the mesh a tolerance's ladder chose, which
    /// compares the largest stress but not a support's: the plan had said nothing of the
    /// clamp, 7.1 % low on the 256 elements a tolerance of 1e-2 chose at mid-span, where the
    /// same mesh given by `solver.elements` warned (a review's). None for a structure (its
    /// supports are checked segment by segment when it is planned).
    pub(crate) fn clamp_word(&self, end_time: f64) -> (Vec<String>, Vec<String>) {
        let (mut reasons, mut warnings) = (Vec::new(), Vec::new());
        if let (Some(beam), None) = (&self.analytic, self.scene_structure()) {
            let bar = (self.material.youngs_modulus / self.material.density).sqrt();
            let (wavelength, group_velocity) = shortest_wave(
                beam.flexural_rigidity(),
                beam.mass_per_length(),
                self.sized_duration,
                bar,
            );
            clamped_ends(
                (&self.nodes, self.ends, self.position),
                (wavelength, group_velocity * end_time),
                (&mut reasons, &mut warnings),
            );
        }
        (reasons, warnings)
    }
}

/// Nodes of `n` equal elements from 0 to `length` (m).
pub(crate) fn uniform(length: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|i| length * i as f64 / n as f64).collect()
}

/// Nodes from 0 to `length` with a node at `centre`, element size `h0` within `flat` of it,
/// growing by `growth` per element beyond up to `h_max`.
fn graded_nodes(
    length: f64,
    centre: f64,
    (h0, flat): (f64, f64),
    growth: f64,
    h_max: f64,
) -> Vec<f64> {
    let side = |span: f64| -> Vec<f64> {
        // Offsets from the centre, the last exactly at `span`: equal elements of at most h0
        // where the side lies within `flat` (a support at its end is read on them), and at
        // least two: an end's stress is extrapolated from its two nearest midpoints, which
        // must not straddle the moment's kink under the ball (the paper's cantilever struck
        // 1 mm from its clamp on one element there: the clamp's stress 31 % low).
        if span <= flat {
            let k = (span / h0).ceil().max(2.0) as usize;
            return if span > 0.0 {
                (1..=k).map(|i| span * i as f64 / k as f64).collect()
            } else {
                Vec::new()
            };
        }
        let mut out = Vec::new();
        let (mut at, mut h) = (0.0, h0.min(0.5 * span));
        while span - at > 1.5 * h {
            at += h;
            out.push(at);
            if at >= flat {
                h = (h * growth).min(h_max);
            }
        }
        if span > 0.0 {
            out.push(span);
        }
        out
    };
    let mut nodes: Vec<f64> = side(centre).iter().rev().map(|d| centre - d).collect();
    nodes.push(centre);
    nodes.extend(side(length - centre).iter().map(|d| centre + d));
    nodes[0] = 0.0;
    if let Some(last) = nodes.last_mut() {
        *last = length;
    }
    nodes
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use crate::{Plan, Scene};

    #[test]
    fn a_tip_mass_lengthens_the_swing_the_window_warnings_use() {
        // The paper's cantilever with a tip mass equal to its own (mu = 1): lambda^2 = 1.557298
        // (validation/REFERENCES.md 1.10) against 3.516015 bare; the plan's first period comes
        // from the planar beam on 32 elements, within 1e-3 of the characteristic root.
        let text = std::fs::read_to_string(format!(
            "{}/../../validation/scenes/paper-tip.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap()
        .replace("[ball]", "[[beam.mass]]\nat = 1.15\nmass = 1.128438\n[ball]")
        .replace("method = \"modal\"\nmodes = 128", "method = \"fe\"");
        let plan = Plan::new(&Scene::from_toml(&text).unwrap()).unwrap();
        let (ei, rho_a) = (2.1e11 * 0.025 * 0.005f64.powi(3) / 12.0, 7850.0 * 0.025 * 0.005);
        let omega = 1.557298 * (ei / rho_a).sqrt() / 1.15f64.powi(2);
        let period = plan.first_period.unwrap();
        assert!((period * omega / (2.0 * std::f64::consts::PI) - 1.0).abs() < 1e-3, "{period}");
    }

    #[test]
    fn a_3d_beam_is_the_structure_it_lowers_onto() {
        // The paper's tip struck 10 mm off the centreline by the fe method (3D), with a sensor
        // and a rotational spring: its 3D beam is the structure description's (one segment on
        // the plan's graded nodes, its supports, mass and springs), not a [structure] scene's
        // (its mesh ladder and analytic static flexibility stay the beam's), and a remeshed plan
        // is lowered again onto its new nodes. The planar plan has none.
        let text = std::fs::read_to_string(format!(
            "{}/../../validation/scenes/paper-tip-offset.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap();
        let carried = |method: &str| {
            let text = text.replace(
                "[ball]",
                "[[beam.mass]]\nat = 0.9\nmass = 0.02\n[[beam.spring]]\nat = 0.5\nstiffness = 2000.0\nrotational_stiffness = 20.0\n[ball]",
            );
            let mut scene = Scene::from_toml(&text).unwrap();
            scene.solver = crate::scene::SolverSpec::default();
            scene.solver.method = crate::scene::MethodName::Fe;
            scene.solver.end_time = Some(1e-4);
            if method == "planar" {
                scene.impact.offset = None;
            }
            Plan::new(&scene).unwrap()
        };
        let plan = carried("3d");
        let crate::plan::Method::Fe(fe) = &plan.method else { panic!("not fe") };
        let st = fe.structure.as_deref().unwrap();
        assert!(fe.scene_structure().is_none() && fe.analytic.is_some());
        let model = fe.beam3d().unwrap();
        let x: Vec<f64> = model.mesh().positions.iter().map(|p| p.x).collect();
        assert_eq!(x.len(), fe.nodes.len());
        for (a, b) in x.iter().zip(&fe.nodes) {
            assert!((a - b).abs() <= 4.0 * f64::EPSILON * 1.15, "{a} vs {b}");
        }
        assert_eq!(st.sections.len(), fe.elements());
        assert_eq!(model.rotational_spring_nodes().count(), 1);
        assert_eq!(fe.stress_breaks(), vec![super::node_at(&fe.nodes, 0.5)]);
        let coarse = fe.remeshed(64).unwrap();
        let lowered = coarse.structure.as_deref().unwrap();
        assert_eq!(lowered.model.mesh().positions.len(), coarse.nodes.len());
        let planar = carried("planar");
        let crate::plan::Method::Fe(fe) = &planar.method else { panic!("not fe") };
        assert!(fe.structure.is_none() && !fe.three_d());
    }
}
