//! Planning: validate a scene and choose the model it needs, with the reasons.

use crate::error::{positive, ImpactError};
use crate::scene::{LawName, MethodName, Scene};
use hertz::{HalfSpaceImpact, Hertz, HuntCrossley, Material, Thornton};
use serde::Serialize;
use std::f64::consts::PI;

/// Standard gravity (m/s^2).
pub const GRAVITY: f64 = 9.81;
/// Default time steps per estimated contact duration. The scheme is second order: on the
/// paper's tip scene (64 modes, 5 ms, gravity off, 27 contacts) the energy balance error is
/// 1.6e-5, 4.1e-6, 1.0e-6, 2.6e-7 of the initial energy at 200, 400, 800, 1600; 1000 keeps it
/// below 1e-6 (tested in the impact tests).
pub const DEFAULT_SAMPLES_PER_PULSE: usize = 1000;
/// Modes are kept up to omega t_c = 20 for the estimated contact duration t_c
/// (REFERENCES.md 6.4): the force pulse does not excite faster modes.
pub const MODE_CUTOFF: f64 = 20.0;

/// The contact law a plan resolved, with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// Elastic Hertz.
    Hertz(Hertz),
    /// Hunt-Crossley.
    HuntCrossley(HuntCrossley),
    /// Thornton elastic-plastic.
    Thornton(Thornton),
}

/// What is struck.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A beam, modelled by its modes, struck at `position` (m).
    Beam {
        /// The beam.
        beam: modal::Beam,
        /// Impact point (m) from x = 0.
        position: f64,
        /// Modal damping ratio.
        damping: f64,
        /// Number of modes.
        modes: usize,
    },
    /// A massive half-space: no modes.
    HalfSpace,
}

/// The plan's summary for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanSummary {
    /// `modal` or `half-space`.
    pub method: String,
    /// Number of modes (0 for a half-space).
    pub modes: usize,
    /// Time step in contact (s).
    pub time_step: f64,
    /// Contact law name.
    pub contact_law: String,
    /// Why each choice was made.
    pub reasons: Vec<String>,
}

/// A validated scene with every choice made.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Scene name.
    pub name: String,
    /// What is struck.
    pub target: Target,
    /// Contact law.
    pub law: Law,
    /// Ball mass (kg).
    pub ball_mass: f64,
    /// Ball radius (m).
    pub ball_radius: f64,
    /// Impact speed (m/s).
    pub speed: f64,
    /// Gravity on the ball toward the beam (m/s^2), 0 if off.
    pub gravity: f64,
    /// Simulated time (s).
    pub end_time: f64,
    /// Time step in contact (s).
    pub time_step: f64,
    /// History interval in free flight (s).
    pub output_interval: f64,
    /// Estimated duration of the first contact on a rigid support (s).
    pub estimated_duration: f64,
    /// Softer yield stress (Pa), if known, for yield warnings.
    pub yield_stress: Option<f64>,
    /// Summary for the report.
    pub summary: PlanSummary,
    /// Warnings about the scene (accepted, but worth a look).
    pub warnings: Vec<String>,
}

fn invalid(field: &str, value: impl ToString, allowed: &str) -> ImpactError {
    ImpactError::InvalidField {
        field: field.to_owned(),
        value: value.to_string(),
        allowed: allowed.to_owned(),
    }
}

fn material(
    prefix: &str,
    e: f64,
    nu: f64,
    yield_stress: Option<f64>,
) -> Result<Material, ImpactError> {
    positive(&format!("{prefix}.youngs_modulus"), e, "Pa")?;
    if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
        return Err(invalid(&format!("{prefix}.poisson_ratio"), nu, "must be in (-1, 0.5)"));
    }
    let m = Material::new(e, nu)?;
    match yield_stress {
        Some(y) => {
            positive(&format!("{prefix}.yield_stress"), y, "Pa")?;
            Ok(m.with_yield_stress(y)?)
        }
        None => Ok(m),
    }
}

