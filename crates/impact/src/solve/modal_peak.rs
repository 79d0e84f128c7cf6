//! The true maxima of the modal method's fields, between the instants and points it observes:
//! branch and bound over the beam and the window.
//!
//! A field value at one point is `F(t) p + sum_n r_n q_n(t)` (the displacement at the impact
//! point: r = g, p the residual flexibility; the bending stress at x: r = E h/2 c_n(x),
//! p = E h/2 times the mode-acceleration correction). Within one step of the solver the force
//! is linear in time and every mode is an exact damped oscillator, so over a stretch of the
//! run each mode obeys bounds that follow from its state at the stretch's start alone
//! (validation/REFERENCES.md 1.8):
//!
//! - raw: the amplitude sqrt(q^2 + (v/omega)^2) grows by at most |g| (impulse)/omega, so
//!   |q| <= R = sqrt(q^2 + (v/omega)^2) + |g| I/omega and |v| <= omega R;
//! - about the quasi-static part: with s = g/omega^2 and the force's slope F', the part
//!   q~ = q - s F + 2 zeta s F'/omega is a free damped oscillator inside a step (F'' = 0), whose
//!   amplitude does not grow, and a change of slope moves it by at most
//!   (1 + 2 zeta) |s| |dF'|/omega (a norm in the plane of q~ and q~'/omega), so
//!   |q~| <= A = sqrt((q - s F0)^2 + (v/omega)^2) + (1 + 2 zeta) |s| V/omega, V the slope's
//!   variation;
//! - hence |q| <= Q = min(R, |s| F_max + A + 2 zeta |s| F'_max/omega) and
//!   |q''| <= min((1 + 2 zeta) omega^2 A, |g| F_max + (1 + 2 zeta) omega^2 R) (a rigid-body
//!   mode: |q''| = |g F|).
//!
//! Over a cell [x_a, x_b] x [t_a, t_b] inside one step, the field differs from the bilinear
//! interpolation of its four corners by at most h_x^2/8 max|f_xx| + h_t^2/8 max|f_tt|, with
//! f_tt = sum r_n q_n'' (F is linear) and, for the stress off the impact point and the
//! supports (where the static moment is linear in x), f_xx = E h/2 sum c_n''(x) (q_n - s_n F)
//! (mode-acceleration form) or E h/2 sum c_n'' q_n (plain series); |c_n''| is bounded by the
//! mode's waves ([`modal::ModeShape::curvature_bound`]). So the largest magnitude in a cell is
//! at most its largest corner plus these terms. The search keeps cells in a heap by that bound,
//! splits the one with the largest bound (in x or t, whichever term is larger; a split in time
//! propagates a mode state exactly to the new instant), and stops when no cell can beat the
//! best value found by more than [`PEAK_TOLERANCE`] of it. Stretches whose bound (a triangle
//! bound over the modes) cannot beat the best value observed during the run are dropped as
//! the run goes; the rest are kept with their start state and replayed when the search needs
//! them.

use modal::{ModalState, OneStep, PointModes};
use std::collections::{BinaryHeap, HashMap};
use std::sync::Arc;

/// The relative gap the search over the beam closes: the largest stress reported is below
/// the field's true one by less than this fraction of it (then polished to its local
/// maximum by Newton's method, `ModalStress`). At 1e-4 it stopped on whichever of two local
/// maxima 1.4e-6 apart (the paper's tip at 256 modes over 5 ms) its path met first, so that
/// the whole-grid instants' plan moved the largest stress; at 1e-9 it is the field's own to
/// round-off's scale, whatever the path, for 3 % more time on that run.
pub(crate) const PEAK_TOLERANCE: f64 = 1e-9;
/// The share of the largest of its kind below which a support's stress or a section's
/// torsion shear is certified to that share of the largest, not to [`POINT_TOLERANCE`] of
/// itself (a support no wave has reached yet holds the truncated series' noise).
pub(crate) const FLOOR_SHARE: f64 = 1e-4;
/// The gap past which a search that stopped at its budget warns (a smaller one is in the
/// reasons' note only).
pub(crate) const WARNING_GAP: f64 = 1e-3;
/// The splits between two calls of a batch's `between` ([`search_batch`]): a split costs a
/// few microseconds, about what the solver takes between two whole-grid instants.
const SPLITS_BETWEEN: usize = 2;

/// The relative gap the searches at one point (the displacement at the impact point, each
/// support's stress) close: one dimension (time) makes it cheap to go to round-off's scale,
/// so that the maxima do not depend on which instants the run observed.
pub(crate) const POINT_TOLERANCE: f64 = 1e-10;

/// The most cells one search splits; past it the search stops and reports the gap it reached.
const MAX_SPLITS: usize = 400_000;

/// The most mode-values (a row or a state's q and v: one a mode each) one search makes, a
/// bound on its time and memory (2e7: 160 MB); with many modes (20000, a scene's most) it
/// stops sooner and reports the gap it reached.
const MAX_MODE_VALUES: usize = 20_000_000;

/// What a search may still spend: cells to split and mode-values to make. A search of many
/// batches (the stress's early search, `modal_stress.rs`) spends one budget over all of them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Budget {
    splits: usize,
    mode_values: usize,
}

impl Default for Budget {
    /// One search's: [`MAX_SPLITS`] and [`MAX_MODE_VALUES`].
    fn default() -> Self {
        Self { splits: MAX_SPLITS, mode_values: MAX_MODE_VALUES }
    }
}

/// A field at one point: value = F p + sum r_n q_n.
#[derive(Debug, Clone)]
pub(crate) struct Row {
    pub(crate) r: Vec<f64>,
    pub(crate) p: f64,
}

impl Row {
    pub(crate) fn value(&self, force: f64, q: &[f64]) -> f64 {
        force * self.p + hht::fast::dot(&self.r, q)
    }
}

/// What the bounds need of the modes, fixed for a run.
#[derive(Debug, Clone)]
pub(crate) struct ModeData {
    modes: PointModes,
    /// g / omega^2 (0 for a rigid-body mode) (m sqrt(kg)/N).
    static_q: Vec<f64>,
    /// 1 / omega (0 for a rigid-body mode) (s).
    inv_omega: Vec<f64>,
    /// The first elastic mode (the rigid-body modes, omega = 0, come first).
    elastic_from: usize,
}

impl ModeData {
    pub(crate) fn new(modes: PointModes) -> Self {
        let static_q = modes
            .omega()
            .iter()
            .zip(modes.gain())
            .map(|(w, g)| if *w > 0.0 { g / (w * w) } else { 0.0 })
            .collect();
        let inv_omega =
            modes.omega().iter().map(|w| if *w > 0.0 { 1.0 / w } else { 0.0 }).collect();
        let elastic_from = modes.omega().iter().take_while(|w| **w <= 0.0).count();
        Self { modes, static_q, inv_omega, elastic_from }
    }

    pub(crate) fn modes(&self) -> &PointModes {
        &self.modes
    }

    pub(crate) fn gain(&self) -> &[f64] {
        self.modes.gain()
    }

