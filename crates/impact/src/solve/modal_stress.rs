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
//! anywhere the waves meet later. During the run, at instants about as far apart as the bound
//! of the stress's second time derivative allows for a quarter of the largest so far, the
//! stress is evaluated near the ball (the impact point and points L/2^k away on each side,
//! k = 4..9) and at the supports with every mode, and on a uniform grid of the beam
//! ([`GRID_PER_RADIAN`] points per radian of the bending wave the pulse excites most) with the
//! modes the last stretch chose: the largest of the values the field takes is a floor. Each
//! stretch between two such instants is certified on the spot when its bound (the grid's
//! largest at its ends plus what the second derivatives allow between grid points and
//! instants, `modal_peak`) cannot beat the floor; the others are kept with their start state
//! and searched by branch and bound, to within [`modal_peak::PEAK_TOLERANCE`] of the maximum:
//! the oldest in batches while the run goes on (`GridWatch::hand_over`), the rest at the end;
//! so are the displacement at the impact point and each support's stress (at the end). The
//! whole-grid instants and the search during the run are a [`GridWatch`]'s, on a thread of its
//! own beside the solver's where the process has one to spare (`Watch`); the solver sets each
//! next whole-grid instant by the watch's plan from [`PLAN_LAG`] instants before. The hot loop is compiled for the processor's
//! vectors (`modal::on_four_lanes`: four lanes on x86-64) with fused multiply-adds, so the
//! stress's last bits may differ between processors (and through the whole-grid instants,
//! where the free flight's steps end, the motion's too, at round-off's scale).

use super::modal_peak::{self, ModeData, ModePart, Peak, Row, StressField, Trajectory, Weights};
use super::observe::{BeamRecorder, BeamView, Instant};
use crate::outcome::{BendingStress, Envelope, Field};
use crate::plan::FIELD_POINTS;
use modal::{Beam, Curvatures, ModalState, Mode, PointModes, Support};
use rayon::prelude::*;
use std::sync::Arc;

/// Points of the uniform grid per radian of the bending wave the pulse excites most
/// (wavenumber beta_c with omega(beta_c) = pi / t_c): on the paper's tip 233 intervals, where
/// the grid's spacing leaves about a fifth of the largest stress to the bound between points.
/// Fewer points a grid against more grid instants (the time term takes what the space term
/// leaves): the paper's tip at 256 modes over 5 ms ran 10 % faster with 2 than with 3 (as did
/// paper-tip.toml and paper-midspan.toml; paper-tip-offset.toml 1 % slower), 6 % slower with
/// 1.75 and 2.5, 23 % with 1.5 (validation/REFERENCES.md 1.8).
const GRID_PER_RADIAN: f64 = 2.0;
/// The uniform grid's intervals at least and at most.
const GRID_RANGE: (usize, usize) = (32, 4096);
/// The share of the largest stress so far that the bound of the time between two grid
/// instants may take (a stretch whose grid stays below the rest is certified on the spot).
const TIME_SHARE: f64 = 0.25;
/// Newton steps at most when the largest stress is polished to its local maximum (it converges
/// quadratically from the search's tolerance: three or four suffice).
const POLISH_STEPS: usize = 8;
/// The share of the largest stress so far that a stretch's bound is planned to stay within
/// (the rest kept in hand for the grid's largest growing over the stretch): with 0.9 many
/// more stretches failed to be certified on the paper's tip over 5 ms (629 kept against 114;
/// a run 3 times slower), with 0.6 the run was 5 % faster than with a fixed TIME_SHARE.
const LEFT_SHARE: f64 = 0.6;
/// The share of the largest stress so far that the modes left out of the grid may take.
const TAIL_SHARE: f64 = 0.1;
/// The stretches handed to the stress's search during the run at a time, and how many
/// more must be kept after them first (so that the largest stress seen, which the search
/// starts from, has taken in the stretches around them: on the paper's tip the first
/// contact's stretches hold nearly all of the search's work, and the largest stress is seen
/// at 33 us, within them).
const EARLY_BATCH: usize = 16;
const EARLY_LAG: usize = 16;
/// Points near the ball: L/2^k away on each side for k in this range.
const NEAR_LEVELS: std::ops::RangeInclusive<i32> = 4..=9;

/// The modal beam seen as a stress field: on the solver's thread, what every recorded
/// instant needs (the field, the displacement and the one-point fields seen); the whole-grid
/// instants go to the [`GridWatch`], on a thread of its own where one is free.
pub(crate) struct ModalStress {
    shapes: Vec<Mode>,
    /// The stress row at any point (shared with the watch).
    rows: Arc<StressRows>,
    /// EI (N m^2).
    ei: f64,
    /// The modes' constants and what the bounds weigh them with (the watch's, copied and
    /// shared): the part of each stretch's bounds that the modes alone give is made here,
    /// while the watch observes the grid (`ModePart`).
    data: Arc<ModeData>,
    weights: Arc<Weights>,
    /// The open stretch: its start (t (s), F (N), the modes' state) and its force's pieces
    /// since ([`modal_peak::push_end`]).
    start: (f64, f64, ModalState),
    ends: Vec<(f64, f64)>,
    /// The near points' c_n and corrections (the watch's first rows, copied): their stress
    /// at the whole-grid instants is taken here, off the watch's thread, which has more to do.
    near_curvature: Vec<f64>,
    near_correction: Vec<f64>,
    /// What the run has seen: the displacement's largest (m) and when (s); each one-point
    /// field's largest magnitude and when, and its magnitude at the last instant.
    seen: Seen,
    /// The last instant the whole grid was observed (s), and how far apart such instants are
    /// set (s): the watch's plan from [`PLAN_LAG`] whole-grid instants before.
    last_full: f64,
    full_spacing: f64,
    watch: Watch,
    /// The field, when asked: its points' phi_n/sqrt(M), phi_n'/sqrt(M), c_n (point-major)
    /// and corrections, and what it recorded.
    field: Option<FieldRecorder>,
}

/// What the run has seen of the displacement at the impact point and of the one-point fields.
#[derive(Debug, Default)]
struct Seen {
    /// The largest displacement (m) and when (s).
    displacement: (f64, f64),
    /// Each one-point field's largest magnitude and when (s).
    points: Vec<(f64, f64)>,
    /// Their magnitudes at the last observed instant.
    values: Vec<f64>,
}

impl Clone for Seen {
    fn clone(&self) -> Self {
        let (points, values) = (self.points.clone(), self.values.clone());
        Self { displacement: self.displacement, points, values }
    }

    /// Into the buffers already held: copied at every whole-grid instant, twice.
    fn clone_from(&mut self, source: &Self) {
        self.displacement = source.displacement;
        self.points.clone_from(&source.points);
        self.values.clone_from(&source.values);
    }
}

/// A whole-grid instant as the watch takes it: the state, what the run has seen by then, the
/// steps' ends since the last one.
#[derive(Debug, Default)]
struct Snapshot {
    t: f64,
    force: f64,
    state: ModalState,
    /// The displacement at the impact point now (m).
    displacement: f64,
    /// The stress at the near points now, every mode (Pa).
    near: Vec<f64>,
    seen: Seen,
    /// The stretch's force pieces since the last whole-grid instant, and the part of its
    /// bounds the modes alone give.
    ends: Vec<(f64, f64)>,
    part: ModePart,
}

/// The whole-grid instants' work: the grid and the near points observed, each stretch between
/// two such instants certified or kept, the kept ones searched (the oldest as the run goes on,
/// between the instants, the rest at the end).
struct GridWatch {
    /// The stress row at any point.
    rows: Arc<StressRows>,
    /// c_n(x_p), point-major: curvature[p * N + n] (1/m^2 per sqrt(kg)).
    curvature: Vec<f64>,
    /// s(x_p) - sum_n c_n(x_p) g_n / omega_n^2 (1/m^2 per N).
    correction: Vec<f64>,
    stresses: Vec<f64>,
    /// How many points (the first) are observed with every mode (the near set).
    near_count: usize,
    /// How many modes (the first) the grid is observed with.
    low: usize,
    /// The uniform grid's spacing (m).
    spacing: f64,
    envelope: Envelope,
    /// The search between instants: the modes' constants, the kept stretches, the bounds'
    /// weights (max |E h/2 c_n| and max |E h/2 c_n''| over the beam, E h/2 max |correction|),
    /// the displacement's and the supports' rows.
    peaks: Peaks,
    /// The grid's stress rows and order, as the early search made them: kept when it is
    /// gathered, for the search at the end (made again, they had cost the end some 0.1 ms).
    grid_field: Option<(Vec<Row>, modal_peak::GridOrder)>,
}

/// What the search between instants keeps.
struct Peaks {
    /// The modes' constants (shared with the solver's thread and the early search).
    data: Arc<ModeData>,
    trajectory: Trajectory,
    /// What the bounds weigh the modes with; its `supports` are the one-point fields searched
    /// in time: each support's stress, then (an off-centre strike) those of `points`.
    weights: Arc<Weights>,
    /// The one-point fields after the supports' stresses: what, where and the search's result
    /// (the largest seen is in `seen`).
    points: Vec<PointSearch>,
    /// What the run had seen at the last whole-grid instant.
    seen: Seen,
    /// The stress's search of the stretches kept early in the run.
    early: Early,
    /// Stretches handed over that the stress's search does not want, kept for the others.
    held: Vec<modal_peak::Block>,
    /// Batches handed over, not searched yet, with the largest stress seen then.
    batches: std::collections::VecDeque<(Vec<modal_peak::Block>, Peak)>,
    /// The searches' results, once run: the stress's, the displacement's, each support's.
    stress_peak: Option<Peak>,
    displacement_peak: Option<Peak>,
    support_peaks: Vec<Peak>,
}

/// Which one-point field a [`PointSearch`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PointKind {
    /// The struck section's twist (rad).
    Twist,
    /// The Saint-Venant shear stress of torsion at a section (Pa), and which side of it.
    TorsionShear(&'static str),
}

