//! The finite-element method's plan: the mesh, HHT's alpha and the steps.

use super::modal::MODE_CUTOFF;
use super::Pulse;
use crate::error::{invalid, positive, ImpactError};
use crate::scene::{BeamSpec, SolverSpec, SupportName};
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
    /// The same beam as an Euler-Bernoulli beam: its static stiffness defines the equivalent
    /// static force (as in the modal method).
    pub(crate) analytic: modal::Beam,
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
    /// Largest approach on a rigid support (m): the scale of the event tolerance.
    pub(crate) approach_scale: f64,
    /// The relative error to refine the uniform mesh to, if asked (`solver.tolerance`).
    pub(crate) tolerance: Option<f64>,
}

impl FePlan {
    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.nodes.len() - 1
    }

    /// Node positions along the beam (m), from 0 to L.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// HHT alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
}

/// The finite-element model of `beam` (whose Euler-Bernoulli twin is `analytic`) struck at
/// `position` (m): the mesh asked for or graded from the impact point, alpha and the steps.
pub(super) fn plan(
    beam: &BeamSpec,
    s: &SolverSpec,
    analytic: modal::Beam,
    position: f64,
    damping: f64,
    pulse: &Pulse,
    reasons: &mut Vec<String>,
) -> Result<FePlan, ImpactError> {
    if damping > 0.0 {
        return Err(invalid("beam.modal_damping", damping, "must be 0 or absent with method = \"fe\" (the finite-element beam is undamped; HHT alpha adds numerical damping of high frequencies)"));
    }
    let samples = s.samples_per_pulse.unwrap_or(FE_SAMPLES_PER_PULSE);
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
    let contact_step = estimated_duration / samples as f64;
    let free_time_step = match s.time_step {
        Some(h) => positive("solver.time_step", h, "s")?.max(contact_step),
        None => FE_FREE_STEP_RATIO * contact_step,
    };
    reasons.push("planar geometrically exact beam (Reissner-Simo, 3 unknowns a node): the ball strikes the face along the thickness and nothing moves the beam or the ball out of that plane, so the 3D beam's other 3 unknowns a node would stay zero".into());
    let nodes = mesh(s, &analytic, position, estimated_duration, reasons)?;
    if free_time_step > contact_step * (1.0 + 1e-9) {
        reasons.push(format!("HHT alpha = {alpha}; steps of {contact_step:.4e} s in contact ({samples} per estimated contact duration {estimated_duration:.4e} s), up to {free_time_step:.4e} s out of contact (solver.time_step): the waves the impacts leave in the beam are then integrated with HHT's dispersion at the longer steps, and the contacts after the first few are not converged in time (validation/REFERENCES.md 1.7)"));
    } else {
        reasons.push(format!("HHT alpha = {alpha}; every step {contact_step:.4e} s ({samples} per estimated contact duration {estimated_duration:.4e} s), in contact and out of it: the bending waves an impact sends along the beam decide when later contacts start and end, and longer steps out of contact move them (validation/REFERENCES.md 1.7)"));
    }
    if s.alpha.is_none() {
        reasons.push(format!("alpha = {FE_ALPHA} by default: it damps the vibration the impacts put into frequencies the mesh does not resolve, and energy.numerical_dissipation says how much (at the default steps, on the paper's tip 3e-5 of the ball's energy over 1 ms; on the heavy ball 1.5-2 % over 0.4 s, and 0.2 % and 2.2 % with -0.01 and -0.1: its chattering keeps feeding the high frequencies; longer steps out of contact damp more, 7 % and 12 % at 8 contact steps); set alpha = 0 for an undamped energy study: it conserves energy to 1e-6 on the tip, moves the first three contacts by less than 1e-3 and the heavy ball's largest displacement by 0.6 %, but keeps that unresolved vibration"));
    }
    Ok(FePlan {
        material: simo_beam::Material::new(beam.youngs_modulus, beam.poisson_ratio, beam.density)?,
        analytic,
        width: beam.width,
        thickness: beam.thickness,
        ends: ends(beam.support),
        position,
        nodes,
        alpha,
        free_time_step,
        samples_per_pulse: samples,
        approach_scale: pulse.max_approach,
        tolerance: s.tolerance,
    })
}

