//! The renderer's bake (render::gi): made for the first cell whose bake inputs it has not seen,
//! kept with the composition and shared by every later cell that reads the same.

use std::sync::Arc;

use super::{write_uniforms, CellParams, Renderer, ROLE_FIXED};
use crate::declarations::gi::GiSettings;
use crate::declarations::scene::Role;
use crate::error::Error;
use crate::plan::cell::CellPlan;
use crate::render::gi::lightmaps::{lightmap_from_sums, LightmapEncoding};
use crate::render::gi::{probes, BakedLighting};
use crate::render::prepared::PreparedScene;
use crate::render::truth::bake::{gather, BakeBudget, BakeLight, BakePoint, BakeSums};
use crate::render::truth::TruthKind;
use crate::shading::{wgsl, ShaderModel};

/// What one bake reads: the lights' shares, the static meshes, their materials and the points.
struct BakeInputs {
    key: u64,
    /// The lights the bake reads (values and shares) and the frame's environment, as bytes: part
    /// of the cross-run key, which is made only when the run has not this bake already.
    used_lights: Vec<u8>,
    frame: Vec<u8>,
    lights: Vec<BakeLight>,
    kept: Vec<bool>,
    objects: Vec<u8>,
    points: Vec<BakePoint>,
    texels: usize,
    probes: usize,
    gi: GiSettings,
    /// How the lightmap is stored (the plan's Lightmap Encoding).
    encoding: LightmapEncoding,
}

impl Renderer {
    /// The bake `cell` reads (None: its scene bakes nothing, or nothing baked can reach it).
    pub fn bake(&mut self, prepared: &PreparedScene, cell: &CellParams) -> Result<Option<Arc<BakedLighting>>, Error> {
        let plan = self.plan(prepared, cell)?;
        let fixed_model = self.fixed_model(cell.pipeline)?;
        self.baked_lighting(prepared, cell, &plan, &fixed_model)
    }

    /// The same bake gathered by the CPU tracer in f64 (render::truth::cpu::bake), never cached:
    /// an independent estimate to check the GPU's against.
    pub fn bake_on_cpu(&mut self, prepared: &PreparedScene, cell: &CellParams) -> Result<Option<BakedLighting>, Error> {
        let plan = self.plan(prepared, cell)?;
        let fixed_model = self.fixed_model(cell.pipeline)?;
        let Some(inputs) = self.bake_inputs(prepared, cell, &plan, &fixed_model) else { return Ok(None) };
        let start = std::time::Instant::now();
        let settings = crate::render::truth::TruthSettings { kind: TruthKind::SameBrdf, ..Default::default() };
        let (points, lights, budget) = (&inputs.points, &inputs.lights, (inputs.gi.samples, inputs.gi.bounces));
        let sums = self.with_cpu_truth(prepared, cell, &fixed_model, &settings, true, |scene, cpu_inputs| {
            crate::render::truth::cpu::bake::gather(scene, cpu_inputs, points, lights, budget)
        })?;
        let gathered = (&sums, inputs.gi.samples);
        Ok(Some(finish(prepared, &inputs, gathered, start.elapsed().as_secs_f64())))
    }

