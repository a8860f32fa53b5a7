//! The independent clearance check: the hob as a finite solid swept along
//! every move of the parsed program, against the blank of every gear unit
//! (rapid moves) and against the table, the fixture and the tailstock (every
//! move).
//!
//! It shares nothing with the model's clearance ΔH′ but the machine-neutral
//! frame (`docs/hobbing.md`): the programmed swivel value gives the hob's
//! tilt η = (A − offset)/swivel_sign, the programmed X, Z and shift Y its
//! centre, and the hob is its tip cylinder (radius da0/2, the hob's length)
//! around the axis u = (0, cos η, −sin η). The solid is sampled (its tip
//! cylinder, both end faces, and the edge circles of each obstacle tested
//! against the hob), the poses along each move are sampled, a coarse pass
//! with a Lipschitz bound skips the poses where the hob is well clear, and
//! the four deepest samples are refined by a pattern search. A finding names
//! the line, the obstacle and how deep the hob enters it.
//!
//! # Tolerance
//!
//! A penetration up to [`PEN_TOL`] is ignored: the printed coordinates are
//! rounded to 0.0005 mm and the sampled surface lies within that of the true
//! one after refinement.

use gearcam_geom::Vector3;
use gearcam_proto::{GearSpec, HobData, MachiningModel, MoveKind, PathFinding};

use super::{finding, Trace};
use gearcam_proto::Code;

/// Penetration ignored, mm.
pub(crate) const PEN_TOL: f64 = 0.002;

/// Samples around the hob's circumference.
const N_THETA: usize = 48;
/// Samples along the hob's length (both ends included).
const N_AXIAL: usize = 15;
/// Rings sampled on each end face (plus its centre).
const N_RINGS: usize = 3;
/// Samples on an obstacle's edge circle.
const N_RIM: usize = 240;
/// Largest step between sampled poses along a move, mm.
const POSE_STEP_MM: f64 = 2.0;
/// Pattern-search iterations of the refinement.
const REFINE_ITERS: usize = 60;
/// Deepest samples the refinement starts from.
const REFINE_STARTS: usize = 4;

/// A point or direction in the machine-neutral frame (x radial, y
/// tangential, z axial), mm.
type P3 = Vector3<f64>;

/// The hob at one pose: centre, axis and the two directions across it.
#[derive(Debug, Clone, Copy)]
struct Pose {
    centre: P3,
    axis: P3,
    e1: P3,
    e2: P3,
}

impl Pose {
    fn new(x: f64, z: f64, shift_along_axis: f64, eta_deg: f64) -> Pose {
        let e = eta_deg.to_radians();
        let axis = P3::new(0.0, e.cos(), -e.sin());
        let e1 = P3::new(1.0, 0.0, 0.0);
        let e2 = axis.cross(&e1);
        Pose {
            centre: P3::new(x, 0.0, z) + axis * shift_along_axis,
            axis,
            e1,
            e2,
        }
    }

    /// A point of the hob's surface: on the tip cylinder (`face` 0) at
    /// angle θ and axial position s, or on an end face (`face` ±1) at angle θ
    /// and radius s.
    fn point(&self, hob: &HobSolid, face: i8, theta: f64, s: f64) -> P3 {
        let (sin, cos) = theta.sin_cos();
        let (along, radius) = match face {
            0 => (s.clamp(-hob.half, hob.half), hob.r),
            f => (f64::from(f) * hob.half, s.clamp(0.0, hob.r)),
        };
        let radial = self.e1 * (cos * radius) + self.e2 * (sin * radius);
        self.centre + self.axis * along + radial
    }

    /// How deep a point lies inside the hob solid (positive inside).
    fn depth_of(&self, hob: &HobSolid, p: P3) -> f64 {
        let v = p - self.centre;
        let a = v.dot(&self.axis);
        let radial = (v.dot(&v) - a * a).max(0.0).sqrt();
        (hob.r - radial).min(hob.half - a.abs())
    }
}

/// The hob's tip cylinder.
#[derive(Debug, Clone, Copy)]
struct HobSolid {
    r: f64,
    half: f64,
}

impl HobSolid {
    /// Radius of the sphere around the centre that holds the hob.
    fn reach(&self) -> f64 {
        self.r.hypot(self.half)
    }
}

