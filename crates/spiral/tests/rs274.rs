//! The LinuxCNC program run by the real LinuxCNC interpreter (`rs274` from
//! Debian's `linuxcnc-uspace`, which `.ci/run` installs): its canonical
//! moves are compared with the model's spiral.

use std::process::Command;

use gearcam_spiral::linuxcnc::{program, Cut};
use gearcam_spiral::{chord_deviation, plan, Direction, Region, SpiralSpec};

/// The `STRAIGHT_FEED` end points (x, y, z) of a program, as `rs274 -g` prints them.
fn feeds(ngc: &str) -> Vec<(f64, f64, f64)> {
    let dir = std::env::temp_dir().join(format!("gearcam-rs274-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One file per call: the tests run in parallel.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let file = dir.join(format!("face-{n}.ngc"));
    std::fs::write(&file, ngc).unwrap();
    // rs274 keeps its parameters in a file of the working directory: one at a time.
    static ONE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    let out = Command::new("rs274")
        .current_dir(&dir)
        .arg("-g")
        .arg(&file)
        .output()
        .unwrap_or_else(|e| panic!("rs274 (Debian package linuxcnc-uspace) is needed: {e}"));
    let text = String::from_utf8_lossy(&out.stdout);
    // Every line after `executing` is a canonical command (`   12 N..... X(...)`);
    // anything else is the interpreter's complaint.
    let complaints: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("executing"))
        .skip(1)
        .filter(|l| {
            l.split_whitespace()
                .next()
                .is_none_or(|n| n.parse::<u32>().is_err())
        })
        .collect();
    assert!(
        out.status.success() && complaints.is_empty(),
        "rs274: {complaints:?} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    text.lines()
        .filter_map(|l| l.split_once("STRAIGHT_FEED(").map(|(_, rest)| rest))
        .map(|rest| {
            let v: Vec<f64> = rest
                .trim_end_matches(')')
                .split(',')
                .take(3)
                .map(|x| x.trim().parse().unwrap())
                .collect();
            (v[0], v[1], v[2])
        })
        .collect()
}

#[test]
fn the_linuxcnc_program_runs_in_rs274_and_follows_the_model() {
    let spec = SpiralSpec {
        region: Region {
            outer_radius_mm: 60.0,
            inner_radius_mm: 15.0,
        },
        tool_radius_mm: 8.0,
        step_over_mm: 12.0,
        outer_overtravel_mm: 2.0,
        inner_overtravel_mm: 1.0,
        start_angle_deg: 30.0,
        direction: Direction::OutsideIn,
    };
    let spiral = plan(&spec).unwrap();
    let cut = Cut {
        depth_mm: 1.0,
        passes: 2,
        feed_mm_min: 800.0,
        plunge_feed_mm_min: 200.0,
        spindle_rpm: 1200.0,
        safe_z_mm: 5.0,
        tolerance_mm: 0.005,
    };
    let ngc = program(
        &spiral,
        &cut,
        &["JOB TEST-1".into(), "PART (FLANGE-7)".into()],
    );
    let moves = feeds(&ngc);
    let (step_deg, model) = spiral.chords(cut.tolerance_mm);
    // Per pass: the plunge, then one move per chord of the model.
    let per_pass = model.len(); // plunge + (points − 1) chords
    assert_eq!(moves.len(), 2 * per_pass, "step {step_deg}°");
    for (pass, z) in [(0, -0.5), (1, -1.0)] {
        let ms = &moves[pass * per_pass..(pass + 1) * per_pass];
        assert!(
            ms.iter().all(|m| (m.2 - z).abs() < 1e-9),
            "pass {pass} at z {z}"
        );
        let xy: Vec<(f64, f64)> = ms.iter().map(|m| (m.0, m.1)).collect();
        // The plunge is at the start point; every chord end is the model's
        // point (rs274 prints 4 decimals).
        let worst = xy
            .iter()
            .zip(&model)
            .map(|(a, b)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt())
            .fold(0.0, f64::max);
        assert!(worst < 1e-4, "pass {pass}: {worst} mm from the model");
        // And the interpreted path keeps the chord tolerance against the spiral.
        let dev = chord_deviation(&spiral, &xy);
        assert!(
            dev <= cut.tolerance_mm * 1.01 + 1e-4,
            "pass {pass}: deviation {dev}"
        );
    }
}

/// gearcam's own reading of its LinuxCNC programs (`macrob::replay_linuxcnc`,
/// which the template service and the agents run before a program is
/// stored, where no LinuxCNC is installed) agrees with LinuxCNC's `rs274`
/// move for move, for both senses and both directions.
#[test]
fn gearcams_linuxcnc_reading_agrees_with_rs274() {
    for (direction, sense, ri) in [
        (Direction::OutsideIn, -1, 0.0),
        (Direction::InsideOut, 1, 12.0),
    ] {
        let mut spiral = plan(&SpiralSpec {
            region: Region {
                outer_radius_mm: 45.0,
                inner_radius_mm: ri,
            },
            tool_radius_mm: 6.0,
            step_over_mm: 8.0,
            outer_overtravel_mm: 2.0,
            inner_overtravel_mm: 0.5,
            start_angle_deg: -20.0,
            direction,
        })
        .unwrap();
        spiral.sense = sense;
        let cut = Cut {
            depth_mm: 1.5,
            passes: 3,
            feed_mm_min: 600.0,
            plunge_feed_mm_min: 150.0,
            spindle_rpm: 2000.0,
            safe_z_mm: 5.0,
            tolerance_mm: 0.005,
        };
        let ngc = program(&spiral, &cut, &["JOB TEST-2".into()]);
        let theirs = feeds(&ngc);
        let ours: Vec<(f64, f64, f64)> = gearcam_spiral::macrob::replay_linuxcnc(&ngc, 1_000_000)
            .unwrap()
            .into_iter()
            .filter(|m| m.feed)
            .map(|m| (m.x, m.y, m.z))
            .collect();
        assert_eq!(ours.len(), theirs.len(), "{direction:?}");
        let worst = ours
            .iter()
            .zip(&theirs)
            .map(|(a, b)| {
                (a.0 - b.0)
                    .abs()
                    .max((a.1 - b.1).abs())
                    .max((a.2 - b.2).abs())
            })
            .fold(0.0, f64::max);
        // rs274 prints four decimals.
        assert!(worst < 6e-5, "{direction:?}: {worst} mm apart");
    }
}
