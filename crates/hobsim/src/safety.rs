//! Safety and completeness findings from the same run that cuts the gear.
//!
//! [`check`] walks the [`Timeline`] the cut used and reports, as typed
//! [`SafetyFinding`]s with the program line:
//!
//! - the hob's tip cylinder entering the blank's envelope during a rapid
//!   move ([`SafetyKind::RapidContact`]);
//! - the hob turning inside the blank's envelope while no coupling is on
//!   ([`SafetyKind::CutDecoupled`]), or coupled with a ratio other than the
//!   gear's s_h·z0/z ([`SafetyKind::CutWrongRatio`]);
//! - the hob meeting the table, the fixture or the tailstock on any move
//!   ([`SafetyKind::FixtureContact`]);
//! - the coupled feed not reaching the plunge depth X = r_f + r_a0
//!   ([`SafetyKind::DepthNotReached`]) or not covering the face width and
//!   the generating zone's run-out at full depth
//!   ([`SafetyKind::FaceWidthNotCovered`]);
//! - a shift Y during a coupled cut without the table turn it needs
//!   ([`SafetyKind::UncompensatedShift`]);
//! - a unit coupled again after it cut without synchronised positions
//!   ([`SafetyKind::UnsynchronisedCoupling`]).
//!
//! The contact geometry is in `contact`, the process rules in `process`;
//! `docs/simulation.md` §8 derives each rule.

use gearcam_proto::MachiningModel;

use crate::hob::Hob;
use crate::kinematics::Timeline;

mod contact;
mod process;

pub use contact::{Cylinder, SAMPLE_MM};
pub use process::{DEPTH_TOL_MM, SHIFT_TOL_MM};

/// What a finding is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SafetyKind {
    /// The hob enters the blank's envelope during a rapid move.
    RapidContact,
    /// The hob turns inside the blank's envelope with the gearbox off.
    CutDecoupled,
    /// The hob cuts coupled, but not in the gear's ratio s_h·z0/z.
    CutWrongRatio,
    /// The hob meets the table, the fixture or the tailstock.
    FixtureContact,
    /// The coupled feed does not reach the plunge depth.
    DepthNotReached,
    /// The coupled feed at full depth does not cover the face width.
    FaceWidthNotCovered,
    /// A shift during a coupled cut without its table turn.
    UncompensatedShift,
    /// A unit coupled again after it cut, with an unknown phase.
    UnsynchronisedCoupling,
}

/// One finding: its kind, the program line (of the move, or the coupling),
/// what happens and why it matters.
#[derive(Debug, Clone, PartialEq)]
pub struct SafetyFinding {
    /// The kind.
    pub kind: SafetyKind,
    /// Program line (0 for a hand-built timeline).
    pub line: u32,
    /// What happens, with numbers.
    pub what: String,
    /// Why it matters.
    pub why: String,
}

/// The blank as the safety check sees it: its envelope (a cylinder of the
/// outer radius over the face width) and the gear the cut must make.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlankGeometry {
    /// Outer radius of the blank, mm (a cone's at the lower face).
    pub outer_radius_mm: f64,
    /// Lower face, mm above the table plane.
    pub z_lo_mm: f64,
    /// Upper face, mm.
    pub z_hi_mm: f64,
    /// Root radius the cut must reach, mm (a cone's at the lower face).
    pub root_radius_mm: f64,
    /// How much the outer and root radii grow for every mm up (a conical
    /// gear's X per Z, −tan δ when its large end is at the bottom), 0 for
    /// a cylindrical gear: the hob following the cone stands at full depth
    /// all along it, and the envelope is the cone.
    pub taper: f64,
    /// Number of teeth.
    pub teeth: u32,
    /// How much further out the hob stands in the middle of the face than
    /// at the faces by design (a crowned gear's Cb), mm: a feed that high
    /// is still at full depth.
    pub crowning_mm: f64,
    /// A worm wheel's throat plane (the hob centre's Z at full depth), mm:
    /// the wheel is cut there, not along the face width.
    pub throat_z_mm: Option<f64>,
}

