//! Exact propagation of modal oscillators driven by a point force.

use crate::beam::{Beam, Mode};
use crate::error::{positive, ModalError};
use num_complex::Complex64;
use pulp::{Simd, WithSimd};

/// The modes of a beam seen from one point x = c where a force F(t) acts (and where the
/// displacement is observed): each mode is the oscillator
/// q'' + 2 zeta omega q' + omega^2 q = g F, with the mass-normalised participation
/// g = phi(c) / sqrt(rho A L), and the displacement at c is w = sum g q.
#[derive(Debug, Clone, PartialEq)]
pub struct PointModes {
    omega: Vec<f64>,
    damping_ratio: Vec<f64>,
    gain: Vec<f64>,
}

/// Modal coordinates q (m sqrt(kg)) and their rates v (m sqrt(kg)/s), one per mode.
///
/// # Panics
/// Every function that takes a state panics, naming both lengths, when `q` or `v` does not
/// hold exactly one number per mode of the modes it is used with (a state made for other
/// modes: make it with [`ModalState::at_rest`]`(modes.len())`). A shorter state had panicked
/// deep in a vector kernel, or been read as if its missing modes were at rest (a review's).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModalState {
    /// Modal displacements.
    pub q: Vec<f64>,
    /// Modal velocities.
    pub v: Vec<f64>,
}

/// Panics unless `state` holds `modes` modes (see [`ModalState`]).
#[inline]
fn check_len(state: &ModalState, modes: usize) {
    assert!(
        state.q.len() == modes && state.v.len() == modes,
        "a ModalState of {} displacements and {} rates used with {modes} modes: make it with ModalState::at_rest({modes})",
        state.q.len(),
        state.v.len()
    );
}

impl ModalState {
    /// At rest, for `n` modes.
    pub fn at_rest(n: usize) -> Self {
        Self { q: vec![0.0; n], v: vec![0.0; n] }
    }

    /// Displacement w(x) (m) of the beam at any point, from its modes.
    pub fn displacement_at(&self, beam: &Beam, modes: &[Mode], x: f64) -> f64 {
        check_len(self, modes.len());
        let scale = 1.0 / beam.mass().sqrt();
        modes.iter().zip(&self.q).map(|(m, q)| m.shape.value(x) * scale * q).sum()
    }
}

impl PointModes {
    /// The modes `modes` of `beam` seen from x = `position` (m), all with the modal damping
    /// ratio `damping_ratio` (rigid-body modes stay undamped).
    ///
    /// # Errors
    /// `InvalidParameter` if the position is outside [0, L] or the damping ratio is outside
    /// [0, 1) (critical and over-damping are not supported).
    pub fn new(
        beam: &Beam,
        modes: &[Mode],
        position: f64,
        damping_ratio: f64,
    ) -> Result<Self, ModalError> {
        if !(position.is_finite() && (0.0..=beam.length()).contains(&position)) {
            return Err(ModalError::InvalidParameter {
                name: "position",
                value: position,
                unit: "m",
                allowed: "a point on the beam, 0 <= position <= length",
            });
        }
        let scale = 1.0 / beam.mass().sqrt();
        Self::from_parts(
            modes.iter().map(|m| m.omega).collect(),
            vec![damping_ratio; modes.len()],
            modes.iter().map(|m| m.shape.value(position) * scale).collect(),
        )
    }

    /// From frequencies (rad/s), damping ratios and participations (1/sqrt(kg)) directly.
    ///
    /// # Errors
    /// `InvalidParameter` for lengths that differ, negative or non-finite frequencies,
    /// damping ratios outside [0, 1) or non-finite participations.
    pub fn from_parts(
        omega: Vec<f64>,
        damping_ratio: Vec<f64>,
        gain: Vec<f64>,
    ) -> Result<Self, ModalError> {
        if omega.len() != gain.len() || omega.len() != damping_ratio.len() {
            return Err(ModalError::InvalidParameter {
                name: "modes",
                value: omega.len() as f64,
                unit: "-",
                allowed: "as many frequencies as damping ratios and participations",
            });
        }
        for &w in &omega {
            if !(w.is_finite() && w >= 0.0) {
                return Err(ModalError::InvalidParameter {
                    name: "omega",
                    value: w,
                    unit: "rad/s",
                    allowed: "a finite number >= 0",
                });
            }
        }
        for &z in &damping_ratio {
            if !(z.is_finite() && (0.0..1.0).contains(&z)) {
                return Err(ModalError::InvalidParameter {
                    name: "modal_damping",
                    value: z,
                    unit: "-",
                    allowed: "a damping ratio in [0, 1)",
                });
            }
        }
        for &g in &gain {
            if !g.is_finite() {
                return Err(ModalError::InvalidParameter {
                    name: "participation",
                    value: g,
                    unit: "1/sqrt(kg)",
                    allowed: "a finite number",
                });
            }
        }
        Ok(Self { omega, damping_ratio, gain })
    }

