//! Collisions with the environment (module `stance_motion::collision`): the small humanoid steps down
//! from a 10 cm platform. A landing whose path dives through the platform's edge (a hard task the
//! IK cannot bend) is reported as a collision naming the body, the surface, the time and the
//! segment; a free move towards the same edge is routed around it by the IK's clearance rows.
//! The answers do not depend on where the world's origin is. The small humanoid needs no Python.

use stance_motion::collision::{default_thickness, CollisionCheck};
use stance_motion::result::MotionStatus;
use stance_motion::{run_full, spec::MotionSpec, MotionRun, RunOptions};
use stance_robot::{forward_kinematics, frame_placement, Data};

/// The step down with the world's origin at `origin`; `swing` is the right foot's segments
/// (TOML) between "CoM over the left foot" and "CoM between the feet"; `extra` goes into the
/// platform's table.
fn step_down(origin: [f64; 3], swing: &str, extra: &str) -> MotionSpec {
    let [x, y, z] = origin;
    let text = format!(
        r#"
name = "step-down"
robot = "small-humanoid"
[[environment]]
name = "floor"
position = [{x}, {y}, {z}]
shape = {{ rectangle = {{ half_length = 1.0, half_width = 1.0 }} }}
friction = 0.9
[[environment]]
name = "platform"
position = [{px}, {y}, {pz}]
shape = {{ rectangle = {{ half_length = 0.25, half_width = 0.4 }} }}
friction = 0.9
{extra}
[initial.standing]
com_height = {ch}
contacts = {{ LF = {{ surface = "platform", at = [0.1, 0.1] }}, RF = {{ surface = "platform", at = [0.1, -0.1] }} }}
[planning]
friction = 0.7
area_scale = 0.7
[[segments]]
name = "CoM over the left foot"
stance = {{ LF = "platform", RF = "platform" }}
moves = [{{ com = {{ by = [0.0, 0.1, -0.03] }} }}]
{swing}
[[segments]]
name = "CoM between the feet"
stance = {{ LF = "platform", RF = "floor" }}
moves = [{{ com = {{ by = [0.12, -0.1, -0.05] }} }}]
"#,
        px = x - 0.1,
        pz = z + 0.1,
        ch = z + 0.9,
    );
    toml::from_str(&text).unwrap()
}

/// The landing straight from the platform to the floor: its heel cuts the platform's edge.
const DIVE: &str = r#"
[[segments]]
name = "right foot down the edge"
stance = { LF = "platform" }
# a CoM that stays: the straight landing as written, not a planned swing
moves = [{ com = { by = [0.0, 0.0, 0.0] }, links = [{ surface = "RF", onto = "floor", at = [0.32, -0.1] }] }]
"#;

/// The foot lifted, then moved (a free task) towards a point in front of the platform along a
/// line that passes through its edge, then landed.
const ROUTED: &str = r#"
[[segments]]
name = "right foot forward"
stance = { LF = "platform" }
moves = [
  { links = [{ surface = "RF", by = [0.0, 0.0, 0.05] }] },
  { links = [{ surface = "RF", to = [0.32, -0.1, 0.02] }] },
]
[[segments]]
name = "right foot down"
stance = { LF = "platform" }
moves = [{ links = [{ surface = "RF", onto = "floor", at = [0.32, -0.1] }] }]
"#;

fn run(spec: MotionSpec) -> MotionRun {
    let run = run_full(spec, &RunOptions::default()).unwrap();
    assert_eq!(
        run.result.status,
        MotionStatus::Optimal,
        "{:?}",
        run.result.failure
    );
    run
}

#[test]
fn a_landing_through_a_steps_edge_is_reported_as_a_collision() {
    let r = run(step_down([0.0; 3], DIVE, "")).result;
    let c = r.checks.as_ref().unwrap();
    let first = &c.collisions[0];
    eprintln!("{:#?}", c.collisions);
    assert_eq!(
        (first.body.as_str(), first.surface.as_str(), first.segment),
        ("surface:RF", "platform", 2)
    );
    assert_eq!(first.segment_name, "right foot down the edge");
    assert!(first.depth > 0.02 && first.samples > 0);
    assert!(first.t_first <= first.t && first.t <= r.duration.unwrap());
    assert!((c.max_penetration - first.depth).abs() < 1e-12);
    // the IK could not keep its clearances against the landing's hard task, and says so
    assert!(r.segments[1].ik_clearance_dropped > 0);
    assert_eq!(r.segments[0].ik_clearance_dropped, 0);
}

