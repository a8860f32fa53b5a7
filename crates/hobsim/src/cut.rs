//! The blank as polar outlines on transverse sections, and the material each
//! gash pass removes from it.
//!
//! A gash passes the gear once per hob turn, when its plane points from the
//! hob axis towards the gear axis (body angle + B ≡ 0). While it sweeps the
//! blank its edge at hob angle φ (measured from the direction towards the
//! gear axis, right-handed about u) is there at the pass time plus
//! φ/(2π·n_hob), when the table has turned on. Each point of the edge's
//! outer profile pierces a section plane once on the gear's side; those
//! points, each posed at its own instant, bound what the pass removes from
//! the section, and the outline r(θ) is lowered to them (`pass`,
//! `docs/simulation.md` §3).

mod pass;
mod plane;
mod window;

use plane::Point;

use crate::hob::Hob;
use crate::kinematics::Timeline;
use crate::SimError;

const TAU: f64 = std::f64::consts::TAU;

/// The blank: outlines r(θ) on planes z = `z_mm[j]`, θ counter-clockwise in
/// the workpiece frame, sampled at θ_i = 2π·i/n.
#[derive(Debug, Clone, PartialEq)]
pub struct Blank {
    /// Heights of the sections above the table plane, mm.
    pub z_mm: Vec<f64>,
    /// Outer radius of the uncut blank, mm.
    pub outer_radius_mm: f64,
    /// r(θ_i) per section, mm.
    pub r_mm: Vec<Vec<f64>>,
}

impl Blank {
    /// A cylindrical blank of radius `outer_radius_mm` with sections at
    /// `z_mm` and `n_theta` angles per section.
    pub fn new(z_mm: Vec<f64>, outer_radius_mm: f64, n_theta: usize) -> Result<Blank, SimError> {
        if z_mm.is_empty() || n_theta < 8 || outer_radius_mm <= 0.0 {
            return Err(SimError::Parameter(
                "blank",
                "needs sections, ≥ 8 angles and a radius",
            ));
        }
        let r_mm = vec![vec![outer_radius_mm; n_theta]; z_mm.len()];
        Ok(Blank {
            z_mm,
            outer_radius_mm,
            r_mm,
        })
    }

    /// `n` equally spaced sections over `z_lo..z_hi` (both ends included).
    pub fn planes(z_lo: f64, z_hi: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|j| z_lo + (z_hi - z_lo) * j as f64 / (n.max(2) - 1) as f64)
            .collect()
    }

    /// Angle of sample `i`, radians.
    pub fn theta(&self, i: usize) -> f64 {
        TAU * i as f64 / self.r_mm[0].len() as f64
    }
}

/// Resolution of the material removal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolution {
    /// Largest step along the hob between the profile points whose pierce
    /// points start a pass's curve in a section, mm (the profile's knots
    /// are always among them).
    pub axial_step_mm: f64,
    /// How far the straight pieces between pierce points may stand off the
    /// curve they follow, mm: a step is halved while the curve's midpoint
    /// stands off its chord by more than four times this.
    pub tolerance_mm: f64,
}

impl Resolution {
    /// The fine resolution: the pass's curve within 10⁻⁵ mm (the whole
    /// cut within 10⁻⁴ mm of the exact sweep, `docs/simulation.md` §3).
    /// With [`samples_for`] at 1 µm the outline is within 1 µm.
    pub fn fine() -> Resolution {
        Resolution {
            axial_step_mm: 10.0,
            tolerance_mm: 1e-5,
        }
    }

    /// A coarse resolution for a quick look: the pass's curve within 1 µm,
    /// with [`samples_for`] at about 10 µm.
    pub fn coarse() -> Resolution {
        Resolution {
            axial_step_mm: 10.0,
            tolerance_mm: 1e-3,
        }
    }
}

/// The number of polar samples per section for an outline within
/// `tolerance_um` of the true one on a blank of radius `outer_radius_mm`.
///
/// The outline between two neighbouring rays is read as the straight line
/// through their samples; a curve of radius of curvature ρ leaves
/// L²/(8·ρ) between points L apart along it. Neighbouring samples at radius
/// r are r·Δθ apart across the rays, L = r·Δθ/sin ψ along a curve crossing
/// the rays at angle ψ. Taken here: ρ ≥ 1 mm (a hob tip radius of 0.38·mn
/// for mn ≥ 2.6 mm; a finer module wants a smaller tolerance) and ψ ≥ 10°
/// (an involute crosses its radius at 90° − α_r, the fillet of a gear with
/// at least 10 teeth more steeply), at the outer radius (the largest r).
/// So Δθ = sin 10°·√(8·ρ·tol)/R.
pub fn samples_for(outer_radius_mm: f64, tolerance_um: f64) -> usize {
    let rho_mm = 1.0;
    let psi = 10f64.to_radians();
    let step = psi.sin() * (8.0 * rho_mm * tolerance_um * 1e-3).sqrt() / outer_radius_mm;
    ((TAU / step).ceil() as usize).max(8)
}

