//! Mode shapes as a few bounded exponential waves, exact to high mode numbers for either beam
//! theory.

use crate::support::Support;
use num_complex::Complex64;

/// One wave of a mode shape: W = Re(w e^(lambda (x - anchor))), Psi = Re(psi e^(lambda (x -
/// anchor))). A growing exponential (Re lambda > 0) is anchored at x = L so that it never
/// exceeds its coefficient on the beam; the others are anchored at x = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Wave {
    pub(crate) lambda: Complex64,
    pub(crate) anchor: f64,
    pub(crate) w: Complex64,
    pub(crate) psi: Complex64,
}

impl Wave {
    /// e^(lambda (x - anchor)), with one exp and one sin_cos at most.
    fn factor(&self, x: f64) -> Complex64 {
        let t = x - self.anchor;
        let magnitude = (self.lambda.re * t).exp();
        if self.lambda.im == 0.0 {
            Complex64::new(magnitude, 0.0)
        } else {
            let (s, c) = (self.lambda.im * t).sin_cos();
            Complex64::new(magnitude * c, magnitude * s)
        }
    }
}

/// The waves a shape has at most (a travelling pair as one complex wave, the evanescent or
/// second travelling ones).
const WAVES: usize = 3;

const NO_WAVE: Wave = Wave {
    lambda: Complex64::new(0.0, 0.0),
    anchor: 0.0,
    w: Complex64::new(0.0, 0.0),
    psi: Complex64::new(0.0, 0.0),
};

/// A mode shape: the transverse displacement W(x) and the section rotation Psi(x), scaled so
/// that integral_0^L (W^2 + (rho I / rho A) Psi^2) dx = L. For an Euler-Bernoulli beam
/// Psi = W' and the rotary term is absent, which is the textbook scaling of Blevins, Table 8-1
/// (with it the clamped-free tip value is 2 (-1)^(n+1)); the mass-normalised shape is then
/// W / sqrt(rho A L) for either theory.
///
/// The shape is a sum of at most three waves (a trigonometric pair and two exponentials, or two
/// trigonometric pairs above a Timoshenko beam's cut-off) plus a rigid-body part p + r x/L:
///
/// W(x) = Re sum_j w_j e^(lambda_j (x - a_j)) + p + r x/L,  Psi(x) = Re sum_j psi_j e^(...) + r/L.
///
/// Every coefficient is of order one and no exponential grows, so there is no cancellation:
/// the textbook cosh/sinh form loses about log10(exp(beta L)) digits and is wrong by 100 % past
/// mode 14 (validation/REFERENCES.md 1.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeShape {
    beta: f64,
    length: f64,
    waves: [Wave; WAVES],
    count: usize,
    p: f64,
    r: f64,
}

impl ModeShape {
    /// The Euler-Bernoulli elastic mode with root `beta_l` = beta L of a beam of length `length` (m).
    ///
    /// Derivation: with cosh = (e^x + e^-x)/2, the textbook
    /// cosh(bx) -+ cos(bx) - s (sinh(bx) -+ sin(bx)) becomes
    /// A e^(-b(L-x)) + (1+s)/2 e^(-bx) -+ (cos(bx) - s sin(bx)) with A = (1-s) e^(bL)/2, and s and A
    /// are rewritten with e = exp(-bL) so that nothing large is formed:
    /// clamped-free D = 1 - e^2 + 2e sin, s = (1 + e^2 + 2e cos)/D, A = (sin - cos - e)/D;
    /// clamped-clamped, clamped-pinned, free-free D = 1 - e^2 - 2e sin, s = (1 + e^2 - 2e cos)/D,
    /// A = (cos - sin - e)/D (sin, cos of bL).
    pub(crate) fn elastic(support: Support, beta_l: f64, length: f64) -> Self {
        let beta = beta_l / length;
        let e = (-beta_l).exp();
        let (sn, cs) = beta_l.sin_cos();
        let (s, a) = match support {
            Support::PinnedPinned => (0.0, 0.0),
            Support::ClampedFree => {
                let den = 1.0 - e * e + 2.0 * e * sn;
                ((1.0 + e * e + 2.0 * e * cs) / den, (sn - cs - e) / den)
            }
            Support::ClampedClamped | Support::ClampedPinned | Support::FreeFree => {
                let den = 1.0 - e * e - 2.0 * e * sn;
                ((1.0 + e * e - 2.0 * e * cs) / den, (cs - sn - e) / den)
            }
        };
        // phi = a e^(-beta (L - x)) + b e^(-beta x) + c cos(beta x) + d sin(beta x).
        let (b, c, d) = match support {
            Support::PinnedPinned => (0.0, 0.0, std::f64::consts::SQRT_2),
            Support::FreeFree => (0.5 * (1.0 + s), 1.0, -s),
            _ => (0.5 * (1.0 + s), -1.0, s),
        };
        // For Euler-Bernoulli Psi = W': each wave's psi is lambda times its w.
        let wave = |lambda: Complex64, anchor: f64, w: Complex64| Wave {
            lambda,
            anchor,
            w,
            psi: lambda * w,
        };
        let waves = [
            wave(Complex64::new(0.0, beta), 0.0, Complex64::new(c, -d)),
            wave(Complex64::new(beta, 0.0), length, Complex64::new(a, 0.0)),
            wave(Complex64::new(-beta, 0.0), 0.0, Complex64::new(b, 0.0)),
        ];
        Self { beta, length, waves, count: 3, p: 0.0, r: 0.0 }
    }

