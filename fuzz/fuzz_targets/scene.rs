//! Scene files (JSON text): parse, build the stance, its GIWC and its static-equilibrium
//! polygon. Never a panic; bad input is an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use stance_contact::equilibrium::PolygonWorkspace;
use stance_contact::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scene) = serde_json::from_str::<Scene>(text) else {
        return;
    };
    // Keep each run short: the engine's cost grows with the number of contacts.
    if scene.contacts.len() > 4 {
        return;
    }
    let Ok(stance) = scene.stance() else {
        return;
    };
    let _ = stance.u_stance(&Default::default());
    let _ =
        PolygonWorkspace::new().static_polygon(&stance, scene.gravity, 0.0, &Default::default());
});
