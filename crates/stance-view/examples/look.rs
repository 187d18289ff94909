//! What `stance view` draws of a robot: `cargo run --release -p stance-view --example look --
//! URDF [LOCKED_JOINT ...]` prints each mesh file's triangles (read, drawn), the geometries and
//! the notes, and the time taken.

use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(urdf) = args.first() else {
        eprintln!("usage: look URDF [LOCKED_JOINT ...]");
        std::process::exit(2);
    };
    let options = stance_robot::UrdfOptions {
        locked: args[1..].iter().map(|j| (j.clone(), 0.0)).collect(),
        ..Default::default()
    };
    let t0 = std::time::Instant::now();
    let model = match stance_robot::Model::from_urdf_file(urdf, &options) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let look = match stance_view::robot_look(&model, Some(Path::new(urdf)), true) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let (mut read, mut drawn, mut bytes) = (0, 0, 0);
    for d in &look.mesh_data {
        println!("{:>7} {:>7}  {}", d.file_triangles, d.triangles, d.file);
        read += d.file_triangles;
        drawn += d.triangles;
        bytes += d.positions.len() + d.indices.len();
    }
    println!(
        "{} visuals, {} drawn geometries, {} mesh files: {read} triangles read, {drawn} drawn \
         ({:.2} MB of base64), {ms:.0} ms",
        look.urdf_visuals,
        look.meshes.len(),
        look.mesh_data.len(),
        bytes as f64 / 1e6
    );
    for n in &look.notes {
        println!("note: {n}");
    }
}
