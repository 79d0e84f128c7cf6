//! Goldsmith's method on a structure: the modes of its 3D finite-element beam seen from the
//! contact site, and the recovery of its strains, twists and field from them.
//!
//! The structure's beam (`plan::FeBasis`: its masses, springs and supports) linearised at rest
//! gives K phi = omega^2 M phi; every mode with omega up to the plan's cutoff is solved by
//! `simo_beam::modes_below` (shift-invert Lanczos on a banded factorisation, mass-normalised,
//! rigid-body modes counted by a tolerance). A mode's gain at the site is the struck face's
//! motion along the ball's velocity per unit modal coordinate: g_n = -r . phi_n with r the face
//! rows (the two nodes' translations along `up`, interpolated, plus the offset times their
//! twist). The site's static flexibility f = r . K^-1 r is a static solve of the same beam,
//! and what it exceeds the kept modes' share sum g_n^2 / omega_n^2 by is the residual
//! flexibility (validation/REFERENCES.md 1.4).
//!
//! Recovery: each element's section strains at its midpoint are linear in the nodal motion at
//! rest (`simo_beam::Element::strain_jacobian`), so each mode has its strains, and the
//! mode-acceleration form adds the static solve's strains under the force for the truncated
//! modes ([`modal::Recovery`]). The stress and the Saint-Venant shear are then the fe method's
//! (`FeStress`, the section's worst corner), the twist each node's rotation about its
//! axis. They are evaluated at every recorded instant (about 200 a contact, in free flight one
//! an output interval or end_time / 2000, the shorter, and at least every [`LOOK_PHASE`] of
//! the fastest mode kept), not searched between them: the maxima are the fe method's kind
//! (values the field takes at those instants), not the analytic basis' certified ones.

use super::ball_on_beam3d::{struck_side, struck_strains, Face};
use super::fe_stress::{out_of_plane_factors, FeStress};
use super::observe::{BeamRecorder, BeamView, Instant};
use crate::error::ImpactError;
use crate::outcome::{BendingStress, Field};
use crate::plan::{FeBasis, ModalPlan};
use faer::Col;
use hht::Model;
use modal::{PointModes, Recovery, SiteModes};
use simo_beam::{BeamModel, PlanarState, Support};

/// The modes of a structure at its contact site and their recovery.
pub(super) struct FeSite {
    pub(super) site: SiteModes,
    pub(super) recorder: FeRecovery,
    /// How many modes lie below the cutoff (the site's are those of them that move the
    /// struck face).
    pub(super) below: usize,
}

/// The phase (rad) of the fastest mode kept between two instants a structure's maxima are
/// read at in free flight: a sinusoid sampled every omega dt = 0.5 shows its peak to within
/// 1 - cos(0.25) = 3.1 %, the slower modes that carry most of a stress far closer. Over 50 ms
/// on a 1 m strip the clamp's largest read every 25 us (the default output's) was 1.216 MPa,
/// every 2 us 1.438 MPa.
pub(crate) const LOOK_PHASE: f64 = 0.5;

/// A mode whose gain is at most this fraction of the largest does not move the struck face:
/// its gain is round-off (a symmetric mode's is ~1e-13 of the largest). What one at the bound
/// would add to any quantity is this fraction of what the largest mode adds, times the ratio
/// of their rows.
const UNEXCITED: f64 = 1e-9;

