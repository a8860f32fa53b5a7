//! The machine's limits on the proposed cutting data.

use gearcam_proto::{HobData, MachineProfile, Source, Sourced};

/// Bounds the proposed cutting speed `vc` and feed `fa` by what the machine
/// can run with the hob: the hob and table speed limits bound the cutting
/// speed, the axial feed rate limit the feed per revolution (spur estimate
/// of the table speed Nw = z0·Nt/z). A value clamped takes the source
/// `machine`.
pub(super) fn within_machine_limits(
    vc: &mut Sourced,
    fa: &mut Sourced,
    machine: &MachineProfile,
    hob: &HobData,
    teeth: u32,
) {
    let (da0, z0, z) = (
        hob.od_mm,
        f64::from(hob.starts.max(1)),
        f64::from(teeth.max(1)),
    );
    let nt_max = machine
        .limits
        .max_hob_rpm
        .min(machine.limits.max_table_rpm * z / z0);
    let vc_max = nt_max * std::f64::consts::PI * da0 / 1000.0;
    if da0 > 0.0 && vc.value > vc_max {
        *vc = Sourced {
            value: vc_max,
            source: Source::Machine,
        };
    }
    let nt = vc.value * 1000.0 / (std::f64::consts::PI * da0);
    let fa_max = machine.limits.max_axial_feed_mm_min * z / (z0 * nt);
    if da0 > 0.0 && fa.value > fa_max {
        *fa = Sourced {
            value: fa_max,
            source: Source::Machine,
        };
    }
}
