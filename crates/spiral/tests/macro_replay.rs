//! The FANUC macro replayed by the Macro B interpreter (`macrob`, which
//! knows nothing of spirals): its moves are compared with the model.

use gearcam_spiral::fanuc::macro_program;
use gearcam_spiral::linuxcnc::Cut;
use gearcam_spiral::macrob::replay;
use gearcam_spiral::{chord_deviation, plan, Direction, Region, SpiralSpec};

#[test]
fn the_macro_replays_onto_the_model() {
    for (ri, direction) in [(15.0, Direction::OutsideIn), (20.0, Direction::InsideOut)] {
        let spiral = plan(&SpiralSpec {
            region: Region {
                outer_radius_mm: 60.0,
                inner_radius_mm: ri,
            },
            tool_radius_mm: 8.0,
            step_over_mm: 12.0,
            outer_overtravel_mm: 2.0,
            inner_overtravel_mm: 1.0,
            start_angle_deg: 30.0,
            direction,
        })
        .unwrap();
        let cut = Cut {
            depth_mm: 1.0,
            passes: 2,
            feed_mm_min: 800.0,
            plunge_feed_mm_min: 200.0,
            spindle_rpm: 1200.0,
            safe_z_mm: 5.0,
            tolerance_mm: 0.005,
        };
        let program = macro_program(&spiral, &cut, 2107, &["JOB TEST-1".into()]);
        assert!(program.contains("WHILE [#32 LT #5] DO2") && program.contains("G16"));
        let moves = replay(&program, 1_000_000).unwrap();
        let (_, model) = spiral.chords(cut.tolerance_mm);
        // Per pass: the rapid to the start, the plunge, N chords; then the retract.
        let feeds: Vec<_> = moves.iter().filter(|m| m.feed).collect();
        assert_eq!(feeds.len(), 2 * model.len());
        for (pass, z) in [(0, -0.5), (1, -1.0)] {
            let ms = &feeds[pass * model.len()..(pass + 1) * model.len()];
            assert!(ms.iter().all(|m| (m.z - z).abs() < 1e-12));
            let xy: Vec<(f64, f64)> = ms.iter().map(|m| (m.x, m.y)).collect();
            let worst = xy
                .iter()
                .zip(&model)
                .map(|(a, b)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt())
                .fold(0.0, f64::max);
            assert!(worst < 1e-5, "pass {pass}: {worst} mm from the model");
            assert!(chord_deviation(&spiral, &xy) <= cut.tolerance_mm * 1.01);
        }
        // Ends clear of the part.
        assert_eq!(moves.last().unwrap().z, 5.0);
    }
}

