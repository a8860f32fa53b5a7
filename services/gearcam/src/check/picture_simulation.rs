//! The virtual gear's measuring charts, as a gear-measuring machine prints
//! them: one SVG document ([`simulation_svg`]) with
//!
//! - a title line: the predicted ISO 1328-1:2013 class and the drawing's;
//! - **profile charts** of four teeth about 90° apart (tooth 1, z/4 + 1,
//!   z/2 + 1, 3z/4 + 1), left and right flank, in the middle section: the
//!   roll length runs up the chart (root at the bottom, tip at the top),
//!   the deviation across it (+material to the right), magnified by the
//!   scale the row's heading states (one grid division = so many µm);
//! - **helix charts** of the same flanks at the measuring diameter, the
//!   height from the reference face running up the chart;
//! - **pitch charts** of both flanks: the single pitch deviations fpi as
//!   bars against ±fpT, and the cumulative deviations Fpi as a curve
//!   against a band FpT wide;
//! - the **tooth sections**: three teeth of the middle section, the
//!   simulated outline over the design one, the difference magnified by
//!   the factor the heading states.
//!
//! **Bands.** A trace is drawn centred: its mid-range value
//! ((max + min)/2 over the evaluation range) on the chart's zero line. The
//! total deviation Fα (Fβ) is the range of the trace over the evaluation
//! range (as the measurement computes it), so the trace lies between the
//! two band lines at ±T/2 exactly when Fα ≤ T: the band is the tolerance T
//! of the class drawn, as a gear-measuring machine's chart shows whether a
//! trace fits. The class drawn is the drawing's (the achieved one when the
//! drawing's is not a class of the standard). The cumulative pitch curve
//! is centred the same way against ±FpT/2; the single pitch bars are
//! signed values against ±fpT.
//!
//! Trace points beyond the evaluation range (a profile trace runs on to
//! the tip form circle) may leave the scale chosen for the range: they are
//! drawn at the chart's edge, as a chart recorder's pen stops there.
//!
//! Every text goes through the `svg` crate's `Text` node (escaped);
//! attributes hold numbers, colours and fixed class names only.

use gearcam_gearmeasure::iso1328::{self, Class, GearData, Grade, Item};
use gearcam_gearmeasure::outline::{chart_data, Measurement, TracePoints};
use gearcam_gearmeasure::pitch::PitchDeviations;
use gearcam_hobsim::simulate::Simulation;
use svg::node::element::{Group, Line, Polyline, Rectangle, Text};
use svg::Document;

/// The width of a grid division of a deviation axis, px.
pub(crate) const DIV_PX: f64 = 10.0;
/// The width of a trace chart, px (± 6 divisions about the zero line).
const TRACE_W: f64 = 120.0;
/// The height of a trace chart, px.
const TRACE_H: f64 = 280.0;
/// The horizontal pitch of the trace charts, px.
const TRACE_STEP: f64 = 145.0;
/// The page width, px.
const PAGE_W: f64 = 1200.0;
/// The left margin, px.
const MARGIN: f64 = 20.0;
/// The heights of the pitch panels, px.
const PITCH_H: f64 = 130.0;
/// The size of the tooth-section view, px.
const TOOTH_PX: f64 = 480.0;

/// The charts of a simulated part, each gear's below the one before (a
/// gear that was not measured says why in one line), or `None` when no gear
/// was measured (the report says why) or none's traces can be found again.
pub fn simulation_svg(gears: &[Simulation]) -> Option<String> {
    let mut doc = Document::new();
    let (mut y, mut drawn) = (0.0, 0);
    for sim in gears {
        if let Some((charts, below)) = gear_charts(sim, y) {
            doc = doc.add(charts);
            (y, drawn) = (below, drawn + 1);
        } else if gears.len() > 1 {
            let why = match &sim.measurement {
                Err(why) => why.as_str(),
                Ok(_) => "its traces could not be found again",
            };
            let text = format!("Virtual gear{}: no charts, {why}", unit_name(sim));
            doc = doc.add(label(text, MARGIN, y + 32.0, 16.0));
            y += 50.0;
        }
    }
    (drawn > 0).then(|| {
        doc.set("viewBox", (0.0, 0.0, PAGE_W, y))
            .set("width", PAGE_W)
            .set("height", y.round())
            .to_string()
    })
}

