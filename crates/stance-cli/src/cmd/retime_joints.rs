//! `stance retime-joints FILE`: the time-optimal retiming of a fixed-base robot's joint path
//! under its joint velocity, acceleration and torque limits (the file format:
//! [`stance::joints::spec`]).
//!
//! Output: `status`, `duration`, `failure` (grid point, constraints, what to relax), `limits`
//! (per joint, as used), `binding` (grid points bound by each kind of limit), `between`,
//! `checks` (the largest velocity, acceleration and torque ratios over the output samples, from
//! the path and the inverse dynamics), `phase`, `trajectory` (`t`, `q`, `v`, `a`,
//! `joint_names`) and `timings`. `--plot FILE` draws the phase plane.

use std::path::PathBuf;

use anyhow::Result;
use stance::joints::{retime_joints, JointPathSpec};

use super::io::{read_input, write_output, Common};

#[derive(clap::Args)]
pub struct RetimeJointsArgs {
    /// Joint-path file (JSON, or TOML for .toml): URDF, joints, waypoints, limits.
    pub path: PathBuf,
    /// Output time step of the trajectory and the checks (s), instead of the file's.
    #[arg(long, value_name = "DT", allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Also draw the phase plane (x = s'^2 against s) to this SVG or PNG file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
}

pub fn run(args: RetimeJointsArgs) -> Result<()> {
    let mut spec: JointPathSpec = read_input(&args.path)?;
    if let Some(dt) = args.dt {
        spec.dt = dt;
    }
    let base = args.path.parent().map(std::path::Path::to_path_buf);
    let out = args
        .common
        .repeated(|| retime_joints(&spec, base.as_deref()))?;
    if let Some(path) = &args.plot {
        super::plot::phase_plane(
            path,
            &super::plot::PhasePlane {
                s: &out.phase.s,
                sd: &out.phase.sd,
                controllable: &out.phase.controllable_sets,
                feasible: &out.phase.feasible_sets,
                boundaries: &[],
            },
        )?;
    }
    write_output(&args.common, &out)
}
