//! A glTF file as a whole scene (`[gltf_scene]`, input::gltf_scene): every primitive with its own
//! material, the `KHR_lights_punctual` lights in photometric units converted per pipeline, a camera
//! chosen by name, the subject node taking the swept material; and what it cannot draw refused.

use shadematrix::declarations::scene::{LightKind, MeshSpec, Role, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::shading::registry::Sliders;

/// Two quad meshes with their own materials (the floor, scaled 8×; the vase's), a point and a
/// directional light, and a camera; `tile` is the floor material's members after its name (`TILE`
/// the plain one) and `textures` the file's `textures`/`images` members, if any.
pub(crate) fn room_gltf(tile: &str, textures: &str) -> String {
    let mut bytes = Vec::new();
    for p in [[-0.5f32, 0.0, -0.5], [0.5, 0.0, -0.5], [0.5, 0.0, 0.5], [-0.5, 0.0, 0.5]] {
        bytes.extend(p.iter().flat_map(|v| v.to_le_bytes()));
    }
    for _ in 0..4 {
        bytes.extend([0.0f32, 1.0, 0.0].iter().flat_map(|v| v.to_le_bytes()));
    }
    for i in [0u16, 2, 1, 0, 3, 2] {
        bytes.extend(i.to_le_bytes());
    }
    for uv in [[0.0f32, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]] {
        bytes.extend(uv.iter().flat_map(|v| v.to_le_bytes()));
    }
    use base64::Engine;
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bytes));
    format!(
        r#"{{
  "asset": {{ "version": "2.0" }},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
  "extensions": {{ "KHR_lights_punctual": {{ "lights": [
    {{ "name": "LampLight", "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 20.0, "range": 8.0 }},
    {{ "name": "SunLight", "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 3.0 }}
  ] }} }},
  "buffers": [{{ "byteLength": {len}, "uri": "{uri}" }}],
  "bufferViews": [
    {{ "buffer": 0, "byteOffset": 0, "byteLength": 48 }},
    {{ "buffer": 0, "byteOffset": 48, "byteLength": 48 }},
    {{ "buffer": 0, "byteOffset": 96, "byteLength": 12 }},
    {{ "buffer": 0, "byteOffset": 108, "byteLength": 32 }}
  ],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, 0.0, -0.5], "max": [0.5, 0.0, 0.5] }},
    {{ "bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3" }},
    {{ "bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR" }},
    {{ "bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2" }}
  ],
  "materials": [
    {{ "name": "Tile", {tile} }},
    {{ "name": "Glaze", "pbrMetallicRoughness": {{ "baseColorFactor": [0.1, 0.2, 0.7, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.3 }} }}
  ],
  {textures}
  "meshes": [
    {{ "name": "FloorMesh", "primitives": [{{ "attributes": {{ "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 3 }}, "indices": 2, "material": 0 }}] }},
    {{ "name": "VaseMesh", "primitives": [{{ "attributes": {{ "POSITION": 0, "NORMAL": 1 }}, "indices": 2, "material": 1 }}] }}
  ],
  "cameras": [{{ "name": "Main", "type": "perspective", "perspective": {{ "yfov": 0.8, "znear": 0.1, "zfar": 50.0 }} }}],
  "nodes": [
    {{ "name": "Floor", "mesh": 0, "scale": [8.0, 1.0, 8.0] }},
    {{ "name": "Vase", "mesh": 1, "translation": [0.0, 0.5, 0.0] }},
    {{ "name": "Lamp", "translation": [1.0, 3.0, 2.0], "extensions": {{ "KHR_lights_punctual": {{ "light": 0 }} }} }},
    {{ "name": "Sun", "rotation": [-0.70710678, 0.0, 0.0, 0.70710678], "extensions": {{ "KHR_lights_punctual": {{ "light": 1 }} }} }},
    {{ "name": "Eye", "camera": 0, "translation": [0.0, 1.5, 5.0] }}
  ],
  "scenes": [{{ "nodes": [0, 1, 2, 3, 4] }}],
  "scene": 0
}}"#,
        len = bytes.len()
    )
}

pub(crate) fn scene_text(subject: &str) -> String {
    format!(
        "name = \"gltf_room\"\nobjects = []\n[camera]\nposition = [0.0, 2.0, 6.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 40.0\n[gltf_scene]\npath = \"room.gltf\"\nsubject = \"{subject}\"\ncamera = \"Main\"\n[environment]\nsky = {{ kind = \"constant\", color = [0.2, 0.2, 0.2] }}\n"
    )
}

#[test]
fn a_gltf_scene_brings_its_objects_materials_lights_and_camera() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("room.gltf"), room_gltf(TILE, "")).unwrap();
    std::fs::write(tmp.path().join("room.toml"), scene_text("Vase")).unwrap();
    let scene = Scene::load_file(&tmp.path().join("room.toml")).unwrap();

    // Each primitive an object with its own material; the subject node takes the swept one.
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["floor-0", "vase-0"]);
    let floor = &scene.objects[0];
    assert_eq!(floor.role, Role::Fixed);
    let m = floor.material.as_ref().unwrap();
    assert_eq!(m.base_color_linear.map(|c| (c * 1e6).round() / 1e6), [0.5, 0.4, 0.3]);
    assert!((m.smoothness - 0.2).abs() < 1e-6 && m.metallic == 0.0, "{m:?}");
    assert!(matches!(floor.mesh, MeshSpec::GltfPrimitive { mesh: 0, primitive: 0, .. }));
    assert_eq!(floor.transform.matrix().x_axis.x, 8.0, "the node's scale");
    let vase = &scene.objects[1];
    assert!(vase.role == Role::Subject && vase.material.is_none());
    assert_eq!(vase.transform.matrix().w_axis.y, 0.5);

    // The lights, photometric, converted per pipeline: HDRP's candela as is, URP's I = C/π.
    assert_eq!(scene.lights.len(), 2);
    let lamp = &scene.lights[0];
    assert!(lamp.kind == LightKind::Point && lamp.photometric && lamp.range == 8.0 && !lamp.shadows);
    assert_eq!(lamp.position, [1.0, 3.0, 2.0]);
    let engine = Default::default();
    let (hdrp, urp) =
        (lamp.radiance(Pipeline::Hdrp, lamp.intensity, &engine), lamp.radiance(Pipeline::Urp, lamp.intensity, &engine));
    for (c, want) in [1.0, 0.5, 0.25].iter().enumerate() {
        assert!((hdrp[c] - 20.0 * want).abs() < 1e-9, "HDRP {hdrp:?}");
        assert!((urp[c] - 20.0 * want / std::f64::consts::PI).abs() < 1e-9, "URP {urp:?}");
    }
    let sun = &scene.lights[1];
    assert!(sun.kind == LightKind::Directional && sun.shadows);
    assert!((sun.direction[1] + 1.0).abs() < 1e-6, "the node's −Z turned down: {:?}", sun.direction);

    // The camera by name.
    assert_eq!(scene.camera.position, [0.0, 1.5, 5.0]);
    assert!((scene.camera.target[2] - 4.0).abs() < 1e-9 && (scene.camera.fov_y_deg - 0.8f64.to_degrees()).abs() < 1e-4);

    // Drawn: every pipeline sees the vase lit, in finite values.
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    for pipeline in [Pipeline::Urp, Pipeline::Hdrp] {
        let sliders = Sliders { base_color_linear: [0.8, 0.8, 0.8], metallic: 0.0, smoothness: 0.5 };
        let cell =
            crate::common::cell_params(pipeline, "lit", sliders, (lamp.intensity, lamp.range), 64, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let subject: Vec<usize> = (0..r.roles.len()).filter(|&i| r.roles[i] == 2).collect();
        assert!(subject.len() > 20, "{pipeline:?}: {} subject pixels", subject.len());
        assert!(r.hdr.iter().all(|v| v.is_finite()) && subject.iter().any(|&i| r.hdr[4 * i] > 0.0));
    }
}

#[test]
fn what_a_gltf_scene_cannot_draw_is_refused_by_name() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("room.gltf"), room_gltf(TILE, "")).unwrap();
    std::fs::write(tmp.path().join("typo.toml"), scene_text("Vace")).unwrap();
    let err = Scene::load_file(&tmp.path().join("typo.toml")).unwrap_err().to_string();
    assert!(err.contains("gltf_scene.path") && err.contains("`Vace`") && err.contains("did you mean `Vase`"), "{err}");
    // A texture on a second UV set, or one material's maps transformed differently.
    let second_set = format!(r#"{TILE}, "occlusionTexture": {{ "index": 0, "texCoord": 1 }}"#);
    std::fs::write(tmp.path().join("room.gltf"), room_gltf(&second_set, &textures_json())).unwrap();
    std::fs::write(tmp.path().join("textured.toml"), scene_text("Vase")).unwrap();
    let err = Scene::load_file(&tmp.path().join("textured.toml")).unwrap_err().to_string();
    assert!(err.contains("node `Floor`") && err.contains("coordinate set 1") && err.contains("Tile"), "{err}");
    let two = format!(
        r#"{TILE}, "occlusionTexture": {{ "index": 0 }}, "emissiveTexture": {{ "index": 0, "extensions": {{ "KHR_texture_transform": {{ "offset": [0.5, 0.0] }} }} }}"#
    );
    std::fs::write(tmp.path().join("room.gltf"), room_gltf(&two, &textures_json())).unwrap();
    let err = Scene::load_file(&tmp.path().join("textured.toml")).unwrap_err().to_string();
    assert!(err.contains("KHR_texture_transform") && err.contains("occlusionTexture"), "{err}");
    // A texture whose file is missing: refused naming it when the composition is prepared.
    let missing = format!(r#"{TILE}, "occlusionTexture": {{ "index": 0 }}"#);
    let missing_image = r#""textures": [{ "source": 0 }], "images": [{ "uri": "missing.png" }],"#;
    std::fs::write(tmp.path().join("room.gltf"), room_gltf(&missing, missing_image)).unwrap();
    let scene = Scene::load_file(&tmp.path().join("textured.toml")).unwrap();
    let err = Renderer::new(GpuContext::new().unwrap()).prepare_scene(&scene).err().expect("refused").to_string();
    assert!(err.contains("missing.png"), "{err}");
    // A required extension the tool does not draw.
    let required = room_gltf(TILE, "").replace(
        r#""extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],"#,
        r#""extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"],"#,
    );
    std::fs::write(tmp.path().join("room.gltf"), required).unwrap();
    let err = Scene::load_file(&tmp.path().join("textured.toml")).unwrap_err().to_string();
    assert!(err.contains("gltf_scene.path") && err.contains("KHR_draco_mesh_compression"), "{err}");
    let camera = scene_text("Vase").replace("camera = \"Main\"", "camera = \"Mian\"");
    std::fs::write(tmp.path().join("room.gltf"), room_gltf(TILE, "")).unwrap();
    std::fs::write(tmp.path().join("camera.toml"), camera).unwrap();
    let err = Scene::load_file(&tmp.path().join("camera.toml")).unwrap_err().to_string();
    assert!(err.contains("gltf_scene.camera") && err.contains("Main"), "{err}");
}

/// The floor's material of factors alone.
pub(crate) const TILE: &str = r#""pbrMetallicRoughness": { "baseColorFactor": [0.5, 0.4, 0.3, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8 }"#;

/// A 4×1 texture, red on the left half and blue on the right, as a PNG data URI: the file's
/// `textures` and `images`.
const TEXTURES: &str = r#""textures": [{ "source": 0 }], "images": [{ "uri": "data:image/png;base64,PNG" }],"#;

fn textures_json() -> String {
    let image =
        image::RgbImage::from_fn(4, 1, |x, _| if x < 2 { image::Rgb([255, 0, 0]) } else { image::Rgb([0, 0, 255]) });
    let mut png = std::io::Cursor::new(Vec::new());
    image.write_to(&mut png, image::ImageFormat::Png).unwrap();
    use base64::Engine;
    TEXTURES.replace("PNG", &base64::engine::general_purpose::STANDARD.encode(png.into_inner()))
}

/// A fixed object's own glTF maps are drawn and traced: the floor's base-colour texture (red on
/// the left, blue on the right) shows in the real-time frame and in both truth backends, its
/// KHR_texture_transform offset of half a tile swaps the halves in both, and its emission adds
/// its radiance to both.
#[test]
fn a_fixed_objects_gltf_maps_and_emission_are_drawn_and_traced() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("room.toml"), scene_text("Vase")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.8, 0.8, 0.8], metallic: 0.0, smoothness: 0.5 };
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", sliders, (20.0, 8.0), 48, RenderPath::Forward);
    let settings = shadematrix::render::truth::TruthSettings {
        kind: shadematrix::declarations::matrix::TruthKind::Physical,
        spp: 16,
        noise: 0.0,
        bounces: 1,
        backend: shadematrix::declarations::matrix::TruthBackend::Cpu,
        ..Default::default()
    };
    // Mean linear colour of the floor's pixels in the left and right thirds of the frame.
    let thirds = |rgb: &dyn Fn(usize) -> [f64; 3], roles: &dyn Fn(usize) -> u8| {
        let w = 48;
        let mean = |lo: usize, hi: usize| {
            let px: Vec<usize> = (0..w * w).filter(|&i| (lo..hi).contains(&(i % w)) && roles(i) == 1).collect();
            assert!(px.len() > 30, "{} floor pixels", px.len());
            let sum = px.iter().fold([0.0; 3], |a, &i| [0, 1, 2].map(|c| a[c] + rgb(i)[c]));
            sum.map(|c| c / px.len() as f64)
        };
        (mean(0, w / 3), mean(2 * w / 3, w))
    };
    let mut frame = |tile: &str| {
        std::fs::write(tmp.path().join("room.gltf"), room_gltf(tile, &textures_json())).unwrap();
        let scene = Scene::load_file(&tmp.path().join("room.toml")).unwrap();
        let floor = scene.objects[0].material.as_ref().unwrap();
        assert_eq!(floor.gltf_material.as_ref().map(|r| r.index), Some(0), "the floor keeps its material's maps");
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let t = renderer.render_truth(&prepared, &cell, &settings).unwrap();
        let gpu_settings = shadematrix::render::truth::TruthSettings {
            backend: shadematrix::declarations::matrix::TruthBackend::Gpu,
            ..settings
        };
        let g = renderer.render_truth(&prepared, &cell, &gpu_settings).unwrap();
        let real = thirds(&|i| [0, 1, 2].map(|c| r.hdr[4 * i + c] as f64), &|i| r.roles[i]);
        let traced = thirds(&|i| t.mean[i].map(f64::from), &|i| t.roles[i]);
        let traced_gpu = thirds(&|i| g.mean[i].map(f64::from), &|i| g.roles[i]);
        (real, traced, traced_gpu)
    };
    let plain = frame(
        r#""pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8, "baseColorTexture": { "index": 0 } }"#,
    );
    let moved = frame(
        r#""pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8, "baseColorTexture": { "index": 0, "extensions": { "KHR_texture_transform": { "offset": [0.5, 0.0] } } } }"#,
    );
    let glowing = frame(
        r#""pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8, "baseColorTexture": { "index": 0 } }, "emissiveFactor": [0.0, 0.5, 0.0]"#,
    );
    for (what, (left, right), swapped) in [
        ("real-time", plain.0, false),
        ("truth", plain.1, false),
        ("real-time, transformed", moved.0, true),
        ("truth, transformed", moved.1, true),
        ("GPU truth", plain.2, false),
        ("GPU truth, transformed", moved.2, true),
    ] {
        eprintln!("{what}: left {left:.3?}, right {right:.3?}");
        let (red, blue) = if swapped { (right, left) } else { (left, right) };
        assert!(red[0] > 3.0 * red[2] && blue[2] > 3.0 * blue[0], "{what}: left {left:?}, right {right:?}");
    }
    // The emission (URP's units: 0.5 as it is) adds to both, beside the lit texture.
    for (what, lit, glow) in [
        ("real-time", plain.0 .0, glowing.0 .0),
        ("truth", plain.1 .0, glowing.1 .0),
        ("GPU truth", plain.2 .0, glowing.2 .0),
    ] {
        let added = glow[1] - lit[1];
        eprintln!("{what}: emission adds {added:.4} to the floor's green");
        assert!((added - 0.5).abs() < 0.02, "{what}: {added}");
    }
}