    /// Number of modes.
    pub fn len(&self) -> usize {
        self.omega.len()
    }

    /// True if there are no modes (a massive, rigid support).
    pub fn is_empty(&self) -> bool {
        self.omega.is_empty()
    }

    /// Frequencies omega (rad/s).
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }

    /// Participations g = phi(c)/sqrt(rho A L) (1/sqrt(kg)).
    pub fn gain(&self) -> &[f64] {
        &self.gain
    }

    /// Modal damping ratios.
    pub fn damping_ratio(&self) -> &[f64] {
        &self.damping_ratio
    }

    /// Displacement at the point, w = sum g q (m).
    pub fn displacement(&self, s: &ModalState) -> f64 {
        check_len(s, self.len());
        self.gain.iter().zip(&s.q).map(|(g, q)| g * q).sum()
    }

    /// Velocity at the point, sum g v (m/s). The series does not converge as modes are added
    /// (validation/REFERENCES.md 1.2): use it for estimates, never in the contact condition.
    pub fn velocity(&self, s: &ModalState) -> f64 {
        check_len(s, self.len());
        self.gain.iter().zip(&s.v).map(|(g, v)| g * v).sum()
    }

    /// Kinetic plus strain energy of the beam, sum (v^2 + omega^2 q^2)/2 (J).
    pub fn energy(&self, s: &ModalState) -> f64 {
        check_len(s, self.len());
        self.omega
            .iter()
            .zip(s.q.iter().zip(&s.v))
            .map(|(w, (q, v))| 0.5 * (v * v + w * w * q * q))
            .sum()
    }

    /// Static flexibility of the truncated model at the point, sum over elastic modes of
    /// g^2 / omega^2 (m/N); it converges to the beam's as modes are added.
    pub fn static_flexibility(&self) -> f64 {
        self.omega
            .iter()
            .zip(&self.gain)
            .filter(|(w, _)| **w > 0.0)
            .map(|(w, g)| g * g / (w * w))
            .sum()
    }

    /// Power dissipated by the modal damping, sum 2 zeta omega v^2 (W).
    pub fn damping_power(&self, s: &ModalState) -> f64 {
        check_len(s, self.len());
        self.omega
            .iter()
            .zip(&self.damping_ratio)
            .zip(&s.v)
            .map(|((w, z), v)| 2.0 * z * w * v * v)
            .sum()
    }
}

/// How the force varies over a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hold {
    /// Constant over the step at its start value F0 (the paper's eq. 1).
    Zero,
    /// Linear from F0 at the start to F1 at the end.
    FirstOrder,
}

/// The exact transition of every mode over a step h under a held force:
/// `[q, v](t + h) = E [q, v](t) + G0 F0 + G1 F1`, with `E = exp(A h)`,
/// G0 + G1 = h phi1(A h) b and G1 = h phi2(A h) b for a first-order hold
/// (phi1(z) = (e^z - 1)/z, phi2(z) = (e^z - 1 - z)/z^2; b = [0, g]).
/// No step-size limit: exact for any h and any omega h.
#[derive(Debug, Clone, PartialEq)]
pub struct Transition {
    step: f64,
    hold: Hold,
    e11: Vec<f64>,
    e12: Vec<f64>,
    e21: Vec<f64>,
    e22: Vec<f64>,
    g0q: Vec<f64>,
    g0v: Vec<f64>,
    g1q: Vec<f64>,
    g1v: Vec<f64>,
    /// Participations g, to sum the displacement while advancing.
    gain: Vec<f64>,
    /// omega^2, to sum the energy while advancing.
    omega2: Vec<f64>,
    /// g E11 and g E12: the end displacement at the point from the start state.
    wq: Vec<f64>,
    wv: Vec<f64>,
    w0: f64,
    compliance: f64,
}

