//! What the plots of every command share: the backend chosen by file extension, and text.
//!
//! Text needs a font. plotters is built without system font discovery (no fontconfig or
//! freetype dependency), so the command line looks for one TrueType font, once: the file named by
//! the `STANCE_PLOT_FONT` environment variable, else DejaVu Sans or Liberation Sans where
//! Linux distributions install them. Without a font, plots are drawn without text (axes, ticks
//! and titles are then described in each command's help).

use std::path::Path;
use std::sync::OnceLock;

use anyhow::{anyhow, bail, Context, Result};

/// Tick labels of `f64` axes: plotters' default format, without the `-0.0` it prints for a
/// tick that lands a rounding error below zero (e.g. `-2.8e-17`).
pub(crate) fn tick_label(v: &f64) -> String {
    let s = plotters::data::float::FloatPrettyPrinter {
        allow_scientific: false,
        min_decimal: 1,
        max_decimal: 5,
    }
    .print(*v);
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// The font family name plots use for their text.
pub const FONT: &str = "sans-serif";

/// Standard install locations of a few common permissively licensed sans-serif fonts.
const SYSTEM_FONTS: [&str; 4] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
];

/// Whether a font was found and registered (looked up once per process).
pub fn has_text() -> bool {
    static FOUND: OnceLock<bool> = OnceLock::new();
    *FOUND.get_or_init(|| {
        let from_env = std::env::var_os("STANCE_PLOT_FONT");
        let candidates = from_env
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .chain(SYSTEM_FONTS.iter().map(|s| s.to_string()));
        for path in candidates {
            if let Ok(bytes) = std::fs::read(&path) {
                // plotters keeps a 'static reference to the font: leak it once per process.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font(FONT, plotters::style::FontStyle::Normal, bytes)
                    .is_ok()
                {
                    return true;
                }
            }
        }
        false
    })
}

/// `true` for an SVG file, `false` for PNG; an error for anything else.
pub fn is_svg(path: &Path) -> Result<bool> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
    {
        Some(e) if e == "svg" || e == "png" => {
            // Fail here, with the path, rather than in the drawing backend (whose errors name
            // neither the file nor the cause in words).
            std::fs::File::create(path)
                .with_context(|| format!("cannot write plot file {}", path.display()))?;
            Ok(e == "svg")
        }
        _ => bail!("plot file {} must end in .svg or .png", path.display()),
    }
}

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

#[cfg(test)]
mod tests {
    use super::tick_label;

    #[test]
    fn tick_labels_have_no_negative_zero() {
        assert_eq!(tick_label(&-2.8e-17), "0.0");
        assert_eq!(tick_label(&0.0), "0.0");
        assert_eq!(tick_label(&-0.15), "-0.15");
        assert_eq!(tick_label(&0.05), "0.05");
    }
}
