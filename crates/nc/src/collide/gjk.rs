//! The distance between two convex sets given by their support functions:
//! the Gilbert–Johnson–Keerthi iteration, with the bounds it certifies.
//!
//! The distance between A and B is the distance from the origin to their
//! Minkowski difference K = A − B, whose support in a direction n is
//! s_A(n) − s_B(−n). The iteration keeps a simplex of at most four support
//! points of K and v, the point of the simplex nearest the origin; then
//!
//! - **upper bound** |v|: v is a convex combination of points of K, so
//!   v = a − b with a ∈ A, b ∈ B (the same combination of the support points
//!   of each set, which are convex), and dist(A, B) ≤ |v|;
//! - **lower bound** v̂·w with w = s_K(−v): w minimises v̂·k over K, so every
//!   k ∈ K has |k| ≥ v̂·k ≥ v̂·w; when it is positive, the plane v̂·x = v̂·w
//!   separates K from the origin and the sets do not meet;
//! - **contact**: when the origin lies in a tetrahedron of support points,
//!   it is a convex combination of points of K, so A and B share a point.
//!
//! Each step adds w and moves v to the simplex's nearest point, which is
//! nearer than before unless v is already the nearest point of K (then the
//! lower bound meets the upper one): the bounds close, and the caller stops
//! when they answer its question (`Stop`).

use super::shapes::Support;
use super::P3;

/// Most steps of one distance query.
const MAX_STEPS: usize = 200;

/// When to stop: as soon as one of these holds.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stop {
    /// The lower bound exceeds this (the sets are at least this far apart).
    pub(crate) apart: f64,
    /// The upper bound is at most this (the sets come this close).
    pub(crate) close: f64,
    /// The bounds are this close to each other.
    pub(crate) tol: f64,
}

/// What a distance query certifies.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Gap {
    /// Lower bound of the distance; positive: the sets do not meet.
    pub(crate) lb: f64,
    /// Upper bound: the distance between `on_a` and `on_b`.
    pub(crate) ub: f64,
    /// A point of A.
    pub(crate) on_a: P3,
    /// The sweep parameter of the pose `on_a` belongs to.
    pub(crate) tau_a: f64,
    /// A point of B.
    pub(crate) on_b: P3,
}

#[derive(Debug, Clone, Copy)]
struct Vertex {
    w: P3,
    a: P3,
    b: P3,
    tau: f64,
}

/// The vertices kept of a simplex, their barycentric weights, how many, and
/// the nearest point itself (computed directly, not from the weights: see
/// `triangle`).
type Pick = ([usize; 4], [f64; 4], usize, P3);

/// Bounds on the distance between `a` and `b`.
pub(crate) fn gap(a: &impl Support, b: &impl Support, stop: Stop) -> Gap {
    let (a0, b0) = (a.inner(), b.inner());
    let mut out = Gap {
        lb: f64::NEG_INFINITY,
        ub: (a0 - b0).norm(),
        on_a: a0,
        tau_a: 0.5,
        on_b: b0,
    };
    let mut v = a0 - b0;
    let zero = Vertex {
        w: P3::zeros(),
        a: P3::zeros(),
        b: P3::zeros(),
        tau: 0.0,
    };
    let mut simplex = [zero; 4];
    let mut n = 0;
    for _ in 0..MAX_STEPS {
        let norm = v.norm();
        if norm <= stop.close || norm == 0.0 {
            break;
        }
        let dir = -v / norm;
        let (pa, tau) = a.support(&dir);
        let (pb, _) = b.support(&-dir);
        let w = pa - pb;
        out.lb = out.lb.max(-dir.dot(&w));
        if out.lb > stop.apart || out.ub - out.lb <= stop.tol {
            break;
        }
        // A support point already in the simplex adds nothing: v is as near
        // as this arithmetic finds.
        let scale = 1e-13 * (1.0 + w.norm());
        if simplex[..n].iter().any(|s| (s.w - w).norm() <= scale) {
            break;
        }
        simplex[n] = Vertex {
            w,
            a: pa,
            b: pb,
            tau,
        };
        n += 1;
        let (keep, weights, count, point) = nearest(&simplex, n);
        let (mut pa, mut pb, mut pt) = (P3::zeros(), P3::zeros(), 0.0);
        let mut reduced = [zero; 4];
        for k in 0..count {
            let s = simplex[keep[k]];
            let l = weights[k];
            pa += s.a * l;
            pb += s.b * l;
            pt += s.tau * l;
            reduced[k] = s;
        }
        if n > 1 && count < 4 && point.norm() >= norm {
            // No progress (rounding): keep the last certified point. (The
            // first point, the inner points' difference, is no simplex
            // point, and the first support point may lie further out.)
            break;
        }
        (simplex, n, v) = (reduced, count, point);
        out.on_a = pa;
        out.on_b = pb;
        out.tau_a = pt;
        out.ub = if count == 4 { 0.0 } else { (pa - pb).norm() };
        if count == 4 {
            break;
        }
    }
    out
}

