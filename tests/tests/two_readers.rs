//! Every example's program replayed by two readers that share nothing: the
//! reader gearcam certifies with before a program leaves, and a second
//! reader of the same format written only from its description in `docs/`
//! by someone who had not read gearcam's writers or readers
//! (`tests/readers/`). Each second reader runs the whole program as its
//! control does, from the first block to the end (lead-in, turned sections,
//! subprograms, lead-out, retracts), and the two replays must agree move for
//! move within the control's resolution. Where they disagreed, the docs were
//! ambiguous: the docs were made exact, then the code.
//!
//! The second readers' own tests (hand-computed programs, the published
//! examples of the docs, refusals) run in this binary too.
//!
//! LinuxCNC programs have a third-party reader instead: LinuxCNC's `rs274`
//! (`crates/spiral/tests/rs274.rs`).

#[allow(dead_code)]
#[path = "../readers/b3.rs"]
mod b3;
#[allow(dead_code)]
#[path = "../readers/fanuc_egb.rs"]
mod fanuc_egb;
#[allow(dead_code)]
#[path = "../readers/isowire.rs"]
mod isowire;
#[allow(dead_code)]
#[path = "../readers/macrob.rs"]
mod macrob;
#[allow(dead_code)]
#[path = "../readers/s840d.rs"]
mod s840d;

use std::path::{Path, PathBuf};

use gearcam_proto::MoveKind;
use gearcam_testkit::examples::{on_machine, valid_hobbing};
use gearcam_testkit::pipeline::model_of;
use gearcam_wire::programs::{run_blocks, Rotation};
use gearcam_wire::Segment;

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

/// The golden programs whose name ends with `ext`, with their text.
fn goldens(ext: &str) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(golden_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(ext))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    out.sort();
    out
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// A wire move of a second reader: start, end, and an arc's centre and
/// sense.
type TheirMove = ((f64, f64), (f64, f64), Option<((f64, f64), bool)>);

/// The largest disagreement between two replays of one program, with the
/// move where it is.
#[derive(Debug, Default)]
struct Worst {
    mm: f64,
    at: usize,
}

impl Worst {
    fn see(&mut self, d: f64, at: usize) {
        if d > self.mm {
            *self = Worst { mm: d, at };
        }
    }

    /// Prints the largest disagreement of `moves` moves of program `name`
    /// (the figure the closing notes report) and requires it within
    /// `bound_mm`.
    fn within(&self, name: &str, moves: usize, bound_mm: f64) {
        eprintln!(
            "{name}: {moves} moves, largest disagreement {:.6} µm (move {})",
            self.mm * 1e3,
            self.at
        );
        assert!(self.mm <= bound_mm, "{name}: {self:?}");
    }

    /// Move `i` of a wire program as gearcam replayed it against the second
    /// reader's (start, end, arc centre and sense): the ends and the centre
    /// counted, a line against an arc or another sense refused.
    fn see_move(&mut self, name: &str, i: usize, ours: &Segment, (from, to, arc): TheirMove) {
        self.see(dist(ours.from(), from), i);
        self.see(dist(ours.to(), to), i);
        match (*ours, arc) {
            (Segment::Line { .. }, None) => {}
            (Segment::Arc { centre, ccw, .. }, Some((c, t_ccw))) => {
                assert_eq!(ccw, t_ccw, "{name}: move {i}'s sense");
                self.see(dist(centre, c), i);
            }
            _ => panic!("{name}: move {i} is a line in one reader, an arc in the other"),
        }
    }
}

/// 3B and 4B: gearcam's replay (its rotation line, its block runner) and the
/// second reader's agree within a µm (each rounds an arc's end to the µm
/// grid its own way) at every move's end and every arc's centre, and both
/// end at the start hole.
#[test]
fn three_b_and_four_b_programs_replay_alike_in_both_readers() {
    let mut seen = 0;
    for ext in [".3b", ".4b"] {
        for (name, text) in goldens(ext) {
            let body: String = text
                .lines()
                .filter(|l| !l.starts_with(';'))
                .map(|l| format!("{l}\n"))
                .collect();
            let blocks: Vec<_> = gearcam_wire::fourb::read(&body)
                .unwrap_or_else(|e| panic!("{name}: {e:?}"))
                .into_iter()
                .map(|b| b.block)
                .collect();
            let rotation = Rotation::of_text(&text).unwrap();
            let ours = run_blocks(&blocks, rotation.as_ref(), (0.0, 0.0));
            let theirs = if ext == ".3b" {
                b3::run_3b(&text)
            } else {
                b3::run_4b(&text)
            }
            .unwrap_or_else(|e| panic!("{name}: the second reader: {e}"));
            assert_eq!(ours.len(), theirs.len(), "{name}: moves");
            let mut worst = Worst::default();
            for (i, (o, t)) in ours.iter().zip(&theirs).enumerate() {
                worst.see_move(&name, i, &o.segment, (t.from, t.to, t.arc));
            }
            worst.within(&name, ours.len(), 0.001 + 1e-9);
            let end = theirs.last().unwrap().to;
            assert!(dist(end, (0.0, 0.0)) < 1e-9, "{name}: ends at {end:?}");
            assert!(dist(ours.last().unwrap().segment.to(), (0.0, 0.0)) < 1e-9);
            seen += 1;
        }
    }
    assert!(seen >= 3, "{seen} programs");
}