/// cos x, sin(x)/x, (1 - cos x)/x^2, (x - sin x)/x^3, stable at small x (exact limits 1, 1, 1/2,
/// 1/6 at 0), from one sine and one cosine of x/2 (sin x = 2 s c, 1 - cos x = 2 s^2): the
/// event search evaluates them for every mode at every trial time, and the trigonometry is its
/// cost.
fn undamped_kernels(x: f64) -> (f64, f64, f64, f64) {
    if x < 0.5 {
        // Taylor series in y = -x^2 by Horner's rule on the coefficients tabled at compile
        // time (no division: the low modes of every step take this branch); 9 terms reach
        // round-off for x < 0.5 (x^18/21! < 1e-25).
        let y = -x * x;
        let (mut c1, mut c2, mut c3) = (0.0, 0.0, 0.0);
        for [a1, a2, a3] in KERNEL_TAYLOR.iter().rev() {
            c1 = c1 * y + a1;
            c2 = c2 * y + a2;
            c3 = c3 * y + a3;
        }
        (1.0 + y * c2, c1, c2, c3)
    } else {
        let (s, c) = (0.5 * x).sin_cos();
        let sin = 2.0 * s * c;
        (1.0 - 2.0 * s * s, sin / x, 2.0 * s * s / (x * x), (x - sin) / (x * x * x))
    }
}

/// The Taylor coefficients of sin(x)/x, (1 - cos x)/x^2 and (x - sin x)/x^3 in powers of
/// -x^2: 1/(2k+1)!, 1/(2k+2)!, 1/(2k+3)! for k = 0..8.
const KERNEL_TAYLOR: [[f64; 3]; 9] = {
    let mut table = [[0.0; 3]; 9];
    let mut fact = 1.0; // (2k + 1)!
    let mut k = 0;
    while k < 9 {
        let a = 2.0 * k as f64;
        table[k] = [1.0 / fact, 1.0 / (fact * (a + 2.0)), 1.0 / (fact * (a + 2.0) * (a + 3.0))];
        fact *= (a + 2.0) * (a + 3.0);
        k += 1;
    }
    table
};

/// exp(z), phi1(z), phi2(z) for complex z, by Taylor series near 0 (no cancellation).
fn phi_functions(z: Complex64) -> (Complex64, Complex64, Complex64) {
    let e = z.exp();
    if z.norm() >= 0.5 {
        let p1 = (e - 1.0) / z;
        return (e, p1, (p1 - 1.0) / z);
    }
    let (mut p1, mut p2) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
    let mut term = Complex64::new(1.0, 0.0); // z^j / j!
    for j in 0..24 {
        let jf = j as f64;
        p1 += term / (jf + 1.0);
        p2 += term / ((jf + 1.0) * (jf + 2.0));
        term = term * z / (jf + 1.0);
    }
    (e, p1, p2)
}

/// One mode's exact transition over a step h for a unit participation:
/// e = [E11, E12, E21, E22] and the load columns g0, g1 = [q, v] per newton of F0 and F1.
#[derive(Debug, Clone, Copy)]
struct ModeStep {
    e: [f64; 4],
    g0: [f64; 2],
    g1: [f64; 2],
}

impl ModeStep {
    fn new(w: f64, z: f64, h: f64, hold: Hold) -> Self {
        // e = [e11, e12, e21, e22]; p1, p2 = h phi1(Ah) b and h phi2(Ah) b for b = [0, 1].
        let (e, p1, p2) = if z == 0.0 || w == 0.0 {
            let x = w * h;
            let (cos, c1, c2, c3) = undamped_kernels(x);
            ([cos, h * c1, -w * x * c1, cos], [h * h * c2, h * c1], [h * h * c3, h * c2])
        } else {
            // f(M) = 2 Re[f(mu) (M - conj(mu) I) / (mu - conj(mu))] for M = A h with the
            // eigenvalues mu = h(-zeta omega +- i omega_d) (Sylvester's formula).
            let wd = w * (1.0 - z * z).sqrt();
            let mu = Complex64::new(-z * w * h, wd * h);
            let mub = mu.conj();
            let (f0, f1, f2) = phi_functions(mu);
            let inv = Complex64::new(0.0, 2.0 * wd * h).inv();
            let col2 = [Complex64::new(h, 0.0), Complex64::new(-2.0 * z * w * h, 0.0) - mub];
            let m = |f: Complex64, a: Complex64| 2.0 * (f * a * inv).re;
            (
                [
                    m(f0, -mub),
                    m(f0, col2[0]),
                    m(f0, Complex64::new(-w * w * h, 0.0)),
                    m(f0, col2[1]),
                ],
                [h * m(f1, col2[0]), h * m(f1, col2[1])],
                [h * m(f2, col2[0]), h * m(f2, col2[1])],
            )
        };
        let (g0, g1) = match hold {
            Hold::Zero => (p1, [0.0, 0.0]),
            Hold::FirstOrder => ([p1[0] - p2[0], p1[1] - p2[1]], p2),
        };
        Self { e, g0, g1 }
    }
}

