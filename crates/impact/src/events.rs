//! Contact events, shared by both solvers: locating onset and separation in time (the
//! Illinois variant of regula falsi, Dowell & Jarratt 1971), refining a sampled maximum, and
//! the bookkeeping of one contact from onset to separation ([`ContactRecorder`]).

use crate::outcome::{Contact, PULSE_FRACTION};

/// A bracket [a, b] of a sign change of f, narrowed by [`Illinois::narrow`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Illinois {
    /// Left end and f there.
    pub(crate) a: f64,
    fa: f64,
    /// Right end and f there.
    pub(crate) b: f64,
    fb: f64,
    /// Which end moved last: -1 left, 1 right, 0 none yet.
    side: i8,
}

impl Illinois {
    /// The bracket [a, b] with f(a) = fa and f(b) = fb of opposite signs.
    pub(crate) fn new(a: f64, fa: f64, b: f64, fb: f64) -> Self {
        Self { a, fa, b, fb, side: 0 }
    }

    /// The next trial point (secant through the ends), or `None` once it no longer falls
    /// strictly inside the bracket (the bracket is as narrow as round-off allows).
    pub(crate) fn trial(&self) -> Option<f64> {
        let c = (self.a * self.fb - self.b * self.fa) / (self.fb - self.fa);
        (c > self.a && c < self.b).then_some(c)
    }

    /// Replaces the end on the side of f(c) = fc; when the same end moves twice in a row the
    /// other end's value is halved, which keeps the convergence superlinear where plain
    /// regula falsi would stall with one end fixed.
    pub(crate) fn narrow(&mut self, c: f64, fc: f64) {
        if (fc > 0.0) == (self.fa > 0.0) {
            self.a = c;
            self.fa = fc;
            if self.side == -1 {
                self.fb *= 0.5;
            }
            self.side = -1;
        } else {
            self.b = c;
            self.fb = fc;
            if self.side == 1 {
                self.fa *= 0.5;
            }
            self.side = 1;
        }
    }
}

/// Largest of samples y(t), refined by the parabola through the largest and its two
/// neighbours where it is interior and they are concave: O(h^3) for any spacing.
pub(crate) fn refined_max(times: &[f64], values: &[f64]) -> f64 {
    let Some((k, &best)) = values.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return 0.0;
    };
    if k == 0 || k + 1 >= values.len() || k + 1 >= times.len() {
        return best;
    }
    let (h1, h2) = (times[k] - times[k - 1], times[k + 1] - times[k]);
    if h1 <= 0.0 || h2 <= 0.0 {
        return best;
    }
    // p(u) = y_k + b u + c u^2 with u = t - t_k; c is the second divided difference. For the
    // largest sample with c < 0 the vertex lies between the neighbours.
    let (s1, s2) = ((best - values[k - 1]) / h1, (values[k + 1] - best) / h2);
    let c = (s2 - s1) / (h1 + h2);
    if c < 0.0 {
        let b = s1 + c * h1;
        (best - b * b / (4.0 * c)).max(best)
    } else {
        best
    }
}

/// The time from the first rise of `forces` through `level` to their first fall back through
/// it after the peak, each crossing interpolated linearly between samples: the main pulse,
/// without a ride or a second hump that follows it.
pub(crate) fn pulse_duration(times: &[f64], forces: &[f64], level: f64) -> f64 {
    let crossing = |i: usize| {
        let (f0, f1) = (forces[i], forces[i + 1]);
        times[i] + (times[i + 1] - times[i]) * ((level - f0) / (f1 - f0)).clamp(0.0, 1.0)
    };
    let above = |f: f64| f >= level;
    let Some(first) = forces.iter().position(|f| above(*f)) else {
        return 0.0;
    };
    let peak = forces.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).map_or(first, |p| p.0);
    let last =
        forces[peak..].iter().position(|f| !above(*f)).map_or(forces.len() - 1, |k| peak + k - 1);
    let rise = if first == 0 { times[0] } else { crossing(first - 1) };
    let fall = if last + 1 >= forces.len() { times[last] } else { crossing(last) };
    fall - rise
}

/// One contact from onset to separation, step by step: the force and approach samples for
/// the refined peaks, and the impulse by the trapezoidal rule (exact for the force held
/// linear over each step, as both solvers hold it).
#[derive(Debug, Clone)]
pub(crate) struct ContactRecorder {
    start: f64,
    velocity_before: f64,
    times: Vec<f64>,
    forces: Vec<f64>,
    approaches: Vec<f64>,
    impulse: f64,
    steps: usize,
}

