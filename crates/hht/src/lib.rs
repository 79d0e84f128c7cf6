//! # hht: HHT-alpha and generalized-alpha time integration (placeholder)
//!
//! This crate is reserved for the implicit integrator of the paper's eq. (9): HHT-alpha with
//! alpha in [-1/3, 0], beta = (1 - alpha)^2 / 4, gamma = 1/2 - alpha, and the Chung-Hulbert
//! generalized-alpha family of which HHT is a special case, for models
//! `M(q) a + g(q, v, t) = 0` on configuration spaces that may hold rotations.
//!
//! It is filled by the issue "The second method: HHT-alpha time integration and the Simo
//! geometrically exact beam". Nothing here is usable yet; see `../shared/ARCHITECTURE.md`.
