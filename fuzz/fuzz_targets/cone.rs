//! Cone conversions on arbitrary matrices: the first byte picks the dimension (1 to 8) and the
//! direction, the rest are raw `f64`s (NaN, infinities, subnormals, huge and tiny values
//! included). Never a panic; a certified span -> face answer contains every generator; an
//! error has a message.
#![no_main]

use libfuzzer_sys::fuzz_target;
use polycone::nalgebra::DMatrix;
use polycone::{face_to_span, span_to_face, DdOptions, FaceForm};

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else {
        return;
    };
    let d = 1 + (head & 7) as usize;
    let xs: Vec<f64> = rest
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .take(8 * 24)
        .collect();
    let n = xs.len() / d;
    let m = DMatrix::from_row_slice(n, d, &xs[..n * d]);
    let opts = DdOptions::default();
    if head & 8 == 0 {
        match span_to_face(&m, &opts) {
            Ok(r) if r.certificate.certified => {
                // Soundness, independently of the certificate: every generator (scaled to a
                // unit row) satisfies every facet within a margin far above the tolerance.
                for i in 0..n {
                    let v = m.row(i);
                    let amax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                    if amax == 0.0 {
                        continue;
                    }
                    let v = v / amax;
                    let v = &v / v.norm();
                    for f in 0..r.face.facets.nrows() {
                        let s = (r.face.facets.row(f) * v.transpose())[0];
                        assert!(s < 1e-6, "generator {i} violates facet {f} by {s}");
                    }
                }
            }
            Ok(_) => {}
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    } else {
        let k = n / 2;
        let face = FaceForm::new(
            m.rows(0, k).into_owned(),
            m.rows(k, (n - k).min(2)).into_owned(),
        );
        if let Ok(face) = face {
            let _ = face_to_span(&face, &opts);
        }
    }
});
