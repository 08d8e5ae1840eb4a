//! Scene files (`scenes/*.toml`): camera, lights, objects, environment.
//!
//! Convention, stated once: metres, Y up, right-handed (glTF's own convention, so glTF needs no
//! axis conversion). Colours in scene files are sRGB unless a key says `_linear`.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::error::{Error, InputError};
use crate::input::names::unknown_name;
use crate::input::source::parse_toml;
use crate::input::validate::Checker;

/// The four compositions of `spec/scenes.md`, embedded so the binary works from any folder.
pub const BUILTIN_SCENES: [(&str, &str); 5] = [
    ("default", include_str!("../../scenes/default.toml")),
    ("mitsuba", include_str!("../../scenes/mitsuba.toml")),
    ("medusa", include_str!("../../scenes/medusa.toml")),
    ("spikes", include_str!("../../scenes/spikes.toml")),
    ("composite", include_str!("../../scenes/composite.toml")),
];

/// Sky images built into the tool, by the path a built-in scene names them with (relative to
/// scenes/): scenes/skies/stylized.exr is `environment::stylized_sky`'s bake.
pub const BUILTIN_SKIES: [(&str, &[u8]); 1] =
    [("skies/stylized.exr", include_bytes!("../../scenes/skies/stylized.exr"))];

/// Texture images built into the tool, by the path a built-in scene names them with (relative to
/// scenes/): the composite's photos, baked by `examples/bake_composite_photos`.
pub const BUILTIN_TEXTURES: [(&str, &[u8]); 2] = [
    ("textures/landscape.png", include_bytes!("../../scenes/textures/landscape.png")),
    ("textures/tree.png", include_bytes!("../../scenes/textures/tree.png")),
];

pub fn builtin_scene_names() -> Vec<&'static str> {
    BUILTIN_SCENES.iter().map(|(n, _)| *n).collect()
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub camera: Camera,
    #[serde(default)]
    pub lights: Vec<Light>,
    pub objects: Vec<Object>,
    pub environment: Environment,
    /// Degrees between the directions from the camera target to the camera and to the key light;
    /// when set, the key light is turned about the target to make it (the matrix's `light_angle`
    /// axis overrides it). Medusa and spikes state their 50°.
    #[serde(default)]
    pub light_angle_deg: Option<f64>,
    /// Reflection probes, most important first (`environment.reflections = "probe"` uses them).
    #[serde(default)]
    pub probes: Vec<ReflectionProbe>,
    /// HDRP volume overrides (exposure) for this scene; HDRP's default volume where absent.
    #[serde(default)]
    pub hdrp: crate::pipelines::volume::HdrpVolume,
    /// A glTF file whose nodes, lights and cameras join the scene (`GltfSceneSpec`).
    #[serde(default)]
    pub gltf_scene: Option<GltfSceneSpec>,
    /// Baked global illumination (declarations::gi); absent: nothing is baked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gi: Option<super::gi::GiSettings>,
    /// Where the scene came from: a built-in name or a file path (not part of the TOML).
    #[serde(skip)]
    pub origin: String,
    /// Folder that relative glTF paths resolve against; `None` for embedded scenes.
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    pub position: [f64; 3],
    pub target: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    #[serde(default = "default_near")]
    pub near: f64,
    #[serde(default = "default_far")]
    pub far: f64,
}

fn default_near() -> f64 {
    0.05
}
fn default_far() -> f64 {
    100.0
}

pub use super::light::{Light, LightKind, RenderMode, ShadowSettings};

fn one() -> f64 {
    1.0
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Receives the swept material.
    Subject,
    /// Keeps its own material.
    Fixed,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Object {
    pub name: String,
    pub role: Role,
    pub mesh: MeshSpec,
    #[serde(default)]
    pub transform: Transform,
    /// Required for fixed objects, ignored (and refused) for subjects.
    #[serde(default)]
    pub material: Option<FixedMaterial>,
    /// Unity's Mesh Renderer "Cast Shadows" and "Receive Shadows", both on by default.
    #[serde(default = "yes")]
    pub cast_shadows: bool,
    #[serde(default = "yes")]
    pub receive_shadows: bool,
    /// The faces drawn (`front`, the engines' default; `back`; `both`, a glTF `doubleSided`
    /// material's). Back faces are shaded with the mesh's normal in built-in and URP, whose
    /// hand-written lit shaders read it as it is, and with it flipped in HDRP (Double-Sided
    /// Normal Mode Mirror, its default, which is the flip wherever no normal map bends it).
    #[serde(default, skip_serializing_if = "is_front")]
    pub render_face: crate::pipelines::surface::RenderFace,
    /// A LOD group: coarser meshes for smaller screen heights (`plan::lod`).
    #[serde(default)]
    pub lod: Option<LodGroup>,
}

/// Unity's LODGroup on an object: `mesh` is level 0, `meshes` the levels after it; `transitions`
/// the relative screen height below which each level (level 0 first) gives way, strictly
/// decreasing, the group culled below the last; `bias` QualitySettings.lodBias (absent: the
/// pipeline's default quality level's, `Pipeline::quality_lod_bias`); `fade_width`
/// fadeTransitionWidth with fade mode CrossFade (0: no cross-fade, Unity's default fade mode None).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LodGroup {
    pub meshes: Vec<MeshSpec>,
    pub transitions: Vec<f64>,
    #[serde(default)]
    pub bias: Option<f64>,
    #[serde(default)]
    pub fade_width: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    #[serde(default)]
    pub translate: [f64; 3],
    /// Euler angles in degrees, applied in the order Y, X, Z (Unity's order).
    #[serde(default)]
    pub rotate_deg: [f64; 3],
    #[serde(default = "unit_scale")]
    pub scale: [f64; 3],
    /// A whole object-to-world matrix (column-major) instead of the three above: a glTF node's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[f64; 16]>,
}

