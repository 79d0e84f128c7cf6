//! # simo-beam: geometrically exact 3D beam
//!
//! (manual written below)

mod element;
mod error;
pub mod rotation;
mod section;

pub use element::{Element, Strains};
pub use error::BeamError;
pub use section::{Material, Section, SHEAR_FACTOR_CIRCLE, SHEAR_FACTOR_RECTANGLE};
