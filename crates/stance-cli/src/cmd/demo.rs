//! `stance demo`: the paper's built-in examples end to end, with a readable summary.
//!
//! For each built-in scene (flat single and double support, the 24 cm stair, box climbing): the
//! GIWC face form `U_stance` (once per stance, certified), the static-equilibrium polygon, a
//! retiming of a CoM motion under contact stability (GIWC -> TOPP) with its violation between
//! grid points; for box climbing the robust static-equilibrium polyhedron and a batch of one
//! million robust CoM tests; and the centroidal quantities of the project's small humanoid;
//! then the paper's whole-body experiments on JVRC-1, written by hand and as footholds only.
//! Plots (static-equilibrium polygons, the robust region, phase planes) go to `--out DIR` (default `stance-demo`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use stance::retime::{retime, ComMotionSpec, Discretization, Interpolation, PathSpec, SceneRef};
use stance::stance_contact::equilibrium::{PolygonWorkspace, RobustRegion, StaticEquilibrium};
use stance::stance_contact::{examples, Giwc, GiwcOptions, Scene};
use stance::stance_robot::{Data, Model, UrdfOptions, SMALL_HUMANOID_URDF};

#[derive(clap::Args)]
pub struct DemoArgs {
    /// Directory for the plots (created if missing).
    #[arg(long, default_value = "stance-demo", value_name = "DIR")]
    pub out: PathBuf,
}

/// A CoM motion over each scene: start, middle and end waypoints (m).
fn motion(name: &str) -> Vec<[f64; 3]> {
    match name {
        "single-support" => vec![[-0.03, 0.0, 0.8], [0.03, 0.01, 0.78], [0.03, -0.02, 0.8]],
        "double-support" => vec![[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]],
        "stairs" => vec![[0.0, 0.08, 0.8], [0.12, 0.0, 0.9], [0.26, -0.08, 1.02]],
        "robust-equilibrium" => vec![[0.53, -0.15, 0.8], [0.52, -0.2, 0.82], [0.51, -0.25, 0.8]],
        _ => vec![[0.2, 0.0, 0.8], [0.25, -0.05, 0.85], [0.3, -0.1, 0.9]],
    }
}

pub fn run(args: DemoArgs) -> Result<()> {
    let mut o = String::new();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the output directory {}", args.out.display()))?;
    writeln!(
        o,
        "stance demo: the paper's stances end to end (times are wall-clock, this machine)\n"
    )?;
    let giwcs = giwc_section(&mut o)?;
    polygon_section(&mut o, &giwcs, &args.out)?;
    robust_section(&mut o, &giwcs, &args.out)?;
    retiming_section(&mut o, &giwcs, &args.out)?;
    robot_section(&mut o)?;
    super::io::print_text(&o)?;
    o.clear();
    motions(&mut o, &args.out)?;
    writeln!(
        o,
        "\nPlots (static-equilibrium polygons, the robust region, phase planes x = s'^2 against s): {}",
        args.out.display()
    )?;
    super::io::print_text(&o)
}

/// A built-in scene with its GIWC.
type SceneGiwc = (&'static str, Scene, Giwc);

/// Section 1: `U_stance` of every built-in scene.
fn giwc_section(o: &mut String) -> Result<Vec<SceneGiwc>> {
    writeln!(
        o,
        "1. Gravito-inertial wrench cone, U_stance (once per stance; paper Section III)"
    )?;
    writeln!(
        o,
        "   {:<18} {:>8} {:>10} {:>7} {:>4} {:>4} {:>10} {:>9}",
        "scene", "contacts", "generators", "facets", "eq", "lin", "certified", "time ms"
    )?;
    let mut giwcs = Vec::new();
    for name in examples::NAMES {
        let scene = examples::by_name(name).expect("built-in name");
        let stance = scene.stance()?;
        let span = stance.giwc_span();
        let t = Instant::now();
        let giwc = stance.u_stance(&GiwcOptions::default())?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        writeln!(
            o,
            "   {:<18} {:>8} {:>10} {:>7} {:>4} {:>4} {:>10} {:>9.3}",
            name,
            stance.contacts().len(),
            span.nrows(),
            giwc.facets.nrows(),
            giwc.equations.nrows(),
            giwc.lineality.nrows(),
            giwc.certified,
            ms
        )?;
        giwcs.push((name, scene, giwc));
    }
    Ok(giwcs)
}

/// Section 2: the static-equilibrium polygons, through `U_stance` and from the contacts.
fn polygon_section(o: &mut String, giwcs: &[SceneGiwc], out: &Path) -> Result<()> {
    writeln!(
        o,
        "\n2. Static-equilibrium polygon (vertical gravity; paper Section IV)"
    )?;
    writeln!(
        o,
        "   {:<18} {:>9} {:>10} {:>13} {:>17}",
        "scene", "vertices", "area m^2", "from U ms", "from contacts ms"
    )?;
    let mut ws = PolygonWorkspace::new();
    for (name, scene, giwc) in giwcs {
        let t = Instant::now();
        let eq = StaticEquilibrium::new(giwc, scene.gravity, &Default::default())?;
        let poly = eq.polygon(0.0)?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        // The same polygon straight from the contact forces (no U_stance), certified.
        let stance = scene.stance()?;
        let t = Instant::now();
        let direct = ws.static_polygon(&stance, scene.gravity, 0.0, &Default::default())?;
        let ms_direct = t.elapsed().as_secs_f64() * 1e3;
        if direct.polygon.vertices.len() != poly.vertices.len() {
            bail!("{name}: the direct polygon and the one through U_stance differ");
        }
        super::plot::equilibrium::polygon(
            &out.join(format!("polygon-{name}.svg")),
            &scene.stance()?,
            &poly,
        )?;
        let v = &poly.vertices;
        let area = 0.5
            * (0..v.len())
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % v.len()]);
                    a[0] * b[1] - a[1] * b[0]
                })
                .sum::<f64>();
        writeln!(
            o,
            "   {:<18} {:>9} {:>10.4} {:>13.3} {:>17.3}",
            name,
            v.len(),
            area,
            ms,
            ms_direct
        )?;
    }
    Ok(())
}