    /// The bake this cell's frame reads, made on first use.
    pub(in crate::render) fn baked_lighting(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
        fixed_model: &ShaderModel,
    ) -> Result<Option<Arc<BakedLighting>>, Error> {
        let Some(inputs) = self.bake_inputs(prepared, cell, plan, fixed_model) else { return Ok(None) };
        if let Some(b) = prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).get(&inputs.key) {
            return Ok(Some(b.clone()));
        }
        let disk_key = self.disk_key(prepared, cell, fixed_model, &inputs);
        if let Some((sums, record)) = self.bake_cache.as_ref().and_then(|c| c.load(&disk_key, inputs.points.len())) {
            let mut baked = finish(prepared, &inputs, (&sums, record.texel_samples), record.seconds);
            baked.cached = true;
            let baked = Arc::new(baked);
            prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).insert(inputs.key, baked.clone());
            return Ok(Some(baked));
        }
        let start = std::time::Instant::now();
        let pipeline_key =
            (cell.pipeline, format!("bake:{}", fixed_model.name), fixed_model.name.to_string(), TruthKind::SameBrdf);
        if !self.truth_pipelines.contains_key(&pipeline_key) {
            let source = wgsl::compose_truth(fixed_model, fixed_model);
            let diffuse_only = fixed_model.twin.is_some_and(|t| t.diffuse_only());
            let p = crate::render::truth::TruthPipeline::new(
                &self.gpu,
                &self.bindings.layout,
                &self.ray_layout,
                &source,
                cell.pipeline.shader_id(),
                TruthKind::SameBrdf,
                [diffuse_only; 2],
                "cs_bake",
            )?;
            self.truth_pipelines.insert(pipeline_key.clone(), p);
        }
        let frame_group = self.bindings.frame_group(&self.gpu, prepared, cell.settings.material_maps)?;
        let geometry = self.ray_scene(prepared, inputs.kept.clone())?;
        let budget = BakeBudget { samples: inputs.gi.samples, bounces: inputs.gi.bounces, noise: inputs.gi.noise };
        let gathered = gather(
            &self.gpu,
            &self.truth_pipelines[&pipeline_key],
            &frame_group,
            &geometry,
            &inputs.objects,
            &inputs.points,
            inputs.texels,
            &inputs.lights,
            budget,
        )?;
        let sums = gathered.sums;
        let at = (&sums, gathered.texel_samples);
        let baked = Arc::new(finish(prepared, &inputs, at, start.elapsed().as_secs_f64()));
        if let Some(cache) = &self.bake_cache {
            let record = crate::render::gi::cache::BakeCacheRecord {
                schema: crate::render::gi::cache::BAKE_CACHE_SCHEMA,
                key: disk_key.clone(),
                points: inputs.points.len(),
                samples: inputs.gi.samples,
                texel_samples: gathered.texel_samples,
                bounces: inputs.gi.bounces,
                seconds: baked.seconds,
                adapter: self.gpu.adapter.get_info().name,
            };
            cache.store(&record, &sums)?;
        }
        prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).insert(inputs.key, baked.clone());
        Ok(Some(baked))
    }

    /// The bake's key across runs (render::gi::cache): the composed tracer, the scene as parsed,
    /// the Lighting Settings, the points, the static objects' materials, the lights and frame it
    /// reads, the meshes kept, and the adapter.
    fn disk_key(
        &self,
        prepared: &PreparedScene,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        inputs: &BakeInputs,
    ) -> String {
        let source = wgsl::compose_truth(fixed_model, fixed_model);
        let scene = serde_json::to_vec(&prepared.scene).unwrap_or_default();
        let settings = serde_json::to_vec(&inputs.gi).unwrap_or_default();
        let kept: Vec<u8> = inputs.kept.iter().map(|k| *k as u8).collect();
        crate::render::gi::cache::key(&[
            cell.pipeline.name().as_bytes(),
            source.as_bytes(),
            &scene,
            &settings,
            bytemuck::cast_slice(&inputs.points),
            &inputs.objects,
            &inputs.used_lights,
            &kept,
            &inputs.frame,
            self.gpu.adapter.get_info().name.as_bytes(),
        ])
    }

    /// What this cell's bake reads, and its key; None where nothing baked can reach the frame.
    /// Writes the cell's uniforms without baked light (the bake reads the frame's lights).
    fn bake_inputs(
        &self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
        fixed_model: &ShaderModel,
    ) -> Option<BakeInputs> {
        let (Some(gi_plan), Some(gi)) = (&plan.gi, &prepared.scene.gi) else { return None };
        let written = write_uniforms(&self.gpu.queue, prepared, cell, plan, fixed_model, None);
        if !gi_plan.needs_bake(written.frame.env[1] > 0.0) {
            return None;
        }
        let lights: Vec<BakeLight> = gi_plan
            .lights
            .iter()
            .zip(&plan.lights)
            .map(|(b, l)| BakeLight {
                weights: [
                    b.direct_in_lightmaps as u32 as f32,
                    b.direct_in_probes as u32 as f32,
                    b.indirect as f32,
                    b.shadow_mask.or(b.probe_occlusion).map_or(-1.0, f32::from),
                ],
                shape: [
                    l.baked_shadow_radius as f32,
                    (l.baked_shadow_angle_deg * 0.5).to_radians().tan() as f32,
                    0.0,
                    0.0,
                ],
            })
            .collect();
        // Static objects alone, at their first LOD level whatever the camera draws ("only LOD0
        // affects the surrounding geometry", Unity manual, LOD for baked lightmaps): dynamic
        // objects (the subjects) are not in the bake, nor transparent ones (the window glass lets
        // the light through, as the lightmapper's transparency does for a pane that casts none).
        let first_levels = prepared.scene.objects.len();
        let kept: Vec<bool> = prepared
            .layout
            .meshes
            .iter()
            .enumerate()
            .map(|(i, m)| i < first_levels && m.role == Role::Fixed && !m.transparent)
            .collect();
        let mut objects = Vec::with_capacity(prepared.objects.len() * 128);
        for material in &written.materials {
            objects.extend_from_slice(bytemuck::bytes_of(material));
            objects.extend_from_slice(bytemuck::cast_slice(&[0u32, ROLE_FIXED as u32, 0, 0]));
        }
        // The lightmap's texels first, then the probes.
        let texels = prepared.lightmap.as_ref().map_or(&[][..], |a| &a.texels[..]);
        let grid: Vec<[f64; 3]> = gi.probes.as_ref().map(|g| g.positions()).unwrap_or_default();
        let points: Vec<BakePoint> = texels
            .iter()
            .map(|t| BakePoint::texel(t.position, t.normal))
            .chain(grid.iter().map(|p| BakePoint::probe([p[0] as f32, p[1] as f32, p[2] as f32])))
            .collect();
        let key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            cell.pipeline.name().hash(&mut h);
            fixed_model.name.hash(&mut h);
            serde_json::to_string(gi).unwrap_or_default().hash(&mut h);
            kept.hash(&mut h);
            for (slot, k) in prepared.layout.meshes.iter().zip(&kept) {
                if *k {
                    bytemuck::bytes_of(&written.materials[slot.scene_index]).hash(&mut h);
                }
            }
            let f = &written.frame;
            (bytemuck::bytes_of(&f.env), bytemuck::bytes_of(&f.fixed), f.counts).hash(&mut h);
            // A light the bake holds nothing of does not reach it.
            for (l, b) in written.lights.iter().zip(&lights) {
                if b.weights[..3].iter().any(|w| *w != 0.0) || b.weights[3] >= 0.0 {
                    bytemuck::bytes_of(l).hash(&mut h);
                    bytemuck::bytes_of(b).hash(&mut h);
                }
            }
            h.finish()
        };
        let f = &written.frame;
        let used_lights: Vec<u8> = written
            .lights
            .iter()
            .zip(&lights)
            .filter(|(_, b)| b.weights[..3].iter().any(|w| *w != 0.0) || b.weights[3] >= 0.0)
            .flat_map(|(l, b)| [bytemuck::bytes_of(l), bytemuck::bytes_of(b)].concat())
            .collect();
        let frame = [bytemuck::bytes_of(&f.env), bytemuck::bytes_of(&f.fixed), bytemuck::bytes_of(&f.counts)].concat();
        Some(BakeInputs {
            key,
            used_lights,
            frame,
            lights,
            kept,
            objects,
            points,
            texels: texels.len(),
            probes: grid.len(),
            gi: gi.clone(),
            encoding: LightmapEncoding::of_quality(gi_plan.encoding),
        })
    }
}

/// The bake from the gathered sums and the samples its texels took: the probes' SH and the
/// encoded lightmap.
fn finish(
    prepared: &PreparedScene,
    inputs: &BakeInputs,
    (sums, texel_samples): (&BakeSums, u32),
    seconds: f64,
) -> BakedLighting {
    let gi = &inputs.gi;
    let probes = gi.probes.as_ref().map(|_| probes::probes_from_sums(sums, inputs.texels, inputs.probes));
    let lightmap = prepared
        .lightmap
        .as_ref()
        .filter(|a| !a.texels.is_empty())
        .map(|a| lightmap_from_sums(a, sums, 0, inputs.encoding, gi.padding));
    BakedLighting {
        key: inputs.key,
        probes,
        lightmap,
        directional: gi.directional,
        samples: gi.samples,
        texel_samples,
        noise_target: gi.noise,
        bounces: gi.bounces,
        seconds,
        cached: false,
    }
}
