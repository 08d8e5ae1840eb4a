//! Baked global illumination: the GPU bake against its f64 twin (the CPU tracer's own paths at the
//! same texels and probes), the light modes' effect on the frame, and the Lighting Modes' shadows.

use crate::common::{cell_params, fixture};
use glam::DVec3;
use shadematrix::declarations::gi::{LightBakeMode, MixedLighting};
use shadematrix::declarations::scene::{Role, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::gi::BakedLighting;
use shadematrix::render::{CellRender, Renderer};
use shadematrix::shading::registry::Sliders;

fn sliders() -> Sliders {
    Sliders { base_color_linear: [0.5; 3], metallic: 0.0, smoothness: 0.3 }
}

fn cornell() -> Scene {
    let mut s = Scene::load_file(&fixture("cornell_gi.toml")).unwrap();
    s.hdrp.bloom = false;
    s.hdrp.ssao = false;
    s
}

/// The GPU bake and the CPU twin's of `scene`'s HDRP Lit cell.
fn bakes(scene: &Scene) -> (std::sync::Arc<BakedLighting>, BakedLighting, Renderer) {
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(scene).unwrap();
    let key = scene.lights[0].intensity;
    let cell = cell_params(Pipeline::Hdrp, "lit", sliders(), (key, 6.0), 32, RenderPath::Forward);
    let gpu = renderer.bake(&prepared, &cell).unwrap().expect("the room bakes");
    let cpu = renderer.bake_on_cpu(&prepared, &cell).unwrap().expect("the room bakes");
    let atlas = prepared.lightmap.clone().unwrap();
    assert_eq!(gpu.lightmap.as_ref().unwrap().width, atlas.width);
    (gpu, cpu, renderer)
}

#[test]
fn a_lightmapped_room_matches_its_traced_light_at_every_wall() {
    let _timer = crate::common::timed!();
    let scene = cornell();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let cell = cell_params(Pipeline::Hdrp, "lit", sliders(), (1.5, 6.0), 32, RenderPath::Forward);
    let gpu = renderer.bake(&prepared, &cell).unwrap().expect("the room bakes");
    let cpu = renderer.bake_on_cpu(&prepared, &cell).unwrap().expect("the room bakes");
    let atlas = prepared.lightmap.as_ref().unwrap();
    let (g, c) = (gpu.lightmap.as_ref().unwrap(), cpu.lightmap.as_ref().unwrap());
    let noise = g.noise.expect("covered texels");
    assert!(noise < 0.1, "the bake's stated noise {noise}");
    let at = |map: &shadematrix::render::gi::lightmaps::Lightmap,
              t: &shadematrix::geometry::lightmap_uv::LightmapTexel| {
        let v = map.irradiance[(t.y * atlas.width + t.x) as usize];
        DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
    };
    // Each wall's mean irradiance: GPU against the f64 twin, within what their noise allows.
    for (i, o) in scene.objects.iter().enumerate().filter(|(_, o)| o.role == Role::Fixed) {
        let texels: Vec<_> = atlas.texels.iter().filter(|t| t.object == i).collect();
        assert!(texels.len() > 40, "{}: {} texels", o.name, texels.len());
        let mean = |m| texels.iter().map(|t| at(m, t)).sum::<DVec3>() / texels.len() as f64;
        let (mg, mc) = (mean(g), mean(c));
        // Per-texel noise ≤ `noise` relative; the mean of n texels of both bakes: √2·noise/√n, ×4.
        let allowed = 4.0 * std::f64::consts::SQRT_2 * noise / (texels.len() as f64).sqrt() + 0.01;
        let rel = (mg - mc).length() / mc.length();
        assert!(rel < allowed, "{}: GPU {mg} vs f64 twin {mc}: {rel:.4} > {allowed:.4}", o.name);
    }
    // Bounced light: the floor takes the red wall's colour beside it and the green's beside that.
    let floor = scene.objects.iter().position(|o| o.name == "floor").unwrap();
    let side = |left: bool| {
        let near: Vec<DVec3> = atlas
            .texels
            .iter()
            .filter(|t| t.object == floor && if left { t.position[0] < -0.6 } else { t.position[0] > 0.6 })
            .map(|t| at(g, t))
            .collect();
        near.iter().sum::<DVec3>() / near.len() as f64
    };
    let (l, r) = (side(true), side(false));
    assert!(l.x / l.y > 1.05 * r.x / r.y, "red bleed: left {l}, right {r}");
    assert!(r.y / r.x > 1.05 * l.y / l.x, "green bleed: left {l}, right {r}");
}

#[test]
fn probes_match_an_f64_projection_of_the_traced_radiance() {
    let _timer = crate::common::timed!();
    // Many samples per probe, few texels, one bounce: a second bounce off the ceiling right under
    // the light is heavy-tailed (measured: 10–35 % apart at 4096 samples between two estimates
    // of it), the first is not. The lightmap test checks two bounces, averaged over walls.
    let mut scene = cornell();
    let gi = scene.gi.as_mut().unwrap();
    (gi.samples, gi.texels_per_unit, gi.bounces) = (4096, 1.0, 1);
    let (gpu, cpu, _) = bakes(&scene);
    let (g, c) = (gpu.probes.as_ref().unwrap(), cpu.probes.as_ref().unwrap());
    assert_eq!(g.len(), 8);
    let dirs = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
    for (k, (pg, pc)) in g.iter().zip(c).enumerate() {
        let scale = dirs.iter().map(|d| shadematrix::environment::sh::eval(&pc.sh, *d).length()).fold(0.0, f64::max);
        for d in dirs {
            let (eg, ec) =
                (shadematrix::environment::sh::eval(&pg.sh, d), shadematrix::environment::sh::eval(&pc.sh, d));
            assert!((eg - ec).length() < 0.06 * scale, "probe {k} towards {d}: GPU {eg} vs f64 {ec}");
        }
        // The light is above every probe: more light arrives from above than from below.
        assert!(
            shadematrix::environment::sh::eval(&pg.sh, DVec3::Y).x
                > shadematrix::environment::sh::eval(&pg.sh, -DVec3::Y).x
        );
    }
}

/// The HDRP Lit frame of `scene` (linear RGBA).
fn frame(renderer: &mut Renderer, scene: &Scene, pipeline: Pipeline, shader: &str) -> Vec<f32> {
    rendered(renderer, scene, pipeline, shader).hdr
}

fn rendered(renderer: &mut Renderer, scene: &Scene, pipeline: Pipeline, shader: &str) -> CellRender {
    let prepared = renderer.prepare_scene(scene).unwrap();
    let key = scene.lights[scene.key_light().unwrap()].intensity;
    let cell = cell_params(pipeline, shader, sliders(), (key, 6.0), 64, RenderPath::Forward);
    renderer.render(&prepared, &cell, 1, 0).unwrap()
}

#[test]
fn an_indirect_multiplier_of_zero_equals_the_realtime_cell() {
    let _timer = crate::common::timed!();
    // A mixed light under Baked Indirect, black sky: with no bounced light the bake holds nothing,
    // and the frame is the real-time one to the bit; with bounces it is not.
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let mut realtime = cornell();
    realtime.gi = None;
    realtime.lights[0].mode = LightBakeMode::Realtime;
    let mut mixed = cornell();
    mixed.lights[0].mode = LightBakeMode::Mixed;
    mixed.gi.as_mut().unwrap().mixed_lighting = MixedLighting::BakedIndirect;
    mixed.lights[0].indirect_multiplier = 0.0;
    for (p, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Hdrp, "lit")] {
        let a = frame(&mut renderer, &realtime, p, shader);
        let b = frame(&mut renderer, &mixed, p, shader);
        assert!(a == b, "{}: a mixed light with indirect multiplier 0 changed the frame", p.name());
        let mut bouncing = mixed.clone();
        bouncing.lights[0].indirect_multiplier = 1.0;
        let c = frame(&mut renderer, &bouncing, p, shader);
        let (sa, sc): (f64, f64) = (a.iter().map(|&v| v as f64).sum(), c.iter().map(|&v| v as f64).sum());
        assert!(sc > sa * 1.05, "{}: bounced light adds nothing ({sa} vs {sc})", p.name());
    }
}

