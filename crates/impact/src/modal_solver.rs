//! Ball + modal beam + contact law: Goldsmith's method with exact modal propagation.
//!
//! In contact, each step of length h holds the force linear in time (first-order hold). The
//! beam's displacement at the impact point and the ball's position at the end of the step are
//! both affine in the unknown end force F1, so the approach is delta1 = d_free - C F1 and the
//! step is the scalar monotone equation F1 = law(d_free - C F1), solved by safeguarded Newton.
//! The step is set by the force pulse only (exact propagation has no stability limit).
//! Out of contact the beam and ball move freely; the solver jumps ahead by conservative
//! advancement: a jump is never longer than the gap allows given bounds on how fast the beam
//! and the ball can close it, so no re-contact longer than a quarter contact step is missed.
//! Onset and separation are located by root finding on the approach.

use crate::error::ImpactError;
use crate::history::{History, Sample};
use crate::illinois::Illinois;
use crate::plan::{Law, Plan, Target};
use crate::report::{static_stiffness, Contact, Ending, Energy, Report};
use hertz::ContactLaw;
use modal::{Hold, ModalState, PointModes, Transition};
use std::rc::Rc;

/// What a run produces.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Per-contact metrics and the energy ledger.
    pub report: Report,
    /// Time series.
    pub history: History,
}

/// Runs a plan to its end time.
///
/// # Errors
/// `SolverFailed` if a step produces a non-finite value (not expected for valid plans).
pub fn run(plan: &Plan) -> Result<Outcome, ImpactError> {
    if let Target::Fe(fe) = &plan.target {
        return crate::fe_solver::run(plan, fe);
    }
    match &plan.law {
        Law::Hertz(l) => Solver::new(plan, l)?.run(),
        Law::HuntCrossley(l) => Solver::new(plan, l)?.run(),
        Law::Thornton(l) => Solver::new(plan, l)?.run(),
    }
}

struct Solver<'a, L: ContactLaw> {
    plan: &'a Plan,
    law: &'a L,
    modes: PointModes,
    /// Shared so that a step can use it while the solver's state changes.
    contact_step: Rc<Transition>,
    // State at time t.
    t: f64,
    ball_position: f64,
    ball_velocity: f64,
    beam: ModalState,
    law_state: L::State,
    force: f64,
    /// Beam displacement at the impact point, sum g q, kept in step with `beam`.
    displacement: f64,
    /// Impact position (m), 0 on a half-space: the history's contact point.
    contact_point: f64,
    /// Whether any mode is damped (else the damping work is skipped, not summed as zeros).
    damped: bool,
    // Bookkeeping.
    damping_work: f64,
    history: History,
    contacts: Vec<Contact>,
    max_displacement: (f64, f64),
    record_stride: usize,
}

/// Vertex value of the parabola through three equally spaced samples (the sample itself if
/// they are not concave): refines a discrete maximum to O(h^3).
fn parabola_peak(ym: f64, y0: f64, yp: f64) -> f64 {
    let d = ym - 2.0 * y0 + yp;
    if d < 0.0 {
        y0 - (yp - ym) * (yp - ym) / (8.0 * d)
    } else {
        y0
    }
}

/// Largest of equally spaced samples, refined by a parabola where it is interior.
pub(crate) fn refined_max(samples: &[f64]) -> f64 {
    let Some((k, &best)) = samples.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return 0.0;
    };
    if k > 0 && k + 1 < samples.len() {
        parabola_peak(samples[k - 1], best, samples[k + 1]).max(best)
    } else {
        best
    }
}

/// Largest tau >= 0 with a tau^2 + b tau <= gap on [0, tau], for a >= 0 and gap > 0.
fn quadratic_horizon(a: f64, b: f64, gap: f64) -> f64 {
    if a > 0.0 {
        (-b + (b * b + 4.0 * a * gap).sqrt()) / (2.0 * a)
    } else if b > 0.0 {
        gap / b
    } else {
        f64::INFINITY
    }
}

