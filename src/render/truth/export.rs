//! The scene as the physical truth traces it, written for another renderer (`[outputs]
//! truth_scene = true`; tools/mitsuba_check.py reads it): the camera as rays leave it, every
//! light in the radiometric units the tracer multiplies (a point light's radiant intensity, a
//! directional light's irradiance), each object's triangles in world space as a binary PLY with its
//! physical material, the sky the tracer samples (equirect, `equirect_uv`'s convention), the FGD
//! table its multiple-scattering compensation reads, and the truth itself. Only the physical
//! truth: a same-brdf truth's surfaces are the pipeline's own models, which no other renderer has.
//!
//! PLY is written here: a few lines of a fixed binary layout, not worth a dependency.

use glam::{DMat4, DVec3, DVec4};
use serde::{Deserialize, Serialize};

use super::cpu::{CpuScene, CpuTruthInputs};
use super::{Truth, TruthKind};
use crate::error::Error;
use crate::shading::fgd::FgdTable;
use crate::shading::twin::irradiance_per_intensity;

/// Bumped when a field changes meaning.
pub const TRUTH_SCENE_SCHEMA: u32 = 1;

/// scene.json of an exported truth scene.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TruthSceneRecord {
    pub schema: u32,
    pub width: u32,
    pub height: u32,
    /// Continuation bounces after the camera's hit (the camera segment and the segment to a light
    /// are not counted: Mitsuba's `max_depth` is `bounces + 2`).
    pub bounces: u32,
    /// Paths went on past `bounces` under Russian roulette (every bounce: Mitsuba's
    /// `max_depth = -1`).
    #[serde(default)]
    pub roulette: bool,
    pub spp: u32,
    pub camera: ExportedCamera,
    /// Whether camera rays that miss see the sky.
    pub background: bool,
    pub lights: Vec<ExportedLight>,
    pub objects: Vec<ExportedObject>,
    /// Equirect RGBA32F, radiance already scaled; u = atan2(x, −z)/2π + ½, v = acos(y)/π, texel
    /// lookup nearest. None when the sky sends no light.
    pub sky: Option<String>,
    /// FgdTable texels (RGBA32F, row = perceptual roughness j/(n−1), column = √NV i/(n−1)); the
    /// compensation is 1 + F0·(1/G − 1), G bilinear.
    pub fgd: String,
    /// The truth: mean radiance in RGB, the standard error of its luminance in A (RGBA32F).
    pub truth: String,
}

/// A pinhole camera: rays jittered uniformly over each pixel (a box filter).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ExportedCamera {
    pub position: [f64; 3],
    pub target: [f64; 3],
    pub up: [f64; 3],
    /// Full vertical field of view.
    pub fov_y_deg: f64,
    pub fov_x_deg: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ExportedLight {
    /// Light travelling along `direction`; `irradiance` on a surface facing it.
    Directional { direction: [f64; 3], irradiance: [f64; 3] },
    /// Radiant `intensity`; inverse-square falloff.
    Point { position: [f64; 3], intensity: [f64; 3] },
    /// A point light times sat((cos − cos_outer)/(cos_inner − cos_outer))².
    Spot { position: [f64; 3], direction: [f64; 3], intensity: [f64; 3], cos_outer: f64, cos_inner: f64 },
}

/// The physical model's inputs (render::truth::physical): f = base(1 − m)/π + GGX, F0 =
/// lerp(0.04, base, m), α = (1 − smoothness)²; `checker` replaces the base colour on odd cells of
/// floor(uv / cell).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ExportedObject {
    pub name: String,
    pub mesh: String,
    pub subject: bool,
    pub triangles: usize,
    pub base_color: [f64; 3],
    pub metallic: f64,
    pub smoothness: f64,
    pub emission: [f64; 3],
    pub checker: Option<ExportedChecker>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ExportedChecker {
    pub color: [f64; 3],
    pub cell: f64,
}

