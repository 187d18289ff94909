//! The MuJoCo model written from a motion plan (`stance_sim::mjcf`): its solids are the plan's
//! own collision model.

use stance_motion::plan::MotionPlan;
use stance_motion::spec::MotionSpec;

/// A step down from a 10 cm platform onto the floor (as `stance-motion`'s collision tests).
const STEP_DOWN: &str = r#"
name = "step-down"
robot = "small-humanoid"
[[environment]]
name = "floor"
position = [0.0, 0.0, 0.0]
shape = { rectangle = { half_length = 1.0, half_width = 1.0 } }
friction = 0.9
[[environment]]
name = "platform"
position = [-0.1, 0.0, 0.1]
shape = { rectangle = { half_length = 0.25, half_width = 0.4 } }
friction = 0.9
[initial.standing]
com_height = 0.9
contacts = { LF = { surface = "platform", at = [0.1, 0.1] }, RF = { surface = "platform", at = [0.1, -0.1] } }
[planning]
friction = 0.7
area_scale = 0.7
[[segments]]
name = "CoM over the left foot"
stance = { LF = "platform", RF = "platform" }
moves = [{ com = { by = [0.0, 0.1, -0.03] } }]
[[segments]]
name = "right foot down"
stance = { LF = "platform" }
# a CoM that stays: the straight landing as written, not a planned swing
moves = [{ com = { by = [0.0, 0.0, 0.0] }, links = [{ surface = "RF", onto = "floor", at = [0.32, -0.1] }] }]
[[segments]]
name = "CoM between the feet"
stance = { LF = "platform", RF = "floor" }
moves = [{ com = { by = [0.12, -0.1, -0.05] } }]
"#;

#[test]
fn the_simulators_boxes_are_the_plans_solids() {
    let spec: MotionSpec = toml::from_str(STEP_DOWN).unwrap();
    let plan = MotionPlan::new(spec, None).unwrap();
    // The platform reaches the floor: 10 cm thick, its box centred 5 cm below its surface.
    assert!((plan.environment[1].thickness - 0.1).abs() < 1e-12);
    let xml = stance_sim::mjcf::mjcf(&plan, &Default::default()).unwrap();
    assert!(
        xml.contains("size=\"0.25 0.4 0.05\" pos=\"0 0 -0.05\""),
        "{xml}"
    );
}