/// The expanded program with true arcs, replayed: every arc of the replay
/// stays within the tolerance of the spiral (plus the 0.1 µm of the printed
/// numbers), measured on 20,001 spiral points.
#[test]
fn the_arc_program_replays_within_the_tolerance() {
    use gearcam_spiral::arcs::Arc;
    use gearcam_spiral::fanuc::arc_program;
    let spiral = gearcam_spiral::Spiral {
        start_radius_mm: 100.0,
        end_radius_mm: 20.0,
        start_angle_deg: 0.0,
        turns: 8,
        sense: 1,
    };
    let cut = Cut {
        depth_mm: 0.5,
        passes: 1,
        feed_mm_min: 800.0,
        plunge_feed_mm_min: 200.0,
        spindle_rpm: 1200.0,
        safe_z_mm: 5.0,
        tolerance_mm: 0.001,
    };
    let program = arc_program(&spiral, &cut, 2108, &[]);
    let moves = replay(&program, 100_000).unwrap();
    let mut arcs = Vec::new();
    let mut from = (0.0, 0.0);
    for m in &moves {
        if let Some((centre, ccw)) = m.arc {
            let radius = ((from.0 - centre.0).powi(2) + (from.1 - centre.1).powi(2)).sqrt();
            arcs.push(Arc {
                start: from,
                end: (m.x, m.y),
                centre,
                radius,
                ccw,
                end_phi: 0.0,
            });
        }
        from = (m.x, m.y);
    }
    let blocks = gearcam_spiral::arcs::fit(&spiral, cut.tolerance_mm).len();
    assert_eq!(arcs.len(), blocks);
    let chords = spiral.chords(cut.tolerance_mm).1.len() - 1;
    assert!(chords > 20 * blocks, "{chords} chords vs {blocks} arcs");
    let total = std::f64::consts::TAU * 8.0;
    let mut i: usize = 0;
    for k in 0..=20_000 {
        let p = spiral.point_at(total * k as f64 / 20_000.0);
        // The arcs run in order along the spiral: search a window around the last.
        let (best_i, d) = (i.saturating_sub(2)..(i + 3).min(arcs.len()))
            .map(|j| (j, arcs[j].distance(p)))
            .fold((i, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        i = best_i;
        assert!(d <= cut.tolerance_mm + 1e-4, "{d} mm at sample {k}");
    }
}

fn cut() -> Cut {
    Cut {
        depth_mm: 1.0,
        passes: 2,
        feed_mm_min: 800.0,
        plunge_feed_mm_min: 200.0,
        spindle_rpm: 1200.0,
        safe_z_mm: 5.0,
        tolerance_mm: 0.005,
    }
}

/// The G65 form (a main program with one call line, the value-free family
/// subprogram after it) commands exactly the standalone macro's moves, for
/// both senses of rotation; the interpreter restores the caller's locals.
#[test]
fn the_g65_call_commands_the_same_moves_as_the_macro() {
    use gearcam_spiral::fanuc::g65_program;
    for sense in [1, -1] {
        let spiral = gearcam_spiral::Spiral {
            start_radius_mm: 70.0,
            end_radius_mm: 6.0,
            start_angle_deg: 45.0,
            turns: 6,
            sense,
        };
        let standalone = replay(&macro_program(&spiral, &cut(), 3001, &[]), 1_000_000).unwrap();
        let program = g65_program(&spiral, &cut(), 3002, 7001, &["PART FL-1".into()]);
        assert!(
            program.contains("G65 P7001 A70.0 B6.0 C45.0 I2160.0"),
            "{program}"
        );
        assert!(program.contains("O7001") && program.contains("M99"));
        let called = replay(&program, 1_000_000).unwrap();
        assert_eq!(called, standalone);
        // The replayed chords follow the model's spiral in its sense.
        let (_, model) = spiral.chords(0.005);
        let feeds: Vec<_> = called.iter().filter(|m| m.feed).collect();
        let end = feeds[model.len() - 1];
        let goal = model.last().unwrap();
        assert!((end.x - goal.0).abs() + (end.y - goal.1).abs() < 1e-5);
        let second = feeds[2];
        assert!((second.x - model[2].0).abs() + (second.y - model[2].1).abs() < 1e-5);
    }
}

/// A G65 argument that is not an argument letter, and an M99 outside a
/// call, are refused with the line.
#[test]
fn macro_call_errors_name_the_line() {
    let e = replay("O0001\nG65 P2 G1\nM30\nO0002\nM99\n", 100).unwrap_err();
    assert_eq!(e.line, 2, "{e:?}");
    let e = replay("O0001\nM99\n", 100).unwrap_err();
    assert!(e.message.contains("M99"), "{e:?}");
    let e = replay("O0001\nG65 P9\nM30\n", 100).unwrap_err();
    assert!(e.message.contains("O0009"), "{e:?}");
}

/// The expanded chord program replays onto the model's chord points.
#[test]
fn the_chord_program_replays_onto_the_model() {
    use gearcam_spiral::fanuc::chord_program;
    let spiral = gearcam_spiral::Spiral {
        start_radius_mm: 50.0,
        end_radius_mm: 0.0,
        start_angle_deg: 0.0,
        turns: 5,
        sense: -1,
    };
    let moves = replay(&chord_program(&spiral, &cut(), 3003, &[]), 1_000_000).unwrap();
    let (_, model) = spiral.chords(0.005);
    let feeds: Vec<_> = moves.iter().filter(|m| m.feed && m.z == -1.0).collect();
    assert_eq!(feeds.len(), model.len());
    for (m, p) in feeds.iter().zip(&model) {
        assert!((m.x - p.0).abs() < 6e-5 && (m.y - p.1).abs() < 6e-5);
    }
}
