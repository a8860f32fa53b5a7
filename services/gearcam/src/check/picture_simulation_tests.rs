//! Tests of the simulation charts on a gear built here from the involute's
//! polar form (a simulated cut takes far longer than a test should): a
//! tooth's right flank (facing +θ) at radius ρ stands ψb − inv α(ρ) from
//! its centre, the left flank at the mirror angle, tip and root circles,
//! the teeth turned by h·z·tan β / r up the face. Known errors go in (a
//! larger base circle on the right flanks, one tooth turned) so every
//! chart has something to show. The SVG is read back with an XML parser
//! and its numbers checked against the trace points, the measurement and
//! the standard's tolerances.

use super::*;
use gearcam_gearmeasure::helix::{evaluate_helix, Hand};
use gearcam_gearmeasure::outline::PolarSections;
use gearcam_gearmeasure::outline::{measure, ChartData, GearSpec};
use gearcam_gearmeasure::profile::evaluate_profile;
use gearcam_hobsim::cut::Blank;
use gearcam_hobsim::simulate::Settings;
use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

/// inv α from the radius: tan α − α, cos α = rb/ρ.
fn inv(rb: f64, rho: f64) -> f64 {
    let a = (rb / rho).acos();
    a.tan() - a
}

/// A helical gear built point by point: z = 31, mn = 2.5, β = 15° right
/// hand, b = 20; the right flanks on a base radius `grow` times the
/// design's, tooth 3 turned by `turn_um` of arc at the reference circle.
struct Built {
    spec: GearSpec,
    rb: f64,
    psi_b: f64,
    r: f64,
    grow: f64,
    turn_um: f64,
}

impl Built {
    fn new(grow: f64, turn_um: f64) -> Built {
        let spec = GearSpec::standard(31, 2.5, 15.0, Some(Hand::Right), 20.0);
        let beta = spec.helix_deg.to_radians();
        let r = 31.0 * 2.5 / beta.cos() / 2.0;
        let at = (20f64.to_radians().tan() / beta.cos()).atan();
        let rb = r * at.cos();
        let sn = 2.5 * PI / 2.0;
        let psi_b = sn / beta.cos() / (2.0 * r) + (at.tan() - at);
        Built {
            spec,
            rb,
            psi_b,
            r,
            grow,
            turn_um,
        }
    }

    /// The outline radius at `delta` from a tooth's centre on the side
    /// with base radius `rb` (bisection: the flank angle falls as ρ grows).
    fn side(&self, rb: f64, delta: f64) -> f64 {
        let (ra, rf) = (
            self.spec.tip_diameter_mm / 2.0,
            self.spec.root_diameter_mm / 2.0,
        );
        // The base-circle half angle keeps the thickness at the reference
        // circle when the base radius changes.
        let psi_b = self.psi_b - inv(self.rb, self.r) + inv(rb, self.r);
        let angle = |rho: f64| psi_b - inv(rb, rho);
        if delta <= angle(ra) {
            return ra;
        }
        let low = rb.max(rf);
        if delta > angle(low) {
            return rf;
        }
        let (mut lo, mut hi) = (low, ra);
        for _ in 0..60 {
            let m = (lo + hi) / 2.0;
            if angle(m) >= delta {
                lo = m;
            } else {
                hi = m;
            }
        }
        (lo + hi) / 2.0
    }

    fn radius(&self, theta: f64, height: f64) -> f64 {
        let pitch = TAU / 31.0;
        let t = theta - 15f64.to_radians().tan() / self.r * height;
        let j = (t / pitch).round().rem_euclid(31.0) as usize;
        let mut delta = t - j as f64 * pitch;
        if j == 3 {
            delta -= self.turn_um / 1000.0 / self.r;
        }
        delta -= TAU * (delta / TAU).round();
        if delta >= 0.0 {
            self.side(self.rb * self.grow, delta)
        } else {
            self.side(self.rb, -delta)
        }
    }

