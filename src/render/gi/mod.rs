//! Baked global illumination (plan::gi): what the bake of a cell's scene holds — light probes
//! for the dynamic objects and, for the static ones, lightmaps — gathered by the path tracer
//! (render::truth::bake) as Unity's Progressive Lightmapper gathers them, and how each object
//! reads it in place of the sky's ambient SH.

pub mod probes;

use glam::DVec3;

use probes::Probe;

/// A scene's bake for one set of inputs (`key`), shared by every cell whose bake reads the same.
#[derive(Debug, Clone)]
pub struct BakedLighting {
    /// What the bake read, hashed: cells with the same key share it.
    pub key: u64,
    /// The grid's probes (None: the scene has no probe grid).
    pub probes: Option<Vec<Probe>>,
    /// Samples per probe and texel, and the bounces of their paths.
    pub samples: u32,
    pub bounces: u32,
    /// Wall time of the bake, s (a one-off cost, not per frame).
    pub seconds: f64,
}

/// Where an object's ambient (diffuse indirect) light comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum AmbientSource {
    /// The sky's SH (nothing baked reaches the object).
    Sky,
    /// Its interpolated light probe.
    Probe(Box<Probe>),
}

impl AmbientSource {
    /// The value the shaders read in `Object.lod.z` (forward.wgsl `object_ambient`).
    pub fn shader_value(&self) -> f32 {
        match self {
            AmbientSource::Sky => 0.0,
            AmbientSource::Probe(_) => 1.0,
        }
    }
}

impl BakedLighting {
    /// The ambient source of a dynamic object whose bounds centre is `centre`.
    pub fn dynamic_ambient(&self, grid: Option<&crate::spec::gi::ProbeGrid>, centre: DVec3) -> AmbientSource {
        match (&self.probes, grid) {
            (Some(probes), Some(grid)) => AmbientSource::Probe(Box::new(probes::interpolate(grid, probes, centre))),
            _ => AmbientSource::Sky,
        }
    }
}
