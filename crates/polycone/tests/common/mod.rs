//! Helpers shared by the integration tests.
#![allow(dead_code)]

use polycone::nalgebra::DMatrix;

#[allow(unused_imports)] // not every test binary reads hex fixtures
pub use stance_test_support::hex::parse_hex;

pub fn load(name: &str) -> serde_json::Value {
    let path = format!(
        "{}/../../testdata/cones/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("fixture");
    serde_json::from_str(&text).expect("json")
}

pub fn matrix_hex(v: &serde_json::Value, d: usize) -> DMatrix<f64> {
    stance_test_support::hex::matrix(v, d)
}

pub fn matrix_f64(v: &serde_json::Value, d: usize) -> DMatrix<f64> {
    let rows = v.as_array().expect("rows");
    DMatrix::from_fn(rows.len(), d, |i, j| rows[i][j].as_f64().expect("number"))
}

/// Unit rows.
pub fn normalized(m: &DMatrix<f64>) -> DMatrix<f64> {
    let mut m = m.clone();
    for i in 0..m.nrows() {
        let n = m.row(i).norm();
        if n > 0.0 {
            m.row_mut(i).scale_mut(1.0 / n);
        }
    }
    m
}

/// Angle between two vectors.
pub fn angle(a: &[f64], b: &[f64]) -> f64 {
    let na: f64 = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nb: f64 = b.iter().map(|x| x * x).sum::<f64>().sqrt();
    let c: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>() / (na * nb);
    let s = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x / na - y / nb).powi(2))
        .sum::<f64>()
        .sqrt();
    // Robust for small angles: 2 asin(|a - b| / 2).
    if c > 0.0 {
        2.0 * (s / 2.0).min(1.0).asin()
    } else {
        c.max(-1.0).acos()
    }
}

/// Do the row sets match up to positive scaling (each row of `a` has a row of `b` within
/// `max_angle`, and conversely)? Returns the worst matched angle, or None.
pub fn same_rows_up_to_scaling(a: &DMatrix<f64>, b: &DMatrix<f64>, max_angle: f64) -> Option<f64> {
    if a.nrows() != b.nrows() {
        return None;
    }
    let rows = |m: &DMatrix<f64>| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| m.row(i).iter().copied().collect())
            .collect()
    };
    let (ra, rb) = (rows(a), rows(b));
    let mut worst: f64 = 0.0;
    for (x, y) in [(&ra, &rb), (&rb, &ra)] {
        for r in x.iter() {
            let best = y.iter().map(|s| angle(r, s)).fold(f64::INFINITY, f64::min);
            if best > max_angle {
                return None;
            }
            worst = worst.max(best);
        }
    }
    Some(worst)
}

/// Do two sets of rows span the same subspace (within `eps`)?
pub fn same_span(a: &DMatrix<f64>, b: &DMatrix<f64>, eps: f64) -> bool {
    let rank = |m: &DMatrix<f64>| -> usize {
        if m.nrows() == 0 {
            return 0;
        }
        let s = m.clone().svd(false, false).singular_values;
        let smax = s.iter().copied().fold(0.0, f64::max);
        s.iter().filter(|&&x| x > eps * smax.max(1e-300)).count()
    };
    if a.nrows() == 0 || b.nrows() == 0 {
        return rank(a) == 0 && rank(b) == 0;
    }
    let mut stacked = DMatrix::zeros(a.nrows() + b.nrows(), a.ncols());
    stacked.view_mut((0, 0), a.shape()).copy_from(a);
    stacked.view_mut((a.nrows(), 0), b.shape()).copy_from(b);
    let (ra, rb, rs) = (rank(a), rank(b), rank(&stacked));
    ra == rb && rb == rs
}

