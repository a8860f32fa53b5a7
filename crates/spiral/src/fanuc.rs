//! The FANUC 0i parametric macro of a spiral face, in seed 001's spirit:
//! every shape, process and tool value in a `#` variable at the top with its
//! meaning, `G16` polar coordinates (X radius, Y angle about the face's
//! centre), `G01` chords in `WHILE [...] DO2 … END2`, one `DO1` loop per depth
//! pass. [`crate::macrob`] replays it for the check.

use std::fmt::Write as _;

use crate::linuxcnc::Cut;
use crate::Spiral;

/// The variable table: number, meaning (written into the program).
pub const VARIABLES: &[(u32, &str)] = &[
    (1, "R1 TOOL-CENTRE START RADIUS MM"),
    (2, "R2 TOOL-CENTRE END RADIUS MM"),
    (3, "THETA0 START ANGLE DEG"),
    (4, "SWEEP DEG = 360 X TURNS"),
    (5, "CHORDS ALONG THE SPIRAL"),
    (6, "SENSE +1 CCW -1 CW"),
    (7, "DEPTH BELOW THE FACE MM"),
    (8, "DEPTH PASSES"),
    (9, "FEED MM/MIN"),
    (10, "PLUNGE FEED MM/MIN"),
    (11, "SPINDLE RPM"),
    (12, "SAFE HEIGHT MM"),
];

fn num(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0');
    if s.ends_with('.') {
        format!("{s}0")
    } else {
        s.to_string()
    }
}

/// The macro program `O{number}` (header lines become comments, upper case).
pub fn macro_program(spiral: &Spiral, cut: &Cut, number: u32, header: &[String]) -> String {
    let (_, points) = spiral.chords(cut.tolerance_mm);
    let values = [
        spiral.start_radius_mm,
        spiral.end_radius_mm,
        spiral.start_angle_deg,
        360.0 * f64::from(spiral.turns),
        (points.len() - 1) as f64,
        f64::from(spiral.sense),
        cut.depth_mm,
        f64::from(cut.passes),
        cut.feed_mm_min,
        cut.plunge_feed_mm_min,
        cut.spindle_rpm,
        cut.safe_z_mm,
    ];
    let clean = |s: &str| s.to_uppercase().replace(['(', ')'], " ");
    let mut p = String::from("%\n");
    let _ = writeln!(p, "O{number:04} (SPIRAL FACE MILLING)");
    for line in header {
        let _ = writeln!(p, "({})", clean(line));
    }
    let _ = writeln!(p, "(VARIABLE TABLE)");
    for ((n, doc), v) in VARIABLES.iter().zip(values) {
        let _ = writeln!(p, "#{n}={} ({doc})", num(v));
    }
    p.push_str(
        "G21 G90 G17 G94 G40 G49 G80\n\
         S#11 M03\n\
         G00 Z#12\n\
         #20=1\n\
         WHILE [#20 LE #8] DO1\n\
         #21=0-#7*#20/#8\n\
         G16\n\
         G00 X#1 Y#3\n\
         G01 Z#21 F#10\n\
         F#9\n\
         #22=0\n\
         WHILE [#22 LT #5] DO2\n\
         #22=#22+1\n\
         #23=#4*#22/#5\n\
         G01 X[#1+[#2-#1]*#23/#4] Y[#3+#6*#23]\n\
         END2\n\
         G15\n\
         G00 Z#12\n\
         #20=#20+1\n\
         END1\n\
         M05\n\
         M30\n\
         %\n",
    );
    p
}

/// The expanded FANUC program with true arcs: the spiral as the
/// tangent-continuous arcs of [`crate::arcs::fit`] (`G02`/`G03` with the
/// centre as `I J` from the start), numbers to 0.1 µm, no macro; for controls
/// or shops that want every move written out.
pub fn arc_program(spiral: &Spiral, cut: &Cut, number: u32, header: &[String]) -> String {
    let arcs = crate::arcs::fit(spiral, cut.tolerance_mm);
    let clean = |s: &str| s.to_uppercase().replace(['(', ')'], " ");
    let f = |v: f64| {
        let s = format!("{v:.4}");
        if s == "-0.0000" {
            "0.0000".to_string()
        } else {
            s
        }
    };
    let mut p = String::from("%\n");
    let _ = writeln!(p, "O{number:04} (SPIRAL FACE MILLING, ARCS)");
    for line in header {
        let _ = writeln!(p, "({})", clean(line));
    }
    let _ = writeln!(
        p,
        "({} TANGENT ARCS WITHIN {} MM OF THE SPIRAL)",
        arcs.len(),
        cut.tolerance_mm
    );
    let _ = writeln!(p, "G21 G90 G17 G94 G40 G49 G80");
    let _ = writeln!(p, "S{} M03", f(cut.spindle_rpm));
    let _ = writeln!(p, "G00 Z{}", f(cut.safe_z_mm));
    let (x0, y0) = spiral.point_at(0.0);
    for pass in 1..=cut.passes {
        let z = -cut.depth_mm * f64::from(pass) / f64::from(cut.passes);
        let _ = writeln!(p, "G00 X{} Y{}", f(x0), f(y0));
        let _ = writeln!(p, "G01 Z{} F{}", f(z), f(cut.plunge_feed_mm_min));
        let mut from = (x0, y0);
        for (k, a) in arcs.iter().enumerate() {
            let g = if a.ccw { "G03" } else { "G02" };
            let feed = if k == 0 {
                format!(" F{}", f(cut.feed_mm_min))
            } else {
                String::new()
            };
            let _ = writeln!(
                p,
                "{g} X{} Y{} I{} J{}{feed}",
                f(a.end.0),
                f(a.end.1),
                f(a.centre.0 - from.0),
                f(a.centre.1 - from.1)
            );
            from = a.end;
        }
        let _ = writeln!(p, "G00 Z{}", f(cut.safe_z_mm));
    }
    p.push_str("M05\nM30\n%\n");
    p
}
