//! Whole-body motions across stances (`stance_motion`): the small humanoid's motion needs no
//! Python; the paper's experiments on JVRC-1 need its URDF from the project virtualenv and skip,
//! saying why, without it.
//!
//! What is checked: the chained retiming is never longer than rest to rest and equals it when
//! every boundary speed is forced to zero; it equals an independent one-shot LP over every grid
//! point of the whole motion (clarabel, sparse); the independent force check passes at every
//! output sample and fails on the same trajectory played 1.3 times faster; the box climbing's
//! third segment cannot be retimed from rest to rest but can chained; bad motion files get
//! errors that name what to fix.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, ZeroConeT,
};
use stance_motion::result::MotionStatus;
use stance_motion::{experiments, run, run_full, spec::MotionSpec, RunOptions};
use stance_topp::{solve, CanonicalConstraints, Discretization, Profile, SolveOptions, Status};

fn jvrc1_available(test: &str) -> bool {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    match stance_robot::jvrc1::locate_urdf(Some(&root)) {
        Ok(_) => true,
        Err(why) => {
            eprintln!("SKIPPED {test}: {why}");
            false
        }
    }
}

fn spec(name: &str) -> MotionSpec {
    experiments::by_name(name).unwrap()
}

fn rest_to_rest(mut s: MotionSpec) -> MotionSpec {
    s.retiming.rest_to_rest = true;
    s
}

/// The discretized retiming of `k` (interpolation) on its grid points `first..N` as one sparse
/// LP over the states `x_first..x_N` (clarabel, independent of the crate's LP kernel): minimize
/// `q . x` subject to every row at `(u_i, x_i)` and (`next_rows_at`) at `(u_i, x_i+1)` with
/// `u_i = (x_i+1 - x_i) / (2 Delta_i)`, the bounds on `x` (capped at `x_cap`, the solver's box),
/// `x_N = 0`, and `x_first = 0` when `from_rest`.
fn tail_lp(
    k: &CanonicalConstraints,
    first: usize,
    from_rest: bool,
    x_cap: f64,
    q: &[f64],
) -> Option<Vec<f64>> {
    let n = k.num_points() - first;
    let s = &k.grid()[first..];
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    let mut b = Vec::new();
    let push = |entries: &[(usize, f64)],
                rhs: f64,
                cols: &mut Vec<Vec<(usize, f64)>>,
                b: &mut Vec<f64>| {
        // every row scaled to a largest coefficient of 1 (the same constraint): the actuator
        // rows (ratios to limits) and the contact rows (newtons) differ by orders of magnitude,
        // and unscaled, clarabel's controllable sets were off by 1.5e-6 (relative) with the
        // torque limits of small-sway, 6e-15 scaled
        let r = b.len();
        let sc = entries
            .iter()
            .fold(rhs.abs(), |m, e| m.max(e.1.abs()))
            .max(f64::MIN_POSITIVE);
        for &(j, v) in entries {
            if v != 0.0 {
                cols[j].push((r, v / sc));
            }
        }
        b.push(rhs / sc);
    };
    push(&[(n - 1, 1.0)], 0.0, &mut cols, &mut b);
    if from_rest {
        push(&[(0, 1.0)], 0.0, &mut cols, &mut b);
    }
    let n_eq = b.len();
    for i in 0..n {
        push(&[(i, -1.0)], 0.0, &mut cols, &mut b);
        let [_, hi] = k.x_bounds_at(first + i);
        push(&[(i, 1.0)], hi.min(x_cap), &mut cols, &mut b);
        if i + 1 < n {
            let w = 1.0 / (2.0 * (s[i + 1] - s[i]));
            for r in k.rows_at(first + i) {
                push(
                    &[(i + 1, r.a * w), (i, r.b - r.a * w)],
                    -r.c,
                    &mut cols,
                    &mut b,
                );
            }
            // the next point's rows that also hold at this interval's end (at a stance
            // switch, the stance after it holds with the next interval only)
            for r in k.next_rows_at(first + i + 1) {
                push(
                    &[(i + 1, r.a * w + r.b), (i, -r.a * w)],
                    -r.c,
                    &mut cols,
                    &mut b,
                );
            }
        }
    }
    let m = b.len();
    let mut colptr = vec![0];
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    for c in &cols {
        let mut c = c.clone();
        c.sort_by_key(|e| e.0);
        for (r, v) in c {
            rowval.push(r);
            nzval.push(v);
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(m, n, colptr, rowval, nzval);
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-12)
        .tol_gap_rel(1e-12)
        .tol_feas(1e-12)
        .max_iter(500)
        .build()
        .unwrap();
    let cones = [ZeroConeT(n_eq), NonnegativeConeT(m - n_eq)];
    let mut solver =
        DefaultSolver::new(&CscMatrix::zeros((n, n)), q, &a, &b, &cones, settings).unwrap();
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Some(solver.solution.x.clone()),
        _ => None,
    }
}

