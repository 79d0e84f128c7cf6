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
//! - [`solve_static`]: Newton with load steps and automatic step cutting.
//! - [`natural_modes`]: linearised modes about the reference configuration (faer, dense).
//! - `scene` (feature `scene`): beam-only scene files (TOML) under prescribed loads, static or
//!   dynamic, as `cargo xtask beam` runs them.
//! - [`benchmarks`]: the problems of REFERENCES.md section 3, as tested and validated.
//!
//! Units are SI; a rectangle's `width` lies along E2 and its `thickness` along E3, so bending
//! with `EI2 = E w t^3 / 12` deflects along E3.
//!
//! ## Example
//! ```
//! use simo_beam::benchmarks::mattiasson;
//! // Mattiasson's cantilever at k = P L^2 / EI = 1: tip deflection w/L = 0.30172 (REFERENCES.md 3.3).
//! let [_u, w, _rotation] = mattiasson(1.0, 32, 2)?;
//! assert!((w - 0.30172).abs() < 1e-3);
//! # Ok::<(), simo_beam::BeamError>(())
//! ```

pub mod benchmarks;
mod element;
mod error;
mod mesh;
mod model;
mod modes;
pub mod rotation;
#[cfg(feature = "scene")]
pub mod scene;
mod section;
mod statics;

pub use element::{Element, Strains};
pub use error::BeamError;
pub use mesh::Mesh;
pub use model::{BeamModel, BeamState, Load, Profile, Support};
pub use modes::{natural_frequencies, natural_modes, Mode};
pub use section::{Material, Section, SHEAR_FACTOR_CIRCLE, SHEAR_FACTOR_RECTANGLE};
pub use statics::{solve_static, StaticOptions, StaticSolution};