/// What the hob must not enter: a solid of revolution about the table axis,
/// radius varying linearly from `r_lo` at `z_lo` to `r_hi` at `z_hi`.
#[derive(Debug, Clone)]
struct Obstacle {
    what: String,
    z_lo: f64,
    z_hi: f64,
    r_lo: f64,
    r_hi: f64,
    /// Checked on rapid moves only (the blank, which feed moves cut).
    rapid_only: bool,
}

impl Obstacle {
    fn radius_at(&self, z: f64) -> f64 {
        if self.z_hi - self.z_lo <= 0.0 || !self.z_hi.is_finite() || !self.z_lo.is_finite() {
            return self.r_lo;
        }
        let t = ((z - self.z_lo) / (self.z_hi - self.z_lo)).clamp(0.0, 1.0);
        self.r_lo + (self.r_hi - self.r_lo) * t
    }

    /// How deep a point lies inside (positive inside).
    fn depth_of(&self, p: P3) -> f64 {
        let rho = p[0].hypot(p[1]);
        (self.radius_at(p[2]) - rho)
            .min(p[2] - self.z_lo)
            .min(self.z_hi - p[2])
    }

    /// The edge circles (finite faces only): (height, radius).
    fn rims(&self) -> Vec<(f64, f64)> {
        [(self.z_lo, self.r_lo), (self.z_hi, self.r_hi)]
            .into_iter()
            .filter(|(z, r)| z.is_finite() && *r > 0.0)
            .collect()
    }

    /// Distance from a point to the obstacle's bounding cylinder (0 inside).
    fn bound_distance(&self, p: P3) -> f64 {
        let rmax = self.r_lo.max(self.r_hi);
        let dr = (p[0].hypot(p[1]) - rmax).max(0.0);
        let dz = (self.z_lo - p[2]).max(p[2] - self.z_hi).max(0.0);
        dr.hypot(dz)
    }
}

/// The blanks of every unit, and the table, fixture and tailstock.
fn obstacles(model: &MachiningModel) -> Vec<Obstacle> {
    let m = &model.model;
    // A unit's gear carries its own lower face: the model replaced its
    // fixture height by the first unit's plus the unit's offset.
    let units: Vec<(&GearSpec, f64)> = if m.units.is_empty() {
        vec![(&model.plan.gear, m.blank_od_mm)]
    } else {
        m.units
            .iter()
            .map(|u| (&u.gear, u.model.blank_od_mm))
            .collect()
    };
    let mut out = Vec::new();
    let base = model.plan.gear.fixture_height_mm;
    let mut top = f64::NEG_INFINITY;
    let mut bottom = f64::INFINITY;
    for (i, (gear, od)) in units.iter().enumerate() {
        let z_lo = gear.fixture_height_mm;
        let z_hi = z_lo + gear.face_width_mm;
        let r = od / 2.0;
        let (r_lo, r_hi) = match &gear.cone {
            Some(cone) => {
                let taper = gear.face_width_mm * cone.angle_deg.to_radians().tan();
                match cone.large_end {
                    gearcam_proto::LargeEnd::Bottom => (r, r - taper),
                    gearcam_proto::LargeEnd::Top => (r - taper, r),
                }
            }
            None => (r, r),
        };
        let what = if units.len() > 1 {
            format!("the blank of unit {}", i + 1)
        } else {
            "the blank".to_string()
        };
        out.push(Obstacle {
            what,
            z_lo,
            z_hi,
            r_lo,
            r_hi,
            rapid_only: true,
        });
        top = top.max(z_hi);
        bottom = bottom.min(z_lo);
    }
    let env = &model.plan.machine.envelope;
    out.push(Obstacle {
        what: "the table".into(),
        z_lo: f64::NEG_INFINITY,
        z_hi: 0.0,
        r_lo: env.table_radius_mm,
        r_hi: env.table_radius_mm,
        rapid_only: false,
    });
    let fixture_r = model
        .plan
        .gear
        .fixture_diameter_mm
        .map_or(env.fixture_radius_mm, |d| d / 2.0);
    let fixture_top = bottom.min(base);
    if fixture_r > 0.0 && fixture_top > 0.0 {
        out.push(Obstacle {
            what: "the fixture".into(),
            z_lo: 0.0,
            z_hi: fixture_top,
            r_lo: fixture_r,
            r_hi: fixture_r,
            rapid_only: false,
        });
    }
    if env.tailstock_radius_mm > 0.0 && top.is_finite() {
        out.push(Obstacle {
            what: "the tailstock".into(),
            z_lo: top + env.tailstock_gap_mm,
            z_hi: f64::INFINITY,
            r_lo: env.tailstock_radius_mm,
            r_hi: env.tailstock_radius_mm,
            rapid_only: false,
        });
    }
    out
}

