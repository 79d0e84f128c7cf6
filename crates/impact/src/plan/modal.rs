//! The modal method's plan: which modes carry the beam.

use crate::error::{invalid, ImpactError};
use crate::scene::SolverSpec;

/// The refinement to a tolerance doubles the modes up to this many, tolerance met or not (the
/// paper's tip, 5 ms: 0.15 s a run at 4096 modes).
pub const MODAL_LADDER_END: usize = 8192;

/// Modes are kept up to omega t_c = 20 for the estimated contact duration t_c
/// (validation/REFERENCES.md 6.4): the force pulse does not excite faster modes.
pub const MODE_CUTOFF: f64 = 20.0;

/// Modes are kept up to this many times the contact's local frequency too (see
/// [`local_frequency`]), where that is the higher cutoff: a ball heavy against the beam
/// meets the beam's local response faster than its own rigid-support pulse. The paper's ball
/// on its beam has omega t_c = 20 at 15.3 times its local frequency, so 12 leaves its modes
/// as they were; the review's 1 kg ball at 0.5 m/s on the same beam had 32 modes, 18 % over
/// the converged peak force, and takes 107 now, 0.4 % over. With `solver.tolerance` the
/// ladder starts from the pulse's count, as before, and finds its own.
pub(super) const LOCAL_CUTOFF: f64 = 12.0;

/// The contact's local frequency (rad/s): where the contact's stiffness, linearised at the
/// rigid-support approach (k_c = 3/2 F/delta = 15/8 m v^2/delta^2 for Hertz), meets the
/// point stiffness of an infinite Euler-Bernoulli beam, |K| = 4 sqrt(2) EI beta^3 with
/// beta^4 = rho A omega^2 / EI (Graff, Wave Motion in Elastic Solids, 3.4): the contact force
/// varies on that time scale when the beam's local response, not the ball, sets it.
pub(crate) fn local_frequency(beam: &modal::Beam, ball: (f64, f64, f64)) -> f64 {
    section_local_frequency((beam.flexural_rigidity(), beam.mass_per_length()), ball)
}

/// [`local_frequency`] on a section of bending stiffness EI (N m^2) and mass rho A (kg/m).
pub(crate) fn section_local_frequency(
    (rigidity, mass_per_length): (f64, f64),
    (mass, speed, approach): (f64, f64, f64),
) -> f64 {
    let contact = 15.0 / 8.0 * mass * speed * speed / (approach * approach);
    let beta = (contact / (4.0 * std::f64::consts::SQRT_2 * rigidity)).cbrt();
    beta * beta * (rigidity / mass_per_length).sqrt()
}

/// Where a modal plan's modes come from.
#[derive(Debug, Clone, PartialEq)]
pub enum ModalBasis {
    /// A uniform `[beam]`'s analytic modes (exact).
    Analytic(modal::Beam),
    /// A `[structure]`'s modes computed from its 3D finite-element beam.
    Fe(Box<super::structure::FeBasis>),
}

/// A beam or structure modelled by its first modes, struck at one point.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalPlan {
    /// Where the modes come from.
    pub(crate) basis: ModalBasis,
    /// Impact point (m) from x = 0 (along the segments on a structure).
    pub(crate) position: f64,
    /// Modal damping ratio of every elastic mode (-).
    pub(crate) damping: f64,
    /// Number of modes (the first of the refinement with a tolerance).
    pub(crate) modes: usize,
    /// The relative error to double the modes to, if asked (`solver.tolerance`).
    pub(crate) tolerance: Option<f64>,
    /// Whether the truncated modes' static compliance sits in series with the contact
    /// (`solver.residual_flexibility`).
    pub(crate) residual_flexibility: bool,
    /// Whether the solver takes the residual flexibility where the kept modes leave out a
    /// notable share of the static flexibility at the impact point (neither asked for nor
    /// refused, and no tolerance: `solve::modal`'s `RESIDUAL_SHARE`). Decided there, where the
    /// modes are built: here they would be built twice.
    pub(crate) residual_by_share: bool,
    /// Whether the bending stress is the plain series (`solver.plain_stress_series`), not the
    /// mode-acceleration form.
    pub(crate) plain_stress_series: bool,
    /// The other theory's beam and the first-order shift of the frequency the pulse excites
    /// most, where an Euler-Bernoulli beam was asked for and Timoshenko's correction is
    /// notable: the run measures what the theory changes by running this beam at the same
    /// modes (`solve::measure_theory`), and the estimated error includes it.
    pub(crate) twin: Option<(modal::Beam, f64)>,
    /// An off-centre strike: the beam in torsion and the offset (m). Its modes are those up
    /// to the highest bending mode's frequency (both families cut at one frequency, so the
    /// refinement that doubles the bending modes refines both).
    pub(crate) torsion: Option<(modal::Torsion, f64)>,
}

