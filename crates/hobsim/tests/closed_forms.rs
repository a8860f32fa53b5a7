//! The simulation against closed forms (`docs/simulation.md` §4): the depth
//! of the generating flats and of the feed marks, and the involute.

use gearcam_hobsim::cut::{self, Blank, Resolution};
use gearcam_hobsim::hob::Hob;
use gearcam_hobsim::kinematics::Timeline;

mod common;

const TAU: f64 = std::f64::consts::TAU;

/// A spur gear of module 10 and `Z` teeth and a right-hand hob of
/// reference radius `R0` (addendum 1.25·mn), cut at zero profile shift:
/// X = r + r0. The hob is large (lead angle 0.57° for one start), so its
/// axis lies almost in the transverse plane and a plane through its centre
/// sees the rack profile of its axial section: the set-up the closed forms
/// describe without the small tilt's second-order terms.
const MN: f64 = 10.0;
const R0: f64 = 500.0;
const Z: u32 = 20;
const ALPHA: f64 = 20.0;

fn centre_distance() -> f64 {
    MN * f64::from(Z) / 2.0 + R0
}

/// Cuts `blank` along `tl` with `h` at the fine resolution.
fn cut_blank(tl: &Timeline, h: &Hob, blank: &mut Blank) {
    cut::cut(tl, h, blank, Resolution::fine()).expect("cut");
}

/// One transverse section at z 50 mm, 2¹⁶ samples round, cut by `h` in
/// one pass at that height (1.05 table turns).
fn one_section(h: &Hob) -> Blank {
    let tl = common::spur_feed(h, 50.0, 50.0, 1.05);
    let mut blank = Blank::new(vec![50.0], 110.0, 1 << 16).expect("blank");
    cut_blank(&tl, h, &mut blank);
    blank
}

/// Normal deviation of the sampled outline from the involute of one flank,
/// as (roll angle ε, deviation), for the flank of tooth space 0 rising
/// counter-clockwise from the root; the involute's own angle offset cancels
/// in the depths measured from it.
fn flank(outline: &[f64], rb: f64, r_lo: f64, r_hi: f64) -> Vec<(f64, f64)> {
    let n = outline.len();
    // The tooth whose right flank is sampled: the first sample from the
    // top of the outline going counter-clockwise across a tooth's left side.
    let mut out = vec![];
    let start = (0..n).find(|&i| outline[i] < r_lo).expect("a gap");
    let mut i = start;
    // Walk counter-clockwise from inside the gap up the flank to the tip.
    // At most one turn: a cut without teeth has no flank to end at.
    while outline[i % n] < r_hi && i < start + n {
        let r = outline[i % n];
        if r > r_lo {
            let th = TAU * i as f64 / n as f64;
            let alpha = (rb / r).acos();
            let inv = alpha.tan() - alpha;
            // The flank's polar angle is θ₀ + inv(α_r); its normal deviation
            // is r·Δθ·cos α_r.
            let dev = r * (th - inv) * alpha.cos();
            out.push((alpha.tan(), dev));
        }
        i += 1;
    }
    out
}

/// Depths of the sawtooth: the flats' corners leave material, so they are
/// the local minima of the deviation (more material is a smaller angle on
/// this flank); each corner's depth is measured below the line through the
/// tangent points (local maxima) on either side.
fn sawtooth(samples: &[(f64, f64)], period: f64) -> Vec<(f64, f64)> {
    let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
    let is_ext = |k: usize, max: bool| {
        let (e, v) = samples[k];
        // An extremum needs its whole neighbourhood sampled.
        e - first > 0.4 * period
            && last - e > 0.4 * period
            && samples.iter().all(|&(e2, v2)| {
                (e2 - e).abs() > 0.4 * period || if max { v2 <= v } else { v2 >= v }
            })
    };
    let maxima: Vec<usize> = (0..samples.len()).filter(|&k| is_ext(k, true)).collect();
    let mut out = vec![];
    for w in maxima.windows(2) {
        let (a, b) = (samples[w[0]], samples[w[1]]);
        let Some(k) = (w[0]..w[1])
            .filter(|&k| is_ext(k, false))
            .min_by(|&p, &q| samples[p].1.total_cmp(&samples[q].1))
        else {
            continue;
        };
        if k < w[0] + 6 || k + 6 > w[1] {
            continue;
        }
        // The corner is a kink between samples k − 1 and k + 1: it is where
        // the lines through the samples on either side meet.
        let line = |p: (f64, f64), q: (f64, f64)| ((q.1 - p.1) / (q.0 - p.0), p);
        let (m1, p1) = line(samples[k - 5], samples[k - 1]);
        let (m2, p2) = line(samples[k + 1], samples[k + 5]);
        let e = (p2.1 - p1.1 + m1 * p1.0 - m2 * p2.0) / (m1 - m2);
        let v = p1.1 + m1 * (e - p1.0);
        let base = a.1 + (b.1 - a.1) * (e - a.0) / (b.0 - a.0);
        out.push((e, base - v));
    }
    out
}

