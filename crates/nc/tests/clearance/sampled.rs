//! The sampled sweep: the independent reference of the closed-form
//! clearance (`gearcam_nc::collide_hook::depth`).
//!
//! It computes the same quantity by brute force on its definition, sharing
//! no formula with the closed form (no support function, no level set, no
//! distance iteration): along a move, at poses at most [`POSE_STEP_MM`]
//! apart,
//!
//! ```text
//! D(t) = max( max_{p ∈ H(t)} φ_O(p),  max_{q ∈ O} φ_H(t)(q) )
//! ```
//!
//! with φ the signed depth of a point in a solid, written here from its
//! meaning: inside, the distance to the nearest face (for the hob the mantle
//! or an end face; for a frustum its mantle, measured square to it, or an
//! end face); outside, minus the distance to the solid, found in the
//! point's own section (a rectangle for the hob, the frustum's meridian
//! section). The points p run over a grid of the hob's solid (a square grid
//! across it, drawn in to the tip circle, times the axial positions) and q
//! over a grid of the obstacle near the hob (a box in x, y and height, each
//! point drawn in to the obstacle's radius at its height); the deepest
//! samples of each family are refined by a pattern search and then a
//! restarted Nelder–Mead simplex over the pose and the point's parameters.
//! Every value it returns is the depth of a real point at a real pose, so it
//! never exceeds the true D*; it comes within the refinement's reach of it.

use gearcam_nc::collide_hook::{HobMove, Solid};

/// Largest step between sampled poses, mm of travel of any hob point.
const POSE_STEP_MM: f64 = 2.0;
/// Samples across the hob in each direction.
const N_ACROSS: usize = 16;
/// Samples along the hob.
const N_AXIAL: usize = 15;
/// Samples of the obstacle's window in x and y.
const N_OB_XY: usize = 24;
/// Samples of the obstacle's window in height.
const N_OB_Z: usize = 12;
/// Starting points refined.
const STARTS: usize = 6;
/// Pattern-search evaluations per start.
const REFINE_EVALS: usize = 3000;
/// Cycles of pattern and simplex search per start.
const CYCLES: usize = 3;
/// Restarts of the simplex search per cycle.
const NM_RESTARTS: usize = 5;
/// Simplex steps per restart.
const NM_STEPS: usize = 2000;

type V = [f64; 3];

fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: V, k: f64) -> V {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: V) -> f64 {
    dot(a, a).sqrt()
}

/// The hob at the move's parameter t: centre, axis and the two directions
/// across it (the frame of `docs/hobbing.md` §1).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pose {
    pub(crate) centre: V,
    pub(crate) axis: V,
    e1: V,
    e2: V,
    r: f64,
    half: f64,
}

impl Pose {
    pub(crate) fn at(m: &HobMove, t: f64) -> Pose {
        let lerp = |a: f64, b: f64| a + (b - a) * t;
        let eta = lerp(m.eta_from_deg, m.eta_to_deg).to_radians();
        let axis = [0.0, eta.cos(), -eta.sin()];
        let e1 = [1.0, 0.0, 0.0];
        // e2 = axis × e1.
        let e2 = [0.0, axis[2], -axis[1]];
        let shift = lerp(m.from[2], m.to[2]);
        let centre = add(
            [lerp(m.from[0], m.to[0]), 0.0, lerp(m.from[1], m.to[1])],
            scale(axis, shift),
        );
        Pose {
            centre,
            axis,
            e1,
            e2,
            r: m.radius,
            half: m.half_length,
        }
    }

    /// The hob point at (u1, u2) across it (fractions of r, drawn in to the
    /// unit circle) and axial fraction ua.
    fn point(&self, u1: f64, u2: f64, ua: f64) -> V {
        let len = u1.hypot(u2).max(1.0);
        let (x1, x2) = (u1 / len * self.r, u2 / len * self.r);
        let a = ua.clamp(-1.0, 1.0) * self.half;
        let radial = add(scale(self.e1, x1), scale(self.e2, x2));
        add(add(self.centre, scale(self.axis, a)), radial)
    }