/// An exported scene: its record and its files' contents (images as RGBA32F, written by the run).
pub struct TruthSceneExport {
    pub record: TruthSceneRecord,
    pub meshes: Vec<(String, Vec<u8>)>,
    /// (file, width, height, RGBA32F).
    pub images: Vec<(String, u32, u32, Vec<f32>)>,
}

fn a3(v: DVec3) -> [f64; 3] {
    v.to_array()
}

fn v3(a: [f32; 4]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

/// The camera that `inv_view_proj` and `position` describe: the directions through the image's
/// centre, top and right edges.
fn camera(inv_view_proj: DMat4, position: DVec3) -> ExportedCamera {
    let through = |x: f64, y: f64| {
        let far = inv_view_proj * DVec4::new(x, y, 1.0, 1.0);
        (far.truncate() / far.w - position).normalize()
    };
    let (centre, top, right) = (through(0.0, 0.0), through(0.0, 1.0), through(1.0, 0.0));
    let up = (top - centre * centre.dot(top)).normalize();
    ExportedCamera {
        position: a3(position),
        target: a3(position + centre),
        up: a3(up),
        fov_y_deg: 2.0 * centre.dot(top).clamp(-1.0, 1.0).acos().to_degrees(),
        fov_x_deg: 2.0 * centre.dot(right).clamp(-1.0, 1.0).acos().to_degrees(),
    }
}

/// A binary little-endian PLY of triangles: x y z nx ny nz u v per vertex.
fn ply(vertices: &[[f32; 8]], faces: &[[u32; 3]]) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\n\
         property float v\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        vertices.len(),
        faces.len()
    );
    let mut out = header.into_bytes();
    for v in vertices {
        for x in v {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    for f in faces {
        out.push(3);
        for i in f {
            out.extend_from_slice(&(*i as i32).to_le_bytes());
        }
    }
    out
}

/// The export of a physical truth over `scene` with `inputs`; `names` names each object.
pub fn export(
    scene: &CpuScene,
    inputs: &CpuTruthInputs,
    names: &[String],
    truth: &Truth,
    roulette: bool,
) -> Result<TruthSceneExport, Error> {
    if inputs.kind != TruthKind::Physical {
        return Err(Error::Other(
            "[outputs] truth_scene exports the physical truth only: a same-brdf truth shades with the \
             pipeline's own models, which another renderer does not have"
                .into(),
        ));
    }
    if !inputs.fixed_maps.materials.is_empty() {
        return Err(Error::Other(
            "[outputs] truth_scene does not carry fixed objects' material maps (base_color_map, \
             gltf_material) yet: export a composition whose fixed objects have factors alone"
                .into(),
        ));
    }
    let f = inputs.frame;
    let m4 = |m: [[f32; 4]; 4]| DMat4::from_cols_array_2d(&m.map(|c| c.map(|x| x as f64)));
    let scale = irradiance_per_intensity(inputs.pipeline);
    let lights = inputs
        .lights
        .iter()
        .map(|l| {
            let radiant = a3(v3(l.color) * scale);
            match l.position[3] as u32 {
                0 => ExportedLight::Directional { direction: a3(v3(l.direction).normalize()), irradiance: radiant },
                1 => ExportedLight::Point { position: a3(v3(l.position)), intensity: radiant },
                _ => ExportedLight::Spot {
                    position: a3(v3(l.position)),
                    direction: a3(v3(l.direction).normalize()),
                    intensity: radiant,
                    cos_outer: l.params[1] as f64,
                    cos_inner: l.params[2] as f64,
                },
            }
        })
        .collect();
    let g = &scene.geometry;
    let mut objects = Vec::new();
    let mut meshes = Vec::new();
    for (object, (material, subject)) in inputs.materials.iter().enumerate() {
        // Vertices renumbered per object, in the order its triangles first name them.
        let mut remap = std::collections::HashMap::new();
        let (mut vertices, mut faces) = (Vec::new(), Vec::new());
        for t in g.triangles.iter().filter(|t| t[3] as usize == object) {
            let face = [0, 1, 2].map(|k| {
                *remap.entry(t[k]).or_insert_with(|| {
                    let v = &g.vertices[t[k] as usize];
                    let (p, n) = (v.position, v.normal);
                    vertices.push([p[0], p[1], p[2], n[0], n[1], n[2], p[3], n[3]]);
                    vertices.len() as u32 - 1
                })
            });
            faces.push(face);
        }
        if faces.is_empty() {
            continue;
        }
        let m = if *subject { f.subject } else { *material };
        let file = format!("object_{object}.ply");
        meshes.push((file.clone(), ply(&vertices, &faces)));
        objects.push(ExportedObject {
            name: names.get(object).cloned().unwrap_or_else(|| format!("object {object}")),
            mesh: file,
            subject: *subject,
            triangles: faces.len(),
            base_color: a3(v3(m.base_color)),
            metallic: m.params[0] as f64,
            smoothness: m.params[1] as f64,
            emission: a3(v3(m.emission)),
            checker: (m.params[2] > 0.0)
                .then(|| ExportedChecker { color: a3(v3(m.checker_color)), cell: m.params[2] as f64 }),
        });
    }
    let mut images = Vec::new();
    let env_scale = f.env[1] as f64;
    let sky = (env_scale > 0.0).then(|| {
        let e = &scene.environment;
        let (w, h) = e.size();
        let px = (0..w * h)
            .map(|i| e.texel(i))
            .flat_map(|c| [(c.x * env_scale) as f32, (c.y * env_scale) as f32, (c.z * env_scale) as f32, 1.0]);
        images.push(("sky.exr".to_string(), w as u32, h as u32, px.collect()));
        "sky.exr".to_string()
    });
    let fgd = FgdTable::get();
    let n = fgd.size as u32;
    images.push(("fgd.exr".into(), n, n, fgd.texels.iter().flatten().copied().collect()));
    let px = truth.mean.iter().zip(&truth.std_error).flat_map(|(m, &se)| [m[0], m[1], m[2], se]).collect();
    images.push(("truth.exr".into(), truth.width, truth.height, px));
    let record = TruthSceneRecord {
        schema: TRUTH_SCENE_SCHEMA,
        width: truth.width,
        height: truth.height,
        bounces: truth.bounces,
        roulette,
        spp: truth.spp,
        camera: camera(m4(f.inv_view_proj), v3(f.camera_pos)),
        background: inputs.background,
        lights,
        objects,
        sky,
        fgd: "fgd.exr".into(),
        truth: "truth.exr".into(),
    };
    Ok(TruthSceneExport { record, meshes, images })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_comes_back_from_its_matrices() {
        let eye = DVec3::new(0.0, 3.195, 5.033);
        let target = DVec3::new(0.0, 0.74, 0.0);
        let view = DMat4::look_at_rh(eye, target, DVec3::Y);
        let proj = DMat4::perspective_rh(38f64.to_radians(), 1.5, 0.1, 100.0);
        let c = camera((proj * view).inverse(), eye);
        assert!((c.fov_y_deg - 38.0).abs() < 1e-9, "{}", c.fov_y_deg);
        let want_x = 2.0 * ((19f64.to_radians()).tan() * 1.5).atan().to_degrees();
        assert!((c.fov_x_deg - want_x).abs() < 1e-9);
        let dir = (DVec3::from(c.target) - eye).normalize();
        assert!(dir.dot((target - eye).normalize()) > 1.0 - 1e-12);
        assert!(DVec3::from(c.up).dot(DVec3::Y) > 0.8 && DVec3::from(c.up).dot(dir).abs() < 1e-12);
    }

    #[test]
    fn a_ply_holds_its_header_vertices_and_faces() {
        let bytes = ply(&[[0.0; 8], [1.0; 8], [2.0; 8]], &[[0, 1, 2]]);
        let header_end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        assert_eq!(bytes.len() - header_end, 3 * 32 + 1 + 12);
        assert!(std::str::from_utf8(&bytes[..header_end]).unwrap().contains("element vertex 3\n"));
    }
}