impl ModalPlan {
    /// The uniform beam of an analytic basis; `None` on a structure's fe basis.
    pub fn beam(&self) -> Option<&modal::Beam> {
        match &self.basis {
            ModalBasis::Analytic(beam) => Some(beam),
            ModalBasis::Fe(_) => None,
        }
    }

    /// Impact point (m) from x = 0.
    pub fn position(&self) -> f64 {
        self.position
    }

    /// Number of bending modes (the torsion modes of an off-centre strike come with them); 0
    /// on an fe basis, whose modes are all those below its cutoff, counted when it runs.
    pub fn modes(&self) -> usize {
        self.modes
    }

    /// The static flexibility of the struck face at the impact point (m/N): bending plus
    /// offset^2 times the twist under a unit torque, or a structure's static solve; `None` for
    /// a free body.
    pub fn static_flexibility(&self) -> Option<f64> {
        let beam = match &self.basis {
            ModalBasis::Analytic(beam) => beam,
            ModalBasis::Fe(fe) => return fe.static_flexibility(),
        };
        let bending = beam.static_flexibility(self.position)?;
        match &self.torsion {
            Some((t, e)) => Some(bending + e * e * t.static_flexibility(self.position)?),
            None => Some(bending),
        }
    }

    /// The beam in torsion and the strike's offset (m), for an off-centre strike.
    pub fn torsion(&self) -> Option<(&modal::Torsion, f64)> {
        self.torsion.as_ref().map(|(t, e)| (t, *e))
    }
}