impl<'a, L: ContactLaw> Solver<'a, L> {
    fn new(plan: &'a Plan, law: &'a L) -> Result<Self, ImpactError> {
        let modes = match &plan.target {
            Target::Beam { beam, position, damping, modes } => {
                let m = beam.modes(*modes)?;
                PointModes::new(beam, &m, *position, *damping)?
            }
            Target::HalfSpace | Target::Fe(_) => PointModes::from_parts(vec![], vec![], vec![])?,
        };
        let contact_step = Rc::new(Transition::new(&modes, plan.time_step, Hold::FirstOrder)?);
        let n = modes.len();
        let damped = modes.damping_ratio().iter().any(|z| *z > 0.0);
        let samples = (plan.estimated_duration / plan.time_step).round() as usize;
        Ok(Self {
            plan,
            law,
            modes,
            contact_step,
            t: 0.0,
            ball_position: 0.0,
            ball_velocity: plan.speed,
            beam: ModalState::at_rest(n),
            law_state: L::State::default(),
            force: 0.0,
            displacement: 0.0,
            contact_point: match &plan.target {
                Target::Beam { position, .. } => *position,
                _ => 0.0,
            },
            damped,
            damping_work: 0.0,
            history: History::default(),
            contacts: Vec::new(),
            max_displacement: (0.0, 0.0),
            record_stride: (samples / 200).max(1),
        })
    }

    fn beam_displacement(&self) -> f64 {
        self.displacement
    }

    fn approach(&self) -> f64 {
        self.ball_position - self.beam_displacement()
    }

    fn record(&mut self) {
        let w = self.beam_displacement();
        let m = self.plan.ball_mass;
        let delta = self.ball_position - w;
        self.history.push(Sample {
            ball_energy: 0.5 * m * self.ball_velocity * self.ball_velocity
                - m * self.plan.gravity * self.ball_position,
            beam_energy: self.modes.energy(&self.beam),
            contact_energy: self.law.stored_energy(&self.law_state, delta),
            dissipated_energy: self.law.dissipated_energy(&self.law_state) + self.damping_work,
            time: self.t,
            force: self.force,
            approach: self.ball_position - w,
            ball_position: self.ball_position,
            ball_velocity: self.ball_velocity,
            beam_displacement: w,
            contact_point: self.contact_point,
        });
    }

    fn check_finite(&self, value: f64, what: &str) -> Result<(), ImpactError> {
        if value.is_finite() {
            Ok(())
        } else {
            Err(ImpactError::SolverFailed { t: self.t, reason: format!("{what} is not finite") })
        }
    }

    fn run(mut self) -> Result<Outcome, ImpactError> {
        let clock = std::time::Instant::now();
        self.record();
        // The run starts at first touch: delta = 0 with the ball closing at the impact speed.
        let end = self.plan.end_time;
        while self.t < end {
            self.contact_phase()?;
            if self.t < end {
                self.free_flight()?;
            }
        }
        Ok(self.finish(clock.elapsed().as_secs_f64()))
    }

    /// Scalar implicit contact equation r(F) = F - law(d - C F, a (d - C F) + b) = 0, increasing
    /// in F; safeguarded Newton in the bracket [0, (d - release)/C].
    fn solve_force(&self, d: f64, c: f64, a: f64, b: f64, guess: f64) -> f64 {
        let eval = |f: f64| {
            let delta = d - c * f;
            let cf = self.law.force(&self.law_state, delta, a * delta + b);
            (f - cf.force, 1.0 + c * (cf.stiffness + a * cf.damping))
        };
        if eval(0.0).0 >= 0.0 {
            return 0.0;
        }
        let (mut lo, mut hi) = (0.0, (d - self.law.release_approach(&self.law_state)) / c);
        let mut f = guess.clamp(lo, hi);
        for _ in 0..100 {
            let (r, dr) = eval(f);
            if r > 0.0 {
                hi = f;
            } else {
                lo = f;
            }
            let newton = f - r / dr;
            let next = if newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
            if (next - f).abs() <= 4.0 * f64::EPSILON * next || hi - lo <= 4.0 * f64::EPSILON * hi {
                return next;
            }
            f = next;
        }
        f
    }

    /// Ball position and velocity after tau under gravity and a contact force going linearly
    /// from f0 to f1 (exact for that force).
    fn ball_after(&self, tau: f64, f0: f64, f1: f64) -> (f64, f64) {
        let (m, g) = (self.plan.ball_mass, self.plan.gravity);
        (
            self.ball_position + self.ball_velocity * tau + 0.5 * g * tau * tau
                - tau * tau * (f0 / 3.0 + f1 / 6.0) / m,
            self.ball_velocity + g * tau - tau * (f0 + f1) / (2.0 * m),
        )
    }

