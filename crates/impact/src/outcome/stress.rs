//! The beam's bending stress: its envelope over the beam and the window.
//!
//! Sign convention: the outer fibre of the struck face (the ball's side), tension positive:
//! sigma = E (h/2) w'' with w positive away from the ball, so a cantilever pushed at its tip
//! is in tension on the struck face at its clamp, and a pinned beam pushed at mid-span in
//! compression there under the ball.

use serde::{Deserialize, Serialize};

/// The largest bending stress of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BendingStress {
    /// The largest magnitude of the outer-fibre stress over the beam and the window (Pa).
    pub max: f64,
    /// Its value with its sign, tension positive on the struck face (Pa).
    pub value: f64,
    /// Where along the beam (m, from the end at x = 0).
    pub position: f64,
    /// When (s).
    pub time: f64,
    /// Whether it sits at the window's end: the stress was still growing, so it is not yet
    /// the run's maximum (a longer `solver.end_time` would find a larger one).
    pub at_window_end: bool,
    /// The largest magnitude at each support (a pinned end reports its zero).
    pub supports: Vec<SupportStress>,
    /// `max` over `beam.yield_stress`; null without a yield stress.
    pub yield_ratio: Option<f64>,
}

/// The largest bending stress at one support.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SupportStress {
    /// Where (m).
    pub position: f64,
    /// The largest magnitude there (Pa).
    pub max: f64,
    /// When (s).
    pub time: f64,
}

/// The running maximum of the stress at a fixed set of points, fed at each recorded instant.
#[derive(Debug, Clone)]
pub(crate) struct Envelope {
    /// The points (m).
    pub(crate) points: Vec<f64>,
    /// The indices of the supports among the points, with each one's (largest magnitude,
    /// time).
    supports: Vec<(usize, f64, f64)>,
    /// (|sigma|, sigma, point, time) of the largest so far.
    best: (f64, f64, usize, f64),
    last_time: f64,
}

impl Envelope {
    /// An envelope over `points`, of which those at `supports` (positions, m) are supports.
    pub(crate) fn new(points: Vec<f64>, supports: &[f64]) -> Self {
        let supports = supports
            .iter()
            .filter_map(|s| {
                points.iter().position(|p| p.to_bits() == s.to_bits()).map(|i| (i, 0.0, 0.0))
            })
            .collect();
        Self { points, supports, best: (0.0, 0.0, 0, 0.0), last_time: 0.0 }
    }

    /// Takes the stresses (Pa) at the points at time `t` (s); whether the largest grew.
    pub(crate) fn observe(&mut self, t: f64, stresses: &[f64]) -> bool {
        self.last_time = t;
        for s in &mut self.supports {
            let v = stresses[s.0].abs();
            if v > s.1 {
                (s.1, s.2) = (v, t);
            }
        }
        // The largest magnitude first, in a loop without branches (vectorised); the point only
        // when it beats the best so far (seldom once the first impact has passed). NaNs are
        // never taken (as before).
        let largest = hht::fast::largest_magnitude(stresses);
        if largest <= self.best.0 {
            return false;
        }
        for (i, sigma) in stresses.iter().enumerate() {
            if sigma.abs() > self.best.0 {
                self.best = (sigma.abs(), *sigma, i, t);
            }
        }
        true
    }

    /// The largest so far: (signed stress (Pa), position (m), time (s)).
    pub(crate) fn best(&self) -> (f64, f64, f64) {
        (self.best.1, self.points.get(self.best.2).copied().unwrap_or(0.0), self.best.3)
    }

    /// Each support's (point index, largest magnitude (Pa), time (s)).
    pub(crate) fn supports(&self) -> &[(usize, f64, f64)] {
        &self.supports
    }

    /// Raises support `k`'s largest magnitude to `max` (Pa) at `time` (s), where a search
    /// between instants found more.
    pub(crate) fn raise_support(&mut self, k: usize, max: f64, time: f64) {
        if let Some(s) = self.supports.get_mut(k).filter(|s| max > s.1) {
            (s.1, s.2) = (max, time);
        }
    }

    /// The report's stress, the largest moved to `refined` (position (m), signed stress (Pa),
    /// time (s)) when a search between the points and instants found more; `at_window_end`
    /// when it was found at the last instant observed.
    pub(crate) fn finish(
        &self,
        refined: Option<(f64, f64, f64)>,
        yield_stress: Option<f64>,
    ) -> BendingStress {
        let (mut max, mut value, point, mut time) = self.best;
        let mut position = self.points.get(point).copied().unwrap_or(0.0);
        if let Some((x, sigma, t)) = refined.filter(|r| r.1.abs() > max) {
            (max, value, position, time) = (sigma.abs(), sigma, x, t);
        }
        BendingStress {
            max,
            value,
            position,
            time,
            at_window_end: max > 0.0 && time >= self.last_time,
            supports: self
                .supports
                .iter()
                .map(|&(i, max, time)| SupportStress { position: self.points[i], max, time })
                .collect(),
            yield_ratio: yield_stress.map(|y| max / y),
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::float_cmp)]
    use super::*;

    #[test]
    fn the_envelope_keeps_the_largest_magnitude_its_place_and_time_and_each_supports() {
        let mut e = Envelope::new(vec![0.0, 0.5, 1.0], &[0.0, 1.0]);
        e.observe(0.0, &[0.0, 0.0, 0.0]);
        e.observe(1.0, &[3.0, -5.0, 0.0]);
        e.observe(2.0, &[-4.0, 1.0, 0.0]);
        let s = e.finish(None, Some(10.0));
        assert_eq!((s.max, s.value, s.position, s.time), (5.0, -5.0, 0.5, 1.0));
        assert!(!s.at_window_end);
        assert_eq!(s.yield_ratio, Some(0.5));
        assert_eq!(s.supports[0], SupportStress { position: 0.0, max: 4.0, time: 2.0 });
        assert_eq!(s.supports[1].max, 0.0);
        // Still growing at the last instant: flagged.
        e.observe(3.0, &[0.0, 6.0, 0.0]);
        assert!(e.finish(None, None).at_window_end);
        // A refinement that finds more moves it.
        let r = e.finish(Some((0.55, 6.5, 2.9)), None);
        assert_eq!((r.max, r.position, r.time), (6.5, 0.55, 2.9));
    }
}
