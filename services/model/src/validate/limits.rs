//! Checks after the computation: the run-out against the machine's envelope,
//! units that collide, and every move against the machine's travel and
//! speed limits.

use super::*;
use gearcam_proto::{Code, MachineId, MachineLimits};

/// The hob's run-out below the gear must stay clear of the table and the
/// fixture: at the lowest hob centre Zl of the stroke, the tilted tip
/// cylinder reaches r·cos η + (length/2 + |shift|)·|sin η| below it (the
/// largest shift of any part), which must stay
/// above the table plane where the hob stands over the table; and the hob
/// comes as near as X − r to the table axis (the swivel turns it about X),
/// so a fixture at least that wide under the gear is hit. (The template
/// service's path check sweeps the sampled hob solid independently.)
pub(super) fn run_out(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    k: &Kinematics,
    cfg: &Config,
    prefix: &str,
) {
    let gear = &plan.gear;
    let env = &plan.machine.envelope;
    let r = plan.hob.od_mm / 2.0;
    let half = plan.hob.length_mm / 2.0;
    let eta = k.swivel_deg.to_radians();
    // A shifted hob stands off-centre along its own axis: its far end reaches
    // lower by the shift times sin η. Every part may be cut at any shift
    // position, so the largest one counts.
    let shift = k
        .shift
        .as_ref()
        .map_or(0.0, |s| s.start_mm.abs().max(s.end_mm.abs()))
        .max(
            k.cuts
                .iter()
                .flat_map(|c| c.moves.iter().filter_map(|m| m.y_mm))
                .fold(0.0, |a: f64, y| a.max(y.abs())),
        );
    let below = r * eta.cos() + (half + shift) * eta.sin().abs();
    let (mut low, mut x_low) = (f64::INFINITY, f64::INFINITY);
    for c in &k.cuts {
        for p in [c.positions.C, c.positions.D] {
            if p.z_mm < low {
                (low, x_low) = (p.z_mm, p.x_mm);
            }
        }
        for m in &c.moves {
            if let (Some(z), Some(x)) = (m.z_mm, m.x_mm) {
                if z < low {
                    (low, x_low) = (z, x);
                }
            }
        }
    }
    if !low.is_finite() {
        return;
    }
    let id = &plan.machine.id;
    let lowest = low - below;
    if lowest < -cfg.length_tolerance_mm && x_low - r < env.table_radius_mm {
        let need = gear.fixture_height_mm - lowest;
        errors.push(Stage::Model.error(
            Code::ENVELOPE_COLLISION,
            &format!("{prefix}gear.fixture_height_mm"),
            format!("≥ {} mm", num(need)),
            format!("{} mm", num(gear.fixture_height_mm)),
            format!(
                "Below the gear the hob runs out {} mm below its centre (tip radius {} mm, half its length {} mm, shifted up to {} mm, tilted {}°) and would reach {} mm into machine {id}'s table; raise the gear on a taller fixture or use a shorter hob.",
                num(below),
                num(r),
                num(half),
                num(shift),
                num(k.swivel_deg.abs()),
                num(-lowest)
            ),
        ));
    }
    let fixture_r = gear
        .fixture_diameter_mm
        .map_or(env.fixture_radius_mm, |d| d / 2.0);
    let nearest = x_low - r;
    // The fixture stands under the lowest unit only (a unit above runs out
    // over the unit below it, which `check_unit_collisions` covers).
    if prefix.is_empty()
        && low < gear.fixture_height_mm
        && fixture_r >= nearest - cfg.length_tolerance_mm
    {
        errors.push(Stage::Model.error(
            Code::ENVELOPE_COLLISION,
            &format!("{prefix}gear.fixture_diameter_mm"),
            format!("< {} mm", num(2.0 * nearest)),
            format!(
                "{} mm{}",
                num(2.0 * fixture_r),
                if gear.fixture_diameter_mm.is_none() {
                    format!(" (machine {id}'s default)")
                } else {
                    String::new()
                }
            ),
            format!(
                "Below the gear the hob comes within {} mm of the table axis; a fixture that wide under the gear is cut. Give gear.fixture_diameter_mm of the support actually used, narrower than the gear's root.",
                num(nearest)
            ),
        ));
    }
}