fn is_front(f: &crate::pipelines::surface::RenderFace) -> bool {
    *f == crate::pipelines::surface::RenderFace::Front
}

fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}

impl Default for Transform {
    fn default() -> Self {
        Self { translate: [0.0; 3], rotate_deg: [0.0; 3], scale: unit_scale(), matrix: None }
    }
}

impl Transform {
    pub fn matrix(&self) -> glam::DMat4 {
        if let Some(m) = self.matrix {
            return glam::DMat4::from_cols_array(&m);
        }
        let r = self.rotate_deg.map(f64::to_radians);
        let rotation = glam::DQuat::from_euler(glam::EulerRot::YXZ, r[1], r[0], r[2]);
        glam::DMat4::from_scale_rotation_translation(self.scale.into(), rotation, self.translate.into())
    }
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FixedMaterial {
    /// Linear base colour.
    pub base_color_linear: [f64; 3],
    #[serde(default)]
    pub metallic: f64,
    #[serde(default)]
    pub smoothness: f64,
    /// A UV checkerboard: second colour (linear) and cell size in UV units.
    #[serde(default)]
    pub checker: Option<Checkerboard>,
    /// Emitted radiance, linear colour × intensity in the pipeline's light units (as the
    /// subject's emission axis), added before tonemapping as Unity's emission is; times the
    /// emission map of `gltf_material` where it has one.
    #[serde(default, skip_serializing_if = "is_black")]
    pub emission_linear: [f64; 3],
    /// A base-colour map on UV set 0: an image whose texels multiply `base_color_linear`, PNG
    /// (sRGB-encoded) or OpenEXR (linear), relative to the scene's folder (a built-in scene's
    /// are the tool's `BUILTIN_TEXTURES`); read when the scene is loaded (`input::texture_file`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_color_map: Option<String>,
    /// A glTF file's material whose maps (base colour, metallic-roughness, normal, occlusion,
    /// emission; `KHR_texture_transform` applied to the mesh's UVs) modulate this material's
    /// factors, as the subject's own material does: what `[gltf_scene]` sets for a textured
    /// material. Read when the composition is prepared (`materials::fixed`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gltf_material: Option<GltfMaterialRef>,
    /// Unity's texture tiling and offset (`_MainTex_ST`, TRANSFORM_TEX): the object's UVs become
    /// uv · map_tiling + map_offset, for its maps and its checkerboard alike.
    #[serde(default = "unit_tiling", skip_serializing_if = "is_unit_tiling")]
    pub map_tiling: [f64; 2],
    #[serde(default, skip_serializing_if = "is_zero_offset")]
    pub map_offset: [f64; 2],
    /// The surface type: `opaque` (the default) or `transparent` — Unity's Transparent queue with
    /// Blending Mode Alpha and the specular lighting preserved (built-in Standard's Transparent,
    /// URP Lit's and HDRP Lit's Transparent), the one every pipeline's lit shaders share without a
    /// clip map: the window glass. Drawn after the opaque objects, back to front, writing no depth.
    #[serde(default, skip_serializing_if = "is_opaque")]
    pub surface: crate::pipelines::surface::SurfaceType,
    /// The base colour's alpha (`_Color.a`, `_BaseColor.a`), which a transparent surface blends by.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub alpha: f64,
    /// The base-colour map's SHA-256: serialised into keys, so that an edited image changes them.
    #[serde(default, skip_deserializing, skip_serializing_if = "String::is_empty")]
    pub map_digest: String,
    #[serde(skip)]
    pub map_image: Option<std::sync::Arc<crate::input::texture_file::TextureFile>>,
}

impl FixedMaterial {
    /// A material of factors alone.
    pub fn flat(base_color_linear: [f64; 3], metallic: f64, smoothness: f64) -> FixedMaterial {
        FixedMaterial {
            base_color_linear,
            metallic,
            smoothness,
            checker: None,
            emission_linear: [0.0; 3],
            base_color_map: None,
            gltf_material: None,
            map_tiling: unit_tiling(),
            map_offset: [0.0; 2],
            map_digest: String::new(),
            map_image: None,
            surface: Default::default(),
            alpha: 1.0,
        }
    }

    /// Whether the object is drawn in the Transparent queue.
    pub fn is_transparent(&self) -> bool {
        self.surface.is_transparent()
    }