/// The units' hobs in program order, and the lines of the couplings that
/// start each unit (the first, then every one after a new definition or an
/// uncoupling): a line's hob is the one of the last unit started before it.
struct Hobs<'m> {
    hobs: Vec<&'m HobData>,
    starts: Vec<u32>,
}

impl<'m> Hobs<'m> {
    fn new(model: &'m MachiningModel, trace: &Trace) -> Hobs<'m> {
        let hobs = if model.model.units.is_empty() {
            vec![&model.plan.hob]
        } else {
            model.model.units.iter().map(|u| &u.hob).collect()
        };
        let starts = trace
            .couplings
            .iter()
            .filter(|c| c.unit_start)
            .map(|c| c.line)
            .collect();
        Hobs { hobs, starts }
    }

    /// The hob mounted at `line` (before the first coupling, the first unit's).
    fn at(&self, line: u32) -> &'m HobData {
        let idx = self
            .starts
            .iter()
            .filter(|&&l| l <= line)
            .count()
            .saturating_sub(1);
        self.hobs[idx.min(self.hobs.len() - 1)]
    }
}

/// One worst point found on a move.
#[derive(Debug, Clone, Copy)]
struct Worst {
    depth: f64,
    at: P3,
}

/// The independent clearance and envelope check of a simulated program.
pub(crate) fn check(model: &MachiningModel, trace: &Trace) -> Vec<PathFinding> {
    let settings = &model.plan.machine.settings;
    let axes = &model.plan.machine.axes;
    let obstacles = obstacles(model);
    let rims: Vec<Vec<(f64, f64)>> = obstacles.iter().map(Obstacle::rims).collect();
    let hobs = Hobs::new(model, trace);
    let mut findings = Vec::new();
    let mut from = [
        model.plan.machine.home_x_mm,
        model.plan.machine.home_z_mm,
        0.0,
    ];
    // Before the first programmed swivel the head stands where the program
    // will put it first (the program sets it before any move near the work).
    let first_a = trace.swivel_deg.first().map_or(0.0, |s| s.1);
    let mut a_from = first_a;
    let eta = |a: f64| (a - settings.swivel_offset_deg) * settings.swivel_sign;
    for mv in &trace.moves {
        if mv.kind == MoveKind::Dwell {
            continue;
        }
        let to = [mv.x_mm, mv.z_mm, mv.y_mm];
        let a_to = trace
            .swivel_deg
            .iter()
            .rev()
            .find(|s| s.0 <= mv.line)
            .map_or(first_a, |s| s.1);
        let hob = hobs.at(mv.line);
        let solid = HobSolid {
            r: hob.od_mm / 2.0,
            half: hob.length_mm / 2.0,
        };
        let pose_at = |t: f64| {
            let x = from[0] + (to[0] - from[0]) * t;
            let z = from[1] + (to[1] - from[1]) * t;
            let y = from[2] + (to[2] - from[2]) * t;
            let a = a_from + (a_to - a_from) * t;
            Pose::new(x, z, y * settings.shift_sign, eta(a))
        };
        let length = (to[0] - from[0])
            .hypot(to[1] - from[1])
            .hypot(to[2] - from[2])
            .max((a_to - a_from).abs().to_radians() * solid.reach());
        // A rapid that only moves X outwards withdraws the hob from the gaps
        // it stands in (a worm wheel's retract from the throat): while the
        // whole hob stays on its side of the table axis (X > r), every hob
        // point moves away from the axis and cannot enter a blank.
        let withdrawal = to[0] > from[0]
            && (to[1] - from[1]).abs() <= 1e-9
            && (to[2] - from[2]).abs() <= 1e-9
            && (a_to - a_from).abs() <= 1e-9
            && from[0] > solid.r;
        for (k, ob) in obstacles.iter().enumerate() {
            if ob.rapid_only && (mv.kind != MoveKind::Rapid || withdrawal) {
                continue;
            }
            if let Some(w) = sweep(&solid, ob, &rims[k], &pose_at, length) {
                if w.depth > PEN_TOL {
                    let what = match mv.kind {
                        MoveKind::Rapid => "rapid move",
                        MoveKind::Feed => "feed move",
                        _ => "arc",
                    };
                    let rule = if ob.rapid_only {
                        Code::HOB_CLEARANCE
                    } else {
                        Code::ENVELOPE
                    };
                    findings.push(finding(
                        mv.line,
                        rule,
                        format!(
                            "the {what} to {}={:.3} {}={:.3} takes the hob (tip cylinder {:.3} x {:.3} mm, {}={:.4}) {:.3} mm into {} near radius {:.3} mm, height {:.3} mm",
                            axes.radial,
                            to[0],
                            axes.axial,
                            to[1],
                            hob.od_mm,
                            hob.length_mm,
                            axes.swivel,
                            a_to,
                            w.depth,
                            ob.what,
                            w.at[0].hypot(w.at[1]),
                            w.at[2]
                        ),
                    ));
                }
            }
        }
        from = to;
        a_from = a_to;
    }
    findings
}

