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

use anyhow::{anyhow, Result};
use stance::retime::{retime, MotionSpec, Retiming};

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
    let spec: MotionSpec = read_input(&args.motion)?;
    let mut out = retime(&spec)?;
    for _ in 1..args.common.repeat {
        out = retime(&spec)?;
    }
    if let Some(path) = &args.plot {
        phase_plane(path, &out)?;
    }
    write_output(&args.common, &out)
}

/// Draws the phase plane of a retiming: `x = s'^2` against `s`; feasible sets light grey,
/// controllable sets blue, the profile red (axis labels when a font is available).
pub fn phase_plane(path: &Path, r: &Retiming) -> Result<()> {
    use plotters::prelude::*;
    let svg = super::plot::is_svg(path)?;
    fn draw<DB: DrawingBackend>(
        root: DrawingArea<DB, plotters::coord::Shift>,
        r: &Retiming,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
        root.fill(&WHITE).map_err(e)?;
        let s0 = r.s.first().copied().unwrap_or(0.0);
        let s1 = r.s.last().copied().unwrap_or(1.0);
        // Vertical range: the profile and controllable sets, capped at 3 times the profile's
        // top so that unbounded sets (capped by the solver's box) do not flatten the plot.
        let top_profile = r.sd.iter().map(|v| v * v).fold(0.0, f64::max);
        let top_sets = r
            .controllable_sets
            .iter()
            .flatten()
            .map(|k| k[1])
            .fold(0.0, f64::max);
        let mut top = if top_profile > 0.0 {
            (3.0 * top_profile).min(top_sets.max(top_profile))
        } else {
            top_sets
        };
        if !(top.is_finite() && top > 0.0) {
            top = 1.0;
        }
        let top = top * 1.05;
        let text = super::plot::has_text();
        let label_area = if text { 50 } else { 0 };
        let mut chart = ChartBuilder::on(&root)
            .margin(10)
            .x_label_area_size(label_area)
            .y_label_area_size(label_area)
            .build_cartesian_2d(s0..s1, 0.0..top)
            .map_err(e)?;
        if text {
            chart
                .configure_mesh()
                .x_label_formatter(&crate::cmd::plot::tick_label)
                .y_label_formatter(&crate::cmd::plot::tick_label)
                .x_desc("path parameter s")
                .y_desc("x = (ds/dt)^2")
                .label_style((super::plot::FONT, 13))
                .axis_desc_style((super::plot::FONT, 15))
                .bold_line_style(RGBColor(225, 225, 225))
                .light_line_style(WHITE)
                .draw()
                .map_err(e)?;
        }
        let band = |sets: &[Option<[f64; 2]>]| -> Vec<Vec<(f64, f64)>> {
            // One polygon per run of non-empty sets.
            let mut out = Vec::new();
            let mut run: Vec<(f64, [f64; 2])> = Vec::new();
            for (s, k) in r.s.iter().zip(sets) {
                match k {
                    Some(k) => run.push((*s, [k[0].min(top), k[1].min(top)])),
                    None if !run.is_empty() => out.push(std::mem::take(&mut run)),
                    None => {}
                }
            }
            if !run.is_empty() {
                out.push(run);
            }
            out.into_iter()
                .map(|run| {
                    let mut poly: Vec<(f64, f64)> = run.iter().map(|(s, k)| (*s, k[1])).collect();
                    poly.extend(run.iter().rev().map(|(s, k)| (*s, k[0])));
                    poly
                })
                .collect()
        };
        chart
            .draw_series(
                band(&r.feasible_sets)
                    .into_iter()
                    .map(|p| Polygon::new(p, RGBColor(210, 210, 210))),
            )
            .map_err(e)?;
        chart
            .draw_series(
                band(&r.controllable_sets)
                    .into_iter()
                    .map(|p| Polygon::new(p, BLUE.mix(0.35))),
            )
            .map_err(e)?;
        if !r.sd.is_empty() {
            let profile: Vec<(f64, f64)> =
                r.s.iter().zip(&r.sd).map(|(s, v)| (*s, v * v)).collect();
            chart
                .draw_series(std::iter::once(PathElement::new(
                    profile,
                    RED.stroke_width(2),
                )))
                .map_err(e)?;
        }
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(s0, 0.0), (s1, 0.0), (s1, top), (s0, top), (s0, 0.0)],
                BLACK,
            )))
            .map_err(e)?;
        root.present().map_err(e)?;
        Ok(())
    }
    if svg {
        draw(SVGBackend::new(path, (900, 500)).into_drawing_area(), r)
    } else {
        draw(BitMapBackend::new(path, (900, 500)).into_drawing_area(), r)
    }
}