    /// Signed depth of a point in the hob.
    pub(crate) fn depth_of(&self, q: V) -> f64 {
        let v = sub(q, self.centre);
        let a = dot(v, self.axis);
        let w = norm(sub(v, scale(self.axis, a)));
        let a = a.abs();
        if a <= self.half && w <= self.r {
            (self.r - w).min(self.half - a)
        } else {
            -(w - self.r).max(0.0).hypot((a - self.half).max(0.0))
        }
    }
}

/// The obstacle's radius at height z (on its faces' range).
fn radius_at(s: &Solid, z: f64) -> f64 {
    if s.z_lo.is_finite() && s.z_hi.is_finite() && s.z_hi > s.z_lo {
        s.r_lo + (s.r_hi - s.r_lo) * ((z - s.z_lo) / (s.z_hi - s.z_lo)).clamp(0.0, 1.0)
    } else {
        s.r_lo
    }
}

/// Distance from (x, y) to the segment ab in the plane.
fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// Signed depth of a point in the obstacle.
pub(crate) fn obstacle_depth(s: &Solid, p: V) -> f64 {
    let rho = p[0].hypot(p[1]);
    let z = p[2];
    let cone = s.z_lo.is_finite() && s.z_hi.is_finite() && s.r_lo != s.r_hi;
    if !cone {
        let r = s.r_lo;
        if rho <= r && z >= s.z_lo && z <= s.z_hi {
            return (r - rho).min(z - s.z_lo).min(s.z_hi - z);
        }
        let dz = (s.z_lo - z).max(z - s.z_hi).max(0.0);
        return -(rho - r).max(0.0).hypot(dz);
    }
    // The meridian section: a trapezoid (0, z_lo), (r_lo, z_lo), (r_hi,
    // z_hi), (0, z_hi); the mantle's unit inward normal in the section is
    // (−h, r_hi − r_lo)/len with h the height.
    let h = s.z_hi - s.z_lo;
    let len = h.hypot(s.r_hi - s.r_lo);
    if z >= s.z_lo && z <= s.z_hi && rho <= radius_at(s, z) {
        let to_mantle = (radius_at(s, z) - rho) * h / len;
        return to_mantle.min(z - s.z_lo).min(s.z_hi - z);
    }
    let q = (rho, z);
    let d = to_segment(q, (0.0, s.z_lo), (s.r_lo, s.z_lo))
        .min(to_segment(q, (s.r_lo, s.z_lo), (s.r_hi, s.z_hi)))
        .min(to_segment(q, (s.r_hi, s.z_hi), (0.0, s.z_hi)));
    -d
}

/// The reference's answer: the deepest sampled and refined depth, where.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Found {
    pub(crate) depth: f64,
    pub(crate) at: V,
    pub(crate) t: f64,
}

/// One sample: its depth and its parameters (t and three of the point's;
/// `hob` tells which family).
#[derive(Debug, Clone, Copy)]
struct Sample {
    depth: f64,
    params: [f64; 4],
    hob: bool,
}

/// The window of the obstacle near the hob along the whole move: x, y and
/// height ranges.
#[derive(Debug, Clone, Copy)]
struct Window {
    x: (f64, f64),
    y: (f64, f64),
    z: (f64, f64),
}

fn window(m: &HobMove, s: &Solid) -> Option<Window> {
    let reach = m.radius.hypot(m.half_length) + 1.0;
    let (a, b) = (Pose::at(m, 0.0).centre, Pose::at(m, 1.0).centre);
    let rmax = s.r_lo.max(s.r_hi);
    let range = |k: usize, lo: f64, hi: f64| {
        let r = (
            (a[k].min(b[k]) - reach).max(lo),
            (a[k].max(b[k]) + reach).min(hi),
        );
        (r.0 <= r.1).then_some(r)
    };
    Some(Window {
        x: range(0, -rmax, rmax)?,
        y: range(1, -rmax, rmax)?,
        z: range(2, s.z_lo, s.z_hi)?,
    })
}

