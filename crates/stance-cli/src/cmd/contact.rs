//! `stance giwc SCENE` and `stance equilibrium polygon|region|test SCENE`.
//!
//! `SCENE` is a scene file (JSON, or TOML for a `.toml` file; format in the project's
//! ARCHITECTURE.md) or the name of a built-in example: `single-support`, `double-support`,
//! `stairs`, `box-climbing`.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use serde::{Deserialize, Serialize};
use stance::polycone::polytope::{hull2, polygon_from_halfplanes, PolytopeOptions, RegionStatus};
use stance::stance_contact::equilibrium::{
    PolygonRoute, PolygonWorkspace, RobustRegion, StaticPolygon,
};
use stance::stance_contact::{examples, Giwc, GiwcOptions, Scene, Stance};

use super::io::{read_input, write_output, Common};

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

/// Loads a scene from a file, or a built-in example by name.
fn load_scene(scene: &str) -> Result<Scene> {
    let path = Path::new(scene);
    if path.exists() {
        return read_input(path);
    }
    examples::by_name(scene).ok_or_else(|| {
        anyhow!(
            "`{scene}` is neither a file nor a built-in example ({})",
            examples::NAMES.join(", ")
        )
    })
}

fn stance_and_giwc(scene: &Scene) -> Result<(Stance, Giwc)> {
    let stance = scene.stance().context("invalid scene")?;
    let giwc = stance
        .u_stance(&GiwcOptions::default())
        .context("cannot compute the GIWC")?;
    Ok((stance, giwc))
}

fn rows(m: &stance::stance_contact::nalgebra::DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

fn status_str(s: RegionStatus) -> &'static str {
    match s {
        RegionStatus::Empty => "empty",
        RegionStatus::Bounded => "bounded",
        RegionStatus::Unbounded => "unbounded",
    }
}

#[derive(Serialize)]
struct FaceOut {
    facets: Vec<Vec<f64>>,
    equations: Vec<Vec<f64>>,
    lineality: Vec<Vec<f64>>,
}

#[derive(Serialize)]
struct GiwcOut {
    giwc: FaceOut,
    span: Vec<Vec<f64>>,
    convention: &'static str,
    certified: bool,
    contacts: Vec<String>,
}

pub fn run_giwc(a: GiwcArgs) -> Result<()> {
    let scene = load_scene(&a.scene)?;
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
    let (facets, convention) = if a.net_contact_wrench {
        (
            giwc.net_contact_wrench_face().0,
            "net contact wrench: rows u with u . w_c <= 0, w_c = -w_GI, wrench at the world origin (force, torque)",
        )
    } else {
        (
            giwc.facets.clone(),
            "GIWC (paper): rows u with u . w_GI <= 0, wrench at the world origin (force, torque)",
        )
    };
    let span = if a.net_contact_wrench {
        -stance.giwc_span()
    } else {
        stance.giwc_span()
    };
    write_output(
        &a.common,
        &GiwcOut {
            giwc: FaceOut {
                facets: rows(&facets),
                equations: rows(&giwc.equations),
                lineality: rows(&giwc.lineality),
            },
            span: rows(&span),
            convention,
            certified: giwc.certified,
            contacts: stance
                .contacts()
                .iter()
                .map(|c| c.name().to_string())
                .collect(),
        },
    )
}

#[derive(Serialize)]
struct PolygonOut {
    status: &'static str,
    /// "direct", or "u_stance" with the reason when the direct route gave way.
    route: String,
    /// 2 for a proper polygon, 1 for a segment, 0 for a point (or empty).
    dim: usize,
    vertices: Vec<[f64; 2]>,
    halfplanes: Vec<[f64; 3]>,
    height: f64,
    gravity: [f64; 3],
}

