//! Image skies (`Sky::Image`, input::sky_image): the shipped stylized sky is its bake, an image
//! sky's SH is the projection of its texels, and a constant-colour image sky lights a cell and its
//! truth exactly as the constant sky does.

use glam::DVec3;
use shadematrix::declarations::scene::Scene;
use shadematrix::environment::{sh, stylized_sky, EnvironmentMaps};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::render::truth::TruthSettings;
use shadematrix::shading::registry::Sliders;

const DEFAULT_SKY: &str = "sky = { kind = \"gradient\", sky = [0.212, 0.227, 0.259], equator = [0.114, 0.125, 0.133], ground = [0.047, 0.043, 0.035] }";

/// The default composition with another sky line, written beside `files` in `dir`.
fn default_with_sky(dir: &std::path::Path, name: &str, sky: &str) -> Scene {
    let text = std::fs::read_to_string(crate::common::repo().join("scenes/default.toml")).unwrap();
    assert!(text.contains(DEFAULT_SKY));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text.replace(DEFAULT_SKY, sky).replace("name = \"default\"", &format!("name = \"{name}\"")))
        .unwrap();
    Scene::load_file(&path).unwrap()
}

#[test]
fn the_shipped_stylized_sky_is_its_bake() {
    let _timer = crate::common::timed!();
    let bytes = std::fs::read(crate::common::repo().join("scenes/skies/stylized.exr")).unwrap();
    let shipped = shadematrix::input::sky_image::read_bytes(&bytes, "exr").unwrap();
    let baked = stylized_sky::bake(stylized_sky::WIDTH, stylized_sky::HEIGHT);
    assert_eq!((shipped.width, shipped.height), (stylized_sky::WIDTH, stylized_sky::HEIGHT));
    // 16-bit channels: within half a unit in the last place (2⁻¹¹ relative).
    for (s, b) in shipped.texels.iter().zip(&baked) {
        for c in 0..3 {
            assert!((s[c] - b[c]).abs() <= b[c].abs() * 4.9e-4 + 1e-7, "{s:?} against {b:?}");
        }
    }
}

/// The SH the renderer's ambient reads (`EnvironmentMaps`: the image resampled bilinearly at
/// SOURCE_WIDTH, then projected) against a projection of the image's own texels in f64.
#[test]
fn an_image_skys_sh_is_the_projection_of_its_texels() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let sky = crate::common::repo().join("scenes/skies/stylized.exr");
    let scene = default_with_sky(
        tmp.path(),
        "stylized",
        &format!("sky = {{ kind = \"image\", path = {:?} }}", sky.display().to_string()),
    );
    let image = shadematrix::input::sky_image::read_file(&sky).unwrap();
    let texel = |d: DVec3| {
        let [u, v] = shadematrix::environment::dir_to_uv(d);
        let x = ((u * image.width as f64) as usize).min(image.width - 1);
        let y = ((v * image.height as f64) as usize).min(image.height - 1);
        DVec3::from(image.texels[y * image.width + x].map(f64::from))
    };
    let want = sh::project(&texel, 1024);
    let got = EnvironmentMaps::build(&scene.environment).sh;
    let scale = want[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = (0..9)
        .flat_map(|i| (0..3).map(move |c| (i, c)))
        .map(|(i, c)| (got[i][c] - want[i][c]).abs())
        .fold(0.0, f64::max);
    eprintln!("stylized sky SH: worst coefficient difference {:.2e} of L0 {scale:.4}", worst);
    assert!(worst < 5e-4 * scale, "{got:?} against {want:?}");
    // And it is not the default sky's: the image reached the ambient.
    let gradient = EnvironmentMaps::build(&Scene::load("default", None, "test", "composition").unwrap().environment).sh;
    assert!((gradient[0][2] - got[0][2]).abs() > 0.1 * scale);
}