impl BlankGeometry {
    /// The blank of a model's (first) gear: blank OD, fixture height and face
    /// width of the gear, df/2.
    pub fn of_model(model: &MachiningModel) -> BlankGeometry {
        let g = &model.plan.gear;
        let (taper, large_end_mm) = cone_of(model);
        // How much larger the radii are at the lower face than at the
        // large end (0 but for a cone large at the top).
        let lower = taper * (g.fixture_height_mm - large_end_mm);
        BlankGeometry {
            outer_radius_mm: model.model.blank_od_mm / 2.0 + lower,
            z_lo_mm: g.fixture_height_mm,
            z_hi_mm: g.fixture_height_mm + g.face_width_mm,
            root_radius_mm: model.geometry.df_mm / 2.0 + lower,
            taper,
            teeth: g.teeth,
            crowning_mm: model.model.crowning.as_ref().map_or(0.0, |c| c.amount_mm),
            throat_z_mm: model.model.worm.as_ref().map(|w| w.throat_z_mm),
        }
    }

    /// The envelope: a cylinder, or a cone's frustum.
    pub fn envelope(&self) -> Cylinder {
        Cylinder {
            radius_mm: self.outer_radius_mm,
            z_lo_mm: self.z_lo_mm,
            z_hi_mm: self.z_hi_mm,
            taper: self.taper,
        }
    }
}

/// A model's cone as the simulation uses it: the radius change per mm up
/// of the blank, the root and the hob (X per Z; 0 without a cone) and the
/// height of the face where the blank's outer diameter and the gear's
/// drawing hold (the large end; the lower face without a cone).
pub fn cone_of(model: &MachiningModel) -> (f64, f64) {
    let g = &model.plan.gear;
    match &model.model.cone {
        Some(c) if c.large_end == gearcam_proto::LargeEnd::Top => {
            (c.x_per_z, g.fixture_height_mm + g.face_width_mm)
        }
        Some(c) => (c.x_per_z, g.fixture_height_mm),
        None => (0.0, g.fixture_height_mm),
    }
}

/// The machine's obstacles: named solids of revolution about the table axis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fixtures {
    /// Name and solid of each.
    pub obstacles: Vec<(String, Cylinder)>,
}

impl Fixtures {
    /// The table (radius `table_radius_mm`, below the table plane), the
    /// fixture (the gear's fixture diameter or the machine's fixture radius,
    /// from the table plane up to the blank) and the tailstock (from
    /// `tailstock_gap_mm` above the blank up), from the model's machine
    /// envelope; an obstacle of radius 0 is left out.
    pub fn of_model(model: &MachiningModel, blank: &BlankGeometry) -> Fixtures {
        let env = &model.plan.machine.envelope;
        let fixture_r = model
            .plan
            .gear
            .fixture_diameter_mm
            .map_or(env.fixture_radius_mm, |d| d / 2.0);
        let all = [
            ("the table", env.table_radius_mm, f64::NEG_INFINITY, 0.0),
            ("the fixture", fixture_r, 0.0, blank.z_lo_mm),
            (
                "the tailstock",
                env.tailstock_radius_mm,
                blank.z_hi_mm + env.tailstock_gap_mm,
                f64::INFINITY,
            ),
        ];
        Fixtures {
            obstacles: all
                .iter()
                .filter(|(_, r, lo, hi)| *r > 0.0 && lo < hi)
                .map(|&(n, r, lo, hi)| {
                    (
                        n.to_string(),
                        Cylinder {
                            radius_mm: r,
                            z_lo_mm: lo,
                            z_hi_mm: hi,
                            taper: 0.0,
                        },
                    )
                })
                .collect(),
        }
    }
}

/// Penetration ignored, mm.
pub const PEN_TOL_MM: f64 = 0.002;

/// Every finding of the run, sorted by line.
pub fn check(
    timeline: &Timeline,
    hob: &Hob,
    blank: &BlankGeometry,
    fixtures: &Fixtures,
) -> Vec<SafetyFinding> {
    let mounted = vec![0; timeline.segments().len()];
    check_part(timeline, &[(None, *hob, *blank)], &mounted, fixtures)
}

