use super::*;
use proptest::prelude::*;

/// [`qr_jacobi_svd`] for `d <= 8`: the number of sweeps (`None`: not handled or not
/// converged).
fn small_svd(a: &mut [f64], n: usize, d: usize, sv: &mut [f64], vt: &mut [f64]) -> Option<usize> {
    let (o, m) = ([JACOBI_ORTHOGONALITY, JACOBI_NOISE], JACOBI_MAX_SWEEPS);
    match d {
        1 => qr_jacobi_svd::<1>(a, n, o, m, sv, vt),
        2 => qr_jacobi_svd::<2>(a, n, o, m, sv, vt),
        3 => qr_jacobi_svd::<3>(a, n, o, m, sv, vt),
        4 => qr_jacobi_svd::<4>(a, n, o, m, sv, vt),
        5 => qr_jacobi_svd::<5>(a, n, o, m, sv, vt),
        6 => qr_jacobi_svd::<6>(a, n, o, m, sv, vt),
        7 => qr_jacobi_svd::<7>(a, n, o, m, sv, vt),
        8 => qr_jacobi_svd::<8>(a, n, o, m, sv, vt),
        _ => None,
    }
}

/// The whitening as it was computed before the QR + Jacobi path: nalgebra's SVD of the
/// kept rows (the same scaling, norms and rank rule), for comparison.
fn reference(v: &DMatrix<f64>, tol: &Tolerances) -> (Vec<usize>, Vec<f64>, DMatrix<f64>) {
    let amax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut vs = v.clone();
    if amax > 0.0 && !(0.5..=1.0).contains(&amax) {
        let e = amax.log2().floor() as i32;
        vs = vs * 2f64.powi(-(e / 2)) * 2f64.powi(-(e - e / 2));
    }
    let norms: Vec<f64> = (0..vs.nrows()).map(|i| vs.row(i).norm()).collect();
    let maxn = norms.iter().copied().fold(0.0, f64::max);
    let kept: Vec<usize> = (0..vs.nrows())
        .filter(|&i| norms[i] > 0.0 && norms[i] > tol.zero_generator * maxn)
        .collect();
    if kept.is_empty() {
        return (kept, Vec::new(), DMatrix::zeros(0, v.ncols()));
    }
    let vk = DMatrix::from_fn(kept.len(), v.ncols(), |t, j| vs[(kept[t], j)]);
    let (sv, vt) = sorted_svd_general(&vk);
    (kept, sv, vt)
}

/// Largest entry of `|a - b|`.
fn max_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).abs().max()
}

