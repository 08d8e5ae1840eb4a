//! The approximation study's exact alternatives: which real-time approximations a frame replaces
//! by the terms they approximate (shaders/pass/exact.wgsl, in place of approximations.wgsl).
//! Forward paths only; each object's pipeline then reads the rays' group (render::truth).

/// The approximations a frame computes exactly instead; all false: the pipeline as it ships.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct ExactAlternatives {
    /// Order-2 SH ambient → the exact irradiance E(n)/π (environment::irradiance).
    pub ambient: bool,
    /// SH ambient and the split-sum probe → the environment integrated over the model's whole
    /// BRDF (`EXACT_ENVIRONMENT_SAMPLES` MIS pairs per pixel, unshadowed).
    pub environment: bool,
    /// Shadow maps → every light's visibility by a shadow ray through the BVH.
    pub visibility: bool,
}

impl ExactAlternatives {
    pub fn any(&self) -> bool {
        self.ambient || self.environment || self.visibility
    }

    /// The pipeline-overridable constants of exact.wgsl.
    pub fn constants(&self) -> [(&'static str, f64); 3] {
        [
            ("EXACT_AMBIENT", self.ambient as u32 as f64),
            ("EXACT_ENVIRONMENT", self.environment as u32 as f64),
            ("TRACED_VISIBILITY", self.visibility as u32 as f64),
        ]
    }
}
