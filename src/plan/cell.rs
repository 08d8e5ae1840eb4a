//! A cell's plan, decided on the CPU before any GPU work: where its camera stands, its lights and
//! how each reaches each object, which shadow layers it renders at what resolution, which LOD
//! levels it draws with what cross-fade, its passes and its samples per pixel. The renderer
//! consumes a `CellPlan` and decides nothing; `cell.json` records what it says.

use glam::DVec3;

use super::camera::{cell_lights, posed_camera, ViewAxes};
use super::draws::{plan_draws, DrawPlan, GBufferModels};
use super::exact::ExactAlternatives;
use super::lights::{assign, main_light, LightBudget, ModelLighting, ObjectLights};
use super::lod::{groups_seen, LodUse};
use super::pass::{frame_passes, Pass, PassInputs};
use super::shadows::{
    array_side, cell_resolution, light_layers, shadow_style, CascadeView, ShadowLayerPlan, ShadowStyle,
};
use super::{FramePlan, ShadowMapUse};
use crate::declarations::scene::{Camera, Light, LightKind, Role, Scene};
use crate::geometry::Mesh;
use crate::pipelines::{Antialiasing, Pipeline, RenderPath};
use crate::shading::twin::Surface;
use crate::shading::ShaderModel;

/// What one cell asks (no matrix types: plans and the renderer know scenes, not sweeps).
#[derive(Debug, Clone, Copy)]
pub struct CellParams<'a> {
    pub pipeline: Pipeline,
    pub model: &'a ShaderModel,
    /// The subject's material as the model receives it (`ShaderModel::surface`).
    pub surface: Surface,
    pub light_intensity: f64,
    pub light_range: f64,
    pub width: u32,
    pub height: u32,
    /// Camera distance and light angle, where the cell sets them.
    pub view: ViewAxes,
    /// The rendering path and the light budgets.
    pub settings: CellSettings,
}

impl<'a> CellParams<'a> {
    /// Whether a deferred path draws the subject into its G-buffer: its model has a G-buffer pass
    /// and its surface is not transparent (the engines draw the Transparent queue forward).
    pub fn subject_deferrable(&self) -> bool {
        super::draws::gbuffer_pass(self.pipeline, self.model)
            && !self.settings.surface.kind.is_transparent()
            && self.subsurface().is_none()
    }

    /// The subject's subsurface scattering, where its frame filters it (`subsurface::subsurface`).
    pub fn subsurface(&self) -> Option<super::subsurface::SubsurfacePlan> {
        super::subsurface::subsurface(self.pipeline, self.model, &self.surface.params, self.settings.surface.kind)
    }

    /// What a matrix cell asks: its coordinates resolved (material, emission, maps) into what the
    /// renderer reads, with the pipeline as it ships (no exact alternatives).
    pub fn of(cell: &'a crate::cells::Cell) -> CellParams<'a> {
        CellParams {
            pipeline: cell.pipeline,
            model: cell.model(),
            surface: cell.surface(),
            light_intensity: cell.light_intensity,
            light_range: cell.light_range,
            width: cell.width,
            height: cell.height,
            view: ViewAxes { camera_distance: cell.camera_distance, light_angle: cell.light_angle },
            settings: CellSettings {
                path: cell.path,
                light_budget: cell.light_budget,
                engine: cell.pipeline_settings,
                antialiasing: cell.antialiasing,
                material_maps: cell.material_maps(),
                // A glTF's own emissive colour glows as the file says unless the axis scales it.
                emission: cell.emission.unwrap_or(if cell.own_material() { 1.0 } else { 0.0 }),
                emission_color: cell.material.emissive_linear,
                ambient_intensity: cell.ambient_intensity,
                exact: Default::default(),
                surface: cell.surface_options(),
                carried_workflow: cell.workflow_source(),
            },
        }
    }
}

/// What a cell sets besides its material and light: the path, the light budgets and MSAA.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CellSettings {
    pub path: RenderPath,
    pub light_budget: LightBudget,
    /// The engine settings: the URP asset, built-in's pass structure.
    pub engine: crate::pipelines::settings::PipelineSettings,
    pub antialiasing: Antialiasing,
    /// The preset whose textured form the subject wears (None: flat).
    pub material_maps: Option<&'static str>,
    /// The emission axis (0: none); the model decides whether it emits.
    pub emission: f64,
    /// The emitted colour the axis scales (linear), where it is not the base colour: a glTF
    /// subject's own `emissiveFactor`.
    pub emission_color: Option<[f64; 3]>,
    /// The scene's environment light (its SH ambient, reflections and visible sky) scaled by this
    /// factor; None: as the scene sets it.
    pub ambient_intensity: Option<f64>,
    /// The approximation study's exact alternatives (none: the pipeline as it ships).
    pub exact: ExactAlternatives,
    /// The subject's surface type, alpha and cutoff.
    pub surface: crate::pipelines::surface::SurfaceOptions,
    /// Where the subject's specular workflow is carried over from its metallic workflow (and no
    /// specular axis sets the colour), what from: with maps, the shaders carry it over per texel.
    pub carried_workflow: Option<crate::shading::registry::WorkflowSource>,
}

/// The samples per pixel a cell renders with, and why they differ from what it asked, if they do.
#[derive(Debug, Clone, PartialEq)]
pub struct Multisampling {
    pub samples: u32,
    pub note: Option<String>,
}