#[test]
fn a_free_move_towards_the_edge_is_routed_around_it() {
    let run = run(step_down([0.0; 3], ROUTED, ""));
    let c = run.result.checks.as_ref().unwrap();
    assert!(c.collisions.is_empty(), "{:#?}", c.collisions);
    assert!(c.max_penetration <= stance_motion::tol::COLLISION_PENETRATION);
    // in "right foot forward" the foot's box stays out of the platform (at every IK sample)
    // while its reference passes through the edge: the foot passes above its reference
    let plan = &run.plan;
    let m = &plan.robot.model;
    let mut data = Data::new(m);
    let rf = plan.collision.body("surface:RF").unwrap();
    let platform = plan
        .environment
        .iter()
        .position(|e| e.name == "platform")
        .unwrap();
    let path = &run.paths[1];
    let link = &path.references.links[0];
    let (mut lowest, mut above) = (f64::INFINITY, 0.0f64);
    for smp in &path.samples {
        forward_kinematics(m, &mut data, &smp.q).unwrap();
        if let Some(d) = plan.collision.distance(&data, rf, platform, 0.2) {
            lowest = lowest.min(d.distance);
        }
        let x = frame_placement(m, &data, link.frame).unwrap().translation;
        let mut soft = Vec::new();
        let mut hard = Vec::new();
        path.references.links_at(smp.s, &mut soft, &mut hard);
        above = above.max(x.z - soft[0].reference.p.z);
    }
    eprintln!("RF box to the platform: lowest {lowest:.4} m; foot above its reference by up to {above:.4} m");
    assert!(lowest >= -stance_motion::tol::COLLISION_PENETRATION);
    assert!(above > 5e-3, "the clearance rows had nothing to do");
    // the free move ends short of its via-point, still moving: the landing that follows starts
    // at the foot's rate and still lands on its target (0.6 mm inside the floor when it
    // started from rest)
    let moves = &run.result.segments[1].moves;
    assert!(moves[1].links[0].position_error > 0.01);
    let landing = &run.result.segments[2].moves[0].links[0];
    assert!(landing.position_error < 1e-4, "{landing:?}");
}

fn collisions(run: &MotionRun) -> CollisionCheck {
    let c = run.result.checks.as_ref().unwrap();
    CollisionCheck {
        clearances: c.clearances.clone(),
        collisions: c.collisions.clone(),
        max_penetration: c.max_penetration,
        touches: c.unplanned_touches.clone(),
    }
}

#[test]
fn moving_the_world_origin_does_not_change_the_collisions() {
    let a = collisions(&run(step_down([0.0; 3], DIVE, "")));
    let b = collisions(&run(step_down([1.5, -2.0, 0.7], DIVE, "")));
    assert_eq!(a.collisions.len(), b.collisions.len());
    for (x, y) in a.collisions.iter().zip(&b.collisions) {
        assert_eq!(
            (&x.body, &x.surface, x.segment),
            (&y.body, &y.surface, y.segment)
        );
        assert!((x.depth - y.depth).abs() < 1e-6, "{} {}", x.depth, y.depth);
        assert!((x.t - y.t).abs() < 1e-9);
    }
    assert!((a.max_penetration - b.max_penetration).abs() < 1e-6);
}

#[test]
fn solids_are_as_thick_as_the_file_says_or_reach_the_floor() {
    let spec = step_down([0.0; 3], DIVE, "");
    let plan = stance_motion::plan::MotionPlan::new(spec, None).unwrap();
    let t: Vec<f64> = plan.environment.iter().map(|e| e.thickness).collect();
    assert_eq!(t[0], stance_motion::collision::MIN_SOLID_THICKNESS);
    assert!(
        (t[1] - 0.1).abs() < 1e-12,
        "the platform reaches the floor: {t:?}"
    );
    assert_eq!(t, default_thickness(&plan.environment));
    // (the simulator's boxes are the same solids: crates/stance-sim/tests/model.rs)
    // the file's own thickness, and a bad one named by its key
    let spec = step_down([0.0; 3], DIVE, "thickness = 0.3");
    let plan = stance_motion::plan::MotionPlan::new(spec, None).unwrap();
    assert_eq!(plan.environment[1].thickness, 0.3);
    for bad in [
        "thickness = -0.1",
        "thickness = 0.0",
        "thickness = 1e9",
        "thickness = nan",
    ] {
        let err = stance_motion::plan::MotionPlan::new(step_down([0.0; 3], DIVE, bad), None)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("environment surface \"platform\"") && err.contains("thickness"),
            "{bad}: {err}"
        );
    }
}