    /// A shape from its waves (unnormalised), with bending wavenumber `beta` (1/m).
    pub(crate) fn from_waves(beta: f64, length: f64, waves: &[Wave]) -> Self {
        let mut all = [NO_WAVE; WAVES];
        all[..waves.len()].copy_from_slice(waves);
        Self { beta, length, waves: all, count: waves.len(), p: 0.0, r: 0.0 }
    }

    /// Length of the beam (m).
    pub(crate) fn length(&self) -> f64 {
        self.length
    }

    /// The waves.
    pub(crate) fn waves(&self) -> &[Wave] {
        &self.waves[..self.count]
    }

    /// The shape times `factor`.
    pub(crate) fn scaled(mut self, factor: f64) -> Self {
        for wave in &mut self.waves {
            wave.w *= factor;
            wave.psi *= factor;
        }
        self.p *= factor;
        self.r *= factor;
        self
    }

    /// Rigid-body translation of a free-free beam: W = 1, Psi = 0.
    pub(crate) fn translation(length: f64) -> Self {
        Self { beta: 0.0, length, waves: [NO_WAVE; WAVES], count: 0, p: 1.0, r: 0.0 }
    }

    /// Rigid-body rotation about the centre of a free-free beam: W = k sqrt(3) (2x/L - 1),
    /// Psi = W' = 2 k sqrt(3)/L, with k = 1/sqrt(1 + 12 rotary/L^2) for the rotary term
    /// `rotary` = rho I / rho A (m^2; 0 for Euler-Bernoulli).
    pub(crate) fn rigid_rotation(length: f64, rotary: f64) -> Self {
        let k = 3f64.sqrt() / (1.0 + 12.0 * rotary / (length * length)).sqrt();
        Self { beta: 0.0, length, waves: [NO_WAVE; WAVES], count: 0, p: -k, r: 2.0 * k }
    }

    /// The bending shape of a mode of another family (a torsion mode beside the bending ones):
    /// no displacement, no rotation, no curvature anywhere.
    pub fn absent(length: f64) -> Self {
        Self { beta: 0.0, length, waves: [NO_WAVE; WAVES], count: 0, p: 0.0, r: 0.0 }
    }

    /// Bending wavenumber beta (1/m); zero for a rigid-body mode.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The k-th derivative d^k W / dx^k at x (m), k = 0 (value), 1 (slope, 1/m),
    /// 2 (1/m^2), 3 (1/m^3).
    pub fn derivative(&self, k: u32, x: f64) -> f64 {
        let waves: f64 =
            self.waves().iter().map(|w| (w.w * w.lambda.powu(k) * w.factor(x)).re).sum();
        let linear = match k {
            0 => self.p + self.r * x / self.length,
            1 => self.r / self.length,
            _ => 0.0,
        };
        waves + linear
    }

