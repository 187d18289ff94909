use super::*;
use std::time::Instant;

/// The whitening before this module used QR and Jacobi (nalgebra's SVD of the kept rows,
/// fresh buffers each call), kept to time both in one run.
fn whiten_nalgebra(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
    // Scale by a power of two (exact, and the cone does not change) so that the largest entry
    // is about 1: norms of rows with entries near 1e300 or 1e-300 neither overflow nor vanish.
    let amax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if amax > 0.0 && !(0.5..=1.0).contains(&amax) {
        let e = amax.log2().floor() as i32;
        // Two steps: 2^-e alone may not be representable for subnormal inputs.
        let (e1, e2) = (e / 2, e - e / 2);
        let scaled = v * 2f64.powi(-e1) * 2f64.powi(-e2);
        let mut wh = whiten_nalgebra_scaled(&scaled, tol);
        // (May overflow to infinity for subnormal inputs; users of `scale` check.)
        wh.scale = 2f64.powi(-e1) * 2f64.powi(-e2);
        return wh;
    }
    whiten_nalgebra_scaled(v, tol)
}
fn whiten_nalgebra_scaled(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
    let (n, d) = v.shape();
    let norms: Vec<f64> = (0..n).map(|i| v.row(i).norm()).collect();
    let maxn = norms.iter().copied().fold(0.0, f64::max);
    let kept: Vec<usize> = (0..n)
        .filter(|&i| norms[i] > 0.0 && norms[i] > tol.zero_generator * maxn)
        .collect();
    if kept.is_empty() {
        return Whitened {
            r: 0,
            d,
            q: Vec::new(),
            sv: Vec::new(),
            equations: DMatrix::identity(d, d),
            kept,
            w: Vec::new(),
            distinct: Vec::new(),
            equation_residual: 0.0,
            rank_undecided: None,
            scale: 1.0,
        };
    }
    let mut vk = DMatrix::zeros(kept.len(), d);
    for (r, &i) in kept.iter().enumerate() {
        vk.row_mut(r).copy_from(&v.row(i));
    }
    let (sv_all, vt) = sorted_svd_general(&vk);
    let r = numerical_rank(&sv_all, tol.rank);
    let mut q = Vec::with_capacity(r * d);
    for c in 0..r {
        q.extend(vt.row(c).iter());
    }
    let equations = vt.rows(r, d - r).into_owned();
    let sv = sv_all[..r].to_vec();
    let mut w = vec![0.0; kept.len() * r];
    let mut equation_residual: f64 = 0.0;
    let mut row = vec![0.0; d];
    for (t, &i) in kept.iter().enumerate() {
        for (x, y) in row.iter_mut().zip(v.row(i).iter()) {
            *x = *y;
        }
        let wt = &mut w[t * r..(t + 1) * r];
        for ((o, qc), &s) in wt.iter_mut().zip(q.chunks_exact(d)).zip(&sv) {
            *o = qc.iter().zip(&row).map(|(a, b)| a * b).sum::<f64>() / s;
        }
        normalize(wt);
        for e in 0..d - r {
            let ev = equations.row(e);
            let dot: f64 = ev.iter().zip(&row).map(|(a, b)| a * b).sum();
            equation_residual = equation_residual.max(dot.abs() / maxn);
        }
    }
    let mut distinct: Vec<usize> = Vec::with_capacity(kept.len());
    'outer: for t in 0..kept.len() {
        let gt = &w[t * r..(t + 1) * r];
        for &s in &distinct {
            let gs = &w[s * r..(s + 1) * r];
            // Most pairs differ in the first coordinate already.
            if (gt[0] - gs[0]).abs() > tol.duplicate {
                continue;
            }
            let d2: f64 = gt.iter().zip(gs).map(|(a, b)| (a - b) * (a - b)).sum();
            if d2 <= tol.duplicate * tol.duplicate {
                continue 'outer;
            }
        }
        distinct.push(t);
    }
    Whitened {
        r,
        d,
        q,
        sv,
        equations,
        kept,
        w,
        distinct,
        equation_residual,
        rank_undecided: None,
        scale: 1.0,
    }
}

fn median_us<F: FnMut()>(mut f: F) -> f64 {
    let mut t: Vec<f64> = (0..5000)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// Whitening time, before (nalgebra SVD, allocating) and now (warm buffers), on the golden
/// stances, in one run:
/// `cargo test --release -p polycone --lib whitening_time -- --ignored --nocapture`.
#[test]
#[ignore]
fn whitening_time() {
    let tol = Tolerances::default();
    for case in [
        "single_support_flat",
        "surface_cwc_foot",
        "double_support_flat",
        "double_support_stairs",
        "tilted_foot_hand_ledge",
        "opposing_walls_frictionless",
        "opposing_walls_friction",
    ] {
        let v = super::alloc_count::golden_for_tests(case);
        let (mut out, mut scratch) = (Whitened::default(), WhitenScratch::default());
        let mut before = f64::INFINITY;
        let mut after = f64::INFINITY;
        // Alternating rounds, the best median of each.
        for _ in 0..3 {
            before = before.min(median_us(|| {
                std::hint::black_box(whiten_nalgebra(std::hint::black_box(&v), &tol));
            }));
            after = after.min(median_us(|| {
                whiten_into(std::hint::black_box(&v), &tol, &mut out, &mut scratch);
                std::hint::black_box(&out);
            }));
        }
        let old = whiten_nalgebra(&v, &tol);
        assert_eq!(
            (old.r, &old.kept, &old.distinct),
            (out.r, &out.kept, &out.distinct)
        );
        eprintln!(
            "{case:30} {:3} generators: before {before:5.2} us, now {after:5.2} us, x{:.2}",
            v.nrows(),
            before / after
        );
    }
}