/// Multi-gear parts: while cutting one unit, the hob must stay clear of the
/// other units. For a neighbour of radius Rn, the hob (radius r, swivel γ) at
/// the unit's centre distance L overlaps it radially by hn = Rn + r − L; when
/// hn > 0 the hob centre must stay ΔH′(Rn, r, hn, γ) away from the
/// neighbour's face (the same clearance as the approach, docs/hobbing.md#4-the-cycle-positions-speeds-feeds), over the
/// unit's whole feed stroke.
pub(super) fn check_unit_collisions(errors: &mut Vec<JobError>, k: &Kinematics, cfg: &Config) {
    for (i, u) in k.units.iter().enumerate() {
        let stroke: Vec<f64> = u
            .model
            .cuts
            .iter()
            .flat_map(|c| [c.positions.C.z_mm, c.positions.D.z_mm])
            .collect();
        let lowest = stroke.iter().copied().fold(f64::INFINITY, f64::min);
        let highest = stroke.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let bottom = u.gear.fixture_height_mm;
        let top = bottom + u.gear.face_width_mm;
        for (_, n) in k.units.iter().enumerate().filter(|(j, _)| *j != i) {
            let r_n = n.model.blank_od_mm / 2.0;
            let overlap = r_n + u.hob.od_mm / 2.0 - u.model.centre_distance_mm;
            if !(overlap > 0.0) {
                continue;
            }
            let clear = crate::hobbing::Clearance {
                blank_od_mm: n.model.blank_od_mm,
                hob_od_mm: u.hob.od_mm,
                depth_mm: overlap,
                swivel_deg: u.model.swivel_deg,
                hob_length_mm: u.hob.length_mm,
            }
            .solve()
            .clearance_mm;
            let n_bottom = n.gear.fixture_height_mm;
            let n_top = n_bottom + n.gear.face_width_mm;
            let (bad, limit, got) = if n_top <= bottom + cfg.length_tolerance_mm {
                let min = n_top + clear;
                (
                    lowest < min - cfg.length_tolerance_mm,
                    format!("hob centre ≥ {} mm", num(min)),
                    lowest,
                )
            } else if n_bottom >= top - cfg.length_tolerance_mm {
                let max = n_bottom - clear;
                (
                    highest > max + cfg.length_tolerance_mm,
                    format!("hob centre ≤ {} mm", num(max)),
                    highest,
                )
            } else {
                continue; // overlapping units are reported by validation
            };
            if bad {
                errors.push(Stage::Model.error(
                    Code::UNIT_COLLISION,
                    &format!("units[{i}].model.positions"),
                    limit,
                    format!("hob centre at {} mm", num(got)),
                    format!(
                        "While cutting {} the hob would cut into {} (it needs {} mm of clearance from that unit's face); move the units apart with z_offset_mm or plan a run-out groove.",
                        u.name,
                        n.name,
                        num(clear)
                    ),
                ));
            }
        }
    }
}

/// Every limit of the machine for one unit of the plan (`prefix` names the
/// unit in the errors' fields): spindle speeds and feeds, the travel of
/// every position and move, then the run-out below the gear.
pub(super) fn unit_limits(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    k: &Kinematics,
    cfg: &Config,
    prefix: &str,
) {
    let mut check = LimitCheck {
        errors: &mut *errors,
        id: &plan.machine.id,
        prefix,
        tolerance_mm: cfg.length_tolerance_mm,
    };
    speed_limits(&mut check, &plan.machine.limits, k);
    travel_limits(errors, plan, k, cfg, prefix);
    run_out(errors, plan, k, cfg, prefix);
}

/// Reports values over the machine's limits for one unit (`prefix` names
/// it in the error's field).
struct LimitCheck<'a> {
    errors: &'a mut Vec<JobError>,
    id: &'a MachineId,
    prefix: &'a str,
    tolerance_mm: f64,
}

impl LimitCheck<'_> {
    /// Reports `v` (in `unit`) at `field` when its magnitude is over `max`
    /// (or not a number), saying what to do about it.
    fn over(&mut self, code: Code, field: &str, v: f64, max: f64, unit: &str, todo: &str) {
        let (prefix, id) = (self.prefix, self.id);
        if !(v.abs() <= max + self.tolerance_mm) {
            self.errors.push(Stage::Model.error(
                code,
                &format!("{prefix}{field}"),
                format!("≤ {} {unit}", num(max)),
                format!("{} {unit}", num(v)),
                format!(
                    "Machine {id} allows at most {} {unit} here; {todo}.",
                    num(max)
                ),
            ));
        }
    }
}

