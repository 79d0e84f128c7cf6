//! The modal method's bending stress, by the mode-acceleration form.
//!
//! The plain series w''(x) = sum_n phi_n''(x) q_n / sqrt(M) converges slowly under a point
//! force (the static moment's kink at the load needs every mode; the tail falls as 1/n^2).
//! The mode-acceleration form (the static correction of the residual flexibility,
//! validation/REFERENCES.md 1.4) adds what the truncated modes hold quasi-statically:
//!
//! w''(x, t) = F(t) [s(x; c) - sum_n c_n(x) g_n / omega_n^2] + sum_n c_n(x) q_n(t),
//!
//! with s the static curvature under a unit force at the impact point c
//! ([`modal::Beam::static_curvature`], the beam tables), c_n = phi_n''/sqrt(M) and
//! g_n = phi_n(c)/sqrt(M). A free-free beam has no static solution: it keeps the plain series
//! (as does a scene with `solver.plain_stress_series`).
//! The stress on the struck face is sigma = E (h/2) w''.
//!
//! Where a maximum can occur: at the supports, under the ball, in the bending waves that
//! leave the ball during a contact (within a few centimetres of it on the paper's beam), and
//! anywhere the waves meet later. The envelope is evaluated at every recorded instant of the
//! run (about 200 per contact and one per output interval in free flight) near the ball
//! (the impact point and points L/2^k away on each side, k = 4..9) and at the supports, and
//! at every [`GLOBAL_EVERY`]-th instant on [`GRID`] equal intervals of the beam; after the
//! run the largest is searched again between its point's neighbours at its instant ([`REFINE`]
//! intervals, then golden-section search around the best). The hot loop is compiled for the
//! processor's widest vectors (pulp) with fused multiply-adds, so the stress's last bits may
//! differ between processors (the motion, which it does not feed, does not).

use super::observe::{BeamRecorder, BeamView, Instant};
use crate::outcome::{BendingStress, Envelope, Field};
use crate::plan::FIELD_POINTS;
use modal::{Beam, Mode, Support};

/// Equal intervals of the beam whose ends are candidates of the largest stress.
pub(crate) const GRID: usize = 32;
/// The beam-wide grid is observed at every this many recorded instants.
pub(crate) const GLOBAL_EVERY: usize = 8;
/// Points near the ball: L/2^k away on each side for k in this range.
const NEAR_LEVELS: std::ops::RangeInclusive<i32> = 4..=9;
/// Intervals of the final search's coarse look between the best candidate's neighbours.
pub(crate) const REFINE: usize = 8;
/// Golden-section steps of the final search (its bracket, two of the coarse look's intervals,
/// shrinks 0.618 a step: to 1e-3 of it, some microns on the paper's beam).
const GOLDEN_STEPS: usize = 14;

/// The modal beam seen as a stress field.
pub(crate) struct ModalStress {
    shapes: Vec<Mode>,
    /// 1/sqrt(M) (1/sqrt(kg)).
    scale: f64,
    /// Stress per unit curvature on the struck face, E h/2 (Pa m).
    section: f64,
    /// EI (N m^2).
    ei: f64,
    /// Impact point (m).
    position: f64,
    length: f64,
    /// The beam for its static curvature; `None` keeps the plain series.
    beam: Option<Beam>,
    /// g_n / omega_n^2 (0 for a rigid mode) (m/N per sqrt(kg)).
    static_q: Vec<f64>,
    /// c_n(x_p), point-major: curvature[p * N + n] (1/m^2 per sqrt(kg)).
    curvature: Vec<f64>,
    /// s(x_p) - sum_n c_n(x_p) g_n / omega_n^2 (1/m^2 per N).
    correction: Vec<f64>,
    stresses: Vec<f64>,
    /// How many points (the first) are observed at every instant.
    near_count: usize,
    /// Recorded instants seen so far.
    instants: usize,
    envelope: Envelope,
    /// The modal coordinates and force at the largest stress so far.
    best: Option<(Vec<f64>, f64)>,
    /// The field, when asked: its points' phi_n/sqrt(M), phi_n'/sqrt(M), c_n (point-major)
    /// and corrections, and what it recorded.
    field: Option<FieldRecorder>,
}