/// The depth of a sample from its parameters: the pose t, then (u1, u2, ua)
/// of a hob point, or the fractions of the window in x, y and height of an
/// obstacle point.
fn eval(m: &HobMove, s: &Solid, w: &Option<Window>, hob: bool, p: [f64; 4]) -> (f64, V) {
    let t = p[0].clamp(0.0, 1.0);
    let pose = Pose::at(m, t);
    if hob {
        let q = pose.point(p[1], p[2], p[3]);
        (obstacle_depth(s, q), q)
    } else {
        let Some(w) = w else {
            return (f64::NEG_INFINITY, [0.0; 3]);
        };
        let at = |r: (f64, f64), f: f64| r.0 + (r.1 - r.0) * f.clamp(0.0, 1.0);
        let (x, y, z) = (at(w.x, p[1]), at(w.y, p[2]), at(w.z, p[3]));
        let rho = x.hypot(y);
        let k = if rho > radius_at(s, z) {
            radius_at(s, z) / rho
        } else {
            1.0
        };
        let q = [x * k, y * k, z];
        (pose.depth_of(q), q)
    }
}

/// The reference depth D* of a move into a solid.
pub(crate) fn depth(m: &HobMove, s: &Solid) -> Found {
    let reach = m.radius.hypot(m.half_length);
    let travel = (m.to[0] - m.from[0]).hypot(m.to[1] - m.from[1]) + (m.to[2] - m.from[2]).abs();
    let lever = m.from[2].abs().max(m.to[2].abs()) + reach;
    let turn = (m.eta_to_deg - m.eta_from_deg).to_radians().abs() * lever;
    let n_t = (((travel + turn) / POSE_STEP_MM).ceil() as usize).clamp(1, 2000);
    let win = window(m, s);
    let mut found = Found {
        depth: f64::NEG_INFINITY,
        at: [0.0; 3],
        t: 0.0,
    };
    for (k, start) in samples(m, s, &win, n_t).into_iter().enumerate() {
        let steps = if start.hob {
            [
                0.5 / n_t as f64,
                1.0 / N_ACROSS as f64,
                1.0 / N_ACROSS as f64,
                1.0 / N_AXIAL as f64,
            ]
        } else {
            let xy = 0.5 / N_OB_XY as f64;
            [0.5 / n_t as f64, xy, xy, 0.5 / N_OB_Z as f64]
        };
        let mut keep = |d: f64, at: V, p: [f64; 4]| {
            if d > found.depth {
                found = Found {
                    depth: d,
                    at,
                    t: p[0].clamp(0.0, 1.0),
                };
            }
        };
        // Cycles of a pattern search (which moves along one parameter where
        // the depth hardly changes with the others) and a Nelder–Mead
        // simplex (which turns to follow a ridge where the depth is the
        // least of two faces' terms), restarted smaller.
        let mut x = start;
        for cycle in 0..CYCLES {
            let seed = (k * CYCLES + cycle) as u64 + 1;
            let (d, at, p) = refine(m, s, &win, x, steps, seed);
            keep(d, at, p);
            let mut p = clamp(start.hob, p);
            let mut size = steps;
            for _ in 0..NM_RESTARTS {
                let f = |q| penalised(m, s, &win, start.hob, q);
                let (q, _) = nelder_mead(f, p, size);
                p = clamp(start.hob, q);
                // Again over the parameters not at a bound only: a simplex
                // whose points press against a bound flattens and stalls
                // there, where the optimum often lies.
                let free = free_size(start.hob, p, size);
                if free.iter().any(|s| *s != 0.0) {
                    let (q, _) = nelder_mead(f, p, free);
                    p = clamp(start.hob, q);
                }
                let (d, at) = eval(m, s, &win, start.hob, p);
                keep(d, at, p);
                size = size.map(|s| s * 0.1);
            }
            x = Sample {
                depth: 0.0,
                params: p,
                hob: start.hob,
            };
        }
    }
    found
}

