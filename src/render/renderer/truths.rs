//! The renderer's truths (render::truth): which backend traces a cell, the CPU backend's inputs,
//! what a truth reads (its cache key's content, so that cells whose truths read the same share one)
//! and the scene as a truth sees it exported for other renderers (`[outputs] truth_scene`).

use glam::DVec3;

use super::{write_uniforms, CellParams, Renderer, ROLE_FIXED, ROLE_SUBJECT};
use crate::declarations::scene::Role;
use crate::error::Error;
use crate::geometry::procedural;
use crate::render::prepared::PreparedScene;
use crate::render::truth::TruthKind;
use crate::shading::twin::irradiance_per_intensity;
use crate::shading::{wgsl, ShaderModel};

impl Renderer {
    /// The ground truth of a cell (render::truth): its scene, lights and materials path traced
    /// with the models the cell draws them with (`same-brdf`) or the physical model (`physical`). The meshes are the cell's drawn ones; in a
    /// LOD cross-fade band, the outgoing level alone (the one the shadow pass draws whole).
    pub fn render_truth(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        settings: &crate::render::truth::TruthSettings,
    ) -> Result<crate::render::truth::Truth, Error> {
        let fixed_model = self.fixed_model(cell.pipeline)?;
        let pane = self.plan(prepared, cell)?.transparent_fixed.first().cloned();
        if self.truth_on_cpu(cell, &fixed_model, settings, pane.as_deref())? {
            return self.render_truth_cpu(prepared, cell, &fixed_model, settings);
        }
        let key = (cell.pipeline, cell.model.name.to_string(), fixed_model.name.to_string(), settings.kind);
        if !self.truth_pipelines.contains_key(&key) {
            let source = wgsl::compose_truth(cell.model, &fixed_model);
            let id = cell.pipeline.shader_id();
            let p = crate::render::truth::TruthPipeline::new(
                &self.gpu,
                &self.bindings.layout,
                &self.ray_layout,
                &source,
                id,
                settings.kind,
                [cell.model, &fixed_model].map(|m| m.twin.is_some_and(|t| t.diffuse_only())),
                "cs_truth",
            )?;
            self.truth_pipelines.insert(key.clone(), p);
        }
        let plan = self.plan(prepared, cell)?;
        let written = write_uniforms(&self.gpu.queue, prepared, cell, &plan, &fixed_model, None);
        let frame_group = self.bindings.frame_group(&self.gpu, prepared, cell.settings.material_maps)?;
        let geometry = self.ray_scene(prepared, plan.casting())?;
        let textured = cell.settings.material_maps.is_some();
        let mut objects = Vec::with_capacity(prepared.objects.len() * 128);
        for (slot, material) in prepared.layout.meshes.iter().zip(&written.materials) {
            objects.extend_from_slice(bytemuck::bytes_of(material));
            let flags: [u32; 4] = match slot.role {
                Role::Subject => [1, ROLE_SUBJECT as u32, textured as u32, 0],
                Role::Fixed => [0, ROLE_FIXED as u32, 0, 0],
            };
            objects.extend_from_slice(bytemuck::cast_slice(&flags));
        }
        let inputs = crate::render::truth::TruthInputs {
            scene: &geometry,
            objects: &objects,
            background: prepared.plan.background,
            size: (cell.width, cell.height),
            subject_role: ROLE_SUBJECT,
        };
        crate::render::truth::trace(&self.gpu, &self.truth_pipelines[&key], &frame_group, &inputs, settings)
    }

