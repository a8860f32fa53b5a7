//! The picture of a hobbing job (SVG): the set-up and the hob's path in the
//! X–Z plane of the machine-neutral frame (`docs/hobbing.md` §1), seen along
//! +Y: Z up from the table plane, X to the right, the centre distance from
//! the table axis to the hob centre. Millimetres are the SVG's user units
//! (SVG's y is −Z).
//!
//! Drawn from the model alone: the table, the fixture up to the gear's lower
//! face and the tailstock of the machine's envelope (§5); each unit's blank
//! (its tip radius over its face width, a cone's taper included); the hob
//! centre's path of every cut, rapid moves dashed and feed moves solid, with
//! the approach from A and the return to A as the programs make them
//! (radially first, §4); the finishing cut's positions A–E marked and
//! labelled with their X and Z; the hob's outline at C (its tip cylinder
//! tilted by the swivel η, projected on the plane); and, to the right on
//! the same heights, the view along X, where the hob is a rectangle of its
//! tip diameter and length turned by η over the blank.
//!
//! Every text is a number or goes through the `svg` crate's text node,
//! which escapes it: a part number or a unit's name is never markup. No
//! data goes into an attribute (the crate does not escape quotes there).

use gearcam_proto::{HobData, Kinematics, LargeEnd, MachiningModel, MoveKind, Position};
use svg::node::element::path::Data;
use svg::node::element::{Circle, Group, Line, Path, Text};
use svg::Document;

/// A point of the X–Z plane: X the centre distance, Z the height above the
/// table plane, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Xz {
    /// X, mm.
    pub x_mm: f64,
    /// Z, mm.
    pub z_mm: f64,
}

impl Xz {
    fn of(p: Position) -> Xz {
        Xz {
            x_mm: p.x_mm,
            z_mm: p.z_mm,
        }
    }

    /// The SVG point (y is −Z).
    fn svg(self) -> (f64, f64) {
        (self.x_mm, -self.z_mm)
    }
}

/// One straight piece of the hob centre's path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start.
    pub from: Xz,
    /// End.
    pub to: Xz,
    /// True for a rapid move (drawn dashed), false for a feed (solid).
    pub rapid: bool,
    /// True for a cut before the finishing one (drawn lighter).
    pub rough: bool,
}

/// One gear unit as drawn: its blank, hob and kinematics.
#[derive(Debug, Clone)]
pub struct Unit<'a> {
    /// The unit's name (`blank` for a job of one gear).
    pub name: String,
    /// Height of the unit's lower face above the table plane, mm.
    pub lower_mm: f64,
    /// Face width, mm.
    pub face_width_mm: f64,
    /// Blank radius at the lower face, mm.
    pub lower_radius_mm: f64,
    /// Blank radius at the upper face, mm (smaller at a cone's small end).
    pub upper_radius_mm: f64,
    /// The unit's hob.
    pub hob: &'a HobData,
    /// The unit's kinematics.
    pub kinematics: &'a Kinematics,
}

impl Unit<'_> {
    fn upper_mm(&self) -> f64 {
        self.lower_mm + self.face_width_mm
    }

    /// The blank's outline, both sides of the table axis.
    pub fn outline(&self) -> Vec<Xz> {
        let (lo, hi) = (self.lower_mm, self.upper_mm());
        let (rl, ru) = (self.lower_radius_mm, self.upper_radius_mm);
        vec![
            Xz {
                x_mm: -rl,
                z_mm: lo,
            },
            Xz { x_mm: rl, z_mm: lo },
            Xz { x_mm: ru, z_mm: hi },
            Xz {
                x_mm: -ru,
                z_mm: hi,
            },
        ]
    }
}

/// The blank radii at the lower and upper face of a unit of face width `b`
/// and tip radius `r` (a cone's large end), mm.
fn radii(k: &Kinematics, r: f64, b: f64) -> (f64, f64) {
    match &k.cone {
        Some(c) => {
            let small = r - b * c.angle_deg.to_radians().tan();
            match c.large_end {
                LargeEnd::Bottom => (r, small),
                LargeEnd::Top => (small, r),
            }
        }
        None => (r, r),
    }
}