/// The hob and table spindle speeds, the axial feed and the swivel of the
/// unit; the table speed and axial feed of each rough cut; and the feed
/// rate of each radial (X only) feed move.
fn speed_limits(check: &mut LimitCheck<'_>, lim: &MachineLimits, k: &Kinematics) {
    check.over(
        Code::HOB_RPM_LIMIT,
        "model.hob_rpm",
        k.hob_rpm,
        lim.max_hob_rpm,
        "rpm",
        "lower process.cutting_speed_m_min or use a hob of larger diameter",
    );
    check.over(
        Code::TABLE_RPM_LIMIT,
        "model.table_rpm",
        k.table_rpm,
        lim.max_table_rpm,
        "rpm",
        "lower process.cutting_speed_m_min or use a hob with fewer starts",
    );
    check.over(
        Code::AXIAL_FEED_LIMIT,
        "model.axial_feed_mm_min",
        k.axial_feed_mm_min,
        lim.max_axial_feed_mm_min,
        "mm/min",
        "lower process.feed_mm_per_rev or the cutting speed",
    );
    check.over(
        Code::SWIVEL_LIMIT,
        "model.swivel_deg",
        k.swivel_deg,
        lim.max_swivel_deg,
        "°",
        "use a hob of the same hand as the gear helix or another machine",
    );
    for (i, c) in k.cuts.iter().enumerate().filter(|(_, c)| !c.finish) {
        check.over(
            Code::TABLE_RPM_LIMIT,
            &format!("model.cuts[{i}].table_rpm"),
            c.table_rpm,
            lim.max_table_rpm,
            "rpm",
            "lower process.cutting_speed_m_min or use a hob with fewer starts",
        );
        check.over(
            Code::AXIAL_FEED_LIMIT,
            &format!("model.cuts[{i}].axial_feed_mm_min"),
            c.axial_feed_mm_min,
            lim.max_axial_feed_mm_min,
            "mm/min",
            "lower process.feed_mm_per_rev or the cutting speed",
        );
    }
    for (i, c) in k.cuts.iter().enumerate() {
        for (j, m) in c
            .moves
            .iter()
            .enumerate()
            .filter(|(_, m)| m.kind != gearcam_proto::MoveKind::Rapid)
        {
            if !(m.x_mm.is_some() && m.z_mm.is_none()) {
                continue;
            }
            let rate = m.feed_mm_min;
            check.over(
                Code::FEED_RATE_LIMIT,
                &format!("model.cuts[{i}].moves[{j}].feed_mm_min"),
                rate,
                lim.max_axial_feed_mm_min,
                "mm/min",
                "lower the radial feed per revolution or the cutting speed",
            );
        }
    }
}

/// The travel of the unit's positions, of each cut's positions and of the
/// end of each move.
fn travel_limits(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    k: &Kinematics,
    cfg: &Config,
    prefix: &str,
) {
    let p = &k.positions;
    for (name, pos) in [("A", p.A), ("B", p.B), ("C", p.C), ("D", p.D), ("E", p.E)] {
        check_travel(
            errors,
            plan,
            &|| format!("{prefix}model.positions.{name}"),
            name,
            pos,
            cfg,
        );
    }
    for (i, c) in k.cuts.iter().enumerate() {
        let q = &c.positions;
        for (name, pos) in [("B", q.B), ("C", q.C), ("D", q.D), ("E", q.E)] {
            check_travel(
                errors,
                plan,
                &|| format!("{prefix}model.cuts[{i}].positions.{name}"),
                name,
                pos,
                cfg,
            );
        }
        let mut at = q.B;
        for (j, m) in c.moves.iter().enumerate() {
            at = move_end(at, m);
            check_travel(
                errors,
                plan,
                &|| format!("{prefix}model.cuts[{i}].moves[{j}]"),
                "move",
                at,
                cfg,
            );
        }
    }
}

pub(super) fn move_end(from: Position, m: &Move) -> Position {
    Position {
        x_mm: m.x_mm.unwrap_or(from.x_mm),
        z_mm: m.z_mm.unwrap_or(from.z_mm),
    }
}

pub(super) fn check_travel(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    field: &dyn Fn() -> String,
    name: &str,
    pos: Position,
    cfg: &Config,
) {
    let lim = &plan.machine.limits;
    for (axis, v, [lo, hi]) in [("x", pos.x_mm, lim.x_mm), ("z", pos.z_mm, lim.z_mm)] {
        if v >= lo - cfg.length_tolerance_mm && v <= hi + cfg.length_tolerance_mm {
            continue;
        }
        let todo = if name == "A" {
            "correct the machine's home position in its profile"
        } else if axis == "x" {
            "check the blank and hob diameters, gear.od_correction_mm and the retract and exit distances"
        } else {
            "check gear.fixture_height_mm, the face width and the safety distance"
        };
        // A duplicate of an already reported value (same axis and value) is noise.
        let got = format!("{} mm", num(v));
        // Cut positions and moves repeat the top-level positions; report a
        // value outside the travel once.
        let field = field();
        if field.contains("cuts[")
            && errors.iter().any(|e| {
                e.code == Code::POSITION_TRAVEL_LIMIT
                    && e.got == got
                    && e.field.ends_with(&format!(".{axis}_mm"))
            })
        {
            continue;
        }
        errors.push(Stage::Model.error(
            Code::POSITION_TRAVEL_LIMIT,
            &format!("{field}.{axis}_mm"),
            format!("{} to {} mm", num(lo), num(hi)),
            got,
            format!(
                "Position {name} lies outside machine {}'s {} travel; {todo}.",
                plan.machine.id,
                axis.to_uppercase()
            ),
        ));
    }
}
