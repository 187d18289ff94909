//! `stance motion FILE|NAME`: a whole-body motion across stances (the paper's Section V on a
//! humanoid): IK per segment, `U_stance` and eq. 14 rows, one chained retiming (or rest to rest
//! per segment), the trajectory `q(t), v(t), a(t)` and the independent checks.
//!
//! `FILE` is a motion file (JSON, or TOML for `.toml`; format in the `stance::motion::spec`
//! docs and the README); `NAME` a built-in motion: `stair-climbing`, `box-climbing` (JVRC-1,
//! the paper's experiments) or `small-sway` (the project's small humanoid). Output: the
//! `stance::motion::result::MotionResult` as JSON. `--plot DIR` draws the phase plane of the
//! whole motion (`motion.svg`) and of each segment (`segment-K.svg`); `--table` prints the
//! per-segment table (the paper's Tables I and II columns) to standard error.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use stance::motion::result::MotionResult;
use stance::motion::spec::MotionSpec;
use stance::motion::{plan, run, RunOptions};

use super::io::{write_output, Common};
use super::plot::{phase_plane, PhasePlane};

#[derive(clap::Args)]
pub struct MotionArgs {
    /// Motion file (JSON or TOML), or a built-in motion: stair-climbing, box-climbing, small-sway,
    /// stair-climbing-footholds, box-climbing-footholds, staircase-walk.
    pub motion: String,
    /// Retime every segment from rest to rest (the paper's way) instead of the whole motion as
    /// one problem.
    #[arg(long)]
    pub rest_to_rest: bool,
    /// Output time step of the trajectory (s; 0.01): samples every DT, with the instants where
    /// the path acceleration switches added where two samples would disagree
    #[arg(long, value_name = "DT", allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Time step of the independent checks (s; 0.001)
    #[arg(long, value_name = "DT", allow_hyphen_values = true)]
    pub check_dt: Option<f64>,
    /// Retiming grid intervals per segment (2 to 10000).
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          value_parser = clap::value_parser!(i64).range(2..=stance::tol::MAX_MOTION_GRID as i64))]
    pub grid: Option<i64>,
    /// Draw phase-plane plots (motion.svg and segment-K.svg) into this folder.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Image format of the plots: svg or png.
    #[arg(long, value_name = "FORMAT", default_value = "svg", value_parser = ["svg", "png"])]
    pub plot_format: String,
    /// Skip the independent checks.
    #[arg(long)]
    pub no_checks: bool,
    /// Retime under contact stability alone: no joint velocity, acceleration or torque limits
    /// (the file's [limits] section and the URDF's limits are ignored).
    #[arg(long)]
    pub no_limits: bool,
    /// Check the trajectory played K times faster (K > 1: the force check must then fail
    /// somewhere if the retiming was tight).
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub time_scale: Option<f64>,
    /// Run the force check with each contact's full area and a circular friction cone of radius
    /// MU (an inner 8-sided pyramid), e.g. a simulator's, instead of the planned contacts.
    #[arg(long, value_name = "MU", allow_hyphen_values = true)]
    pub check_friction: Option<f64>,
    /// Print the per-segment table to standard error.
    #[arg(long)]
    pub table: bool,
    /// Write the complete motion file that the footholds planner made of the segments it
    /// plans (CoM via-points, swing paths) to OUT (TOML; JSON for a .json name): `stance
    /// motion OUT` retimes it to the same result, and it can be edited.
    #[arg(long, value_name = "OUT")]
    pub write_plan: Option<PathBuf>,
    /// Do not warn about URDF elements the model does not use (extensions).
    #[arg(long)]
    pub quiet_urdf: bool,
    #[command(flatten)]
    pub common: Common,
}

/// A motion file's spec and folder, or a built-in motion by name.
pub fn load(motion: &str) -> Result<(MotionSpec, Option<PathBuf>)> {
    Ok(stance::input::motion(motion)?)
}