/// What the adapter multisamples: the sample counts that every forward target resolves with, and
/// how a note names the adapter and the formats.
#[derive(Debug, Clone, PartialEq)]
pub struct MsaaSupport {
    pub counts: Vec<u32>,
    /// "<adapter> multisamples <formats>".
    pub what: String,
}

impl MsaaSupport {
    /// The samples a cell asking `asked` (after its path's rule, `why_one`) renders with: the
    /// largest count up to `asked` the adapter supports.
    pub fn multisampling(&self, asked: u32, why_one: Option<&str>) -> Multisampling {
        let used = self.counts.iter().copied().filter(|&n| n <= asked).max().unwrap_or(1);
        let note = if used != asked {
            let counts: Vec<String> = self.counts.iter().map(|n| format!("{n}×")).collect();
            Some(format!(
                "{asked}× MSAA asked; {} at {}: rendered {used}×",
                self.what,
                if counts.is_empty() { "no count".to_string() } else { counts.join(", ") }
            ))
        } else {
            why_one.map(str::to_string)
        };
        Multisampling { samples: used, note }
    }

    pub fn for_settings(&self, settings: &CellSettings) -> Multisampling {
        let (asked, why_one) = settings.antialiasing.samples_on(settings.path);
        self.multisampling(asked, why_one)
    }
}

/// One mesh the composition draws: a scene object's, or one of its further LOD levels.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshSlot {
    pub role: Role,
    /// The scene object it draws.
    pub scene_index: usize,
    /// Its level in the object's LOD group, if it has one.
    pub lod_level: Option<usize>,
    pub cast_shadows: bool,
    /// The faces its pipelines draw (`Object::render_face`).
    pub render_face: crate::pipelines::surface::RenderFace,
    /// A fixed object in the Transparent queue (its material's surface; the subject's queue is
    /// its cell's).
    pub transparent: bool,
}

/// The composition's shadow array: per scene light its first layer when it casts shadows (a
/// directional light reserves `MAX_CASCADES`, a point light 6, a spot 1), the layer count and the
/// layers' side (`shadows::array_side`: the largest map its lights can ask for). Without a shadow
/// pass in the frame plan no light has layers and one unused 1×1 layer is bound.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowArray {
    pub first_layer: Vec<Option<usize>>,
    pub layers: usize,
    pub side: u32,
}

/// A composition's meshes and bounds as cell plans need them: made once per composition, from
/// the scene and its meshes, without the GPU.
#[derive(Debug, Clone)]
pub struct SceneLayout {
    /// Every mesh drawn: the scene's objects in order, then their further LOD levels.
    pub meshes: Vec<MeshSlot>,
    /// Each object's name and world-space bounds centre (what the light budget ranks lights by).
    pub object_centres: Vec<(String, DVec3)>,
    /// Each scene object's world bounds (level 0's mesh): what LOD selection measures.
    pub world_bounds: Vec<(DVec3, DVec3)>,
    /// The bounds of every object (directional shadow maps fit them).
    pub scene_bounds: (DVec3, DVec3),
    pub shadows: ShadowArray,
}

impl SceneLayout {
    /// `meshes`: one per scene object, in order; `lod_levels`: (object, level) of each further LOD
    /// mesh, in the order they are drawn after the objects.
    pub fn new(scene: &Scene, frame: &FramePlan, meshes: &[Mesh], lod_levels: &[(usize, usize)]) -> SceneLayout {
        let mut slots: Vec<MeshSlot> = scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| MeshSlot {
                role: o.role,
                scene_index: i,
                lod_level: o.lod.as_ref().map(|_| 0),
                cast_shadows: o.cast_shadows,
                render_face: o.render_face,
                transparent: o.material.as_ref().is_some_and(|m| m.is_transparent()),
            })
            .collect();
        let further: Vec<MeshSlot> =
            lod_levels.iter().map(|&(i, level)| MeshSlot { lod_level: Some(level), ..slots[i].clone() }).collect();
        slots.extend(further);
        let world_bounds = scene
            .objects
            .iter()
            .zip(meshes)
            .map(|(o, m)| crate::geometry::placement::world_bounds_of(o, &m.bounds()))
            .collect();
        let active = frame.shadows();
        let mut first_layer = Vec::with_capacity(scene.lights.len());
        let (mut layers, mut side) = (0usize, 1u32);
        for l in &scene.lights {
            if active && l.shadows {
                first_layer.push(Some(layers));
                layers += match l.kind {
                    LightKind::Point => 6,
                    LightKind::Directional => crate::pipelines::MAX_CASCADES,
                    LightKind::Spot => 1,
                    // Refused by the scene's checks (declarations::area_light): no shadow maps.
                    LightKind::Rect | LightKind::Disc => 0,
                };
                side = side.max(array_side(l, &frame.engines));
            } else {
                first_layer.push(None);
            }
        }
        SceneLayout {
            meshes: slots,
            object_centres: crate::geometry::placement::object_centres(scene, meshes),
            world_bounds,
            scene_bounds: crate::geometry::placement::world_bounds(scene, meshes),
            shadows: ShadowArray { first_layer, layers: layers.max(1), side },
        }
    }
}

/// A light's place in the shadow array this cell: its first layer and how many it uses, and how
/// its shadow is filtered and biased (`shadows::shadow_style`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LightShadow {
    pub first_layer: Option<usize>,
    pub layers: usize,
    pub style: Option<ShadowStyle>,
}

