//! The truth on the CPU: the estimator of shaders/pass/truth.wgsl traced in f64 on every core, its
//! surfaces evaluated by the models' f64 twins (`shading::twin`, `SurfaceTwin::direct_for_light`)
//! and by `physical::physical_response` — the formulas the GPU tracer's WGSL has twins of, not a
//! third copy. Per pixel and sample: a camera ray jittered over the pixel; at every hit each light
//! exactly (shadow ray, the pipeline's attenuation or the physical inverse square), the
//! environment importance-sampled from the same tables as the GPU's and weighed against the
//! surface's sampling by the power heuristic, and a continuation drawn from the surface, up to
//! `bounces` times. Same inputs as the GPU's: the frame and object uniforms the cell wrote. Where
//! no ray can pass a surface, a pixel's samples are traced eight at a time in lockstep (`lanes`),
//! each the path the one-at-a-time tracer draws, to the bit.
//!
//! Why a CPU tracer at all: on a CPU adapter (llvmpipe) the GPU tracer runs the same arithmetic
//! through a shader JIT at ~0.2 M paths/s; here rayon spreads the rows over the cores with no
//! compute-shader limits (stack depth, f32). Hand-written around Embree, which casts the rays in f32
//! against the triangles the GPU reads (`bvh::TruthGeometry`); every hit is then recomputed in f64
//! (`CpuScene::barycentrics`): no crate traces these models. Embree rather than a Rust BVH
//! (obvhs's CWBVH, which this used before): 41 % of the tracer's time was traversal, and Embree
//! traverses the same rays in well under half that (docs/performance.md).

use glam::{DMat4, DVec2, DVec3, DVec4};
use rayon::prelude::*;
use std::f64::consts::PI;

use super::bvh::TruthGeometry;
use super::{physical, Truth, TruthKind, TruthSettings};
use crate::declarations::matrix::TruthSampler;
use crate::error::Error;
use crate::pipelines::Pipeline;
use crate::render::uniforms::{FrameUniforms, GpuLight, GpuMaterial};
use crate::shading::twin::{irradiance_per_intensity, Surface, SurfaceTwin};

pub mod bake;
mod environment;
mod glass;
mod lanes;

pub use environment::CpuEnvironment;
use environment::{EnvironmentSample, PendingEnvironmentSample};

/// Offset of a continued or shadow ray from its surface (rays.wgsl RAY_EPSILON).
const RAY_EPSILON: f64 = 1e-4;
/// The HDRP roughness floor of environment and continuation directions (truth.wgsl).
const NO_LIGHT_FLOOR: f64 = 4.617e-5;

/// Random numbers: PCG (O'Neill 2014) hashed from pixel and sample, on a stream of its own (the
/// GPU's seeds differ), so that the two backends' estimates are independent; or, for the
/// `sobol` sampler, the sample's point of an Owen-scrambled Sobol sequence seeded per pixel, one
/// dimension per draw (PCG past the sequence's dimensions).
struct Rng {
    state: u32,
    sobol: Option<SobolPoint>,
}

struct SobolPoint {
    index: u32,
    seed: u32,
    dimension: u32,
}

fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

impl Rng {
    fn new(pixel: u32, sample: u32) -> Rng {
        Rng { state: pcg_hash(pixel ^ pcg_hash(sample.wrapping_mul(7919).wrapping_add(0x9e37_79b9))), sobol: None }
    }

    fn sobol(pixel: u32, sample: u32) -> Rng {
        let seed = pcg_hash(pixel.wrapping_add(0x2c1b_3c6d));
        Rng { sobol: Some(SobolPoint { index: sample, seed, dimension: 0 }), ..Rng::new(pixel, sample) }
    }

    /// Uniform in [0, 1): 32 bits (PCG), 24 (Sobol).
    fn next(&mut self) -> f64 {
        if let Some(p) = self.sobol.as_mut().filter(|p| p.dimension < sobol_burley::NUM_DIMENSIONS) {
            p.dimension += 1;
            return sobol_burley::sample(p.index, p.dimension - 1, p.seed) as f64;
        }
        self.state = pcg_hash(self.state);
        self.state as f64 * (1.0 / 4_294_967_296.0)
    }
}

/// A light as the tracer reads it (scene.wgsl `Light`, from the cell's `GpuLight`).
#[derive(Debug, Clone, Copy)]
struct TracedLight {
    kind: u32,
    position: DVec3,
    direction: DVec3,
    color: DVec3,
    range: f64,
    cos_outer: f64,
    cos_inner: f64,
    min_roughness: f64,
    /// Area lights: the right axis and the half width and height (a disc: its radius twice).
    right: DVec3,
    half_size: DVec2,
    /// HDRP's light terms (uniforms::GpuLight `features`): its shape and range attenuation.
    shape: crate::pipelines::hdrp_light::SpotShape,
    range_attenuation: bool,
}

/// scene.wgsl's area-light kinds (pipelines::Emitter::shader_kind).
const LIGHT_RECT: u32 = 3;
const LIGHT_DISC: u32 = 4;

impl From<&GpuLight> for TracedLight {
    fn from(l: &GpuLight) -> TracedLight {
        let v3 = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        TracedLight {
            kind: l.position[3] as u32,
            position: v3(l.position),
            direction: v3(l.direction),
            color: v3(l.color),
            range: l.params[0] as f64,
            cos_outer: l.params[1] as f64,
            cos_inner: l.params[2] as f64,
            min_roughness: l.params[3] as f64,
            right: v3(l.shape),
            half_size: DVec2::new(l.params[1] as f64, l.params[2] as f64),
            shape: match l.features[3] as u32 & 6 {
                // The window reads its half-size from params.yz; the sizes themselves are not needed.
                2 => crate::pipelines::hdrp_light::SpotShape::Pyramid { aspect_ratio: 1.0 },
                4 => crate::pipelines::hdrp_light::SpotShape::Box { width: 1.0, height: 1.0 },
                _ => crate::pipelines::hdrp_light::SpotShape::Cone,
            },
            range_attenuation: l.features[3] as u32 & 1 == 0,
        }
    }
}

/// sat((S·L − cos outer)/max(0.001, cos inner − cos outer))²: conventions.wgsl `angle_attenuation`.
fn angle_attenuation(cos_angle: f64, cos_outer: f64, cos_inner: f64) -> f64 {
    let a = ((cos_angle - cos_outer) / (cos_inner - cos_outer).max(0.001)).clamp(0.0, 1.0);
    a * a
}

impl TracedLight {
    /// A point drawn uniformly on an area light from (u1, u2), and the light's area.
    fn area_point(&self, u1: f64, u2: f64) -> (DVec3, f64) {
        let forward = self.direction.normalize();
        let up = forward.cross(self.right);
        let (hw, hh) = (self.half_size.x, self.half_size.y);
        if self.kind == LIGHT_DISC {
            let (r, phi) = (hw * u1.sqrt(), 2.0 * PI * u2);
            (self.position + self.right * (r * phi.cos()) + up * (r * phi.sin()), PI * hw * hw)
        } else {
            (self.position + self.right * (hw * (2.0 * u1 - 1.0)) + up * (hh * (2.0 * u2 - 1.0)), 4.0 * hw * hh)
        }
    }

