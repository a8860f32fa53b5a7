//! The LinuxCNC program of a spiral face (or planar spiral groove): named
//! parameters at the top (the variable table, documented in the program), an
//! `o`-word `while` loop of `G1` chords in polar words (`@` radius, `^` angle
//! about the face's centre), one loop per depth pass. The LinuxCNC `rs274`
//! interpreter runs it; the tests compare its canonical moves with the model.

use std::fmt::Write as _;

use crate::Spiral;

/// The cutting data of a spiral program (the model's, [`gearcam_proto::SpiralCut`]):
/// depth below the face and passes, feed, plunge feed, spindle speed, safe
/// height, chord tolerance.
pub use gearcam_proto::SpiralCut as Cut;

fn num(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() || s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// The program, with a header naming the job and part (`comment` text is
/// put in parentheses with parentheses removed).
pub fn program(spiral: &Spiral, cut: &Cut, header: &[String]) -> String {
    let chords = spiral.chord_count(cut.tolerance_mm);
    let total = 360.0 * f64::from(spiral.turns);
    let mut p = String::new();
    let clean = |s: &str| s.replace(['(', ')'], " ");
    for line in header {
        let _ = writeln!(p, "({})", clean(line));
    }
    let _ = writeln!(
        p,
        "(variable table: every shape, process and tool value is a named parameter)"
    );
    let rows = [
        (
            "r1",
            spiral.start_radius_mm,
            "tool-centre start radius R1, mm",
        ),
        ("r2", spiral.end_radius_mm, "tool-centre end radius R2, mm"),
        ("theta0", spiral.start_angle_deg, "start angle, degrees"),
        ("total", total, "sweep, degrees = 360 x turns"),
        (
            "chords",
            chords as f64,
            "chords along the spiral, from the tolerance",
        ),
        (
            "sense",
            f64::from(spiral.sense),
            "+1 counter-clockwise, -1 clockwise",
        ),
        ("depth", cut.depth_mm, "total depth below the face, mm"),
        ("passes", f64::from(cut.passes), "depth passes"),
        ("feed", cut.feed_mm_min, "feed along the spiral, mm/min"),
        ("plunge", cut.plunge_feed_mm_min, "plunge feed, mm/min"),
        ("rpm", cut.spindle_rpm, "spindle speed, rpm"),
        ("safe", cut.safe_z_mm, "safe height above the face, mm"),
    ];
    for (name, value, doc) in rows {
        let _ = writeln!(p, "#<{name}> = {}  ({})", num(value), clean(doc));
    }
    p.push_str(
        "G21 G90 G17 G94 G40 G49 G80\n\
         S[#<rpm>] M3\n\
         G0 Z[#<safe>]\n\
         #<pass> = 1\n\
         o100 while [#<pass> LE #<passes>]\n\
         \x20 #<z> = [0 - #<depth> * #<pass> / #<passes>]\n\
         \x20 G0 @[#<r1>] ^[#<theta0>]\n\
         \x20 G1 Z[#<z>] F[#<plunge>]\n\
         \x20 F[#<feed>]\n\
         \x20 #<k> = 0\n\
         \x20 o110 while [#<k> LT #<chords>]\n\
         \x20   #<k> = [#<k> + 1]\n\
         \x20   #<phi> = [#<total> * #<k> / #<chords>]\n\
         \x20   G1 @[#<r1> + [#<r2> - #<r1>] * #<phi> / #<total>] ^[#<theta0> + #<sense> * #<phi>]\n\
         \x20 o110 endwhile\n\
         \x20 G0 Z[#<safe>]\n\
         \x20 #<pass> = [#<pass> + 1]\n\
         o100 endwhile\n\
         M5\n\
         M2\n",
    );
    p
}