    /// Steps through one contact, from onset (force zero) to separation or the end time.
    fn contact_phase(&mut self) -> Result<(), ImpactError> {
        let end = self.plan.end_time;
        let start = self.t;
        let velocity_before = self.ball_velocity;
        let (mut forces, mut approaches) = (vec![self.force], vec![self.approach()]);
        let mut impulse = 0.0;
        let mut previous_approach: Option<f64> = None;
        let mut complete = false;
        let mut steps = 0;
        while self.t < end {
            let remaining = end - self.t;
            let tr = if remaining < self.contact_step.step_size() {
                Rc::new(Transition::new(&self.modes, remaining, Hold::FirstOrder)?)
            } else {
                Rc::clone(&self.contact_step)
            };
            let h = tr.step_size();
            let f0 = self.force;
            let delta0 = self.approach();
            let (u_free, _) = self.ball_after(h, f0, 0.0);
            let d_free = u_free - tr.free_displacement(&self.beam, f0);
            let compliance = h * h / (6.0 * self.plan.ball_mass) + tr.compliance();
            // Approach rate from displacements only (the modal velocity series does not
            // converge): BDF2 on equal steps, backward Euler on the first.
            let (a, b) = match previous_approach {
                Some(dm1) if Rc::ptr_eq(&tr, &self.contact_step) => {
                    (1.5 / h, (dm1 - 4.0 * delta0) / (2.0 * h))
                }
                _ => (1.0 / h, -delta0 / h),
            };
            let guess = forces.len().checked_sub(2).map_or(f0, |k| 2.0 * f0 - forces[k]);
            let f1 = self.solve_force(d_free, compliance, a, b, guess);
            self.check_finite(f1, "the contact force")?;
            let release = self.law.release_approach(&self.law_state);
            if f1 == 0.0 {
                // Separation within this step: find when the approach returns to the release
                // approach with the force falling linearly to zero.
                // A touch that carries no force on its first step is stepped over whole, so that
                // time always advances by at least one contact step.
                let tau = if d_free <= release && steps > 0 {
                    self.locate_separation(h, f0, release)?
                } else {
                    h
                };
                self.advance(tau, f0, 0.0)?;
                impulse += 0.5 * tau * f0;
                let delta = self.approach();
                self.law.commit(&mut self.law_state, delta, (delta - delta0) / tau);
                forces.push(0.0);
                approaches.push(delta);
                complete = true;
                steps += 1;
                break;
            }
            let delta1 = d_free - compliance * f1;
            self.advance_with(&tr, f0, f1)?;
            impulse += 0.5 * h * (f0 + f1);
            self.law.commit(&mut self.law_state, delta1, a * delta1 + b);
            previous_approach = Some(delta0);
            forces.push(f1);
            approaches.push(delta1);
            steps += 1;
            if steps % self.record_stride == 0 {
                self.record();
            }
        }
        self.record();
        if forces.iter().all(|f| *f == 0.0) {
            // A grazing touch that never carried force is not a contact.
            return Ok(());
        }
        // The interior samples are equally spaced; the first and last steps may not be, and
        // refined_max only refines an interior maximum.
        self.contacts.push(Contact {
            start,
            duration: self.t - start,
            complete,
            peak_force: refined_max(&forces),
            max_approach: refined_max(&approaches),
            impulse,
            ball_velocity_before: velocity_before,
            ball_velocity_after: self.ball_velocity,
            print_radius: self.law.print_radius(&self.law_state),
            steps,
        });
        Ok(())
    }

    /// Advances ball and beam by tau with the force linear from f0 to f1, and accounts the
    /// modal damping work (trapezoidal in contact; in free flight it is exact: see free_flight).
    fn advance(&mut self, tau: f64, f0: f64, f1: f64) -> Result<(), ImpactError> {
        if tau <= 0.0 {
            return Ok(());
        }
        let tr = Transition::new(&self.modes, tau, Hold::FirstOrder)?;
        self.advance_with(&tr, f0, f1)
    }

