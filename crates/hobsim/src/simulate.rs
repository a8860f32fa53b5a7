//! Virtual hobbing end to end: a program's read-back trace run on the model
//! of its machine ([`crate::kinematics`]), the blank cut by the hob's gash
//! edges ([`crate::cut`]), the gear it cut measured as a gear-measuring
//! machine measures and graded by ISO 1328-1:2013
//! ([`gearcam_gearmeasure::outline`]), and the safety findings of the same
//! run ([`crate::safety`]).
//!
//! The blank is the model's: its outer diameter, standing on the fixture at
//! `fixture_height_mm`, `sections` transverse sections over the face width
//! (inset from each face by the helix evaluation range's exclusion, the
//! smaller of 5 % of b and one module, so every section is one a
//! gear-measuring machine would trace). The drawing the cut gear is measured
//! against is the model's gear: teeth, normal module and pressure angle,
//! helix angle and hand, profile shift, tip and root diameters, the design
//! tooth thickness.

use gearcam_gearmeasure::helix::Hand as MeasureHand;
use gearcam_gearmeasure::iso1328::Grade;
use gearcam_gearmeasure::outline::{self, GearSpec, Measurement, PolarSections};
use gearcam_nc::Trace;
use gearcam_proto::hobbing::Hand;
use gearcam_proto::simulation::{Deviation, SafetyIssue};
use gearcam_proto::{MachiningModel, SimulationReport};

use crate::cut::{self, samples_for, Blank, Resolution, Wanted};
use crate::hob::{Hob, HobExtras};
use crate::kinematics::{self, MachineErrors, MachineRates};
use crate::safety::{self, BlankGeometry, Fixtures, SafetyFinding, SafetyKind};
use crate::SimError;

/// How finely to simulate, and on which machine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// `fine` or `coarse`: the name the report carries.
    pub mode: &'static str,
    /// Transverse sections over the face width (at least 9).
    pub sections: usize,
    /// Outline tolerance the polar sampling is chosen for, µm.
    pub outline_um: f64,
    /// The removal's resolution.
    pub resolution: Resolution,
    /// What the trace does not say about the machine.
    pub rates: MachineRates,
    /// The what-if errors of the machine and the hob (zero: ideal).
    pub errors: MachineErrors,
    /// What the hob record does not say (gashes, tip radius).
    pub hob: HobExtras,
    /// Threads the run may use (0: one per core): the sections are shared
    /// among them, each cut by one (a section cut all round while fewer
    /// such sections than threads are, as windows going round it), and the
    /// safety rules run beside the cut. The result is the same with any
    /// number (to 10⁻⁹ mm, `docs/simulation.md` §3; bit for bit in the
    /// tests).
    pub threads: usize,
    /// Trace profile and helix on four teeth a quarter turn apart outside
    /// the middle section, as a gear-measuring machine does, instead of on
    /// every tooth: the middle section (pitch, runout, size, every tooth's
    /// profile) is cut all round first, then the others only about those
    /// teeth. A worm wheel's throat section alone is cut.
    pub four_teeth: bool,
}

impl Settings {
    /// The proof a delivered program carries: 9 sections, the outline
    /// within 1 µm, the fine removal.
    pub fn fine() -> Settings {
        Settings {
            mode: "fine",
            sections: 9,
            outline_um: 1.0,
            resolution: Resolution::fine(),
            rates: MachineRates::default(),
            errors: MachineErrors::default(),
            hob: HobExtras::default(),
            threads: 0,
            four_teeth: false,
        }
    }

    /// The threads to run on: [`Settings::threads`], or one per core.
    pub fn thread_count(&self) -> usize {
        match self.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n,
        }
    }

    /// A quick look: 9 sections, the outline within about 10 µm, the coarse
    /// removal, profile and helix traced on four teeth outside the middle
    /// section.
    pub fn coarse() -> Settings {
        Settings {
            mode: "coarse",
            outline_um: 10.0,
            resolution: Resolution::coarse(),
            four_teeth: true,
            ..Settings::fine()
        }
    }
}