/// The deepest samples of each family (hob points in the obstacle,
/// obstacle points in the hob) over the poses.
fn samples(m: &HobMove, s: &Solid, win: &Option<Window>, n_t: usize) -> Vec<Sample> {
    // The deepest sample of each family at each pose: the starts are then
    // the deepest of those at different poses (along a swivel move the
    // depth may peak at more than one pose).
    let mut tops: [Vec<Sample>; 2] = [Vec::new(), Vec::new()];
    let frac = |i: usize, n: usize| i as f64 / n as f64;
    for i in 0..=n_t {
        let t = frac(i, n_t);
        let mut here: [Option<Sample>; 2] = [None, None];
        let mut keep = |x: Sample| {
            let best = &mut here[usize::from(x.hob)];
            if best.is_none_or(|b| x.depth > b.depth) {
                *best = Some(x);
            }
        };
        let mut best_here = f64::NEG_INFINITY;
        for i1 in 0..=N_ACROSS {
            for i2 in 0..=N_ACROSS {
                for j in 0..N_AXIAL {
                    let p = [
                        t,
                        2.0 * frac(i1, N_ACROSS) - 1.0,
                        2.0 * frac(i2, N_ACROSS) - 1.0,
                        2.0 * frac(j, N_AXIAL - 1) - 1.0,
                    ];
                    let (depth, _) = eval(m, s, win, true, p);
                    best_here = best_here.max(depth);
                    keep(Sample {
                        depth,
                        params: p,
                        hob: true,
                    });
                }
            }
        }
        // Obstacle points inside the hob only matter where the two meet:
        // every hob point lies within a third of the larger of r and h of a
        // sample, and depth changes no faster than the point moves.
        if best_here >= -0.5 * m.radius.max(m.half_length) {
            for ix in 0..=N_OB_XY {
                for iy in 0..=N_OB_XY {
                    for iz in 0..=N_OB_Z {
                        let p = [t, frac(ix, N_OB_XY), frac(iy, N_OB_XY), frac(iz, N_OB_Z)];
                        let (depth, _) = eval(m, s, win, false, p);
                        keep(Sample {
                            depth,
                            params: p,
                            hob: false,
                        });
                    }
                }
            }
        }
        for (k, best) in here.into_iter().enumerate() {
            tops[k].extend(best);
        }
    }
    let mut top = Vec::new();
    for mut family in tops {
        family.sort_by(|a, b| b.depth.total_cmp(&a.depth));
        family.truncate(STARTS);
        top.extend(family);
    }
    top
}

