//! The robot's visual meshes for the page: found from the URDF's file names, read (Collada,
//! STL, OBJ), simplified to a triangle budget and packed.
//!
//! # Finding a mesh file
//!
//! A URDF names meshes as `package://PKG/REST`, `file:///ABS` or a path relative to the URDF.
//! `package://PKG/REST` is `A/REST` for the nearest ancestor `A` of the URDF's (resolved)
//! folder named `PKG`, else `A/PKG/REST` for the nearest ancestor holding `PKG` (a ROS
//! workspace's `share/` or `src/`), else `P/PKG/REST` for a folder `P` of `ROS_PACKAGE_PATH`.
//! This finds the meshes of the description packages on PyPI (`jvrc-description`,
//! `example-robot-data`) where pip installs them, without ROS.
//!
//! # Simplification
//!
//! Vertex clustering (Rossignac and Borrel, "Multi-resolution 3D approximations for rendering
//! complex scenes", 1993): space is cut into cubes of side `h`, the vertices in a cube merge
//! into their mean, and triangles with two corners in one cube disappear (as do duplicates).
//! `h` is the smallest power-of-two fraction of the mesh's bounding-box diagonal (down to
//! 2^-12) whose mesh fits the mesh's share of [`crate::MESH_TRIANGLE_BUDGET`]; a mesh within its
//! share is kept as it is. The result is within `h sqrt(3)` of the original surface.
//!
//! # Packing
//!
//! Positions as little-endian `f32` triples and triangle corners as little-endian `u16` (fewer
//! than 65,536 vertices) or `u32`, each base64-encoded (RFC 4648): the page decodes them into
//! typed arrays without parsing numbers.

pub mod collada;
pub mod obj;
pub mod stl;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde::Serialize;

/// A triangle mesh (m, the file's frame).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Triangles as vertex indices (counter-clockwise seen from outside, as the file gives them).
    pub triangles: Vec<[u32; 3]>,
}

/// Merges corners with bit-identical coordinates (STL repeats each corner per triangle).
#[derive(Default)]
pub(crate) struct Welder {
    seen: HashMap<[u32; 3], u32>,
}

impl Welder {
    pub(crate) fn index(&mut self, mesh: &mut TriMesh, p: [f32; 3]) -> u32 {
        let key = p.map(|x| if x == 0.0 { 0 } else { x.to_bits() });
        *self.seen.entry(key).or_insert_with(|| {
            mesh.positions.push(p);
            mesh.positions.len() as u32 - 1
        })
    }
}

impl TriMesh {
    /// The mesh simplified by vertex clustering at cube side `h` (module doc).
    ///
    /// ```
    /// use stance_view::meshes::TriMesh;
    /// // two triangles, one of them 1 mm wide: at h = 1 cm it collapses
    /// let m = TriMesh {
    ///     positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.001, 0.0]],
    ///     triangles: vec![[0, 1, 2], [1, 3, 2]],
    /// };
    /// assert_eq!(m.clustered(0.01).triangles.len(), 1);
    /// ```
    pub fn clustered(&self, h: f64) -> TriMesh {
        let mut cell_of: HashMap<[i64; 3], u32> = HashMap::new();
        let mut sums: Vec<([f64; 3], f64)> = Vec::new();
        let mut map = Vec::with_capacity(self.positions.len());
        for p in &self.positions {
            let key = p.map(|x| (f64::from(x) / h).floor() as i64);
            let k = *cell_of.entry(key).or_insert_with(|| {
                sums.push(([0.0; 3], 0.0));
                sums.len() as u32 - 1
            });
            let s = &mut sums[k as usize];
            for (a, x) in s.0.iter_mut().zip(p) {
                *a += f64::from(*x);
            }
            s.1 += 1.0;
            map.push(k);
        }
        let positions = sums
            .iter()
            .map(|(s, n)| s.map(|x| (x / n) as f32))
            .collect();
        let mut seen = std::collections::HashSet::new();
        let mut triangles = Vec::new();
        for t in &self.triangles {
            let c = t.map(|i| map[i as usize]);
            if c[0] == c[1] || c[1] == c[2] || c[0] == c[2] {
                continue;
            }
            // the same triangle (any rotation of its corners) once
            let r = (0..3).min_by_key(|&k| c[k]).unwrap_or(0);
            let key = [c[r], c[(r + 1) % 3], c[(r + 2) % 3]];
            if seen.insert(key) {
                triangles.push(c);
            }
        }
        let mut mesh = TriMesh {
            positions,
            triangles,
        };
        mesh.drop_unused();
        mesh
    }

    /// Removes vertices no triangle uses (renumbering the triangles).
    fn drop_unused(&mut self) {
        let mut new_index = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        for t in &mut self.triangles {
            for i in t.iter_mut() {
                let n = &mut new_index[*i as usize];
                if *n == u32::MAX {
                    positions.push(self.positions[*i as usize]);
                    *n = positions.len() as u32 - 1;
                }
                *i = *n;
            }
        }
        self.positions = positions;
    }

    /// The mesh with at most `budget` triangles: itself, or clustered at the smallest cube
    /// side `diagonal / 2^k` that fits (module doc); when even the coarsest does not (a budget
    /// of a few dozen triangles), its first `budget` triangles.
    pub fn within(&self, budget: usize) -> TriMesh {
        if self.triangles.len() <= budget {
            return self.clone();
        }
        let (lo, hi) = self.positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    [0, 1, 2].map(|k| lo[k].min(f64::from(p[k]))),
                    [0, 1, 2].map(|k| hi[k].max(f64::from(p[k]))),
                )
            },
        );
        let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
        let mut best = self.clustered(diagonal.max(1e-9));
        for k in (1..=12).rev() {
            let m = self.clustered(diagonal.max(1e-9) / f64::from(1u32 << k));
            if m.triangles.len() <= budget {
                best = m;
                break;
            }
        }
        if best.triangles.len() > budget {
            best.triangles.truncate(budget);
            best.drop_unused();
        }
        best
    }
}

