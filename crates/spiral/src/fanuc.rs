//! The FANUC 0i parametric macro of a spiral face, in seed 001's spirit:
//! every shape, process and tool value in a `#` variable at the top with its
//! meaning, `G16` polar coordinates (X radius, Y angle about the face's
//! centre), `G01` chords in `WHILE [...] DO2 … END2`, one `DO1` loop per depth
//! pass. [`crate::macrob`] replays it for the check.

use std::fmt::Write as _;

use crate::linuxcnc::Cut;
use crate::Spiral;

/// The variable table: number, `G65` argument letter, meaning (written
/// into the program). The numbers are those the argument letters set
/// (argument specification I), so the same body runs as a standalone
/// program with the table at its top and as a `G65`-called subprogram.
pub const VARIABLES: &[(u32, char, &str)] = &[
    (1, 'A', "R1 TOOL-CENTRE START RADIUS MM"),
    (2, 'B', "R2 TOOL-CENTRE END RADIUS MM"),
    (3, 'C', "THETA0 START ANGLE DEG"),
    (4, 'I', "SWEEP DEG = 360 X TURNS"),
    (5, 'J', "CHORDS ALONG THE SPIRAL"),
    (6, 'K', "SENSE +1 CCW -1 CW"),
    (7, 'D', "DEPTH BELOW THE FACE MM"),
    (8, 'E', "DEPTH PASSES"),
    (9, 'F', "FEED MM/MIN"),
    (11, 'H', "SPINDLE RPM"),
    (13, 'M', "PLUNGE FEED MM/MIN"),
    (17, 'Q', "SAFE HEIGHT MM"),
];

/// The values of [`VARIABLES`] for a spiral and its cut.
fn values(spiral: &Spiral, cut: &Cut) -> [f64; 12] {
    [
        spiral.start_radius_mm,
        spiral.end_radius_mm,
        spiral.start_angle_deg,
        360.0 * f64::from(spiral.turns),
        spiral.chord_count(cut.tolerance_mm) as f64,
        f64::from(spiral.sense),
        cut.depth_mm,
        f64::from(cut.passes),
        cut.feed_mm_min,
        cut.spindle_rpm,
        cut.plunge_feed_mm_min,
        cut.safe_z_mm,
    ]
}

/// The macro body: one `DO1` loop per depth pass, `G16` polar `G01` chords
/// in `DO2`; loop counters in #30–#33 (no argument letter sets them).
const BODY: &str = "G21 G90 G17 G94 G40 G49 G80\n\
     S#11 M03\n\
     G00 Z#17\n\
     #30=1\n\
     WHILE [#30 LE #8] DO1\n\
     #31=0-#7*#30/#8\n\
     G16\n\
     G00 X#1 Y#3\n\
     G01 Z#31 F#13\n\
     F#9\n\
     #32=0\n\
     WHILE [#32 LT #5] DO2\n\
     #32=#32+1\n\
     #33=#4*#32/#5\n\
     G01 X[#1+[#2-#1]*#33/#4] Y[#3+#6*#33]\n\
     END2\n\
     G15\n\
     G00 Z#17\n\
     #30=#30+1\n\
     END1\n\
     M05\n";

fn num(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0');
    if s.ends_with('.') {
        format!("{s}0")
    } else {
        s.to_string()
    }
}

fn clean(s: &str) -> String {
    s.to_uppercase().replace(['(', ')'], " ")
}

/// The macro program `O{number}` (header lines become comments, upper case).
pub fn macro_program(spiral: &Spiral, cut: &Cut, number: u32, header: &[String]) -> String {
    let mut p = String::from("%\n");
    let _ = writeln!(p, "O{number:04} (SPIRAL FACE MILLING)");
    for line in header {
        let _ = writeln!(p, "({})", clean(line));
    }
    let _ = writeln!(p, "(VARIABLE TABLE, G65 ARGUMENT LETTER IN BRACKETS)");
    for ((n, letter, doc), v) in VARIABLES.iter().zip(values(spiral, cut)) {
        let _ = writeln!(p, "#{n}={} ({letter} {doc})", num(v));
    }
    p.push_str(BODY);
    p.push_str("M30\n%\n");
    p
}