/// A one-point field searched in time besides the supports' stresses.
struct PointSearch {
    kind: PointKind,
    /// Where (m).
    x: f64,
    /// The search's result.
    peak: Option<Peak>,
}

/// The largest torsion shear the run observed over the sections searched (Pa), from what it
/// has `seen` of each one-point field.
fn largest_shear_seen(points: &[PointSearch], seen: &[(f64, f64)]) -> f64 {
    points
        .iter()
        .zip(seen)
        .filter(|(p, _)| matches!(p.kind, PointKind::TorsionShear(_)))
        .map(|(_, s)| s.0)
        .fold(0.0, f64::max)
}

/// What the modal stress recovery needs besides the beam and its modes.
pub(crate) struct StressSetup {
    /// The impact point (m).
    pub(crate) position: f64,
    /// Section (m).
    pub(crate) thickness: f64,
    pub(crate) width: f64,
    /// By the plain series instead of the mode-acceleration form.
    pub(crate) plain: bool,
    /// The point modes the solver steps (their frequencies, damping, participations).
    pub(crate) modes: PointModes,
    /// The residual flexibility in series with the contact (m/N; 0 without).
    pub(crate) residual: f64,
    /// The contact's estimated duration (s): sets the grid's density.
    pub(crate) duration: f64,
    /// An off-centre strike: the struck section's twist (rad) as a row over the modes.
    pub(crate) twist: Option<Row>,
    /// An off-centre strike: the torsion shear stress (Pa) at sections (m) as rows over the
    /// modes (`solve/modal.rs::torsion_shear_rows`).
    pub(crate) torsion_shear: Vec<super::modal::Section>,
}

/// The field's precomputed rows.
struct FieldRecorder {
    value: Vec<f64>,
    slope: Vec<f64>,
    curvature: Vec<f64>,
    correction: Vec<f64>,
    /// The truncated modes' static deflection per unit force at each point (m/N), where the
    /// run takes the residual flexibility (empty otherwise).
    deflection: Vec<f64>,
    field: Field,
}

impl ModalStress {
    /// The stress field of `shapes` of `beam`, struck as `setup` says.
    pub(crate) fn new(beam: &Beam, shapes: Vec<Mode>, setup: StressSetup) -> Self {
        let StressSetup {
            position,
            thickness,
            width,
            plain,
            modes,
            residual,
            duration,
            twist,
            torsion_shear,
        } = setup;
        let length = beam.length();
        let scale = 1.0 / beam.mass().sqrt();
        let inertia = width * thickness.powi(3) / 12.0;
        let section = beam.flexural_rigidity() * 0.5 * thickness / inertia;
        let supports: &[f64] = match beam.support() {
            Support::ClampedFree => &[0.0],
            Support::FreeFree => &[],
            _ => &[0.0, length],
        };
        // The near set first (observed with every mode), then the rest of the grid.
        let mut near: Vec<f64> = supports.to_vec();
        near.push(position);
        for k in NEAR_LEVELS {
            let d = length / f64::powi(2.0, k);
            near.extend(
                [position - d, position + d].into_iter().filter(|x| (0.0..=length).contains(x)),
            );
        }
        // The uniform grid: beta_c from EI beta^4 = rho A omega^2 at omega = pi / t_c.
        let beta_c = (std::f64::consts::PI / duration).sqrt()
            * (beam.mass_per_length() / beam.flexural_rigidity()).powf(0.25);
        let intervals =
            ((length * beta_c * GRID_PER_RADIAN).ceil() as usize).clamp(GRID_RANGE.0, GRID_RANGE.1);
        let spacing = length / intervals as f64;
        // The grid's points not already near, each with its number k on the grid.
        let grid: Vec<(usize, f64)> = (0..=intervals)
            .map(|k| (k, length * k as f64 / intervals as f64))
            .filter(|(_, x)| !near.contains(x))
            .collect();
        let near_count = near.len();
        let points: Vec<f64> = near.iter().copied().chain(grid.iter().map(|g| g.1)).collect();
        // The plain series, as asked: no static part, so no correction.
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
        let n = shapes.len();
        let mut curvature = vec![0.0; n * p];
        let curvatures = Curvatures::new(shapes.iter().map(|m| &m.shape));
        for (k, x) in near.iter().enumerate() {
            let row = &mut curvature[k * n..(k + 1) * n];
            curvatures.at(*x, &mut [&mut *row]);
            row.iter_mut().for_each(|c| *c *= scale);
        }
        // The grid's curvatures carried from point to point (a fifth of the cost), each mode's
        // on its own (side by side where threads are free: 0.5 of the 12 ms of the paper's tip).
        let on_grids: Vec<Vec<f64>> = shapes
            .par_iter()
            .map(|m| m.shape.curvatures_on_grid(0.0, spacing, intervals + 1))
            .collect();
        // Into the point-major rows, eight modes at a time (a cache line of each row per point:
        // mode by mode, every write had gone to another row, 0.15 of the 0.6 ms here).
        for (block, on_grids) in on_grids.chunks(8).enumerate() {
            for (j, (k, _)) in grid.iter().enumerate() {
                let row = (near_count + j) * n + 8 * block;
                for (to, on_grid) in curvature[row..row + on_grids.len()].iter_mut().zip(on_grids) {
                    *to = on_grid[*k] * scale;
                }
            }
        }
        let correct = |k: usize, x: f64| match &static_beam {
            Some(b) => {
                let kept: f64 = (0..n).map(|i| curvature[k * n + i] * static_q[i]).sum();
                b.static_curvature(position, x).unwrap_or(0.0) - kept
            }
            None => 0.0,
        };
        let correction: Vec<f64> = points.iter().enumerate().map(|(k, x)| correct(k, *x)).collect();
        let peaks = Peaks::new(
            &shapes,
            (scale, section),
            static_beam.as_ref(),
            &static_q,
            PeakSetup {
                modes,
                residual,
                spacing,
                corrections: &correction,
                supports: (0..supports.len())
                    .map(|k| Row {
                        r: curvature[k * n..(k + 1) * n].iter().map(|c| c * section).collect(),
                        p: correction[k] * section,
                    })
                    .collect(),
                points: twist
                    .map(|row| (PointKind::Twist, position, row))
                    .into_iter()
                    .chain(
                        torsion_shear
                            .into_iter()
                            .map(|(x, which, r)| (PointKind::TorsionShear(which), x, r)),
                    )
                    .collect(),
            },
        );
        let rows = Arc::new(StressRows {
            curvatures,
            scale,
            section,
            position,
            length,
            beam: static_beam,
            static_q,
        });
        let seen = peaks.seen.clone();
        let near_curvature = curvature[..near_count * n].to_vec();
        let near_correction = correction[..near_count].to_vec();
        let watch = GridWatch {
            rows: Arc::clone(&rows),
            curvature,
            correction,
            stresses: vec![0.0; p],
            near_count,
            low: n,
            spacing,
            envelope: Envelope::new(points, supports),
            peaks,
            grid_field: None,
        };
        Self {
            rows,
            shapes,
            ei: beam.flexural_rigidity(),
            data: Arc::clone(&watch.peaks.data),
            weights: Arc::clone(&watch.peaks.weights),
            start: (0.0, 0.0, ModalState::at_rest(n)),
            ends: Vec::new(),
            near_curvature,
            near_correction,
            seen,
            last_full: f64::NEG_INFINITY,
            full_spacing: 0.0,
            watch: Watch::start(watch),
            field: None,
        }
    }

    /// Records the field at every observed instant, at the ends of [`FIELD_POINTS`] equal
    /// intervals and the impact point: the displacement and slope by the modal series
    /// (converging as n^-4 and n^-3), with the truncated modes' static deflection added to the
    /// displacement where the run takes the residual flexibility (`residual`, m/N; the history's
    /// displacement at the ball has it, and the field had not: 1 mm from a clamp, where the
    /// plan takes it, they had differed by 86 %), the moment and stress by the same form as
    /// the envelope.
    pub(crate) fn record_field(&mut self, residual: f64) {
        let mut points: Vec<f64> = (0..=FIELD_POINTS)
            .map(|k| self.rows.length * k as f64 / FIELD_POINTS as f64)
            .chain([self.rows.position])
            .collect();
        points.sort_by(f64::total_cmp);
        points.dedup();
        let n = self.shapes.len();
        let (shapes, scale) = (&self.shapes, self.rows.scale);
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
            .map(|(k, x)| match &self.rows.beam {
                Some(b) => {
                    let kept: f64 =
                        (0..n).map(|i| curvature[k * n + i] * self.rows.static_q[i]).sum();
                    b.static_curvature(self.rows.position, *x).unwrap_or(0.0) - kept
                }
                None => 0.0,
            })
            .collect();
        let deflection = match &self.rows.beam {
            Some(b) if residual > 0.0 => points
                .iter()
                .enumerate()
                .map(|(k, x)| {
                    let kept: f64 = (0..n).map(|i| value[k * n + i] * self.rows.static_q[i]).sum();
                    b.static_deflection(self.rows.position, *x).map_or(0.0, |w| w - kept)
                })
                .collect(),
            _ => Vec::new(),
        };
        self.field = Some(FieldRecorder {
            value,
            slope,
            curvature,
            correction,
            deflection,
            field: Field::new(points),
        });
    }

    /// The recorded field, if any.
    fn take_recorded_field(&mut self) -> Option<Field> {
        self.field.take().map(|f| f.field)
    }

