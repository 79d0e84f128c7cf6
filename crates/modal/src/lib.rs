//! # modal: uniform Euler-Bernoulli and Timoshenko beams, exactly and stably
//!
//! Natural modes of a uniform beam EI w'''' + rho A w-double-dot = f(x, t) with any of five end
//! conditions ([`Support`]), or of a Timoshenko beam ([`Beam::with_shear`]: shear deformation and
//! rotary inertia, both branches of its spectrum, validation/REFERENCES.md 1.6), and the exact
//! time propagation of its modes under a point force: the building blocks of Goldsmith's
//! analytic impact method (the paper's eq. 1).
//!
//! **Eigenvalues.** beta_n L solves the characteristic equation written in a bounded form
//! (cos x + sech x = 0 for a cantilever, validation/REFERENCES.md 1.1), found by safeguarded Newton in a
//! bracket of half-width pi/4 around the asymptotic root, to a few ulps for any n.
//! omega_n = (beta_n L)^2 sqrt(EI / (rho A L^4)).
//!
//! **Shapes.** [`ModeShape`] uses the textbook scaling (integral phi^2 dx = L) in a form without
//! growing exponentials (validation/REFERENCES.md 1.3), exact to round-off at mode 1000; the mass-normalised
//! shape is phi / sqrt(rho A L).
//!
//! **Propagation.** Each mode is the oscillator q'' + 2 zeta omega q' + omega^2 q = g F(t),
//! g = phi(c)/sqrt(rho A L), and the displacement at the load point is w = sum g q
//! ([`PointModes`]). [`Transition`] advances all modes exactly over a step h with the force
//! held constant or linear; the end displacement is affine in the end force, which is what makes
//! an implicit contact step a scalar equation. [`duhamel_series`] is the paper's eq. (1),
//! kept as a reference.
//!
//! **Curvatures at a point.** [`Curvatures`]: the curvature of many modes at one point at once
//! and its first two x-derivatives, each wave's factor from a sine, cosine and exponential
//! written in plain arithmetic that the compiler vectorises (`lanes.rs`: Cody and Waite's
//! reduction and Taylor series, within 2 ulp of the standard library's, the same on every
//! processor): what a search for the largest bending stress evaluates at each new point.
//!
//! **Torsion.** [`Torsion`]: Saint-Venant torsion of the same uniform beam (G J theta'' =
//! rho Ip theta-double-dot, sine or cosine modes; a clamped or pinned end holds the twist),
//! its static twist, and [`rectangle_torsion`], the exact torsion constant of a rectangle: what
//! an off-centre strike adds to the bending modes (validation/REFERENCES.md 1.9).
//!
//! **Any basis.** [`SiteModes`]: the kept modes at a contact site with the site's static
//! flexibility (the residual flexibility is their difference), and [`Recovery`]: quantities
//! linear in the motion read from the modal coordinates and the force, mode-acceleration
//! form. What the impact coupling needs of a basis, whether this crate's analytic uniform beam
//! or modes computed from a finite-element model of a structure (`simo_beam::modes_below`).
//!
//! **Units.** SI: m, kg, s, N; modal coordinates in m sqrt(kg).
//!
//! ```
//! use modal::{Beam, Hold, ModalState, PointModes, Support, Transition};
//!
//! // The paper's cantilever: steel, 25 x 5 mm, L = 1.15 m.
//! let beam = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, Support::ClampedFree)?;
//! let modes = beam.modes(64)?;
//! assert!((modes[0].beta_l - 1.87510406871196).abs() < 1e-13);
//! let tip = PointModes::new(&beam, &modes, 1.15, 0.0)?;
//! // A 1 N force held for 1 ms on the tip, from rest.
//! let step = Transition::new(&tip, 1e-3, Hold::Zero)?;
//! let mut state = ModalState::at_rest(modes.len());
//! step.advance(&mut state, 1.0, 1.0);
//! assert!(tip.displacement(&state) > 0.0);
//! # Ok::<(), modal::ModalError>(())
//! ```

mod beam;
mod duhamel;
mod error;
mod lanes;
mod propagate;
mod shape;
mod site;
mod support;
mod timoshenko;
mod torsion;

pub use beam::{Beam, Mode, Shear, Theory};
pub use duhamel::duhamel_series;
pub use error::ModalError;
pub use lanes::on_four_lanes;
pub use propagate::{Hold, ModalState, OneStep, PointModes, Transition};
pub use shape::{Curvatures, ModeShape};
pub use site::{Recovery, SiteModes};
pub use support::Support;
pub use torsion::{rectangle_torsion, Torsion, TorsionMode};
