//! A composition on the GPU: its meshes, uniform slots, environment, light and shadow buffers
//! and probes, uploaded once per composition, with the layout its cell plans read
//! (`plan::cell::SceneLayout`).

use glam::DMat4;
use std::collections::HashMap;
use wgpu::util::DeviceExt;

use super::formats::SHADOW_FORMAT;
use crate::declarations::scene::Scene;
use crate::environment::EnvironmentMaps;
use crate::error::Error;
use crate::geometry::{procedural, Mesh};
use crate::gpu::GpuContext;
use crate::plan::cell::{SceneLayout, ShadowArray};
use crate::plan::FramePlan;
use crate::render::uniforms::*;
use crate::shading::registry::Sliders;
use bytemuck::Zeroable;

/// One mesh on the GPU; its role, scene object and whether it casts are its slot in the layout
/// (`PreparedScene::layout.meshes`, same index).
pub(in crate::render) struct GpuObject {
    pub(in crate::render) vertices: wgpu::Buffer,
    pub(in crate::render) indices: wgpu::Buffer,
    pub(in crate::render) index_count: u32,
    pub(in crate::render) model: DMat4,
    /// Fixed objects: their own material in slider units (mapped per pipeline at draw time) and
    /// their checkerboard.
    pub(in crate::render) fixed: Option<(Sliders, GpuMaterial)>,
    pub(in crate::render) receive_shadows: bool,
}

/// A composition's shadow maps: the depth array, a view per layer to render into, the layer
/// matrices (a uniform slot per layer for the shadow pass, a storage array for the forward pass).
pub(in crate::render) struct ShadowResources {
    pub(in crate::render) layer_views: Vec<wgpu::TextureView>,
    pub(in crate::render) array_view: wgpu::TextureView,
    pub(in crate::render) layer_uniforms: wgpu::Buffer,
    pub(in crate::render) layer_stride: u64,
    pub(in crate::render) layer_bind_group: wgpu::BindGroup,
    pub(in crate::render) layers_storage: wgpu::Buffer,
    /// What the layers hold now (`WrittenFrame::shadow_key`), when a cell's frame rendered them
    /// last; None after anything else did.
    pub(in crate::render) holds: std::sync::Mutex<Option<u64>>,
}

/// The truth's geometry of a composition with the meshes it holds (render::truth::bvh).
pub(in crate::render) type CpuTruthSceneCache =
    std::sync::Mutex<Option<(Vec<bool>, std::sync::Arc<crate::render::truth::cpu::CpuScene>)>>;
pub(in crate::render) type TruthGeometryCache =
    std::sync::Mutex<Option<(Vec<bool>, std::sync::Arc<crate::render::truth::TruthScene>)>>;

pub struct PreparedScene {
    pub scene: Scene,
    pub plan: FramePlan,
    pub env: EnvironmentMaps,
    pub(in crate::render) objects: Vec<GpuObject>,
    pub(in crate::render) object_buffer: wgpu::Buffer,
    pub(in crate::render) object_stride: u64,
    pub(in crate::render) object_bind_group: wgpu::BindGroup,
    pub(in crate::render) frame_buffer: wgpu::Buffer,
    pub(in crate::render) env_view: wgpu::TextureView,
    /// The scene's reflection probes (`environment.reflections = "probe"`); their levels follow
    /// the sky's in `env_view`.
    pub(in crate::render) probes: Option<crate::render::reflection_probes::SceneProbes>,
    /// The frame bind group per material-map set the subject wears ("" flat), made on first use.
    pub(in crate::render) frame_groups: std::sync::Mutex<HashMap<&'static str, std::sync::Arc<wgpu::BindGroup>>>,
    /// The fixed objects' material maps (`materials::fixed`), four layers per material.
    pub(in crate::render) fixed_maps: GpuFixedMaps,
    /// A glTF subject's own material maps (preset `own`), read and uploaded on first use.
    pub(in crate::render) own_textures: std::sync::OnceLock<crate::render::material_maps::MaterialTextures>,
    /// The same maps on the CPU, for the CPU truth (read on first use).
    pub(in crate::render) own_maps: std::sync::OnceLock<std::sync::Arc<crate::materials::MaterialMaps>>,
    /// The truth's environment on the GPU, made for the first truth.
    pub(in crate::render) env_table: std::sync::OnceLock<crate::render::truth::TruthEnvironment>,
    /// The truth's geometry on the GPU for the last set of meshes a cell kept (LOD levels change
    /// it), so cells of one composition build the meshes and the BVH and upload them once.
    pub(in crate::render) truth_geometry: TruthGeometryCache,
    /// The same for the CPU tracer (render::truth::cpu): its geometry and environment.
    pub(in crate::render) cpu_truth_scene: CpuTruthSceneCache,
    /// The scene's bakes by what they read (render::gi), made for the first cell that reads each.
    pub(in crate::render) bakes: std::sync::Mutex<HashMap<u64, std::sync::Arc<crate::render::gi::BakedLighting>>>,
    /// The static objects' lightmap atlas (where the scene bakes), and the texture that holds the
    /// last bake's lightmap (a 1×1 stand-in elsewhere).
    pub lightmap: Option<crate::geometry::lightmap_uv::LightmapAtlas>,
    pub(in crate::render) lightmap_texture: crate::render::gi::LightmapTexture,
    pub(in crate::render) lights_buffer: wgpu::Buffer,
    pub(in crate::render) modes_buffer: wgpu::Buffer,
    pub(in crate::render) shadows: ShadowResources,
    /// The composition's meshes and bounds as cell plans read them.
    pub layout: SceneLayout,
    pub triangle_count: usize,
}

