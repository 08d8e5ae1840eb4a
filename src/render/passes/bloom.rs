//! HDRP's bloom on the frame's HDR target (shaders/pass/bloom.wgsl; f64 twin: `images::bloom`),
//! as PostProcessSystem.DoBloom runs it with the Default Volume Profile's Bloom (intensity 0.2,
//! scatter 0.7 default, threshold 0, resolution Half, high-quality prefiltering off, high-quality
//! filtering on; Editor/RenderPipelineResources/DefaultSettingsVolumeProfile.asset):
//! - the composite is UberPost's lerp(colour, bloom, 2^intensity − 1) (0.1487 for 0.2), so a
//!   uniform image is unchanged;
//! - each upsample lerps towards the coarser level by lerp(0.05, 0.95, scatter) (0.68 for 0.7);
//! - ⌊log2(max side) − 2⌋ levels (at most 16), level i RoundToInt(side / 2^(i+1));
//! - below 800×450 the upsamples filter bilinearly instead of bicubically; the composite filters
//!   bicubically at every size (UberPost.compute compiles its bilinear fetch out, `#if 0`).
//!
//! The chain's textures are made per target size and kept with the targets.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::error::Error;
use crate::gpu::GpuContext;
use crate::render::resources::ComputeStep;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct BloomParams {
    dims: [u32; 4],
    factor: [f32; 4],
}

const PREFILTER: u32 = 0;
const DOWNSAMPLE: u32 = 1;
const BLUR_ACROSS: u32 = 2;
const BLUR_DOWN: u32 = 3;
const LERP: u32 = 4;

/// The bloom's settings as the volume sets them (HDRP's default profile's Bloom).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BloomSettings {
    pub intensity: f64,
    pub scatter: f64,
    /// Bloom.highQualityFiltering: bicubic upsampling (on in the default profile).
    pub high_quality_filtering: bool,
    /// Bloom.resolution Quarter rather than Half.
    pub quarter: bool,
    /// Bloom.highQualityPrefiltering: the 13-tap prefilter (BloomPrefilter.compute HIGH_QUALITY).
    pub high_quality_prefiltering: bool,
}

impl Default for BloomSettings {
    fn default() -> Self {
        BloomSettings {
            intensity: 0.2,
            scatter: 0.7,
            high_quality_filtering: true,
            quarter: false,
            high_quality_prefiltering: false,
        }
    }
}

impl BloomSettings {
    /// The default profile's Bloom at a quality level (GlobalPostProcessingQualitySettings:
    /// BloomRes Quarter / Half / Half, BloomHighQualityFiltering off / on / on,
    /// BloomHighQualityPrefiltering off / off / on).
    pub fn at(quality: crate::pipelines::settings::HdrpQuality) -> BloomSettings {
        use crate::pipelines::settings::HdrpQuality;
        let low = quality == HdrpQuality::Low;
        BloomSettings {
            high_quality_filtering: !low,
            quarter: low,
            high_quality_prefiltering: quality == HdrpQuality::High,
            ..BloomSettings::default()
        }
    }

    /// UberPost's composite weight: 2^intensity − 1 ("makes intensity easier to control").
    pub fn composite_weight(&self) -> f64 {
        2f64.powf(self.intensity) - 1.0
    }

    /// The upsample's lerp towards the coarser level: lerp(0.05, 0.95, scatter).
    pub fn upsample_scatter(&self) -> f64 {
        0.05 + 0.9 * self.scatter
    }

    /// Whether a `width`×`height` frame upsamples bicubically: DoBloom turns high-quality
    /// filtering off below 800×450. The composite is bicubic at every size (UberPost.compute).
    pub fn bicubic(&self, width: u32, height: u32) -> bool {
        self.high_quality_filtering && width >= 800 && height >= 450
    }
}

/// The pyramid's levels for a frame of `width`×`height` (DoBloom): ⌊log2(max side) − 2⌋ levels
/// at Half resolution, one fewer at Quarter (at least 1, at most 16); level i RoundToInt(scale ·
/// side / 2^(i+1)) (C#'s round-half-to-even), at least 1, where the scale is 1 / (resolution / 2)
/// (Half 1, Quarter ½) but 1 below 800×450 ("less than 50 % of 900p").
pub fn level_sizes(width: u32, height: u32, quarter: bool) -> Vec<(u32, u32)> {
    let fewer = if quarter { 1.0 } else { 0.0 };
    let count = ((width.max(height) as f64).log2() - 2.0 - fewer).floor().clamp(1.0, 16.0) as i32;
    let small = width < 800 || height < 450;
    let scale = if quarter && !small { 0.5 } else { 1.0 };
    let side = |s: u32, k: i32| ((scale * s as f64 / 2f64.powi(k + 1)).round_ties_even() as u32).max(1);
    (0..count).map(|k| (side(width, k), side(height, k))).collect()
}