/// A constant-colour image sky is the constant sky: the real-time cell (ambient SH, probe) and its
/// physical truth (importance-sampled sky) agree with the constant sky's.
#[test]
fn a_constant_image_sky_lights_like_the_constant_sky() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let srgb = [0.4, 0.5, 0.7];
    let linear: Vec<f32> = srgb.iter().map(|&c| shadematrix::color::srgb_to_linear(c) as f32).collect();
    let px: Vec<f32> = (0..32 * 16).flat_map(|_| [linear[0], linear[1], linear[2], 1.0]).collect();
    std::fs::write(tmp.path().join("flat.exr"), shadematrix::images::encode::exr_bytes(32, 16, &px).unwrap()).unwrap();
    let image = default_with_sky(tmp.path(), "flat", "sky = { kind = \"image\", path = \"flat.exr\" }");
    let constant =
        default_with_sky(tmp.path(), "constant", &format!("sky = {{ kind = \"constant\", color = {srgb:?} }}"));
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.5, 0.5, 0.5], metallic: 0.0, smoothness: 0.6 };
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", sliders, (2.0, 10.0), 48, RenderPath::Forward);
    let settings = TruthSettings {
        kind: shadematrix::declarations::matrix::TruthKind::Physical,
        spp: 32,
        noise: 0.0,
        bounces: 1,
        ..Default::default()
    };
    let mut frame = |scene: &Scene| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let hdr = renderer.render(&prepared, &cell, 1, 0).unwrap().hdr;
        (hdr, renderer.render_truth(&prepared, &cell, &settings).unwrap())
    };
    let ((a, ta), (b, tb)) = (frame(&image), frame(&constant));
    let peak = b.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
    eprintln!("constant image sky against the constant sky: real-time worst {:.2e} of peak {peak:.3}", worst);
    assert!(worst < 2e-4 * peak, "real-time cells differ by {worst}");
    let z = ta.mean.iter().zip(&tb.mean).zip(ta.std_error.iter().zip(&tb.std_error)).map(|((x, y), (sx, sy))| {
        let lum = |c: &[f32; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let se = ((*sx as f64).powi(2) + (*sy as f64).powi(2)).sqrt().max(1e-9);
        (lum(x) - lum(y)) / se
    });
    let worst_z = z.fold(0.0f64, |m, v| m.max(v.abs()));
    eprintln!("truths: worst per-pixel |z| {worst_z:.3}");
    assert!(worst_z < 5.0, "the truths differ beyond noise: {worst_z}");
}

/// A sky in nits is physical radiance: HDRP reads it as it is, built-in and URP ÷ 10⁴ (the tool's
/// ratio of their units to HDRP's), so a nits sky of 10⁴·L renders every pipeline as the relative
/// sky of L does, and HDRP's ambient from it equals its texels.
#[test]
fn a_sky_in_nits_is_read_as_physical_radiance() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let write = |name: &str, v: f32| {
        let px: Vec<f32> = (0..32 * 16).flat_map(|_| [v, 0.8 * v, 0.6 * v, 1.0]).collect();
        std::fs::write(tmp.path().join(name), shadematrix::images::encode::exr_bytes(32, 16, &px).unwrap()).unwrap();
    };
    write("relative.exr", 0.5);
    write("nits.exr", 5000.0);
    let relative = default_with_sky(tmp.path(), "relative", "sky = { kind = \"image\", path = \"relative.exr\" }");
    let nits =
        default_with_sky(tmp.path(), "nits", "sky = { kind = \"image\", path = \"nits.exr\", units = \"nits\" }");
    let up = glam::DVec3::Y;
    let hdrp = |s: &Scene| {
        shadematrix::environment::sky::radiance(&s.environment.sky, up)
            * shadematrix::pipelines::Pipeline::Hdrp.environment_scale()
    };
    assert!((hdrp(&nits).x - 5000.0).abs() < 1e-6, "HDRP reads nits as they are: {}", hdrp(&nits));
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.5, 0.5, 0.5], metallic: 0.0, smoothness: 0.6 };
    for pipeline in [Pipeline::Urp, Pipeline::Hdrp] {
        let cell = crate::common::cell_params(pipeline, "lit", sliders, (2.0, 10.0), 32, RenderPath::Forward);
        let mut frame = |scene: &Scene| {
            let prepared = renderer.prepare_scene(scene).unwrap();
            renderer.render(&prepared, &cell, 1, 0).unwrap().hdr
        };
        let (a, b) = (frame(&relative), frame(&nits));
        let peak = a.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
        assert!(worst < 1e-3 * peak, "{pipeline:?}: worst {worst} of {peak}");
    }
}

