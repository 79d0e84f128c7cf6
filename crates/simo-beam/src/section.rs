//! Cross-section properties: the diagonal stiffness and inertia of a Simo beam section.

use crate::error::{positive, BeamError};

/// Linear elastic material of the beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Shear modulus G (Pa).
    pub shear_modulus: f64,
    /// Density rho (kg/m^3).
    pub density: f64,
}

impl Material {
    /// From E (Pa), Poisson's ratio nu and density (kg/m^3); `G = E / (2 (1 + nu))`.
    ///
    /// # Errors
    /// [`BeamError::InvalidParameter`] for a non-positive modulus or density, or nu outside
    /// (-1, 0.5).
    pub fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Result<Self, BeamError> {
        positive("youngs_modulus", youngs_modulus)?;
        positive("density", density)?;
        if !(poisson_ratio.is_finite() && poisson_ratio > -1.0 && poisson_ratio < 0.5) {
            return Err(BeamError::InvalidParameter {
                name: "poisson_ratio",
                value: poisson_ratio,
                allowed: "a number in (-1, 0.5)",
            });
        }
        Ok(Self {
            youngs_modulus,
            shear_modulus: youngs_modulus / (2.0 * (1.0 + poisson_ratio)),
            density,
        })
    }
}

/// Section stiffness `diag(EA, GA2, GA3, GJ, EI2, EI3)` and inertia per unit length, in the
/// section frame (E1 along the beam axis, E2 and E3 the principal axes of the section).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Axial stiffness EA (N).
    pub ea: f64,
    /// Shear stiffness along E2, k G A (N).
    pub ga2: f64,
    /// Shear stiffness along E3, k G A (N).
    pub ga3: f64,
    /// Torsional stiffness G J (N m^2).
    pub gj: f64,
    /// Bending stiffness about E2, E I2 (N m^2).
    pub ei2: f64,
    /// Bending stiffness about E3, E I3 (N m^2).
    pub ei3: f64,
    /// Mass per unit length rho A (kg/m).
    pub rho_a: f64,
    /// Rotational inertia per unit length about E1, E2, E3: rho (I2 + I3), rho I2, rho I3 (kg m).
    pub rho_i: [f64; 3],
}

/// Shear correction factor of a rectangle (Timoshenko's 5/6).
pub const SHEAR_FACTOR_RECTANGLE: f64 = 5.0 / 6.0;
/// Shear correction factor of a solid circle, `6 (1 + nu) / (7 + 6 nu)` at nu = 0.3 is 0.886;
/// the common nu-free value 0.9 is used.
pub const SHEAR_FACTOR_CIRCLE: f64 = 0.9;

impl Section {
    /// A solid rectangle of `width` along E2 and `thickness` along E3 (m). Bending about E2 uses
    /// `I2 = w t^3 / 12` (the flexible direction when t < w). Saint-Venant torsion constant
    /// `J = b c^3 (1/3 - 0.21 (c/b)(1 - (c/b)^4/12))` with b >= c (Roark).
    ///
    /// # Errors
    /// [`BeamError::InvalidParameter`] for non-positive dimensions.
    pub fn rectangle(material: &Material, width: f64, thickness: f64) -> Result<Self, BeamError> {
        positive("width", width)?;
        positive("thickness", thickness)?;
        let area = width * thickness;
        let i2 = width * thickness.powi(3) / 12.0;
        let i3 = thickness * width.powi(3) / 12.0;
        let (b, c) = (width.max(thickness), width.min(thickness));
        let r = c / b;
        let j = b * c.powi(3) * (1.0 / 3.0 - 0.21 * r * (1.0 - r.powi(4) / 12.0));
        Ok(Self::from_geometry(material, area, i2, i3, j, SHEAR_FACTOR_RECTANGLE))
    }

    /// A solid circle of `radius` (m).
    ///
    /// # Errors
    /// [`BeamError::InvalidParameter`] for a non-positive radius.
    pub fn circle(material: &Material, radius: f64) -> Result<Self, BeamError> {
        positive("radius", radius)?;
        let area = std::f64::consts::PI * radius * radius;
        let i = 0.25 * std::f64::consts::PI * radius.powi(4);
        Ok(Self::from_geometry(material, area, i, i, 2.0 * i, SHEAR_FACTOR_CIRCLE))
    }

    fn from_geometry(m: &Material, area: f64, i2: f64, i3: f64, j: f64, k: f64) -> Self {
        let (e, g, rho) = (m.youngs_modulus, m.shear_modulus, m.density);
        Self {
            ea: e * area,
            ga2: k * g * area,
            ga3: k * g * area,
            gj: g * j,
            ei2: e * i2,
            ei3: e * i3,
            rho_a: rho * area,
            rho_i: [rho * (i2 + i3), rho * i2, rho * i3],
        }
    }

    /// Checks every number is finite and positive (benchmarks give stiffnesses directly).
    ///
    /// # Errors
    /// [`BeamError::InvalidParameter`] naming the first bad entry.
    pub fn validated(self) -> Result<Self, BeamError> {
        positive("EA", self.ea)?;
        positive("GA2", self.ga2)?;
        positive("GA3", self.ga3)?;
        positive("GJ", self.gj)?;
        positive("EI2", self.ei2)?;
        positive("EI3", self.ei3)?;
        positive("rho_a", self.rho_a)?;
        for r in self.rho_i {
            positive("rho_i", r)?;
        }
        Ok(self)
    }

    /// Force-strain stiffness diag(EA, GA2, GA3) (N).
    pub(crate) fn force_stiffness(&self) -> [f64; 3] {
        [self.ea, self.ga2, self.ga3]
    }

    /// Moment-curvature stiffness diag(GJ, EI2, EI3) (N m^2).
    pub(crate) fn moment_stiffness(&self) -> [f64; 3] {
        [self.gj, self.ei2, self.ei3]
    }
}
