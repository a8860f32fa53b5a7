//! The table's phase at each coupling: synchronised or unknown.
//!
//! While coupled, C − k_b·B − k_z·Z − k_y·Y is constant (the coupling's
//! *residual* ρ, neutral frame). Switching the gearbox off and on again
//! loses it unless the new coupling is synchronised: an 840D `EGONSYNE`
//! moves the table to its synchronised positions relative to the hob, so a
//! unit coupled again at the same positions has the same ρ; a plain `EGON`
//! (and a FANUC `G81` without phase synchronisation, the only form the
//! dialect reads) couples wherever the axes stand. The simulation cannot
//! know that phase; it takes the worst case for a program that has already
//! cut: half a pitch of the gear (π/z of table) off the first cut's.

/// How one coupling's phase was set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CouplingPhase {
    /// Line of the coupling block.
    pub line: u32,
    /// First segment it drives.
    pub segment: usize,
    /// True for an `EGONSYNE` (synchronised positions).
    pub synchronised: bool,
    /// The gear unit (index into the model's units).
    pub unit: usize,
    /// Line of the coupling whose phase this one must keep (the unit's first
    /// coupling that cut), or its own line when it sets the reference.
    pub reference_line: u32,
    /// True when the table's phase relative to the hob is unknown at a
    /// coupling after a cut of the same unit: the worst case is taken.
    pub phase_unknown: bool,
    /// The table's jump when coupling, radians (neutral frame): back to the
    /// reference residual, plus `offset_rad`.
    pub jump_rad: f64,
    /// The worst-case offset taken for an unknown phase, radians (π/z).
    pub offset_rad: f64,
}

/// A coupling that starts at a segment, as the trace gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct CouplingStart {
    pub(super) line: u32,
    pub(super) synchronised: bool,
    pub(super) unit: usize,
    /// Half a pitch of the unit's gear in table angle, radians (π/z).
    pub(super) half_pitch_rad: f64,
}

/// The phase bookkeeping over a program.
#[derive(Debug, Default)]
pub(super) struct Phaser {
    /// The reference: (line, synchronised, unit, residual).
    reference: Option<(u32, bool, usize, f64)>,
    /// A coupled cut since the reference was set.
    cut: bool,
    pub(super) phases: Vec<CouplingPhase>,
}

impl Phaser {
    /// The jump of C at the start of segment `segment`, where coupling
    /// `start` begins with residual `residual`.
    pub(super) fn couple(&mut self, segment: usize, start: CouplingStart, residual: f64) -> f64 {
        let same_unit = self.reference.is_some_and(|r| r.2 == start.unit);
        let mut phase = CouplingPhase {
            line: start.line,
            segment,
            synchronised: start.synchronised,
            unit: start.unit,
            reference_line: start.line,
            phase_unknown: false,
            jump_rad: 0.0,
            offset_rad: 0.0,
        };
        match self.reference {
            Some((line, sync, _, rho)) if same_unit && self.cut => {
                let known = sync && start.synchronised;
                phase.reference_line = line;
                phase.phase_unknown = !known;
                phase.offset_rad = if known { 0.0 } else { start.half_pitch_rad };
                phase.jump_rad = rho + phase.offset_rad - residual;
            }
            _ => {
                self.reference = Some((start.line, start.synchronised, start.unit, residual));
                self.cut = false;
            }
        }
        self.phases.push(phase);
        phase.jump_rad
    }

    /// Notes that a coupled segment cut (a feed with the hob turning).
    pub(super) fn cutting(&mut self) {
        if self.reference.is_some() {
            self.cut = true;
        }
    }
}