/// The default room lit by one mixed directional light under a black sky, its reflection probe
/// left out: the static objects' light is the sun's, real-time or baked.
fn mixed_sun_room() -> Scene {
    let mut scene = Scene::load("default", None, "t", "k").unwrap();
    scene.lights = vec![scene.lights[0].clone()];
    let l = &mut scene.lights[0];
    l.kind = shadematrix::declarations::scene::LightKind::Directional;
    l.direction = [-0.4, -0.8, -0.45];
    l.intensity = 1.0;
    l.mode = LightBakeMode::Mixed;
    scene.environment.sky = shadematrix::declarations::scene::Sky::Constant { color: [0.0; 3] };
    scene.environment.reflections = shadematrix::declarations::scene::Reflections::Sky;
    scene.probes.clear();
    scene
}

/// A static box of `size` centred at `at`, in the material of `scene`'s first fixed object.
fn static_box(scene: &Scene, name: &str, size: [f64; 3], at: [f64; 3]) -> shadematrix::declarations::scene::Object {
    let mut o = scene.objects.iter().find(|o| o.role == Role::Fixed).unwrap().clone();
    o.name = name.into();
    o.mesh = toml::from_str(&format!("kind = \"box\"\nsize = {size:?}")).unwrap();
    o.transform = toml::from_str(&format!("translate = {at:?}")).unwrap();
    o
}

