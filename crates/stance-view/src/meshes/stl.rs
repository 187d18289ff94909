//! STL, binary or ASCII: a list of triangles, each with its three corners (the normals are
//! ignored; the page shades flat from the corners). Corners with the same coordinates are
//! merged.

use super::TriMesh;

/// Reads an STL file's bytes.
///
/// Binary STL: an 80-byte header, a `u32` triangle count `n`, then `n` records of 50 bytes
/// (normal, three corners as 3 `f32` each, a `u16`), so the file has `84 + 50 n` bytes; any
/// other file that starts with `solid` is read as ASCII (`vertex x y z` lines, three per
/// facet).
///
/// ```
/// let mut b = vec![0u8; 80];
/// b.extend(1u32.to_le_bytes());
/// for x in [0.0f32, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
///     b.extend(x.to_le_bytes());
/// }
/// b.extend([0, 0]);
/// let m = stance_view::meshes::stl::read(&b).unwrap();
/// assert_eq!((m.positions.len(), m.triangles.len()), (3, 1));
/// ```
///
/// # Errors
///
/// A file that is neither (a message saying why).
pub fn read(bytes: &[u8]) -> Result<TriMesh, String> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n.checked_mul(50).and_then(|x| x.checked_add(84)) == Some(bytes.len()) {
            let mut mesh = TriMesh::default();
            let mut weld = super::Welder::default();
            for k in 0..n {
                let rec = &bytes[84 + 50 * k..84 + 50 * (k + 1)];
                let f = |i: usize| {
                    let o = 12 + 4 * i;
                    f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]])
                };
                let mut t = [0; 3];
                for (c, i) in t.iter_mut().enumerate() {
                    let p = [f(3 * c), f(3 * c + 1), f(3 * c + 2)];
                    if p.iter().any(|x| !x.is_finite()) {
                        return Err(format!("triangle {k} has a corner that is not finite"));
                    }
                    *i = weld.index(&mut mesh, p);
                }
                mesh.triangles.push(t);
            }
            return Ok(mesh);
        }
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|_| "neither a binary STL (84 + 50 n bytes) nor an ASCII one".to_string())?;
    if !text.trim_start().starts_with("solid") {
        return Err("neither a binary STL (84 + 50 n bytes) nor an ASCII one (`solid ...`)".into());
    }
    let mut mesh = TriMesh::default();
    let mut weld = super::Welder::default();
    let mut corners = Vec::with_capacity(3);
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("vertex") {
            continue;
        }
        let xyz: Vec<f32> = words.filter_map(|w| w.parse().ok()).collect();
        if xyz.len() != 3 || xyz.iter().any(|x| !x.is_finite()) {
            return Err(format!(
                "line {}: a vertex needs three finite numbers",
                line_no + 1
            ));
        }
        corners.push(weld.index(&mut mesh, [xyz[0], xyz[1], xyz[2]]));
        if corners.len() == 3 {
            mesh.triangles.push([corners[0], corners[1], corners[2]]);
            corners.clear();
        }
    }
    Ok(mesh)
}