/// The deepest penetration of the swept hob into one obstacle along a move,
/// or `None` when the hob never comes near it.
fn sweep(
    hob: &HobSolid,
    ob: &Obstacle,
    rims: &[(f64, f64)],
    pose_at: &dyn Fn(f64) -> Pose,
    length: f64,
) -> Option<Worst> {
    let n = ((length / POSE_STEP_MM).ceil() as usize).clamp(1, 2000);
    // The deepest samples, deepest first, each with its parameters
    // (t, face, θ, s); face 2 marks an obstacle edge point inside the hob.
    let mut top: Vec<(Worst, f64, i8, f64, f64)> = Vec::with_capacity(REFINE_STARTS + 1);
    let mut consider = |w: Worst, t: f64, face: i8, theta: f64, s: f64| {
        if top.len() < REFINE_STARTS || w.depth > top[top.len() - 1].0.depth {
            let at = top.partition_point(|b| b.0.depth >= w.depth);
            top.insert(at, (w, t, face, theta, s));
            top.truncate(REFINE_STARTS);
        }
    };
    let dtheta = std::f64::consts::TAU / N_THETA as f64;
    let step = length / n as f64;
    let margin = coarse_margin(hob, ob, rims, step);
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let pose = pose_at(t);
        if ob.bound_distance(pose.centre) > hob.reach() + 1.0 {
            continue;
        }
        // A coarse pass bounds the pose's deepest point from above (depth is
        // Lipschitz in the point, every surface point lies within the coarse
        // grid's half-diagonal of a sample, and a pose between two sampled
        // ones within half a step): well clear, the fine pass is skipped.
        if coarse_depth(hob, ob, rims, &pose) + margin < 0.0 {
            continue;
        }
        for a in 0..N_THETA {
            let theta = dtheta * a as f64;
            for j in 0..N_AXIAL {
                let s = -hob.half + 2.0 * hob.half * j as f64 / (N_AXIAL - 1) as f64;
                let p = pose.point(hob, 0, theta, s);
                let w = Worst {
                    depth: ob.depth_of(p),
                    at: p,
                };
                consider(w, t, 0, theta, s);
            }
            for face in [-1i8, 1] {
                for ring in 0..=N_RINGS {
                    let s = hob.r * ring as f64 / N_RINGS as f64;
                    let p = pose.point(hob, face, theta, s);
                    let w = Worst {
                        depth: ob.depth_of(p),
                        at: p,
                    };
                    consider(w, t, face, theta, s);
                }
            }
        }
        // The obstacle's edge circles against the hob (face 2 + circle).
        for (c, &(z, r)) in rims.iter().enumerate() {
            for i in 0..N_RIM {
                let phi = std::f64::consts::TAU * i as f64 / N_RIM as f64;
                let q = rim_point(z, r, phi);
                let w = Worst {
                    depth: pose.depth_of(hob, q),
                    at: q,
                };
                consider(w, t, 2 + c as i8, phi, 0.0);
            }
        }
    }
    let mut best: Option<Worst> = None;
    for (w, t, face, theta, s) in top {
        let w = refine(hob, ob, rims, pose_at, n, dtheta, (w, t, face, theta, s));
        if best.is_none_or(|b| w.depth > b.depth) {
            best = Some(w);
        }
    }
    best
}

