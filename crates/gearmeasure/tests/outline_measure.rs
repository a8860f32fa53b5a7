//! The outline measurement (gearcam_gearmeasure::outline) against gears
//! built here from the involute's polar form alone: a tooth's right flank
//! (facing +θ) at radius ρ lies at the angle ψb − inv α(ρ) from the tooth's
//! centre, cos α = rb/ρ, its left flank at the mirror angle; the tip and
//! root are circles; a helical gear's teeth turn by h·z·tan β / r. Known
//! errors are put into the construction one at a time (a base radius, a
//! waviness, a shifted tooth, an eccentricity, a lead, the hand) and the
//! measurement must return them, with the values derived in each test.
//! Nothing of the measurement code is used to build the gears.

use gearcam_gearmeasure::helix::{helix_angle_sign, Flank, Hand};
use gearcam_gearmeasure::iso1328::{Grade, Item};
use gearcam_gearmeasure::outline::{measure, Direction, GearSpec, Measurement, PolarSections};
use gearcam_gearmeasure::profile::EvaluationRange;
use gearcam_gearmeasure::size::Involute;
use std::f64::consts::{PI, TAU};

/// inv α from the roll length L on the base radius rb: tan α − α with
/// tan α = L/rb.
fn inv_of_roll(l: f64, rb: f64) -> f64 {
    l / rb - (l / rb).atan()
}

/// One flank side of the built gear.
#[derive(Clone, Copy)]
struct Side {
    /// Base radius, mm.
    rb: f64,
    /// Half angle of the tooth on the base circle, rad.
    psi_b: f64,
    /// Waviness e(L) = amp·cos(2π·k·(L − l0)/(l1 − l0)) along the design
    /// roll length, mm: (amp, k, l0, l1).
    wave: Option<(f64, f64, f64, f64)>,
}

/// A gear built point by point.
#[derive(Clone)]
struct Built {
    z: usize,
    /// Design base radius (the waviness's abscissa), mm.
    rb: f64,
    ra: f64,
    rf: f64,
    right: Side,
    left: Side,
    /// Turn of the teeth per mm of height, rad (h·tan β / r).
    twist: f64,
    /// Extra turn of each tooth, rad.
    shift: Vec<f64>,
    /// The gear's centre, mm.
    ecc: [f64; 2],
    /// One tooth whose right flank differs: (tooth, its side).
    odd_tooth: Option<(usize, Side)>,
    /// Crowning: every flank stands amount·(1 − (2·z/b − 1)²) further into
    /// its space along the base tangent at height z: (amount mm, b mm).
    crown: (f64, f64),
    /// A cone: at height z the tip and root circles and the generating
    /// rack stand taper·(z − b/2) further out than in the middle of the
    /// face: (taper mm per mm, b mm).
    cone: (f64, f64),
    /// tan αn / (r·cos β): the half-angle a tooth gains on every circle
    /// for each mm its rack stands further out (its normal thickness
    /// grows by 2·tan αn per mm, its transverse one by 2·tan αn / cos β).
    thickening: f64,
}

impl Built {
    /// The design gear of `spec` (thickness from the shift, no thinning).
    fn new(spec: &GearSpec) -> Built {
        let (mn, an, beta) = (
            spec.normal_module_mm,
            spec.normal_pressure_angle_deg.to_radians(),
            spec.helix_deg.to_radians(),
        );
        let z = spec.teeth as usize;
        let r = z as f64 * mn / beta.cos() / 2.0;
        let at = (an.tan() / beta.cos()).atan();
        let rb = r * at.cos();
        let sn = mn * (PI / 2.0 + 2.0 * spec.profile_shift * an.tan());
        // Half the transverse arc thickness at r, carried down the involute.
        let psi_b = sn / beta.cos() / (2.0 * r) + (at.tan() - at);
        let h = match spec.hand {
            Some(Hand::Right) => 1.0,
            Some(Hand::Left) => -1.0,
            None => 0.0,
        };
        let side = Side {
            rb,
            psi_b,
            wave: None,
        };
        Built {
            z,
            rb,
            ra: spec.tip_diameter_mm / 2.0,
            rf: spec.root_diameter_mm / 2.0,
            right: side,
            left: side,
            twist: h * beta.tan() / r,
            shift: vec![0.0; z],
            ecc: [0.0, 0.0],
            odd_tooth: None,
            crown: (0.0, spec.face_width_mm),
            cone: (0.0, spec.face_width_mm),
            thickening: an.tan() / (r * beta.cos()),
        }
    }

    /// How far the rack stands further out at `height` than in the middle
    /// of the face, mm.
    fn cone_offset(&self, height: f64) -> f64 {
        let (taper, b) = self.cone;
        taper * (height - b / 2.0)
    }

