//! The parameters of the alpha family of implicit schemes.

use crate::error::{in_range, HhtError};

/// One member of the generalized-alpha family (Chung & Hulbert 1993), written as
///
/// `(1 - alpha_m) I_{n+1} + alpha_m I_n + (1 - alpha_f) g_{n+1} + alpha_f g_n = 0`
///
/// with `I` the inertial force and `g` the rest of the force balance, and Newmark's updates
/// `d_{n+1} = d_n + h v_n + h^2 ((1/2 - beta) a_n + beta a_{n+1})`,
/// `v_{n+1} = v_n + h ((1 - gamma) a_n + gamma a_{n+1})`.
///
/// HHT-alpha (Hilber, Hughes & Taylor 1977; the paper's eq. 9) is `alpha_m = 0`,
/// `alpha_f = -alpha` with `alpha` in `[-1/3, 0]` (validation/REFERENCES.md 4.1): the force balance is
/// weighted `(1 + alpha)` at the new time and `-alpha` at the old one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scheme {
    /// Weight of the old inertial force, `alpha_m` (dimensionless).
    pub alpha_m: f64,
    /// Weight of the old force balance, `alpha_f` (dimensionless).
    pub alpha_f: f64,
    /// Newmark's beta (dimensionless).
    pub beta: f64,
    /// Newmark's gamma (dimensionless).
    pub gamma: f64,
}

impl Scheme {
    /// HHT-alpha with the original sign convention: `alpha` in `[-1/3, 0]`,
    /// `beta = (1 - alpha)^2 / 4`, `gamma = 1/2 - alpha`. `alpha = 0` is the trapezoidal rule;
    /// the spectral radius at infinite frequency is `(1 + alpha) / (1 - alpha)`.
    ///
    /// # Errors
    /// [`HhtError::InvalidParameter`] when `alpha` is not a number in `[-1/3, 0]`. A positive
    /// alpha with these beta and gamma is unconditionally unstable (validation/REFERENCES.md 4.3), which is
    /// why it is refused rather than clamped.
    pub fn hht(alpha: f64) -> Result<Self, HhtError> {
        in_range(
            "alpha",
            alpha,
            -1.0 / 3.0,
            0.0,
            "HHT alpha in [-1/3, 0] (original sign convention)",
        )?;
        Ok(Self {
            alpha_m: 0.0,
            alpha_f: -alpha,
            beta: 0.25 * (1.0 - alpha) * (1.0 - alpha),
            gamma: 0.5 - alpha,
        })
    }

    /// Generalized-alpha with the optimal parameters of Chung & Hulbert (1993) for a spectral
    /// radius `rho_inf` at infinite frequency (validation/REFERENCES.md 4.4): `alpha_m = (2 rho - 1) /
    /// (rho + 1)`, `alpha_f = rho / (rho + 1)`, `gamma = 1/2 - alpha_m + alpha_f`,
    /// `beta = (1 - alpha_m + alpha_f)^2 / 4`.
    ///
    /// # Errors
    /// [`HhtError::InvalidParameter`] when `rho_inf` is not in `[0, 1]`.
    pub fn generalized_alpha(rho_inf: f64) -> Result<Self, HhtError> {
        in_range("rho_inf", rho_inf, 0.0, 1.0, "a spectral radius in [0, 1]")?;
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        Ok(Self { alpha_m, alpha_f, beta: 0.25 * (gamma + 0.5) * (gamma + 0.5), gamma })
    }

    /// The trapezoidal rule (Newmark, `beta = 1/4`, `gamma = 1/2`): HHT with `alpha = 0`.
    pub fn trapezoidal() -> Self {
        Self { alpha_m: 0.0, alpha_f: 0.0, beta: 0.25, gamma: 0.5 }
    }

    /// Any member of the family from its four numbers, for studies of the scheme itself.
    /// Accepts only the unconditionally stable, second-order region of Chung & Hulbert:
    /// `alpha_m <= alpha_f <= 1/2`, `gamma = 1/2 - alpha_m + alpha_f`,
    /// `1/4 + (alpha_f - alpha_m) / 2 <= beta <= 10` (a larger beta only damps more, far past
    /// any use).
    ///
    /// # Errors
    /// [`HhtError::InvalidParameter`] naming the first number outside that region.
    pub fn custom(alpha_m: f64, alpha_f: f64, beta: f64, gamma: f64) -> Result<Self, HhtError> {
        in_range("alpha_f", alpha_f, -1.0, 0.5, "alpha_f <= 1/2")?;
        in_range("alpha_m", alpha_m, -1.0, alpha_f, "-1 <= alpha_m <= alpha_f")?;
        let g = 0.5 - alpha_m + alpha_f;
        in_range("gamma", gamma, g - 1e-12, g + 1e-12, "gamma = 1/2 - alpha_m + alpha_f")?;
        in_range(
            "beta",
            beta,
            0.25 + 0.5 * (alpha_f - alpha_m),
            10.0,
            "1/4 + (alpha_f - alpha_m)/2 <= beta <= 10",
        )?;
        Ok(Self { alpha_m, alpha_f, beta, gamma })
    }

    /// This scheme if its four numbers are in [`Scheme::custom`]'s region, which every
    /// constructor's are: the integrator checks a scheme written as a struct literal with it
    /// before a step (the unstable convention of validation/REFERENCES.md 4.3 had run to
    /// 1.2e18 in 200 steps without a word, a review's).
    ///
    /// # Errors
    /// As [`Scheme::custom`].
    pub fn checked(self) -> Result<Self, HhtError> {
        Self::custom(self.alpha_m, self.alpha_f, self.beta, self.gamma)
    }
}
