//! # simo-beam: geometrically exact 3D beam
//!
//! (manual written below)

pub mod benchmarks;
mod element;
mod error;
mod mesh;
mod model;
mod modes;
pub mod rotation;
mod section;
mod statics;

pub use element::{Element, Strains};
pub use error::BeamError;
pub use mesh::Mesh;
pub use model::{BeamModel, BeamState, Load, Profile, Support};
pub use modes::{natural_frequencies, natural_modes, Mode};
pub use section::{Material, Section, SHEAR_FACTOR_CIRCLE, SHEAR_FACTOR_RECTANGLE};
pub use statics::{solve_static, StaticOptions, StaticSolution};