fn duration_of(k: &CanonicalConstraints, x: &[f64]) -> f64 {
    let n = x.len();
    Profile::from_states(
        k.grid().to_vec(),
        x.iter().map(|v| v.max(0.0)).collect(),
        vec![0.0; n - 1],
    )
    .unwrap()
    .duration()
}

#[test]
fn small_sway_is_retimed_and_every_sample_has_supporting_forces() {
    let r = run(spec("small-sway"), &RunOptions::default()).unwrap();
    assert_eq!(r.status, MotionStatus::Optimal, "{:?}", r.failure);
    let c = r.checks.as_ref().unwrap();
    eprintln!(
        "small-sway: {:.3} s, {} samples, friction usage {:.3}, drift {:.1e} m, between {:.1e} N",
        r.duration.unwrap(),
        c.samples,
        c.max_friction_usage,
        c.max_contact_drift,
        c.max_between_violation
    );
    assert_eq!(c.samples_without_forces, 0, "{:?}", c.first_without_forces);
    assert!(c.samples > 100);
    assert!(c.max_contact_drift < 1e-4);
    assert_eq!(c.max_joint_violation, 0.0);
    // the rows hold at every IK sample (both limits) after the refinement, to round-off
    assert!(c.max_between_violation < 1e-9 * 43.2 * 9.81);
    // one landing, made at rest
    assert_eq!(r.landings.len(), 1);
    let l = &r.landings[0];
    assert!(l.max_sd.is_none_or(|m| m * l.path_speed <= 1e-3 + 1e-12));
    // segment times tile the motion
    let segs = &r.segments;
    assert_eq!(segs[0].t_start, Some(0.0));
    for w in segs.windows(2) {
        assert_eq!(w[0].t_end, w[1].t_start);
    }
    assert!((segs[2].t_end.unwrap() - r.duration.unwrap()).abs() < 1e-12);
    // the trajectory starts and ends at rest
    let tr = r.trajectory.as_ref().unwrap();
    let vmax = |v: &Vec<f64>| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(vmax(&tr.v[0]) < 1e-12 && vmax(tr.v.last().unwrap()) < 1e-9);
}

/// On a coarse grid (10 intervals per segment) the rows between IK samples decide: the
/// refinement evaluates them inside the steps that come close to a bound, down to 1/32 of a
/// step where a point fails, and every 1 ms sample of the force check then has supporting forces
/// (with the midpoints alone, 8 samples at 0.85 s had none: a row 4.6e-6 of the weight over its
/// bound at 0.88 of an IK step).
#[test]
fn a_coarse_grid_still_passes_the_force_check_at_every_sample() {
    let mut s = spec("small-sway");
    s.retiming.grid = 10;
    let r = run(s, &RunOptions::default()).unwrap();
    assert_eq!(r.status, MotionStatus::Optimal, "{:?}", r.failure);
    let c = r.checks.as_ref().unwrap();
    assert_eq!(c.samples_without_forces, 0, "{:?}", c.first_without_forces);
}

/// Small-sway with the CoM still moving (1 cm further over the left foot) while the right foot
/// lifts: it crosses the first stance switch moving, where chaining gains. (In small-sway
/// itself the CoM arrives at rest on its via-point before the foot lifts, and the whole body is
/// at rest in path terms at every switch: chaining gains 1.5 % there.)
fn sway_through() -> MotionSpec {
    let mut s = spec("small-sway");
    s.segments[1].moves[0].com = Some(stance_motion::spec::ComTarget::By([0.0, 0.01, 0.0]));
    s
}

