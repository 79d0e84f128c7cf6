//! Exact propagation of modal oscillators driven by a point force.

use crate::beam::{Beam, Mode};
use crate::error::{positive, ModalError};
use num_complex::Complex64;

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
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModalState {
    /// Modal displacements.
    pub q: Vec<f64>,
    /// Modal velocities.
    pub v: Vec<f64>,
}

impl ModalState {
    /// At rest, for `n` modes.
    pub fn at_rest(n: usize) -> Self {
        Self { q: vec![0.0; n], v: vec![0.0; n] }
    }

    /// Displacement w(x) (m) of the beam at any point, from its modes.
    pub fn displacement_at(&self, beam: &Beam, modes: &[Mode], x: f64) -> f64 {
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
        self.gain.iter().zip(&s.q).map(|(g, q)| g * q).sum()
    }

    /// Velocity at the point, sum g v (m/s). The series does not converge as modes are added
    /// (REFERENCES.md 1.2): use it for estimates, never in the contact condition.
    pub fn velocity(&self, s: &ModalState) -> f64 {
        self.gain.iter().zip(&s.v).map(|(g, v)| g * v).sum()
    }

    /// Kinetic plus strain energy of the beam, sum (v^2 + omega^2 q^2)/2 (J).
    pub fn energy(&self, s: &ModalState) -> f64 {
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
/// [q, v](t + h) = E [q, v](t) + G0 F0 + G1 F1, with E = exp(A h),
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
    /// g E11 and g E12: the end displacement at the point from the start state.
    wq: Vec<f64>,
    wv: Vec<f64>,
    w0: f64,
    compliance: f64,
}

/// sin(x)/x, (1 - cos x)/x^2, (x - sin x)/x^3, stable at small x (exact limits 1, 1/2, 1/6 at 0).
fn undamped_kernels(x: f64) -> (f64, f64, f64) {
    if x < 0.5 {
        // Taylor series; 9 terms reach round-off for x < 0.5 (x^18/21! < 1e-25).
        let x2 = x * x;
        let (mut c1, mut c2, mut c3) = (0.0, 0.0, 0.0);
        let mut term = 1.0; // (-x^2)^k
        let mut fact = 1.0; // (2k + 1)!
        for k in 0..9 {
            let kf = k as f64;
            c1 += term / fact;
            c2 += term / (fact * (2.0 * kf + 2.0));
            c3 += term / (fact * (2.0 * kf + 2.0) * (2.0 * kf + 3.0));
            term *= -x2;
            fact *= (2.0 * kf + 2.0) * (2.0 * kf + 3.0);
        }
        (c1, c2, c3)
    } else {
        let s = x.sin();
        let half = (0.5 * x).sin();
        (s / x, 2.0 * half * half / (x * x), (x - s) / (x * x * x))
    }
}

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
            wq: Vec::with_capacity(n),
            wv: Vec::with_capacity(n),
            w0: 0.0,
            compliance: 0.0,
        };
        for i in 0..n {
            let (w, z, g) = (modes.omega[i], modes.damping_ratio[i], modes.gain[i]);
            // e = [e11, e12, e21, e22]; p1, p2 = h phi1(Ah) b and h phi2(Ah) b for b = [0, 1].
            let (e, p1, p2) = if z == 0.0 || w == 0.0 {
                let x = w * h;
                let (c1, c2, c3) = undamped_kernels(x);
                let cos = x.cos();
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
            t.e11.push(e[0]);
            t.e12.push(e[1]);
            t.e21.push(e[2]);
            t.e22.push(e[3]);
            t.g0q.push(g * g0[0]);
            t.g0v.push(g * g0[1]);
            t.g1q.push(g * g1[0]);
            t.g1v.push(g * g1[1]);
            t.wq.push(g * e[0]);
            t.wv.push(g * e[1]);
            t.w0 += g * g * g0[0];
            t.compliance += g * g * g1[0];
        }
        Ok(t)
    }

    /// The step h (s).
    pub fn step_size(&self) -> f64 {
        self.step
    }

    /// Advances `state` over the step with the force going from `f0` to `f1` (N)
    /// (`f1` is ignored for a zero-order hold), and returns the new displacement at the point,
    /// sum g q (m), summed in the same pass.
    pub fn advance(&self, state: &mut ModalState, f0: f64, f1: f64) -> f64 {
        let f1 = if self.hold == Hold::Zero { 0.0 } else { f1 };
        let mut w = 0.0;
        for i in 0..self.e11.len() {
            let (q, v) = (state.q[i], state.v[i]);
            let q1 = self.e11[i] * q + self.e12[i] * v + self.g0q[i] * f0 + self.g1q[i] * f1;
            state.v[i] = self.e21[i] * q + self.e22[i] * v + self.g0v[i] * f0 + self.g1v[i] * f1;
            state.q[i] = q1;
            w += self.gain[i] * q1;
        }
        w
    }

    /// Displacement at the point at the end of the step if the end force were zero (m):
    /// the end displacement is `free_displacement + compliance * f1`.
    pub fn free_displacement(&self, state: &ModalState, f0: f64) -> f64 {
        let mut w = self.w0 * f0;
        for i in 0..self.wq.len() {
            w += self.wq[i] * state.q[i] + self.wv[i] * state.v[i];
        }
        w
    }

    /// d(end displacement)/d(end force) (m/N), sum g^2 G1_q >= 0.
    pub fn compliance(&self) -> f64 {
        self.compliance
    }
}