/// The field's precomputed rows.
struct FieldRecorder {
    value: Vec<f64>,
    slope: Vec<f64>,
    curvature: Vec<f64>,
    correction: Vec<f64>,
    field: Field,
}

impl ModalStress {
    /// The stress field of `shapes` of `beam` struck at `position`, of section `width` x
    /// `thickness` (m); by the plain series when `plain`.
    pub(crate) fn new(
        beam: &Beam,
        shapes: Vec<Mode>,
        position: f64,
        thickness: f64,
        width: f64,
        plain: bool,
    ) -> Self {
        let length = beam.length();
        let scale = 1.0 / beam.mass().sqrt();
        let inertia = width * thickness.powi(3) / 12.0;
        let section = beam.flexural_rigidity() * 0.5 * thickness / inertia;
        let supports: &[f64] = match beam.support() {
            Support::ClampedFree => &[0.0],
            Support::FreeFree => &[],
            _ => &[0.0, length],
        };
        // The near set first (observed at every instant), then the rest of the grid.
        let mut near: Vec<f64> = supports.to_vec();
        near.push(position);
        for k in NEAR_LEVELS {
            let d = length / f64::powi(2.0, k);
            near.extend(
                [position - d, position + d].into_iter().filter(|x| (0.0..=length).contains(x)),
            );
        }
        // The grid's points not already near, each with its number k on the grid.
        let grid: Vec<(usize, f64)> = (0..=GRID)
            .map(|k| (k, length * k as f64 / GRID as f64))
            .filter(|(_, x)| !near.contains(x))
            .collect();
        let near_count = near.len();
        let points: Vec<f64> = near.iter().copied().chain(grid.iter().map(|g| g.1)).collect();
        // The plain series: no static part, so no correction (as for a free-free beam).
        let static_beam = beam.static_curvature(position, 0.0).filter(|_| !plain).map(|_| *beam);
        let static_q: Vec<f64> = shapes
            .iter()
            .map(|m| {
                if m.omega > 0.0 && static_beam.is_some() {
                    m.shape.value(position) * scale / (m.omega * m.omega)
                } else {
                    0.0
                }
            })
            .collect();
        let p = points.len();
        let modes = shapes.len();
        let mut curvature = vec![0.0; modes * p];
        for (n, m) in shapes.iter().enumerate() {
            for (k, x) in near.iter().enumerate() {
                curvature[k * modes + n] = m.shape.curvature(*x) * scale;
            }
            // The grid's curvatures carried from point to point: a fifth of the cost.
            let on_grid = m.shape.curvatures_on_grid(0.0, length / GRID as f64, GRID + 1);
            for (i, (k, _)) in grid.iter().enumerate() {
                curvature[(near_count + i) * modes + n] = on_grid[*k] * scale;
            }
        }
        let correction = points
            .iter()
            .enumerate()
            .map(|(k, x)| match &static_beam {
                Some(b) => {
                    let kept: f64 =
                        (0..modes).map(|n| curvature[k * modes + n] * static_q[n]).sum();
                    b.static_curvature(position, *x).unwrap_or(0.0) - kept
                }
                None => 0.0,
            })
            .collect();
        Self {
            shapes,
            scale,
            section,
            ei: beam.flexural_rigidity(),
            position,
            length,
            beam: static_beam,
            static_q,
            curvature,
            correction,
            stresses: vec![0.0; p],
            near_count,
            instants: 0,
            envelope: Envelope::new(points, supports),
            best: None,
            field: None,
        }
    }