#[test]
fn chained_is_never_longer_than_rest_to_rest_and_equal_with_zero_boundary_speeds() {
    let chained = run_full(sway_through(), &RunOptions::default()).unwrap();
    let r2r = run_full(rest_to_rest(sway_through()), &RunOptions::default()).unwrap();
    let (dc, dr) = (
        chained.result.duration.unwrap(),
        r2r.result.duration.unwrap(),
    );
    eprintln!("small-sway, CoM through the switch: chained {dc:.4} s, rest to rest {dr:.4} s");
    assert!(dc <= dr * (1.0 + 1e-12));
    assert!(dc < 0.95 * dr, "chaining should gain here (measured 9 %)");
    // rest to rest solved segment by segment equals the whole grid solved as one problem with
    // x = 0 forced at the boundaries (the rest-to-rest layout)
    let k = &r2r.retimed.as_ref().unwrap().constraints;
    let one = solve(k, &SolveOptions::new(Discretization::Interpolation)).unwrap();
    assert_eq!(one.status, Status::Optimal);
    let d_one = one.duration().unwrap();
    assert!(
        (d_one - dr).abs() <= 1e-9 * dr,
        "one problem {d_one} vs per segment {dr}"
    );
    // and every segment's chained re-solve matches the chained profile
    for s in &chained.retimed.as_ref().unwrap().segments {
        assert!(s.resolve_mismatch < 1e-6, "{s:?}");
    }
}

/// The chained retiming against one LP over every grid point of the whole motion: the
/// controllable sets (the largest and smallest `x_i` from which the end can be reached at rest,
/// each an LP over the grid points `i..N`) at every segment boundary and every tenth grid point
/// equal the reachability analysis' to 1e-6; and the whole motion from rest to rest as one LP
/// (maximize the weighted sum of the states) gives a duration within 1 % of the greedy
/// profile's. (The greedy forward pass is time-optimal as the grid is refined, not exactly on
/// the grid when rows couple `u` and `x`: stance-topp's Limitations; measured here, the LP's
/// profile is 0.23 % shorter.)
#[test]
fn chained_retiming_equals_an_independent_one_shot_lp() {
    let run = run_full(spec("small-sway"), &RunOptions::default()).unwrap();
    let rt = run.retimed.as_ref().unwrap();
    let k = &rt.constraints;
    let cap = stance_topp::Tolerances::default().max_x;
    let n = k.num_points();
    let mut points: Vec<usize> = (0..n - 1).step_by(10).collect();
    points.extend(&rt.seg_start[1..rt.seg_start.len() - 1]);
    let mut worst = 0.0f64;
    for &i in &points {
        let mut q = vec![0.0; n - i];
        let [lo, hi] = rt.controllable[i].expect("controllable");
        q[0] = -1.0;
        let x_hi = tail_lp(k, i, false, cap, &q).expect("max x_i solves")[0];
        q[0] = 1.0;
        let x_lo = tail_lp(k, i, false, cap, &q).expect("min x_i solves")[0];
        for (a, b) in [(hi, x_hi), (lo, x_lo)] {
            let d = (a - b).abs() / b.abs().max(1.0);
            worst = worst.max(d);
            assert!(
                d < 1e-6,
                "K_{i}: reachability [{lo}, {hi}], LP [{x_lo}, {x_hi}]"
            );
        }
    }
    let greedy = run.result.duration.unwrap();
    let xg = rt.profile.as_ref().unwrap().x();
    let q: Vec<f64> = xg.iter().map(|v| -1.0 / v.max(1.0)).collect();
    let x = tail_lp(k, 0, true, cap, &q).expect("the LP solves");
    let lp = duration_of(k, &x);
    eprintln!(
        "small-sway: {} controllable sets agree to {worst:.1e}; durations: greedy {greedy:.6} s, \
         one-shot LP {lp:.6} s over {n} grid points",
        points.len()
    );
    assert!(
        (greedy - lp).abs() <= 1e-2 * lp,
        "greedy {greedy} vs LP {lp}"
    );
}

#[test]
fn the_force_check_fails_on_the_motion_played_faster() {
    let fast = run(
        spec("small-sway"),
        &RunOptions {
            time_scale: Some(1.3),
            ..Default::default()
        },
    )
    .unwrap();
    let c = fast.checks.unwrap();
    eprintln!(
        "small-sway x1.3: {} of {} samples without supporting forces",
        c.samples_without_forces, c.samples
    );
    assert!(c.samples_without_forces > 0);
}

