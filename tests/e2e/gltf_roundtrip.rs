//! `export-mesh` writes GLB that the importer reads back with the same vertices and bounds.

use shadematrix::geometry::{gltf_io, procedural, Mesh};
use shadematrix::spec::scene::Scene;

#[test]
fn exported_composition_loads_back_identically() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("mitsuba.glb");
    let (rc, stdout, stderr) =
        crate::common::shadematrix(tmp.path(), &["export-mesh", "mitsuba", out.to_str().unwrap()], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("7 objects"), "{stdout}");

    let scene = Scene::load("mitsuba", None, "test", "composition").unwrap();
    let mut expected = Mesh::default();
    for o in &scene.objects {
        expected.append(procedural::build(&o.mesh, None, "test", "mesh").unwrap().transformed(o.transform.matrix()));
    }
    let loaded = gltf_io::load(&out).unwrap();
    assert_eq!(loaded.vertices.len(), expected.vertices.len());
    assert_eq!(loaded.indices.len(), expected.indices.len());
    let (a, b) = (loaded.bounds(), expected.bounds());
    assert!((a.0 - b.0).abs().max_element() < 1e-6 && (a.1 - b.1).abs().max_element() < 1e-6, "{a:?} vs {b:?}");
    let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(p, q)| (p - q).abs() < 1e-6);
    // Normals are renormalised on import, so they agree to f32 rounding rather than bit for bit.
    assert!(loaded
        .vertices
        .iter()
        .zip(&expected.vertices)
        .all(|(x, y)| x.position == y.position && close(x.normal, y.normal)));
}

#[test]
fn gltf_meshes_render_in_a_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["export-mesh", "default", "room.glb"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    let scene =
        std::fs::read_to_string(crate::common::fixture("gltf_scene.toml")).unwrap().replace("MESH_PATH", "room.glb");
    std::fs::write(tmp.path().join("scene.toml"), scene).unwrap();
    let m = crate::common::write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"g\"\ncompositions = [\"scene.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\"]\npresets = [\"plastic\"]\n[image]\nwidth = 32\nheight = 32\n",
    );
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("1 rendered"), "{stdout}");
}