/// The name of a gear of a part of several, quoted after a space; empty
/// for a part of one gear.
fn unit_name(sim: &Simulation) -> String {
    sim.unit
        .as_ref()
        .map_or(String::new(), |u| format!(" \"{u}\""))
}

/// One gear's charts from the height `y0` down, and the height below them;
/// `None` when the gear was not measured or its traces cannot be found
/// again.
fn gear_charts(sim: &Simulation, y0: f64) -> Option<(Group, f64)> {
    let m = sim.measurement.as_ref().ok()?;
    let spec = &sim.spec;
    let sections = sim.measured_sections();
    let data = chart_data(&sections, spec, sim.traced.as_deref()).ok()?;
    let gear = GearData::new(
        spec.teeth,
        spec.normal_module_mm,
        spec.helix_deg,
        spec.face_width_mm,
    )
    .ok()?;
    let class = Class::new(sim.required_grade).unwrap_or(match m.overall {
        Grade::Class(c) => c,
        Grade::WorseThan11 => Class::COARSEST,
    });
    let tol = |item| iso1328::tolerance_um(&gear, item, class);
    let mut y = y0 + 20.0;
    let mut doc = Group::new();
    doc = doc.add(label(title(sim, m), MARGIN, y + 12.0, 16.0));
    y += 40.0;
    let picked = picked_teeth(spec.teeth as usize);
    let profile = TraceRow {
        kind: "profile",
        heading: format!(
            "Profile, middle section z = {:.2} mm: roll length up (mm), root at the bottom",
            m.middle_section_mm
        ),
        symbols: ["Fα", "fHα", "ffα"],
        range: (
            m.geometry.profile_range.start_mm,
            m.geometry.profile_range.end_mm,
        ),
        tol_um: tol(Item::ProfileTotal),
        class,
    };
    let every: Vec<(usize, usize)> = picked.iter().map(|&t| (t, t)).collect();
    let (g, h) = profile.draw(&data.profile, &every, y, |t, right| {
        let d = if right {
            &m.profile.right
        } else {
            &m.profile.left
        }[t];
        [d.total_um, d.slope_um, d.form_um]
    });
    doc = doc.add(g);
    y += h;
    if let (Some(traces), Some(hx)) = (&data.helix, &m.helix) {
        let helix = TraceRow {
            kind: "helix",
            heading: format!(
                "Helix at the measuring diameter {:.3} mm: height from the reference face up (mm)",
                m.geometry.measuring_diameter_mm
            ),
            symbols: ["Fβ", "fHβ", "ffβ"],
            range: (
                m.geometry.helix_range.start_mm,
                m.geometry.helix_range.end_mm,
            ),
            tol_um: tol(Item::HelixTotal),
            class,
        };
        // The helix traces are of the teeth traced, in their order.
        let traced: Vec<(usize, usize)> = picked
            .iter()
            .filter_map(|&t| {
                data.helix_teeth
                    .iter()
                    .position(|&x| x == t)
                    .map(|i| (t, i))
            })
            .collect();
        let (g, h) = helix.draw(traces, &traced, y, |t, right| {
            let d = if right { &hx.right } else { &hx.left }[t];
            [d.total_um, d.slope_um, d.form_um]
        });
        doc = doc.add(g);
        y += h;
    }
    let (g, h) = pitch_charts(
        m,
        y,
        tol(Item::SinglePitch),
        tol(Item::CumulativePitch),
        class,
    );
    doc = doc.add(g);
    y += h;
    let (g, h) = tooth_sections(
        &sections.r_mm[data.middle_section],
        &data,
        spec,
        &m.geometry,
        y,
    );
    doc = doc.add(g);
    y += h;
    Some((doc, y))
}

