//! The Nelder–Mead simplex the fit runs, with its vertices kept in place:
//! sorting moves them (a stable sort by value, as a sort of their indices
//! would order them), and the trial points reuse their buffers, so an
//! iteration allocates nothing; the arithmetic is the textbook method's,
//! operation for operation.
//!
//! A trial point's value is compared, not kept, when it loses: the
//! reflection against the second worst (its exact value matters only
//! below that), the expansion against the reflection, the contraction
//! against the worst. So `f` is told that bound and may stop at it: any
//! value at or above the bound takes the same branch (each comparison is
//! a strict `<` against the bound), and a point kept always has its exact
//! value. The path is the textbook method's to the bit either way (the
//! test runs it with a function that returns nonsense above the bound).

/// Nelder–Mead on `f` from `x0` with initial steps `scale`: at most
/// `iterations` steps, stopping once the best value is at most
/// `good_enough` or the simplex has flattened. Returns the best vertex and
/// its value. `f(x, bound)` is the value at x when it is below `bound`,
/// else any value at or above `bound` (see the module).
pub(crate) fn nelder_mead(
    f: &dyn Fn(&[f64], f64) -> f64,
    x0: &[f64],
    scale: &[f64],
    iterations: usize,
    good_enough: f64,
) -> (Vec<f64>, f64) {
    let n = x0.len();
    let mut s: Vec<(Vec<f64>, f64)> = (0..=n)
        .map(|i| {
            let mut x = x0.to_vec();
            if i > 0 {
                x[i - 1] += scale[i - 1];
            }
            let fx = f(&x, f64::INFINITY);
            (x, fx)
        })
        .collect();
    let (mut c, mut xr, mut xe, mut xc) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for _ in 0..iterations {
        s.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (s[0].1, s[n].1);
        // Stop once good enough, or once the simplex has flattened (a
        // relative spread of 1e-6 moves the deviation by far less than the
        // tolerance's rounding).
        if best <= good_enough || (worst - best).abs() <= 1e-6 * best.abs().max(1e-12) {
            break;
        }
        for (j, cj) in c.iter_mut().enumerate() {
            *cj = s[..n].iter().map(|x| x.0[j]).sum::<f64>() / n as f64;
        }
        let along = |t: f64, out: &mut Vec<f64>, far: &[f64]| {
            for j in 0..n {
                out[j] = c[j] + t * (far[j] - c[j]);
            }
        };
        along(-1.0, &mut xr, &s[n].0);
        // Kept below the second worst; compared only, at or above it.
        let fr = f(&xr, s[n - 1].1);
        if fr < best {
            along(-2.0, &mut xe, &s[n].0);
            // Kept only below the reflection.
            let fe = f(&xe, fr);
            if fe < fr {
                std::mem::swap(&mut s[n].0, &mut xe);
                s[n].1 = fe;
            } else {
                std::mem::swap(&mut s[n].0, &mut xr);
                s[n].1 = fr;
            }
        } else if fr < s[n - 1].1 {
            std::mem::swap(&mut s[n].0, &mut xr);
            s[n].1 = fr;
        } else {
            along(0.5, &mut xc, &s[n].0);
            // Kept only below the worst.
            let fc = f(&xc, worst);
            if fc < worst {
                std::mem::swap(&mut s[n].0, &mut xc);
                s[n].1 = fc;
            } else {
                let (first, rest) = s.split_at_mut(1);
                let x0 = &first[0].0;
                for v in rest.iter_mut() {
                    for (vj, x0j) in v.0.iter_mut().zip(x0) {
                        *vj = x0j + 0.5 * (*vj - x0j);
                    }
                    v.1 = f(&v.0, f64::INFINITY);
                }
            }
        }
    }
    let best = (0..=n)
        .min_by(|&a, &b| s[a].1.total_cmp(&s[b].1))
        .expect("a simplex");
    s.swap_remove(best)
}

#[cfg(test)]
mod tests {
    use super::nelder_mead;

    /// A cost function.
    type Cost<'a> = &'a dyn Fn(&[f64]) -> f64;
    /// A cost function told the bound it may stop at.
    type Bounded<'a> = &'a dyn Fn(&[f64], f64) -> f64;

