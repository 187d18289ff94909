//! Benchmark runner for `bench/peers/joints.py`: a fixed-base joint path retimed under its
//! limits (the rows by the inverse dynamics along the path, then reachability analysis), on the
//! file's grid without refinement, repeated.
//!
//! Usage: `bench_joints FILE.toml REPEAT OUTPUT.json`. Writes the status, the duration, `s'` at
//! the grid points, and the time of one retiming (rows + TOPP; median and minimum over `REPEAT`
//! runs, us), then the same for the rows alone.

use std::path::Path;
use std::time::Instant;

use serde_json::json;
use stance_motion::joints::{JointPathSpec, JointProblem};
use stance_topp::{SolveOptions, Workspace};

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
    if args.len() != 4 {
        return Err("usage: bench_joints FILE.toml REPEAT OUTPUT.json".into());
    }
    let path = Path::new(&args[1]);
    let spec: JointPathSpec = stance_motion::input::read_file(path)?;
    let repeat: usize = args[2].parse()?;
    let problem = JointProblem::new(&spec, path.parent())?;
    let grid = problem.uniform_grid(spec.grid_points);
    let opts = SolveOptions::new(spec.discretization)
        .with_start(spec.sd_start)
        .with_end(spec.sd_end);
    let mut ws = Workspace::new();
    let sol = problem.solve_on_grid(&grid, &opts, &mut ws)?;
    let mut times = Vec::with_capacity(repeat);
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let s = problem.solve_on_grid(&grid, &opts, &mut ws)?;
        times.push(t.elapsed().as_secs_f64() * 1e6);
        std::hint::black_box(s);
    }
    let out = json!({
        "status": sol.status.name(),
        "duration": sol.duration(),
        "sd": sol.profile.as_ref().map(|p| p.sd()),
        "grid_points": grid.len(),
        "retime_us_median": median(times.clone()),
        "retime_us_min": times.iter().copied().fold(f64::INFINITY, f64::min),
        "repeat": times.len(),
    });
    std::fs::write(&args[3], serde_json::to_string_pretty(&out)? + "\n")?;
    Ok(())
}