    /// An area light sampled at one point of it: the direction there, its distance, and the
    /// attenuation that makes the light one point of intensity L·cos θ'·A (per unit luminance):
    /// cos θ'·A/d², times HDRP's box window for a same-BRDF truth of a rect.
    fn area_incidence(&self, p: DVec3, kind: TruthKind, rng: &mut Rng) -> (DVec3, f64, f64) {
        let (q, area) = self.area_point(rng.next(), rng.next());
        let to = q - p;
        let d2 = to.length_squared().max(1e-12);
        let l = to / d2.sqrt();
        let cos_light = (-l).dot(self.direction.normalize());
        if cos_light <= 0.0 {
            return (l, 0.0, 0.0);
        }
        let mut atten = cos_light * area / d2;
        if kind == TruthKind::SameBrdf && self.kind == LIGHT_RECT {
            atten *= crate::shading::ltc::RectLight {
                center: self.position,
                forward: self.direction.normalize(),
                right: self.right,
                half_size: self.half_size,
                range: self.range,
            }
            .attenuation(p);
        }
        (l, atten, d2.sqrt())
    }

    /// Direction to the light and its attenuation at p: scene.wgsl `light_incidence` with the
    /// pipeline's distance falloff, truth.wgsl `physical_attenuation` (inverse square) or
    /// `baked_attenuation` (the lightmapper's).
    fn incidence(&self, p: DVec3, falloff: Falloff) -> (DVec3, f64) {
        if self.kind == 0 {
            return (-self.direction.normalize(), 1.0);
        }
        if !self.shape.is_cone() || !self.range_attenuation {
            return self.hdrp_incidence(p, falloff);
        }
        let to_light = self.position - p;
        let d = to_light.length();
        let l = to_light / d.max(1e-6);
        let mut atten = match falloff {
            Falloff::InverseSquare => 1.0 / to_light.length_squared().max(1e-4),
            Falloff::RealTime(a) => a.eval(d, self.range),
            Falloff::Baked(b) => b.eval(d, self.range),
        };
        if self.kind == 2 {
            atten *= angle_attenuation(self.direction.normalize().dot(-l), self.cos_outer, self.cos_inner);
        }
        (l, atten)
    }
}

impl TracedLight {
    /// scene.wgsl `hdrp_light_incidence` (and truth.wgsl `physical_attenuation` for a physical
    /// truth: a box's collimated beam, a pyramid's inverse square), windowed by the projector.
    fn hdrp_incidence(&self, p: DVec3, falloff: Falloff) -> (DVec3, f64) {
        use crate::pipelines::hdrp_light::{projector_window, punctual_attenuation, SpotShape};
        let forward = self.direction.normalize();
        let to_sample = p - self.position;
        let box_light = matches!(self.shape, SpotShape::Box { .. });
        let (l, d) = if box_light {
            (-forward, to_sample.dot(forward))
        } else {
            let d = to_sample.length();
            (-to_sample / d.max(1e-6), d)
        };
        let mut atten = match (falloff, box_light) {
            (Falloff::RealTime(_), _) => punctual_attenuation(d, self.range, self.range_attenuation, box_light),
            (_, true) => 1.0,
            _ => 1.0 / to_sample.length_squared().max(1e-4),
        };
        if self.shape.is_cone() {
            if self.kind == 2 {
                atten *= angle_attenuation(forward.dot(-l), self.cos_outer, self.cos_inner);
            }
        } else {
            let local =
                DVec3::new(to_sample.dot(self.right), to_sample.dot(forward.cross(self.right)), to_sample.dot(forward));
            atten *= projector_window(self.shape, local, (self.half_size.x, self.half_size.y), self.range);
        }
        (l, atten)
    }

    /// How far a shadow ray from p travels to the light: scene.wgsl `light_distance`.
    fn shadow_distance(&self, p: DVec3) -> f64 {
        match (self.kind, self.shape) {
            (0, _) => f64::INFINITY,
            (_, crate::pipelines::hdrp_light::SpotShape::Box { .. }) => {
                (p - self.position).dot(self.direction.normalize())
            }
            _ => (self.position - p).length(),
        }
    }
}

/// What one CPU truth reads besides the scene: the cell's uniforms as written for the GPU.
pub struct CpuTruthInputs<'a> {
    pub pipeline: Pipeline,
    pub kind: TruthKind,
    /// The models' twins: a same-brdf truth needs both, a physical one neither.
    pub subject_twin: Option<&'a dyn SurfaceTwin>,
    pub fixed_twin: Option<&'a dyn SurfaceTwin>,
    pub frame: &'a FrameUniforms,
    pub lights: &'a [GpuLight],
    /// Per object: its material (the subject's is the frame's) and whether it is the subject.
    pub materials: &'a [(GpuMaterial, bool)],
    /// Per object: whether it is a fixed object in the Transparent queue (`glass`).
    pub glass: &'a [bool],
    pub background: bool,
    pub size: (u32, u32),
    pub subject_role: u8,
    pub fixed_role: u8,
    /// The fixed objects' maps (a fixed material's `params.w` is 1 + its slot), read at their
    /// finest level as the GPU tracer's textureSampleLevel(…, 0) does.
    pub fixed_maps: &'a crate::materials::fixed::FixedMaps,
    /// The share of the subject's surface that is there (`SurfaceType` coverage): 1 opaque, a
    /// Fade surface's alpha, 1 or 0 for a cutout whose alpha is above or below its cutoff. A ray
    /// meeting the subject passes it with probability 1 − coverage. With maps, the coverage at a
    /// hit is the surface's alpha × the albedo map's there (`subject_surface`).
    pub subject_coverage: f64,
    /// The subject's maps where it wears them, read at their finest level as the GPU tracer does.
    pub subject_maps: Option<&'a crate::materials::MaterialMaps>,
    /// The subject blends Standard's secondary maps into its maps (`ShaderModel::draws_detail`).
    pub subject_detail: bool,
    /// The subject's surface type, alpha and cutoff.
    pub subject_surface: crate::pipelines::surface::SurfaceOptions,
}