/// The title line: the predicted class and the drawing's.
fn title(sim: &Simulation, m: &Measurement) -> String {
    let grade = match m.overall {
        Grade::Class(c) => format!("class {}", c.number()),
        Grade::WorseThan11 => "worse than class 11".to_string(),
    };
    format!(
        "Virtual gear{} ({} simulation), ISO 1328-1:2013: predicted {grade}, drawing class {}; z = {}, mn = {} mm, β = {}°",
        unit_name(sim), sim.settings.mode, sim.required_grade, sim.spec.teeth, sim.spec.normal_module_mm, sim.spec.helix_deg
    )
}

/// The teeth charted (indices from 0): 1, z/4 + 1, z/2 + 1, 3z/4 + 1 in
/// the numbering from 1, the four a coarse run traces.
pub(crate) fn picked_teeth(z: usize) -> Vec<usize> {
    gearcam_gearmeasure::outline::four_teeth(z)
}

/// The µm per grid division that fits `extent_um` (the largest distance
/// from the zero line to draw) within `divisions`: the smallest of 1, 2, 5
/// times a power of ten that does.
pub(crate) fn um_per_division(extent_um: f64, divisions: f64) -> f64 {
    let need = (extent_um / divisions).max(1e-3);
    let mut decade = 10f64.powf(need.log10().floor());
    loop {
        for f in [1.0, 2.0, 5.0] {
            if f * decade >= need {
                return f * decade;
            }
        }
        decade *= 10.0;
    }
}

/// The deviations of a trace at the abscissae within `range`, µm.
fn in_range(t: &TracePoints, range: (f64, f64)) -> impl Iterator<Item = f64> + '_ {
    let (lo, hi) = (range.0.min(range.1), range.0.max(range.1));
    t.x_mm
        .iter()
        .zip(&t.deviation_um)
        .filter(move |(x, _)| (lo - 1e-9..=hi + 1e-9).contains(*x))
        .map(|(_, e)| *e)
}

/// The middle of a trace's range over `range` (the abscissae within it;
/// all when none is), µm.
pub(crate) fn mid_range(t: &TracePoints, range: (f64, f64)) -> f64 {
    let inside: Vec<f64> = in_range(t, range).collect();
    let v = if inside.is_empty() {
        &t.deviation_um
    } else {
        &inside
    };
    let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = v.iter().copied().fold(f64::INFINITY, f64::min);
    if max.is_finite() {
        (max + min) / 2.0
    } else {
        0.0
    }
}