/// The compute pipeline, made once per renderer.
pub struct BloomPipeline {
    pipeline: wgpu::ComputePipeline,
    /// The High level's prefilter (`cs_bloom_prefilter_high`), its own kernel.
    prefilter_high: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    space: crate::gpu::ConstantSpace,
}

impl BloomPipeline {
    pub fn new(gpu: &GpuContext) -> Result<BloomPipeline, Error> {
        let device = &gpu.device;
        let module =
            gpu.shader_module(crate::plan::Pass::Bloom.name(), include_str!("../../../shaders/pass/bloom.wgsl"))?;
        use crate::render::resources::compute_entry::{constants, float_2d, storage_2d};
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(crate::plan::Pass::Bloom.name()),
            entries: &[constants(gpu.constants, 0), float_2d(1), float_2d(2), storage_2d(3, FORMAT)],
        });
        let pipeline = crate::render::resources::compute_pipeline(
            device,
            crate::plan::Pass::Bloom.name(),
            &layout,
            &module,
            "cs_bloom",
        );
        let prefilter_high = crate::render::resources::compute_pipeline(
            device,
            crate::plan::Pass::Bloom.name(),
            &layout,
            &module,
            "cs_bloom_prefilter_high",
        );
        Ok(BloomPipeline { pipeline, prefilter_high, layout, space: gpu.constants })
    }
}

/// The bloom of one target size: the pyramid's textures, the output and the dispatches.
pub struct BloomChain {
    pub settings: BloomSettings,
    /// The bloomed frame (full resolution): what is read back when the cell blooms.
    pub output: wgpu::Texture,
    steps: Vec<ComputeStep>,
}

