//! Motion files (JSON text): parse and validate (the plan stage: robot, surfaces, segments,
//! contacts on their surfaces), and, for a file with segments left to the footholds planner,
//! its geometry (static-equilibrium regions, switch points, swing paths) with the margin
//! fraction fixed, so that no pipeline runs. Never a panic; bad input is an error. (Running the
//! whole pipeline, about 0.1 s per motion, is left to the tests.)
#![no_main]

use libfuzzer_sys::fuzz_target;
use stance::motion::footholds;
use stance::motion::plan::MotionPlan;
use stance::motion::spec::MotionSpec;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(mut spec) = serde_json::from_str::<MotionSpec>(text) else {
        return;
    };
    if footholds::needs_planning(&spec) {
        spec.planning.switch_margin = Some(spec.planning.switch_margin.unwrap_or(0.5));
        let _ = footholds::plan(&spec, &Default::default());
    } else {
        let _ = MotionPlan::new(spec, None);
    }
});