impl Plan {
    /// Validates `scene` and makes every choice: the model, the modes, the step, the law.
    ///
    /// # Errors
    /// `InvalidField` naming the first field with a bad value, `Inconsistent` for a combination
    /// that is not a scene (both or neither of speed and drop height, a plastic law without a
    /// yield stress, ...), `Unsupported` for the finite-element method.
    pub fn new(scene: &Scene) -> Result<Self, ImpactError> {
        let mut reasons = Vec::new();
        let mut warnings = Vec::new();

        let b = &scene.ball;
        let radius = positive("ball.radius", b.radius, "m")?;
        let density = positive("ball.density", b.density, "kg/m^3")?;
        let ball_material = material("ball", b.youngs_modulus, b.poisson_ratio, b.yield_stress)?;
        let volume = 4.0 / 3.0 * PI * radius.powi(3);
        let ball_mass = match b.mass {
            Some(m) => {
                positive("ball.mass", m, "kg")?;
                let implied = m / volume;
                if !(0.8..=1.25).contains(&(implied / density)) {
                    warnings.push(format!(
                        "ball.mass = {m} kg with ball.radius = {radius} m implies a density of {implied:.0} kg/m^3, \
                         not ball.density = {density} kg/m^3; the mass is used as given"
                    ));
                }
                m
            }
            None => density * volume,
        };

        let speed = match (scene.impact.drop_height, scene.impact.speed) {
            (Some(h), None) => (2.0 * GRAVITY * positive("impact.drop_height", h, "m")?).sqrt(),
            (None, Some(v)) => positive("impact.speed", v, "m/s")?,
            (Some(_), Some(_)) => {
                return Err(ImpactError::Inconsistent(
                    "impact: give exactly one of drop_height (m) and speed (m/s), not both".into(),
                ))
            }
            (None, None) => {
                return Err(ImpactError::Inconsistent(
                    "impact: give one of drop_height (m) or speed (m/s)".into(),
                ))
            }
        };
        let gravity = if scene.impact.gravity { GRAVITY } else { 0.0 };

        let (counterface, beam_spec) = match (&scene.beam, &scene.half_space) {
            (Some(beam), None) => (
                material("beam", beam.youngs_modulus, beam.poisson_ratio, beam.yield_stress)?,
                Some(beam),
            ),
            (None, Some(hs)) => (
                material("half_space", hs.youngs_modulus, hs.poisson_ratio, hs.yield_stress)?,
                None,
            ),
            (Some(_), Some(_)) => {
                return Err(ImpactError::Inconsistent(
                    "give [beam] or [half_space], not both".into(),
                ))
            }
            (None, None) => {
                return Err(ImpactError::Inconsistent(
                    "the scene needs a [beam] or a [half_space] to strike".into(),
                ))
            }
        };
        let hertz =
            Hertz::between(&ball_material, &counterface, hertz::geometry::sphere_on_flat(radius)?)?;
        let rigid = HalfSpaceImpact::elastic(&hertz, ball_mass, speed)?;
        let estimated_duration = rigid.duration;
        let yield_stress = hertz::softer_yield_stress(&ball_material, &counterface);

        let c = &scene.contact;
        let law = match c.law {
            LawName::Hertz => {
                if c.damping.is_some() || c.restitution.is_some() || c.limiting_pressure.is_some() {
                    return Err(ImpactError::Inconsistent("contact.law = \"hertz\" takes no damping, restitution or limiting_pressure".into()));
                }
                Law::Hertz(hertz)
            }
            LawName::HuntCrossley => match (c.damping, c.restitution) {
                (Some(d), None) => {
                    if !(d.is_finite() && d >= 0.0) {
                        return Err(invalid("contact.damping", d, "must be a finite number >= 0 (s/m)"));
                    }
                    Law::HuntCrossley(HuntCrossley::new(hertz, d)?)
                }
                (None, Some(e)) => {
                    if !(e.is_finite() && e > 0.0 && e <= 1.0) {
                        return Err(invalid("contact.restitution", e, "must be in (0, 1]"));
                    }
                    reasons.push(format!("Hunt-Crossley damping chi = 3(1 - e)/(2 V) = {:.4} s/m from restitution {e} at {speed:.4} m/s", 1.5 * (1.0 - e) / speed));
                    Law::HuntCrossley(HuntCrossley::from_restitution(hertz, e, speed)?)
                }
                _ => return Err(ImpactError::Inconsistent("contact.law = \"hunt-crossley\" needs exactly one of damping (s/m) or restitution".into())),
            },
            LawName::Thornton => {
                let p = match (c.limiting_pressure, yield_stress) {
                    (Some(p), _) => positive("contact.limiting_pressure", p, "Pa")?,
                    (None, Some(y)) => {
                        reasons.push(format!("Thornton limiting pressure 1.6 Y = {:.4e} Pa from the softer yield stress Y = {y:.4e} Pa", 1.6 * y));
                        hertz::FIRST_YIELD_PRESSURE_RATIO * y
                    }
                    (None, None) => return Err(ImpactError::Inconsistent(
                        "contact.law = \"thornton\" needs a yield stress: set beam.yield_stress (or half_space.yield_stress, ball.yield_stress, or contact.limiting_pressure)".into(),
                    )),
                };
                Law::Thornton(Thornton::new(hertz, p)?)
            }
        };
        if let (Law::Hertz(_) | Law::HuntCrossley(_), Some(y)) = (law, yield_stress) {
            let vy = hertz::elastic_limit_velocity(
                &hertz,
                ball_mass,
                hertz::FIRST_YIELD_PRESSURE_RATIO * y,
            )?;
            if speed > vy {
                warnings.push(format!(
                    "the impact speed {speed:.3} m/s exceeds the first-yield speed {vy:.3} m/s (p0 = 1.6 Y): the contact yields; contact.law = \"thornton\" models it"
                ));
            }
        }

        let s = &scene.solver;
        let samples = s.samples_per_pulse.unwrap_or(DEFAULT_SAMPLES_PER_PULSE);
        if samples < 10 {
            return Err(invalid("solver.samples_per_pulse", samples, "must be at least 10"));
        }
        let time_step = estimated_duration / samples as f64;
        reasons.push(format!(
            "time step {time_step:.4e} s in contact: {samples} steps per estimated contact duration {estimated_duration:.4e} s (Hertz, rigid support)"
        ));

        let target = match beam_spec {
            None => {
                if s.method == MethodName::Fe || s.modes.is_some() {
                    return Err(ImpactError::Inconsistent("a [half_space] scene needs no solver.method = \"fe\" nor solver.modes: the block is rigid".into()));
                }
                reasons.push("massive half-space: no beam model, the ball meets a rigid-backed Hertz contact".into());
                Target::HalfSpace
            }
            Some(beam) => {
                match s.method {
                    MethodName::Fe => return Err(ImpactError::Unsupported(
                        "solver.method = \"fe\" is not available yet (the finite-element beam arrives with the Simo-beam issue); use \"modal\" or \"auto\"".into(),
                    )),
                    MethodName::Auto => reasons.push("method modal (auto): Goldsmith's modal series, exact between steps; small deflections assumed".into()),
                    MethodName::Modal => reasons.push("method modal, as asked".into()),
                }
                let length = positive("beam.length", beam.length, "m")?;
                positive("beam.width", beam.width, "m")?;
                positive("beam.thickness", beam.thickness, "m")?;
                positive("beam.density", beam.density, "kg/m^3")?;
                let m = modal::Beam::rectangular(
                    beam.youngs_modulus,
                    beam.density,
                    beam.width,
                    beam.thickness,
                    length,
                    beam.support.into(),
                )?;
                let position = scene.impact.position.ok_or_else(|| {
                    ImpactError::Inconsistent(
                        "impact.position (m) is required with a [beam]".into(),
                    )
                })?;
                if !(position.is_finite() && (0.0..=length).contains(&position)) {
                    return Err(invalid(
                        "impact.position",
                        position,
                        &format!(
                            "must be on the beam, 0 <= position <= beam.length = {length} (m)"
                        ),
                    ));
                }
                let damping = beam.modal_damping.unwrap_or(0.0);
                if !(damping.is_finite() && (0.0..1.0).contains(&damping)) {
                    return Err(invalid(
                        "beam.modal_damping",
                        damping,
                        "must be a damping ratio in [0, 1)",
                    ));
                }
                let needed = modes_needed(&m, estimated_duration)?;
                let modes = match s.modes {
                    Some(0) => return Err(invalid("solver.modes", 0, "must be at least 1")),
                    Some(n) if n > 20_000 => {
                        return Err(invalid("solver.modes", n, "must be at most 20000"))
                    }
                    Some(n) => {
                        reasons.push(format!(
                            "{n} modes, as asked (omega t_c <= {MODE_CUTOFF} would need {needed})"
                        ));
                        n
                    }
                    None => {
                        reasons.push(format!("{needed} modes: all with omega t_c <= {MODE_CUTOFF} for the estimated contact duration"));
                        needed
                    }
                };
                Target::Beam { beam: m, position, damping, modes }
            }
        };

        let default_end = match target {
            Target::HalfSpace => 4.0 * estimated_duration,
            Target::Beam { .. } => 0.005,
        };
        let end_time = match s.end_time {
            Some(t) => positive("solver.end_time", t, "s")?,
            None => {
                reasons.push(format!("end time {default_end:.4e} s (default)"));
                default_end
            }
        };
        let output_interval = match s.output_interval {
            Some(dt) => positive("solver.output_interval", dt, "s")?,
            None => end_time / 2000.0,
        };

        let (method, modes) = match &target {
            Target::Beam { modes, .. } => ("modal", *modes),
            Target::HalfSpace => ("half-space", 0),
        };
        let contact_law = match c.law {
            LawName::Hertz => "hertz",
            LawName::HuntCrossley => "hunt-crossley",
            LawName::Thornton => "thornton",
        };
        Ok(Self {
            name: scene.name.clone(),
            summary: PlanSummary {
                method: method.into(),
                modes,
                time_step,
                contact_law: contact_law.into(),
                reasons,
            },
            target,
            law,
            ball_mass,
            ball_radius: radius,
            speed,
            gravity,
            end_time,
            time_step,
            output_interval,
            estimated_duration,
            yield_stress,
            warnings,
        })
    }
}

/// Number of modes with omega_n t_c <= MODE_CUTOFF (at least 4, so the lowest modes that carry
/// the beam's gross motion are always there).
fn modes_needed(beam: &modal::Beam, duration: f64) -> Result<usize, ImpactError> {
    let limit = MODE_CUTOFF / duration;
    let rigid = beam.support().rigid_modes();
    let mut n = 1;
    while n < 20_000 && beam.omega(beam.support().eigenvalue(n)?) <= limit {
        n += 1;
    }
    Ok((n - 1 + rigid).max(4))
}
