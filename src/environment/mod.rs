//! The environment: sky radiance, its SH projection for ambient diffuse, and the prefiltered
//! probe for specular reflections. Computed on the CPU, once per analytic sky per process.

pub mod filtered;
pub mod irradiance;
pub mod prefilter;
pub mod sh;
pub mod sky;
pub mod stylized_sky;

use glam::DVec3;

use crate::declarations::scene::{Environment, Sky};

/// Everything the GPU needs about an environment (unscaled: pipelines scale radiance).
#[derive(Debug, Clone)]
pub struct EnvironmentMaps {
    /// Cosine-convolved SH coefficients: E(n)/π = Σ sh[i]·Y_i(n), linear RGB.
    pub sh: [[f64; 3]; 9],
    pub probe: prefilter::Probe,
    /// Multiplies all environment radiance (the scene's ambient intensity).
    pub intensity: f64,
}

impl EnvironmentMaps {
    pub fn build(env: &Environment) -> EnvironmentMaps {
        let radiance = |d: DVec3| sky::radiance(&env.sky, d);
        let (sh, probe) = match &env.sky {
            // A constant sky needs no prefiltering: every level is the same colour; its SH is exact.
            Sky::Constant { .. } => (sh::constant(radiance(DVec3::Y)), prefilter::Probe::constant(radiance(DVec3::Y))),
            Sky::Gradient { .. } | Sky::Procedural { .. } => {
                // An analytic sky is all in its parameters, so their serialisation keys it.
                let key = serde_json::to_string(&env.sky).expect("a sky serialises");
                let built = analytic_skies().lock().unwrap_or_else(|e| e.into_inner()).get(&key).cloned();
                let built = built.unwrap_or_else(|| {
                    let built = std::sync::Arc::new(Self::prefilter(&radiance));
                    let mut skies = analytic_skies().lock().unwrap_or_else(|e| e.into_inner());
                    if skies.len() >= ANALYTIC_SKIES_KEPT {
                        skies.clear();
                    }
                    skies.insert(key, built.clone());
                    built
                });
                (built.0, built.1.clone())
            }
            Sky::Image { .. } | Sky::Cubemap { .. } => Self::prefilter(&radiance),
        };
        EnvironmentMaps { sh, probe, intensity: env.ambient_intensity }
    }

    /// The SH projection and prefiltered probe of a sky's radiance: the costliest CPU step of
    /// preparing a scene.
    fn prefilter(radiance: &(dyn Fn(DVec3) -> DVec3 + Sync)) -> ([[f64; 3]; 9], prefilter::Probe) {
        let source =
            prefilter::EquirectImage::sample(radiance, prefilter::SOURCE_WIDTH, prefilter::SOURCE_WIDTH / 2, 4);
        (sh::project_image(&source), prefilter::Probe::from_source(&source))
    }

    /// f64 twin of the shader's `ambient_diffuse` (before the pipeline's radiance scale).
    pub fn ambient_diffuse(&self, n: DVec3) -> DVec3 {
        sh::eval(&self.sh, n).max(DVec3::ZERO) * self.intensity
    }
}

/// How many analytic skies' maps a process keeps: a run prepares each composition's sky once,
/// but tests and the viewer's studies prepare a few skies over and over.
const ANALYTIC_SKIES_KEPT: usize = 16;

type SkyMaps = std::sync::Arc<([[f64; 3]; 9], prefilter::Probe)>;

/// The maps of the analytic skies built so far in this process, by their serialised parameters.
fn analytic_skies() -> &'static std::sync::Mutex<std::collections::HashMap<String, SkyMaps>> {
    static SKIES: std::sync::OnceLock<std::sync::Mutex<std::collections::HashMap<String, SkyMaps>>> =
        std::sync::OnceLock::new();
    SKIES.get_or_init(Default::default)
}

/// Equirectangular mapping (u: azimuth from −Z towards +X, v: polar angle from +Y), as in scene.wgsl.
pub fn dir_to_uv(d: DVec3) -> [f64; 2] {
    [d.x.atan2(-d.z) / std::f64::consts::TAU + 0.5, d.y.clamp(-1.0, 1.0).acos() / std::f64::consts::PI]
}

pub fn uv_to_dir(u: f64, v: f64) -> DVec3 {
    let phi = (u - 0.5) * std::f64::consts::TAU;
    let theta = v * std::f64::consts::PI;
    DVec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_mapping_round_trips() {
        for d in [DVec3::new(0.3, 0.5, -0.8), DVec3::new(-0.9, -0.1, 0.2), DVec3::new(0.0, 0.2, 1.0)] {
            let d = d.normalize();
            let [u, v] = dir_to_uv(d);
            assert!((uv_to_dir(u, v) - d).length() < 1e-12);
        }
    }
}