/// What the run left: the cut blank, the measured gear, the safety findings.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The settings it ran with.
    pub settings: Settings,
    /// The cut blank.
    pub blank: Blank,
    /// Gash passes cut.
    pub passes: u64,
    /// The drawing the gear was measured against.
    pub spec: GearSpec,
    /// The measurement, or why the cut gear could not be measured (a wrong
    /// tooth count, a gap not cut: the gear is visibly wrong).
    pub measurement: Result<Measurement, String>,
    /// The safety findings, by line.
    pub safety: Vec<SafetyFinding>,
    /// The class the drawing asks for.
    pub required_grade: u8,
    /// The gear's name on a part of several gears (`None` for a single
    /// gear).
    pub unit: Option<String>,
    /// How far the measurement goes, where it does not go all the way (a
    /// worm wheel's).
    pub note: Option<String>,
    /// The sections of `blank` the gear was measured in (all but a worm
    /// wheel's), by index.
    pub measured: Vec<usize>,
    /// The teeth profile and helix were traced on outside the middle
    /// section (`None`: every tooth); the sections other than the middle
    /// one were cut only about them ([`Settings::four_teeth`]).
    pub traced: Option<Vec<usize>>,
}

impl Simulation {
    /// The outlines of the sections the gear was measured in.
    pub fn measured_sections(&self) -> PolarSections {
        sections_of(&self.blank, &self.measured)
    }
}

/// The outlines of `blank`'s sections `which`, by index.
fn sections_of(blank: &Blank, which: &[usize]) -> PolarSections {
    PolarSections {
        z_mm: which.iter().map(|&j| blank.z_mm[j]).collect(),
        r_mm: which.iter().map(|&j| blank.r_mm[j].clone()).collect(),
    }
}

/// The sections the gear is measured in (indices into the blank's), and a
/// note when that is not all of them: a worm wheel is measured in its throat plane alone. Its teeth
/// are throated (each section away from the throat is cut by another part
/// of the hob, so no helix runs across them), while in the throat plane
/// the straight-sided axial section of the hob (its gashes are axial
/// planes) generates the involute of a cylindrical gear of the wheel's
/// transverse data, which is measured there: profile, pitch, runout and
/// size, no helix.
fn measured_sections(blank: &Blank, model: &MachiningModel) -> (Vec<usize>, Option<String>) {
    let Some(worm) = &model.model.worm else {
        return ((0..blank.z_mm.len()).collect(), None);
    };
    let throat = (0..blank.z_mm.len())
        .min_by(|&a, &b| {
            let d = |j: usize| (blank.z_mm[j] - worm.throat_z_mm).abs();
            d(a).total_cmp(&d(b))
        })
        .unwrap_or(0);
    let note = format!(
        "a worm wheel: measured in its throat plane (Z {:.3}) as the cylindrical gear of its transverse data, no helix; ISO 1328-1 does not cover worm wheels, so its classes are an indication",
        blank.z_mm[throat]
    );
    (vec![throat], Some(note))
}

/// Runs `trace` (the program read back against `model`) on the machine
/// model and measures the gear it cuts: on a part of several gears, the
/// first ([`simulate_part`] gives them all).
pub fn simulate(
    trace: &Trace,
    model: &MachiningModel,
    settings: &Settings,
) -> Result<Simulation, SimError> {
    let mut all = simulate_part(trace, model, settings)?;
    Ok(all.swap_remove(0))
}