impl CpuTruthInputs<'_> {
    /// Whether every ray stops at the first surface it meets (no subject that lets light through).
    fn all_opaque(&self) -> bool {
        if self.glass.contains(&true) {
            return false;
        }
        if self.subject_maps.is_some() {
            return self.subject_surface.kind == crate::pipelines::surface::SurfaceType::Opaque;
        }
        self.subject_coverage >= 1.0
    }

    /// The share of the subject that is there at uv: its flat coverage, or with maps its alpha
    /// there as its surface type reads it (Fade: the alpha; a cutout: there where the alpha
    /// reaches the cutoff) — forward.wgsl `material_alpha`, `clip_alpha`.
    fn coverage_at(&self, uv: DVec2) -> f64 {
        use crate::pipelines::surface::SurfaceType;
        let Some(maps) = self.subject_maps else { return self.subject_coverage };
        let level = &maps.levels[0];
        let s = &self.subject_surface;
        // Unless the albedo's alpha holds the smoothness (scene.wgsl `alpha_from_maps`).
        let map_alpha = match self.frame.subject.emission[3] > 0.5 {
            true => 1.0,
            false => crate::materials::bilinear(&level.albedo, level.size, level.size, uv.x, uv.y)[3] as f64,
        };
        let alpha = s.alpha * map_alpha;
        match s.kind {
            SurfaceType::Fade => alpha.clamp(0.0, 1.0),
            SurfaceType::Cutout => (alpha >= s.cutoff) as u32 as f64,
            _ => 1.0,
        }
    }
}

/// The scene a CPU truth traces: the triangles and vertices the GPU's reads, cast against by
/// Embree (its BVH over the same f32 positions, traversed by the kernels it picks for this CPU),
/// and the environment.
pub struct CpuScene {
    pub geometry: TruthGeometry,
    pub environment: CpuEnvironment,
    /// None for a scene without triangles (Embree refuses an empty buffer).
    rays: Option<embree3::Scene<'static>>,
}

struct Hit {
    triangle: usize,
    b1: f64,
    b2: f64,
}

fn v3(a: [f32; 4]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

fn f3(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// One Embree device for the process: its build threads are started once, not per truth.
fn embree_device() -> Result<&'static embree3::Device, Error> {
    static DEVICE: std::sync::OnceLock<Result<embree3::Device, String>> = std::sync::OnceLock::new();
    DEVICE
        .get_or_init(|| embree3::Device::new().map_err(|e| format!("{e:?}")))
        .as_ref()
        .map_err(|e| Error::Device(format!("Embree (the CPU truth's ray casting): {e}")))
}

impl CpuScene {
    pub fn new(geometry: TruthGeometry, environment: CpuEnvironment) -> Result<CpuScene, Error> {
        let rays = if geometry.triangles.is_empty() { None } else { Some(Self::embree_scene(&geometry)?) };
        Ok(CpuScene { geometry, environment, rays })
    }

    /// The triangles as one Embree geometry; a hit's primitive id is its index in
    /// `geometry.triangles`.
    fn embree_scene(geometry: &TruthGeometry) -> Result<embree3::Scene<'static>, Error> {
        use embree3::{BufferUsage, Format, GeometryKind};
        let failed = |what: &str, e: embree3::Error| {
            Error::Device(format!("Embree (the CPU truth's ray casting): {what}: {e:?}"))
        };
        let device = embree_device()?;
        let mut mesh = device.create_geometry(GeometryKind::TRIANGLE).map_err(|e| failed("geometry", e))?;
        let vertices = &geometry.vertices;
        mesh.set_new_buffer::<[f32; 4]>(BufferUsage::VERTEX, 0, Format::FLOAT3, 16, vertices.len())
            .map_err(|e| failed("vertex buffer", e))?
            .iter_mut()
            .zip(vertices)
            .for_each(|(dst, v)| *dst = v.position);
        let triangles = &geometry.triangles;
        mesh.set_new_buffer::<[u32; 4]>(BufferUsage::INDEX, 0, Format::UINT3, 16, triangles.len())
            .map_err(|e| failed("index buffer", e))?
            .copy_from_slice(triangles);
        let mesh = mesh.commit();
        let mut scene = device.create_scene().map_err(|e| failed("scene", e))?;
        scene.set_build_quality(embree3::BuildQuality::HIGH);
        scene.attach_geometry(&mesh);
        scene.commit();
        Ok(scene)
    }

    /// Barycentrics of the hit on triangle `k` (Möller–Trumbore in f64, rays.wgsl
    /// `intersect_triangle`), clamped onto the triangle where f32 traversal and f64 disagree.
    fn barycentrics(&self, o: DVec3, d: DVec3, k: usize) -> (f64, f64) {
        let vs = &self.geometry.vertices;
        let tri = self.geometry.triangles[k];
        let p0 = v3(vs[tri[0] as usize].position);
        let e1 = v3(vs[tri[1] as usize].position) - p0;
        let e2 = v3(vs[tri[2] as usize].position) - p0;
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            return (1.0 / 3.0, 1.0 / 3.0);
        }
        let tv = o - p0;
        let qv = tv.cross(e1);
        let (b1, b2) = ((tv.dot(pv) / det).clamp(0.0, 1.0), (d.dot(qv) / det).clamp(0.0, 1.0));
        let over = (b1 + b2 - 1.0).max(0.0) / 2.0;
        (b1 - over, b2 - over)
    }

    /// The position of a hit, interpolated from its triangle's vertices.
    fn point_of(&self, hit: &Hit) -> DVec3 {
        let g = &self.geometry;
        let tri = g.triangles[hit.triangle];
        let [a, b, c] = [0, 1, 2].map(|k| v3(g.vertices[tri[k] as usize].position));
        a * (1.0 - hit.b1 - hit.b2) + b * hit.b1 + c * hit.b2
    }

    fn ray(o: DVec3, d: DVec3, t_max: f64) -> embree3::Ray {
        embree3::Ray::segment(f3(o), f3(d), RAY_EPSILON as f32, t_max.min(f32::MAX as f64) as f32)
    }

    /// The nearest hit along o + t·d for t in (ε, t_max).
    fn trace(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<Hit> {
        let scene = self.rays.as_ref()?;
        let mut ray = embree3::RayHit::from(Self::ray(o, d, t_max));
        scene.intersect(&mut embree3::IntersectContext::incoherent(), &mut ray);
        ray.hit.is_valid().then(|| self.hit(o, d, ray.hit.primID as usize))
    }

    /// The hit of o + t·d on the triangle Embree reports, placed in f64.
    fn hit(&self, o: DVec3, d: DVec3, triangle: usize) -> Hit {
        let (b1, b2) = self.barycentrics(o, d, triangle);
        Hit { triangle, b1, b2 }
    }

    /// Whether anything lies along o + t·d for t in (ε, t_max): a shadow ray.
    fn occluded(&self, o: DVec3, d: DVec3, t_max: f64) -> bool {
        let Some(scene) = self.rays.as_ref() else { return false };
        scene.occluded(&mut embree3::IntersectContext::incoherent(), &mut Self::ray(o, d, t_max))
    }
}

/// A hit point as the models see it (truth.wgsl `SurfacePoint`).
struct SurfacePoint {
    p: DVec3,
    n: DVec3,
    ng: DVec3,
    object: usize,
    s: Surface,
    emission: DVec3,
    /// A physical truth's model there, seen along the ray that found the point.
    lobe: Option<physical::PhysicalLobe>,
    /// What the point's own light is weighed by: a pane's 1/(1 − T) (`glass`), 1 elsewhere.
    weight: f64,
}