/// Every unit of the job in machining order: the job's gear alone, or each
/// unit of a multi-gear part at its offset above the first.
pub fn units(model: &MachiningModel) -> Vec<Unit<'_>> {
    let plan = &model.plan;
    let k = &model.model;
    if k.units.is_empty() {
        let b = plan.gear.face_width_mm;
        let (lower, upper) = radii(k, k.blank_od_mm / 2.0, b);
        return vec![Unit {
            name: "blank".into(),
            lower_mm: plan.gear.fixture_height_mm,
            face_width_mm: b,
            lower_radius_mm: lower,
            upper_radius_mm: upper,
            hob: &plan.hob,
            kinematics: k,
        }];
    }
    k.units
        .iter()
        .map(|u| {
            let b = u.gear.face_width_mm;
            let (lower, upper) = radii(&u.model, u.model.blank_od_mm / 2.0, b);
            Unit {
                name: u.name.clone(),
                lower_mm: plan.gear.fixture_height_mm + u.z_offset_mm,
                face_width_mm: b,
                lower_radius_mm: lower,
                upper_radius_mm: upper,
                hob: &u.hob,
                kinematics: &u.model,
            }
        })
        .collect()
}

/// Points on the circle through `from`, `via` and `to`, from `from`
/// (excluded) to `to` (included); `via` and `to` when the three are in line.
fn arc_points(from: Xz, via: Xz, to: Xz) -> Vec<Xz> {
    let (ax, az, bx, bz, cx, cz) = (from.x_mm, from.z_mm, via.x_mm, via.z_mm, to.x_mm, to.z_mm);
    let d = 2.0 * (ax * (bz - cz) + bx * (cz - az) + cx * (az - bz));
    if d.abs() < 1e-12 {
        return vec![via, to];
    }
    let sq = |x: f64, z: f64| x * x + z * z;
    let ux = (sq(ax, az) * (bz - cz) + sq(bx, bz) * (cz - az) + sq(cx, cz) * (az - bz)) / d;
    let uz = (sq(ax, az) * (cx - bx) + sq(bx, bz) * (ax - cx) + sq(cx, cz) * (bx - ax)) / d;
    let r = (ax - ux).hypot(az - uz);
    let angle = |x: f64, z: f64| (z - uz).atan2(x - ux);
    let tau = std::f64::consts::TAU;
    let (t0, t1, tv) = (angle(ax, az), angle(cx, cz), angle(bx, bz));
    // Counter-clockwise from t0, the sweep to `to` passes `via` or runs the
    // other way round.
    let ccw = |t: f64| (t - t0).rem_euclid(tau);
    let sweep = if ccw(tv) <= ccw(t1) {
        ccw(t1)
    } else {
        ccw(t1) - tau
    };
    let n = 32;
    (1..=n)
        .map(|i| {
            let t = t0 + sweep * f64::from(i) / f64::from(n);
            Xz {
                x_mm: ux + r * t.cos(),
                z_mm: uz + r * t.sin(),
            }
        })
        .collect()
}

