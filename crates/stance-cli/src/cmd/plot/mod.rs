//! The command line's plots, all in this folder: `phase_plane.rs` (a retiming's `s'^2(s)`, for
//! `stance retime` and `stance motion --plot`), `equilibrium.rs` (the static-equilibrium polygon
//! and the robust region, for `stance equilibrium` and `stance demo`); and here what they share:
//! the backend chosen by file extension, and text.
//!
//! Text needs a font. plotters is built without system font discovery (no fontconfig or
//! freetype dependency), so the command line looks for one TrueType font, once: the file named by
//! the `STANCE_PLOT_FONT` environment variable, else DejaVu Sans or Liberation Sans where
//! Linux distributions install them. Without a font, plots are drawn without text (axes, ticks
//! and titles are then described in each command's help).

use std::path::Path;
use std::sync::OnceLock;

use anyhow::{bail, Context, Result};

pub mod equilibrium;
mod phase_plane;
pub use phase_plane::{phase_plane, PhasePlane};

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