/// Distance from `b` to the cone spanned by the rows of `v` (Lawson-Hanson non-negative least
/// squares): an independent membership oracle for the tests, `0` (up to rounding) iff `b` is in
/// `span(V)`.
pub fn cone_distance(v: &DMatrix<f64>, b: &[f64]) -> f64 {
    let (n, d) = v.shape();
    let a = v.transpose(); // d x n, columns are generators
    let bv = polycone::nalgebra::DVector::from_column_slice(b);
    let mut x = polycone::nalgebra::DVector::<f64>::zeros(n);
    let mut passive = vec![false; n];
    // Columns whose entry failed (degenerate: the least-squares solution gave them a
    // non-positive weight right away, Lawson and Hanson's rule); cleared when x moves.
    let mut banned = vec![false; n];
    let tol = 1e-13 * (1.0 + bv.norm()) * (1.0 + a.norm());
    for _outer in 0..(10 * n + 10) {
        let w = a.transpose() * (&bv - &a * &x);
        let j = (0..n)
            .filter(|&j| !passive[j] && !banned[j])
            .max_by(|&i, &k| w[i].total_cmp(&w[k]));
        let Some(j) = j else { break };
        if w[j] <= tol {
            break;
        }
        passive[j] = true;
        let mut first = true;
        for _inner in 0..(3 * n + 10) {
            let idx: Vec<usize> = (0..n).filter(|&i| passive[i]).collect();
            let ap = DMatrix::from_fn(d, idx.len(), |r, c| a[(r, idx[c])]);
            let s_p = ap
                .clone()
                .svd(true, true)
                .solve(&bv, 1e-14)
                .expect("svd solve");
            if first {
                first = false;
                let cj = idx.iter().position(|&i| i == j).expect("j is passive");
                if s_p[cj] <= 0.0 {
                    passive[j] = false;
                    banned[j] = true;
                    break;
                }
            }
            if s_p.iter().all(|&s| s > 0.0) {
                x.fill(0.0);
                for (c, &i) in idx.iter().enumerate() {
                    x[i] = s_p[c];
                }
                banned.fill(false);
                break;
            }
            // Step back to the boundary: the variable that hits zero first leaves the passive
            // set exactly (not by a threshold, which rounding defeats).
            let mut alpha = f64::INFINITY;
            let mut leaving = usize::MAX;
            for (c, &i) in idx.iter().enumerate() {
                if s_p[c] <= 0.0 && x[i] - s_p[c] > 0.0 {
                    let al = x[i] / (x[i] - s_p[c]);
                    if al < alpha {
                        alpha = al;
                        leaving = i;
                    }
                }
            }
            if !alpha.is_finite() {
                alpha = 0.0;
            }
            for (c, &i) in idx.iter().enumerate() {
                x[i] += alpha * (s_p[c] - x[i]);
                if i == leaving || x[i] <= 0.0 {
                    x[i] = 0.0;
                    passive[i] = false;
                }
            }
            banned.fill(false);
        }
    }
    (&bv - &a * &x).norm()
}

/// Unit cosine within which a generator lies on a facet's hyperplane, for the points that
/// [`probe_unmatched_facets`] tests.
pub const ON_FACET: f64 = 1e-7;

/// Two face forms of the cone spanned by the rows of `v` that may differ by how structure
/// degenerate at the scale of the tolerances was merged: tests the facets of `fa` that match no
/// facet of `fb` (angle above `max_angle`) with the membership oracle, where the two differ most.
/// From the centre `c` of the unit generators on such a facet `f` (cosine within `ON_FACET`),
/// the point `x = c + t f` half way to the boundary of `fb` (or at `t = 1`) is outside `fa` by
/// `t`. If `fb` contains `x` by more than `1e-6` (relative), the oracle must find `x` in the cone
/// (relative distance below `1e-7`), otherwise `fb` is wrong; if `fa` excludes it by more than
/// `1e-6`, the oracle must find it outside (beyond `1e-9`), otherwise `fa` is wrong: the band and
/// thresholds of `tests/properties.rs`. A face form missing a genuine facet (what cddlib's float
/// mode loses) contains points beyond it by the margin of its other facets; one that merged it
/// into a facet through the same generators does not. Returns how many facets were probed, or the
/// first disagreement.
pub fn probe_unmatched_facets(
    fa: &DMatrix<f64>,
    fb: &DMatrix<f64>,
    v: &DMatrix<f64>,
    max_angle: f64,
) -> Result<usize, String> {
    const BAND: f64 = 1e-6;
    const IN_CONE: f64 = 1e-7;
    let rows = |m: &DMatrix<f64>| -> Vec<Vec<f64>> {
        let m = normalized(m);
        (0..m.nrows())
            .map(|i| m.row(i).iter().copied().collect())
            .collect()
    };
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let d = v.ncols();
    let (gens, ub) = (rows(v), rows(fb));
    let mut probed = 0;
    for (i, f) in rows(fa).into_iter().enumerate() {
        if ub.iter().any(|g| angle(&f, g) <= max_angle) {
            continue;
        }
        probed += 1;
        let mut c = vec![0.0; d];
        let mut on = 0;
        for g in gens.iter().filter(|g| dot(&f, g).abs() <= ON_FACET) {
            for (ck, gk) in c.iter_mut().zip(g) {
                *ck += gk;
            }
            on += 1;
        }
        let cn = dot(&c, &c).sqrt();
        if on + 1 < d || cn == 0.0 {
            return Err(format!("facet {i}: {on} generators on it"));
        }
        c.iter_mut().for_each(|ck| *ck /= cn);
        // Half way from c to the boundary of fb along f.
        let t = ub
            .iter()
            .filter(|g| dot(g, &f) > 0.0)
            .map(|g| (-dot(g, &c)).max(0.0) / dot(g, &f))
            .fold(2.0, f64::min)
            / 2.0;
        let x: Vec<f64> = c.iter().zip(&f).map(|(ck, fk)| ck + t * fk).collect();
        let xn = dot(&x, &x).sqrt();
        let dist = cone_distance(v, &x) / xn;
        let inside_b = -ub
            .iter()
            .map(|g| dot(g, &x) / xn)
            .fold(f64::NEG_INFINITY, f64::max);
        if inside_b > BAND && dist >= IN_CONE {
            return Err(format!(
                "facet {i}: the other answer contains the point outside it by {inside_b:.1e}, \
                 {dist:.1e} from the cone"
            ));
        }
        if t / xn > BAND && dist <= 1e-9 {
            return Err(format!(
                "facet {i}: the point {:.1e} outside it is in the cone",
                t / xn
            ));
        }
    }
    Ok(probed)
}

