//! `stance giwc SCENE` and `stance equilibrium polygon|region|test SCENE`.
//!
//! `SCENE` is a scene file (JSON, or TOML for a `.toml` file; format in the project's
//! ARCHITECTURE.md) or the name of a built-in example: `single-support`, `double-support`,
//! `stairs`, `box-climbing`.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use serde::Deserialize;
use stance::stance_contact::equilibrium::{PolygonWorkspace, RobustRegion};
use stance::stance_contact::{Giwc, GiwcOptions, Scene, Stance};

use stance::report::{GiwcReport, PolygonReport, RegionReport, StabilityReport};

use super::io::{read_input, write_output, Common};
use super::plot;

/// A gravity-like vector `gx,gy,gz` (m/s^2).
pub fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected gx,gy,gz (three numbers), got `{s}`"));
    }
    let mut out = [0.0; 3];
    for (o, p) in out.iter_mut().zip(&parts) {
        *o = p
            .parse::<f64>()
            .map_err(|_| format!("`{p}` is not a number"))?;
        if !o.is_finite() {
            return Err(format!("`{p}` is not finite"));
        }
    }
    Ok(out)
}

#[derive(clap::Args)]
pub struct GiwcArgs {
    /// Scene file (JSON/TOML) or built-in example name.
    pub scene: String,
    /// Face form of the net contact wrench cone (`-U`, w_c = -w_GI) instead of the GIWC.
    #[arg(long)]
    pub net_contact_wrench: bool,
    /// Certified exact combinatorics for the generators as computed in floating point (slower;
    /// rounding of rotated/translated generators can split facets of the intended geometry).
    #[arg(long)]
    pub exact: bool,

    #[command(flatten)]
    pub common: Common,
}

#[derive(clap::Subcommand)]
pub enum EquilibriumCommand {
    /// Static-equilibrium polygon of the CoM for the scene's gravity (or --gravity).
    Polygon(PolygonArgs),
    /// Robust static-equilibrium region M for gravity-like vectors (3-D polyhedron).
    Region(RegionArgs),
    /// Test CoMs: static equilibrium (scene gravity) or robust (every --gravity).
    Test(TestArgs),
}

#[derive(clap::Args)]
pub struct PolygonArgs {
    /// Scene file (JSON/TOML) or built-in example name.
    pub scene: String,
    /// Gravity gx,gy,gz (default: the scene's); e.g. --gravity=-0.15,0,-9.81.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub gravity: Option<[f64; 3]>,
    /// Height z (m) of the cross-section (matters only for non-vertical gravity).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub height: f64,
    /// Also draw the polygon and the contact footprints to this .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Compute through U_stance (the GIWC face form) instead of directly from the contact
    /// forces (the default, which falls back to U_stance by itself when it must).
    #[arg(long)]
    pub via_u_stance: bool,
    #[command(flatten)]
    pub common: Common,
}

#[derive(clap::Args)]
pub struct RegionArgs {
    /// Scene file (JSON/TOML) or built-in example name.
    pub scene: String,
    /// Gravity-like vector gx,gy,gz; repeat the option for several (default: the scene's).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub gravity: Vec<[f64; 3]>,
    /// Also draw three orthogonal projections of the region to this .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
}

#[derive(clap::Args)]
pub struct TestArgs {
    /// Scene file (JSON/TOML) or built-in example name.
    pub scene: String,
    /// Points file: {"points": [[x, y, z], ...]} (JSON or TOML).
    #[arg(long, value_name = "FILE")]
    pub points: PathBuf,
    /// Gravity-like vector gx,gy,gz; repeat for a robust test (default: the scene's).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub gravity: Vec<[f64; 3]>,
    /// Also report each point's signed margin (m).
    #[arg(long)]
    pub margin: bool,
    #[command(flatten)]
    pub common: Common,
}

fn stance_and_giwc(scene: &Scene) -> Result<(Stance, Giwc)> {
    let stance = scene.stance().context("invalid scene")?;
    let giwc = stance
        .u_stance(&GiwcOptions::default())
        .context("cannot compute the GIWC")?;
    Ok((stance, giwc))
}