#[derive(Serialize)]
struct RegionOut {
    status: &'static str,
    vertices: Vec<[f64; 3]>,
    faces: Vec<Vec<usize>>,
    halfspaces: Vec<[f64; 4]>,
    gravities: Vec<[f64; 3]>,
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

#[derive(Serialize)]
struct TestOut {
    stable: Vec<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    margin: Option<Vec<f64>>,
    gravities: Vec<[f64; 3]>,
}

pub fn run_equilibrium(c: EquilibriumCommand) -> Result<()> {
    let opts = Default::default();
    match c {
        EquilibriumCommand::Polygon(a) => {
            let scene = load_scene(&a.scene)?;
            let g = a.gravity.unwrap_or(scene.gravity);
            if !a.height.is_finite() {
                bail!("--height must be finite");
            }
            let stance = scene.stance()?;
            let mut ws = PolygonWorkspace::new();
            let (poly, route) = a.common.repeated(|| -> Result<_> {
                Ok(if a.via_u_stance {
                    let p = ws.static_polygon_via_u_stance(&stance, g, a.height, &opts)?;
                    (p, "u_stance (requested)".to_string())
                } else {
                    let d = ws.static_polygon(&stance, g, a.height, &opts)?;
                    let route = match d.route {
                        PolygonRoute::Direct => "direct".to_string(),
                        PolygonRoute::ViaUStance(why) => format!("u_stance ({why:?})"),
                    };
                    (d.polygon, route)
                })
            })?;
            if let Some(path) = &a.plot {
                plot::polygon(path, &stance, &poly)?;
            }
            write_output(
                &a.common,
                &PolygonOut {
                    status: status_str(poly.status),
                    route,
                    dim: poly.dim,
                    halfplanes: poly
                        .halfplanes
                        .iter()
                        .map(|(n, b)| [n[0], n[1], *b])
                        .collect(),
                    vertices: poly.vertices,
                    height: a.height,
                    gravity: g,
                },
            )
        }
        EquilibriumCommand::Region(a) => {
            let scene = load_scene(&a.scene)?;
            let gs = if a.gravity.is_empty() {
                vec![scene.gravity]
            } else {
                a.gravity.clone()
            };
            let (stance, giwc) = stance_and_giwc(&scene)?;
            let region = a.common.repeated(|| RobustRegion::new(&giwc, &gs, &opts))?;
            if let Some(path) = &a.plot {
                plot::region(path, &stance, &region)?;
            }
            let p = &region.polyhedron;
            write_output(
                &a.common,
                &RegionOut {
                    status: status_str(p.status),
                    vertices: p.vertices.clone(),
                    faces: p.faces.clone(),
                    halfspaces: region
                        .halfspaces
                        .normals
                        .iter()
                        .zip(&region.halfspaces.offsets)
                        .map(|(n, d)| [n[0], n[1], n[2], *d])
                        .collect(),
                    gravities: gs,
                },
            )
        }
        EquilibriumCommand::Test(a) => {
            let scene = load_scene(&a.scene)?;
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
                &TestOut {
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

/// Used by the plot module: the 2-D hull of projected points.
fn hull_of(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    if points.is_empty() {
        return Vec::new();
    }
    hull2(points, &PolytopeOptions::default())
        .map(|h| h.vertices)
        .unwrap_or_default()
}

/// Used by the plot module: the part of the convex polygon `poly` (vertices in order) inside the
/// box `[lo, hi]` (unbounded regions reach the 1e6 m far box, which would squash the plot).
fn clip_to_box(poly: &[[f64; 2]], lo: [f64; 2], hi: [f64; 2]) -> Vec<[f64; 2]> {
    let opts = PolytopeOptions::default();
    let Ok(hull) = hull2(poly, &opts) else {
        return Vec::new();
    };
    if hull.dim < 2 {
        // A segment or a point: clamp its (at most two) points into the box.
        return hull
            .vertices
            .iter()
            .map(|p| [p[0].clamp(lo[0], hi[0]), p[1].clamp(lo[1], hi[1])])
            .collect();
    }
    let mut a: Vec<[f64; 2]> = vec![[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
    let mut b: Vec<f64> = vec![hi[0], -lo[0], hi[1], -lo[1]];
    for (n, c) in hull.halfplanes() {
        a.push(n);
        b.push(c);
    }
    polygon_from_halfplanes(&a, &b, &opts)
        .map(|p| p.vertices)
        .unwrap_or_default()
}

/// Plots with plotters, SVG or PNG by file extension: axes in metres with tick labels when a font
/// is available (see `cmd::plot`), otherwise grid lines every power of ten (0.1 m, 1 m, ...)
/// that gives 4 to 40 lines and no text; contact footprints in grey, regions in blue. The region plot shows its projections on (x, y), (x, z), (y, z).
/// An unbounded region (e.g. the prism of a single gravity) is drawn within 1 m of the contacts.
pub(crate) mod plot {
    use std::path::Path;

    use anyhow::{anyhow, Result};
    use plotters::coord::Shift;
    use plotters::prelude::*;

    use super::{clip_to_box, hull_of, RobustRegion, Stance, StaticPolygon};
    use stance::polycone::polytope::RegionStatus;

    /// Fallback grid spacing (m).
    const GRID: f64 = 0.1;
    /// Margin around the drawn geometry (m).
    const PAD: f64 = 0.1;
    /// An unbounded region is drawn within this distance (m) of the contacts' bounding box.
    const UNBOUNDED_WINDOW: f64 = 1.0;

    /// The drawn part of a region's shadow: all of it when bounded, else its part within
    /// [`UNBOUNDED_WINDOW`] of the footprints.
    fn window(shadow: Vec<[f64; 2]>, feet: &[Vec<[f64; 2]>], unbounded: bool) -> Vec<[f64; 2]> {
        if !unbounded {
            return shadow;
        }
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in feet.iter().flatten() {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if !lo[0].is_finite() || !lo[1].is_finite() {
            return shadow;
        }
        let w = UNBOUNDED_WINDOW;
        clip_to_box(&shadow, [lo[0] - w, lo[1] - w], [hi[0] + w, hi[1] + w])
    }

    fn footprints(stance: &Stance) -> Vec<Vec<[f64; 3]>> {
        stance
            .contacts()
            .iter()
            .map(|c| c.vertices_world())
            .collect()
    }

    /// Bounds of 2-D point sets, padded (`square`: same range on both axes).
    fn bounds(sets: &[Vec<[f64; 2]>], square: bool) -> ((f64, f64), (f64, f64)) {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in sets.iter().flatten() {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if !lo[0].is_finite() {
            return ((-1.0, 1.0), (-1.0, 1.0));
        }
        let c = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        let mut half = [(hi[0] - lo[0]) / 2.0 + PAD, (hi[1] - lo[1]) / 2.0 + PAD];
        if square {
            let h = half[0].max(half[1]);
            half = [h, h];
        }
        (
            (c[0] - half[0], c[0] + half[0]),
            (c[1] - half[1], c[1] + half[1]),
        )
    }

    /// Grid spacing for a range: a power of ten giving 4 to 40 lines.
    fn spacing(range: f64) -> f64 {
        let s = 10f64.powf((range / 4.0).log10().floor());
        if s.is_finite() && s > 0.0 {
            s
        } else {
            GRID
        }
    }

    fn panel<DB: DrawingBackend>(
        area: &DrawingArea<DB, Shift>,
        feet: &[Vec<[f64; 2]>],
        region: &[[f64; 2]],
        square: bool,
        axes: (&str, &str),
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let mut sets: Vec<Vec<[f64; 2]>> = feet.to_vec();
        sets.push(region.to_vec());
        let ((x0, x1), (y0, y1)) = bounds(&sets, square);
        let (gx, gy) = (spacing(x1 - x0), spacing(y1 - y0));
        let grid = RGBColor(225, 225, 225);
        let text = crate::cmd::plot::has_text();
        let label_area = if text { 45 } else { 0 };
        let mut chart = ChartBuilder::on(area)
            .margin(8)
            .x_label_area_size(label_area)
            .y_label_area_size(label_area)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        if text {
            chart
                .configure_mesh()
                .x_label_formatter(&crate::cmd::plot::tick_label)
                .y_label_formatter(&crate::cmd::plot::tick_label)
                .x_desc(axes.0)
                .y_desc(axes.1)
                .label_style((crate::cmd::plot::FONT, 13))
                .axis_desc_style((crate::cmd::plot::FONT, 15))
                .bold_line_style(grid)
                .light_line_style(WHITE)
                .draw()
                .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        }
        if !text {
            let mut lines = Vec::new();
            let mut x = (x0 / gx).ceil() * gx;
            while x <= x1 {
                lines.push(vec![(x, y0), (x, y1)]);
                x += gx;
            }
            let mut y = (y0 / gy).ceil() * gy;
            while y <= y1 {
                lines.push(vec![(x0, y), (x1, y)]);
                y += gy;
            }
            chart
                .draw_series(lines.into_iter().map(|l| PathElement::new(l, grid)))
                .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        }
        for f in feet {
            let pts: Vec<(f64, f64)> = f.iter().map(|p| (p[0], p[1])).collect();
            chart
                .draw_series(std::iter::once(Polygon::new(
                    pts.clone(),
                    RGBColor(150, 150, 150).mix(0.5),
                )))
                .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
            let mut closed = pts;
            closed.push(closed[0]);
            chart
                .draw_series(std::iter::once(PathElement::new(closed, BLACK)))
                .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        }
        if !region.is_empty() {
            let pts: Vec<(f64, f64)> = region.iter().map(|p| (p[0], p[1])).collect();
            chart
                .draw_series(std::iter::once(Polygon::new(pts.clone(), BLUE.mix(0.35))))
                .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
            let mut closed = pts;
            closed.push(closed[0]);
            chart
                .draw_series(std::iter::once(PathElement::new(
                    closed,
                    BLUE.stroke_width(2),
                )))
                .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        }
        Ok(())
    }

    fn draw_polygon<DB: DrawingBackend>(
        root: DrawingArea<DB, Shift>,
        stance: &Stance,
        poly: &StaticPolygon,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE)
            .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        let feet: Vec<Vec<[f64; 2]>> = footprints(stance)
            .iter()
            .map(|f| hull_of(&f.iter().map(|p| [p[0], p[1]]).collect::<Vec<_>>()))
            .collect();
        let shown = window(
            poly.vertices.clone(),
            &feet,
            poly.status == RegionStatus::Unbounded,
        );
        panel(&root, &feet, &shown, true, ("x (m)", "y (m)"))?;
        root.present()
            .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        Ok(())
    }

    fn draw_region<DB: DrawingBackend>(
        root: DrawingArea<DB, Shift>,
        stance: &Stance,
        region: &RobustRegion,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE)
            .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        let panels = root.split_evenly((1, 3));
        // Projections onto (x, y), (x, z), (y, z), like the paper's Fig. 3.
        let names = ["x (m)", "y (m)", "z (m)"];
        for (area, (i, j)) in panels.iter().zip([(0, 1), (0, 2), (1, 2)]) {
            let proj = |p: &[f64; 3]| [p[i], p[j]];
            let feet: Vec<Vec<[f64; 2]>> = footprints(stance)
                .iter()
                .map(|f| hull_of(&f.iter().map(proj).collect::<Vec<_>>()))
                .collect();
            let shadow = hull_of(
                &region
                    .polyhedron
                    .vertices
                    .iter()
                    .map(proj)
                    .collect::<Vec<_>>(),
            );
            let unbounded = region.polyhedron.status == RegionStatus::Unbounded;
            let shown = window(shadow, &feet, unbounded);
            panel(area, &feet, &shown, false, (names[i], names[j]))?;
        }
        root.present()
            .map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        Ok(())
    }

    pub fn polygon(path: &Path, stance: &Stance, poly: &StaticPolygon) -> Result<()> {
        if crate::cmd::plot::is_svg(path)? {
            draw_polygon(
                SVGBackend::new(path, (640, 640)).into_drawing_area(),
                stance,
                poly,
            )
        } else {
            draw_polygon(
                BitMapBackend::new(path, (640, 640)).into_drawing_area(),
                stance,
                poly,
            )
        }
    }

    pub fn region(path: &Path, stance: &Stance, region: &RobustRegion) -> Result<()> {
        if crate::cmd::plot::is_svg(path)? {
            draw_region(
                SVGBackend::new(path, (1500, 500)).into_drawing_area(),
                stance,
                region,
            )
        } else {
            draw_region(
                BitMapBackend::new(path, (1500, 500)).into_drawing_area(),
                stance,
                region,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::clip_to_box;

    /// Review of issue 3: unbounded regions (the prism of a single gravity) were drawn out to
    /// the 1e6 m far box, squashing the contacts into a line.
    #[test]
    fn unbounded_shadows_are_clipped_to_the_window() {
        let far = 1e6;
        let prism = [[-0.1, -far], [0.1, -far], [0.1, far], [-0.1, far]];
        let clipped = clip_to_box(&prism, [-1.0, -2.0], [1.0, 3.0]);
        assert_eq!(clipped.len(), 4);
        for want in [[-0.1, -2.0], [0.1, -2.0], [0.1, 3.0], [-0.1, 3.0]] {
            assert!(clipped
                .iter()
                .any(|p| (p[0] - want[0]).abs() < 1e-9 && (p[1] - want[1]).abs() < 1e-9));
        }
        // A segment is clamped into the box.
        let seg = clip_to_box(&[[0.0, -far], [0.0, far]], [-1.0, -1.0], [1.0, 1.0]);
        assert!(seg.iter().all(|p| p[1].abs() <= 1.0));
    }
}