/// sum a_i b_i with four running sums: independent chains the processor overlaps (and a fixed
/// summation order, so results are reproducible).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut sums = [0.0; 4];
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ac.remainder().iter().zip(bc.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ac.zip(bc) {
        for k in 0..4 {
            sums[k] += x[k] * y[k];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

impl PointModes {
    /// The part of the displacement at the point (m) and of its rate (m/s) that the modes in
    /// `range` carry: sum g q and sum g v over them (the whole rate series does not converge,
    /// see [`PointModes::velocity`]; a partial one is a finite sum).
    ///
    /// # Panics
    /// If `range` reaches past the modes.
    pub fn partial_motion(&self, state: &ModalState, range: std::ops::Range<usize>) -> (f64, f64) {
        check_len(state, self.len());
        let gain = &self.gain[range.clone()];
        (dot(gain, &state.q[range.clone()]), dot(gain, &state.v[range]))
    }

    /// Displacement at the point after a step tau from `state` with the force going linearly
    /// from `f0` to zero (m), without building a [`Transition`]: what event location needs, at
    /// any trial tau (see [`OneStep`] to keep the step for the advance that follows).
    ///
    /// # Errors
    /// `InvalidParameter` if tau is not finite and positive.
    pub fn free_displacement_after(
        &self,
        state: &ModalState,
        tau: f64,
        f0: f64,
    ) -> Result<f64, ModalError> {
        let mut step = OneStep::default();
        self.one_step(tau, &mut step)?;
        Ok(step.free_displacement(self, state, f0))
    }

    /// Advances `state` by tau (s) with the force going linearly from `f0` to `f1` (N), and
    /// returns the displacement at the point (m) and the beam's energy (J) after it: the
    /// same as [`Transition::new`] then [`Transition::advance_with_energy`], without building
    /// and storing the transition, for a step taken once (the partial step to an event).
    ///
    /// # Errors
    /// `InvalidParameter` if tau is not finite and positive.
    pub fn advance_once(
        &self,
        state: &mut ModalState,
        tau: f64,
        f0: f64,
        f1: f64,
    ) -> Result<(f64, f64), ModalError> {
        let mut step = OneStep::default();
        self.one_step(tau, &mut step)?;
        Ok(step.advance(self, state, f0, f1))
    }

    /// Every mode's exact step over tau (s), into `step` (its buffer reused): a sine and a
    /// cosine per mode, the cost of a step taken once.
    ///
    /// # Errors
    /// `InvalidParameter` if tau is not finite and positive.
    pub fn one_step(&self, tau: f64, step: &mut OneStep) -> Result<(), ModalError> {
        let h = positive("time_step", tau, "s")?;
        step.step = h;
        step.modes.clear();
        step.modes.extend(
            self.omega
                .iter()
                .zip(&self.damping_ratio)
                .map(|(&w, &z)| ModeStep::new(w, z, h, Hold::FirstOrder)),
        );
        Ok(())
    }
}

/// Every mode's exact step over one step length, for a step that is taken once (an event's
/// trial steps, then the step to it): built by [`PointModes::one_step`], it answers both where
/// the point would be ([`OneStep::free_displacement`]) and the step itself
/// ([`OneStep::advance`]) without computing the trigonometry twice.
#[derive(Debug, Clone, Default)]
pub struct OneStep {
    step: f64,
    modes: Vec<ModeStep>,
}

impl OneStep {
    /// The step (s); 0 before the first [`PointModes::one_step`].
    pub fn step_size(&self) -> f64 {
        self.step
    }

    /// Displacement at the point at the end of the step with the force going linearly from
    /// `f0` to zero (m).
    pub fn free_displacement(&self, modes: &PointModes, state: &ModalState, f0: f64) -> f64 {
        check_len(state, modes.len());
        let mut w = 0.0;
        for (i, s) in self.modes.iter().enumerate() {
            let g = modes.gain[i];
            w += g * (s.e[0] * state.q[i] + s.e[1] * state.v[i] + g * s.g0[0] * f0);
        }
        w
    }

    /// Advances `state` over the step with the force going linearly from `f0` to `f1` (N);
    /// returns the displacement at the point (m) and the beam's energy (J) after it.
    pub fn advance(
        &self,
        modes: &PointModes,
        state: &mut ModalState,
        f0: f64,
        f1: f64,
    ) -> (f64, f64) {
        check_len(state, modes.len());
        let (mut w, mut energy) = (0.0, 0.0);
        for (i, s) in self.modes.iter().enumerate() {
            let (g, omega) = (modes.gain[i], modes.omega[i]);
            let (q, v) = (state.q[i], state.v[i]);
            let q1 = s.e[0] * q + s.e[1] * v + g * (s.g0[0] * f0 + s.g1[0] * f1);
            let v1 = s.e[2] * q + s.e[3] * v + g * (s.g0[1] * f0 + s.g1[1] * f1);
            state.q[i] = q1;
            state.v[i] = v1;
            w += g * q1;
            energy += 0.5 * (v1 * v1 + omega * omega * q1 * q1);
        }
        (w, energy)
    }

    /// [`OneStep::advance`] without the sums: the same state, to the bit, for a caller that
    /// replays steps and reads neither the displacement nor the energy (the sums' chains of
    /// additions set the loop's time).
    pub fn advance_state(&self, modes: &PointModes, state: &mut ModalState, f0: f64, f1: f64) {
        check_len(state, modes.len());
        let n = self.modes.len();
        let (gain, q, v) = (&modes.gain[..n], &mut state.q[..n], &mut state.v[..n]);
        for (i, s) in self.modes.iter().enumerate() {
            let (q0, v0) = (q[i], v[i]);
            q[i] = s.e[0] * q0 + s.e[1] * v0 + gain[i] * (s.g0[0] * f0 + s.g1[0] * f1);
            v[i] = s.e[2] * q0 + s.e[3] * v0 + gain[i] * (s.g0[1] * f0 + s.g1[1] * f1);
        }
    }
}

/// The step's update of every mode, with the sums of the displacement at the point, the
/// energy, and the displacement at the point at the end of one more step of the same
/// transition with the force held at `f1` and no load added (what [`FreeKernel`] gives from
/// the new state with f0 = f1). The hot loops are compiled for the processor's vector instructions,
/// on x86-64 at most four lanes (`on_four_lanes`: pulp checks at run time and inlines `with_simd`
/// into a function built for them); the operations and their order are the same on every path, and
/// Rust never fuses a multiply and an add on its own, so neither are the results. Without a force
/// (`FORCED` false: free flight) the load columns are not read.
struct AdvanceKernel<'a, const FORCED: bool> {
    t: &'a Transition,
    state: &'a mut ModalState,
    f0: f64,
    f1: f64,
    /// The force at the start of the predicted step.
    f_next: f64,
}

impl<const FORCED: bool> WithSimd for AdvanceKernel<'_, FORCED> {
    /// (displacement at the point, beam energy, the next step's free end displacement).
    type Output = (f64, f64, f64);

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) -> (f64, f64, f64) {
        let Self { t, state, f0, f1, f_next } = self;
        // Every slice cut to one length, so the loops have no bounds checks and vectorise.
        let n = t.e11.len();
        let (q, v) = (&mut state.q[..n], &mut state.v[..n]);
        let (e11, e12, e21, e22) = (&t.e11[..n], &t.e12[..n], &t.e21[..n], &t.e22[..n]);
        if FORCED {
            let (g0q, g0v, g1q, g1v) = (&t.g0q[..n], &t.g0v[..n], &t.g1q[..n], &t.g1v[..n]);
            for i in 0..n {
                let (qi, vi) = (q[i], v[i]);
                q[i] = e11[i] * qi + e12[i] * vi + g0q[i] * f0 + g1q[i] * f1;
                v[i] = e21[i] * qi + e22[i] * vi + g0v[i] * f0 + g1v[i] * f1;
            }
        } else {
            for i in 0..n {
                let (qi, vi) = (q[i], v[i]);
                q[i] = e11[i] * qi + e12[i] * vi;
                v[i] = e21[i] * qi + e22[i] * vi;
            }
        }
        let (gain, omega2, wq, wv) = (&t.gain[..n], &t.omega2[..n], &t.wq[..n], &t.wv[..n]);
        // Four running sums of each, in a fixed order: independent chains that vectorise (the
        // next step's two in the order of `dot`, so the sum is FreeKernel's to the last bit).
        // Where the processor's vectors hold four f64 they are the four lanes of one vector
        // each (written out: the compiler's own vectorisation of the loop below shuffled the
        // lanes and took half the kernel's time); elsewhere the loop keeps them as four
        // scalars. Both add the same products in the same order, so the results are equal.
        let (mut w, mut e, mut nq, mut nv) = ([0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]);
        if S::F64_LANES == 4 {
            let (g4, o4) = (S::as_simd_f64s(gain).0, S::as_simd_f64s(omega2).0);
            let (a4, b4) = (S::as_simd_f64s(wq).0, S::as_simd_f64s(wv).0);
            let (q4, v4) = (S::as_simd_f64s(q).0, S::as_simd_f64s(v).0);
            let zero = simd.splat_f64s(0.0);
            let (mut sw, mut se, mut sq, mut sv) = (zero, zero, zero, zero);
            for (((g, o), (a, b)), (qq, vv)) in
                g4.iter().zip(o4).zip(a4.iter().zip(b4)).zip(q4.iter().zip(v4))
            {
                sw = simd.add_f64s(sw, simd.mul_f64s(*g, *qq));
                let kinetic = simd.mul_f64s(*vv, *vv);
                let strain = simd.mul_f64s(simd.mul_f64s(*o, *qq), *qq);
                se = simd.add_f64s(se, simd.add_f64s(kinetic, strain));
                sq = simd.add_f64s(sq, simd.mul_f64s(*a, *qq));
                sv = simd.add_f64s(sv, simd.mul_f64s(*b, *vv));
            }
            let lanes = |x: S::f64s| {
                let l: &[f64] = pulp::bytemuck::cast_slice(std::slice::from_ref(&x));
                [l[0], l[1], l[2], l[3]]
            };
            (w, e, nq, nv) = (lanes(sw), lanes(se), lanes(sq), lanes(sv));
        } else {
            let lanes = gain
                .chunks_exact(4)
                .zip(omega2.chunks_exact(4))
                .zip(wq.chunks_exact(4).zip(wv.chunks_exact(4)))
                .zip(q.chunks_exact(4).zip(v.chunks_exact(4)));
            for (((g, o), (a, b)), (qq, vv)) in lanes {
                for k in 0..4 {
                    w[k] += g[k] * qq[k];
                    e[k] += vv[k] * vv[k] + o[k] * qq[k] * qq[k];
                    nq[k] += a[k] * qq[k];
                    nv[k] += b[k] * vv[k];
                }
            }
        }
        let (mut w_tail, mut e_tail, mut nq_tail, mut nv_tail) = (0.0, 0.0, 0.0, 0.0);
        for j in n - n % 4..n {
            w_tail += gain[j] * q[j];
            e_tail += v[j] * v[j] + omega2[j] * q[j] * q[j];
            nq_tail += wq[j] * q[j];
            nv_tail += wv[j] * v[j];
        }
        let sum = |s: [f64; 4], tail: f64| (s[0] + s[1]) + (s[2] + s[3]) + tail;
        (sum(w, w_tail), 0.5 * sum(e, e_tail), t.w0 * f_next + sum(nq, nq_tail) + sum(nv, nv_tail))
    }
}