/// Where a section's outline is wanted.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Wanted {
    /// All round: every pass cuts it wherever it reaches.
    #[default]
    Everywhere,
    /// Within these windows of angle `(from, to)`, from ≤ to, rad, in the
    /// workpiece frame (θ counter-clockwise, any turn): only the steps of a
    /// pass that can change the outline there are traced (`cut/window.rs`
    /// bounds them), so the outline within them is the one cut everywhere
    /// would leave (to 10⁻⁹ mm: `docs/simulation.md` §3), and outside them
    /// it stands where those steps left it.
    /// No windows: the section is not cut.
    Within(Vec<(f64, f64)>),
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution::fine()
    }
}

/// Cuts `blank` with `hob` along the whole `timeline`; returns the number of
/// gash passes that were posed near the blank.
pub fn cut(
    timeline: &Timeline,
    hob: &Hob,
    blank: &mut Blank,
    res: Resolution,
) -> Result<u64, SimError> {
    cut_with(timeline, hob, blank, res, (true, 1), (None, &[]))
}

/// [`cut`] along the segments `i` of the timeline with `mine[i]` only: the
/// moves `hob` makes on a machine that changes hobs between the gears of
/// one part; section j only where `wanted[j]` says (all of every section
/// when `wanted` is empty). The sections are shared among `threads`
/// threads (the outline is the same with any number); when fewer sections
/// are wanted everywhere than there are threads, each of those is shared
/// too, as windows that together go round it.
pub fn cut_segments(
    timeline: &Timeline,
    hob: &Hob,
    blank: &mut Blank,
    res: Resolution,
    mine: &[bool],
    (wanted, threads): (&[Wanted], usize),
) -> Result<u64, SimError> {
    cut_with(
        timeline,
        hob,
        blank,
        res,
        (true, threads),
        (Some(mine), wanted),
    )
}

/// [`cut`] with every pass's curve refined to the tolerance everywhere,
/// also where it stands clear of the outline and cannot cut: many times
/// slower, the same outline. Tests hold [`cut`] to it, so the pieces it
/// leaves out are shown to change nothing.
pub fn cut_exhaustive(
    timeline: &Timeline,
    hob: &Hob,
    blank: &mut Blank,
    res: Resolution,
) -> Result<u64, SimError> {
    cut_with(timeline, hob, blank, res, (false, 1), (None, &[]))
}

/// [`cut_exhaustive`] with section j cut only where `wanted[j]` says.
pub fn cut_exhaustive_within(
    timeline: &Timeline,
    hob: &Hob,
    blank: &mut Blank,
    res: Resolution,
    wanted: &[Wanted],
) -> Result<u64, SimError> {
    cut_with(timeline, hob, blank, res, (false, 1), (None, wanted))
}

