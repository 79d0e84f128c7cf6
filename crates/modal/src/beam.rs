//! A uniform beam, Euler-Bernoulli or Timoshenko, and its modes.

use crate::error::{positive, ModalError};
use crate::shape::ModeShape;
use crate::support::Support;
use crate::timoshenko::Timoshenko;

/// A uniform beam on 0 <= x <= L: Euler-Bernoulli, EI w'''' + rho A w-double-dot = f(x, t), or,
/// with [`Shear`], Timoshenko (shear deformation and rotary inertia, `crate::timoshenko`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beam {
    flexural_rigidity: f64,
    mass_per_length: f64,
    length: f64,
    support: Support,
    shear: Option<Shear>,
}

/// What a Timoshenko beam adds to an Euler-Bernoulli one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shear {
    /// Shear rigidity k G A (N), k the section's shear coefficient (5/6 for a rectangle).
    pub rigidity: f64,
    /// Rotary inertia per unit length rho I (kg m).
    pub rotary_inertia: f64,
}

/// The beam theory of a [`Beam`]: the one place a third theory would be added (a variant here,
/// its modes in a module of its own, its static flexibility and moment in [`Beam`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Theory {
    /// Plane sections stay normal to the axis; no rotary inertia.
    EulerBernoulli,
    /// Shear deformation and rotary inertia (Timoshenko 1921).
    Timoshenko,
}