/// The vertices of the simplex (its first `n`) whose convex hull holds its
/// point nearest the origin, with that point's barycentric weights (all
/// four only when the origin lies inside the tetrahedron).
fn nearest(s: &[Vertex; 4], n: usize) -> Pick {
    match n {
        1 => one(0, s[0].w),
        2 => segment(s[0].w, s[1].w, [0, 1]),
        3 => triangle([s[0].w, s[1].w, s[2].w], [0, 1, 2]),
        _ => tetrahedron([s[0].w, s[1].w, s[2].w, s[3].w]),
    }
}

/// One kept vertex, at `p`.
fn one(i: usize, p: P3) -> Pick {
    ([i, 0, 0, 0], [1.0, 0.0, 0.0, 0.0], 1, p)
}

/// Two kept vertices a and b with weights 1 − t and t.
fn two(i: usize, j: usize, t: f64, a: P3, b: P3) -> Pick {
    ([i, j, 0, 0], [1.0 - t, t, 0.0, 0.0], 2, a + (b - a) * t)
}

/// Nearest point of the segment ab to the origin.
fn segment(a: P3, b: P3, idx: [usize; 2]) -> Pick {
    let ab = b - a;
    let len2 = ab.dot(&ab);
    if len2 <= 1e-300 {
        return one(idx[1], b);
    }
    let t = -a.dot(&ab) / len2;
    if t <= 0.0 {
        one(idx[0], a)
    } else if t >= 1.0 {
        one(idx[1], b)
    } else {
        two(idx[0], idx[1], t, a, b)
    }
}