    /// The angle of the flank of `side` at radius `rho` from the tooth's
    /// centre (≥ 0), or None below its base circle.
    fn flank_angle(&self, s: &Side, rho: f64) -> Option<f64> {
        if rho < s.rb {
            return None;
        }
        let l = (rho * rho - s.rb * s.rb).sqrt();
        let mut a = s.psi_b - inv_of_roll(l, s.rb);
        if let Some((amp, k, l0, l1)) = s.wave {
            let ld = (rho * rho - self.rb * self.rb).max(0.0).sqrt();
            a += amp * (TAU * k * (ld - l0) / (l1 - l0)).cos() / s.rb;
        }
        Some(a)
    }

    /// The outline radius at the angle `delta` (≥ 0) from a tooth's centre
    /// on `side`: the tip where the flank at the tip is further out, the
    /// root where the flank at the base (or root) circle is nearer, else
    /// the radius where the flank is at `delta`, by bisection on ρ (the
    /// flank angle falls as ρ grows).
    fn side_radius(&self, s: &Side, delta: f64, height: f64) -> f64 {
        let (ra, rf) = (
            self.ra + self.cone_offset(height),
            self.rf + self.cone_offset(height),
        );
        let low = s.rb.max(rf);
        if delta <= self.flank_angle(s, ra).unwrap_or(f64::NEG_INFINITY) {
            return ra;
        }
        match self.flank_angle(s, low) {
            Some(a) if delta <= a => {}
            _ => return rf,
        }
        let (mut lo, mut hi) = (low, ra);
        for _ in 0..60 {
            let m = (lo + hi) / 2.0;
            if self.flank_angle(s, m).unwrap_or(f64::INFINITY) >= delta {
                lo = m;
            } else {
                hi = m;
            }
        }
        (lo + hi) / 2.0
    }

    /// The outline radius at angle `theta` about the gear's own centre, at
    /// height `height`.
    fn radius_own(&self, theta: f64, height: f64) -> f64 {
        let pitch = TAU / self.z as f64;
        let t = theta - self.twist * height;
        let j = (t / pitch).round().rem_euclid(self.z as f64) as usize;
        let mut delta = t - j as f64 * pitch - self.shift[j];
        delta -= TAU * (delta / TAU).round();
        // A flank moved out by c along the base tangent is turned by c/rb.
        let (c, b) = self.crown;
        let turn = c * (1.0 - (2.0 * height / b - 1.0).powi(2)) / self.rb
            + self.cone_offset(height) * self.thickening;
        if delta >= 0.0 {
            let side = match self.odd_tooth {
                Some((k, side)) if k == j => side,
                _ => self.right,
            };
            self.side_radius(&side, (delta - turn).max(0.0), height)
        } else {
            self.side_radius(&self.left, (-delta - turn).max(0.0), height)
        }
    }

    /// The outline radius at angle `theta` about the measuring axis: the
    /// point r·(cos θ, sin θ) minus the gear's centre is on the outline,
    /// solved by iterating r ← r + R(θ′) − r′ (θ′, r′ the point's polar
    /// coordinates about the gear's centre).
    fn radius(&self, theta: f64, height: f64) -> f64 {
        let mut r = self.radius_own(theta, height);
        if self.ecc == [0.0, 0.0] {
            return r;
        }
        for _ in 0..20 {
            let p = [r * theta.cos() - self.ecc[0], r * theta.sin() - self.ecc[1]];
            let (rr, tt) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
            let step = self.radius_own(tt, height) - rr;
            r += step;
            if step.abs() < 1e-13 {
                break;
            }
        }
        r
    }

    fn sections(&self, z_mm: &[f64], n: usize) -> PolarSections {
        let r_mm = z_mm
            .iter()
            .map(|&h| {
                (0..n)
                    .map(|i| self.radius(TAU * i as f64 / n as f64, h))
                    .collect()
            })
            .collect();
        PolarSections {
            z_mm: z_mm.to_vec(),
            r_mm,
        }
    }
}

/// Spur, z = 24, mn = 3, x = +0.2, b = 20: one section.
fn spur() -> GearSpec {
    let mut s = GearSpec::standard(24, 3.0, 0.0, None, 20.0);
    s.profile_shift = 0.2;
    s.tip_diameter_mm += 2.0 * 0.2 * 3.0;
    s.root_diameter_mm += 2.0 * 0.2 * 3.0;
    s
}