fn cut_with(
    timeline: &Timeline,
    hob: &Hob,
    blank: &mut Blank,
    res: Resolution,
    (skip_clear, threads): (bool, usize),
    (mine, wanted): (Option<&[bool]>, &[Wanted]),
) -> Result<u64, SimError> {
    if !(wanted.is_empty() || wanted.len() == blank.z_mm.len()) {
        return Err(SimError::Parameter(
            "wanted",
            "one entry per section, or none",
        ));
    }
    let bad_window = |w: &Wanted| match w {
        Wanted::Everywhere => false,
        Wanted::Within(w) => w
            .iter()
            .any(|&(from, to)| !(from.is_finite() && to.is_finite() && from <= to)),
    };
    if wanted.iter().any(bad_window) {
        return Err(SimError::Parameter(
            "wanted",
            "windows (from, to) of finite angles, from ≤ to",
        ));
    }
    let mut work = work_items(wanted, blank.z_mm.len(), threads.max(1));
    let windowed = work.iter().any(|w| w.windows.is_some());
    if !(res.axial_step_mm > 0.0 && res.tolerance_mm > 0.0) {
        return Err(SimError::Parameter(
            "resolution",
            "step and tolerance must be positive",
        ));
    }
    let (z_lo, z_hi) = blank
        .z_mm
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &z| (a.min(z), b.max(z)));
    let reach = hob.tip_radius_mm + hob.length_mm / 2.0;
    // The rays' directions (cos θ_i, sin θ_i), once.
    let n_theta = blank.r_mm[0].len();
    let dirs: Vec<(f64, f64)> = (0..n_theta)
        .map(|i| {
            let (sn, cs) = (TAU * i as f64 / n_theta as f64).sin_cos();
            (cs, sn)
        })
        .collect();
    let mut passes = Vec::new();
    for (i, s) in timeline.segments().iter().enumerate() {
        if s.hob_rev_s == 0.0 || s.t1_s <= s.t0_s || mine.is_some_and(|m| !m[i]) {
            continue;
        }
        let x_min = s.from.x_mm.min(s.to.x_mm);
        let near_z =
            s.from.z_mm.min(s.to.z_mm) - reach < z_hi && s.from.z_mm.max(s.to.z_mm) + reach > z_lo;
        if x_min - hob.tip_radius_mm >= blank.outer_radius_mm || !near_z {
            continue;
        }
        let b0 = timeline.pose_in(i, s.t0_s).b_rad;
        let b1 = timeline.pose_in(i, s.t1_s).b_rad;
        let step = TAU / f64::from(hob.gashes);
        let (lo, hi) = (b0.min(b1), b0.max(b1));
        let mut n = (lo / step).ceil() as i64;
        while (n as f64) * step <= hi {
            let b = n as f64 * step;
            let t = s.t0_s + (b - b0) / (TAU * s.hob_rev_s);
            let k = (-n).rem_euclid(i64::from(hob.gashes)) as u32;
            let pass = pass::Pass::new(timeline, i, t, hob, k, blank.outer_radius_mm, res);
            passes.push(if windowed { pass.windowed() } else { pass });
            n += 1;
        }
    }
    let clip_r = blank.outer_radius_mm + CLIP_MARGIN_MM;
    let cut_one = |item: &mut WorkItem| {
        let windows = item.windows.as_deref();
        let zs = blank.z_mm[item.section];
        cut_section(
            &passes,
            zs,
            &mut item.r,
            (clip_r, &dirs),
            (skip_clear, windows),
        );
    };
    for item in &mut work {
        item.r.clone_from(&blank.r_mm[item.section]);
    }
    // Each item is cut by one thread with every pass, and an outline is
    // the least of its items' (each lowers it only where the cut reaches,
    // and within its windows exactly as far as the whole cut would), so it
    // does not depend on how many threads share the work.
    let threads = threads.clamp(1, work.len().max(1));
    if threads == 1 {
        work.iter_mut().for_each(cut_one);
    } else {
        let queue = std::sync::Mutex::new(work.iter_mut());
        std::thread::scope(|scope| {
            for _ in 0..threads {
                scope.spawn(|| loop {
                    let next = queue.lock().map(|mut w| w.next());
                    match next {
                        Ok(Some(item)) => cut_one(item),
                        _ => break,
                    }
                });
            }
        });
    }
    for item in work {
        let out = &mut blank.r_mm[item.section];
        for (o, r) in out.iter_mut().zip(item.r) {
            *o = o.min(r);
        }
    }
    Ok(passes.len() as u64)
}

/// One section, or windows of it, as one thread cuts it into an outline
/// of its own.
struct WorkItem {
    section: usize,
    /// `None`: all round.
    windows: Option<Vec<(f64, f64)>>,
    r: Vec<f64>,
}

/// The work of cutting `sections` sections as `wanted` says, for
/// `threads` threads: a section wanted everywhere is one item, or, when
/// fewer sections than threads are, as many windows going round it as
/// give every thread a share; a section with windows is one item; one with
/// none is not cut. Those all round come first: they take longest.
fn work_items(wanted: &[Wanted], sections: usize, threads: usize) -> Vec<WorkItem> {
    let everywhere = |j: usize| wanted.get(j).is_none_or(|w| *w == Wanted::Everywhere);
    let whole = (0..sections).filter(|&j| everywhere(j)).count();
    let parts = if whole == 0 || whole >= threads {
        1
    } else {
        threads.div_ceil(whole)
    };
    let item = |section, windows| WorkItem {
        section,
        windows,
        r: Vec::new(),
    };
    let mut out = Vec::new();
    for j in (0..sections).filter(|&j| everywhere(j)) {
        if parts == 1 {
            out.push(item(j, None));
            continue;
        }
        let w = TAU / parts as f64;
        out.extend((0..parts).map(|k| item(j, Some(vec![(w * k as f64, w * (k + 1) as f64)]))));
    }
    for (j, w) in wanted.iter().enumerate() {
        if let Wanted::Within(windows) = w {
            if !windows.is_empty() {
                out.push(item(j, Some(windows.clone())));
            }
        }
    }
    out
}