/// The free end displacement's sums (see [`AdvanceKernel`]).
struct FreeKernel<'a> {
    t: &'a Transition,
    state: &'a ModalState,
    f0: f64,
}

impl WithSimd for FreeKernel<'_> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> f64 {
        let Self { t, state, f0 } = self;
        t.w0 * f0 + dot(&t.wq, &state.q) + dot(&t.wv, &state.v)
    }
}

impl Transition {
    /// The transition of `modes` over a step `step` (s) with the given hold.
    ///
    /// # Errors
    /// `InvalidParameter` if the step is not finite and positive.
    pub fn new(modes: &PointModes, step: f64, hold: Hold) -> Result<Self, ModalError> {
        let h = positive("time_step", step, "s")?;
        let n = modes.len();
        let mut t = Self {
            step: h,
            hold,
            e11: Vec::with_capacity(n),
            e12: Vec::with_capacity(n),
            e21: Vec::with_capacity(n),
            e22: Vec::with_capacity(n),
            g0q: Vec::with_capacity(n),
            g0v: Vec::with_capacity(n),
            g1q: Vec::with_capacity(n),
            g1v: Vec::with_capacity(n),
            gain: modes.gain.clone(),
            omega2: modes.omega.iter().map(|w| w * w).collect(),
            wq: Vec::with_capacity(n),
            wv: Vec::with_capacity(n),
            w0: 0.0,
            compliance: 0.0,
        };
        for i in 0..n {
            let g = modes.gain[i];
            let s = ModeStep::new(modes.omega[i], modes.damping_ratio[i], h, hold);
            t.e11.push(s.e[0]);
            t.e12.push(s.e[1]);
            t.e21.push(s.e[2]);
            t.e22.push(s.e[3]);
            t.g0q.push(g * s.g0[0]);
            t.g0v.push(g * s.g0[1]);
            t.g1q.push(g * s.g1[0]);
            t.g1v.push(g * s.g1[1]);
            t.wq.push(g * s.e[0]);
            t.wv.push(g * s.e[1]);
            t.w0 += g * g * s.g0[0];
            t.compliance += g * g * s.g1[0];
        }
        Ok(t)
    }