/// One row of trace charts (profile or helix).
struct TraceRow {
    /// The class name of its charts: `profile` or `helix`.
    kind: &'static str,
    heading: String,
    /// Total, slope, form.
    symbols: [&'static str; 3],
    /// The evaluation range, mm.
    range: (f64, f64),
    /// The tolerance of the total deviation in the class drawn, µm.
    tol_um: f64,
    class: Class,
}

impl TraceRow {
    /// The row's charts at `top`, and the row's height. `picked` holds each
    /// tooth charted and the index of its traces in `traces`;
    /// `values(index, right)` is the measured total, slope and form
    /// deviation of a flank.
    fn draw(
        &self,
        traces: &gearcam_gearmeasure::outline::TeethTraces<TracePoints>,
        picked: &[(usize, usize)],
        top: f64,
        values: impl Fn(usize, bool) -> [f64; 3],
    ) -> (Group, f64) {
        let flanks: Vec<((usize, usize), bool, &TracePoints)> = picked
            .iter()
            .flat_map(|&(t, i)| {
                [false, true].into_iter().filter_map(move |right| {
                    let side = if right { &traces.right } else { &traces.left };
                    side.get(i).map(|p| ((t, i), right, p))
                })
            })
            .collect();
        let extent = flanks
            .iter()
            .map(|(_, _, p)| {
                let c = mid_range(p, self.range);
                in_range(p, self.range)
                    .map(|e| (e - c).abs())
                    .fold(0.0, f64::max)
            })
            .fold(self.tol_um / 2.0, f64::max);
        let um_div = um_per_division(extent, 5.5);
        let heading = format!(
            "{}; deviation across, +material to the right, 1 division = {} µm; band: {} tolerance {} µm of class {}",
            self.heading,
            um_div,
            self.symbols[0],
            self.tol_um,
            self.class.number()
        );
        let mut g = Group::new()
            .set("class", format!("{}-row", self.kind))
            .add(label(heading, MARGIN, top + 12.0, 12.0));
        let (lo, hi) = axis_span(&flanks, self.range);
        for (k, ((t, i), right, p)) in flanks.iter().enumerate() {
            let x0 = MARGIN + k as f64 * TRACE_STEP;
            let chart = TraceChart {
                x0,
                y0: top + 34.0,
                lo,
                hi,
                px_per_um: DIV_PX / um_div,
            };
            let v = values(*i, *right);
            g = g.add(chart.draw(self, *t, *right, p, v));
        }
        (g, TRACE_H + 110.0)
    }
}

/// The abscissa span of a row's charts: the evaluation range and every
/// trace point, with a margin of 5 %.
fn axis_span(flanks: &[((usize, usize), bool, &TracePoints)], range: (f64, f64)) -> (f64, f64) {
    let (mut lo, mut hi) = (range.0.min(range.1), range.0.max(range.1));
    for (_, _, p) in flanks {
        for x in &p.x_mm {
            lo = lo.min(*x);
            hi = hi.max(*x);
        }
    }
    let pad = 0.05 * (hi - lo).max(1e-6);
    (lo - pad, hi + pad)
}

/// Where a trace chart stands and its scales.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TraceChart {
    /// Left edge, px.
    pub(crate) x0: f64,
    /// Top edge, px.
    pub(crate) y0: f64,
    /// The abscissa at the bottom and at the top, mm.
    pub(crate) lo: f64,
    pub(crate) hi: f64,
    /// The deviation scale, px per µm.
    pub(crate) px_per_um: f64,
}

impl TraceChart {
    /// The zero line's x, px.
    pub(crate) fn zero_x(&self) -> f64 {
        self.x0 + TRACE_W / 2.0
    }

    /// The y of abscissa `x_mm`, px (up the chart as it grows).
    pub(crate) fn y_of(&self, x_mm: f64) -> f64 {
        self.y0 + TRACE_H * (self.hi - x_mm) / (self.hi - self.lo)
    }

    /// The chart of one flank's trace `p` with its values `v` (total,
    /// slope, form, µm).
    fn draw(
        &self,
        row: &TraceRow,
        tooth: usize,
        right: bool,
        p: &TracePoints,
        v: [f64; 3],
    ) -> Group {
        let zero = self.zero_x();
        let c = mid_range(p, row.range);
        let mut g = Group::new()
            .set("class", format!("{}-chart", row.kind))
            .add(
                Rectangle::new()
                    .set("x", self.x0)
                    .set("y", self.y0)
                    .set("width", TRACE_W)
                    .set("height", TRACE_H)
                    .set("fill", "none")
                    .set("stroke", "#999")
                    .set("stroke-width", 0.5),
            );
        let divisions = (TRACE_W / 2.0 / DIV_PX).floor() as i32;
        for k in -divisions..=divisions {
            let x = zero + f64::from(k) * DIV_PX;
            let class = if k == 0 { "zero" } else { "grid" };
            let colour = if k == 0 { "#555" } else { "#ddd" };
            g = g.add(vline(x, self.y0, self.y0 + TRACE_H, colour, 0.5).set("class", class));
        }
        let (ya, yb) = (self.y_of(row.range.0), self.y_of(row.range.1));
        for y in [ya, yb] {
            g = g.add(hline(self.x0, self.x0 + TRACE_W, y, "#333", 1.0).set("class", "range"));
        }
        let half = row.tol_um / 2.0 * self.px_per_um;
        for x in [zero - half, zero + half] {
            g = g.add(vline(x, ya, yb, "#c00", 1.0).set("class", "band"));
        }
        let points: Vec<(f64, f64)> = p
            .x_mm
            .iter()
            .zip(&p.deviation_um)
            .map(|(x, e)| {
                let across = (zero + (e - c) * self.px_per_um).clamp(self.x0, self.x0 + TRACE_W);
                (across, self.y_of(*x))
            })
            .collect();
        g = g.add(
            Polyline::new()
                .set("class", "trace")
                .set("points", points)
                .set("fill", "none")
                .set("stroke", "#08519c")
                .set("stroke-width", 1.0),
        );
        let flank = if right { "right" } else { "left" };
        let below = self.y0 + TRACE_H;
        let s = row.symbols;
        g.add(label(
            format!("tooth {} {flank}", tooth + 1),
            self.x0,
            self.y0 - 2.0,
            11.0,
        ))
        .add(label(
            format!("{} {} µm", s[0], one_decimal(v[0])),
            self.x0,
            below + 14.0,
            11.0,
        ))
        .add(label(
            format!("{} {} µm", s[1], one_decimal(v[1])),
            self.x0,
            below + 28.0,
            11.0,
        ))
        .add(label(
            format!("{} {} µm", s[2], one_decimal(v[2])),
            self.x0,
            below + 42.0,
            11.0,
        ))
        .add(label(
            format!("{:.2} to {:.2} mm", row.range.0, row.range.1),
            self.x0,
            below + 56.0,
            10.0,
        ))
    }
}

