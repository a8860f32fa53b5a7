//! Tests of the hobbing picture: what it draws, checked against the model
//! and the set-up it comes from.

use super::*;
use gearcam_proto::MachiningModel;

/// The model of an example job, as `gearcam check` computes it.
fn model_of(example: &str) -> MachiningModel {
    let text = gearcam_testkit::examples::example(example);
    let spec = crate::jobfile::parse(&text, example).unwrap();
    let req = crate::jobfile::request(spec);
    let conn = gearcam_knowledge::db::open_in_memory().unwrap();
    let plan = gearcam_knowledge::plan::plan(&conn, &req).unwrap();
    gearcam_model::compute(&plan).unwrap()
}

/// The distance from `p` to the closed polygon `poly` (0 inside it).
fn distance_to(p: Xz, poly: &[Xz]) -> f64 {
    let mut inside = false;
    let mut best = f64::MAX;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if (a.z_mm > p.z_mm) != (b.z_mm > p.z_mm) {
            let x = a.x_mm + (p.z_mm - a.z_mm) / (b.z_mm - a.z_mm) * (b.x_mm - a.x_mm);
            if p.x_mm < x {
                inside = !inside;
            }
        }
        let (dx, dz) = (b.x_mm - a.x_mm, b.z_mm - a.z_mm);
        let t = (((p.x_mm - a.x_mm) * dx + (p.z_mm - a.z_mm) * dz) / (dx * dx + dz * dz))
            .clamp(0.0, 1.0);
        best = best.min((a.x_mm + t * dx - p.x_mm).hypot(a.z_mm + t * dz - p.z_mm));
    }
    if inside {
        0.0
    } else {
        best
    }
}

/// The nearest the segment comes to the polygon, sampled every 0.1 mm.
fn nearest(s: &Segment, poly: &[Xz]) -> f64 {
    let len = (s.to.x_mm - s.from.x_mm).hypot(s.to.z_mm - s.from.z_mm);
    let n = (len / 0.1).ceil().max(1.0) as usize;
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let p = Xz {
                x_mm: s.from.x_mm + t * (s.to.x_mm - s.from.x_mm),
                z_mm: s.from.z_mm + t * (s.to.z_mm - s.from.z_mm),
            };
            distance_to(p, poly)
        })
        .fold(f64::MAX, f64::min)
}

/// Each position of the finishing cut is marked at the model's X and Z
/// (the SVG's y is −Z) and labelled with both; C stands above the blank's
/// upper face by the clearance and the safety distance, D below its lower
/// face by the same, as the job's set-up puts them (docs/hobbing.md §4).
#[test]
fn the_positions_are_marked_and_labelled_where_the_model_puts_them() {
    let model = model_of("spur_840d.toml");
    let svg = hobbing_svg(&model);
    let k = &model.model;
    let p = &k.positions;
    for (name, pos) in [("A", p.A), ("B", p.B), ("C", p.C), ("D", p.D), ("E", p.E)] {
        let mark = format!("cx=\"{}\" cy=\"{}\"", pos.x_mm, -pos.z_mm);
        assert!(svg.contains(&mark), "{name}: no mark {mark}");
        let text = format!("{name} X{} Z{}", num(pos.x_mm), num(pos.z_mm));
        assert!(svg.contains(&text), "{name}: no label {text}");
    }
    let gear = &model.plan.gear;
    let over = k.clearance_mm + k.safety_mm;
    let top = gear.fixture_height_mm + gear.face_width_mm;
    assert!((p.C.z_mm - (top + over)).abs() < 1e-9, "{p:?}");
    assert!((p.D.z_mm - (gear.fixture_height_mm - over)).abs() < 1e-9);
    let u = &units(&model)[0];
    assert_eq!((u.lower_mm, u.upper_mm()), (gear.fixture_height_mm, top));
    assert_eq!(u.lower_radius_mm, k.blank_od_mm / 2.0);
}