/// Helical, z = 31, mn = 2.5, β = 15° right hand, x = −0.1, b = 20.
fn helical(hand: Hand) -> GearSpec {
    let mut s = GearSpec::standard(31, 2.5, 15.0, Some(hand), 20.0);
    s.profile_shift = -0.1;
    s.tip_diameter_mm -= 2.0 * 0.1 * 2.5;
    s.root_diameter_mm -= 2.0 * 0.1 * 2.5;
    s
}

/// Sections every mm over the face.
fn faces(spec: &GearSpec) -> Vec<f64> {
    (0..=spec.face_width_mm as usize)
        .map(|i| i as f64)
        .collect()
}

const N: usize = 16384;

fn value(m: &Measurement, item: Item) -> f64 {
    m.item(item).map(|i| i.value_um).unwrap_or(f64::NAN)
}

/// Every flank item's magnitude is below `tol` µm.
fn assert_flanks_clean(m: &Measurement, tol: f64) {
    for i in &m.items {
        assert!(
            i.value_um.abs() <= tol,
            "{:?} = {} µm, expected ≤ {tol}\n{m}",
            i.item,
            i.value_um
        );
    }
}

#[test]
fn a_perfect_spur_gear_measures_perfect_with_its_design_size() {
    let spec = spur();
    let m = measure(&Built::new(&spec).sections(&[10.0], N), &spec).unwrap();
    assert!(m.helix.is_none());
    assert_flanks_clean(&m, 0.05);
    let inv = Involute::new(24, 3.0, 20.0, 0.0).unwrap();
    let sn = inv.thickness_from_shift(0.2);
    let s = m.size;
    // Sizes within 0.1 µm (1e-4 mm).
    assert!((s.thickness_mm - sn).abs() < 1e-4, "{s:?}");
    assert!(
        (s.span_mm - inv.span_mm(s.span_teeth, sn).unwrap()).abs() < 1e-4,
        "{s:?}"
    );
    let md = inv.over_balls_mm(s.ball_diameter_mm, sn).unwrap();
    assert!((s.over_balls_mm - md).abs() < 1e-4, "{s:?}");
    assert!(
        (s.span_thickness_mm - sn).abs() < 1e-4 && (s.over_balls_thickness_mm - sn).abs() < 1e-4
    );
    assert!(matches!(m.overall, Grade::Class(c) if c.number() == 1));
}

#[test]
fn the_report_lists_every_item_and_survives_json() {
    let spec = helical(Hand::Right);
    let m = measure(&Built::new(&spec).sections(&faces(&spec), 4096), &spec).unwrap();
    assert_eq!(m.items.len(), 9);
    let text = m.to_string();
    for sym in [
        "fp ", "Fp ", "fHα", "ffα", "Fα ", "fHβ", "ffβ", "Fβ ", "Fr ", "overall", "W4",
    ] {
        assert!(text.contains(sym), "{sym} missing from\n{text}");
    }
    let json = serde_json::to_string(&m).unwrap();
    let back: Measurement = serde_json::from_str(&json).unwrap();
    assert_eq!(back.items, m.items);
    assert_eq!(back.overall, m.overall);
    // serde_json's float parsing is not exact to the last bit.
    let (a, b) = (back.size, m.size);
    for (x, y) in [
        (a.span_mm, b.span_mm),
        (a.over_balls_mm, b.over_balls_mm),
        (a.design_thickness_mm, b.design_thickness_mm),
    ] {
        assert!((x - y).abs() < 1e-12 * y.abs());
    }
    assert_eq!(back.pitch.left.cumulative_um.len(), 31);
}

#[test]
fn a_perfect_helical_gear_measures_perfect_in_every_section() {
    for hand in [Hand::Right, Hand::Left] {
        let spec = helical(hand);
        let m = measure(&Built::new(&spec).sections(&faces(&spec), N), &spec).unwrap();
        let h = m.helix.as_ref().expect("helix measured");
        assert_eq!(h.left.len(), 31);
        assert_flanks_clean(&m, 0.05);
        // The profile of every section, each tooth followed up the helix.
        assert_eq!(m.profile_by_section.len(), 21);
        for p in &m.profile_by_section {
            assert!(p.total_um <= 0.05 && p.slope_um.abs() <= 0.05, "{p:?}");
        }
        let inv = Involute::new(31, 2.5, 20.0, 15.0).unwrap();
        let sn = inv.thickness_from_shift(-0.1);
        let s = m.size;
        assert!((s.thickness_mm - sn).abs() < 1e-4, "{s:?}");
        assert!(
            (s.span_mm - inv.span_mm(s.span_teeth, sn).unwrap()).abs() < 1e-4,
            "{s:?}"
        );
        let md = inv.over_balls_mm(s.ball_diameter_mm, sn).unwrap();
        assert!((s.over_balls_mm - md).abs() < 1e-4, "{s:?} {md}");
    }
}

