//! `stance retime MOTION`: retime a CoM motion under contact stability (paper Section V).
//!
//! `MOTION` (JSON, or TOML for `.toml`): `{"scene": <scene object or example name>, "path":
//! {"waypoints": [[x, y, z], ...], "knots"?: [...], "interpolation"?: "spline" | "polyline"},
//! "grid_points"?: 101, "sd_start"?: 0, "sd_end"?: 0, "discretization"?: "interpolation" |
//! "collocation", "max_violation_fraction"?: 0.01, "samples_per_interval"?: 10, "dt"?: 0.01,
//! "angular_momentum"?: {"s"?: [...], "l1": [[x, y, z], ...], "l2": [...]}}` (the optional
//! angular-momentum terms `L' = l1 s'' + l2 s'^2` of a whole-body motion, linear between samples taken
//! at `s`, by default at the path knots).
//! Output: the retimed trajectory as JSON (status, duration, grid, `sd`, `sdd`, `t`, CoM,
//! controllable and feasible sets of `x = s'^2`, violation between grid points in newtons and as
//! a fraction of the weight, timings `t_u`, `t_abc`, `t_topp`). `--plot FILE.svg|FILE.png` draws
//! the phase plane: `x = s'^2` (vertical) against `s` (horizontal), feasible sets in light grey,
//! controllable sets in blue, the profile in red.

use std::path::{Path, PathBuf};

use anyhow::Result;
use stance::retime::{retime, ComMotionSpec, Retiming};

use super::io::{read_input, write_output, Common};

#[derive(clap::Args)]
pub struct RetimeArgs {
    /// Motion file: scene (or built-in example name) and CoM path.
    pub motion: PathBuf,
    /// Also draw the phase plane (x = s'^2 against s) to this SVG or PNG file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
}

pub fn run(args: RetimeArgs) -> Result<()> {
    let spec: ComMotionSpec = read_input(&args.motion)?;
    let out = args.common.repeated(|| retime(&spec))?;
    if let Some(path) = &args.plot {
        phase_plane(path, &out)?;
    }
    write_output(&args.common, &out)
}

/// Draws the phase plane of a retiming (see [`super::plot::phase_plane`]).
pub fn phase_plane(path: &Path, r: &Retiming) -> Result<()> {
    super::plot::phase_plane(
        path,
        &super::plot::PhasePlane {
            s: &r.s,
            sd: &r.sd,
            controllable: &r.controllable_sets,
            feasible: &r.feasible_sets,
            boundaries: &[],
        },
    )
}