/// A fixed material's maps at uv (albedo, tangent-space normal, mask, emission): scene.wgsl
/// `fixed_map_level0`.
fn fixed_maps_at(maps: &crate::materials::fixed::FixedMaps, m: &GpuMaterial, uv: DVec2) -> Option<[[f64; 4]; 4]> {
    let slot = (m.params[3] + 0.5) as usize;
    Some(maps_at(&maps.materials.get(slot.checked_sub(1)?)?.levels[0], uv))
}

/// One level's maps at uv (albedo, tangent-space normal, mask, emission; emission 1 without a map).
fn maps_at(level: &crate::materials::MapLevel, uv: DVec2) -> [[f64; 4]; 4] {
    let at =
        |texels: &[[f32; 4]]| crate::materials::bilinear(texels, level.size, level.size, uv.x, uv.y).map(f64::from);
    let emission = if level.emission.is_empty() { [1.0; 4] } else { at(&level.emission) };
    [at(&level.albedo), at(&level.normal), at(&level.mask), emission]
}

/// scene.wgsl `tangent_to_world`: the tangent frame (bitangent = cross(n, t)·w) carries a
/// tangent-space normal to world space; n where the mesh has no tangent.
fn tangent_to_world(n: DVec3, tangent: DVec3, sign: f64, ts: DVec3) -> DVec3 {
    let t_raw = tangent - n * n.dot(tangent);
    if t_raw.length_squared() < 1e-12 {
        return n;
    }
    let t = t_raw.normalize();
    let b = n.cross(t) * if sign < 0.0 { -1.0 } else { 1.0 };
    (t * ts.x + b * ts.y + n * ts.z).normalize_or(n)
}

/// The Surface a model receives from a material at uv: scene.wgsl `surface_from` without maps.
fn surface_from(m: &GpuMaterial, uv: DVec2) -> Surface {
    let mut s = Surface {
        base_color: v3(m.base_color),
        metallic: m.params[0] as f64,
        smoothness: m.params[1] as f64,
        specular: v3(m.specular),
        params: std::array::from_fn(|i| [m.model0, m.model1, m.model2][i / 4][i % 4] as f64),
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
    };
    let scale = m.params[2] as f64;
    if scale > 0.0 {
        let cell = (uv / scale).floor();
        if ((cell.x as i64 + cell.y as i64) & 1) == 1 {
            s.base_color = v3(m.checker_color);
        }
    }
    s
}

/// scene.wgsl `carried_specular`: the specular workflow carried over texel by texel where the
/// material says so (checker_color.w), from the metallic workflow's colour and metallic and the
/// dielectric F0 in `specular`.
fn carried_specular(s: &mut Surface, m: &GpuMaterial) {
    if m.checker_color[3] < 0.5 {
        return;
    }
    let dielectric = v3(m.specular);
    s.specular = dielectric.lerp(s.base_color, s.metallic);
    s.base_color *= 1.0 - s.metallic;
    s.metallic = 0.0;
}

// ---- Sampling the surface: rays.wgsl, cosine or GGX visible normals (Heitz 2018).

fn basis(n: DVec3) -> [DVec3; 3] {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    [DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x), DVec3::new(b, s + n.y * n.y * a, -n.y), n]
}

/// The share of continuations drawn from the GGX lobe (rays.wgsl `specular_share`) for a model
/// with a specular lobe; `Tracer::lobe_share` gives diffuse-only models none.
fn specular_share(s: &Surface) -> f64 {
    (0.25 + 0.5 * s.smoothness * (0.5 + 0.5 * s.metallic)).clamp(0.1, 0.9)
}

fn ggx_alpha(s: &Surface) -> f64 {
    let pr = 1.0 - s.smoothness;
    (pr * pr).max(1e-3)
}

fn ggx_g1(nv: f64, a: f64) -> f64 {
    let a2 = a * a;
    2.0 * nv / (nv + (a2 + (1.0 - a2) * nv * nv).sqrt())
}

/// The density of `sample_surface` for l (solid angle), `k` the GGX share.
fn surface_pdf(s: &Surface, k: f64, n: DVec3, v: DVec3, l: DVec3) -> f64 {
    let (nl, nv) = (n.dot(l), n.dot(v));
    if nl <= 0.0 || nv <= 0.0 {
        return 0.0;
    }
    let a = ggx_alpha(s);
    let h = (v + l).normalize();
    let spec = if k > 0.0 { crate::shading::twin::d_ggx(n.dot(h), a) * ggx_g1(nv, a) / (4.0 * nv) } else { 0.0 };
    k * spec + (1.0 - k) * nl / PI
}

fn reflect(i: DVec3, n: DVec3) -> DVec3 {
    i - 2.0 * n.dot(i) * n
}

fn sample_surface(s: &Surface, k: f64, n: DVec3, v: DVec3, rng: &mut Rng) -> DVec3 {
    let [t, b, nn] = basis(n);
    let to_world = |x: DVec3| t * x.x + b * x.y + nn * x.z;
    let (u1, u2) = (rng.next(), rng.next());
    if rng.next() >= k {
        let r = u1.sqrt();
        let phi = 2.0 * PI * u2;
        return to_world(DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt()));
    }
    let a = ggx_alpha(s);
    let vl = DVec3::new(t.dot(v), b.dot(v), nn.dot(v));
    if vl.z <= 0.0 {
        return reflect(-v, n);
    }
    let vh = DVec3::new(a * vl.x, a * vl.y, vl.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 { DVec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt() } else { DVec3::X };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let p1 = r * phi.cos();
    let blend = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - blend) * (1.0 - p1 * p1).sqrt() + blend * r * phi.sin();
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    let m = DVec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize();
    to_world(reflect(-vl, m))
}

fn power_heuristic(a: f64, b: f64) -> f64 {
    a * a / (a * a + b * b).max(1e-30)
}

/// One tracer over one cell's inputs.
struct Tracer<'a> {
    scene: &'a CpuScene,
    inputs: &'a CpuTruthInputs<'a>,
    lights: Vec<TracedLight>,
    inv_view_proj: DMat4,
    camera: DVec3,
    env_scale: f64,
    subject: GpuMaterial,
    bounces: u32,
    roulette: bool,
    /// Whether the paths gather a bake (cpu::bake): lights fall off as the lightmapper's do.
    baking: bool,
}

/// A punctual light's distance falloff in one trace.
#[derive(Debug, Clone, Copy)]
enum Falloff {
    RealTime(crate::pipelines::Attenuation),
    Baked(crate::pipelines::BakedFalloff),
    InverseSquare,
}

impl<'a> Tracer<'a> {
    fn falloff(&self) -> Falloff {
        match (self.inputs.kind, self.baking) {
            (TruthKind::Physical, _) => Falloff::InverseSquare,
            (TruthKind::SameBrdf, true) => Falloff::Baked(self.inputs.pipeline.baked_falloff()),
            (TruthKind::SameBrdf, false) => Falloff::RealTime(self.inputs.pipeline.attenuation()),
        }
    }