    /// The simulation of a cut that left this gear: 9 sections, 8192
    /// angles each, measured by the real measurement.
    fn simulation(&self, required_grade: u8) -> Simulation {
        let n = 8192;
        let z_mm: Vec<f64> = (0..9).map(|k| 1.0 + 18.0 * k as f64 / 8.0).collect();
        let r_mm: Vec<Vec<f64>> = z_mm
            .iter()
            .map(|&h| {
                (0..n)
                    .map(|i| self.radius(TAU * i as f64 / n as f64, h))
                    .collect()
            })
            .collect();
        let sections = PolarSections {
            z_mm: z_mm.clone(),
            r_mm: r_mm.clone(),
        };
        let measurement = measure(&sections, &self.spec).map_err(|e| e.to_string());
        Simulation {
            settings: Settings::coarse(),
            blank: Blank {
                z_mm,
                outer_radius_mm: self.spec.tip_diameter_mm / 2.0 + 1.0,
                r_mm,
            },
            passes: 0,
            spec: self.spec,
            measurement,
            safety: Vec::new(),
            required_grade,
            unit: None,
            note: None,
            measured: (0..9).collect(),
            traced: None,
        }
    }
}

/// An element of the parsed SVG.
#[derive(Debug, Default)]
struct Elem {
    name: String,
    attrs: HashMap<String, String>,
    text: String,
    children: Vec<Elem>,
}

impl Elem {
    fn attr(&self, a: &str) -> &str {
        self.attrs.get(a).map_or("", String::as_str)
    }

    fn num(&self, a: &str) -> f64 {
        self.attr(a)
            .parse()
            .unwrap_or_else(|_| panic!("{a} of {} is a number", self.name))
    }

    /// Every element below (and with) this one, depth first.
    fn all(&self) -> Vec<&Elem> {
        let mut v = vec![self];
        for c in &self.children {
            v.extend(c.all());
        }
        v
    }

    fn with_class(&self, class: &str) -> Vec<&Elem> {
        self.all()
            .into_iter()
            .filter(|e| e.attr("class") == class)
            .collect()
    }

    fn texts(&self) -> Vec<String> {
        self.all()
            .into_iter()
            .filter(|e| e.name == "text")
            .map(|e| e.text.trim().to_string())
            .collect()
    }

    fn points(&self) -> Vec<(f64, f64)> {
        let v: Vec<f64> = self
            .attr("points")
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().expect("a number"))
            .collect();
        assert_eq!(v.len() % 2, 0, "points in pairs");
        v.chunks(2).map(|p| (p[0], p[1])).collect()
    }
}

/// The SVG parsed by xml-rs into a tree (panics when it is not XML).
fn parse(svg: &str) -> Elem {
    use xml::reader::{EventReader, XmlEvent};
    let mut stack = vec![Elem::default()];
    for ev in EventReader::from_str(svg) {
        match ev.expect("well-formed XML") {
            XmlEvent::StartElement {
                name, attributes, ..
            } => stack.push(Elem {
                name: name.local_name,
                attrs: attributes
                    .into_iter()
                    .map(|a| (a.name.local_name, a.value))
                    .collect(),
                ..Elem::default()
            }),
            XmlEvent::EndElement { .. } => {
                let e = stack.pop().unwrap();
                stack.last_mut().unwrap().children.push(e);
            }
            XmlEvent::Characters(t) => stack.last_mut().unwrap().text.push_str(&t),
            _ => {}
        }
    }
    stack.pop().unwrap().children.pop().expect("a root element")
}

/// The gear the tests chart: right flanks 0.05 % larger in base radius,
/// tooth 4 turned 10 µm; the drawing asks for class 7.
fn charted() -> (Simulation, Elem, ChartData) {
    let sim = Built::new(1.0005, 10.0).simulation(7);
    let svg = simulation_svg(std::slice::from_ref(&sim)).expect("a picture");
    let sections = PolarSections {
        z_mm: sim.blank.z_mm.clone(),
        r_mm: sim.blank.r_mm.clone(),
    };
    let data = chart_data(&sections, &sim.spec, sim.traced.as_deref()).unwrap();
    (sim, parse(&svg), data)
}