#[derive(Debug, Clone)]
pub struct CellPlan {
    /// The scene's camera at the cell's distance, and the image's aspect.
    pub camera: Camera,
    pub aspect: f64,
    /// The scene's lights with the key light at the cell's intensity, range and angle.
    pub lights: Vec<Light>,
    /// The pipeline's main light (the brightest directional), if any.
    pub main_light: Option<usize>,
    /// How each light reaches each object, and why.
    pub assignment: Vec<ObjectLights>,
    /// Per light: its layers in the shadow array.
    pub light_shadows: Vec<LightShadow>,
    /// Every layer of the array (zero where unused), and the (layer, resolution) of those in use.
    pub shadow_layers: Vec<ShadowLayerPlan>,
    pub used_layers: Vec<(usize, u32)>,
    /// Each shadowed light's map resolution, and why it differs from the pipeline's default.
    pub shadow_maps: Vec<ShadowMapUse>,
    /// (what, why) for each shadow the scene asks for that the pipeline's settings do not draw, and
    /// each light setting the pipeline has not (plan::light_terms).
    pub left_out: Vec<(String, String)>,
    /// Each LOD group's screen height and the levels drawn.
    pub lod: Vec<LodUse>,
    /// Each mesh's LOD fade (None: not drawn; 1 for meshes without LOD).
    pub fades: Vec<Option<f64>>,
    /// The draws of each pass, and each mesh's additive (ForwardAdd) lights.
    pub draws: DrawPlan,
    /// The passes of the frame in the order they run (`pass::frame_passes`): what the frame loop
    /// runs, what `cell.json` records and what the timings are keyed by.
    pub passes: Vec<Pass>,
    pub multisampling: Multisampling,
    /// The scene's baked lighting in this pipeline (None: the scene bakes nothing).
    pub gi: Option<super::gi::GiPlan>,
    /// How the frame reads each of the scene's reflection probes (`probes::probe_use`); empty
    /// where the composition captures none.
    pub probes: Vec<super::probes::ProbeUse>,
    /// Per mesh (layout order), the probe it takes at full weight where probes are chosen per
    /// renderer (`probes::renderer_probe`); None elsewhere, or where no probe holds it.
    pub renderer_probes: Vec<Option<usize>>,
    /// How the subject casts into the shadow maps (`shadows::subject_caster`).
    pub subject_caster: super::shadows::SubjectCaster,
    /// Where the frame's screen-space occlusion applies (`ao::ambient_occlusion`).
    pub ao: super::ao::AoUse,
    /// How a forward-drawn dynamic object's probe occlusion meets a real-time shadow
    /// (`gi::probe_occlusion`).
    pub probe_occlusion: super::gi::ProbeOcclusion,
    /// The subject's alpha test resolves by alpha-to-coverage (`draws::alpha_to_coverage`).
    pub alpha_to_coverage: bool,
    /// Which models a deferred path draws into the G-buffer (`draws::gbuffer_pass`).
    pub gbuffer: GBufferModels,
    /// Shadow layers that draw the dynamic objects alone: a mixed light's under Shadowmask and
    /// Subtractive, whose static objects' shadows are baked.
    pub dynamic_casters_only: Vec<usize>,
    /// Each light's lobes, shape window, attenuation, dimmers and shadow tint (plan::light_terms).
    pub light_terms: Vec<super::light_terms::LightTerms>,
    /// Why a same-BRDF truth cannot trace the subject's surface (`ShaderModel::untraceable`).
    pub subject_untraceable: Option<String>,
    /// The subject's screen-space subsurface scattering (`subsurface::subsurface`), where the
    /// frame splits its lighting and filters it.
    pub subsurface: Option<super::subsurface::SubsurfacePlan>,
    /// Per mesh, whether it is in the Transparent queue, and the queue's drawn meshes in the order
    /// it draws them (`draws::transparent_queue`).
    pub transparent: Vec<bool>,
    pub transparent_order: Vec<usize>,
    /// The drawn fixed objects in the Transparent queue, by name (the panes only the CPU truth
    /// lets rays through).
    pub transparent_fixed: Vec<String>,
}

impl CellPlan {
    /// Why the truth cannot represent this cell's lights (`LightTerms::unphysical`), if it cannot:
    /// its column is then left empty rather than wrong.
    pub fn truth_unreachable(&self) -> Option<String> {
        self.light_terms.iter().zip(&self.light_shadows).find_map(|(t, s)| t.unphysical(s.style.is_some()))
    }

    /// Why this cell has no truth, as its record says it: a light doing what no light transport
    /// does (any truth), or a subject a same-BRDF truth cannot trace (`ShaderModel::untraceable`).
    pub fn truth_gap(&self, same_brdf: bool) -> Option<String> {
        if let Some(why) = self.truth_unreachable() {
            return Some(format!("no truth: {why}, which no light transport does; the column is left empty"));
        }
        let why = self.subject_untraceable.as_ref().filter(|_| same_brdf)?;
        Some(format!("no same-BRDF truth: {why}; the column is left empty"))
    }

    /// The optional light-loop paths this cell's frame needs compiled in.
    pub fn light_paths(&self) -> super::lights::LightPaths {
        super::lights::LightPaths {
            area: super::lights::needs_area_path(&self.lights),
            hdrp_terms: self.light_terms.iter().any(super::light_terms::LightTerms::needs_shader_path),
            pcss: self.light_shadows.iter().any(|s| s.style.is_some_and(|style| style.pcss)),
        }
    }

    /// The lights whose terms differ from the common light's (HDRP's settings at work), for the record.
    pub fn distinct_light_terms(&self) -> Vec<super::light_terms::LightTerms> {
        let common =
            |t: &super::light_terms::LightTerms| super::light_terms::LightTerms::common(t.light, &self.lights[t.light]);
        self.light_terms.iter().filter(|t| **t != common(t)).cloned().collect()
    }