    fn new(scene: &'a CpuScene, inputs: &'a CpuTruthInputs<'a>, bounces: u32, roulette: bool) -> Tracer<'a> {
        let f = inputs.frame;
        let m4 = |m: [[f32; 4]; 4]| DMat4::from_cols_array_2d(&m.map(|c| c.map(|x| x as f64)));
        Tracer {
            scene,
            inputs,
            lights: inputs.lights.iter().map(TracedLight::from).collect(),
            inv_view_proj: m4(f.inv_view_proj),
            camera: v3(f.camera_pos),
            env_scale: f.env[1] as f64,
            subject: f.subject,
            bounces,
            roulette,
            baking: false,
        }
    }

    /// Whether a ray along d passes the surface it hit: the subject's where it is not all there,
    /// with probability 1 − coverage (a screen door, as alpha blending a Fade surface stands for);
    /// a pane's with probability its transmittance (`glass`). An opaque scene draws no number,
    /// so its paths are those of a scene without the test.
    fn passes(&self, hit: &Hit, d: DVec3, rng: &mut Rng) -> bool {
        let object = self.scene.geometry.triangles[hit.triangle][3] as usize;
        if self.inputs.all_opaque() {
            return false;
        }
        if self.inputs.glass[object] {
            return rng.next() < self.pane_transmittance(hit, d);
        }
        if !self.inputs.materials[object].1 {
            return false;
        }
        let coverage = self.inputs.coverage_at(self.uv_at(hit));
        coverage < 1.0 && rng.next() >= coverage
    }

    /// The share of light a pane lets through along d where the ray hit it (`glass`).
    fn pane_transmittance(&self, hit: &Hit, d: DVec3) -> f64 {
        let g = &self.scene.geometry;
        let tri = g.triangles[hit.triangle];
        let [a, b, c] = [0, 1, 2].map(|k| v3(g.vertices[tri[k] as usize].position));
        glass::transmittance(&self.inputs.materials[tri[3] as usize].0, (b - a).cross(c - a), d)
    }

    /// The interpolated uv of a hit.
    fn uv_at(&self, hit: &Hit) -> DVec2 {
        let g = &self.scene.geometry;
        let tri = g.triangles[hit.triangle];
        let [a, b, c] = [0, 1, 2].map(|k| &g.vertices[tri[k] as usize]);
        let uv_of = |v: &super::bvh::TruthVertex| DVec2::new(v.position[3] as f64, v.normal[3] as f64);
        uv_of(a) * (1.0 - hit.b1 - hit.b2) + uv_of(b) * hit.b1 + uv_of(c) * hit.b2
    }

    /// The nearest surface along o + t·d that the ray does not pass.
    fn nearest(&self, mut o: DVec3, d: DVec3, rng: &mut Rng) -> Option<Hit> {
        loop {
            let hit = self.scene.trace(o, d, f64::INFINITY)?;
            if !self.passes(&hit, d, rng) {
                return Some(hit);
            }
            o = self.point_at(&hit) + d * RAY_EPSILON;
        }
    }

    /// Whether a shadow ray from o along d is stopped before t_max.
    fn blocked(&self, mut o: DVec3, d: DVec3, t_max: f64, rng: &mut Rng) -> bool {
        if self.inputs.all_opaque() {
            return self.scene.occluded(o, d, t_max);
        }
        let mut left = t_max;
        loop {
            let Some(hit) = self.scene.trace(o, d, left) else { return false };
            if !self.passes(&hit, d, rng) {
                return true;
            }
            let p = self.point_at(&hit);
            left -= (p - o).length();
            o = p + d * RAY_EPSILON;
        }
    }

    /// The position of a hit (as `surface_at` interpolates it).
    fn point_at(&self, hit: &Hit) -> DVec3 {
        self.scene.point_of(hit)
    }

    fn surface_at(&self, hit: &Hit, d: DVec3) -> SurfacePoint {
        let g = &self.scene.geometry;
        let tri = g.triangles[hit.triangle];
        let [a, b, c] = [0, 1, 2].map(|k| &g.vertices[tri[k] as usize]);
        let b0 = 1.0 - hit.b1 - hit.b2;
        let lerp = |x: [f32; 4], y: [f32; 4], z: [f32; 4]| v3(x) * b0 + v3(y) * hit.b1 + v3(z) * hit.b2;
        let p = lerp(a.position, b.position, c.position);
        let uv_of = |v: &super::bvh::TruthVertex| DVec2::new(v.position[3] as f64, v.normal[3] as f64);
        let uv = uv_of(a) * b0 + uv_of(b) * hit.b1 + uv_of(c) * hit.b2;
        let mut ng = (v3(b.position) - v3(a.position)).cross(v3(c.position) - v3(a.position)).normalize();
        let front = ng.dot(d) < 0.0;
        if !front {
            ng = -ng;
        }
        let interpolated = lerp(a.normal, b.normal, c.normal);
        let mut n = ng;
        if interpolated.length_squared() > 1e-30 {
            n = interpolated.normalize();
            // Flipped on back faces, as the rasteriser's shading normal is.
            if !front {
                n = -n;
            }
        }
        let object = tri[3] as usize;
        let (material, is_subject) = self.inputs.materials[object];
        let m = if is_subject { self.subject } else { material };
        let mut s = surface_from(&m, uv);
        // The subject's emission where its model emits; a fixed object's own (zero for most).
        let mut emission = v3(m.emission);
        // scene.wgsl `surface_from` with maps: the subject's or a fixed object's modulate its material.
        let maps = match (is_subject, self.inputs.subject_maps) {
            (true, Some(maps)) => Some(maps_at(&maps.levels[0], uv)),
            (true, None) => None,
            (false, _) => fixed_maps_at(self.inputs.fixed_maps, &m, uv),
        };
        if let Some([mut albedo, mut normal, mask, glow]) = maps {
            let mut hdrp_detail = None;
            if is_subject && self.inputs.subject_detail {
                // Standard's secondary maps (materials::detail, truth.wgsl)
                use crate::materials::detail::{detail_blend, detail_levels, DETAIL_TILING};
                let l = &detail_levels()[0];
                let d =
                    crate::materials::bilinear(&l.texels, l.size, l.size, uv.x * DETAIL_TILING, uv.y * DETAIL_TILING);
                let dn = [d[0] as f64, d[1] as f64, d[2] as f64];
                let n0 = [normal[0], normal[1], normal[2]];
                let (f, blended) = detail_blend(self.inputs.pipeline, d[3] as f64, n0, dn, mask[2]);
                if self.inputs.pipeline == Pipeline::Hdrp {
                    hdrp_detail = Some((d[3] as f64, mask[2]));
                }
                albedo = [albedo[0] * f, albedo[1] * f, albedo[2] * f, albedo[3]];
                normal = [blended[0], blended[1], blended[2], normal[3]];
            }
            s.base_color *= DVec3::new(albedo[0], albedo[1], albedo[2]);
            if let Some((d, m)) = hdrp_detail {
                // HDRP's overlay acts on the base colour (truth.wgsl `surface_at`).
                let b = crate::materials::detail::hdrp_detail_albedo(s.base_color.to_array(), d, m);
                s.base_color = DVec3::from(b);
            }
            s.metallic = crate::materials::metallic_from_mask(s.metallic, mask[0]);
            // scene.wgsl `smoothness_from_maps`: the albedo's alpha × the slider under Source =
            // Albedo Alpha, else the mask's offset.
            s.smoothness = match m.emission[3] > 0.5 {
                true => (albedo[3] * s.smoothness).clamp(0.0, 1.0),
                false => (s.smoothness + mask[3] - 0.5).clamp(0.0, 1.0),
            };
            emission *= DVec3::new(glow[0], glow[1], glow[2]);
            let t = lerp(a.tangent, b.tangent, c.tangent);
            let w = a.tangent[3] as f64 * b0 + b.tangent[3] as f64 * hit.b1 + c.tangent[3] as f64 * hit.b2;
            n = tangent_to_world(n, t, w, DVec3::new(normal[0], normal[1], normal[2]));
        }
        carried_specular(&mut s, &m);
        if self.inputs.kind == TruthKind::SameBrdf {
            // HDRP Lit's anisotropy reads the tangent (truth.wgsl `surface_at`); the physical model none.
            s.tangent = lerp(a.tangent, b.tangent, c.tangent);
        }
        let mut weight = 1.0;
        if self.inputs.glass[object] {
            s.diffuse_weight = glass::alpha(&m);
            weight = glass::stop_weight(glass::transmittance(&m, ng, d));
        }
        let lobe = (self.inputs.kind == TruthKind::Physical).then(|| physical::PhysicalLobe::new(&s, n, -d));
        SurfacePoint { p, n, ng, object, s, emission: emission * weight, lobe, weight }
    }

    /// The GGX share of this point's continuations: none for a diffuse-only model (a same-brdf
    /// truth's Lambert), else `specular_share` — sampling from the model's own lobes.
    fn lobe_share(&self, sp: &SurfacePoint) -> f64 {
        let twin = if self.inputs.materials[sp.object].1 { self.inputs.subject_twin } else { self.inputs.fixed_twin };
        match self.inputs.kind {
            TruthKind::SameBrdf if twin.is_some_and(|t| t.diffuse_only()) => 0.0,
            _ => specular_share(&sp.s),
        }
    }

    /// f·NL at a point seen from v (the ray that found it): the subject's or the fixed objects'
    /// model without the pipeline's irradiance per intensity, or the physical model (truth.wgsl
    /// `response`).
    fn response(&self, sp: &SurfacePoint, v: DVec3, l: DVec3, min_roughness: f64) -> DVec3 {
        if sp.ng.dot(l) <= 0.0 {
            return DVec3::ZERO;
        }
        let p = self.inputs.pipeline;
        if let Some(lobe) = &sp.lobe {
            return lobe.response(l) * sp.weight;
        }
        let twin = if self.inputs.materials[sp.object].1 { self.inputs.subject_twin } else { self.inputs.fixed_twin };
        // Present for a same-brdf truth (`Renderer::with_cpu_truth` refuses one without).
        twin.map_or(DVec3::ZERO, |t| t.direct_for_light(p, &sp.s, sp.n, v, l, min_roughness).max(DVec3::ZERO))
            * sp.weight
            / irradiance_per_intensity(p)
    }

    /// Light `light` at sp seen from v, before its shadow ray: the direction to it, how far the
    /// shadow ray goes, and what it adds unshadowed (f·NL × its colour × attenuation, in the
    /// pipeline's units: the model's own factor taken back out); None where it adds nothing.
    fn light_sample(&self, light: &TracedLight, sp: &SurfacePoint, v: DVec3, rng: &mut Rng) -> Option<LightSample> {
        let (l, atten, distance) = if light.kind >= LIGHT_RECT {
            let (l, atten, d) = light.area_incidence(sp.p, self.inputs.kind, rng);
            (l, atten, d * (1.0 - 1e-4))
        } else {
            let (l, atten) = light.incidence(sp.p, self.falloff());
            let d = light.shadow_distance(sp.p) * (1.0 - 1e-4);
            (l, atten, d)
        };
        if atten <= 0.0 {
            return None;
        }
        let f = self.response(sp, v, l, light.min_roughness);
        (f.max_element() > 0.0).then(|| LightSample {
            l,
            distance,
            radiance: f * irradiance_per_intensity(self.inputs.pipeline) * light.color * atten,
        })
    }

    /// The environment's sample at sp seen from v (begun before the point was built), before its
    /// shadow ray: its radiance × f·NL over its density, weighed against the surface's sampling.
    fn environment_sample(
        &self,
        sp: &SurfacePoint,
        v: DVec3,
        pending: &PendingEnvironmentSample,
    ) -> Option<LightSample> {
        let EnvironmentSample { direction: l, pdf, radiance } = self.scene.environment.finish_sample(pending);
        let f = self.response(sp, v, l, NO_LIGHT_FLOOR);
        (pdf > 0.0 && f.max_element() > 0.0).then(|| {
            let radiance = radiance * self.env_scale;
            let weight = power_heuristic(pdf, surface_pdf(&sp.s, self.lobe_share(sp), sp.n, v, l));
            LightSample { l, distance: f64::INFINITY, radiance: f * radiance / pdf * weight }
        })
    }

    /// Every light exactly (light i scaled by `weight(i)`: 1 in the truth, the bake's share in a
    /// bake) and the environment sampled once (truth.wgsl `direct_light`).
    /// `environment`: the environment's sample for this point, begun before the point was built
    /// (present where the environment lights the scene).
    fn direct_light(
        &self,
        sp: &SurfacePoint,
        v: DVec3,
        rng: &mut Rng,
        weight: &dyn Fn(usize) -> f64,
        environment: Option<PendingEnvironmentSample>,
    ) -> DVec3 {
        let mut c = DVec3::ZERO;
        let origin = sp.p + sp.ng * RAY_EPSILON;
        for (i, light) in self.lights.iter().enumerate() {
            let w = weight(i);
            if w <= 0.0 {
                continue;
            }
            if let Some(sample) = self.light_sample(light, sp, v, rng) {
                if !self.blocked(origin, sample.l, sample.distance, rng) {
                    c += sample.radiance * w;
                }
            }
        }
        if let Some(sample) = environment.and_then(|pending| self.environment_sample(sp, v, &pending)) {
            if !self.blocked(origin, sample.l, f64::INFINITY, rng) {
                c += sample.radiance;
            }
        }
        c
    }

    /// One path through pixel (x, y) (truth.wgsl `path`); also the object of the first hit.
    fn path(&self, x: u32, y: u32, rng: &mut Rng) -> (DVec3, Option<usize>) {
        let d = self.camera_ray(x, y, rng);
        self.incoming(self.camera, d, (0, None), rng, &|_, _| 1.0)
    }

    /// The direction of a camera ray through pixel (x, y), jittered over the pixel.
    fn camera_ray(&self, x: u32, y: u32, rng: &mut Rng) -> DVec3 {
        let (w, h) = self.inputs.size;
        let (jx, jy) = (rng.next(), rng.next());
        let ndc = DVec2::new((x as f64 + jx) / w as f64 * 2.0 - 1.0, 1.0 - (y as f64 + jy) / h as f64 * 2.0);
        let far = self.inv_view_proj * DVec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - self.camera).normalize()
    }