/// The least and the largest x of the points between the heights `top`
/// and `bottom` (the evaluation range's marks), px.
fn span_between(points: &[(f64, f64)], top: f64, bottom: f64) -> (f64, f64) {
    let xs: Vec<f64> = points
        .iter()
        .filter(|p| p.1 >= top - 1e-9 && p.1 <= bottom + 1e-9)
        .map(|p| p.0)
        .collect();
    (
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// The µm per division a row's heading states.
fn stated_um_per_division(row: &Elem) -> f64 {
    let heading = row.texts().into_iter().next().unwrap();
    let after = heading.split("1 division = ").nth(1).expect("the scale");
    after.split(' ').next().unwrap().parse().unwrap()
}

fn gear_of(sim: &Simulation) -> GearData {
    let s = &sim.spec;
    GearData::new(s.teeth, s.normal_module_mm, s.helix_deg, s.face_width_mm).unwrap()
}

/// One SVG document: the title with the predicted and the drawing's
/// class, 8 profile and 8 helix charts (4 teeth × 2 flanks), each with one
/// trace, two band lines and two range marks, 2 pitch charts with z bars
/// and a cumulative curve each, one tooth-section view.
#[test]
fn the_picture_is_one_svg_with_every_chart() {
    let (sim, svg, _) = charted();
    assert_eq!(svg.name, "svg");
    let m = sim.measurement.as_ref().unwrap();
    let predicted = match m.overall {
        Grade::Class(c) => format!("predicted class {}", c.number()),
        Grade::WorseThan11 => "predicted worse than class 11".into(),
    };
    let title = &svg.texts()[0];
    assert!(title.contains(&predicted), "{title}");
    assert!(title.contains("drawing class 7"), "{title}");
    for kind in ["profile-chart", "helix-chart"] {
        let charts = svg.with_class(kind);
        assert_eq!(charts.len(), 8, "{kind}");
        for c in &charts {
            assert_eq!(c.with_class("trace").len(), 1, "{kind}");
            assert_eq!(c.with_class("band").len(), 2, "{kind}");
            assert_eq!(c.with_class("range").len(), 2, "{kind}");
        }
        let labels: Vec<String> = charts.iter().map(|c| c.texts()[0].clone()).collect();
        assert_eq!(
            labels,
            [
                "tooth 1 left",
                "tooth 1 right",
                "tooth 8 left",
                "tooth 8 right",
                "tooth 16 left",
                "tooth 16 right",
                "tooth 24 left",
                "tooth 24 right"
            ]
        );
    }
    let pitch = svg.with_class("pitch-chart");
    assert_eq!(pitch.len(), 2);
    for p in pitch {
        assert_eq!(p.with_class("bar").len(), 31);
        assert_eq!(p.with_class("cumulative")[0].points().len(), 31);
        assert_eq!(p.with_class("band").len(), 4);
    }
    let teeth = svg.with_class("tooth-sections");
    assert_eq!(teeth.len(), 1);
    assert_eq!(teeth[0].with_class("design").len(), 3);
    assert_eq!(teeth[0].with_class("cut").len(), 1);
}

/// A profile trace's points stand where the stated scale puts them: down
/// the chart by roll length between the evaluation range's marks, across
/// it by (e − e₀)·(division px / stated µm per division) from the first
/// point; centred on the zero line, its width is Fα as measured.
#[test]
fn a_trace_point_lands_where_the_stated_scale_puts_it() {
    let (sim, svg, data) = charted();
    let m = sim.measurement.as_ref().unwrap();
    let row = svg.with_class("profile-row")[0];
    let chart = svg.with_class("profile-chart")[1]; // tooth 1, right flank
    let grid: Vec<f64> = chart
        .with_class("grid")
        .iter()
        .map(|l| l.num("x1"))
        .collect();
    let zero = chart.with_class("zero")[0].num("x1");
    let division = grid
        .iter()
        .map(|x| (x - zero).abs())
        .fold(f64::INFINITY, f64::min);
    let px_per_um = division / stated_um_per_division(row);
    let trace = chart.with_class("trace")[0].points();
    let p = &data.profile.right[0];
    assert_eq!(trace.len(), p.x_mm.len());
    let range = m.geometry.profile_range;
    let marks: Vec<f64> = chart
        .with_class("range")
        .iter()
        .map(|l| l.num("y1"))
        .collect();
    let (y_start, y_end) = (marks[0], marks[1]);
    assert!(y_end < y_start, "the tip is at the top");
    let inside = |k: usize| (range.start_mm..=range.end_mm).contains(&p.x_mm[k]);
    let first = (0..trace.len()).find(|&k| inside(k)).unwrap();
    for (k, (x, y)) in trace.iter().enumerate() {
        let down = y_start
            + (y_end - y_start) * (p.x_mm[k] - range.start_mm) / (range.end_mm - range.start_mm);
        assert!((y - down).abs() < 1e-6, "point {k}: {y} vs {down}");
        if inside(k) {
            let across = (p.deviation_um[k] - p.deviation_um[first]) * px_per_um;
            assert!((x - trace[first].0 - across).abs() < 1e-6, "point {k}");
        }
    }
    assert!(
        trace.iter().any(|t| t.1 < y_end - 1.0),
        "the trace runs on to the tip"
    );
    let (min, max) = span_between(&trace, y_end, y_start);
    assert!(((max + min) / 2.0 - zero).abs() < 1e-6);
    let fa = m.profile.right[0].total_um;
    assert!(fa > 2.0, "the built slope shows: Fα {fa}");
    assert!((max - min - fa * px_per_um).abs() < 1e-6);
}

/// The band lines stand at ±T/2 of the class the drawing asks for about
/// the zero line of every trace chart (T the tolerance of Fα or Fβ), the
/// pitch lines at ±fpT and ±FpT/2.
#[test]
fn the_band_lines_stand_at_half_the_tolerance_of_the_drawing() {
    let (sim, svg, _) = charted();
    let gear = gear_of(&sim);
    let class = Class::new(7).unwrap();
    for (row, chart, item) in [
        ("profile-row", "profile-chart", Item::ProfileTotal),
        ("helix-row", "helix-chart", Item::HelixTotal),
    ] {
        let row = svg.with_class(row)[0];
        let tol = iso1328::tolerance_um(&gear, item, class);
        let px_per_um = DIV_PX / stated_um_per_division(row);
        for c in svg.with_class(chart) {
            let zero = c.with_class("zero")[0].num("x1");
            let mut band: Vec<f64> = c
                .with_class("band")
                .iter()
                .map(|l| l.num("x1") - zero)
                .collect();
            band.sort_by(f64::total_cmp);
            let want = tol / 2.0 * px_per_um;
            assert!(
                (band[0] + want).abs() < 1e-9 && (band[1] - want).abs() < 1e-9,
                "{item:?}: {band:?} vs ±{want}"
            );
        }
    }
    let row = svg.with_class("pitch-row")[0];
    let px_per_um = DIV_PX / stated_um_per_division(row);
    let fpt = iso1328::tolerance_um(&gear, Item::SinglePitch, class);
    let fpt_total = iso1328::tolerance_um(&gear, Item::CumulativePitch, class);
    for c in svg.with_class("pitch-chart") {
        let zeros: Vec<f64> = c.with_class("zero").iter().map(|l| l.num("y1")).collect();
        let mut lines: Vec<f64> = c.with_class("band").iter().map(|l| l.num("y1")).collect();
        lines.sort_by(f64::total_cmp);
        let mut want = vec![
            zeros[0] - fpt * px_per_um,
            zeros[0] + fpt * px_per_um,
            zeros[1] - fpt_total / 2.0 * px_per_um,
            zeros[1] + fpt_total / 2.0 * px_per_um,
        ];
        want.sort_by(f64::total_cmp);
        for (a, b) in lines.iter().zip(&want) {
            assert!((a - b).abs() < 1e-9, "{lines:?} vs {want:?}");
        }
    }
}

/// The bars are the single pitch deviations at the stated scale, up for
/// +: tooth 4, turned 10 µm forward, has a right-flank pitch of about
/// +10 µm and tooth 5 one of about −10 µm.
#[test]
fn the_pitch_bars_are_the_single_pitch_deviations() {
    let (sim, svg, _) = charted();
    let m = sim.measurement.as_ref().unwrap();
    let row = svg.with_class("pitch-row")[0];
    let px_per_um = DIV_PX / stated_um_per_division(row);
    let right = svg.with_class("pitch-chart")[1];
    let zero = right.with_class("zero")[0].num("y1");
    let bars = right.with_class("bar");
    for (i, b) in bars.iter().enumerate() {
        let (y, h) = (b.num("y"), b.num("height"));
        let up = if y < zero - 1e-9 { h } else { -h };
        assert!(
            (up - m.pitch.right.single_um[i] * px_per_um).abs() < 1e-9,
            "tooth {}",
            i + 1
        );
    }
    let up = |i: usize| zero - bars[i].num("y");
    assert!(
        (up(3) / px_per_um - 10.0).abs() < 1.5,
        "{}",
        up(3) / px_per_um
    );
    assert!(bars[4].num("y") >= zero - 1e-9);
}

/// The chart's points are the ones the measurement graded: evaluated
/// again they give every tooth's and flank's deviations.
#[test]
fn the_chart_points_give_the_measured_deviations() {
    let (sim, _, data) = charted();
    let m = sim.measurement.as_ref().unwrap();
    let helix = data.helix.as_ref().unwrap();
    let mh = m.helix.as_ref().unwrap();
    for t in 0..31 {
        for (pts, want) in [
            (&data.profile.left[t], m.profile.left[t]),
            (&data.profile.right[t], m.profile.right[t]),
        ] {
            let got =
                evaluate_profile(&pts.x_mm, &pts.deviation_um, m.geometry.profile_range).unwrap();
            assert_eq!(got, want, "tooth {}", t + 1);
        }
        for (pts, want) in [(&helix.left[t], mh.left[t]), (&helix.right[t], mh.right[t])] {
            let got = evaluate_helix(&pts.x_mm, &pts.deviation_um, m.geometry.helix_range).unwrap();
            assert_eq!(got, want, "tooth {}", t + 1);
        }
    }
}

/// The design tooth is the built gear's: on a perfect gear every sample of
/// the middle section between the form and the tip form circle lies
/// within 0.5 µm of the design outline turned to its tooth's measured
/// centre.
#[test]
fn the_design_outline_is_the_perfect_gears() {
    let sim = Built::new(1.0, 0.0).simulation(7);
    let m = sim.measurement.as_ref().unwrap();
    let design = DesignTooth::new(&sim.spec, &m.geometry);
    let sections = PolarSections {
        z_mm: sim.blank.z_mm.clone(),
        r_mm: sim.blank.r_mm.clone(),
    };
    let data = chart_data(&sections, &sim.spec, sim.traced.as_deref()).unwrap();
    let r_mm = &sim.blank.r_mm[data.middle_section];
    let n = r_mm.len();
    let c = data.tooth_centre_rad[0];
    let mut checked = 0;
    for (i, &r) in r_mm.iter().enumerate() {
        let d = wrap(TAU * i as f64 / n as f64 - c);
        if d.abs() > 0.5 * TAU / 31.0 || r < design.r_form + 1e-3 || r > design.r_tip - 1e-3 {
            continue;
        }
        let p = (r * d.sin(), r * d.cos());
        let q = design.nearest(p);
        let dist = (p.0 - q.0).hypot(p.1 - q.1);
        assert!(dist < 5e-4, "sample {i}: {dist} mm off");
        checked += 1;
    }
    assert!(checked > 20, "{checked} samples");
}

/// The magnified differences are the cut points' distances from the
/// design times the stated factor.
#[test]
fn the_tooth_view_states_its_magnification() {
    assert_eq!(magnification(0.01, 0.375), 20.0);
    assert_eq!(magnification(0.0, 0.375), 1000.0);
    assert_eq!(magnification(1.0, 0.375), 1.0);
    let (_, svg, _) = charted();
    let view = svg.with_class("tooth-sections")[0];
    let heading = &view.texts()[0];
    assert!(heading.contains("differences ×"), "{heading}");
}

/// The scale steps 1, 2, 5 and fits the extent in the divisions.
#[test]
fn the_scale_is_the_smallest_round_step_that_fits() {
    assert_eq!(um_per_division(11.0, 5.5), 2.0);
    assert_eq!(um_per_division(11.1, 5.5), 5.0);
    assert_eq!(um_per_division(300.0, 5.5), 100.0);
    assert_eq!(um_per_division(0.3, 5.5), 0.1);
}

/// A real program (the spur example for the 840D, its model beside it),
/// simulated coarse: the picture has every chart, and each profile and
/// helix trace spans the measured Fα or Fβ at its row's stated scale
/// between the evaluation range's marks.
#[test]
fn a_real_program_charts_the_gear_it_cuts() {
    let text = include_str!("../../../../crates/nc/tests/programs/spur_840d.nc");
    let json = include_str!("../../../../crates/nc/tests/programs/spur_840d.model.json");
    let model: gearcam_proto::MachiningModel = serde_json::from_str(json).unwrap();
    let (check, trace) = gearcam_nc::check(text, &model);
    assert!(check.ok, "{:?}", check.findings);
    let sim = gearcam_hobsim::simulate::simulate(&trace, &model, &Settings::coarse()).unwrap();
    let m = sim.measurement.as_ref().expect("the cut gear measures");
    let svg = parse(&simulation_svg(std::slice::from_ref(&sim)).expect("a picture"));
    let picked = picked_teeth(sim.spec.teeth as usize);
    let helix = m.helix.as_ref().expect("9 sections: a helix");
    for (row, kind) in [
        ("profile-row", "profile-chart"),
        ("helix-row", "helix-chart"),
    ] {
        let px_per_um = DIV_PX / stated_um_per_division(svg.with_class(row)[0]);
        let charts = svg.with_class(kind);
        assert_eq!(charts.len(), 2 * picked.len(), "{kind}");
        for (k, c) in charts.iter().enumerate() {
            let (t, right) = (picked[k / 2], k % 2 == 1);
            // The helix traces are of the teeth traced, in their order.
            let h = m.helix_teeth.iter().position(|&x| x == t).expect("traced");
            let total = match (kind, right) {
                ("profile-chart", false) => m.profile.left[t].total_um,
                ("profile-chart", true) => m.profile.right[t].total_um,
                (_, false) => helix.left[h].total_um,
                (_, true) => helix.right[h].total_um,
            };
            let marks: Vec<f64> = c.with_class("range").iter().map(|l| l.num("y1")).collect();
            let (min, max) = span_between(&c.with_class("trace")[0].points(), marks[1], marks[0]);
            let width = max - min;
            assert!(
                (width - total * px_per_um).abs() < 1e-6,
                "{kind} {k}: {width} px vs {total} µm"
            );
        }
    }
    assert_eq!(svg.with_class("pitch-chart").len(), 2);
    assert_eq!(svg.with_class("tooth-sections").len(), 1);
}

/// A part of several gears charts each gear under its name, the second's
/// charts below the first's; a gear that did not measure says why in a
/// line of its own instead of hiding the others' charts.
#[test]
fn a_part_charts_every_gear_under_its_name() {
    let mut upper = Built::new(1.0005, 10.0).simulation(7);
    upper.unit = Some("upper".into());
    let mut lower = Built::new(1.0, 0.0).simulation(6);
    lower.unit = Some("lower".into());
    let mut unmeasured = Built::new(1.0, 0.0).simulation(6);
    unmeasured.unit = Some("spline".into());
    unmeasured.measurement = Err("18 gaps where the drawing has 31".into());
    let svg = parse(&simulation_svg(&[upper, lower, unmeasured]).expect("a picture"));
    let texts = svg.texts();
    let title = |name: &str| {
        texts
            .iter()
            .position(|t| t.starts_with(&format!("Virtual gear \"{name}\" (coarse simulation)")))
            .unwrap_or_else(|| panic!("no title for {name}: {texts:?}"))
    };
    assert!(title("upper") < title("lower"), "{texts:?}");
    assert!(texts
        .iter()
        .any(|t| t == "Virtual gear \"spline\": no charts, 18 gaps where the drawing has 31"));
    let rows = svg.with_class("profile-row");
    assert_eq!(rows.len(), 2);
    // The heights an element's shapes and labels reach, px.
    let heights = |e: &Elem| -> Vec<f64> {
        e.all()
            .into_iter()
            .flat_map(|c| ["y", "y1", "y2"].map(|a| c.attrs.get(a).and_then(|y| y.parse().ok())))
            .flatten()
            .collect()
    };
    let pitch = svg.with_class("pitch-row");
    assert_eq!(pitch.len(), 2);
    let first_lowest = heights(pitch[0]).into_iter().fold(f64::MIN, f64::max);
    let second_highest = heights(rows[1]).into_iter().fold(f64::MAX, f64::min);
    assert!(
        second_highest > first_lowest,
        "the lower gear's charts ({second_highest} px down) overlap the upper's ({first_lowest} px)"
    );
    // The page is tall enough for everything on it.
    let deepest = heights(&svg).into_iter().fold(f64::MIN, f64::max);
    assert!(deepest <= svg.num("height"), "{deepest} below the page");
    // One gear alone: no name in its title, as before.
    let alone = parse(&simulation_svg(&[Built::new(1.0, 0.0).simulation(6)]).unwrap());
    assert!(alone
        .texts()
        .iter()
        .any(|t| t.starts_with("Virtual gear (coarse")));
}
