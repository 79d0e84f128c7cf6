//! Saint-Venant torsion of a uniform beam: G J theta'' = rho Ip theta-double-dot
//! (validation/REFERENCES.md 1.9).
//!
//! Warping is free (Saint-Venant), so the twist obeys the wave equation with speed
//! c_t = sqrt(G J / (rho Ip)). An end that is clamped or pinned holds the twist (a pin in a
//! fork: the usual reading of a pinned strip); a free end carries no torque, theta' = 0. The
//! modes, scaled like the bending ones so that integral Theta^2 dx = L:
//!
//! - both ends held: Theta_n = sqrt 2 sin(n pi x / L), omega_n = n pi c_t / L;
//! - held at x = 0, free at x = L: Theta_n = sqrt 2 sin((n - 1/2) pi x / L),
//!   omega_n = (n - 1/2) pi c_t / L;
//! - both free: the rigid twist Theta_0 = 1 (omega = 0), then Theta_n = sqrt 2 cos(n pi x / L).
//!
//! The mass-normalised shape is Theta / sqrt(rho Ip L).

use crate::error::{positive, ModalError};
use crate::support::Support;
use std::f64::consts::{PI, SQRT_2};

/// A uniform beam in Saint-Venant torsion on 0 <= x <= L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torsion {
    rigidity: f64,
    inertia: f64,
    length: f64,
    support: Support,
}

/// Which ends hold the twist.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ends {
    /// Both ends held (clamped or pinned).
    Held,
    /// Held at x = 0, free at x = L.
    HeldFree,
    /// Both ends free.
    Free,
}

/// One torsion mode: Theta(x) = amplitude trig(k x), trig = sin or cos.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorsionMode {
    /// Natural circular frequency (rad/s); 0 for the rigid twist of a free-free beam.
    pub omega: f64,
    /// Wavenumber k (1/m).
    wavenumber: f64,
    /// sqrt 2 for an elastic mode, 1 for the rigid twist.
    amplitude: f64,
    /// cos (free at x = 0) rather than sin.
    cosine: bool,
}

impl TorsionMode {
    /// Theta(x), scaled so that integral Theta^2 dx = L.
    pub fn value(&self, x: f64) -> f64 {
        let phase = self.wavenumber * x;
        self.amplitude * if self.cosine { phase.cos() } else { phase.sin() }
    }

    /// Theta'(x) (1/m): the twist rate, so that the torque is G J Theta'.
    pub fn rate(&self, x: f64) -> f64 {
        let phase = self.wavenumber * x;
        self.amplitude * self.wavenumber * if self.cosine { -phase.sin() } else { phase.cos() }
    }

    /// An upper bound of |Theta^(k+1)| on the beam (1/m^(k+1)): the twist rate's k-th
    /// derivative.
    pub fn rate_bound(&self, k: i32) -> f64 {
        self.amplitude * self.wavenumber.powi(k + 1)
    }
}

impl Torsion {
    /// From the torsional rigidity G J (N m^2), the rotary inertia about the axis per length
    /// rho Ip (kg m), the length L (m) and the end conditions (which ends hold the twist: see
    /// the module's manual).
    ///
    /// # Errors
    /// `InvalidParameter` naming the first value that is not finite and positive.
    pub fn new(
        torsional_rigidity: f64,
        rotary_inertia: f64,
        length: f64,
        support: Support,
    ) -> Result<Self, ModalError> {
        positive("torsional_rigidity", torsional_rigidity, "N m^2")?;
        positive("rotary_inertia", rotary_inertia, "kg m")?;
        positive("length", length, "m")?;
        Ok(Self { rigidity: torsional_rigidity, inertia: rotary_inertia, length, support })
    }

    fn ends(&self) -> Ends {
        match self.support {
            Support::ClampedFree => Ends::HeldFree,
            Support::FreeFree => Ends::Free,
            Support::PinnedPinned | Support::ClampedClamped | Support::ClampedPinned => Ends::Held,
        }
    }

    /// Which ends hold the twist (x = 0, x = L): where a torque reaches a support.
    pub fn held_ends(&self) -> (bool, bool) {
        match self.ends() {
            Ends::HeldFree => (true, false),
            Ends::Held => (true, true),
            Ends::Free => (false, false),
        }
    }

    /// Torsional rigidity G J (N m^2).
    pub fn rigidity(&self) -> f64 {
        self.rigidity
    }

    /// Rotary inertia per length rho Ip (kg m).
    pub fn rotary_inertia(&self) -> f64 {
        self.inertia
    }

    /// Length (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// rho Ip L (kg m^2): divide a shape by its square root to mass-normalise it.
    pub fn mass(&self) -> f64 {
        self.inertia * self.length
    }

    /// The wave speed c_t = sqrt(G J / (rho Ip)) (m/s).
    pub fn wave_speed(&self) -> f64 {
        (self.rigidity / self.inertia).sqrt()
    }

    /// The number of rigid-body modes (the free twist of a free-free beam).
    pub fn rigid_modes(&self) -> usize {
        usize::from(self.ends() == Ends::Free)
    }

