//! The project's JVRC-1 data (`models/jvrc1.json`) and the Rust module `stance_robot::jvrc1`
//! agree; with the URDF available, the soles are where a standing robot's soles are.

use std::path::{Path, PathBuf};

use serde_json::Value;
use stance_robot::*;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn models_file_matches_the_rust_module() {
    let text = std::fs::read_to_string(root().join("models/jvrc1.json")).unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    let locked = v["locked_joints"].as_object().unwrap();
    assert_eq!(locked.len(), jvrc1::FINGER_JOINTS.len());
    for name in jvrc1::FINGER_JOINTS {
        assert_eq!(locked[name].as_f64(), Some(0.0), "{name}");
    }
    let soles = jvrc1::sole_rectangles();
    for (s, j) in soles.iter().zip(v["soles"].as_array().unwrap()) {
        assert_eq!(j["frame"].as_str(), Some(s.frame));
        let c: Vec<f64> = j["center_in_ankle"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(c, s.center_in_ankle.to_vec());
        assert_eq!(j["length"].as_f64(), Some(2.0 * s.half_length));
        assert_eq!(j["width"].as_f64(), Some(2.0 * s.half_width));
    }
    let hands: Vec<&str> = v["hands"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap())
        .collect();
    assert_eq!(hands, jvrc1::HAND_FRAMES.to_vec());
}

#[test]
fn soles_are_level_and_below_the_ankles_at_the_neutral_configuration() {
    let path = match jvrc1::locate_urdf(Some(&root())) {
        Ok(p) => p,
        Err(why) => {
            eprintln!(
                "SKIPPED soles_are_level_and_below_the_ankles_at_the_neutral_configuration: {why}"
            );
            return;
        }
    };
    let model = Model::from_urdf_file(path, &jvrc1::urdf_options()).unwrap();
    assert_eq!((model.nq, model.nv), (39, 38));
    let mut data = Data::new(&model);
    forward_kinematics(&model, &mut data, &model.neutral()).unwrap();
    let mut heights = Vec::new();
    for sole in jvrc1::sole_rectangles() {
        let ankle = frame_placement(&model, &data, model.frame_id(sole.frame).unwrap()).unwrap();
        let center = ankle.transform_point(&nalgebra::Vector3::from(sole.center_in_ankle));
        assert!(
            center.z < ankle.translation.z - 0.1,
            "sole centre below the ankle"
        );
        heights.push(center.z);
    }
    assert!(
        (heights[0] - heights[1]).abs() < 1e-12,
        "both soles at the same height"
    );
    for hand in jvrc1::HAND_FRAMES {
        assert!(model.frame_id(hand).is_ok());
    }
}
