//! Probes of what bounds `FactoredRows::fill` (the rows of eq. 14 from `U`), on the instances
//! `bench/peers/topp.py --write-instances INSTANCES.json` writes (see `bench/peers/topp.md`,
//! "Rows from U"):
//!
//! `cargo run --release -p stance-topp --example fill_bounds -- INSTANCES.json`
//!
//! For each instance with at most 200 grid intervals, on one warm buffer of the fill's size:
//! the fill with each kernel; *stores only* (the same bytes written by aligned 64-byte stores,
//! nothing computed); *arithmetic only* (the AVX-512 kernel's 14 multiply-adds per row, no
//! stores; x86-64 with AVX-512F only); and the fill split between two threads by grid points
//! (two factored forms on the two halves of the grid, `rayon::join`, called from inside and from
//! outside a 2-thread pool). Prints one JSON object per instance.

use stance_topp::factored::{eq14_vectors, FactoredRows, FillKernel};
use stance_topp::path::{PathCurve, PathPoint};
use stance_topp::Row;

mod common;
use common::{timed_us, Input};

#[cfg(target_arch = "x86_64")]
mod probes {
    use std::arch::x86_64::*;

    /// Writes `bytes` bytes (a multiple of 64 is written; the rest left) from the first 64-byte
    /// boundary of `buf` with aligned 64-byte stores.
    ///
    /// # Safety
    ///
    /// AVX-512F.
    #[target_feature(enable = "avx512f")]
    pub unsafe fn stores_only(buf: &mut [f64], value: f64) {
        let skip = buf.as_ptr().align_offset(64).min(buf.len());
        let v = _mm512_set1_pd(value);
        let lines = (buf.len() - skip) / 8;
        let p = buf.as_mut_ptr().add(skip);
        for l in 0..lines {
            _mm512_store_pd(p.add(8 * l), v);
        }
    }

    /// One cache line of `f64` (64-byte aligned storage, as the kernel's columns).
    #[derive(Clone, Copy)]
    #[repr(C, align(64))]
    pub struct Line(pub [f64; 8]);

    /// The AVX-512 kernel's arithmetic (`a`, `b` full products, `c` from the constant force
    /// part and two torque terms) over all grid points, 8 rows at a time from aligned columns,
    /// reduced to maxima instead of stored.
    ///
    /// # Safety
    ///
    /// AVX-512F and FMA; every column has the same number of lines.
    #[target_feature(enable = "avx512f,fma")]
    pub unsafe fn arithmetic_only(cols: &[Vec<Line>; 7], w: &[[[f64; 6]; 3]]) -> f64 {
        let [c0, c1, c2, c3, c4, c5, c6] = cols;
        let mut acc = [_mm512_setzero_pd(); 3];
        for wi in w {
            let wa: [__m512d; 6] = std::array::from_fn(|q| _mm512_set1_pd(wi[0][q]));
            let wb: [__m512d; 6] = std::array::from_fn(|q| _mm512_set1_pd(wi[1][q]));
            let (wc3, wc4) = (_mm512_set1_pd(wi[2][3]), _mm512_set1_pd(wi[2][4]));
            let rows = c0.iter().zip(c1).zip(c2).zip(c3).zip(c4).zip(c5).zip(c6);
            for ((((((l0, l1), l2), l3), l4), l5), l6) in rows {
                let u: [__m512d; 7] =
                    [l0, l1, l2, l3, l4, l5, l6].map(|l| _mm512_load_pd(l.0.as_ptr()));
                let mut a = _mm512_mul_pd(u[0], wa[0]);
                let mut b = _mm512_mul_pd(u[0], wb[0]);
                for q in 1..6 {
                    a = _mm512_fmadd_pd(u[q], wa[q], a);
                    b = _mm512_fmadd_pd(u[q], wb[q], b);
                }
                let c = _mm512_fmadd_pd(u[4], wc4, _mm512_fmadd_pd(u[3], wc3, u[6]));
                acc = [
                    _mm512_max_pd(acc[0], a),
                    _mm512_max_pd(acc[1], b),
                    _mm512_max_pd(acc[2], c),
                ];
            }
        }
        _mm512_reduce_max_pd(_mm512_max_pd(acc[0], _mm512_max_pd(acc[1], acc[2])))
    }
}

fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: fill_bounds INSTANCES.json");
    let input: Input =
        serde_json::from_str(&std::fs::read_to_string(path).expect("read input")).expect("JSON");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool");
    let reps = 3000;
    for inst in input.instances.iter().filter(|i| i.s.len() <= 201) {
        let (m, n) = (inst.u.len(), inst.s.len());
        let samples: Vec<PathPoint> = inst.s.iter().map(|&s| inst.bow.eval(s)).collect();
        let make = |lo: usize, hi: usize| {
            FactoredRows::from_samples(
                &inst.u,
                inst.s[lo..hi].to_vec(),
                &samples[lo..hi],
                inst.mass,
                inst.gravity,
                None,
            )
            .expect("valid instance")
        };
        let f = make(0, n);
        let mut buf = vec![Row::default(); m * n];
        let mut out = serde_json::Map::new();
        out.insert("name".into(), inst.name.clone().into());
        out.insert("rows".into(), m.into());
        out.insert("grid_points".into(), n.into());
        out.insert("bytes".into(), (m * n * std::mem::size_of::<Row>()).into());
        for kernel in [
            FillKernel::Avx512Gz,
            FillKernel::Avx512,
            FillKernel::Avx2Fma,
            FillKernel::Portable,
        ] {
            if kernel.is_available() {
                let t = timed_us(reps, || {
                    f.fill_with(std::hint::black_box(&mut buf), kernel).unwrap()
                });
                out.insert(format!("fill_{}_us", kernel.name()), t.to_vec().into());
            }
        }
        // Two halves of the grid, filled on two threads.
        let half = n / 2;
        let (lo, hi) = (make(0, half), make(half, n));
        let mut split = vec![Row::default(); m * n];
        {
            let (a, b) = split.split_at_mut(half * m);
            lo.fill(a).unwrap();
            hi.fill(b).unwrap();
        }
        f.fill(&mut buf).unwrap();
        assert!(split == buf, "the halves give the same rows");
        let join = |buf: &mut [Row]| {
            let (a, b) = buf.split_at_mut(half * m);
            rayon::join(|| lo.fill(a).unwrap(), || hi.fill(b).unwrap());
        };
        let t = pool.install(|| timed_us(reps, || join(std::hint::black_box(&mut split))));
        out.insert("fill_2_threads_in_pool_us".into(), t.to_vec().into());
        let t = timed_us(reps, || join(std::hint::black_box(&mut split)));
        out.insert("fill_2_threads_from_outside_us".into(), t.to_vec().into());
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("fma") {
            let flat: &mut [f64] = unsafe {
                // SAFETY: `Row` is `#[repr(C)]` with three `f64` fields and no padding.
                std::slice::from_raw_parts_mut(buf.as_mut_ptr().cast::<f64>(), 3 * buf.len())
            };
            // SAFETY: AVX-512F checked above.
            let t = timed_us(reps, || unsafe {
                probes::stores_only(std::hint::black_box(flat), 1.0)
            });
            out.insert("stores_only_us".into(), t.to_vec().into());
            let w: Vec<[[f64; 6]; 3]> = samples
                .iter()
                .map(|q| eq14_vectors(q, inst.mass, inst.gravity, [0.0; 3], [0.0; 3]))
                .collect();
            let mr = m / 8 * 8;
            let force = w[0][2];
            let cols: [Vec<probes::Line>; 7] = std::array::from_fn(|q| {
                inst.u[..mr]
                    .chunks_exact(8)
                    .map(|rows| {
                        probes::Line(std::array::from_fn(|t| {
                            let r = rows[t];
                            if q < 6 {
                                r[q]
                            } else {
                                r[0] * force[0] + r[1] * force[1] + r[2] * force[2]
                            }
                        }))
                    })
                    .collect()
            });
            // SAFETY: AVX-512F and FMA checked above; the columns have mr entries.
            let t = timed_us(reps, || unsafe {
                std::hint::black_box(probes::arithmetic_only(&cols, std::hint::black_box(&w)));
            });
            // Scaled from the mr rows computed to all m rows.
            out.insert(
                "arithmetic_only_us".into(),
                vec![t[0] * m as f64 / mr as f64, t[1] * m as f64 / mr as f64].into(),
            );
        }
        println!("{}", serde_json::Value::Object(out));
    }
}