/// Rotation about a unit axis by `angle` radians (contact frame -> world).
pub fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let [x, y, z] = axis;
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

/// A rectangular contact: position, rotation (contact -> world), half sizes, friction.
#[derive(Clone, Copy, Debug)]
pub struct Contact {
    pub pos: [f64; 3],
    pub rot: [[f64; 3]; 3],
    pub half: [f64; 2],
    pub mu: f64,
}

impl Contact {
    pub fn flat(pos: [f64; 3], half: [f64; 2], mu: f64) -> Self {
        Self {
            pos,
            rot: rotation([0.0, 0.0, 1.0], 0.0),
            half,
            mu,
        }
    }
}

fn mat_vec(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// GIWC generators `-(f, p x f)` at the world origin: the 4 pyramid edges `(+-mu, +-mu, 1)` at
/// the 4 corners of each rectangle (the paper's `A_stance V_all`, docs/math.md section 3).
pub fn giwc_generators(contacts: &[Contact]) -> DMatrix<f64> {
    let mut rows = Vec::new();
    for c in contacts {
        for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)] {
            let corner_local = [sx * c.half[0], sy * c.half[1], 0.0];
            let cl = mat_vec(&c.rot, corner_local);
            let p = [c.pos[0] + cl[0], c.pos[1] + cl[1], c.pos[2] + cl[2]];
            for (ex, ey) in [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)] {
                let f = mat_vec(&c.rot, [ex * c.mu, ey * c.mu, 1.0]);
                let t = cross(p, f);
                rows.push([-f[0], -f[1], -f[2], -t[0], -t[1], -t[2]]);
            }
        }
    }
    DMatrix::from_fn(rows.len(), 6, |i, j| rows[i][j])
}

/// The linear map of wrenches `(f, t) -> (f, t - s x f)` (moving the reference point by `s`:
/// what the generators of stances translated by `s` are, in the original's coordinates).
pub fn shift_wrenches(v: &DMatrix<f64>, s: [f64; 3]) -> DMatrix<f64> {
    let mut out = v.clone();
    for i in 0..v.nrows() {
        let f = [v[(i, 0)], v[(i, 1)], v[(i, 2)]];
        let sf = cross(s, f);
        for k in 0..3 {
            out[(i, 3 + k)] = v[(i, 3 + k)] + sf[k];
        }
    }
    out
}

/// Facets of the cone shifted by `s` (wrenches `(f, t + s x f)`, [`shift_wrenches`]), pulled
/// back to the unshifted frame: `u_local = M^T u`, normalized.
pub fn pull_back_facets(facets: &DMatrix<f64>, s: [f64; 3]) -> DMatrix<f64> {
    let mut m = DMatrix::<f64>::identity(6, 6);
    // t' = t + [s]x f
    let sx = [[0.0, -s[2], s[1]], [s[2], 0.0, -s[0]], [-s[1], s[0], 0.0]];
    for i in 0..3 {
        for j in 0..3 {
            m[(3 + i, j)] = sx[i][j];
        }
    }
    normalized(&(facets * m))
}

/// The random two-contact stance of the property tests: contact `a` at `p[0..3]` rolled by
/// `ang[0]` about x, contact `b` at `p[3..6]` turned by `ang[1]` about y then `ang[2]` about z
/// (heights scaled by 0.3), half sizes `half`, friction `mu`.
#[allow(clippy::needless_range_loop)] // a 3x3 matrix product, indexed as written
pub fn two_contacts(p: [f64; 6], ang: [f64; 3], half: [f64; 4], mu: f64) -> [Contact; 2] {
    let mut a = Contact::flat([p[0], p[1], 0.3 * p[2]], [half[0], half[1]], mu);
    a.rot = rotation([1.0, 0.0, 0.0], ang[0]);
    let mut b = Contact::flat([p[3], p[4], 0.3 * p[5]], [half[2], half[3]], mu);
    let r1 = rotation([0.0, 1.0, 0.0], ang[1]);
    let r2 = rotation([0.0, 0.0, 1.0], ang[2]);
    b.rot = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                b.rot[i][j] += r1[i][k] * r2[k][j];
            }
        }
    }
    [a, b]
}
