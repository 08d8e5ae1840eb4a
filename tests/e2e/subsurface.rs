//! HDRP Lit's Subsurface Scattering material type: the screen-space filter on the GPU against its
//! f64 twin on the same buffers, and in rendered frames the split lighting (the type at mask 0
//! draws as Translucent: pre- and post-scatter √albedo multiply back to the albedo) and the blur
//! of the diffuse light across the terminator (SubsurfaceScattering.compute, DiffusionProfile.hlsl).

use crate::common::cell_params;
use glam::DVec3;
use shadematrix::declarations::scene::{Camera, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::images::subsurface::{subsurface_scattering, SubsurfaceBuffers};
use shadematrix::pipelines::{Antialiasing, Pipeline, RenderPath};
use shadematrix::plan::subsurface::{SubsurfacePlan, SAMPLE_BUDGET_MEDIUM};
use shadematrix::plan::Pass;
use shadematrix::render::passes::subsurface::{scattered_of, SubsurfaceFrame};
use shadematrix::render::Renderer;
use shadematrix::shading::diffusion_profile::DiffusionProfile;
use shadematrix::shading::registry::Sliders;
use shadematrix::shading::twin::{SUBSURFACE_MASK_SLOT, SUBSURFACE_SLOT, TRANSMISSION_SLOT};

/// A 96×64 frame through a 10° lens: a plane 0.25 m away tilted across x, a step 3 cm nearer in
/// its right third, a gap of no SSS pixels and bottom rows far away; the light falls off across x
/// with a hard shadow edge, the albedo varies.
fn synthetic(frame: &SubsurfaceFrame) -> (Vec<[f32; 4]>, Vec<[f32; 4]>, Vec<f32>) {
    let (w, h) = (frame.dims[0] as usize, frame.dims[1] as usize);
    let (near, far) = (frame.camera[0] as f64, frame.camera[1] as f64);
    let device = |z: f64| (far * (z - near) / (z * (far - near))) as f32;
    let (mut diffuse, mut albedo, mut depth) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            let u = x as f64 / w as f64;
            let mut z = 0.25 + 0.04 * (u - 0.5) + 0.01 * (y as f64 / h as f64);
            if u > 0.66 {
                z -= 0.03;
            }
            // The bottom rows lie 30 m away, where a pixel spans 9 cm: no sample, the light kept.
            if y >= 60 {
                z = 30.0;
            }
            let gap = (10..14).contains(&y);
            let lit = if u < 0.4 { 2.0 } else { 0.3 } * (1.0 + 0.3 * (y as f64 * 0.2).sin());
            let e = if gap { [0.0; 3] } else { [lit, 0.7 * lit, 0.4 * lit] };
            diffuse.push([e[0] as f32, e[1] as f32, (e[2] as f32).max(if gap { 0.0 } else { 6.1e-5 }), 1.0]);
            albedo.push([0.8, 0.5 + 0.3 * u as f32, 0.3, 1.0]);
            depth.push(if gap { 1.0 } else { device(z) });
        }
    }
    (diffuse, albedo, depth)
}

#[test]
fn gpu_subsurface_filter_matches_its_twin_on_the_same_buffers() {
    let _timer = crate::common::timed!();
    let camera = Camera { position: [0.0, 0.0, 0.0], target: [0.0, 0.0, -1.0], fov_y_deg: 10.0, near: 0.05, far: 50.0 };
    let plan =
        SubsurfacePlan { profile: DiffusionProfile::hdrp_default(), mask: 1.0, sample_budget: SAMPLE_BUDGET_MEDIUM };
    let frame = SubsurfaceFrame::new(&camera, (96, 64), &plan);
    let (diffuse, albedo, depth) = synthetic(&frame);
    let gpu = GpuContext::new().unwrap();
    let got = scattered_of(&gpu, &frame, (&diffuse, &albedo, &depth)).unwrap();
    let twin = subsurface_scattering(&frame, &SubsurfaceBuffers { diffuse: &diffuse, albedo: &albedo, depth: &depth });
    let (mut worst, mut compared, mut borderline) = (0f64, 0, 0);
    for (g, t) in got.iter().zip(&twin) {
        if t.borderline {
            borderline += 1;
            continue;
        }
        compared += 1;
        for (k, v) in g.iter().take(3).enumerate() {
            worst = worst.max((*v as f64 - t.light[k]).abs() / t.light[k].abs().max(1e-3));
        }
    }
    eprintln!("subsurface filter GPU vs twin: worst {worst:.2e} over {compared} pixels ({borderline} borderline)");
    assert!(worst <= 1e-4, "{worst}");
    assert!(borderline * 20 < got.len(), "{borderline} pixels with a sample on a pixel boundary");
    // Where the filter takes no sample a pixel keeps its split light (√albedo·E) × √albedo.
    let (d, a) = (diffuse[62 * 96 + 20][0] as f64, albedo[62 * 96 + 20][0] as f64);
    assert!((twin[62 * 96 + 20].light.x - d * a.sqrt()).abs() < 1e-12 * d, "{:?}", twin[62 * 96 + 20]);
    assert!((got[62 * 96 + 20][0] as f64 - d * a.sqrt()).abs() < 1e-6 * d);
    // The gap holds no split lighting: nothing is added there.
    assert!(got[12 * 96 + 40].iter().take(3).all(|v| *v == 0.0));
    // Across the shadow edge the light spreads both ways: the first dark column gains, the last
    // lit one loses, against the unfiltered albedo × light.
    let unfiltered = |x: usize| {
        let (d, a) = (diffuse[30 * 96 + x], albedo[30 * 96 + x]);
        d[0] as f64 * a[0] as f64
    };
    let edge = (0..96).find(|&x| x as f64 / 96.0 >= 0.4).unwrap();
    assert!(twin[30 * 96 + edge].light.x > unfiltered(edge) * 1.05, "the dark side gains");
    assert!(twin[30 * 96 + edge - 1].light.x < unfiltered(edge - 1) * 0.95, "the lit side loses");
}

