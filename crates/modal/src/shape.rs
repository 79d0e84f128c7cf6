//! Mode shapes in a bounded form that stays exact to high mode numbers.

use crate::support::Support;

/// A mode shape scaled so that integral_0^L phi^2 dx = L (the textbook scaling of Blevins,
/// Table 8-1; with it the clamped-free tip value is 2 (-1)^(n+1)), written as
///
/// phi(x) = a exp(-beta (L - x)) + b exp(-beta x) + c cos(beta x) + d sin(beta x) + p + r x/L.
///
/// Every coefficient is of order one and no exponential grows, so there is no cancellation:
/// the textbook cosh/sinh form loses about log10(exp(beta L)) digits and is wrong by 100 % past
/// mode 14 (validation/REFERENCES.md 1.3). The linear part carries the rigid-body modes of a free-free beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeShape {
    beta: f64,
    length: f64,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    p: f64,
    r: f64,
}

impl ModeShape {
    /// The elastic mode with root `beta_l` = beta L of a beam of length `length` (m).
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
        let zero = Self { beta, length, a: 0.0, b: 0.0, c: 0.0, d: 0.0, p: 0.0, r: 0.0 };
        let e = (-beta_l).exp();
        let (sn, cs) = beta_l.sin_cos();
        let (s, a) = match support {
            Support::PinnedPinned => return Self { d: std::f64::consts::SQRT_2, ..zero },
            Support::ClampedFree => {
                let den = 1.0 - e * e + 2.0 * e * sn;
                ((1.0 + e * e + 2.0 * e * cs) / den, (sn - cs - e) / den)
            }
            Support::ClampedClamped | Support::ClampedPinned | Support::FreeFree => {
                let den = 1.0 - e * e - 2.0 * e * sn;
                ((1.0 + e * e - 2.0 * e * cs) / den, (cs - sn - e) / den)
            }
        };
        let trig = if support == Support::FreeFree { 1.0 } else { -1.0 };
        Self { a, b: 0.5 * (1.0 + s), c: trig, d: -trig * s, ..zero }
    }

    /// Rigid-body translation of a free-free beam: phi = 1.
    pub(crate) fn translation(length: f64) -> Self {
        Self { beta: 0.0, length, a: 0.0, b: 0.0, c: 0.0, d: 0.0, p: 1.0, r: 0.0 }
    }

    /// Rigid-body rotation about the centre of a free-free beam: phi = sqrt(3) (2x/L - 1).
    pub(crate) fn rotation(length: f64) -> Self {
        let k = 3f64.sqrt();
        Self { beta: 0.0, length, a: 0.0, b: 0.0, c: 0.0, d: 0.0, p: -k, r: 2.0 * k }
    }

    /// Wavenumber beta (1/m); zero for a rigid-body mode.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The k-th derivative d^k phi / dx^k at x (m), k = 0 (value), 1 (slope, 1/m),
    /// 2 (curvature, 1/m^2), 3 (1/m^3).
    pub fn derivative(&self, k: u32, x: f64) -> f64 {
        let bk = self.beta.powi(k as i32);
        let right = self.a * (-self.beta * (self.length - x)).exp();
        let left = self.b * (-self.beta * x).exp();
        let left_sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let (s, c) = (self.beta * x).sin_cos();
        // d^k/dx^k of (c cos + d sin) cycles through (cos, -sin, -cos, sin) times beta^k.
        let trig = match k % 4 {
            0 => self.c * c + self.d * s,
            1 => -self.c * s + self.d * c,
            2 => -self.c * c - self.d * s,
            _ => self.c * s - self.d * c,
        };
        let linear = match k {
            0 => self.p + self.r * x / self.length,
            1 => self.r / self.length,
            _ => 0.0,
        };
        bk * (right + left_sign * left + trig) + linear
    }

    /// phi(x).
    pub fn value(&self, x: f64) -> f64 {
        self.derivative(0, x)
    }

    /// phi'(x) (1/m).
    pub fn slope(&self, x: f64) -> f64 {
        self.derivative(1, x)
    }

    /// phi''(x) (1/m^2).
    pub fn curvature(&self, x: f64) -> f64 {
        self.derivative(2, x)
    }

    /// phi''(x) (1/m^2) at x = x0 + k dx for k = 0 .. count, as [`ModeShape::curvature`] gives
    /// it but with two exponentials and one sine and cosine for the whole grid: each term is
    /// carried from point to point by its factor over dx (the decaying exponentials each from
    /// the end where it is largest, the trigonometric pair by a rotation), to about `count`
    /// ulps of the largest term.
    pub fn curvatures_on_grid(&self, x0: f64, dx: f64, count: usize) -> Vec<f64> {
        let mut out = vec![0.0; count];
        if count == 0 {
            return out;
        }
        let b2 = self.beta * self.beta;
        let step = (-self.beta * dx).exp();
        // a exp(-beta (L - x)): largest at the last point, carried downward.
        let last = x0 + dx * (count - 1) as f64;
        let mut right = self.a * (-self.beta * (self.length - last)).exp();
        for v in out.iter_mut().rev() {
            *v += right;
            right *= step;
        }
        // b exp(-beta x): largest at the first point, carried upward.
        let mut left = self.b * (-self.beta * x0).exp();
        let (mut sn, mut cs) = (self.beta * x0).sin_cos();
        let (rs, rc) = (self.beta * dx).sin_cos();
        for v in &mut out {
            // The second derivative of c cos + d sin is -(c cos + d sin) beta^2.
            *v = b2 * (*v + left - (self.c * cs + self.d * sn));
            left *= step;
            (cs, sn) = (cs * rc - sn * rs, sn * rc + cs * rs);
        }
        out
    }
}