    /// Observes the beam at time `t` (s) with modal coordinates `q`, rates `v`, under the
    /// force `force`; `sampled` at a recorded instant (the field is recorded then), `last` at
    /// the run's final one (the whole grid is observed then).
    pub(crate) fn observe_modes(
        &mut self,
        t: f64,
        (q, v): (&[f64], &[f64]),
        force: f64,
        (sampled, last): (bool, bool),
    ) {
        if let Some(f) = self.field.as_mut().filter(|_| sampled) {
            let dot = |rows: &[f64], k: usize| -> f64 {
                rows[k * q.len()..(k + 1) * q.len()].iter().zip(q).map(|(a, b)| a * b).sum()
            };
            let ei_over_section = self.ei;
            f.field.push_instant(t);
            for k in 0..f.field.points.len() {
                let residual = f.deflection.get(k).map_or(0.0, |d| force * d);
                f.field.displacement.push(dot(&f.value, k) + residual);
                f.field.slope.push(dot(&f.slope, k));
                let curvature = dot(&f.curvature, k) + force * f.correction[k];
                f.field.moment.push(ei_over_section * curvature);
                f.field.stress.push(self.rows.section * curvature);
            }
        }
        let w = self.weights.displacement.value(force, q);
        let seen = &mut self.seen;
        if w > seen.displacement.0 {
            seen.displacement = (w, t);
        }
        let point_rows = &self.weights.supports[self.weights.support_count..];
        for ((p, value), row) in seen.points.iter_mut().zip(&mut seen.values).zip(point_rows) {
            *value = row.value(force, q).abs();
            if *value > p.0 {
                *p = (*value, t);
            }
        }
        if !(last || t - self.last_full >= self.full_spacing) {
            return;
        }
        // A whole-grid instant: to the watch, with the steps since the last; the next one is
        // where the watch's plan of PLAN_LAG such instants before sets it (so that the solver
        // seldom waits for the watch on its own thread).
        let mut snapshot = self.watch.spare();
        snapshot.t = t;
        snapshot.force = force;
        modal_peak::copy_state(&mut snapshot.state, q, v);
        snapshot.displacement = w;
        snapshot.near.resize(self.near_correction.len(), 0.0);
        modal::on_four_lanes(StressKernel {
            stresses: &mut snapshot.near,
            correction: &self.near_correction,
            curvature: &self.near_curvature,
            stride: q.len(),
            q,
            force,
            section: self.rows.section,
        });
        snapshot.seen.clone_from(&self.seen);
        // The stretch's part from the modes alone, where the watch closes it: after a start
        // and some steps (as `Trajectory::observe` bounds it).
        let (t0, f0, state) = &self.start;
        if t > *t0 && !self.ends.is_empty() {
            snapshot.part.make(&self.data, &self.weights, (*t0, *f0, state), &self.ends);
        } else {
            snapshot.part.clear();
        }
        std::mem::swap(&mut snapshot.ends, &mut self.ends);
        self.ends.clear();
        self.start.0 = t;
        self.start.1 = force;
        modal_peak::copy_state(&mut self.start.2, q, v);
        self.last_full = t;
        self.full_spacing = self.watch.observe(snapshot);
    }
}

impl GridWatch {
    /// A whole-grid instant: the near points with every mode, the grid with the modes the
    /// last stretch chose, the stretch since the last such instant certified or kept (the
    /// oldest kept handed to the search in a batch); returns how far away the next such
    /// instant is planned (s).
    fn observe(&mut self, at: &Snapshot) -> f64 {
        let Snapshot {
            t,
            force,
            state: ModalState { ref q, ref v },
            displacement: w,
            ref near,
            ref seen,
            ref ends,
            ref part,
        } = *at;
        let n = q.len();
        for &(t, force) in ends {
            self.peaks.trajectory.step(t, force);
        }
        self.peaks.seen.clone_from(seen);
        // The near points with every mode (taken on the solver's thread), at the whole-grid
        // instants: values the field takes (the floor that certifies stretches, each
        // support's stress at the stretches' ends). At every recorded instant they had cost
        // 6 % of the paper's tip run and raised the floor too little to certify more stretches
        // (kept 192 against 186; the largest stress and every support's are searched to their
        // tolerance either way).
        self.stresses[..self.near_count].copy_from_slice(near);
        self.envelope.observe(t, &self.stresses[..self.near_count]);
        // The stretch's field values at this end, all modes (the supports are among the near
        // points, evaluated above), before the grid's evaluation overwrites them.
        let supports = self.peaks.weights.support_count;
        let values: Vec<f64> = [w]
            .into_iter()
            .chain(self.stresses[..supports].iter().copied())
            .chain(seen.values.iter().copied())
            .collect();
        // The grid with the modes the last stretch chose (with all of them, its values are
        // the field's), then the stretch since the last such instant, certified or kept for
        // the search.
        let low = self.low.min(n);
        self.evaluate(self.stresses.len(), low, q, force);
        if low == n {
            self.envelope.observe(t, &self.stresses);
        }
        let best = self.largest_seen();
        let Peaks { trajectory, weights, .. } = &mut self.peaks;
        let now = (t, force, &q[..], &v[..]);
        let shares = trajectory.observe(part, weights, now, (&self.stresses, &values), &best);
        // The next stretch: the fewest modes whose left-out share stays within TAIL_SHARE of
        // the largest stress, and the next whole-grid instant where the time term of its bound
        // would take what is left of LEFT_SHARE of the largest after the grid's largest now,
        // the space term and the left-out share (at least TIME_SHARE of it).
        let best = best[0];
        let grid = hht::fast::largest_magnitude(&self.stresses);
        let spacing = |s: &modal_peak::Share| {
            if s.tt > 0.0 && best > 0.0 {
                let space = self.spacing * self.spacing / 8.0 * s.xx;
                let left = (LEFT_SHARE * best - grid - space - s.tail).max(TIME_SHARE * best);
                (8.0 * left / s.tt).sqrt()
            } else {
                0.0
            }
        };
        // Of the counts whose left-out share is small enough, the one with the least work a
        // unit of time: the grid's modes plus half of all (what a stretch costs besides the
        // grid: its bounds over every mode, the states it keeps) over its spacing (fewer modes
        // leave a larger tail but a smaller bound of the time derivative: longer stretches).
        let cost = |s: &modal_peak::Share| (s.modes + n / 2) as f64 / spacing(s);
        let share = shares
            .iter()
            .filter(|s| best > 0.0 && s.tail <= TAIL_SHARE * best)
            .min_by(|a, b| cost(a).total_cmp(&cost(b)))
            .or(shares.last())
            .copied();
        let next = share.map_or(n, |s| s.modes);
        let planned = share.map_or(0.0, |s| spacing(&s));
        if next != low {
            self.low = next;
            self.evaluate(self.stresses.len(), next, q, force);
            self.peaks.trajectory.regrid(&self.stresses, next);
        }
        self.hand_over();
        planned
    }

    /// The largest seen so far of each field the stretches are kept for: the stress, the
    /// displacement, each support's stress, then the one-point fields'.
    fn largest_seen(&self) -> Vec<f64> {
        [self.envelope.best().0.abs(), self.peaks.seen.displacement.0]
            .into_iter()
            .chain(self.envelope.supports().iter().map(|s| s.1))
            .chain(self.peaks.seen.points.iter().map(|p| p.0))
            .collect()
    }

    /// Hands the oldest [`EARLY_BATCH`] kept stretches to the stress's search once
    /// [`EARLY_LAG`] more have been kept after them, with the largest stress seen by then to
    /// start from (it only prunes: a lower start costs work, never the result). The batches
    /// are searched in their order between the whole-grid instants ([`Self::search_batches`]),
    /// so most of the search is done when the run ends (most of its work lies in the first
    /// contact's stretches). Which stretches go in a batch and what it starts from depend on
    /// the run alone, never on when the batch is searched, so neither does the result.
    fn hand_over(&mut self) {
        if matches!(self.peaks.early, Early::Off | Early::Gathered(..))
            || self.peaks.trajectory.kept.len() < EARLY_BATCH + EARLY_LAG
        {
            return;
        }
        // Those whose bounds all stay below the largest seen are dropped (as the trajectory's
        // pruning would have); of the others, those whose stress bound beats it go to the
        // search, the rest wait for the one-point searches at the end.
        let best = self.largest_seen();
        // Those held from earlier batches too, as the trajectory's pruning (which its list
        // no longer reaches: batches keep it short) would have.
        self.peaks.held.retain(|b| b.wanted(&best));
        let mut batch = Vec::new();
        for block in self.peaks.trajectory.kept.drain(..EARLY_BATCH) {
            if block.stress_wanted(best[0]) {
                batch.push(block);
            } else if block.wanted(&best) {
                self.peaks.held.push(block);
            }
        }
        if !batch.is_empty() {
            let (value, x, t) = self.envelope.best();
            self.peaks.batches.push_back((batch, Peak { value, x, t, bound: value.abs() }));
        }
    }

    /// Searches the batches handed over, in their order; `between` is called every few of
    /// the search's splits (the watch's thread observes the whole-grid instants waiting
    /// then, so that the solver need not wait for the search).
    fn search_batches(&mut self, between: &mut dyn FnMut(&mut Self)) {
        while let Some((batch, start)) = self.peaks.batches.pop_front() {
            let mut search = match std::mem::replace(&mut self.peaks.early, Early::Searching) {
                Early::Ready(search) => search,
                _ => Box::new(EarlySearch::new(self)),
            };
            search.search(batch, start, &mut || between(self));
            self.peaks.early = Early::Ready(search);
        }
    }

    /// The stretches the early search searched at the front of the kept ones, then those
    /// held, with its result: once, before any search at the end.
    fn gather(&mut self) {
        self.search_batches(&mut |_| {});
        let peaks = &mut self.peaks;
        if let Early::Ready(search) = std::mem::replace(&mut peaks.early, Early::Off) {
            let EarlySearch { mut searched, found, grid, order, .. } = *search;
            self.grid_field = Some((grid, order));
            let count = searched.len();
            searched.append(&mut peaks.held);
            searched.append(&mut peaks.trajectory.kept);
            peaks.trajectory.kept = searched;
            peaks.early = Early::Gathered(count, found);
        }
    }

    /// The grid's stress rows (E h/2 c_n and the correction's share) and order along the beam:
    /// what a search of the stress over the grid's points takes.
    fn make_grid_field(&self) -> (Vec<Row>, modal_peak::GridOrder) {
        let grid = grid_rows(&self.curvature, &self.correction, &self.rows);
        (grid, modal_peak::GridOrder::new(&self.envelope.points))
    }

