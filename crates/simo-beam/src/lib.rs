//! # simo-beam: geometrically exact 3D beam
//!
//! Simo's (1985) finite-strain rod: centre line `r(s)` and section rotation `Lambda(s)`, strains
//! `Gamma = Lambda^T r' - E1` (extension, two shears) and `K = axial(Lambda^T Lambda')` (torsion,
//! two bendings), section stiffness `diag(EA, GA2, GA3, GJ, EI2, EI3)` ([`Section`]).
//!
//! - Two-node elements with one-point (reduced) integration against shear locking; rotations
//!   stored as unit quaternions and interpolated relative to the element's midpoint rotation
//!   (Crisfield & Jelenic 1999), so strains are objective and results path independent
//!   ([`Element`]). The tangent is the exact derivative of the internal force along the update
//!   `Lambda <- Lambda exp(th^)`, by forward-mode automatic differentiation (num-dual).
//! - [`BeamModel`] implements [`hht::Model`]: six unknowns per free node (displacement, material
//!   rotation increment); consistent translational mass, lumped rotary inertia with the
//!   gyroscopic term; dead and follower point loads with their load stiffness, in time through a
//!   [`Profile`].
//! - [`PlanarBeam`]: the same rod restricted to the x-z plane (three unknowns a node, analytic
//!   tangent, banded Newton matrix), for motions that stay in a plane, such as a ball striking
//!   the beam's face; point masses and elastic supports at its nodes
//!   ([`PlanarBeam::attach_mass`], [`PlanarBeam::attach_spring`]), its modes by [`planar_modes`].
//! - [`solve_static`]: Newton with load steps and automatic step cutting.
//! - [`natural_modes`]: linearised modes about the reference configuration (faer, dense).
//! - `scene` (feature `scene`): beam-only scene files (TOML) under prescribed loads, static or
//!   dynamic, as `cargo xtask beam` runs them.
//! - [`benchmarks`]: the problems of validation/REFERENCES.md section 3, as tested and validated.
//!
//! Units are SI; a rectangle's `width` lies along E2 and its `thickness` along E3, so bending
//! with `EI2 = E w t^3 / 12` deflects along E3.
//!
//! ## Example: mesh, model, loads, solve
//! The paper's steel strip (L = 1.15 m, 25 x 5 mm) clamped at x = 0 with 1 N pulling its free
//! end down: small enough that the tip deflection is the Euler-Bernoulli `P L^3 / (3 E I)`
//! (plus a shear term of (h / L)^2 and a geometric one of (w / L)^2, both below 1e-4), less the
//! one-point-integrated element's `1 / (4 n^2)` (6e-5 at n = 64; 1e-3 at n = 16).
//! ```
//! use nalgebra::Vector3;
//! use simo_beam::{solve_static, BeamModel, Load, Material, Mesh, Profile, Section, StaticOptions, Support};
//!
//! let steel = Material::new(2.1e11, 0.3, 7850.0)?;
//! let section = Section::rectangle(&steel, 0.025, 0.005)?; // width along E2, thickness along E3
//! let (length, elements) = (1.15, 64);
//! let mesh = Mesh::straight(Vector3::zeros(), Vector3::new(length, 0.0, 0.0), elements, section, Vector3::z())?;
//! let tip_load = Load {
//!     node: elements,
//!     force: Vector3::new(0.0, 0.0, -1.0), // (N), dead
//!     moment: Vector3::zeros(),
//!     follower: false,
//!     profile: Profile::Constant,
//! };
//! let model = BeamModel::new(mesh)?.support(0, Support::Clamped)?.load(tip_load)?;
//! let solution = solve_static(&model, StaticOptions::default())?;
//! let deflection = -solution.state.positions[elements].z;
//! let ei = 2.1e11 * 0.025 * 0.005_f64.powi(3) / 12.0;
//! let bernoulli = length.powi(3) / (3.0 * ei);
//! assert!((deflection - bernoulli).abs() < 3e-4 * bernoulli, "{deflection} vs {bernoulli}");
//! # Ok::<(), simo_beam::BeamError>(())
//! ```
//!
//! [`benchmarks`] builds the published problems the same way; `mattiasson(1.0, 32, 2)` gives
//! the large-deflection tip of validation/REFERENCES.md 3.3.

pub mod benchmarks;
mod eigen;
mod element;
mod element_block;
mod error;
mod mesh;
mod model;
mod modes;
mod planar;
pub mod rotation;
#[cfg(feature = "scene")]
pub mod scene;
mod section;
mod statics;

pub use element::{Element, Strains};
pub use error::BeamError;
pub use mesh::Mesh;
pub use model::{BeamModel, BeamState, Load, Profile, Support};
pub use modes::{
    bending_frequencies, modes_below, natural_frequencies, natural_modes, planar_modes,
    planar_modes_below, rigid_body_modes, AtRest, Mode,
};
pub use planar::{PlanarBeam, PlanarState};
pub use section::{Material, Section, SHEAR_FACTOR_CIRCLE, SHEAR_FACTOR_RECTANGLE};
pub use statics::{solve_static, StaticOptions, StaticSolution};
