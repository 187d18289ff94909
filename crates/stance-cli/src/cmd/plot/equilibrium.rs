//! The static-equilibrium polygon and the robust region, plotted with plotters (SVG or PNG by
//! file extension): axes in metres with tick labels when a font is available (see the parent
//! module), otherwise grid lines every power of ten (0.1 m, 1 m, ...) that gives 4 to 40 lines
//! and no text; contact footprints in grey, regions in blue. The region plot shows its
//! projections on (x, y), (x, z), (y, z). An unbounded region (e.g. the prism of a single
//! gravity) is drawn within 1 m of the contacts.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use stance::polycone::polytope::{hull2, polygon_from_halfplanes, PolytopeOptions, RegionStatus};
use stance::stance_contact::equilibrium::{RobustRegion, StaticPolygon};
use stance::stance_contact::Stance;

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
    let text = super::has_text();
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
            .x_label_formatter(&super::tick_label)
            .y_label_formatter(&super::tick_label)
            .x_desc(axes.0)
            .y_desc(axes.1)
            .label_style((super::FONT, 13))
            .axis_desc_style((super::FONT, 15))
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
    if super::is_svg(path)? {
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
    if super::is_svg(path)? {
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

/// The 2-D hull of projected points.
fn hull_of(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    if points.is_empty() {
        return Vec::new();
    }
    hull2(points, &PolytopeOptions::default())
        .map(|h| h.vertices)
        .unwrap_or_default()
}

/// The part of the convex polygon `poly` (vertices in order) inside the
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