/// Section 3: the robust region of the paper's Fig. 3 scene and a million CoM tests.
fn robust_section(o: &mut String, giwcs: &[SceneGiwc], out: &Path) -> Result<()> {
    let mut gravities = Vec::new();
    for (gx, gy) in [(0.15, 0.0), (-0.15, 0.0), (0.0, 0.15), (0.0, -0.15)] {
        gravities.push([gx, gy, -9.81]);
    }
    let (_, fig3_scene, fig3_giwc) = giwcs
        .iter()
        .find(|(n, _, _)| *n == "robust-equilibrium")
        .expect("built-in scene");
    let t = Instant::now();
    let region = RobustRegion::new(fig3_giwc, &gravities, &Default::default())?;
    let region_ms = t.elapsed().as_secs_f64() * 1e3;
    super::plot::equilibrium::region(
        &out.join("region-robust-equilibrium.svg"),
        &fig3_scene.stance()?,
        &region,
    )?;
    let n = 1_000_000;
    let points: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            // A deterministic low-discrepancy cloud over a 1 m box around the stance.
            let f = |k: f64| (i as f64 * k).fract();
            [
                f(0.754_877_666) - 0.2,
                f(0.569_840_29) - 0.6,
                0.4 + f(0.438_579_32),
            ]
        })
        .collect();
    let mut stable = vec![false; n];
    let t = Instant::now();
    region.contains_batch(&points, &mut stable)?;
    let batch = t.elapsed();
    writeln!(
        o,
        "\n3. Robust static equilibrium, the paper's Fig. 3 scene (right foot on a tilted box, \
         forearm on a ledge), 4 gravity vectors (+-0.15 m/s^2 tilts)"
    )?;
    writeln!(
        o,
        "   U_stance: {} rows (paper: 105, unpruned cdd, 3.5 ms)",
        fig3_giwc.facets.nrows()
    )?;
    writeln!(
        o,
        "   3-D region M: {} vertices, {} faces ({:?}) in {:.3} ms",
        region.polyhedron.vertices.len(),
        region.polyhedron.faces.len(),
        region.polyhedron.status,
        region_ms
    )?;
    writeln!(
        o,
        "   {} CoM tests: {} stable, {:.1} ms in all, {:.1} ns per CoM (paper: 0.1 ms per test)",
        n,
        stable.iter().filter(|s| **s).count(),
        batch.as_secs_f64() * 1e3,
        batch.as_secs_f64() * 1e9 / n as f64
    )?;
    Ok(())
}

/// Section 4: a CoM motion retimed in every built-in scene.
fn retiming_section(o: &mut String, giwcs: &[SceneGiwc], out: &Path) -> Result<()> {
    writeln!(
        o,
        "\n4. Retiming a CoM motion under contact stability (GIWC -> TOPP; paper Section V)"
    )?;
    writeln!(
        o,
        "   {:<18} {:>6} {:>5} {:>11} {:>10} {:>12} {:>7} {:>7} {:>7}",
        "scene", "grid", "rows", "status", "duration s", "between %mg", "t_u ms", "t_abc", "t_topp"
    )?;
    for (name, _, _) in giwcs {
        let spec = ComMotionSpec {
            scene: SceneRef::Named(name.to_string()),
            path: PathSpec {
                waypoints: motion(name),
                knots: None,
                interpolation: Interpolation::Spline,
            },
            grid_points: 101,
            sd_start: 0.0,
            sd_end: 0.0,
            discretization: Discretization::Interpolation,
            max_violation_fraction: None,
            samples_per_interval: 10,
            dt: None,
            angular_momentum: None,
        };
        let r = retime(&spec)?;
        let plot = out.join(format!("phase-{name}.svg"));
        super::retime::phase_plane(&plot, &r)?;
        writeln!(
            o,
            "   {:<18} {:>6} {:>5} {:>11} {:>10} {:>12} {:>7.3} {:>7.3} {:>7.3}",
            name,
            r.s.len(),
            r.rows_per_point,
            r.status,
            r.duration.map_or("-".into(), |d| format!("{d:.4}")),
            r.between.map_or("-".into(), |b| format!(
                "{:.3}",
                100.0 * b.fraction_of_weight.max(0.0)
            )),
            r.timings.t_u_ms,
            r.timings.t_abc_ms,
            r.timings.t_topp_ms
        )?;
    }
    Ok(())
}

