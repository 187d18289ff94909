//! `stance robot centroidal --urdf FILE --q q0,q1,... [--v v0,v1,...] [--lock JOINT ...]`:
//! mass, CoM, CoM Jacobian, centroidal momentum matrix `A_g` and `dA_g/dt v`, with Pinocchio's
//! conventions (see the `stance-robot` crate docs).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use stance::report::CentroidalReport;
use stance::stance_robot::{centroidal_map_dot_v, Data, Model, UrdfOptions};

use super::io::{write_output, Common};

#[derive(clap::Subcommand)]
pub enum RobotCommand {
    /// Mass, CoM, CoM Jacobian, A_g and dA_g/dt v of a free-floating URDF robot.
    Centroidal(CentroidalArgs),
}

#[derive(clap::Args)]
pub struct CentroidalArgs {
    /// The robot's URDF file (the root link gets a free-flyer joint).
    #[arg(long, value_name = "FILE")]
    pub urdf: PathBuf,
    /// Configuration, comma separated: x,y,z,qx,qy,qz,qw then the joints in Pinocchio's order
    /// (continuous joints as cos,sin). Negative values work: --q=-0.2,...
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub q: String,
    /// Velocity, comma separated: base linear and angular (base frame), then the joints.
    /// Default: zero.
    #[arg(long, value_name = "V", allow_hyphen_values = true)]
    pub v: Option<String>,
    /// Joints to lock (removed from q and v), at 0 or at NAME=VALUE (rad or m).
    #[arg(long, value_name = "JOINT", num_args = 1.., action = clap::ArgAction::Append)]
    pub lock: Vec<String>,
    /// Do not warn about URDF elements the model does not use (extensions).
    #[arg(long)]
    pub quiet_urdf: bool,
    #[command(flatten)]
    pub common: Common,
}

pub fn run(cmd: RobotCommand) -> Result<()> {
    match cmd {
        RobotCommand::Centroidal(args) => centroidal(args),
    }
}

fn parse_list(what: &str, text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .enumerate()
        .map(|(i, s)| {
            let s = s.trim();
            s.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .with_context(|| format!("--{what}: entry {i} ('{s}') is not a finite number"))
        })
        .collect()
}

fn parse_lock(spec: &str) -> Result<(String, f64)> {
    match spec.split_once('=') {
        None => Ok((spec.to_string(), 0.0)),
        Some((name, value)) => {
            let v: f64 = value
                .trim()
                .parse()
                .with_context(|| format!("--lock {spec}: '{value}' is not a number"))?;
            if name.is_empty() {
                bail!("--lock {spec}: the joint name is empty");
            }
            Ok((name.to_string(), v))
        }
    }
}

fn centroidal(args: CentroidalArgs) -> Result<()> {
    let locked = args
        .lock
        .iter()
        .map(|s| parse_lock(s))
        .collect::<Result<Vec<_>>>()?;
    let options = UrdfOptions {
        locked,
        ..Default::default()
    };
    let model = Model::from_urdf_file(&args.urdf, &options)?;
    if !args.quiet_urdf {
        super::io::warn_unknown_urdf_elements(&args.urdf, &model.unknown_elements);
    }
    let q = parse_list("q", &args.q)?;
    let v = match &args.v {
        Some(text) => parse_list("v", text)?,
        None => vec![0.0; model.nv],
    };
    // dA_g/dt v is quadratic in v: beyond this it overflows (and wrote `null`s, exit 0).
    const MAX_SPEED: f64 = 1e150;
    if let Some(x) = v.iter().find(|x| x.abs() > MAX_SPEED) {
        bail!(
            "--v: {x:e} is beyond the supported range of joint velocities, |v| <= {MAX_SPEED:e} \
             (dA_g/dt v, quadratic in v, would overflow); give velocities in that range"
        );
    }
    let mut data = Data::new(&model);
    let dh = args
        .common
        .repeated(|| centroidal_map_dot_v(&model, &mut data, &q, &v))?;
    let out = CentroidalReport::new(&model, &data, dh.as_slice());
    let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
    if !(finite(&out.com)
        && finite(&out.centroidal_map_dot_v)
        && out.com_jacobian.iter().all(|r| finite(r))
        && out.centroidal_map.iter().all(|r| finite(r)))
    {
        bail!(
            "--q, --v: the centroidal quantities overflow at this configuration and velocity \
             (largest |q| {:e}, |v| {:e}); give positions and velocities of physical size",
            q.iter().fold(0.0f64, |m, x| m.max(x.abs())),
            v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
        );
    }
    write_output(&args.common, &out)
}