impl PreparedScene {
    /// Upload a composition: its meshes (one per object, in order), with its frame plan;
    /// `prefilter` made already where the scene has reflection probes.
    pub(in crate::render) fn upload(
        gpu: &GpuContext,
        (object_layout, shadow_layer_layout): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
        prefilter: Option<&crate::render::reflection_probes::Prefilter>,
        scene: &Scene,
        plan: FramePlan,
        mut meshes: Vec<Mesh>,
    ) -> Result<PreparedScene, Error> {
        let env = EnvironmentMaps::build(&scene.environment);
        let device = &gpu.device;
        let mut objects = Vec::new();
        let mut triangle_count = 0;
        let lod_meshes = procedural::lod_meshes(scene)?;
        let lod_levels: Vec<(usize, usize)> = lod_meshes.iter().map(|(i, j, _)| (*i, *j)).collect();
        let layout = SceneLayout::new(scene, &plan, &meshes, &lod_levels);
        let maps = crate::materials::fixed::FixedMaps::of(scene)?;
        // Lightmap UVs for the static objects where the scene bakes (their meshes are re-cut at seams).
        let lightmap = match &scene.gi {
            Some(gi) => Some(crate::geometry::lightmap_uv::unwrap(scene, &mut meshes, gi)?),
            None => None,
        };
        let lightmap_texture = crate::render::gi::LightmapTexture::new(gpu, lightmap.as_ref());
        for ((o, mesh), slot) in scene.objects.iter().zip(meshes).zip(&maps.slots) {
            triangle_count += mesh.triangle_count();
            let (vertices, indices) = mesh_buffers(device, &o.name, &mesh);
            let fixed = o.material.as_ref().map(|m| {
                let sliders =
                    Sliders { base_color_linear: m.base_color_linear, metallic: m.metallic, smoothness: m.smoothness };
                let mut pattern = GpuMaterial::zeroed();
                // The base colour's alpha, which a transparent surface blends by.
                pattern.base_color[3] = m.alpha as f32;
                if let Some(c) = &m.checker {
                    pattern.params[2] = c.cell as f32;
                    pattern.checker_color = rgba(c.color_linear);
                }
                // scene.wgsl `Material.params.w`: 1 + the material's slot in the fixed maps' array.
                pattern.params[3] = slot.map_or(0.0, |s| s as f32 + 1.0);
                // In the scene's units; the pipeline's light units are applied per cell.
                // w 0: a fixed object reads its smoothness from its mask (scene.wgsl `Material`).
                let e = m.emission_linear;
                pattern.emission = [e[0] as f32, e[1] as f32, e[2] as f32, 0.0];
                (sliders, pattern)
            });
            objects.push(GpuObject {
                vertices,
                indices,
                index_count: mesh.indices.len() as u32,
                model: o.transform.matrix(),
                fixed,
                receive_shadows: o.receive_shadows,
            });
        }
        // LOD levels after the first: extra meshes of their object, after every scene object (so
        // the first scene-object-count slots stay the scene's objects).
        for (i, j, mesh) in lod_meshes {
            {
                let key = format!("objects[{i}].lod.meshes[{j}]");
                triangle_count += mesh.triangle_count();
                let first = &objects[i];
                let (vertices, indices) = mesh_buffers(device, &key, &mesh);
                objects.push(GpuObject {
                    vertices,
                    indices,
                    index_count: mesh.indices.len() as u32,
                    model: first.model,
                    fixed: first.fixed,
                    receive_shadows: first.receive_shadows,
                });
            }
        }
        let (object_buffer, object_stride, object_bind_group) = crate::render::resources::uniform_slots(
            device,
            gpu.constants,
            object_layout,
            "objects",
            std::mem::size_of::<ObjectUniforms>() as u64,
            objects.len(),
        );
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: gpu.constants.usage() | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let probes = match scene.environment.reflections {
            crate::declarations::scene::Reflections::Probe if !scene.probes.is_empty() => {
                let prefilter =
                    prefilter.ok_or_else(|| Error::Other("reflection probes without their prefilter".into()))?;
                Some(crate::render::reflection_probes::SceneProbes::new(gpu, prefilter, &scene.probes, &env.probe))
            }
            _ => None,
        };
        // With probes the sky's levels sit in the probes' array; otherwise they are the array.
        let env_view = match &probes {
            Some(p) => p.view(),
            None => sky_probe_view(gpu, &env.probe),
        };
        // A scene without lights still binds one (unused) element: a runtime-sized array needs one.
        let storage = |label: &str, bytes: u64, element: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(element).next_multiple_of(16),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let light_size = std::mem::size_of::<GpuLight>() as u64;
        let lights_buffer = storage("lights", scene.lights.len() as u64 * light_size, light_size);
        let modes_buffer = storage("light modes", (scene.lights.len() * objects.len() * 4) as u64, 4);
        let shadows = shadow_resources(gpu, shadow_layer_layout, &layout.shadows);
        let fixed_maps = GpuFixedMaps::new(gpu, maps);
        gpu.check_errors(&format!("uploading composition `{}`", scene.name))?;
        Ok(PreparedScene {
            scene: scene.clone(),
            plan,
            env,
            objects,
            object_buffer,
            object_stride,
            object_bind_group,
            frame_buffer,
            env_view,
            probes,
            frame_groups: Default::default(),
            own_textures: Default::default(),
            own_maps: Default::default(),
            fixed_maps,
            env_table: Default::default(),
            truth_geometry: Default::default(),
            cpu_truth_scene: Default::default(),
            bakes: Default::default(),
            lightmap,
            lightmap_texture,
            lights_buffer,
            modes_buffer,
            shadows,
            triangle_count,
            layout,
        })
    }
}