/// Section 5: the project's small humanoid's centroidal quantities.
fn robot_section(o: &mut String) -> Result<()> {
    writeln!(
        o,
        "\n5. Robot model: the project's small humanoid (URDF), centroidal quantities"
    )?;
    let model = Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions::default())?;
    let mut data = Data::new(&model);
    let q = model.neutral();
    let t = Instant::now();
    stance::stance_robot::centroidal_map(&model, &mut data, &q)?;
    let us = t.elapsed().as_secs_f64() * 1e6;
    writeln!(
        o,
        "   mass {:.3} kg, nq {}, nv {}, CoM at neutral {:?}, A_g in {:.1} us",
        model.total_mass(),
        model.nq,
        model.nv,
        data.com.map(|c| (c * 1e4).round() / 1e4),
        us
    )?;
    Ok(())
}

/// JVRC-1's URDF, installed from PyPI (as `stance setup` does) when missing.
fn ensure_jvrc1() -> Result<()> {
    use stance::motion::venv;
    if venv::jvrc1_urdf().is_ok() {
        return Ok(());
    }
    eprintln!(
        "stance demo: JVRC-1's URDF is not installed; installing {} into {} from PyPI, as \
         `stance setup` does ...",
        venv::REQUIREMENTS.join(" and "),
        venv::dir()?.display()
    );
    venv::setup("python3").context("cannot install JVRC-1's description")?;
    venv::jvrc1_urdf()
        .map(|_| ())
        .context("JVRC-1 is still not available after the setup")
}

/// Section 6: the paper's whole-body experiments on JVRC-1, beside Tables I and II
/// ([`stance::motion::paper`]).
fn motions(o: &mut String, out: &std::path::Path) -> Result<()> {
    use stance::motion::{experiments, paper, run, RunOptions};
    ensure_jvrc1()?;
    o.push_str("\n6. ");
    o.push_str(paper::HEADER);
    for table in &paper::TABLES {
        let spec = experiments::by_name(table.motion)?;
        let mut r2r_spec = spec.clone();
        r2r_spec.retiming.rest_to_rest = true;
        let r = run(spec, &RunOptions::default())?;
        let r2r = run(
            r2r_spec,
            &RunOptions {
                skip_checks: true,
                ..Default::default()
            },
        )?;
        super::motion::plots(&out.join(table.motion), &r, "svg")?;
        o.push_str(&table.compare(&r, &r2r));
    }
    footholds(o)
}

/// The paper's experiments written by hand and as footholds only, side by side.
fn footholds(o: &mut String) -> Result<()> {
    use stance::motion::{experiments, run, RunOptions};
    writeln!(
        o,
        "\n7. The footholds planner: the same experiments written as stances and landings only \
         (CoM via-points and swings planned)\n   {:<16} {:>12} {:>12} {:>12} {:>14}  checks (hand / \
         planned)",
        "motion", "hand-tuned s", "planned s", "planning ms", "plan+pipe ms"
    )?;
    for name in ["stair-climbing", "box-climbing"] {
        let hand = run(experiments::by_name(name)?, &RunOptions::default())?;
        let planned = run(
            experiments::by_name(&format!("{name}-footholds"))?,
            &RunOptions::default(),
        )?;
        // what fails, or "pass"
        let checks = |r: &stance::motion::result::MotionResult| {
            let Some(c) = r.checks.as_ref() else {
                return "-".to_string();
            };
            let mut fails = Vec::new();
            if c.samples_without_forces > 0 {
                fails.push(format!(
                    "{} samples without forces",
                    c.samples_without_forces
                ));
            }
            if !c.collisions.is_empty() {
                fails.push(format!("{} collisions", c.collisions.len()));
            }
            if let Some(m) = c
                .via_points_missed
                .iter()
                .map(|m| m.distance)
                .reduce(f64::max)
            {
                fails.push(format!("via-point missed by {:.1} mm", m * 1e3));
            }
            if fails.is_empty() {
                "pass".into()
            } else {
                fails.join(", ")
            }
        };
        let secs = |r: &stance::motion::result::MotionResult| {
            r.duration.map_or("-".into(), |d| format!("{d:.2}"))
        };
        writeln!(
            o,
            "   {:<16} {:>12} {:>12} {:>12.0} {:>14.0}  {} / {}",
            name,
            secs(&hand),
            secs(&planned),
            planned.planning.as_ref().map_or(0.0, |p| p.millis),
            planned.timings.t_pipeline_ms,
            checks(&hand),
            checks(&planned)
        )?;
    }
    writeln!(
        o,
        "   (box-climbing-footholds also lands the left foot on the box, where the paper stops with \
         it lifted towards it)"
    )?;
    Ok(())
}
