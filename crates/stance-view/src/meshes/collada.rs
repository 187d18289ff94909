//! Collada (`.dae`, COLLADA 1.4/1.5): the triangles of the geometries that the visual scene
//! instantiates, placed by its nodes' transforms, in metres, z up.
//!
//! - A `<mesh>`'s `<vertices>` name the `POSITION` `<source>` (a `<float_array>` read with its
//!   accessor's stride). Its `<triangles>`, `<polylist>` (with `<vcount>`) and `<polygons>`
//!   list corners as tuples of `stride = 1 + max offset` indices, of which the `VERTEX` input's
//!   is the position; polygons are split into fans. `<lines>`, strips and fans are skipped.
//! - A `<node>` transforms its children by the product of its `<matrix>` (row-major),
//!   `<translate>`, `<rotate>` (axis, degrees) and `<scale>` elements in document order;
//!   `<instance_geometry url="#id">` places a geometry there. A file without a visual scene
//!   gives its geometries untransformed.
//! - `<unit meter="s">` scales everything by `s`; `<up_axis>Y_UP</up_axis>` turns y into z
//!   (a rotation of +90 degrees about x), `X_UP` x into z (-90 degrees about y).
//!
//! Materials and textures are not read: the URDF gives the colour.

use std::collections::HashMap;

use nalgebra::{Matrix4, Vector3};
use roxmltree::{Document, Node};

use super::TriMesh;

/// Reads a Collada document.
///
/// ```
/// let dae = r##"<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
///   <asset><unit meter="0.001"/><up_axis>Z_UP</up_axis></asset>
///   <library_geometries><geometry id="g"><mesh>
///     <source id="p"><float_array id="pa" count="9">0 0 0 1000 0 0 0 1000 0</float_array>
///       <technique_common><accessor source="#pa" count="3" stride="3"/></technique_common></source>
///     <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
///     <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
///   </mesh></geometry></library_geometries>
///   <library_visual_scenes><visual_scene id="s"><node><translate>0 0 500</translate>
///     <instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
/// </COLLADA>"##;
/// let m = stance_view::meshes::collada::read(dae).unwrap();
/// assert_eq!(m.triangles.len(), 1);
/// assert_eq!(m.positions[1], [1.0, 0.0, 0.5]);
/// ```
///
/// # Errors
///
/// Text that is not XML, or indices outside their arrays (the message names the element).
pub fn read(text: &str) -> Result<TriMesh, String> {
    let doc = Document::parse(text).map_err(|e| format!("not a Collada (XML) file: {e}"))?;
    let root = doc.root_element();
    let named = |n: &Node, name: &str| n.tag_name().name() == name;
    let asset = root.children().find(|n| named(n, "asset"));
    let unit = asset
        .and_then(|a| a.children().find(|n| named(n, "unit")))
        .and_then(|u| u.attribute("meter"))
        .and_then(|m| m.trim().parse::<f64>().ok())
        .filter(|m| m.is_finite() && *m > 0.0)
        .unwrap_or(1.0);
    let up = asset
        .and_then(|a| a.children().find(|n| named(n, "up_axis")))
        .and_then(|u| u.text())
        .map_or("Z_UP", str::trim);
    let mut world = Matrix4::identity();
    match up {
        "Y_UP" => {
            world = Matrix4::new(
                1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            )
        }
        "X_UP" => {
            world = Matrix4::new(
                0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            )
        }
        _ => {}
    }
    world *= Matrix4::new_scaling(unit);

    let geometries: HashMap<&str, Node> = root
        .descendants()
        .filter(|n| named(n, "geometry"))
        .filter_map(|n| n.attribute("id").map(|id| (id, n)))
        .collect();
    let mut placed: Vec<(Node, Matrix4<f64>)> = Vec::new();
    let scene = root.descendants().find(|n| named(n, "visual_scene"));
    match scene {
        Some(scene) => {
            for node in scene.children().filter(|n| named(n, "node")) {
                collect_instances(node, world, &geometries, &mut placed)?;
            }
        }
        None => placed.extend(geometries.values().map(|g| (*g, world))),
    }
    let mut mesh = TriMesh::default();
    for (geometry, m) in placed {
        for part in geometry.children().filter(|n| named(n, "mesh")) {
            add_mesh(part, &m, &mut mesh)?;
        }
    }
    Ok(mesh)
}

fn floats(text: Option<&str>) -> Vec<f64> {
    text.unwrap_or("")
        .split_ascii_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect()
}

