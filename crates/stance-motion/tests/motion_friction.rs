//! Friction in motion files means Coulomb's `mu`: by default every contact's GIWC uses the
//! 8-sided pyramid inscribed in the circular cone of the surface's `friction`, so that no plan
//! needs more friction than the file gives (`checks.max_friction_usage`, measured against the
//! circle, stays at most 1); the paper's outer 4-sided pyramid stays available
//! (`[planning] friction_cone = { sides = 4, approximation = "outer" }`) and accepts what only
//! its corners can hold. The small humanoid needs no Python.

use stance_contact::Approximation;
use stance_motion::result::{MotionResult, MotionStatus};
use stance_motion::{experiments, run, spec::MotionSpec, RunOptions};

/// The small humanoid standing on a slope of friction `mu` that rises along the surface's y axis
/// by `atan(slope)`, its feet turned by 45 degrees: gravity pulls along the feet's diagonal, where
/// the paper's 4-sided outer pyramid reaches `mu sqrt 2` and Coulomb's cone `mu`. It crouches by
/// 2 cm. `planning` is the `[planning]` table's body.
fn diagonal_slope(mu: f64, slope: f64, planning: &str) -> MotionSpec {
    let text = format!(
        r#"
name = "diagonal-slope"
robot = "small-humanoid"
[[environment]]
name = "slope"
position = [0.0, 0.0, 0.0]
rpy = [{angle}, 0.0, 0.0]
shape = {{ rectangle = {{ half_length = 2.0, half_width = 2.0 }} }}
friction = {mu}
[initial.standing]
com_height = 0.9
contacts = {{ LF = {{ surface = "slope", at = [0.0, 0.1], yaw = 0.7853981633974483 }}, RF = {{ surface = "slope", at = [0.0, -0.1], yaw = 0.7853981633974483 }} }}
[planning]
{planning}
[[segments]]
name = "crouch"
stance = {{ LF = "slope", RF = "slope" }}
moves = [{{ com = {{ by = [0.0, 0.0, -0.02] }} }}]
"#,
        angle = slope.atan()
    );
    toml::from_str(&text).unwrap()
}

fn usage(r: &MotionResult) -> f64 {
    assert_eq!(r.status, MotionStatus::Optimal, "{:?}", r.failure);
    let c = r.checks.as_ref().unwrap();
    assert_eq!(c.samples_without_forces, 0, "{:?}", c.first_without_forces);
    c.max_friction_usage
}

#[test]
fn the_default_cone_is_inside_coulombs_and_the_outer_one_is_the_papers() {
    let s = diagonal_slope(0.2, 0.1, "");
    assert_eq!(s.planning.friction_cone.sides, 8);
    assert_eq!(s.planning.friction_cone.approximation, Approximation::Inner);
    // the paper's experiments state the paper's pyramid
    for name in ["stair-climbing", "box-climbing"] {
        let c = experiments::by_name(name).unwrap().planning.friction_cone;
        assert_eq!(
            (c.sides, c.approximation),
            (4, Approximation::Outer),
            "{name}"
        );
    }
    // the scene files' key is accepted
    let old = diagonal_slope(
        0.2,
        0.1,
        r#"friction_model = { sides = 6, approximation = "inner" }"#,
    );
    assert_eq!(old.planning.friction_cone.sides, 6);
}

#[test]
fn a_stance_that_needs_the_outer_pyramids_corners_is_refused_by_default() {
    // tan = 0.24 along the feet's diagonal: within the outer pyramid's 0.2 sqrt 2 = 0.283, beyond
    // Coulomb's 0.2 and the inner octagon's 0.2 cos(pi / 8) = 0.185 at 45 degrees
    let outer = r#"friction_cone = { sides = 4, approximation = "outer" }"#;
    let r = run(diagonal_slope(0.2, 0.24, ""), &RunOptions::default()).unwrap();
    assert_eq!(r.status, MotionStatus::NotRetimable);
    let f = r.failure.as_ref().unwrap();
    assert!(f.reason.contains("contact stability"), "{}", f.reason);
    let accepted = run(diagonal_slope(0.2, 0.24, outer), &RunOptions::default()).unwrap();
    let u = usage(&accepted);
    // what it accepted needs more than Coulomb's friction: the force check reports it
    assert!(u > 1.0 + 1e-3, "usage {u}");
    // a gentler slope (tan 0.15 < 0.185) is planned under the default within Coulomb's cone
    let gentle = run(diagonal_slope(0.2, 0.15, ""), &RunOptions::default()).unwrap();
    let u = usage(&gentle);
    assert!(u <= 1.0 + 1e-6, "usage {u}");
}

#[test]
fn a_stance_at_friction_0_3_plans_within_coulombs_cone() {
    // small-sway on a floor of friction 0.3, planned with the surface's own friction
    let mut s = experiments::by_name("small-sway").unwrap();
    s.environment[0].friction = 0.3;
    s.planning.friction = None;
    let r = run(s.clone(), &RunOptions::default()).unwrap();
    let u = usage(&r);
    assert!(u <= 1.0 + 1e-6, "usage {u}");
    // the same motion under the paper's outer pyramid is never slower (it admits more)
    s.planning.friction_cone = stance_contact::FrictionModel::default();
    let outer = run(s, &RunOptions::default()).unwrap();
    assert!(outer.duration.unwrap() <= r.duration.unwrap() * (1.0 + 1e-9));
}
