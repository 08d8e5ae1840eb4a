//! HDRP Lit's Translucent material type with the default diffusion profile: the GPU against the
//! f64 twin for lights on either side, and in rendered frames the transmittance's share of the
//! light from behind and of the ambient at −N (SurfaceShading.hlsl, Lit.hlsl
//! ModifyBakedDiffuseLighting, DiffusionProfile.hlsl ComputeTransmittanceDisney).

use crate::common::{cell_params, find_model};
use glam::DVec3;
use shadematrix::audit::samples::halton;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::probe::{BrdfProbe, ProbeInput};
use shadematrix::render::Renderer;
use shadematrix::shading::registry::Sliders;
use shadematrix::shading::twin::{compute_transmittance_disney, Surface, THICKNESS_SLOT, TRANSMISSION_SLOT};

fn on_sphere(u: f64, w: f64) -> DVec3 {
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * (std::f64::consts::TAU * w).cos(), z, r * (std::f64::consts::TAU * w).sin())
}

/// The default profile's transmittance at `_Thickness` t: S = 2/mm, the tint ¼, 5 mm per unit.
fn transmittance(t: f64) -> f64 {
    compute_transmittance_disney(DVec3::splat(2.0), DVec3::splat(0.25), 5.0 * t).x
}

#[test]
fn translucent_lit_matches_its_twin_with_the_light_on_either_side() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let model = find_model(Pipeline::Hdrp, "lit").unwrap();
    let (mut inputs, mut cases) = (Vec::new(), Vec::new());
    let mut behind = 0;
    for i in 1..=1024u64 {
        let v = on_sphere(0.45 * halton(i, 2), halton(i, 3));
        // Any direction: a light behind the surface reaches it through the slab.
        let l = on_sphere(halton(i, 5), halton(i, 7));
        behind += (l.y < 0.0) as usize;
        let sliders = Sliders {
            base_color_linear: [0.2 + 0.8 * halton(i, 11), 0.6, 0.1 + 0.9 * halton(i, 13)],
            metallic: [0.0, 1.0][(i % 2) as usize],
            smoothness: 0.95 * halton(i, 17),
        };
        let mut s: Surface = model.surface(Pipeline::Hdrp, &sliders);
        s.params[TRANSMISSION_SLOT] = 1.0;
        s.params[THICKNESS_SLOT] = halton(i, 19);
        let (gd, gs) = (DVec3::new(0.2, 0.3, 0.4), DVec3::new(0.5, 0.4, 0.3));
        inputs.push(ProbeInput::new(&s, DVec3::Y, v, l, gd, gs));
        cases.push((s.rounded_f32(), v, l, gd, gs));
    }
    let out = BrdfProbe::new(&gpu).evaluate_full(&gpu, Pipeline::Hdrp, model, &inputs).unwrap();
    let twin = model.twin.unwrap();
    let (mut worst, mut lit_behind) = (0f64, 0);
    for ((s, v, l, gd, gs), (d_gpu, i_gpu, _)) in cases.iter().zip(&out) {
        let r = |x: DVec3| x.as_vec3().as_dvec3();
        let (v, l) = (r(*v), r(*l));
        let d = twin.direct(Pipeline::Hdrp, s, DVec3::Y, v, l);
        let ind = twin.indirect(Pipeline::Hdrp, s, DVec3::Y, v, r(*gd), r(*gs));
        lit_behind += (l.y < 0.0 && d.max_element() > 0.0) as usize;
        for (cpu, g) in [(d, d_gpu), (ind, i_gpu)] {
            for k in 0..3 {
                worst = worst.max((g[k] as f64 - cpu[k]).abs() / cpu[k].abs().max(1e-3));
            }
        }
    }
    eprintln!("hdrp/lit translucent parity: worst {worst:.2e}; {lit_behind} of {behind} lights behind reach through");
    assert!(worst <= 1e-4, "{worst}");
    assert!(lit_behind * 2 > behind, "most lights behind the surface reach through it: {lit_behind} of {behind}");
}

/// A sphere before the camera, a directional light straight behind it (no shadows), sky `sky`.
fn back_lit(sky: f64, light: f64) -> Scene {
    let text = format!(
        r#"
name = "back_lit"
[camera]
position = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 40.0
[[lights]]
kind = "directional"
direction = [0.0, 0.0, 1.0]
intensity = {light}
key = true
[[objects]]
name = "sphere"
role = "subject"
mesh = {{ kind = "uv_sphere", radius = 0.8, rings = 96, segments = 192 }}
[environment]
sky = {{ kind = "constant", color = [{sky}, {sky}, {sky}] }}
background = false
[hdrp]
bloom = false
ssao = false
"#
    );
    crate::common::scene_from_text("back_lit", &text)
}

/// The centre pixel of a translucent HDRP Lit sphere of `_Thickness` t.
fn centre(renderer: &mut Renderer, scene: &Scene, t: f64) -> f64 {
    const SIZE: u32 = 33;
    let prepared = renderer.prepare_scene(scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.6, 0.4], metallic: 0.0, smoothness: 0.5 };
    let mut cell = cell_params(Pipeline::Hdrp, "lit", sliders, (1.0, 10.0), SIZE, RenderPath::Forward);
    cell.surface.params[TRANSMISSION_SLOT] = 1.0;
    cell.surface.params[THICKNESS_SLOT] = t;
    let hdr = renderer.render(&prepared, &cell, 1, 0).unwrap().hdr;
    let i = ((SIZE / 2) * SIZE + SIZE / 2) as usize * 4;
    hdr[i + 1] as f64
}

#[test]
fn light_from_behind_and_the_ambient_at_minus_n_reach_through_the_slab() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    // The light straight behind, no ambient: the centre (N towards the camera, N·L = −1) sees the
    // diffuse term at the wrapped −NL through the transmittance alone, so the thickness scales it
    // by T(t).
    let dark = back_lit(0.0, 1.0);
    let thin = centre(&mut renderer, &dark, 0.0);
    assert!(thin > 0.0, "the light behind reaches the front");
    for t in [0.25, 0.5] {
        let got = centre(&mut renderer, &dark, t) / thin;
        let want = transmittance(t) / transmittance(0.0);
        assert!((got - want).abs() <= 2e-3 * want, "t = {t}: {got} vs {want}");
    }
    // No light, a constant sky: the baked diffuse gains the ambient at −N × T(t), the rest of the
    // pixel unchanged, so differences between thicknesses go as differences of T.
    let sky = back_lit(0.5, 0.0);
    let (r0, r_half, r1) =
        (centre(&mut renderer, &sky, 0.0), centre(&mut renderer, &sky, 0.5), centre(&mut renderer, &sky, 1.0));
    let got = (r0 - r1) / (r_half - r1);
    let want = (transmittance(0.0) - transmittance(1.0)) / (transmittance(0.5) - transmittance(1.0));
    assert!((got - want).abs() <= 5e-3 * want, "{got} vs {want}");
}