    /// The index of a path's last surface vertex.
    fn last_bounce(&self) -> u32 {
        if self.roulette {
            crate::declarations::matrix::MAX_ROULETTE_BOUNCES
        } else {
            self.bounces + 1
        }
    }

    /// The light arriving at o from −d along one path (truth.wgsl `incoming`), and the object of
    /// its first hit. `first`: the index of the first surface vertex (0 for a camera ray, 1 for a
    /// bake's ray) and the density d was drawn with against the environment's sampling at o (None:
    /// a camera ray, which sees the sky where the background shows it, or a probe's, which always
    /// does); `weight(vertex, light)`: each light's share at each vertex.
    pub(super) fn incoming(
        &self,
        o: DVec3,
        d: DVec3,
        (first, mis_pdf): (u32, Option<f64>),
        rng: &mut Rng,
        weight: &dyn Fn(u32, usize) -> f64,
    ) -> (DVec3, Option<usize>) {
        let mut path = PathState::new(o, d, mis_pdf);
        let env = &self.scene.environment;
        let last = self.last_bounce();
        for bounce in first..=last {
            let Some(hit) = self.nearest(path.o, path.d, rng) else {
                path.c += self.missed(&path, first > 0 || self.inputs.background);
                break;
            };
            // The environment's sample at this point is drawn first, so that its table reads
            // overlap building the point and tracing to the lights.
            let environment = (bounce != last && self.env_scale > 0.0).then(|| env.begin_sample(rng));
            let sp = self.surface_at(&hit, path.d);
            if let Some(pending) = &environment {
                env.prefetch_texel(pending);
            }
            if bounce == first {
                path.first_object = Some(sp.object);
            }
            path.c += path.throughput * sp.emission;
            // The last vertex only receives the environment along the continued ray (its weight).
            if bounce == last {
                break;
            }
            path.c += path.throughput * self.direct_light(&sp, -path.d, rng, &|i| weight(bounce, i), environment);
            if !self.continue_path(&mut path, &sp, bounce, rng) {
                break;
            }
        }
        (path.c, path.first_object)
    }

