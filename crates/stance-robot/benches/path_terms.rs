//! The inverse dynamics along a path at one sample, both sides (`torque_path_terms_two`: one
//! forward kinematics and four recursive passes), and one `rnea` for scale, on JVRC-1 (when
//! its URDF is installed) and on the project's small humanoid: the part of the actuator-limit
//! rows that any method of retiming under torque limits computes at every grid sample.
//!
//! `cargo bench -p stance-robot --bench path_terms`

use criterion::{criterion_group, criterion_main, Criterion};
use stance_robot::{
    jvrc1, rnea, torque_path_terms_two, Data, Model, UrdfOptions, SMALL_HUMANOID_URDF,
};

fn models() -> Vec<(&'static str, Model)> {
    let mut out = Vec::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    match jvrc1::locate_urdf(Some(&root)) {
        Ok(urdf) => out.push((
            "jvrc1",
            Model::from_urdf_file(urdf, &jvrc1::urdf_options()).unwrap(),
        )),
        Err(why) => eprintln!("JVRC-1 skipped: {why}"),
    }
    let small = Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap();
    out.push(("small-humanoid", small));
    out
}

fn path_terms(c: &mut Criterion) {
    for (name, m) in models() {
        let mut d = Data::new(&m);
        let mut q = m.neutral();
        q[2] = 0.8;
        // a path derivative and two second derivatives with every coordinate moving
        let wave = |k: usize, f: f64| {
            (0..m.nv)
                .map(|i| f * ((i * k % 7) as f64 - 3.0))
                .collect::<Vec<f64>>()
        };
        let (q_s, q_ss, q_ss_other) = (wave(3, 0.1), wave(5, 0.2), wave(2, 0.3));
        let g = [0.0, 0.0, -9.81];
        c.bench_function(&format!("torque_path_terms_two/{name}"), |b| {
            b.iter(|| torque_path_terms_two(&m, &mut d, &q, &q_s, &q_ss, &q_ss_other, g).unwrap())
        });
        c.bench_function(&format!("rnea/{name}"), |b| {
            b.iter(|| rnea(&m, &mut d, &q, &q_s, &q_ss, g).unwrap())
        });
    }
}

criterion_group!(benches, path_terms);
criterion_main!(benches);
