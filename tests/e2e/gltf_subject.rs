//! A glTF subject whose primitives name several materials keeps them all: the swept material
//! fills the first slot (Unity's `Renderer.material`, `materials[0]`), each other material its
//! own primitives, drawn and traced as a fixed object placed as the subject is.

use shadematrix::declarations::scene::{MeshSpec, Role, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::shading::registry::Sliders;

/// One mesh of three quads facing +z side by side along x: the left names `Body` (white), the
/// middle names none, the right `Trim` (blue); `trim` replaces Trim's members after its name.
fn two_material_gltf(trim: &str) -> String {
    let mut bytes = Vec::new();
    for x0 in [-1.5f32, -0.5, 0.5] {
        for p in [[x0, -0.5, 0.0], [x0 + 0.9, -0.5, 0.0], [x0 + 0.9, 0.5, 0.0], [x0, 0.5, 0.0]] {
            bytes.extend(p.iter().flat_map(|v| v.to_le_bytes()));
        }
    }
    for _ in 0..12 {
        bytes.extend([0.0f32, 0.0, 1.0].iter().flat_map(|v| v.to_le_bytes()));
    }
    for q in 0..3u16 {
        for i in [0u16, 1, 2, 0, 2, 3] {
            bytes.extend((4 * q + i).to_le_bytes());
        }
    }
    use base64::Engine;
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bytes));
    let prim = |q: usize, material: &str| {
        format!(r#"{{ "attributes": {{ "POSITION": 0, "NORMAL": 1 }}, "indices": {}{material} }}"#, 2 + q)
    };
    format!(
        r#"{{
  "asset": {{ "version": "2.0" }},
  "buffers": [{{ "byteLength": {len}, "uri": "{uri}" }}],
  "bufferViews": [
    {{ "buffer": 0, "byteOffset": 0, "byteLength": 144 }},
    {{ "buffer": 0, "byteOffset": 144, "byteLength": 144 }},
    {{ "buffer": 0, "byteOffset": 288, "byteLength": 36 }}
  ],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": 12, "type": "VEC3", "min": [-1.5, -0.5, 0.0], "max": [1.4, 0.5, 0.0] }},
    {{ "bufferView": 1, "componentType": 5126, "count": 12, "type": "VEC3" }},
    {{ "bufferView": 2, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR" }},
    {{ "bufferView": 2, "byteOffset": 12, "componentType": 5123, "count": 6, "type": "SCALAR" }},
    {{ "bufferView": 2, "byteOffset": 24, "componentType": 5123, "count": 6, "type": "SCALAR" }}
  ],
  "materials": [
    {{ "name": "Trim", {trim} }},
    {{ "name": "Body", "pbrMetallicRoughness": {{ "baseColorFactor": [0.9, 0.9, 0.9, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6 }} }}
  ],
  "meshes": [{{ "name": "Model", "primitives": [{}, {}, {}] }}],
  "nodes": [{{ "name": "Model", "mesh": 0 }}],
  "scenes": [{{ "nodes": [0] }}],
  "scene": 0
}}"#,
        prim(0, r#", "material": 1"#),
        prim(1, ""),
        prim(2, r#", "material": 0"#),
        len = bytes.len()
    )
}

const TRIM: &str = r#""pbrMetallicRoughness": { "baseColorFactor": [0.05, 0.1, 0.8, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.7 }"#;

fn scene_text(mesh: &str) -> String {
    format!(
        "name = \"two_materials\"\n[camera]\nposition = [0.0, 0.0, 3.2]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 50.0\n\
         [[lights]]\nkind = \"directional\"\ndirection = [0.0, 0.0, -1.0]\nintensity = 1.0\n\
         [[objects]]\nname = \"model\"\nrole = \"subject\"\nmesh = {mesh}\n\
         transform = {{ translate = [0.0, 0.1, 0.0] }}\n\
         [environment]\nsky = {{ kind = \"constant\", color = [0.0, 0.0, 0.0] }}\n"
    )
}

#[test]
fn a_gltf_subject_keeps_its_other_materials_drawn_and_traced() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("model.gltf"), two_material_gltf(TRIM)).unwrap();
    std::fs::write(tmp.path().join("model.toml"), scene_text("{ kind = \"gltf\", path = \"model.gltf\" }")).unwrap();
    let scene = Scene::load_file(&tmp.path().join("model.toml")).unwrap();

    // The first slot in walk order is Body (material 1): the subject keeps its primitives and the
    // one naming none; Trim's is a fixed object with Trim's factors, placed as the subject is.
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["model", "model-trim"]);
    let (model, trim) = (&scene.objects[0], &scene.objects[1]);
    assert!(model.role == Role::Subject && matches!(model.mesh, MeshSpec::Gltf { material: Some(1), .. }));
    assert!(trim.role == Role::Fixed && matches!(trim.mesh, MeshSpec::Gltf { material: Some(0), .. }));
    let m = trim.material.as_ref().unwrap();
    assert_eq!(m.base_color_linear.map(|c| (c * 1e6).round() / 1e6), [0.05, 0.1, 0.8]);
    assert!((m.smoothness - 0.3).abs() < 1e-6 && m.metallic == 0.0 && trim.cast_shadows, "{m:?}");
    assert_eq!(trim.transform.matrix(), model.transform.matrix());

    // Drawn and traced: the swept colour on the left two thirds, Trim's blue on the right.
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.1, 0.05], metallic: 0.0, smoothness: 0.4 };
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 48, RenderPath::Forward);
    let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
    let settings = shadematrix::render::truth::TruthSettings {
        kind: shadematrix::declarations::matrix::TruthKind::Physical,
        spp: 8,
        noise: 0.0,
        bounces: 1,
        backend: shadematrix::declarations::matrix::TruthBackend::Cpu,
        ..Default::default()
    };
    let t = renderer.render_truth(&prepared, &cell, &settings).unwrap();
    let w = 48;
    // The mean colour of the pixels of `role` in columns lo..hi, and how many there are.
    let mean = |rgb: &dyn Fn(usize) -> [f64; 3], roles: &[u8], role: u8, (lo, hi): (usize, usize)| {
        let px: Vec<usize> = (0..w * w).filter(|&i| (lo..hi).contains(&(i % w)) && roles[i] == role).collect();
        let sum = px.iter().fold([0.0; 3], |a, &i| [0, 1, 2].map(|c| a[c] + rgb(i)[c]));
        (sum.map(|c| c / px.len().max(1) as f64), px.len())
    };
    let real = |i: usize| [0, 1, 2].map(|c| r.hdr[4 * i + c] as f64);
    let traced = |i: usize| [0, 1, 2].map(|c| t.mean[i][c] as f64);
    for (what, rgb, roles) in
        [("real-time", &real as &dyn Fn(usize) -> [f64; 3], &r.roles), ("truth", &traced, &t.roles)]
    {
        let (left, n_left) = mean(rgb, roles, 2, (0, w / 2));
        let (right, n_right) = mean(rgb, roles, 1, (2 * w / 3, w));
        assert!(n_left > 100 && n_right > 100, "{what}: {n_left} subject, {n_right} trim pixels");
        assert!(left[0] > 4.0 * left[2], "{what}: the swept red on the subject {left:?}");
        assert!(right[2] > 4.0 * right[0], "{what}: Trim's blue kept {right:?}");
        let (stray, _) = mean(rgb, roles, 2, (3 * w / 4, w));
        assert_eq!(stray, [0.0; 3], "{what}: no subject pixel on the trim");
    }

    // The same file as a `[gltf_scene]` whose subject node is the model: the same slots.
    let whole = "name = \"whole\"\nobjects = []\n[camera]\nposition = [0.0, 0.0, 3.2]\ntarget = [0.0, 0.0, 0.0]\n\
                 fov_y_deg = 50.0\n[gltf_scene]\npath = \"model.gltf\"\nsubject = \"Model\"\n\
                 [environment]\nsky = { kind = \"constant\", color = [0.0, 0.0, 0.0] }\n";
    std::fs::write(tmp.path().join("whole.toml"), whole).unwrap();
    let roles: Vec<(String, Role)> = Scene::load_file(&tmp.path().join("whole.toml"))
        .unwrap()
        .objects
        .iter()
        .map(|o| (o.name.clone(), o.role))
        .collect();
    let want = [("model-0", Role::Subject), ("model-1", Role::Subject), ("model-2", Role::Fixed)];
    assert_eq!(roles, want.map(|(n, r)| (n.to_string(), r)));

    // Asked by index: a material no primitive names is refused naming the file and the index.
    std::fs::write(tmp.path().join("bad.toml"), scene_text("{ kind = \"gltf\", path = \"model.gltf\", material = 5 }"))
        .unwrap();
    let bad = Scene::load_file(&tmp.path().join("bad.toml")).unwrap();
    let err = Renderer::new(GpuContext::new().unwrap()).prepare_scene(&bad).err().expect("refused").to_string();
    assert!(err.contains("model.gltf") && err.contains("material 5"), "{err}");
}