    /// Whether this cell's truth is traced on the CPU (`TruthBackend`): `auto` on a CPU adapter
    /// where both models have f64 twins and the subject is untextured, and wherever a surface lets
    /// rays through (a subject not all there, `pane`: a drawn fixed object in the Transparent
    /// queue); `cpu` refuses a cell it cannot trace.
    fn truth_on_cpu(
        &self,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        settings: &crate::render::truth::TruthSettings,
        pane: Option<&str>,
    ) -> Result<bool, Error> {
        use crate::declarations::matrix::TruthBackend;
        let twins = cell.model.twin.is_some() && fixed_model.twin.is_some();
        let coverage = subject_coverage(cell)?;
        // Only the CPU tracer lets rays through a surface; a textured cutout or Fade subject is
        // not all there wherever its alpha map says so.
        let textured_see_through = cell.settings.material_maps.is_some()
            && matches!(
                cell.settings.surface.kind,
                crate::pipelines::surface::SurfaceType::Cutout | crate::pipelines::surface::SurfaceType::Fade
            );
        // What lets rays through, which only the CPU tracer traces: a pane first, then the subject.
        let see_through = match pane {
            Some(name) => Some(format!("the transparent fixed object `{name}`")),
            None => (coverage < 1.0 || textured_see_through)
                .then(|| format!("this cell's `{}` subject", cell.settings.surface.kind.name())),
        };
        if let Some(what) = see_through {
            return match settings.backend {
                TruthBackend::Gpu => Err(Error::Other(format!(
                    "truth backend \"gpu\" draws every surface opaque and cannot let rays through {what}: use \
                     backend = \"cpu\" or \"auto\""
                ))),
                _ if !twins && settings.kind == TruthKind::SameBrdf => Err(Error::Other(format!(
                    "`{}` has no f64 twin, and only the CPU tracer traces {what}",
                    cell.model.name
                ))),
                _ => Ok(true),
            };
        }
        let why_not = if !twins && settings.kind == TruthKind::SameBrdf {
            Some(format!("`{}` has no f64 twin (a user model)", cell.model.name))
        } else {
            None
        };
        Ok(match (settings.backend, why_not) {
            (TruthBackend::Gpu, _) => false,
            (TruthBackend::Cpu, None) => true,
            (TruthBackend::Cpu, Some(why)) => {
                return Err(Error::Other(format!(
                    "truth backend \"cpu\" cannot trace this cell: {why}; use backend = \"gpu\" or \"auto\""
                )))
            }
            (TruthBackend::Auto, None) if settings.sampler == crate::declarations::matrix::TruthSampler::Sobol => true,
            (TruthBackend::Auto, Some(why)) if settings.sampler == crate::declarations::matrix::TruthSampler::Sobol => {
                return Err(Error::Other(format!(
                    "the Sobol sampler runs on the CPU backend, which cannot trace this cell: {why}; use sampler = \"independent\""
                )))
            }
            // A textured opaque subject stays on the GPU tracer under `auto`, as its truths were traced.
            (TruthBackend::Auto, why) => {
                why.is_none()
                    && self.gpu.adapter.get_info().device_type == wgpu::DeviceType::Cpu
                    && cell.settings.material_maps.is_none()
            }
        })
    }

    fn render_truth_cpu(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        settings: &crate::render::truth::TruthSettings,
    ) -> Result<crate::render::truth::Truth, Error> {
        self.with_cpu_truth(prepared, cell, fixed_model, settings, false, |scene, inputs| {
            crate::render::truth::cpu::trace(scene, inputs, settings)
        })
    }