    /// The step h (s).
    pub fn step_size(&self) -> f64 {
        self.step
    }

    /// Advances `state` over the step with the force going from `f0` to `f1` (N)
    /// (`f1` is ignored for a zero-order hold), and returns the new displacement at the point,
    /// sum g q (m).
    pub fn advance(&self, state: &mut ModalState, f0: f64, f1: f64) -> f64 {
        self.advance_with_energy(state, f0, f1).0
    }

    /// [`Transition::advance`], also returning the beam's energy after the step (J), summed in
    /// the same pass: what an energy ledger needs at every step, for the cost of a few
    /// multiplications per mode.
    pub fn advance_with_energy(&self, state: &mut ModalState, f0: f64, f1: f64) -> (f64, f64) {
        let (w, energy, _) = self.advance_predicting(state, f0, f1);
        (w, energy)
    }

    /// [`Transition::advance_with_energy`], also returning where the point would be at the
    /// end of one more step of this transition from the new state with the force starting at
    /// `f1` (even for a zero-order hold) and the end force zero: [`Transition::free_displacement`]`(state, f1)` after the
    /// step, to the last bit, summed in the same pass. A run that takes the same step again
    /// (free flight, and most of a contact) needs exactly that to decide the next step, and
    /// saves a second pass over the modes.
    pub fn advance_predicting(&self, state: &mut ModalState, f0: f64, f1: f64) -> (f64, f64, f64) {
        check_len(state, self.e11.len());
        let f_next = f1;
        let f1 = if self.hold == Hold::Zero { 0.0 } else { f1 };
        if f0 == 0.0 && f1 == 0.0 {
            crate::on_four_lanes(AdvanceKernel::<false> { t: self, state, f0, f1, f_next })
        } else {
            crate::on_four_lanes(AdvanceKernel::<true> { t: self, state, f0, f1, f_next })
        }
    }

    /// Displacement at the point at the end of the step if the end force were zero (m):
    /// the end displacement is `free_displacement + compliance * f1`.
    pub fn free_displacement(&self, state: &ModalState, f0: f64) -> f64 {
        check_len(state, self.e11.len());
        crate::on_four_lanes(FreeKernel { t: self, state, f0 })
    }

    /// d(end displacement)/d(end force) (m/N), sum g^2 G1_q >= 0.
    pub fn compliance(&self) -> f64 {
        self.compliance
    }
}