/// One natural mode of a beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// beta L: for an Euler-Bernoulli beam the root of the characteristic equation, for a
    /// Timoshenko beam the bending wavenumber of the mode times L (0 for a rigid-body mode).
    pub beta_l: f64,
    /// Natural circular frequency (rad/s): omega = (beta L)^2 sqrt(EI / (rho A L^4)) for an
    /// Euler-Bernoulli beam; for a Timoshenko beam the root of its own frequency equation,
    /// below that formula of its `beta_l` (shear and rotary inertia lower it: a review's
    /// pinned-pinned 25 x 50 mm strip of 0.5 m, 2899 against 2947 rad/s in the first mode,
    /// 2.03e5 against 4.73e5 in the thirteenth), so not to be rescaled by it.
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
        Ok(Self { flexural_rigidity, mass_per_length, length, support, shear: None })
    }

    /// The same beam with shear deformation and rotary inertia (a Timoshenko beam): shear
    /// rigidity k G A (N) and rotary inertia per unit length rho I (kg m).
    ///
    /// # Errors
    /// `InvalidParameter` naming the first value that is not finite and positive.
    pub fn with_shear(self, shear_rigidity: f64, rotary_inertia: f64) -> Result<Self, ModalError> {
        positive("shear_rigidity", shear_rigidity, "N")?;
        positive("rotary_inertia", rotary_inertia, "kg m")?;
        Ok(Self { shear: Some(Shear { rigidity: shear_rigidity, rotary_inertia }), ..self })
    }

    /// The same beam as Euler-Bernoulli would model it.
    pub fn euler_bernoulli(self) -> Self {
        Self { shear: None, ..self }
    }

    /// Its beam theory.
    pub fn theory(&self) -> Theory {
        match self.shear {
            None => Theory::EulerBernoulli,
            Some(_) => Theory::Timoshenko,
        }
    }

    /// Shear rigidity and rotary inertia, for a Timoshenko beam.
    pub fn shear(&self) -> Option<Shear> {
        self.shear
    }

    fn timoshenko(&self) -> Option<Timoshenko> {
        self.shear.map(|s| Timoshenko {
            ei: self.flexural_rigidity,
            rho_a: self.mass_per_length,
            kga: s.rigidity,
            rho_i: s.rotary_inertia,
            length: self.length,
            support: self.support,
        })
    }

    /// Shear flexibility 1/(k G A) (1/N); 0 for Euler-Bernoulli.
    fn shear_flexibility(&self) -> f64 {
        self.shear.map_or(0.0, |s| 1.0 / s.rigidity)
    }

    /// The circular frequency (rad/s) above which a Timoshenko beam's second (shear) branch
    /// travels, sqrt(k G A / rho I); `None` for Euler-Bernoulli.
    pub fn shear_cutoff(&self) -> Option<f64> {
        self.timoshenko().map(|t| t.cutoff())
    }

    /// Number of natural frequencies (rigid-body modes included) below `omega` (rad/s): for
    /// Timoshenko the exact Wittrick-Williams count of both branches.
    ///
    /// # Errors
    /// `RootNotBracketed` should not occur.
    pub fn count_below(&self, omega: f64) -> Result<usize, ModalError> {
        if let Some(t) = self.timoshenko() {
            return Ok(t.count_below(omega));
        }
        let rigid = if omega > 0.0 { self.support.rigid_modes() } else { 0 };
        let mut n = 0;
        while n < 1_000_000 && self.omega(self.support.eigenvalue(n + 1)?) < omega {
            n += 1;
        }
        Ok(rigid + n)
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

    /// Euler-Bernoulli omega for a root beta L (rad/s).
    pub fn omega(&self, beta_l: f64) -> f64 {
        let l2 = self.length * self.length;
        beta_l * beta_l / l2 * (self.flexural_rigidity / self.mass_per_length).sqrt()
    }

    /// The first `count` modes in order of frequency (rigid-body modes first for free-free),
    /// of the beam's theory; a Timoshenko beam's list holds both branches as they come.
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
        let rigid = self.support.rigid_modes().min(count);
        // rho I / rho A, the rotary term of the shapes' scaling (0 for Euler-Bernoulli).
        let rotary = self.shear.map_or(0.0, |s| s.rotary_inertia / self.mass_per_length);
        let mut modes: Vec<Mode> = (0..rigid)
            .map(|i| {
                let shape = if i == 0 {
                    ModeShape::translation(self.length)
                } else {
                    ModeShape::rigid_rotation(self.length, rotary)
                };
                Mode { beta_l: 0.0, omega: 0.0, shape }
            })
            .collect();
        let elastic = count - rigid;
        if let Some(t) = self.timoshenko() {
            if elastic > 0 {
                modes.extend(t.elastic_modes(elastic)?);
            }
            return Ok(modes);
        }
        for n in 1..=elastic {
            let beta_l = self.support.eigenvalue(n)?;
            let shape = ModeShape::elastic(self.support, beta_l, self.length);
            modes.push(Mode { beta_l, omega: self.omega(beta_l), shape });
        }
        Ok(modes)
    }

    /// Static flexibility w(c)/P (m/N) under a point force P at x = c, at the force, shear
    /// included for a Timoshenko beam (g = 1/(k G A), 0 for Euler-Bernoulli). The closed forms of
    /// beam tables (Roark, Table 8.1) with the shear deflection of the unit-load method:
    /// clamped-free c^3/(3EI) + c g; pinned-pinned c^2 (L-c)^2/(3EIL) + c (L-c) g / L. The two
    /// statically indeterminate supports by the force method on the cantilever clamped at 0
    /// (`redundants`). `None` for free-free, which has no static stiffness, and for a point
    /// off the beam (c not in [0, L], or not a number: the closed forms had answered there,
    /// a negative flexibility at c = -1, a review's).
    pub fn static_flexibility(&self, c: f64) -> Option<f64> {
        let c = self.on_beam(c)?;
        let (l, ei, g) = (self.length, self.flexural_rigidity, self.shear_flexibility());
        let b = l - c;
        match self.support {
            Support::PinnedPinned => Some(c * c * b * b / (3.0 * ei * l) + c * b * g / l),
            // The influence line at the force (the same sums, to the bit).
            _ => self.static_deflection(c, c),
        }
    }

    /// Static deflection w(x)/P (m/N) at `x` under a point force P at `c`, both along w, shear
    /// included for a Timoshenko beam: [`Beam::static_flexibility`]'s influence line (at x = c
    /// the same; symmetric in x and c, Maxwell). Pinned-pinned by the beam tables (Roark,
    /// Table 8.1): x b (L^2 - b^2 - x^2)/(6 EI L) for x <= c, b = L - c, plus x b g / L; a
    /// clamp at 0 by the cantilever's line and the redundants at L. `None` for free-free and
    /// for points off the beam.
    pub fn static_deflection(&self, c: f64, x: f64) -> Option<f64> {
        let (c, x) = (self.on_beam(c)?, self.on_beam(x)?);
        let (l, ei, g) = (self.length, self.flexural_rigidity, self.shear_flexibility());
        match self.support {
            Support::FreeFree => None,
            Support::PinnedPinned => {
                let (x, c) = if x <= c { (x, c) } else { (l - x, l - c) };
                let b = l - c;
                Some(x * b * (l * l - b * b - x * x) / (6.0 * ei * l) + x * b * g / l)
            }
            _ => {
                let (force, moment) = self.redundants(c)?;
                Some(
                    self.cantilever(x, c)
                        + force * self.cantilever(x, l)
                        + moment * x * x / (2.0 * ei),
                )
            }
        }
    }

    /// Deflection at x of the cantilever clamped at 0 under a unit force at a (m/N):
    /// x^2 (3a - x)/(6EI) + x g for x <= a, symmetric in x and a (Maxwell).
    fn cantilever(&self, x: f64, a: f64) -> f64 {
        let (x, a) = if x <= a { (x, a) } else { (a, x) };
        x * x * (3.0 * a - x) / (6.0 * self.flexural_rigidity) + x * self.shear_flexibility()
    }

    /// The force (N, along w) and moment (N m, turning as +Psi) that the support at x = L puts on
    /// the cantilever clamped at 0 under a unit force at c, from w(L) = 0 (and Psi(L) = 0 for a
    /// clamp): the force method with the tip flexibilities L^3/(3EI) + L g, L^2/(2EI), L/EI and
    /// the load's tip deflection and rotation, cantilever(L, c) and c^2/(2EI). Zero for a free
    /// end; `None` for pinned-pinned and free-free (not clamped at 0).
    fn redundants(&self, c: f64) -> Option<(f64, f64)> {
        let (l, ei) = (self.length, self.flexural_rigidity);
        let deflection = self.cantilever(l, c);
        match self.support {
            Support::ClampedFree => Some((0.0, 0.0)),
            Support::ClampedPinned => Some((-deflection / self.cantilever(l, l), 0.0)),
            Support::ClampedClamped => {
                let (f11, f12, f22) = (self.cantilever(l, l), l * l / (2.0 * ei), l / ei);
                let rotation = c * c / (2.0 * ei);
                let det = f11 * f22 - f12 * f12;
                Some((
                    -(f22 * deflection - f12 * rotation) / det,
                    -(f11 * rotation - f12 * deflection) / det,
                ))
            }
            Support::PinnedPinned | Support::FreeFree => None,
        }
    }

    /// `x` (m) on the beam: in [0, L] to within round-off's 1e-9 L (a grid's last point may
    /// land an ulp past L), held to it; `None` off it or not a number.
    fn on_beam(&self, x: f64) -> Option<f64> {
        let slack = 1e-9 * self.length;
        (x >= -slack && x <= self.length + slack).then(|| x.clamp(0.0, self.length))
    }

    /// Static bending curvature Psi'(x) = M(x)/EI (1/m^2 per N) under a unit point force at
    /// x = c, both in the direction of w (W'' for Euler-Bernoulli): the bending moment diagram
    /// of beam tables (Roark, Table 8.1). Pinned-pinned: -x (L - c)/(L EI) for x <= c,
    /// -c (L - x)/(L EI) beyond. Supports clamped at 0: the cantilever's (c - x)_+ plus the far
    /// support's force F and moment M (`redundants`, shear included): ((c - x)_+ + F (L - x) +
    /// M)/EI. Free-free, by inertia relief (the force balanced by the rigid-body motion's
    /// inertia, which the elastic modes' static sum holds): the rigid acceleration a0 +
    /// alpha (s - L/2) with a0 = 1/(rho A L) and alpha = (c - L/2)/(rho A L^3/12 + rho I L),
    /// and M(x) = (c - x)_+ - rho A [(a0 + alpha (x - L/2)) b^2/2 + alpha b^3/3] - rho I alpha b
    /// over the part beyond x, b = L - x (zero at both ends). `None` for a point off the beam
    /// (c or x not in [0, L]).
    pub fn static_curvature(&self, c: f64, x: f64) -> Option<f64> {
        let (c, x) = (self.on_beam(c)?, self.on_beam(x)?);
        let (l, ei) = (self.length, self.flexural_rigidity);
        if self.support == Support::FreeFree {
            let (mu, rho_i) = (self.mass_per_length, self.shear.map_or(0.0, |s| s.rotary_inertia));
            let a0 = 1.0 / (mu * l);
            let alpha = (c - 0.5 * l) / (mu * l.powi(3) / 12.0 + rho_i * l);
            let b = l - x;
            let inertia =
                mu * ((a0 + alpha * (x - 0.5 * l)) * b * b / 2.0 + alpha * b.powi(3) / 3.0);
            return Some(((c - x).max(0.0) - inertia - rho_i * alpha * b) / ei);
        }
        if self.support == Support::PinnedPinned {
            let sagging = if x <= c { x * (l - c) / l } else { c * (l - x) / l };
            return Some(-sagging / ei);
        }
        let (force, moment) = self.redundants(c)?;
        Some(((c - x).max(0.0) + force * (l - x) + moment) / ei)
    }
}
