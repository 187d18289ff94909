//! The phase plane of a retiming: `x = s'^2` against the path parameter `s`.

use std::path::Path;

use anyhow::{anyhow, Result};

use super::{has_text, is_svg, tick_label, FONT};

/// What a phase-plane plot draws: `x = s'^2` against `s`; feasible sets light grey, controllable
/// sets blue, the profile red, segment boundaries as grey vertical lines.
pub struct PhasePlane<'a> {
    /// Grid.
    pub s: &'a [f64],
    /// Path speed at the grid points (empty: no profile).
    pub sd: &'a [f64],
    /// Controllable sets.
    pub controllable: &'a [Option<[f64; 2]>],
    /// Feasible sets.
    pub feasible: &'a [Option<[f64; 2]>],
    /// Values of `s` where segments meet.
    pub boundaries: &'a [f64],
}

/// Draws a phase plane (axis labels when a font is available).
pub fn phase_plane(path: &Path, r: &PhasePlane) -> Result<()> {
    use plotters::prelude::*;
    let svg = is_svg(path)?;
    fn draw<DB: DrawingBackend>(
        root: DrawingArea<DB, plotters::coord::Shift>,
        r: &PhasePlane,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("cannot draw the plot: {e}");
        root.fill(&WHITE).map_err(e)?;
        let s0 = r.s.first().copied().unwrap_or(0.0);
        let s1 = r.s.last().copied().unwrap_or(1.0);
        // Vertical range: the profile and controllable sets, capped at 3 times the profile's
        // top so that unbounded sets (capped by the solver's box) do not flatten the plot.
        let top_profile = r.sd.iter().map(|v| v * v).fold(0.0, f64::max);
        let top_sets = r
            .controllable
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
        let text = has_text();
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
                .x_label_formatter(&tick_label)
                .y_label_formatter(&tick_label)
                .x_desc("path parameter s")
                .y_desc("x = (ds/dt)^2")
                .label_style((FONT, 13))
                .axis_desc_style((FONT, 15))
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
                band(r.feasible)
                    .into_iter()
                    .map(|p| Polygon::new(p, RGBColor(210, 210, 210))),
            )
            .map_err(e)?;
        chart
            .draw_series(
                band(r.controllable)
                    .into_iter()
                    .map(|p| Polygon::new(p, BLUE.mix(0.35))),
            )
            .map_err(e)?;
        if !r.sd.is_empty() {
            let profile: Vec<(f64, f64)> = r.s.iter().zip(r.sd).map(|(s, v)| (*s, v * v)).collect();
            chart
                .draw_series(std::iter::once(PathElement::new(
                    profile,
                    RED.stroke_width(2),
                )))
                .map_err(e)?;
        }
        chart
            .draw_series(
                r.boundaries
                    .iter()
                    .map(|&b| PathElement::new(vec![(b, 0.0), (b, top)], BLACK.mix(0.5))),
            )
            .map_err(e)?;
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
