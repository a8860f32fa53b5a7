//! The seed's graphical check as an SVG (docs/wire.md#for-people-gearcam-check): on the
//! left one tooth space — the theoretical outline, the fitted arcs in
//! alternating colours with their junctions, the wire's path, and the
//! deviation of the arcs from the outline magnified; on the right the whole
//! part with the wire's path, the start hole and the lead-in. Millimetres,
//! the gear's centre at the origin, Y up.

use svg::node::element::path::Data;
use svg::node::element::{Circle, Group, Path, Text, SVG};
use svg::Document;

use crate::outline::Outline;
use crate::programs::Made;
use crate::Segment;
use gearcam_geom::plane::rotate;

/// How much the deviation is magnified.
pub const MAGNIFY: f64 = 500.0;

fn polyline(points: &[(f64, f64)]) -> Data {
    let mut d = Data::new();
    for (i, p) in points.iter().enumerate() {
        d = if i == 0 {
            d.move_to((p.0, -p.1))
        } else {
            d.line_to((p.0, -p.1))
        };
    }
    d
}

fn points_of(s: &Segment, n: usize) -> Vec<(f64, f64)> {
    let a = s.arc();
    (0..=n)
        .map(|i| a.point_at(a.length * i as f64 / n as f64))
        .collect()
}

fn stroke(d: Data, colour: &str, width: f64) -> Path {
    Path::new()
        .set("d", d)
        .set("fill", "none")
        .set("stroke", colour)
        .set("stroke-width", width)
}

/// The SVG of a made die job: the tooth space on the left, the whole part
/// on the right, the title and the caption below.
pub fn die_svg(made: &Made, title: &str) -> String {
    let (left, caption) = tooth_space_view(made);
    let right = whole_part_view(made);
    Document::new()
        .set("viewBox", (0, 0, 1200, 660))
        .set("width", 1200)
        .set("height", 660)
        .add(left)
        .add(right)
        .add(
            Text::new(format!("{title} — {caption}"))
                .set("x", 10)
                .set("y", 640)
                .set("font-size", 13)
                .set("font-family", "sans-serif"),
        )
        .to_string()
}

/// The left view, framed on one tooth space: the theoretical outline, the
/// fitted arcs with their deviation magnified, and the wire's path; and
/// the caption that says what it shows, with the certificate's measure.
fn tooth_space_view(made: &Made) -> (SVG, String) {
    let o = &made.cut.outline;
    let z = f64::from(o.teeth);
    // The tooth space counter-clockwise of the tooth on +Y.
    let theory = o.theory_space(200);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in &theory {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    let margin = 0.15 * (x1 - x0).max(y1 - y0);
    let side = (x1 - x0).max(y1 - y0) + 2.0 * margin;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let w = side / 500.0;
    let space = Group::new().add(stroke(polyline(&theory), "black", 2.0 * w));
    let per = o.period.len();
    let pitch = std::f64::consts::TAU / z;
    let mut space = fitted_arcs(space, o, pitch, w);
    let path_pts: Vec<(f64, f64)> = made
        .cut
        .path
        .iter()
        .take(made.cut.path.len() / o.teeth as usize)
        .flat_map(|s| points_of(&s.map(|p| rotate(p, pitch)), 30))
        .collect();
    let dash = stroke(polyline(&path_pts), "#2171b5", 1.5 * w)
        .set("stroke-dasharray", format!("{} {}", 8.0 * w, 4.0 * w));
    space = space.add(dash);
    let m = &made.certificate.measure;
    let caption = format!(
        "one tooth space: outline (black), {} arcs (green/orange), wire path (blue), deviation x{} (pink): flank {:.3} um, fillet {:.3} um",
        per, MAGNIFY, m.flank_mm * 1e3, m.fillet_mm * 1e3
    );
    let left = SVG::new()
        .set("x", 0)
        .set("y", 0)
        .set("width", 600)
        .set("height", 600)
        .set("viewBox", (cx - side / 2.0, -cy - side / 2.0, side, side))
        .add(space);
    (left, caption)
}

/// `space` with the fitted arcs of the tooth space in alternating colours,
/// a dot at each junction, and the outline's distance from them magnified
/// [`MAGNIFY`] times along their normals (line width `w`). The arcs of that
/// space: the contour's last period turned back one pitch lies there (the
/// contour runs clockwise from the tooth on +Y).
fn fitted_arcs(mut space: Group, o: &Outline, pitch: f64, w: f64) -> Group {
    let arcs: Vec<Segment> = o
        .period
        .iter()
        .map(|s| s.map(|p| rotate(p, pitch)))
        .collect();
    let mut magnified = Vec::new();
    for (i, s) in arcs.iter().enumerate() {
        let pts = points_of(s, 60);
        let colour = if i % 2 == 0 { "#1b9e77" } else { "#d95f02" };
        space = space.add(stroke(polyline(&pts), colour, 3.0 * w));
        space = space.add(
            Circle::new()
                .set("cx", s.from().0)
                .set("cy", -s.from().1)
                .set("r", 4.0 * w)
                .set("fill", "black"),
        );
        let a = s.arc();
        for (k, q) in pts.iter().enumerate() {
            let ang = a.start_angle + a.curvature * a.length * k as f64 / 60.0;
            let n = (-ang.sin(), ang.cos());
            let (d, _) = o.distance(*q);
            let probe = (q.0 + 1e-5 * n.0, q.1 + 1e-5 * n.1);
            let sign = if o.distance(probe).0 > d { 1.0 } else { -1.0 };
            let k = sign * (MAGNIFY - 1.0) * d;
            magnified.push((q.0 + k * n.0, q.1 + k * n.1));
        }
    }
    space.add(stroke(polyline(&magnified), "#e7298a", 1.5 * w))
}

/// The right view: the whole part's contour, the wire's path, the lead-in
/// (dashed) from the start hole and the hole itself, framed to the largest
/// of the path, the tip circle and the start hole.
fn whole_part_view(made: &Made) -> SVG {
    let f = &made.cut.outline.figures;
    let extent = made
        .cut
        .path
        .iter()
        .map(|s| s.from().0.hypot(s.from().1))
        .chain(std::iter::once(
            made.layout.start_hole.0.hypot(made.layout.start_hole.1),
        ))
        .fold(f.tip_radius_mm, f64::max)
        * 1.08;
    let ww = extent / 300.0;
    let contour: Vec<(f64, f64)> = made
        .cut
        .contour
        .iter()
        .flat_map(|s| points_of(s, 8))
        .collect();
    let wire: Vec<(f64, f64)> = made.cut.path.iter().flat_map(|s| points_of(s, 8)).collect();
    let start = made.layout.start_hole;
    let lead = [start, made.cut.path[0].from()];
    let whole = Group::new()
        .add(stroke(polyline(&contour), "black", ww))
        .add(stroke(polyline(&wire), "#2171b5", ww))
        .add(
            stroke(polyline(&lead), "#2171b5", ww)
                .set("stroke-dasharray", format!("{} {}", 4.0 * ww, 2.0 * ww)),
        )
        .add(
            Circle::new()
                .set("cx", start.0)
                .set("cy", -start.1)
                .set("r", 3.0 * ww)
                .set("fill", "none")
                .set("stroke", "black")
                .set("stroke-width", ww),
        );
    SVG::new()
        .set("x", 600)
        .set("y", 0)
        .set("width", 600)
        .set("height", 600)
        .set("viewBox", (-extent, -extent, 2.0 * extent, 2.0 * extent))
        .add(whole)
}