    /// W(x).
    pub fn value(&self, x: f64) -> f64 {
        self.derivative(0, x)
    }

    /// W'(x) (1/m).
    pub fn slope(&self, x: f64) -> f64 {
        self.derivative(1, x)
    }

    /// Section rotation Psi(x) (1/m): the slope W' for an Euler-Bernoulli beam, the slope less
    /// the shear strain for a Timoshenko beam.
    pub fn rotation_at(&self, x: f64) -> f64 {
        self.waves().iter().map(|w| (w.psi * w.factor(x)).re).sum::<f64>() + self.r / self.length
    }

    /// Bending curvature Psi'(x) (1/m^2), so that the bending moment is EI Psi': W'' for an
    /// Euler-Bernoulli beam.
    pub fn curvature(&self, x: f64) -> f64 {
        self.waves().iter().map(|w| (w.psi * w.lambda * w.factor(x)).re).sum()
    }

    /// d^k Psi'/dx^k at x (m) (1/m^(2+k)): the curvature's k-th derivative, k = 1 the
    /// bending moment's rate over EI (the shear over EI for Euler-Bernoulli).
    pub fn curvature_derivative(&self, k: u32, x: f64) -> f64 {
        self.waves().iter().map(|w| (w.psi * w.lambda.powu(k + 1) * w.factor(x)).re).sum()
    }

    /// An upper bound of |d^k Psi'/dx^k| anywhere on the beam (1/m^(2+k)): k = 0 bounds the
    /// curvature, k = 2 its second derivative. Each wave contributes Re(psi lambda^(k+1)
    /// e^(lambda (x - anchor))), and no wave's exponential exceeds 1 in magnitude on the beam
    /// (a growing one is anchored at x = L), so |psi| |lambda|^(k+1) summed over the waves
    /// bounds it. What a search for the largest bending stress needs to know how much the
    /// curvature can change between two points where it was evaluated.
    pub fn curvature_bound(&self, k: i32) -> f64 {
        self.waves().iter().map(|w| w.psi.norm() * w.lambda.norm().powi(k + 1)).sum()
    }

    /// Psi'(x) (1/m^2) at x = x0 + k dx for k = 0 .. count, as [`ModeShape::curvature`] gives
    /// it but with one exponential per wave for the whole grid: each wave is carried from point
    /// to point by its factor over dx (a growing one downward from the last point, the others
    /// upward from the first, so each is carried from where it is largest), to about `count`
    /// ulps of the largest term.
    pub fn curvatures_on_grid(&self, x0: f64, dx: f64, count: usize) -> Vec<f64> {
        let mut out = vec![0.0; count];
        if count == 0 {
            return out;
        }
        let last = x0 + dx * (count - 1) as f64;
        for wave in self.waves() {
            let coefficient = wave.psi * wave.lambda;
            let step = (wave.lambda * dx).exp();
            if wave.lambda.re > 0.0 {
                let mut term = coefficient * wave.factor(last);
                let back = 1.0 / step;
                for v in out.iter_mut().rev() {
                    *v += term.re;
                    term *= back;
                }
            } else {
                let mut term = coefficient * wave.factor(x0);
                for v in &mut out {
                    *v += term.re;
                    term *= step;
                }
            }
        }
        out
    }

    /// integral_0^L (W_a W_b + rotary Psi_a Psi_b) dx of the wave parts of two shapes, in closed
    /// form: with Re X Re Y = (Re XY + Re X conj(Y))/2 every product is one exponential.
    pub(crate) fn wave_inner(&self, other: &Self, rotary: f64) -> f64 {
        let length = self.length;
        let mut total = 0.0;
        for a in self.waves() {
            for b in other.waves() {
                for conjugate in [false, true] {
                    let (lb, wb, pb) = if conjugate {
                        (b.lambda.conj(), b.w.conj(), b.psi.conj())
                    } else {
                        (b.lambda, b.w, b.psi)
                    };
                    let mu = a.lambda + lb;
                    let shift = a.lambda * a.anchor + lb * b.anchor;
                    let integral = exp_integral(mu, shift, length);
                    total += 0.5 * ((a.w * wb + rotary * a.psi * pb) * integral).re;
                }
            }
        }
        total
    }
}