#[test]
fn a_bad_clearance_names_its_key() {
    for bad in ["-0.01", "1.0", "inf"] {
        let mut spec = step_down([0.0; 3], ROUTED, "");
        spec.ik.clearance = bad.parse().unwrap();
        let err = stance_motion::plan::MotionPlan::new(spec, None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("ik.clearance"), "{bad}: {err}");
    }
}

/// The signed distances (parry3d's GJK) against an independent computation: where the right
/// foot's box is apart from the platform during the dive, the distance from the platform's box
/// (axis-aligned: a point's distance in closed form) to points sampled every 1 mm over the
/// foot box's faces is at least parry's distance (within 0.1 um) and exceeds it by less than the sampling's
/// reach (half a diagonal of a 1 mm cell).
#[test]
fn distances_agree_with_sampled_faces() {
    use nalgebra::Vector3;
    use stance_motion::collision::{surface_box_half_sizes, SURFACE_THICKNESS};
    let run = run(step_down([0.0; 3], DIVE, ""));
    let plan = &run.plan;
    let m = &plan.robot.model;
    let mut data = Data::new(m);
    let rf = plan.collision.body("surface:RF").unwrap();
    let surface = plan.robot.surfaces.iter().find(|s| s.name == "RF").unwrap();
    let [hl, hw] = surface_box_half_sizes(&surface.shape, "RF").unwrap();
    let k = plan
        .environment
        .iter()
        .position(|e| e.name == "platform")
        .unwrap();
    let e = &plan.environment[k];
    let stance_contact::Shape::Rectangle {
        half_length,
        half_width,
    } = e.shape
    else {
        panic!("a rectangle")
    };
    let lo = e.pose.translation - Vector3::new(half_length, half_width, e.thickness);
    let hi = e.pose.translation + Vector3::new(half_length, half_width, 0.0);
    let to_box = |p: Vector3<f64>| {
        let d = Vector3::new(
            (lo.x - p.x).max(p.x - hi.x).max(0.0),
            (lo.y - p.y).max(p.y - hi.y).max(0.0),
            (lo.z - p.z).max(p.z - hi.z).max(0.0),
        );
        d.norm()
    };
    let h = 1e-3;
    let half = [hl, hw, 0.5 * SURFACE_THICKNESS];
    let mut compared = 0;
    for smp in run.paths[1].samples.iter().step_by(8) {
        forward_kinematics(m, &mut data, &smp.q).unwrap();
        let Some(d) = plan.collision.distance(&data, rf, k, 0.2) else {
            continue;
        };
        if d.distance <= 1e-3 {
            continue;
        }
        let x = frame_placement(m, &data, surface.frame).unwrap();
        let mut sampled = f64::INFINITY;
        // every face of the box: axis `a` fixed at +-half, the two others on a grid
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let (nb, nc) = (
                (2.0 * half[b] / h).ceil() as usize,
                (2.0 * half[c] / h).ceil() as usize,
            );
            for sign in [-1.0, 1.0] {
                for i in 0..=nb {
                    for j in 0..=nc {
                        let mut local = [0.0; 3];
                        local[a] = sign * half[a];
                        local[b] = -half[b] + 2.0 * half[b] * i as f64 / nb as f64;
                        local[c] = -half[c] + 2.0 * half[c] * j as f64 / nc as f64;
                        let p = x.transform_point(&Vector3::new(
                            local[0],
                            local[1],
                            local[2] + 0.5 * SURFACE_THICKNESS,
                        ));
                        sampled = sampled.min(to_box(p));
                    }
                }
            }
        }
        // GJK stops within its convergence tolerance (nanometres here)
        assert!(sampled >= d.distance - 1e-7, "{sampled} < {}", d.distance);
        assert!(sampled - d.distance <= h, "{sampled} vs {}", d.distance);
        compared += 1;
    }
    assert!(compared >= 5, "only {compared} samples compared");
}