/// Runs `trace` on the machine model and measures every gear of the part
/// it cuts, in the model's order. Each gear's blank is cut by every hob of
/// the program along the moves made with it (the hob of the gear whose
/// coupling started last, as the path check mounts them); the safety
/// findings of the whole run go with the first gear.
pub fn simulate_part(
    trace: &Trace,
    model: &MachiningModel,
    settings: &Settings,
) -> Result<Vec<Simulation>, SimError> {
    if settings.sections < 9 {
        return Err(SimError::Parameter(
            "sections",
            "at least 9 across the face",
        ));
    }
    let timeline = kinematics::from_trace_with(trace, model, settings.rates, settings.errors)?;
    let units = unit_models(model);
    let setups = units
        .iter()
        .map(|(name, m)| {
            let hob = Hob::from_data(&m.plan.hob, settings.hob)?;
            Ok((name.clone(), hob, BlankGeometry::of_model(m)))
        })
        .collect::<Result<Vec<safety::UnitSetup>, SimError>>()?;
    let mounted = mounted_units(&timeline, units.len());
    let span = setups
        .iter()
        .skip(1)
        .fold(setups[0].2, |a, (_, _, b)| BlankGeometry {
            z_lo_mm: a.z_lo_mm.min(b.z_lo_mm),
            z_hi_mm: a.z_hi_mm.max(b.z_hi_mm),
            ..a
        });
    let fixtures = Fixtures::of_model(model, &span);
    let mine: Vec<Vec<bool>> = (0..units.len())
        .map(|j| safety::moves_with(&mounted, j))
        .collect();
    let threads = settings.thread_count();
    // The safety rules on one thread beside the cut on the others.
    let check = || safety::check_part(&timeline, &setups, &mounted, &fixtures);
    let cut_all = |threads: usize| -> Result<Vec<CutUnit>, SimError> {
        // Every hob of the part along its own moves.
        let cut_by_all = |blank: &mut Blank, wanted: &[Wanted]| {
            let mut passes = 0;
            for ((_, hob, _), mine) in setups.iter().zip(&mine) {
                passes += cut::cut_segments(
                    &timeline,
                    hob,
                    blank,
                    settings.resolution,
                    mine,
                    (wanted, threads),
                )?;
            }
            Ok(passes)
        };
        units
            .iter()
            .map(|(_, m)| cut_unit(&cut_by_all, m, settings))
            .collect()
    };
    let (mut safety, cut) = if threads > 1 {
        std::thread::scope(|scope| {
            let checked = scope.spawn(check);
            let cut = cut_all(threads);
            (
                checked
                    .join()
                    .unwrap_or_else(|p| std::panic::resume_unwind(p)),
                cut,
            )
        })
    } else {
        (check(), cut_all(1))
    };
    let mut out = Vec::with_capacity(units.len());
    for ((name, m), (blank, passes, traced)) in units.iter().zip(cut?) {
        let spec = drawing(m);
        let (measured, note) = measured_sections(&blank, m);
        let note = note.or_else(|| traced.as_deref().map(traced_note));
        let sections = sections_of(&blank, &measured);
        let measurement =
            outline::measure_traced(&sections, &spec, traced.as_deref()).map_err(|e| e.to_string());
        out.push(Simulation {
            settings: *settings,
            blank,
            passes,
            spec,
            measurement,
            safety: std::mem::take(&mut safety),
            required_grade: m.plan.gear.quality_grade,
            unit: name.clone(),
            note,
            measured,
            traced,
        });
    }
    Ok(out)
}

/// What a run that traced only `teeth` (numbered from 0) measured, for a
/// planner: the teeth numbered from 1, as the charts print them.
fn traced_note(teeth: &[usize]) -> String {
    let names: Vec<String> = teeth.iter().map(|t| (t + 1).to_string()).collect();
    format!(
        "profile and helix traced on teeth {} outside the middle section, as a gear-measuring machine traces them (the other sections cut only about those teeth); pitch, runout, size and the middle section's profile on every tooth",
        names.join(", ")
    )
}

/// Cuts a blank's sections as told, returning the gash passes.
type CutBlank<'a> = dyn Fn(&mut Blank, &[Wanted]) -> Result<u64, SimError> + 'a;

/// One gear's cut blank, the gash passes that cut it, and the teeth traced
/// outside its middle section when not every one is.
type CutUnit = (Blank, u64, Option<Vec<usize>>);

/// Cuts the blank of the gear `model` with `cut` (which cuts a blank's
/// sections as it is told, returning the gash passes). All round, unless
/// [`Settings::four_teeth`]: then the section measured as the middle one
/// first, all round, and the others only within the windows about the
/// four teeth found there ([`outline::trace_windows`]); a worm wheel's
/// throat section alone. Where the middle section's teeth cannot be found
/// (a gear the measurement will refuse), the others are cut all round, so
/// the outlines shown are the whole cut.
fn cut_unit(
    cut: &CutBlank<'_>,
    model: &MachiningModel,
    settings: &Settings,
) -> Result<CutUnit, SimError> {
    let mut blank = unit_blank(model, settings)?;
    if !settings.four_teeth {
        let passes = cut(&mut blank, &[])?;
        return Ok((blank, passes, None));
    }
    let (measured, _) = measured_sections(&blank, model);
    let spec = drawing(model);
    let heights: Vec<f64> = measured.iter().map(|&j| blank.z_mm[j]).collect();
    let Ok(k) = outline::middle_section(&heights, &spec) else {
        let passes = cut(&mut blank, &[])?;
        return Ok((blank, passes, None));
    };
    let first = measured[k];
    let n = blank.z_mm.len();
    let nothing = || Wanted::Within(Vec::new());
    let wanted: Vec<Wanted> = (0..n)
        .map(|j| {
            if j == first {
                Wanted::Everywhere
            } else {
                nothing()
            }
        })
        .collect();
    let passes = cut(&mut blank, &wanted)?;
    if measured.len() < 2 {
        return Ok((blank, passes, None));
    }
    let teeth = outline::four_teeth(spec.teeth as usize);
    let sections = sections_of(&blank, &measured);
    let (rest, traced): (Vec<Wanted>, _) = match outline::trace_windows(&sections, &spec, &teeth) {
        Ok(windows) => {
            let mut rest = vec![nothing(); n];
            for (&j, w) in measured.iter().zip(windows) {
                if j != first {
                    rest[j] = Wanted::Within(w);
                }
            }
            (rest, Some(teeth))
        }
        Err(_) => {
            let rest = (0..n)
                .map(|j| {
                    if j == first {
                        nothing()
                    } else {
                        Wanted::Everywhere
                    }
                })
                .collect();
            (rest, None)
        }
    };
    cut(&mut blank, &rest)?;
    Ok((blank, passes, traced))
}

