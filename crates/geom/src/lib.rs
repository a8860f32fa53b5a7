//! The geometry every layer of gearcam shares, written once.
//!
//! - [`plane`]: points of the plane turned about the origin or a centre and
//!   mirrored about a line, for any [`plane::Planar`] point (a `(x, y)` pair or
//!   a `nalgebra` [`Point2`]);
//! - [`involute`]: the involute function, its inverse and the working pressure
//!   angle of a meshing pair, used by the hobbing model and by the wire
//!   family's tooth-space generation;
//! - [`Vector3`]: the 3-D vector of the NC path check's swept-hob clearance,
//!   `nalgebra`'s own.
//!
//! Nothing here knows a gear family, a message or a machine: it depends on
//! `nalgebra` alone, so every crate can use it.

pub mod involute;
pub mod plane;

pub use nalgebra::{Point2, Vector2, Vector3};