/// A small sphere close to the camera, lit from the side (its terminator down the middle), a dim
/// sky; SSS needs millimetres to span pixels.
fn close_sphere() -> Scene {
    let text = r#"
name = "close_sphere"
[camera]
position = [0.0, 0.0, 0.32]
target = [0.0, 0.0, 0.0]
fov_y_deg = 40.0
near = 0.01
far = 10.0
[[lights]]
kind = "directional"
direction = [-1.0, 0.0, 0.0]
intensity = 3.0
key = true
[[objects]]
name = "sphere"
role = "subject"
mesh = { kind = "uv_sphere", radius = 0.1, rings = 96, segments = 192 }
[environment]
sky = { kind = "constant", color = [0.05, 0.05, 0.05] }
background = false
[hdrp]
bloom = false
ssao = false
"#;
    crate::common::scene_from_text("close_sphere", text)
}

#[test]
fn the_type_splits_the_diffuse_light_and_blurs_it_across_the_terminator() {
    let _timer = crate::common::timed!();
    const SIZE: u32 = 128;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let scene = close_sphere();
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.5, 0.35], metallic: 0.0, smoothness: 0.5 };
    let mut render = |sss: Option<f64>| {
        let mut cell = cell_params(Pipeline::Hdrp, "lit", sliders, (3.0, 10.0), SIZE, RenderPath::Forward);
        cell.surface.params[TRANSMISSION_SLOT] = 1.0;
        if let Some(mask) = sss {
            cell.surface.params[SUBSURFACE_SLOT] = 1.0;
            cell.surface.params[SUBSURFACE_MASK_SLOT] = mask;
        }
        // Mask 0 leaves the filter out, with the reason: no pixel's light moves.
        let plan = renderer.plan(&prepared, &cell).unwrap();
        let filters = sss.is_some_and(|mask| mask > 0.0);
        assert_eq!(plan.has(Pass::SubsurfaceScattering), filters);
        assert_eq!(plan.has(Pass::SubsurfaceLighting), filters);
        let why = plan.left_out.iter().find(|(what, _)| what == Pass::SubsurfaceScattering.name());
        assert_eq!(why.is_some(), sss == Some(0.0), "{why:?}");
        let hdr = renderer.render(&prepared, &cell, 1, 0).unwrap().hdr;
        hdr.chunks(4).map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect::<Vec<_>>()
    };
    let translucent = render(None);
    let unblurred = render(Some(0.0));
    let scattered = render(Some(1.0));
    // Mask 0: drawn unsplit, the Translucent image.
    let peak = translucent.iter().map(|p| p.max_element()).fold(0.0, f64::max);
    let worst = translucent.iter().zip(&unblurred).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0, f64::max);
    eprintln!("mask 0 against Translucent: worst |Δ| {worst:.2e} of a peak {peak:.3}");
    assert!(peak > 0.0 && worst <= 1e-5 * peak, "{worst} of {peak}");
    // Mask 1, where the filter runs: away from the terminator the split light comes back whole
    // (√albedo before the filter, √albedo after), so only the light the blur moves differs.
    // Mask 1: the light falls from +x, so the terminator runs down the middle column; the blur
    // carries light across it, brightening the dark side next to it (averaged over the middle
    // rows: the random rotation leaves per-pixel noise, which HDRP's TAA would average), while the
    // sphere's light is kept (the renormalised blur moves light, it does not make or lose it).
    let band = |img: &[DVec3], xs: std::ops::Range<u32>| {
        let rows = SIZE / 2 - 8..SIZE / 2 + 8;
        let n = (rows.len() * xs.len()) as f64;
        rows.flat_map(|y| xs.clone().map(move |x| (y, x))).map(|(y, x)| img[(y * SIZE + x) as usize].x).sum::<f64>() / n
    };
    let gain = |xs: std::ops::Range<u32>| band(&scattered, xs.clone()) / band(&translucent, xs);
    let (next_to, far_dark, far_lit) =
        (gain(SIZE / 2 - 4..SIZE / 2), gain(SIZE / 2 - 12..SIZE / 2 - 8), gain(SIZE / 2 + 8..SIZE / 2 + 12));
    eprintln!(
        "dark side next to the terminator ×{next_to:.4}; 8–12 px away ×{far_dark:.4} (dark), ×{far_lit:.4} (lit)"
    );
    assert!(next_to > 1.05, "the dark side next to the terminator gains: ×{next_to}");
    // 8 px here is 10 mm, where the profile's CDF has passed 0.999: nothing moves that far.
    for far in [far_dark, far_lit] {
        assert!((far - 1.0).abs() < 5e-3, "×{far}");
    }
    let total = |img: &[DVec3]| img.iter().map(|p| p.x + p.y + p.z).sum::<f64>();
    let kept = total(&scattered) / total(&translucent);
    eprintln!("light kept ×{kept:.4}");
    assert!((kept - 1.0).abs() < 0.03, "{kept}");
}