/// Checks the fast whitening of `v` against [`reference`] and against the definition.
fn check_against_reference(v: &DMatrix<f64>) -> Result<(), TestCaseError> {
    let tol = Tolerances::default();
    let d = v.ncols();
    let wh = whiten(v, &tol);
    let (kept, sv_ref, vt_ref) = reference(v, &tol);
    prop_assert_eq!(&wh.kept, &kept);
    if kept.is_empty() {
        prop_assert_eq!(wh.r, 0);
        prop_assert_eq!(max_diff(&wh.equations, &DMatrix::identity(d, d)), 0.0);
        return Ok(());
    }
    // The fast path handled it (no fallback), in few sweeps.
    let mut a = vec![0.0; kept.len() * d];
    for (t, &i) in kept.iter().enumerate() {
        for j in 0..d {
            a[j * kept.len() + t] = v[(i, j)] * wh.scale;
        }
    }
    let (mut sv, mut vt) = (vec![0.0; d], vec![0.0; d * d]);
    let sweeps = small_svd(&mut a, kept.len(), d, &mut sv, &mut vt);
    prop_assert!(sweeps.is_some_and(|s| s <= 12), "sweeps {:?}", sweeps);
    // Singular values: those of `V + E`, `|E| <= c eps |V|` (Weyl: they move by |E|).
    // Where the general SVD disagrees, it is the one that is wrong: its `|V q_c|` is not its
    // `s_c`, while ours is (nalgebra 0.34 is off by 1.5e-3 on a rank-2 19 x 8 matrix, and
    // LAPACK agrees with this one).
    let smax = sv_ref[0].max(sv[0]);
    // `|E| <= c eps |V|_F`, with the `16 eps` per column of the skipped rotations.
    let vk = DMatrix::from_fn(kept.len(), d, |t, j| v[(kept[t], j)] * wh.scale);
    let bound = 64.0 * f64::EPSILON * vk.norm();
    let defect = |s: &[f64], vt: &dyn Fn(usize, usize) -> f64| -> f64 {
        (0..d)
            .map(|c| {
                let q = nalgebra::DVector::from_fn(d, |j, _| vt(c, j));
                ((&vk * q).norm() - s[c]).abs()
            })
            .fold(0.0, f64::max)
    };
    let ours = defect(&sv, &|c, j| vt[c * d + j]);
    prop_assert!(ours <= bound, "|V q_c| - s_c: {ours:e}");
    if sv.iter().zip(&sv_ref).any(|(a, b)| (a - b).abs() > bound) {
        let theirs = defect(&sv_ref, &|c, j| vt_ref[(c, j)]);
        prop_assert!(theirs > bound, "{sv:?} vs {sv_ref:?}");
        return Ok(());
    }
    // The rank, unless a singular value is within rounding of the threshold.
    let r_ref = numerical_rank(&sv_ref, tol.rank);
    let near = sv_ref
        .iter()
        .any(|&s| (s - tol.rank * smax).abs() <= 2.0 * bound);
    if near {
        return Ok(());
    }
    prop_assert_eq!(wh.r, r_ref);
    let r = wh.r;
    // [Q; E] is orthogonal.
    let mut all = DMatrix::zeros(d, d);
    for c in 0..r {
        for j in 0..d {
            all[(c, j)] = wh.q[c * d + j];
        }
    }
    all.rows_mut(r, d - r).copy_from(&wh.equations);
    prop_assert!(max_diff(&(&all * all.transpose()), &DMatrix::identity(d, d)) <= 1e-14);
    // span(V): the projector on the rows of Q, up to rounding over the gap (Wedin).
    let gap = sv_ref[r - 1] - sv_ref.get(r).copied().unwrap_or(0.0);
    let q_new = all.rows(0, r).into_owned();
    let q_ref = vt_ref.rows(0, r).into_owned();
    let p_diff = max_diff(&(q_new.transpose() * &q_new), &(q_ref.transpose() * &q_ref));
    prop_assert!(
        p_diff <= 1e-14 * smax / gap,
        "projector {p_diff:e}, gap {gap:e}"
    );
    // The whitened generators before normalization, `Y = V Q^T S^-1`, have orthonormal
    // columns: rounding in `Q` along `s_1` shows up multiplied by `s_1 / s_r`. (Checked
    // here rather than against the general SVD, which is the less accurate of the two:
    // on a row scaled by 1e4 it gave cosines of 4e-9 between whitened rows that are
    // orthogonal, where this whitening gives 5e-13.)
    let cond = smax / sv_ref[r - 1];
    let mut y = DMatrix::zeros(kept.len(), r);
    for (t, &i) in kept.iter().enumerate() {
        for c in 0..r {
            y[(t, c)] = (0..d)
                .map(|j| wh.q[c * d + j] * v[(i, j)] * wh.scale)
                .sum::<f64>()
                / wh.sv[c];
        }
        // `w` is `y` normalized (each component within `d eps |v| / s_r`, relative to
        // `|y| >= |v| / s_1`).
        let yn = y.row(t).norm();
        for c in 0..r {
            let err = (wh.w[t * r + c] - y[(t, c)] / yn).abs();
            prop_assert!(err <= 4.0 * d as f64 * f64::EPSILON * cond, "w: {err:e}");
        }
    }
    let orth = max_diff(&(y.transpose() * &y), &DMatrix::identity(r, r));
    prop_assert!(
        orth <= 64.0 * f64::EPSILON * cond,
        "Y^T Y - I: {orth:e}, cond {cond:e}"
    );
    prop_assert!(wh.equation_residual <= 1e-14 + tol.rank * 2.0);
    // Positively parallel rows (the copies the test makes, and rows of a rank-1 matrix
    // with the same sign) are merged, the others kept: unit input rows at most 1e-9 apart
    // (rounding makes ~1e-16; random rows are much farther apart). Their whitened rows
    // agree up to rounding times `cond` (the same bound as above), so this is only
    // expected when that is below `tol.duplicate`.
    // (And only when the directions dropped by the rank decision are rounding: otherwise
    // rows that differ only along them are rightly merged.)
    let dropped = sv_ref.get(r).copied().unwrap_or(0.0);
    if 64.0 * f64::EPSILON * cond > tol.duplicate || dropped > bound {
        return Ok(());
    }
    let unit = |i: usize| (v.row(i) * wh.scale).normalize();
    let mut distinct_ref: Vec<usize> = Vec::new();
    for t in 0..kept.len() {
        if !distinct_ref
            .iter()
            .any(|&s| (unit(kept[t]) - unit(kept[s])).norm() <= 1e-9)
        {
            distinct_ref.push(t);
        }
    }
    prop_assert_eq!(&wh.distinct, &distinct_ref);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]
    /// Random `n x d` matrices (`n < d` included) of rank `k`, rows scaled by up to
    /// `10^+-6`, some rows positive multiples of others, the whole scaled by `10^e` with
    /// `e` up to +-300: the fast whitening agrees with the general SVD.
    #[test]
    fn fast_whitening_matches_the_general_svd(
        d in 1usize..=8,
        n in 0usize..20,
        k in 1usize..=8,
        left in proptest::collection::vec(-1.0f64..1.0, 20 * 8),
        right in proptest::collection::vec(-1.0f64..1.0, 8 * 8),
        row_exp in proptest::collection::vec(-6i32..=6, 20),
        scale_rows in any::<bool>(),
        copies in 0usize..4,
        global_exp in -300i32..=300,
    ) {
        let k = k.min(d);
        let l = DMatrix::from_fn(n, k, |i, j| left[i * 8 + j]);
        let rt = DMatrix::from_fn(k, d, |i, j| right[i * 8 + j]);
        let mut v = l * rt;
        if scale_rows {
            for i in 0..n {
                v.row_mut(i).scale_mut(10f64.powi(row_exp[i]));
            }
        }
        for c in 0..copies.min(n / 2) {
            let row = v.row(n - 1 - c) * 3.0;
            v.row_mut(c).copy_from(&row);
        }
        let v = v * 10f64.powi(global_exp);
        check_against_reference(&v)?;
    }
}