/// Cuts the outline `r` of the section `zs` with every pass, the deepest
/// first: the outline is then near its last shape early, and the shallower
/// passes' pieces stand clear of it.
fn cut_section(
    passes: &[pass::Pass<'_>],
    zs: f64,
    r: &mut [f64],
    (clip_r, dirs): (f64, &[(f64, f64)]),
    (skip_clear, windows): (bool, Option<&[(f64, f64)]>),
) {
    let mut order: Vec<(f64, usize)> = passes
        .iter()
        .enumerate()
        .map(|(i, p)| (p.depth_in(zs), i))
        .collect();
    order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    // The knots and the grid of each pass, in buffers kept between passes.
    let mut scratch = pass::Scratch::default();
    let mut blocks = Vec::new();
    for (k, &(_, i)) in order.iter().enumerate() {
        // The blocks' maxima only fall as the outline is cut, so a stale
        // one is still an upper bound: refreshed as the outline takes its
        // shape (after 16, 32, … passes), then every 512.
        if k == 0 || (k >= 16 && (k.is_power_of_two() || k % 512 == 0)) {
            block_maxima(r, &mut blocks);
        }
        passes[i].cut(
            zs,
            clip_r,
            (r, &blocks),
            dirs,
            (skip_clear, windows),
            &mut scratch,
        );
    }
}

/// Margin outside the blank's radius within which a pass is traced, mm:
/// what lies further out cannot lower an outline that starts at the blank's
/// radius.
const CLIP_MARGIN_MM: f64 = 0.05;

/// The sample rays the segment p→q spans (p and q hold x, y and their
/// polar angle): the first ray's index and how many, counting on past the
/// last ray to the first (the span may wrap round θ = 2π).
fn ray_span(n: usize, p: Point, q: Point) -> (usize, usize) {
    let (ta, tb) = (p[2], q[2]);
    let mut span = tb - ta;
    if span > std::f64::consts::PI {
        span -= TAU;
    } else if span < -std::f64::consts::PI {
        span += TAU;
    }
    let start = if span >= 0.0 { ta } else { ta + span };
    let scale = n as f64 / TAU;
    let i0 = (start * scale).ceil() as i64;
    let i1 = ((start + span.abs()) * scale).floor() as i64;
    let first = i0.rem_euclid(n as i64) as usize;
    (first, ((i1 - i0 + 1).max(0) as usize).min(n))
}

/// The rays of [`ray_span`] as two index ranges (the second empty unless
/// the span wraps).
fn ray_ranges(n: usize, p: Point, q: Point) -> [std::ops::Range<usize>; 2] {
    let (first, count) = ray_span(n, p, q);
    let end = first + count;
    [first..end.min(n), 0..end.saturating_sub(n)]
}

/// Lowers r(θ_i) to where the segment p→q crosses each sample ray it spans.
/// `dirs` holds (cos θ_i, sin θ_i) of every ray. The crossing radius is
/// (p × d)/(dir × d), d = q − p, positive on the segment's side of the
/// axis.
fn raster(r: &mut [f64], dirs: &[(f64, f64)], p: Point, q: Point) {
    let d = [q[0] - p[0], q[1] - p[1]];
    let num = p[0] * d[1] - p[1] * d[0];
    for range in ray_ranges(dirs.len(), p, q) {
        for i in range {
            let (cs, sn) = dirs[i];
            let den = cs * d[1] - sn * d[0];
            // num/den in (0, r_i), without dividing where it is not.
            if num * den > 0.0 && num.abs() < r[i] * den.abs() {
                r[i] = num / den;
            } else if den == 0.0 && num == 0.0 {
                // Along the ray: its nearer end.
                r[i] = r[i].min(p[0].hypot(p[1]).min(q[0].hypot(q[1])));
            }
        }
    }
}

/// Rays per block of [`block_maxima`].
const BLOCK: usize = 32;

/// The largest r(θ_i) of every block of [`BLOCK`] rays into `out`.
fn block_maxima(r: &[f64], out: &mut Vec<f64>) {
    out.clear();
    out.extend(
        r.chunks(BLOCK)
            .map(|c| c.iter().fold(0.0, |m: f64, &x| m.max(x))),
    );
}

/// True when every curve within `margin` of the segment p→q (measured
/// across it) stands further out than r(θ_i) on every sample ray the
/// segment spans: such a curve cannot lower the outline. Along a ray at
/// angle ψ to the segment the margin is margin/sin ψ, and sin ψ = |dir × d|/|d|.
///
/// `r` comes with upper bounds of its blocks of [`BLOCK`] rays; the rays a
/// segment spans within one block are cleared at once when the block's
/// bound, times the largest `den` of those rays, is clear: `den` = dir × d
/// is |d|·sin of the angle from d to the ray, which over at most a block's
/// Δθ stands at most |d|·Δθ²/8 above the larger of its two ends.
fn clear_of(
    (r, blocks): (&[f64], &[f64]),
    dirs: &[(f64, f64)],
    p: Point,
    q: Point,
    margin: f64,
) -> bool {
    let d = [q[0] - p[0], q[1] - p[1]];
    let num = p[0] * d[1] - p[1] * d[0];
    let (size, sign) = (num.abs(), num.signum());
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let slack = margin * len;
    let den = |i: usize| {
        let (cs, sn) = dirs[i];
        // With num's sign: negative, the crossing is behind the axis.
        sign * (cs * d[1] - sn * d[0])
    };
    // The rays of a stretch, all tested without a branch per ray (which
    // the compiler turns into vector instructions).
    let stretch_clear = |lo: usize, hi: usize| {
        dirs[lo..hi]
            .iter()
            .zip(&r[lo..hi])
            .fold(true, |ok, (&(cs, sn), &ri)| {
                let den = sign * (cs * d[1] - sn * d[0]);
                ok & ((den < 0.0) | (size > ri * den + slack))
            })
    };
    let step = TAU / dirs.len() as f64 * (BLOCK - 1) as f64;
    let bow = len * step * step / 8.0;
    // A stretch within one block: cleared at once by the block's bound, or
    // ray by ray.
    let block_clear = |lo: usize, hi: usize| {
        if lo >= hi {
            return true;
        }
        let top = den(lo).max(den(hi - 1)) + bow;
        top < 0.0 || size > blocks[lo / BLOCK] * top + slack || stretch_clear(lo, hi)
    };
    ray_ranges(dirs.len(), p, q).into_iter().all(|range| {
        // The stretch before the first whole block, the whole blocks, the
        // stretch after the last.
        let first = range.start.next_multiple_of(BLOCK).min(range.end);
        let last = first.max(range.end / BLOCK * BLOCK);
        block_clear(range.start, first)
            && block_clear(last, range.end)
            && (first..last)
                .step_by(BLOCK)
                .all(|i| block_clear(i, i + BLOCK))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_lowers_the_rays_it_crosses_to_its_own_radius() {
        let mut r = vec![10.0; 360];
        let dirs: Vec<(f64, f64)> = (0..360)
            .map(|i| {
                let (s, c) = (TAU * f64::from(i) / 360.0).sin_cos();
                (c, s)
            })
            .collect();
        // The line x = 5 from y = −1 to y = 1.
        let (p, q) = ([5.0, -1.0, (-0.2f64).atan()], [5.0, 1.0, 0.2f64.atan()]);
        raster(&mut r, &dirs, p, q);
        assert!((r[0] - 5.0).abs() < 1e-12);
        let th = TAU * 5.0 / 360.0;
        assert!((r[5] - 5.0 / th.cos()).abs() < 1e-12);
        assert_eq!(r[20], 10.0);
        assert_eq!(r[180], 10.0);
    }

    #[test]
    fn the_chord_pieces_of_the_sweep_cover_the_chord_once() {
        // φ from −π to π in 7 pieces cover s ∈ [−S, S] for t ≠ 0.
        let (t, big_s) = (0.3, 2.0);
        let mut total = 0.0;
        for m in 0..7 {
            let w = TAU / 7.0;
            let pa = -std::f64::consts::PI + w * f64::from(m);
            if let Some((lo, hi)) = plane::s_range(t, pa, pa + w, big_s) {
                total += hi - lo;
            }
        }
        assert!((total - 2.0 * big_s).abs() < 1e-9, "{total}");
    }
}
