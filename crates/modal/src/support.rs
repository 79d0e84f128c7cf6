//! End conditions and their well-conditioned characteristic equations.

use crate::error::ModalError;
use std::f64::consts::PI;

/// End conditions of a uniform beam, x = 0 first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Support {
    /// Clamped at x = 0, free at x = L (a cantilever).
    ClampedFree,
    /// Pinned at both ends (simply supported).
    PinnedPinned,
    /// Clamped at both ends.
    ClampedClamped,
    /// Clamped at x = 0, pinned at x = L (propped cantilever).
    ClampedPinned,
    /// Free at both ends: two rigid-body modes, then the elastic ones.
    FreeFree,
}

impl Support {
    /// All supports.
    pub const ALL: [Support; 5] = [
        Support::ClampedFree,
        Support::PinnedPinned,
        Support::ClampedClamped,
        Support::ClampedPinned,
        Support::FreeFree,
    ];

    /// The scene-file name, e.g. `clamped-free`.
    pub fn name(self) -> &'static str {
        match self {
            Support::ClampedFree => "clamped-free",
            Support::PinnedPinned => "pinned-pinned",
            Support::ClampedClamped => "clamped-clamped",
            Support::ClampedPinned => "clamped-pinned",
            Support::FreeFree => "free-free",
        }
    }

    /// Parses a scene-file name.
    ///
    /// # Errors
    /// `UnknownSupport` naming the value and the allowed names.
    pub fn from_name(name: &str) -> Result<Self, ModalError> {
        Self::ALL
            .into_iter()
            .find(|s| s.name() == name)
            .ok_or_else(|| ModalError::UnknownSupport(name.to_owned()))
    }

    /// Number of rigid-body modes (zero frequency) that come before the elastic ones.
    pub fn rigid_modes(self) -> usize {
        if self == Support::FreeFree {
            2
        } else {
            0
        }
    }

    /// Asymptotic root (beta L) of elastic mode n >= 1, which is also the centre of a bracket
    /// of half-width pi/4 that holds exactly that root (validation/REFERENCES.md 1.1).
    pub(crate) fn asymptotic_root(self, n: usize) -> f64 {
        let n = n as f64;
        match self {
            Support::ClampedFree => (2.0 * n - 1.0) * PI / 2.0,
            Support::PinnedPinned => n * PI,
            Support::ClampedClamped | Support::FreeFree => (2.0 * n + 1.0) * PI / 2.0,
            Support::ClampedPinned => (4.0 * n + 1.0) * PI / 4.0,
        }
    }

    /// The characteristic function in a bounded form and its derivative. The textbook forms
    /// (e.g. 1 + cos x cosh x = 0) have derivatives ~cosh x ~ 1e13 at mode 10 and lose digits;
    /// dividing by cosh x keeps every term of order one (validation/REFERENCES.md 1.1):
    /// clamped-free cos x + sech x; clamped-clamped and free-free cos x - sech x;
    /// clamped-pinned sin x - cos x tanh x; pinned-pinned sin x.
    pub(crate) fn characteristic(self, x: f64) -> (f64, f64) {
        let (s, c) = x.sin_cos();
        let sech = 1.0 / x.cosh();
        let tanh = x.tanh();
        match self {
            Support::ClampedFree => (c + sech, -s - sech * tanh),
            Support::ClampedClamped | Support::FreeFree => (c - sech, -s + sech * tanh),
            Support::ClampedPinned => (s - c * tanh, c + s * tanh - c * sech * sech),
            Support::PinnedPinned => (s, c),
        }
    }

    /// beta_n L of elastic mode n >= 1, by safeguarded Newton in a sign-changing bracket,
    /// to a few ulps.
    ///
    /// # Errors
    /// `RootNotBracketed` if the bracket does not change sign (not expected for any n).
    pub fn eigenvalue(self, n: usize) -> Result<f64, ModalError> {
        let guess = self.asymptotic_root(n.max(1));
        if self == Support::PinnedPinned {
            return Ok(guess);
        }
        let (mut lo, mut hi) = (guess - PI / 4.0, guess + PI / 4.0);
        let (f_lo, _) = self.characteristic(lo);
        let (f_hi, _) = self.characteristic(hi);
        if f_lo * f_hi > 0.0 {
            return Err(ModalError::RootNotBracketed { mode: n, support: self.name(), guess });
        }
        let rising = f_hi > f_lo;
        let mut x = guess;
        // Safeguarded Newton: a Newton step that leaves the bracket is replaced by bisection.
        for _ in 0..200 {
            let (f, df) = self.characteristic(x);
            if (f > 0.0) == rising {
                hi = x;
            } else {
                lo = x;
            }
            let newton = x - f / df;
            let next = if newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
            let done = (next - x).abs() <= 1e-9 * x;
            x = next;
            if done {
                break;
            }
        }
        // Polish: Newton converges quadratically here, so a few steps reach the f64 root; stop
        // when the residual no longer falls (round-off).
        let mut f = self.characteristic(x).0;
        for _ in 0..4 {
            let (_, df) = self.characteristic(x);
            let next = x - f / df;
            let f_next = self.characteristic(next).0;
            if f_next.abs() >= f.abs() {
                break;
            }
            x = next;
            f = f_next;
        }
        Ok(x)
    }
}

impl std::fmt::Display for Support {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