    /// Mode n = 0, 1, ... (the rigid twist first where there is one).
    fn mode(&self, n: usize) -> TorsionMode {
        let (index, cosine) = match self.ends() {
            Ends::Held => (n as f64 + 1.0, false),
            Ends::HeldFree => (n as f64 + 0.5, false),
            Ends::Free => (n as f64, true),
        };
        let wavenumber = index * PI / self.length;
        let amplitude = if wavenumber > 0.0 { SQRT_2 } else { 1.0 };
        TorsionMode { omega: wavenumber * self.wave_speed(), wavenumber, amplitude, cosine }
    }

    /// The first `count` modes, in increasing frequency.
    pub fn modes(&self, count: usize) -> Vec<TorsionMode> {
        (0..count).map(|n| self.mode(n)).collect()
    }

    /// How many modes have omega <= `omega` (rad/s), the rigid twist included.
    pub fn count_below(&self, omega: f64) -> usize {
        if omega.is_nan() || omega < 0.0 {
            return 0;
        }
        let index = omega * self.length / (PI * self.wave_speed());
        let offset = match self.ends() {
            Ends::Held => 0.0,
            Ends::HeldFree => 0.5,
            Ends::Free => 1.0,
        };
        // Mode n has index n + 1 (held), n + 1/2 (held-free) or n (free): those at or below
        // `index` number floor(index + offset).
        let count = (index + offset).floor();
        if count.is_finite() && count > 0.0 {
            count.min(1e9) as usize
        } else {
            0
        }
    }

    /// The twist (rad) at x = `c` (m) under a unit static torque (N m) there, or `None` for a
    /// free-free beam (no static solution): c / GJ held-free, c (L - c) / (L GJ) held-held.
    pub fn static_flexibility(&self, c: f64) -> Option<f64> {
        let l = self.length;
        match self.ends() {
            Ends::HeldFree => Some(c / self.rigidity),
            Ends::Held => Some(c * (l - c) / (l * self.rigidity)),
            Ends::Free => None,
        }
    }

    /// The static twist rate theta' (1/m) at x under a unit torque (N m) at `c`: the torque
    /// there over G J (the torque is constant on each side of c, split between held ends in
    /// proportion to the other side's length). `None` for a free-free beam.
    pub fn static_rate(&self, c: f64, x: f64) -> Option<f64> {
        let l = self.length;
        let torque = match self.ends() {
            Ends::HeldFree => f64::from(u8::from(x < c)),
            Ends::Held => {
                if x < c {
                    (l - c) / l
                } else {
                    -c / l
                }
            }
            Ends::Free => return None,
        };
        Some(torque / self.rigidity)
    }
}

/// The Saint-Venant torsion constant J (m^4) of a `width` x `thickness` rectangle by its exact
/// series (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 109):
/// J = (b t^3 / 3) (1 - (192 / pi^5) (t / b) sum over odd n of tanh(n pi b / (2 t)) / n^5),
/// b >= t the longer side; and the factor k of the largest shear stress, at the middle of the
/// longer side, tau_max = k G t theta', k = 1 - (8 / pi^2) sum over odd n of
/// 1 / (n^2 cosh(n pi b / (2 t))).
pub fn rectangle_torsion(width: f64, thickness: f64) -> (f64, f64) {
    let (b, t) = if width >= thickness { (width, thickness) } else { (thickness, width) };
    let (mut j_sum, mut k_sum) = (0.0, 0.0);
    // Terms fall as n^-5 and n^-2 sech: 200 odd terms leave < 1e-12 of either.
    for i in 0..200 {
        let n = (2 * i + 1) as f64;
        let arg = n * PI * b / (2.0 * t);
        j_sum += arg.tanh() / n.powi(5);
        k_sum += if arg < 700.0 { 1.0 / (n * n * arg.cosh()) } else { 0.0 };
    }
    let j = b * t.powi(3) / 3.0 * (1.0 - 192.0 / PI.powi(5) * (t / b) * j_sum);
    let k = 1.0 - 8.0 / (PI * PI) * k_sum;
    (j, k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_has_the_tabulated_constant() {
        // Timoshenko & Goodier, table of sec. 109: b/t = 1: J = 0.141 b t^3, tau = 0.675 G t theta'.
        let (j, k) = rectangle_torsion(1.0, 1.0);
        assert!((j - 0.1406).abs() < 1e-4, "{j}");
        assert!((k - 0.675).abs() < 1e-3, "{k}");
        // A thin strip: J -> b t^3 / 3 (1 - 0.630 t / b), k -> 1.
        let (j, k) = rectangle_torsion(0.025, 0.005);
        let thin = 0.025 * 0.005f64.powi(3) / 3.0 * (1.0 - 0.630 * 0.2);
        assert!((j / thin - 1.0).abs() < 1e-3, "{j} vs {thin}");
        assert!((k - 1.0).abs() < 1e-3, "{k}");
    }

    #[test]
    fn counts_agree_with_the_modes() {
        for support in Support::ALL {
            let t = Torsion::new(2.0, 0.5, 1.3, support).unwrap();
            let modes = t.modes(40);
            for n in 0..39 {
                let between = 0.5 * (modes[n].omega + modes[n + 1].omega);
                assert_eq!(t.count_below(between), n + 1, "{support:?} {n}");
            }
        }
    }
}