    /// The method as first written: the vertices and their values sorted
    /// by a sort of their indices and copied, each trial point a new
    /// vector.
    fn textbook(
        f: &dyn Fn(&[f64]) -> f64,
        x0: &[f64],
        scale: &[f64],
        iterations: usize,
        good_enough: f64,
    ) -> (Vec<f64>, f64) {
        let n = x0.len();
        let mut s: Vec<Vec<f64>> = (0..=n)
            .map(|i| {
                let mut x = x0.to_vec();
                if i > 0 {
                    x[i - 1] += scale[i - 1];
                }
                x
            })
            .collect();
        let mut fs: Vec<f64> = s.iter().map(|x| f(x)).collect();
        for _ in 0..iterations {
            let mut order: Vec<usize> = (0..=n).collect();
            order.sort_by(|&a, &b| fs[a].total_cmp(&fs[b]));
            s = order.iter().map(|&i| s[i].clone()).collect();
            fs = order.iter().map(|&i| fs[i]).collect();
            if fs[0] <= good_enough || (fs[n] - fs[0]).abs() <= 1e-6 * fs[0].abs().max(1e-12) {
                break;
            }
            let c: Vec<f64> = (0..n)
                .map(|j| s[..n].iter().map(|x| x[j]).sum::<f64>() / n as f64)
                .collect();
            let along =
                |t: f64| -> Vec<f64> { (0..n).map(|j| c[j] + t * (s[n][j] - c[j])).collect() };
            let xr = along(-1.0);
            let fr = f(&xr);
            if fr < fs[0] {
                let xe = along(-2.0);
                let fe = f(&xe);
                (s[n], fs[n]) = if fe < fr { (xe, fe) } else { (xr, fr) };
            } else if fr < fs[n - 1] {
                (s[n], fs[n]) = (xr, fr);
            } else {
                let xc = along(0.5);
                let fc = f(&xc);
                if fc < fs[n] {
                    (s[n], fs[n]) = (xc, fc);
                } else {
                    for i in 1..=n {
                        s[i] = (0..n)
                            .map(|j| s[0][j] + 0.5 * (s[i][j] - s[0][j]))
                            .collect();
                        fs[i] = f(&s[i]);
                    }
                }
            }
        }
        let best = (0..=n)
            .min_by(|&a, &b| fs[a].total_cmp(&fs[b]))
            .expect("a simplex");
        (s[best].clone(), fs[best])
    }

    /// On Rosenbrock's valley, a minimax of distances (the fit's kind of
    /// cost: kinks, ties) and a flat function (every value equal), from
    /// several starts and sizes, in 2 to 7 dimensions: the same vertex and
    /// value to the last bit, after every number of iterations, whether the
    /// function gives its exact value or stops at the bound it is told.
    #[test]
    fn the_simplex_in_place_runs_as_the_textbook_one() {
        let rosenbrock = |x: &[f64]| -> f64 {
            x.windows(2)
                .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
                .sum()
        };
        let minimax = |x: &[f64]| -> f64 {
            x.iter()
                .enumerate()
                .map(|(i, v)| (v - 0.3 * i as f64).abs() * (1.0 + i as f64))
                .fold(0.0, f64::max)
        };
        let flat = |_: &[f64]| -> f64 { 1.0 };
        let fs: [Cost; 3] = [&rosenbrock, &minimax, &flat];
        let mut runs = 0;
        for f in fs {
            for n in 2..=7 {
                for start in [-1.2, 0.4, 3.0] {
                    let x0: Vec<f64> = (0..n).map(|i| start + 0.1 * i as f64).collect();
                    let scale: Vec<f64> = (0..n).map(|i| 0.05 + 0.01 * i as f64).collect();
                    for iterations in [0, 1, 7, 50, 400, 3000] {
                        for good in [0.0, 1e-3] {
                            let b = textbook(f, &x0, &scale, iterations, good);
                            // The exact value always, and a value far
                            // off (but at or above the bound) whenever
                            // the exact one reaches the bound.
                            let exact = |x: &[f64], _: f64| f(x);
                            let stopping = |x: &[f64], bound: f64| {
                                let v = f(x);
                                if v >= bound {
                                    bound + 12_345.0
                                } else {
                                    v
                                }
                            };
                            for g in [&exact as Bounded, &stopping] {
                                let a = nelder_mead(g, &x0, &scale, iterations, good);
                                let bits =
                                    |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                                assert_eq!(
                                    bits(&a.0),
                                    bits(&b.0),
                                    "n {n} start {start} it {iterations}"
                                );
                                assert_eq!(a.1.to_bits(), b.1.to_bits());
                                runs += 1;
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(runs, 3 * 6 * 3 * 6 * 2 * 2);
    }
}