/// The fixed objects' maps on the GPU: one Rgba16Float array, layers 4k … 4k + 3 the albedo,
/// normal, mask and emission maps of material k (scene.wgsl `fixed_maps`), with their mips; a
/// 1×1 neutral set where no fixed object has maps.
pub(in crate::render) struct GpuFixedMaps {
    pub(in crate::render) view: wgpu::TextureView,
    /// The maps on the CPU (the CPU truth samples them).
    pub(in crate::render) maps: std::sync::Arc<crate::materials::fixed::FixedMaps>,
}

impl GpuFixedMaps {
    fn new(gpu: &GpuContext, maps: crate::materials::fixed::FixedMaps) -> GpuFixedMaps {
        let neutral = crate::materials::MaterialMaps {
            levels: vec![crate::materials::MapLevel {
                size: 1,
                albedo: vec![[1.0; 4]],
                normal: vec![[0.0, 0.0, 1.0, 1.0]],
                mask: vec![[1.0, 1.0, 1.0, 0.5]],
                emission: Vec::new(),
            }],
        };
        let materials = if maps.materials.is_empty() { std::slice::from_ref(&neutral) } else { &maps.materials[..] };
        let size = materials[0].levels[0].size as u32;
        let mips = materials[0].levels.len() as u32;
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("fixed material maps"),
            size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 4 * materials.len() as u32 },
            mip_level_count: mips,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for (k, m) in materials.iter().enumerate() {
            for (mip, level) in m.levels.iter().enumerate() {
                // A material without an emission map: white.
                let white;
                let emission = match level.emission.is_empty() {
                    true => {
                        white = vec![[1.0f32; 4]; level.size * level.size];
                        &white[..]
                    }
                    false => &level.emission[..],
                };
                for (j, texels) in [&level.albedo[..], &level.normal, &level.mask, emission].into_iter().enumerate() {
                    crate::render::material_maps::write_level(
                        &gpu.queue,
                        &texture,
                        (mip, 4 * k + j),
                        level.size,
                        texels,
                    );
                }
            }
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        GpuFixedMaps { view, maps: std::sync::Arc::new(maps) }
    }

