//! The shading library's must-shows: the audit passes for every built-in model, known physics
//! holds, and the three pipelines' lit shaders differ exactly where the spec says they do.

use crate::common::find_model;
use glam::DVec3;
use shadematrix::audit::{audit_all, directional_albedo};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::Pipeline;
use shadematrix::render::probe::{evaluate, BrdfProbe, ProbeInput};
use shadematrix::shading::registry::Sliders;
use shadematrix::shading::twin::Surface;

#[test]
fn audit_of_every_builtin_model_has_no_failure() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let audits = audit_all(&gpu, crate::common::models(), None).unwrap();
    assert!(audits.len() >= 40, "every (pipeline, model): {}", audits.len());
    for a in &audits {
        assert!(a.failures.is_empty(), "{}: {:?}", a.key, a.failures);
        // No NaN or Inf anywhere in the audit set, extreme domain included, on either side.
        assert_eq!((a.gpu.nan, a.gpu.inf), (0, 0), "{}", a.key);
        let cpu = a.cpu.expect("built-in models have twins");
        assert_eq!((cpu.nan, cpu.inf), (0, 0), "{}", a.key);
        let well = a.parity_well.unwrap();
        assert!(well.max_rel <= a.parity_tolerance, "{}: parity {:e}", a.key, well.max_rel);
        if a.expected.reciprocal {
            assert!(
                a.reciprocity.unwrap() <= 1e-3,
                "{}: claims reciprocity, measured {:e}",
                a.key,
                a.reciprocity.unwrap()
            );
        }
    }
    // The expectations can fail: unnormalised Blinn-Phong is flagged as gaining energy.
    let bp = audits.iter().find(|a| a.key == "urp/blinn_phong").unwrap();
    assert!(bp.energy.as_ref().unwrap().max_albedo > 1.2 && !bp.findings.is_empty());
}

#[test]
fn lambert_directional_albedo_is_its_albedo_in_every_pipeline() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let mut probe = BrdfProbe::new(&gpu);
    for p in Pipeline::ALL {
        let model = find_model(p, "lambert").unwrap();
        for rho in [0.25, 0.5, 0.9] {
            for deg in [0.0f64, 45.0, 80.0] {
                let v = DVec3::new(deg.to_radians().sin(), deg.to_radians().cos(), 0.0);
                let sliders = Sliders { base_color_linear: [rho; 3], metallic: 0.0, smoothness: 0.5 };
                let (a, samples, _) = directional_albedo(&gpu, &mut probe, model, p, &sliders, v).unwrap();
                assert!(samples >= 4096);
                assert!((a - rho).abs() < 1e-3, "{}: albedo {a} for ρ = {rho} at {deg}°", p.name());
            }
        }
    }
}

#[test]
fn hdrp_energy_compensation_brings_a_rough_white_metal_closer_to_one() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let model = find_model(Pipeline::Hdrp, "lit").unwrap();
    let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 1.0, smoothness: 0.0 };
    let v = DVec3::new(0.5, 0.75f64.sqrt(), 0.0);
    let with = directional_albedo(&gpu, &mut BrdfProbe::new(&gpu), model, Pipeline::Hdrp, &sliders, v).unwrap().0;
    // Off: the same model with its energy_compensation parameter at 0, through the f64 twin.
    let twin = model.twin.unwrap();
    let mut s = model.surface(Pipeline::Hdrp, &sliders);
    s.params[0] = 0.0;
    let (dirs, weights) = shadematrix::audit::mis_directions(v, 1.0, 16384);
    let without: f64 =
        dirs.iter().zip(&weights).map(|(l, w)| twin.direct(Pipeline::Hdrp, &s, DVec3::Y, v, *l).x * w).sum::<f64>()
            / 16384.0;
    eprintln!("rough white metal at 30°: albedo {with} with energy compensation, {without} without");
    assert!(without < 0.9, "single scattering loses energy on a rough metal: {without}");
    assert!((with - 1.0).abs() < (without - 1.0).abs(), "with compensation {with}, without {without}");
    assert!((with - 1.0).abs() < 0.02, "compensated albedo {with}");
}

fn gpu_direct(gpu: &GpuContext, p: Pipeline, shader: &str, s: &Surface, v: DVec3, l: DVec3) -> DVec3 {
    let model = find_model(p, shader).unwrap();
    let out = evaluate(gpu, p, model, &[ProbeInput::new(s, DVec3::Y, v, l, DVec3::ZERO, DVec3::ZERO)]).unwrap();
    DVec3::new(out[0].0[0] as f64, out[0].0[1] as f64, out[0].0[2] as f64)
}

/// Diffuse part of a model's output: the base colour's contribution (F0 of a dielectric does not
/// depend on it), measured on the GPU as out(albedo) − out(black).
fn diffuse(gpu: &GpuContext, p: Pipeline, shader: &str, albedo: f64, smoothness: f64, v: DVec3, l: DVec3) -> f64 {
    let s = |a: f64| Surface::basic(DVec3::splat(a), 0.0, smoothness);
    (gpu_direct(gpu, p, shader, &s(albedo), v, l) - gpu_direct(gpu, p, shader, &s(0.0), v, l)).x
}

