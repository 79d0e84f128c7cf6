//! A uniform Euler-Bernoulli beam and its modes.

use crate::error::{positive, ModalError};
use crate::shape::ModeShape;
use crate::support::Support;

/// A uniform Euler-Bernoulli beam: EI w'''' + rho A w-double-dot = f(x, t) on 0 <= x <= L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beam {
    flexural_rigidity: f64,
    mass_per_length: f64,
    length: f64,
    support: Support,
}

/// One natural mode of a beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// beta L, the root of the characteristic equation (0 for a rigid-body mode).
    pub beta_l: f64,
    /// Natural circular frequency omega = (beta L)^2 sqrt(EI / (rho A L^4)) (rad/s).
    pub omega: f64,
    /// Shape with integral phi^2 dx = L; divide by sqrt(rho A L) to mass-normalise.
    pub shape: ModeShape,
}

impl Beam {
    /// From EI (N m^2), rho A (kg/m), L (m) and the end conditions.
    ///
    /// # Errors
    /// `InvalidParameter` naming the first value that is not finite and positive.
    pub fn new(
        flexural_rigidity: f64,
        mass_per_length: f64,
        length: f64,
        support: Support,
    ) -> Result<Self, ModalError> {
        positive("flexural_rigidity", flexural_rigidity, "N m^2")?;
        positive("mass_per_length", mass_per_length, "kg/m")?;
        positive("length", length, "m")?;
        Ok(Self { flexural_rigidity, mass_per_length, length, support })
    }

    /// A rectangular section of `width` x `thickness` (m), bending across the thickness:
    /// I = width thickness^3 / 12.
    ///
    /// # Errors
    /// `InvalidParameter` naming the first value that is not finite and positive.
    pub fn rectangular(
        youngs_modulus: f64,
        density: f64,
        width: f64,
        thickness: f64,
        length: f64,
        support: Support,
    ) -> Result<Self, ModalError> {
        positive("youngs_modulus", youngs_modulus, "Pa")?;
        positive("density", density, "kg/m^3")?;
        positive("width", width, "m")?;
        positive("thickness", thickness, "m")?;
        let area = width * thickness;
        let inertia = width * thickness.powi(3) / 12.0;
        Self::new(youngs_modulus * inertia, density * area, length, support)
    }

    /// Flexural rigidity EI (N m^2).
    pub fn flexural_rigidity(&self) -> f64 {
        self.flexural_rigidity
    }

    /// Mass per unit length rho A (kg/m).
    pub fn mass_per_length(&self) -> f64 {
        self.mass_per_length
    }

    /// Length L (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// End conditions.
    pub fn support(&self) -> Support {
        self.support
    }

    /// Total mass rho A L (kg), the modal mass of every mode in the textbook scaling.
    pub fn mass(&self) -> f64 {
        self.mass_per_length * self.length
    }

    /// omega for a root beta L (rad/s).
    pub fn omega(&self, beta_l: f64) -> f64 {
        let l2 = self.length * self.length;
        beta_l * beta_l / l2 * (self.flexural_rigidity / self.mass_per_length).sqrt()
    }

    /// The first `count` modes in order of frequency (rigid-body modes first for free-free).
    ///
    /// # Errors
    /// `InvalidParameter` if `count` is zero; `RootNotBracketed` should not occur.
    pub fn modes(&self, count: usize) -> Result<Vec<Mode>, ModalError> {
        if count == 0 {
            return Err(ModalError::InvalidParameter {
                name: "modes",
                value: 0.0,
                unit: "-",
                allowed: "at least one mode",
            });
        }
        let rigid = self.support.rigid_modes();
        (0..count)
            .map(|i| {
                if i < rigid {
                    let shape = if i == 0 {
                        ModeShape::translation(self.length)
                    } else {
                        ModeShape::rotation(self.length)
                    };
                    return Ok(Mode { beta_l: 0.0, omega: 0.0, shape });
                }
                let beta_l = self.support.eigenvalue(i + 1 - rigid)?;
                let shape = ModeShape::elastic(self.support, beta_l, self.length);
                Ok(Mode { beta_l, omega: self.omega(beta_l), shape })
            })
            .collect()
    }

    /// Static flexibility w(c)/P (m/N) under a point force P at x = c, at the force: the
    /// closed forms of beam tables (Roark, Table 8.1): clamped-free c^3/(3EI); pinned-pinned
    /// c^2 (L-c)^2/(3EIL); clamped-clamped c^3 (L-c)^3/(3EIL^3); clamped-pinned
    /// c^3 (L-c)^2 (3L + (L-c))/(12EIL^3). `None` for free-free, which has no static stiffness.
    pub fn static_flexibility(&self, c: f64) -> Option<f64> {
        let (l, ei) = (self.length, self.flexural_rigidity);
        let b = l - c;
        match self.support {
            Support::ClampedFree => Some(c.powi(3) / (3.0 * ei)),
            Support::PinnedPinned => Some(c * c * b * b / (3.0 * ei * l)),
            Support::ClampedClamped => Some(c.powi(3) * b.powi(3) / (3.0 * ei * l.powi(3))),
            Support::ClampedPinned => {
                Some(c.powi(3) * b * b * (3.0 * l + b) / (12.0 * ei * l.powi(3)))
            }
            Support::FreeFree => None,
        }
    }

    /// Static curvature w''(x) (1/m^2 per N) under a unit point force at x = c, both in the
    /// direction of w: the bending moment diagram of beam tables divided by EI (Roark, Table
    /// 8.1), M(x) = EI w''(x). Clamped-free (clamped at 0): (c - x)/EI for x < c, else 0.
    /// Pinned-pinned: -x (L - c)/(L EI) for x <= c, -c (L - x)/(L EI) beyond. Clamped-clamped
    /// and clamped-pinned (clamped at 0): the sagging moment M_s(x) = M_0 + R_0 x - (x - c)_+
    /// with the clamp's moment and reaction of the tables, w'' = -M_s/EI: clamped-clamped
    /// M_0 = -c b^2/L^2, R_0 = b^2 (3c + b)/L^3; clamped-pinned from the pinned end's reaction
    /// R_L = c^2 (3L - c)/(2L^3), M_s(x) = R_L (L - x) - (c - x)_+. `None` for free-free.
    pub fn static_curvature(&self, c: f64, x: f64) -> Option<f64> {
        let (l, ei) = (self.length, self.flexural_rigidity);
        let b = l - c;
        let after = (x - c).max(0.0);
        let sagging = match self.support {
            Support::ClampedFree => -(c - x).max(0.0),
            Support::PinnedPinned => {
                if x <= c {
                    x * b / l
                } else {
                    c * (l - x) / l
                }
            }
            Support::ClampedClamped => {
                -c * b * b / (l * l) + b * b * (3.0 * c + b) / l.powi(3) * x - after
            }
            Support::ClampedPinned => {
                let r_l = c * c * (3.0 * l - c) / (2.0 * l.powi(3));
                r_l * (l - x) - (c - x).max(0.0)
            }
            Support::FreeFree => return None,
        };
        Some(-sagging / ei)
    }
}