/// integral_0^L e^(mu x - shift) dx without overflow: the exponential is factored at the end
/// where it is largest, e^(mu L - shift) L h(mu L) for Re mu >= 0 and e^(-shift) L h(-mu L)
/// otherwise, with h(z) = (1 - e^-z)/z.
fn exp_integral(mu: Complex64, shift: Complex64, length: f64) -> Complex64 {
    let z = mu * length;
    if mu.re >= 0.0 {
        (z - shift).exp() * length * relaxation(z)
    } else {
        (-shift).exp() * length * relaxation(-z)
    }
}

/// The curvature Psi' of many mode shapes at one point at a time and its first two
/// x-derivatives: the shapes' waves laid out slot by slot over the modes, each wave's factor
/// e^(lambda (x - anchor)) from the vectorised sine, cosine and exponential of
/// `lanes.rs` (what [`ModeShape::curvature_derivative`] gives each, to a few ulps of its
/// terms; 3.7 times faster over 256 Timoshenko modes, criterion `modal/curvatures`). A row of
/// the bending stress over the modes at a new point of a search for its largest is one such
/// evaluation.
#[derive(Debug, Clone)]
pub struct Curvatures {
    modes: usize,
    /// Per wave slot (slot-major: slot j of mode m at j * modes + m; a shape with fewer waves
    /// has zero coefficients there): Re and Im of lambda, the anchor, and Re and Im of
    /// psi lambda^(k+1) for k = 0, 1, 2.
    lambda: [Vec<f64>; 2],
    anchor: Vec<f64>,
    coefficient: [[Vec<f64>; 2]; 3],
    /// Per slot, whether any of its waves has a real part of lambda (an exponential to take)
    /// and an imaginary part (a sine and cosine): the travelling waves fill the slots from
    /// the first, the evanescent ones from the last, so that most slots take one of the two.
    needs: [(bool, bool); WAVES],
}

impl Curvatures {
    /// The evaluator of `shapes` (in their order).
    pub fn new<'a>(shapes: impl IntoIterator<Item = &'a ModeShape>) -> Self {
        let shapes: Vec<&ModeShape> = shapes.into_iter().collect();
        let modes = shapes.len();
        let size = WAVES * modes;
        let mut out = Self {
            modes,
            lambda: [vec![0.0; size], vec![0.0; size]],
            anchor: vec![0.0; size],
            coefficient: std::array::from_fn(|_| [vec![0.0; size], vec![0.0; size]]),
            needs: [(false, false); WAVES],
        };
        for (m, shape) in shapes.iter().enumerate() {
            // Travelling waves (Re lambda = 0) from the first slot up, the others from the
            // last down.
            let (mut up, mut down) = (0, WAVES);
            for w in shape.waves() {
                let j = if w.lambda.re == 0.0 {
                    up += 1;
                    up - 1
                } else {
                    down -= 1;
                    down
                };
                let i = j * modes + m;
                out.needs[j].0 |= w.lambda.re != 0.0;
                out.needs[j].1 |= w.lambda.im != 0.0;
                (out.lambda[0][i], out.lambda[1][i]) = (w.lambda.re, w.lambda.im);
                out.anchor[i] = w.anchor;
                for (k, c) in out.coefficient.iter_mut().enumerate() {
                    let value = w.psi * w.lambda.powu(k as u32 + 1);
                    (c[0][i], c[1][i]) = (value.re, value.im);
                }
            }
        }
        out
    }

    /// How many shapes.
    pub fn len(&self) -> usize {
        self.modes
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.modes == 0
    }

    /// d^k Psi'/dx^k at x of every shape for k = 0 .. `out.len()` (at most 3), into `out[k]`
    /// (each as long as the shapes). Beyond |lambda (x - anchor)| = 1e6 (a wavenumber far
    /// past any mode's) a wave's sine and cosine are the standard library's.
    pub fn at(&self, x: f64, out: &mut [&mut [f64]]) {
        assert!(
            out.len() <= 3 && out.iter().all(|o| o.len() == self.modes),
            "at most 3 rows, each of the shapes' count"
        );
        crate::on_four_lanes(AtPoint { curvatures: self, x, out });
    }
}