    /// Per-mode bounds over `stretch` from the state at its start, into `out` (inlined into
    /// [`PartKernel`]'s wider copy).
    #[inline(always)]
    fn bounds(&self, state: &ModalState, stretch: &Stretch, out: &mut ModeBounds) {
        let n = self.modes.len();
        out.q.resize(n, 0.0);
        out.acc.resize(n, 0.0);
        out.dev.resize(n, 0.0);
        // Every slice cut to n, so that the loop below runs without bounds checks.
        let (omega, zeta, gain) =
            (&self.modes.omega()[..n], &self.modes.damping_ratio()[..n], &self.modes.gain()[..n]);
        let (static_q, inv_omega) = (&self.static_q[..n], &self.inv_omega[..n]);
        let (state_q, state_v) = (&state.q[..n], &state.v[..n]);
        let (out_q, out_acc, out_dev) = (&mut out.q[..n], &mut out.acc[..n], &mut out.dev[..n]);
        let fmax = stretch.force_max;
        // A rigid-body mode: q'' = g F. It has no curvature, so the stress weighs its |q| and
        // |q - s F| by 0: they are left 0 here (its displacement is bounded through q'' only).
        let rigid = self.elastic_from.min(n);
        out_q[..rigid].fill(0.0);
        out_dev[..rigid].fill(0.0);
        for (acc, g) in out_acc[..rigid].iter_mut().zip(gain) {
            *acc = g.abs() * fmax;
        }
        // The elastic modes, in a loop without branches (the compiler vectorises it). The
        // amplitudes are the Euclidean ones of (q, v/omega): |q| + |v|/omega, what they were,
        // is up to sqrt(2) larger (4/pi on average over the phase).
        for k in rigid..n {
            let (w, z, g, s, iw) = (omega[k], zeta[k], gain[k], static_q[k], inv_omega[k]);
            let (q, v) = (state_q[k], state_v[k]);
            let vw = v * iw;
            let raw = (q * q + vw * vw).sqrt() + g.abs() * stretch.impulse * iw;
            let qs = q - s * stretch.force_start;
            let free =
                (qs * qs + vw * vw).sqrt() + (1.0 + 2.0 * z) * s.abs() * stretch.variation * iw;
            let dev = free + 2.0 * z * s.abs() * stretch.slope_max * iw;
            let bound = raw.min(s.abs() * fmax + dev);
            out_q[k] = bound;
            out_acc[k] = ((1.0 + 2.0 * z) * w * w * free)
                .min(g.abs() * fmax + (1.0 + 2.0 * z) * w * w * raw);
            out_dev[k] = dev.min(s.abs() * fmax + bound);
        }
    }
}

/// Per-mode bounds over a stretch: |q| <= q, |q''| <= acc, |q - s F| <= dev (a rigid-body
/// mode's q and dev are 0: see [`ModeData::bounds`]).
#[derive(Debug, Default)]
struct ModeBounds {
    q: Vec<f64>,
    acc: Vec<f64>,
    dev: Vec<f64>,
    /// The mode counts the sums are taken at (0, every 16 to 128, then an eighth more each, and
    /// all), and the sums of the stress's weights times q, acc and dev over the modes below
    /// each ([`cumulative`]).
    marks: Vec<usize>,
    q_sums: Vec<f64>,
    acc_sums: Vec<f64>,
    dev_sums: Vec<f64>,
}