/// ISO wire: every move of both replays — the lead-in, each call of the
/// subprogram under its `G68` turn, the lead-out — agrees within 0.1 µm, with
/// the same compensation in force; both end at the `G92` start.
#[test]
fn iso_wire_programs_replay_alike_in_both_readers() {
    let mut seen = 0;
    for (name, text) in goldens(".iso") {
        let ours = gearcam_wire::iso::replay(&text).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let theirs =
            isowire::run_iso(&text).unwrap_or_else(|e| panic!("{name}: the second reader: {e}"));
        assert_eq!(ours.moves.len(), theirs.moves.len(), "{name}: moves");
        assert!(dist(ours.start, theirs.start) < 1e-9, "{name}: start");
        let mut worst = Worst::default();
        for (i, (o, t)) in ours.moves.iter().zip(&theirs.moves).enumerate() {
            assert_eq!(o.line, t.line, "{name}: move {i}'s line");
            assert_eq!(o.rapid, t.rapid, "{name}: move {i}");
            let side = match o.side {
                None => isowire::Comp::Off,
                Some(gearcam_wire::iso::Side::Left) => isowire::Comp::Left,
                Some(gearcam_wire::iso::Side::Right) => isowire::Comp::Right,
            };
            assert_eq!(side, t.comp, "{name}: move {i}'s compensation");
            assert!((o.offset_mm.unwrap_or(0.0) - t.offset_mm).abs() < 1e-12);
            worst.see_move(&name, i, &o.segment, (t.from, t.to, t.arc));
        }
        worst.within(&name, ours.moves.len(), 1e-4);
        let end = theirs.moves.last().unwrap().to;
        assert!(dist(end, theirs.start) < 1e-9, "{name}: ends at {end:?}");
        seen += 1;
    }
    assert!(seen >= 2, "{seen} programs");
}

/// The FANUC spiral programs (macro, arcs, chords; faces and a groove):
/// every move from the first block to `M30` agrees within 0.1 µm in X, Y
/// and Z, rapid or feed and arc centre alike; both end with the tool at the
/// safe height.
#[test]
fn fanuc_spiral_programs_replay_alike_in_both_readers() {
    let mut seen = 0;
    for (name, text) in goldens(".nc") {
        let spiral = name.starts_with("face_") || name.starts_with("groove_");
        if !spiral || name.contains("linuxcnc") {
            continue;
        }
        let budget = 10_000_000;
        let ours = gearcam_spiral::macrob::replay(&text, budget)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let theirs = macrob::run_fanuc(&text, budget)
            .unwrap_or_else(|e| panic!("{name}: the second reader: {e}"));
        assert_eq!(ours.len(), theirs.moves.len(), "{name}: moves");
        let mut worst = Worst::default();
        for (i, (o, t)) in ours.iter().zip(&theirs.moves).enumerate() {
            assert_eq!(o.feed, !t.rapid, "{name}: move {i}");
            let d = (o.x - t.to.0)
                .abs()
                .max((o.y - t.to.1).abs())
                .max((o.z - t.to.2).abs());
            worst.see(d, i);
            match (o.arc, t.arc) {
                (None, None) => {}
                (Some((c, ccw)), Some((tc, t_ccw))) => {
                    assert_eq!(ccw, t_ccw, "{name}: move {i}'s sense");
                    worst.see(dist(c, tc), i);
                }
                _ => panic!("{name}: move {i} is an arc in one reader only"),
            }
        }
        worst.within(&name, ours.len(), 1e-4);
        assert_eq!(theirs.ended_by, "M30", "{name}");
        let last = theirs.moves.last().unwrap();
        assert!(last.rapid && last.to.2 >= 5.0 - 1e-9, "{name}: {last:?}");
        seen += 1;
    }
    assert!(seen >= 4, "{seen} programs");
}

/// One axis move of a hobbing program: (line, rapid, X, Z, Y).
type AxisAt = (usize, bool, f64, f64, f64);

