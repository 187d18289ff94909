//! Moving the origin to the region before clipping: the routines start from the box
//! `[-far, far]^d` about the origin and round at the scale of the coordinates, so a region far
//! from the origin would be cut by the box (called empty) or lose digits. Translating the
//! region does not change it, so the rows are shifted to a point of it and the answer moved
//! back.
//!
//! # Method
//!
//! A first pass about the origin. If it finds the region and the centroid `c` of the region's
//! own vertices (those within `far / 2` of the origin: not the box's) is within
//! `tol::NEAR_ORIGIN` of the origin, it is the answer (bit for bit what it always was).
//! Otherwise the rows are moved to `c` (`a_i . p' <= b_i - a_i . c`, `p = p' + c`) and the
//! region computed again. If the first pass finds nothing, coarse passes from boxes reaching
//! past every plane, 1e4 times larger each time (the corners of a thin wedge lie farther than
//! its planes), locate the region at their rounding, enough to find a point of it, and the
//! precise pass runs about that point; the precise pass alone decides the answer (a region
//! a coarse pass finds only by rounding comes back empty). The centroid is a point of the region (or of its part inside the box), so
//! the rows that matter are at the region's scale about it, and redundant rows far away (a
//! stance's GIWC gives rows 1e10 m from the polygon) neither move it nor cut the box.

use super::tol::NEAR_ORIGIN;
use super::{PolytopeOptions, RegionStatus};

/// A region a routine returns: where it is, and how to move it.
pub trait Region<const D: usize> {
    /// Its status.
    fn status(&self) -> RegionStatus;
    /// Its vertices.
    fn vertices(&self) -> &[[f64; D]];
    /// Moves it by `c` (vertices, and planes where it has them).
    fn translate(&mut self, c: &[f64; D]);
}

/// The region of the rows computed by `about_origin` (a routine for rows near the origin),
/// about a point of the region when it is far from the origin (module doc).
pub fn recentred<const D: usize, R: Region<D>>(
    normals: &[[f64; D]],
    offsets: &[f64],
    opts: &PolytopeOptions,
    about_origin: impl Fn(&[f64], &PolytopeOptions) -> R,
) -> R {
    let first = about_origin(offsets, opts);
    let c = if first.status() == RegionStatus::Empty {
        // Boxes reaching past every plane, growing: the corners of a thin wedge lie farther
        // than its planes (by one over the sine of their angle).
        let reach = reach(normals, offsets, opts.zero_normal);
        let mut found = None;
        let mut far = (2.0 * reach).max(4.0 * opts.far);
        while found.is_none() && far < 1e300 {
            let coarse = PolytopeOptions { far, ..*opts };
            found = from_vertices(about_origin(offsets, &coarse).vertices(), far);
            far *= 1e4;
        }
        found
    } else {
        from_vertices(first.vertices(), opts.far)
    };
    let Some(c) = c else {
        return first;
    };
    let mut region = about_origin(&shifted(normals, offsets, &c, opts.zero_normal), opts);
    region.translate(&c);
    region
}

/// Where to move the rows, from the first pass's `vertices` (`None`: keep the first pass).
fn from_vertices<const D: usize>(vertices: &[[f64; D]], far: f64) -> Option<[f64; D]> {
    let own: Vec<&[f64; D]> = vertices
        .iter()
        .filter(|v| v.iter().all(|x| x.abs() < 0.5 * far))
        .collect();
    let pts: Vec<&[f64; D]> = if own.is_empty() {
        vertices.iter().collect()
    } else {
        own
    };
    if pts.is_empty() {
        return None;
    }
    let mut c = [0.0; D];
    for p in &pts {
        for k in 0..D {
            c[k] += p[k];
        }
    }
    for x in &mut c {
        *x /= pts.len() as f64;
    }
    let far_off = c.iter().any(|x| x.abs() > NEAR_ORIGIN);
    (far_off && c.iter().all(|x| x.is_finite())).then_some(c)
}

/// The largest distance from the origin of a row's plane (rows with a normal above
/// `zero_normal`; 0 when there is none).
fn reach<const D: usize>(normals: &[[f64; D]], offsets: &[f64], zero_normal: f64) -> f64 {
    normals
        .iter()
        .zip(offsets)
        .filter_map(|(a, &b)| {
            let na = a.iter().map(|x| x * x).sum::<f64>().sqrt();
            (na >= zero_normal && na.is_finite()).then(|| (b / na).abs())
        })
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max)
}

/// The offsets of the rows about `c`: `b_i - a_i . c`; a row whose normal is below
/// `zero_normal` is the constant constraint `0 <= b_i` and keeps its offset (its normal is
/// noise: moved by `c` it could change the constant's sign).
fn shifted<const D: usize>(
    normals: &[[f64; D]],
    offsets: &[f64],
    c: &[f64; D],
    zero_normal: f64,
) -> Vec<f64> {
    normals
        .iter()
        .zip(offsets)
        .map(|(a, &b)| {
            let na = a.iter().map(|x| x * x).sum::<f64>().sqrt();
            if na < zero_normal {
                b
            } else {
                b - (0..D).map(|k| a[k] * c[k]).sum::<f64>()
            }
        })
        .collect()
}