/// A gear of the part as the safety rules see it: its name on a part of
/// several gears, its hob and its blank.
pub type UnitSetup = (Option<String>, Hob, BlankGeometry);

/// Every finding of the run of a part of several gears, sorted by line:
/// `units` holds each gear's name, hob and blank, `mounted[i]` the unit
/// whose hob segment `i` is made with. Every blank is checked against the
/// hob mounted at each move (a rapid into any gear is a crash; a turning
/// hob in a blank must be coupled in that gear's ratio); depth, face width
/// and shifts of each gear against the moves of its own hob, named by the
/// gear; the fixtures against every move. A move followed in pieces (an
/// arc) gives each finding once.
pub fn check_part(
    timeline: &Timeline,
    units: &[UnitSetup],
    mounted: &[usize],
    fixtures: &Fixtures,
) -> Vec<SafetyFinding> {
    let mut out = Vec::new();
    for (u, (name, hob, blank)) in units.iter().enumerate() {
        let blank_name = name
            .as_ref()
            .map_or("the blank".to_string(), |n| format!("the blank of \"{n}\""));
        blank_contacts(timeline, units, mounted, (blank, &blank_name), &mut out);
        let mine = moves_with(mounted, u);
        let before = out.len();
        process::depth_and_face(timeline, hob, blank, &mine, &mut out);
        process::shifts(timeline, hob, blank, &mine, &mut out);
        if let Some(n) = name {
            for f in &mut out[before..] {
                f.what = format!("gear \"{n}\": {}", f.what);
            }
        }
    }
    fixture_contacts(timeline, units, mounted, fixtures, &mut out);
    process::couplings(timeline, &mut out);
    out.sort_by_key(|f| f.line);
    let mut seen = std::collections::HashSet::new();
    out.retain(|f| seen.insert((f.kind, f.line, f.why.clone())));
    out
}

/// The hob as the contact walk samples it.
fn solid(hob: &Hob) -> contact::HobSolid {
    contact::HobSolid {
        radius_mm: hob.tip_radius_mm,
        length_mm: hob.length_mm,
    }
}

/// Which segments are made with unit `unit`'s hob, given the unit mounted
/// at each.
pub(crate) fn moves_with(mounted: &[usize], unit: usize) -> Vec<bool> {
    mounted.iter().map(|&m| m == unit).collect()
}

/// Rapid contact, cutting decoupled or in a wrong ratio, with the blank
/// `name`d, by the hob mounted at each move.
fn blank_contacts(
    tl: &Timeline,
    units: &[UnitSetup],
    mounted: &[usize],
    (blank, name): (&BlankGeometry, &str),
    out: &mut Vec<SafetyFinding>,
) {
    let env = blank.envelope();
    for (i, s) in tl.segments().iter().enumerate() {
        let hob = &units[mounted[i]].1;
        let want = hob.hand * f64::from(hob.starts) / f64::from(blank.teeth.max(1));
        let turning = s.hob_rev_s != 0.0 && s.t1_s > s.t0_s;
        let wrong_ratio = s.gearbox.filter(|g| (g.c_per_b - want).abs() > 1e-9);
        let kind = if !s.feed && !dwell(s) {
            if blank.throat_z_mm.is_some() && retraces_its_feed(tl, i) {
                continue;
            }
            SafetyKind::RapidContact
        } else if turning && s.gearbox.is_none() {
            SafetyKind::CutDecoupled
        } else if turning && wrong_ratio.is_some() {
            SafetyKind::CutWrongRatio
        } else {
            continue;
        };
        let Some(c) = contact::along(tl, i, solid(hob), &env, PEN_TOL_MM) else {
            continue;
        };
        let (what, why) = match kind {
            SafetyKind::RapidContact => (
                format!("the hob's tip cylinder enters {name} {:.3} mm during a rapid move (X {:.3}, Z {:.3})", c.depth_mm, c.pose.axes.x_mm, c.pose.axes.z_mm),
                format!("a rapid move into {name} crashes the hob"),
            ),
            SafetyKind::CutDecoupled => (
                format!("the hob turns {:.3} mm inside the envelope of {name} with the gearbox off (X {:.3}, Z {:.3})", c.depth_mm, c.pose.axes.x_mm, c.pose.axes.z_mm),
                "without the coupling the table does not follow the hob: the teeth are cut away".to_string(),
            ),
            _ => (
                format!(
                    "the hob cuts {name} {:.3} mm deep coupled at C/B {:.6}, the gear needs s_h·z0/z = {want:.6}",
                    c.depth_mm,
                    wrong_ratio.map_or(0.0, |g| g.c_per_b)
                ),
                "the table does not turn in the gear's ratio: the gaps do not index".to_string(),
            ),
        };
        out.push(SafetyFinding {
            kind,
            line: s.line,
            what,
            why,
        });
    }
}

