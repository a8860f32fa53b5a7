//! A planar spiral groove ("planar thread", seed 001): the spiral with a
//! step-over larger than the tool, so the turns do not overlap and a groove
//! of the tool's width runs with an exact pitch, lands between its turns.

use gearcam_proto::Code;
use gearcam_proto::Problem;
use serde::{Deserialize, Serialize};

use crate::Spiral;

/// A spiral groove: its centreline from `outer_radius_mm` inwards, `turns`
/// turns of `pitch_mm`, cut by a tool of `tool_radius_mm` (the groove's
/// width is the tool's diameter).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GrooveSpec {
    /// Radius of the groove's centreline at its start, mm.
    pub outer_radius_mm: f64,
    /// Pitch: the radial distance between turns, mm.
    pub pitch_mm: f64,
    /// Turns (≥ 1).
    pub turns: u32,
    /// Tool radius, mm (the groove is 2·rt wide).
    pub tool_radius_mm: f64,
    /// Start angle, degrees.
    pub start_angle_deg: f64,
}

/// What a groove is, once planned.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Groove {
    /// The tool-centre spiral.
    pub spiral: Spiral,
    /// Groove width, mm (the tool's diameter).
    pub width_mm: f64,
    /// Land between turns, mm (pitch − width).
    pub land_mm: f64,
}

/// The groove's spiral, or its input errors (typed, on their fields).
pub fn plan_groove(g: &GrooveSpec) -> Result<Groove, Vec<Problem>> {
    let mut errors = Vec::new();
    let bad = |field: &str, expected: String, got: f64, message: &str| {
        Problem::new(
            Code::GROOVE_RANGE,
            field,
            expected,
            format!("{got}"),
            message,
        )
    };
    let width = 2.0 * g.tool_radius_mm;
    if !(g.tool_radius_mm.is_finite() && g.tool_radius_mm > 0.0) {
        errors.push(bad(
            "mill.radius_mm",
            "a radius > 0 mm".into(),
            g.tool_radius_mm,
            "the tool's radius must be positive",
        ));
    }
    if !(g.pitch_mm.is_finite() && g.pitch_mm > 0.0) {
        errors.push(bad(
            "groove.pitch_mm",
            "a pitch > 0 mm".into(),
            g.pitch_mm,
            "the pitch is the radial distance between turns",
        ));
    } else if g.tool_radius_mm > 0.0 && g.pitch_mm <= width {
        errors.push(bad(
            "groove.pitch_mm",
            format!("more than the groove's width {width} mm (the tool's diameter)"),
            g.pitch_mm,
            "with a pitch of the tool's diameter or less the turns overlap: that is a face, not a groove",
        ));
    }
    if g.turns == 0 {
        errors.push(bad(
            "groove.turns",
            "1 or more".into(),
            0.0,
            "a groove has at least one turn",
        ));
    }
    let end = g.outer_radius_mm - g.pitch_mm * f64::from(g.turns);
    if errors.is_empty() && end < g.tool_radius_mm {
        errors.push(bad(
            "groove.turns",
            format!(
                "at most {} turns of {} mm from radius {} mm",
                ((g.outer_radius_mm - g.tool_radius_mm) / g.pitch_mm).floor(),
                g.pitch_mm,
                g.outer_radius_mm
            ),
            f64::from(g.turns),
            "the groove's last turn would run into the centre",
        ));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(Groove {
        spiral: Spiral {
            start_radius_mm: g.outer_radius_mm,
            end_radius_mm: end,
            start_angle_deg: g.start_angle_deg,
            turns: g.turns,
            sense: 1,
        },
        width_mm: width,
        land_mm: g.pitch_mm - width,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fanuc::macro_program;
    use crate::linuxcnc::Cut;
    use crate::macrob::replay;

    fn spec() -> GrooveSpec {
        GrooveSpec {
            outer_radius_mm: 80.0,
            pitch_mm: 10.0,
            turns: 5,
            tool_radius_mm: 3.0,
            start_angle_deg: 0.0,
        }
    }

    #[test]
    fn a_groove_has_its_pitch_width_and_land() {
        let g = plan_groove(&spec()).unwrap();
        assert_eq!((g.width_mm, g.land_mm), (6.0, 4.0));
        assert_eq!(g.spiral.end_radius_mm, 30.0);
        // The pitch measured on the replayed macro: the same angle one turn
        // later is one pitch further in.
        let cut = Cut {
            depth_mm: 1.5,
            passes: 3,
            feed_mm_min: 600.0,
            plunge_feed_mm_min: 150.0,
            spindle_rpm: 3000.0,
            safe_z_mm: 5.0,
            tolerance_mm: 0.002,
        };
        let moves = replay(&macro_program(&g.spiral, &cut, 3001, &[]), 10_000_000).unwrap();
        let last: Vec<(f64, f64)> = moves
            .iter()
            .filter(|m| m.feed && (m.z + 1.5).abs() < 1e-12)
            .map(|m| (m.x, m.y))
            .collect();
        // Unwrapped polar angle and radius of each replayed point.
        let mut polar: Vec<(f64, f64)> = Vec::new();
        for p in &last {
            let a = p.1.atan2(p.0).to_degrees();
            let a = match polar.last() {
                Some(&(prev, _)) => prev + (a - prev + 180.0).rem_euclid(360.0) - 180.0,
                None => a,
            };
            polar.push((a, (p.0 * p.0 + p.1 * p.1).sqrt()));
        }
        // The radius where the path crosses angle `a` (on a chord, linearly).
        let radius_at = |a: f64| {
            let i = polar
                .windows(2)
                .position(|w| w[0].0 <= a && a <= w[1].0)
                .unwrap();
            let (w0, w1) = (polar[i], polar[i + 1]);
            w0.1 + (w1.1 - w0.1) * (a - w0.0) / (w1.0 - w0.0)
        };
        for a in [10.0, 123.4, 350.0] {
            let pitch = radius_at(a) - radius_at(a + 360.0);
            assert!((pitch - 10.0).abs() < 1e-3, "pitch {pitch} at {a} degrees");
        }
        // Three depth passes, each its own loop.
        let depths: std::collections::BTreeSet<i64> = moves
            .iter()
            .filter(|m| m.feed)
            .map(|m| (m.z * 1000.0).round() as i64)
            .collect();
        assert_eq!(depths.into_iter().collect::<Vec<_>>(), [-1500, -1000, -500]);
    }

    #[test]
    fn a_groove_that_is_a_face_or_runs_into_the_centre_is_refused() {
        let e = plan_groove(&GrooveSpec {
            pitch_mm: 6.0,
            ..spec()
        })
        .unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str()),
            ("GROOVE_RANGE", "groove.pitch_mm")
        );
        let e = plan_groove(&GrooveSpec { turns: 8, ..spec() }).unwrap_err();
        assert_eq!(e[0].field, "groove.turns");
        assert!(e[0].expected.contains("at most 7 turns"), "{:?}", e[0]);
    }
}