/// How the two ends of a beam are held in the finite-element model.
fn ends(support: SupportName) -> (Support, Support) {
    match support {
        SupportName::ClampedFree => (Support::Clamped, Support::Free),
        SupportName::PinnedPinned => (Support::Pinned, Support::Pinned),
        SupportName::ClampedClamped => (Support::Clamped, Support::Clamped),
        SupportName::ClampedPinned => (Support::Clamped, Support::Pinned),
        SupportName::FreeFree => (Support::Free, Support::Free),
    }
}

/// The node positions (m): `solver.elements` equal elements, or a mesh graded from the impact
/// point from `solver.element_size` or from the flexural wavelength the pulse excites.
fn mesh(
    s: &SolverSpec,
    beam: &modal::Beam,
    position: f64,
    estimated_duration: f64,
    reasons: &mut Vec<String>,
) -> Result<Vec<f64>, ImpactError> {
    let length = beam.length();
    // Flexural wavelength at the fastest frequency the pulse excites (omega t_c = MODE_CUTOFF,
    // as for the modes): lambda = 2 pi (EI / rho A)^(1/4) / sqrt(omega).
    let omega = MODE_CUTOFF / estimated_duration;
    let wavelength =
        2.0 * PI * (beam.flexural_rigidity() / beam.mass_per_length()).powf(0.25) / omega.sqrt();
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
        reasons.push(format!("uniform meshes from {FE_LADDER_START} elements, doubled until two successive ones agree within solver.tolerance = {tolerance} on every significant contact's start, duration and peak force and on the largest displacement (second-order Richardson estimate of the finer mesh's error); then, on that mesh, uniform steps of the contact step divided by 2, 4, ... until two runs agree again (the steps' error is their whole difference), the estimated error being the mesh's plus the steps'"));
        return Ok(uniform(length, FE_LADDER_START));
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
                Some(h) => positive("solver.element_size", h, "m")?.min(length),
                None => (wavelength / FE_ELEMENTS_PER_WAVELENGTH).min(length / 16.0),
            };
            // Elements needed: about log(1 + L (r - 1) / h0) / log(r) per side.
            let estimate =
                2.0 * (1.0 + length * (FE_GROWTH - 1.0) / h0).ln() / FE_GROWTH.ln() + 32.0;
            if estimate > MAX_ELEMENTS as f64 {
                return Err(invalid(
                    "solver.element_size",
                    h0,
                    "too small: the mesh would exceed 100000 elements",
                ));
            }
            let nodes = graded_nodes(length, position, h0, FE_GROWTH, length / 16.0);
            let why = if s.element_size.is_some() {
                "as asked".to_string()
            } else {
                format!("1/{FE_ELEMENTS_PER_WAVELENGTH} of the flexural wavelength {wavelength:.3e} m at omega t_c = {MODE_CUTOFF}")
            };
            reasons.push(format!(
                "{} elements graded from {h0:.3e} m at the impact point ({why}) growing by {FE_GROWTH} per element to at most L/16",
                nodes.len() - 1
            ));
            Ok(nodes)
        }
    }
}

/// Nodes of `n` equal elements from 0 to `length` (m).
pub(crate) fn uniform(length: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|i| length * i as f64 / n as f64).collect()
}

/// Nodes from 0 to `length` with a node at `centre`, element size `h0` there, growing by
/// `growth` per element away from it up to `h_max`.
fn graded_nodes(length: f64, centre: f64, h0: f64, growth: f64, h_max: f64) -> Vec<f64> {
    let side = |span: f64| -> Vec<f64> {
        // Offsets from the centre, the last exactly at `span`.
        let mut out = Vec::new();
        let (mut at, mut h) = (0.0, h0);
        while span - at > 1.5 * h {
            at += h;
            out.push(at);
            h = (h * growth).min(h_max);
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