    /// The stress at the first `points` points with the first `modes` modes, into `stresses`.
    fn evaluate(&mut self, points: usize, modes: usize, q: &[f64], force: f64) {
        modal::on_four_lanes(StressKernel {
            stresses: &mut self.stresses[..points],
            correction: &self.correction[..points],
            curvature: &self.curvature,
            stride: q.len(),
            q: &q[..modes],
            force,
            section: self.rows.section,
        });
    }

    /// The stress at (x, t) of the kept stretches with its first and second derivatives, and
    /// the force's linear piece around t.
    fn stress_derivatives(
        &self,
        kept: &[modal_peak::Block],
        (x, t): (f64, f64),
        stepper: &mut modal_peak::Stepper,
    ) -> Option<Derivatives> {
        let (state, force, slope, piece) =
            modal_peak::state_at(&self.peaks.data, kept, t, stepper)?;
        let modes = self.peaks.data.modes();
        let acc: Vec<f64> = (0..state.q.len())
            .map(|k| {
                let (w, z, g) = (modes.omega()[k], modes.damping_ratio()[k], modes.gain()[k]);
                g * force - w * w * state.q[k] - 2.0 * z * w * state.v[k]
            })
            .collect();
        let rows = self.rows.row_derivatives(x);
        let at = |row: &Row, q: &[f64], f: f64| row.value(f, q);
        let sigma = at(&rows[0], &state.q, force);
        let gradient = [at(&rows[1], &state.q, force), at(&rows[0], &state.v, slope)];
        let hessian =
            [at(&rows[2], &state.q, force), at(&rows[1], &state.v, slope), at(&rows[0], &acc, 0.0)];
        Some(Derivatives { sigma, gradient, hessian, piece })
    }

    /// The search's largest, moved by Newton's method to the local maximum of |sigma| it
    /// sits on (within its cell of the field: the same side of the impact point, the same
    /// piece of the force; at the impact point or a support, in time only); a step is kept
    /// only if it raises |sigma|, so the result is a value the field takes and at least the
    /// search's.
    fn polish(&self, kept: &[modal_peak::Block], peak: Peak) -> Peak {
        let sign = if peak.value < 0.0 { -1.0 } else { 1.0 };
        let knots = [0.0, self.rows.position, self.rows.length];
        let on_knot = knots.iter().any(|k| (peak.x - k).abs() <= 1e-12 * self.rows.length);
        let (lo, hi) = if peak.x < self.rows.position {
            (0.0, self.rows.position)
        } else {
            (self.rows.position, self.rows.length)
        };
        let mut best = peak;
        let mut stepper = modal_peak::Stepper::default();
        // The derivatives at `best` (those of the step that moved it there, after the first).
        let mut at_best = self.stress_derivatives(kept, (best.x, best.t), &mut stepper);
        for _ in 0..POLISH_STEPS {
            let Some(Derivatives { sigma, gradient: g, hessian: h, piece }) = at_best.take() else {
                break;
            };
            let (g, h) = (g.map(|v| sign * v), h.map(|v| sign * v));
            // Newton's step for the maximum: H d = -g, with H negative definite (else stop).
            let (dx, dt) = if on_knot {
                if h[2] >= 0.0 {
                    break;
                }
                (0.0, -g[1] / h[2])
            } else {
                let det = h[0] * h[2] - h[1] * h[1];
                if !(h[0] < 0.0 && det > 0.0) {
                    break;
                }
                ((-g[0] * h[2] + g[1] * h[1]) / det, (-g[1] * h[0] + g[0] * h[1]) / det)
            };
            // (A step into the next piece of the force is tried too: the stress's time rate
            // jumps there by E h/2 corr(x) times the slope's change, so the value decides.)
            let x = (best.x + dx).clamp(lo, hi);
            let t = best.t + dt.clamp(-(piece.1 - piece.0), piece.1 - piece.0);
            let Some(there) = self.stress_derivatives(kept, (x, t), &mut stepper) else {
                break;
            };
            let moved = there.sigma;
            if sign * moved <= sign * sigma || moved.is_nan() {
                break;
            }
            at_best = Some(there);
            let settled = (x - best.x).abs() <= 1e-13 * self.rows.length
                && (t - best.t).abs() <= 1e-13 * (piece.1 - piece.0);
            best = Peak { value: moved, x, t, bound: best.bound.max(moved.abs()) };
            if settled {
                break;
            }
        }
        best
    }

    /// The envelope with its largest, and each support's, searched between the observed
    /// points and instants.
    pub(crate) fn envelope(&mut self, yield_stress: Option<f64>) -> BendingStress {
        self.gather();
        let mut kept = std::mem::take(&mut self.peaks.trajectory.kept);
        let (rows, order) = self.grid_field.take().unwrap_or_else(|| self.make_grid_field());
        let row_at = |x: f64| self.rows.row_at(x);
        let points = &self.envelope.points;
        let field =
            StressField::new((points, &order), &rows, &row_at, self.peaks.weights.correction);
        // The stretches the early search left, from the largest seen or found so far.
        let (value, x, t) = self.envelope.best();
        let seen = Peak { value, x, t, bound: value.abs() };
        let (searched, early) = self.peaks.early_found();
        let start = early.map_or(seen, |e| larger(seen, e));
        let rest = modal_peak::search(
            &self.peaks.data,
            &mut kept[searched..],
            &modal_peak::Field::Stress(&field),
            start,
        );
        let peak = early.map_or(rest, |e| larger(e, rest));
        // The run's order again for the searches that follow (the held stretches had come
        // after the early search's, and are older than its later batches').
        kept.sort_by(|a, b| a.start().total_cmp(&b.start()));
        let peak = self.polish(&kept, peak);
        let mut supports = Vec::new();
        let count = self.peaks.weights.support_count;
        let weights = Arc::clone(&self.peaks.weights);
        for (k, row) in weights.supports[..count].iter().enumerate() {
            let (i, max, time) = self.envelope.supports()[k];
            let x = self.envelope.points[i];
            let seen = Peak { value: max, x, t: time, bound: max };
            let floor = modal_peak::FLOOR_SHARE * peak.value.abs();
            let field = modal_peak::Field::Magnitude(row, x, k, floor);
            supports.push(modal_peak::search(&self.peaks.data, &mut kept, &field, seen));
        }
        for (k, found) in supports.iter().enumerate() {
            self.envelope.raise_support(k, found.value.abs(), found.t);
        }
        let Peaks { data, points, seen, .. } = &mut self.peaks;
        let rows = &weights.supports;
        // The torsion shear's sections, like the supports' stresses, to 1e-4 of the largest
        // torsion shear seen (a section the twist has not reached yet holds the truncated
        // series' noise).
        let shear_floor = modal_peak::FLOOR_SHARE * largest_shear_seen(points, &seen.points);
        for (k, ((p, row), &(max, time))) in
            points.iter_mut().zip(&rows[count..]).zip(&seen.points).enumerate()
        {
            let seen = Peak { value: max, x: p.x, t: time, bound: max };
            let floor = match p.kind {
                PointKind::Twist => 0.0,
                PointKind::TorsionShear(_) => shear_floor,
            };
            let field = modal_peak::Field::Magnitude(row, p.x, count + k, floor);
            p.peak = Some(modal_peak::search(data, &mut kept, &field, seen));
        }
        self.peaks.trajectory.kept = kept;
        self.peaks.stress_peak = Some(peak);
        self.peaks.support_peaks = supports;
        self.envelope.finish(Some((peak.x, peak.value, peak.t)), yield_stress)
    }
}

/// The stress row at any point of the beam: E h/2 c_n(x) and the mode-acceleration form's
/// correction, with their x-derivatives (the search's new rows, Newton's polish). Immutable
/// once made, so the watch and its search share it.
struct StressRows {
    /// The shapes' curvatures at a point, all at once.
    curvatures: Curvatures,
    /// 1/sqrt(M) (1/sqrt(kg)).
    scale: f64,
    /// Stress per unit curvature on the struck face, E h/2 (Pa m).
    section: f64,
    /// Impact point (m).
    position: f64,
    length: f64,
    /// The beam for its static curvature; `None` keeps the plain series.
    beam: Option<Beam>,
    /// g_n / omega_n^2 (0 for a rigid mode) (m/N per sqrt(kg)), one a mode (its length is
    /// the modes' count).
    static_q: Vec<f64>,
}

impl StressRows {
    /// The stress row at x: E h/2 c_n(x) and E h/2 times the correction (Pa per unit q, Pa/N).
    pub(crate) fn row_at(&self, x: f64) -> Row {
        let [c] = self.scaled_curvatures(x);
        self.stress_row(x, 0, c)
    }

    /// The stress row at x and its first two x-derivatives (off the impact point and the
    /// supports, where the static curvature is linear in x).
    fn row_derivatives(&self, x: f64) -> [Row; 3] {
        let [c0, c1, c2] = self.scaled_curvatures(x);
        [self.stress_row(x, 0, c0), self.stress_row(x, 1, c1), self.stress_row(x, 2, c2)]
    }

    /// The modes' curvature c_n = phi_n''/sqrt(M) at x and its x-derivatives of the orders
    /// below K, from one evaluation of their waves ([`modal::Curvatures`]).
    fn scaled_curvatures<const K: usize>(&self, x: f64) -> [Vec<f64>; K] {
        let n = self.static_q.len();
        let mut c: [Vec<f64>; K] = std::array::from_fn(|_| vec![0.0; n]);
        let mut rows: Vec<&mut [f64]> = c.iter_mut().map(|v| v.as_mut_slice()).collect();
        self.curvatures.at(x, &mut rows);
        for v in &mut c {
            v.iter_mut().for_each(|c| *c *= self.scale);
        }
        c
    }