pub fn run_cmd(args: MotionArgs) -> Result<()> {
    let (mut spec, base_dir) = load(&args.motion)?;
    if args.rest_to_rest {
        spec.retiming.rest_to_rest = true;
    }
    if let Some(dt) = args.dt {
        spec.retiming.dt = dt;
    }
    if let Some(dt) = args.check_dt {
        spec.retiming.check_dt = dt;
    }
    if let Some(g) = args.grid {
        spec.retiming.grid = g as usize;
    }
    plan::check_retiming(&spec.retiming)?;
    let options = RunOptions {
        base_dir,
        skip_checks: args.no_checks,
        time_scale: args.time_scale,
        check_friction: args.check_friction,
        no_limits: args.no_limits,
        progress: Some(|line| eprintln!("{line}")),
    };
    // with --write-plan, the plan written is the plan run (planned once), with what the
    // planner did in the output
    let mut planning = None;
    if let Some(out) = &args.write_plan {
        let planned = write_plan(&spec, &options, out)?;
        spec = planned.spec;
        planning = Some(planned.info).filter(|i| !i.segments.is_empty());
    }
    let mut out = args.common.repeated(|| run(spec.clone(), &options))?;
    if planning.is_some() {
        out.planning = planning;
    }
    if let Some(dir) = &args.plot {
        plots(dir, &out, &args.plot_format)?;
    }
    if args.table {
        eprint!("{}", table(&out));
    }
    let unknown = &out.robot.unknown_urdf_elements;
    if !args.quiet_urdf && !unknown.is_empty() {
        eprintln!(
            "warning: the URDF of {} has elements the model does not use: {}; --quiet-urdf \
             silences this",
            out.robot.name,
            unknown.join(", ")
        );
    }
    write_output(&args.common, &out)
}

/// Plans `spec` and writes the complete motion file to `out` (a relative URDF path is made
/// relative to `out`'s folder, or absolute).
fn write_plan(
    spec: &MotionSpec,
    options: &RunOptions,
    out: &Path,
) -> Result<stance::motion::footholds::PlannedMotion> {
    let base_dir = options.base_dir.as_deref();
    let planned = stance::motion::footholds::plan(spec, options)?;
    let mut written = planned.spec.clone();
    if let stance::motion::spec::RobotRef::Urdf(r) = &mut written.robot {
        let urdf = Path::new(&r.urdf);
        if urdf.is_relative() {
            let from = base_dir.unwrap_or(Path::new(".")).join(urdf);
            let from = std::fs::canonicalize(&from).unwrap_or(from);
            let to_dir = out.parent().filter(|p| !p.as_os_str().is_empty());
            let to_dir = to_dir.map_or_else(|| PathBuf::from("."), Path::to_path_buf);
            let to_dir = std::fs::canonicalize(&to_dir).unwrap_or(to_dir);
            r.urdf = from
                .strip_prefix(&to_dir)
                .map_or_else(|_| from.display().to_string(), |p| p.display().to_string());
        }
    }
    let text = if out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        serde_json::to_string_pretty(&written)?
    } else {
        toml::to_string(&written).context("writing the plan as TOML")?
    };
    std::fs::write(out, text).with_context(|| format!("writing the plan to {}", out.display()))?;
    Ok(planned)
}

/// The phase planes of the whole motion and of each segment, as `ext` files (`svg`, `png`).
pub fn plots(dir: &Path, r: &MotionResult, ext: &str) -> Result<()> {
    let Some(ph) = &r.phase else {
        return Ok(());
    };
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create the plot folder {}", dir.display()))?;
    let starts = &ph.segment_starts;
    let boundaries: Vec<f64> = starts[1..starts.len() - 1]
        .iter()
        .map(|&i| ph.s[i])
        .collect();
    let whole = PhasePlane {
        s: &ph.s,
        sd: &ph.sd,
        controllable: &ph.controllable_sets,
        feasible: &ph.feasible_sets,
        boundaries: &boundaries,
    };
    phase_plane(&dir.join(format!("motion.{ext}")), &whole)?;
    for k in 0..starts.len() - 1 {
        let (a, b) = (starts[k], starts[k + 1]);
        let part = PhasePlane {
            s: &ph.s[a..=b],
            sd: if ph.sd.is_empty() { &[] } else { &ph.sd[a..=b] },
            controllable: &ph.controllable_sets[a..=b],
            feasible: &ph.feasible_sets[a..=b],
            boundaries: &[],
        };
        phase_plane(&dir.join(format!("segment-{}.{ext}", k + 1)), &part)?;
    }
    Ok(())
}