    /// The plan of `cell` in a composition laid out as `layout`, whose fixed objects the pipeline
    /// draws with `fixed_model`, on an adapter that multisamples as `msaa` says.
    pub fn new(
        scene: &Scene,
        frame: &FramePlan,
        layout: &SceneLayout,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        msaa: &MsaaSupport,
    ) -> CellPlan {
        let p = cell.pipeline;
        let aspect = cell.width as f64 / cell.height as f64;
        let camera = posed_camera(&scene.camera, &cell.view);
        let lights = cell_lights(scene, cell.light_intensity, cell.light_range, &camera, &cell.view);
        let gi = scene.gi.as_ref().map(|g| super::gi::GiPlan::new(g, p, &lights, main_light(p, &lights)));
        // Per light, why the bake alone brings it to static (fixed) and to dynamic objects.
        let baked_on = |dynamic: bool| gi.as_ref().map_or_else(Vec::new, |g| g.baked_alone(dynamic));
        let (baked_static, baked_dynamic) = (baked_on(false), baked_on(true));
        let model = |i: usize| match scene.objects[i].role {
            Role::Subject => ModelLighting {
                forward_only: !cell.subject_deferrable(),
                area_lights: cell.model.area_lights(),
                baked: baked_dynamic.clone(),
                lightmapped: false,
            },
            _ => ModelLighting {
                forward_only: !super::draws::gbuffer_pass(p, fixed_model),
                area_lights: fixed_model.area_lights(),
                baked: baked_static.clone(),
                // The static objects are lightmapped wherever the scene bakes (geometry::lightmap_uv).
                lightmapped: gi.is_some(),
            },
        };
        let assignment =
            assign(p, cell.settings.path, &cell.settings.light_budget, &lights, &layout.object_centres, model);
        let sh = &layout.shadows;
        let mut shadow_layers = vec![ShadowLayerPlan::default(); sh.layers];
        let (mut used_layers, mut shadow_maps, mut light_shadows) = (Vec::new(), Vec::new(), Vec::new());
        let engine = &cell.settings.engine;
        let cascades = p.shadow_cascades_with(engine);
        let main = main_light(p, &lights);
        // A textured cutout's shadow is clipped by its alpha map (passes::shadow); a flat cutout is
        // all there or, below its cutoff, left out entirely (below).
        let (light_terms, mut left_out) =
            super::light_terms::light_terms(p, &lights, glam::DVec3::from(camera.position));
        let mut dynamic_casters_only = Vec::new();
        let surface = cell.settings.surface;
        for (slot, l) in lights.iter().enumerate() {
            let Some(first) = sh.first_layer[slot] else {
                light_shadows.push(LightShadow::default());
                continue;
            };
            if let Some(b) = gi.as_ref().map(|g| &g.lights[slot]).filter(|b| !b.drawn_on_static && !b.drawn_on_dynamic)
            {
                left_out.push((
                    format!("shadow of light {slot} ({:?})", l.kind),
                    format!("not drawn in real time ({}); its shadows are in the bake", b.note),
                ));
                light_shadows.push(LightShadow::default());
                continue;
            }
            let mut style = match shadow_style(p, engine, l, main == Some(slot)) {
                Ok(style) => style,
                Err(why) => {
                    left_out.push((format!("shadow of light {slot} ({:?})", l.kind), why));
                    light_shadows.push(LightShadow::default());
                    continue;
                }
            };
            let view = CascadeView { camera: &camera, aspect, cascades: &cascades };
            let (resolution, note) = cell_resolution(p, engine, l, &camera, (cell.width, cell.height), sh.side);
            let mut layers =
                light_layers(l, light_terms[slot].shape, (resolution, sh.side), layout.scene_bounds, &view);
            if style.pcss {
                // HDRP raises its slope bias with the PCSS softness (per request; the light's
                // largest here, one bias serving all its layers).
                let softness = layers.iter().map(|x| x.pcss[0] as f64).fold(0.0, f64::max);
                style.bias *= super::shadows::pcss_bias_scale(softness);
            } else {
                layers.iter_mut().for_each(|x| x.pcss = [0.0; 4]);
            }
            shadow_maps.push(ShadowMapUse { light: slot, resolution, note, style: Some(style) });
            used_layers.extend((first..first + layers.len()).map(|layer| (layer, resolution)));
            light_shadows.push(LightShadow { first_layer: Some(first), layers: layers.len(), style: Some(style) });
            if gi.as_ref().is_some_and(|g| g.static_shadows_baked(slot)) {
                dynamic_casters_only.extend(first..first + layers.len());
            }
            for (k, layer) in layers.into_iter().enumerate() {
                shadow_layers[first + k] = layer;
            }
        }
        let gbuffer = GBufferModels {
            subject: cell.subject_deferrable(),
            fixed: super::draws::gbuffer_pass(p, fixed_model),
            subject_legacy: super::draws::legacy_deferred(p, cell.model),
        };
        let mut lod = Vec::new();
        let mut fades: Vec<Option<f64>> = layout.meshes.iter().map(|m| m.lod_level.is_none().then_some(1.0)).collect();
        for seen in groups_seen(scene, &layout.world_bounds, &camera, p.quality_lod_bias_with(engine)) {
            for (m, mesh) in layout.meshes.iter().enumerate().filter(|(_, m)| m.scene_index == seen.object) {
                fades[m] = seen.drawn.iter().find(|d| Some(d.level) == mesh.lod_level).map(|d| d.fade);
            }
            lod.push(LodUse {
                object: scene.objects[seen.object].name.clone(),
                relative_height: seen.relative_height,
                drawn: seen.drawn,
            });
        }
        // A flat cutout below its cutoff clips every fragment: not drawn, casting no shadow.
        let reflectivity = cell.model.twin.map_or(0.0, |t| t.reflectivity(&cell.surface));
        let subject_caster =
            super::shadows::subject_caster(p, &surface, cell.settings.material_maps.is_some(), reflectivity);
        let clipped = subject_caster == super::shadows::SubjectCaster::Nothing;
        if clipped {
            for (fade, m) in fades.iter_mut().zip(&layout.meshes) {
                if m.role == Role::Subject {
                    *fade = None;
                }
            }
            left_out.push((
                "the subject".to_string(),
                format!(
                    "a cutout whose alpha {} is below its cutoff {} clips all of it: neither drawn nor casting a shadow",
                    surface.alpha, surface.cutoff
                ),
            ));
        }
        let drawn: Vec<bool> = fades.iter().map(Option::is_some).collect();
        let transparent: Vec<bool> = layout
            .meshes
            .iter()
            .map(|m| if m.role == Role::Subject { surface.kind.is_transparent() } else { m.transparent })
            .collect();
        let eye = DVec3::from(camera.position);
        let distance = |i: usize| layout.object_centres[layout.meshes[i].scene_index].1.distance(eye);
        let transparent_order = super::draws::transparent_queue(&transparent, &drawn, distance);
        let transparent_fixed: Vec<String> = transparent_order
            .iter()
            .filter(|&&i| layout.meshes[i].role == Role::Fixed)
            .map(|&i| layout.object_centres[layout.meshes[i].scene_index].0.clone())
            .collect();
        if frame.probes() && !transparent_fixed.is_empty() {
            left_out.push((
                format!("the transparent fixed objects ({}) in the reflection probes", transparent_fixed.join(", ")),
                "the captures draw the opaque objects and the sky".to_string(),
            ));
        }
        let meshes: Vec<(usize, bool, &ShaderModel, bool, bool)> = layout
            .meshes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let subject = m.role == Role::Subject;
                let model = if subject { cell.model } else { fixed_model };
                // The engines cannot put a transparent surface in a G-buffer.
                let deferrable = !transparent[i] && if subject { gbuffer.subject } else { gbuffer.fixed };
                (m.scene_index, drawn[i], model, deferrable, transparent[i])
            })
            .collect();
        let draws = plan_draws(p, cell.settings.path, engine, &meshes, &assignment, main);
        let subsurface = cell.subsurface().filter(|sss| {
            let why = sss.left_out_because(camera.fov_y_deg, cell.height, subject_depth(layout, &camera));
            why.map(|why| left_out.push((Pass::SubsurfaceScattering.name().to_string(), why))).is_none()
        });
        let ao = super::ao::ambient_occlusion(
            p,
            cell.settings.path,
            engine,
            (&cell.model.name, surface.kind),
            frame.hdrp_ssao && engine.hdrp.ssao,
        );
        if p == Pipeline::Hdrp {
            let off = [
                (frame.hdrp_bloom && !engine.hdrp.bloom, Pass::Bloom),
                (frame.hdrp_ssao && !engine.hdrp.ssao, Pass::Ssao),
            ];
            for (_, pass) in off.iter().filter(|(off, _)| *off) {
                left_out
                    .push((pass.name().to_string(), "the HDRP setting turns it off (the volume's override)".into()));
            }
        }
        let passes = frame_passes(PassInputs {
            pipeline: p,
            path: cell.settings.path,
            probes: frame.probes(),
            shadow_maps: frame.shadows() && !used_layers.is_empty(),
            ssao: ao.ssao.then_some(ao.method),
            transparent_queue: !transparent_order.is_empty(),
            traced_visibility: cell.settings.exact.visibility,
            bloom: frame.hdrp_bloom && engine.hdrp.bloom,
            subsurface: subsurface.is_some(),
        });
        let probes = match frame.probes() {
            true => scene
                .probes
                .iter()
                .map(|probe| super::probes::probe_use(p, cell.settings.path, engine, probe))
                .collect(),
            false => Vec::new(),
        };
        let per_renderer =
            probes.iter().any(|u: &super::probes::ProbeUse| u.weight == super::probes::ProbeWeight::Renderer);
        let renderer_probes = layout
            .meshes
            .iter()
            .map(|m| {
                let centre = layout.object_centres[m.scene_index].1;
                per_renderer.then(|| super::probes::renderer_probe(&scene.probes, centre)).flatten()
            })
            .collect();
        // HDRP's shadow reads its Shadow Dimmer, faded with distance, where the others read Strength.
        for (shadow, t) in light_shadows.iter_mut().zip(&light_terms) {
            if let Some(style) = shadow.style.as_mut() {
                style.strength = t.shadow_dimmer;
            }
        }
        let mut multisampling = msaa.for_settings(&cell.settings);
        if subsurface.is_some() && multisampling.samples > 1 {
            multisampling = Multisampling {
                samples: 1,
                note: Some(format!(
                    "{}× MSAA asked; the subsurface scattering filter here reads single-sample buffers \
                     (HDRP's MSAA variant resolves them first): rendered 1×",
                    multisampling.samples
                )),
            };
        }
        let alpha_to_coverage = super::draws::alpha_to_coverage(p, surface.kind, multisampling.samples);
        CellPlan {
            transparent,
            transparent_order,
            transparent_fixed,
            subsurface,
            light_terms,
            subject_untraceable: cell.model.untraceable(&cell.surface.params),
            probes,
            alpha_to_coverage,
            renderer_probes,
            subject_caster,
            ao,
            probe_occlusion: super::gi::probe_occlusion(p),
            gbuffer,
            draws,
            main_light: main,
            left_out,
            camera,
            aspect,
            lights,
            assignment,
            light_shadows,
            shadow_layers,
            used_layers,
            shadow_maps,
            lod,
            fades,
            passes,
            multisampling,
            gi,
            dynamic_casters_only,
        }
    }

    /// Whether each mesh is drawn.
    pub fn drawn(&self) -> Vec<bool> {
        self.fades.iter().map(Option::is_some).collect()
    }

    /// Whether each mesh casts shadows this frame: a LOD level fading in does not (the shadow
    /// pass draws each group's outgoing level whole).
    pub fn casting(&self) -> Vec<bool> {
        self.fades.iter().map(|f| f.is_some_and(|f| f > 0.0)).collect()
    }

    /// The meshes that shadow this frame's lights: casting (`casting`) with their renderer's Cast
    /// Shadows on. The shadow maps draw them, and the study's traced visibility, which stands for
    /// the maps (`ExactAlternatives::visibility`), casts its rays against them alone.
    pub fn shadow_casters(&self, layout: &SceneLayout) -> Vec<bool> {
        self.casting().into_iter().zip(&layout.meshes).map(|(c, m)| c && m.cast_shadows).collect()
    }

    /// Whether the frame draws `pass`.
    pub fn has(&self, pass: Pass) -> bool {
        self.passes.contains(&pass)
    }
}