    /// Records the field at every observed instant, at the ends of [`FIELD_POINTS`] equal
    /// intervals and the impact point: the displacement and slope by the modal series
    /// (converging as n^-4 and n^-3: the truncated modes' quasi-static share, which the
    /// residual flexibility adds at the impact point, is left out along the beam), the moment
    /// and stress by the same form as the envelope.
    pub(crate) fn record_field(&mut self) {
        let mut points: Vec<f64> = (0..=FIELD_POINTS)
            .map(|k| self.length * k as f64 / FIELD_POINTS as f64)
            .chain([self.position])
            .collect();
        points.sort_by(f64::total_cmp);
        points.dedup();
        let n = self.shapes.len();
        let (shapes, scale) = (&self.shapes, self.scale);
        let row = |f: &dyn Fn(&Mode, f64) -> f64| -> Vec<f64> {
            let mut out = Vec::with_capacity(points.len() * n);
            for x in &points {
                out.extend(shapes.iter().map(|m| f(m, *x) * scale));
            }
            out
        };
        let value = row(&|m, x| m.shape.value(x));
        let slope = row(&|m, x| m.shape.slope(x));
        let curvature = row(&|m, x| m.shape.curvature(x));
        let correction = points
            .iter()
            .enumerate()
            .map(|(k, x)| match &self.beam {
                Some(b) => {
                    let kept: f64 = (0..n).map(|i| curvature[k * n + i] * self.static_q[i]).sum();
                    b.static_curvature(self.position, *x).unwrap_or(0.0) - kept
                }
                None => 0.0,
            })
            .collect();
        self.field =
            Some(FieldRecorder { value, slope, curvature, correction, field: Field::new(points) });
    }

    /// The recorded field, if any.
    fn take_recorded_field(&mut self) -> Option<Field> {
        self.field.take().map(|f| f.field)
    }

    /// Observes the beam at time `t` (s) with modal coordinates `q` under the force `force`;
    /// `last` for the run's final instant (the whole grid is observed then).
    pub(crate) fn observe_modes(&mut self, t: f64, q: &[f64], force: f64, last: bool) {
        let all = last || self.instants % GLOBAL_EVERY == 0;
        self.instants += 1;
        let used = if all { self.stresses.len() } else { self.near_count };
        pulp::Arch::new().dispatch(StressKernel {
            stresses: &mut self.stresses[..used],
            correction: &self.correction[..used],
            curvature: &self.curvature,
            q,
            force,
            section: self.section,
        });
        if let Some(f) = &mut self.field {
            let dot = |rows: &[f64], k: usize| -> f64 {
                rows[k * q.len()..(k + 1) * q.len()].iter().zip(q).map(|(a, b)| a * b).sum()
            };
            let ei_over_section = self.ei;
            f.field.push_instant(t);
            for k in 0..f.field.points.len() {
                f.field.displacement.push(dot(&f.value, k));
                f.field.slope.push(dot(&f.slope, k));
                let curvature = dot(&f.curvature, k) + force * f.correction[k];
                f.field.moment.push(ei_over_section * curvature);
                f.field.stress.push(self.section * curvature);
            }
        }
        if self.envelope.observe(t, &self.stresses[..used]) {
            match &mut self.best {
                Some((best_q, best_force)) => {
                    best_q.copy_from_slice(q);
                    *best_force = force;
                }
                None => self.best = Some((q.to_vec(), force)),
            }
        }
    }

    /// The stress (Pa) at `x` for the state `q`, `force`, by the same form.
    fn stress_at(&self, x: f64, q: &[f64], force: f64) -> f64 {
        let mut curvature = 0.0;
        let mut kept = 0.0;
        for ((m, qn), sq) in self.shapes.iter().zip(q).zip(&self.static_q) {
            let c = m.shape.curvature(x) * self.scale;
            curvature += c * qn;
            kept += c * sq;
        }
        let correction = match &self.beam {
            Some(b) => b.static_curvature(self.position, x).unwrap_or(0.0) - kept,
            None => 0.0,
        };
        self.section * (curvature + force * correction)
    }