#[test]
fn a_deferred_or_multisampled_cell_scatters_its_subject_drawn_forward_on_one_sample() {
    let _timer = crate::common::timed!();
    const SIZE: u32 = 128;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&close_sphere()).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.5, 0.35], metallic: 0.0, smoothness: 0.5 };
    let cell = |path, sss: bool, antialiasing| {
        let mut cell = cell_params(Pipeline::Hdrp, "lit", sliders, (3.0, 10.0), SIZE, path);
        cell.surface.params[TRANSMISSION_SLOT] = 1.0;
        cell.surface.params[SUBSURFACE_SLOT] = sss as u32 as f64;
        cell.settings.antialiasing = antialiasing;
        cell
    };
    // Deferred: the subject leaves the G-buffer for the forward-only pass, counted there alone.
    let deferred = cell(RenderPath::Deferred, true, Antialiasing::None);
    let plan = renderer.plan(&prepared, &deferred).unwrap();
    let at = |p: Pass| plan.passes.iter().position(|q| *q == p).unwrap();
    assert!(
        at(Pass::ForwardOnly) < at(Pass::SubsurfaceLighting)
            && at(Pass::SubsurfaceLighting) < at(Pass::SubsurfaceScattering)
    );
    assert!(!plan.gbuffer.subject);
    assert_eq!(plan.draws.counts.get(Pass::Transparent.name()), None, "an opaque subject");
    // Forward with 4× MSAA asked: one sample, and the note says why.
    let msaa = cell(RenderPath::Forward, true, Antialiasing::Msaa4);
    let plan = renderer.plan(&prepared, &msaa).unwrap();
    assert_eq!(plan.multisampling.samples, 1);
    assert!(
        plan.multisampling.note.as_deref().is_some_and(|n| n.contains("subsurface")),
        "{:?}",
        plan.multisampling.note
    );
    // Either way the dark side next to the terminator gains, as on the forward path.
    for (path, aa) in [(RenderPath::Deferred, Antialiasing::None), (RenderPath::Forward, Antialiasing::Msaa4)] {
        let mut band = |sss: bool| {
            let hdr = renderer.render(&prepared, &cell(path, sss, aa), 1, 0).unwrap().hdr;
            let rows = SIZE / 2 - 8..SIZE / 2 + 8;
            let xs = SIZE / 2 - 4..SIZE / 2;
            let n = (rows.len() * xs.len()) as f64;
            rows.flat_map(|y| xs.clone().map(move |x| (y * SIZE + x) as usize * 4)).map(|i| hdr[i] as f64).sum::<f64>()
                / n
        };
        let gain = band(true) / band(false);
        eprintln!("{path:?} {aa:?}: dark side next to the terminator ×{gain:.4}");
        assert!(gain > 1.05, "{path:?}: ×{gain}");
    }
}