    /// The k-th x-derivative of the stress row at x from the modes' k-th curvature derivatives
    /// over sqrt(M) `c`.
    fn stress_row(&self, x: f64, k: u32, c: Vec<f64>) -> Row {
        let mut kept = 0.0;
        for (c, sq) in c.iter().zip(&self.static_q) {
            kept += c * sq;
        }
        let r = c.into_iter().map(|c| self.section * c).collect();
        let correction = match &self.beam {
            Some(b) => {
                let s = |x: f64| b.static_curvature(self.position, x).unwrap_or(0.0);
                // The static curvature is linear on each side of the impact point.
                let (lo, hi) = if x < self.position {
                    (0.0, self.position)
                } else {
                    (self.position, self.length)
                };
                let static_part = match k {
                    0 => s(x),
                    1 if hi > lo => (s(hi) - s(lo)) / (hi - lo),
                    _ => 0.0,
                };
                static_part - kept
            }
            None => 0.0,
        };
        Row { r, p: self.section * correction }
    }
}

/// The stress rows at the grid's points: E h/2 c_n(x_p) and E h/2 times the correction.
fn grid_rows(curvature: &[f64], correction: &[f64], rows: &StressRows) -> Vec<Row> {
    let n = rows.static_q.len();
    correction
        .iter()
        .enumerate()
        .map(|(k, c)| Row {
            r: curvature[k * n..(k + 1) * n].iter().map(|c| c * rows.section).collect(),
            p: c * rows.section,
        })
        .collect()
}

/// The larger of two searches' results (the first on a tie), with the larger bound: no value
/// of the field in either's stretches exceeds it.
fn larger(a: Peak, b: Peak) -> Peak {
    let bound = a.bound.max(b.bound);
    if b.value.abs() > a.value.abs() {
        Peak { bound, ..b }
    } else {
        Peak { bound, ..a }
    }
}

/// Where the stress's search of the early stretches is ([`GridWatch::hand_over`]).
enum Early {
    /// No batch searched yet.
    NotStarted,
    /// Between batches.
    Ready(Box<EarlySearch>),
    /// A batch being searched (the search is out of the watch meanwhile).
    Searching,
    /// Not wanted (a test's): every stretch is searched at the end.
    Off,
    /// Done: how many of the kept stretches (the first) it searched and the largest found.
    Gathered(usize, Option<Peak>),
}

/// The stress's search over the batches of kept stretches handed over as the run goes: its
/// own copies of what it needs (the watch observes instants between its splits), one budget
/// and one set of exact steps for all the batches, what it searched and the largest found.
struct EarlySearch {
    data: Arc<ModeData>,
    rows: Arc<StressRows>,
    grid: Vec<Row>,
    points: Vec<f64>,
    order: modal_peak::GridOrder,
    /// E h/2 max |correction| (Pa/N).
    peak_correction: f64,
    stepper: modal_peak::Stepper,
    budget: modal_peak::Budget,
    searched: Vec<modal_peak::Block>,
    found: Option<Peak>,
}

impl EarlySearch {
    fn new(watch: &GridWatch) -> Self {
        let (grid, order) = watch.make_grid_field();
        Self {
            data: Arc::clone(&watch.peaks.data),
            rows: Arc::clone(&watch.rows),
            grid,
            points: watch.envelope.points.clone(),
            order,
            peak_correction: watch.peaks.weights.correction,
            stepper: modal_peak::Stepper::default(),
            budget: modal_peak::Budget::default(),
            searched: Vec::new(),
            found: None,
        }
    }

    /// Searches `batch` from `start`, or from the largest found in the batches before if
    /// larger (they come in the run's order: still the run's alone).
    fn search(
        &mut self,
        mut batch: Vec<modal_peak::Block>,
        start: Peak,
        between: &mut dyn FnMut(),
    ) {
        let rows = &self.rows;
        let row_at = |x: f64| rows.row_at(x);
        let points = (&self.points[..], &self.order);
        let field = StressField::new(points, &self.grid, &row_at, self.peak_correction);
        let start = self.found.map_or(start, |f| larger(start, f));
        let peak = modal_peak::search_batch(
            &self.data,
            &mut batch,
            &modal_peak::Field::Stress(&field),
            start,
            (&mut self.stepper, &mut self.budget),
            between,
        );
        self.found = Some(self.found.map_or(peak, |f| larger(f, peak)));
        self.searched.append(&mut batch);
    }
}

/// The stress at one point and instant with its derivatives (Pa, Pa/m, Pa/s, ...).
struct Derivatives {
    sigma: f64,
    /// d/dx, d/dt.
    gradient: [f64; 2],
    /// d2/dx2, d2/dxdt, d2/dt2.
    hessian: [f64; 3],
    /// The force's linear piece around the instant (s, s).
    piece: (f64, f64),
}

/// What the search needs besides the beam and its modes.
struct PeakSetup<'a> {
    modes: PointModes,
    residual: f64,
    /// The grid's widest spacing (m) and the correction at its points (1/m^2 per N).
    spacing: f64,
    corrections: &'a [f64],
    /// Each support's stress row.
    supports: Vec<Row>,
    /// The one-point fields besides the supports' stresses (an off-centre strike's twist of
    /// the struck section and torsion shear at sections): what, where, the row.
    points: Vec<(PointKind, f64, Row)>,
}

impl Peaks {
    /// With `scale` = 1/sqrt(M) and `section` = E h/2 (the stress per unit curvature).
    fn new(
        shapes: &[Mode],
        (scale, section): (f64, f64),
        static_beam: Option<&Beam>,
        static_q: &[f64],
        setup: PeakSetup<'_>,
    ) -> Self {
        let PeakSetup { modes, residual, spacing, corrections, mut supports, points } = setup;
        let mode_acceleration = static_beam.is_some();
        let support_count = supports.len();
        let points: Vec<PointSearch> = points
            .into_iter()
            .map(|(kind, x, row)| {
                supports.push(row);
                PointSearch { kind, x, peak: None }
            })
            .collect();
        let bound = |k: i32| -> Vec<f64> {
            shapes.iter().map(|m| section * scale * m.shape.curvature_bound(k)).collect()
        };
        let (curvature, curvature2) = (bound(0), bound(2));
        // The correction's largest magnitude: its largest at the grid's points (the impact
        // point among them: off it and the ends the static curvature is linear, so the
        // correction's second derivative is -sum c_n'' s_n) plus what that second derivative
        // allows between them.
        let correction = if static_beam.is_some() {
            let largest = corrections.iter().fold(0.0, |m: f64, c| m.max(c.abs()));
            let second: f64 = curvature2.iter().zip(static_q).map(|(b, s)| b * s.abs()).sum();
            section * largest + spacing * spacing / 8.0 * second
        } else {
            0.0
        };
        let n = modes.len();
        let data = Arc::new(ModeData::new(modes));
        let displacement = Row { r: data.gain().to_vec(), p: residual };
        Self {
            trajectory: Trajectory::new(n),
            data,
            weights: Arc::new(Weights {
                stress: curvature,
                stress2: curvature2,
                mode_acceleration,
                spacing,
                correction,
                displacement,
                supports,
                support_count,
            }),
            seen: Seen {
                displacement: (0.0, 0.0),
                points: vec![(0.0, 0.0); points.len()],
                values: vec![0.0; points.len()],
            },
            points,
            early: Early::NotStarted,
            held: Vec::new(),
            batches: Default::default(),
            stress_peak: None,
            displacement_peak: None,
            support_peaks: Vec::new(),
        }
    }

    /// The largest displacement at the impact point, searched between instants from the
    /// largest `seen` by the solver.
    fn displacement(&mut self, seen: (f64, f64), position: f64) -> (f64, f64) {
        let own = self.seen.displacement;
        let start = if seen.0 >= own.0 { seen } else { own };
        let best = Peak { value: start.0, x: position, t: start.1, bound: start.0 };
        let peak = modal_peak::search(
            &self.data,
            &mut self.trajectory.kept,
            &modal_peak::Field::Signed(&self.weights.displacement, position),
            best,
        );
        self.displacement_peak = Some(peak);
        (peak.value, peak.t)
    }

    /// How many of the kept stretches (the first) the early search searched, and the largest
    /// it found (once gathered).
    fn early_found(&self) -> (usize, Option<Peak>) {
        match self.early {
            Early::Gathered(count, found) => (count, found),
            _ => (0, None),
        }
    }

    /// What the reasons say of the searches: the gap each closed, as a fraction of its value.
    fn note(&self) -> Option<String> {
        let all = self.gaps();
        let worst = all.iter().map(|g| g.1).fold(0.0, f64::max);
        // A gap of zero: no stretch's bound reached the value found (the search had nothing
        // left to split), which "within 0.0e0" had said unbelievably (a review's).
        let within = if worst > 0.0 {
            format!("each within {worst:.1e} of the field's maximum")
        } else {
            "each the field's maximum itself: every stretch between the observed instants was bounded below the value found, which Newton's method polished to its local maximum".to_string()
        };
        (!all.is_empty()).then(|| {
            format!(
                "largest stress (over the beam), each support's, the largest displacement at the impact point{}: found between the observed points and instants by branch and bound on bounds from the modal amplitudes (validation/REFERENCES.md 1.8), {within} (asked {:.0e} for the stress, {:.0e} at a point; a support's stress or a section's torsion shear below {floor:.0e} of the largest of its kind to {floor:.0e} of that largest)",
                self.point_names(),
                modal_peak::PEAK_TOLERANCE,
                modal_peak::POINT_TOLERANCE,
                floor = modal_peak::FLOOR_SHARE
            )
        })
    }