    /// The envelope, its largest searched again around its point at its instant.
    pub(crate) fn envelope(&self, yield_stress: Option<f64>) -> BendingStress {
        let refined = self.best.as_ref().map(|(q, force)| {
            let (point, _) = self.envelope.best_point();
            let points = &self.envelope.points;
            let centre = points[point];
            // Between the nearest candidates on either side.
            let below = points.iter().filter(|x| **x < centre).fold(0.0, |a: f64, x| a.max(*x));
            let above =
                points.iter().filter(|x| **x > centre).fold(self.length, |a: f64, x| a.min(*x));
            // A coarse look between the neighbours, then golden-section search around its best
            // (the stress between two candidates has one extremum there in practice).
            let at = |x: f64| (x, self.stress_at(x, q, *force));
            let step = (above - below) / REFINE as f64;
            let coarse: Vec<(f64, f64)> =
                (0..=REFINE).map(|k| at(below + step * k as f64)).collect();
            let k = (0..coarse.len())
                .max_by(|a, b| coarse[*a].1.abs().total_cmp(&coarse[*b].1.abs()))
                .unwrap_or(0);
            // Golden-section search for the largest magnitude, one new point a step.
            let golden = 0.5 * (5f64.sqrt() - 1.0);
            let (mut lo, mut hi) =
                ((coarse[k].0 - step).max(below), (coarse[k].0 + step).min(above));
            let mut best = coarse[k];
            let mut a = at(hi - golden * (hi - lo));
            let mut b = at(lo + golden * (hi - lo));
            for _ in 0..GOLDEN_STEPS {
                for c in [a, b] {
                    if c.1.abs() > best.1.abs() {
                        best = c;
                    }
                }
                if a.1.abs() > b.1.abs() {
                    hi = b.0;
                    b = a;
                    a = at(hi - golden * (hi - lo));
                } else {
                    lo = a.0;
                    a = b;
                    b = at(lo + golden * (hi - lo));
                }
            }
            for c in [a, b] {
                if c.1.abs() > best.1.abs() {
                    best = c;
                }
            }
            if best.1.abs() > 0.0 {
                best
            } else {
                (centre, 0.0)
            }
        });
        self.envelope.finish(refined, yield_stress)
    }
}

impl BeamRecorder for ModalStress {
    fn observe(&mut self, at: &Instant<'_>) {
        if let BeamView::Modal { q, force } = at.beam {
            self.observe_modes(at.t, q, force, at.last);
        }
    }

    fn finish(&self, yield_stress: Option<f64>) -> BendingStress {
        self.envelope(yield_stress)
    }

    fn take_field(&mut self) -> Option<Field> {
        self.take_recorded_field()
    }
}

/// sigma_p = E h/2 (F correction_p + sum_n c_n(x_p) q_n) for the points of `stresses`: a dot
/// product a point in the widest vectors pulp finds at run time, fused multiply-adds, four
/// points at a time.
struct StressKernel<'a> {
    stresses: &'a mut [f64],
    correction: &'a [f64],
    /// Point-major, one row of `q.len()` a point.
    curvature: &'a [f64],
    q: &'a [f64],
    force: f64,
    section: f64,
}

