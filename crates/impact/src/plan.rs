//! Planning: validate a scene and choose the model it needs, with the reasons.

use crate::error::{positive, ImpactError};
use crate::scene::{LawName, MethodName, Scene};
use hertz::{HalfSpaceImpact, Hertz, HuntCrossley, Material, Thornton};
use serde::Serialize;
use std::f64::consts::PI;

/// Standard gravity (m/s^2).
pub const GRAVITY: f64 = 9.81;
/// Default time steps per estimated contact duration: the modal method's largest contact
/// step. With uniform steps the scheme is second order: on the paper's tip scene (64 modes,
/// 5 ms, gravity off, 27 contacts) the energy balance error is 1.6e-5, 4.1e-6, 1.0e-6, 2.6e-7
/// of the initial energy at 200, 400, 800, 1600 steps, almost all of it made in the first
/// steps after onset. The adaptive step (the default) refines there and keeps the error at
/// 4e-7 with 6000 steps in all where uniform steps needed 1000 per pulse (24000); see
/// `DEFAULT_ENERGY_TOLERANCE` and the impact tests.
pub const DEFAULT_SAMPLES_PER_PULSE: usize = 200;
/// Default allowed energy mismatch of the modal method's adaptive contact step, as a fraction
/// of the impact energy per estimated contact duration.
pub const DEFAULT_ENERGY_TOLERANCE: f64 = 1e-6;
/// Default steps per estimated contact duration for the finite-element method (each step is a
/// Newton solve of the whole beam; see the convergence table in the FE tests).
pub const FE_SAMPLES_PER_PULSE: usize = 200;
/// Default HHT alpha of the finite-element method: a little numerical damping of the
/// frequencies above the mesh's resolution (the contact excites them), spectral radius 0.9 at
/// infinity, period and damping errors O((omega h)^2) below.
pub const FE_ALPHA: f64 = -0.05;
/// Default largest step out of contact, in contact steps.
pub const FE_FREE_STEP_RATIO: f64 = 10.0;
/// Elements per flexural wavelength at the impact point in the default graded mesh.
pub const FE_ELEMENTS_PER_WAVELENGTH: f64 = 16.0;
/// Growth of the element size away from the impact point in the default graded mesh.
pub const FE_GROWTH: f64 = 1.15;
/// The auto plan takes the finite-element method when the ball could bend the beam by more
/// than this fraction of its length.
pub const LARGE_DEFLECTION: f64 = 0.1;
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
    /// A beam, modelled by geometrically exact finite elements (Simo) and HHT-alpha.
    Fe(FeTarget),
    /// A massive half-space: no modes.
    HalfSpace,
}

/// The finite-element model of a struck beam.
#[derive(Debug, Clone, PartialEq)]
pub struct FeTarget {
    /// The same beam as an Euler-Bernoulli beam: its static stiffness defines the equivalent
    /// static force (as in the modal method).
    pub analytic: modal::Beam,
    /// Beam material.
    pub material: simo_beam::Material,
    /// Section width (m), along y.
    pub width: f64,
    /// Section thickness (m), along z (the direction of impact).
    pub thickness: f64,
    /// End conditions.
    pub support: crate::scene::SupportName,
    /// Impact point (m) from x = 0.
    pub position: f64,
    /// Node positions along x (m), from 0 to L.
    pub nodes: Vec<f64>,
    /// HHT alpha in [-1/3, 0].
    pub alpha: f64,
    /// Largest step out of contact (s).
    pub free_time_step: f64,
    /// Steps per estimated contact duration.
    pub samples_per_pulse: usize,
    /// Largest approach on a rigid support (m): the scale of the event tolerance.
    pub approach_scale: f64,
}

