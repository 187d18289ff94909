//! Wavefront OBJ: `v x y z` vertices and `f` faces (`i`, `i/t`, `i//n` or `i/t/n` corners,
//! indices from 1, negative ones counted back from the last vertex); a face of more than three
//! corners is split into a fan. Everything else (normals, texture coordinates, materials,
//! groups) is ignored.

use super::TriMesh;

/// Reads an OBJ file's text.
///
/// ```
/// let m = stance_view::meshes::obj::read("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 -1\n").unwrap();
/// assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
/// ```
///
/// # Errors
///
/// A vertex without three numbers, or a face corner that is not a vertex (with the line).
pub fn read(text: &str) -> Result<TriMesh, String> {
    let mut mesh = TriMesh::default();
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                if xyz.len() != 3 || xyz.iter().any(|x| !x.is_finite()) {
                    return Err(format!(
                        "line {}: a vertex needs three finite numbers",
                        line_no + 1
                    ));
                }
                mesh.positions.push([xyz[0], xyz[1], xyz[2]]);
            }
            Some("f") => {
                let n = mesh.positions.len() as i64;
                let corners: Vec<u32> = words
                    .map(|w| {
                        let i: i64 = w
                            .split('/')
                            .next()
                            .and_then(|x| x.parse().ok())
                            .unwrap_or(0);
                        let i = if i < 0 { n + i } else { i - 1 };
                        if (0..n).contains(&i) {
                            Ok(i as u32)
                        } else {
                            Err(format!(
                                "line {}: face corner {w:?} is not one of the {n} vertices so far",
                                line_no + 1
                            ))
                        }
                    })
                    .collect::<Result<_, _>>()?;
                for k in 1..corners.len().saturating_sub(1) {
                    mesh.triangles
                        .push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(mesh)
}
