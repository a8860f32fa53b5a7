//! Checks against the machine profile before the computation: its settings,
//! its limits, the hob's diameter and the blank's window.

use super::*;
use gearcam_proto::Code;

pub(super) fn check_machine_settings(r: &mut Report, plan: &ProcessPlan) -> bool {
    let before = r.errors.len();
    let s = &plan.machine.settings;
    for (name, v) in [
        ("blank_od_below_mm", s.blank_od_below_mm),
        ("blank_od_above_mm", s.blank_od_above_mm),
        ("depth_allowance_mm", s.depth_allowance_mm),
        ("retract_mm", s.retract_mm),
        ("exit_mm", s.exit_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            r.error(
                Code::MACHINE_SETTING_RANGE,
                &format!("machine.settings.{name}"),
                "≥ 0 mm",
                format!("{} mm", num(v)),
                format!(
                    "Machine {}'s setting {name} must not be negative; correct the machine profile in the knowledge base.",
                    plan.machine.id
                ),
            );
        }
    }
    for (name, v) in [
        ("swivel_sign", s.swivel_sign),
        ("table_sign", s.table_sign),
        ("hob_sign", s.hob_sign),
        ("shift_sign", s.shift_sign),
    ] {
        if v != 1.0 && v != -1.0 {
            r.error(
                Code::MACHINE_SETTING_RANGE,
                &format!("machine.settings.{name}"),
                "1 or -1",
                num(v),
                format!(
                    "Machine {}'s {name} is the sense of that axis against the neutral frame (docs/hobbing.md), 1 or -1; correct the machine profile in the knowledge base.",
                    plan.machine.id
                ),
            );
        }
    }
    if !s.swivel_offset_deg.is_finite() {
        r.error(
            Code::MACHINE_SETTING_RANGE,
            "machine.settings.swivel_offset_deg",
            "a finite angle",
            num(s.swivel_offset_deg),
            "The swivel offset is the swivel axis reading with the hob parallel to the gear's end face; correct the machine profile.".to_string(),
        );
    }
    let env = &plan.machine.envelope;
    for (name, v) in [
        ("table_radius_mm", env.table_radius_mm),
        ("fixture_radius_mm", env.fixture_radius_mm),
        ("tailstock_radius_mm", env.tailstock_radius_mm),
        ("tailstock_gap_mm", env.tailstock_gap_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            r.error(
                Code::MACHINE_SETTING_RANGE,
                &format!("machine.envelope.{name}"),
                "≥ 0 mm",
                format!("{} mm", num(v)),
                format!(
                    "Machine {}'s envelope (table, fixture, tailstock) keeps the hob off them; correct the machine profile.",
                    plan.machine.id
                ),
            );
        }
    }
    if let Some(d) = plan.gear.fixture_diameter_mm {
        if !(d >= 0.0 && d.is_finite()) {
            r.error(
                Code::MACHINE_SETTING_RANGE,
                "gear.fixture_diameter_mm",
                "≥ 0 mm",
                format!("{} mm", num(d)),
                "The fixture diameter is the support under the gear's lower face; give it in mm or leave it out for the machine's.".to_string(),
            );
        }
    }
    let p = plan.machine.parameters;
    let slots = gearcam_proto::ParameterBlock::SLOTS;
    let (field, first, lo, hi) = match plan.machine.dialect {
        gearcam_proto::Dialect::Fanuc => {
            ("machine.parameters.macro_first", p.macro_first, 500, 999)
        }
        _ => ("machine.parameters.r_first", p.r_first, 0, 999),
    };
    if first < lo || first + slots - 1 > hi {
        r.error(
            Code::MACHINE_SETTING_RANGE,
            field,
            format!("{lo} to {}", hi + 1 - slots),
            first.to_string(),
            format!(
                "gearcam's programs use {slots} consecutive parameters from this one (the hob-shift part counter among them, which the control must keep between runs); name a free block of the machine's retained parameters in the profile."
            ),
        );
    }
    r.errors.len() == before
}

