//! `export-mesh` writes GLB that the importer reads back with the same vertices and bounds.

use shadematrix::declarations::scene::Scene;
use shadematrix::geometry::{gltf_io, procedural, Mesh};

#[test]
fn exported_composition_loads_back_identically() {
    let _timer = crate::common::timed!();
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
    let loaded = gltf_io::load(&out, None).unwrap();
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
    let _timer = crate::common::timed!();
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

/// `export-mesh --preset P --textured` writes the preset's maps as glTF textures on the subject:
/// read back, the base colour texture's mean is the flat preset (its maps' mean is 1) and the
/// roughness the preset's.
#[test]
fn a_textured_preset_exports_as_gltf_textures() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("mitsuba.glb");
    let args = ["export-mesh", "mitsuba", out.to_str().unwrap(), "--preset", "brick", "--textured"];
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &args, &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("4 textured materials"), "the four subject parts: {stdout}");
    let (doc, _, images) = gltf::import(&out).unwrap();
    let brick = shadematrix::declarations::presets::find_preset("brick").unwrap();
    let shell = doc.materials().find(|m| m.name() == Some("shell")).expect("the subject's material");
    let pbr = shell.pbr_metallic_roughness();
    assert!(shell.normal_texture().is_some() && shell.occlusion_texture().is_some());
    let mean = |index: usize, c: usize, srgb: bool| {
        let img = &images[index];
        let n = (img.width * img.height) as f64;
        img.pixels
            .chunks(4)
            .map(|p| {
                let v = p[c] as f64 / 255.0;
                if srgb {
                    shadematrix::color::srgb_to_linear(v)
                } else {
                    v
                }
            })
            .sum::<f64>()
            / n
    };
    let base = pbr.base_color_texture().unwrap().texture().source().index();
    for c in 0..3 {
        let m = mean(base, c, true);
        assert!((m / brick.base_color[c] - 1.0).abs() < 0.03, "channel {c}: {m} vs {}", brick.base_color[c]);
    }
    let mr = pbr.metallic_roughness_texture().unwrap().texture().source().index();
    let roughness = mean(mr, 1, false) * pbr.roughness_factor() as f64;
    assert!((roughness - (1.0 - brick.smoothness)).abs() < 0.02, "roughness {roughness}");
}

/// A glTF subject's own textured material survives `export-mesh` (the default for such a subject):
/// the re-read material has its factors, its base colour texture and its emission.
#[test]
fn a_gltf_subjects_own_material_exports_with_its_textures() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    crate::common::write_textured_gltf(dir);
    let scene =
        std::fs::read_to_string(crate::common::fixture("gltf_scene.toml")).unwrap().replace("MESH_PATH", "plane.gltf");
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let (rc, stdout, stderr) = crate::common::shadematrix(dir, &["export-mesh", "scene.toml", "again.glb"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("1 objects") && stdout.contains("1 textured material"), "{stdout}");
    let (_, material) = gltf_io::load_with_material(&dir.join("again.glb")).unwrap();
    let m = material.expect("the subject's own material is written");
    assert_eq!(m.texture_count, 5, "base colour, metallic-roughness, normal, occlusion, emissive");
    assert_eq!(m.emissive, [1.0; 3]);
    let base = m.base_color_texture.expect("decoded");
    let (left, right) = (base.texels[base.width / 8], base.texels[base.width - 1 - base.width / 8]);
    assert!(left[0] > 0.9 && left[2] < 0.05 && right[2] > 0.9 && right[0] < 0.05, "{left:?} {right:?}");
    let emissive = m.emissive_texture.expect("decoded");
    let (top, bottom) = (emissive.texels[0], emissive.texels[emissive.texels.len() - 1]);
    assert!(top[1] > 0.9 && bottom[1] < 0.05, "{top:?} {bottom:?}");
}