/// The hob centre's path of a unit's cycle: from A down at A's X to B's
/// height and in to B; each cut's moves from B to E (an arc through its
/// intermediate point); to the next cut out at the current height to its
/// B's X, then to its B's height; after the last, radially out to A's X and
/// up to A (`docs/hobbing.md` §4). Moves of the shift axis alone and dwells
/// do not move in the plane.
pub fn path(k: &Kinematics) -> Vec<Segment> {
    let a = Xz::of(k.cuts.first().map_or(k.positions.A, |c| c.positions.A));
    let mut out = Vec::new();
    let mut at = a;
    let last = k.cuts.len().saturating_sub(1);
    let mut go = |to: Xz, rapid: bool, rough: bool, at: &mut Xz| {
        if to != *at {
            out.push(Segment {
                from: *at,
                to,
                rapid,
                rough,
            });
            *at = to;
        }
    };
    for (i, cut) in k.cuts.iter().enumerate() {
        let rough = i < last;
        let b = Xz::of(cut.positions.B);
        let turn = if i == 0 {
            Xz {
                x_mm: at.x_mm,
                z_mm: b.z_mm,
            }
        } else {
            Xz {
                x_mm: b.x_mm,
                z_mm: at.z_mm,
            }
        };
        go(turn, true, rough, &mut at);
        go(b, true, rough, &mut at);
        for m in &cut.moves {
            let to = Xz {
                x_mm: m.x_mm.unwrap_or(at.x_mm),
                z_mm: m.z_mm.unwrap_or(at.z_mm),
            };
            match (m.kind, m.via) {
                (MoveKind::Rapid, _) => go(to, true, rough, &mut at),
                (MoveKind::Feed, _) | (MoveKind::Arc, None) => go(to, false, rough, &mut at),
                (MoveKind::Arc, Some(via)) => {
                    for p in arc_points(at, Xz::of(via), to) {
                        go(p, false, rough, &mut at);
                    }
                }
                (MoveKind::Dwell, _) => {}
            }
        }
    }
    let out_at = Xz {
        x_mm: a.x_mm,
        z_mm: at.z_mm,
    };
    go(out_at, true, false, &mut at);
    go(a, true, false, &mut at);
    out
}

/// The outline of the hob's tip cylinder (radius `r`, length `len`) tilted
/// by `eta_deg` about X, centred at `c`, projected on the X–Z plane: at X
/// offset t a point of the cylinder lies up to (len/2)·|sin η| + √(r² − t²)·cos η
/// above or below the centre (the hob axis is (0, cos η, −sin η)).
pub fn hob_outline(c: Xz, r: f64, len: f64, eta_deg: f64) -> Vec<Xz> {
    let eta = eta_deg.to_radians();
    let reach = |t: f64| 0.5 * len * eta.sin().abs() + (r * r - t * t).max(0.0).sqrt() * eta.cos();
    let n = 48;
    let ts: Vec<f64> = (0..=n)
        .map(|i| -r + 2.0 * r * f64::from(i) / f64::from(n))
        .collect();
    let top = ts.iter().map(|&t| Xz {
        x_mm: c.x_mm + t,
        z_mm: c.z_mm + reach(t),
    });
    let bottom = ts.iter().rev().map(|&t| Xz {
        x_mm: c.x_mm + t,
        z_mm: c.z_mm - reach(t),
    });
    top.chain(bottom).collect()
}