/// Pattern search from one sample: steps along each parameter and along
/// pseudo-random directions, kept when deeper; all steps halve when no
/// direction goes deeper.
fn refine(
    m: &HobMove,
    s: &Solid,
    win: &Option<Window>,
    start: Sample,
    mut steps: [f64; 4],
    seed: u64,
) -> (f64, V, [f64; 4]) {
    let mut p = start.params;
    let (mut d, mut at) = eval(m, s, win, start.hob, p);
    let mut rng = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        // xorshift64*: a fixed sequence, the same in every run.
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        (rng.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut evals = 0;
    while evals < REFINE_EVALS && steps.iter().any(|s| *s > 1e-12) {
        let mut moved = false;
        let mut dirs: Vec<[f64; 4]> = (0..4)
            .map(|k| {
                let mut e = [0.0; 4];
                e[k] = 1.0;
                e
            })
            .collect();
        for _ in 0..16 {
            dirs.push([next(), next(), next(), next()]);
        }
        for dir in dirs {
            for sign in [1.0, -1.0] {
                let mut c = p;
                for k in 0..4 {
                    c[k] += sign * dir[k] * steps[k];
                }
                c[0] = c[0].clamp(0.0, 1.0);
                let (cd, cat) = eval(m, s, win, start.hob, c);
                evals += 1;
                if cd > d {
                    (p, d, at) = (c, cd, cat);
                    moved = true;
                }
            }
        }
        if !moved {
            for st in &mut steps {
                *st *= 0.5;
            }
        }
    }
    (d, at, p)
}

/// The simplex sizes with those of the parameters at a bound of their box
/// set to 0.
fn free_size(hob: bool, p: [f64; 4], size: [f64; 4]) -> [f64; 4] {
    let lo = if hob { -1.0 } else { 0.0 };
    let mut out = size;
    for k in 0..4 {
        let (low, high) = if k == 0 { (0.0, 1.0) } else { (lo, 1.0) };
        if (p[k] - low).abs() < 1e-9 || (p[k] - high).abs() < 1e-9 {
            out[k] = 0.0;
        }
    }
    out
}

/// The parameters clamped to their box.
fn clamp(hob: bool, p: [f64; 4]) -> [f64; 4] {
    let lo = if hob { -1.0 } else { 0.0 };
    [
        p[0].clamp(0.0, 1.0),
        p[1].clamp(lo, 1.0),
        p[2].clamp(lo, 1.0),
        p[3].clamp(lo, 1.0),
    ]
}

/// The depth with the parameters clamped, less how far outside the box
/// they lie: the search then stays on the box.
fn penalised(m: &HobMove, s: &Solid, win: &Option<Window>, hob: bool, p: [f64; 4]) -> f64 {
    let c = clamp(hob, p);
    let outside: f64 = (0..4).map(|k| (p[k] - c[k]).abs()).sum();
    eval(m, s, win, hob, c).0 - 100.0 * outside - drawn_in(m, s, win, hob, c)
}

/// How far `eval` drew the point in to the tip circle or the obstacle's
/// radius, mm: where it does, the point stands still while the parameters
/// move, and a search there sees a flat depth; less this, the depth falls
/// off outside and the search returns to where the point moves.
fn drawn_in(m: &HobMove, s: &Solid, win: &Option<Window>, hob: bool, p: [f64; 4]) -> f64 {
    if hob {
        return (p[1].hypot(p[2]) - 1.0).max(0.0) * m.radius;
    }
    let Some(w) = win else { return 0.0 };
    let at = |r: (f64, f64), f: f64| r.0 + (r.1 - r.0) * f;
    let (x, y, z) = (at(w.x, p[1]), at(w.y, p[2]), at(w.z, p[3]));
    (x.hypot(y) - radius_at(s, z)).max(0.0)
}

/// Nelder–Mead maximisation from `x0` with a first simplex of the given
/// sizes: reflect the worst point through the others' centroid, expand,
/// contract or shrink (the usual coefficients 1, 2, ½, ½).
fn nelder_mead(f: impl Fn([f64; 4]) -> f64, x0: [f64; 4], size: [f64; 4]) -> ([f64; 4], f64) {
    let mut pts: Vec<([f64; 4], f64)> = vec![(x0, f(x0))];
    for k in (0..4).filter(|&k| size[k] != 0.0) {
        let mut x = x0;
        x[k] += size[k];
        pts.push((x, f(x)));
    }
    let last = pts.len() - 1;
    let lerp = |a: [f64; 4], b: [f64; 4], t: f64| -> [f64; 4] {
        [0, 1, 2, 3].map(|k| a[k] + (b[k] - a[k]) * t)
    };
    for _ in 0..NM_STEPS {
        pts.sort_by(|a, b| b.1.total_cmp(&a.1));
        let spread = (0..4)
            .map(|k| {
                pts.iter()
                    .map(|p| (p.0[k] - pts[0].0[k]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        if spread < 1e-13 {
            break;
        }
        let centroid =
            [0, 1, 2, 3].map(|k| pts[..last].iter().map(|p| p.0[k]).sum::<f64>() / last as f64);
        let worst = pts[last];
        let reflected = lerp(worst.0, centroid, 2.0);
        let fr = f(reflected);
        if fr > pts[0].1 {
            let expanded = lerp(worst.0, centroid, 3.0);
            let fe = f(expanded);
            pts[last] = if fe > fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr > pts[last - 1].1 {
            pts[last] = (reflected, fr);
        } else {
            let contracted = lerp(worst.0, centroid, 0.5);
            let fc = f(contracted);
            if fc > worst.1 {
                pts[last] = (contracted, fc);
            } else {
                let best = pts[0].0;
                for p in pts.iter_mut().skip(1) {
                    p.0 = lerp(best, p.0, 0.5);
                    p.1 = f(p.0);
                }
            }
        }
    }
    pts.sort_by(|a, b| b.1.total_cmp(&a.1));
    (pts[0].0, pts[0].1)
}