    /// What a path whose ray leaves the scene adds: the environment along it, weighed against
    /// the environment's sampling where the ray was drawn from a surface (`last_pdf`); a camera
    /// ray's where the background shows the sky (`sees_sky`).
    fn missed(&self, path: &PathState, sees_sky: bool) -> DVec3 {
        let env = &self.scene.environment;
        match path.last_pdf {
            None if sees_sky => path.throughput * env.radiance(path.d) * self.env_scale,
            None => DVec3::ZERO,
            Some(pdf) if self.env_scale > 0.0 => {
                let (radiance, env_pdf) = env.lookup(path.d);
                path.throughput * radiance * self.env_scale * power_heuristic(pdf, env_pdf)
            }
            Some(_) => DVec3::ZERO,
        }
    }

    /// The continuation from sp: draws the next direction from the surface and carries the
    /// throughput along it; false where the path ends there.
    fn continue_path(&self, path: &mut PathState, sp: &SurfacePoint, bounce: u32, rng: &mut Rng) -> bool {
        let v = -path.d;
        let k = self.lobe_share(sp);
        let l = sample_surface(&sp.s, k, sp.n, v, rng);
        if self.env_scale > 0.0 {
            self.scene.environment.prefetch_direction(l);
        }
        let pdf = surface_pdf(&sp.s, k, sp.n, v, l);
        if pdf <= 0.0 {
            return false;
        }
        path.throughput *= self.response(sp, v, l, NO_LIGHT_FLOOR) / pdf;
        if path.throughput.max_element() <= 0.0 {
            return false;
        }
        // Past the budget, the continuation survives Russian roulette or the path ends.
        if self.roulette && bounce >= self.bounces {
            let q = path.throughput.max_element().min(0.95);
            if rng.next() >= q {
                return false;
            }
            path.throughput /= q;
        }
        path.last_pdf = Some(pdf);
        path.o = sp.p + sp.ng * RAY_EPSILON;
        path.d = l;
        true
    }
}

/// What a light or the environment adds at a point unless its shadow ray is blocked.
struct LightSample {
    l: DVec3,
    distance: f64,
    radiance: DVec3,
}

/// One path between bounces: its ray, its throughput and sum so far, the density its ray was
/// drawn with (None: a camera's or probe's), and the object of its first hit.
struct PathState {
    o: DVec3,
    d: DVec3,
    throughput: DVec3,
    c: DVec3,
    last_pdf: Option<f64>,
    first_object: Option<usize>,
}

impl PathState {
    fn new(o: DVec3, d: DVec3, last_pdf: Option<f64>) -> PathState {
        PathState { o, d, throughput: DVec3::ONE, c: DVec3::ZERO, last_pdf, first_object: None }
    }
}

/// Trace batches until converged (render::truth's module comment), on every core: the samples
/// of a pixel eight at a time in lockstep where the scene allows (`lanes`), else one by one.
pub fn trace(scene: &CpuScene, inputs: &CpuTruthInputs, settings: &TruthSettings) -> Result<Truth, Error> {
    trace_paths(scene, inputs, settings, true)
}