/// The per-segment table: the paper's columns (rows of `U_stance`, `T_U`, `T_abc`, `T_TOPP`)
/// with `T_IK`, the grid and the durations, and the totals.
pub fn table(r: &MotionResult) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{} ({:?}, {:?}): duration {}",
        r.name,
        r.status,
        r.mode,
        r.duration
            .map_or_else(|| "none".to_string(), |d| format!("{d:.3} s"))
    );
    let _ = writeln!(
        o,
        "  {:<34} {:>5} {:>6} {:>6} {:>7} {:>7} {:>7} {:>8} {:>8} {:>9}",
        "segment", "rows", "grid", "T_IK", "T_U", "T_abc", "T_TOPP", "start", "end", "duration"
    );
    let f = |x: Option<f64>, p: usize| x.map_or_else(|| "-".to_string(), |v| format!("{v:.p$}"));
    for s in &r.segments {
        let _ = writeln!(
            o,
            "  {:<34} {:>5} {:>6} {:>6.1} {:>7.2} {:>7.2} {:>7} {:>8} {:>8} {:>9}",
            s.name.chars().take(34).collect::<String>(),
            s.u_stance_rows,
            s.grid_points,
            s.t_ik_ms,
            s.t_u_ms,
            s.t_abc_ms,
            f(s.t_topp_ms, 2),
            f(s.t_start, 3),
            f(s.t_end, 3),
            f(s.duration, 3),
        );
    }
    let t = &r.timings;
    let _ = writeln!(
        o,
        "  times in ms; U_stance + rows + TOPP {:.2} (refinement {:.2}), IK {:.1}, pipeline {:.1}",
        t.t_u_abc_topp_ms, t.t_refine_ms, t.t_ik_ms, t.t_pipeline_ms
    );
    if let Some(c) = &r.checks {
        let _ = writeln!(
            o,
            "  checks: {} samples, {} without supporting forces, friction usage <= {:.3}, \
             contact drift <= {:.2e} m, violation between grid points {:.2e} of the weight \
             ({:.1} us per sample)",
            c.samples,
            c.samples_without_forces,
            c.max_friction_usage,
            c.max_contact_drift,
            c.max_between_violation_fraction,
            c.t_per_sample_us
        );
        match c.collisions.first() {
            None => {
                let closest = c.clearances.first().map_or_else(
                    || "every body farther than 0.2 m".to_string(),
                    |k| {
                        format!(
                            "closest {} to {} at {:.1} mm",
                            k.body,
                            k.surface,
                            k.distance * 1e3
                        )
                    },
                );
                let _ = writeln!(o, "  collisions: none ({closest})");
            }
            Some(_) => {
                for k in &c.collisions {
                    let _ = writeln!(
                        o,
                        "  collision: {} {:.1} mm inside {} at t = {:.3} s (segment {}, {}), \
                         {} samples from t = {:.3} s",
                        k.body,
                        k.depth * 1e3,
                        k.surface,
                        k.t,
                        k.segment,
                        k.segment_name,
                        k.samples,
                        k.t_first
                    );
                }
            }
        }
        for v in &c.via_points_missed {
            let _ = writeln!(
                o,
                "  via-point missed: {} {:.1} mm{} from its target at the end of move {} of \
                 {}: out of reach, held off a solid by the clearance (ik.clearance), or traded for \
                 another task (ik.w_com, ik.w_link)",
                v.target,
                v.distance * 1e3,
                if v.angle_deg > 0.0 {
                    format!(", {:.2} deg", v.angle_deg)
                } else {
                    String::new()
                },
                v.move_number,
                plan::segment_label(v.segment.saturating_sub(1), &v.segment_name)
            );
        }
        for k in &c.unplanned_touches {
            let _ = writeln!(
                o,
                "  unplanned touch: {} on {} for {:.3} s from t = {:.3} s (segment {}, {})",
                k.body, k.surface, k.duration, k.t, k.segment, k.segment_name
            );
        }
    }
    if let Some(fl) = &r.failure {
        let _ = writeln!(o, "  failure: {}: {}", fl.status, fl.reason);
    }
    o
}
