//! The guards of each built-in model's stiff terms (spec §6): the WGSL function that bounds them and
//! what it clamps, as the conditioning table and the stability table name them.

use crate::pipelines::Pipeline;

/// The guard of each built-in model's stiff terms (its WGSL function and what it clamps).
pub fn stiff_terms(name: &str, p: Pipeline) -> &'static str {
    let base = name.trim_end_matches("_vertex");
    match base {
        "lit" if p == Pipeline::Hdrp => {
            "dv_smith_joint_ggx (max(…, REAL_MIN)), clamp_n_dot_v (NV ≥ 1e-4), light_min_roughness (per light)"
        }
        "standard" => "roughness_clamped (α ≥ 0.002); v_smith_joint_approx (+1e-5)",
        "standard_brdf2" => "spec_brdf2 (d = NH²(α² − 1) + 1.00001, max(0.1, LH²))",
        "standard_brdf3" => "spec_brdf3 (n ≥ 1e-4, LUT range cap)",
        "lit" => "urp_brdf_data (α ≥ 2⁻⁷, α² ≥ 2⁻¹⁴), spec_urp (+1.00001, max(0.1, LH²))",
        "simple_lit" | "phong" | "blinn_phong" => "shininess_from_smoothness (n = 2..2048)",
        "cook_torrance" => "d_beckmann (NH² ≥ ε, m ≥ 1e-3), g_cook_torrance (VH ≥ ε)",
        "cook_torrance_1982" => "d_beckmann_unnormalised (NH² ≥ ε, m ≥ 1e-3), g_cook_torrance (VH ≥ ε)",
        "torrance_sparrow" | "torrance_sparrow_corrected" => "ts_direct (d_ggx, v_smith_schlick: no floor on α)",
        "srp_lit" => "specular_strength (d = NH²(r² − 1) + 1.00001, max(0.1, LH²); no floor on r, as the tutorial)",
        "oren_nayar" => "model_direct: tan β over max(cos β, 1e-4)",
        "oren_nayar_057" => "model_direct: max(max(NL, NV), 1e-4)",
        _ => "none needed: the model reads no roughness",
    }
}
