//! Motion files (JSON text): parse and validate (the plan stage: robot, surfaces, segments,
//! contacts on their surfaces). Never a panic; bad input is an error. (Running the whole
//! pipeline, about 0.1 s per motion, is left to the tests.)
#![no_main]

use libfuzzer_sys::fuzz_target;
use stance::motion::plan::MotionPlan;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(spec) = serde_json::from_str(text) {
        let _ = MotionPlan::new(spec, None);
    }
});