/// The duplicate test, brute force: each row against every earlier distinct one.
fn distinct_brute_force(w: &[f64], nk: usize, r: usize, duplicate: f64) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::new();
    for t in 0..nk {
        let gt = &w[t * r..(t + 1) * r];
        let dup = out.iter().any(|&s| {
            let gs = &w[s * r..(s + 1) * r];
            gt.iter()
                .zip(gs)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                <= duplicate * duplicate
        });
        if !dup {
            out.push(t);
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// `mark_distinct` decides like the brute force, on rows with tied coordinates and
    /// copies moved by 0.3 to 3 times the threshold (both sides of it), in any direction.
    #[test]
    fn mark_distinct_matches_the_brute_force(
        r in 0usize..5,
        grid in proptest::collection::vec(-2i32..=2, 24 * 4),
        jitter in proptest::collection::vec(-3.0f64..3.0, 24 * 4),
        copy_of in proptest::collection::vec(0usize..24, 24),
        nk in 0usize..24,
    ) {
        let dup = 1e-12;
        let mut w = vec![0.0; nk * r];
        for t in 0..nk {
            for c in 0..r {
                w[t * r + c] = grid[t * 4 + c] as f64 * 0.5;
            }
            // Some rows: a copy of an earlier one, moved by jitter * dup per coordinate.
            if copy_of[t] < t && t % 2 == 0 {
                for c in 0..r {
                    w[t * r + c] = w[copy_of[t] * r + c] + jitter[t * 4 + c] * dup / 2.0;
                }
            }
        }
        let (mut distinct, mut order, mut position, mut flag) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        mark_distinct(&w, nk, r, dup, &mut distinct, [&mut order, &mut position], &mut flag);
        prop_assert_eq!(distinct, distinct_brute_force(&w, nk, r, dup));
    }
}

/// The golden stances, and a flat one (rank 5), agree with the general SVD too.
#[test]
fn golden_stances_match_the_general_svd() {
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
        check_against_reference(&v).unwrap();
        let mut flat = v.clone();
        flat.column_mut(5).fill(0.0);
        check_against_reference(&flat).unwrap();
    }
}