/// Each gear of the part as a model of its own (its gear, hob, geometry
/// and kinematics in place of the first's), named when there are several.
fn unit_models(model: &MachiningModel) -> Vec<(Option<String>, MachiningModel)> {
    if model.model.units.is_empty() {
        return vec![(None, model.clone())];
    }
    model
        .model
        .units
        .iter()
        .map(|u| {
            let mut m = model.clone();
            m.plan.gear = u.gear.clone();
            m.plan.hob = u.hob.clone();
            m.geometry = u.geometry.clone();
            m.model = u.model.clone();
            m.model.units.clear();
            (Some(u.name.clone()), m)
        })
        .collect()
}

/// The unit whose hob is mounted during each segment: that of the last
/// coupling started at or before it (the first unit's before any).
fn mounted_units(timeline: &kinematics::Timeline, units: usize) -> Vec<usize> {
    let phases = timeline.couplings();
    let mut k = 0;
    let mut unit = 0;
    (0..timeline.segments().len())
        .map(|i| {
            while k < phases.len() && phases[k].segment <= i {
                unit = phases[k].unit.min(units.saturating_sub(1));
                k += 1;
            }
            unit
        })
        .collect()
}

/// The uncut blank of a gear: its outer diameter, `settings.sections`
/// sections over its face width inset by the helix evaluation range's
/// exclusion. A conical gear's blank is a cone: each section starts at the
/// cone's radius there, the outer diameter being the large end's.
fn unit_blank(model: &MachiningModel, settings: &Settings) -> Result<Blank, SimError> {
    let g = &model.plan.gear;
    let inset = (0.05 * g.face_width_mm).min(g.module_mm);
    let z = Blank::planes(
        g.fixture_height_mm + inset,
        g.fixture_height_mm + g.face_width_mm - inset,
        settings.sections,
    );
    let outer = model.model.blank_od_mm / 2.0;
    let mut blank = Blank::new(z, outer, samples_for(outer, settings.outline_um))?;
    let (taper, large_end_mm) = safety::cone_of(model);
    for (r, z) in blank.r_mm.iter_mut().zip(&blank.z_mm) {
        let here = outer + taper * (z - large_end_mm);
        r.iter_mut().for_each(|r| *r = here);
    }
    Ok(blank)
}

/// The drawing of the model's gear, measured with the default choices.
pub fn drawing(model: &MachiningModel) -> GearSpec {
    let g = &model.plan.gear;
    let geo = &model.geometry;
    let hand = match (g.helix_angle_deg.abs() > 0.0, g.helix_hand) {
        (false, _) => None,
        (true, Some(Hand::Left)) => Some(MeasureHand::Left),
        (true, _) => Some(MeasureHand::Right),
    };
    // A conical gear's drawing holds at its large end; the spec's is that
    // of the middle of the face, where the rack stands `mid` further out.
    // Its teeth are a spur gear's generated by the hob's rack as it stands
    // in a transverse section, its depths stretched by 1/cos δ
    // (gearcam_model::path::cone_offsets): flanks at tan α′ = tan αn·cos δ,
    // the thickness of the shift's rack position at that angle.
    let (taper, large_end_mm) = safety::cone_of(model);
    let mid = taper * (g.fixture_height_mm + g.face_width_mm / 2.0 - large_end_mm);
    let (alpha, thickness) = match &model.model.cone {
        Some(c) => (
            (g.pressure_angle_deg.to_radians().tan() * c.angle_deg.to_radians().cos())
                .atan()
                .to_degrees(),
            None,
        ),
        None => (g.pressure_angle_deg, Some(geo.sn_mm)),
    };
    GearSpec {
        normal_pressure_angle_deg: alpha,
        profile_shift: g.profile_shift + mid / g.module_mm,
        face_start_mm: g.fixture_height_mm,
        // A blank smaller than the tip circle is the gear's tip (topped).
        tip_diameter_mm: geo.da_mm.min(model.model.blank_od_mm) + 2.0 * mid,
        root_diameter_mm: geo.df_mm + 2.0 * mid,
        normal_thickness_mm: thickness,
        helix_crowning_mm: helix_crowning_mm(model),
        taper,
        ..GearSpec::standard(
            g.teeth,
            g.module_mm,
            g.helix_angle_deg.abs(),
            hand,
            g.face_width_mm,
        )
    }
}