/// A number of millimetres or degrees as the labels show it: at most three
/// decimals, no trailing zeros.
pub fn num(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// A closed polygon through `points`.
fn polygon(points: &[Xz], stroke: &str, fill: &str, width: f64) -> Path {
    let mut d = Data::new();
    for (i, p) in points.iter().enumerate() {
        d = if i == 0 {
            d.move_to(p.svg())
        } else {
            d.line_to(p.svg())
        };
    }
    Path::new()
        .set("d", d.close())
        .set("fill", fill)
        .set("stroke", stroke)
        .set("stroke-width", width)
}

/// A rectangle from (x0, z0) to (x1, z1).
fn rect(x0: f64, z0: f64, x1: f64, z1: f64) -> Vec<Xz> {
    vec![
        Xz { x_mm: x0, z_mm: z0 },
        Xz { x_mm: x1, z_mm: z0 },
        Xz { x_mm: x1, z_mm: z1 },
        Xz { x_mm: x0, z_mm: z1 },
    ]
}

/// A label at `at` (mm), left-aligned unless `anchor` says otherwise.
fn label(text: String, at: (f64, f64), size: f64, anchor: &'static str) -> Text {
    Text::new(text)
        .set("x", at.0)
        .set("y", at.1)
        .set("font-size", size)
        .set("font-family", "sans-serif")
        .set("text-anchor", anchor)
}

/// Colours of the units' paths, in machining order.
const COLOURS: [&str; 4] = ["#08519c", "#a63603", "#006d2c", "#54278f"];

/// The drawing's frame: the extent of what it shows and the sizes that
/// follow from it.
#[derive(Debug, Clone, Copy)]
struct Frame {
    x0: f64,
    x1: f64,
    z0: f64,
    z1: f64,
    /// Font size, mm.
    font: f64,
    /// Line width, mm.
    line: f64,
}

impl Frame {
    fn around(points: impl Iterator<Item = Xz>) -> Frame {
        let (mut x0, mut x1, mut z0, mut z1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in points {
            x0 = x0.min(p.x_mm);
            x1 = x1.max(p.x_mm);
            z0 = z0.min(p.z_mm);
            z1 = z1.max(p.z_mm);
        }
        let extent = (x1 - x0).max(z1 - z0).max(1.0);
        Frame {
            x0,
            x1,
            z0,
            z1,
            font: extent / 70.0,
            line: extent / 700.0,
        }
    }
}

/// The table, the fixture under the first unit and the tailstock over the
/// last, with their dimensions.
fn envelope(model: &MachiningModel, units: &[Unit<'_>], f: &Frame, top_mm: f64) -> Group {
    let env = &model.plan.machine.envelope;
    let gear = &model.plan.gear;
    let fixture_r = gear
        .fixture_diameter_mm
        .map_or(env.fixture_radius_mm, |d| d / 2.0);
    let h = units.first().map_or(gear.fixture_height_mm, |u| u.lower_mm);
    let table_depth = 4.0 * f.font;
    let (fs, w) = (f.font, f.line);
    let mut g = Group::new()
        .add(polygon(
            &rect(-env.table_radius_mm, -table_depth, env.table_radius_mm, 0.0),
            "#444",
            "#d9d9d9",
            w,
        ))
        .add(label(
            format!(
                "table r {} (Z 0: the table plane)",
                num(env.table_radius_mm)
            ),
            (-env.table_radius_mm + fs, table_depth - fs),
            fs,
            "start",
        ))
        .add(polygon(
            &rect(-fixture_r, 0.0, fixture_r, h),
            "#444",
            "#f0f0f0",
            w,
        ))
        .add(label(
            format!("fixture Ø{}, H {}", num(2.0 * fixture_r), num(h)),
            (-fixture_r - fs, -0.5 * h),
            fs,
            "end",
        ));
    if env.tailstock_radius_mm > 0.0 {
        let top = units.iter().map(Unit::upper_mm).fold(h, f64::max);
        let low = top + env.tailstock_gap_mm;
        let rt = env.tailstock_radius_mm;
        g = g
            .add(polygon(&rect(-rt, low, rt, top_mm), "#444", "#f0f0f0", w))
            .add(label(
                format!(
                    "tailstock Ø{}, {} above the top face",
                    num(2.0 * rt),
                    num(env.tailstock_gap_mm)
                ),
                (-rt - fs, -low - fs),
                fs,
                "end",
            ));
    }
    g
}

/// A unit's blank, its path (rapid dashed, feed solid), the finishing
/// cut's positions A–E marked and labelled (A only when `label_a`: units
/// share their start), and the hob's outline at C.
fn unit_drawing(u: &Unit<'_>, colour: &str, f: &Frame, label_a: bool) -> Group {
    let (fs, w) = (f.font, f.line);
    let k = u.kinematics;
    let mut g = Group::new()
        .add(polygon(&u.outline(), "black", "#fdd0a2", 2.0 * w))
        .add(label(
            format!(
                "{}: tip Ø{} × b {}, lower face Z {}",
                u.name,
                num(2.0 * u.lower_radius_mm.max(u.upper_radius_mm)),
                num(u.face_width_mm),
                num(u.lower_mm)
            ),
            (-u.upper_radius_mm, -u.upper_mm() - 0.5 * fs),
            fs,
            "start",
        ));
    for s in path(k) {
        let ((x1, y1), (x2, y2)) = (s.from.svg(), s.to.svg());
        let mut line = Line::new()
            .set("x1", x1)
            .set("y1", y1)
            .set("x2", x2)
            .set("y2", y2)
            .set("stroke", colour)
            .set("stroke-width", if s.rapid { w } else { 2.5 * w })
            .set("opacity", if s.rough { 0.45 } else { 1.0 });
        if s.rapid {
            line = line.set("stroke-dasharray", (6.0 * w, 4.0 * w));
        }
        g = g.add(line);
    }
    let c = Xz::of(k.positions.C);
    g = g.add(polygon(
        &hob_outline(c, u.hob.od_mm / 2.0, u.hob.length_mm, k.swivel_deg),
        colour,
        "none",
        w,
    ));
    g = g.add(label(
        format!(
            "hob Ø{} × {} at C, swivel η {}° (outline projected along Y)",
            num(u.hob.od_mm),
            num(u.hob.length_mm),
            num(k.swivel_deg)
        ),
        (c.x_mm + 0.5 * u.hob.od_mm + fs, -c.z_mm - u.hob.od_mm / 2.0),
        fs,
        "start",
    ));
    let p = &k.positions;
    // Where each label sits from its mark, and its alignment: D and E share
    // a height 5 mm apart, B and C another.
    let marks = [
        ("A", p.A, (1.0, -1.0), "start"),
        ("B", p.B, (1.0, -1.0), "start"),
        ("C", p.C, (-1.0, -1.0), "end"),
        ("D", p.D, (-1.0, 1.8), "end"),
        ("E", p.E, (1.0, 1.8), "start"),
    ];
    for (name, pos, (dx, dz), anchor) in marks {
        let (cx, cy) = Xz::of(pos).svg();
        g = g.add(
            Circle::new()
                .set("cx", cx)
                .set("cy", cy)
                .set("r", 3.0 * w)
                .set("fill", colour),
        );
        if name != "A" || label_a {
            g = g.add(label(
                format!("{name} X{} Z{}", num(pos.x_mm), num(pos.z_mm)),
                (cx + dx * fs * 0.6, cy + dz * fs * 0.6),
                fs,
                anchor,
            ));
        }
    }
    g
}

/// The view along X at each unit's C, placed with its Y axis at `y_axis_mm`
/// on the drawing's X: the blank as a rectangle of its tip diameter over its
/// face width and the hob as a rectangle of its tip diameter and length
/// turned by η (its axis (cos η, −sin η) in Y and Z). The blanks first, the
/// hobs over them, the labels on top.
fn side_view(units: &[Unit<'_>], y_axis_mm: f64, f: &Frame) -> Group {
    let (fs, w) = (f.font, f.line);
    let (mut blanks, mut hobs, mut labels) = (Group::new(), Group::new(), Group::new());
    let mut top = f64::MIN;
    for (i, u) in units.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let k = u.kinematics;
        let r = u.lower_radius_mm.max(u.upper_radius_mm);
        let c = k.positions.C;
        let (r0, half) = (u.hob.od_mm / 2.0, u.hob.length_mm / 2.0);
        // How high the turned hob reaches above its centre.
        let eta = k.swivel_deg.to_radians();
        top = top.max(c.z_mm + r0 * eta.cos() + half * eta.sin().abs());
        blanks = blanks.add(polygon(
            &rect(y_axis_mm - r, u.lower_mm, y_axis_mm + r, u.upper_mm()),
            "black",
            "#fdd0a2",
            2.0 * w,
        ));
        let hob = rect(y_axis_mm - half, c.z_mm - r0, y_axis_mm + half, c.z_mm + r0);
        hobs = hobs.add(polygon(&hob, colour, "none", w).set(
            "transform",
            format!("rotate({} {} {})", k.swivel_deg, y_axis_mm, -c.z_mm),
        ));
        labels = labels.add(label(
            format!(
                "{}: hob at C turned by η {}° (ΔH′ {} + safety {})",
                u.name,
                num(k.swivel_deg),
                num(k.clearance_mm),
                num(k.safety_mm)
            ),
            (y_axis_mm + half + fs, -c.z_mm),
            fs,
            "start",
        ));
    }
    Group::new()
        .add(label(
            "seen along X, from the hob towards the table axis (Y to the right)".into(),
            (y_axis_mm, -top - 1.5 * fs),
            fs,
            "middle",
        ))
        .add(blanks)
        .add(hobs)
        .add(labels)
}

/// The SVG picture of a hobbing job's model: set-up, path, positions, hob.
pub fn hobbing_svg(model: &MachiningModel) -> String {
    let units = units(model);
    let env = &model.plan.machine.envelope;
    // Everything the main view holds, for its frame.
    let mut points: Vec<Xz> = vec![
        Xz {
            x_mm: -env.table_radius_mm,
            z_mm: 0.0,
        },
        Xz {
            x_mm: env.table_radius_mm,
            z_mm: 0.0,
        },
    ];
    for u in &units {
        points.extend(u.outline());
        for s in path(u.kinematics) {
            points.push(s.from);
            points.push(s.to);
        }
        let c = Xz::of(u.kinematics.positions.C);
        points.extend(hob_outline(
            c,
            u.hob.od_mm / 2.0,
            u.hob.length_mm,
            u.kinematics.swivel_deg,
        ));
    }
    let main = Frame::around(points.into_iter());
    let f = Frame {
        z0: main.z0 - 5.0 * main.font,
        ..main
    };
    // The side view to the right, wide enough for the longest hob turned.
    let side_half = units
        .iter()
        .map(|u| {
            let r = u.lower_radius_mm.max(u.upper_radius_mm);
            r.max(0.5 * u.hob.length_mm + 0.5 * u.hob.od_mm)
        })
        .fold(0.0, f64::max);
    let y_axis = f.x1 + 20.0 * f.font + side_half;
    // Room for the side view's labels to its right.
    let (x0, x1) = (f.x0 - 22.0 * f.font, y_axis + side_half + 30.0 * f.font);
    let (z0, z1) = (f.z0 - 4.0 * f.font, f.z1 + 6.0 * f.font);
    let (width, height) = (x1 - x0, z1 - z0);
    let px = 1200.0;
    let part = &model.plan.request.spec.job.part_number;
    let mut doc = Document::new()
        .set("viewBox", (x0, -z1, width, height))
        .set("width", px)
        .set("height", (px * height / width).round())
        .add(
            Line::new()
                .set("x1", 0)
                .set("y1", -f.z0)
                .set("x2", 0)
                .set("y2", -f.z1)
                .set("stroke", "#777")
                .set("stroke-width", f.line)
                .set("stroke-dasharray", (12.0 * f.line, 3.0 * f.line, 2.0 * f.line, 3.0 * f.line)),
        )
        .add(envelope(model, &units, &f, f.z1))
        .add(label(
            format!("{part} · job {} · machine {}", model.job_id, model.plan.machine.id),
            (x0 + f.font, -z1 + 1.5 * f.font),
            1.2 * f.font,
            "start",
        ))
        .add(label(
            "X–Z plane seen along +Y: Z up from the table plane, X the centre distance; mm, degrees; the hob centre's path, rapid moves dashed, feed moves solid".into(),
            (x0 + f.font, -z1 + 3.0 * f.font),
            f.font,
            "start",
        ));
    for (i, u) in units.iter().enumerate() {
        let label_a = units[..i]
            .iter()
            .all(|v| v.kinematics.positions.A != u.kinematics.positions.A);
        doc = doc.add(unit_drawing(u, COLOURS[i % COLOURS.len()], &f, label_a));
    }
    doc.add(side_view(&units, y_axis, &f)).to_string()
}

#[cfg(test)]
#[path = "picture_hobbing_tests.rs"]
mod tests;