impl BloomChain {
    /// The chain that blooms `color` (`width`×`height`, TEXTURE_BINDING) into its own output.
    pub fn new(
        device: &wgpu::Device,
        pipeline: &BloomPipeline,
        color: &wgpu::Texture,
        (width, height): (u32, u32),
        settings: BloomSettings,
    ) -> BloomChain {
        let make = |label: &str, (w, h): (u32, u32), extra: wgpu::TextureUsages| {
            crate::render::resources::texture_2d(
                device,
                label,
                (w, h),
                FORMAT,
                wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING | extra,
            )
        };
        let sizes = level_sizes(width, height, settings.quarter);
        // Per level: the blurred level (m), a scratch for the first blur (s), and the level's input
        // before blurring, reused for its upsampled result (t).
        let levels: Vec<[wgpu::Texture; 3]> = sizes
            .iter()
            .map(|&s| {
                [
                    make("bloom level", s, wgpu::TextureUsages::empty()),
                    make("bloom scratch", s, wgpu::TextureUsages::empty()),
                    make("bloom input", s, wgpu::TextureUsages::empty()),
                ]
            })
            .collect();
        let output = make("bloomed frame", (width, height), wgpu::TextureUsages::COPY_SRC);
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let mut steps = Vec::new();
        let mut step = |mode: u32,
                        source: &wgpu::Texture,
                        coarse: &wgpu::Texture,
                        dst: &wgpu::Texture,
                        size: (u32, u32),
                        (factor, bicubic): (f64, bool)| {
            let bicubic = bicubic as u32 as f32;
            let params = BloomParams { dims: [size.0, size.1, mode, 0], factor: [factor as f32, bicubic, 0.0, 0.0] };
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("bloom step"),
                contents: bytemuck::bytes_of(&params),
                usage: pipeline.space.usage(),
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("bloom step"),
                layout: &pipeline.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view(source)) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&view(coarse)) },
                    wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&view(dst)) },
                ],
            });
            steps.push(ComputeStep { group, size });
        };
        for (k, (&size, [m, s, t])) in sizes.iter().zip(&levels).enumerate() {
            match k {
                0 => step(PREFILTER, color, color, t, size, (0.0, false)),
                _ => step(DOWNSAMPLE, &levels[k - 1][0], color, t, size, (0.0, false)),
            }
            step(BLUR_ACROSS, t, color, s, size, (0.0, false));
            step(BLUR_DOWN, s, color, m, size, (0.0, false));
        }
        // Upsampled level k (in its `t`): lerp(level k, bicubic(upsampled k + 1), scatter); the
        // coarsest level is its own upsampled result.
        let n = levels.len();
        let upsampled = |k: usize| if k + 1 == n { &levels[k][0] } else { &levels[k][2] };
        for k in (0..n.saturating_sub(1)).rev() {
            let upsample = (settings.upsample_scatter(), settings.bicubic(width, height));
            step(LERP, &levels[k][0], upsampled(k + 1), &levels[k][2], sizes[k], upsample);
        }
        // UberPost.compute: the composite's fetch is bicubic whatever the size.
        step(LERP, color, upsampled(0), &output, (width, height), (settings.composite_weight(), true));
        BloomChain { settings, output, steps }
    }

    pub fn encode(
        &self,
        pipeline: &BloomPipeline,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(crate::plan::Pass::Bloom.name()),
            timestamp_writes: timestamps,
        });
        // The first step is the prefilter: the High level's kernel where it is asked for.
        for (i, s) in self.steps.iter().enumerate() {
            match i {
                0 if self.settings.high_quality_prefiltering => pass.set_pipeline(&pipeline.prefilter_high),
                0 | 1 => pass.set_pipeline(&pipeline.pipeline),
                _ => {}
            }
            pass.set_bind_group(0, &s.group, &[]);
            pass.dispatch_workgroups(s.size.0.div_ceil(8), s.size.1.div_ceil(8), 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_mirror_the_wgsl_struct() {
        let (size, fields) = crate::mirror_layout!(BloomParams, [dims, factor]);
        crate::gpu::layout::check_mirror(
            include_str!("../../../shaders/pass/bloom.wgsl"),
            "BloomParams",
            size,
            &fields,
        )
        .unwrap();
    }

    #[test]
    fn the_pyramid_starts_at_half_resolution() {
        let s = level_sizes(384, 384, false);
        assert_eq!(s[0], (192, 192));
        assert_eq!(s.len(), 6, "⌊log2 384 − 2⌋ = 6");
        assert_eq!(*s.last().unwrap(), (6, 6));
        assert_eq!(level_sizes(2, 2, false), vec![(1, 1)]);
        // 100 / 8 = 12.5 rounds to 12, as Mathf.RoundToInt (half to even) does.
        assert_eq!(level_sizes(100, 100, false), vec![(50, 50), (25, 25), (12, 12), (6, 6)]);
        // Quarter (Low): one level fewer, the same sizes below 800×450, half of them above.
        assert_eq!(level_sizes(384, 384, true), s[..5].to_vec());
        assert_eq!(level_sizes(1600, 900, true)[0], (400, 225));
        assert_eq!(level_sizes(1600, 900, false)[0], (800, 450));
        let low = BloomSettings::at(crate::pipelines::settings::HdrpQuality::Low);
        assert!(low.quarter && !low.high_quality_filtering);
        assert_eq!(BloomSettings::at(crate::pipelines::settings::HdrpQuality::Medium), BloomSettings::default());
        let hdrp = BloomSettings::default();
        assert!((hdrp.composite_weight() - 0.148698).abs() < 1e-6);
        assert!((hdrp.upsample_scatter() - 0.68).abs() < 1e-12);
        assert!(!hdrp.bicubic(799, 600) && !hdrp.bicubic(1024, 449) && hdrp.bicubic(800, 450));
    }
}

/// HDRP's bloom as a frame runs it: its pipeline (made for the first cell that blooms) and its
/// chain on the frame's colour target.
#[derive(Default)]
pub(in crate::render) struct BloomPass {
    pipeline: Option<BloomPipeline>,
    /// (the targets' generation, the chain on their colour)
    chain: Option<(u64, BloomChain)>,
}

impl BloomPass {
    /// Ready the pass for a frame on `targets` with `settings` (the chain is remade when either
    /// changes).
    pub(in crate::render) fn prepare(
        &mut self,
        gpu: &GpuContext,
        targets: &crate::render::targets::Targets,
        settings: BloomSettings,
    ) -> Result<(), Error> {
        if self.pipeline.is_none() {
            self.pipeline = Some(BloomPipeline::new(gpu)?);
        }
        let pipeline = self.pipeline.as_ref().expect("just made");
        let stale =
            |(generation, chain): &(u64, BloomChain)| *generation != targets.generation || chain.settings != settings;
        if self.chain.as_ref().is_none_or(stale) {
            let size = (targets.width, targets.height);
            let chain = BloomChain::new(&gpu.device, pipeline, &targets.color, size, settings);
            self.chain = Some((targets.generation, chain));
        }
        Ok(())
    }

    /// The prepared chain and its pipeline.
    pub(in crate::render) fn ready(&self) -> Option<(&BloomChain, &BloomPipeline)> {
        Some((&self.chain.as_ref()?.1, self.pipeline.as_ref()?))
    }
}