/// The modes asked for, or all up to [`MODE_CUTOFF`] for the estimated contact duration (s).
pub(super) fn plan(
    s: &SolverSpec,
    beam: modal::Beam,
    position: f64,
    damping: f64,
    (duration, local): (f64, f64),
    reasons: &mut Vec<String>,
) -> Result<ModalPlan, ImpactError> {
    // With a tolerance the ladder starts from the pulse's count and finds its own; without,
    // the local frequency may ask for more.
    let by_pulse = modes_needed(&beam, (duration, 0.0))?;
    let local = if s.tolerance.is_some() { 0.0 } else { local };
    // Counted again only where the local cutoff is the higher.
    let needed = if LOCAL_CUTOFF * local > MODE_CUTOFF / duration {
        modes_needed(&beam, (duration, local))?
    } else {
        by_pulse
    };
    let cutoff = if needed > by_pulse {
        reasons.push(format!("modes up to {LOCAL_CUTOFF} times the contact's local frequency {local:.4e} rad/s (the contact's stiffness against the beam's point stiffness), above omega t_c = {MODE_CUTOFF}'s {by_pulse}: the ball is heavy against the beam, whose local response sets the force's time scale (a 1 kg ball at 0.5 m/s on the paper's beam: 32 modes by the pulse were 18 % over the converged peak force)"));
        format!("below {LOCAL_CUTOFF} times the contact's local frequency")
    } else {
        format!("with omega t_c <= {MODE_CUTOFF} for the estimated contact duration")
    };
    // A pulse short against the beam's waves (a tiny ball) excites more modes than the method
    // takes: refused unless a count is given (it ran on 20000, clamped, for minutes).
    if needed > MAX_MODES && s.modes.is_none() {
        return Err(ImpactError::Inconsistent(format!("the estimated contact duration {duration:.3e} s excites {needed} modes of the beam below omega t_c = {MODE_CUTOFF}, more than the modal method's {MAX_MODES}: the beam is nearly a half-space under so short a pulse; solve it by solver.method = \"fe\", or give solver.modes (at most {MAX_MODES}) to truncate the series knowingly")));
    }
    // With a tolerance the plan takes the residual flexibility unless told not to: on the
    // paper's tip (1 ms) it cuts the first contact's error 160 times at 128 modes (2.6e-5
    // against 4.2e-3) and the contact sequence's 60 times (3.6e-4 against 2.2e-2), so the
    // tolerance is met with a quarter of the modes (validation/REFERENCES.md 1.4).
    // A free-free beam has no static flexibility to take it from: refused where asked,
    // left out (with the reason) where the tolerance would have chosen it.
    let supported = beam.static_flexibility(position).is_some();
    let residual_flexibility = s.residual_flexibility.unwrap_or(s.tolerance.is_some() && supported);
    if s.residual_flexibility.is_none() && s.tolerance.is_some() && !supported {
        reasons.push("no residual flexibility with the tolerance: a free-free beam has no static flexibility to take it from, so the modes alone converge (more of them)".into());
    }
    let plain_stress_series = s.plain_stress_series.unwrap_or(false);
    if plain_stress_series {
        reasons.push("bending stress by the plain modal series, as asked (no quasi-static share of the truncated modes: it converges as 1/N near the ball)".into());
    }
    if residual_flexibility {
        if !supported {
            return Err(ImpactError::Inconsistent(
                "solver.residual_flexibility needs a supported beam: a free-free beam has no static flexibility".into(),
            ));
        }
        reasons.push(format!("residual flexibility{}: the truncated modes' static compliance at the impact point (static flexibility minus the kept modes' share) in series with the contact (mode-acceleration method)", if s.residual_flexibility.is_some() { ", as asked" } else { " (chosen with the tolerance)" }));
    }
    if let Some(tolerance) = s.tolerance {
        if s.modes.is_some() {
            return Err(ImpactError::Inconsistent(
                "solver.tolerance chooses the modes: give it without solver.modes".into(),
            ));
        }
        let tolerance = super::checked_tolerance(tolerance)?;
        reasons.push(format!("modes from {needed} (all {cutoff}), doubled until two successive runs agree within solver.tolerance = {tolerance} on every significant contact's start, duration and peak force, the largest displacement and the largest stress (the estimated error of the finer: {})", if beam.theory() == modal::Theory::Timoshenko { "their whole difference, Timoshenko modes being in no asymptotic range at the ladder's first rungs (a third had claimed 3 times too little on the chattering tip)" } else { "a third of their difference, Richardson at second order, where the paper's tip converges at about third order in the modes" }));
        return Ok(ModalPlan {
            basis: ModalBasis::Analytic(beam),
            position,
            damping,
            modes: needed,
            tolerance: Some(tolerance),
            residual_flexibility,
            residual_by_share: false,
            plain_stress_series,
            twin: None,
            torsion: None,
        });
    }
    let modes = match s.modes {
        Some(0) => return Err(invalid("solver.modes", 0, "must be at least 1")),
        Some(n) if n > MAX_MODES => {
            return Err(invalid("solver.modes", n, &format!("must be at most {MAX_MODES}")))
        }
        Some(n) => {
            reasons.push(format!("{n} modes, as asked (all {cutoff} would be {needed})"));
            n
        }
        None => {
            reasons.push(format!("{needed} modes: all {cutoff}"));
            needed
        }
    };
    Ok(ModalPlan {
        basis: ModalBasis::Analytic(beam),
        position,
        damping,
        modes,
        tolerance: None,
        residual_flexibility,
        residual_by_share: s.residual_flexibility.is_none() && supported,
        plain_stress_series,
        twin: None,
        torsion: None,
    })
}

/// The most modes the modal method takes (`solver.modes`' bound).
pub(super) const MAX_MODES: usize = 20_000;

/// Whether a pulse of `duration` (s) excites more of `beam`'s modes than [`MAX_MODES`].
pub(super) fn too_many_modes(beam: &modal::Beam, duration: f64) -> Result<bool, ImpactError> {
    Ok(modes_needed(beam, (duration, 0.0))? > MAX_MODES)
}

/// Number of modes with omega_n t_c <= MODE_CUTOFF, of either branch for a Timoshenko beam (at
/// least 4, so the lowest modes that carry the beam's gross motion are always there).
fn modes_needed(beam: &modal::Beam, (duration, local): (f64, f64)) -> Result<usize, ImpactError> {
    let limit = (MODE_CUTOFF / duration).max(LOCAL_CUTOFF * local);
    Ok(beam.count_below(limit)?.max(4))
}