fn err(spec_text: &str) -> String {
    let spec: MotionSpec = match toml::from_str(spec_text) {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    match run(spec, &RunOptions::default()) {
        Ok(r) => panic!("expected an error, got {:?}", r.status),
        Err(e) => e.to_string(),
    }
}

const BASE: &str = r#"
robot = "small-humanoid"
[[environment]]
name = "floor"
position = [0.0, 0.0, 0.0]
shape = { rectangle = { half_length = 2.0, half_width = 2.0 } }
friction = 0.9
[initial.standing]
com_height = 0.9
contacts = { LF = { surface = "floor", at = [0.0, 0.1] }, RF = { surface = "floor", at = [0.0, -0.1] } }
"#;

#[test]
fn bad_motion_files_get_errors_that_say_what_to_fix() {
    let seg = "[[segments]]\nstance = { LF = \"floor\", RF = \"floor\" }\nmoves = [{ com = { by = [0.0, 0.05, 0.0] } }]\n";
    let cases: Vec<(String, &str)> = vec![
        (format!("{BASE}{seg}[planning]\nfriction = 1.2\n"), "exceeds the friction"),
        (
            format!("{BASE}{seg}[planning]\nfriction = 0.0\n"),
            "planning.friction is 0; give a friction coefficient > 0",
        ),
        (
            format!("{BASE}{seg}[planning]\nfriction = -0.5\n"),
            "planning.friction is -0.5",
        ),
        (
            format!("{}{seg}", BASE.replace("friction = 0.9", "friction = -0.9")),
            "environment surface \"floor\": friction is -0.9; give Coulomb's coefficient",
        ),
        (format!("{BASE}{seg}[planning]\narea_scale = 0\n"), "planning.area_scale"),
        (format!("{BASE}{seg}[retiming]\ndt = -1\n"), "retiming.dt"),
        (format!("{BASE}{seg}[retiming]\ngrid = 1\n"), "retiming.grid"),
        (format!("{BASE}{seg}[ik]\nsubsteps = 0\n"), "ik.substeps"),
        (format!("{BASE}{seg}[ik]\ngian = 3\n"), "unknown field"),
        (
            format!("gravity = [0.0, 0.0, -1e-5]\n{BASE}{seg}"),
            "whole-body motions support 0.01 to 1000 m/s^2",
        ),
        (
            format!("gravity = [0.0, 0.0, 0.0]\n{BASE}{seg}"),
            "whole-body motions support 0.01 to 1000 m/s^2",
        ),
        (
            format!("{BASE}[[segments]]\nstance = {{ LF = \"roof\" }}\nmoves = [{{}}]\n"),
            "\"roof\", which does not exist",
        ),
        (
            format!("{BASE}[[segments]]\nstance = {{ TAIL = \"floor\" }}\nmoves = [{{}}]\n"),
            "no surface \"TAIL\"",
        ),
        (
            format!(
                "{BASE}[[segments]]\nstance = {{ LF = \"floor\" }}\nmoves = [{{ links = [{{ surface = \"RF\" }}] }}]\n"
            ),
            "exactly one of `by`",
        ),
        (
            format!(
                "{BASE}[[segments]]\nstance = {{ LF = \"floor\" }}\nmoves = [{{ links = [{{ surface = \"LF\", by = [0.0, 0.0, 0.1] }}] }}]\n"
            ),
            "a contact of the segment's stance",
        ),
        (
            format!("{BASE}[[segments]]\nstance = {{ LF = \"floor\" }}\nmoves = [{{ duration = 0.0 }}]\n"),
            "duration",
        ),
        // the right foot is lifted in the first segment and never landed: the second cannot
        // stand on it
        (
            format!(
                "{BASE}[[segments]]\nstance = {{ LF = \"floor\" }}\nmoves = [{{ links = [{{ surface = \"RF\", by = [0.0, 0.0, 0.05] }}] }}]\n[[segments]]\nstance = {{ LF = \"floor\", RF = \"floor\" }}\nmoves = [{{}}]\n"
            ),
            "is not on \"floor\" at the segment's start",
        ),
        (
            format!(
                "{}{seg}",
                BASE.split("[initial.standing]").next().unwrap().to_string()
                    + "[initial]\nconfiguration = [0.0]\n"
            ),
            "initial.configuration",
        ),
        (
            format!(
                "robot = \"small-humanoid\"\nenvironment = []\ninitial = {{ configuration = [0.0] }}\n{seg}"
            ),
            "\"floor\", which does not exist",
        ),
        (
            format!("{BASE}[[segments]]\nstance = {{ LF = \"floor\" }}\nmoves = [{{}}]\n")
                .replace("com_height = 0.9", "com_height = 3.0"),
            "no standing posture",
        ),
    ];
    for (text, want) in cases {
        let e = err(&text);
        assert!(e.contains(want), "expected {want:?} in the error, got: {e}");
    }
    assert!(experiments::by_name("moonwalk")
        .unwrap_err()
        .to_string()
        .contains("stair-climbing"));
}

#[test]
fn jvrc1_stair_climbing_is_retimed_and_checked_and_fails_faster() {
    if !jvrc1_available("jvrc1_stair_climbing_is_retimed_and_checked_and_fails_faster") {
        return;
    }
    let r = run(spec("stair-climbing"), &RunOptions::default()).unwrap();
    assert_eq!(r.status, MotionStatus::Optimal, "{:?}", r.failure);
    let c = r.checks.as_ref().unwrap();
    eprintln!(
        "stair-climbing: {:.3} s, {} samples, friction usage {:.3}, drift {:.1e} m",
        r.duration.unwrap(),
        c.samples,
        c.max_friction_usage,
        c.max_contact_drift
    );
    assert_eq!(c.samples_without_forces, 0, "{:?}", c.first_without_forces);
    assert!(c.max_contact_drift < 1e-3);
    assert_eq!(c.max_joint_violation, 0.0);
    assert_eq!(r.segments.len(), 5);
    let rows: Vec<usize> = r.segments.iter().map(|s| s.u_stance_rows).collect();
    // single support: the 16 rows of one rectangle, exactly
    assert_eq!((rows[1], rows[3]), (16, 16));
    let r2r = run(rest_to_rest(spec("stair-climbing")), &RunOptions::default()).unwrap();
    assert!(r.duration.unwrap() <= r2r.duration.unwrap());
    let fast = run(
        spec("stair-climbing"),
        &RunOptions {
            time_scale: Some(1.3),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(fast.checks.unwrap().samples_without_forces > 0);
}

#[test]
fn jvrc1_box_climbing_third_segment_needs_the_chained_retiming() {
    if !jvrc1_available("jvrc1_box_climbing_third_segment_needs_the_chained_retiming") {
        return;
    }
    let chained = run(spec("box-climbing"), &RunOptions::default()).unwrap();
    assert_eq!(
        chained.status,
        MotionStatus::Optimal,
        "{:?}",
        chained.failure
    );
    let c = chained.checks.as_ref().unwrap();
    assert_eq!(c.samples_without_forces, 0, "{:?}", c.first_without_forces);
    assert_eq!(c.max_joint_violation, 0.0);
    // the third segment is crossed with momentum: its end speed is not zero
    let sd = chained.segments[2].sd_boundaries.unwrap();
    assert!(sd[1] > 0.1, "{sd:?}");
    let r2r = run(rest_to_rest(spec("box-climbing")), &RunOptions::default()).unwrap();
    assert_eq!(r2r.status, MotionStatus::NotRetimable);
    let f = r2r.failure.unwrap();
    eprintln!(
        "box-climbing rest to rest: {} in segment {}: {}",
        f.status, f.segment, f.reason
    );
    assert_eq!(f.segment, 3, "the third segment cannot end at rest");
    let fast = run(
        spec("box-climbing"),
        &RunOptions {
            time_scale: Some(1.3),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(fast.checks.unwrap().samples_without_forces > 0);
}

#[test]
fn a_name_given_twice_in_a_motion_file_is_an_error() {
    use stance_motion::spec::SegmentSpec;
    let e = serde_json::from_str::<SegmentSpec>(
        r#"{"stance": {"LF": "floor", "RF": "floor", "LF": "step"}, "moves": []}"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("\"LF\" is given twice"), "{e}");
    let ok = serde_json::from_str::<SegmentSpec>(
        r#"{"stance": {"LF": "floor", "RF": "floor"}, "moves": []}"#,
    );
    assert!(ok.is_ok(), "{ok:?}");
}

#[test]
fn a_bad_check_friction_names_the_option() {
    for mu in [-1.0, 0.0, f64::NAN] {
        let e = run(
            spec("small-sway"),
            &RunOptions {
                check_friction: Some(mu),
                ..Default::default()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("--check-friction") && e.contains("> 0"), "{e}");
    }
}