#[test]
fn a_larger_base_circle_is_a_profile_slope() {
    // Flanks on rb' = rb·(1 + ε), as thick at the reference circle: at the
    // radius ρ the flank is turned by inv α(ρ) − inv α'(ρ) ≈ tan α·Δrb/rb
    // (d inv α / d rb = −tan α / rb at fixed ρ), so it deviates by
    // e = rb·tan α·ε = ε·L (+material towards the tip, both flanks):
    // fHα = ε·(L1 − L0), Fα the same, ffα of second order in ε.
    let spec = spur();
    let mut g = Built::new(&spec);
    let eps = 2e-4;
    let r = 24.0 * 3.0 / 2.0;
    let at = 20.0_f64.to_radians();
    for s in [&mut g.right, &mut g.left] {
        let psi_r = s.psi_b - (at.tan() - at);
        s.rb *= 1.0 + eps;
        let l = (r * r - s.rb * s.rb).sqrt();
        s.psi_b = psi_r + inv_of_roll(l, s.rb);
    }
    let m = measure(&g.sections(&[10.0], N), &spec).unwrap();
    let range = m.geometry.profile_range;
    let expected = eps * (range.end_mm - range.start_mm) * 1000.0;
    for d in m.profile.left.iter().chain(&m.profile.right) {
        assert!(
            (d.slope_um - expected).abs() < 0.01 * expected,
            "{d:?} vs {expected}"
        );
        assert!((d.total_um - expected).abs() < 0.01 * expected);
        assert!(d.form_um < 0.05, "{d:?}");
    }
    assert!((m.profile_slope_mean_um.left - expected).abs() < 0.01 * expected);
    assert!(value(&m, Item::SinglePitch) < 0.05);
    // The same on the right flank of one tooth only: the graded fHα is that
    // flank's (the worst), the mean over the right flanks 1/24 of it.
    let mut one = Built::new(&spec);
    one.odd_tooth = Some((5, g.right));
    let m = measure(&one.sections(&[10.0], N), &spec).unwrap();
    assert!(
        (value(&m, Item::ProfileSlope) - expected).abs() < 0.01 * expected,
        "{m}"
    );
    assert!((value(&m, Item::ProfileTotal) - expected).abs() < 0.01 * expected);
    assert!((m.profile_slope_mean_um.right - expected / 24.0).abs() < 0.01 * expected);
    assert!(m.profile_slope_mean_um.left.abs() < 0.05);
}

#[test]
fn a_waviness_on_the_right_flanks_is_their_form_deviation() {
    // e(L) = A·cos(2π·3·(L − L0)/(L1 − L0)) over the range: symmetric about
    // its middle, so its least-squares line is flat; the form and total
    // deviations are 2A, the slope 0; the left flanks stay clean.
    let mut spec = spur();
    let (l0, l1) = (6.0, 14.0);
    spec.profile_range = Some(EvaluationRange {
        start_mm: l0,
        end_mm: l1,
    });
    let mut g = Built::new(&spec);
    let amp = 0.002;
    g.right.wave = Some((amp, 3.0, l0, l1));
    let m = measure(&g.sections(&[10.0], N), &spec).unwrap();
    for d in &m.profile.right {
        assert!((d.form_um - 2000.0 * amp).abs() < 0.05, "{d:?}");
        assert!((d.total_um - 2000.0 * amp).abs() < 0.05, "{d:?}");
        assert!(d.slope_um.abs() < 0.05, "{d:?}");
    }
    for d in &m.profile.left {
        assert!(d.form_um < 0.05 && d.total_um < 0.05, "{d:?}");
    }
    assert!((value(&m, Item::ProfileForm) - 4.0).abs() < 0.05);
}

#[test]
fn one_tooth_turned_10_um_is_one_pitch_up_and_the_next_down() {
    let spec = spur();
    let mut g = Built::new(&spec);
    let rho = m_diameter(&spec) / 2.0;
    g.shift[7] = 0.010 / rho;
    let m = measure(&g.sections(&[10.0], N), &spec).unwrap();
    for p in [&m.pitch.left, &m.pitch.right] {
        assert!((p.single_max_um - 10.0).abs() < 0.05, "{p:?}");
        assert!((p.cumulative_total_um - 10.0).abs() < 0.05, "{p:?}");
        // Tooth 7 of the construction: the tooth the measurement numbers 7
        // or 8 (its tooth 0 is the first from θ = 0; the construction's
        // tooth 0 is centred on θ = 0).
        let up = p.single_um.iter().position(|f| *f > 9.9).unwrap();
        assert!((p.single_um[(up + 1) % 24] + 10.0).abs() < 0.05);
    }
    assert!(value(&m, Item::ProfileTotal) < 0.05);
}