/// Sum of w_n b_n over the modes whose weight is not zero (an infinite bound of a mode that
/// the weight ignores does not count).
#[inline(always)]
fn weighted(weights: &[f64], bounds: &[f64]) -> f64 {
    // In four partial sums, each term a select (vectorised; one chain of additions would be
    // bound by their latency).
    let term = |w: f64, b: f64| if w != 0.0 { w.abs() * b } else { 0.0 };
    let mut sums = [0.0; 4];
    let (ws, bs) = (weights.chunks_exact(4), bounds.chunks_exact(4));
    let tail: f64 = ws.remainder().iter().zip(bs.remainder()).map(|(w, b)| term(*w, *b)).sum();
    for (w, b) in ws.zip(bs) {
        for k in 0..4 {
            sums[k] += term(w[k], b[k]);
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

/// The sums of w_n b_n over the modes below each of `marks` (increasing), into `out`: each
/// segment between marks in four partial sums (the weights are not negative).
#[inline(always)]
fn cumulative(weights: &[f64], bounds: &[f64], marks: &[usize], out: &mut Vec<f64>) {
    out.clear();
    let (mut sum, mut from) = (0.0, 0);
    for &m in marks {
        sum += hht::fast::dot(&weights[from..m], &bounds[from..m]);
        out.push(sum);
        from = m;
    }
}

/// What bounds the modes over a stretch of piecewise-linear force.
#[derive(Debug, Clone, Copy, Default)]
struct Stretch {
    force_start: f64,
    force_max: f64,
    /// Upper bound of the integral of |F| (N s).
    impulse: f64,
    /// |first slope| + sum |change of slope| (N/s).
    variation: f64,
    slope_max: f64,
    length: f64,
    /// The largest |F - chord| over the stretch (N), the chord from its start to its end: F
    /// is linear between breakpoints, so at one of them. (It was bounded by how far F rose
    /// above the lower end, which missed F below the chord: a Hertz onset is convex.)
    off_chord: f64,
}

impl Stretch {
    /// The stretch from (t0, f0) through the pieces' ends.
    fn new(t0: f64, f0: f64, ends: &[(f64, f64)]) -> Self {
        let mut s = Self { force_start: f0, force_max: f0.abs(), ..Self::default() };
        let (mut t, mut f, mut slope) = (t0, f0, 0.0);
        for &(t1, f1) in ends {
            let h = t1 - t;
            let next = if h > 0.0 { (f1 - f) / h } else { 0.0 };
            s.variation += (next - slope).abs();
            s.slope_max = s.slope_max.max(next.abs());
            s.force_max = s.force_max.max(f1.abs());
            s.impulse += 0.5 * h * (f.abs() + f1.abs());
            (t, f, slope) = (t1, f1, next);
        }
        s.length = t - t0;
        s.off_chord = off_chord((t0, f0), (t, f), ends);
        s
    }
}

/// The largest |F - chord| at the breakpoints `inside` (t, F), the chord from `start` to `end`
/// (t, F): where a piecewise-linear force departs most from its chord.
fn off_chord(start: (f64, f64), end: (f64, f64), inside: &[(f64, f64)]) -> f64 {
    let length = end.0 - start.0;
    let slope = if length > 0.0 { (end.1 - start.1) / length } else { 0.0 };
    inside.iter().map(|&(t, f)| (f - (start.1 + slope * (t - start.0))).abs()).fold(0.0, f64::max)
}

/// An instant of a kept stretch: time, force, the modes (shared: a stretch's end is the
/// next one's start).
#[derive(Debug, Clone)]
struct Node {
    t: f64,
    force: f64,
    state: Arc<ModalState>,
}

/// A stretch of the run between two whole-grid instants, kept for the search.
#[derive(Debug, Clone)]
pub(crate) struct Block {
    f0: f64,
    /// (t, F) at the ends of the force's linear pieces (the last is the stretch's end).
    ends: Vec<(f64, f64)>,
    /// Its instants: the start and the end first, then those the search adds.
    nodes: Vec<Node>,
    /// Per field searched (stress, displacement, each support): the stretch's bound, and its
    /// bounds of the second derivatives in x and t.
    bounds: Vec<f64>,
    rates: Vec<(f64, f64)>,
    /// The field at the start and at the end: the stress of the first `low` modes at the
    /// grid's points (in the recovery's order; none where the stress's bound did not beat the
    /// largest stress seen when the stretch was kept), then the displacement and each
    /// support's stress (all modes).
    grid: Option<[Arc<Vec<f64>>; 2]>,
    values: [Vec<f64>; 2],
    /// The grid's modes, the other modes' largest stress over the stretch (Pa), and the
    /// second derivatives' bounds of the grid's modes' stress.
    low: usize,
    tail: f64,
    low_rates: (f64, f64),
}

/// A stretch's force pieces, from its start's force `f0`: a step ended at `t` with the force
/// `force`, the force linear since the last. Force-free steps in a row merge into one piece
/// (the propagation is exact).
pub(crate) fn push_end(ends: &mut Vec<(f64, f64)>, f0: f64, (t, force): (f64, f64)) {
    let start_of_last = ends.len().checked_sub(2).map_or(f0, |k| ends[k].1);
    let merge =
        force == 0.0 && ends.last().is_some_and(|last| last.1 == 0.0) && start_of_last == 0.0;
    match ends.last_mut() {
        Some(last) if merge => last.0 = t,
        _ => ends.push((t, force)),
    }
}

/// What a closed stretch tells of the modes' share, for the next, at one candidate count of
/// modes K.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Share {
    pub(crate) modes: usize,
    /// The bound of the stress of the modes from K on (Pa).
    pub(crate) tail: f64,
    /// The bounds of the second time and space derivatives of the stress of the modes below K
    /// (Pa/s^2, Pa/m^2).
    pub(crate) tt: f64,
    pub(crate) xx: f64,
}

/// [`Share`]s at the candidate counts of modes (see [`ModePart::make`]) and all of them.
pub(crate) type Shares = Vec<Share>;

/// The run as stretches between whole-grid instants: the one being observed and those kept.
pub(crate) struct Trajectory {
    /// The open stretch: its start (t, F, state), its pieces' ends, the field at its start
    /// (the grid's of the first `low` modes).
    start: Node,
    ends: Vec<(f64, f64)>,
    grid: Arc<Vec<f64>>,
    values: Vec<f64>,
    low: usize,
    pub(crate) kept: Vec<Block>,
    /// The kept blocks' count at the last pruning.
    pruned_at: usize,
}

/// What the bounds weigh the modes with (fixed for a run; the solver's thread and the watch's
/// share them).
#[derive(Debug)]
pub(crate) struct Weights {
    /// max |E h/2 c_n(x)| and max |E h/2 c_n''(x)| over the beam (Pa per unit q, Pa/m^2 per
    /// unit q).
    pub(crate) stress: Vec<f64>,
    pub(crate) stress2: Vec<f64>,
    /// Whether the stress is by the mode-acceleration form (its f_xx from q - s F).
    pub(crate) mode_acceleration: bool,
    /// The largest spacing of the grid the stress is observed on (m).
    pub(crate) spacing: f64,
    /// The stress's correction term's largest magnitude over the beam, E h/2 max|corr| (Pa/N).
    pub(crate) correction: f64,
    /// The displacement row (g) and its force term (the residual flexibility).
    pub(crate) displacement: Row,
    /// Each support's stress row, then the one-point fields' rows (an off-centre strike's).
    pub(crate) supports: Vec<Row>,
    /// How many of `supports` are supports.
    pub(crate) support_count: usize,
}

impl Trajectory {
    /// Starts at rest, at t = 0, with `n` modes.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            start: Node { t: 0.0, force: 0.0, state: Arc::new(ModalState::at_rest(n)) },
            ends: Vec::new(),
            grid: Arc::default(),
            values: Vec::new(),
            low: n,
            kept: Vec::new(),
            pruned_at: 0,
        }
    }

    /// A step of the run ended at `t` with the force `force`: the force was linear since the
    /// last. Force-free steps in a row merge into one piece (the propagation is exact).
    pub(crate) fn step(&mut self, t: f64, force: f64) {
        push_end(&mut self.ends, self.start.force, (t, force));
    }

    /// Closes the open stretch at a whole-grid instant (time `t`, `force`, the modes `q`,
    /// `v`), with the stress of the first `low` modes on the grid there (`grid`, the same
    /// count as at the stretch's start) and `values` (the displacement, then each support's
    /// stress), and `part`, what its bounds take from the modes alone ([`ModePart::make`] from
    /// this stretch's start and pieces; read only for a stretch after its start with pieces);
    /// keeps it if any of its bounds beats `best` (the largest stress magnitude, displacement
    /// and supports' stress magnitudes seen). Returns the stretch's [`Shares`] (empty for an
    /// empty stretch).
    pub(crate) fn observe(
        &mut self,
        part: &ModePart,
        weights: &Weights,
        now: (f64, f64, &[f64], &[f64]),
        (grid, values): (&[f64], &[f64]),
        best: &[f64],
    ) -> Shares {
        let (t, force, q, v) = now;
        let mut shares = Vec::new();
        let (mut kept, mut kept_grid) = (false, false);
        if t > self.start.t && !self.ends.is_empty() && self.grid.len() == grid.len() {
            // The part must be this stretch's (the solver's copy of the open stretch and this
            // one are kept alike: `ModalStress`).
            debug_assert_eq!(part.made_for, Some((self.start.t, self.ends.len())));
            let span = self.span(part, weights, grid, values);
            shares = span.shares;
            if span.bounds.iter().zip(best).any(|(b, best)| b > best) {
                // The end's state (and grid) are the next stretch's start's: made once, shared.
                // A stretch kept for the displacement or a support only keeps no grid: the
                // stress's search passes it by (its stress bound is below the largest stress
                // seen, which the search only raises). A displacement that rises through the
                // window keeps nearly every stretch for a while: most kept stretches are such.
                kept = true;
                let end = Arc::new(ModalState { q: q.to_vec(), v: v.to_vec() });
                let start = std::mem::replace(&mut self.start.state, end.clone());
                let grids = (span.bounds[0] > best[0]).then(|| {
                    let end_grid = Arc::new(grid.to_vec());
                    [std::mem::replace(&mut self.grid, end_grid.clone()), end_grid]
                });
                kept_grid = grids.is_some();
                self.kept.push(Block {
                    f0: self.start.force,
                    // Taken, not copied: the open stretch's pieces start afresh below.
                    ends: std::mem::take(&mut self.ends),
                    nodes: vec![Node { state: start, ..self.start }, Node { t, force, state: end }],
                    bounds: span.bounds,
                    rates: span.rates,
                    grid: grids,
                    values: [std::mem::take(&mut self.values), values.to_vec()],
                    low: self.low,
                    tail: span.tail,
                    low_rates: span.low_rates,
                });
                if self.kept.len() >= 2 * self.pruned_at + 64 {
                    self.kept.retain(|b| b.wanted(best));
                    self.pruned_at = self.kept.len();
                }
            }
        }
        self.start.t = t;
        self.start.force = force;
        if !kept {
            set_shared(&mut self.start.state, |s| copy_state(s, q, v));
        }
        if !kept_grid {
            set_shared(&mut self.grid, |g| {
                g.clear();
                g.extend_from_slice(grid);
            });
        }
        self.ends.clear();
        self.values.clear();
        self.values.extend_from_slice(values);
        shares
    }

    /// The open stretch's grid at its start, of the first `low` modes (when the next stretch
    /// observes another count than the one just closed).
    pub(crate) fn regrid(&mut self, grid: &[f64], low: usize) {
        self.grid = Arc::new(grid.to_vec());
        self.low = low;
    }

    /// The open stretch's bounds (stress, displacement, supports): the larger end plus what
    /// the second derivatives allow between grid points and instants, plus how far the force's
    /// term can depart from its chord (the stress's also plus the bound of the modes the grid
    /// left out, and capped by the triangle bound over the modes); per field, its bounds of the
    /// second derivatives in x and t; and the modes' shares. From `part`, what they take from
    /// the modes alone (made where the stretch closes, [`ModePart::make`]), and the grid and
    /// values at the stretch's two ends.
    fn span(&self, part: &ModePart, weights: &Weights, grid: &[f64], values: &[f64]) -> Span {
        let (b, stretch) = (&part.bounds, &part.stretch);
        let n = b.q.len();
        let at = |sums: &[f64], k: usize| {
            b.marks.iter().position(|m| *m == k).map_or(f64::INFINITY, |i| sums[i])
        };
        let (q_sums, acc_sums, xx_sums) = (&b.q_sums[..], &b.acc_sums[..], &b.dev_sums[..]);
        let reach = stretch.length * stretch.length / 8.0;
        let largest = hht::fast::largest_magnitude;
        let low = self.low.min(n);
        let tail = at(q_sums, n) - at(q_sums, low);
        let (xx, tt) = (at(xx_sums, n), at(acc_sums, n));
        let low_rates = (at(xx_sums, low), at(acc_sums, low));
        let triangle = stretch.force_max * weights.correction + at(q_sums, n);
        let on_grid = largest(&self.grid).max(largest(grid))
            + weights.spacing * weights.spacing / 8.0 * low_rates.0
            + reach * low_rates.1
            + weights.correction * stretch.off_chord
            + tail;
        let mut bounds = vec![on_grid.min(triangle)];
        let mut rates = vec![(xx, tt)];
        let d = &weights.displacement;
        let w =
            (self.values.first().copied().unwrap_or(0.0), values.first().copied().unwrap_or(0.0));
        bounds.push(w.0.max(w.1) + reach * part.dtt + d.p.abs() * stretch.off_chord);
        rates.push((0.0, part.dtt));
        for (k, (row, &stt)) in weights.supports.iter().zip(&part.stt).enumerate() {
            let ends = (
                self.values.get(1 + k).copied().unwrap_or(0.0),
                values.get(1 + k).copied().unwrap_or(0.0),
            );
            bounds.push(
                ends.0.abs().max(ends.1.abs()) + reach * stt + row.p.abs() * stretch.off_chord,
            );
            rates.push((0.0, stt));
        }
        // Each candidate count's share.
        let shares = b.marks[1..]
            .iter()
            .zip(&q_sums[1..])
            .zip(acc_sums[1..].iter().zip(&xx_sums[1..]))
            .map(|((&k, q), (acc, xx))| Share {
                modes: k,
                tail: at(q_sums, n) - q,
                tt: *acc,
                xx: *xx,
            })
            .collect();
        Span { bounds, rates, tail, low_rates, shares }
    }
}

