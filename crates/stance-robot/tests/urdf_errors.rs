//! Bad input gives a clear `RobotError`, never a panic: malformed URDFs, non-trees, unsupported
//! or unknown joint types, non-physical or missing inertias, bad locks, bad vectors.

use stance_robot::*;

const INERTIAL: &str = r#"<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>"#;

fn link(name: &str) -> String {
    format!(r#"<link name="{name}">{INERTIAL}</link>"#)
}

fn joint(name: &str, kind: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
    )
}

fn robot(body: &str) -> String {
    format!(r#"<?xml version="1.0"?><robot name="r">{body}</robot>"#)
}

fn build(text: &str) -> Result<Model, RobotError> {
    Model::from_urdf_str(text, &UrdfOptions::default())
}

fn err(text: &str) -> RobotError {
    build(text).expect_err("should be rejected")
}

#[test]
fn malformed_xml_and_missing_elements() {
    assert!(matches!(
        err("<robot name=\"x\"><link name=\"a\"></robot>"),
        RobotError::Urdf(_)
    ));
    assert!(matches!(err("not xml at all"), RobotError::Urdf(_)));
    // a joint without a child
    let text = robot(&format!(
        r#"{}{}<joint name="j" type="revolute"><parent link="a"/></joint>"#,
        link("a"),
        link("b")
    ));
    assert!(matches!(err(&text), RobotError::Urdf(_)));
    assert!(matches!(
        err(&robot("")),
        RobotError::NotATree(_) | RobotError::Urdf(_)
    ));
}

#[test]
fn unknown_and_unsupported_joint_types() {
    let text = robot(&format!(
        "{}{}{}",
        link("a"),
        link("b"),
        joint("j", "hinge", "a", "b")
    ));
    let e = err(&text);
    assert!(matches!(e, RobotError::Urdf(_)), "{e}");
    assert!(e.to_string().contains("hinge"), "{e}");
    for kind in ["floating", "planar", "spherical"] {
        let text = robot(&format!(
            "{}{}{}",
            link("a"),
            link("b"),
            joint("j", kind, "a", "b")
        ));
        let e = err(&text);
        assert!(matches!(e, RobotError::UnsupportedJointType { .. }), "{e}");
        assert!(e.to_string().contains(kind));
    }
}

#[test]
fn trees_only() {
    // duplicate names
    let text = robot(&format!("{}{}", link("a"), link("a")));
    assert!(matches!(
        err(&text),
        RobotError::DuplicateName { kind: "link", .. }
    ));
    let text = robot(&format!(
        "{}{}{}{}{}",
        link("a"),
        link("b"),
        link("c"),
        joint("j", "revolute", "a", "b"),
        joint("j", "revolute", "a", "c")
    ));
    assert!(matches!(
        err(&text),
        RobotError::DuplicateName { kind: "joint", .. }
    ));
    // unknown link
    let text = robot(&format!(
        "{}{}",
        link("a"),
        joint("j", "revolute", "a", "zz")
    ));
    assert!(matches!(err(&text), RobotError::UnknownLink { .. }));
    // two parents
    let text = robot(&format!(
        "{}{}{}{}{}",
        link("a"),
        link("b"),
        link("c"),
        joint("j1", "revolute", "a", "c"),
        joint("j2", "revolute", "b", "c")
    ));
    assert!(matches!(err(&text), RobotError::MultipleParents { .. }));
    // a cycle through every link: no root
    let text = robot(&format!(
        "{}{}{}{}",
        link("a"),
        link("b"),
        joint("j1", "revolute", "a", "b"),
        joint("j2", "revolute", "b", "a")
    ));
    let e = err(&text);
    assert!(matches!(e, RobotError::NotATree(_)), "{e}");
    assert!(e.to_string().contains("cycle"));
    // a cycle beside a tree: the cycle is unreachable
    let text = robot(&format!(
        "{}{}{}{}{}",
        link("root"),
        link("b"),
        link("c"),
        joint("j1", "revolute", "b", "c"),
        joint("j2", "revolute", "c", "b")
    ));
    assert!(matches!(err(&text), RobotError::NotATree(_)));
    // two roots
    let text = robot(&format!("{}{}", link("a"), link("b")));
    assert!(matches!(err(&text), RobotError::NotATree(_)));
}

#[test]
fn inertias_must_be_physical_and_present() {
    let bad_mass = r#"<link name="a"><inertial><mass value="-1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>"#;
    assert!(matches!(
        err(&robot(bad_mass)),
        RobotError::InvalidInertia { .. }
    ));
    let not_psd = r#"<link name="a"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0.5" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>"#;
    assert!(matches!(
        err(&robot(not_psd)),
        RobotError::InvalidInertia { .. }
    ));
    let triangle = r#"<link name="a"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.5"/></inertial></link>"#;
    assert!(matches!(
        err(&robot(triangle)),
        RobotError::InvalidInertia { .. }
    ));
    let nan = r#"<link name="a"><inertial><mass value="NaN"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>"#;
    assert!(build(&robot(nan)).is_err());
    // no <inertial> anywhere: no CoM
    let text = robot(
        r#"<link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>"#,
    );
    let e = err(&text);
    assert!(matches!(e, RobotError::MissingInertia { .. }), "{e}");
}

#[test]
fn zero_axis_is_rejected() {
    let text = robot(&format!(
        r#"{}{}<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#,
        link("a"),
        link("b")
    ));
    assert!(matches!(err(&text), RobotError::ZeroAxis { .. }));
}

#[test]
fn locks_must_name_movable_joints() {
    let lock = |name: &str| UrdfOptions {
        locked: vec![(name.into(), 0.0)],
        ..Default::default()
    };
    let e = Model::from_urdf_str(SMALL_HUMANOID_URDF, &lock("nope")).unwrap_err();
    assert!(matches!(e, RobotError::CannotLock { .. }));
    let e = Model::from_urdf_str(SMALL_HUMANOID_URDF, &lock("r_sole_fixed")).unwrap_err();
    assert!(e.to_string().contains("fixed"));
    let nan = UrdfOptions {
        locked: vec![("neck".into(), f64::NAN)],
        ..Default::default()
    };
    assert!(Model::from_urdf_str(SMALL_HUMANOID_URDF, &nan).is_err());
}

#[test]
fn bad_vectors_and_frames() {
    let m = build(SMALL_HUMANOID_URDF).unwrap();
    let mut d = Data::new(&m);
    let q = m.neutral();
    assert!(matches!(
        forward_kinematics(&m, &mut d, &q[..5]),
        Err(RobotError::Dimension {
            expected: 29,
            got: 5,
            ..
        })
    ));
    let mut q_nan = q.clone();
    q_nan[9] = f64::NAN;
    assert!(matches!(
        forward_kinematics(&m, &mut d, &q_nan),
        Err(RobotError::NonFinite { index: 9, .. })
    ));
    let mut q_quat = q.clone();
    q_quat[3] = 0.5; // |quat| = sqrt(1.25)
    assert!(matches!(
        centroidal_map(&m, &mut d, &q_quat),
        Err(RobotError::NotUnit { index: 3, .. })
    ));
    let neck = m.joints[m.joint_id("neck").unwrap()].idx_q;
    let mut q_neck = q.clone();
    q_neck[neck] = 0.0; // (cos, sin) = (0, 0)
    assert!(matches!(
        centroidal_map(&m, &mut d, &q_neck),
        Err(RobotError::NotUnit { .. })
    ));
    // slightly off-unit quaternions (printed with few digits) are accepted and normalized
    let mut q_close = q.clone();
    q_close[6] = 1.0 + 1e-8;
    assert!(centroidal_map(&m, &mut d, &q_close).is_ok());
    assert!(centroidal_map_dot_v(&m, &mut d, &q, &[0.0; 3]).is_err());
    assert!(matches!(
        m.frame_id("nope"),
        Err(RobotError::UnknownFrame(_))
    ));
    let mut jac = nalgebra::Matrix6xX::zeros(m.nv);
    assert!(frame_jacobian(&m, &d, 10_000, ReferenceFrame::World, &mut jac).is_err());
    // accelerations need velocities
    let mut fresh = Data::new(&m);
    forward_kinematics(&m, &mut fresh, &q).unwrap();
    assert!(matches!(
        frame_classical_acceleration(&m, &fresh, 1, ReferenceFrame::Local),
        Err(RobotError::NoVelocity)
    ));
}

/// A very deep chain must not overflow the stack (the tree is walked without recursion).
#[test]
fn regression_deep_chain_does_not_overflow_the_stack() {
    let n = 20_000;
    let mut body = String::new();
    for i in 0..n {
        body += &link(&format!("l{i}"));
        if i > 0 {
            body += &joint(
                &format!("j{i}"),
                "revolute",
                &format!("l{}", i - 1),
                &format!("l{i}"),
            );
        }
    }
    let m = build(&robot(&body)).unwrap();
    assert_eq!(m.nv, 6 + n - 1);
}

#[test]
fn fixed_root_matches_the_free_flyer_at_identity() {
    let ff = build(SMALL_HUMANOID_URDF).unwrap();
    let fixed = Model::from_urdf_str(
        SMALL_HUMANOID_URDF,
        &UrdfOptions {
            root: RootJoint::Fixed,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(fixed.nv, ff.nv - 6);
    let (mut d1, mut d2) = (Data::new(&ff), Data::new(&fixed));
    let q1 = ff.neutral();
    let q2 = fixed.neutral();
    forward_kinematics(&ff, &mut d1, &q1).unwrap();
    forward_kinematics(&fixed, &mut d2, &q2).unwrap();
    for name in ["r_sole", "l_hand", "imu"] {
        let a = frame_placement(&ff, &d1, ff.frame_id(name).unwrap()).unwrap();
        let b = frame_placement(&fixed, &d2, fixed.frame_id(name).unwrap()).unwrap();
        assert!((a.translation - b.translation).norm() < 1e-15);
        assert!((a.rotation - b.rotation).norm() < 1e-15);
    }
    // the fixed root link's mass is not part of the moving robot
    assert!((ff.total_mass() - fixed.total_mass() - 8.0).abs() < 1e-12);
}

#[test]
fn small_humanoid_mass_is_the_sum_of_the_urdf_masses() {
    // 8 (pelvis) + 2 x (1 + 0.5 + 3 + 2 + 0.3 + 0.8 + 0.4) (legs) + 6 + 5 + 2 (torso, chest, head)
    // + 2 x (1.5 + 0.2 + 1 + 0.4) (arms)
    let m = build(SMALL_HUMANOID_URDF).unwrap();
    let expected = 8.0 + 2.0 * 8.0 + 13.0 + 2.0 * 3.1;
    assert!((m.total_mass() - expected).abs() < 1e-12);
}

#[test]
fn limits_reversed_are_rejected_and_missing_limits_mean_none() {
    let text = robot(&format!(
        r#"{}{}<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="1" upper="-1" effort="1" velocity="1"/></joint>"#,
        link("a"),
        link("b")
    ));
    assert!(matches!(err(&text), RobotError::InvalidLimits { .. }));
    let text = robot(&format!(
        r#"{}{}<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>"#,
        link("a"),
        link("b")
    ));
    let m = build(&text).unwrap();
    let j = &m.joints[m.joint_id("j").unwrap()];
    assert_eq!((j.lower, j.upper), (f64::NEG_INFINITY, f64::INFINITY));
}

#[test]
fn a_workspace_of_another_model_is_an_error_not_a_panic() {
    let m = build(SMALL_HUMANOID_URDF).unwrap();
    let m2 = Model::from_urdf_str(
        SMALL_HUMANOID_URDF,
        &UrdfOptions {
            locked: vec![("r_knee".into(), 0.3)],
            ..Default::default()
        },
    )
    .unwrap();
    let mut wrong = Data::new(&m2);
    let q = m.neutral();
    assert!(forward_kinematics(&m, &mut wrong, &q).is_err());
    assert!(centroidal_map(&m, &mut wrong, &q).is_err());
    assert!(centroidal_map_dot_v(&m, &mut wrong, &q, &vec![0.0; m.nv]).is_err());
    assert!(frame_placement(&m, &wrong, 1).is_err());
    let mut jac = nalgebra::Matrix6xX::zeros(m.nv);
    assert!(frame_jacobian(&m, &wrong, 1, ReferenceFrame::World, &mut jac).is_err());
}

/// 20,000 nested elements overflowed the stack of the XML parsers (a crash): now an error that
/// names the depth and the line, before any parser runs. Comments, CDATA, declarations,
/// self-closing tags and `>` inside attribute values do not count as levels.
#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let deep = format!(
        r#"<?xml version="1.0"?><robot name="r">{}{}{}</robot>"#,
        link("a"),
        "<x>\n".repeat(20_000),
        "</x>".repeat(20_000)
    );
    let RobotError::Urdf(msg) = err(&deep) else {
        panic!("not a URDF error")
    };
    assert!(msg.contains("nested 65 deep at line 64"), "{msg}");
    // Shallow files with the constructs that do not nest still load.
    let fine = robot(&format!(
        r#"<!-- <a><b><c> -->{}<![CDATA[<d><e>]]><?pi <f>?>"#,
        link(r#"a" note="x > y"#)
    ));
    build(&fine).unwrap();
}

/// URDF readers ignore unknown elements, so a misspelled `<origin>` or `<inertial>` silently
/// changed the model: now an error naming the line and the element meant. Extensions
/// (`<gazebo>` content, namespaced or unrelated names) still pass.
#[test]
fn misspelled_elements_are_errors() {
    let text = robot(
        r#"<link name="a"><inertial><orgin xyz="0 0 1"/><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>"#,
    );
    let RobotError::Urdf(msg) = err(&text) else {
        panic!("not a URDF error")
    };
    assert!(msg.contains("<orgin>") && msg.contains("<origin>"), "{msg}");
    let text = robot(r#"<link name="a"><inertail><mass value="1"/></inertail></link>"#);
    let RobotError::Urdf(msg) = err(&text) else {
        panic!("not a URDF error")
    };
    assert!(
        msg.contains("<inertail>") && msg.contains("did you mean"),
        "{msg}"
    );
    let fine = robot(&format!(
        r#"{}<gazebo reference="a"><mu1>0.9</mu1><materal>x</materal></gazebo><extra_thing/>"#,
        link("a")
    ));
    build(&fine).unwrap();
}

#[test]
fn unknown_elements_are_listed_once_with_their_line() {
    let text = format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n{}\n<extra_thing/>\n<ros2_control name=\"x\">\
         <hardware><plugin>p</plugin></hardware></ros2_control>\n<extra_thing/>\n\
         <gazebo reference=\"a\"><mu1>0.9</mu1></gazebo>\n<xacro:property name=\"k\"/>\n</robot>",
        link("a")
    );
    let m = build(&text).unwrap();
    // The extension's content is its own; gazebo and namespaced elements are known.
    assert_eq!(
        m.unknown_elements,
        vec![
            ("extra_thing".to_string(), 4),
            ("ros2_control".to_string(), 5)
        ]
    );
    let plain = build(&robot(&link("a"))).unwrap();
    assert!(plain.unknown_elements.is_empty());
}

#[test]
fn a_joint_locked_twice_is_an_error() {
    let text = robot(&format!(
        "{}{}{}",
        link("a"),
        link("b"),
        joint("j", "revolute", "a", "b")
    ));
    let options = UrdfOptions {
        locked: vec![("j".into(), 0.1), ("j".into(), 0.2)],
        ..Default::default()
    };
    let e = Model::from_urdf_str(&text, &options)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("locked twice") && e.contains("0.1") && e.contains("0.2"),
        "{e}"
    );
}

#[test]
fn centroidal_quantities_reject_bad_configurations_far_from_the_origin_too() {
    let m = Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap();
    let mut d = Data::new(&m);
    let v = vec![0.0; m.nv];
    let mut q = m.neutral();
    q[0] = 1e6;
    assert!(centroidal_map_dot_v(&m, &mut d, &q[..3], &v).is_err());
    q[1] = f64::NAN;
    assert!(centroidal_map_dot_v(&m, &mut d, &q, &v).is_err());
    assert!(centroidal_map(&m, &mut d, &q).is_err());
}

#[test]
fn a_fixed_base_with_every_joint_locked_says_nothing_moves() {
    let text = robot(
        r#"<link name="a"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
           <link name="b"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
           <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
             <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#,
    );
    let options = UrdfOptions {
        root: stance_robot::RootJoint::Fixed,
        locked: vec![("j".into(), 0.0)],
        ..Default::default()
    };
    let e = Model::from_urdf_str(&text, &options).unwrap_err();
    assert!(matches!(e, RobotError::NothingMoves), "{e}");
    assert!(e.to_string().contains("locked"));
    // unlocked, it moves
    let options = UrdfOptions {
        root: stance_robot::RootJoint::Fixed,
        ..Default::default()
    };
    assert_eq!(Model::from_urdf_str(&text, &options).unwrap().nv, 1);
}