/// Reads a mesh file by its extension (`.dae`, `.stl`, `.obj`, any case).
///
/// # Errors
///
/// An unreadable file, another format, or a file its reader refuses (the message names the file).
pub fn read_mesh(path: &Path) -> Result<TriMesh, String> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let size = std::fs::metadata(path)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .len();
    if size > crate::MAX_MESH_FILE_BYTES {
        return Err(format!(
            "{}: {} MB, more than the {} MB a mesh file is read up to (simplify it, or view \
             with --no-meshes)",
            path.display(),
            size / 1_000_000,
            crate::MAX_MESH_FILE_BYTES / 1_000_000
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = || String::from_utf8_lossy(&bytes).into_owned();
    let mesh = match ext.as_str() {
        "stl" => stl::read(&bytes),
        "dae" => collada::read(&text()),
        "obj" => obj::read(&text()),
        _ => Err(format!(
            "a .{ext} mesh: the page reads Collada (.dae), STL and OBJ"
        )),
    };
    mesh.map_err(|e| format!("{}: {e}", path.display()))
}

/// The file a URDF's mesh `filename` names, for the URDF at `urdf` (module doc), if it exists.
///
/// ```
/// let dir = std::env::temp_dir().join("stance-doc-resolve/my_robot");
/// std::fs::create_dir_all(dir.join("urdf")).unwrap();
/// std::fs::create_dir_all(dir.join("meshes")).unwrap();
/// std::fs::write(dir.join("meshes/base.stl"), b"solid x\nendsolid x\n").unwrap();
/// let urdf = dir.join("urdf/robot.urdf");
/// let found = stance_view::meshes::resolve("package://my_robot/meshes/base.stl", &urdf);
/// assert_eq!(found.unwrap(), dir.join("meshes/base.stl").canonicalize().unwrap());
/// assert!(stance_view::meshes::resolve("package://other/x.stl", &urdf).is_none());
/// ```
pub fn resolve(filename: &str, urdf: &Path) -> Option<PathBuf> {
    // the file's own folder when it is a link (a URDF linked into a project)
    let folder = match urdf.canonicalize() {
        Ok(p) => p.parent()?.to_path_buf(),
        Err(_) => urdf.parent()?.canonicalize().ok()?,
    };
    let existing = |p: PathBuf| p.is_file().then_some(p);
    if let Some(rest) = filename.strip_prefix("package://") {
        let (package, rest) = rest.split_once('/')?;
        for a in folder.ancestors() {
            if a.file_name().is_some_and(|n| n == package) {
                if let Some(p) = existing(a.join(rest)) {
                    return Some(p);
                }
            }
            if let Some(p) = existing(a.join(package).join(rest)) {
                return Some(p);
            }
        }
        let paths = std::env::var_os("ROS_PACKAGE_PATH")?;
        return std::env::split_paths(&paths).find_map(|p| existing(p.join(package).join(rest)));
    }
    if let Some(abs) = filename.strip_prefix("file://") {
        return existing(PathBuf::from(abs));
    }
    existing(folder.join(filename))
}

/// A mesh packed for the page (module doc).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshData {
    /// The file, as the URDF names it.
    pub file: String,
    /// Vertex count.
    pub vertices: usize,
    /// Triangle count (after simplification).
    pub triangles: usize,
    /// Triangle count of the file.
    pub file_triangles: usize,
    /// Positions: `f32` little-endian x, y, z per vertex, base64.
    pub positions: String,
    /// Bytes per index: 2 (`u16`) or 4 (`u32`).
    pub index_bytes: usize,
    /// Corners: three indices per triangle, little-endian, base64.
    pub indices: String,
}

impl MeshData {
    /// Packs `mesh` (already within its budget), read from `file` with `file_triangles`.
    pub fn pack(file: &str, mesh: &TriMesh, file_triangles: usize) -> Self {
        let mut pos = Vec::with_capacity(12 * mesh.positions.len());
        for p in &mesh.positions {
            for x in p {
                pos.extend(x.to_le_bytes());
            }
        }
        let small = mesh.positions.len() < 1 << 16;
        let mut idx = Vec::with_capacity(if small { 6 } else { 12 } * mesh.triangles.len());
        for t in &mesh.triangles {
            for &i in t {
                if small {
                    idx.extend((i as u16).to_le_bytes());
                } else {
                    idx.extend(i.to_le_bytes());
                }
            }
        }
        Self {
            file: file.to_string(),
            vertices: mesh.positions.len(),
            triangles: mesh.triangles.len(),
            file_triangles,
            positions: base64(&pos),
            index_bytes: if small { 2 } else { 4 },
            indices: base64(&idx),
        }
    }
}

/// RFC 4648 base64 with padding.
///
/// ```
/// assert_eq!(stance_view::meshes::base64(b"Man"), "TWFu");
/// assert_eq!(stance_view::meshes::base64(b"Ma"), "TWE=");
/// assert_eq!(stance_view::meshes::base64(b"M"), "TQ==");
/// assert_eq!(stance_view::meshes::base64(b""), "");
/// ```
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}