/// The view depth of the subject's nearest point: the nearest corner of its objects' world bounds
/// along the view direction, at least the near plane.
fn subject_depth(layout: &SceneLayout, camera: &crate::declarations::scene::Camera) -> f64 {
    let eye = DVec3::from(camera.position);
    let forward = (DVec3::from(camera.target) - eye).normalize();
    let subjects = layout.meshes.iter().filter(|m| m.role == Role::Subject).map(|m| layout.world_bounds[m.scene_index]);
    let corners = subjects.flat_map(|(lo, hi)| {
        (0..8).map(move |k| DVec3::new([lo.x, hi.x][k & 1], [lo.y, hi.y][(k >> 1) & 1], [lo.z, hi.z][k >> 2]))
    });
    corners.map(|c| (c - eye).dot(forward)).fold(f64::INFINITY, f64::min).max(camera.near)
}

#[cfg(test)]
mod tests {
    //! The plan's decisions, without a GPU: which lights reach which object how, where shadow
    //! layers go and at what resolution, which LOD levels a distance draws. What the pixels do
    //! with them stays end to end (tests/e2e: lights, shadows, lod).
    use super::*;
    use crate::plan::lights::LightMode;
    use crate::shading::registry::Sliders;
    use crate::shading::Registry;

    fn repo(path: &str) -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
    }

    fn no_msaa() -> MsaaSupport {
        MsaaSupport { counts: vec![1, 4], what: "test adapter multisamples".into() }
    }

    /// The plan of a `shader` cell on `path` with the key light at `intensity`, at `size`².
    fn plan_of(scene: &Scene, pipeline: Pipeline, path: RenderPath, view: ViewAxes, size: u32) -> CellPlan {
        planned(scene, pipeline, path, view, size).0
    }

    fn planned(
        scene: &Scene,
        pipeline: Pipeline,
        path: RenderPath,
        view: ViewAxes,
        size: u32,
    ) -> (CellPlan, SceneLayout) {
        planned_with(scene, pipeline, path, view, size, Default::default())
    }

    /// `planned` with the cell's engine settings.
    fn planned_with(
        scene: &Scene,
        pipeline: Pipeline,
        path: RenderPath,
        view: ViewAxes,
        size: u32,
        engine: crate::pipelines::settings::PipelineSettings,
    ) -> (CellPlan, SceneLayout) {
        let models = Registry::builtin();
        let model = models.find(pipeline, pipeline.fixed_object_shader()).expect("the default lit model");
        let sliders = Sliders { base_color_linear: [0.5; 3], metallic: 0.0, smoothness: 0.5 };
        let cell = CellParams {
            pipeline,
            model,
            surface: model.surface(pipeline, &sliders),
            light_intensity: scene.key_light().map_or(1.0, |k| scene.lights[k].intensity),
            light_range: scene.key_light().map_or(10.0, |k| scene.lights[k].range),
            width: size,
            height: size,
            view,
            settings: CellSettings { path, engine, ..Default::default() },
        };
        let meshes = crate::geometry::procedural::build_scene(scene).expect("the scene's meshes");
        let lod: Vec<(usize, usize)> = crate::geometry::procedural::lod_meshes(scene)
            .expect("the LOD meshes")
            .into_iter()
            .map(|(i, j, _)| (i, j))
            .collect();
        let frame = FramePlan::for_scene(scene);
        let layout = SceneLayout::new(scene, &frame, &meshes, &lod);
        (CellPlan::new(scene, &frame, &layout, &cell, model, &no_msaa()), layout)
    }

    fn modes(plan: &CellPlan, mode: LightMode) -> usize {
        plan.assignment[0].lights.iter().filter(|u| u.mode == mode).count()
    }

    /// window_pane.toml with a second pane nearer the camera named before the first.
    fn two_panes() -> Scene {
        let text = std::fs::read_to_string(repo("tests/fixtures/window_pane.toml")).unwrap();
        let upper = "[[objects]]\nname = \"upper\"\nrole = \"fixed\"\n\
                     mesh = { kind = \"plane\", size = [0.4, 0.4], subdivisions = 1 }\n\
                     transform = { translate = [0.1, 1.8, 0.0] }\n\
                     material = { base_color_linear = [0.5, 0.5, 0.5], surface = \"transparent\", alpha = 0.5 }\n\
                     cast_shadows = false\n\n";
        let at = text.find("# Black and rough").unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("two_panes.toml");
        std::fs::write(&path, format!("{}{upper}{}", &text[..at], &text[at..])).unwrap();
        Scene::load_file(&path).unwrap()
    }

    #[test]
    fn the_transparent_queue_is_drawn_back_to_front_and_forward() {
        let scene = two_panes();
        let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["plane", "upper", "pane"]);
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let plan = plan_of(&scene, Pipeline::Urp, path, ViewAxes::default(), 64);
            // The lower pane is farther from the camera (1.6 m against 0.8 m): drawn first.
            assert_eq!(plan.transparent, [false, true, true]);
            assert_eq!(plan.transparent_order, [2, 1]);
            assert_eq!(plan.transparent_fixed, ["pane", "upper"]);
            // The CPU truth traces the panes (render::truth::cpu::glass).
            assert_eq!(plan.truth_gap(true), None);
            let count = |kind: &str| plan.draws.counts.get(kind).copied().unwrap_or(0);
            match path {
                RenderPath::Deferred => {
                    assert!(plan.has(Pass::Transparent));
                    assert_eq!((count(Pass::GBuffer.name()), count(Pass::Transparent.name())), (1, 2));
                }
                _ => assert_eq!(count(Pass::Forward.name()), 3, "{:?}", plan.draws.counts),
            }
        }
    }

    #[test]
    fn twelve_lights_reach_the_object_as_each_path_budgets_them() {
        let scene = Scene::load_file(&repo("tests/fixtures/twelve_points.toml")).unwrap();
        assert_eq!(scene.lights.len(), 12);
        let at = |p, path| plan_of(&scene, p, path, ViewAxes::default(), 64);
        // Built-in's vertex-lit path: ShadeVertexLightsFull's 8, the rest not rendered.
        let v = at(Pipeline::Builtin, RenderPath::VertexLit);
        assert_eq!((modes(&v, LightMode::PerVertex), modes(&v, LightMode::Dropped)), (8, 4), "{:?}", v.assignment);
        // URP forward: the per-object limit (4 by default) after the main light; the rest dropped.
        let u = at(Pipeline::Urp, RenderPath::Forward);
        assert_eq!(modes(&u, LightMode::PerPixel), 4, "{:?}", u.assignment);
        assert_eq!(modes(&u, LightMode::Dropped), 8);
        // HDRP's clustered loop and every deferred path: all per pixel.
        for (p, path) in [(Pipeline::Hdrp, RenderPath::Forward), (Pipeline::Builtin, RenderPath::Deferred)] {
            assert_eq!(modes(&at(p, path), LightMode::PerPixel), 12, "{p:?} {path:?}");
        }
        // Built-in forward: 4 per-pixel (the pixel light count), 4 per-vertex, the rest in SH.
        let b = at(Pipeline::Builtin, RenderPath::Forward);
        let counts = (modes(&b, LightMode::PerPixel), modes(&b, LightMode::PerVertex), modes(&b, LightMode::Sh));
        assert_eq!(counts.0 + counts.1 + counts.2, 12, "{:?}", b.assignment);
        assert!(counts.0 <= 4 && counts.1 <= 4, "{counts:?}");
    }

    #[test]
    fn a_point_light_takes_six_layers_at_its_pipeline_resolution() {
        let scene = Scene::load_file(&repo("tests/fixtures/shadow_box.toml")).unwrap();
        for p in Pipeline::ALL {
            let plan = plan_of(&scene, p, RenderPath::Forward, ViewAxes::default(), 128);
            if p == Pipeline::Urp {
                // No layer in use: no shadow pass either.
                assert!(!plan.has(Pass::Shadow), "{:?}", plan.passes);
                // The code-default URP asset draws no additional-light shadows.
                assert_eq!(plan.light_shadows[0].first_layer, None);
                assert!(plan.left_out[0].1.contains("additional-light shadows off"), "{:?}", plan.left_out);
                continue;
            }
            assert!(plan.has(Pass::Shadow), "{p:?}: {:?}", plan.passes);
            assert_eq!((plan.light_shadows[0].first_layer, plan.light_shadows[0].layers), (Some(0), 6));
            assert_eq!(plan.shadow_maps.len(), 1);
            let res = plan.shadow_maps[0].resolution;
            assert_eq!(plan.used_layers, (0..6).map(|l| (l, res)).collect::<Vec<_>>());
            let light = &scene.lights[0];
            let (wanted, _) =
                crate::plan::shadows::cell_resolution(p, &Default::default(), light, &plan.camera, (128, 128), 1 << 20);
            assert_eq!(res, wanted.min(array_side(light, &[])), "{p:?}");
            // Each face sees along its axis from the light.
            for (face, dir) in [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z].iter().enumerate() {
                let m = glam::Mat4::from_cols_array_2d(&plan.shadow_layers[face].view_proj).as_dmat4();
                let clip = m * (DVec3::from(light.position) + *dir).extend(1.0);
                assert!((clip.x / clip.w).abs() < 1e-5 && (clip.y / clip.w).abs() < 1e-5, "{p:?} face {face}");
            }
        }
        // The vertex-lit path renders no shadows, so its plan has no shadow pass.
        let v = plan_of(&scene, Pipeline::Builtin, RenderPath::VertexLit, ViewAxes::default(), 128);
        assert!(!v.has(Pass::Shadow), "{:?}", v.passes);
    }

    #[test]
    fn a_directional_light_fits_its_pipelines_cascades_to_the_posed_camera() {
        let mut scene = Scene::load_file(&repo("tests/fixtures/shadow_box.toml")).unwrap();
        scene.lights[0].kind = LightKind::Directional;
        scene.lights[0].direction = [0.2, -1.0, 0.1];
        for p in Pipeline::ALL {
            for distance in [2.0, 6.0] {
                let view = ViewAxes { camera_distance: Some(distance), light_angle: None };
                let plan = plan_of(&scene, p, RenderPath::Forward, view, 128);
                let cascades = p.shadow_cascades();
                assert_eq!(plan.light_shadows[0].layers, cascades.splits.len(), "{p:?}");
                // Each cascade's sphere holds the view-axis point at its slice's far edge.
                let eye = DVec3::from(plan.camera.position);
                assert!((eye.length() - distance).abs() < 1e-9, "the camera stands where the cell says");
                let forward = (DVec3::from(plan.camera.target) - eye).normalize();
                for (k, split) in cascades.splits.iter().enumerate() {
                    let s = plan.shadow_layers[k].sphere;
                    let at = eye + forward * (split * cascades.max_distance * 0.999);
                    let centre = DVec3::new(s[0] as f64, s[1] as f64, s[2] as f64);
                    assert!((at - centre).length() <= s[3] as f64 * 1.0001, "{p:?} cascade {k} at {distance}");
                }
            }
        }
    }

    #[test]
    fn a_distance_sweep_draws_each_lod_level_and_the_bands_between() {
        let scene = Scene::load_file(&repo("scenes/default_lod.toml")).unwrap();
        let drawn = |d: f64| {
            let view = ViewAxes { camera_distance: Some(d), light_angle: None };
            let (plan, layout) = planned(&scene, Pipeline::Urp, RenderPath::Forward, view, 128);
            assert_eq!(plan.lod.len(), 1, "one LOD group");
            // Every mesh of the group is drawn exactly when its level is.
            for (fade, mesh) in plan.fades.iter().zip(&layout.meshes).filter(|(_, m)| m.lod_level.is_some()) {
                let level = plan.lod[0].drawn.iter().find(|l| Some(l.level) == mesh.lod_level);
                assert_eq!(fade.is_some(), level.is_some(), "level {:?} at {d}", mesh.lod_level);
                assert_eq!(*fade, level.map(|l| l.fade));
            }
            plan.lod[0].drawn.iter().map(|l| (l.level, l.fade < 1.0)).collect::<Vec<_>>()
        };
        // matrices/lod.toml's distances in URP (QualitySettings.lodBias 2): every level whole, and
        // both bands.
        assert_eq!(drawn(8.0), vec![(0, false)], "close: level 0 whole");
        assert_eq!(drawn(12.0), vec![(0, true), (1, true)], "level 0 fading into level 1");
        assert_eq!(drawn(16.0), vec![(1, false)]);
        assert_eq!(drawn(24.0), vec![(1, true), (2, true)], "level 1 fading into level 2");
        assert_eq!(drawn(28.0), vec![(2, false)]);
    }

    /// Built-in's quality level sets QualitySettings.lodBias: Low's 0.4 switches to coarser levels
    /// at distances where Ultra's 2 still draws the finest.
    #[test]
    fn a_built_in_quality_levels_lod_bias_moves_the_switch() {
        use crate::pipelines::settings::{PipelineSettings, QualityLevel};
        let scene = Scene::load_file(&repo("scenes/default_lod.toml")).unwrap();
        let view = ViewAxes { camera_distance: Some(8.0), light_angle: None };
        let first_level = |level: QualityLevel| {
            let mut engine = PipelineSettings::default();
            engine.builtin.quality = level.fields().0;
            let (plan, _) = planned_with(&scene, Pipeline::Builtin, RenderPath::Forward, view, 128, engine);
            plan.lod[0].drawn.first().map(|l| l.level)
        };
        assert_eq!(first_level(QualityLevel::Ultra), Some(0), "lodBias 2 at 8 m: level 0, as URP's");
        let low = first_level(QualityLevel::Low);
        assert!(low.is_none_or(|l| l > 0), "lodBias 0.4 at 8 m: a coarser level or culled, not {low:?}");
    }

    #[test]
    fn msaa_falls_back_to_what_the_adapter_resolves_and_says_so() {
        let support = no_msaa();
        assert_eq!(support.multisampling(4, None), Multisampling { samples: 4, note: None });
        let eight = support.multisampling(8, None);
        assert_eq!(eight.samples, 4);
        assert!(eight.note.is_some_and(|n| n.contains("8× MSAA asked") && n.contains("rendered 4×")));
        let deferred =
            CellSettings { path: RenderPath::Deferred, antialiasing: Antialiasing::Msaa4, ..Default::default() };
        let m = support.for_settings(&deferred);
        assert_eq!(m.samples, 1, "the deferred path renders one sample");
        assert!(m.note.is_some());
    }
}
