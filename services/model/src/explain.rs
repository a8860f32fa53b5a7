//! Where every value of a model came from, so a planner can check it: the
//! job, a knowledge-base case, the tool library, the machine profile, the
//! drawing's class (a finishing feed held to it), a documented default, or
//! the model's own computation (with its formula).

use gearcam_proto::{Explained, Geometry, Kinematics, Origin, ProcessPlan, Source};

use crate::hobbing::{DEFAULT_FINISH_ALLOWANCE_PER_MODULE, DEFAULT_RADIAL_FEED_FRACTION};

/// The origin of a plan's [`Source`].
pub fn origin(source: Source) -> Origin {
    match source {
        Source::Job => Origin::Job,
        Source::Case => Origin::Case,
        Source::Machine => Origin::Machine,
        Source::Default => Origin::Default,
        Source::Library => Origin::Library,
        Source::Grade => Origin::Grade,
    }
}

fn e(name: &str, value: f64, unit: &str, origin: Origin, note: &str) -> Explained {
    Explained {
        name: name.into(),
        value,
        unit: unit.into(),
        origin,
        note: note.into(),
    }
}

/// Every input and result of a model with its origin, in reading order:
/// drawing data, hob, process, machine, geometry, kinematics.
pub fn explain(plan: &ProcessPlan, geo: &Geometry, k: &Kinematics) -> Vec<Explained> {
    let mut out = drawing(plan, k);
    out.extend(hob(plan));
    out.extend(process(plan, k));
    out.extend(machine(plan));
    out.extend(geometry(geo));
    out.extend(model(k));
    out
}

/// The origin of a decided value the plan lists; gearcam's default otherwise.
fn from_values(plan: &ProcessPlan, name: &str) -> Origin {
    plan.values
        .get(name)
        .map(|s| origin(s.source))
        .unwrap_or(Origin::Default)
}

/// The job's origin when it gave the value, else `other`.
fn job_or(given: bool, other: Origin) -> Origin {
    if given {
        Origin::Job
    } else {
        other
    }
}

/// Drawing data: the job's, unless the plan took it from the workpiece
/// library (values `gear.*` with source `library`).
fn gear_origin(plan: &ProcessPlan, name: &str) -> Origin {
    plan.values
        .get(name)
        .map(|s| origin(s.source))
        .unwrap_or(Origin::Job)
}

/// The gear's drawing data.
fn drawing(plan: &ProcessPlan, k: &Kinematics) -> Vec<Explained> {
    let g = &plan.gear;
    let gear_origin = |name: &str| gear_origin(plan, name);
    vec![
        e(
            "gear.module_mm",
            g.module_mm,
            "mm",
            gear_origin("gear.module_mm"),
            "normal module mn",
        ),
        e(
            "gear.teeth",
            f64::from(g.teeth),
            "",
            gear_origin("gear.teeth"),
            "number of teeth z",
        ),
        e(
            "gear.pressure_angle_deg",
            g.pressure_angle_deg,
            "deg",
            gear_origin("gear.pressure_angle_deg"),
            "normal pressure angle αn (default 20)",
        ),
        e(
            "gear.helix_angle_deg",
            g.helix_angle_deg,
            "deg",
            gear_origin("gear.helix_angle_deg"),
            "helix angle β (default 0)",
        ),
        e(
            "gear.face_width_mm",
            g.face_width_mm,
            "mm",
            gear_origin("gear.face_width_mm"),
            "face width b",
        ),
        e(
            "gear.profile_shift",
            g.profile_shift,
            "",
            gear_origin("gear.profile_shift"),
            "profile shift coefficient x (default 0)",
        ),
        e(
            "gear.blank_od_mm",
            k.blank_od_mm,
            "mm",
            if g.blank_od_mm.is_some() {
                gear_origin("gear.blank_od_mm")
            } else {
                Origin::Computed
            },
            if g.blank_od_mm.is_some() {
                "blank outside diameter Da1"
            } else {
                "default: the tip diameter da"
            },
        ),
        e(
            "gear.fixture_height_mm",
            g.fixture_height_mm,
            "mm",
            gear_origin("gear.fixture_height_mm"),
            "H, lower tooth face above the table",
        ),
    ]
}