/// Solves the basis of `basis` as `m` plans it: its modes, gains, residual flexibility and the
/// recovery's rows; `field` also records the field along the arc length.
///
/// # Errors
/// `Inconsistent` naming what to change when the eigen-solver fails or finds no mode below the
/// cutoff; the modal crate's errors for a non-finite value.
pub(super) fn site(m: &ModalPlan, basis: &FeBasis, field: bool) -> Result<FeSite, ImpactError> {
    let fe = &basis.fe;
    let st = basis.structure()?;
    let model = &basis.model()?;
    let at_rest = basis.at_rest();
    let modes = at_rest.modes_below(basis.cutoff).map_err(|e| {
        ImpactError::Inconsistent(format!(
            "the structure's modes up to omega = {:.4e} rad/s could not be solved ({e}); give solver.method = \"fe\", or fewer elements per segment",
            basis.cutoff
        ))
    })?;
    if modes.is_empty() {
        return Err(ImpactError::Inconsistent(format!(
            "the structure has no mode below omega = {:.4e} rad/s (omega t_c = 20 for the estimated contact duration): the contact is over before the structure moves; strike it by solver.method = \"fe\"",
            basis.cutoff
        )));
    }
    let site_rows = basis.face_rows(model);
    let gain_of =
        |mode: &simo_beam::Mode| -site_rows.iter().map(|(i, w)| w * mode.shape[*i]).sum::<f64>();
    // A mode that does not move the struck face is never excited: the structure starts at
    // rest and the contact force is its only load. Left out (on a planar structure struck
    // normal to its plane, or on a straight member struck on its centre line, about half of
    // them: the motions in the plane, and the twist), their gains being round-off.
    let below = modes.len();
    let largest = modes.iter().fold(0.0, |m: f64, mode| m.max(gain_of(mode).abs()));
    let modes: Vec<simo_beam::Mode> =
        modes.into_iter().filter(|mode| gain_of(mode).abs() > UNEXCITED * largest).collect();
    let gain: Vec<f64> = modes.iter().map(gain_of).collect();
    let omega: Vec<f64> = modes.iter().map(|mode| mode.omega).collect();
    let point = PointModes::from_parts(omega, vec![m.damping; modes.len()], gain)?;
    // The load r with the modes `which` takes taken out (see `SiteModes::with_residual`):
    // r' = r - M Phi Phi^T r = r + M sum_n phi_n g_n, and its static response.
    let free = st.rigid_modes > 0;
    let deflated_response = |which: &dyn Fn(f64) -> bool| {
        let mut kept = Col::<f64>::zeros(model.ndof());
        for (mode, g) in modes.iter().zip(point.gain()).filter(|(mode, _)| which(mode.omega)) {
            kept += &mode.shape * *g;
        }
        let mut deflated = mass_times(at_rest, &kept);
        for (i, w) in &site_rows {
            deflated[*i] += w;
        }
        if free {
            relieved_response(model, &deflated)
        } else {
            let rows: Vec<(usize, f64)> = deflated.iter().copied().enumerate().collect();
            super::static_response_at_rest(at_rest, &rows)
        }
    };
    // Held: solved once, when planned. Free: by inertia relief, the load balanced by the
    // rigid-body modes' inertia (those left out carry none of it: their gains are round-off)
    // and the elastic response to it.
    let static_flexibility = if free {
        deflated_response(&|omega| omega == 0.0).map(|(f, _)| f)
    } else {
        basis.static_flexibility()
    };
    // The truncated modes' share, solved from the load with every kept mode taken out.
    let truncated = static_flexibility.and_then(|_| deflated_response(&|_| true));
    let residual = static_flexibility.map(|_| truncated.as_ref().map_or(0.0, |(r, _)| *r));
    let site = SiteModes::with_residual(point, static_flexibility, residual)?;
    let static_u = truncated.map(|(_, u)| u).filter(|_| !m.plain_stress_series);
    let sections = &st.struck_sections();
    let recorder = FeRecovery::new(
        model,
        (&modes, site.modes(), static_u.as_ref()),
        (sections, basis.quiet_strains()),
        (&fe.nodes, &fe.supports(), &st.joints(), fe.impact_site()),
        (st.up, st.face, field),
    )?;
    Ok(FeSite { site, recorder, below })
}

