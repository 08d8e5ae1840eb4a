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
    let _timer = crate::common::timed!();
    let forward = compose(PassKind::Forward, Some(lambert()));
    let exact = compose(PassKind::ForwardExact, Some(lambert()));
    let probe = compose(PassKind::BrdfProbe, Some(lambert()));
    let ssao = with_math(include_str!("../../shaders/pass/ssao.wgsl"));
    let urp_ssao = with_math(include_str!("../../shaders/pass/urp_ssao.wgsl"));
    let subsurface = with_math(include_str!("../../shaders/pass/subsurface.wgsl"));
    use shadematrix::render::passes::ssao::SsaoFrame;
    use shadematrix::render::passes::subsurface::SubsurfaceFrame;
    use shadematrix::render::passes::urp_ssao::UrpSsaoFrame;
    use shadematrix::render::probe::ProbeInput;
    use shadematrix::render::truth::bvh::{GpuBvhNode, TruthVertex};
    type Mirror<'a> = (&'a str, &'a str, (usize, Vec<(&'a str, usize)>));
    let mirrors: Vec<Mirror> = vec![
        (
            &forward,
            "Light",
            mirror_layout!(
                GpuLight,
                [position, direction, color, params, shadow, shadow_bias, shape, features, shadow_tint]
            ),
        ),
        (&forward, "ShadowLayer", mirror_layout!(ShadowLayer, [view_proj, params, sphere, pcss])),
        (
            &forward,
            "Material",
            mirror_layout!(
                GpuMaterial,
                [base_color, params, checker_color, specular, model0, model1, model2, emission]
            ),
        ),
        (&forward, "ReflectionProbe", mirror_layout!(GpuReflectionProbe, [position, box_min, box_max])),
        (
            &forward,
            "Frame",
            mirror_layout!(
                FrameUniforms,
                [view_proj, inv_view_proj, camera_pos, counts, sh, env, subject, fixed, reflection, probes, screen]
            ),
        ),
        (
            &forward,
            "Object",
            mirror_layout!(
                ObjectUniforms,
                [model, normal_matrix, material, flags, light_sh, lod, bake, occlusion, reflection_probe, shadow_color]
            ),
        ),
        (&exact, "BvhNode", mirror_layout!(GpuBvhNode, [min, max])),
        (&exact, "RayVertex", mirror_layout!(TruthVertex, [position, normal, tangent])),
        (
            &probe,
            "ProbeInput",
            mirror_layout!(
                ProbeInput,
                [n, v, l, base_color, params, gi_diffuse, gi_specular, specular, model0, model1, model2, tangent]
            ),
        ),
        (
            &ssao,
            "SsaoFrame",
            mirror_layout!(SsaoFrame, [buffer_size, params0, params1, depth_to_view, z_buffer, view_x, view_y, view_z]),
        ),
        (
            &urp_ssao,
            "UrpSsaoFrame",
            mirror_layout!(
                UrpSsaoFrame,
                [source_size, params, top_left, x_extent, y_extent, camera, view_proj0, view_proj1, view_z]
            ),
        ),
        (&subsurface, "SubsurfaceFrame", mirror_layout!(SubsurfaceFrame, [dims, camera, shape, kernel])),
    ];
    let bad: Vec<String> = mirrors
        .iter()
        .filter_map(|(source, name, (size, fields))| check_mirror(source, name, *size, fields).err())
        .collect();
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Terms (functions) of a model's WGSL file and of the shared BRDF file that no f64 twin defines
/// under the same name. `twins` is the twins' Rust source.
fn terms_without_twin(composed: &str, own: &[&str], twins: &str) -> Result<(Vec<String>, Vec<String>), String> {
    let module = naga::front::wgsl::parse_str(composed).map_err(|e| format!("WGSL does not parse: {}", e.message()))?;
    // The twin of the FGD table fetch is a method (shading::fgd::FgdTable::lookup, named in its comment).
    let aliases = [("fgd_sample", "fn lookup(")];
    let (mut missing, mut checked) = (Vec::new(), Vec::new());
    for (_, f) in module.functions.iter() {
        let Some(name) = f.name.as_deref() else { continue };
        // model_direct / model_indirect are the twins' SurfaceTwin::direct / indirect.
        if name.starts_with("model_") || !own.iter().any(|text| text.contains(&format!("fn {name}("))) {
            continue;
        }
        checked.push(name.to_string());
        let twin = aliases.iter().find(|(w, _)| *w == name).map_or(format!("fn {name}("), |(_, r)| r.to_string());
        if !twins.contains(&twin) {
            missing.push(name.to_string());
        }
    }
    Ok((missing, checked))
}

#[test]
fn every_wgsl_term_has_its_f64_twin_of_the_same_name() {
    let _timer = crate::common::timed!();
    let repo = crate::common::repo();
    let mut twins = String::new();
    for dir in ["src/shading/twin", "src/shading"] {
        for entry in std::fs::read_dir(repo.join(dir)).unwrap().filter_map(|e| e.ok()) {
            if entry.path().extension().is_some_and(|x| x == "rs") {
                twins.push_str(&std::fs::read_to_string(entry.path()).unwrap());
            }
        }
    }
    let shared = std::fs::read_to_string(repo.join("shaders/common/brdf.wgsl")).unwrap();
    let (mut missing, mut checked) = (std::collections::BTreeSet::new(), std::collections::BTreeSet::new());
    for model in crate::common::models().models().iter().filter(|m| m.source_path.starts_with("shaders/brdf/")) {
        let composed = compose(PassKind::Forward, Some(model));
        let (m, n) = terms_without_twin(&composed, &[&model.wgsl, &shared], &twins)
            .unwrap_or_else(|e| panic!("{}: {e}", model.name));
        missing.extend(m.into_iter().map(|t| format!("{t} ({})", model.source_path)));
        checked.extend(n);
    }
    eprintln!("{} distinct model terms checked against their twins", checked.len());
    assert!(missing.is_empty(), "WGSL terms without an f64 twin of that name: {missing:?}");
    assert!(checked.len() > 40, "only {} terms found: the check reads too few", checked.len());
    // The check can fail: a term its twin lacks.
    let fake =
        format!("{}\nfn d_made_up(x: f32) -> f32 {{ return x; }}\n", compose(PassKind::Forward, Some(lambert())));
    let (m, _) = terms_without_twin(&fake, &["fn d_made_up("], &twins).unwrap();
    assert_eq!(m, vec!["d_made_up".to_string()]);
}