/// The pitch charts of both flanks at `top`, and their height.
fn pitch_charts(
    m: &Measurement,
    top: f64,
    fpt_um: f64,
    fpt_total_um: f64,
    class: Class,
) -> (Group, f64) {
    let flanks = [("left", &m.pitch.left), ("right", &m.pitch.right)];
    let extent = flanks
        .iter()
        .flat_map(|(_, p)| {
            let c = cumulative_mid(p);
            p.single_um
                .iter()
                .map(|v| v.abs())
                .chain(p.cumulative_um.iter().map(move |v| (v - c).abs()))
                .collect::<Vec<_>>()
        })
        .fold(fpt_um.max(fpt_total_um / 2.0), f64::max);
    let panel_div = (PITCH_H / 2.0 / DIV_PX - 0.5).floor();
    let um_div = um_per_division(extent, panel_div);
    let heading = format!(
        "Pitch at the measuring diameter: fpi bars against ±fpT = {fpt_um} µm, Fpi curve (centred) against a band FpT = {fpt_total_um} µm wide, class {}; 1 division = {um_div} µm",
        class.number()
    );
    let mut g =
        Group::new()
            .set("class", "pitch-row")
            .add(label(heading, MARGIN, top + 12.0, 12.0));
    let width = (PAGE_W - 3.0 * MARGIN) / 2.0;
    for (k, (name, p)) in flanks.iter().enumerate() {
        let chart = PitchChart {
            x0: MARGIN + k as f64 * (width + MARGIN),
            y0: top + 40.0,
            width,
            px_per_um: DIV_PX / um_div,
        };
        g = g.add(chart.draw(name, p, fpt_um, fpt_total_um));
    }
    (g, 2.0 * PITCH_H + 90.0)
}

/// The middle of the cumulative curve's range, µm.
pub(crate) fn cumulative_mid(p: &PitchDeviations) -> f64 {
    let max = p
        .cumulative_um
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let min = p
        .cumulative_um
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    if max.is_finite() {
        (max + min) / 2.0
    } else {
        0.0
    }
}

/// Where a pitch chart stands: two panels, fpi above, Fpi below.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PitchChart {
    pub(crate) x0: f64,
    pub(crate) y0: f64,
    pub(crate) width: f64,
    /// px per µm, up positive.
    pub(crate) px_per_um: f64,
}

impl PitchChart {
    /// The zero line of panel `k` (0: fpi, 1: Fpi), px.
    pub(crate) fn zero_y(&self, k: usize) -> f64 {
        self.y0 + PITCH_H * (k as f64 + 0.5)
    }