/// The static response of a free `model` to a balanced load `load` (no share along a
/// rigid-body mode): solved with node 0 clamped, where such a load has no reaction, so that
/// the clamped model's displacement solves K u = load (up to a rigid motion, which the
/// load does no work on and no strain sees). As [`super::static_response`]: the work
/// load . u and -u, over `model`'s unknowns.
fn relieved_response(model: &BeamModel, load: &Col<f64>) -> Option<(f64, Col<f64>)> {
    let held = model.clone().support(0, simo_beam::Support::Clamped).ok()?;
    let nodes = model.mesh().positions.len();
    let pairs: Vec<(usize, usize)> = (0..nodes)
        .flat_map(|node| (0..6).map(move |k| (node, k)))
        .filter_map(|(node, k)| Some((model.dof(node, k)?, held.dof(node, k)?)))
        .collect();
    let rows: Vec<(usize, f64)> = pairs.iter().map(|(i, j)| (*j, load[*i])).collect();
    let (_, u_held) = super::static_response(&held, &rows)?;
    let mut u = Col::<f64>::zeros(model.ndof());
    for (i, j) in &pairs {
        u[*i] = u_held[*j];
    }
    // The work over every unknown (the clamped node's load included: u is 0 there).
    let work = -load.iter().zip(u.iter()).map(|(f, x)| f * x).sum::<f64>();
    (work.is_finite() && work > 0.0).then_some((work, u))
}

/// M v for the beam at rest (its consistent mass and point masses), symmetrised as the
/// eigen-solver takes it.
fn mass_times(beam: &simo_beam::AtRest, v: &Col<f64>) -> Col<f64> {
    let mut out = Col::<f64>::zeros(beam.ndof());
    for (r, c, x) in beam.mass().iter() {
        out[r] += 0.5 * x * v[c];
        out[c] += 0.5 * x * v[r];
    }
    out
}

/// The rows of one quantity per mode (and, with `static_u`, its value under the unit static
/// force carried by the truncated modes), from a linear functional of the nodal unknowns.
struct RowBuilder<'a> {
    modes: &'a [simo_beam::Mode],
    static_u: Option<&'a Col<f64>>,
    rows: Vec<f64>,
    statics: Vec<f64>,
}

impl RowBuilder<'_> {
    /// Adds the quantity `read` of a vector over the unknowns.
    fn push(&mut self, read: impl Fn(&Col<f64>) -> f64) {
        self.rows.extend(self.modes.iter().map(|mode| read(&mode.shape)));
        if let Some(u) = self.static_u {
            self.statics.push(read(u));
        }
    }

    fn finish(self, point: &PointModes) -> Result<Recovery, ImpactError> {
        let statics = self.static_u.map(|_| self.statics.as_slice());
        Ok(Recovery::new(point, self.rows, statics)?)
    }
}

/// A structure's strains, stress, twist and field from its modes.
pub(super) struct FeRecovery {
    /// Per element: extension, twist rate, the curvatures about E2 and E3, those the modes
    /// can strain (`slots`: each one's row, `None` for one they cannot, which is 0).
    strains: Recovery,
    slots: Vec<[Option<usize>; 4]>,
    /// Per node: its rotation about its axis (rad), then per corner end (an element's end
    /// whose frame is its node's turned by a corner offset) the rotation about that element's
    /// own axis; `None` where every node's is held (a straight member struck on its centre
    /// line: 0).
    twists: Option<Recovery>,
    /// Per element, which of the struck faces' pair meets the ball, and the faces
    /// ([`super::ball_on_beam3d::struck_side`]): which curvature bends the struck face.
    sides: Vec<f64>,
    face: Face,
    /// Per element, the twist row of each end (its node's, or its own at a corner), and per
    /// row its node.
    twist_rows: Vec<[usize; 2]>,
    twist_nodes: Vec<usize>,
    /// The struck element and the impact point's local coordinate on it: the struck section's
    /// twist is its ends', interpolated.
    struck: (usize, f64),
    /// Per node, when the field is asked: the displacement along `up` and the rotation about
    /// E2 (the planar view's z and -theta).
    field_rows: Option<Recovery>,
    stress: FeStress,
    /// Per element: E (w/2) (Pa m) for the lateral curvature, k G t (Pa m) for the twist rate
    /// (`out_of_plane_factors`).
    lateral_per_curvature: Vec<f64>,
    shear_per_rate: Vec<f64>,
    /// Node arc lengths (m).
    nodes: Vec<f64>,
    // Work space, kept: no allocation an instant.
    values: Vec<f64>,
    section_strains: Vec<(f64, f64, f64)>,
    lateral: Vec<f64>,
    twist_values: Vec<f64>,
    field_values: Vec<f64>,
    view: PlanarState,
    /// The struck section's largest twist (rad) and when (s); the largest anywhere, at which
    /// node and when; the largest torsion shear (Pa), in which element and when.
    max_twist: (f64, f64),
    largest_twist: (f64, usize, f64),
    max_shear: (f64, usize, f64),
    /// The longest free flight between two instants it sees (s) and the last it saw: the
    /// maxima are read at instants, so a coarse `solver.output_interval` had thinned them (a
    /// review's clamp stress 39 % low at 2e-4 s on a 1 ms window).
    look_spacing: f64,
    last_seen: f64,
}