/// The node's transform (its elements in order), then its instances and child nodes.
fn collect_instances<'a, 'i>(
    node: Node<'a, 'i>,
    parent: Matrix4<f64>,
    geometries: &HashMap<&str, Node<'a, 'i>>,
    out: &mut Vec<(Node<'a, 'i>, Matrix4<f64>)>,
) -> Result<(), String> {
    let mut m = parent;
    for child in node.children().filter(Node::is_element) {
        let v = || floats(child.text());
        match child.tag_name().name() {
            "matrix" => {
                let x = v();
                if x.len() == 16 {
                    m *= Matrix4::from_row_slice(&x);
                }
            }
            "translate" => {
                let x = v();
                if x.len() == 3 {
                    m *= Matrix4::new_translation(&Vector3::new(x[0], x[1], x[2]));
                }
            }
            "rotate" => {
                let x = v();
                if x.len() == 4 {
                    let axis = Vector3::new(x[0], x[1], x[2]);
                    if axis.norm() > 0.0 {
                        m *= Matrix4::from_scaled_axis(axis.normalize() * x[3].to_radians());
                    }
                }
            }
            "scale" => {
                let x = v();
                if x.len() == 3 {
                    m *= Matrix4::new_nonuniform_scaling(&Vector3::new(x[0], x[1], x[2]));
                }
            }
            "instance_geometry" => {
                let url = child.attribute("url").unwrap_or("");
                let g = geometries.get(url.trim_start_matches('#')).ok_or_else(|| {
                    format!("<instance_geometry url={url:?}> names no geometry of the file")
                })?;
                out.push((*g, m));
            }
            "node" => collect_instances(child, m, geometries, out)?,
            _ => {}
        }
    }
    Ok(())
}

/// The triangles of one `<mesh>`, transformed by `m`, appended to `out`.
fn add_mesh(mesh: Node, m: &Matrix4<f64>, out: &mut TriMesh) -> Result<(), String> {
    let named = |n: &Node, name: &str| n.tag_name().name() == name;
    let by_id = |id: &str| {
        let id = id.trim_start_matches('#');
        mesh.children()
            .find(|n| n.attribute("id") == Some(id) && n.is_element())
    };
    // positions: <vertices><input semantic="POSITION" source="#src"/>
    let Some(vertices) = mesh.children().find(|n| named(n, "vertices")) else {
        return Ok(());
    };
    let source = vertices
        .children()
        .find(|n| named(n, "input") && n.attribute("semantic") == Some("POSITION"))
        .and_then(|i| i.attribute("source"))
        .and_then(by_id)
        .ok_or("a <vertices> without a POSITION source")?;
    let values = floats(
        source
            .children()
            .find(|n| named(n, "float_array"))
            .and_then(|a| a.text()),
    );
    let stride = source
        .descendants()
        .find(|n| named(n, "accessor"))
        .and_then(|a| a.attribute("stride"))
        .and_then(|s| s.parse::<usize>().ok())
        .filter(|&s| s >= 3)
        .unwrap_or(3);
    let base = out.positions.len() as u32;
    let count = values.len() / stride;
    for k in 0..count {
        let p = m.transform_point(&nalgebra::Point3::new(
            values[stride * k],
            values[stride * k + 1],
            values[stride * k + 2],
        ));
        let p = [p.x as f32, p.y as f32, p.z as f32];
        if p.iter().any(|x| !x.is_finite()) {
            return Err(format!(
                "position {k} of {:?} is not finite (or the node transforms overflow)",
                source.attribute("id").unwrap_or("its source")
            ));
        }
        out.positions.push(p);
    }
    for prim in mesh.children().filter(Node::is_element) {
        let kind = prim.tag_name().name();
        if !matches!(kind, "triangles" | "polylist" | "polygons") {
            continue;
        }
        let inputs: Vec<Node> = prim.children().filter(|n| named(n, "input")).collect();
        let offset_of = |n: &Node| {
            n.attribute("offset")
                .and_then(|o| o.parse::<usize>().ok())
                .unwrap_or(0)
        };
        let tuple = inputs.iter().map(|i| offset_of(i) + 1).max().unwrap_or(1);
        let Some(vertex) = inputs
            .iter()
            .find(|i| i.attribute("semantic") == Some("VERTEX"))
            .map(offset_of)
        else {
            continue;
        };
        let ints = |n: Node| -> Vec<usize> {
            n.text()
                .unwrap_or("")
                .split_ascii_whitespace()
                .filter_map(|w| w.parse().ok())
                .collect()
        };
        // one list of polygon sizes and one of indices
        let mut polygons: Vec<(Vec<usize>, Vec<usize>)> = Vec::new();
        for p in prim.children().filter(|n| named(n, "p")) {
            let idx = ints(p);
            let sizes = match kind {
                "triangles" => vec![3; idx.len() / tuple / 3],
                "polylist" => prim
                    .children()
                    .find(|n| named(n, "vcount"))
                    .map(ints)
                    .unwrap_or_default(),
                _ => vec![idx.len() / tuple],
            };
            polygons.push((sizes, idx));
        }
        for (sizes, idx) in polygons {
            let mut at = 0usize;
            for n in sizes {
                let end = at.checked_add(n).and_then(|e| e.checked_mul(tuple));
                if end.is_none_or(|e| e > idx.len()) {
                    return Err(format!("<{kind}> has fewer indices than its counts say"));
                }
                let corner = |k: usize| -> Result<u32, String> {
                    let i = idx[(at + k) * tuple + vertex];
                    if i < count {
                        Ok(base + i as u32)
                    } else {
                        Err(format!(
                            "<{kind}> names vertex {i} of a source of {count} positions"
                        ))
                    }
                };
                for k in 1..n.saturating_sub(1) {
                    out.triangles.push([corner(0)?, corner(k)?, corner(k + 1)?]);
                }
                at += n;
            }
        }
    }
    Ok(())
}
