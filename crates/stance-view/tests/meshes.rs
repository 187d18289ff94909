//! The robot's meshes for the page: the readers against independent counts and each other,
//! the simplification's bounds, the packing's round trip, and the drawn geometry of JVRC-1,
//! Talos and a URDF with a missing mesh.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use stance_view::meshes::{base64, collada, obj, read_mesh, stl, MeshData, TriMesh};
use stance_view::{robot_look, ShapeView, MESH_TRIANGLE_BUDGET};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn jvrc1_urdf() -> PathBuf {
    stance_robot::jvrc1::locate_urdf(Some(&root())).expect("JVRC-1 in the virtualenv")
}

/// A base64 decoder written for the test (the page decodes with the browser's `atob`).
fn unbase64(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let mut out = Vec::new();
    for chunk in s.as_bytes().chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let mut n = 0u32;
        for &c in chunk {
            n = (n << 6) | u32::from(if c == b'=' { 0 } else { value(c) });
        }
        let b = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend(&b[..3 - pad]);
    }
    out
}

#[test]
fn every_jvrc1_collada_mesh_has_the_triangles_its_file_counts() {
    let folder = jvrc1_urdf().parent().unwrap().join("../meshes");
    let mut files = 0;
    for entry in std::fs::read_dir(&folder).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "dae") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        // the counts the file declares, read by plain string search
        let declared: usize = text
            .split("<triangles ")
            .skip(1)
            .map(|rest| {
                let at = rest.find("count=\"").unwrap() + 7;
                rest[at..]
                    .split('"')
                    .next()
                    .unwrap()
                    .parse::<usize>()
                    .unwrap()
            })
            .sum();
        let m = read_mesh(&path).unwrap();
        assert_eq!(m.triangles.len(), declared, "{}", path.display());
        // link-sized, in metres
        assert!(
            m.positions
                .iter()
                .all(|p| p.iter().all(|x| x.is_finite() && x.abs() < 0.5)),
            "{}",
            path.display()
        );
        files += 1;
    }
    assert_eq!(files, 35);
}

#[test]
fn collada_up_axis_units_and_node_transforms() {
    let dae = |up: &str, node: &str| {
        format!(
            r##"<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="0.01"/><up_axis>{up}</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="12">0 0 0 100 0 0 0 100 0 0 0 100</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <polylist count="1"><input semantic="VERTEX" source="#v" offset="0"/>
      <input semantic="NORMAL" source="#v" offset="1"/><vcount>4</vcount><p>0 0 1 0 2 0 3 0</p></polylist>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s">{node}</visual_scene></library_visual_scenes>
</COLLADA>"##
        )
    };
    let plain = "<node><instance_geometry url=\"#g\"/></node>";
    let m = collada::read(&dae("Z_UP", plain)).unwrap();
    // a polygon of 4 corners: a fan of 2 triangles; centimetres to metres
    assert_eq!(m.triangles.len(), 2);
    assert_eq!(m.positions[1], [1.0, 0.0, 0.0]);
    // Y up: the file's y is the world's z
    let y = collada::read(&dae("Y_UP", plain)).unwrap();
    assert_eq!(y.positions[2], [0.0, 0.0, 1.0]);
    assert_eq!(y.positions[3], [0.0, -1.0, 0.0]);
    // nested nodes: rotate 90 degrees about z, then translate (the parent's transform first)
    let nested = "<node><translate>0 0 50</translate><node><rotate>0 0 1 90</rotate>\
                  <instance_geometry url=\"#g\"/></node></node>";
    let n = collada::read(&dae("Z_UP", nested)).unwrap();
    let p = n.positions[1];
    assert!((p[0]).abs() < 1e-6 && (p[1] - 1.0).abs() < 1e-6 && (p[2] - 0.5).abs() < 1e-6);
    // a corner outside its source
    let bad = dae("Z_UP", plain).replace("<p>0 0 1 0 2 0 3 0</p>", "<p>0 0 1 0 2 0 9 0</p>");
    assert!(collada::read(&bad).unwrap_err().contains("vertex 9"));
    assert!(collada::read("<COLLADA")
        .unwrap_err()
        .contains("not a Collada"));
}