    /// Whether the material samples maps.
    pub fn has_maps(&self) -> bool {
        self.base_color_map.is_some() || self.gltf_material.is_some()
    }
}

fn is_opaque(s: &crate::pipelines::surface::SurfaceType) -> bool {
    *s == crate::pipelines::surface::SurfaceType::Opaque
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

fn is_black(c: &[f64; 3]) -> bool {
    c.iter().all(|v| *v == 0.0)
}

fn unit_tiling() -> [f64; 2] {
    [1.0; 2]
}

fn is_unit_tiling(t: &[f64; 2]) -> bool {
    *t == [1.0; 2]
}

fn is_zero_offset(o: &[f64; 2]) -> bool {
    *o == [0.0; 2]
}

/// Material `index` of the glTF file at `path` (relative to the scene's folder).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GltfMaterialRef {
    pub path: String,
    pub index: usize,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Checkerboard {
    pub color_linear: [f64; 3],
    pub cell: f64,
}

/// `[gltf_scene]`: a glTF file as (the rest of) the scene, read when the scene is loaded
/// (`input::gltf_scene`): each node's triangle primitives become objects with their own
/// material's factors (base colour, metallic, smoothness = 1 − roughness) at the node's world
/// transform; the nodes at and below `subject` are the subject (they take the swept material);
/// `KHR_lights_punctual` lights join `[[lights]]` in their photometric units (`Light::photometric`);
/// `camera` names a camera node that replaces `[camera]` (its roll is not kept: the tool's camera
/// keeps +Y up).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GltfSceneSpec {
    pub path: String,
    pub subject: String,
    #[serde(default)]
    pub camera: Option<String>,
}

/// Mesh sources: procedural kinds with their parameters, or a glTF/GLB file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshSpec {
    UvSphere {
        radius: f64,
        rings: u32,
        segments: u32,
    },
    Box {
        size: [f64; 3],
    },
    /// In the XZ plane, normal +Y, centred at the origin.
    Plane {
        size: [f64; 2],
        subdivisions: u32,
    },
    /// Surface of revolution about +Y of a 2-D profile of (radius, height) points.
    Lathe {
        profile: Vec<[f64; 2]>,
        segments: u32,
    },
    /// The material-preview knob's outer shell: a thick sphere shell with a bevelled window.
    KnobShell {
        center_height: f64,
        outer_radius: f64,
        inner_radius: f64,
        window_half_angle_deg: f64,
        /// Azimuth of the window axis about +Y, degrees, measured from +Z towards +X.
        window_azimuth_deg: f64,
        rings: u32,
        segments: u32,
    },
    /// A floor bending up into a back wall (photographer's cyclorama), extruded along X.
    Cyclorama {
        width: f64,
        depth: f64,
        height: f64,
        bend_radius: f64,
        segments: u32,
    },
    /// BRDF-evaluation disc with sunflower-lattice bumps (spec: spikes).
    Spikes {
        radius: f64,
        count: u32,
        bump_radius: f64,
        bump_height: f64,
        rings: u32,
        segments: u32,
    },
    /// BRDF-evaluation disc with angle-modulated radial waves (spec: medusa).
    Medusa {
        radius: f64,
        amplitude: f64,
        k: f64,
        n: u32,
        m: f64,
        rings: u32,
        segments: u32,
    },
    /// A glTF or GLB file, relative to the scene file: every triangle primitive of its scene, or
    /// with `material` those naming that material (with the file's first material, also those
    /// naming none): a subject's other materials are drawn as their own fixed objects
    /// (`Scene::split_gltf_subject`).
    Gltf {
        path: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        material: Option<usize>,
    },
    /// One primitive of one mesh of a glTF file, in the mesh's own space (`[gltf_scene]` makes
    /// these).
    GltfPrimitive {
        path: String,
        mesh: usize,
        primitive: usize,
    },
}