    /// Advances by a prepared transition.
    fn advance_with(
        &mut self,
        transition: &Transition,
        f0: f64,
        f1: f64,
    ) -> Result<(), ImpactError> {
        let tau = transition.step_size();
        let p0 = if self.damped { self.modes.damping_power(&self.beam) } else { 0.0 };
        self.displacement = transition.advance(&mut self.beam, f0, f1);
        (self.ball_position, self.ball_velocity) = self.ball_after(tau, f0, f1);
        if self.damped {
            self.damping_work += 0.5 * tau * (p0 + self.modes.damping_power(&self.beam));
        }
        self.t += tau;
        self.force = f1;
        self.check_finite(self.ball_position + self.displacement, "the state")?;
        if self.displacement > self.max_displacement.0 {
            self.max_displacement = (self.displacement, self.t);
        }
        Ok(())
    }

    /// Approach after tau of a step from the current state with the force going from f0 to 0.
    fn approach_after(&self, tau: f64, f0: f64) -> Result<f64, ImpactError> {
        if tau <= 0.0 {
            return Ok(self.approach());
        }
        let tr = Transition::new(&self.modes, tau, Hold::FirstOrder)?;
        Ok(self.ball_after(tau, f0, 0.0).0 - tr.free_displacement(&self.beam, f0))
    }

    /// Root of approach(tau) = target in (0, h) by the Illinois variant of regula falsi, given
    /// approach(0) > target >= approach(h) (or the reverse for onset).
    fn locate(
        &self,
        h: f64,
        f0: f64,
        target: f64,
        delta0: f64,
        delta_h: f64,
    ) -> Result<f64, ImpactError> {
        let mut bracket = Illinois::new(0.0, delta0 - target, h, delta_h - target);
        for _ in 0..100 {
            let Some(c) = bracket.trial() else { break };
            if bracket.b - bracket.a <= 1e-13 * h {
                break;
            }
            let fc = self.approach_after(c, f0)? - target;
            if fc == 0.0 {
                return Ok(c);
            }
            bracket.narrow(c, fc);
        }
        Ok(0.5 * (bracket.a + bracket.b))
    }

    fn locate_separation(&self, h: f64, f0: f64, release: f64) -> Result<f64, ImpactError> {
        let d_h = self.approach_after(h, f0)?;
        self.locate(h, f0, release, self.approach(), d_h)
    }

    /// Conservative-advancement horizon: no contact can start within it. With the modes split
    /// at k, |w_high(t)| <= H_k = sum_{n>=k} |g_n| A_n / omega_n for all t, and the low modes move
    /// the point at most P_k = sum_{n<k} |g_n| A_n fast, with A_n = sqrt(v_n^2 + omega_n^2 q_n^2)
    /// (non-increasing in free vibration, damped or not). So
    /// delta(t + tau) <= delta(t) + 2 H_k + (v_ball + P_k) tau + g tau^2 / 2.
    fn safe_horizon(&self, release: f64) -> f64 {
        let delta = self.approach();
        let n = self.modes.len();
        let (omega, gain) = (self.modes.omega(), self.modes.gain());
        let mut high = vec![0.0; n + 1];
        for k in (0..n).rev() {
            let amplitude = (self.beam.v[k].powi(2) + (omega[k] * self.beam.q[k]).powi(2)).sqrt();
            let bound =
                if omega[k] > 0.0 { gain[k].abs() * amplitude / omega[k] } else { f64::INFINITY };
            high[k] = high[k + 1] + bound;
        }
        let mut best: f64 = 0.0;
        let mut low_speed = 0.0;
        for k in 0..=n {
            let gap = release - delta - 2.0 * high[k];
            if gap > 0.0 {
                best = best.max(quadratic_horizon(
                    0.5 * self.plan.gravity,
                    self.ball_velocity + low_speed,
                    gap,
                ));
            }
            if k < n {
                let amplitude =
                    (self.beam.v[k].powi(2) + (omega[k] * self.beam.q[k]).powi(2)).sqrt();
                low_speed += gain[k].abs() * amplitude;
            }
        }
        best
    }