    /// Each search's name, the gap it left and what that is a fraction of: its value, or, for
    /// a support's stress or a section's torsion shear below 1e-4 of the largest of its kind
    /// (the floor its search was certified to), that largest.
    fn gaps(&self) -> Vec<(String, f64, &'static str)> {
        let gap = |p: &Peak| if p.value.abs() > 0.0 { p.bound / p.value.abs() - 1.0 } else { 0.0 };
        let floored = |p: &Peak, largest: f64, of: &'static str| {
            if largest > 0.0 && p.value.abs() < modal_peak::FLOOR_SHARE * largest {
                ((p.bound - p.value.abs()) / largest, of)
            } else {
                (gap(p), "itself")
            }
        };
        let mut out: Vec<(String, f64, &'static str)> = Vec::new();
        let mut push = |name: String, (g, of): (f64, &'static str)| out.push((name, g, of));
        if let Some(p) = &self.stress_peak {
            push("the largest stress".to_string(), (gap(p), "itself"));
        }
        if let Some(p) = &self.displacement_peak {
            push("the largest displacement".to_string(), (gap(p), "itself"));
        }
        let largest = self.stress_peak.map_or(0.0, |p| p.value.abs());
        for p in &self.support_peaks {
            push(format!("the stress at x = {} m", p.x), floored(p, largest, "the largest stress"));
        }
        let shear = largest_shear_seen(&self.points, &self.seen.points);
        for p in &self.points {
            let Some(found) = &p.peak else { continue };
            match p.kind {
                PointKind::Twist => push("the largest twist".to_string(), (gap(found), "itself")),
                PointKind::TorsionShear(which) => push(
                    format!("the torsion shear at x = {:.4} m{which}", p.x),
                    floored(found, shear, "the largest torsion shear"),
                ),
            }
        }
        out
    }

    /// What the note adds for the one-point fields besides the supports' stresses.
    fn point_names(&self) -> String {
        let has = |shear: bool| {
            let kind = |p: &PointSearch| matches!(p.kind, PointKind::TorsionShear(_)) == shear;
            self.points.iter().any(|p| kind(p) && p.peak.is_some())
        };
        let mut out = String::new();
        if has(false) {
            out.push_str(", the struck section's largest twist");
        }
        if has(true) {
            out.push_str(", the torsion shear at the supports that hold the twist and on each side of the struck section (the places the static torque is largest; not searched elsewhere along the beam)");
        }
        out
    }

    /// The largest of the twist's (`shear` false) or the torsion shear's searches:
    /// magnitude, where (m), when (s).
    fn largest(&self, shear: bool) -> Option<(f64, f64, f64)> {
        self.points
            .iter()
            .filter(|p| matches!(p.kind, PointKind::TorsionShear(_)) == shear)
            .filter_map(|p| p.peak.map(|found| (found.value.abs(), p.x, found.t)))
            .fold(None, |best, this| match best {
                Some(b) if b.0 >= this.0 => Some(b),
                _ => Some(this),
            })
    }

    /// Warnings for searches that stopped at their budget short of their tolerance: the
    /// value printed is one the field takes, but a larger one is not ruled out.
    fn warnings(&self) -> Vec<String> {
        self.gaps()
            .into_iter()
            .filter(|(_, g, _)| *g > modal_peak::WARNING_GAP)
            .map(|(what, g, of)| {
                format!(
                    "{what} is certain only to {g:.1e} of {of}: the search between the observed instants stopped at its budget ({} modes make its bounds loose); fewer modes, or solver.tolerance",
                    self.weights.displacement.r.len()
                )
            })
            .collect()
    }
}

impl ModalStress {
    /// The watch back on this thread for the searches at the end, with what the run has seen
    /// at its last instant (the same as at its last whole-grid instant when the last instant
    /// was observed as the last, as the solvers do).
    fn watch_at_end(&mut self) -> &mut GridWatch {
        let watch = self.watch.back();
        watch.peaks.seen.clone_from(&self.seen);
        watch
    }
}

impl BeamRecorder for ModalStress {
    fn observe(&mut self, at: &Instant<'_>) {
        if let BeamView::Modal { q, v, force } = at.beam {
            self.observe_modes(at.t, (q, v), force, (at.sample.is_some(), at.last));
        }
    }

    fn step(&mut self, t: f64, force: f64) {
        modal_peak::push_end(&mut self.ends, self.start.1, (t, force));
    }

    fn next_look(&self) -> f64 {
        self.last_full + self.full_spacing
    }

    fn finish(&mut self, yield_stress: Option<f64>) -> BendingStress {
        self.watch_at_end().envelope(yield_stress)
    }

    fn displacement_peak(&mut self, seen: (f64, f64)) -> (f64, f64) {
        let position = self.rows.position;
        let watch = self.watch_at_end();
        watch.gather();
        watch.peaks.displacement(seen, position)
    }

    fn twist_peak(&self) -> Option<(f64, f64)> {
        self.watch.returned()?.peaks.largest(false).map(|(max, _, t)| (max, t))
    }

    fn torsion_shear_peak(&self) -> Option<(f64, f64, f64)> {
        self.watch.returned()?.peaks.largest(true)
    }

    fn search_note(&self) -> Option<String> {
        self.watch.returned()?.peaks.note()
    }

    fn search_warnings(&self) -> Vec<String> {
        self.watch.returned().map_or_else(Vec::new, |w| w.peaks.warnings())
    }

    fn take_field(&mut self) -> Option<Field> {
        self.take_recorded_field()
    }
}

/// Whole-grid instants the solver runs ahead of the [`GridWatch`]: the next such instant is
/// set by the watch's plan from this many before, so that the solver seldom waits for the
/// watch (which searches the kept stretches between instants). The plan only sets how long a
/// stretch is; each stretch is certified or kept by its own bounds, so the maxima do not
/// depend on it beyond the searches' tolerances. On the paper's tip at 256 modes over 5 ms:
/// 888 whole-grid instants with the plan of the instant itself, 898, 921, 947, 992 with it
/// from 4, 16, 32, 64 before; the run 3 % faster with 32 than with 16, as fast as with 64.
const PLAN_LAG: usize = 32;

/// Where the [`GridWatch`] is.
enum Watch {
    /// On the solver's thread (a sweep's run, whose threads are all busy; a process with one
    /// processor; or no thread was given): each whole-grid instant observed as it comes, its
    /// plan held back [`PLAN_LAG`] instants as on a thread of its own (instant k gets instant
    /// k - PLAN_LAG's plan either way). At the run's end, the watch is back here, with the way
    /// back to its thread where it had one (`free`: see [`ModalStress`]'s `Drop`).
    Here {
        watch: Box<GridWatch>,
        plans: std::collections::VecDeque<f64>,
        spare: Box<Snapshot>,
        free: Option<std::sync::mpsc::Sender<Box<GridWatch>>>,
    },
    /// On a thread of its own.
    Away(WatchThread),
    /// Between the two (only while being moved; left so after a panic on the watch's thread,
    /// which goes on on the solver's, and once the watch is sent back to its thread to be
    /// freed, as the recovery is dropped).
    Moving,
}

/// The [`GridWatch`] on its own thread: the whole-grid instants go to it, its plans (with the
/// instants' buffers, for the next) come back; at the run's end the watch comes back
/// (`returned`) and, once the searches at the end are done with it, goes to its thread again
/// to be freed (`free`). Dropped before its run ends (a run that failed or was stopped), it
/// tells its thread to stop: the thread ends once the batch it is searching is done.
struct WatchThread {
    instants: Option<std::sync::mpsc::Sender<Snapshot>>,
    plans: std::sync::mpsc::Receiver<(f64, Snapshot)>,
    returned: std::sync::mpsc::Receiver<Box<GridWatch>>,
    free: Option<std::sync::mpsc::Sender<Box<GridWatch>>>,
    worker: Option<std::thread::JoinHandle<()>>,
    stop: Arc<std::sync::atomic::AtomicBool>,
    /// Instants sent whose plans have not come back.
    pending: usize,
    spare: Vec<Snapshot>,
}

/// A watch that had a thread of its own is freed there: its kept stretches are thousands of
/// blocks that its thread allocated, and freed on the solver's thread (each a free to another
/// thread's heap) they took 0.25 ms of the paper's tip run (256 modes, 5 ms) between the
/// searches at the end and the report.
impl Drop for ModalStress {
    fn drop(&mut self) {
        if let Watch::Here { free: Some(_), .. } = self.watch {
            if let Watch::Here { watch, free: Some(free), .. } =
                std::mem::replace(&mut self.watch, Watch::Moving)
            {
                // (If its thread is gone, the watch comes back in the error and is freed here.)
                let _ = free.send(watch);
            }
        }
    }
}

impl Drop for WatchThread {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        self.instants = None;
        if let Some(worker) = &self.worker {
            worker.thread().unpark();
        }
    }
}

impl Watch {
    /// On a thread of its own, unless the run is one of a sweep's (on rayon's threads, all
    /// busy with runs), the process has one processor (rayon's pool, sized by what the system
    /// allows the process, has one thread: the two threads sharing it took 30 % longer than
    /// one) or the system gives no thread.
    fn start(watch: GridWatch) -> Self {
        let watch = Box::new(watch);
        if rayon::current_thread_index().is_some() || rayon::current_num_threads() < 2 {
            Self::here(watch, None)
        } else {
            Self::spawn(watch)
        }
    }

    /// On the solver's thread, with the way back to its own thread where it had one.
    fn here(watch: Box<GridWatch>, free: Option<std::sync::mpsc::Sender<Box<GridWatch>>>) -> Self {
        Self::Here { watch, plans: std::collections::VecDeque::new(), spare: Box::default(), free }
    }

