//! A `[structure]`: its beam from the segments (the parser and validation `xtask beam` uses,
//! `simo_beam::scene::structure`), where the ball strikes it and from where, and the fe plan on
//! the 3D beam.

use super::fe::{FePlan, Steps};
use super::{offset, ModalBasis, ModalPlan, Pulse, MODE_CUTOFF};
use crate::error::{invalid, not_negative, ImpactError};
use crate::scene::{FeModelName, MethodName, Scene, StructureSpec};
use crate::solve::Face;
use nalgebra::Vector3;
use simo_beam::{AtRest, BeamModel, Support};
use std::sync::Arc;

/// A free body's rigid-body modes.
pub(crate) const FREE_BODY: usize = 6;

/// A face normal within this of the strike's direction (1 - |cos|) is the struck face.
const NORMAL: f64 = 1e-6;

/// The 3D beam of a structure and the strike on it.
#[derive(Debug, Clone)]
pub(crate) struct StructurePlan {
    pub(crate) model: BeamModel,
    /// The ball centre at first touch (m), and against its velocity (unit).
    pub(crate) ball_start: Vector3<f64>,
    pub(crate) up: Vector3<f64>,
    /// The faces struck, and their distance from the centre line (m).
    pub(crate) face: Face,
    pub(crate) half_depth: f64,
    /// Each element's section: E (Pa), G (Pa), width and thickness (m).
    pub(crate) sections: Vec<[f64; 4]>,
    /// The rigid-body modes the supports leave free: 0 where they hold the structure,
    /// [`FREE_BODY`] for a free body, between for a mechanism (refused by the modal method).
    pub(crate) rigid_modes: usize,
    /// The fastest frequency the impact makes the struck section answer at (rad/s,
    /// `Pulse::fastest`): the modes' cutoff.
    pub(crate) fastest: f64,
    /// The scene and pulse it was made from, and its elements: a refinement rebuilds it with
    /// every segment's elements multiplied ([`StructurePlan::refined`]).
    source: Box<(Scene, Pulse)>,
    pub(crate) base_elements: usize,
}

impl StructurePlan {
    /// The fe plan of the same strike with every segment's `elements` times `factor`.
    ///
    /// # Errors
    /// As [`plan`] (which made this one, so none expected).
    pub(crate) fn refined(&self, factor: usize) -> Result<FePlan, ImpactError> {
        let (scene, pulse) = &*self.source;
        let mut scene = scene.clone();
        if let Some(st) = scene.structure.as_mut() {
            for seg in &mut st.segments {
                seg.elements *= factor;
            }
        }
        let spec = scene.structure.clone().ok_or_else(|| {
            ImpactError::Inconsistent("a structure's plan without its [structure]".into())
        })?;
        build(&scene, &spec, pulse, (&mut Vec::new(), &mut Vec::new()))
    }
}

impl StructurePlan {
    /// The first elastic mode's angular frequency (rad/s) of the structure linearised at rest,
    /// `None` if no rung finds one: modes below a cutoff raised fourfold from 1 rad/s until
    /// one is elastic (a count of the eigenvalues below it, one factorisation, decides each
    /// rung with none; a free body's or a mechanism's rigid modes, at zero, are passed over,
    /// and a rung whose solution fails on them, a shift at their eigenvalue, is passed too: it
    /// had ended the search, and a free bar's window went unwarned, a review's). Without it a
    /// structure's window warnings had nothing to measure the swing by, and a largest
    /// displacement still rising at a 2 ms window's end (a frame whose quarter period is
    /// 42.5 ms) was reported as the maximum without a word (a review's).
    pub(crate) fn first_frequency(&self) -> Option<f64> {
        let at_rest = simo_beam::AtRest::of(&self.model);
        let mut cutoff = 1.0;
        for _ in 0..40 {
            let elastic = at_rest
                .modes_below(cutoff)
                .ok()
                .and_then(|modes| modes.iter().map(|m| m.omega).find(|w| *w > 0.0));
            if elastic.is_some() {
                return elastic;
            }
            cutoff *= 4.0;
        }
        None
    }

    /// The held nodes and how: clamped where all six unknowns are, pinned where the three
    /// translations are (a fork's too: neither holds a bending moment), as the model holds
    /// them (a `[beam]`'s ends lowered too).
    pub(crate) fn supports(&self) -> Vec<(usize, Support)> {
        let held = |node: usize, k: std::ops::Range<usize>| {
            k.into_iter().all(|k| self.model.dof(node, k).is_none())
        };
        (0..self.model.mesh().positions.len())
            .filter_map(|node| {
                if held(node, 0..6) {
                    Some((node, Support::Clamped))
                } else if held(node, 0..3) {
                    Some((node, Support::Pinned))
                } else {
                    None
                }
            })
            .collect()
    }

    /// Each element's section as the struck face sees it: E (Pa), G (Pa), its size across the
    /// face and its depth along the strike (m): `sections` as they are on a thickness face,
    /// width and thickness swapped on a width face (its bending is about the thickness axis,
    /// its outer fibre half the width from the centre line).
    pub(crate) fn struck_sections(&self) -> Vec<[f64; 4]> {
        match self.face {
            Face::Thickness => self.sections.clone(),
            Face::Width => self.sections.iter().map(|&[e, g, w, t]| [e, g, t, w]).collect(),
        }
    }

    /// The interior nodes where the stress along the arc length may jump: where segments meet
    /// (a corner turns one member's bending into the next one's torsion; a step changes the
    /// section) and where a support or a rotational spring holds a node between the ends (its
    /// reaction moment).
    pub(crate) fn joints(&self) -> Vec<usize> {
        let (scene, _) = &*self.source;
        let segments = scene.structure.as_ref().map_or(&[][..], |st| &st.segments[..]);
        let last = self.model.mesh().positions.len() - 1;
        // The segments are meshed in order, each on its own `elements` (the scene kept is the
        // one this plan was built from, refined or not).
        let mut joints: Vec<usize> = segments
            .iter()
            .scan(0, |node, seg| {
                *node += seg.elements;
                Some(*node)
            })
            .filter(|node| *node < last)
            .collect();
        joints.extend((1..last).filter(|&node| (0..6).any(|k| self.model.dof(node, k).is_none())));
        joints.extend(self.model.rotational_spring_nodes().filter(|&node| 0 < node && node < last));
        joints.sort_unstable();
        joints.dedup();
        joints
    }
}

impl PartialEq for StructurePlan {
    fn eq(&self, other: &Self) -> bool {
        let (a, b) = (self.model.mesh(), other.model.mesh());
        self.ball_start == other.ball_start
            && self.up == other.up
            && self.face == other.face
            && self.half_depth.to_bits() == other.half_depth.to_bits()
            && self.sections == other.sections
            && self.base_elements == other.base_elements
            && self.rigid_modes == other.rigid_modes
            && a.positions == b.positions
            && a.frames == b.frames
            && (0..a.positions.len())
                .all(|n| (0..6).all(|k| self.model.dof(n, k) == other.model.dof(n, k)))
    }
}

/// A scene-file error of the structure's parts, its keys named as the impact scene writes them
/// (`structure.segment[1].end`).
fn prefixed(e: simo_beam::scene::SceneError) -> ImpactError {
    use simo_beam::scene::SceneError;
    match e {
        SceneError::InvalidField { field, value, allowed } => {
            ImpactError::InvalidField { field: format!("structure.{field}"), value, allowed }
        }
        SceneError::Inconsistent(message)
            if ["section", "segment", "support"].iter().any(|k| message.starts_with(k)) =>
        {
            ImpactError::Inconsistent(format!("structure.{message}"))
        }
        other => ImpactError::Inconsistent(format!("structure: {other}")),
    }
}