    /// Free flight until the next onset or the end time.
    fn free_flight(&mut self) -> Result<(), ImpactError> {
        let end = self.plan.end_time;
        let dt_out = self.plan.output_interval;
        let min_step = 0.25 * self.contact_step.step_size();
        // Jumps are dt_out / 2^k, the largest that the safe horizon allows (at least about a
        // quarter contact step), so their transitions are built once per level and reused.
        let levels = ((dt_out / min_step).log2().ceil().max(0.0) as usize).min(60);
        let mut cache: Vec<Option<Transition>> = vec![None; levels + 1];
        let mut next_output = ((self.t / dt_out).floor() + 1.0) * dt_out;
        while self.t < end {
            let release = self.law.release_approach(&self.law_state);
            let horizon = self.safe_horizon(release).max(min_step);
            let level = if horizon >= dt_out {
                0
            } else {
                ((dt_out / horizon).log2().ceil() as usize).min(levels)
            };
            let built;
            let tr = if end - self.t < dt_out / f64::powi(2.0, level as i32) {
                built = Transition::new(&self.modes, end - self.t, Hold::FirstOrder)?;
                &built
            } else {
                if cache[level].is_none() {
                    cache[level] = Some(Transition::new(
                        &self.modes,
                        dt_out / f64::powi(2.0, level as i32),
                        Hold::FirstOrder,
                    )?);
                }
                cache[level].as_ref().ok_or_else(|| ImpactError::SolverFailed {
                    t: self.t,
                    reason: "transition cache".into(),
                })?
            };
            let tau = tr.step_size();
            let delta0 = self.approach();
            let delta_tau =
                self.ball_after(tau, 0.0, 0.0).0 - tr.free_displacement(&self.beam, 0.0);
            if delta_tau > release {
                let onset = self.locate(tau, 0.0, release, delta0, delta_tau)?;
                self.free_advance(onset, None)?;
                return Ok(());
            }
            self.free_advance(tau, Some(tr))?;
            // Record at the first step end at or after each output instant.
            if self.t >= next_output || self.t >= end {
                self.record();
                next_output = ((self.t / dt_out).floor() + 1.0) * dt_out;
            }
        }
        Ok(())
    }

    /// Force-free advance: the beam's energy loss is exactly the modal damping work.
    fn free_advance(&mut self, tau: f64, prepared: Option<&Transition>) -> Result<(), ImpactError> {
        let before = if self.damped { self.modes.energy(&self.beam) } else { 0.0 };
        let work = self.damping_work;
        match prepared {
            Some(tr) => self.advance_with(tr, 0.0, 0.0)?,
            None => self.advance(tau, 0.0, 0.0)?,
        }
        if !self.damped {
            return Ok(());
        }
        self.damping_work = work + (before - self.modes.energy(&self.beam));
        Ok(())
    }

    fn finish(self, wall_time: f64) -> Outcome {
        let plan = self.plan;
        let m = plan.ball_mass;
        let delta = self.approach();
        let initial = 0.5 * m * plan.speed * plan.speed;
        let ball_kinetic = 0.5 * m * self.ball_velocity * self.ball_velocity;
        let ball_potential = -m * plan.gravity * self.ball_position;
        let beam = self.modes.energy(&self.beam);
        let contact_stored = self.law.stored_energy(&self.law_state, delta);
        let dissipated = self.law.dissipated_energy(&self.law_state) + self.damping_work;
        let balance_error =
            initial - (ball_kinetic + ball_potential + beam + contact_stored + dissipated);

        let mut warnings = plan.warnings.clone();
        let static_stiffness = match &plan.target {
            Target::Beam { beam, position, .. } => {
                let length = beam.length();
                if self.max_displacement.0 > crate::plan::LARGE_DEFLECTION * length {
                    warnings.push(format!(
                        "the largest displacement {:.4} m is {:.0} % of the beam length: small-deflection (modal) theory is exceeded",
                        self.max_displacement.0,
                        100.0 * self.max_displacement.0 / length
                    ));
                }
                static_stiffness(beam, *position, &mut warnings)
            }
            Target::HalfSpace | Target::Fe(_) => None,
        };
        let report = Report::assemble(
            plan,
            Ending {
                plan: plan.summary.clone(),
                warnings,
                contacts: self.contacts,
                max_displacement: self.max_displacement,
                static_stiffness,
                energy: Energy {
                    initial,
                    ball_kinetic,
                    ball_potential,
                    beam,
                    contact_stored,
                    dissipated,
                    balance_error,
                },
                wall_time,
            },
        );
        Outcome { report, history: self.history }
    }
}
