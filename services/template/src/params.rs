//! The parameter table: every value a template can read, by scope (docs/programs.md#standard-templates step
//! 1, "load the parameter values").
//!
//! Each scope has a fixed list of names ([`PART`], [`UNIT`], [`CUT`], [`MOVE`]);
//! a compiled template gives every name a slot, and instantiation fills the slots
//! of a scope from the machining model each time the scope is entered. Lengths are
//! mm, feeds mm/min, speeds rpm, angles degrees, times minutes unless named `_s`.
//! A value the model does not have is `null` (test it with `has()`).

use gearcam_proto::{Cut, GearSpec, HobData, Kinematics, MachiningModel, Move, MoveKind};

use crate::expr::TplValue;

/// What the renderer adds to the model for the part scope.
#[derive(Debug)]
pub struct PartInput<'a> {
    /// The model.
    pub model: &'a MachiningModel,
    /// The job's gear (the first unit's for a multi-gear part).
    pub gear: &'a GearSpec,
    /// Program name under the controller's rules (`SP_2002`, `O2002`).
    pub program_name: &'a str,
    /// Program file name (`_N_SP_2002_MPF`, `O2002`).
    pub program_file: &'a str,
    /// Template id and version.
    pub template_id: &'a str,
    /// Template version.
    pub template_version: u32,
    /// Generator (this crate and version).
    pub generator: &'a str,
    /// Knowledge-base cases, space-separated, or `NONE`.
    pub cases: &'a str,
    /// The units to program.
    pub units: &'a [UnitInput<'a>],
}

/// One gear unit: every unit of a multi-gear part, or the job's gear.
#[derive(Debug, Clone, Copy)]
pub struct UnitInput<'a> {
    /// Name (empty for a single gear).
    pub name: &'a str,
    /// Height of the unit's lower face above the first unit's, mm.
    pub z_offset_mm: f64,
    /// A hob change is needed before this unit.
    pub hob_change: bool,
    /// Gear data.
    pub gear: &'a GearSpec,
    /// Hob.
    pub hob: &'a HobData,
    /// Kinematics.
    pub kin: &'a Kinematics,
}

/// Helix angles below this are spur gears, degrees.
pub const HELIX_EPS_DEG: f64 = 1e-9;

/// Enum values as the lower-case names the job file and messages use.
trait Named {
    fn name(&self) -> &'static str;
}

macro_rules! named {
    ($t:ty { $($v:ident => $n:literal),* }) => {
        impl Named for $t {
            fn name(&self) -> &'static str {
                match self { $(<$t>::$v => $n),* }
            }
        }
    };
}

named!(gearcam_proto::Hand { Right => "right", Left => "left" });
named!(gearcam_proto::CutMode { Conventional => "conventional", Climb => "climb" });
named!(gearcam_proto::LargeEnd { Bottom => "bottom", Top => "top" });
named!(gearcam_proto::CrowningShape { Circular => "circular", Parabolic => "parabolic" });
named!(gearcam_proto::WormInfeed { Radial => "radial", Tangential => "tangential" });
named!(gearcam_proto::ShiftMode { Part => "part", Cut => "cut" });

fn lower(v: &impl Named) -> TplValue {
    TplValue::from(v.name())
}