    /// On a thread of its own (here if the system gives none).
    fn spawn(watch: Box<GridWatch>) -> Self {
        let (instants, received) = std::sync::mpsc::channel::<Snapshot>();
        let (planned, plans) = std::sync::mpsc::channel::<(f64, Snapshot)>();
        let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        // The watch goes to the thread once it runs: if none comes, it stays here.
        let (give, take) = std::sync::mpsc::channel::<Box<GridWatch>>();
        let (give_back, returned) = std::sync::mpsc::channel::<Box<GridWatch>>();
        let (free, to_free) = std::sync::mpsc::channel::<Box<GridWatch>>();
        let spawned = std::thread::Builder::new().name("grid-watch".into()).spawn(move || {
            let Ok(mut watch) = take.recv() else { return };
            let stopped = || stopped.load(std::sync::atomic::Ordering::Relaxed);
            // Every instant waiting, each with its plan back: how many (`None` once the solver
            // is gone).
            let observe_waiting = |watch: &mut GridWatch| {
                let mut observed = 0;
                loop {
                    match received.try_recv() {
                        Ok(instant) => {
                            let plan = watch.observe(&instant);
                            planned.send((plan, instant)).ok()?;
                            observed += 1;
                        }
                        Err(std::sync::mpsc::TryRecvError::Empty) => return Some(observed),
                        Err(std::sync::mpsc::TryRecvError::Disconnected) => return None,
                    }
                }
            };
            // The instants first (the solver waits for their plans), the search's batches
            // between them (the instants observed every few splits); a while spinning, a
            // while yielding (the solver's thread may be waiting for this processor), then
            // asleep until woken, or a millisecond.
            let mut idle = 0usize;
            while !stopped() {
                let Some(observed) = observe_waiting(&mut watch) else { break };
                if observed > 0 {
                    idle = 0;
                } else if !watch.peaks.batches.is_empty() {
                    idle = 0;
                    watch.search_batches(&mut |watch| {
                        if !stopped() {
                            observe_waiting(watch);
                        }
                    });
                } else if idle < SPINS {
                    idle += 1;
                    std::hint::spin_loop();
                } else if idle < SPINS + YIELDS {
                    idle += 1;
                    std::thread::yield_now();
                } else {
                    std::thread::park_timeout(std::time::Duration::from_millis(1));
                }
            }
            // Back to the solver's thread for the searches at the end, then freed here, where
            // its blocks were allocated, while the solver's thread writes the report.
            if give_back.send(watch).is_ok() {
                drop(to_free.recv());
            }
        });
        match spawned {
            Ok(worker) => match give.send(watch) {
                Ok(()) => Self::Away(WatchThread {
                    instants: Some(instants),
                    plans,
                    returned,
                    free: Some(free),
                    worker: Some(worker),
                    stop,
                    pending: 0,
                    spare: Vec::new(),
                }),
                Err(returned) => Self::here(returned.0, None),
            },
            Err(_) => Self::here(watch, None),
        }
    }

    /// A snapshot to fill (its buffers reused).
    fn spare(&mut self) -> Snapshot {
        match self {
            Self::Here { spare, .. } => std::mem::take(&mut **spare),
            Self::Away(away) => away.spare.pop().unwrap_or_default(),
            Self::Moving => Snapshot::default(),
        }
    }

    /// Observes a whole-grid instant; returns the plan of the one [`PLAN_LAG`] before (0, the
    /// next recorded instant, before there is one).
    fn observe(&mut self, instant: Snapshot) -> f64 {
        match self {
            Self::Here { watch, plans, spare, .. } => {
                plans.push_back(watch.observe(&instant));
                watch.search_batches(&mut |_| {});
                **spare = instant;
                if plans.len() > PLAN_LAG {
                    plans.pop_front().unwrap_or(0.0)
                } else {
                    0.0
                }
            }
            Self::Away(away) => {
                let sent = away.instants.as_ref().is_some_and(|to| to.send(instant).is_ok());
                let received = if sent {
                    away.pending += 1;
                    let worker = away.worker.as_ref().map(|w| w.thread());
                    if away.pending % WAKE_EVERY == 0 {
                        worker.inspect(|w| w.unpark());
                    }
                    if away.pending <= PLAN_LAG {
                        return 0.0;
                    }
                    worker.inspect(|w| w.unpark());
                    spin_for(&away.plans)
                } else {
                    None
                };
                match received {
                    Some((plan, spare)) => {
                        away.pending -= 1;
                        away.spare.push(spare);
                        plan
                    }
                    // Its thread stopped, which only a panic there does: it goes on here.
                    None => {
                        self.back();
                        unreachable!("the stress recovery's watch stopped before its run ended")
                    }
                }
            }
            Self::Moving => 0.0,
        }
    }

    /// The watch, back on this thread (waiting for it to finish the instants sent); a panic
    /// on its thread goes on here.
    fn back(&mut self) -> &mut GridWatch {
        if let Self::Away(_) = self {
            let Self::Away(mut away) = std::mem::replace(self, Self::Moving) else {
                unreachable!()
            };
            // (Its plans are kept until it is done: it observes every instant sent.)
            away.instants = None;
            if let Some(worker) = away.worker.take() {
                worker.thread().unpark();
                match away.returned.recv() {
                    Ok(watch) => *self = Self::here(watch, away.free.take()),
                    // Its thread ended without handing it back: only a panic there does.
                    Err(_) => match worker.join() {
                        Err(panic) => std::panic::resume_unwind(panic),
                        Ok(()) => unreachable!("the watch was given to its thread"),
                    },
                }
            }
        }
        match self {
            Self::Here { watch, .. } => watch,
            _ => unreachable!("the watch is back on this thread"),
        }
    }

    /// The watch, once back.
    fn returned(&self) -> Option<&GridWatch> {
        match self {
            Self::Here { watch, .. } => Some(watch),
            _ => None,
        }
    }
}

/// The next message, `None` once the other side is gone: the solver's thread waits for the
/// watch's plan without sleeping (a thread's waking from sleep takes tens of microseconds,
/// the watch's instant a few), yielding after [`SPINS`] tries (the watch may be waiting for
/// this very processor: spinning a millisecond before yielding had made one run in three of
/// a criterion bench, whose threads the system placed so, 40 % slower).
fn spin_for<T>(from: &std::sync::mpsc::Receiver<T>) -> Option<T> {
    let mut spins = 0usize;
    loop {
        match from.try_recv() {
            Ok(message) => return Some(message),
            Err(std::sync::mpsc::TryRecvError::Empty) if spins < SPINS => {
                spins += 1;
                std::hint::spin_loop();
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => std::thread::yield_now(),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => return None,
        }
    }
}

/// How many times a thread waiting for the other tries before yielding between tries (some
/// tens of microseconds), and how many times the watch's yields before it sleeps.
const SPINS: usize = 1 << 10;
const YIELDS: usize = 1 << 8;

/// The solver wakes the watch's thread every this many whole-grid instants it sends (and
/// whenever it waits for a plan).
const WAKE_EVERY: usize = 8;

/// sigma_p = E h/2 (F correction_p + sum_n c_n(x_p) q_n) for the points of `stresses`: a dot
/// product a point in the vectors `modal::on_four_lanes` takes at run time, fused multiply-adds,
/// four points at a time.
struct StressKernel<'a> {
    stresses: &'a mut [f64],
    correction: &'a [f64],
    /// Point-major, one row of `stride` a point, of which the first `q.len()` are used.
    curvature: &'a [f64],
    stride: usize,
    q: &'a [f64],
    force: f64,
    section: f64,
}

