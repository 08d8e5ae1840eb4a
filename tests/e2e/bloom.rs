//! HDRP's bloom (`render::passes::bloom`) against its f64 twin (`images::bloom`), and the switch that
//! turns it off.

use glam::DVec3;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::images::bloom::{bloom, Image};
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::Pass;
use shadematrix::render::renderer::Renderer;

#[test]
fn gpu_bloom_matches_its_twin_and_the_switch_turns_it_off() {
    let _timer = crate::common::timed!();
    let with = Scene::load("mitsuba", None, "test", "composition").unwrap();
    assert!(with.hdrp.bloom, "on by default, as HDRP's default volume");
    let mut without = with.clone();
    without.hdrp.bloom = false;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let gold = shadematrix::shading::registry::Sliders {
        base_color_linear: [1.0, 0.766, 0.336],
        metallic: 1.0,
        smoothness: 0.9,
    };
    let cell = crate::common::cell_params(Pipeline::Hdrp, "lit", gold, (2.0, 10.0), 96, RenderPath::Forward);
    let mut render = |scene: &Scene| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let passes: Vec<Pass> = r.gpu_passes.map(|p| p.into_iter().map(|(n, _)| n).collect()).unwrap_or_default();
        let texels = r.hdr.chunks(4).map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect();
        (
            Image { width: 96, height: 96, texels },
            passes,
            prepared.plan.passes_for(RenderPath::Forward, Pipeline::Hdrp, &Default::default(), false),
        )
    };
    let (bloomed, timed, plan) = render(&with);
    let (plain, _, plan_off) = render(&without);
    assert!(plan.contains(&Pass::Bloom) && !plan_off.contains(&Pass::Bloom), "{plan:?} / {plan_off:?}");
    if !timed.is_empty() {
        assert!(timed.contains(&Pass::Bloom), "{timed:?}");
    }
    let twin = bloom(&plain, &shadematrix::render::passes::bloom::BloomSettings::default());
    let peak = plain.texels.iter().map(|t| t.max_element()).fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    let mut changed = 0;
    for ((g, c), p) in bloomed.texels.iter().zip(&twin.texels).zip(&plain.texels) {
        worst = worst.max(((*g - *c).abs() / (c.abs() + DVec3::splat(1e-4 * peak))).max_element());
        if ((*g - *p).abs() / (p.abs() + DVec3::splat(1e-4 * peak))).max_element() > 0.01 {
            changed += 1;
        }
    }
    eprintln!(
        "GPU bloom vs f64 twin: worst relative difference {worst:.2e}; {changed} of 9216 pixels changed by > 1 %"
    );
    assert!(worst < 1e-3, "{worst}");
    assert!(changed > 500, "bloom changes {changed} pixels");
}

/// A one-pixel highlight bloomed by the GPU chain against the reference computed from HDRP's
/// formulas (`images::bloom`): weight 2^0.2 − 1, scatter lerp(0.05, 0.95, 0.7), Karis-weighted
/// prefilter, ⌊log2 − 2⌋ levels, bilinear below 800×450 and bicubic at 800×450; and at the Low
/// quality level (Quarter resolution: a level fewer, and at 800×450 each half the size; bilinear)
/// and the High one (the 13-tap prefilter).
#[test]
fn a_one_pixel_highlight_blooms_as_hdrps_formulas_say() {
    let _timer = crate::common::timed!();
    use shadematrix::render::passes::bloom::{BloomChain, BloomPipeline, BloomSettings};
    let gpu = GpuContext::new().unwrap();
    let pipeline = BloomPipeline::new(&gpu).unwrap();
    let low = BloomSettings::at(shadematrix::pipelines::settings::HdrpQuality::Low);
    let high = BloomSettings::at(shadematrix::pipelines::settings::HdrpQuality::High);
    let mut spreads = Vec::new();
    for (settings, (width, height)) in [
        (BloomSettings::default(), (96u32, 64u32)),
        (BloomSettings::default(), (800, 450)),
        (low, (96, 64)),
        (low, (800, 450)),
        (high, (96, 64)),
        (high, (800, 450)),
    ] {
        let mut image = Image {
            width: width as usize,
            height: height as usize,
            texels: vec![DVec3::splat(0.05); (width * height) as usize],
        };
        let at = (height as usize / 2) * width as usize + width as usize / 3;
        image.texels[at] = DVec3::new(400.0, 300.0, 200.0);
        let texels: Vec<f32> = image.texels.iter().flat_map(|t| [t.x as f32, t.y as f32, t.z as f32, 1.0]).collect();
        let color = shadematrix::render::resources::texture_2d(
            &gpu.device,
            "highlight",
            (width, height),
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        gpu.queue.write_texture(
            color.as_image_copy(),
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(width * 16), rows_per_image: None },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
        let chain = BloomChain::new(&gpu.device, &pipeline, &color, (width, height), settings);
        let readback = shadematrix::gpu::readback::TextureReadback::new(&gpu.device, "bloomed", width, height, 16);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        chain.encode(&pipeline, &mut encoder, None);
        readback.encode_copy(&mut encoder, &chain.output);
        gpu.queue.submit([encoder.finish()]);
        let bytes = readback.read(&gpu.device).unwrap();
        let gpu_out: &[f32] = bytemuck::cast_slice(&bytes);
        let reference = bloom(&image, &settings);
        let (mut worst, mut spread) = (0.0f64, 0usize);
        for (k, r) in reference.texels.iter().enumerate() {
            let g = DVec3::new(gpu_out[4 * k] as f64, gpu_out[4 * k + 1] as f64, gpu_out[4 * k + 2] as f64);
            worst = worst.max(((g - *r).abs() / (r.abs() + DVec3::splat(1e-3))).max_element());
            spread += (r.x > 0.05 * 1.01) as usize;
        }
        let centre = reference.texels[at].x;
        eprintln!(
            "{width}×{height}{}: GPU vs HDRP-formula reference worst {worst:.2e}; centre {centre:.2} of 400; \
             {spread} pixels brightened by > 1 %",
            match (settings.quarter, settings.high_quality_prefiltering) {
                (true, _) => " (Low)",
                (_, true) => " (High)",
                _ => "",
            }
        );
        if settings.high_quality_prefiltering {
            // High differs from Medium by its 13-tap prefilter alone.
            let medium = bloom(&image, &BloomSettings::default());
            let moved = reference.texels.iter().zip(&medium.texels).map(|(h, m)| (*h - *m).abs().max_element());
            let moved = moved.fold(0.0, f64::max);
            eprintln!("  High against Medium: largest change {moved:.3}");
            assert!(moved > 1e-2, "{moved}");
        }
        spreads.push(spread);
        assert!(worst < 1e-3, "{width}×{height}: {worst}");
        // The composite keeps (2 − 2^0.2) of the pixel itself, and the bloom reaches far past it.
        assert!((centre / 400.0 - (1.0 - settings.composite_weight())).abs() < 0.01, "{centre}");
        assert!(spread > 40, "{spread}");
    }
    // A level fewer spreads the highlight otherwise (at 96×64 over more pixels, each by more).
    assert!(spreads[2] != spreads[0] && spreads[3] != spreads[1], "{spreads:?}");
}
