//! The slack loop: `u . g` of every facet against every generator, in blocks of [`LANES`]
//! generators (portable and AVX2 + FMA builds, chosen at run time), with the incidence bitsets.

/// Lanes of the slack loop: generators are processed in blocks of this many, so that the
/// products, the running maximum and the incidence flags vectorize.
pub(super) const LANES: usize = 8;

/// Slacks `s = u . g` of `nf` unit facets `fw` (`nf x r`) against `ng` generators given
/// transposed in `gt` (`r x ng`), into `slack` (`nf x ng`, row-major). Returns the largest slack
/// (at least 0). When `inc` is `Some((inc, gw, eps))`, also sets bit `i` of facet `f`'s `gw`-word
/// row of `inc` for every `|s| <= eps`.
pub(super) fn slacks(
    fw: &[f64],
    gt: &[f64],
    r: usize,
    ng: usize,
    slack: &mut Vec<f64>,
    inc: Option<(&mut [u64], usize, f64)>,
) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU has AVX2 and FMA, checked just above.
            return unsafe { slacks_avx2(fw, gt, r, ng, slack, inc) };
        }
    }
    slacks_body(fw, gt, r, ng, slack, inc)
}

/// [`slacks_body`] compiled for AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn slacks_avx2(
    fw: &[f64],
    gt: &[f64],
    r: usize,
    ng: usize,
    slack: &mut Vec<f64>,
    inc: Option<(&mut [u64], usize, f64)>,
) -> f64 {
    slacks_body(fw, gt, r, ng, slack, inc)
}

#[inline(always)]
pub(super) fn slacks_body(
    fw: &[f64],
    gt: &[f64],
    r: usize,
    ng: usize,
    slack: &mut Vec<f64>,
    mut inc: Option<(&mut [u64], usize, f64)>,
) -> f64 {
    let nf = fw.len().checked_div(r).unwrap_or(0);
    slack.clear();
    slack.resize(nf * ng, 0.0);
    let mut lane_max = [0.0f64; LANES];
    for (f, (u, s_row)) in fw
        .chunks_exact(r.max(1))
        .zip(slack.chunks_exact_mut(ng.max(1)))
        .enumerate()
    {
        if r == 0 || ng == 0 {
            break;
        }
        // Blocks of LANES generators: the sums stay in registers across the r coordinates.
        let full = ng / LANES * LANES;
        for b in (0..full).step_by(LANES) {
            let mut acc = [0.0f64; LANES];
            for (c, &uc) in u.iter().enumerate() {
                let g = &gt[c * ng + b..c * ng + b + LANES];
                for (a, &gv) in acc.iter_mut().zip(g) {
                    *a += uc * gv;
                }
            }
            s_row[b..b + LANES].copy_from_slice(&acc);
            for (m, &s) in lane_max.iter_mut().zip(&acc) {
                *m = if s > *m { s } else { *m };
            }
        }
        for i in full..ng {
            let s: f64 = u
                .iter()
                .enumerate()
                .map(|(c, &uc)| uc * gt[c * ng + i])
                .sum();
            s_row[i] = s;
            lane_max[0] = if s > lane_max[0] { s } else { lane_max[0] };
        }
        if let Some((inc, gw, eps)) = inc.as_mut() {
            let row = &mut inc[f * *gw..(f + 1) * *gw];
            for (wi, chunk) in s_row.chunks(64).enumerate() {
                let mut w = 0u64;
                for (b, &s) in chunk.iter().enumerate() {
                    w |= ((s.abs() <= *eps) as u64) << b;
                }
                row[wi] = w;
            }
        }
    }
    lane_max.iter().copied().fold(0.0, f64::max)
}