/// The crowning of the model's flanks along the base tangent in the
/// transverse plane, mm: the hob stands Cb further out (X) in the middle of
/// the face than at the faces, and a rack moved out by ΔX leaves each flank
/// ΔX·sin αn further into its space normal to the flank, ΔX·sin αn/cos βb =
/// ΔX·sin αt along the transverse base tangent.
fn helix_crowning_mm(model: &MachiningModel) -> f64 {
    let Some(c) = &model.model.crowning else {
        return 0.0;
    };
    let g = &model.plan.gear;
    let alpha_t =
        (g.pressure_angle_deg.to_radians().tan() / g.helix_angle_deg.to_radians().cos()).atan();
    c.amount_mm * alpha_t.sin()
}

impl Simulation {
    /// The report the program carries; `ms` is the run's wall time as the
    /// caller measured it.
    pub fn report(&self, ms: f64) -> SimulationReport {
        let class = |g: Grade| match g {
            Grade::Class(c) => Some(c.number()),
            Grade::WorseThan11 => None,
        };
        let (grade, deviations, sizes, not_measured) = match &self.measurement {
            Ok(m) => (
                class(m.overall),
                m.items
                    .iter()
                    .map(|i| Deviation {
                        item: outline::symbol(i.item).to_string(),
                        value_um: i.value_um,
                        tolerance_um: i.tolerance_um,
                        class: class(i.grade),
                    })
                    .collect(),
                Some(m.size),
                None,
            ),
            Err(why) => (None, Vec::new(), None, Some(why.clone())),
        };
        let e = &self.settings.errors;
        let what_if = [
            ("centre-distance offset", e.centre_distance_mm, "mm"),
            ("swivel offset", e.swivel_deg, "°"),
            ("hob radial runout", e.hob_radial_mm, "mm"),
            ("hob axial runout", e.hob_axial_mm, "mm"),
            ("table runout", e.table_mm, "mm"),
        ]
        .iter()
        .filter(|(_, v, _)| *v != 0.0)
        .map(|(name, v, unit)| format!("{name} {v} {unit}"))
        .collect();
        SimulationReport {
            mode: self.settings.mode.to_string(),
            what_if,
            grade,
            required_grade: self.required_grade,
            deviations,
            not_measured,
            safety: self
                .safety
                .iter()
                .map(|f| SafetyIssue {
                    kind: kind_name(f.kind).to_string(),
                    line: f.line,
                    what: f.what.clone(),
                    why: f.why.clone(),
                })
                .collect(),
            sections: self.blank.z_mm.len() as u32,
            samples_per_section: self.blank.r_mm.first().map_or(0, Vec::len) as u32,
            passes: self.passes,
            thickness_mm: sizes.map(|s| (s.thickness_mm, s.design_thickness_mm)),
            span_mm: sizes.map(|s| (s.span_mm, s.span_design_mm)),
            over_balls_mm: sizes.map(|s| (s.over_balls_mm, s.over_balls_design_mm)),
            ms,
            unit: self.unit.clone(),
            note: self.note.clone(),
            units: Vec::new(),
        }
    }
}

/// The report of a whole part ([`simulate_part`]'s gears, at least one):
/// the first gear's, with the others' in `units`.
pub fn part_report(gears: &[Simulation], ms: f64) -> SimulationReport {
    let mut first = gears[0].report(ms);
    first.units = gears[1..].iter().map(|g| g.report(ms)).collect();
    first
}

/// The report's name of a finding's kind.
fn kind_name(kind: SafetyKind) -> &'static str {
    match kind {
        SafetyKind::RapidContact => "rapid_contact",
        SafetyKind::CutDecoupled => "cut_decoupled",
        SafetyKind::CutWrongRatio => "cut_wrong_ratio",
        SafetyKind::FixtureContact => "fixture_contact",
        SafetyKind::DepthNotReached => "depth_not_reached",
        SafetyKind::FaceWidthNotCovered => "face_width_not_covered",
        SafetyKind::UncompensatedShift => "uncompensated_shift",
        SafetyKind::UnsynchronisedCoupling => "unsynchronised_coupling",
    }
}