/// The fe plan of a ball striking `spec` as `scene.impact` says.
pub(super) fn plan(
    scene: &Scene,
    spec: &StructureSpec,
    pulse: &Pulse,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<FePlan, ImpactError> {
    let s = &scene.solver;
    if s.modes.is_some()
        || s.residual_flexibility.is_some()
        || s.plain_stress_series.is_some()
        || s.beam_theory.is_some()
        || s.adaptive_step.is_some()
        || s.energy_tolerance.is_some()
    {
        return Err(ImpactError::Inconsistent("solver.modes, residual_flexibility, plain_stress_series, beam_theory, adaptive_step and energy_tolerance belong to the modal method (solver.method = \"modal\" on a [structure]); the fe method takes none of them".into()));
    }
    checked_mesh_keys(s)?;
    let tolerance = s.tolerance.map(super::checked_tolerance).transpose()?;
    if let Some(tolerance) = tolerance {
        reasons.push(format!("every segment's elements doubled until two successive runs agree within solver.tolerance = {tolerance} on every significant contact and the largest displacement (second-order Richardson estimate of the finer's error), then the steps as for a beam"));
    }
    if s.fe_model == Some(FeModelName::Planar) {
        return Err(ImpactError::Inconsistent(
            "solver.fe_model = \"planar\" with a [structure]: a structure takes the 3D beam".into(),
        ));
    }
    let fe = build(scene, spec, pulse, (reasons, warnings))?;
    Steps::new(s, pulse, fe.local_frequency)?.reasons(s, pulse.duration, reasons);
    Ok(FePlan { tolerance, ..fe })
}

/// A structure's mesh is its segments' `elements`.
fn checked_mesh_keys(s: &crate::scene::SolverSpec) -> Result<(), ImpactError> {
    if s.elements.is_some() || s.element_size.is_some() {
        return Err(ImpactError::Inconsistent("a [structure]'s mesh is its segments' `elements`: solver.elements and element_size do not apply (give more elements per segment, or solver.tolerance)".into()));
    }
    Ok(())
}

/// Why a structure's modes stop at `cutoff` (rad/s) for a pulse of `duration` (s): omega t_c
/// = [`MODE_CUTOFF`], or `LOCAL_CUTOFF` (12) times the contact's local frequency where
/// that is higher ([`Pulse::fastest`]; the reason had said omega t_c <= 20 of a cutoff at 38.6,
/// a review's).
fn cutoff_reason(cutoff: f64, duration: f64) -> String {
    let product = cutoff * duration;
    if product > MODE_CUTOFF * (1.0 + 1e-9) {
        format!("omega t_c = {product:.1} for the estimated contact duration: {} times the contact's local frequency (the contact's stiffness against the struck section's point stiffness), above omega t_c = {MODE_CUTOFF}", super::modal::LOCAL_CUTOFF)
    } else {
        format!("omega t_c <= {MODE_CUTOFF} for the estimated contact duration")
    }
}

/// The modal method's plan on a structure (Goldsmith's method on a finite-element basis):
/// the 3D beam of [`plan`], its modes kept up to [`MODE_CUTOFF`] over the estimated contact
/// duration (computed when the plan runs), and the site's static flexibility by a static
/// solve; the truncated modes' share (solved from the deflated load when it runs) is in series
/// with the contact by default.
pub(super) fn modal_plan(
    scene: &Scene,
    spec: &StructureSpec,
    pulse: &Pulse,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<ModalPlan, ImpactError> {
    let s = &scene.solver;
    if s.modes.is_some() || s.beam_theory.is_some() {
        return Err(ImpactError::Inconsistent("solver.modes and beam_theory belong to the modal method's analytic modes of a uniform [beam] without masses or springs: the modes of a [structure], or of a [beam] that carries masses or springs (solver.modal_basis = \"fe\"), are its 3D finite-element beam's (shear and rotary inertia), all below the plan's cutoff (omega t_c = 20 for the estimated contact duration, or 12 times the contact's local frequency where that is higher); leave them out, and give solver.tolerance to refine them".into()));
    }
    checked_mesh_keys(s)?;
    let tolerance = s.tolerance.map(super::checked_tolerance).transpose()?;
    let fe = build(scene, spec, pulse, (reasons, warnings))?;
    if let Some(st) = &fe.structure {
        modes_keep_springs(spec, &st.sections, &fe.nodes)?;
        modes_keep_masses(spec, &st.model, &fe.nodes)?;
    }
    let cutoff = fe.structure.as_ref().map_or(MODE_CUTOFF / pulse.duration, |st| st.fastest);
    let basis = FeBasis::new(fe, cutoff)?;
    reasons.extend(basis.reduction());
    let static_flexibility = basis.static_flexibility();
    let residual_flexibility = s.residual_flexibility.unwrap_or(true);
    let plain_stress_series = s.plain_stress_series.unwrap_or(false);
    reasons.push(format!(
        "Goldsmith's method on the structure's own modes (solver.modal_basis = \"fe\"): every mode of its 3D beam linearised at rest (its masses, springs and supports; consistent mass) with omega <= {:.4e} rad/s ({}), by shift-invert Lanczos on a banded factorisation (counted by Sylvester's inertia), mass-normalised; the site's gain is the struck face's motion along the strike (bending plus offset x twist)",
        basis.cutoff,
        cutoff_reason(basis.cutoff, pulse.duration)
    ));
    if residual_flexibility {
        reasons.push(format!("residual flexibility{}: the truncated modes' static compliance at the site, solved from the load with the kept modes taken out (r' K^-1 r', r' = r - M Phi Phi^T r: a difference of the static flexibility and the modes' share would be round-off), in series with the contact; the strains' quasi-static share from the same solve (mode-acceleration method){}", if s.residual_flexibility.is_some() { ", as asked" } else { " (default on a structure: the mesh's highest modes are its least accurate, the static solve is exact to the mesh)" }, if static_flexibility.is_none() { "; the structure is free, so by inertia relief: r' is balanced by the rigid-body modes' inertia (they are among the kept ones) and solved with one node clamped, where a balanced load has no reaction (validation/REFERENCES.md 1.13)" } else { "" }));
    }
    if let Some(tolerance) = tolerance {
        reasons.push(format!("every segment's elements doubled (the modes' cutoff kept: the residual flexibility holds those above it) until two successive runs agree within solver.tolerance = {tolerance} on every significant contact's start, duration and peak force, the largest displacement and the largest stress (the finer's error a third of their difference, Richardson at second order; the largest displacement's their whole difference, its mesh error swinging in sign with the waves' dispersion)"));
    }
    reasons.push("structure: the bending stress is the section's worst corner's (extension and both bendings, in magnitude) and torsion_shear the Saint-Venant shear stress at each element's midpoint (positions are arc lengths; the bending stress at the impact point too, extrapolated from the midpoints on each side), from the modes' section strains plus the static solve's for the truncated ones, at every recorded instant (about 200 a contact, in free flight one every output interval or every end_time / 2000, whichever is shorter, and at most half a radian of the fastest mode kept apart (a peak within 3 % for that mode, closer for the slower ones that carry most of a stress): a coarse output thins the history, not the maxima): not searched between them; the twist likewise at every node".into());
    Ok(ModalPlan {
        basis: ModalBasis::Fe(Box::new(basis)),
        position: scene.impact.at.unwrap_or(0.0),
        damping: 0.0,
        modes: 0,
        tolerance,
        residual_flexibility,
        residual_by_share: false,
        plain_stress_series,
        twin: None,
        torsion: None,
    })
}

/// The most a rotational spring may outweigh its node's elements (their largest of E I2,
/// E I3 and G J over their length) for the modal method: the structure's modes are solved in
/// double precision, where a spring 1e9 times its elements' stiffness leaves the low modes
/// its round-off (the review's frame, 0.5 m members of 16 elements, 25 x 5 mm, a spring about
/// all three axes at its free tip: 1e12 N m/rad, 2.3e7 times, agrees with the fe method to
/// 1e-5; 1e14, 2.3e9 times, is 0.5 % off; 1e16, 66 %).
const SPRING_OVER_ELEMENTS: f64 = 1e8;

/// The most a translational spring may outweigh the structure's bending scale (the least
/// E I over the chain's length cubed) for the modal method: the static solve of its residual
/// flexibility and the deflation of its modes see the spring against the structure's softest
/// stiffness, a condition number of about their ratio. On the paper's strip propped at its tip
/// (scale 36 N/m), struck at 0.8 m, the largest displacement over 0.4 ms against a prop of
/// 1e13 N/m: 1e15 N/m (2.8e13 times) 4e-5 off, 1e16 3.5e-4 (about 1.4e-18 times the ratio);
/// over 0.2 ms 1e18 was 1.8 % off and 1e20 132 %, with a first mode of 35 us for 18 ms (a
/// review's). Against the elements beside the spring the bound had refused springs of 1e7 to
/// 1e8 N/m on coarse meshes (2 to 8 elements a member) that the modes carry to 1e-4 of the
/// fe method (a second review's). The bound keeps the error near 1e-4.
const PROP_OVER_STRUCTURE: f64 = 7e13;

/// Refuses for the modal method a spring that outweighs the structure's bending scale by more
/// than [`PROP_OVER_STRUCTURE`] (along a direction) or its node's elements by more than
/// [`SPRING_OVER_ELEMENTS`] (about an axis), naming it, the ratio and what holds the node
/// instead.
fn modes_keep_springs(
    spec: &StructureSpec,
    sections: &[[f64; 4]],
    nodes: &[f64],
) -> Result<(), ImpactError> {
    let length = nodes.last().copied().unwrap_or(0.0) - nodes.first().copied().unwrap_or(0.0);
    let least =
        sections.iter().map(|[young, _, w, t]| young * (w * t.powi(3)).min(t * w.powi(3)) / 12.0);
    let scale = least.fold(f64::INFINITY, f64::min) / length.powi(3);
    for (k, sp) in spec.springs.iter().enumerate() {
        let Some(node) = node_at(nodes, sp.at) else { continue };
        let elements = [node.checked_sub(1), (node < sections.len()).then_some(node)];
        // Along a direction: against the structure's own bending scale, the least E I over
        // the whole chain's length cubed: the static solve and the modes' deflation see the
        // spring against the structure's softest stiffness, a condition number of about their
        // ratio, not against the elements beside it.
        let largest = sp.stiffness.iter().copied().fold(0.0, f64::max);
        if largest > PROP_OVER_STRUCTURE * scale {
            return Err(invalid(
                &format!("structure.spring[{k}].stiffness"),
                format!("[{:e}, {:e}, {:e}]", sp.stiffness[0], sp.stiffness[1], sp.stiffness[2]),
                &format!("at most {PROP_OVER_STRUCTURE:e} times the structure's bending scale ({scale:.4e} N/m, the least E I over the chain's length cubed) for the modal method: this one is {:.1e} times, and the structure's static solve and modes, in double precision, would lose their accuracy to its round-off; hold the node by a [[structure.support]] (kind = \"pinned\") instead, or run solver.method = \"fe\"", largest / scale),
            ));
        }
        let Some(rotational) = sp.rotational_stiffness else { continue };
        let stiffness = |e: usize| {
            let [young, shear, w, t] = sections[e];
            let (j, _) = modal::rectangle_torsion(w, t);
            let largest =
                (young * w * t.powi(3) / 12.0).max(young * t * w.powi(3) / 12.0).max(shear * j);
            largest / (nodes[e + 1] - nodes[e])
        };
        let own = elements.into_iter().flatten().map(stiffness).fold(0.0, f64::max);
        let largest = rotational.iter().copied().fold(0.0, f64::max);
        if own > 0.0 && largest > SPRING_OVER_ELEMENTS * own {
            return Err(invalid(
                &format!("structure.spring[{k}].rotational_stiffness"),
                format!("[{:e}, {:e}, {:e}]", rotational[0], rotational[1], rotational[2]),
                &format!("at most {SPRING_OVER_ELEMENTS:e} times the rotational stiffness of the elements at its node ({own:.4e} N m/rad, the largest of E I and G J over their length) for the modal method: this one is {:.1e} times, and the structure's modes, solved in double precision, would lose their lowest to its round-off; hold the node by a [[structure.support]] (kind = \"clamped\") instead, or run solver.method = \"fe\"", largest / own),
            ));
        }
    }
    Ok(())
}

/// The most a point mass or its rotary inertia may outweigh its node's own share of its
/// elements' (half of each element's rho A l, rho I l) for the modal method: a review's tip
/// block of J2 = 1e15 kg m^2 on a 1 m strip (2e22 times its node's share) still met the fe
/// method's first contact to 2e-4, at 1e20 (2e27 times) the modes gave 0.034 N against 24.78
/// N. The bound is set far below both, where nothing physical is near (a mass a million
/// million times its node's is a support).
const MASS_OVER_ELEMENTS: f64 = 1e12;

/// Refuses for the modal method a point mass or rotary inertia that outweighs its node's own
/// share of the elements' by more than [`MASS_OVER_ELEMENTS`], naming it and the ratio.
fn modes_keep_masses(
    spec: &StructureSpec,
    model: &BeamModel,
    nodes: &[f64],
) -> Result<(), ImpactError> {
    let mesh = model.mesh();
    for (k, m) in spec.masses.iter().enumerate() {
        let Some(node) = node_at(nodes, m.at) else { continue };
        let (mut own, mut own_rotary) = (0.0, 0.0);
        for e in mesh.elements.iter().filter(|e| e.nodes.contains(&node)) {
            own += 0.5 * e.length * e.section.rho_a;
            own_rotary += 0.5 * e.length * e.section.rho_i.iter().copied().fold(0.0, f64::max);
        }
        let rotary = m.rotary_inertia.map_or([0.0; 3], crate::scene::RotaryInertia::axes);
        let largest = rotary.iter().copied().fold(0.0, f64::max);
        let key = if spec.lowered { "beam" } else { "structure" };
        for (what, value, share) in [("mass", m.mass, own), ("rotary_inertia", largest, own_rotary)]
        {
            if share > 0.0 && value > MASS_OVER_ELEMENTS * share {
                return Err(invalid(
                    &format!("{key}.mass[{k}].{what}"),
                    format!("{value:e}"),
                    &format!("at most {MASS_OVER_ELEMENTS:e} times its node's share of the elements' ({share:.4e}) for the modal method: this one is {:.1e} times, and the structure's modes, solved in double precision, lose the structure to it; hold the node by a support instead, or run solver.method = \"fe\"", value / share),
                ));
            }
        }
    }
    Ok(())
}

/// Segment `k`'s density (kg/m^3): its own section's or the structure's; `None` where neither
/// gives a positive one (the units check has said so).
fn density_of(spec: &StructureSpec, k: usize) -> Option<f64> {
    spec.segments[k]
        .section
        .as_ref()
        .and_then(|own| own.density)
        .or(spec.section.density)
        .filter(|d| *d > 0.0)
}

/// Warns where the struck element is too long for the bending wave the pulse excites in the
/// strike's plane, as a `[beam]`'s mesh check does (`super::fe`'s `resolution`: the largest
/// stress near the ball low by about 0.6 (h/lambda)^2, the contact force too), naming the
/// segment's `elements` and how many would do; not with `solver.tolerance`, whose refinement
/// checks its meshes against each other.
fn mesh_at_impact(
    scene: &Scene,
    (sections, stations, (e, segment)): (&[[f64; 4]], &[f64], (usize, usize)),
    (face, duration): (Face, f64),
    warnings: &mut Vec<String>,
) {
    if scene.solver.tolerance.is_some() {
        return;
    }
    let Some(st) = &scene.structure else { return };
    let [young, _, w, t] = sections[e];
    let density = density_of(st, segment).unwrap_or(0.0);
    let (across, depth) = if face == Face::Thickness { (w, t) } else { (t, w) };
    let rigidity = young * across * depth.powi(3) / 12.0;
    let omega = MODE_CUTOFF / duration;
    let wavelength =
        2.0 * std::f64::consts::PI * (rigidity / (density * w * t)).powf(0.25) / omega.sqrt();
    let h = stations[e + 1] - stations[e];
    let stress_error = super::fe::STRESS_MESH_ERROR * (h / wavelength).powi(2);
    if density > 0.0 && stress_error > super::fe::STRESS_MESH_WARNING {
        let size = if h > wavelength {
            "several times off".to_string()
        } else {
            format!("about {:.0} % low", 100.0 * stress_error)
        };
        let elements = st.segments[segment].elements;
        let enough = (elements as f64 * h
            / (wavelength
                * (super::fe::STRESS_MESH_WARNING / super::fe::STRESS_MESH_ERROR).sqrt()))
        .ceil();
        warnings.push(format!(
            "structure.segment[{segment}].elements = {elements}: elements of {h:.3e} m at the impact point, {:.2} of the flexural wavelength the pulse excites in the strike's plane ({wavelength:.3e} m at omega t_c = {MODE_CUTOFF}): the contact force, the stress near the ball and the displacement under it are not resolved (the largest stress {size}; a review's frame of validation/REFERENCES.md 1.11 at 0.51 of the wavelength: its first peak force and largest displacement 1 % and 2.1 % high, the stress 6.4 % low, the modal and fe methods agreeing to 1e-4 on the same mesh, so that comparing them does not show it); give the segment at least {enough} elements, or set solver.tolerance",
            h / wavelength
        ));
    }
}

/// The supports whose stress is extrapolated from midpoints (a clamp, an interior support; a
/// pin at an end holds no moment): its size on the shortest wave the pulse excites into the
/// reasons, warned where large (`super::fe::support_mesh`), where the waves reach it within the
/// window (its arc length from the ball within their reach); the wave's section is that of the
/// support's longer neighbouring element, bent across its thinner side (the shorter wave); not
/// with `solver.tolerance`, whose meshes come later.
fn supports_mesh(
    scene: &Scene,
    (sections, stations, segment_of): (&[[f64; 4]], &[f64], &[usize]),
    (at, duration): (f64, f64),
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) {
    let Some(st) = scene.structure.as_ref().filter(|_| scene.solver.tolerance.is_none()) else {
        return;
    };
    let total = stations.last().copied().unwrap_or(0.0);
    for sp in &st.supports {
        let Some(node) = stations.iter().position(|x| (x - sp.at).abs() <= 1e-9 * total.max(1.0))
        else {
            continue;
        };
        let end = node == 0 || node + 1 == stations.len();
        if end && sp.kind != Support::Clamped {
            continue;
        }
        let what =
            format!("the {} support at s = {} m", format!("{:?}", sp.kind).to_lowercase(), sp.at);
        // An interior support too (a review's clamp at s = 0.6 struck 1 mm beside it: 27 % low,
        // unwarned, where the same strike beside an end clamp was warned).
        let segment = segment_of[if node == 0 { 0 } else { node - 1 }];
        let advice = format!("structure.segment[{segment}].elements");
        super::fe::kink_beside((stations, node, at), (&what, &advice), warnings);
        // The longer of its neighbouring elements.
        let Some(e) = [node.checked_sub(1), (node + 1 < stations.len()).then_some(node)]
            .into_iter()
            .flatten()
            .max_by(|a, b| {
                (stations[a + 1] - stations[*a]).total_cmp(&(stations[b + 1] - stations[*b]))
            })
        else {
            continue;
        };
        let [young, _, w, t] = sections[e];
        let segment = segment_of[e];
        let Some(density) = density_of(st, segment) else { continue };
        let (across, depth) = (w.max(t), w.min(t));
        let rigidity = young * across * depth.powi(3) / 12.0;
        let bar = (young / density).sqrt();
        let (wavelength, speed) =
            super::fe::shortest_wave(rigidity, density * w * t, duration, bar);
        if (sp.at - at).abs() > super::fe::reach(&scene.solver, speed) {
            continue;
        }
        let key = format!("structure.segment[{segment}].elements");
        let elements = st.segments[segment].elements;
        let h = stations[e + 1] - stations[e];
        super::fe::support_mesh((&what, &key, elements), (h, wavelength), (reasons, warnings));
    }
}

/// A `[beam]` that carries masses or springs, written as the `[structure]` it is (one straight
/// member along x, struck on its thickness face from +z, a node at each attachment and at the
/// impact point), for the modal method on its finite-element basis. The mesh: elements of at
/// most a sixteenth of the bending wavelength at the cutoff (omega t_c = 20), as the fe
/// method's, and at most L / 64 (with an eighth, a 0.5 m cantilever over 2 ms: its clamp's
/// stress 10 % high with a 20 g tip mass, struck 10 mm off the centre line its twist 5.5 % high
/// and its largest stress 8.7 % low; with a sixteenth 3.8 % low, 0.35 % and 1 % against runs
/// refined to 2e-3; validation/REFERENCES.md 1.13).
/// A spring's rotational stiffness is about the section's width axis, as the fe method's.
pub(super) fn lowered(
    scene: &Scene,
    beam: &crate::scene::BeamSpec,
    position: f64,
    pulse: &Pulse,
) -> (Scene, StructureSpec) {
    let length = beam.length;
    let area = beam.width * beam.thickness;
    let ei = beam.youngs_modulus * beam.width * beam.thickness.powi(3) / 12.0;
    let cutoff = pulse.fastest(ei, beam.density * area);
    let wavenumber = (beam.density * area * cutoff * cutoff / ei).powf(0.25);
    let size = (2.0 * std::f64::consts::PI / wavenumber / super::fe::FE_ELEMENTS_PER_WAVELENGTH)
        .min(length / 64.0);
    // The pieces between the ends, the attachments and the impact point.
    let mut cuts: Vec<f64> =
        beam.masses.iter().map(|m| m.at).chain(beam.springs.iter().map(|s| s.at)).collect();
    cuts.extend([0.0, position, length]);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * length);
    let mut segments = Vec::new();
    let pieces = cuts.len() - 1;
    for (k, w) in cuts.windows(2).enumerate() {
        // At least two elements on a piece at an end: its stress is extrapolated from its two
        // nearest midpoints, which must not straddle the kink the ball or an attachment puts in
        // the moment at the piece's other end (1 mm from the clamp on one element: the clamp's
        // stress 32 % low, a review's; validation/REFERENCES.md 1.5).
        let least = if k == 0 || k + 1 == pieces { 2.0 } else { 1.0 };
        segments.push(simo_beam::scene::SegmentSpec::straight(
            (k == 0).then_some([0.0, 0.0, 0.0]),
            [w[1], 0.0, 0.0],
            ((w[1] - w[0]) / size).ceil().max(least) as usize,
        ));
    }
    let spec = beam_as_structure(beam, segments);
    let mut lowered = scene.clone();
    lowered.beam = None;
    lowered.structure = Some(spec.clone());
    lowered.impact.position = None;
    lowered.impact.at = Some(position);
    lowered.impact.direction = Some([0.0, 0.0, -1.0]);
    (lowered, spec)
}

/// A `[beam]` written as the `[structure]` it is, on `segments` (along x from 0 to its length,
/// thickness along z): its section, its ends' supports, its masses, and its springs along z
/// and, where given, about the section's width axis E2 (against the bending rotation).
fn beam_as_structure(
    beam: &crate::scene::BeamSpec,
    segments: Vec<simo_beam::scene::SegmentSpec>,
) -> StructureSpec {
    let [first, last] = beam.support.ends();
    // A [beam]'s pinned end is a fork in 3D: it holds the twist, as its torsion modes do
    // (validation/REFERENCES.md 1.9); a bare pin would leave the strip free to spin about its
    // axis (struck off the centre line, its twist had grown without bound).
    let forked = |kind: Support| if kind == Support::Pinned { Support::Forked } else { kind };
    let supports = [(0.0, first), (beam.length, last)]
        .into_iter()
        .filter(|(_, kind)| *kind != Support::Free)
        .map(|(at, kind)| simo_beam::scene::SupportSpec { at, kind: forked(kind) })
        .collect();
    StructureSpec {
        section: simo_beam::scene::SectionSpec {
            youngs_modulus: Some(beam.youngs_modulus),
            poisson_ratio: Some(beam.poisson_ratio),
            density: Some(beam.density),
            width: Some(beam.width),
            thickness: Some(beam.thickness),
            ..Default::default()
        },
        segments,
        supports,
        yield_stress: beam.yield_stress,
        masses: beam.masses.clone(),
        springs: beam
            .springs
            .iter()
            .map(|s| crate::scene::StructureSpringSpec {
                at: s.at,
                stiffness: [0.0, 0.0, s.stiffness],
                rotational_stiffness: s
                    .rotational_stiffness
                    .filter(|r| *r > 0.0)
                    .map(|r| [0.0, r, 0.0]),
            })
            .collect(),
        lowered: true,
    }
}

/// A `[beam]`'s 3D beam for the fe method, as the `[structure]` it is ([`beam_as_structure`]):
/// one straight member on the fe plan's own nodes (its graded mesh: `SegmentSpec::nodes`),
/// struck on its thickness face from +z at `fe.position`, `fe.offset` across the width. The same description, parser and model as a
/// `[structure]`'s ([`model_of`]); the plan's other parts stay the beam's (its analytic static
/// flexibility, its mesh ladder).
///
/// # Errors
/// From the description (not expected: the beam was checked).
pub(super) fn of_beam(
    fe: &FePlan,
    scene: &Scene,
    pulse: &Pulse,
) -> Result<StructurePlan, ImpactError> {
    let beam = scene.beam.as_ref().ok_or_else(|| {
        ImpactError::Inconsistent("a [beam]'s structure without its [beam]".into())
    })?;
    let length = fe.nodes.last().copied().unwrap_or(0.0);
    let elements = fe.elements();
    let segment = simo_beam::scene::SegmentSpec {
        nodes: Some(fe.nodes.iter().map(|x| x / length).collect()),
        ..simo_beam::scene::SegmentSpec::straight(Some([0.0; 3]), [length, 0.0, 0.0], elements)
    };
    let spec = beam_as_structure(beam, vec![segment]);
    let (model, _) = model_of(&spec)?;
    let m = &fe.material;
    let half_depth = 0.5 * fe.thickness;
    let clamped = [fe.ends.0, fe.ends.1].contains(&Support::Clamped);
    let rigid_modes = if clamped { 0 } else { simo_beam::rigid_body_modes(&model)? };
    let mut source = scene.clone();
    source.structure = Some(spec);
    Ok(StructurePlan {
        model,
        ball_start: Vector3::new(fe.position, fe.offset, half_depth + scene.ball.radius),
        up: Vector3::z(),
        face: Face::Thickness,
        half_depth,
        sections: vec![[m.youngs_modulus, m.shear_modulus, fe.width, fe.thickness]; elements],
        rigid_modes,
        fastest: pulse.fastest(
            m.youngs_modulus * fe.width * fe.thickness.powi(3) / 12.0,
            m.density * fe.width * fe.thickness,
        ),
        source: Box::new((source, *pulse)),
        base_elements: elements,
    })
}

impl StructurePlan {
    /// The scene and pulse the plan was made from.
    pub(super) fn source(&self) -> (&Scene, &Pulse) {
        let (scene, pulse) = &*self.source;
        (scene, pulse)
    }
}

/// A structure's modal basis as planned: its 3D beam and strike (the fe method's plan) and
/// the cutoff; the static flexibility at the site is solved when planned, the modes when run
/// (`solve::modal`).
#[derive(Debug, Clone)]
pub struct FeBasis {
    pub(crate) fe: FePlan,
    /// Modes are kept up to this angular frequency (rad/s).
    pub(crate) cutoff: f64,
    /// The site's static flexibility (m/N), `None` for a free structure.
    static_flexibility: Option<f64>,
    /// The unknowns the strike cannot move, held in the basis' model, and why.
    reduction: Option<Uncoupled>,
    /// The basis' model linearised at rest: assembled once for the static solves and the
    /// eigen-solution (shared by the plan's clones; what the fields above determine).
    at_rest: Arc<AtRest>,
}

impl PartialEq for FeBasis {
    fn eq(&self, other: &Self) -> bool {
        self.fe == other.fe
            && self.cutoff.to_bits() == other.cutoff.to_bits()
            && self.static_flexibility == other.static_flexibility
            && self.reduction == other.reduction
    }
}

/// Two directions are parallel (or a point on a line or plane) within this.
const ALIGNED: f64 = 1e-9;

/// What a strike cannot move (see [`uncoupled`]).
#[derive(Debug, Clone, PartialEq)]
struct Uncoupled {
    /// The unknowns (node, component) held.
    held: Vec<(usize, usize)>,
    /// Per element, which of its section strains (extension, twist rate, the curvatures about
    /// E2 and E3) the held model cannot strain: their rows would be round-off.
    quiet: Vec<[bool; 4]>,
    why: &'static str,
}

/// Whether every node of `mesh` lies in the plane through its first node normal to `normal`
/// (a unit vector), within [`ALIGNED`] of the mesh's extent.
fn in_plane(mesh: &simo_beam::Mesh, normal: &Vector3<f64>) -> bool {
    let origin = mesh.positions[0];
    let extent = mesh.positions.iter().map(|p| (p - origin).norm()).fold(0.0, f64::max);
    mesh.positions.iter().all(|p| (p - origin).dot(normal).abs() <= ALIGNED * extent)
}

/// The material axis (1: E2, 2: E3) of the section `frame` along `normal`, if one is.
fn normal_axis(frame: &nalgebra::UnitQuaternion<f64>, normal: &Vector3<f64>) -> Option<usize> {
    (1..3).find(|c| (frame * Vector3::ith(*c, 1.0)).dot(normal).abs() >= 1.0 - ALIGNED)
}

/// The node of `nodes` (arc lengths, m) at `at`, if one is.
fn node_at(nodes: &[f64], at: f64) -> Option<usize> {
    nodes.iter().position(|x| (x - at).abs() <= 1e-9 * (1.0 + x.abs()))
}

/// Whether a chain that is not a straight line lies in one plane and is struck in that plane
/// (centred: the caller checks the offset), every section with a principal axis (E2 or E3)
/// normal to it and every spring's stiffness mapping that normal onto itself: then the motions
/// in the plane uncouple from those out of it and only these are loaded, so nothing twists (a
/// review's portal struck at mid-beam twisted 1.6e-14 rad and had been warned of a torsion
/// shear 30 % off, advising 13933 elements).
fn struck_in_its_plane(mesh: &simo_beam::Mesh, spec: &StructureSpec, d: Vector3<f64>) -> bool {
    let origin = mesh.positions[0];
    let far = mesh.positions.iter().map(|p| p - origin).fold(Vector3::zeros(), |a, b| {
        if b.norm() > a.norm() {
            b
        } else {
            a
        }
    });
    let Some(normal) = mesh
        .positions
        .iter()
        .map(|p| far.cross(&(p - origin)))
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .filter(|n| n.norm() > 0.0)
        .map(|n| n.normalize())
    else {
        return false;
    };
    let principal = |frame: &nalgebra::UnitQuaternion<f64>| normal_axis(frame, &normal).is_some();
    let sections = mesh.frames.iter().all(principal)
        && mesh
            .elements
            .iter()
            .all(|e| (0..2).all(|end| principal(&(mesh.frames[e.nodes[end]] * e.offsets[end]))));
    let springs = spec.springs.iter().all(|sp| {
        let k = Vector3::from(sp.stiffness).component_mul(&normal);
        k.cross(&normal).norm() <= ALIGNED * k.norm()
    });
    in_plane(mesh, &normal) && sections && springs && d.dot(&normal).abs() <= ALIGNED
}

/// The unknowns of `st`'s beam that a strike along `-st.up` at `offset` cannot move when
/// linearised at rest, and why: where every node lies in one plane normal to the strike, the
/// strike is along a coordinate axis (the springs act along the axes, the rotational ones about
/// the section's) and every node's and element end's section has a principal axis along it,
/// the motions in the plane (the two
/// translations in it, the rotation about its normal) uncouple from those out of it, and only
/// these are loaded; where, besides, the nodes lie on one line and the strike is on the
/// centre line, the twist uncouples too (a rectangle's shear centre is its centroid). The
/// modes of the held model are then the structure's modes that move the face, exactly, and
/// they strain no element in extension or in bending about the plane's normal (nor in twist,
/// on the line).
fn uncoupled(st: &StructurePlan, offset: f64) -> Option<Uncoupled> {
    let mesh = st.model.mesh();
    let n = st.up;
    let axis = (0..3).find(|a| n[*a].abs() >= 1.0 - ALIGNED)?;
    let origin = mesh.positions[0];
    let extent = mesh.positions.iter().map(|p| (p - origin).norm()).fold(0.0, f64::max);
    let normal_axis = |frame: &nalgebra::UnitQuaternion<f64>| normal_axis(frame, &n);
    let normals = mesh.frames.iter().map(normal_axis).collect::<Option<Vec<usize>>>()?;
    let element_normals = mesh
        .elements
        .iter()
        .map(|e| {
            let [a, b] =
                [0, 1].map(|end| normal_axis(&(mesh.frames[e.nodes[end]] * e.offsets[end])));
            a.filter(|c| Some(*c) == b)
        })
        .collect::<Option<Vec<usize>>>()?;
    if !in_plane(mesh, &n) {
        return None;
    }
    let last = mesh.positions[mesh.positions.len() - 1];
    let line = (last - origin).normalize();
    let straight = offset == 0.0
        && extent > 0.0
        && mesh.positions.iter().all(|p| (p - origin).cross(&line).norm() <= ALIGNED * extent)
        && mesh.frames.iter().all(|f| (f * Vector3::x()).dot(&line).abs() >= 1.0 - ALIGNED);
    let mut held = Vec::new();
    for (node, normal) in normals.iter().enumerate() {
        held.extend((0..3).filter(|k| *k != axis).map(|k| (node, k)));
        held.push((node, 3 + normal));
        if straight {
            held.push((node, 3));
        }
    }
    // Extension and the bending about the normal (K2 where E2 is along it, K3 where E3 is)
    // are in-plane strains; the twist rate is quiet on the line.
    let quiet = element_normals.iter().map(|c| [true, straight, *c == 1, *c == 2]).collect();
    let why = if straight {
        "a straight member struck on its centre line normal to a face: only its bending across that face moves it (the motions in the face's plane and the twist uncouple)"
    } else {
        "a planar structure struck normal to its plane: only its motions out of the plane move the face (bending across the plane and twist; those in the plane uncouple)"
    };
    Some(Uncoupled { held, quiet, why })
}

impl FeBasis {
    /// The basis of `fe`'s structure up to `cutoff` (rad/s), with the site's static
    /// flexibility.
    ///
    /// # Errors
    /// `Inconsistent` if `fe` holds no structure.
    pub(crate) fn new(fe: FePlan, cutoff: f64) -> Result<Self, ImpactError> {
        let reduction = uncoupled(Self::structure_of(&fe)?, fe.offset);
        Self::with_reduction(fe, cutoff, reduction)
    }

    /// The basis with `reduction`'s unknowns held: its model linearised at rest and the site's
    /// static flexibility on it, `None` unless it is held.
    fn with_reduction(
        fe: FePlan,
        cutoff: f64,
        reduction: Option<Uncoupled>,
    ) -> Result<Self, ImpactError> {
        let model = Self::model_of(&fe, reduction.as_ref())?;
        let at_rest = Arc::new(AtRest::of(&model));
        let mut basis = Self { fe, cutoff, static_flexibility: None, reduction, at_rest };
        let rows = basis.face_rows(&model);
        basis.static_flexibility = (basis.structure()?.rigid_modes == 0)
            .then(|| crate::solve::static_response_at_rest(&basis.at_rest, &rows).map(|(f, _)| f))
            .flatten();
        Ok(basis)
    }

    /// The same basis on the whole model (no unknown held): what the reduction must equal.
    #[cfg(test)]
    pub(crate) fn whole(&self) -> Result<Self, ImpactError> {
        Self::with_reduction(self.fe.clone(), self.cutoff, None)
    }

    /// The basis' model linearised at rest.
    pub(crate) fn at_rest(&self) -> &AtRest {
        &self.at_rest
    }

    /// Per element, which section strains (extension, twist rate, the curvatures about E2 and
    /// E3) the basis' modes cannot strain (none where nothing is held).
    pub(crate) fn quiet_strains(&self) -> Option<&[[bool; 4]]> {
        self.reduction.as_ref().map(|r| r.quiet.as_slice())
    }

    /// The structure the basis is of.
    ///
    /// # Errors
    /// `Inconsistent` if the basis holds none (not expected: it is built from one).
    pub(crate) fn structure(&self) -> Result<&StructurePlan, ImpactError> {
        Self::structure_of(&self.fe)
    }

    fn structure_of(fe: &FePlan) -> Result<&StructurePlan, ImpactError> {
        fe.structure
            .as_deref()
            .ok_or_else(|| ImpactError::Inconsistent("an fe basis without its structure".into()))
    }

    /// The basis' model: the structure's 3D beam with the unknowns the strike cannot move held.
    ///
    /// # Errors
    /// `Inconsistent` if the basis holds no structure.
    pub(crate) fn model(&self) -> Result<BeamModel, ImpactError> {
        Self::model_of(&self.fe, self.reduction.as_ref())
    }

    fn model_of(fe: &FePlan, reduction: Option<&Uncoupled>) -> Result<BeamModel, ImpactError> {
        let st = Self::structure_of(fe)?;
        Ok(match reduction {
            Some(r) => st.model.clone().hold(&r.held)?,
            None => st.model.clone(),
        })
    }

    /// The face rows of the strike (see [`crate::solve::face_rows`]) on `model` (the basis').
    pub(crate) fn face_rows(&self, model: &BeamModel) -> Vec<(usize, f64)> {
        self.fe.structure.as_ref().map_or_else(Vec::new, |st| {
            crate::solve::face_rows(model, (st.up, st.face, self.fe.offset), self.fe.impact_site())
        })
    }

    /// Why the basis' model holds some unknowns, and how many it keeps of how many, if it does.
    pub(crate) fn reduction(&self) -> Option<String> {
        let st = self.fe.structure.as_ref()?;
        let why = self.reduction.as_ref()?.why;
        use hht::Model;
        let (kept, all) = (self.model().ok()?.ndof(), st.model.ndof());
        Some(format!("{why}: the modes are solved on those unknowns only, {kept} of {all}, the others held (exact for the structure linearised at rest)"))
    }

    /// The site's static flexibility (m/N), `None` for a free structure.
    pub fn static_flexibility(&self) -> Option<f64> {
        self.static_flexibility
    }

    /// The same basis on every segment's elements times `factor` (a rung of the tolerance's
    /// ladder), at the same cutoff: the modes above it answer the pulse quasi-statically, and
    /// the residual flexibility holds them at any mesh (doubling the cutoff with the mesh took
    /// the frame's ladder to 8475 modes and 291 s at 2560 elements for no change it could
    /// see).
    ///
    /// # Errors
    /// From rebuilding the structure (not expected: it was built once).
    pub(crate) fn refined(&self, factor: usize) -> Result<Self, ImpactError> {
        Self::new(self.structure()?.refined(factor)?, self.cutoff)
    }

    /// Each segment's elements (the basis' mesh).
    pub(crate) fn elements(&self) -> usize {
        self.fe.elements()
    }

    /// The structure's length along its segments (m).
    pub(crate) fn length(&self) -> f64 {
        self.fe.nodes.last().copied().unwrap_or(0.0) - self.fe.nodes.first().copied().unwrap_or(0.0)
    }
}

/// The 3D beam of `spec` (its segments, supports, masses and springs) and its nodes' arc
/// lengths (m): what a `[structure]` and a `[beam]` lowered onto one share.
fn model_of(spec: &StructureSpec) -> Result<(BeamModel, Vec<f64>), ImpactError> {
    let (mut model, stations) =
        simo_beam::scene::structure(&spec.section, &spec.segments, &spec.supports)
            .map_err(prefixed)?;
    // A mass or a spring sits on a node: the node at its arc length, or refused naming the
    // nearest.
    let node =
        |key: String, at: f64| simo_beam::scene::node_at(&stations, key, at).map_err(prefixed);
    for (k, m) in spec.masses.iter().enumerate() {
        let n = node(format!("mass[{k}].at"), m.at)?;
        let mass = not_negative(&format!("structure.mass[{k}].mass"), m.mass, "kg")?;
        let rotary = super::rotary_inertia(&format!("structure.mass[{k}]"), m.rotary_inertia)?;
        model = model.attach_mass(n, mass, rotary)?;
    }
    for (k, sp) in spec.springs.iter().enumerate() {
        let n = node(format!("spring[{k}].at"), sp.at)?;
        for (i, v) in sp.stiffness.iter().enumerate() {
            not_negative(&format!("structure.spring[{k}].stiffness[{i}]"), *v, "N/m")?;
        }
        model = model.attach_spring(n, Vector3::from(sp.stiffness))?;
        if let Some(rotational) = sp.rotational_stiffness {
            for (i, v) in rotational.iter().enumerate() {
                not_negative(
                    &format!("structure.spring[{k}].rotational_stiffness[{i}]"),
                    *v,
                    "N m/rad",
                )?;
            }
            model = model.attach_rotational_spring(n, Vector3::from(rotational))?;
        }
    }
    Ok((model, stations))
}

/// The 3D beam of `spec` and the strike on it, as `scene.impact` says (the steps are the
/// caller's).
fn build(
    scene: &Scene,
    spec: &StructureSpec,
    pulse: &Pulse,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<FePlan, ImpactError> {
    let s = &scene.solver;
    let impact = &scene.impact;
    if impact.position.is_some() {
        return Err(ImpactError::Inconsistent("impact.position belongs to a [beam]; a [structure] takes impact.at (the arc length along its segments, m) and impact.direction (the ball's velocity)".into()));
    }
    let (model, stations) = model_of(spec)?;
    let total = stations.last().copied().unwrap_or(0.0);
    if !(spec.masses.is_empty() && spec.springs.is_empty()) {
        reasons.push(format!(
            "{} point mass(es) and {} spring(s) at their nodes",
            spec.masses.len(),
            spec.springs.len()
        ));
    }
    // Each element's section: the structure's, or its segment's own (a stepped member).
    let rectangle = |key: &str, section: &simo_beam::scene::SectionSpec| {
        match (
        section.width,
        section.thickness,
        section.youngs_modulus,
        section.poisson_ratio,
    ) {
        (Some(w), Some(t), Some(e), Some(nu)) => Ok([e, e / (2.0 * (1.0 + nu)), w, t]),
        _ => Err(ImpactError::Inconsistent(format!("{key}: give width and thickness (m), a rectangle of a material (youngs_modulus, poisson_ratio, density): a struck structure's stresses are read at its members' faces, which the stiffnesses alone do not place"))),
    }
    };
    let shared = rectangle("structure.section", &spec.section)?;
    // Each element's section and segment.
    let (mut sections, mut segment_of) = (Vec::new(), Vec::new());
    for (i, seg) in spec.segments.iter().enumerate() {
        let own = match &seg.section {
            Some(own) => rectangle(&format!("structure.segment[{i}].section"), own)?,
            None => shared,
        };
        sections.extend(std::iter::repeat_n(own, seg.elements));
        segment_of.extend(std::iter::repeat_n(i, seg.elements));
    }
    let section = &spec.section;
    let material = simo_beam::Material::new(
        section.youngs_modulus.unwrap_or(f64::NAN),
        section.poisson_ratio.unwrap_or(f64::NAN),
        section.density.unwrap_or(f64::NAN),
    )?;
    let at = impact.at.ok_or_else(|| {
        ImpactError::Inconsistent("impact.at (m, the arc length along the [structure]'s segments) is required with a [structure]".into())
    })?;
    if !(at.is_finite() && (0.0..=total).contains(&at)) {
        return Err(invalid(
            "impact.at",
            at,
            &format!("must be on the structure, 0 <= at <= {total} m (its segments' length)"),
        ));
    }
    let e = stations.partition_point(|x| *x <= at).saturating_sub(1).min(stations.len() - 2);
    let xi = (at - stations[e]) / (stations[e + 1] - stations[e]);
    let mesh = model.mesh();
    let [a, b] = mesh.elements[e].nodes;
    // The struck element's section: its faces, and the contact's material (the law is set from
    // the structure's section).
    let [struck_e, _, width, thickness] = sections[e];
    if (struck_e - shared[0]).abs() > 1e-12 * shared[0] {
        return Err(ImpactError::Inconsistent(format!("impact.at = {at} m strikes a segment whose own section's youngs_modulus ({struck_e:e} Pa) is not the structure's ({:e} Pa): the contact is set from [structure.section]; strike a member of that material", shared[0])));
    }
    // The struck element's own end frames (at a corner its node's frame is the other
    // member's: the faces' normals were interpolated from it on the element after a corner).
    let offsets = mesh.elements[e].offsets;
    let axis = |k: Vector3<f64>| {
        let (fa, fb) = (mesh.frames[a] * offsets[0], mesh.frames[b] * offsets[1]);
        ((fa * k) * (1.0 - xi) + (fb * k) * xi).normalize()
    };
    let (e2, e3) = (axis(Vector3::y()), axis(Vector3::z()));
    let d = impact.direction.ok_or_else(|| {
        ImpactError::Inconsistent("impact.direction (the ball's velocity, a vector normal to the struck face) is required with a [structure]".into())
    })?;
    let d = Vector3::from(d);
    if !(d.iter().all(|x| x.is_finite()) && d.amax() > 0.0) {
        return Err(invalid(
            "impact.direction",
            format!("{:?}", [d.x, d.y, d.z]),
            "a vector of three finite numbers, not all zero",
        ));
    }
    // Scaled by its largest component first: the norm of [0, 0, 1e300] overflows, of
    // [0, 0, 1e-300] underflows, and any length is allowed.
    let d = (d / d.amax()).normalize();
    // Gravity acts along the ball's velocity: on a structure (z up) that is the world's only
    // for a strike straight down (one from below had been pulled back up into the structure,
    // three contacts in 0.3 s). A drop height alone is a speed, sqrt(2 g h).
    if impact.gravity && 1.0 + d.z > NORMAL {
        return Err(ImpactError::Inconsistent(format!(
            "impact.gravity = true: gravity acts on the ball along its velocity (a drop), so with it the strike must be straight down (impact.direction = [0, 0, -1], z up); this one is [{:.6}, {:.6}, {:.6}]: set impact.gravity = false (the ball then keeps its impact speed)",
            d.x, d.y, d.z
        )));
    }
    let show = |v: Vector3<f64>| format!("[{:.6}, {:.6}, {:.6}]", v.x, v.y, v.z);
    // The face the direction is normal to: its distance from the centre line, the axis and
    // the size of the face across (where the offset goes).
    let (face, half_depth, across, size) = if 1.0 - d.dot(&e3).abs() <= NORMAL {
        (Face::Thickness, 0.5 * thickness, e2, width)
    } else if 1.0 - d.dot(&e2).abs() <= NORMAL {
        (Face::Width, 0.5 * width, e3, thickness)
    } else {
        return Err(invalid(
            "impact.direction",
            show(d),
            &format!("must be normal to a face of the struck section at impact.at = {at} m: its thickness faces' normals are +-{}, its width faces' +-{}; an oblique strike would need friction, which is not modelled", show(e3), show(e2)),
        ));
    };
    // A width face of an arc curves in the strike's plane; the contact follows the elements'
    // straight chords, which kink there at every node: on the convex side a ball over a node
    // starts inside the chords' face (0.34 mm on a 0.25 m arc of 8 elements a half turn: its
    // first contact then made 50 times the ball's energy), on the concave side it meets two.
    let k = segment_of[e];
    if face == Face::Width && spec.segments[k].centre.is_some() {
        return Err(invalid(
            "impact.direction",
            show(d),
            &format!("strikes a width face (normal +-{}) of structure.segment[{k}], an arc: its width faces curve in the strike's plane, which the contact (on the elements' straight chords) does not follow; strike its thickness faces (normal +-{}) or a straight member", show(e2), show(e3)),
        ));
    }
    let offset = offset(size, impact.offset, scene.ball.radius, pulse, warnings)?;
    let up = -d;
    // A face the supports hold still (a supported node, or an element between two): the ball
    // would meet a rigid face (it ran, as a rigid strike, warned as "a free-free beam").
    if crate::solve::face_rows(&model, (up, face, offset), (e, xi)).is_empty() {
        // On a node the element's other node is not loaded (xi is 0, or 1 at the chain's end).
        let on_node = xi <= 0.0 || xi >= 1.0;
        return Err(invalid(
            "impact.at",
            at,
            &if on_node {
                "must be a point the supports leave free: it is a supported node, where the ball would meet a rigid face".to_string()
            } else {
                format!("must be a point the supports leave free: both nodes of its element (at {} and {} m) are supported, so the mesh holds the face still; give the member more elements", stations[e], stations[e + 1])
            },
        ));
    }
    let point = mesh.positions[a] * (1.0 - xi) + mesh.positions[b] * xi + across * offset;
    let ball_start = point + up * (half_depth + scene.ball.radius);
    let supports: Vec<String> = spec
        .supports
        .iter()
        .map(|sp| format!("{:?} at s = {} m", sp.kind, sp.at).to_lowercase())
        .collect();
    reasons.push(format!(
        "structure of {} segment(s), {} elements, {} m of members, held {}: 3D geometrically exact beam (Simo's rod, 6 unknowns a node; rigid joints where segments meet), the ball striking the face at s = {at} m along {} (a {} face){}",
        spec.segments.len(),
        mesh.elements.len(),
        total,
        if supports.is_empty() { "nowhere".to_string() } else { supports.join(", ") },
        show(d),
        if face == Face::Thickness { "thickness" } else { "width" },
        if offset != 0.0 { format!(", {offset} m across the width") } else { String::new() }
    ));
    // The time scale the meshes are sized for: the pulse's, or the contact's local response
    // on the struck section for a heavy ball (`Pulse::sized`).
    // And the steps: at least LOCAL_STEPS a period of the contact's local frequency there (a
    // 100 kg ball on a cantilever structure's tip had its first contact 29 % long at the
    // rigid-support pulse's 200 a pulse, a review's; validation/REFERENCES.md 1.5).
    let (sized, local_frequency) = {
        let [young, _, w, t] = sections[e];
        let (across, depth) = if face == Face::Thickness { (w, t) } else { (t, w) };
        match density_of(spec, k) {
            Some(rho) => {
                let section = (young * across * depth.powi(3) / 12.0, rho * w * t);
                let ball = (pulse.ball_mass, pulse.speed, pulse.max_approach);
                (
                    pulse.sized(section.0, section.1),
                    Some(super::modal::section_local_frequency(section, ball)),
                )
            }
            None => (pulse.duration, None),
        }
    };
    let steps = Steps::new(s, pulse, local_frequency)?;
    if let Some(local) = local_frequency {
        super::fe::local_steps(local, &steps, s, warnings);
    }
    mesh_at_impact(scene, (&sections, &stations, (e, k)), (face, sized), warnings);
    supports_mesh(scene, (&sections, &stations, &segment_of), (at, sized), (reasons, warnings));
    // A support closer along the members than the struck section's depth: past beam theory, as
    // a [beam]'s (validation/REFERENCES.md 1.5).
    let depth = 2.0 * half_depth;
    for sp in &spec.supports {
        let distance = (sp.at - at).abs();
        if distance > 0.0 && distance < depth {
            warnings.push(format!(
                "impact.at is {distance:.3e} m along the members from the {} support at s = {} m, closer than the struck section's depth {depth:.3e} m: there the load goes into the support through the section's depth, which beam theory (both methods) does not model; the displacement under the ball and the support's stress are a beam's answer, not the solid's",
                format!("{:?}", sp.kind).to_lowercase(),
                sp.at
            ));
        }
    }
    // What twists: a strike off the centre line, or a chain that is not one straight line (a
    // corner: one member's bending is the next one's twist; an arc), unless it is a plane
    // frame struck in its own plane. Segments in a line (a [beam] cut at its attachments) do
    // not.
    let (first, last) = (mesh.positions[0], mesh.positions[mesh.positions.len() - 1]);
    let line = last - first;
    let straight = mesh
        .positions
        .iter()
        .all(|p| (p - first).cross(&line).norm() <= 1e-9 * line.norm_squared());
    let twists = offset != 0.0 || !(straight || struck_in_its_plane(mesh, spec, d));
    if twists && s.tolerance.is_none() {
        // The struck element's own section: its G J and rho Ip.
        let section = &mesh.elements[e].section;
        if section.rho_i[0] > 0.0 {
            let speed = (section.gj / section.rho_i[0]).sqrt();
            let h = stations.windows(2).map(|x| x[1] - x[0]).fold(0.0, f64::max);
            // A [beam] lowered to its own modes has no elements of its own to set.
            let lowered = spec.lowered;
            let advice = |h: f64| {
                if lowered {
                    "solver.tolerance (it refines the beam's own modes' mesh)".to_string()
                } else {
                    format!(
                        "elements of at most {h:.3e} m ({} in all), or solver.tolerance",
                        (total / h).ceil()
                    )
                }
            };
            let what = if lowered { "the beam's own modes' mesh" } else { "the structure" };
            super::fe::torsion_mesh(
                (what, &advice),
                (h, speed, pulse.duration),
                s,
                (reasons, warnings),
            );
        }
    }
    // As a [beam]'s (`super::free_end`): the patch over a free end of the chain (said once:
    // a [beam] lowered onto a structure has said it).
    let said = warnings.iter().any(|w| w.contains("from a free end of the beam"));
    let patch = (scene.ball.radius * pulse.max_approach).sqrt();
    let held =
        |end: f64| spec.supports.iter().any(|sp| (sp.at - end).abs() <= 1e-9 * total.max(1.0));
    let free_ends = [0.0, total].into_iter().filter(|end| !held(*end));
    let distance = free_ends.map(|end| (end - at).abs()).find(|d| *d < patch);
    if let Some(distance) = distance.filter(|_| !said) {
        warnings.push(format!(
            "impact.at is {distance:.3e} m from a free end of the structure, within the contact radius (about {patch:.3e} m): the contact patch runs over the member's end, where the contact law (a half-space) does not hold, and the beam models load one point where the response changes fast with it (validation/REFERENCES.md 1.6); strike at least the contact radius inside the end for a result the models vouch for"
        ));
    }
    // A step of the struck face (a stepped member's segments meet with another depth across
    // that face; the centre lines meet, so each face steps by half the difference): a
    // neighbour standing proud by h meets the ball's sphere before the face does unless the
    // strike is sqrt(2 R h - h^2) from it (R the ball's radius); struck on the proud side, the
    // patch runs off its edge within the contact radius. A flush face (only the other
    // dimension changes) is no step for the ball.
    let radius = scene.ball.radius;
    let face_depth = |k: usize| {
        let [_, _, w, t] = sections[k];
        0.5 * if face == Face::Thickness { t } else { w }
    };
    let step = (1..sections.len()).find_map(|i| {
        let (x, distance) = (stations[i], (stations[i] - at).abs());
        let (struck, other) = if at < x { (i - 1, i) } else { (i, i - 1) };
        let rise = face_depth(other) - face_depth(struck);
        let reach = if rise > 0.0 {
            (2.0 * radius * rise.min(radius) - rise.min(radius).powi(2)).sqrt()
        } else {
            patch
        };
        (rise.abs() > 1e-9 * face_depth(struck) && distance < reach)
            .then_some((x, distance, rise, reach))
    });
    if let Some((x, distance, rise, reach)) = step {
        let what = if rise > 0.0 {
            format!("the face beyond it stands {rise:.3e} m proud, so the ball's sphere meets that step's corner before the struck face unless it strikes at least sqrt(2 R h - h^2) = {reach:.3e} m from it")
        } else {
            format!("the struck face stands {:.3e} m proud of the one beyond, so the contact patch (about {patch:.3e} m in radius) runs over its edge", -rise)
        };
        warnings.push(format!(
            "impact.at is {distance:.3e} m from a step of the struck face at s = {x} m: {what}, where the contact law (a half-space, one face) does not hold; strike farther from the step for a result the models vouch for"
        ));
    }
    if s.method != MethodName::Modal {
        reasons.push("structure: the bending stress is the section's worst corner's (extension and both bendings, in magnitude) and torsion_shear the Saint-Venant shear stress, at each element's midpoint (positions are arc lengths; the bending stress at the impact point too, extrapolated from the midpoints on each side) and every accepted step; the twist is read at every node".into());
    }
    // What the supports leave free: 0 rigid-body modes where they hold the structure, 6 for a
    // free body; between, a mechanism. Counted once: no static stiffness without a hold (a
    // static solve of a singular K gives a number, not a flexibility: 7e-8 N/m on the free
    // frame before this was counted). A clamp holds all six: the members form one chain with
    // rigid joints, so a rigid motion that holds one node's position and rotation holds every
    // node's (no count needed: the count's two factorisations of the whole model are a tenth
    // of a modal run on the paper's beam).
    let clamped = spec.supports.iter().any(|sp| sp.kind == Support::Clamped);
    let rigid_modes = if clamped { 0 } else { simo_beam::rigid_body_modes(&model)? };
    let held = if supports.is_empty() { "no support".to_string() } else { supports.join(", ") };
    if rigid_modes == FREE_BODY {
        reasons.push(format!("the structure is a free body ({held}): its six rigid-body motions are free; it has no static stiffness"));
    } else if rigid_modes > 0 {
        if s.method == MethodName::Modal {
            return Err(ImpactError::Inconsistent(format!("the structure is a mechanism: its supports (structure.support: {held}) leave {rigid_modes} rigid-body motion(s) free, which the modal method would take linearised at rest; clamp a node, or pin it at points not all on one line (pins on one straight line leave the turn about that line free: a forked support, a pin that holds the twist, holds it), or strike it by solver.method = \"fe\", which follows large rotations")));
        }
        warnings.push(format!("the structure is a mechanism: its supports (structure.support: {held}) leave {rigid_modes} rigid-body motion(s) free; it has no static stiffness (no equivalent static force is reported); pins on one straight line leave the turn about that line free: kind = \"forked\" (a pin that holds the twist) holds it"));
    }
    let Steps { alpha, samples, free_time_step, .. } = steps;
    Ok(FePlan {
        material,
        analytic: None,
        width,
        thickness,
        ends: (Support::Free, Support::Free),
        position: at,
        nodes: stations,
        alpha,
        free_time_step,
        samples_per_pulse: samples,
        local_frequency,
        approach_scale: pulse.max_approach,
        sized_duration: sized,
        tolerance: None,
        attachments: Vec::new(),
        offset,
        torsion: None,
        structure: Some(Box::new(StructurePlan {
            model,
            ball_start,
            up,
            face,
            half_depth,
            base_elements: sections.len(),
            sections,
            rigid_modes,
            fastest: MODE_CUTOFF / sized,
            source: Box::new((scene.clone(), *pulse)),
        })),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cutoff_s_reason_names_the_rule_that_set_it() {
        // A review's stepped cantilever kept modes to omega t_c = 39.3 (the local rule) while
        // the reason said omega t_c <= 20.
        let t_c = 6.9e-5;
        let by_pulse = cutoff_reason(MODE_CUTOFF / t_c, t_c);
        assert!(by_pulse.contains("omega t_c <= 20"), "{by_pulse}");
        let local = cutoff_reason(39.3 / t_c, t_c);
        assert!(local.contains("omega t_c = 39.3") && local.contains("local frequency"), "{local}");
    }
}