impl ContactRecorder {
    /// A contact starting at time `t` (s) with `force` (N), `approach` (m) and the ball
    /// closing at `ball_velocity` (m/s).
    pub(crate) fn start(t: f64, force: f64, approach: f64, ball_velocity: f64) -> Self {
        Self {
            start: t,
            velocity_before: ball_velocity,
            times: vec![t],
            forces: vec![force],
            approaches: vec![approach],
            impulse: 0.0,
            steps: 0,
        }
    }

    /// The state after a step of `dt` (s) ending at `t` with `force` (N) and `approach` (m).
    pub(crate) fn step(&mut self, t: f64, dt: f64, force: f64, approach: f64) {
        let f0 = self.forces.last().copied().unwrap_or(0.0);
        self.impulse += 0.5 * dt * (f0 + force);
        self.times.push(t);
        self.forces.push(force);
        self.approaches.push(approach);
        self.steps += 1;
    }

    /// Forces so far (N), from onset.
    pub(crate) fn forces(&self) -> &[f64] {
        &self.forces
    }

    /// Steps taken so far.
    pub(crate) fn steps(&self) -> usize {
        self.steps
    }

    /// The contact, ended at `t` (s) with the ball at `ball_velocity` (m/s) and a print of
    /// `print_radius` (m); `complete` if it ended by separation, not by the end of the run.
    /// `None` for a grazing touch that never carried force.
    pub(crate) fn finish(
        self,
        t: f64,
        complete: bool,
        ball_velocity: f64,
        print_radius: f64,
    ) -> Option<Contact> {
        if self.forces.iter().all(|f| *f == 0.0) {
            return None;
        }
        let peak = refined_max(&self.times, &self.forces);
        Some(Contact {
            start: self.start,
            duration: t - self.start,
            complete,
            pulse_duration: pulse_duration(&self.times, &self.forces, PULSE_FRACTION * peak),
            peak_force: peak,
            max_approach: refined_max(&self.times, &self.approaches),
            impulse: self.impulse,
            ball_velocity_before: self.velocity_before,
            ball_velocity_after: ball_velocity,
            print_radius,
            // The stresses at the peak are the report's to fill in: they need the law.
            max_pressure: 0.0,
            contact_radius: 0.0,
            ball_max_shear: 0.0,
            ball_max_shear_depth: 0.0,
            body_max_shear: 0.0,
            body_max_shear_depth: 0.0,
            steps: self.steps,
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)] // the end sample is kept exactly
    use super::{refined_max, Illinois};

    #[test]
    fn the_pulse_is_read_between_level_crossings() {
        // A triangle 0 -> 10 -> 0 over [0, 2] and then a long ride, at 0.1 and then a hump
        // to 2: at level 1 the pulse runs from 0.1 to 1 + 9/9.9, whatever follows it.
        let times = [0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0];
        let forces = [0.0, 10.0, 0.1, 0.1, 0.1, 2.0, 0.1];
        let pulse = super::pulse_duration(&times, &forces, 1.0);
        assert!((pulse - (1.0 + 9.0 / 9.9 - 0.1)).abs() < 1e-12, "{pulse}");
    }

    #[test]
    fn refined_max_is_exact_for_a_parabola_on_any_spacing() {
        // y = 3 - 2 (t - 0.37)^2 sampled unevenly: the vertex value 3 is recovered.
        let times = [0.0, 0.1, 0.3, 0.35, 0.5, 0.9];
        let values: Vec<f64> = times.iter().map(|t| 3.0 - 2.0 * (t - 0.37) * (t - 0.37)).collect();
        assert!((refined_max(&times, &values) - 3.0).abs() < 1e-14);
        // On equal spacing it is the classical three-point vertex; a maximum at an end is kept.
        let ramp = [1.0, 2.0, 3.0];
        assert!(refined_max(&[0.0, 1.0, 2.0], &ramp) == 3.0);
    }

    #[test]
    fn finds_the_root_of_a_convex_function_superlinearly() {
        // f(x) = x^3 - 2 on [0, 2]: plain regula falsi keeps the right end and needs ~100
        // iterations for 1e-12; Illinois needs well under 20.
        let f = |x: f64| x * x * x - 2.0;
        let mut bracket = Illinois::new(0.0, f(0.0), 2.0, f(2.0));
        let mut iterations = 0;
        while let Some(c) = bracket.trial() {
            let fc = f(c);
            iterations += 1;
            if fc.abs() < 1e-12 {
                assert!((c - 2f64.cbrt()).abs() < 1e-12);
                break;
            }
            bracket.narrow(c, fc);
        }
        assert!(iterations < 20, "{iterations} iterations");
    }
}
