//! Contact laws: the one place where a scene's `[contact]` becomes a law and where a law is
//! handed to a solver.
//!
//! A new law is one variant of [`Law`] with its arm in [`Law::resolve`] (its parameters from
//! the scene, with the reasons), [`Law::name`] and [`Law::with`] (the dispatch to the solvers,
//! which are generic over [`hertz::ContactLaw`]), plus its name in [`LawName`] for the scene
//! file. Nothing else in the crate names a law.

use crate::error::{bounded, invalid, range, ImpactError};
use crate::scene::{ContactSpec, LawName};
use hertz::{ContactLaw, Hertz, HuntCrossley, Thornton};

/// The largest Hunt-Crossley damping factor (s/m) a scene may give.
const MAX_DAMPING: f64 = 1e6;

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

/// What a law's parameters are resolved from.
pub(crate) struct LawContext {
    /// The elastic contact between the ball and the struck body.
    pub(crate) hertz: Hertz,
    /// Ball mass (kg).
    pub(crate) ball_mass: f64,
    /// Impact speed (m/s).
    pub(crate) speed: f64,
    /// The softer of the two yield stresses (Pa), if either is known.
    pub(crate) yield_stress: Option<f64>,
}

/// Something to do with a law whatever its type: the solvers are generic over
/// [`ContactLaw`], and [`Law::with`] is the one match that hands them the concrete law.
pub(crate) trait WithLaw {
    /// What it produces.
    type Output;
    /// Does it with `law`.
    fn apply<L: ContactLaw>(self, law: &L) -> Self::Output;
}

impl Law {
    /// The central pressure p0 (Pa) and the contact radius a (m) of a contact that reached
    /// `peak_force` (N) and `max_approach` (m). Elastic laws: Hertz at the peak force,
    /// a = (3 F R / (4 E*))^(1/3), p0 = 3 F / (2 pi a^2) (Johnson, *Contact Mechanics*, eqs.
    /// 4.22-4.24; Hunt-Crossley's damping adds force but not the elastic pressure's shape, so
    /// this is its elastic part's bound at the peak force). Thornton: a contact that loaded
    /// past first yield, the pressure its law caps, p_y, over the radius of its plastic contact
    /// a = sqrt(R delta_max) (the print's rim); a later contact that reloaded the print
    /// elastically (below the history's largest approach, from the print after it,
    /// `print_radius`), Hertz on the print's enlarged radius
    /// ([`hertz::Thornton::pressure_and_radius`]).
    pub(crate) fn peak_pressure(
        &self,
        peak_force: f64,
        max_approach: f64,
        print_radius: f64,
    ) -> (f64, f64) {
        match self {
            Law::Thornton(t) => {
                // The history's largest approach from the print after this contact,
                // a_p^2 = R delta_max (none: elastic so far).
                let history = (print_radius * print_radius / t.hertz().effective_radius())
                    .max(max_approach.min(t.yield_approach()));
                t.pressure_and_radius(history, max_approach, peak_force)
            }
            _ => {
                let delta = self.hertz().approach_for_force(peak_force.max(0.0));
                (self.hertz().max_pressure(delta), self.hertz().contact_radius(delta))
            }
        }
    }

    /// The elastic contact underneath every law.
    fn hertz(&self) -> &Hertz {
        match self {
            Law::Hertz(h) => h,
            Law::HuntCrossley(h) => h.hertz(),
            Law::Thornton(t) => t.hertz(),
        }
    }

    /// The law `spec` asks for, with its parameters; the reasons for derived parameters go to
    /// `reasons`, and an elastic law driven past first yield adds a warning.
    ///
    /// # Errors
    /// `InvalidField` for a parameter out of range, `Inconsistent` for parameters that do not
    /// belong to the law or a plastic law without a yield stress.
    pub(crate) fn resolve(
        spec: &ContactSpec,
        context: &LawContext,
        reasons: &mut Vec<String>,
        warnings: &mut Vec<String>,
    ) -> Result<Self, ImpactError> {
        let LawContext { hertz, ball_mass, speed, yield_stress } = *context;
        let law = match spec.law {
            LawName::Hertz => {
                if spec.damping.is_some()
                    || spec.restitution.is_some()
                    || spec.limiting_pressure.is_some()
                {
                    return Err(ImpactError::Inconsistent("contact.law = \"hertz\" takes no damping, restitution or limiting_pressure".into()));
                }
                Law::Hertz(hertz)
            }
            LawName::HuntCrossley => match (spec.damping, spec.restitution) {
                (Some(d), None) => {
                    // chi V is the loss: at 1e3 s/m a 1 m/s impact keeps e ~ 1e-3.
                    if !(d.is_finite() && (0.0..=MAX_DAMPING).contains(&d)) {
                        return Err(invalid(
                            "contact.damping",
                            crate::error::show(d),
                            "must be from 0 to 1e6 (s/m)",
                        ));
                    }
                    Law::HuntCrossley(HuntCrossley::new(hertz, d)?)
                }
                (None, Some(e)) => {
                    if !(e.is_finite() && e > 0.0 && e <= 1.0) {
                        return Err(invalid("contact.restitution", e, "must be in (0, 1]"));
                    }
                    let law = HuntCrossley::from_restitution(hertz, e, speed)?;
                    reasons.push(format!("Hunt-Crossley damping chi = {:.4} s/m for restitution {e} at {speed:.4} m/s: the exact half-space relation chi V - ln(1 + chi V) = -e chi V - ln(1 - e chi V) (the small-damping 3(1 - e)/(2 V) = {:.4} s/m gives less loss); on a beam the beam's vibration takes more", law.damping_factor(), 1.5 * (1.0 - e) / speed));
                    Law::HuntCrossley(law)
                }
                _ => return Err(ImpactError::Inconsistent("contact.law = \"hunt-crossley\" needs exactly one of damping (s/m) or restitution".into())),
            },
            LawName::Thornton => {
                let p = match (spec.limiting_pressure, yield_stress) {
                    (Some(p), _) => {
                        bounded("contact.limiting_pressure", p, range::MODULUS, "Pa")?
                    }
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
                // The rigid-support estimate of the first contact's central pressure.
                let p0 = hertz::HalfSpaceImpact::elastic(&hertz, ball_mass, speed)
                    .map_or(0.0, |i| i.max_pressure);
                warnings.push(format!(
                    "the impact speed {speed:.3} m/s exceeds the first-yield speed {vy:.3} m/s: the central pressure p0 = {:.4e} Pa (Hertz, rigid support) passes 1.6 Y = {:.4e} Pa; the contact yields; contact.law = \"thornton\" models it",
                    p0,
                    hertz::FIRST_YIELD_PRESSURE_RATIO * y
                ));
            }
        }
        Ok(law)
    }

    /// The law's name, as a scene file writes it.
    pub fn name(&self) -> LawName {
        match self {
            Law::Hertz(_) => LawName::Hertz,
            Law::HuntCrossley(_) => LawName::HuntCrossley,
            Law::Thornton(_) => LawName::Thornton,
        }
    }

    /// Hands the concrete law to `work`.
    pub(crate) fn with<W: WithLaw>(&self, work: W) -> W::Output {
        match self {
            Law::Hertz(l) => work.apply(l),
            Law::HuntCrossley(l) => work.apply(l),
            Law::Thornton(l) => work.apply(l),
        }
    }
}