/// Declares a scope's names and its fill function together, so the order of the
/// names and of the values can never drift apart.
macro_rules! scope_table {
    ($(#[$doc:meta])* $names:ident, $fill:ident, ($($arg:ident: $ty:ty),*), { $($name:literal => $val:expr),* $(,)? }) => {
        $(#[$doc])*
        pub const $names: &[&str] = &[$($name),*];
        /// Fills this scope's slots (`out` has exactly the scope's length).
        pub fn $fill($($arg: $ty),*, out: &mut [TplValue]) {
            let values = [$(TplValue::from($val)),*];
            for (slot, v) in out.iter_mut().zip(values) {
                *slot = v;
            }
        }
    };
}

scope_table!(
    /// Part scope: the program, the machine, the job's options, the first unit.
    PART, fill_part, (p: &PartInput<'_>), {
    "program.name" => p.program_name,
    "program.file" => p.program_file,
    "template.id" => p.template_id,
    "template.version" => p.template_version,
    "generator" => p.generator,
    "job_id" => p.model.job_id.as_str(),
    "part_number" => p.model.plan.request.spec.job.part_number.as_str(),
    "quantity" => p.model.plan.request.spec.job.quantity,
    "submitted" => gearcam_proto::utc_text(p.model.plan.request.submitted_at_ms),
    "submitted_by" => p.model.plan.request.submitted_by.as_str(),
    "class" => p.model.plan.class.as_str(),
    "cases" => p.cases,
    "model_version" => p.model.model_version.as_str(),
    "machine.id" => p.model.plan.machine.id.as_str(),
    "machine.name" => p.model.plan.machine.name.as_str(),
    "machine.max_feed" => p.model.plan.machine.limits.max_axial_feed_mm_min,
    "machine.work_offset" => p.model.plan.machine.work_offset.as_str(),
    "machine.gcode_system" => p.model.plan.machine.gcode_system.as_str(),
    "ax.radial" => p.model.plan.machine.axes.radial.as_str(),
    "ax.axial" => p.model.plan.machine.axes.axial.as_str(),
    "ax.swivel" => p.model.plan.machine.axes.swivel.as_str(),
    "ax.hob" => p.model.plan.machine.axes.hob.as_str(),
    "ax.table" => p.model.plan.machine.axes.table.as_str(),
    "ax.shift" => p.model.plan.machine.axes.shift.as_str(),
    "mc.spindle_on" => p.model.plan.machine.mcodes.spindle_on,
    "mc.spindle_off" => p.model.plan.machine.mcodes.spindle_off,
    "mc.coolant_on" => p.model.plan.machine.mcodes.coolant_on,
    "mc.coolant_off" => p.model.plan.machine.mcodes.coolant_off,
    "mc.outer_support_on" => p.model.plan.machine.mcodes.outer_support_on,
    "mc.outer_support_off" => p.model.plan.machine.mcodes.outer_support_off,
    "mc.fixture_clamp" => p.model.plan.machine.mcodes.fixture_clamp,
    "mc.fixture_unclamp" => p.model.plan.machine.mcodes.fixture_unclamp,
    "mc.chip_conveyor_on" => p.model.plan.machine.mcodes.chip_conveyor_on,
    "mc.chip_conveyor_off" => p.model.plan.machine.mcodes.chip_conveyor_off,
    "mc.mist_on" => p.model.plan.machine.mcodes.mist_on,
    "mc.mist_off" => p.model.plan.machine.mcodes.mist_off,
    "mc.program_end" => p.model.plan.machine.mcodes.program_end,
    "options.coolant" => p.model.plan.sections().options.coolant,
    "options.outer_support" => p.model.plan.sections().options.outer_support,
    "options.fixture_clamp" => p.model.plan.sections().options.fixture_clamp,
    "options.sync_cancel" => p.model.plan.sections().options.sync_cancel,
    "options.chip_conveyor" => p.model.plan.sections().options.chip_conveyor,
    "options.mist_separator" => p.model.plan.sections().options.mist_separator,
    "gear.module" => p.gear.module_mm,
    "gear.teeth" => p.gear.teeth,
    "gear.helix" => p.gear.helix_angle_deg,
    "gear.hand" => p.gear.helix_hand.map_or(TplValue::Null, |h| lower(&h)),
    "gear.face_width" => p.gear.face_width_mm,
    "gear.material" => p.gear.material.as_str(),
    "gear.quality" => u32::from(p.gear.quality_grade),
    "helical" => p.gear.helix_angle_deg.abs() > HELIX_EPS_DEG,
    "hob.id" => p.model.plan.hob.id.as_str(),
    "hob.starts" => p.model.plan.hob.starts,
    "hob.od" => p.model.plan.hob.od_mm,
    "hob.module" => p.model.plan.hob.module_mm,
    "hob.lead_angle" => p.model.plan.hob.lead_angle_deg,
    "hob.hand" => lower(&p.model.plan.hob.hand),
    "process.cutting_speed" => p.model.plan.process.cutting_speed_m_min,
    "process.feed" => p.model.plan.process.feed_mm_per_rev,
    "kin.cut_mode" => lower(&p.model.model.cut_mode),
    "kin.depth" => p.model.model.depth_mm,
    "kin.centre_distance" => p.model.model.centre_distance_mm,
    "kin.blank_od" => p.model.model.blank_od_mm,
    "kin.part_time" => p.model.model.part_time_min,
    "kin.cuts" => p.model.model.cuts.len() as u32,
    "A.x" => p.model.model.positions.A.x_mm,
    "A.z" => p.model.model.positions.A.z_mm,
    "units" => p.units.len() as u32,
    "multi" => p.units.len() > 1,
    "any_shift" => p.units.iter().any(|u| u.kin.shift.is_some()),
    "first.B.x" => p.units.first().and_then(|u| u.kin.cuts.first()).map(|c| c.positions.B.x_mm),
    "first.B.z" => p.units.first().and_then(|u| u.kin.cuts.first()).map(|c| c.positions.B.z_mm),
    "first.swivel" => p.units.first().map(|u| u.kin.swivel_axis_deg),
});

fn use_z(u: &UnitInput<'_>) -> bool {
    u.gear.helix_angle_deg.abs() > HELIX_EPS_DEG && u.kin.factors.c_per_z_deg_per_mm != 0.0
}

fn tangential(k: &Kinematics) -> bool {
    k.worm
        .as_ref()
        .is_some_and(|w| w.infeed == gearcam_proto::WormInfeed::Tangential)
}

scope_table!(
    /// Unit scope (`u.*` the unit, `k.*` its kinematics): entered per gear unit.
    UNIT, fill_unit, (i: usize, count: usize, u: &UnitInput<'_>), {
    "u.index" => (i + 1) as u32,
    "u.first" => i == 0,
    "u.last" => i + 1 == count,
    "u.name" => u.name,
    "u.z_offset" => u.z_offset_mm,
    "u.hob_change" => u.hob_change,
    "u.helical" => u.gear.helix_angle_deg.abs() > HELIX_EPS_DEG,
    "u.module" => u.gear.module_mm,
    "u.teeth" => u.gear.teeth,
    "u.helix" => u.gear.helix_angle_deg,
    "u.hand" => u.gear.helix_hand.map_or(TplValue::Null, |h| lower(&h)),
    "u.hob.id" => u.hob.id.as_str(),
    "u.hob.starts" => u.hob.starts,
    "u.hob.lead_angle" => u.hob.lead_angle_deg,
    "u.hob.hand" => lower(&u.hob.hand),
    "k.class" => u.kin.class.as_str(),
    "k.swivel" => u.kin.swivel_axis_deg,
    "k.B.x" => u.kin.cuts.first().map(|c| c.positions.B.x_mm),
    "k.B.z" => u.kin.cuts.first().map(|c| c.positions.B.z_mm),
    "k.y0" => u.kin.cuts.iter().flat_map(|c| &c.moves).find_map(|m| m.y_mm),
    "k.hob_rpm" => u.kin.hob_rpm,
    "k.cuts" => u.kin.cuts.len() as u32,
    "k.cut_mode" => lower(&u.kin.cut_mode),
    "k.coupling.num" => u.kin.factors.c_per_b.num,
    "k.coupling.den" => u.kin.factors.c_per_b.den,
    "k.c_per_z" => u.kin.factors.c_per_z_deg_per_mm,
    "k.c_per_y" => u.kin.factors.c_per_y_deg_per_mm,
    "k.use_z" => use_z(u),
    "k.use_y" => u.kin.shift.is_some() || tangential(u.kin),
    "k.tangential" => tangential(u.kin),
    "k.has_cone" => u.kin.cone.is_some(),
    "k.cone.angle" => u.kin.cone.as_ref().map(|c| c.angle_deg),
    "k.cone.large_end" => u.kin.cone.as_ref().map_or(TplValue::Null, |c| lower(&c.large_end)),
    "k.cone.x_per_z" => u.kin.cone.as_ref().map(|c| c.x_per_z),
    "k.cone.x_large" => u.kin.cone.as_ref().map(|c| c.x_large_mm),
    "k.has_crowning" => u.kin.crowning.is_some(),
    "k.crowning.shape" => u.kin.crowning.as_ref().map_or(TplValue::Null, |c| lower(&c.shape)),
    "k.crowning.amount" => u.kin.crowning.as_ref().map(|c| c.amount_mm),
    "k.crowning.radius" => u.kin.crowning.as_ref().and_then(|c| c.radius_mm),
    "k.crowning.chords" => u.kin.crowning.as_ref().map_or(TplValue::Null, |c| TplValue::from(c.chords)),
    "k.crowning.max_deviation" => u.kin.crowning.as_ref().map(|c| c.max_deviation_mm),
    "k.has_worm" => u.kin.worm.is_some(),
    "k.worm.infeed" => u.kin.worm.as_ref().map_or(TplValue::Null, |w| lower(&w.infeed)),
    "k.worm.centre_distance" => u.kin.worm.as_ref().map(|w| w.centre_distance_mm),
    "k.worm.throat_z" => u.kin.worm.as_ref().map(|w| w.throat_z_mm),
    "k.has_shift" => u.kin.shift.is_some(),
    "k.shift.mode" => u.kin.shift.as_ref().map_or(TplValue::Null, |s| lower(&s.mode)),
    "k.shift.by_cut" => u.kin.shift.as_ref().is_some_and(|s| s.mode == gearcam_proto::ShiftMode::Cut),
    "k.shift.positions" => u.kin.shift.as_ref().map_or(TplValue::Null, |s| TplValue::from(s.positions)),
    "k.shift.start" => u.kin.shift.as_ref().map(|s| s.start_mm),
    "k.shift.end" => u.kin.shift.as_ref().map(|s| s.end_mm),
    "k.shift.last" => u.kin.shift.as_ref().map(|s| {
        let dir = if s.end_mm >= s.start_mm { 1.0 } else { -1.0 };
        s.start_mm + dir * s.step_mm * f64::from(s.positions.saturating_sub(1))
    }),
    "k.shift.step" => u.kin.shift.as_ref().map(|s| if s.end_mm >= s.start_mm { s.step_mm } else { -s.step_mm }),
    "k.shift.parts_per_step" => u.kin.shift.as_ref().map_or(TplValue::Null, |s| TplValue::from(s.parts_per_step)),
});

scope_table!(
    /// Cut scope (`cut.*`): entered per cut of the unit.
    CUT, fill_cut, (count: usize, c: &Cut), {
    "cut.number" => c.number,
    "cut.count" => count as u32,
    "cut.last" => c.number as usize == count,
    "cut.finish" => c.finish,
    "cut.depth" => c.depth_mm,
    "cut.centre_distance" => c.centre_distance_mm,
    "cut.time" => c.time_min,
    "cut.resync" => c.resync,
    "cut.B.x" => c.positions.B.x_mm,
    "cut.B.z" => c.positions.B.z_mm,
});

fn kind(m: &Move) -> &'static str {
    match m.kind {
        MoveKind::Rapid => "rapid",
        MoveKind::Feed => "feed",
        MoveKind::Arc => "arc",
        MoveKind::Dwell => "dwell",
    }
}

scope_table!(
    /// Move scope (`m.*`): entered per move of the cut; an axis the move does not
    /// change is `null`.
    MOVE, fill_move, (i: usize, m: &Move), {
    "m.index" => (i + 1) as u32,
    "m.kind" => kind(m),
    "m.x" => m.x_mm,
    "m.z" => m.z_mm,
    "m.y" => m.y_mm,
    "m.feed" => m.feed_mm_min,
    "m.via.x" => m.via.as_ref().map(|v| v.x_mm),
    "m.via.z" => m.via.as_ref().map(|v| v.z_mm),
    "m.radius" => m.radius_mm,
    "m.dwell" => m.dwell_s,
    "m.note" => m.note.as_str(),
});

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_across_scopes() {
        let mut all: Vec<&str> = PART
            .iter()
            .chain(UNIT)
            .chain(CUT)
            .chain(MOVE)
            .copied()
            .collect();
        let n = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), n);
    }

    #[test]
    fn enum_names_are_the_serde_names() {
        assert_eq!(
            lower(&gearcam_proto::CutMode::Climb),
            TplValue::from("climb")
        );
        assert_eq!(lower(&gearcam_proto::Hand::Right), TplValue::from("right"));
    }
}