/// A held node and how (see [`FeStress::new`]).
type Held = (usize, Support);

impl FeRecovery {
    fn new(
        model: &BeamModel,
        (modes, point, static_u): (&[simo_beam::Mode], &PointModes, Option<&Col<f64>>),
        (sections, quiet): (&[[f64; 4]], Option<&[[bool; 4]]>),
        (nodes, held, breaks, (struck, xi)): (&[f64], &[Held], &[usize], (usize, f64)),
        (up, face, field): (nalgebra::Vector3<f64>, Face, bool),
    ) -> Result<Self, ImpactError> {
        let mesh = model.mesh();
        let sides = (0..mesh.elements.len()).map(|e| struck_side(model, (up, face), e)).collect();
        let reference = model.reference_state();
        let local = |v: &Col<f64>, element: &simo_beam::Element| {
            let mut u = nalgebra::SVector::<f64, 12>::zeros();
            for (end, node) in element.nodes.into_iter().enumerate() {
                for k in 0..6 {
                    if let Some(d) = model.dof(node, k) {
                        u[6 * end + k] = v[d];
                    }
                }
            }
            u
        };
        let unknown =
            |v: &Col<f64>, node: usize, k: usize| model.dof(node, k).map_or(0.0, |d| v[d]);
        let builder = || RowBuilder { modes, static_u, rows: Vec::new(), statics: Vec::new() };
        let mut strains = builder();
        let mut slots = Vec::with_capacity(mesh.elements.len());
        let mut rows = 0;
        for (e, element) in mesh.elements.iter().enumerate() {
            let [a, b] = element.nodes;
            let jacobian = element.strain_jacobian(
                [&reference.positions[a], &reference.positions[b]],
                [&reference.rotations[a], &reference.rotations[b]],
            );
            // Gamma_1, K_1, K_2, K_3: the quiet ones (in the plane of a planar structure
            // struck normal to it) are not evaluated.
            let quiet = quiet.and_then(|q| q.get(e)).copied().unwrap_or([false; 4]);
            slots.push(std::array::from_fn(|k| {
                (!quiet[k]).then(|| {
                    let j = jacobian.row([0, 3, 4, 5][k]).into_owned();
                    strains.push(|v| j.dot(&local(v, element).transpose()));
                    rows += 1;
                    rows - 1
                })
            }));
        }
        let nodes_count = mesh.positions.len();
        let twisted = (0..nodes_count).any(|node| model.dof(node, 3).is_some());
        let mut twists = builder();
        let mut twist_nodes: Vec<usize> = (0..nodes_count).collect();
        let mut twist_rows: Vec<[usize; 2]> = mesh.elements.iter().map(|e| e.nodes).collect();
        if twisted {
            for node in 0..nodes_count {
                twists.push(|v| unknown(v, node, 3));
            }
            // A corner end's frame is its node's turned by the offset O: a material rotation
            // theta of the node turns it by O^T theta, whose twist is theta . (O E1).
            for (e, element) in mesh.elements.iter().enumerate().filter(|(_, e)| !e.straight()) {
                for ((row, node), offset) in
                    twist_rows[e].iter_mut().zip(element.nodes).zip(element.offsets)
                {
                    let axis = offset * nalgebra::Vector3::x();
                    twists.push(|v| (0..3).map(|k| axis[k] * unknown(v, node, 3 + k)).sum());
                    *row = twist_nodes.len();
                    twist_nodes.push(node);
                }
            }
        }
        let field_rows = if field {
            let mut rows = builder();
            for node in 0..mesh.positions.len() {
                rows.push(|v| (0..3).map(|k| up[k] * unknown(v, node, k)).sum());
                // Minus the slope in the strike's plane, -up . (R0 (psi x E1)) (as the fe
                // method's `planar_view`): psi_2 on a [beam], -psi_3 on a width face.
                let frame = mesh.frames[node];
                let (along_e2, along_e3) = (
                    up.dot(&(frame * nalgebra::Vector3::y())),
                    up.dot(&(frame * nalgebra::Vector3::z())),
                );
                rows.push(move |v| along_e3 * unknown(v, node, 4) - along_e2 * unknown(v, node, 5));
            }
            Some(rows.finish(point)?)
        } else {
            None
        };
        let [e0, _, _, t0] = sections[0];
        let attached = model.attachment_nodes();
        let mut stress = FeStress::new(nodes, held, (e0, t0), ((struck, xi), breaks, &attached))
            .with_sections(sections);
        if field {
            stress = stress.with_field(nodes, sections[0][2]);
        }
        let elements = mesh.elements.len();
        let strains = strains.finish(point)?;
        let twists = if twisted { Some(twists.finish(point)?) } else { None };
        let (lateral_per_curvature, shear_per_rate) = out_of_plane_factors(sections);
        Ok(Self {
            values: vec![0.0; strains.len()],
            slots,
            twist_values: vec![0.0; twist_nodes.len()],
            twist_rows,
            twist_nodes,
            sides,
            face,
            field_values: vec![0.0; field_rows.as_ref().map_or(0, Recovery::len)],
            strains,
            twists,
            field_rows,
            struck: (struck, xi),
            stress,
            lateral_per_curvature,
            shear_per_rate,
            nodes: nodes.to_vec(),
            section_strains: vec![(0.0, 0.0, 0.0); elements],
            lateral: vec![0.0; elements],
            view: PlanarState { x: nodes.to_vec(), z: Vec::new(), theta: Vec::new() },
            max_twist: (0.0, 0.0),
            largest_twist: (0.0, 0, 0.0),
            max_shear: (0.0, 0, 0.0),
            look_spacing: f64::INFINITY,
            last_seen: 0.0,
        })
    }