/// What a stretch's bounds take from the modes alone, from its start's state and its force's
/// pieces, not from its grid or values: made by the solver's thread while the watch's
/// observes the grid (`ModalStress`), then finished by [`Trajectory::observe`].
#[derive(Debug, Default)]
pub(crate) struct ModePart {
    /// The stretch it was made for: its start (s) and pieces' count (`None`: not made).
    made_for: Option<(f64, usize)>,
    stretch: Stretch,
    /// The per-mode bounds and their weighted sums at the candidate counts.
    bounds: ModeBounds,
    /// The displacement's and each support's (and one-point field's) bound of the second time
    /// derivative over the stretch.
    dtt: f64,
    stt: Vec<f64>,
}

impl ModePart {
    /// The part of the stretch from `start` (t (s), F (N), the modes' state) through `ends`
    /// (the pieces as [`push_end`] makes them). Compiled for the processor's widest vectors
    /// (separate multiplies and adds in every copy, so the bounds are the same to the bit).
    pub(crate) fn make(
        &mut self,
        data: &ModeData,
        weights: &Weights,
        start: (f64, f64, &ModalState),
        ends: &[(f64, f64)],
    ) {
        hht::fast::run(PartKernel { part: self, data, weights, start, ends });
    }

    /// Not made (for a stretch the watch does not bound).
    pub(crate) fn clear(&mut self) {
        self.made_for = None;
    }

    /// [`Self::make`]'s body.
    #[inline(always)]
    fn make_inline(
        &mut self,
        data: &ModeData,
        weights: &Weights,
        (t0, f0, state): (f64, f64, &ModalState),
        ends: &[(f64, f64)],
    ) {
        self.made_for = Some((t0, ends.len()));
        self.stretch = Stretch::new(t0, f0, ends);
        data.bounds(state, &self.stretch, &mut self.bounds);
        let b = &mut self.bounds;
        let n = b.q.len();
        // Candidate counts: every 16 modes, an eighth more each past 128, and all (the
        // stretch's own among them).
        b.marks.clear();
        b.marks.push(0);
        let mut k = 16;
        while k < n {
            b.marks.push(k);
            k = (k + 16).max(k + k / 8);
        }
        b.marks.push(n);
        let marks = &b.marks;
        cumulative(&weights.stress, &b.q, marks, &mut b.q_sums);
        cumulative(&weights.stress, &b.acc, marks, &mut b.acc_sums);
        let dev = if weights.mode_acceleration { &b.dev } else { &b.q };
        cumulative(&weights.stress2, dev, marks, &mut b.dev_sums);
        self.dtt = weighted(&weights.displacement.r, &b.acc);
        self.stt.clear();
        self.stt.extend(weights.supports.iter().map(|row| weighted(&row.r, &b.acc)));
    }
}

/// [`ModePart::make`] as a [`hht::fast::Kernel`].
struct PartKernel<'a> {
    part: &'a mut ModePart,
    data: &'a ModeData,
    weights: &'a Weights,
    start: (f64, f64, &'a ModalState),
    ends: &'a [(f64, f64)],
}

impl hht::fast::Kernel for PartKernel<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        let Self { part, data, weights, start, ends } = self;
        part.make_inline(data, weights, start, ends);
    }
}

/// A closed stretch's bounds (see [`Trajectory::span`]).
struct Span {
    bounds: Vec<f64>,
    rates: Vec<(f64, f64)>,
    tail: f64,
    low_rates: (f64, f64),
    shares: Shares,
}

/// A maximum found: its value (signed), where (m) and when (s), and the gap left: no value of
/// the field exceeds `bound` (in magnitude, or in value for a signed search).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Peak {
    pub(crate) value: f64,
    pub(crate) x: f64,
    pub(crate) t: f64,
    pub(crate) bound: f64,
}