/// Generating flats: in the transverse plane through the hob centre a gash
/// cuts the straight flank of the rack; consecutive gashes cut tangents to
/// the involute whose roll angles differ by Δε = 2π·z0/(z·i). Two tangents
/// of a curve of radius of curvature ρ = r_b·ε meet ρ·Δε²/8 outside it:
/// δ = r_b·ε·Δε²/8 (at the pitch circle π²·mn·z0²·sin α/(4·z·i²)).
#[test]
#[ignore = "about 30 s in release, minutes in debug: cargo test --release -p gearcam-hobsim -- --ignored"]
fn generating_flats_are_as_deep_as_the_tangents_of_the_involute_leave() {
    let rb = MN * f64::from(Z) / 2.0 * ALPHA.to_radians().cos();
    for (starts, gashes) in [(1, 3), (1, 4), (1, 6), (2, 6)] {
        let h = common::rack_hob(R0, starts, gashes, 0.0);
        let blank = one_section(&h);
        let d_eps = TAU * f64::from(starts) / (f64::from(Z) * f64::from(gashes));
        let f = flank(&blank.r_mm[0], rb, 96.0, 107.0);
        eprintln!(
            "{} flank samples, ε {:?}..{:?}",
            f.len(),
            f.first(),
            f.last()
        );
        // A flank of this gear spans about 450 samples; a cut gone wrong
        // spans none or the whole outline.
        assert!(
            f.len() > 100 && f.len() < 2000,
            "z0 {starts} i {gashes}: {} flank samples",
            f.len()
        );
        let teeth = sawtooth(&f, d_eps);
        assert!(
            teeth.len() >= 2,
            "z0 {starts} i {gashes}: {} flats",
            teeth.len()
        );
        for (e, depth) in teeth {
            let want = rb * e * d_eps * d_eps / 8.0;
            let ratio = depth / want;
            eprintln!("z0 {starts} i {gashes}: ε {e:.4} depth {depth:.5} closed form {want:.5} ratio {ratio:.4}");
            assert!(
                (ratio - 1.0).abs() < 0.02,
                "z0 {starts} i {gashes}: ε {e}: {depth} vs {want}"
            );
        }
    }
}

/// Feed marks: the tip cylinder of the hob (radius r_a0 = d_a0/2) cuts the
/// root of a tooth space once per table turn, the hob lower by the feed f
/// each time. In the gear's axial plane through the space's centre each cut
/// is a circle of radius r_a0 about the hob centre (the hob axis lies across
/// that plane; tilted by η the circle is an ellipse of semi-axes r_a0 and
/// r_a0/cos η, here η = 0.57°, 5·10⁻⁵ relative). Two circles f apart leave a
/// cusp midway: δ = r_a0 − √(r_a0² − f²/4) ≈ f²/(8·r_a0) = f²/(4·d_a0).
/// Measured over 13 sections f/6 apart (a cut height and a cusp height among
/// them) on the ray of a space centre, which a gash's tip land crosses
/// exactly once per table turn (z·i/z0 passes per turn, an integer); the
/// passes beside it stand off by a table step and cut shallower.
#[test]
fn feed_marks_in_the_root_are_as_deep_as_the_tip_circles_leave() {
    for f in [4.0, 8.0, 12.0] {
        let mut h = common::rack_hob(R0, 1, 12, 0.0);
        h.length_mm = 20.0;
        let tl = common::spur_feed(&h, 50.0 + 3.0 * f, 50.0 - f, 4.0);
        let z = Blank::planes(50.0, 50.0 + 2.0 * f, 13);
        let mut blank = Blank::new(z, 110.0, 20 * 64).expect("blank");
        cut_blank(&tl, &h, &mut blank);
        let root: Vec<f64> = blank.r_mm.iter().map(|o| o[0]).collect();
        let lo = root.iter().cloned().fold(f64::MAX, f64::min);
        let hi = root.iter().cloned().fold(f64::MIN, f64::max);
        let ra0 = h.tip_radius_mm;
        let want = ra0 - (ra0 * ra0 - f * f / 4.0).sqrt();
        eprintln!(
            "f {f}: root {lo:.5}..{hi:.5}, depth {:.6}, closed form {want:.6}",
            hi - lo
        );
        // The hob reaches X − r_a0 and no deeper.
        assert!(
            (lo - (centre_distance() - ra0)).abs() < 2e-3 * want + 1e-9,
            "f {f}: deepest {lo}"
        );
        assert!(
            ((hi - lo) / want - 1.0).abs() < 0.02,
            "f {f}: {} vs {want}",
            hi - lo
        );
    }
}