    /// Sees the beam at least every `spacing` (s) in free flight.
    pub(super) fn look_every(&mut self, spacing: f64) {
        self.look_spacing = spacing;
    }
}

impl BeamRecorder for FeRecovery {
    fn next_look(&self) -> f64 {
        self.last_seen + self.look_spacing
    }

    fn observe(&mut self, at: &Instant<'_>) {
        let BeamView::Modal { q, force, .. } = at.beam else { return };
        self.last_seen = at.t;
        self.strains.evaluate(q, force, &mut self.values);
        for (e, slots) in self.slots.iter().enumerate() {
            let [extension, twist_rate, k2, k3] = slots.map(|k| k.map_or(0.0, |i| self.values[i]));
            // The planar beam's (extension, shear, curvature) as the struck face sees them, as
            // the fe method's 3D beam hands them over; the lateral bending adds at the worst
            // corner.
            let all = [extension, 0.0, 0.0, twist_rate, k2, k3];
            let (planar, (lateral, _, _)) = struck_strains(self.face, self.sides[e], all);
            self.section_strains[e] = planar;
            self.lateral[e] = self.lateral_per_curvature[e] * lateral.abs();
            let tau = self.shear_per_rate[e] * twist_rate.abs();
            if tau > self.max_shear.0 {
                self.max_shear = (tau, e, at.t);
            }
        }
        self.stress.observe_strains(at.t, &self.section_strains, &self.lateral);
        if let Some(twists) = &self.twists {
            twists.evaluate(q, force, &mut self.twist_values);
        }
        let (e, xi) = self.struck;
        let [a, b] = self.twist_rows[e];
        let struck = (1.0 - xi) * self.twist_values[a] + xi * self.twist_values[b];
        if struck.abs() > self.max_twist.0 {
            self.max_twist = (struck.abs(), at.t);
        }
        for (&node, twist) in self.twist_nodes.iter().zip(&self.twist_values) {
            if twist.abs() > self.largest_twist.0 {
                self.largest_twist = (twist.abs(), node, at.t);
            }
        }
        if let (Some(rows), Some(_)) = (&self.field_rows, &at.sample) {
            rows.evaluate(q, force, &mut self.field_values);
            let (z, theta) = (&mut self.view.z, &mut self.view.theta);
            z.clear();
            theta.clear();
            for pair in self.field_values.chunks_exact(2) {
                z.push(pair[0]);
                theta.push(-pair[1]);
            }
            self.stress.record_field(at.t, &self.view, &self.section_strains);
        }
    }