/// Hobbing, 840D on H01 and FANUC EGB on H02: the path check's simulation
/// (which the program must pass before it leaves) and the second reader run
/// every example's program from its first block to its end, set-up, hob
/// changes and unit changes included, and agree on every move's line, kind
/// and X, Z and shift Y within the printed resolution; both end with the
/// hob at the start point A.
#[test]
fn hobbing_programs_replay_alike_in_both_readers() {
    let mut seen = 0;
    for (name, job) in valid_hobbing() {
        for machine in ["H01", "H02"] {
            let model = model_of(&on_machine(&job, machine))
                .unwrap_or_else(|e| panic!("{name} on {machine}: {e:?}"));
            let file =
                golden_dir().join(format!("{}.{machine}.nc", name.trim_end_matches(".toml")));
            let text = std::fs::read_to_string(&file).unwrap();
            let (check, trace) = gearcam_nc::check(&text, &model);
            assert!(check.ok, "{name} on {machine}: {:?}", check.findings);
            let axes = &model.plan.machine.axes;
            let ours: Vec<AxisAt> = trace
                .moves
                .iter()
                .filter(|m| m.kind != MoveKind::Dwell)
                .map(|m| {
                    (
                        m.line as usize,
                        m.kind == MoveKind::Rapid,
                        m.x_mm,
                        m.z_mm,
                        m.y_mm,
                    )
                })
                .collect();
            let (moves, ended_by) = if machine == "H01" {
                let r = s840d::run_840d(&text, &[])
                    .unwrap_or_else(|e| panic!("{name} on {machine}: the second reader: {e}"));
                let m: Vec<_> = r
                    .moves
                    .iter()
                    .filter(|m| m.dwell_s.is_none())
                    .map(|m| (m.line, m.rapid, m.to.clone()))
                    .collect();
                (m, r.ended_by)
            } else {
                let r = fanuc_egb::run_fanuc_egb(&text, &[])
                    .unwrap_or_else(|e| panic!("{name} on {machine}: the second reader: {e}"));
                let m: Vec<_> = r
                    .moves
                    .iter()
                    .filter(|m| m.dwell_s.is_none())
                    .map(|m| (m.line, m.rapid, m.to.clone()))
                    .collect();
                (m, r.ended_by)
            };
            let get =
                |to: &std::collections::BTreeMap<String, f64>, axis: &str| to.get(axis).copied();
            // Positions before the first word of an axis: the machine's
            // start point A for X and Z, 0 for the shift.
            let home = (
                model.plan.machine.home_x_mm,
                model.plan.machine.home_z_mm,
                0.0,
            );
            let theirs: Vec<AxisAt> = moves
                .iter()
                .map(|(line, rapid, to)| {
                    (
                        *line,
                        *rapid,
                        get(to, &axes.radial).unwrap_or(home.0),
                        get(to, &axes.axial).unwrap_or(home.1),
                        get(to, &axes.shift).unwrap_or(home.2),
                    )
                })
                .collect();
            // gearcam's trace holds the moves of the linear axes; a block
            // that moves only the swivel is in its swivel list instead.
            let theirs: Vec<AxisAt> = theirs
                .iter()
                .enumerate()
                .filter(|(i, t)| {
                    let before = if *i == 0 {
                        (home.0, home.1, home.2)
                    } else {
                        let p = theirs[i - 1];
                        (p.2, p.3, p.4)
                    };
                    let moved =
                        (t.2 - before.0).abs() + (t.3 - before.1).abs() + (t.4 - before.2).abs();
                    moved > 0.0 || ours.iter().any(|o| o.0 == t.0)
                })
                .map(|(_, t)| *t)
                .collect();
            let lines = |v: &[AxisAt]| v.iter().map(|m| m.0).collect::<Vec<_>>();
            assert_eq!(
                lines(&ours),
                lines(&theirs),
                "{name} on {machine}: move lines"
            );
            let mut worst = Worst::default();
            for (i, (o, t)) in ours.iter().zip(&theirs).enumerate() {
                assert_eq!(o.1, t.1, "{name} on {machine}: line {} rapid", o.0);
                let d = (o.2 - t.2)
                    .abs()
                    .max((o.3 - t.3).abs())
                    .max((o.4 - t.4).abs());
                worst.see(d, i);
            }
            worst.within(
                &format!("{name} on {machine} ({ended_by})"),
                ours.len(),
                0.0005 + 1e-9,
            );
            let last = theirs.last().unwrap();
            assert!(
                (last.2 - home.0).abs() < 1e-9 && (last.3 - home.1).abs() < 1e-9,
                "{name} on {machine}: ends at X{} Z{}",
                last.2,
                last.3
            );
            seen += 1;
        }
    }
    assert!(seen >= 28, "{seen} programs");
}