/// The same as a family program: the main program `O{number}` calls the
/// value-free subprogram `O{sub}` with `G65 P{sub}` and one argument letter
/// per value (the seed's "one program for the whole part family": the
/// subprogram stays in the control, each part is one `G65` line).
pub fn g65_program(spiral: &Spiral, cut: &Cut, number: u32, sub: u32, header: &[String]) -> String {
    let mut p = String::from("%\n");
    let _ = writeln!(p, "O{number:04} (SPIRAL FACE MILLING, G65 CALL)");
    for line in header {
        let _ = writeln!(p, "({})", clean(line));
    }
    let args: Vec<String> = VARIABLES
        .iter()
        .zip(values(spiral, cut))
        .map(|((_, letter, _), v)| format!("{letter}{}", num(v)))
        .collect();
    let _ = writeln!(p, "G65 P{sub} {}", args.join(" "));
    p.push_str("M30\n");
    let _ = writeln!(p, "O{sub:04} (SPIRAL FACE MILLING FAMILY MACRO)");
    for (n, letter, doc) in VARIABLES {
        let _ = writeln!(p, "(#{n} = {letter} {doc})");
    }
    p.push_str(BODY);
    p.push_str("M99\n%\n");
    p
}

/// The expanded FANUC program of `G01` chords (the macro's chords written
/// out, Cartesian X Y to 0.1 µm), for controls without macros or arcs.
pub fn chord_program(spiral: &Spiral, cut: &Cut, number: u32, header: &[String]) -> String {
    let (_, points) = spiral.chords(cut.tolerance_mm);
    let mut p = String::from("%\n");
    let _ = writeln!(p, "O{number:04} (SPIRAL FACE MILLING, CHORDS)");
    for line in header {
        let _ = writeln!(p, "({})", clean(line));
    }
    let _ = writeln!(
        p,
        "({} CHORDS WITHIN {} MM OF THE SPIRAL)",
        points.len() - 1,
        cut.tolerance_mm
    );
    let _ = writeln!(p, "G21 G90 G17 G94 G40 G49 G80");
    let _ = writeln!(p, "S{:.0} M03", cut.spindle_rpm);
    let _ = writeln!(p, "G00 Z{}", fixed(cut.safe_z_mm));
    for pass in 1..=cut.passes {
        let z = -cut.depth_mm * f64::from(pass) / f64::from(cut.passes);
        let _ = writeln!(p, "G00 X{} Y{}", fixed(points[0].0), fixed(points[0].1));
        let _ = writeln!(p, "G01 Z{} F{}", fixed(z), fixed(cut.plunge_feed_mm_min));
        for (k, q) in points.iter().enumerate().skip(1) {
            let feed = if k == 1 {
                format!(" F{}", fixed(cut.feed_mm_min))
            } else {
                String::new()
            };
            let _ = writeln!(p, "G01 X{} Y{}{feed}", fixed(q.0), fixed(q.1));
        }
        let _ = writeln!(p, "G00 Z{}", fixed(cut.safe_z_mm));
    }
    p.push_str("M05\nM30\n%\n");
    p
}

/// A number with four decimals (0.1 µm), never `-0.0000`.
fn fixed(v: f64) -> String {
    let s = format!("{v:.4}");
    if s == "-0.0000" {
        "0.0000".to_string()
    } else {
        s
    }
}

/// The expanded FANUC program with true arcs: the spiral as the
/// tangent-continuous arcs of [`crate::arcs::fit`] (`G02`/`G03` with the
/// centre as `I J` from the start), numbers to 0.1 µm, no macro; for controls
/// or shops that want every move written out.
pub fn arc_program(spiral: &Spiral, cut: &Cut, number: u32, header: &[String]) -> String {
    let arcs = crate::arcs::fit(spiral, cut.tolerance_mm);
    let f = fixed;
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
    let _ = writeln!(p, "S{:.0} M03", cut.spindle_rpm);
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