    fn finish(&mut self, yield_stress: Option<f64>) -> BendingStress {
        self.stress.finish(yield_stress)
    }

    fn twist_peak(&self) -> Option<(f64, f64)> {
        Some(self.max_twist)
    }

    fn largest_twist_peak(&self) -> Option<(f64, f64, f64)> {
        let (max, node, time) = self.largest_twist;
        Some((max, self.nodes[node], time))
    }

    fn torsion_shear_peak(&self) -> Option<(f64, f64, f64)> {
        let (max, e, time) = self.max_shear;
        Some((max, 0.5 * (self.nodes[e] + self.nodes[e + 1]), time))
    }

    fn take_field(&mut self) -> Option<Field> {
        self.stress.take_field()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::plan::{Method, ModalBasis, Plan};
    use crate::Scene;

    /// validation/scenes/frame-impact.toml by the modal method, `elements` a member, with
    /// `edits` (text replaced).
    fn frame(elements: usize, edits: &[(&str, &str)]) -> Plan {
        let mut text = include_str!("../../../../validation/scenes/frame-impact.toml")
            .replace("method = \"fe\"", "method = \"modal\"")
            .replace("elements = 40", &format!("elements = {elements}"));
        for (from, to) in edits {
            assert!(text.contains(from), "{from}");
            text = text.replace(from, to);
        }
        Plan::new(&Scene::from_toml(&text).unwrap()).unwrap()
    }

    fn basis(plan: &Plan) -> (&ModalPlan, &FeBasis) {
        let Method::Modal(m) = &plan.method else { panic!("modal expected") };
        let ModalBasis::Fe(basis) = &m.basis else { panic!("fe basis expected") };
        (m, basis)
    }

    #[test]
    fn every_mode_s_share_is_the_static_solve_s_flexibility() {
        // The frame at 3 elements a member (36 unknowns) with every mode kept (cutoff far above
        // the mesh's highest): sum g_n^2 / omega_n^2 over all modes is r . K^-1 r exactly
        // (K^-1 = Phi Omega^-2 Phi^T for mass-normalised modes), so the residual flexibility is
        // round-off: 1e-10 of the flexibility (the eigen-solver's residuals are ~1e-12). Struck
        // off the centre line (offset x twist in the gain) and between nodes.
        let plan = frame(
            3,
            &[("at = 0.9 ", "at = 0.85 "), ("gravity = false", "gravity = false\noffset = 0.01")],
        );
        let (m, planned) = basis(&plan);
        let mut all = planned.clone();
        all.cutoff = 1e9;
        // The frame lies in a plane and is struck normal to it: its in-plane unknowns are
        // held (18 of 36 kept), and on the whole model the 18 modes in its plane do not move the
        // face and are left out. Both give the same modes, gains and flexibility.
        let whole = site(m, &all.whole().unwrap(), false).unwrap();
        let site = site(m, &all, false).unwrap();
        assert_eq!((whole.below, whole.site.modes().len()), (36, 18));
        assert_eq!((site.below, site.site.modes().len()), (18, 18));
        for (name, a, b) in [
            ("omega", site.site.modes().omega(), whole.site.modes().omega()),
            ("gain", site.site.modes().gain(), whole.site.modes().gain()),
        ] {
            for (x, y) in a.iter().zip(b) {
                assert!((x.abs() - y.abs()).abs() <= 1e-9 * y.abs(), "{name}: {x} vs {y}");
            }
        }
        let flexibility = site.site.static_flexibility().unwrap();
        let whole_flexibility = whole.site.static_flexibility().unwrap();
        assert!(
            (flexibility / whole_flexibility - 1.0).abs() < 1e-10,
            "{flexibility:e} vs {whole_flexibility:e}"
        );
        let share = site.site.modes().static_flexibility();
        assert!((share / flexibility - 1.0).abs() < 1e-10, "{share:e} vs {flexibility:e}");
        // At the plan's cutoff the residual is what the modes left out hold, and positive.
        let kept = super::site(m, planned, false).unwrap();
        assert!(kept.site.modes().len() < 36);
        assert!(kept.site.residual_flexibility().unwrap() > 0.0);
    }

    #[test]
    fn a_free_structure_s_modes_and_residual_make_its_inertia_relief_flexibility() {
        // The frame with its support taken away (a free body: six rigid-body modes, counted
        // when planned), at 3 elements a member: the elastic modes' share sum g_n^2/omega_n^2
        // plus the residual (r' K^-1 r' with every kept mode taken out, solved with one node
        // clamped) is the inertia-relief flexibility (the load balanced by the rigid modes'
        // inertia, solved the same way) to round-off: with every mode kept the residual is
        // nothing, at a low cutoff it holds what the modes left out hold.
        let plan = frame(
            3,
            &[
                ("[[structure.support]]\nat = 0.0\nkind = \"clamped\"\n", ""),
                ("at = 0.9 ", "at = 0.85 "),
                ("gravity = false", "gravity = false\noffset = 0.01"),
            ],
        );
        let (m, planned) = basis(&plan);
        assert_eq!(planned.fe.structure.as_ref().unwrap().rigid_modes, 6);
        assert_eq!(planned.static_flexibility(), None, "a free body has no static stiffness");
        let mut all = planned.clone();
        all.cutoff = 1e9;
        // The mesh is so coarse that the plan's cutoff holds every mode: a lower one leaves
        // out all but the first few (532, 748, 2475 rad/s, ...).
        let mut few = planned.clone();
        few.cutoff = 3000.0;
        for (basis, every) in [(&all, true), (&few, false)] {
            let site = site(m, basis, false).unwrap();
            let relief = site.site.static_flexibility().unwrap();
            let residual = site.site.residual_flexibility().unwrap();
            let share = site.site.modes().static_flexibility();
            assert!(
                ((share + residual) / relief - 1.0).abs() < 1e-10,
                "{share:e} + {residual:e} vs {relief:e}"
            );
            if every {
                assert!(residual < 1e-10 * relief, "{residual:e}");
                // 3 unknowns a node out of the plane, 7 nodes: 18 elastic modes, 3 rigid.
                assert_eq!(site.below, 21);
            } else {
                assert!(residual > 1e-3 * relief, "{residual:e} of {relief:e}");
            }
        }
    }
}