/// Bad input: a sky image that is missing or not 2:1 is refused naming the key and the file.
#[test]
fn a_missing_or_misshapen_sky_image_is_refused_by_name() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(crate::common::repo().join("scenes/default.toml")).unwrap();
    let missing = tmp.path().join("missing.toml");
    std::fs::write(&missing, text.replace(DEFAULT_SKY, "sky = { kind = \"image\", path = \"nowhere.exr\" }")).unwrap();
    let err = Scene::load_file(&missing).unwrap_err().to_string();
    assert!(err.contains("environment.sky.path") && err.contains("nowhere.exr"), "{err}");
    let px = vec![0.5f32; 16 * 16 * 4];
    std::fs::write(tmp.path().join("square.exr"), shadematrix::images::encode::exr_bytes(16, 16, &px).unwrap())
        .unwrap();
    let square = tmp.path().join("square.toml");
    std::fs::write(&square, text.replace(DEFAULT_SKY, "sky = { kind = \"image\", path = \"square.exr\" }")).unwrap();
    let err = Scene::load_file(&square).unwrap_err().to_string();
    assert!(err.contains("twice as wide") && err.contains("square.exr"), "{err}");
}

/// The default composition under a cube-map sky of six `size`² faces written into `dir` (named
/// `prefix` + px, nx, py, ny, pz, nz), texel (face, x, y) → linear RGB.
fn cube_sky(
    dir: &std::path::Path,
    prefix: &str,
    size: usize,
    texel: impl Fn(usize, usize, usize) -> [f32; 3],
) -> Scene {
    let names = ["px", "nx", "py", "ny", "pz", "nz"].map(|f| format!("{prefix}{f}.exr"));
    for (k, name) in names.iter().enumerate() {
        let px: Vec<f32> = (0..size * size)
            .flat_map(|i| {
                let [r, g, b] = texel(k, i % size, i / size);
                [r, g, b, 1.0]
            })
            .collect();
        let bytes = shadematrix::images::encode::exr_bytes(size as u32, size as u32, &px).unwrap();
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let faces: Vec<String> = names.iter().map(|f| format!("{f:?}")).collect();
    default_with_sky(dir, prefix, &format!("sky = {{ kind = \"cubemap\", faces = [{}] }}", faces.join(", ")))
}

/// A cube-map sky reads its six faces as a `samplerCube` does: the major axis picks the face
/// (+X −X +Y −Y +Z −Z), and within a face s and t follow the OpenGL/Vulkan table (t down the
/// image: +Y is up on the side faces; on the +Y face, +Z is its bottom). Sampled from the stylized
/// equirect sky, it gives that sky's ambient.
#[test]
fn a_cubemap_sky_reads_its_faces_as_a_sampler_cube_does() {
    let _timer = crate::common::timed!();
    use shadematrix::environment::sky::radiance;
    let tmp = tempfile::tempdir().unwrap();
    // Face k: grey 0.1·(k + 1), with its top row (t < 1/8) and left column (s < 1/8) marked.
    let scene = cube_sky(tmp.path(), "marked", 8, |k, x, y| {
        let base = 0.1 * (k + 1) as f32;
        [if y == 0 { 5.0 } else { base }, if x == 0 { 7.0 } else { base }, base]
    });
    let sky = &scene.environment.sky;
    for (k, d) in [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z].into_iter().enumerate() {
        let c = radiance(sky, d);
        assert!((c.z - 0.1 * (k + 1) as f64).abs() < 1e-6, "face {k} along {d}: {c}");
    }
    let t_top = |d: DVec3| radiance(sky, d.normalize()).x > 4.0;
    let s_left = |d: DVec3| radiance(sky, d.normalize()).y > 6.0;
    // +X: t = (−y/|x| + 1)/2 → the top row looks up; s = (−z/|x| + 1)/2 → the left column looks +Z.
    assert!(t_top(DVec3::new(1.0, 0.95, 0.0)) && !t_top(DVec3::new(1.0, -0.95, 0.0)));
    assert!(s_left(DVec3::new(1.0, 0.0, 0.95)) && !s_left(DVec3::new(1.0, 0.0, -0.95)));
    // +Y: t = (z/|y| + 1)/2 → its top row looks −Z; s = (x/|y| + 1)/2 → its left column looks −X.
    assert!(t_top(DVec3::new(0.0, 1.0, -0.95)) && !t_top(DVec3::new(0.0, 1.0, 0.95)));
    assert!(s_left(DVec3::new(-0.95, 1.0, 0.0)));
    // −Z: s = (−x/|z| + 1)/2 → its left column looks +X.
    assert!(s_left(DVec3::new(0.95, 0.0, -1.0)) && !s_left(DVec3::new(-0.95, 0.0, -1.0)));

    // The stylized sky as six 128² faces (each texel the equirect's radiance along its centre)
    // lights the ambient as the equirect does.
    let equirect = default_with_sky(
        tmp.path(),
        "stylized",
        &format!(
            "sky = {{ kind = \"image\", path = {:?} }}",
            crate::common::repo().join("scenes/skies/stylized.exr").display().to_string()
        ),
    );
    let size = 128;
    let cube = cube_sky(tmp.path(), "resampled", size, |k, x, y| {
        let (s, t) = ((x as f64 + 0.5) / size as f64 * 2.0 - 1.0, (y as f64 + 0.5) / size as f64 * 2.0 - 1.0);
        let d = match k {
            0 => DVec3::new(1.0, -t, -s),
            1 => DVec3::new(-1.0, -t, s),
            2 => DVec3::new(s, 1.0, t),
            3 => DVec3::new(s, -1.0, -t),
            4 => DVec3::new(s, -t, 1.0),
            _ => DVec3::new(-s, -t, -1.0),
        };
        let c = radiance(&equirect.environment.sky, d.normalize());
        [c.x as f32, c.y as f32, c.z as f32]
    });
    let (a, b) = (EnvironmentMaps::build(&equirect.environment), EnvironmentMaps::build(&cube.environment));
    for n in [DVec3::Y, DVec3::X, -DVec3::Z, DVec3::new(0.3, -0.8, 0.5).normalize()] {
        let (ea, eb) = (a.ambient_diffuse(n), b.ambient_diffuse(n));
        assert!((ea - eb).abs().max_element() < 0.01 * ea.max_element(), "ambient along {n}: {ea} against {eb}");
    }
}

/// The fifth composition, `composite`: a furnished room under the built-in stylized sky, light
/// enough for lavapipe, with the many lights, shadows and a probe that tell the pipelines apart;
/// every pipeline draws it with the vase (the subject) in view and finite values.
#[test]
fn the_composite_room_loads_and_renders_in_every_pipeline() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::scene::{LightKind, Role, Sky};
    let scene = Scene::load("composite", None, "test", "composition").unwrap();
    let triangles: usize =
        shadematrix::geometry::procedural::build_scene(&scene).unwrap().iter().map(|m| m.triangle_count()).sum();
    let fixed = scene.objects.iter().filter(|o| o.role == Role::Fixed).count();
    eprintln!(
        "composite: {} objects ({fixed} fixed), {triangles} triangles, {} lights",
        scene.objects.len(),
        scene.lights.len()
    );
    assert!(triangles <= 200_000 && fixed >= 40, "{triangles} triangles, {fixed} fixed objects");
    assert!(scene.lights.iter().any(|l| l.kind == LightKind::Directional) && scene.lights.len() >= 4);
    assert!(!scene.probes.is_empty());
    assert!(matches!(&scene.environment.sky, Sky::Image { image: Some(_), .. }), "the built-in stylized sky is read");
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    for (pipeline, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit"), (Pipeline::Hdrp, "lit")] {
        let sliders = Sliders { base_color_linear: [1.0, 0.766, 0.336], metallic: 1.0, smoothness: 0.9 };
        let cell = crate::common::cell_params(pipeline, shader, sliders, (1.5, 6.0), 96, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let subject = r.roles.iter().filter(|&&role| role == 2).count();
        assert!(r.hdr.iter().all(|v| v.is_finite()), "{pipeline:?}: a non-finite value");
        assert!(subject > 50, "{pipeline:?}: the vase covers {subject} pixels");
    }
}