/// The measuring diameter of a spec: the middle of the tooth depth.
fn m_diameter(spec: &GearSpec) -> f64 {
    (spec.tip_diameter_mm + spec.root_diameter_mm) / 2.0
}

#[test]
fn an_eccentric_gear_has_runout_2e_and_a_sine_of_pitch() {
    // The gear's centre at e·(cos ε, sin ε), ε on the middle of a space
    // (z even: the opposite space too). A ball resting in a space keeps its
    // place on the gear, so its distance from the axis changes by
    // e·cos(γ − ε) to first order: Fr = 2e. A flank seen at the measuring
    // radius ρ from the axis is the gear's flank at ρ − e·cos(φ − ε),
    // turned by the eccentricity by −e·sin(φ − ε)/ρ, and along the
    // involute (dθ/dρ = ∓tan α/ρ, right/left) by n·tan α·e·cos(φ − ε)/ρ:
    // its position moves by e·[−sin(φ − ε) + n·tan αm·cos(φ − ε)] of arc.
    let spec = spur();
    let mut g = Built::new(&spec);
    let z = 24;
    let pitch = TAU / z as f64;
    let (e, eps) = (0.010, 5.5 * pitch);
    g.ecc = [e * eps.cos(), e * eps.sin()];
    let m = measure(&g.sections(&[10.0], N), &spec).unwrap();
    assert!(
        (m.runout.runout_um - 2000.0 * e).abs() < 0.05,
        "{:?}",
        m.runout
    );
    let rho = m_diameter(&spec) / 2.0;
    let rb = g.rb;
    let alpha_m = (rb / rho).acos();
    let half = g.right.psi_b - inv_of_roll((rho * rho - rb * rb).sqrt(), rb);
    for (n, p) in [(1.0, &m.pitch.right), (-1.0, &m.pitch.left)] {
        let pos: Vec<f64> = (0..z)
            .map(|i| {
                let phi = i as f64 * pitch + n * half - eps;
                1000.0 * e * (-phi.sin() + n * alpha_m.tan() * phi.cos())
            })
            .collect();
        let fp_total = pos.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - pos.iter().cloned().fold(f64::INFINITY, f64::min);
        let fp = (0..z)
            .map(|i| (pos[i] - pos[(i + z - 1) % z]).abs())
            .fold(0.0, f64::max);
        assert!(
            (p.cumulative_total_um - fp_total).abs() < 0.05,
            "{p:?} vs {fp_total}"
        );
        assert!((p.single_max_um - fp).abs() < 0.05, "{p:?} vs {fp}");
        // About 2e/cos αm.
        assert!((fp_total - 2000.0 * e / alpha_m.cos()).abs() < 0.1);
        // Tooth by tooth: the measurement's tooth 0 is the first whose left
        // flank is at θ ≥ 0, the construction's tooth 1 (its tooth 0 is
        // centred on θ = 0).
        for (i, f) in p.cumulative_um.iter().enumerate() {
            let want = pos[(i + 1) % z] - pos[1];
            assert!((f - want).abs() < 0.05, "tooth {i}: {f} vs {want}");
        }
    }
}

#[test]
fn a_steeper_lead_is_a_helix_slope_of_the_right_sign() {
    // Teeth turned by tan β' / r per mm instead of tan β / r: at the
    // measuring radius the flank is off by (tan β' − tan β)·z/r, e =
    // n·h·rb·(tan β' − tan β)/r·z along the base tangent, so fHβ =
    // n·h·cos αt·Δtan β·(Lβ1 − Lβ0), and by helix_angle_sign it reads as
    // steeper.
    for hand in [Hand::Right, Hand::Left] {
        let spec = helical(hand);
        let mut g = Built::new(&spec);
        let h = if hand == Hand::Right { 1.0 } else { -1.0 };
        let r = 31.0 * 2.5 / 15.0_f64.to_radians().cos() / 2.0;
        let dtan = 2e-4;
        g.twist += h * dtan / r;
        let m = measure(&g.sections(&faces(&spec), N), &spec).unwrap();
        let range = m.geometry.helix_range;
        let cos_at = 2.0 * g.rb / m.geometry.reference_diameter_mm;
        let hx = m.helix.as_ref().unwrap();
        for (flank, n, traces) in [
            (Flank::Right, 1.0, &hx.right),
            (Flank::Left, -1.0, &hx.left),
        ] {
            let expected = n * h * cos_at * dtan * (range.end_mm - range.start_mm) * 1000.0;
            for d in traces {
                assert!(
                    (d.slope_um - expected).abs() < 0.05,
                    "{hand:?} {flank:?} {d:?} vs {expected}"
                );
                assert!(d.form_um < 0.05);
                assert!(d.slope_um * helix_angle_sign(flank, hand) > 0.0);
            }
        }
        assert!(value(&m, Item::ProfileTotal) < 0.05);
    }
}

