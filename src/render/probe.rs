//! GPU evaluation of one model for given inputs (compute pass), the counterpart of the f64 twins.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::error::Error;
use crate::gpu::{readback::map_read, GpuContext};
use crate::pipelines::Pipeline;
use crate::shading::twin::Surface;
use crate::shading::{wgsl, ShaderModel};
use glam::DVec3;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, Default)]
pub struct ProbeInput {
    pub n: [f32; 4],
    pub v: [f32; 4],
    pub l: [f32; 4],
    pub base_color: [f32; 4],
    /// metallic (as the shader receives it), smoothness
    pub params: [f32; 4],
    pub gi_diffuse: [f32; 4],
    pub gi_specular: [f32; 4],
    pub specular: [f32; 4],
    pub model0: [f32; 4],
    pub model1: [f32; 4],
    pub model2: [f32; 4],
    /// The surface's tangent (`Surface::tangent`).
    pub tangent: [f32; 4],
}

impl ProbeInput {
    /// Directions and ambient for `s`, rounded to f32 as the GPU receives them.
    pub fn new(s: &Surface, n: DVec3, v: DVec3, l: DVec3, gi_diffuse: DVec3, gi_specular: DVec3) -> Self {
        let v4 = |x: DVec3| [x.x as f32, x.y as f32, x.z as f32, 0.0];
        let p = s.params.map(|x| x as f32);
        ProbeInput {
            n: v4(n),
            v: v4(v),
            l: [l.x as f32, l.y as f32, l.z as f32, crate::shading::twin::default_light_min_roughness() as f32],
            base_color: v4(s.base_color),
            params: [s.metallic as f32, s.smoothness as f32, 0.0, 0.0],
            gi_diffuse: v4(gi_diffuse),
            gi_specular: v4(gi_specular),
            specular: v4(s.specular),
            model0: [p[0], p[1], p[2], p[3]],
            model1: [p[4], p[5], p[6], p[7]],
            model2: [p[8], p[9], p[10], p[11]],
            tangent: v4(s.tangent),
        }
    }
}

impl ProbeInput {
    /// The light's HDRP roughness floor (`Emitter::hdrp_min_roughness`).
    pub fn with_min_roughness(mut self, min_roughness: f64) -> Self {
        self.l[3] = min_roughness as f32;
        self
    }
}

/// `model_direct` and `model_indirect` of one input, linear RGB.
pub type ProbeOutput = ([f32; 3], [f32; 3]);

/// With the direction the model fetched the environment along (zero if it did not).
pub type ProbeOutputFull = ([f32; 3], [f32; 3], [f32; 3]);

/// The compute layouts, the FGD table and one pipeline per (pipeline, model), built once per
/// device and reused for every evaluation (the audit evaluates each model several times).
pub struct BrdfProbe {
    bind_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    fgd: wgpu::TextureView,
    pipelines: std::collections::HashMap<(Pipeline, String, String, u32), wgpu::ComputePipeline>,
}

impl BrdfProbe {
    pub fn new(gpu: &GpuContext) -> BrdfProbe {
        let device = &gpu.device;
        let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        // Explicit: an automatic layout would drop the FGD table for models that never read it.
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("brdf probe"),
            entries: &[
                storage(0, true),
                storage(1, false),
                crate::render::luts::fgd_layout_entry(2, wgpu::ShaderStages::COMPUTE),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("brdf probe"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        BrdfProbe { bind_layout, layout, fgd: crate::render::luts::fgd_texture(gpu), pipelines: Default::default() }
    }

    fn pipeline(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        terms: u32,
    ) -> Result<&wgpu::ComputePipeline, Error> {
        // Keyed by source path too: user models may share a name across folders in one process.
        let key = (pipeline, model.name.to_string(), model.source_path.to_string(), terms);
        if !self.pipelines.contains_key(&key) {
            let source = wgsl::compose(wgsl::PassKind::BrdfProbe, Some(model));
            let module = gpu.shader_module(&format!("probe {}/{}", pipeline.name(), model.name), &source)?;
            let constants = [("PIPELINE", pipeline.shader_id() as f64), ("TERMS", terms as f64)];
            let compute = gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("brdf probe"),
                layout: Some(&self.layout),
                module: &module,
                entry_point: Some("probe_main"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                cache: None,
            });
            self.pipelines.insert(key.clone(), compute);
        }
        Ok(&self.pipelines[&key])
    }

    /// (direct, indirect) per input, as `model_direct` and `model_indirect` return them.
    pub fn evaluate(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        inputs: &[ProbeInput],
    ) -> Result<Vec<ProbeOutput>, Error> {
        Ok(self.evaluate_full(gpu, pipeline, model, inputs)?.into_iter().map(|(d, i, _)| (d, i)).collect())
    }

    /// (direct, indirect, environment fetch direction) per input.
    pub fn evaluate_full(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        inputs: &[ProbeInput],
    ) -> Result<Vec<ProbeOutputFull>, Error> {
        self.evaluate_terms(gpu, pipeline, model, inputs, crate::pipelines::terms::LIGHT)
    }

    /// The same with the model compiled for the term bits `terms` (pipelines::terms): each lobe
    /// kept only where its term is, as a term layer draws it.
    pub fn evaluate_terms(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        inputs: &[ProbeInput],
        terms: u32,
    ) -> Result<Vec<ProbeOutputFull>, Error> {
        if inputs.is_empty() {
            return Ok(Vec::new());
        }
        self.pipeline(gpu, pipeline, model, terms)?;
        let compute = &self.pipelines[&(pipeline, model.name.to_string(), model.source_path.to_string(), terms)];
        let device = &gpu.device;
        let input_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe inputs"),
            contents: bytemuck::cast_slice(inputs),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let out_size = (inputs.len() * 3 * 16) as u64;
        let output_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe outputs"),
            size: out_size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe staging"),
            size: out_size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("probe"),
            layout: &self.bind_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: input_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: output_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&self.fgd) },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(compute);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups((inputs.len() as u32).div_ceil(64), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&output_buf, 0, &staging, 0, out_size);
        gpu.queue.submit([encoder.finish()]);
        let bytes = map_read(device, &staging)?;
        gpu.check_errors("evaluating the BRDF probe")?;
        let floats: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        let rgb = |v: [f32; 4]| [v[0], v[1], v[2]];
        Ok(floats.chunks_exact(3).map(|p| (rgb(p[0]), rgb(p[1]), rgb(p[2]))).collect())
    }
}

/// One-shot evaluation (builds a probe for this call); prefer a `BrdfProbe` for many calls.
pub fn evaluate(
    gpu: &GpuContext,
    pipeline: Pipeline,
    model: &ShaderModel,
    inputs: &[ProbeInput],
) -> Result<Vec<ProbeOutput>, Error> {
    BrdfProbe::new(gpu).evaluate(gpu, pipeline, model, inputs)
}
