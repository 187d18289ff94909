//! `stance view FILE|NAME [-o view.html]`: one self-contained HTML page (three.js and the data
//! inlined; opens offline from `file://`) of a scene, a motion, or a motion's result JSON. The
//! library computes everything (`stance_view`); this writes the page.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use stance_view::{build, render, MotionViewOptions, SceneViewOptions, SourceKind};

use super::contact::parse_vec3;

#[derive(clap::Args)]
pub struct ViewArgs {
    /// A scene or motion file (JSON/TOML), the JSON output of `stance motion`, or a built-in
    /// name: motions stair-climbing, box-climbing, small-sway, stair-climbing-footholds,
    /// box-climbing-footholds, staircase-walk; scenes single-support, double-support, stairs (box-climbing names the motion: use --scene for the scene).
    pub source: String,
    /// Read the source as a scene.
    #[arg(long, conflicts_with = "motion")]
    pub scene: bool,
    /// Read the source as a motion (file or name).
    #[arg(long)]
    pub motion: bool,
    /// Height (m) of the scene's static polygon (default: 0.8 m above the highest contact).
    #[arg(long, value_name = "Z", allow_hyphen_values = true)]
    pub com_height: Option<f64>,
    /// Gravity-like vector gx,gy,gz of the scene's robust region M; repeat for several
    /// (default: the scene's gravity and four tilts of it by 10 %, i.e. horizontal accelerations of 0.1 g).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub gravity: Vec<[f64; 3]>,
    /// Draw the robot without its mesh files (the URDF's primitives and capsules): a page of
    /// about 1 MB instead of a few.
    #[arg(long)]
    pub no_meshes: bool,
    /// The page to write.
    #[arg(
        short = 'o',
        long = "output",
        value_name = "FILE",
        default_value = "view.html"
    )]
    pub output: PathBuf,
}

pub fn run(a: ViewArgs) -> Result<()> {
    if a.com_height.is_some_and(|z| !z.is_finite()) {
        bail!("--com-height must be a finite number of metres");
    }
    let kind = if a.scene {
        Some(SourceKind::Scene)
    } else if a.motion {
        Some(
            stance_view::source_kind(&a.source).map_or(SourceKind::Motion, |k| match k {
                SourceKind::MotionResult => k,
                _ => SourceKind::Motion,
            }),
        )
    } else {
        None
    };
    let options = SceneViewOptions {
        com_height: a.com_height,
        gravities: a.gravity,
    };
    let motion_options = MotionViewOptions {
        meshes: !a.no_meshes,
        progress: Some(|line| eprintln!("{line}")),
    };
    let view = build(&a.source, kind, &options, &motion_options)?;
    write_page(&a.output, &view)
}

/// Writes the page of `view` to `path` and says where on standard error.
pub fn write_page(path: &std::path::Path, view: &stance_view::ViewData) -> Result<()> {
    let page = render(view);
    std::fs::write(path, &page)
        .with_context(|| format!("cannot write the page {}", path.display()))?;
    eprintln!(
        "wrote {} ({:.2} MB): open it in a browser (it needs no network)",
        path.display(),
        page.len() as f64 / 1e6
    );
    Ok(())
}