#[test]
fn a_crowned_helix_measures_clean_against_its_crowned_design_and_not_against_a_plain_one() {
    // Flanks crowned by c = 10 µm (parabola over the face): against a spec
    // with the same crowning the helix is clean; against a plain spec its
    // form is the parabola over the evaluation range, c·(1 − (2·x/b − 1)²)
    // less its best line: with the range x ∈ [x0, b − x0] symmetric, the
    // best line is level and the trace runs from c·(1 − u²) at the range's
    // ends (u = 2·x0/b − 1) to c in the middle: Fβ = ffβ = c·u².
    let c = 0.010;
    let plain = helical(Hand::Right);
    let crowned = GearSpec {
        helix_crowning_mm: c,
        ..plain
    };
    let mut g = Built::new(&plain);
    g.crown = (c, plain.face_width_mm);
    let clean = measure(&g.sections(&faces(&plain), N), &crowned).unwrap();
    assert!(value(&clean, Item::HelixTotal) < 0.05, "{:?}", clean.items);
    assert!(value(&clean, Item::HelixForm) < 0.05);
    let range = clean.geometry.helix_range;
    let u = 2.0 * range.start_mm / plain.face_width_mm - 1.0;
    let expected = c * u * u * 1000.0;
    let against_plain = measure(&g.sections(&faces(&plain), N), &plain).unwrap();
    assert!(
        (value(&against_plain, Item::HelixTotal) - expected).abs() < 0.05 * expected,
        "Fβ {} vs {expected}",
        value(&against_plain, Item::HelixTotal)
    );
    assert!(value(&against_plain, Item::HelixSlope).abs() < 0.05);
    // A plain gear against the crowned design misses the crowning as much.
    let flat = Built::new(&plain);
    let missing = measure(&flat.sections(&faces(&plain), N), &crowned).unwrap();
    assert!((value(&missing, Item::HelixTotal) - expected).abs() < 0.05 * expected);
}

#[test]
fn a_conical_gear_measures_clean_against_its_cone_in_every_section() {
    // A cone of 3° narrowing upwards over the face: the rack stands
    // tan 3° further in for every mm up, so the tip, the root and the
    // tooth thickness follow it. Against a spec with that taper every
    // section's profile and every helix are clean and the middle section
    // has its design size; against the same spec without the taper the
    // flanks lean: each stands Δ·tan αn / cos β = Δ·tan αt / r·rb further
    // into its space where the rack stood Δ further out, a helix slope of
    // −taper·sin αt over the evaluation range on both flanks (less
    // material towards the face where the rack stood further in).
    let taper = -3.0_f64.to_radians().tan();
    for hand in [Hand::Right, Hand::Left] {
        let plain = helical(hand);
        let conical = GearSpec { taper, ..plain };
        let mut g = Built::new(&plain);
        g.cone = (taper, plain.face_width_mm);
        // Twice the samples: the small end's profiles start nearer the base
        // circle, where the involute runs steeply through the samples.
        let sections = g.sections(&faces(&plain), 2 * N);
        let m = measure(&sections, &conical).unwrap();
        assert_flanks_clean(&m, 0.05);
        assert_eq!(m.profile_by_section.len(), 21);
        for p in &m.profile_by_section {
            assert!(p.total_um <= 0.05 && p.slope_um.abs() <= 0.05, "{p:?}");
        }
        let inv = Involute::new(31, 2.5, 20.0, 15.0).unwrap();
        let shift = -0.1 + taper * (m.middle_section_mm - 10.0) / 2.5;
        let sn = inv.thickness_from_shift(shift);
        assert!((m.size.thickness_mm - sn).abs() < 1e-4, "{:?}", m.size);
        // A section's own drawing: the shift follows the rack, and a
        // given thickness follows it as the shift's thickness does.
        let given = GearSpec {
            normal_thickness_mm: Some(inv.thickness_from_shift(-0.1)),
            ..conical
        };
        let top = given.at(18.0).unwrap();
        let x_top = -0.1 + taper * 8.0 / 2.5;
        assert!((top.profile_shift - x_top).abs() < 1e-12);
        let s_top = top.normal_thickness_mm.unwrap();
        assert!((s_top - inv.thickness_from_shift(x_top)).abs() < 1e-12);
        assert!((top.tip_diameter_mm - plain.tip_diameter_mm - 16.0 * taper).abs() < 1e-12);
        // Without the taper: cos αt = rb / r, the slope over the range.
        let range = m.geometry.helix_range;
        let sin_at = (20.0_f64.to_radians().tan() / 15.0_f64.to_radians().cos())
            .atan()
            .sin();
        let expected = taper * sin_at * (range.end_mm - range.start_mm) * 1000.0;
        let leaning = measure(
            &sections,
            &GearSpec {
                measuring_diameter_mm: Some(m.geometry.measuring_diameter_mm),
                ..plain
            },
        )
        .unwrap();
        let hx = leaning.helix.as_ref().unwrap();
        for d in hx.right.iter().chain(&hx.left) {
            assert!(
                (d.slope_um - expected).abs() < 0.05,
                "{hand:?} {d:?} vs {expected}"
            );
        }
    }
}