pub(super) fn check_machine_limits(
    r: &mut Report,
    plan: &ProcessPlan,
    geo: &Geometry,
    cfg: &Config,
) {
    let gear = &plan.gear;
    let lim = &plan.machine.limits;
    let id = &plan.machine.id;
    let [lo, hi] = lim.module_mm;
    let mn = gear.module_mm;
    if !(mn >= lo - cfg.length_tolerance_mm && mn <= hi + cfg.length_tolerance_mm) {
        r.error(
            Code::MACHINE_MODULE_LIMIT,
            "gear.module_mm",
            format!("{} to {} mm", num(lo), num(hi)),
            format!("{} mm", num(mn)),
            format!("Machine {id} cuts modules from {} to {} mm only; choose another machine for this gear.", num(lo), num(hi)),
        );
    }
    let blank = gear.blank_od_mm.unwrap_or(geo.da_mm);
    if !(blank <= lim.max_workpiece_od_mm + cfg.length_tolerance_mm) {
        r.error(
            Code::WORKPIECE_OD_LIMIT,
            "gear.blank_od_mm",
            format!("≤ {} mm", num(lim.max_workpiece_od_mm)),
            format!("{} mm", num(blank)),
            format!("The blank is larger than machine {id} takes; choose a larger machine."),
        );
    }
    check_hob_od_limit(r, plan, cfg);
}

pub(super) fn check_hob_od_limit(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let lim = &plan.machine.limits;
    let od = plan.hob.od_mm;
    if od.is_finite() && !(od <= lim.max_hob_od_mm + cfg.length_tolerance_mm) {
        r.error(
            Code::HOB_OD_LIMIT,
            "hob.od_mm",
            format!("≤ {} mm", num(lim.max_hob_od_mm)),
            format!("{} mm", num(od)),
            format!(
                "Hob {} is larger than machine {}'s hob head takes; choose a smaller hob or another machine.",
                plan.hob.id, plan.machine.id
            ),
        );
    }
}

/// Check 1: the blank OD lies in [da − below, da + above]; warns near an edge.
pub(super) fn check_blank_window(r: &mut Report, plan: &ProcessPlan, geo: &Geometry, cfg: &Config) {
    let s = cfg;
    let da = geo.da_mm;
    let blank = blank_od(plan, geo);
    let (lo, hi) = (da - s.blank_od_below_mm, da + s.blank_od_above_mm);
    if !(blank >= lo - cfg.length_tolerance_mm && blank <= hi + cfg.length_tolerance_mm) {
        r.error(
            Code::BLANK_OD_WINDOW,
            "gear.blank_od_mm",
            format!("{} to {} mm (tip diameter da {} mm)", num(lo), num(hi), num(da)),
            format!("{} mm", num(blank)),
            format!(
                "The blank OD must lie between {} mm under and {} mm over the tip diameter; turn the blank to size or correct gear.blank_od_mm.",
                num(s.blank_od_below_mm),
                num(s.blank_od_above_mm)
            ),
        );
        return;
    }
    let dev = blank - da;
    let allowed = if dev < 0.0 {
        s.blank_od_below_mm
    } else {
        s.blank_od_above_mm
    };
    if allowed > 0.0 && dev.abs() > (1.0 - cfg.edge_fraction) * allowed {
        r.warnings.push(Warning {
            code: Code::BLANK_OD_EDGE,
            field: "gear.blank_od_mm".into(),
            message: format!(
                "The blank OD {} mm is within {} % of the edge of its window {} to {} mm; check the blank before cutting.",
                num(blank),
                num(cfg.edge_fraction * 100.0),
                num(lo),
                num(hi)
            ),
        });
    }
}

pub(super) fn blank_od(plan: &ProcessPlan, geo: &Geometry) -> f64 {
    plan.gear.blank_od_mm.unwrap_or(geo.da_mm)
}