/// The hob mounted at each move against the table, fixture and tailstock.
fn fixture_contacts(
    tl: &Timeline,
    units: &[UnitSetup],
    mounted: &[usize],
    fixtures: &Fixtures,
    out: &mut Vec<SafetyFinding>,
) {
    for (i, s) in tl.segments().iter().enumerate() {
        let hob = &units[mounted[i]].1;
        for (name, ob) in &fixtures.obstacles {
            if let Some(c) = contact::along(tl, i, solid(hob), ob, PEN_TOL_MM) {
                out.push(SafetyFinding {
                    kind: SafetyKind::FixtureContact,
                    line: s.line,
                    what: format!(
                        "the hob enters {name} {:.3} mm (X {:.3}, Z {:.3})",
                        c.depth_mm, c.pose.axes.x_mm, c.pose.axes.z_mm
                    ),
                    why: format!("the hob meets {name}: a collision"),
                });
            }
        }
    }
}

/// A dwell: no motion.
fn dwell(s: &crate::kinematics::Segment) -> bool {
    s.from == s.to
}

/// Hob turns per millimetre of feed below which a feed is not taken to
/// have swept every hob angle at each depth.
const RETRACE_TURNS_PER_MM: f64 = 10.0;

/// True when rapid segment `i` runs straight back along the coupled feed
/// before it (dwells between them aside), no further than that feed came:
/// a worm wheel's radial retract out of the gaps it has just cut. At every
/// point of the way back the hob stands where the feed passed it, and with
/// the table following the hob in the same gearbox, at the same swivel and
/// with no extra table turn between, the hob–wheel geometry there depends
/// on the hob angle alone, all of which the feed swept at that depth (at
/// least [`RETRACE_TURNS_PER_MM`] turns per millimetre): the way back
/// removes nothing but what the feed left between its turns.
fn retraces_its_feed(tl: &Timeline, i: usize) -> bool {
    let segs = tl.segments();
    let s = &segs[i];
    let same = |p: &crate::kinematics::Segment| {
        p.gearbox.is_some()
            && p.gearbox == s.gearbox
            && p.eta_rad == s.eta_rad
            && p.hob_rev_s == s.hob_rev_s
            && p.c_extra_rad == 0.0
    };
    if s.hob_rev_s == 0.0 || s.c_extra_rad != 0.0 {
        return false;
    }
    let mut before = segs[..i].iter().rev();
    let Some(feed) = before.by_ref().find(|p| !dwell(p) || !same(p)) else {
        return false;
    };
    if !(same(feed) && feed.feed && feed.to == s.from) {
        return false;
    }
    let d = |a: &crate::kinematics::Axes, b: &crate::kinematics::Axes| {
        [b.x_mm - a.x_mm, b.y_mm - a.y_mm, b.z_mm - a.z_mm]
    };
    let (back, fed) = (d(&s.from, &s.to), d(&feed.from, &feed.to));
    let dot: f64 = back.iter().zip(&fed).map(|(a, b)| a * b).sum();
    let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let (nb, nf) = (norm(&back), norm(&fed));
    let turns_per_mm = feed.hob_rev_s.abs() * (feed.t1_s - feed.t0_s) / nf.max(1e-12);
    // Opposite directions within 10⁻⁹ rad², no longer than the feed.
    nb > 0.0
        && nf > 0.0
        && dot < 0.0
        && 1.0 + dot / (nb * nf) < 1e-9
        && nb <= nf + 1e-9
        && turns_per_mm >= RETRACE_TURNS_PER_MM
}