    /// Whether a fixed object samples maps.
    pub(in crate::render) fn any(&self) -> bool {
        !self.maps.materials.is_empty()
    }
}

/// The shadow layers a composition needs (1 for a directional or spot light that casts
/// shadows, 6 for a point light), as large as the largest map its lights can ask for
/// (`shadows::array_side`).
pub(in crate::render) fn shadow_resources(
    gpu: &GpuContext,
    shadow_layer_layout: &wgpu::BindGroupLayout,
    array: &ShadowArray,
) -> ShadowResources {
    let device = &gpu.device;
    let (layers, resolution) = (array.layers as u32, array.side);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("shadow maps"),
        size: wgpu::Extent3d { width: resolution, height: resolution, depth_or_array_layers: layers },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let layer_views = (0..layers)
        .map(|i| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: i,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let (layer_uniforms, layer_stride, layer_bind_group) = crate::render::resources::uniform_slots(
        device,
        gpu.constants,
        shadow_layer_layout,
        "shadow layer matrices",
        64,
        layers as usize,
    );
    let layers_storage = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("shadow layers"),
        size: (std::mem::size_of::<ShadowLayer>() * layers as usize) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    ShadowResources {
        layer_views,
        array_view,
        layer_uniforms,
        layer_stride,
        layer_bind_group,
        layers_storage,
        holds: Default::default(),
    }
}

/// A mesh's vertex and index buffers.
pub(in crate::render) fn mesh_buffers(device: &wgpu::Device, label: &str, mesh: &Mesh) -> (wgpu::Buffer, wgpu::Buffer) {
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(&mesh.vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(&mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    (vertices, indices)
}

/// The sky's prefiltered levels as an array texture (Rgba16Float, one layer per level).
pub(in crate::render) fn sky_probe_view(
    gpu: &GpuContext,
    probe: &crate::environment::prefilter::Probe,
) -> wgpu::TextureView {
    let texels: Vec<half::f16> = probe
        .levels
        .iter()
        .flat_map(|l| l.texels.iter().flat_map(|t| crate::render::resources::half_texel(*t)))
        .collect();
    let env_texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("environment probe"),
            size: wgpu::Extent3d {
                width: probe.width as u32,
                height: probe.height as u32,
                depth_or_array_layers: probe.levels.len() as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&texels),
    );
    env_texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// The textures of a composition's glTF subject's own material (`materials::gltf`).
pub(in crate::render) fn own_textures(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
) -> Result<crate::render::material_maps::MaterialTextures, Error> {
    Ok(crate::render::material_maps::MaterialTextures::new(device, queue, &own_maps(scene)?))
}

/// The maps of the scene's glTF subject's own material.
pub(in crate::render) fn own_maps(scene: &Scene) -> Result<crate::materials::MaterialMaps, Error> {
    let no_maps =
        || Error::Other(format!("composition `{}`: the subject has no glTF material with textures", scene.name));
    let path = scene.subject_gltf().ok_or_else(no_maps)?;
    let (_, material) = crate::geometry::gltf_io::load_with_material(&path)?;
    material.as_ref().and_then(crate::materials::gltf::maps).ok_or_else(no_maps)
}

/// The maps the subject wears with `maps` (a preset's, or `own`: its glTF material's), on the CPU.
pub(in crate::render) fn subject_maps(
    prepared: &PreparedScene,
    maps: &str,
) -> Result<std::sync::Arc<crate::materials::MaterialMaps>, Error> {
    if maps != crate::declarations::presets::OWN.name {
        return Ok(crate::materials::MaterialMaps::of(maps));
    }
    if let Some(m) = prepared.own_maps.get() {
        return Ok(m.clone());
    }
    let m = std::sync::Arc::new(own_maps(&prepared.scene)?);
    Ok(prepared.own_maps.get_or_init(|| m).clone())
}