    /// `then` with the CPU truth's scene (built once per composition and set of kept meshes) and
    /// this cell's inputs.
    pub(super) fn with_cpu_truth<T>(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        settings: &crate::render::truth::TruthSettings,
        static_only: bool,
        then: impl FnOnce(
            &crate::render::truth::cpu::CpuScene,
            &crate::render::truth::cpu::CpuTruthInputs,
        ) -> Result<T, Error>,
    ) -> Result<T, Error> {
        use crate::render::truth::cpu;
        let plan = self.plan(prepared, cell)?;
        let written = write_uniforms(&self.gpu.queue, prepared, cell, &plan, fixed_model, None);
        // A bake traces the static (fixed) objects alone, without the panes (`Renderer::bake`).
        let kept: Vec<bool> = plan
            .casting()
            .iter()
            .zip(&prepared.layout.meshes)
            .map(|(c, m)| *c && !(static_only && (m.role == Role::Subject || m.transparent)))
            .collect();
        let cached = prepared.cpu_truth_scene.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let scene = match cached {
            Some((k, s)) if k == kept => s,
            _ => {
                let geometry = truth_geometry(prepared, &kept)?;
                let environment = cpu::CpuEnvironment::new(&truth_sky(&prepared.scene));
                let s = std::sync::Arc::new(cpu::CpuScene::new(geometry, environment)?);
                *prepared.cpu_truth_scene.lock().unwrap_or_else(|e| e.into_inner()) = Some((kept, s.clone()));
                s
            }
        };
        let materials: Vec<_> = prepared
            .layout
            .meshes
            .iter()
            .zip(&written.materials)
            .map(|(slot, m)| (*m, slot.role == Role::Subject))
            .collect();
        let glass: Vec<bool> =
            prepared.layout.meshes.iter().map(|m| m.role == Role::Fixed && m.transparent && !static_only).collect();
        let twins = (cell.model.twin, fixed_model.twin);
        if settings.kind == TruthKind::SameBrdf && (twins.0.is_none() || twins.1.is_none()) {
            return Err(Error::Other(format!("`{}` has no f64 twin for the CPU truth", cell.model.name)));
        }
        let subject_maps = match cell.settings.material_maps {
            Some(maps) => Some(crate::render::prepared::subject_maps(prepared, maps)?),
            None => None,
        };
        let inputs = cpu::CpuTruthInputs {
            pipeline: cell.pipeline,
            kind: settings.kind,
            subject_twin: twins.0,
            fixed_twin: twins.1,
            frame: &written.frame,
            lights: &written.lights,
            materials: &materials,
            glass: &glass,
            background: prepared.plan.background,
            size: (cell.width, cell.height),
            subject_role: ROLE_SUBJECT,
            fixed_role: ROLE_FIXED,
            fixed_maps: &prepared.fixed_maps.maps,
            subject_coverage: subject_coverage(cell)?,
            subject_maps: subject_maps.as_deref(),
            subject_detail: subject_maps.is_some() && cell.model.draws_detail(&cell.surface),
            subject_surface: cell.settings.surface,
        };
        then(&scene, &inputs)
    }

    /// The scene as this cell's physical truth traces it, with `truth`, for another renderer
    /// (render::truth::export).
    pub fn export_truth_scene(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        settings: &crate::render::truth::TruthSettings,
        truth: &crate::render::truth::Truth,
    ) -> Result<crate::render::truth::export::TruthSceneExport, Error> {
        let fixed_model = self.fixed_model(cell.pipeline)?;
        if subject_coverage(cell)? < 1.0 {
            return Err(Error::Other(
                "the exported truth scene holds opaque surfaces only; this cell's subject is not all there".into(),
            ));
        }
        if let Some(name) = self.plan(prepared, cell)?.transparent_fixed.first() {
            return Err(Error::Other(format!(
                "the exported truth scene holds opaque surfaces only; the fixed object `{name}` is transparent"
            )));
        }
        let objects = &prepared.scene.objects;
        let names: Vec<String> = (0..prepared.layout.meshes.len())
            .map(|i| objects.get(i).map_or_else(|| format!("lod mesh {}", i - objects.len()), |o| o.name.clone()))
            .collect();
        self.with_cpu_truth(prepared, cell, &fixed_model, settings, false, |scene, inputs| {
            crate::render::truth::export::export(scene, inputs, &names, truth, settings.roulette)
        })
    }