/// What a search looks for.
pub(crate) enum Field<'a> {
    /// The largest value of one point's field (the displacement at the impact point, the
    /// blocks' value 0), at x.
    Signed(&'a Row, f64),
    /// The largest magnitude of one point's field (support `k`'s stress, the blocks' value
    /// 1 + k), at x, certified to [`POINT_TOLERANCE`] of itself or to below a floor, whichever
    /// is larger: a value below the floor need not be told apart from the floor (a support's
    /// stress, a section's torsion shear: [`FLOOR_SHARE`] of the largest of its kind; 0 for
    /// none).
    Magnitude(&'a Row, f64, usize, f64),
    /// The largest stress magnitude over the beam.
    Stress(&'a StressField<'a>),
}

/// The stress over the beam, for the search: its grid's points and rows, a row anywhere.
pub(crate) struct StressField<'a> {
    /// The grid's points (m) in the recovery's order (that of the blocks' grids), with the
    /// supports and the impact point among them (where the static moment has its kinks).
    points: &'a [f64],
    /// Their rows (same order).
    rows: &'a [Row],
    /// The row at any x.
    row_at: &'a dyn Fn(f64) -> Row,
    /// The stress's correction term's largest magnitude over the beam (Pa/N).
    correction: f64,
    /// The points in order along the beam and each point's row.
    grid: &'a GridOrder,
}

impl<'a> StressField<'a> {
    /// The field of the grid's `points` (in the order `grid` was made from) and their `rows`,
    /// `row_at` elsewhere; `correction` as [`StressField::correction`].
    pub(crate) fn new(
        (points, grid): (&'a [f64], &'a GridOrder),
        rows: &'a [Row],
        row_at: &'a dyn Fn(f64) -> Row,
        correction: f64,
    ) -> Self {
        Self { points, rows, row_at, correction, grid }
    }
}

/// A grid's points in order along the beam, each once, and each point's row: made once for
/// every search of the field (the early search runs one a batch).
#[derive(Debug, Clone)]
pub(crate) struct GridOrder {
    order: Vec<usize>,
    index: HashMap<u64, u32>,
}

impl GridOrder {
    pub(crate) fn new(points: &[f64]) -> Self {
        let mut order: Vec<usize> = (0..points.len()).collect();
        order.sort_by(|a, b| points[*a].total_cmp(&points[*b]));
        order.dedup_by(|a, b| points[*a].to_bits() == points[*b].to_bits());
        let mut index = HashMap::with_capacity(points.len());
        for (k, x) in points.iter().enumerate() {
            index.insert(x.to_bits(), k as u32);
        }
        Self { order, index }
    }
}

/// A cell of the search: a rectangle of x (rows xa, xb) and t (nodes ta, tb of a block),
/// with its field values at the corners (xa, ta), (xb, ta), (xa, tb), (xb, tb).
#[derive(Debug, Clone, Copy)]
struct Cell {
    bound: f64,
    /// Whether the corners hold the whole field (else the grid's modes' only, see [`Block`]).
    full: bool,
    block: u32,
    xa: u32,
    xb: u32,
    ta: u32,
    tb: u32,
    corners: [f64; 4],
}

impl PartialEq for Cell {
    fn eq(&self, other: &Self) -> bool {
        self.bound.total_cmp(&other.bound).is_eq()
    }
}
impl Eq for Cell {}
impl PartialOrd for Cell {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Cell {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.bound.total_cmp(&other.bound)
    }
}

/// One search over the kept stretches.
struct Search<'a> {
    data: &'a ModeData,
    blocks: &'a mut [Block],
    field: &'a Field<'a>,
    /// Which of a block's bounds is this search's.
    slot: usize,
    /// Rows by index: the field's own (the grid's, for the stress; the point's otherwise),
    /// borrowed, then those the search made; their x, and the index of each x.
    base: &'a [Row],
    rows: Vec<Row>,
    xs: Vec<f64>,
    row_of: HashMap<u64, u32>,
    /// Exact steps by length, for the instants a split adds.
    stepper: &'a mut Stepper,
    best: Peak,
    /// The largest bound of a cell that could not be split further.
    stuck: f64,
    /// The instants this search added to the blocks (its budget counts its own).
    nodes_made: usize,
}

/// Exact steps of the modes by length, each built once (a sine and a cosine per mode): the
/// force's pieces come from the solver's few step lengths, so a replay reuses them.
#[derive(Default)]
pub(crate) struct Stepper {
    steps: HashMap<u64, OneStep>,
}

impl Stepper {
    /// Advances `state` by tau with the force linear from f0 to f1; a failure (a non-finite
    /// step) leaves the state as it was.
    fn advance(&mut self, modes: &PointModes, state: &mut ModalState, tau: f64, f0: f64, f1: f64) {
        if tau > 0.0 {
            let step = self.steps.entry(tau.to_bits()).or_default();
            if step.step_size().to_bits() != tau.to_bits() && modes.one_step(tau, step).is_err() {
                return;
            }
            step.advance_state(modes, state, f0, f1);
        }
    }
}

/// The modes at time t in a kept block (q, v), with the force there, its slope, and the
/// force's linear piece around t (s, s), by exact steps from the latest instant the block
/// holds before t; `None` if no kept block holds t.
pub(crate) fn state_at(
    data: &ModeData,
    blocks: &[Block],
    t: f64,
    stepper: &mut Stepper,
) -> Option<(ModalState, f64, f64, (f64, f64))> {
    let b = blocks.iter().find(|b| b.nodes[0].t <= t && t <= b.nodes[1].t)?;
    let (node, slope, piece) = b.at(t, &data.modes, stepper);
    let state = Arc::unwrap_or_clone(node.state);
    state.q.iter().all(|q| q.is_finite()).then_some((state, node.force, slope, piece))
}

impl Block {
    /// Whether a search may find more in it than `best` (per field: the stress, the
    /// displacement, each support's stress, the one-point fields').
    pub(crate) fn wanted(&self, best: &[f64]) -> bool {
        self.bounds.iter().zip(best).any(|(b, best)| b > best)
    }

    /// When it starts (s).
    pub(crate) fn start(&self) -> f64 {
        self.nodes[0].t
    }

    /// Whether the stress's search may find more in it than `best` (it kept its grid).
    pub(crate) fn stress_wanted(&self, best: f64) -> bool {
        self.grid.is_some() && self.bounds[0] > best
    }

