//! Benchmark runner for `bench/peers/motion.py`: a whole-body motion through the pipeline,
//! repeated, with what the peers need to redo its parts on the same inputs.
//!
//! Usage: `bench_motion NAME|FILE REPEAT OUTPUT.json [--no-limits]`. Runs the motion (chained,
//! checks once; with `--no-limits` under contact stability alone) `REPEAT` times and writes:
//!
//! - `timings`: medians over the repeats of every stage (ms), per segment and in all, the IK
//!   time per step (us), the checks (ms in all, us per sample), and the first run's
//!   `t_u_abc_topp_ms` (a fresh process);
//! - per segment: the GIWC's generators (rows, wrench at the world origin, the span form given
//!   to the double description) and the rows of `U_stance` (unit, `u . w <= 0`);
//! - the whole motion's retiming constraints as solved (grid, rows `a, b, c` per grid point, the
//!   bounds on `x`; an upper bound of -1 means none), the discretization, our profile (`sd`,
//!   duration) and the time of solving them alone (200 solves: median and minimum, us), for the
//!   TOPP peer.

use std::time::Instant;

use serde_json::{json, Value};
use stance_motion::{experiments, run_full, spec::MotionSpec, RunOptions};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let no_limits = args.len() == 5 && args[4] == "--no-limits";
    if args.len() != 4 && !no_limits {
        return Err("usage: bench_motion NAME|FILE REPEAT OUTPUT.json [--no-limits]".into());
    }
    let spec: MotionSpec = match experiments::by_name(&args[1]) {
        Ok(s) => s,
        Err(_) => toml::from_str(&std::fs::read_to_string(&args[1])?)?,
    };
    let repeat: usize = args[2].parse()?;
    // The first run is kept whole; of the others only the results (a run's rows and paths are
    // tens of megabytes: keeping them all would make every run allocate fresh memory, which a
    // user's single run in a process does not pay more than once either).
    let mut first = None;
    let mut results = Vec::new();
    let mut wall = Vec::new();
    for i in 0..repeat.max(1) {
        let options = RunOptions {
            skip_checks: i > 0,
            no_limits,
            ..Default::default()
        };
        let t = Instant::now();
        let run = run_full(spec.clone(), &options)?;
        wall.push(t.elapsed().as_secs_f64() * 1e3);
        results.push(run.result.clone());
        if i == 0 {
            first = Some(run);
        }
    }
    let first = first.expect("one run at least");
    let res = &first.result;
    let nseg = first.paths.len();
    let seg_median = |f: &dyn Fn(&stance_motion::result::SegmentInfo) -> f64, k: usize| {
        median(results.iter().map(|r| f(&r.segments[k])).collect())
    };
    let total_median = |f: &dyn Fn(&stance_motion::result::Timings) -> f64| {
        median(results.iter().map(|r| f(&r.timings)).collect())
    };
    let ik_steps: usize = res.segments.iter().map(|s| s.ik_steps).sum();
    let mut segments = Vec::new();
    for k in 0..nseg {
        let rows = &first.rows[k];
        let span = rows.stance.giwc_span();
        let generators: Vec<Vec<f64>> = span
            .row_iter()
            .map(|r| r.iter().copied().collect())
            .collect();
        let s = &res.segments[k];
        segments.push(json!({
            "name": s.name,
            "u_stance_rows": s.u_stance_rows,
            "generators": generators,
            "u": rows.u,
            "grid_points": s.grid_points,
            "ik_steps": s.ik_steps,
            "duration": s.duration,
            "t_ik_ms": seg_median(&|x| x.t_ik_ms, k),
            "t_u_ms": seg_median(&|x| x.t_u_ms, k),
            "t_abc_ms": seg_median(&|x| x.t_abc_ms, k),
            "t_topp_ms": seg_median(&|x| x.t_topp_ms.unwrap_or(f64::NAN), k),
        }));
    }
    let mut constraints = Value::Null;
    if let Some(rt) = &first.retimed {
        let k = &rt.constraints;
        // the whole motion's solve alone, repeated (the side-by-side TOPP comparison)
        let opts = stance_topp::SolveOptions::new(stance_topp::Discretization::Interpolation);
        let mut ws = stance_topp::Workspace::new();
        let solve_us: Vec<f64> = (0..200)
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(ws.solve(k, &opts).ok());
                t.elapsed().as_secs_f64() * 1e6
            })
            .collect();
        let n = k.num_points();
        let rows_at = |f: &dyn Fn(&stance_topp::Row) -> f64| -> Vec<Vec<f64>> {
            (0..n)
                .map(|i| k.rows_at(i).iter().map(f).collect())
                .collect()
        };
        constraints = json!({
            "s": k.grid(),
            "a": rows_at(&|r| r.a),
            "b": rows_at(&|r| r.b),
            "c": rows_at(&|r| r.c),
            "x_bounds": (0..n).map(|i| {
                let [lo, hi] = k.x_bounds_at(i);
                vec![lo, if hi.is_finite() { hi } else { -1.0 }]
            }).collect::<Vec<_>>(),
            "discretization": "interpolation",
            "sd": rt.profile.as_ref().map(|p| p.sd()),
            "duration": res.duration,
            "solve_us_median": median(solve_us.clone()),
            "solve_us_min": solve_us.iter().copied().fold(f64::INFINITY, f64::min),
        });
    }
    let checks = res.checks.as_ref();
    let out = json!({
        "name": res.name,
        "status": res.status,
        "duration": res.duration,
        "repeat": results.len(),
        "segments": segments,
        "constraints": constraints,
        "timings": {
            "t_plan_ms": total_median(&|t| t.t_plan_ms),
            "t_ik_ms": total_median(&|t| t.t_ik_ms),
            "t_ik_step_us": total_median(&|t| t.t_ik_ms) * 1e3 / ik_steps as f64,
            "ik_steps": ik_steps,
            "t_u_ms": total_median(&|t| t.t_u_ms),
            "t_abc_ms": total_median(&|t| t.t_abc_ms),
            "t_topp_ms": total_median(&|t| t.t_topp_ms),
            "t_refine_ms": total_median(&|t| t.t_refine_ms),
            "t_u_abc_topp_ms": total_median(&|t| t.t_u_abc_topp_ms),
            "t_lifted_ms": total_median(&|t| t.t_lifted_ms),
            // the first run's (a fresh process: cold caches and memory)
            "t_u_abc_topp_first_ms": res.timings.t_u_abc_topp_ms,
            "t_pipeline_ms": total_median(&|t| t.t_pipeline_ms),
            "t_wall_ms": median(wall[1.min(wall.len() - 1)..].to_vec()),
            "t_checks_ms": checks.map(|c| c.t_checks_ms),
            "t_check_per_sample_us": checks.map(|c| c.t_per_sample_us),
            "check_samples": checks.map(|c| c.samples),
            "samples_without_forces": checks.map(|c| c.samples_without_forces),
        },
    });
    std::fs::write(&args[3], serde_json::to_string(&out)?)?;
    Ok(())
}