#[test]
fn normal_to_the_flank_the_deviations_are_cos_beta_b_of_the_transverse_ones() {
    // The flank normal lies in the base tangent plane at βb to the
    // transverse plane: a transverse deviation e along the base tangent is
    // e·cos βb along the normal. A lead error and a base radius error on
    // the helical gear, measured both ways.
    let spec = helical(Hand::Right);
    let mut g = Built::new(&spec);
    let r = 31.0 * 2.5 / 15.0_f64.to_radians().cos() / 2.0;
    g.twist += 2e-4 / r;
    g.right.rb *= 1.0 + 1e-4;
    let sec = g.sections(&faces(&spec), N);
    let transverse = measure(&sec, &spec).unwrap();
    let mut normal_spec = spec;
    normal_spec.direction = Direction::Normal;
    let normal = measure(&sec, &normal_spec).unwrap();
    // sin βb = sin β·cos αn.
    let cos_bb = (15.0_f64.to_radians().sin() * 20.0_f64.to_radians().cos())
        .asin()
        .cos();
    for item in [Item::HelixSlope, Item::ProfileSlope, Item::ProfileTotal] {
        let (t, n) = (value(&transverse, item), value(&normal, item));
        assert!(t.abs() > 0.5, "{item:?} {t}");
        assert!(
            (n - t * cos_bb).abs() < 1e-9,
            "{item:?}: {n} vs {t}·{cos_bb}"
        );
    }
    // Pitch is an arc on the measuring circle either way.
    assert_eq!(
        value(&transverse, Item::SinglePitch),
        value(&normal, Item::SinglePitch)
    );
}

#[test]
fn the_wrong_hand_is_a_helix_slope_of_twice_the_lead_and_fails_every_class() {
    // A left-hand gear measured as right-hand: e = n·(rb·θ − z·tan βb) with
    // θ = −z·tan β/r, so fHβ = −2·n·tan βb·(Lβ1 − Lβ0).
    let built = Built::new(&helical(Hand::Left));
    let spec = helical(Hand::Right);
    let m = measure(&built.sections(&faces(&spec), N), &spec).unwrap();
    let range = m.geometry.helix_range;
    let tan_bb = m.geometry.base_helix_deg.to_radians().tan();
    let expected = 2.0 * tan_bb * (range.end_mm - range.start_mm) * 1000.0;
    let hx = m.helix.as_ref().unwrap();
    for d in &hx.right {
        assert!((d.slope_um + expected).abs() < 0.05, "{d:?} vs {expected}");
    }
    for d in &hx.left {
        assert!((d.slope_um - expected).abs() < 0.05, "{d:?} vs {expected}");
    }
    assert_eq!(m.item(Item::HelixSlope).unwrap().grade, Grade::WorseThan11);
    assert_eq!(m.overall, Grade::WorseThan11);
    assert!(value(&m, Item::SinglePitch) < 0.05);
}