/// The hob.
fn hob(plan: &ProcessPlan) -> Vec<Explained> {
    let hob = &plan.hob;
    let hob_origin = origin(hob.source);
    vec![
        e(
            "hob.starts",
            f64::from(hob.starts),
            "",
            hob_origin,
            &format!("hob {}", hob.id),
        ),
        e(
            "hob.od_mm",
            hob.od_mm,
            "mm",
            hob_origin,
            "hob outside diameter da0",
        ),
        e(
            "hob.module_mm",
            hob.module_mm,
            "mm",
            hob_origin,
            "hob normal module mn0",
        ),
        e(
            "hob.lead_angle_deg",
            hob.lead_angle_deg,
            "deg",
            hob_origin,
            "hob lead angle γ0",
        ),
        e(
            "hob.length_mm",
            hob.length_mm,
            "mm",
            hob_origin,
            "overall hob length",
        ),
        e(
            "hob.usable_length_mm",
            hob.usable_mm(),
            "mm",
            if hob.usable_length_mm.is_some() {
                hob_origin
            } else {
                Origin::Default
            },
            if hob.usable_length_mm.is_some() {
                "usable hob length: the shift travels in it"
            } else {
                "usable hob length: the overall length (the job gave the hob inline)"
            },
        ),
    ]
}

/// The process values, with the rough cuts' and the radial feed when they apply.
fn process(plan: &ProcessPlan, k: &Kinematics) -> Vec<Explained> {
    let g = &plan.gear;
    let o = &plan.sections().process;
    let from_values = |name: &str| from_values(plan, name);
    let mut out = vec![
        e(
            "process.cutting_speed_m_min",
            plan.process.cutting_speed_m_min,
            "m/min",
            from_values("cutting_speed_m_min"),
            "cutting speed vc",
        ),
        e(
            "process.feed_mm_per_rev",
            plan.process.feed_mm_per_rev,
            "mm/rev",
            from_values("feed_mm_per_rev"),
            "axial feed per workpiece revolution fa",
        ),
        e(
            "process.cuts",
            f64::from(plan.process.cuts),
            "",
            from_values("cuts"),
            "number of cuts",
        ),
        e(
            "process.safety_mm",
            plan.process.safety_mm,
            "mm",
            from_values("safety_mm"),
            "safety distance added to ΔH′",
        ),
        e(
            "process.depth_mm",
            k.depth_mm,
            "mm",
            job_or(plan.process.depth_mm.is_some(), Origin::Computed),
            if plan.process.depth_mm.is_some() {
                "radial depth h"
            } else {
                "h = (da0 + Da1)/2 − theoretical centre distance (docs/reference.md#validation-checks)"
            },
        ),
    ];
    if plan.process.cuts > 1 {
        let allowance = k.cuts.first().map(|c| c.allowance_mm).unwrap_or(0.0);
        out.push(e(
            "process.finish_allowance_mm",
            allowance,
            "mm",
            match (o.finish_allowance_mm, plan.values.get("allowance_mm")) {
                (Some(_), _) => Origin::Job,
                (None, Some(v)) if v.value > 0.0 => origin(v.source),
                _ => Origin::Default,
            },
            &format!(
                "radial stock of the rough cuts (default {DEFAULT_FINISH_ALLOWANCE_PER_MODULE}·mn)"
            ),
        ));
        out.push(e(
            "process.finish_feed_mm_per_rev",
            k.cuts.last().map(|c| c.feed_mm_per_rev).unwrap_or(0.0),
            "mm/rev",
            match (o.finish_feed_mm_per_rev, plan.values.get("finish_feed_mm_per_rev")) {
                (Some(_), _) => Origin::Job,
                (None, Some(v)) => origin(v.source),
                _ => Origin::Default,
            },
            "feed of the finishing cut (default: the knowledge base's for the drawing's class, else the feed)",
        ));
    }
    if let Some(c) = k.cuts.iter().find(|c| c.radial_feed_mm_min > 0.0) {
        let given = o.radial_feed_mm_per_rev.is_some()
            || g.worm_wheel
                .as_ref()
                .is_some_and(|w| w.radial_feed_mm_per_rev.is_some());
        out.push(e(
            "process.radial_feed_mm_min",
            c.radial_feed_mm_min,
            "mm/min",
            job_or(given, Origin::Default),
            &format!(
                "radial feed rate (default {DEFAULT_RADIAL_FEED_FRACTION:.4}·fa per revolution)"
            ),
        ));
    }
    out
}