impl pulp::WithSimd for StressKernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        let Self { stresses, correction, curvature, q, force, section } = self;
        let n = q.len();
        let (q_head, q_tail) = S::as_simd_f64s(q);
        let lanes = |v: S::f64s| -> f64 {
            let l: &[f64] = pulp::bytemuck::cast_slice(std::slice::from_ref(&v));
            l.iter().sum()
        };
        let tail_dot = |row: &[f64]| -> f64 {
            row[n - q_tail.len()..].iter().zip(q_tail).map(|(a, b)| a * b).sum()
        };
        let used = stresses.len();
        let rows = &curvature[..used * n];
        // Four points at a time share each load of q (register blocking), then the rest one
        // by one; each point's sum has a fixed order, so the result does not depend on which.
        let blocks = used / 4;
        for (block, out) in rows.chunks_exact(4 * n).zip(stresses.chunks_exact_mut(4)) {
            let heads: [&[S::f64s]; 4] =
                std::array::from_fn(|j| S::as_simd_f64s(&block[j * n..(j + 1) * n]).0);
            let mut acc = [simd.splat_f64s(0.0); 4];
            for (k, qk) in q_head.iter().enumerate() {
                for j in 0..4 {
                    acc[j] = simd.mul_add_f64s(heads[j][k], *qk, acc[j]);
                }
            }
            for j in 0..4 {
                out[j] = lanes(acc[j]) + tail_dot(&block[j * n..(j + 1) * n]);
            }
        }
        for (row, out) in rows[4 * blocks * n..].chunks_exact(n).zip(&mut stresses[4 * blocks..]) {
            let head = S::as_simd_f64s(row).0;
            let mut acc = simd.splat_f64s(0.0);
            for (a, qk) in head.iter().zip(q_head) {
                acc = simd.mul_add_f64s(*a, *qk, acc);
            }
            *out = lanes(acc) + tail_dot(row);
        }
        for (s, c) in stresses.iter_mut().zip(correction) {
            *s = section * (force * c + *s);
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// The paper's beam (steel, 25 x 5 mm, L = 1.15 m) with `support`.
    fn beam(support: Support) -> Beam {
        Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, support).unwrap()
    }

    #[test]
    fn a_static_force_gives_the_beam_tables_moment_at_every_point_with_few_modes() {
        // The modes held at their static values q_n = g_n F / omega_n^2 under F = 10 N at
        // c: the mode-acceleration form returns E h/2 s(x) F exactly (the kept modes' part
        // cancels against the correction), with 8 modes as with 800; the plain series with
        // 8 modes is far off near the load.
        for support in [Support::ClampedFree, Support::PinnedPinned, Support::ClampedPinned] {
            let b = beam(support);
            let (c, force) = (0.8, 10.0);
            let shapes = b.modes(8).unwrap();
            let q: Vec<f64> = shapes
                .iter()
                .map(|m| m.shape.value(c) / b.mass().sqrt() * force / (m.omega * m.omega))
                .collect();
            let mut s = ModalStress::new(&b, shapes, c, 0.005, 0.025, false);
            let section = 2.1e11 * 0.0025;
            for k in 0..=46 {
                let x = 1.15 * k as f64 / 46.0;
                let exact = section * b.static_curvature(c, x).unwrap() * force;
                let got = s.stress_at(x, &q, force);
                assert!(
                    (got - exact).abs() <= 1e-9 * section * force,
                    "{support:?} x = {x}: {got} vs {exact}"
                );
            }
            // At the load the plain 8-mode series misses a good part of the moment.
            let plain: f64 =
                s.shapes.iter().zip(&q).map(|(m, qn)| m.shape.curvature(c) * s.scale * qn).sum();
            let exact = b.static_curvature(c, c).unwrap();
            assert!((plain - exact).abs() > 1e-2 * exact.abs(), "{support:?}: {plain} vs {exact}");
            // The envelope of one observation: the static moment's largest, where the tables
            // put it (the clamp of a cantilever, the load on a pinned beam).
            s.observe_modes(0.0, &q, force, true);
            let e = s.envelope(None);
            let tables = (0..=1150)
                .map(|k| b.static_curvature(c, k as f64 / 1000.0).unwrap().abs())
                .fold(0.0, f64::max)
                * section
                * force;
            assert!((e.max - tables).abs() < 1e-6 * tables, "{support:?}: {} vs {tables}", e.max);
        }
    }

    #[test]
    fn the_candidates_hold_the_supports_the_impact_point_and_the_grid() {
        let b = beam(Support::ClampedClamped);
        let s = ModalStress::new(&b, b.modes(4).unwrap(), 0.3, 0.005, 0.025, false);
        let points = &s.envelope.points;
        for x in [0.0, 1.15, 0.3, 0.3 + 1.15 / 16.0, 0.3 - 1.15 / 512.0, 1.15 / 32.0] {
            assert!(points.iter().any(|p| (p - x).abs() < 1e-12), "{x} missing");
        }
        assert_eq!(s.near_count, 2 + 1 + 12);
    }
}
