//! `stance simulate FILE|NAME`: the motion retimed, then executed in MuJoCo by a simulated robot
//! under joint-space PD control with inverse-dynamics feedforward (the paper's check "in a
//! physics simulator with simulated PID torque control"); prints the report JSON (`held`,
//! `reason`, `max_slip_m`, `contact_losses`, `fell`, `max_base_error_m`, `max_friction_usage`,
//! per-contact measurements with the simulated and planned friction, wall time); each surface
//! is simulated at its own `friction` (`--friction MU` for all). MuJoCo comes from PyPI into the project virtualenv
//! (`stance setup`); see `stance_sim` for the model, the control and the measurements.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use stance_sim::{simulate, SimOptions};

use super::io::{write_output, Common};

#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Motion file (JSON or TOML), or a built-in motion: stair-climbing, box-climbing, small-sway,
    /// stair-climbing-footholds, box-climbing-footholds, staircase-walk.
    pub motion: String,
    /// Play the retimed motion K times faster (K < 1: slower).
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub time_scale: Option<f64>,
    /// Simulate only segments FIRST..LAST (1-based, inclusive), e.g. 1..1.
    #[arg(long, value_name = "FIRST..LAST", allow_hyphen_values = true)]
    pub segments: Option<String>,
    /// Keep the MuJoCo model and the harness's input in this folder.
    #[arg(long, value_name = "DIR")]
    pub keep: Option<PathBuf>,
    /// Retime under contact stability alone (no joint velocity, acceleration or torque limits).
    #[arg(long)]
    pub no_limits: bool,
    /// Simulate every environment surface at this friction coefficient (default: each
    /// surface's own `friction` from the motion file).
    #[arg(long, value_name = "MU", allow_hyphen_values = true)]
    pub friction: Option<f64>,
    /// Also write the page of `stance view` with the simulation beside the plan (the executed
    /// robot solid, the plan a ghost, the events marked; `stance view REPORT.json` writes the same
    /// page from the report later).
    #[arg(long, value_name = "PAGE")]
    pub view: Option<PathBuf>,
    /// With --view: draw the robot without its mesh files.
    #[arg(long, requires = "view")]
    pub no_meshes: bool,
    #[command(flatten)]
    pub common: Common,
}

pub fn run(args: SimulateArgs) -> Result<()> {
    let (spec, base_dir) = super::motion::load(&args.motion)?;
    let segments = match &args.segments {
        None => None,
        Some(text) => {
            let parse = |x: &str| x.trim().parse::<usize>().ok().filter(|&v| v >= 1);
            match text.split_once("..").map(|(a, b)| (parse(a), parse(b))) {
                Some((Some(a), Some(b))) if a <= b => Some([a - 1, b - 1]),
                _ => bail!("--segments {text}: give FIRST..LAST, 1-based, e.g. 1..2"),
            }
        }
    };
    if let Some(mu) = args.friction {
        if !(mu.is_finite() && mu > 0.0 && mu <= 10.0) {
            bail!("--friction {mu}: give a friction coefficient in (0, 10], e.g. 0.9");
        }
    }
    let options = SimOptions {
        mjcf: stance_sim::mjcf::MjcfOptions {
            friction: args.friction,
            ..Default::default()
        },
        time_scale: args.time_scale,
        segments,
        base_dir,
        keep: args.keep.clone(),
        no_limits: args.no_limits,
        progress: Some(|line| eprintln!("{line}")),
        ..Default::default()
    };
    let (run, mut report) = simulate(spec, &options)?;
    // what was simulated, so that `stance view REPORT.json` can draw the plan again
    let path = std::path::Path::new(&args.motion);
    report.motion = Some(stance_sim::SimSource {
        motion: if path.is_file() {
            path.canonicalize()
                .map_or(args.motion.clone(), |p| p.display().to_string())
        } else {
            args.motion.clone()
        },
        time_scale: args.time_scale.unwrap_or(1.0),
        segments: segments.map(|[a, b]| [a + 1, b + 1]),
        no_limits: args.no_limits,
        duration: run.result.duration.unwrap_or(0.0),
    });
    write_output(&args.common, &report)?;
    if let Some(page) = &args.view {
        let record: stance_view::SimRecord = serde_json::to_value(&report)
            .and_then(serde_json::from_value)
            .context("cannot pass the report to the page")?;
        let motion_options = stance_view::MotionViewOptions {
            meshes: !args.no_meshes,
            progress: None,
        };
        let view = stance_view::simulation_page(&run, &record, &motion_options)?;
        super::view::write_page(page, &view)?;
    }
    Ok(())
}
