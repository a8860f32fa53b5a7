//! A picture of a spiral face for people (where they would rather look than
//! read): the region, the tool-centre path, the area the tool sweeps, and
//! the worst uncovered point if the coverage check found one. SVG, millimetres
//! as user units, the face's centre at the origin (Y up).

use svg::node::element::path::Data;
use svg::node::element::{Circle, Group, Path, Text};
use svg::Document;

use crate::{Coverage, Region};

/// The SVG of a face, its tool path `points`, the tool's radius and the
/// coverage found.
pub fn face_svg(
    region: &Region,
    tool_radius_mm: f64,
    points: &[(f64, f64)],
    coverage: &Coverage,
) -> String {
    let extent = points
        .iter()
        .map(|p| (p.0 * p.0 + p.1 * p.1).sqrt())
        .fold(region.outer_radius_mm, f64::max)
        + tool_radius_mm
        + 5.0;
    let mut path = Data::new();
    for (i, p) in points.iter().enumerate() {
        // SVG's Y runs down: flip it so the picture reads as the machine's XY.
        path = if i == 0 {
            path.move_to((p.0, -p.1))
        } else {
            path.line_to((p.0, -p.1))
        };
    }
    let swept = Path::new()
        .set("d", path.clone())
        .set("fill", "none")
        .set("stroke", "#9ecae1")
        .set("stroke-width", 2.0 * tool_radius_mm)
        .set("stroke-linejoin", "round")
        .set("stroke-linecap", "round")
        .set("opacity", 0.6);
    let centre_line = Path::new()
        .set("d", path)
        .set("fill", "none")
        .set("stroke", "#08519c")
        .set("stroke-width", extent / 800.0);
    let mut region_g = Group::new().add(
        Circle::new()
            .set("r", region.outer_radius_mm)
            .set("fill", "none")
            .set("stroke", "black")
            .set("stroke-width", extent / 400.0),
    );
    if region.inner_radius_mm > 0.0 {
        region_g = region_g.add(
            Circle::new()
                .set("r", region.inner_radius_mm)
                .set("fill", "none")
                .set("stroke", "black")
                .set("stroke-width", extent / 400.0),
        );
    }
    let verdict = if coverage.ok {
        "covered".to_string()
    } else {
        format!("GAP {:.3} mm", coverage.max_gap_mm)
    };
    let mut doc = Document::new()
        .set("viewBox", (-extent, -extent, 2.0 * extent, 2.0 * extent))
        .set("width", "800")
        .set("height", "800")
        .add(swept)
        .add(region_g)
        .add(centre_line)
        .add(
            Text::new(format!(
                "Ro {} mm, Ri {} mm, tool r {} mm: {verdict}",
                region.outer_radius_mm, region.inner_radius_mm, tool_radius_mm
            ))
            .set("x", -extent * 0.95)
            .set("y", -extent * 0.92)
            .set("font-size", extent / 25.0),
        );
    if !coverage.ok {
        let (x, y) = coverage.worst_point;
        doc = doc.add(
            Circle::new()
                .set("cx", x)
                .set("cy", -y)
                .set("r", extent / 60.0)
                .set("fill", "red"),
        );
    }
    doc.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{coverage, plan, Direction, SpiralSpec};

    #[test]
    fn the_picture_shows_the_face_the_path_and_a_gap() {
        let region = Region {
            outer_radius_mm: 60.0,
            inner_radius_mm: 15.0,
        };
        let spec = SpiralSpec {
            region,
            tool_radius_mm: 8.0,
            step_over_mm: 12.0,
            outer_overtravel_mm: 2.0,
            inner_overtravel_mm: 1.0,
            start_angle_deg: 0.0,
            direction: Direction::OutsideIn,
        };
        let spiral = plan(&spec).unwrap();
        let (_, pts) = spiral.chords(0.01);
        let ok = coverage(&region, 8.0, &pts, 1.0);
        let svg = face_svg(&region, 8.0, &pts, &ok);
        assert!(
            svg.starts_with("<svg") && svg.contains("covered"),
            "{}",
            &svg[..200]
        );
        assert_eq!(
            svg.matches("<circle").count(),
            2,
            "two region circles, no gap mark"
        );
        let short = crate::Spiral {
            end_radius_mm: 23.0,
            ..spiral
        };
        let (_, pts) = short.chords(0.01);
        let gap = coverage(&region, 8.0, &pts, 1.0);
        let svg = face_svg(&region, 8.0, &pts, &gap);
        assert!(svg.contains("GAP") && svg.contains("fill=\"red\""));
    }
}
