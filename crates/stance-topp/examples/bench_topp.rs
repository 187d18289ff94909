//! Rust side of `bench/peers/topp.py`: times the solver, the factored eq. 14 rows and the
//! between-grid check on the instances the script writes, and prints JSON.
//!
//! `cargo run --release -p stance-topp --example bench_topp -- INPUT.json`
//!
//! Input: see `common/mod.rs`.

use stance_topp::between::{check_between, refine_until, PathRows};
use stance_topp::factored::{FactoredRows, FillKernel};
use stance_topp::path::{PathCurve, PathPoint};
use stance_topp::tol::DEFAULT_BETWEEN_GRID_FRACTION;
use stance_topp::{CanonicalConstraints, Discretization, SolveOptions, Workspace};

mod common;
use common::{timed_us, Input};

fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: bench_topp INPUT.json");
    let input: Input =
        serde_json::from_str(&std::fs::read_to_string(path).expect("read input")).expect("JSON");
    let mut out = Vec::new();
    for inst in &input.instances {
        let k = CanonicalConstraints::from_dense(&inst.s, &inst.a, &inst.b, &inst.c).unwrap();
        let n = inst.s.len() - 1;
        let reps = if n <= 200 { 400 } else { 60 };
        let mg = inst.mass * inst.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
        let rows = PathRows::new(inst.u.clone(), inst.bow, inst.mass, inst.gravity).unwrap();
        for disc in [Discretization::Collocation, Discretization::Interpolation] {
            let mut ws = Workspace::new();
            let opts = SolveOptions::new(disc);
            let sol = ws.solve(&k, &opts).unwrap();
            let warm_us = timed_us(reps, || {
                std::hint::black_box(ws.solve(&k, &opts).unwrap());
            });
            let cold_opts = SolveOptions {
                warm_start: false,
                ..opts
            };
            let cold = ws.solve(&k, &cold_opts).unwrap();
            let cold_us = timed_us(reps, || {
                std::hint::black_box(ws.solve(&k, &cold_opts).unwrap());
            });
            let profile = sol.profile.as_ref().unwrap();
            let res = profile.residuals(&k, disc);
            let (between, _) = check_between(profile, &rows, 20, mg);
            let refine = if n <= 200 {
                let r = refine_until(
                    &rows,
                    inst.s.clone(),
                    &opts,
                    DEFAULT_BETWEEN_GRID_FRACTION * mg,
                    mg,
                    100_000,
                    20,
                )
                .unwrap();
                serde_json::json!({
                    "converged": r.converged, "rounds": r.rounds, "points_added": r.points_added,
                    "ms": r.elapsed.as_secs_f64() * 1e3, "fraction": r.between.fraction,
                    "duration": r.solution.duration(),
                })
            } else {
                serde_json::Value::Null
            };
            out.push(serde_json::json!({
                "name": inst.name, "N": n, "rows": k.rows_at(0).len(), "discretization": disc.name(),
                "status": sol.status.name(), "duration": sol.duration(),
                "duration_cold": cold.duration(),
                "solve_us": warm_us[0], "solve_cold_us": cold_us[0],
                "solve_min_us": warm_us[1], "solve_cold_min_us": cold_us[1],
                "moves": sol.stats.moves, "inner_steps": sol.stats.inner_steps,
                "moves_cold": cold.stats.moves, "inner_steps_cold": cold.stats.inner_steps,
                "max_residual": res.enforced_max,
                "x": profile.x(),
                "between_newton": between.max_violation, "between_fraction": between.fraction,
                "between_at_s": between.at_s,
                "refine": refine,
            }));
        }
        // The rows from U: eq. 14 vectors per grid point, then the product with U.
        let samples: Vec<PathPoint> = inst.s.iter().map(|&s| inst.bow.eval(s)).collect();
        let f = FactoredRows::from_samples(
            &inst.u,
            inst.s.clone(),
            &samples,
            inst.mass,
            inst.gravity,
            None,
        )
        .unwrap();
        let kf = f.to_constraints();
        let worst = kf
            .rows()
            .iter()
            .zip(k.rows())
            .map(|(x, y)| {
                ((x.a - y.a)
                    .abs()
                    .max((x.b - y.b).abs())
                    .max((x.c - y.c).abs()))
                    / y.c.abs().max(1.0)
            })
            .fold(0.0, f64::max);
        // Every fill kernel this CPU runs, on the same warm buffer: outputs compared first (the
        // fused ones must agree bit for bit), then timed in 3 interleaved rounds.
        let kernels: Vec<FillKernel> = [
            FillKernel::Portable,
            FillKernel::Avx2Fma,
            FillKernel::Avx512,
            FillKernel::Avx512Gz,
        ]
        .into_iter()
        .filter(|k| k.is_available())
        .collect();
        let mut buf = kf.rows().to_vec();
        let mut fused_identical = true;
        let mut portable_rel = 0.0f64;
        for &kernel in &kernels {
            f.fill_with(&mut buf, kernel).unwrap();
            if kernel == FillKernel::Portable {
                portable_rel = buf
                    .iter()
                    .zip(kf.rows())
                    .map(|(x, y)| {
                        let d = (x.a - y.a)
                            .abs()
                            .max((x.b - y.b).abs())
                            .max((x.c - y.c).abs());
                        d / y.a.abs().max(y.b.abs()).max(y.c.abs()).max(1.0)
                    })
                    .fold(0.0, f64::max);
            } else {
                fused_identical &= buf.as_slice() == kf.rows();
            }
        }
        let mut by_kernel = vec![(Vec::new(), f64::INFINITY); kernels.len()];
        for _round in 0..3 {
            for (t, &kernel) in by_kernel.iter_mut().zip(&kernels) {
                let [med, min] = timed_us(3000, || {
                    f.fill_with(std::hint::black_box(&mut buf), kernel).unwrap()
                });
                t.0.push(med);
                t.1 = t.1.min(min);
            }
        }
        let by_kernel: serde_json::Map<String, serde_json::Value> = kernels
            .iter()
            .zip(&by_kernel)
            .map(|(k, (meds, min))| {
                let mut meds = meds.clone();
                meds.sort_by(f64::total_cmp);
                (
                    k.name().to_string(),
                    serde_json::json!({"median_us": meds[1], "min_us": min, "round_medians_us": meds}),
                )
            })
            .collect();
        let auto = FillKernel::Auto.resolve();
        let fill_us = [
            by_kernel[auto.name()]["median_us"].as_f64().unwrap(),
            by_kernel[auto.name()]["min_us"].as_f64().unwrap(),
        ];
        let build_us = timed_us(2000, || {
            std::hint::black_box(
                FactoredRows::from_samples(
                    &inst.u,
                    inst.s.clone(),
                    &samples,
                    inst.mass,
                    inst.gravity,
                    None,
                )
                .unwrap(),
            );
        });
        out.push(serde_json::json!({
            "name": inst.name, "N": n, "rows": inst.u.len(), "abc_fill_us": fill_us[0],
            "abc_fill_min_us": fill_us[1], "abc_setup_us": build_us[0], "abc_max_rel_diff": worst,
            "abc_fill_kernel": auto.name(), "abc_fill_by_kernel": by_kernel,
            "abc_fused_kernels_identical": fused_identical,
            "abc_portable_max_rel_diff": portable_rel,
        }));
    }
    println!("{}", serde_json::to_string_pretty(&out).unwrap());
}