/// The machine profile's settings.
fn machine(plan: &ProcessPlan) -> Vec<Explained> {
    let m = &plan.machine;
    vec![
        e(
            "machine.retract_mm",
            m.settings.retract_mm,
            "mm",
            Origin::Machine,
            "X lift of B over C",
        ),
        e(
            "machine.exit_mm",
            m.settings.exit_mm,
            "mm",
            Origin::Machine,
            "X lift of E over D",
        ),
        e(
            "machine.swivel_sign",
            m.settings.swivel_sign,
            "",
            Origin::Machine,
            "A = swivel_sign·η + swivel_offset",
        ),
        e(
            "machine.home_x_mm",
            m.home_x_mm,
            "mm",
            Origin::Machine,
            "position A, X",
        ),
        e(
            "machine.home_z_mm",
            m.home_z_mm,
            "mm",
            Origin::Machine,
            "position A, Z",
        ),
    ]
}

/// The gear's geometry.
fn geometry(geo: &Geometry) -> Vec<Explained> {
    vec![
        e(
            "geometry.d_mm",
            geo.d_mm,
            "mm",
            Origin::Computed,
            "d = z·mn / cos β",
        ),
        e(
            "geometry.da_mm",
            geo.da_mm,
            "mm",
            Origin::Computed,
            "da = d + 2·mn·(ha* + x)",
        ),
        e(
            "geometry.sn_mm",
            geo.sn_mm,
            "mm",
            Origin::Computed,
            "sn = mn·(π/2 + 2·x·tan αn)",
        ),
        e(
            "geometry.span_mm",
            geo.span_mm,
            "mm",
            Origin::Computed,
            &format!("Wk over k = {} teeth (ISO 21771)", geo.span_teeth),
        ),
        e(
            "geometry.over_balls_mm",
            geo.over_balls_mm,
            "mm",
            Origin::Computed,
            &format!("MdK over {} mm balls (ISO 21771)", geo.ball_mm),
        ),
    ]
}

/// The hobbing model's results.
fn model(k: &Kinematics) -> Vec<Explained> {
    vec![
        e(
            "model.swivel_deg",
            k.swivel_deg,
            "deg",
            Origin::Computed,
            "η = s_g·β − s_h·γ0, signed (docs/hobbing.md §2)",
        ),
        e(
            "model.clearance_mm",
            k.clearance_mm,
            "mm",
            Origin::Computed,
            "ΔH′: lowest point of the finite hob over the blank, 1/cos γ (docs/hobbing.md §3)",
        ),
        e(
            "model.centre_distance_mm",
            k.centre_distance_mm,
            "mm",
            Origin::Computed,
            "L = (da0 + Da1)/2 − h",
        ),
        e(
            "model.hob_rpm",
            k.hob_rpm,
            "rpm",
            Origin::Computed,
            "Nt = 1000·vc / (π·da0)",
        ),
        e(
            "model.index_rpm",
            k.index_rpm,
            "rpm",
            Origin::Computed,
            "Ni = z0·Nt / z",
        ),
        e(
            "model.table_rpm",
            k.table_rpm,
            "rpm",
            Origin::Computed,
            "Nw = Ni / (1 ∓ fa/Pz)",
        ),
        e(
            "model.axial_feed_mm_min",
            k.axial_feed_mm_min,
            "mm/min",
            Origin::Computed,
            "Vf = fa·Nw",
        ),
        e(
            "model.factors.c_per_z_deg_per_mm",
            k.factors.c_per_z_deg_per_mm,
            "deg/mm",
            Origin::Computed,
            "table_sign·s_g·360·sin β / (π·mn·z): the gear's hand alone",
        ),
        e(
            "model.factors.c_per_y_deg_per_mm",
            k.factors.c_per_y_deg_per_mm,
            "deg/mm",
            Origin::Computed,
            "−table_sign·shift_sign·360·cos γ0 / (π·mn0·z), either hand",
        ),
        e(
            "model.cut_time_min",
            k.cut_time_min,
            "min",
            Origin::Computed,
            "(b + 2·ΔH′)·z / (Nt·z0·fa) (docs/hobbing.md#4-the-cycle-positions-speeds-feeds)",
        ),
        e(
            "model.part_time_min",
            k.part_time_min,
            "min",
            Origin::Computed,
            "every cut's feed moves and dwells",
        ),
    ]
}