#[test]
fn standard_lit_and_hdrp_lit_differ_where_the_spec_says() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let up = DVec3::Y;
    // At normal incidence every diffuse shaping term is 1: what is left is the convention.
    let d_std = diffuse(&gpu, Pipeline::Builtin, "standard", 0.5, 0.0, up, up);
    let d_urp = diffuse(&gpu, Pipeline::Urp, "lit", 0.5, 0.0, up, up);
    let d_hdrp = diffuse(&gpu, Pipeline::Hdrp, "lit", 0.5, 0.0, up, up);
    // Built-in and URP: albedo·(1 − 0.04·…) = 0.96·albedo, no 1/π (§1, §2).
    assert!((d_std - 0.96 * 0.5).abs() < 1e-6, "standard {d_std}");
    assert!((d_urp - 0.96 * 0.5).abs() < 1e-6, "urp lit {d_urp}");
    // HDRP: no 0.96 factor, 1/π, and the Disney renormalisation 1/1.03571 (§3).
    let expected_hdrp = 0.5 / std::f64::consts::PI / 1.03571;
    assert!((d_hdrp - expected_hdrp).abs() < 1e-6, "hdrp lit {d_hdrp} vs {expected_hdrp}");

    // Away from normal incidence built-in's Disney diffuse departs from URP's Lambert by exactly
    // (1 + (fd90 − 1)(1 − nl)⁵)(1 + (fd90 − 1)(1 − nv)⁵), fd90 = 0.5 + 2·lh²·pr.
    let v = DVec3::new(0.8, 0.6, 0.0);
    let l = DVec3::new(-0.6, 0.8, 0.0);
    let (d_std, d_urp) = (
        diffuse(&gpu, Pipeline::Builtin, "standard", 0.5, 0.2, v, l),
        diffuse(&gpu, Pipeline::Urp, "lit", 0.5, 0.2, v, l),
    );
    let (nl, nv, lh, pr) = (0.8f64, 0.6f64, (l.dot((l + v).normalize())), 0.8f64);
    let fd90 = 0.5 + 2.0 * lh * lh * pr;
    let disney = (1.0 + (fd90 - 1.0) * (1.0 - nl).powi(5)) * (1.0 + (fd90 - 1.0) * (1.0 - nv).powi(5));
    assert!((d_std / d_urp - disney).abs() < 1e-5, "ratio {} vs Disney factor {disney}", d_std / d_urp);

    // URP Lit's specular is numerically the built-in BRDF2 linear branch where URP's clamps are idle.
    for smoothness in [0.2, 0.5, 0.7] {
        let s = Surface::basic(DVec3::new(0.9, 0.6, 0.3), 1.0, smoothness);
        let (a, b) = (
            gpu_direct(&gpu, Pipeline::Urp, "lit", &s, v, l),
            gpu_direct(&gpu, Pipeline::Builtin, "standard_brdf2", &s, v, l),
        );
        assert!(((a - b).abs() / b).max_element() < 1e-5, "s {smoothness}: urp lit {a} vs brdf2 {b}");
    }
    // And URP clamps α ≥ 2⁻⁷ where BRDF2 does not: at smoothness 1, in the mirror direction, BRDF2's
    // α² = 0 numerator makes the lobe vanish (a delta no point light can hit), while URP keeps a
    // finite peak α²/(d²·max(0.1, LH²)·(4α + 2)) with α = 2⁻⁷, α² = 2⁻¹⁴, d = α² + 1e-5 at NH = 1
    // and LH = NL = 0.6 (H = N in the mirror direction), times NL.
    let s = Surface::basic(DVec3::ONE, 1.0, 1.0);
    let m = DVec3::new(-0.8, 0.6, 0.0);
    let (a, b) = (
        gpu_direct(&gpu, Pipeline::Urp, "lit", &s, v, m),
        gpu_direct(&gpu, Pipeline::Builtin, "standard_brdf2", &s, v, m),
    );
    assert_eq!(b, DVec3::ZERO, "BRDF2 unclamped at α = 0");
    let (r, r2) = (0.0078125f64, 6.103515625e-5f64);
    let d = r2 + 0.00001;
    let peak = r2 / (d * d * (m.y * m.y).max(0.1) * (4.0 * r + 2.0)) * m.y;
    assert!((a.x - peak).abs() / peak < 1e-3, "URP clamped peak {a} vs {peak}");
}

#[test]
fn brdf_command_reports_cpu_and_gpu() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let args = [
        "brdf",
        "--pipeline",
        "hdrp",
        "--shader",
        "lit",
        "--param",
        "albedo=0.8,0.5,0.2",
        "--param",
        "metallic=0.5",
        "--param",
        "smoothness=0.6",
        "--n",
        "0,1,0",
        "--l",
        "0.3,0.9,0.1",
        "--v",
        "-0.4,0.8,0.2",
        "--gpu",
        "--json",
    ];
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &args, &[]);
    assert_eq!(rc, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let radiance: Vec<f64> = v["radiance"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let brdf: Vec<f64> = v["brdf"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let nl = DVec3::new(0.3, 0.9, 0.1).normalize().y;
    assert!(radiance[0] > 0.0 && (brdf[0] - radiance[0] / nl).abs() < 1e-12);
    for d in v["gpu"]["rel_diff"].as_array().unwrap() {
        assert!(d.as_f64().unwrap() < 1e-4, "{stdout}");
    }
    // Unknown parameter: exit 2 with the nearest.
    let (rc, _, stderr) = crate::common::shadematrix(
        tmp.path(),
        &[
            "brdf",
            "--pipeline",
            "hdrp",
            "--shader",
            "lit",
            "--param",
            "energy_compensatio=0",
            "--n",
            "0,1,0",
            "--l",
            "0,1,0",
            "--v",
            "0,1,0",
        ],
        &[],
    );
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("did you mean `energy_compensation`?"), "{stderr}");
    let (rc, _, stderr) = crate::common::shadematrix(
        tmp.path(),
        &["brdf", "--pipeline", "urp", "--shader", "standard", "--n", "0,1,0", "--l", "0,1,0", "--v", "0,1,0"],
        &[],
    );
    assert_eq!(rc, 2);
    assert!(stderr.contains("not a shader of urp"), "{stderr}");
}
