//! # simo-beam: geometrically exact 3D beam (placeholder)
//!
//! This crate is reserved for Simo's (1985) finite-strain beam: centre line r(s) and rotation
//! Lambda(s), strains Gamma = Lambda^T r' - E1 and K = axial(Lambda^T Lambda'), two-node elements
//! with reduced integration and rotations interpolated relative to a reference rotation
//! (Crisfield & Jelenic 1999), implementing `hht::Model`.
//!
//! It is filled by the issue "The second method: HHT-alpha time integration and the Simo
//! geometrically exact beam". Nothing here is usable yet; see `../shared/ARCHITECTURE.md`.