#[test]
fn a_right_hand_gear_turns_plus_theta_going_up_and_is_a_right_handed_helix() {
    // The convention: a right-hand gear's tooth centres turn +θ as z
    // grows. The construction follows it, and its centre line
    // (r·cos kz, r·sin kz, z) with k > 0 has positive torsion k/(1 + r²k²)
    // (by finite differences here): a right-handed helix.
    let spec = helical(Hand::Right);
    let g = Built::new(&spec);
    assert!(g.twist > 0.0);
    let (r, k) = (40.0, g.twist);
    let c = |t: f64| [r * (k * t).cos(), r * (k * t).sin(), t];
    let h = 0.05;
    let comb = |w: [f64; 5], s: f64| {
        let pts: Vec<[f64; 3]> = (0..5).map(|i| c((i as f64 - 2.0) * h)).collect();
        let mut v = [0.0; 3];
        for (p, wi) in pts.iter().zip(w) {
            for (vk, pk) in v.iter_mut().zip(p) {
                *vk += wi * pk / s;
            }
        }
        v
    };
    let d1 = comb([0.0, -0.5, 0.0, 0.5, 0.0], h);
    let d2 = comb([0.0, 1.0, -2.0, 1.0, 0.0], h * h);
    let d3 = comb([-0.5, 1.0, 0.0, -1.0, 0.5], h * h * h);
    let cross = [
        d2[1] * d3[2] - d2[2] * d3[1],
        d2[2] * d3[0] - d2[0] * d3[2],
        d2[0] * d3[1] - d2[1] * d3[0],
    ];
    let triple = d1[0] * cross[0] + d1[1] * cross[1] + d1[2] * cross[2];
    // det[r′, r″, r‴] = r²k⁵ for this helix: the torsion's sign.
    let exact = r * r * k.powi(5);
    assert!(
        triple > 0.0 && (triple - exact).abs() < 1e-2 * exact,
        "{triple} vs {exact}"
    );
    // And the measurement reads this gear as right-hand (flat helices).
    let m = measure(&g.sections(&faces(&spec), 4096), &spec).unwrap();
    assert!(value(&m, Item::HelixSlope).abs() < 1.0, "{m}");
}

#[test]
fn wrong_inputs_are_refused_with_their_name() {
    let spec = spur();
    let sec = Built::new(&spec).sections(&[10.0], 2048);
    let mut wrong = spec;
    wrong.teeth = 25;
    wrong.tip_diameter_mm = 25.0 * 3.0 + 7.2;
    wrong.root_diameter_mm = 25.0 * 3.0 - 6.3;
    assert!(measure(&sec, &wrong).is_err());
    let mut spur_with_hand = spec;
    spur_with_hand.hand = Some(Hand::Right);
    assert!(measure(&sec, &spur_with_hand).is_err());
    let mut short = Built::new(&spec).sections(&[9.0, 10.0], 2048);
    short.r_mm[1].pop();
    assert!(measure(&short, &spec).is_err());
    let mut two = sec.clone();
    two.z_mm.push(5.0);
    two.r_mm.push(sec.r_mm[0].clone());
    assert!(measure(&two, &spec).is_err(), "heights must increase");
}

#[test]
fn sampling_needs_about_15_um_of_arc_per_sample_for_a_tenth_of_a_micrometre() {
    // The worst graded item of the perfect spur gear (r = 36 mm) against n:
    // 16 384 (13.8 µm of arc per sample at the reference circle) is within
    // 0.05 µm, 8 192 within 1 µm (0.53), 4 096 is not (3.1): near the form
    // circle the flank is nearly radial and its samples sparse.
    let spec = spur();
    let worst = |n: usize| {
        let m = measure(&Built::new(&spec).sections(&[10.0], n), &spec).unwrap();
        m.items.iter().map(|i| i.value_um.abs()).fold(0.0, f64::max)
    };
    assert!(worst(16384) <= 0.05);
    assert!(worst(8192) <= 1.0);
    assert!(worst(4096) > 1.0);
}

#[test]
fn the_default_ranges_start_where_the_rack_ends_the_involute() {
    // The spur gear: r = 36, rb = 36·cos 20°, rf = 32.85, ra = 39.6 mm. The
    // basic rack's straight flank ends h = (r − rf) − 0.38·mn·(1 − sin αn)
    // inside the pitch line; in the rolling position where it meets the
    // line of action (through the pitch point, at αt to the pitch line) it
    // is at (−h/tan αt, −h) from the pitch point, with the gear's centre at
    // (0, −r): the involute starts at that point's distance from the
    // centre. Lα ends at 95 % of the roll length up to the tip.
    let spec = spur();
    let g = spec.geometry().unwrap();
    let a = 20.0_f64.to_radians();
    let (r, rf, ra) = (36.0, 32.85, 39.6);
    let h = (r - rf) - 0.38 * 3.0 * (1.0 - a.sin());
    let form = 2.0 * (h / a.tan()).hypot(r - h);
    assert!((g.form_diameter_mm - form).abs() < 1e-9, "{g:?} {form}");
    let rb = r * a.cos();
    let roll = |rr: f64| (rr * rr - rb * rb).sqrt();
    let l0 = roll(form / 2.0);
    assert!((g.profile_range.start_mm - l0).abs() < 1e-9);
    assert!((g.profile_range.end_mm - (l0 + 0.95 * (roll(ra) - l0))).abs() < 1e-9);
    // Lβ: b = 20 less min(5 % of b, mn) = 1 mm at each end.
    assert_eq!((g.helix_range.start_mm, g.helix_range.end_mm), (1.0, 19.0));
    assert!((g.measuring_diameter_mm - (2.0 * ra + 2.0 * rf) / 2.0).abs() < 1e-9);
}