#[test]
fn subtractive_and_shadowmask_differ_where_dynamic_shadows_fall_on_static_objects() {
    let _timer = crate::common::timed!();
    // The default room under a mixed directional light: Subtractive bakes the light into the
    // static objects' lightmaps and darkens them towards the Realtime Shadow Color where a dynamic
    // object's real-time shadow falls; Shadowmask draws it in real time with baked static
    // occlusion. On the static objects they agree (to the lightmap's resolution) outside the
    // dynamic shadows and part inside them.
    let mut base = mixed_sun_room();
    base.gi = Some(toml::from_str("texels_per_unit = 8\nsamples = 96\nbounces = 1").unwrap());
    let with = |mode: MixedLighting, subjects_cast: bool| {
        let mut s = base.clone();
        s.gi.as_mut().unwrap().mixed_lighting = mode;
        for o in s.objects.iter_mut().filter(|o| o.role == Role::Subject) {
            o.cast_shadows = subjects_cast;
        }
        s
    };
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    // The unshadowed frame's bake is the shadowmask one's (the subjects are dynamic): read back.
    let cache = tempfile::tempdir().unwrap();
    renderer.bake_cache = Some(shadematrix::render::gi::cache::BakeCache::new(cache.path().into()));
    let (p, shader) = (Pipeline::Urp, "lit");
    let sub = frame(&mut renderer, &with(MixedLighting::Subtractive, true), p, shader);
    let shadowmask = rendered(&mut renderer, &with(MixedLighting::Shadowmask, true), p, shader);
    let (mask, roles) = (shadowmask.hdr, shadowmask.roles);
    let unshadowed = frame(&mut renderer, &with(MixedLighting::Shadowmask, false), p, shader);
    let lum = |img: &[f32], i: usize| {
        0.2126 * img[4 * i] as f64 + 0.7152 * img[4 * i + 1] as f64 + 0.0722 * img[4 * i + 2] as f64
    };
    let (mut outside, mut inside) = (Vec::new(), Vec::new());
    for (i, role) in roles.iter().enumerate() {
        if *role != shadematrix::render::uniforms::ROLE_FIXED {
            continue;
        }
        let dynamic_shadow = lum(&mask, i) < 0.7 * lum(&unshadowed, i);
        let rel = (lum(&sub, i) - lum(&mask, i)).abs() / lum(&mask, i).max(1e-3);
        if dynamic_shadow {
            inside.push(rel)
        } else {
            outside.push(rel)
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    assert!(
        inside.len() > 20 && outside.len() > 1000,
        "{} pixels in dynamic shadow, {} outside",
        inside.len(),
        outside.len()
    );
    assert!(mean(&outside) < 0.08, "outside the dynamic shadows the modes differ by {:.3}", mean(&outside));
    assert!(mean(&inside) > 3.0 * mean(&outside), "inside {:.3} vs outside {:.3}", mean(&inside), mean(&outside));
}

#[test]
fn cells_share_a_bake_within_a_run_and_across_runs_and_list_counts_them() {
    let _timer = crate::common::timed!();
    // Two presets in one run share the room's bake (the subject is dynamic, so its material
    // cannot change the lightmaps): the first cell makes it, the second reads it. A later run's
    // new cell reads it from the cache beside the runs.
    let dir = tempfile::tempdir().unwrap();
    let mut scene = std::fs::read_to_string(fixture("cornell_gi.toml")).unwrap();
    scene = scene.replace("texels_per_unit = 4", "texels_per_unit = 2").replace("samples = 128", "samples = 16");
    std::fs::write(dir.path().join("room.toml"), scene).unwrap();
    let body = |presets: &str| {
        format!(
            "name = \"bakes\"\ncompositions = [\"room.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [{presets}]\n[image]\nwidth = 32\nheight = 24\n"
        )
    };
    let bakes = |run: &std::path::Path| -> Vec<(bool, bool)> {
        let mut out = Vec::new();
        for entry in std::fs::read_dir(run.join("cells")).unwrap() {
            let record: serde_json::Value =
                serde_json::from_slice(&std::fs::read(entry.unwrap().path().join("cell.json")).unwrap()).unwrap();
            let b = &record["bake"];
            out.push((b["made"].as_bool().unwrap(), b["cached"].as_bool().unwrap()));
        }
        out.sort();
        out
    };
    let m = crate::common::write_matrix(dir.path(), "list.toml", &body("\"plastic\", \"gold\""));
    let (code, listed, err) = crate::common::shadematrix(dir.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
    assert!(listed.contains("bakes: 1 for its 2 rendered cells"), "{listed}");
    let first = crate::common::run_matrix(dir.path(), &body("\"plastic\", \"gold\""), "a");
    assert_eq!(bakes(&first), [(false, false), (true, false)]);
    let second = crate::common::run_matrix(dir.path(), &body("\"rubber\""), "b");
    assert_eq!(bakes(&second), [(true, true)]);
}

#[test]
fn the_baked_falloffs_match_their_twins() {
    let _timer = crate::common::timed!();
    use shadematrix::pipelines::BakedFalloff;
    let source =
        crate::common::pair_kernel("vec4<f32>(baked_distance_attenuation(a.x > 0.5, a.y, a.z), 0.0, 0.0, 0.0)");
    let mut cases = Vec::new();
    for falloff in [BakedFalloff::Legacy, BakedFalloff::InverseSquared] {
        for range in [0.5, 6.0, 40.0] {
            for x in [0.0005, 0.01, 0.2, 0.5, 0.79, 0.8, 0.85, 0.95, 0.999, 1.0, 1.3] {
                cases.push((falloff, x * range, range));
            }
        }
    }
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|(f, d, r)| [[(*f == BakedFalloff::Legacy) as u32 as f32, *d as f32, *r as f32, 0.0], [0.0; 4]])
        .collect();
    let gpu = GpuContext::new().unwrap();
    let got = crate::common::run_kernel(&gpu, &source, &inputs, cases.len(), &[]);
    for ((f, d, r), g) in cases.iter().zip(&got) {
        let want = f.eval(*d, *r);
        let err = (g[0] as f64 - want).abs();
        assert!(err <= 2e-6 * want.max(1.0), "{f:?} at d {d} of range {r}: GPU {} vs twin {want}", g[0]);
    }
    // The curves differ: Legacy is normalised to the range, inverse square is not.
    assert!(BakedFalloff::Legacy.eval(1.0, 6.0) > 0.4 && BakedFalloff::InverseSquared.eval(1.0, 6.0) > 0.9);
}

#[test]
fn deferred_paths_read_the_shadow_mask_and_leave_subtractives_main_light_to_the_lightmap() {
    let _timer = crate::common::timed!();
    // The default room under a mixed directional light, with a static pillar whose shadow on the
    // floor is baked (the light's shadow map holds the dynamic objects alone). URP's deferred path
    // reads the baked occlusion from its shadow-mask G-buffer and, under Subtractive, leaves the
    // main light off lightmapped pixels: its static objects match the forward frame's. Built-in's
    // deferred lighting has no lightmapped flag and draws the light over the lightmap there.
    let mut scene = mixed_sun_room();
    let pillar = static_box(&scene, "pillar", [0.5, 2.4, 0.5], [0.2, 1.2, -1.6]);
    scene.objects.push(pillar);
    // Both paths of a mode read one bake, so its noise is common to the frames compared.
    scene.gi = Some(toml::from_str("texels_per_unit = 8\nsamples = 32\nnoise = 0\nbounces = 1").unwrap());
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let lum = |img: &[f32], i: usize| {
        0.2126 * img[4 * i] as f64 + 0.7152 * img[4 * i + 1] as f64 + 0.0722 * img[4 * i + 2] as f64
    };
    for (mode, p, shader) in [
        (MixedLighting::Shadowmask, Pipeline::Urp, "lit"),
        (MixedLighting::Subtractive, Pipeline::Urp, "lit"),
        (MixedLighting::Subtractive, Pipeline::Builtin, "standard"),
    ] {
        let mut s = scene.clone();
        s.gi.as_mut().unwrap().mixed_lighting = mode;
        let prepared = renderer.prepare_scene(&s).unwrap();
        let mut frames = Vec::new();
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let cell = cell_params(p, shader, sliders(), (1.0, 10.0), 64, path);
            frames.push(renderer.render(&prepared, &cell, 1, 0).unwrap());
        }
        let (fwd, def) = (&frames[0], &frames[1]);
        let fixed: Vec<usize> =
            (0..fwd.roles.len()).filter(|&i| fwd.roles[i] == shadematrix::render::uniforms::ROLE_FIXED).collect();
        let apart = fixed
            .iter()
            .filter(|&&i| (lum(&def.hdr, i) - lum(&fwd.hdr, i)).abs() > 0.15 * lum(&fwd.hdr, i).max(1e-3))
            .count();
        let share = apart as f64 / fixed.len() as f64;
        let brighter =
            fixed.iter().map(|&i| lum(&def.hdr, i) / lum(&fwd.hdr, i).max(1e-3)).sum::<f64>() / fixed.len() as f64;
        let what = format!(
            "{} {}: {apart} of {} static pixels apart, deferred/forward {brighter:.3}",
            p.name(),
            mode.name(),
            fixed.len()
        );
        eprintln!("{what}");
        if p == Pipeline::Urp {
            assert!(share < 0.02 && (brighter - 1.0).abs() < 0.05, "{what}");
        } else {
            assert!(brighter > 1.3, "{what}");
        }
    }
}

#[test]
fn a_dynamic_objects_further_lod_levels_read_its_probe() {
    let _timer = crate::common::timed!();
    // The Cornell room's light is baked and it opens on a grey sky: the dynamic ball's ambient is
    // the probes', which hold the sky's light. Drawn at its second LOD level it reads the same
    // (before: the probe plus the sky's SH again).
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let mut scene = cornell();
    scene.environment.sky = shadematrix::declarations::scene::Sky::Constant { color: [0.3; 3] };
    let lum = |img: &[f32], roles: &[u8]| {
        let px: Vec<usize> =
            (0..roles.len()).filter(|&i| roles[i] == shadematrix::render::uniforms::ROLE_SUBJECT).collect();
        let sum: f64 = px
            .iter()
            .map(|&i| 0.2126 * img[4 * i] as f64 + 0.7152 * img[4 * i + 1] as f64 + 0.0722 * img[4 * i + 2] as f64)
            .sum();
        (sum / px.len().max(1) as f64, px.len())
    };
    let mut seen = Vec::new();
    // Level 0 above a screen height of 0.9 (never here), level 1 down to 0.001: the ball's
    // second level is drawn; then the same mesh as the ball's only level.
    for lod in [true, false] {
        let ball = scene.objects.iter_mut().find(|o| o.name == "ball").unwrap();
        ball.lod = lod.then(|| {
            toml::from_str(
                "meshes = [{ kind = \"uv_sphere\", radius = 0.25, rings = 12, segments = 24 }]\ntransitions = [0.9, 0.001]",
            )
            .unwrap()
        });
        if !lod {
            ball.mesh = toml::from_str("kind = \"uv_sphere\"\nradius = 0.25\nrings = 12\nsegments = 24").unwrap();
        }
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let cell = cell_params(Pipeline::Urp, "lit", sliders(), (1.5, 6.0), 64, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        seen.push(lum(&r.hdr, &r.roles));
    }
    let ((at_level_1, n1), (alone, n)) = (seen[0], seen[1]);
    assert!(n1 > 20 && n > 20, "ball pixels: {n1}, {n}");
    assert!(alone > 0.0, "the probe lights the ball");
    assert!((at_level_1 - alone).abs() < 0.02 * alone, "LOD 1 {at_level_1} vs the same mesh alone {alone}");
}

#[test]
fn lightmap_encodings_decode_to_the_same_light() {
    let _timer = crate::common::timed!();
    // The Cornell room's URP frame with its lightmap stored at each Lightmap Encoding quality:
    // double LDR, RGBM and half floats decode to the same light within their 8-bit steps, where
    // the light stays inside double LDR's range (the ceiling over the lamp clips at 4.59, as
    // Unity's would). HDRP keeps High Quality whatever is asked.
    use shadematrix::declarations::gi::LightmapQuality;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let mut frames = Vec::new();
    for q in [LightmapQuality::Low, LightmapQuality::Normal, LightmapQuality::High] {
        let mut scene = cornell();
        scene.gi.as_mut().unwrap().encoding = Some(q);
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let cell = cell_params(Pipeline::Urp, "lit", sliders(), (1.5, 6.0), 48, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        assert_eq!(r.bake.as_ref().unwrap().encoding, ["dldr", "rgbm", "hdr"][frames.len()]);
        frames.push(r.hdr);
    }
    let high = &frames[2];
    let peak = high.iter().cloned().fold(0.0f32, f32::max) as f64;
    assert!(peak > 0.05, "the room is lit: peak {peak}");
    let clipped = frames[0].iter().zip(high).filter(|(a, b)| (**a as f64 - **b as f64).abs() > 0.5).count();
    assert!(clipped > 0, "double LDR clips the brightest texels");
    let inside: Vec<usize> = (0..high.len() / 4).filter(|&i| high[4 * i..4 * i + 3].iter().all(|v| *v < 2.0)).collect();
    assert!(inside.len() > high.len() / 8, "{} of {} pixels in range", inside.len(), high.len() / 4);
    for (name, f) in ["dldr", "rgbm"].iter().zip(&frames[..2]) {
        let mut d: Vec<f64> = inside
            .iter()
            .flat_map(|&i| (0..3).map(move |k| 4 * i + k))
            .map(|k| {
                let delta = (f[k] as f64 - high[k] as f64).abs();
                // RGBM's step scales with the texel's multiplier: compared relative to the light
                if *name == "rgbm" {
                    delta / (high[k] as f64 + 0.02)
                } else {
                    delta
                }
            })
            .collect();
        d.sort_by(f64::total_cmp);
        let (mean, p99) = (d.iter().sum::<f64>() / d.len() as f64, d[d.len() * 99 / 100]);
        eprintln!("{name}: mean {mean:.2e}, 99th percentile {p99:.2e} against half floats");
        // Double LDR within one 8-bit step of its range (4.59/255); RGBM within a few steps of
        // its multiplier (bilinear reads blend encoded texels, as the engines' do).
        let (p99_bound, mean_bound) = if *name == "rgbm" { (0.1, 0.02) } else { (4.59 / 255.0, 0.25 * 4.59 / 255.0) };
        assert!(p99 < p99_bound && mean < mean_bound, "{name}: mean {mean}, 99th percentile {p99}");
    }
    let mut scene = cornell();
    scene.gi.as_mut().unwrap().encoding = Some(LightmapQuality::Low);
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let cell = cell_params(Pipeline::Hdrp, "lit", sliders(), (1.5, 6.0), 32, RenderPath::Forward);
    let (plan, r) = renderer.render_planned(&prepared, &cell, 1, 0).unwrap();
    assert_eq!(r.bake.unwrap().encoding, "hdr");
    assert!(plan.gi.unwrap().encoding_note.is_some());
}

#[test]
fn under_subtractive_static_objects_shadow_dynamic_ones_through_the_probes() {
    let _timer = crate::common::timed!();
    // A static roof over the sun-lit room: the main light's shadow map holds the dynamic objects
    // alone (Subtractive, Shadowmask), so the subjects under the roof are shadowed by the probes'
    // occlusion of the sun or not at all. Subtractive (the engine scales the light by it) and
    // Shadowmask (min with the shadow mask's probe channel) agree on them; without a roof the
    // subjects take the sun.
    let mut scene = mixed_sun_room();
    let roof = static_box(&scene, "roof", [8.0, 0.2, 6.0], [0.0, 3.5, 0.0]);
    scene.gi = Some(
        toml::from_str(
            "texels_per_unit = 2\nsamples = 32\nnoise = 0\nbounces = 1\nprobes = { min = [-3.5, 0.3, -2.5], max = [3.5, 3.0, 2.5], counts = [3, 2, 3] }",
        )
        .unwrap(),
    );
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let subject_light = |renderer: &mut Renderer, s: &Scene, p: Pipeline, shader: &str, path: RenderPath| {
        let prepared = renderer.prepare_scene(s).unwrap();
        let cell = cell_params(p, shader, sliders(), (1.0, 10.0), 48, path);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let px: Vec<usize> =
            (0..r.roles.len()).filter(|&i| r.roles[i] == shadematrix::render::uniforms::ROLE_SUBJECT).collect();
        px.iter()
            .map(|&i| {
                0.2126 * r.hdr[4 * i] as f64 + 0.7152 * r.hdr[4 * i + 1] as f64 + 0.0722 * r.hdr[4 * i + 2] as f64
            })
            .sum::<f64>()
            / px.len() as f64
    };
    for (p, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit")] {
        let mut seen = Vec::new();
        for (mode, roofed) in
            [(MixedLighting::Subtractive, true), (MixedLighting::Shadowmask, true), (MixedLighting::Subtractive, false)]
        {
            let mut s = scene.clone();
            s.gi.as_mut().unwrap().mixed_lighting = mode;
            if roofed {
                s.objects.push(roof.clone());
            }
            seen.push(subject_light(&mut renderer, &s, p, shader, RenderPath::Forward));
            if p == Pipeline::Urp && mode == MixedLighting::Subtractive {
                // URP's deferred lighting reads the probe's occlusion from the shadow-mask G-buffer
                let deferred = subject_light(&mut renderer, &s, p, shader, RenderPath::Deferred);
                let forward = seen[seen.len() - 1];
                assert!((deferred - forward).abs() < 0.1 * forward, "urp deferred {deferred} vs forward {forward}");
            }
        }
        let [subtractive, shadowmask, open] = [seen[0], seen[1], seen[2]];
        eprintln!(
            "{}: subjects under the roof {subtractive:.4} (subtractive), {shadowmask:.4} (shadowmask); open {open:.4}",
            p.name()
        );
        assert!((subtractive - shadowmask).abs() < 0.1 * shadowmask, "{}: {subtractive} vs {shadowmask}", p.name());
        assert!(open > 2.0 * subtractive, "{}: the roof's probe shadow: open {open} vs roofed {subtractive}", p.name());
    }
}

/// Shadowmask on a dynamic object: built-in's forward passes attenuate the light's colour by the
/// object's probe occlusion on the CPU (UnityShadowLibrary.cginc UnitySampleBakedOcclusion: "light
/// probe occlusion is done on the CPU by attenuating the light color"), so a real-time shadow of
/// strength 0.5 on it halves what the probe left: the product. URP takes min(real-time, baked)
/// (MixRealtimeAndBakedShadows), so where the probe's occlusion is already at or below the
/// real-time shadow's, the shadow adds nothing.
#[test]
fn builtins_forward_multiplies_a_dynamic_objects_shadow_by_its_probe_occlusion() {
    let _timer = crate::common::timed!();
    let scene = |sphere_casts: bool| {
        let text = format!(
            r#"
name = "probe_occlusion"
[camera]
position = [1.5, 5.0, 3.0]
target = [1.5, 0.8, 0.0]
fov_y_deg = 40.0
[[lights]]
kind = "directional"
direction = [0.0, -1.0, 0.0001]
intensity = 1.0
shadows = true
shadow = {{ strength = 0.5 }}
key = true
mode = "mixed"
[[objects]]
name = "box"
role = "subject"
mesh = {{ kind = "box", size = [1.0, 1.0, 1.0] }}
transform = {{ translate = [1.5, 0.5, 0.0] }}
[[objects]]
name = "ball"
role = "subject"
cast_shadows = {sphere_casts}
mesh = {{ kind = "uv_sphere", radius = 0.4, rings = 16, segments = 32 }}
transform = {{ translate = [1.5, 2.0, 0.0] }}
[[objects]]
name = "floor"
role = "fixed"
mesh = {{ kind = "plane", size = [12.0, 12.0], subdivisions = 2 }}
material = {{ base_color_linear = [0.5, 0.5, 0.5], smoothness = 0.0 }}
[[objects]]
name = "roof"
role = "fixed"
mesh = {{ kind = "box", size = [6.0, 0.2, 12.0] }}
transform = {{ translate = [-1.9, 4.0, 0.0] }}
material = {{ base_color_linear = [0.5, 0.5, 0.5], smoothness = 0.0 }}
[environment]
sky = {{ kind = "constant", color = [0.0, 0.0, 0.0] }}
ambient_intensity = 0.0
background = false
[gi]
mixed_lighting = "shadowmask"
bounces = 0
texels_per_unit = 2
samples = 16
noise = 0
probes = {{ min = [0.0, 0.3, -3.0], max = [3.0, 3.0, 3.0], counts = [2, 2, 2] }}
"#
        );
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), text).unwrap();
        Scene::load_file(&tmp.path().join("s.toml")).unwrap()
    };
    let (cast, uncast) = (scene(true), scene(false));
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let mut subject = |s: &Scene, p: Pipeline, shader: &str| {
        let prepared = renderer.prepare_scene(s).unwrap();
        let cell = cell_params(p, shader, sliders(), (1.0, 10.0), 96, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let luma = |i: usize| {
            0.2126 * r.hdr[4 * i] as f64 + 0.7152 * r.hdr[4 * i + 1] as f64 + 0.0722 * r.hdr[4 * i + 2] as f64
        };
        (0..r.roles.len())
            .map(|i| (r.roles[i] == shadematrix::render::uniforms::ROLE_SUBJECT).then(|| luma(i)))
            .collect::<Vec<_>>()
    };
    // The box's top under the ball's real-time shadow: subject pixels the ball's cast darkens.
    for (p, shader, product) in [(Pipeline::Builtin, "standard", true), (Pipeline::Urp, "lit", false)] {
        let (a, b) = (subject(&cast, p, shader), subject(&uncast, p, shader));
        let lit = b.iter().flatten().cloned().fold(0.0, f64::max);
        let ratios: Vec<f64> = a
            .iter()
            .zip(&b)
            .filter_map(|(x, y)| match (x, y) {
                (Some(x), Some(y)) if *y > 0.1 * lit => Some(x / y),
                _ => None,
            })
            .collect();
        let darkened: Vec<f64> = ratios.iter().cloned().filter(|r| *r < 0.9).collect();
        let mean = darkened.iter().sum::<f64>() / darkened.len().max(1) as f64;
        eprintln!(
            "{}: {} of {} lit subject pixels darkened by the ball's shadow, mean ratio {mean:.3}",
            p.name(),
            darkened.len(),
            ratios.len()
        );
        if product {
            assert!(darkened.len() > 40, "{}: the ball's shadow on the box ({} pixels)", p.name(), darkened.len());
            assert!((mean - 0.5).abs() < 0.1, "{}: strength 0.5 times the probe's occlusion: {mean}", p.name());
        } else {
            assert!(
                darkened.len() < 10,
                "{}: min with the probe's occlusion hides it ({} pixels)",
                p.name(),
                darkened.len()
            );
        }
    }
}

/// Under Shadowmask a static object's shadow of a mixed light lives in the bake alone (the
/// light's real-time map draws the dynamic casters): a bake whose lights carry no baked light
/// (indirect multiplier 0, black sky) must still bake the shadow mask, or the static shadows vanish.
#[test]
fn a_shadow_mask_is_baked_when_nothing_else_is() {
    let _timer = crate::common::timed!();
    let text = |multiplier: f64| {
        format!(
            r#"
name = "mask_only"
[camera]
position = [0.0, 8.0, 0.001]
target = [0.0, 0.0, 0.0]
fov_y_deg = 50.0
[[lights]]
kind = "directional"
direction = [1.0, -1.0, 0.0]
intensity = 1.0
shadows = true
key = true
mode = "mixed"
indirect_multiplier = {multiplier}
[[objects]]
name = "ball"
role = "subject"
mesh = {{ kind = "uv_sphere", radius = 0.3, rings = 12, segments = 24 }}
transform = {{ translate = [0.0, 0.3, -3.0] }}
[[objects]]
name = "floor"
role = "fixed"
mesh = {{ kind = "plane", size = [8.0, 8.0], subdivisions = 2 }}
material = {{ base_color_linear = [0.5, 0.5, 0.5], smoothness = 0.0 }}
[[objects]]
name = "roof"
role = "fixed"
mesh = {{ kind = "box", size = [4.0, 0.2, 8.0] }}
transform = {{ translate = [-3.0, 3.0, 0.0] }}
material = {{ base_color_linear = [0.5, 0.5, 0.5], smoothness = 0.0 }}
[environment]
sky = {{ kind = "constant", color = [0.0, 0.0, 0.0] }}
ambient_intensity = 0.0
background = false
[gi]
mixed_lighting = "shadowmask"
bounces = 0
texels_per_unit = 2
samples = 16
noise = 0
"#
        )
    };
    let tmp = tempfile::tempdir().unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    // Seen from 8 m above (the floor spans x ∈ ±3.73 m), the sun at 45° throws the roof's shadow
    // (x ∈ [-5, -1] at 3 m) onto x ∈ [-2, 2]: the floor's mean green at x ∈ (0, 1), columns
    // 50–63, and in the open at x ∈ (2.5, 3.3), columns 84–94.
    let mut floor = |multiplier: f64| {
        std::fs::write(tmp.path().join("s.toml"), text(multiplier)).unwrap();
        let scene = Scene::load_file(&tmp.path().join("s.toml")).unwrap();
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let cell = cell_params(Pipeline::Builtin, "standard", sliders(), (1.0, 10.0), 100, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let mean = |x0: usize, x1: usize| {
            let px: Vec<f64> =
                (40..60).flat_map(|y| (x0..x1).map(move |x| y * 100 + x)).map(|i| r.hdr[4 * i + 1] as f64).collect();
            px.iter().sum::<f64>() / px.len() as f64
        };
        (mean(50, 63), mean(84, 94))
    };
    for multiplier in [1.0, 0.0] {
        let (under, open) = floor(multiplier);
        eprintln!("indirect multiplier {multiplier}: floor under the roof {under:.4}, in the open {open:.4}");
        assert!(open > 0.05, "the sun lights the open floor");
        assert!(under < 0.2 * open, "multiplier {multiplier}: the roof's baked shadow ({under} against {open})");
    }
}

/// Built-in and URP bake area lights only (Unity's Area Light is Baked): in a scene with baked
/// lighting the rectangle reaches their frames through the lightmaps and probes, where without a
/// bake the frame leaves it out (Figs 3.2/3.3). HDRP draws it in real time either way.
#[test]
fn a_baked_area_light_reaches_built_in_and_urp_frames() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let mut baked = cornell();
    let light = &mut baked.lights[0];
    light.kind = shadematrix::declarations::scene::LightKind::Rect;
    light.mode = LightBakeMode::Realtime;
    light.direction = [0.0, -1.0, 0.0];
    light.size = Some([0.6, 0.6]);
    let mut unbaked = baked.clone();
    unbaked.gi = None;
    for (p, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit")] {
        let sum = |f: Vec<f32>| f.chunks(4).map(|px| px[..3].iter().map(|&v| v as f64).sum::<f64>()).sum::<f64>();
        let (with, without) =
            (sum(frame(&mut renderer, &baked, p, shader)), sum(frame(&mut renderer, &unbaked, p, shader)));
        eprintln!("{}: frame sum {with:.1} with the bake, {without:.1} without (black sky)", p.name());
        assert!(with > 20.0 * without.max(1e-3), "{}: the baked rectangle does not reach the frame", p.name());
    }
}
