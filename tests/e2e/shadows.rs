//! Shadow maps: a caster darkens what lies under it when its light casts shadows, for every light
//! kind and pipeline; and the frame plan leaves the shadow pass out when nothing can cast.

use crate::common::{cell_params, fixture};
use shadematrix::color::luminance;
use shadematrix::declarations::scene::{LightKind, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::FramePlan;
use shadematrix::render::Renderer;
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 65;

/// Luminance at the image centre (under the box) and near the bottom edge (floor in the open).
fn centre_and_open_floor(renderer: &mut Renderer, scene: &Scene, pipeline: Pipeline) -> (f64, f64) {
    let prepared = renderer.prepare_scene(scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8; 3], metallic: 0.0, smoothness: 0.5 };
    // The pipeline's lit shader: built-in's Standard is compiled with fullforwardshadows, so its
    // ForwardAdd lights (the point and the spot) cast shadows; a classic model's would not.
    let shader = pipeline.fixed_object_shader();
    let cell = cell_params(pipeline, shader, sliders, (1.5, 10.0), SIZE, RenderPath::Forward);
    let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
    let at = |row: u32| {
        let i = (row * SIZE + SIZE / 2) as usize * 4;
        luminance([r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64])
    };
    (at(SIZE / 2), at(SIZE - 3))
}

#[test]
fn a_caster_darkens_the_receiver_under_it_only_with_shadows_on() {
    let _timer = crate::common::timed!();
    let mut base = Scene::load_file(&fixture("shadow_box.toml")).unwrap();
    // Shadowed and lit pixels side by side: HDRP's bloom would blur the edge between them.
    base.hdrp.bloom = false;
    base.hdrp.ssao = false;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    for kind in [LightKind::Point, LightKind::Spot, LightKind::Directional] {
        for pipeline in Pipeline::ALL {
            let mut on = base.clone();
            on.lights[0].kind = kind;
            let mut off = on.clone();
            off.lights[0].shadows = false;
            let (lit, open_off) = centre_and_open_floor(&mut renderer, &off, pipeline);
            let (shadowed, open_on) = centre_and_open_floor(&mut renderer, &on, pipeline);
            eprintln!("{kind:?} in {}: centre {shadowed:.4e} with shadows, {lit:.4e} without", pipeline.name());
            assert!(lit > 0.0, "{kind:?}/{}: the centre is lit without shadows", pipeline.name());
            if pipeline == Pipeline::Urp && kind != LightKind::Directional {
                // The code-default URP asset has additional-light shadows off (tests/e2e/passes.rs
                // turns them on): the point and the spot cast none.
                assert_eq!(shadowed, lit, "{kind:?}/urp");
                continue;
            }
            assert!(shadowed < 0.5 * lit, "{kind:?}/{}: {shadowed} vs {lit}", pipeline.name());
            // Floor in the open keeps its light: no acne, no map edge darkening it.
            assert!(
                (open_on - open_off).abs() <= 1e-3 * open_off,
                "{kind:?}/{}: open floor {open_on} vs {open_off}",
                pipeline.name()
            );
        }
    }
}

#[test]
fn no_shadow_pass_without_a_caster_a_receiver_or_a_shadowed_light() {
    let _timer = crate::common::timed!();
    let base = Scene::load_file(&fixture("shadow_box.toml")).unwrap();
    assert!(FramePlan::for_scene(&base).passes.contains(&shadematrix::plan::Pass::Shadow));
    let reason = |scene: &Scene| {
        let plan = FramePlan::for_scene(scene);
        assert!(!plan.passes.contains(&shadematrix::plan::Pass::Shadow));
        plan.left_out.iter().find(|(what, _)| what == "shadow pass").map(|(_, why)| why.clone()).unwrap()
    };
    let mut no_caster = base.clone();
    no_caster.objects.iter_mut().for_each(|o| o.cast_shadows = false);
    assert_eq!(reason(&no_caster), "no object casts shadows");
    let mut no_light = base.clone();
    no_light.lights[0].shadows = false;
    assert_eq!(reason(&no_light), "no light casts shadows");
    let mut no_receiver = base;
    no_receiver.objects.iter_mut().for_each(|o| o.receive_shadows = false);
    assert_eq!(reason(&no_receiver), "no object receives shadows");
}