pub fn run_giwc(a: GiwcArgs) -> Result<()> {
    let scene = stance::input::scene(&a.scene)?;
    let stance = scene.stance().context("invalid scene")?;
    let mut opts = GiwcOptions::default();
    if a.exact {
        opts.dd.arithmetic = stance::polycone::Arithmetic::Exact;
    }
    let mut ws = stance::polycone::Workspace::new();
    let giwc = a
        .common
        .repeated(|| stance.u_stance_with(&mut ws, &opts))
        .context("cannot compute the GIWC")?;
    write_output(
        &a.common,
        &GiwcReport::new(&stance, &giwc, a.net_contact_wrench),
    )
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PointsIn {
    points: Vec<Com>,
}

/// A CoM `[x, y, z]`: exactly three numbers. (A plain `[f64; 3]` read from TOML silently drops
/// extra numbers; this checks the length in every format without allocating per point.)
struct Com([f64; 3]);

impl<'de> Deserialize<'de> for Com {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::{Error, IgnoredAny, SeqAccess, Visitor};
        struct Three;
        impl<'de> Visitor<'de> for Three {
            type Value = Com;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a point [x, y, z] of 3 numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<Com, A::Error> {
                let mut p = [0.0; 3];
                for (i, x) in p.iter_mut().enumerate() {
                    *x = seq
                        .next_element()?
                        .ok_or_else(|| A::Error::invalid_length(i, &self))?;
                }
                let mut n = 3;
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    n += 1;
                }
                if n != 3 {
                    return Err(A::Error::invalid_length(n, &self));
                }
                Ok(Com(p))
            }
        }
        d.deserialize_seq(Three)
    }
}

/// The CoMs of a points file, checked finite.
fn com_points(coms: Vec<Com>) -> Result<Vec<[f64; 3]>> {
    let points: Vec<[f64; 3]> = coms.into_iter().map(|c| c.0).collect();
    if let Some(i) = points.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        bail!("point {i} has a non-finite coordinate");
    }
    Ok(points)
}

pub fn run_equilibrium(c: EquilibriumCommand) -> Result<()> {
    let opts = Default::default();
    match c {
        EquilibriumCommand::Polygon(a) => {
            let scene = stance::input::scene(&a.scene)?;
            let g = a.gravity.unwrap_or(scene.gravity);
            if !a.height.is_finite() {
                bail!("--height must be finite");
            }
            let stance = scene.stance()?;
            let mut ws = PolygonWorkspace::new();
            let (poly, route) = a.common.repeated(|| -> Result<_> {
                Ok(if a.via_u_stance {
                    let p = ws.static_polygon_via_u_stance(&stance, g, a.height, &opts)?;
                    (p, None)
                } else {
                    let d = ws.static_polygon(&stance, g, a.height, &opts)?;
                    (d.polygon, Some(d.route))
                })
            })?;
            if let Some(path) = &a.plot {
                plot::equilibrium::polygon(path, &stance, &poly)?;
            }
            write_output(
                &a.common,
                &PolygonReport::new(&poly, route.as_ref(), a.height, g),
            )
        }
        EquilibriumCommand::Region(a) => {
            let scene = stance::input::scene(&a.scene)?;
            let gs = if a.gravity.is_empty() {
                vec![scene.gravity]
            } else {
                a.gravity.clone()
            };
            let (stance, giwc) = stance_and_giwc(&scene)?;
            let region = a.common.repeated(|| RobustRegion::new(&giwc, &gs, &opts))?;
            if let Some(path) = &a.plot {
                plot::equilibrium::region(path, &stance, &region)?;
            }
            write_output(&a.common, &RegionReport::new(&region))
        }
        EquilibriumCommand::Test(a) => {
            let scene = stance::input::scene(&a.scene)?;
            let pts: PointsIn = read_input(&a.points)?;
            let points = com_points(pts.points)
                .with_context(|| format!("in the points file {}", a.points.display()))?;
            let gs = if a.gravity.is_empty() {
                vec![scene.gravity]
            } else {
                a.gravity.clone()
            };
            let (_, giwc) = stance_and_giwc(&scene)?;
            let region = RobustRegion::new(&giwc, &gs, &opts)?;
            let mut stable = vec![false; points.len()];
            a.common
                .repeated(|| batch_with_progress(&region, &points, &mut stable))?;
            let margin = a
                .margin
                .then(|| points.iter().map(|&p| region.margin(p)).collect());
            write_output(
                &a.common,
                &StabilityReport {
                    stable,
                    margin,
                    gravities: gs,
                },
            )
        }
    }
}

/// Batch test with a progress bar on standard error for long batches.
fn batch_with_progress(region: &RobustRegion, points: &[[f64; 3]], out: &mut [bool]) -> Result<()> {
    /// Batches shorter than this finish in well under a second: no progress bar.
    const LONG_BATCH: usize = 10_000_000;
    /// Points per progress step.
    const STEP: usize = 1_000_000;
    if points.len() < LONG_BATCH {
        region.contains_batch(points, out)?;
        return Ok(());
    }
    let bar = indicatif::ProgressBar::new(points.len() as u64);
    for (p, o) in points.chunks(STEP).zip(out.chunks_mut(STEP)) {
        region.contains_batch(p, o)?;
        bar.inc(p.len() as u64);
    }
    bar.finish_and_clear();
    Ok(())
}