    /// The centre x of tooth `i` of `z`, px.
    pub(crate) fn x_of(&self, i: usize, z: usize) -> f64 {
        self.x0 + self.width * (i as f64 + 0.5) / z as f64
    }

    fn draw(&self, name: &str, p: &PitchDeviations, fpt_um: f64, fpt_total_um: f64) -> Group {
        let z = p.single_um.len();
        let mut g = Group::new().set("class", "pitch-chart");
        for k in 0..2 {
            let top = self.y0 + PITCH_H * k as f64;
            g = g
                .add(
                    Rectangle::new()
                        .set("x", self.x0)
                        .set("y", top)
                        .set("width", self.width)
                        .set("height", PITCH_H)
                        .set("fill", "none")
                        .set("stroke", "#999")
                        .set("stroke-width", 0.5),
                )
                .add(
                    hline(self.x0, self.x0 + self.width, self.zero_y(k), "#555", 0.5)
                        .set("class", "zero"),
                );
        }
        let lines = [
            (0, fpt_um),
            (0, -fpt_um),
            (1, fpt_total_um / 2.0),
            (1, -fpt_total_um / 2.0),
        ];
        for (k, v) in lines {
            let y = self.zero_y(k) - v * self.px_per_um;
            g = g.add(hline(self.x0, self.x0 + self.width, y, "#c00", 1.0).set("class", "band"));
        }
        let bar = 0.6 * self.width / z.max(1) as f64;
        for (i, v) in p.single_um.iter().enumerate() {
            let (y, h) = (self.zero_y(0), v * self.px_per_um);
            g = g.add(
                Rectangle::new()
                    .set("class", "bar")
                    .set("x", self.x_of(i, z) - bar / 2.0)
                    .set("y", y - h.max(0.0))
                    .set("width", bar)
                    .set("height", h.abs())
                    .set("fill", "#6baed6"),
            );
        }
        let c = cumulative_mid(p);
        let points: Vec<(f64, f64)> = p
            .cumulative_um
            .iter()
            .enumerate()
            .map(|(i, v)| (self.x_of(i, z), self.zero_y(1) - (v - c) * self.px_per_um))
            .collect();
        g = g.add(
            Polyline::new()
                .set("class", "cumulative")
                .set("points", points)
                .set("fill", "none")
                .set("stroke", "#08519c")
                .set("stroke-width", 1.0),
        );
        g.add(label(
            format!(
                "{name} flanks: fp {:.1} µm (bars, tooth 1 at the left), Fp {:.1} µm (curve)",
                p.single_max_um, p.cumulative_total_um
            ),
            self.x0,
            self.y0 - 4.0,
            11.0,
        ))
    }
}

/// `v` to one decimal, without a minus on a value that rounds to zero.
fn one_decimal(v: f64) -> String {
    if v.abs() < 0.05 {
        "0.0".to_string()
    } else {
        format!("{v:.1}")
    }
}

pub(crate) fn label(text: String, x: f64, y: f64, size: f64) -> Text {
    Text::new(text)
        .set("x", x)
        .set("y", y)
        .set("font-size", size)
        .set("font-family", "sans-serif")
}

fn vline(x: f64, y1: f64, y2: f64, colour: &'static str, width: f64) -> Line {
    Line::new()
        .set("x1", x)
        .set("y1", y1)
        .set("x2", x)
        .set("y2", y2)
        .set("stroke", colour)
        .set("stroke-width", width)
}

fn hline(x1: f64, x2: f64, y: f64, colour: &'static str, width: f64) -> Line {
    Line::new()
        .set("x1", x1)
        .set("y1", y)
        .set("x2", x2)
        .set("y2", y)
        .set("stroke", colour)
        .set("stroke-width", width)
}

mod tooth;

use tooth::tooth_sections;
#[cfg(test)]
use tooth::{magnification, wrap, DesignTooth};

#[cfg(test)]
#[path = "picture_simulation_tests.rs"]
mod tests;
