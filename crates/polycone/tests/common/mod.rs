//! Helpers shared by the integration tests.
#![allow(dead_code)]

use polycone::nalgebra::DMatrix;

/// Parses a Python `float.hex()` string (`-0x1.8p+3`, `0x0.0p+0`, `inf`...).
pub fn parse_hex(s: &str) -> f64 {
    let (neg, rest) = match s.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, s),
    };
    let rest = rest.strip_prefix("0x").expect("hex float");
    let (mant, exp) = rest.split_once('p').expect("exponent");
    let exp: i32 = exp.parse().expect("exponent value");
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let mut m: u64 = u64::from_str_radix(int, 16).expect("int part");
    for c in frac.chars() {
        m = m * 16 + c.to_digit(16).expect("hex digit") as u64;
    }
    let e = exp - 4 * frac.len() as i32;
    let v = (m as f64) * 2f64.powi(e);
    if neg {
        -v
    } else {
        v
    }
}

pub fn load(name: &str) -> serde_json::Value {
    let path = format!(
        "{}/../../testdata/cones/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("fixture");
    serde_json::from_str(&text).expect("json")
}

pub fn matrix_hex(v: &serde_json::Value, d: usize) -> DMatrix<f64> {
    let rows = v.as_array().expect("rows");
    DMatrix::from_fn(rows.len(), d, |i, j| {
        parse_hex(rows[i][j].as_str().expect("hex"))
    })
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