/// Samples of the coarse pass: around the hob, along it, on each end face's
/// radius, and on an obstacle's edge circle.
const COARSE_THETA: usize = 24;
const COARSE_AXIAL: usize = 8;
const COARSE_RINGS: usize = 3;
const COARSE_RIM: usize = 48;

/// The deepest point of the coarse samples of a pose (hob surface in the
/// obstacle, or obstacle edge in the hob).
fn coarse_depth(hob: &HobSolid, ob: &Obstacle, rims: &[(f64, f64)], pose: &Pose) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for a in 0..COARSE_THETA {
        let theta = std::f64::consts::TAU * a as f64 / COARSE_THETA as f64;
        for j in 0..COARSE_AXIAL {
            let s = -hob.half + 2.0 * hob.half * j as f64 / (COARSE_AXIAL - 1) as f64;
            best = best.max(ob.depth_of(pose.point(hob, 0, theta, s)));
        }
        for face in [-1i8, 1] {
            for ring in 0..=COARSE_RINGS {
                let s = hob.r * ring as f64 / COARSE_RINGS as f64;
                best = best.max(ob.depth_of(pose.point(hob, face, theta, s)));
            }
        }
    }
    for &(z, r) in rims {
        for i in 0..COARSE_RIM {
            let phi = std::f64::consts::TAU * i as f64 / COARSE_RIM as f64;
            best = best.max(pose.depth_of(hob, rim_point(z, r, phi)));
        }
    }
    best
}

/// How much deeper than the coarse samples a pose's deepest point can be:
/// the Lipschitz constant of the depth (1 + the obstacle's taper) times the
/// largest distance from any point to its nearest coarse sample (the hob
/// grid's and the edge circles' half spacings) plus half a pose step.
fn coarse_margin(hob: &HobSolid, ob: &Obstacle, rims: &[(f64, f64)], step: f64) -> f64 {
    let arc = hob.r * std::f64::consts::TAU / COARSE_THETA as f64;
    let along = 2.0 * hob.half / (COARSE_AXIAL - 1) as f64;
    let ring = hob.r / COARSE_RINGS as f64;
    let surface = 0.5 * arc.hypot(along.max(ring));
    let rim = rims
        .iter()
        .map(|(_, r)| 0.5 * r * std::f64::consts::TAU / COARSE_RIM as f64)
        .fold(0.0, f64::max);
    let taper = if ob.z_hi.is_finite() && ob.z_lo.is_finite() && ob.z_hi > ob.z_lo {
        ((ob.r_hi - ob.r_lo) / (ob.z_hi - ob.z_lo)).abs()
    } else {
        0.0
    };
    (1.0 + taper) * (surface.max(rim) + 0.5 * step) + PEN_TOL
}