/// [`Curvatures::at`]'s loops, compiled for the processor's vectors (`on_four_lanes`:
/// pulp inlines `with_simd` into a copy built for them).
struct AtPoint<'a, 'b> {
    curvatures: &'a Curvatures,
    x: f64,
    out: &'a mut [&'b mut [f64]],
}

impl pulp::WithSimd for AtPoint<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Self { curvatures: c, x, out } = self;
        let n = c.modes;
        for o in out.iter_mut() {
            o.fill(0.0);
        }
        let (mut real, mut imaginary) = (vec![0.0; n], vec![0.0; n]);
        for (slot, &(needs_exp, needs_trig)) in c.needs.iter().enumerate() {
            if !needs_exp && !needs_trig {
                // No wave here (lambda = 0 gives no curvature).
                continue;
            }
            let range = slot * n..(slot + 1) * n;
            let (re, im) = (&c.lambda[0][range.clone()], &c.lambda[1][range.clone()]);
            let anchor = &c.anchor[range.clone()];
            // e^(lambda (x - anchor)) = e^(Re lambda t) (cos, sin)(Im lambda t), t = x - anchor
            // (zipped slices: no bounds checks, so the loops vectorise), the exponential or
            // the sine and cosine left out where the slot has none.
            let factors = real.iter_mut().zip(imaginary.iter_mut());
            let waves = factors.zip(re.iter().zip(im).zip(anchor));
            match (needs_exp, needs_trig) {
                (true, true) => {
                    for ((fr, fi), ((re, im), anchor)) in waves {
                        let t = x - anchor;
                        let magnitude = crate::lanes::exp(re * t);
                        let (sin, cos) = crate::lanes::sin_cos(im * t);
                        (*fr, *fi) = (magnitude * cos, magnitude * sin);
                    }
                }
                (false, _) => {
                    for ((fr, fi), ((_, im), anchor)) in waves {
                        (*fi, *fr) = crate::lanes::sin_cos(im * (x - anchor));
                    }
                }
                (true, false) => {
                    for ((fr, fi), ((re, _), anchor)) in waves {
                        (*fr, *fi) = (crate::lanes::exp(re * (x - anchor)), 0.0);
                    }
                }
            }
            // The rare argument past the reduction's reach: the standard library's.
            let factors = real.iter_mut().zip(imaginary.iter_mut());
            for ((fr, fi), ((re, im), anchor)) in factors.zip(re.iter().zip(im).zip(anchor)) {
                let t = x - anchor;
                if needs_trig && (im * t).abs() > crate::lanes::SIN_COS_REACH {
                    let magnitude = crate::lanes::exp(re * t);
                    let (sin, cos) = (im * t).sin_cos();
                    (*fr, *fi) = (magnitude * cos, magnitude * sin);
                }
            }
            for (k, o) in out.iter_mut().enumerate() {
                let [cr, ci] = &c.coefficient[k];
                let (cr, ci) = (&cr[range.clone()], &ci[range.clone()]);
                let terms = cr.iter().zip(ci).zip(real.iter().zip(&imaginary));
                for (o, ((cr, ci), (fr, fi))) in o.iter_mut().zip(terms) {
                    *o += cr * fr - ci * fi;
                }
            }
        }
    }
}

/// h(z) = (1 - e^-z)/z for Re z >= 0, by its Taylor series sum (-z)^k/(k+1)! near 0.
fn relaxation(z: Complex64) -> Complex64 {
    if z.norm() < 0.5 {
        // 18 terms: 0.5^18/19! < 1e-22.
        let mut sum = Complex64::new(0.0, 0.0);
        for k in (0..18).rev() {
            sum = sum * (-z) / (k as f64 + 2.0) + 1.0;
        }
        sum
    } else {
        (1.0 - (-z).exp()) / z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relaxation_is_continuous_at_its_switch() {
        for z in [Complex64::new(0.4999, 0.0), Complex64::new(0.3, 0.39), Complex64::new(0.0, 0.49)]
        {
            let series = relaxation(z);
            let direct = (1.0 - (-z).exp()) / z;
            assert!((series - direct).norm() < 1e-15, "{z}: {series} vs {direct}");
        }
    }
}