/// The path runs A → B → C (rapid), C → D (the only feed), D → E and back
/// to A (rapid); on every rapid move the hob's tip circle (its radius
/// shrunk by cos η, the least it reaches in the plane) stays clear of the
/// blank, and the feed runs into it (it cuts the teeth).
#[test]
fn a_collision_free_path_keeps_the_hob_clear_of_the_blank_on_rapid_moves() {
    let model = model_of("spur_840d.toml");
    let k = &model.model;
    let segments = path(k);
    let p = &k.positions;
    let first = segments.first().unwrap();
    let last = segments.last().unwrap();
    assert_eq!(first.from, Xz::of(p.A));
    assert_eq!(last.to, Xz::of(p.A));
    let feeds: Vec<&Segment> = segments.iter().filter(|s| !s.rapid).collect();
    assert_eq!(feeds.len(), 1, "{segments:?}");
    assert_eq!((feeds[0].from, feeds[0].to), (Xz::of(p.C), Xz::of(p.D)));
    for pos in [p.B, p.E] {
        assert!(
            segments.iter().any(|s| s.to == Xz::of(pos)),
            "{pos:?} not on {segments:?}"
        );
    }
    let u = &units(&model)[0];
    let blank = u.outline();
    let r = u.hob.od_mm / 2.0 * k.swivel_deg.to_radians().cos();
    for s in segments.iter().filter(|s| s.rapid) {
        let d = nearest(s, &blank);
        assert!(d >= r, "rapid {s:?} comes {d} mm from the blank, hob r {r}");
    }
    assert!(nearest(feeds[0], &blank) < r, "the feed does not cut");
}

/// A part of two gears draws both blanks at their heights, each unit's
/// path and positions, and a hob at each unit's C.
#[test]
fn a_multi_gear_part_draws_every_unit() {
    let model = model_of("multi_gear_840d.toml");
    let all = units(&model);
    assert_eq!(all.len(), 2);
    let h = model.plan.gear.fixture_height_mm;
    for (u, m) in all.iter().zip(&model.model.units) {
        assert_eq!(u.lower_mm, h + m.z_offset_mm);
        assert_eq!(u.face_width_mm, m.gear.face_width_mm);
    }
    assert!(all[1].lower_mm > all[0].upper_mm());
    let svg = hobbing_svg(&model);
    for u in &all {
        let c = u.kinematics.positions.C;
        assert!(svg.contains(&format!("cx=\"{}\" cy=\"{}\"", c.x_mm, -c.z_mm)));
        assert!(svg.contains(&format!("{}: tip", u.name)), "{}", u.name);
    }
    assert_eq!(svg.matches("hob Ø").count(), 2);
}

/// A cone's blank is narrower at its small end by b·tan δ.
#[test]
fn a_conical_blank_narrows_at_its_small_end() {
    let model = model_of("conical_840d.toml");
    let cone = model.model.cone.as_ref().unwrap();
    let u = &units(&model)[0];
    let b = model.plan.gear.face_width_mm;
    let wide = u.lower_radius_mm.max(u.upper_radius_mm);
    let narrow = u.lower_radius_mm.min(u.upper_radius_mm);
    assert!((wide - narrow - b * cone.angle_deg.to_radians().tan()).abs() < 1e-9);
    assert_eq!(wide, model.model.blank_od_mm / 2.0);
}

/// A part number or a unit's name with markup in it is text in the
/// picture, never an element: no script can ride in on it.
#[test]
fn markup_in_a_part_number_or_unit_name_is_text() {
    let script = "<script>alert(1)</script>\"'&";
    let mut model = model_of("multi_gear_840d.toml");
    model.plan.request.spec.job.part_number = script.into();
    model.model.units[1].name = script.into();
    let svg = hobbing_svg(&model);
    assert!(!svg.contains("<script"), "{svg}");
    assert_eq!(
        svg.matches("&lt;script&gt;alert(1)&lt;/script&gt;").count(),
        3
    );
}

/// An arc through three points passes its intermediate point and ends at
/// its end, on the circle through all three.
#[test]
fn an_arc_runs_through_its_intermediate_point() {
    let xz = |x_mm, z_mm| Xz { x_mm, z_mm };
    let pts = arc_points(xz(0.0, 0.0), xz(1.0, 1.0), xz(2.0, 0.0));
    assert_eq!(*pts.last().unwrap(), xz(2.0, 0.0));
    for p in &pts {
        assert!(((p.x_mm - 1.0).hypot(p.z_mm) - 1.0).abs() < 1e-9, "{p:?}");
        assert!(p.z_mm >= -1e-9, "the arc runs the other way: {p:?}");
    }
    let pts = arc_points(xz(0.0, 0.0), xz(1.0, -1.0), xz(2.0, 0.0));
    assert!(pts.iter().all(|p| p.z_mm <= 1e-9));
    assert_eq!(
        arc_points(xz(0.0, 0.0), xz(1.0, 0.0), xz(2.0, 0.0)).len(),
        2
    );
}