    /// The block at time t (within it): its modes by exact steps from the latest instant it
    /// holds before t through the force's breakpoints in between, with the force's slope at t
    /// and its linear piece around t (s, s).
    fn at(&self, t: f64, modes: &PointModes, stepper: &mut Stepper) -> (Node, f64, (f64, f64)) {
        let start = self
            .nodes
            .iter()
            .filter(|n| n.t <= t)
            .max_by(|a, c| a.t.total_cmp(&c.t))
            .unwrap_or(&self.nodes[0]);
        let mut state = ModalState::clone(&start.state);
        let (mut time, mut force) = (start.t, start.force);
        // The force at t: linear on the piece that ends first at or after t (the pieces found
        // by bisection: a long contact's stretch holds thousands).
        let k = self.ends.partition_point(|e| e.0 < t);
        let (mut at_t, mut slope, mut piece) = (self.f0, 0.0, (t, t));
        if let Some(&(te, fe)) = self.ends.get(k) {
            let previous = k.checked_sub(1).map_or((self.nodes[0].t, self.f0), |j| self.ends[j]);
            let span = te - previous.0;
            (slope, at_t) = if span > 0.0 {
                let slope = (fe - previous.1) / span;
                (slope, previous.1 + slope * (t - previous.0))
            } else {
                (0.0, fe)
            };
            piece = (previous.0, te);
        }
        let first = self.ends.partition_point(|e| e.0 <= time);
        let stops = self.ends[first..k.max(first)].iter().copied().chain([(t, at_t)]);
        for (te, fe) in stops {
            stepper.advance(modes, &mut state, te - time, force, fe);
            (time, force) = (te, fe);
        }
        (Node { t, force, state: Arc::new(state) }, slope, piece)
    }
}

/// `state` set to `q`, `v` (in its own memory).
pub(crate) fn copy_state(state: &mut ModalState, q: &[f64], v: &[f64]) {
    for (to, from) in [(&mut state.q, q), (&mut state.v, v)] {
        to.clear();
        to.extend_from_slice(from);
    }
}

/// Sets a shared value by `set` (which overwrites all of it): in place when nothing else holds
/// it, else on a new one (the shared one stays as it was).
fn set_shared<T: Default>(shared: &mut Arc<T>, set: impl FnOnce(&mut T)) {
    match Arc::get_mut(shared) {
        Some(value) => set(value),
        None => {
            let mut value = T::default();
            set(&mut value);
            *shared = Arc::new(value);
        }
    }
}

/// The largest of `field` over the kept `blocks`, starting from `best` (a value the run
/// observed, which the search only raises).
pub(crate) fn search(data: &ModeData, blocks: &mut [Block], field: &Field<'_>, best: Peak) -> Peak {
    let work = (&mut Stepper::default(), &mut Budget::default());
    search_batch(data, blocks, field, best, work, &mut || {})
}

/// [`search`] with the exact steps of `stepper` and what is left of `budget`, which it
/// spends: a search of many batches keeps both (the same step lengths recur, and a step's
/// values are its length's alone; the budget bounds all the batches together). `between` is
/// called every [`SPLITS_BETWEEN`] splits (it must not touch the search's blocks).
pub(crate) fn search_batch(
    data: &ModeData,
    blocks: &mut [Block],
    field: &Field<'_>,
    best: Peak,
    (stepper, budget): (&mut Stepper, &mut Budget),
    between: &mut dyn FnMut(),
) -> Peak {
    let slot = match field {
        Field::Stress(_) => 0,
        Field::Signed(..) => 1,
        Field::Magnitude(_, _, k, _) => 2 + k,
    };
    let before: Vec<usize> = blocks.iter().map(|b| b.nodes.len()).collect();
    let mut s = Search {
        data,
        blocks: &mut *blocks,
        field,
        slot,
        base: match field {
            Field::Signed(row, _) | Field::Magnitude(row, ..) => std::slice::from_ref(*row),
            Field::Stress(f) => f.rows,
        },
        rows: Vec::new(),
        xs: Vec::new(),
        row_of: HashMap::new(),
        stepper,
        best,
        stuck: f64::NEG_INFINITY,
        nodes_made: 0,
    };
    let peak = s.run(budget, between);
    // A one-point search's instants go with it: each has its own budget, and the memory
    // they hold stays that of the stress's search plus one other.
    if !matches!(field, Field::Stress(_)) {
        for (b, &count) in blocks.iter_mut().zip(&before) {
            b.nodes.truncate(count);
        }
    }
    peak
}

