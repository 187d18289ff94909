//! URDF text: the model is built or an error says why. Never a panic or a stack overflow.
#![no_main]

use libfuzzer_sys::fuzz_target;
use stance_robot::{Model, UrdfOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = Model::from_urdf_str(text, &UrdfOptions::default());
});