/// The feed marks on a flank (`docs/simulation.md` §4): the hob's flank, a
/// surface of revolution inclined by α to its radius, curves by sin α/ρ
/// along the feed at distance ρ from the hob axis, so two of its cuts one
/// feed f apart leave a cusp δn = f²·sin α/(8·ρ) normal to the flank. A
/// gear point at radius r is cut where the line of action meets it, s =
/// √(r² − rb²) − r·sin α from the pitch point (r the reference radius),
/// s·sin α nearer the hob axis than its reference radius: ρ = r0 − s·sin α.
/// Measured at two radii on the right flank of space 0 over one feed in
/// f/240 steps (the cusp is a corner, so the steps are fine): the flank's
/// angle at the radius, times rb, is its normal position.
#[test]
fn feed_marks_on_the_flank_are_as_deep_as_the_hobs_curvature_leaves() {
    let rb = MN * f64::from(Z) / 2.0 * ALPHA.to_radians().cos();
    let r_ref = MN * f64::from(Z) / 2.0;
    let sin_a = ALPHA.to_radians().sin();
    for f in [8.0, 12.0, 16.0] {
        let h = common::rack_hob(R0, 1, 12, 0.0);
        let tl = common::spur_feed(&h, 50.0 + 3.0 * f, 50.0 - f, 4.0);
        let z = Blank::planes(50.0, 50.0 + f, 241);
        let mut blank = Blank::new(z, 110.0, 20 * 1024).expect("blank");
        cut_blank(&tl, &h, &mut blank);
        for r in [r_ref, r_ref + 0.6 * MN] {
            let normal: Vec<f64> = blank
                .r_mm
                .iter()
                .map(|o| rb * right_flank_angle(o, r))
                .collect();
            let lo = normal.iter().cloned().fold(f64::MAX, f64::min);
            let hi = normal.iter().cloned().fold(f64::MIN, f64::max);
            let s = (r * r - rb * rb).sqrt() - r_ref * sin_a;
            let rho = R0 - s * sin_a;
            let want = f * f * sin_a / (8.0 * rho);
            eprintln!(
                "f {f}, r {r}: normal range {:.6} mm, closed form {want:.6} (ρ {rho:.2})",
                hi - lo
            );
            assert!(
                ((hi - lo) / want - 1.0).abs() < 0.02,
                "f {f}, r {r}: {} vs {want}",
                hi - lo
            );
        }
    }
}

/// The polar angle at which the right flank of space 0 (the space centred
/// on the ray at θ 0) crosses the radius `r`, interpolated between samples.
fn right_flank_angle(outline: &[f64], r: f64) -> f64 {
    let n = outline.len();
    let i = (1..n / 4).find(|&i| outline[i] >= r).expect("the flank");
    let (r0, r1) = (outline[i - 1], outline[i]);
    TAU * ((i - 1) as f64 + (r - r0) / (r1 - r0)) / n as f64
}

/// With many gashes the flank is the involute of the base circle r·cos α
/// touched by the flats: every flat is a tangent of the involute, so the
/// tangent points (the local maxima of the deviation, one per flat) lie on
/// it. Their deviations from the involute agree within 0.1 µm over the
/// flank (roll angles 0.27..0.53), no slope taken out. (Before the
/// simulation posed every chord point at its own instant they fell on a
/// slope of −9 µm per radian of roll: the numerical error of holding the
/// table while a sub-interval of the pass was swept, docs/simulation.md §4.)
#[test]
#[ignore = "about 40 s in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn many_gashes_cut_the_involute() {
    let rb = MN * f64::from(Z) / 2.0 * ALPHA.to_radians().cos();
    let h = common::rack_hob(R0, 1, 32, 0.0);
    let blank = one_section(&h);
    // The flank half a turn from where the plunge starts and ends (the gap
    // at θ 0 is also cut by the first and last passes, whose hob turns
    // before the move starts or after it ends and which are held there).
    let mut outline = blank.r_mm[0].clone();
    let half = outline.len() / 2;
    outline.rotate_left(half);
    let f = flank(&outline, rb, 97.0, 107.0);
    assert!(f.len() > 100, "{} flank samples", f.len());
    let d_eps = TAU / (f64::from(Z) * 32.0);
    let tangents = local_maxima(&f, d_eps);
    assert!(tangents.len() > 20, "{} tangent points", tangents.len());
    let lo = tangents.iter().map(|p| p.1).fold(f64::MAX, f64::min);
    let hi = tangents.iter().map(|p| p.1).fold(f64::MIN, f64::max);
    eprintln!(
        "{} tangent points over ε {:.3}..{:.3}: deviation range {:.2e} mm",
        tangents.len(),
        tangents[0].0,
        tangents[tangents.len() - 1].0,
        hi - lo
    );
    for p in tangents.iter().step_by(4) {
        eprintln!("  ε {:.4} deviation {:.2e}", p.0, p.1 - hi);
    }
    assert!(hi - lo < 1e-4, "tangent points spread {} mm", hi - lo);
}

/// The samples that are the largest within ±0.4 `period` of roll angle
/// (the tangent points of the flats).
fn local_maxima(samples: &[(f64, f64)], period: f64) -> Vec<(f64, f64)> {
    let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
    samples
        .iter()
        .filter(|&&(e, v)| {
            e - first > 0.4 * period
                && last - e > 0.4 * period
                && samples
                    .iter()
                    .all(|&(e2, v2)| (e2 - e).abs() > 0.4 * period || v2 <= v)
        })
        .copied()
        .collect()
}