    /// Everything this cell's truth reads that differs between cells of one run — the backend,
    /// the settings, the image size, the meshes kept, the camera, the lights and every material as
    /// the tracer reads them, and for a same-brdf truth or the GPU tracer the pipeline and the
    /// models — so that cells whose truths read the same share one. A physical truth reads no
    /// model and its lights only times the pipeline's irradiance per intensity: cells of one
    /// preset with different shaders, or pipelines whose lights agree, share it. The scene's
    /// files, the tool and the adapter are the caller's part of the key.
    pub fn truth_reads(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        settings: &crate::render::truth::TruthSettings,
    ) -> Result<serde_json::Value, Error> {
        let fixed_model = self.fixed_model(cell.pipeline)?;
        let plan = self.plan(prepared, cell)?;
        let on_cpu =
            self.truth_on_cpu(cell, &fixed_model, settings, plan.transparent_fixed.first().map(String::as_str))?;
        let written = write_uniforms(&self.gpu.queue, prepared, cell, &plan, &fixed_model, None);
        let f = &written.frame;
        let physical = settings.kind == TruthKind::Physical && on_cpu;
        let material = |m: &crate::render::uniforms::GpuMaterial| -> serde_json::Value {
            if physical {
                serde_json::json!([m.base_color, m.params, m.checker_color, m.emission])
            } else {
                serde_json::json!(bytemuck::cast_slice::<_, u32>(std::slice::from_ref(m)))
            }
        };
        let materials: Vec<serde_json::Value> = prepared
            .layout
            .meshes
            .iter()
            .zip(&written.materials)
            .map(|(slot, m)| match slot.role {
                Role::Subject => serde_json::json!("subject"),
                // A pane draws its own random numbers (`cpu::glass`).
                Role::Fixed if slot.transparent => serde_json::json!(["pane", material(m)]),
                Role::Fixed => material(m),
            })
            .collect();
        let lights: Vec<serde_json::Value> = written
            .lights
            .iter()
            .map(|l| {
                if physical {
                    let k = irradiance_per_intensity(cell.pipeline) as f32;
                    serde_json::json!([l.position, l.direction, l.color.map(|c| c * k), l.params[1], l.params[2]])
                } else {
                    serde_json::json!([l.position, l.direction, l.color, l.params])
                }
            })
            .collect();
        let models = (!physical).then(|| {
            serde_json::json!({
                "pipeline": cell.pipeline,
                "source": wgsl::compose_truth(cell.model, &fixed_model),
                "material_maps": format!("{:?}", cell.settings.material_maps),
                "counts": f.counts,
            })
        });
        let mut reads = serde_json::json!({
            "backend": if on_cpu { "cpu" } else { "gpu" },
            "settings": format!("{settings:?}"),
            "size": [cell.width, cell.height],
            "background": prepared.plan.background,
            "kept": plan.casting(),
            "camera": [f.inv_view_proj, [f.camera_pos]],
            "environment": f.env[1],
            "subject": material(&f.subject),
            "subject_coverage": subject_coverage(cell)?,
            "materials": materials,
            "lights": lights,
            "models": models,
        });
        // A textured subject's maps, and how its surface reads their alpha (in every truth kind;
        // untextured cells' reads stay as they were).
        if let Some(maps) = cell.settings.material_maps {
            reads["subject_maps"] = serde_json::json!([maps, format!("{:?}", cell.settings.surface)]);
        }
        Ok(reads)
    }
}

/// The sky as either truth backend samples it: an ENV_WIDTH × ENV_WIDTH/2 equirect.
/// How much of the subject's surface is there, as a path tracer sees it: all of an opaque one,
/// alpha of a Fade surface (alpha blending stands for a screen door), all or none of a cutout.
/// The premultiplied, additive and multiplying surfaces stand for no such surface (their
/// reflections stay whole while the rest fades): refused.
fn subject_coverage(cell: &CellParams) -> Result<f64, Error> {
    use crate::pipelines::surface::SurfaceType;
    let o = cell.settings.surface;
    Ok(match o.kind {
        SurfaceType::Opaque => 1.0,
        SurfaceType::Cutout => (o.alpha >= o.cutoff) as u32 as f64,
        SurfaceType::Fade => o.alpha.clamp(0.0, 1.0),
        other => {
            return Err(Error::Other(format!(
                "the path-traced truth has no counterpart of a `{}` surface (its reflection stays whole while its \
                 diffuse light fades, which no physical surface does); `fade` and `cutout` are traced as coverage",
                other.name()
            )))
        }
    })
}

pub(super) fn truth_sky(scene: &crate::declarations::scene::Scene) -> crate::environment::prefilter::EquirectImage {
    let radiance = |d: DVec3| crate::environment::sky::radiance(&scene.environment.sky, d);
    let w = crate::render::truth::ENV_WIDTH;
    crate::environment::prefilter::EquirectImage::sample(&radiance, w, w / 2, 2)
}

/// The meshes a cell keeps (`kept`, per object) in world space with their BVH, for either backend.
pub(super) fn truth_geometry(
    prepared: &PreparedScene,
    kept: &[bool],
) -> Result<crate::render::truth::bvh::TruthGeometry, Error> {
    let mut meshes = procedural::build_scene(&prepared.scene)?;
    meshes.extend(procedural::lod_meshes(&prepared.scene)?.into_iter().map(|(_, _, m)| m));
    let objects = prepared.objects.iter().zip(&meshes).enumerate().filter(|(i, _)| kept[*i]);
    Ok(crate::render::truth::bvh::TruthGeometry::build(objects.map(|(i, (o, m))| (i as u32, m, o.model))))
}
