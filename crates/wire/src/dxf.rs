//! A contour as a DXF drawing (through the `dxf` crate, MIT), and a
//! drawing read back into a contour (docs/wire.md).
//!
//! The drawing holds LINE and ARC entities only, on layer `OUTLINE`, in
//! mm (`$INSUNITS` 4, so the version is AutoCAD 2000, the first to carry
//! it). An ARC is a true arc: centre, radius, and start and end angles in
//! degrees, counter-clockwise from start to end as DXF requires, so a
//! clockwise arc is written with its ends swapped. An arc that ends where
//! it starts (a whole circle) is written as two half circles.
//!
//! [`read_back`] takes every LINE and ARC, chains them end to start
//! (turning an entity round where its end meets the chain: that recovers an
//! arc's direction), requires the chain to close, and returns it clockwise
//! about the part (material on the right), starting with the drawing's
//! first entity.

use dxf::entities::{Arc, Entity, EntityType, Line};
use dxf::enums::{AcadVersion, Units};
use dxf::tables::Layer;
use dxf::{Drawing, Point};

use crate::Segment;

/// The layer of the outline.
pub const LAYER: &str = "OUTLINE";

/// Two ends closer than this (mm) are joined when chaining.
const JOIN_MM: f64 = 1e-3;

/// A drawing that cannot be written or read back as a contour.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DrawingError {
    /// What is wrong.
    pub message: String,
}

fn error(message: impl Into<String>) -> DrawingError {
    DrawingError {
        message: message.into(),
    }
}

/// The angle of `p` about `c`, degrees in [0, 360).
fn degrees(p: (f64, f64), c: (f64, f64)) -> f64 {
    (p.1 - c.1).atan2(p.0 - c.0).to_degrees().rem_euclid(360.0)
}

/// The DXF text (ASCII) of a contour.
pub fn drawing(contour: &[Segment]) -> Result<Vec<u8>, DrawingError> {
    let mut d = Drawing::new();
    d.header.version = AcadVersion::R2000;
    d.header.default_drawing_units = Units::Millimeters;
    d.add_layer(Layer {
        name: LAYER.into(),
        ..Default::default()
    });
    let mut add = |specific: EntityType| {
        let mut e = Entity::new(specific);
        e.common.layer = LAYER.into();
        d.add_entity(e);
    };
    let pt = |p: (f64, f64)| Point::new(p.0, p.1, 0.0);
    for s in contour {
        match *s {
            Segment::Line { from, to } => add(EntityType::Line(Line::new(pt(from), pt(to)))),
            Segment::Arc {
                from,
                to,
                centre,
                ccw,
            } => {
                let r = (from.0 - centre.0).hypot(from.1 - centre.1);
                let (mut a, mut b) = (degrees(from, centre), degrees(to, centre));
                if !ccw {
                    std::mem::swap(&mut a, &mut b);
                }
                if (from.0 - to.0).hypot(from.1 - to.1) < 1e-9 {
                    // A whole circle: two halves, start and end unambiguous,
                    // the first the half the contour runs first.
                    let half = (a + 180.0).rem_euclid(360.0);
                    let (first, second) = if ccw {
                        ((a, half), (half, a))
                    } else {
                        ((half, a), (a, half))
                    };
                    add(EntityType::Arc(Arc::new(pt(centre), r, first.0, first.1)));
                    add(EntityType::Arc(Arc::new(pt(centre), r, second.0, second.1)));
                } else {
                    add(EntityType::Arc(Arc::new(pt(centre), r, a, b)));
                }
            }
        }
    }
    let mut out = Vec::new();
    d.save(&mut out)
        .map_err(|e| error(format!("the dxf crate cannot write the drawing: {e}")))?;
    Ok(out)
}

/// Twice the area a closed contour encloses, positive when it runs
/// counter-clockwise: the polygon of its ends plus each arc's circular
/// segment, r²·(θ − sin θ) for a signed sweep θ.
fn twice_area(contour: &[Segment]) -> f64 {
    contour
        .iter()
        .map(|s| {
            let (a, b) = (s.from(), s.to());
            let chord = a.0 * b.1 - b.0 * a.1;
            match *s {
                Segment::Line { .. } => chord,
                Segment::Arc { centre, ccw, .. } => {
                    let r = (a.0 - centre.0).hypot(a.1 - centre.1);
                    let theta = if ccw { s.sweep() } else { -s.sweep() };
                    chord + r * r * (theta - theta.sin())
                }
            }
        })
        .sum()
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// The closed contour of a drawing's LINE and ARC entities, clockwise,
/// from its first entity. Any other entity, an end that meets no other, or
/// an empty drawing is an error.
pub fn read_back(bytes: &[u8]) -> Result<Vec<Segment>, DrawingError> {
    let d = Drawing::load(&mut &bytes[..])
        .map_err(|e| error(format!("the dxf crate cannot read the drawing: {e}")))?;
    let mut pieces = Vec::new();
    for (i, e) in d.entities().enumerate() {
        pieces.push(match &e.specific {
            EntityType::Line(l) => Segment::Line {
                from: (l.p1.x, l.p1.y),
                to: (l.p2.x, l.p2.y),
            },
            EntityType::Arc(a) => {
                let c = (a.center.x, a.center.y);
                let at = |deg: f64| {
                    let (s, co) = deg.to_radians().sin_cos();
                    (c.0 + a.radius * co, c.1 + a.radius * s)
                };
                Segment::Arc {
                    from: at(a.start_angle),
                    to: at(a.end_angle),
                    centre: c,
                    ccw: true,
                }
            }
            other => {
                let name = format!("{other:?}");
                let name = name.split(['(', ' ']).next().unwrap_or("?");
                return Err(error(format!("entity {}: {name}, not LINE or ARC", i + 1)));
            }
        });
    }
    let mut chain = vec![*pieces
        .first()
        .ok_or_else(|| error("no LINE or ARC in the drawing"))?];
    let mut left: Vec<Segment> = pieces[1..].to_vec();
    while !left.is_empty() {
        let end = chain[chain.len() - 1].to();
        // The nearest end of what is left, and whether it is the piece's end.
        let (k, flip, gap) = left
            .iter()
            .enumerate()
            .flat_map(|(k, s)| {
                [
                    (k, false, dist(s.from(), end)),
                    (k, true, dist(s.to(), end)),
                ]
            })
            .fold(
                (0, false, f64::INFINITY),
                |b, c| if c.2 < b.2 { c } else { b },
            );
        if gap > JOIN_MM {
            return Err(error(format!(
                "the outline is open at ({:.6}, {:.6}): no entity starts there",
                end.0, end.1
            )));
        }
        let s = left.swap_remove(k);
        chain.push(if flip { s.reversed() } else { s });
    }
    let (first, last) = (chain[0].from(), chain[chain.len() - 1].to());
    if dist(first, last) > JOIN_MM {
        return Err(error(format!(
            "the outline does not close: it ends at ({:.6}, {:.6})",
            last.0, last.1
        )));
    }
    if twice_area(&chain) > 0.0 {
        // Counter-clockwise: run it the other way, still from the first.
        let mut back = vec![chain[0].reversed()];
        back.extend(chain[1..].iter().rev().map(Segment::reversed));
        chain = back;
    }
    Ok(chain)
}