impl MeshSpec {
    /// Parameter checks, so bad scene values fail before anything is generated.
    pub fn validate(&self) -> Result<(), String> {
        let spec = self;
        let pos = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} = {v} must be > 0"))
            }
        };
        let tess = |name: &str, v: u32, lo: u32| {
            if (lo..=4096).contains(&v) {
                Ok(())
            } else {
                Err(format!("{name} = {v} is out of range; allowed {lo}..=4096"))
            }
        };
        match spec {
            MeshSpec::UvSphere { radius, rings, segments } => {
                pos("radius", *radius)?;
                tess("rings", *rings, 2)?;
                tess("segments", *segments, 3)
            }
            MeshSpec::Box { size } => size.iter().try_for_each(|s| pos("size", *s)),
            MeshSpec::Plane { size, subdivisions } => {
                size.iter().try_for_each(|s| pos("size", *s))?;
                tess("subdivisions", *subdivisions, 1)
            }
            MeshSpec::Lathe { profile, segments } => {
                tess("segments", *segments, 3)?;
                if profile.len() < 2 {
                    return Err("profile needs at least 2 points".into());
                }
                if profile.iter().any(|p| p[0] < 0.0 || !p[0].is_finite() || !p[1].is_finite()) {
                    return Err("profile radii must be finite and >= 0".into());
                }
                Ok(())
            }
            MeshSpec::KnobShell {
                center_height: _,
                outer_radius,
                inner_radius,
                window_half_angle_deg,
                window_azimuth_deg: _,
                rings,
                segments,
            } => {
                pos("outer_radius", *outer_radius)?;
                pos("inner_radius", *inner_radius)?;
                if inner_radius >= outer_radius {
                    return Err(format!(
                        "inner_radius {inner_radius} must be smaller than outer_radius {outer_radius}"
                    ));
                }
                if !(1.0..=89.0).contains(window_half_angle_deg) {
                    return Err(format!(
                        "window_half_angle_deg = {window_half_angle_deg} is out of range; allowed 1..=89"
                    ));
                }
                tess("rings", *rings, 4)?;
                tess("segments", *segments, 8)
            }
            MeshSpec::Cyclorama { width, depth, height, bend_radius, segments } => {
                pos("width", *width)?;
                pos("depth", *depth)?;
                pos("height", *height)?;
                pos("bend_radius", *bend_radius)?;
                if *bend_radius > depth.min(*height) {
                    return Err(format!("bend_radius {bend_radius} must not exceed depth and height"));
                }
                tess("segments", *segments, 4)
            }
            MeshSpec::Spikes { radius, count, bump_radius, bump_height, rings, segments } => {
                pos("radius", *radius)?;
                pos("bump_radius", *bump_radius)?;
                pos("bump_height", *bump_height)?;
                if !(1..=2000).contains(count) {
                    return Err(format!("count = {count} is out of range; allowed 1..=2000"));
                }
                tess("rings", *rings, 8)?;
                tess("segments", *segments, 8)
            }
            MeshSpec::Medusa { radius, amplitude, k, n: _, m, rings, segments } => {
                pos("radius", *radius)?;
                if !amplitude.is_finite() || !k.is_finite() || !m.is_finite() {
                    return Err("amplitude, k and m must be finite".into());
                }
                tess("rings", *rings, 8)?;
                tess("segments", *segments, 8)
            }
            MeshSpec::Gltf { path, .. } | MeshSpec::GltfPrimitive { path, .. } => {
                if path.is_empty() {
                    Err("path is empty".into())
                } else {
                    Ok(())
                }
            }
        }
    }

    pub fn kind_name(&self) -> &'static str {
        match self {
            MeshSpec::UvSphere { .. } => "uv_sphere",
            MeshSpec::Box { .. } => "box",
            MeshSpec::Plane { .. } => "plane",
            MeshSpec::Lathe { .. } => "lathe",
            MeshSpec::KnobShell { .. } => "knob_shell",
            MeshSpec::Cyclorama { .. } => "cyclorama",
            MeshSpec::Spikes { .. } => "spikes",
            MeshSpec::Medusa { .. } => "medusa",
            MeshSpec::Gltf { .. } => "gltf",
            MeshSpec::GltfPrimitive { .. } => "gltf_primitive",
        }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Environment {
    pub sky: Sky,
    /// Multiplies the environment's radiance for ambient and reflections.
    #[serde(default = "one")]
    pub ambient_intensity: f64,
    /// Whether the environment is drawn behind the scene (otherwise black).
    #[serde(default = "yes")]
    pub background: bool,
    /// Where specular reflections come from: the sky alone, or the scene's reflection probes
    /// (`[[probes]]`) with the sky where no probe reaches.
    #[serde(default)]
    pub reflections: Reflections,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reflections {
    #[default]
    Sky,
    Probe,
}

/// A reflection probe: it captures the scene (without the subject: a dynamic object, which Unity's
/// baked probes of all three pipelines leave out) from `position` into a cubemap, prefiltered for
/// roughness; points inside its box take its reflections, weighed by the engine's rule over
/// `blend_distance` (`plan::probes`; absent: each engine's default, 1 m for the Reflection Probe
/// component of built-in and URP, 0 for HDRP's influence volume; box projection off, 128² faces).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ReflectionProbe {
    pub position: [f64; 3],
    /// The influence (and box-projection) volume, world space, axis-aligned.
    pub box_min: [f64; 3],
    pub box_max: [f64; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend_distance: Option<f64>,
    #[serde(default)]
    pub box_projection: bool,
    /// Texels per cube face (a power of two, 16–512).
    #[serde(default = "default_probe_resolution")]
    pub resolution: u32,
    /// Unity's `ReflectionProbe.nearClipPlane` default.
    #[serde(default = "default_probe_near")]
    pub near: f64,
}

/// Probes a scene may place (the frame uniform holds this many).
pub const MAX_PROBES: usize = 4;

fn default_probe_resolution() -> u32 {
    128
}

fn default_probe_near() -> f64 {
    0.3
}

fn yes() -> bool {
    true
}

/// What an image sky's texels are. `relative` (the default): radiance in the units of built-in
/// and URP, whose skybox feeds the ambient as it is; HDRP takes it × 10⁴ as every light and sky
/// of the tool (`Pipeline::environment_scale`), so ambient keeps its proportion to the direct
/// light. `nits`: physical radiance (cd/m², a calibrated HDRI): HDRP reads the values as they are
/// (its HDRI Sky at exposure 0, multiplier 1), built-in and URP read them ÷ 10⁴, the tool's one
/// ratio between their units and HDRP's.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SkyUnits {
    #[default]
    Relative,
    Nits,
}

