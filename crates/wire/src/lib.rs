//! Wire EDM of spur-gear punches and dies (seed 002, issue 15), the pure
//! part, in progress: the involute of a gear ([`involute`]), the
//! rack-generated tooth space ([`gear`]), and the program formats written
//! and read back: 3B ([`threeb`]), 4B ([`fourb`]), ISO wire G-code
//! ([`iso`]) and the contour as DXF ([`dxf`](mod@crate::dxf)). The whole
//! outline fitted, the offsets, and the family's place in the system are
//! still to come (docs/wire.md).
//!
//! A contour is a `Vec<Segment>` whose segments join end to start, about
//! the gear's centre at the origin, running clockwise (the material on the
//! right of the travel).
#![forbid(unsafe_code)]

pub mod dxf;
pub mod fourb;
pub mod gear;
pub mod involute;
pub mod iso;
pub mod threeb;

/// A piece of a wire path: a line or a circular arc, in mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segment {
    /// A straight move.
    Line {
        /// Start point.
        from: (f64, f64),
        /// End point.
        to: (f64, f64),
    },
    /// A circular arc.
    Arc {
        /// Start point.
        from: (f64, f64),
        /// End point.
        to: (f64, f64),
        /// Centre.
        centre: (f64, f64),
        /// Counter-clockwise (else clockwise).
        ccw: bool,
    },
}

impl Segment {
    /// The start point.
    pub fn from(&self) -> (f64, f64) {
        match *self {
            Segment::Line { from, .. } | Segment::Arc { from, .. } => from,
        }
    }

    /// The end point.
    pub fn to(&self) -> (f64, f64) {
        match *self {
            Segment::Line { to, .. } | Segment::Arc { to, .. } => to,
        }
    }

    /// The arc of an arc spline as a segment (a line when it is straight).
    pub fn of_arc(a: &gearcam_arcfit::Arc) -> Segment {
        match a.circle() {
            None => Segment::Line {
                from: a.start,
                to: a.end(),
            },
            Some((centre, _)) => Segment::Arc {
                from: a.start,
                to: a.end(),
                centre,
                ccw: a.curvature > 0.0,
            },
        }
    }
}