/// HDRP's shadow filters (shaders/pass/shadow_filters.wgsl) on the GPU against their f64 twin
/// (`shading::shadow_filter`) on a 64² map drawn from a known depth (a disc blocker at 0.3 over a
/// slanted receiver): the 3×3, 5×5 and 7×7 tents and PCSS on an orthographic and a perspective
/// map, at receivers across the blocker's edge.
#[test]
fn hdrps_shadow_filters_match_their_twin() {
    let _timer = crate::common::timed!();
    use shadematrix::shading::shadow_filter::{shadow_pcss, shadow_tent, DepthMap};
    const SIDE: u32 = 64;
    let gpu = GpuContext::new().unwrap();
    let device = &gpu.device;
    let map = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test shadow map"),
        size: wgpu::Extent3d { width: SIDE, height: SIDE, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    // The map's depth per texel, drawn by a full-screen triangle (depth textures take no copies).
    let draw = r#"
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(p * 2.0 - 1.0, 0.0, 1.0);
}
@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @builtin(frag_depth) f32 {
    let t = floor(p.xy);
    let d = t - vec2<f32>(24.0, 30.0);
    if (dot(d, d) < 144.0) {
        return 0.3;
    }
    return 0.85 - 0.002 * t.x;
}
"#;
    let module = gpu.shader_module("test shadow map", draw).unwrap();
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            buffers: &[],
            compilation_options: Default::default(),
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            targets: &[],
            compilation_options: Default::default(),
        }),
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    });
    let layer_view = map.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        ..Default::default()
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &layer_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.draw(0..3, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
    let depth_at = |x: i64, y: i64| -> f64 {
        let (dx, dy) = (x as f32 - 24.0, y as f32 - 30.0);
        if dx * dx + dy * dy < 144.0 {
            0.3
        } else {
            (0.85f32 - 0.002f32 * x as f32) as f64
        }
    };
    let twin_map = DepthMap { side: SIDE as usize, scale: 1.0, depth: &depth_at };

    // PCSS terms: an orthographic layer (softness, min filter, range scale) and a perspective one
    // (softness, min filter, 1/z's terms for near 0.05 and far 10).
    let ortho = [0.01f32, 0.0001, 0.4, 0.0];
    let (n, f) = (0.05f64, 10.0f64);
    let persp = [0.004f32, 0.0001, ((f - n) / (n * f)) as f32, (1.0 / f) as f32];
    let kernel = format!(
        r#"
struct ShadowLayer {{
    view_proj: mat4x4<f32>,
    params: vec4<f32>,
    sphere: vec4<f32>,
    pcss: vec4<f32>,
}};
@group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;
@group(0) @binding(2) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;
var<private> shading_pixel: vec2<f32> = vec2<f32>(0.0);
fn interleaved_gradient_noise(pixel: vec2<f32>) -> f32 {{
    return fract(52.9829189 * fract(dot(pixel, vec2<f32>(0.06711056, 0.00583715))));
}}
{filters}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    if (2u * id.x >= arrayLength(&inputs)) {{ return; }}
    let a = inputs[2u * id.x];
    let b = inputs[2u * id.x + 1u];
    shading_pixel = b.xy;
    var info: ShadowLayer;
    info.params = vec4<f32>(0.0, b.w, {SIDE}.0, 1.0);
    info.pcss = select(vec4<f32>({o0}, {o1}, {o2}, {o3}), vec4<f32>({p0}, {p1}, {p2}, {p3}), b.w > 0.5);
    var v = 0.0;
    if (b.z > 0.5) {{
        v = shadow_tent(0u, a.xy, a.z, b.z);
    }} else {{
        v = shadow_pcss(0u, info, a.xy, a.z);
    }}
    outputs[id.x] = vec4<f32>(v, 0.0, 0.0, 0.0);
}}
"#,
        filters = include_str!("../../shaders/pass/shadow_filters.wgsl"),
        o0 = ortho[0],
        o1 = ortho[1],
        o2 = ortho[2],
        o3 = ortho[3],
        p0 = persp[0],
        p1 = persp[1],
        p2 = persp[2],
        p3 = persp[3],
    );
    let source = [shadematrix::shading::wgsl::common().as_str(), &kernel].join("\n");
    // Receivers along a row through the disc's edge and the open receiver, at depths behind the
    // blocker and in front of the receiver; (u, v, depth, —) and (pixel, filter: n or 0 PCSS, perspective).
    let mut inputs: Vec<[f32; 4]> = Vec::new();
    let mut cases = Vec::new();
    for (filter, perspective) in [(3.0f32, 0.0f32), (5.0, 0.0), (7.0, 0.0), (0.0, 0.0), (0.0, 1.0)] {
        for k in 0..48 {
            let x = 4.0 + k as f32 * 0.93;
            let y = 29.3 + (k % 5) as f32 * 0.7;
            let depth = 0.8 - 0.002 * x;
            let pixel = [(k * 7 % 64) as f32 + 0.5, (k * 3 % 64) as f32 + 0.5];
            inputs.push([x / SIDE as f32, y / SIDE as f32, depth, 0.0]);
            inputs.push([pixel[0], pixel[1], filter, perspective]);
            cases.push(([x, y], depth, pixel, filter, perspective));
        }
    }
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    });
    let array_view = map.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let got = crate::common::run_kernel(
        &gpu,
        &source,
        &inputs,
        cases.len(),
        &[wgpu::BindingResource::TextureView(&array_view), wgpu::BindingResource::Sampler(&sampler)],
    );
    let (mut worst, mut partial) = (0.0f64, 0);
    for (g, (s, depth, pixel, filter, perspective)) in got.iter().zip(&cases) {
        let (s, depth, pixel) = ([s[0] as f64, s[1] as f64], *depth as f64, [pixel[0] as f64, pixel[1] as f64]);
        let want = if *filter > 0.5 {
            shadow_tent(s, *filter as u32, [SIDE as i64 - 1; 2], |x, y| depth <= depth_at(x, y))
        } else {
            let pcss = if *perspective > 0.5 { persp } else { ortho }.map(f64::from);
            let uv = [s[0] / SIDE as f64, s[1] / SIDE as f64];
            shadow_pcss(&twin_map, uv, depth, pixel, pcss, *perspective > 0.5)
        };
        partial += (want > 0.01 && want < 0.99) as usize;
        worst = worst.max((g[0] as f64 - want).abs());
    }
    eprintln!(
        "shadow filters GPU vs twin: worst |Δ| {worst:.2e} over {} receivers, {partial} in a penumbra",
        cases.len()
    );
    // Bilinear comparison weights are fixed-point on many GPUs (lavapipe's: 8 bits).
    assert!(worst < 1e-2, "worst {worst}");
    assert!(partial > 20, "{partial} receivers in a penumbra");
}