impl SkyUnits {
    fn is_relative(&self) -> bool {
        *self == SkyUnits::Relative
    }

    /// The factor from the texels to the tool's radiance (built-in units).
    pub fn scale(self) -> f64 {
        match self {
            SkyUnits::Relative => 1.0,
            SkyUnits::Nits => 1.0 / crate::pipelines::Pipeline::Hdrp.intensity_scale(),
        }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Sky {
    /// One sRGB colour in every direction.
    Constant { color: [f64; 3] },
    /// Unity's trilight ambient: sky above, equator at the horizon, ground below (sRGB).
    Gradient { sky: [f64; 3], equator: [f64; 3], ground: [f64; 3] },
    /// An equirectangular image of linear radiance (OpenEXR or Radiance HDR, 2:1; `path` relative
    /// to the scene's folder), times `intensity`, turned `rotation_deg` about +Y. Texel (u, v) is
    /// the direction of `environment::uv_to_dir` (u = atan2(x, −z)/2π + ½, v = acos(y)/π), looked
    /// up bilinearly; read when the scene is loaded (`input::sky_image`).
    Image {
        path: String,
        #[serde(default = "one")]
        intensity: f64,
        #[serde(default)]
        rotation_deg: f64,
        #[serde(default, skip_serializing_if = "SkyUnits::is_relative")]
        units: SkyUnits,
        /// The file's SHA-256: serialised into keys, so that an edited image changes them.
        #[serde(default, skip_deserializing)]
        digest: String,
        #[serde(skip)]
        image: Option<std::sync::Arc<crate::input::sky_image::SkyImage>>,
    },
    /// A cube map: six square images of linear radiance (`faces`: +X, −X, +Y, −Y, +Z, −Z, each
    /// OpenEXR or Radiance HDR, relative to the scene's folder), read as a `samplerCube` reads
    /// them (`environment::sky`), times `intensity`, turned `rotation_deg` about +Y.
    Cubemap {
        faces: [String; 6],
        #[serde(default = "one")]
        intensity: f64,
        #[serde(default)]
        rotation_deg: f64,
        #[serde(default, skip_serializing_if = "SkyUnits::is_relative")]
        units: SkyUnits,
        /// The six files' SHA-256, joined: serialised into keys.
        #[serde(default, skip_deserializing)]
        digest: String,
        #[serde(skip)]
        images: Option<std::sync::Arc<Vec<crate::input::sky_image::SkyImage>>>,
    },
    /// An analytic approximation of a procedural sky (see `environment::sky`).
    Procedural {
        /// Direction towards the sun.
        sun_direction: [f64; 3],
        #[serde(default = "sun_size")]
        sun_size: f64,
        #[serde(default = "one")]
        atmosphere_thickness: f64,
        #[serde(default = "sky_tint")]
        sky_tint: [f64; 3],
        #[serde(default = "ground_color")]
        ground: [f64; 3],
        #[serde(default = "sky_exposure")]
        exposure: f64,
    },
}

fn sun_size() -> f64 {
    0.04
}
fn sky_tint() -> [f64; 3] {
    [0.5, 0.5, 0.5]
}
fn ground_color() -> [f64; 3] {
    [0.369, 0.349, 0.341]
}
fn sky_exposure() -> f64 {
    1.3
}

pub use crate::input::validate::{MAX_INTENSITY, MAX_UV};

impl Scene {
    /// Load a composition: a built-in name, or a path to a scene TOML (relative to `base_dir`).
    pub fn load(name_or_path: &str, base_dir: Option<&Path>, referenced_from: &str, key: &str) -> Result<Scene, Error> {
        if let Some((_, text)) = BUILTIN_SCENES.iter().find(|(n, _)| *n == name_or_path) {
            let origin = format!("<built-in scene {name_or_path}>");
            let mut scene: Scene = parse_toml(&origin, text)?;
            scene.origin = origin;
            if scene.gltf_scene.is_some() {
                return Err(InputError::at_key(&scene.origin, "gltf_scene", "a built-in scene names no file").into());
            }
            scene.read_sky_image()?;
            scene.read_map_images()?;
            scene.validate()?;
            return Ok(scene);
        }
        if !name_or_path.ends_with(".toml") {
            return Err(unknown_name(referenced_from, key, "composition", name_or_path, &builtin_scene_names()).into());
        }
        let path = match base_dir {
            Some(d) => d.join(name_or_path),
            None => PathBuf::from(name_or_path),
        };
        // A FIFO or a device would block or read without end: said with the key that names it.
        crate::input::source::regular_file(&path).map_err(|e| {
            InputError::at_key(referenced_from, key, format!("composition `{name_or_path}`: {}: {}", e.file, e.message))
        })?;
        if !path.is_file() {
            return Err(InputError::at_key(
                referenced_from,
                key,
                format!(
                    "composition file `{name_or_path}` not found at {} (a path resolves against the referencing \
                     file's folder; built-in compositions: {})",
                    path.display(),
                    builtin_scene_names().join(", ")
                ),
            )
            .into());
        }
        Self::load_file(&path)
    }

    pub fn load_file(path: &Path) -> Result<Scene, Error> {
        let mut scene: Scene = crate::input::source::read_toml(path)?;
        scene.origin = path.display().to_string();
        scene.base_dir = Some(path.parent().map(Path::to_path_buf).unwrap_or_default());
        scene.read_gltf_scene()?;
        scene.split_gltf_subject();
        scene.read_sky_image()?;
        scene.read_map_images()?;
        scene.validate()?;
        Ok(scene)
    }

    /// The glTF file the subject's mesh comes from, resolved against the scene's folder (None: a
    /// procedural subject, or an embedded scene that cannot resolve paths).
    pub fn subject_gltf(&self) -> Option<PathBuf> {
        let subject = self.objects.iter().find(|o| o.role == Role::Subject)?;
        match &subject.mesh {
            MeshSpec::Gltf { path, .. } => Some(self.base_dir.as_ref()?.join(path)),
            _ => None,
        }
    }

    /// Index of the key light (receives the intensity and range axes).
    pub fn key_light(&self) -> Option<usize> {
        self.lights.iter().position(|l| l.key).or_else(|| self.lights.iter().position(|l| l.kind == LightKind::Point))
    }

    pub fn has_shadow_casting_light(&self) -> bool {
        self.lights.iter().any(|l| l.shadows)
    }

    /// Whether a shadow pass can change the image: a light that casts shadows, an object that
    /// casts and one that receives. None, or why not.
    pub fn shadow_pass_needed(&self) -> Result<(), String> {
        if !self.has_shadow_casting_light() {
            return Err("no light casts shadows".into());
        }
        if !self.objects.iter().any(|o| o.cast_shadows) {
            return Err("no object casts shadows".into());
        }
        if !self.objects.iter().any(|o| o.receive_shadows) {
            return Err("no object receives shadows".into());
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), InputError> {
        let c = Checker::new(&self.origin);
        c.name("name", &self.name)?;
        c.positive("camera.fov_y_deg", self.camera.fov_y_deg)?;
        c.range("camera.fov_y_deg", self.camera.fov_y_deg, 1.0, 170.0)?;
        c.positive("camera.near", self.camera.near)?;
        // TOML reads `nan` and `inf`: unchecked, they gave empty images with exit 0.
        c.finite_vector("camera.position", self.camera.position)?;
        c.finite_vector("camera.target", self.camera.target)?;
        c.positive("camera.far", self.camera.far)?;
        if self.camera.far <= self.camera.near {
            return Err(
                c.err("camera.far", format!("far {} must be greater than near {}", self.camera.far, self.camera.near))
            );
        }
        if self.camera.position == self.camera.target {
            return Err(c.err("camera.target", "target equals position: the view direction is undefined"));
        }
        if let Some(gi) = &self.gi {
            super::gi::validate(&c, gi)?;
        }
        if self.lights.iter().filter(|l| l.key).count() > 1 {
            return Err(c.err("lights.key", "at most one light may be the key light"));
        }
        for (i, o) in self.objects.iter().enumerate() {
            let Some(lod) = &o.lod else { continue };
            let k = |f: &str| format!("objects[{i}].lod.{f}");
            if lod.transitions.len() != lod.meshes.len() + 1 {
                return Err(c.err(
                    &k("transitions"),
                    format!(
                        "{} transitions for {} levels (the object's mesh and {} in `meshes`): one per level",
                        lod.transitions.len(),
                        lod.meshes.len() + 1,
                        lod.meshes.len()
                    ),
                ));
            }
            for (j, t) in lod.transitions.iter().enumerate() {
                c.range(&format!("{}[{j}]", k("transitions")), *t, 1e-6, 1.0)?;
                if j > 0 && *t >= lod.transitions[j - 1] {
                    return Err(c.err(
                        &k("transitions"),
                        format!("{:?} must decrease strictly (level 0's first)", lod.transitions),
                    ));
                }
            }
            if let Some(bias) = lod.bias {
                c.range(&k("bias"), bias, 1e-3, 100.0)?;
            }
            c.range(&k("fade_width"), lod.fade_width, 0.0, 1.0)?;
            for (j, m) in lod.meshes.iter().enumerate() {
                m.validate().map_err(|e| c.err(&format!("{}[{j}]", k("meshes")), e))?;
            }
        }
        if self.environment.reflections == Reflections::Probe && self.probes.is_empty() {
            return Err(
                c.err("environment.reflections", "\"probe\" needs at least one [[probes]] entry (or use \"sky\")")
            );
        }
        if self.probes.len() > MAX_PROBES {
            return Err(c.err("probes", format!("{} probes; at most {} are allowed", self.probes.len(), MAX_PROBES)));
        }
        for (i, p) in self.probes.iter().enumerate() {
            let k = |f: &str| format!("probes[{i}].{f}");
            for (key, v) in [("position", p.position), ("box_min", p.box_min), ("box_max", p.box_max)] {
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(c.err(&k(key), format!("{v:?} must be finite")));
                }
            }
            if (0..3).any(|axis| p.box_min[axis] >= p.box_max[axis]) {
                return Err(c.err(
                    &k("box_max"),
                    format!("box_max {:?} must exceed box_min {:?} on every axis", p.box_max, p.box_min),
                ));
            }
            if let Some(blend) = p.blend_distance {
                c.range(&k("blend_distance"), blend, 0.0, 1e4)?;
            }
            c.range(&k("near"), p.near, 1e-3, 100.0)?;
            if !p.resolution.is_power_of_two() || !(16..=512).contains(&p.resolution) {
                return Err(
                    c.err(&k("resolution"), format!("{} is not allowed: a power of two from 16 to 512", p.resolution))
                );
            }
        }
        for (i, l) in self.lights.iter().enumerate() {
            let k = |f: &str| match &l.from_gltf {
                Some(from) => format!("gltf_scene.path: {from}: {f}"),
                None => format!("lights[{i}].{f}"),
            };
            c.finite_vector(&k("position"), l.position)?;
            c.color(&k("color"), l.color)?;
            c.range(&k("intensity"), l.intensity, 0.0, MAX_INTENSITY)?;
            c.positive(&k("range"), l.range)?;
            if l.kind != LightKind::Point {
                c.nonzero_vector(&k("direction"), l.direction)?;
            }
            let gi_keys = super::gi::LightGiKeys {
                mode: l.mode,
                indirect_multiplier: l.indirect_multiplier,
                baked_shadow_radius: l.baked_shadow_radius,
                baked_shadow_angle_deg: l.baked_shadow_angle_deg,
                directional: l.kind == LightKind::Directional,
                area: l.is_area(),
            };
            super::gi::validate_light(&c, i, gi_keys, self.gi.is_some())?;
            let baked = l.mode != super::gi::LightBakeMode::Realtime;
            let of = super::hdrp_light::LightOf { kind: l.kind.name(), baked };
            super::hdrp_light::validate(&c, i, of, &l.hdrp)?;
            if l.is_area() {
                let keys = super::area_light::AreaKeys {
                    disc: l.kind == LightKind::Disc,
                    shadows: l.shadows,
                    size: l.size,
                    radius: l.shape_radius,
                };
                super::area_light::validate(&c, i, keys)?;
            }
            let only = |key: &str, set: bool, kinds: &str| -> Result<(), InputError> {
                if set {
                    Err(c.err(&k(key), format!("only {kinds} lights have this key; this one is {:?}", l.kind)))
                } else {
                    Ok(())
                }
            };
            match l.kind {
                LightKind::Directional => {
                    only("shape_radius", l.shape_radius.is_some(), "point and spot")?;
                    only("reflector", l.reflector.is_some(), "spot")?;
                }
                LightKind::Point => {
                    only("angular_diameter_deg", l.angular_diameter_deg.is_some(), "directional")?;
                    only("reflector", l.reflector.is_some(), "spot")?;
                }
                LightKind::Spot => only("angular_diameter_deg", l.angular_diameter_deg.is_some(), "directional")?,
                LightKind::Rect | LightKind::Disc => {
                    only("angular_diameter_deg", l.angular_diameter_deg.is_some(), "directional")?;
                    only("reflector", l.reflector.is_some(), "spot")?;
                }
            }
            if l.kind != LightKind::Rect {
                only("size", l.size.is_some(), "rect")?;
            }
            c.unit(&k("shadow.strength"), l.shadow.strength)?;
            c.range(&k("shadow.bias"), l.shadow.bias, 0.0, 10.0)?;
            c.range(&k("shadow.normal_bias"), l.shadow.normal_bias, 0.0, 10.0)?;
            if let Some(r) = l.shadow.resolution {
                c.range(&k("shadow.resolution"), r as f64, 16.0, 8192.0)?;
            }
            if let Some(r) = l.shape_radius {
                c.range(&k("shape_radius"), r, 0.0, 100.0)?;
            }
            if let Some(d) = l.angular_diameter_deg {
                c.range(&k("angular_diameter_deg"), d, 0.0, 90.0)?;
            }
            if l.kind == LightKind::Spot {
                c.range(&k("spot_angle_deg"), l.spot_angle_deg, 1.0, 179.0)?;
                if let Some(inner) = l.inner_spot_angle_deg {
                    c.range(&k("inner_spot_angle_deg"), inner, 0.0, l.spot_angle_deg)?;
                }
            }
        }
        if !self.objects.iter().any(|o| o.role == Role::Subject) {
            return Err(c.err("objects", "a scene needs at least one object with role = \"subject\""));
        }
        for (i, o) in self.objects.iter().enumerate() {
            let k = |f: &str| format!("objects[{i}].{f}");
            c.name(&k("name"), &o.name)?;
            c.finite_vector(&k("transform.translate"), o.transform.translate)?;
            c.finite_vector(&k("transform.rotate_deg"), o.transform.rotate_deg)?;
            for s in o.transform.scale {
                if s == 0.0 || !s.is_finite() {
                    return Err(c.err(&k("transform.scale"), format!("scale {s} must be finite and non-zero")));
                }
            }
            match (o.role, &o.material) {
                (Role::Fixed, None) => {
                    return Err(c.err(&k("material"), "a fixed object needs its own material (base_color_linear, ...)"))
                }
                (Role::Subject, Some(_)) => {
                    return Err(c.err(&k("material"), "a subject receives the swept material; remove its material"))
                }
                (_, Some(m)) => {
                    c.color(&k("material.base_color_linear"), m.base_color_linear)?;
                    c.unit(&k("material.metallic"), m.metallic)?;
                    c.unit(&k("material.smoothness"), m.smoothness)?;
                    c.unit(&k("material.alpha"), m.alpha)?;
                    use crate::pipelines::surface::SurfaceType;
                    if !matches!(m.surface, SurfaceType::Opaque | SurfaceType::Transparent) {
                        return Err(c.err(
                            &k("material.surface"),
                            format!(
                                "`{}` is not a fixed object's surface; allowed: opaque, transparent (the surface \
                                 types every pipeline's lit shaders share without a clip map)",
                                m.surface.name()
                            ),
                        ));
                    }
                    if m.is_transparent() && o.cast_shadows {
                        return Err(c.err(
                            &k("cast_shadows"),
                            "a transparent fixed object casts no shadow here: set cast_shadows = false (as a \
                             window's renderer has it; built-in casts a transparent surface dithered by its alpha, \
                             URP and HDRP opaque, which this tool does not emulate)",
                        ));
                    }
                    if let Some(ch) = &m.checker {
                        c.color(&k("material.checker.color_linear"), ch.color_linear)?;
                        c.positive(&k("material.checker.cell"), ch.cell)?;
                    }
                    // Emitted radiance is ≥ 0 and finite; a NaN or negative one gave NaN or
                    // negative images with exit 0.
                    for (j, e) in m.emission_linear.iter().enumerate() {
                        c.range(&k(&format!("material.emission_linear[{j}]")), *e, 0.0, MAX_INTENSITY)?;
                    }
                    for (key, v) in [("map_tiling", m.map_tiling), ("map_offset", m.map_offset)] {
                        for (j, x) in v.iter().enumerate() {
                            c.range(&k(&format!("material.{key}[{j}]")), *x, -MAX_UV, MAX_UV)?;
                        }
                    }
                }
                _ => {}
            }
            o.mesh.validate().map_err(|m| c.err(&k("mesh"), m))?;
        }
        if let Some(a) = self.light_angle_deg {
            c.range("light_angle_deg", a, 0.0, 180.0)?;
            if self.key_light().is_none() {
                return Err(c.err("light_angle_deg", "the scene has no key light to turn"));
            }
        }
        let x = &self.hdrp.exposure;
        c.range("hdrp.exposure.limit_min", x.limit_min, -20.0, 30.0)?;
        c.range("hdrp.exposure.limit_max", x.limit_max, x.limit_min, 30.0)?;
        c.range("hdrp.exposure.compensation", x.compensation, -20.0, 20.0)?;
        c.range("hdrp.exposure.fixed_ev", x.fixed_ev, -20.0, 30.0)?;
        c.range("hdrp.exposure.histogram_percent[0]", x.histogram_percent[0], 0.0, 100.0)?;
        c.range("hdrp.exposure.histogram_percent[1]", x.histogram_percent[1], x.histogram_percent[0], 100.0)?;
        let e = &self.environment;
        c.range("environment.ambient_intensity", e.ambient_intensity, 0.0, MAX_INTENSITY)?;
        match &e.sky {
            Sky::Constant { color } => c.color("environment.sky.color", *color)?,
            Sky::Gradient { sky, equator, ground } => {
                c.color("environment.sky.sky", *sky)?;
                c.color("environment.sky.equator", *equator)?;
                c.color("environment.sky.ground", *ground)?;
            }
            Sky::Image { path, intensity, rotation_deg, image, .. } => {
                c.range("environment.sky.intensity", *intensity, 0.0, MAX_INTENSITY)?;
                c.finite_vector("environment.sky.rotation_deg", [*rotation_deg; 3])?;
                if image.is_none() {
                    return Err(c.err("environment.sky.path", format!("`{path}` was not read")));
                }
            }
            Sky::Cubemap { intensity, rotation_deg, images, .. } => {
                c.range("environment.sky.intensity", *intensity, 0.0, MAX_INTENSITY)?;
                c.finite_vector("environment.sky.rotation_deg", [*rotation_deg; 3])?;
                if images.is_none() {
                    return Err(c.err("environment.sky.faces", "the faces were not read"));
                }
            }
            Sky::Procedural { sun_direction, sun_size, atmosphere_thickness, sky_tint, ground, exposure } => {
                c.nonzero_vector("environment.sky.sun_direction", *sun_direction)?;
                c.range("environment.sky.sun_size", *sun_size, 0.0, 1.0)?;
                c.range("environment.sky.atmosphere_thickness", *atmosphere_thickness, 0.0, 5.0)?;
                c.color("environment.sky.sky_tint", *sky_tint)?;
                c.color("environment.sky.ground", *ground)?;
                c.range("environment.sky.exposure", *exposure, 0.0, 8.0)?;
            }
        }
        Ok(())
    }
}