/// Nearest point of the triangle to the origin by its Voronoi regions
/// (Ericson, Real-Time Collision Detection, §5.1.5). Inside the face the
/// point is the origin's projection on the plane, n·(n·a)/|n|²: the
/// weights come from differences of products of dot products and lose
/// digits on a long thin triangle near the origin (the simplex of two
/// nearly parallel faces), and a point built from them would point the next
/// search askew; the projection keeps its direction to rounding.
fn triangle(p: [P3; 3], idx: [usize; 3]) -> Pick {
    let [a, b, c] = p;
    let (ab, ac) = (b - a, c - a);
    let (d1, d2) = (-ab.dot(&a), -ac.dot(&a));
    if d1 <= 0.0 && d2 <= 0.0 {
        return one(idx[0], a);
    }
    let (d3, d4) = (-ab.dot(&b), -ac.dot(&b));
    if d3 >= 0.0 && d4 <= d3 {
        return one(idx[1], b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return two(idx[0], idx[1], d1 / (d1 - d3), a, b);
    }
    let (d5, d6) = (-ab.dot(&c), -ac.dot(&c));
    if d6 >= 0.0 && d5 <= d6 {
        return one(idx[2], c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return two(idx[0], idx[2], d2 / (d2 - d6), a, c);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return two(idx[1], idx[2], (d4 - d3) / ((d4 - d3) + (d5 - d6)), b, c);
    }
    let sum = va + vb + vc;
    let n = ab.cross(&ac);
    let n2 = n.dot(&n);
    if sum <= 1e-300 || n2 <= 1e-300 {
        // A degenerate (flat) triangle: the nearest of its edges.
        return [(0, 1), (0, 2), (1, 2)]
            .map(|(i, j)| segment(p[i], p[j], [idx[i], idx[j]]))
            .into_iter()
            .min_by(|x, y| x.3.norm().total_cmp(&y.3.norm()))
            .unwrap_or_else(|| one(idx[0], a));
    }
    let (v, w) = (vb / sum, vc / sum);
    let point = n * (n.dot(&a) / n2);
    let weights = [(1.0 - v - w).max(0.0), v.max(0.0), w.max(0.0)];
    let total: f64 = weights.iter().sum();
    let [l0, l1, l2] = weights.map(|l| l / total);
    ([idx[0], idx[1], idx[2], 0], [l0, l1, l2, 0.0], 3, point)
}

/// Nearest point of the tetrahedron to the origin: inside, all four
/// vertices with the origin's barycentric weights; else the nearest point of
/// the faces the origin lies beyond (Ericson §5.1.6). A flat tetrahedron has
/// no inside: all its faces are tried.
fn tetrahedron(p: [P3; 4]) -> Pick {
    const FACES: [([usize; 3], usize); 4] = [
        ([0, 1, 2], 3),
        ([0, 1, 3], 2),
        ([0, 2, 3], 1),
        ([1, 2, 3], 0),
    ];
    let scale = p.iter().map(|q| q.norm()).fold(0.0, f64::max).max(1e-300);
    let mut best: Option<Pick> = None;
    let mut inside = [0.0; 4];
    for (face, opposite) in FACES {
        let [a, b, c] = face.map(|i| p[i]);
        let n = (b - a).cross(&(c - a));
        let side_o = -a.dot(&n);
        let side_d = (p[opposite] - a).dot(&n);
        let flat = side_d.abs() <= 1e-12 * scale * n.norm();
        if flat || side_o * side_d < 0.0 {
            let pick = triangle([a, b, c], face);
            if best.is_none_or(|b| pick.3.norm() < b.3.norm()) {
                best = Some(pick);
            }
        } else {
            inside[opposite] = side_o / side_d;
        }
    }
    // The origin's weights from the four faces, made a convex combination
    // (rounding may leave their sum off 1 on a thin tetrahedron, and the
    // witness points built from them must lie in their sets).
    best.unwrap_or_else(|| {
        let clamped = inside.map(|l| l.max(0.0));
        let sum: f64 = clamped.iter().sum();
        let weights = if sum > 0.0 {
            clamped.map(|l| l / sum)
        } else {
            [0.25; 4]
        };
        ([0, 1, 2, 3], weights, 4, P3::zeros())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::shapes::{Frustum, Sweep};

    fn far(tol: f64) -> Stop {
        Stop {
            apart: f64::INFINITY,
            close: 0.0,
            tol,
        }
    }

    #[test]
    fn the_nearest_point_of_a_long_thin_triangle_is_square_to_it() {
        // A simplex met on a hob 32 mm deep in a table: two vertices 68 mm
        // one way, one 88 mm the other, the origin 1.7e-4 mm off its plane.
        // Built from the barycentric weights, the nearest point came out
        // 3.5e-4 rad askew (6e-8 mm of rounding on 1.7e-4 mm), which points
        // the next search askew and spoils its lower bound; the projection
        // on the plane is square to the triangle.
        let p = [
            P3::new(0.002652997875429719, -87.70822746147965, 36.960304423676995),
            P3::new(
                -0.002561886519927725,
                67.76322216291697,
                -28.553202708879667,
            ),
            P3::new(0.009756570188045544, 67.71166351129206, -28.5647495364574),
        ];
        let (_, _, count, v) = triangle(p, [0, 1, 2]);
        assert_eq!(count, 3);
        assert!((v.norm() - 1.7e-4).abs() < 1e-5, "{v:?}");
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let edge = p[j] - p[i];
            let cos = v.dot(&edge) / (v.norm() * edge.norm());
            assert!(cos.abs() < 1e-9, "edge {i}{j}: cos {cos}");
        }
    }

    #[test]
    fn a_hob_over_a_disc_by_its_closed_form_distance() {
        // A hob without tilt (axis along y) 5 mm above a disc's top face,
        // over the disc: the distance is 5, the nearest points one above the
        // other.
        let hob = Sweep {
            start: P3::new(10.0, 0.0, 30.0 + 5.0 + 40.0),
            travel: P3::zeros(),
            axis: P3::new(0.0, 1.0, 0.0),
            r: 40.0,
            half: 50.0,
        };
        let disc = Frustum {
            z_lo: 0.0,
            z_hi: 30.0,
            r_lo: 60.0,
            r_hi: 60.0,
            grow: 0.0,
        };
        let g = gap(&hob, &disc, far(1e-9));
        assert!(
            (g.lb - 5.0).abs() < 1e-8 && (g.ub - 5.0).abs() < 1e-8,
            "{g:?}"
        );
        // Beside the disc's rim: distance from the rim circle's nearest
        // point (60, 0, 30) to the hob's axis line, minus r.
        let hob = Sweep {
            start: P3::new(120.0, 0.0, 40.0),
            ..hob
        };
        let g = gap(&hob, &disc, far(1e-9));
        let expect = (60.0f64).hypot(10.0) - 40.0;
        assert!(
            (g.lb - expect).abs() < 1e-7 && (g.ub - expect).abs() < 1e-7,
            "{g:?} {expect}"
        );
        // Overlapping: a contact.
        let hob = Sweep {
            start: P3::new(90.0, 0.0, 20.0),
            ..hob
        };
        let g = gap(&hob, &disc, far(1e-9));
        assert!(g.ub <= 1e-9 && g.lb <= 1e-9, "{g:?}");
    }
}