/// The small humanoid standing on a floor: a motion file without its segments.
const CROUCH: &str = r#"
name = "crouch"
robot = "small-humanoid"
[[environment]]
name = "floor"
position = [0.0, 0.0, 0.0]
shape = { rectangle = { half_length = 1.0, half_width = 1.0 } }
friction = 0.9
[initial.standing]
com_height = 0.9
contacts = { LF = { surface = "floor", at = [0.0, 0.1] }, RF = { surface = "floor", at = [0.0, -0.1] } }
"#;

/// A foot on the floor that the plan does not hold there is an unplanned touch for as long as it
/// stays: the check is given a standing motion's samples with the right foot taken out of the
/// stance (the IK itself lifts a free foot off its surface to its clearance, and holds a
/// landing foot's path, which can dwell on the floor). The routed step down's lift-off and
/// landing touch only briefly and are not reported.
#[test]
fn a_foot_on_the_floor_but_not_in_the_stance_is_an_unplanned_touch() {
    let text = format!(
        "{CROUCH}{}",
        r#"
[[segments]]
name = "crouch"
stance = { LF = "floor", RF = "floor" }
moves = [{ com = { by = [0.0, 0.0, -0.03] } }]
"#
    );
    let run = run(toml::from_str(&text).unwrap());
    assert!(run
        .result
        .checks
        .as_ref()
        .unwrap()
        .unplanned_touches
        .is_empty());
    let plan = &run.plan;
    let rf = plan
        .robot
        .surfaces
        .iter()
        .position(|x| x.name == "RF")
        .unwrap();
    let mut paths = run.paths.clone();
    paths[0].contacts.retain(|c| c.surface != rf);
    let c = stance_motion::collision::check_collisions(plan, &plan.collision, &paths, &run.samples)
        .unwrap();
    let touch = &c.touches[0];
    eprintln!("{touch:?}");
    assert_eq!(
        (touch.body.as_str(), touch.surface.as_str(), touch.segment),
        ("surface:RF", "floor", 1)
    );
    let duration = run.result.duration.unwrap();
    assert!(
        (touch.duration - duration).abs() < 1e-9,
        "{} of {duration}",
        touch.duration
    );
    let routed = run_full(step_down([0.0; 3], ROUTED, ""), &RunOptions::default()).unwrap();
    assert!(routed.result.checks.unwrap().unplanned_touches.is_empty());
}

/// A touch that lasts until the body is held on that surface is its landing, reached early (a
/// landing arrives at rest, so its last micrometre can take tens of milliseconds), and is not
/// reported; the same foot on the floor after it is held is an unplanned touch.
#[test]
fn a_touch_that_ends_in_a_landing_is_not_unplanned() {
    let text = format!(
        "{CROUCH}{}",
        r#"
[[segments]]
name = "down"
stance = { LF = "floor", RF = "floor" }
moves = [{ com = { by = [0.0, 0.0, -0.03] } }]
[[segments]]
name = "up"
stance = { LF = "floor", RF = "floor" }
moves = [{ com = { by = [0.0, 0.0, 0.03] } }]
"#
    );
    let run = run(toml::from_str(&text).unwrap());
    let plan = &run.plan;
    let rf = plan
        .robot
        .surfaces
        .iter()
        .position(|x| x.name == "RF")
        .unwrap();
    let check = |free: usize| {
        let mut paths = run.paths.clone();
        paths[free].contacts.retain(|c| c.surface != rf);
        stance_motion::collision::check_collisions(plan, &plan.collision, &paths, &run.samples)
            .unwrap()
            .touches
    };
    // on the floor, then held there: a landing
    assert!(check(0).is_empty(), "{:?}", check(0));
    // held, then on the floor though free: unplanned
    let late = check(1);
    assert_eq!(late.len(), 1, "{late:?}");
    assert_eq!(
        (
            late[0].body.as_str(),
            late[0].surface.as_str(),
            late[0].segment
        ),
        ("surface:RF", "floor", 2)
    );
}
