//! The report of a hobbing program's virtual run: the program as delivered,
//! read back, run on a model of its machine, cutting a virtual blank with
//! the hob's edges; the gear it cut measured as a gear-measuring machine
//! measures and graded by ISO 1328-1:2013; the safety findings of the same
//! run. It travels with the program (`NcProgram::simulation`) so the planner
//! sees what the machine will cut before it does.

use serde::{Deserialize, Serialize};

/// One graded deviation of the cut gear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Deviation {
    /// The item's symbol: `fp`, `Fp`, `fHα`, `ffα`, `Fα`, `fHβ`, `ffβ`,
    /// `Fβ`, `Fr`.
    pub item: String,
    /// Its value, µm (the worst over the teeth and flanks; slopes signed).
    pub value_um: f64,
    /// The tolerance of the class it meets (of class 11 when worse), µm.
    pub tolerance_um: f64,
    /// The finest ISO 1328-1:2013 class it meets; `None`: worse than 11.
    pub class: Option<u8>,
}

/// A safety finding of the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SafetyIssue {
    /// The kind, snake case (`rapid_contact`, `cut_decoupled`,
    /// `double_teeth`, ...).
    pub kind: String,
    /// The program line it happens at (0: not a line of its own).
    pub line: u32,
    /// What happens, with numbers.
    pub what: String,
    /// Why it matters.
    pub why: String,
}

/// The virtual run of a hobbing program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimulationReport {
    /// `fine` (the delivery's proof) or `coarse` (interactive).
    pub mode: String,
    /// The machine and hob errors the run was made with (a what-if run);
    /// empty for the ideal machine.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub what_if: Vec<String>,
    /// The predicted ISO 1328-1:2013 class of the gear (the worst item's);
    /// `None` when worse than 11 or not measured.
    pub grade: Option<u8>,
    /// The class the drawing asks for.
    pub required_grade: u8,
    /// Every graded item.
    pub deviations: Vec<Deviation>,
    /// Why the gear could not be measured, when it could not (a wrong
    /// tooth count, a gap not cut): the gear is visibly wrong.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_measured: Option<String>,
    /// The safety findings.
    pub safety: Vec<SafetyIssue>,
    /// Transverse sections of the blank.
    pub sections: u32,
    /// Outline samples per section.
    pub samples_per_section: u32,
    /// Gash passes cut.
    pub passes: u64,
    /// The measured size: mean normal tooth thickness at the reference
    /// circle and its design value, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness_mm: Option<(f64, f64)>,
    /// Span over k teeth, measured and design, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub span_mm: Option<(f64, f64)>,
    /// Dimension over balls, measured and design, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub over_balls_mm: Option<(f64, f64)>,
    /// Wall time of the run, ms (taken by the caller, 0 when not timed).
    pub ms: f64,
    /// The gear this report is about, on a part of several gears (the
    /// first; `units` holds the others).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// How far the measurement goes where it does not go all the way (a
    /// worm wheel is measured in its throat plane, and ISO 1328-1 does not
    /// cover it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// The reports of the part's other gears, each with its `unit` name
    /// (the safety findings of the whole run are the first's).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub units: Vec<SimulationReport>,
}

impl SimulationReport {
    /// This report and those of the part's other gears.
    pub fn every_gear(&self) -> impl Iterator<Item = &SimulationReport> {
        std::iter::once(self).chain(&self.units)
    }

    /// The predicted class of the whole part: the worst gear's (`None`
    /// when one is worse than 11 or not measured).
    pub fn part_grade(&self) -> Option<u8> {
        self.every_gear()
            .map(|g| g.grade)
            .try_fold(0, |worst, g| g.map(|g| worst.max(g)))
    }

    /// The deviation that sets the grade: the first item of the worst
    /// class (none when nothing was graded).
    pub fn limiting(&self) -> Option<&Deviation> {
        // `max_by_key` keeps the last of equals: reversed, the first.
        self.deviations
            .iter()
            .rev()
            .max_by_key(|d| d.class.unwrap_or(12))
    }
}