/// A closed box of 12 triangles.
fn cube() -> TriMesh {
    let positions = (0..8)
        .map(|k| [(k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32])
        .collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    TriMesh {
        positions,
        triangles,
    }
}

#[test]
fn binary_and_ascii_stl_and_obj_of_one_cube_read_the_same() {
    let m = cube();
    let mut bin = vec![0u8; 80];
    bin.extend((m.triangles.len() as u32).to_le_bytes());
    let mut ascii = String::from("solid cube\n");
    let mut objtext = String::new();
    for p in &m.positions {
        objtext += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in &m.triangles {
        bin.extend([0u8; 12]);
        ascii += "facet normal 0 0 0\nouter loop\n";
        for &i in t {
            for x in m.positions[i as usize] {
                bin.extend(x.to_le_bytes());
            }
            let p = m.positions[i as usize];
            ascii += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        bin.extend([0, 0]);
        ascii += "endloop\nendfacet\n";
        objtext += &format!("f {} {}/1 {}//2\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    ascii += "endsolid cube\n";
    let corners = |m: &TriMesh| -> Vec<[[f32; 3]; 3]> {
        m.triangles
            .iter()
            .map(|t| t.map(|i| m.positions[i as usize]))
            .collect()
    };
    let a = stl::read(&bin).unwrap();
    let b = stl::read(ascii.as_bytes()).unwrap();
    let c = obj::read(&objtext).unwrap();
    // the welded STL has the cube's 8 corners, not 36
    assert_eq!(a.positions.len(), 8);
    assert_eq!(corners(&a), corners(&m));
    assert_eq!(corners(&b), corners(&m));
    assert_eq!(corners(&c), corners(&m));
    assert!(stl::read(b"not a mesh").is_err());
    assert!(obj::read("v 0 0 0\nf 1 2 3\n")
        .unwrap_err()
        .contains("line 2"));
}

#[test]
fn packed_meshes_decode_to_the_positions_and_triangles() {
    for m in [cube(), TriMesh::default()] {
        let d = MeshData::pack("cube", &m, m.triangles.len());
        let pos: Vec<f32> = unbase64(&d.positions)
            .chunks(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let idx: Vec<u32> = unbase64(&d.indices)
            .chunks(2)
            .map(|b| u32::from(u16::from_le_bytes([b[0], b[1]])))
            .collect();
        assert_eq!(d.index_bytes, 2);
        assert_eq!(pos, m.positions.concat());
        assert_eq!(idx, m.triangles.concat());
    }
    // more than 65,535 vertices: 4-byte indices
    let big = TriMesh {
        positions: (0..70_000).map(|k| [k as f32, 0.0, 0.0]).collect(),
        triangles: vec![[0, 1, 69_999]],
    };
    let d = MeshData::pack("big", &big, 1);
    assert_eq!(d.index_bytes, 4);
    let idx = unbase64(&d.indices);
    assert_eq!(
        u32::from_le_bytes([idx[8], idx[9], idx[10], idx[11]]),
        69_999
    );
    assert_eq!(
        base64(b"any carnal pleasure."),
        "YW55IGNhcm5hbCBwbGVhc3VyZS4="
    );
}

/// A sphere-like mesh of many small triangles (a subdivided octahedron, pushed outwards).
fn ball(level: u32) -> TriMesh {
    let mut m = TriMesh {
        positions: vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ],
        triangles: vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    };
    for _ in 0..level {
        let mut tri = Vec::new();
        for t in &m.triangles {
            let mut mid = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (
                    m.positions[t[k] as usize],
                    m.positions[t[(k + 1) % 3] as usize],
                );
                let c = [0, 1, 2].map(|i| (a[i] + b[i]) / 2.0);
                let n = c.iter().map(|x| x * x).sum::<f32>().sqrt();
                m.positions.push(c.map(|x| x / n));
                mid[k] = m.positions.len() as u32 - 1;
            }
            tri.extend([
                [t[0], mid[0], mid[2]],
                [mid[0], t[1], mid[1]],
                [mid[2], mid[1], t[2]],
                mid,
            ]);
        }
        m.triangles = tri;
    }
    m
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Clustering at cube side h moves no vertex farther than the cube's diagonal, keeps valid
    /// indices and no degenerate triangle; `within` meets its budget.
    #[test]
    fn clustering_stays_near_the_surface_and_within_budget(
        level in 2u32..5, h in 0.01f64..0.5, budget in 60usize..3000,
    ) {
        let m = ball(level);
        let c = m.clustered(h);
        for p in &c.positions {
            let near = m.positions.iter().map(|q| {
                (0..3).map(|k| (f64::from(p[k]) - f64::from(q[k])).powi(2)).sum::<f64>().sqrt()
            }).fold(f64::INFINITY, f64::min);
            prop_assert!(near <= h * 3f64.sqrt() + 1e-6);
        }
        for t in &c.triangles {
            prop_assert!(t.iter().all(|&i| (i as usize) < c.positions.len()));
            prop_assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
        }
        prop_assert!(c.triangles.len() <= m.triangles.len());
        let w = m.within(budget);
        prop_assert!(w.triangles.len() <= budget);
        prop_assert!(!w.triangles.is_empty());
    }
}

#[test]
fn jvrc1_draws_every_visual_as_its_mesh_in_its_urdf_colour() {
    let urdf = jvrc1_urdf();
    let model =
        stance_robot::Model::from_urdf_file(&urdf, &stance_robot::jvrc1::urdf_options()).unwrap();
    let look = robot_look(&model, Some(&urdf), true).unwrap();
    assert_eq!(look.urdf_visuals, 35);
    assert_eq!(look.meshes.len(), 35);
    assert!(look.notes.is_empty(), "{:?}", look.notes);
    assert!(look
        .meshes
        .iter()
        .all(|m| matches!(m.shape, ShapeView::Mesh { .. }) && m.source == "visual"));
    let torso = look.meshes.iter().find(|m| m.link == "WAIST_R_S").unwrap();
    assert_eq!(torso.color, [1.0, 0.5, 0.0, 1.0]); // the URDF's "orange"
                                                   // without meshes: nothing of JVRC-1 is a primitive, and its collision shapes are meshes too
    let bare = robot_look(&model, Some(&urdf), false).unwrap();
    assert!(bare.meshes.is_empty() && bare.mesh_data.is_empty());
}

#[test]
fn talos_shares_its_mesh_files_within_the_budget() {
    let Ok(urdf) = stance_test_support::robots::talos_urdf(&root()) else {
        panic!("example-robot-data is not in the virtualenv (scripts/setup-venv.sh --peers)");
    };
    let model = stance_robot::Model::from_urdf_file(&urdf, &Default::default()).unwrap();
    let look = robot_look(&model, Some(&urdf), true).unwrap();
    assert_eq!(look.meshes.len(), 52);
    // left and right limbs name the same files: 25 of them
    assert_eq!(look.mesh_data.len(), 25);
    let drawn: usize = look.mesh_data.iter().map(|d| d.triangles).sum();
    let read: usize = look.mesh_data.iter().map(|d| d.file_triangles).sum();
    assert!(read > MESH_TRIANGLE_BUDGET && drawn <= MESH_TRIANGLE_BUDGET);
    assert!(look.notes.is_empty(), "{:?}", look.notes);
}

#[test]
fn a_missing_mesh_is_drawn_as_its_links_collision_primitive_with_a_note() {
    let dir = std::env::temp_dir().join(format!("stance-missing-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("r.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="r">
  <material name="blue"><color rgba="0 0 1 1"/></material>
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://gone/base.stl"/></geometry><material name="blue"/></visual>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.1 0.2 0.3"/></geometry></collision>
  </link>
  <link name="tip">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/><geometry><sphere radius="0.05"/></geometry></visual>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#,
    )
    .unwrap();
    let model = stance_robot::Model::from_urdf_file(&urdf, &Default::default()).unwrap();
    let look = robot_look(&model, Some(&urdf), true).unwrap();
    assert_eq!(look.urdf_visuals, 2);
    assert_eq!(look.meshes.len(), 2);
    let base = &look.meshes[0];
    assert_eq!(base.source, "collision");
    assert_eq!(
        base.shape,
        ShapeView::Box {
            size: [0.1, 0.2, 0.3]
        }
    );
    assert_eq!(base.color, [0.0, 0.0, 1.0, 1.0]);
    assert_eq!(base.origin[2], 0.1);
    assert!(look
        .notes
        .iter()
        .any(|n| n.contains("package://gone/base.stl")));
    // the sphere moves with joint j, placed at its origin (a quarter turn about z)
    let tip = &look.meshes[1];
    assert_eq!(model.joints[tip.joint + 1].name, "j");
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let o = tip.origin;
    assert!((o[2] - 0.5).abs() < 1e-12 && (o[5] - h).abs() < 1e-12 && (o[6] - h).abs() < 1e-12);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn hostile_mesh_files_are_errors_not_panics() {
    // a polygon count that overflows, a position that is not finite, a binary STL with a NaN
    let head = r##"<COLLADA><library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array>0 0 0 1 0 0 0 1 X</float_array>
      <technique_common><accessor stride="3"/></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>"##;
    let tail = "</mesh></geometry></library_geometries></COLLADA>";
    let overflow = format!(
        "{}<polylist><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><vcount>18446744073709551615 3</vcount><p>0 1 2</p></polylist>{tail}",
        head.replace(" X<", " 0<")
    );
    assert!(collada::read(&overflow)
        .unwrap_err()
        .contains("fewer indices"));
    let infinite = format!(
        "{}<triangles><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>0 1 2</p></triangles>{tail}",
        head.replace(" X<", " inf<")
    );
    assert!(collada::read(&infinite).unwrap_err().contains("not finite"));
    let mut bin = vec![0u8; 80];
    bin.extend(1u32.to_le_bytes());
    bin.extend([0u8; 12]);
    for x in [f32::NAN, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend(x.to_le_bytes());
    }
    bin.extend([0, 0]);
    assert!(stl::read(&bin).unwrap_err().contains("not finite"));
    // a budget below what the coarsest clustering reaches: the first triangles
    let b = ball(3);
    assert!(b.within(5).triangles.len() <= 5);
}