/// The plan's summary for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanSummary {
    /// `modal`, `fe` or `half-space`.
    pub method: String,
    /// Number of modes (0 unless modal).
    pub modes: usize,
    /// Number of finite elements (0 unless fe).
    pub elements: usize,
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
    /// Time step in contact (s): the largest of the modal method's adaptive step, the
    /// smallest of the fe method's.
    pub time_step: f64,
    /// The modal method's adaptive contact step: its energy tolerance (see
    /// `DEFAULT_ENERGY_TOLERANCE`), or `None` for uniform steps.
    pub energy_tolerance: Option<f64>,
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
    /// yield stress, ...).
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
        let fe_asked = s.method == MethodName::Fe;
        let fe_keys = s.elements.is_some()
            || s.element_size.is_some()
            || s.alpha.is_some()
            || s.time_step.is_some();
        if fe_keys && s.method == MethodName::Modal {
            return Err(ImpactError::Inconsistent(
                "solver.elements, element_size, alpha and time_step belong to method = \"fe\"; the modal method takes solver.modes".into(),
            ));
        }
        if fe_asked && s.modes.is_some() {
            return Err(ImpactError::Inconsistent(
                "solver.modes belongs to method = \"modal\"; the fe method takes solver.elements"
                    .into(),
            ));
        }

        let target = match beam_spec {
            None => {
                if fe_asked || fe_keys || s.modes.is_some() {
                    return Err(ImpactError::Inconsistent("a [half_space] scene needs no solver.method = \"fe\", elements, alpha, time_step nor modes: the block is rigid".into()));
                }
                reasons.push("massive half-space: no beam model, the ball meets a rigid-backed Hertz contact".into());
                Target::HalfSpace
            }
            Some(beam) => {
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
                // The deflection if the ball's whole kinetic energy went into static bending
                // at the impact point, w = sqrt(m V^2 f): an upper bound that decides whether
                // small-deflection theory can hold.
                let flexibility = m.static_flexibility(position).unwrap_or(0.0);
                let deflection = (ball_mass * speed * speed * flexibility).sqrt();
                let large = deflection > LARGE_DEFLECTION * length;
                let use_fe = match s.method {
                    MethodName::Fe => {
                        reasons.push(
                            "method fe, as asked: geometrically exact Simo beam with HHT-alpha"
                                .into(),
                        );
                        true
                    }
                    MethodName::Modal => {
                        reasons.push("method modal, as asked".into());
                        false
                    }
                    MethodName::Auto if large || fe_keys => {
                        reasons.push(format!(
                            "method fe (auto): {}",
                            if large {
                                format!("the ball's energy could bend the beam {deflection:.3e} m at the impact point, more than {:.0} % of its length (sqrt(m V^2 / k)): small-deflection theory does not hold", 100.0 * LARGE_DEFLECTION)
                            } else {
                                "solver.elements, alpha or time_step given".into()
                            }
                        ));
                        true
                    }
                    MethodName::Auto => {
                        reasons.push(format!("method modal (auto): Goldsmith's modal series, exact between steps; the ball's energy bends the beam at most {deflection:.3e} m (sqrt(m V^2 / k)), small against its length"));
                        false
                    }
                };
                if use_fe {
                    if damping > 0.0 {
                        return Err(invalid("beam.modal_damping", damping, "must be 0 or absent with method = \"fe\" (the finite-element beam is undamped; HHT alpha adds numerical damping of high frequencies)"));
                    }
                    let samples = s.samples_per_pulse.unwrap_or(FE_SAMPLES_PER_PULSE);
                    if samples < 10 {
                        return Err(invalid(
                            "solver.samples_per_pulse",
                            samples,
                            "must be at least 10",
                        ));
                    }
                    let alpha = s.alpha.unwrap_or(FE_ALPHA);
                    if !(alpha.is_finite() && (-1.0 / 3.0..=0.0).contains(&alpha)) {
                        return Err(invalid(
                            "solver.alpha",
                            alpha,
                            "must be in [-1/3, 0] (HHT, the paper's eq. 9)",
                        ));
                    }
                    let contact_step = estimated_duration / samples as f64;
                    let free_time_step = match s.time_step {
                        Some(h) => positive("solver.time_step", h, "s")?.max(contact_step),
                        None => FE_FREE_STEP_RATIO * contact_step,
                    };
                    // Flexural wavelength at the fastest frequency the pulse excites
                    // (omega t_c = MODE_CUTOFF, as for the modes): lambda = 2 pi (EI / rho A)^(1/4) / sqrt(omega).
                    let omega = MODE_CUTOFF / estimated_duration;
                    let wavelength =
                        2.0 * PI * (m.flexural_rigidity() / m.mass_per_length()).powf(0.25)
                            / omega.sqrt();
                    if s.elements.is_some() && s.element_size.is_some() {
                        return Err(ImpactError::Inconsistent("solver: give elements (a uniform mesh) or element_size (a mesh graded from the impact point), not both".into()));
                    }
                    let nodes = match s.elements {
                        Some(0) => return Err(invalid("solver.elements", 0, "must be at least 1")),
                        Some(n) if n > 100_000 => {
                            return Err(invalid("solver.elements", n, "must be at most 100000"))
                        }
                        Some(n) => {
                            reasons.push(format!("{n} equal elements, as asked"));
                            (0..=n).map(|i| length * i as f64 / n as f64).collect()
                        }
                        None => {
                            let h0 = match s.element_size {
                                Some(h) => positive("solver.element_size", h, "m")?.min(length),
                                None => {
                                    (wavelength / FE_ELEMENTS_PER_WAVELENGTH).min(length / 16.0)
                                }
                            };
                            // Elements needed: about log(1 + L (r - 1) / h0) / log(r) per side.
                            let estimate = 2.0 * (1.0 + length * (FE_GROWTH - 1.0) / h0).ln()
                                / FE_GROWTH.ln()
                                + 32.0;
                            if estimate > 100_000.0 {
                                return Err(invalid(
                                    "solver.element_size",
                                    h0,
                                    "too small: the mesh would exceed 100000 elements",
                                ));
                            }
                            let nodes =
                                graded_nodes(length, position, h0, FE_GROWTH, length / 16.0);
                            let why = if s.element_size.is_some() {
                                "as asked".to_string()
                            } else {
                                format!("1/{FE_ELEMENTS_PER_WAVELENGTH} of the flexural wavelength {wavelength:.3e} m at omega t_c = {MODE_CUTOFF}")
                            };
                            reasons.push(format!(
                                "{} elements graded from {h0:.3e} m at the impact point ({why}) growing by {FE_GROWTH} per element to at most L/16",
                                nodes.len() - 1
                            ));
                            nodes
                        }
                    };
                    reasons.push(format!("HHT alpha = {alpha}; steps of {contact_step:.4e} s in contact ({samples} per estimated contact duration {estimated_duration:.4e} s), up to {free_time_step:.4e} s out of contact"));
                    let rigid_approach = rigid.max_approach;
                    Target::Fe(FeTarget {
                        analytic: m,
                        material: simo_beam::Material::new(
                            beam.youngs_modulus,
                            beam.poisson_ratio,
                            beam.density,
                        )?,
                        width: beam.width,
                        thickness: beam.thickness,
                        support: beam.support,
                        position,
                        nodes,
                        alpha,
                        free_time_step,
                        samples_per_pulse: samples,
                        approach_scale: rigid_approach,
                    })
                } else {
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
            }
        };

        let samples = match &target {
            Target::Fe(fe) => fe.samples_per_pulse,
            _ => s.samples_per_pulse.unwrap_or(DEFAULT_SAMPLES_PER_PULSE),
        };
        if samples < 10 {
            return Err(invalid("solver.samples_per_pulse", samples, "must be at least 10"));
        }
        let time_step = estimated_duration / samples as f64;
        let energy_tolerance = match (&target, s.adaptive_step, s.energy_tolerance) {
            (Target::Fe(_), None, None) => None,
            (Target::Fe(_), ..) => {
                return Err(ImpactError::Inconsistent(
                    "solver.adaptive_step and energy_tolerance belong to the modal method; the fe method adapts its step on the ball's local error".into(),
                ))
            }
            (_, Some(false), Some(_)) => {
                return Err(ImpactError::Inconsistent(
                    "solver.energy_tolerance is the adaptive step's: it has no use with adaptive_step = false".into(),
                ))
            }
            (_, Some(false), None) => None,
            (_, _, tol) => {
                let tol = tol.unwrap_or(DEFAULT_ENERGY_TOLERANCE);
                if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
                    return Err(invalid(
                        "solver.energy_tolerance",
                        tol,
                        "must be a fraction of the impact energy, 0 < tolerance < 1",
                    ));
                }
                Some(tol)
            }
        };
        reasons.push(match (&target, energy_tolerance) {
            (Target::Fe(_), _) => format!(
                "time step {time_step:.4e} s in contact: {samples} steps per estimated contact duration {estimated_duration:.4e} s (Hertz, rigid support)"
            ),
            (_, Some(tol)) => format!(
                "adaptive step in contact, at most {time_step:.4e} s ({samples} per estimated contact duration {estimated_duration:.4e} s, Hertz, rigid support), halved down to 1/{} of it to keep the energy mismatch within {tol:.1e} of the impact energy per contact duration",
                1usize << crate::modal_solver::FINEST_LEVEL
            ),
            (_, None) => format!(
                "uniform time step {time_step:.4e} s in contact: {samples} steps per estimated contact duration {estimated_duration:.4e} s (Hertz, rigid support)"
            ),
        });

        let default_end = match target {
            Target::HalfSpace => 4.0 * estimated_duration,
            Target::Beam { .. } | Target::Fe(_) => 0.005,
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

        let (method, modes, elements) = match &target {
            Target::Beam { modes, .. } => ("modal", *modes, 0),
            Target::Fe(fe) => ("fe", 0, fe.nodes.len() - 1),
            Target::HalfSpace => ("half-space", 0, 0),
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
                elements,
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
            energy_tolerance,
            output_interval,
            estimated_duration,
            yield_stress,
            warnings,
        })
    }
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
