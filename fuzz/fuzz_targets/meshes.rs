//! Mesh files as `stance view` reads them (Collada, STL, OBJ): each reader gives a mesh or an
//! error, never a panic or an overflow; a mesh read is simplified to a budget (from the first
//! byte) that it then meets, and packed. The first byte also picks the reader.
#![no_main]

use libfuzzer_sys::fuzz_target;
use stance_view::meshes::{collada, obj, stl, MeshData};

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let mesh = match head % 3 {
        0 => stl::read(rest),
        1 => obj::read(&text),
        _ => collada::read(&text),
    };
    let Ok(mesh) = mesh else {
        return;
    };
    for t in &mesh.triangles {
        assert!(t.iter().all(|&i| (i as usize) < mesh.positions.len()));
    }
    let budget = 60 + usize::from(head) * 8;
    let simple = mesh.within(budget);
    assert!(simple.triangles.len() <= budget);
    for t in &simple.triangles {
        assert!(t.iter().all(|&i| (i as usize) < simple.positions.len()));
    }
    let _ = MeshData::pack("fuzz", &simple, mesh.triangles.len());
});