impl pulp::WithSimd for StressKernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        let Self { stresses, correction, curvature, stride: n, q, force, section } = self;
        let m = q.len();
        let (q_head, q_tail) = S::as_simd_f64s(q);
        let lanes = |v: S::f64s| -> f64 {
            let l: &[f64] = pulp::bytemuck::cast_slice(std::slice::from_ref(&v));
            l.iter().sum()
        };
        let tail_dot = |row: &[f64]| -> f64 {
            row[m - q_tail.len()..m].iter().zip(q_tail).map(|(a, b)| a * b).sum()
        };
        let used = stresses.len();
        let rows = &curvature[..used * n];
        // Four points at a time share each load of q (register blocking), then the rest one
        // by one; each point's sum has a fixed order, so the result does not depend on which.
        let blocks = used / 4;
        for (block, out) in rows.chunks_exact(4 * n).zip(stresses.chunks_exact_mut(4)) {
            let heads: [&[S::f64s]; 4] =
                std::array::from_fn(|j| S::as_simd_f64s(&block[j * n..j * n + m]).0);
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
            let head = S::as_simd_f64s(&row[..m]).0;
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

    /// The recovery of `count` modes of `b` struck at `c`, undamped, without residual, for a
    /// pulse of `duration` (s).
    fn recovery(b: &Beam, count: usize, c: f64, duration: f64) -> ModalStress {
        let shapes = b.modes(count).unwrap();
        let modes = PointModes::new(b, &shapes, c, 0.0).unwrap();
        let setup = StressSetup {
            position: c,
            thickness: 0.005,
            width: 0.025,
            plain: false,
            modes,
            residual: 0.0,
            duration,
            twist: None,
            torsion_shear: Vec::new(),
        };
        ModalStress::new(b, shapes, setup)
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
            let mut s = recovery(&b, 8, c, 4e-5);
            let q: Vec<f64> = s
                .shapes
                .iter()
                .map(|m| m.shape.value(c) / b.mass().sqrt() * force / (m.omega * m.omega))
                .collect();
            let v = vec![0.0; q.len()];
            let section = 2.1e11 * 0.0025;
            for k in 0..=46 {
                let x = 1.15 * k as f64 / 46.0;
                let exact = section * b.static_curvature(c, x).unwrap() * force;
                let got = s.rows.row_at(x).value(force, &q);
                assert!(
                    (got - exact).abs() <= 1e-9 * section * force,
                    "{support:?} x = {x}: {got} vs {exact}"
                );
            }
            // At the load the plain 8-mode series misses a good part of the moment.
            let plain: f64 = s
                .shapes
                .iter()
                .zip(&q)
                .map(|(m, qn)| m.shape.curvature(c) * s.rows.scale * qn)
                .sum();
            let exact = b.static_curvature(c, c).unwrap();
            assert!((plain - exact).abs() > 1e-2 * exact.abs(), "{support:?}: {plain} vs {exact}");
            // The envelope of one observation: the static moment's largest, where the tables
            // put it (the clamp of a cantilever, the load on a pinned beam).
            s.observe_modes(0.0, (&q, &v), force, (true, true));
            let e = s.finish(None);
            let tables = (0..=1150)
                .map(|k| b.static_curvature(c, k as f64 / 1000.0).unwrap().abs())
                .fold(0.0, f64::max)
                * section
                * force;
            assert!((e.max - tables).abs() < 1e-6 * tables, "{support:?}: {} vs {tables}", e.max);
        }
    }

    #[test]
    fn the_points_hold_the_supports_the_impact_point_and_a_uniform_grid() {
        // Supports, impact point, L/2^k around it; the uniform grid: no two points further
        // apart than L/intervals, with intervals = ceil(2 L beta_c) (beta_c the wavenumber of
        // omega = pi/t_c, EI beta^4 = rho A omega^2: 233 on the paper's beam at t_c = 41 us).
        let b = beam(Support::ClampedClamped);
        let mut s = recovery(&b, 4, 0.3, 4.1237e-5);
        let watch = s.watch.back();
        let points = &watch.envelope.points;
        for x in [0.0, 1.15, 0.3, 0.3 + 1.15 / 16.0, 0.3 - 1.15 / 512.0] {
            assert!(points.iter().any(|p| (p - x).abs() < 1e-12), "{x} missing");
        }
        assert_eq!(watch.near_count, 2 + 1 + 12);
        let mut sorted = points.clone();
        sorted.sort_by(f64::total_cmp);
        let widest = sorted.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        let beta_c = (std::f64::consts::PI / 4.1237e-5
            * (7850.0 * 1.25e-4 / (2.1e11 * 2.604_166_666_666_667e-10_f64)).sqrt())
        .sqrt();
        let intervals = (2.0 * 1.15 * beta_c).ceil();
        assert!((intervals - 233.0).abs() < 0.5);
        assert!((watch.spacing - 1.15 / intervals).abs() < 1e-12, "{}", watch.spacing);
        assert!(widest <= watch.spacing * (1.0 + 1e-12), "{widest} vs {}", watch.spacing);
    }

    #[test]
    fn a_maximum_between_the_points_and_between_the_instants_is_found() {
        // A pinned-pinned beam ringing in its 7th mode alone: q = A cos(omega t + phi), the
        // plain series (no static part). Its stress E h/2 c_7(x) q(t) peaks at
        // |E h/2 A c_7|max = E h/2 A beta^2 sqrt(2)/sqrt(M) wherever sin(beta x) = +-1 (x =
        // (2k+1) L/14: on no point of the grid, 32 intervals), and in time at
        // omega t* = pi - phi, half-way between two observed instants. The search must find
        // the peak to within its tolerance (plus round-off) and Newton's polish to round-off.
        let b = beam(Support::PinnedPinned);
        let count = 8;
        let shapes = b.modes(count).unwrap();
        let modes = PointModes::new(&b, &shapes, 0.5, 0.0).unwrap();
        let setup = StressSetup {
            position: 0.5,
            thickness: 0.005,
            width: 0.025,
            plain: true,
            modes,
            residual: 0.0,
            duration: 1.0,
            twist: None,
            torsion_shear: Vec::new(),
        };
        let mut s = ModalStress::new(&b, shapes, setup);
        let mode = &s.shapes[6];
        let (omega, beta) = (mode.omega, mode.shape.beta());
        let amplitude = 1e-4;
        let phi = 0.3;
        let t_star = (std::f64::consts::PI - phi) / omega;
        let step = t_star / 10.5;
        let section = 2.1e11 * 0.0025;
        let exact = section * amplitude * beta * beta * 2f64.sqrt() / b.mass().sqrt();
        let mut t: f64 = 0.0;
        let end = t_star + 5.0 * step;
        while t <= end {
            let mut q = vec![0.0; count];
            let mut v = vec![0.0; count];
            q[6] = amplitude * (omega * t + phi).cos();
            v[6] = -amplitude * omega * (omega * t + phi).sin();
            if t > 0.0 {
                s.step(t, 0.0);
            }
            s.observe_modes(t, (&q, &v), 0.0, (true, t + step > end));
            t += step;
        }
        let e = s.finish(None);
        assert!(e.max <= exact * (1.0 + 1e-12), "{} above {exact}", e.max);
        assert!(
            e.max >= exact * (1.0 - 1e-10),
            "{} vs {exact}: relative {:e}",
            e.max,
            e.max / exact - 1.0
        );
        assert!(((beta * e.position).sin().abs() - 1.0).abs() < 1e-5, "at {}", e.position);
        assert!((e.time - t_star).abs() < 1e-9, "at {} vs {t_star}", e.time);
    }

    #[test]
    fn the_watch_on_its_thread_finds_what_it_finds_here_and_what_the_end_finds() {
        // Sixteen modes of the paper's cantilever ringing together (no force), observed at
        // 4000 instants over 40 ms: hundreds of stretches are kept, so the oldest go to the
        // stress's search in batches, searched between the whole-grid instants. The watch on a
        // thread of its own, the same watch on this thread, and one that searches every
        // stretch at the end must give the same largest stress, where and when, and bound
        // left, to the bit: the whole-grid instants, their plans and the batches depend on the
        // run alone, and each batch's search and the rest's find the same local maximum,
        // which Newton's method polishes alike.
        let b = beam(Support::ClampedFree);
        let run = |watch: &str| {
            let mut s = recovery(&b, 16, 1.15, 2e-4);
            // (With one processor `Watch::start` keeps the watch here: sent away all the same.)
            if let Watch::Here { .. } = s.watch {
                let Watch::Here { watch, .. } = std::mem::replace(&mut s.watch, Watch::Moving)
                else {
                    unreachable!()
                };
                s.watch = Watch::spawn(watch);
            }
            assert!(matches!(s.watch, Watch::Away(_)), "the watch has no thread of its own");
            if watch != "away" {
                s.watch.back();
            }
            if watch == "end" {
                s.watch.back().peaks.early = Early::Off;
            }
            let omega: Vec<f64> = s.shapes.iter().map(|m| m.omega).collect();
            let amplitude: Vec<f64> = (0..16).map(|k| 1e-4 / (1.0 + k as f64).powi(2)).collect();
            let phase: Vec<f64> = (0..16).map(|k| 0.7 * k as f64).collect();
            let step = 1e-5;
            for i in 0..=4000 {
                let t = i as f64 * step;
                let q: Vec<f64> =
                    (0..16).map(|k| amplitude[k] * (omega[k] * t + phase[k]).cos()).collect();
                let v: Vec<f64> = (0..16)
                    .map(|k| -amplitude[k] * omega[k] * (omega[k] * t + phase[k]).sin())
                    .collect();
                if i > 0 {
                    s.step(t, 0.0);
                }
                s.observe_modes(t, (&q, &v), 0.0, (true, i == 4000));
            }
            let e = s.finish(None);
            let watch = s.watch.back();
            (e, watch.peaks.early_found().0, watch.peaks.stress_peak.unwrap())
        };
        let (away, searched, peak_away) = run("away");
        let (here, searched_here, peak_here) = run("here");
        let (at_end, none, peak_at_end) = run("end");
        assert!(searched > 0, "no stretch was searched during the run");
        assert_eq!(searched, searched_here);
        assert_eq!(none, 0);
        for (e, peak) in [(here, peak_here), (at_end, peak_at_end)] {
            for (a, b) in [
                (away.max, e.max),
                (away.position, e.position),
                (away.time, e.time),
                (peak_away.bound, peak.bound),
            ] {
                assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
            }
        }
    }

    #[test]
    fn the_largest_twist_between_instants_is_found() {
        // An off-centre strike's basis: 8 bending modes of a pinned-pinned beam and a torsion
        // mode (no bending shape) ringing alone, q = A cos(omega t + phi), seen through the
        // twist row (its Theta(c)/sqrt(rho Ip L) = 3). The twist's largest magnitude is 3 A at
        // omega t* = pi - phi, half-way between two observed instants; the stress stays 0.
        let b = beam(Support::PinnedPinned);
        let mut shapes = b.modes(8).unwrap();
        let omega = 4.0 * shapes[7].omega;
        shapes.push(Mode { beta_l: 0.0, omega, shape: modal::ModeShape::absent(b.length()) });
        let mut gain: Vec<f64> = shapes[..8].iter().map(|m| m.shape.value(0.5)).collect();
        gain.push(0.01 * 3.0);
        let modes =
            PointModes::from_parts(shapes.iter().map(|m| m.omega).collect(), vec![0.0; 9], gain)
                .unwrap();
        let mut row = vec![0.0; 9];
        row[8] = 3.0;
        let setup = StressSetup {
            position: 0.5,
            thickness: 0.005,
            width: 0.025,
            plain: false,
            modes,
            residual: 0.0,
            duration: 1e-3,
            twist: Some(Row { r: row, p: 0.0 }),
            torsion_shear: Vec::new(),
        };
        let mut s = ModalStress::new(&b, shapes, setup);
        let (amplitude, phi) = (1e-3, 0.3);
        let t_star = (std::f64::consts::PI - phi) / omega;
        let step = t_star / 10.5;
        let mut t: f64 = 0.0;
        let end = t_star + 5.0 * step;
        while t <= end {
            let (mut q, mut v) = (vec![0.0; 9], vec![0.0; 9]);
            q[8] = amplitude * (omega * t + phi).cos();
            v[8] = -amplitude * omega * (omega * t + phi).sin();
            if t > 0.0 {
                s.step(t, 0.0);
            }
            s.observe_modes(t, (&q, &v), 0.0, (true, t + step > end));
            t += step;
        }
        let e = s.finish(None);
        assert!(e.max.abs() < 1e-300, "{}", e.max);
        let (twist, when) = s.twist_peak().unwrap();
        let exact = 3.0 * amplitude;
        assert!(
            twist <= exact * (1.0 + 1e-12) && twist >= exact * (1.0 - 1e-10),
            "{twist} vs {exact}"
        );
        assert!((when - t_star).abs() < 1e-6 * t_star, "at {when} vs {t_star}");
    }
}
