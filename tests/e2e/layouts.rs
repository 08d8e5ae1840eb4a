//! Every public `#[repr(C)]` GPU mirror against its WGSL struct, member by member, as naga lays
//! the WGSL out (`gpu::layout`); the private mirrors (bloom, prefilter, truth, metric params) are
//! checked by unit tests beside them.

use shadematrix::gpu::layout::check_mirror;
use shadematrix::mirror_layout;
use shadematrix::pipelines::Pipeline;
use shadematrix::render::uniforms::*;
use shadematrix::shading::wgsl::{compose, with_math, PassKind};

fn lambert() -> &'static shadematrix::shading::ShaderModel {
    crate::common::find_model(Pipeline::Urp, "lambert").unwrap()
}

#[test]
fn uniform_mirrors_match_their_wgsl_structs() {
    let forward = compose(PassKind::Forward, Some(lambert()));
    let exact = compose(PassKind::ForwardExact, Some(lambert()));
    let probe = compose(PassKind::BrdfProbe, Some(lambert()));
    let ssao = with_math(include_str!("../../shaders/pass/ssao.wgsl"));
    use shadematrix::render::passes::ssao::SsaoFrame;
    use shadematrix::render::probe::ProbeInput;
    use shadematrix::render::truth::bvh::{GpuBvhNode, TruthVertex};
    type Mirror<'a> = (&'a str, &'a str, (usize, Vec<(&'a str, usize)>));
    let mirrors: Vec<Mirror> = vec![
        (&forward, "Light", mirror_layout!(GpuLight, [position, direction, color, params, shadow, shadow_bias])),
        (&forward, "ShadowLayer", mirror_layout!(ShadowLayer, [view_proj, params, sphere])),
        (
            &forward,
            "Material",
            mirror_layout!(GpuMaterial, [base_color, params, checker_color, specular, model0, model1, emission]),
        ),
        (&forward, "ReflectionProbe", mirror_layout!(GpuReflectionProbe, [position, box_min, box_max])),
        (
            &forward,
            "Frame",
            mirror_layout!(
                FrameUniforms,
                [view_proj, inv_view_proj, camera_pos, counts, sh, env, subject, fixed, reflection, probes]
            ),
        ),
        (&forward, "Object", mirror_layout!(ObjectUniforms, [model, normal_matrix, material, flags, light_sh, lod])),
        (&exact, "BvhNode", mirror_layout!(GpuBvhNode, [min, max])),
        (&exact, "RayVertex", mirror_layout!(TruthVertex, [position, normal, tangent])),
        (
            &probe,
            "ProbeInput",
            mirror_layout!(
                ProbeInput,
                [n, v, l, base_color, params, gi_diffuse, gi_specular, specular, model0, model1]
            ),
        ),
        (
            &ssao,
            "SsaoFrame",
            mirror_layout!(SsaoFrame, [buffer_size, params0, params1, depth_to_view, z_buffer, view_x, view_y, view_z]),
        ),
    ];
    let bad: Vec<String> = mirrors
        .iter()
        .filter_map(|(source, name, (size, fields))| check_mirror(source, name, *size, fields).err())
        .collect();
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