/// `trace`, with the lockstep tracer allowed or not (the tests compare the two).
fn trace_paths(
    scene: &CpuScene,
    inputs: &CpuTruthInputs,
    settings: &TruthSettings,
    allow_lockstep: bool,
) -> Result<Truth, Error> {
    let start = std::time::Instant::now();
    let tracer = Tracer::new(scene, inputs, settings.bounces, settings.roulette);
    let lockstep = allow_lockstep && tracer.lockstep();
    let (width, height) = inputs.size;
    let pixels = (width * height) as usize;
    // Per pixel: the sum (rgb) and count (w), then the sum of squares, as the GPU accumulates.
    let mut accum = vec![[0f64; 4]; 2 * pixels];
    let mut roles = vec![0u32; pixels];
    let role_of = |object: Option<usize>| match object {
        None => 0,
        Some(o) if inputs.materials[o].1 => inputs.subject_role as u32,
        Some(_) => inputs.fixed_role as u32,
    };
    let batch = settings.batch.max(1);
    let spp = settings.spp.max(1);
    let mut done = 0u32;
    loop {
        let count = batch.min(spp - done);
        accum.par_chunks_mut(2 * width as usize).zip(roles.par_chunks_mut(width as usize)).enumerate().for_each(
            |(y, (row, row_roles))| {
                for x in 0..width as usize {
                    let index = (y * width as usize + x) as u32;
                    let rng = |k: u32| match settings.sampler {
                        TruthSampler::Independent => Rng::new(index, done + k),
                        TruthSampler::Sobol => Rng::sobol(index, done + k),
                    };
                    let mut add = |(mut c, first): (DVec3, Option<usize>)| {
                        row_roles[x] = role_of(first);
                        // A NaN or infinite sample (a model's singularity) counts as 0, as on the GPU.
                        if !c.is_finite() || c.abs().max_element() > 1e30 {
                            c = DVec3::ZERO;
                        }
                        let (s, q) = (&mut row[2 * x], c * c);
                        *s = [s[0] + c.x, s[1] + c.y, s[2] + c.z, s[3] + 1.0];
                        let sq = &mut row[2 * x + 1];
                        *sq = [sq[0] + q.x, sq[1] + q.y, sq[2] + q.z, 0.0];
                    };
                    if !lockstep {
                        (0..count).for_each(|k| add(tracer.path(x as u32, y as u32, &mut rng(k))));
                        continue;
                    }
                    for first in (0..count).step_by(lanes::LANES) {
                        let n = (count - first).min(lanes::LANES as u32) as usize;
                        let mut rngs: [Rng; lanes::LANES] = std::array::from_fn(|i| rng(first + i as u32));
                        tracer.paths(x as u32, y as u32, &mut rngs[..n]).into_iter().take(n).for_each(&mut add);
                    }
                }
            },
        );
        done += count;
        let sums: Vec<[f32; 4]> = accum.iter().map(|a| a.map(|v| v as f32)).collect();
        let mut result = super::summarise(&sums, &roles, inputs.size, inputs.subject_role, done);
        let converged = result.subject_noise.is_some_and(|n| n <= settings.noise);
        if converged || done >= spp {
            result.seconds = start.elapsed().as_secs_f64();
            result.bounces = settings.bounces;
            result.kind = settings.kind;
            return Ok(result);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embree_finds_the_nearest_triangle_brute_force_finds() {
        // Random rays through two overlapping spheres: the hit Embree reports is at the distance
        // of the nearest triangle any ray-triangle test over all of them finds.
        let sphere = crate::geometry::procedural::uv_sphere(1.0, 12, 24);
        let shifted = DMat4::from_translation(DVec3::new(0.8, 0.3, 0.0));
        let geometry = TruthGeometry::build([(0, &sphere, DMat4::IDENTITY), (1, &sphere, shifted)]);
        let image = crate::environment::prefilter::EquirectImage { width: 4, height: 2, texels: vec![DVec3::ONE; 8] };
        let scene = CpuScene::new(geometry, CpuEnvironment::new(&image)).expect("an Embree scene");
        let g = &scene.geometry;
        let distance = |o: DVec3, d: DVec3, k: usize| {
            let [p0, p1, p2] = [0, 1, 2].map(|i| v3(g.vertices[g.triangles[k][i] as usize].position));
            let (e1, e2) = (p1 - p0, p2 - p0);
            let pv = d.cross(e2);
            let det = e1.dot(pv);
            let tv = o - p0;
            let qv = tv.cross(e1);
            let (b1, b2, t) = (tv.dot(pv) / det, d.dot(qv) / det, e2.dot(qv) / det);
            (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && t > RAY_EPSILON).then_some(t)
        };
        let mut rng = Rng::new(11, 2);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..2000 {
            let o = DVec3::new(rng.next() * 6.0 - 3.0, rng.next() * 6.0 - 3.0, rng.next() * 6.0 - 3.0);
            let target = DVec3::new(rng.next() * 4.0 - 2.0, rng.next() * 4.0 - 2.0, rng.next() * 4.0 - 2.0);
            let d = (target - o).normalize();
            let nearest = (0..g.triangles.len()).filter_map(|k| distance(o, d, k)).min_by(f64::total_cmp);
            match (scene.trace(o, d, f64::INFINITY), nearest) {
                (Some(hit), Some(t)) => {
                    let found = distance(o, d, hit.triangle).unwrap_or_else(|| (scene.point_of(&hit) - o).length());
                    assert!((found - t).abs() < 1e-4 * t.max(1.0), "hit at {found}, nearest at {t}");
                    assert!(scene.occluded(o, d, t * 1.01) && !scene.occluded(o, d, t * 0.99));
                    hits += 1;
                }
                (None, None) => misses += 1,
                // A ray grazing an edge: f32 and f64 may disagree there, nowhere else.
                (a, b) => panic!("Embree {:?}, brute force {b:?}", a.map(|h| h.triangle)),
            }
        }
        assert!(hits > 500 && misses > 100, "{hits} hits, {misses} misses");
    }

    #[test]
    fn surface_sampling_density_integrates_to_one() {
        // The mixture's pdf over the hemisphere is 1 (less the specular lobe's share below the
        // horizon): a midpoint quadrature.
        let s = Surface::basic(DVec3::splat(0.5), 0.5, 0.6);
        let n = DVec3::Z;
        let v = DVec3::new(0.6, 0.0, 0.8);
        let (steps_t, steps_p) = (400, 400);
        let mut total = 0.0;
        for i in 0..steps_t {
            let theta = (i as f64 + 0.5) / steps_t as f64 * PI / 2.0;
            for j in 0..steps_p {
                let phi = (j as f64 + 0.5) / steps_p as f64 * 2.0 * PI;
                let l = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                total += surface_pdf(&s, specular_share(&s), n, v, l)
                    * theta.sin()
                    * (PI / 2.0 / steps_t as f64)
                    * (2.0 * PI / steps_p as f64);
            }
        }
        assert!(total > 0.95 && total <= 1.001, "{total}");
    }

    #[test]
    fn sampled_directions_follow_the_density() {
        // The mean of 1/pdf over sampled directions above the horizon estimates the hemisphere's
        // solid angle (2π) when the sampler draws from that density.
        let s = Surface::basic(DVec3::splat(0.5), 0.0, 0.4);
        let (n, v) = (DVec3::Z, DVec3::new(0.3, 0.0, 0.954).normalize());
        let mut rng = Rng::new(7, 1);
        let (mut sum, count) = (0.0, 200_000);
        for _ in 0..count {
            let l = sample_surface(&s, specular_share(&s), n, v, &mut rng);
            let pdf = surface_pdf(&s, specular_share(&s), n, v, l);
            if l.z > 0.0 && pdf > 0.0 {
                sum += 1.0 / pdf;
            }
        }
        let estimate = sum / count as f64;
        assert!((estimate / (2.0 * PI) - 1.0).abs() < 0.03, "{estimate}");
    }
}