/// A point of an edge circle at height `z`, radius `r`, angle `phi`.
fn rim_point(z: f64, r: f64, phi: f64) -> P3 {
    P3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Pattern search on (t, θ, s) from one sample: try a step either way along
/// each parameter, keep what goes deeper, halve the steps when nothing does.
fn refine(
    hob: &HobSolid,
    ob: &Obstacle,
    rims: &[(f64, f64)],
    pose_at: &dyn Fn(f64) -> Pose,
    n: usize,
    dtheta: f64,
    start: (Worst, f64, i8, f64, f64),
) -> Worst {
    let (mut w, mut t, face, mut theta, mut s) = start;
    let mut steps = [
        1.0 / n as f64,
        if face >= 2 {
            std::f64::consts::TAU / N_RIM as f64
        } else {
            dtheta
        },
        match face {
            0 => 2.0 * hob.half / (N_AXIAL - 1) as f64,
            1 | -1 => hob.r / N_RINGS as f64,
            _ => 0.0,
        },
    ];
    let eval = |t: f64, theta: f64, s: f64| {
        if face >= 2 {
            // An edge point of the obstacle, how deep inside the hob.
            let (z, r) = rims[(face - 2) as usize];
            let q = rim_point(z, r, theta);
            Worst {
                depth: pose_at(t).depth_of(hob, q),
                at: q,
            }
        } else {
            let p = pose_at(t).point(hob, face, theta, s);
            Worst {
                depth: ob.depth_of(p),
                at: p,
            }
        }
    };
    for _ in 0..REFINE_ITERS {
        let mut moved = false;
        for k in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut c = [t, theta, s];
                c[k] += sign * steps[k];
                c[0] = c[0].clamp(0.0, 1.0);
                let cand = eval(c[0], c[1], c[2]);
                if cand.depth > w.depth {
                    (w, t, theta, s) = (cand, c[0], c[1], c[2]);
                    moved = true;
                }
            }
        }
        if !moved {
            for st in &mut steps {
                *st /= 2.0;
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hob_just_above_a_disc_is_outside_and_just_below_is_inside() {
        // Hob r 40 × 100 without tilt at X = 73.75 over a blank R 40.5
        // (h 6.75): the lowest point over the disc lies √(h·(2r − h)) =
        // 22.235951 mm below the hob centre, at the blank's rim.
        let reach = (6.75f64 * (80.0 - 6.75)).sqrt();
        let hob = HobSolid {
            r: 40.0,
            half: 50.0,
        };
        let ob = Obstacle {
            what: "the blank".into(),
            z_lo: 0.0,
            z_hi: 30.0,
            r_lo: 40.5,
            r_hi: 40.5,
            rapid_only: true,
        };
        let rims = ob.rims();
        let at = |z: f64| move |_t: f64| Pose::new(73.75, z, 0.0, 0.0);
        // Outside, the depth is negative: a lower bound of the gap measured
        // along the hob's or the blank's own normal.
        let above = sweep(&hob, &ob, &rims, &at(30.0 + reach + 0.5), 0.0).unwrap();
        assert!(above.depth < -0.2 && above.depth > -0.5 - 1e-3, "{above:?}");
        let touching = sweep(&hob, &ob, &rims, &at(30.0 + reach + 0.01), 0.0).unwrap();
        assert!(touching.depth < 0.0, "{touching:?}");
        let below = sweep(&hob, &ob, &rims, &at(30.0 + reach - 0.5), 0.0).unwrap();
        assert!(below.depth > 0.1, "{below:?}");
    }

    #[test]
    fn a_tilted_hob_reaches_further_down_by_its_length() {
        // Tilted by 30° with half length 50, the low end of the axis is 25 mm
        // below the centre, and the tip cylinder r·cos 30° below that.
        let hob = HobSolid {
            r: 10.0,
            half: 50.0,
        };
        let table = Obstacle {
            what: "the table".into(),
            z_lo: f64::NEG_INFINITY,
            z_hi: 0.0,
            r_lo: 500.0,
            r_hi: 500.0,
            rapid_only: false,
        };
        let rims = table.rims();
        let low = 25.0 + 10.0 * 30f64.to_radians().cos();
        let pose = move |_t: f64| Pose::new(100.0, low - 1.0, 0.0, 30.0);
        let w = sweep(&hob, &table, &rims, &pose, 0.0).unwrap();
        assert!((w.depth - 1.0).abs() < 1e-3, "{w:?}");
        let pose = move |_t: f64| Pose::new(100.0, low + 1.0, 0.0, 30.0);
        let w = sweep(&hob, &table, &rims, &pose, 0.0).unwrap();
        assert!((w.depth + 1.0).abs() < 1e-3, "{w:?}");
    }

    #[test]
    fn a_move_through_the_blank_is_caught_between_its_end_points() {
        // A rapid straight across a small blank: both end poses are clear,
        // the middle of the move is not.
        let hob = HobSolid { r: 5.0, half: 10.0 };
        let ob = Obstacle {
            what: "the blank".into(),
            z_lo: 0.0,
            z_hi: 10.0,
            r_lo: 20.0,
            r_hi: 20.0,
            rapid_only: true,
        };
        let rims = ob.rims();
        let pose = |t: f64| Pose::new(-100.0 + 200.0 * t, 5.0, 0.0, 0.0);
        let w = sweep(&hob, &ob, &rims, &pose, 200.0).unwrap();
        assert!(w.depth > 4.0, "{w:?}");
    }
}