impl Search<'_> {
    fn signed(&self) -> bool {
        matches!(self.field, Field::Signed(..))
    }

    /// What the search maximises of a value.
    fn measure(&self, v: f64) -> f64 {
        if self.signed() {
            v
        } else {
            v.abs()
        }
    }

    fn target(&self) -> f64 {
        let b = self.measure(self.best.value);
        let tolerance = match self.field {
            Field::Stress(_) => PEAK_TOLERANCE,
            _ => POINT_TOLERANCE,
        };
        (b + tolerance * b.abs().max(f64::MIN_POSITIVE)).max(self.floor())
    }

    /// The floor a search need not tell values below apart from (see [`Field::Magnitude`]).
    fn floor(&self) -> f64 {
        match self.field {
            Field::Magnitude(.., floor) => *floor,
            _ => 0.0,
        }
    }

    fn offer(&mut self, value: f64, x: f64, t: f64) {
        if self.measure(value) > self.measure(self.best.value) {
            (self.best.value, self.best.x, self.best.t) = (value, x, t);
        }
    }

    fn run(&mut self, budget: &mut Budget, between: &mut dyn FnMut()) -> Peak {
        let mut heap = BinaryHeap::new();
        match self.field {
            Field::Signed(_, x) | Field::Magnitude(_, x, ..) => {
                self.xs.push(*x);
                let value = self.slot - 1;
                for k in 0..self.blocks.len() {
                    let b = &self.blocks[k];
                    let (va, vb) = (b.values[0][value], b.values[1][value]);
                    let cell = Cell {
                        bound: 0.0,
                        full: true,
                        block: k as u32,
                        xa: 0,
                        xb: 0,
                        ta: 0,
                        tb: 1,
                        corners: [va, va, vb, vb],
                    };
                    self.push(cell, &mut heap);
                }
            }
            Field::Stress(f) => {
                let order = &f.grid.order;
                self.xs.extend_from_slice(f.points);
                for k in 0..self.blocks.len() {
                    let target = self.target();
                    if self.blocks[k].bounds[0] <= target {
                        continue;
                    }
                    let b = &self.blocks[k];
                    // A block kept without its grid has a stress bound below the largest
                    // stress seen then, so below the target: not reached.
                    let Some(grid) = &b.grid else { continue };
                    let full = b.low >= f.rows[0].r.len();
                    let (xx, in_time) = self.time_terms(k as u32, full, (0, 1));
                    for pair in order.windows(2) {
                        let (i, j) = (pair[0], pair[1]);
                        let corners = [grid[0][i], grid[0][j], grid[1][i], grid[1][j]];
                        let hx = f.points[j] - f.points[i];
                        let bound = self.bound_of(&corners, hx, (xx, in_time));
                        if bound > target {
                            let (xa, xb) = (i as u32, j as u32);
                            let block = k as u32;
                            let cell = Cell { bound, full, block, xa, xb, ta: 0, tb: 1, corners };
                            heap.push(cell);
                        }
                    }
                }
            }
        }
        let mut splits = 0;
        let mut left = f64::NEG_INFINITY;
        // Mode-values: the field's own rows count against each search's budget (as when they
        // were copied into it), what it makes (rows, instants' q and v) against the budget
        // left, which the batches of one search share.
        let width = self.base.first().map_or(1, |r| r.r.len().max(1));
        let made = |s: &Self| (s.rows.len() + 2 * s.nodes_made) * width;
        let own = self.base.len() * width;
        while let Some(cell) = heap.pop() {
            let over = splits >= budget.splits || own + made(self) >= budget.mode_values;
            if cell.bound <= self.target() || over {
                left = cell.bound;
                break;
            }
            splits += 1;
            if splits % SPLITS_BETWEEN == 0 {
                between();
            }
            if cell.full {
                self.split(&cell, &mut heap);
            } else {
                // The grid's modes only at its corners: the whole field there, then back in.
                let corners = [
                    (cell.xa, cell.ta),
                    (cell.xb, cell.ta),
                    (cell.xa, cell.tb),
                    (cell.xb, cell.tb),
                ]
                .map(|(x, t)| self.value(x, cell.block, t));
                self.push(Cell { full: true, corners, ..cell }, &mut heap);
            }
        }
        budget.splits = budget.splits.saturating_sub(splits);
        budget.mode_values = budget.mode_values.saturating_sub(made(self));
        let reached = self.measure(self.best.value);
        // Cells below the floor were dropped unsearched: the floor is then what is certain.
        let floor = self.floor();
        let dropped = if self.target() <= floor { floor } else { f64::NEG_INFINITY };
        self.best.bound = reached.max(left).max(self.stuck).max(dropped);
        self.best
    }

    /// Pushes `cell` with its bound, unless that cannot beat the best.
    fn push(&mut self, mut cell: Cell, heap: &mut BinaryHeap<Cell>) {
        cell.bound = self.cell_bound(&cell);
        if cell.bound > self.target() {
            heap.push(cell);
        }
    }

    /// The largest corner, plus what the second derivatives allow inside, plus how far the
    /// force's term can depart from its chord where the cell holds a change of slope.
    fn cell_bound(&self, c: &Cell) -> f64 {
        let hx = self.xs[c.xb as usize] - self.xs[c.xa as usize];
        self.bound_of(&c.corners, hx, self.time_terms(c.block, c.full, (c.ta, c.tb)))
    }

    /// [`Self::cell_bound`] from a cell's corners, its width `hx` (m) and its block's
    /// [`Self::time_terms`].
    fn bound_of(&self, corners: &[f64; 4], hx: f64, (xx, in_time): (f64, f64)) -> f64 {
        let largest = corners.iter().map(|v| self.measure(*v)).fold(f64::NEG_INFINITY, f64::max);
        largest + hx * hx / 8.0 * xx + in_time
    }

    /// What a cell of `block` between its nodes `ta` and `tb` adds to its largest corner
    /// besides the space term: the time term, how far the force's term departs from its
    /// chord where the cell holds a change of slope, and (a cell of the grid's modes only) the
    /// other modes' bound; with the space term's rate (the same for every cell of a block between two
    /// nodes, so seeding a block's cells takes it once).
    fn time_terms(&self, block: u32, full: bool, (ta, tb): (u32, u32)) -> (f64, f64) {
        let b = &self.blocks[block as usize];
        let ((xx, tt), tail) = if full { (b.rates[self.slot], 0.0) } else { (b.low_rates, b.tail) };
        let (na, nb) = (&b.nodes[ta as usize], &b.nodes[tb as usize]);
        let ht = nb.t - na.t;
        // How far the force departs from its chord over the cell: F is linear between its
        // breakpoints, so at one of those strictly inside (ta, tb) (the ends are in time order).
        let first = b.ends.partition_point(|e| e.0 <= na.t);
        let last = b.ends.partition_point(|e| e.0 < nb.t);
        let inside = &b.ends[first..last.max(first)];
        let off_chord = off_chord((na.t, na.force), (nb.t, nb.force), inside);
        let force_term = match self.field {
            Field::Signed(row, _) | Field::Magnitude(row, ..) => row.p.abs(),
            Field::Stress(f) => f.correction,
        };
        (xx, ht * ht / 8.0 * tt + force_term * off_chord + tail)
    }

    /// The field at row `row` and node `node` of `block`.
    fn value(&self, row: u32, block: u32, node: u32) -> f64 {
        let n = &self.blocks[block as usize].nodes[node as usize];
        self.row_at(row).value(n.force, &n.state.q)
    }

    /// How many rows: the field's own and those made.
    fn row_count(&self) -> usize {
        self.base.len() + self.rows.len()
    }

    /// Row `k`: the field's own first, then those made.
    fn row_at(&self, k: u32) -> &Row {
        let k = k as usize;
        self.base.get(k).unwrap_or_else(|| &self.rows[k - self.base.len()])
    }

    /// The row at x, made once.
    fn row(&mut self, x: f64) -> u32 {
        let known = match self.field {
            Field::Stress(f) => f.grid.index.get(&x.to_bits()),
            _ => None,
        };
        if let Some(k) = known.or_else(|| self.row_of.get(&x.to_bits())) {
            return *k;
        }
        let row = match self.field {
            Field::Stress(f) => (f.row_at)(x),
            _ => self.base[0].clone(),
        };
        let k = self.row_count() as u32;
        self.rows.push(row);
        self.xs.push(x);
        self.row_of.insert(x.to_bits(), k);
        k
    }

    /// A node of `block` at time t: exact steps from the latest node before it through the
    /// force's breakpoints in between.
    fn node(&mut self, block: u32, t: f64) -> u32 {
        let b = &mut self.blocks[block as usize];
        if let Some(k) = b.nodes.iter().position(|n| n.t.to_bits() == t.to_bits()) {
            return k as u32;
        }
        let (node, ..) = b.at(t, &self.data.modes, self.stepper);
        b.nodes.push(node);
        self.nodes_made += 1;
        (b.nodes.len() - 1) as u32
    }

    /// Where a cell of `block` between ta and tb is split in time: at the end of one of the
    /// force's pieces in its middle half, the one nearest its middle, else at its middle. A
    /// node at a piece's end is reached by whole pieces, whose exact steps the solver's few
    /// step lengths make once for the whole search, where a node inside a piece needs a step
    /// of its own length (a sine and a cosine a mode) there and from there on (the paper's tip
    /// at 256 modes: its first contact 19.7 -> 15.4 ms, one run each; over 5 ms 23.9 -> 22.3
    /// ms, medians of 15 interleaved runs).
    fn split_time(&self, block: u32, (ta, tb): (f64, f64)) -> f64 {
        let (tm, quarter) = (0.5 * (ta + tb), 0.25 * (tb - ta));
        let ends = &self.blocks[block as usize].ends;
        let after = ends.partition_point(|e| e.0 < tm);
        [after.checked_sub(1), Some(after)]
            .into_iter()
            .flatten()
            .filter_map(|k| ends.get(k).map(|e| e.0))
            .filter(|t| (t - tm).abs() <= quarter && *t > ta && *t < tb)
            .min_by(|a, b| (a - tm).abs().total_cmp(&(b - tm).abs()))
            .unwrap_or(tm)
    }

    fn split(&mut self, c: &Cell, heap: &mut BinaryHeap<Cell>) {
        let (xx, tt) = self.blocks[c.block as usize].rates[self.slot];
        let (xa, xb) = (self.xs[c.xa as usize], self.xs[c.xb as usize]);
        let nodes = &self.blocks[c.block as usize].nodes;
        let (ta, tb) = (nodes[c.ta as usize].t, nodes[c.tb as usize].t);
        let x_term = (xb - xa) * (xb - xa) / 8.0 * xx;
        let t_term = (tb - ta) * (tb - ta) / 8.0 * tt;
        let (xm, tm) = (0.5 * (xa + xb), 0.5 * (ta + tb));
        let [aa, ba, ab, bb] = c.corners;
        if x_term >= t_term && xm > xa && xm < xb {
            let m = self.row(xm);
            let (va, vb) = (self.value(m, c.block, c.ta), self.value(m, c.block, c.tb));
            self.offer(va, xm, ta);
            self.offer(vb, xm, tb);
            self.push(Cell { xb: m, corners: [aa, va, ab, vb], ..*c }, heap);
            self.push(Cell { xa: m, corners: [va, ba, vb, bb], ..*c }, heap);
        } else if tm > ta && tm < tb {
            let tm = self.split_time(c.block, (ta, tb));
            let m = self.node(c.block, tm);
            let (va, vb) = (self.value(c.xa, c.block, m), self.value(c.xb, c.block, m));
            self.offer(va, xa, tm);
            self.offer(vb, xb, tm);
            self.push(Cell { tb: m, corners: [aa, ba, va, vb], ..*c }, heap);
            self.push(Cell { ta: m, corners: [va, vb, ab, bb], ..*c }, heap);
        } else {
            // Too small to split in floating point: its bound stands as what is left.
            self.stuck = self.stuck.max(c.bound);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::float_cmp)] // exact in binary: small integers
    fn the_force_departs_from_its_chord_below_it_too() {
        // A convex stretch (a Hertz onset): 0 -> 1 -> 10 N over 2 s sits 4 N below its chord
        // at t = 1 s, where the rise above the lower end, 1 N, is what the cells counted.
        assert_eq!(off_chord((0.0, 0.0), (2.0, 10.0), &[(1.0, 1.0)]), 4.0);
        // A concave one sits above it: 0 -> 9 -> 10 N, 4 N above.
        assert_eq!(off_chord((0.0, 0.0), (2.0, 10.0), &[(1.0, 9.0)]), 4.0);
        // The stretch's, from its start through its pieces' ends to the last.
        let s = Stretch::new(0.0, 0.0, &[(1.0, 1.0), (2.0, 10.0)]);
        assert_eq!(s.off_chord, 4.0);
        assert_eq!(off_chord((0.0, 3.0), (1.0, 3.0), &[]), 0.0);
    }

    /// The modes' states every `tau / substeps` through a force linear between (0, f0) and
    /// the `ends`, by the modal crate's exact steps, each handed to `check` with its force.
    fn walk(
        modes: &PointModes,
        mut state: ModalState,
        (f0, ends): (f64, &[(f64, f64)]),
        substeps: usize,
        mut check: impl FnMut(&ModalState, f64),
    ) {
        let mut step = OneStep::default();
        let (mut t, mut f) = (0.0, f0);
        for &(t1, f1) in ends {
            let h = (t1 - t) / substeps as f64;
            modes.one_step(h, &mut step).unwrap();
            for k in 0..substeps {
                let (fa, fb) = (
                    f + (f1 - f) * k as f64 / substeps as f64,
                    f + (f1 - f) * (k + 1) as f64 / substeps as f64,
                );
                step.advance_state(modes, &mut state, fa, fb);
                check(&state, fb);
            }
            (t, f) = (t1, f1);
        }
    }

    #[test]
    fn the_mode_bounds_hold_through_a_stretch_and_are_the_amplitude_in_free_flight() {
        // A rigid mode, an undamped one and two damped ones through a stretch of three force
        // pieces (a rise, a fall, a release), sampled 400 times a piece by exact steps: every
        // |q|, |q''| and |q - s F| stays within its bound (validation/REFERENCES.md 1.8).
        let omega = vec![0.0, 2.0e3, 5.0e3, 9.0e3];
        let modes = PointModes::from_parts(
            omega.clone(),
            vec![0.0, 0.0, 0.05, 0.2],
            vec![0.3, 1.0, -0.7, 0.4],
        )
        .unwrap();
        let data = ModeData::new(modes.clone());
        let start =
            ModalState { q: vec![0.01, 0.02, -0.01, 5e-3], v: vec![0.5, -30.0, 40.0, -10.0] };
        let (f0, ends) = (2.0, [(1e-4, 5.0), (2.5e-4, 1.0), (4e-4, 0.0)]);
        let mut b = ModeBounds::default();
        data.bounds(&start, &Stretch::new(0.0, f0, &ends), &mut b);
        let mut largest = [[0.0_f64; 3]; 4];
        walk(&modes, start, (f0, &ends), 400, |state, force| {
            for k in 0..4 {
                let (w, z, g) = (omega[k], modes.damping_ratio()[k], modes.gain()[k]);
                let acc = g * force - w * w * state.q[k] - 2.0 * z * w * state.v[k];
                let dev = if w > 0.0 { state.q[k] - g / (w * w) * force } else { 0.0 };
                let q = if w > 0.0 { state.q[k] } else { 0.0 };
                for (l, v) in largest[k].iter_mut().zip([q, acc, dev]) {
                    *l = l.max(v.abs());
                }
            }
        });
        for (k, seen) in largest.iter().enumerate() {
            let bounds = [b.q[k], b.acc[k], b.dev[k]];
            for (j, (seen, bound)) in seen.iter().zip(bounds).enumerate() {
                assert!(*seen <= bound * (1.0 + 1e-12), "mode {k}, bound {j}: {seen} > {bound}");
            }
        }
        // Free flight, undamped, the state at 45 degrees of phase (q = v/omega): |q| reaches
        // sqrt(q^2 + (v/omega)^2) within the period, and the bound is that amplitude (the sum
        // |q| + |v|/omega, what it was, is sqrt(2) larger). 2000 samples a period: the sampled
        // largest is within (pi/2000)^2/2 = 1.2e-6 of the amplitude.
        let w = 2.0e3;
        let free = PointModes::from_parts(vec![w], vec![0.0], vec![1.0]).unwrap();
        let data = ModeData::new(free.clone());
        let start = ModalState { q: vec![0.01], v: vec![0.01 * w] };
        let period = 2.0 * std::f64::consts::PI / w;
        let ends = [(period, 0.0)];
        data.bounds(&start, &Stretch::new(0.0, 0.0, &ends), &mut b);
        let amplitude = 0.01 * 2.0_f64.sqrt();
        assert!((b.q[0] - amplitude).abs() <= 1e-15 * amplitude, "{} vs {amplitude}", b.q[0]);
        let mut seen = 0.0_f64;
        walk(&free, start, (0.0, &ends), 2000, |s, _| seen = seen.max(s.q[0].abs()));
        // (The exact steps' round-off may pass the amplitude by an ulp or so.)
        assert!(
            seen <= b.q[0] * (1.0 + 1e-12) && seen >= b.q[0] * (1.0 - 2e-6),
            "{seen} vs {}",
            b.q[0]
        );
        assert!((b.acc[0] - w * w * amplitude).abs() <= 1e-12 * w * w * amplitude);
    }
}
