//! Standard's and URP Lit's secondary maps (registry DETAIL, materials::detail): blended in where
//! the detail mask lets them, each as its engine does, in the frame and in both tracers
//! (truth.wgsl against the CPU's f64 twin).

use crate::common::{cell_params, fixture, same_brdf_truth as truth, subject_mean};
use shadematrix::declarations::matrix::TruthBackend;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::{PreparedScene, Renderer};
use shadematrix::shading::registry::Sliders;

#[test]
fn secondary_maps_blend_in_under_the_mask_and_both_tracers_follow_them() {
    let _timer = crate::common::timed!();
    let plane = Scene::load_file(&fixture("textured_plane.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&plane).unwrap();
    for (pipeline, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit"), (Pipeline::Hdrp, "lit")] {
        secondary_maps_in(&mut renderer, &prepared, pipeline, shader);
    }
}

fn secondary_maps_in(renderer: &mut Renderer, prepared: &PreparedScene, pipeline: Pipeline, shader: &str) {
    let sliders = Sliders { base_color_linear: [0.83, 0.79, 0.75], metallic: 0.0, smoothness: 0.5 };
    let mut cell = cell_params(pipeline, shader, sliders, (1.0, 10.0), 48, RenderPath::Forward);
    cell.settings.material_maps = Some("marble");
    let without = renderer.render(prepared, &cell, 1, 0).unwrap();
    let truth_without = truth(renderer, prepared, &cell, TruthBackend::Cpu);
    let slot = cell.model.params.iter().find(|p| p.name == "detail").unwrap().slot;
    cell.surface.params[slot] = 1.0;
    let with = renderer.render(prepared, &cell, 1, 0).unwrap();
    // The frame: detail where the mask lets it (part of the tile), the rest as it was.
    let n = with.roles.len();
    let changed = (0..n).filter(|&i| (with.hdr[4 * i] - without.hdr[4 * i]).abs() > 0.01 * without.hdr[4 * i]).count();
    let same = (0..n).filter(|&i| (with.hdr[4 * i] - without.hdr[4 * i]).abs() <= 0.002 * without.hdr[4 * i]).count();
    eprintln!("{shader} secondary maps: {changed} of {n} pixels change by over 1%, {same} by at most 0.2%");
    assert!(changed * 10 > n && same * 10 > n, "{changed} changed, {same} the same of {n}");
    // Both tracers blend them as the frame does: their subjects agree within noise…
    let (cpu, gpu) =
        (truth(renderer, prepared, &cell, TruthBackend::Cpu), truth(renderer, prepared, &cell, TruthBackend::Gpu));
    let z = crate::common::subject_z(&cpu, &gpu);
    // …and the frame's change of the subject's mean is the truth's (mip-mapped against level 0).
    let frame_ratio = subject_mean(&with.roles, |i| with.hdr[4 * i] as f64)
        / subject_mean(&without.roles, |i| without.hdr[4 * i] as f64);
    let truth_ratio = subject_mean(&cpu.roles, |i| cpu.mean[i][0] as f64)
        / subject_mean(&truth_without.roles, |i| truth_without.mean[i][0] as f64);
    eprintln!(
        "{shader}: CPU − GPU truth Z {z:.2}; subject mean with/without: frame {frame_ratio:.4}, truth {truth_ratio:.4}"
    );
    assert!(z.abs() < 4.0, "the tracers' subjects differ by {z:.2} standard errors");
    assert!((frame_ratio - truth_ratio).abs() < 0.04, "frame {frame_ratio} vs truth {truth_ratio}");
    if pipeline != Pipeline::Builtin {
        // URP's ×2 and HDRP's overlay of the grain read as linear data are neutral at its sRGB 0.5.
        return;
    }
    // Both darken: the ×2 albedo of a grain around sRGB 0.5 is 0.98 on average. The truth reads
    // the finest level, where the grain's normals tilt NL away; the frame's mips average them
    // flat (as Unity's do), so the truth darkens more (measured 0.9605 against 0.9887).
    assert!(frame_ratio < 0.997 && truth_ratio < frame_ratio, "frame {frame_ratio}, truth {truth_ratio}");
    assert!(frame_ratio - truth_ratio < 0.04, "frame {frame_ratio} vs truth {truth_ratio}");
}

#[test]
fn the_detail_blends_match_their_twins() {
    let _timer = crate::common::timed!();
    use shadematrix::materials::detail::{
        blend_normal_rnm, blend_normals, detail_albedo_mulx2, detail_albedo_x2_urp, hdrp_detail_albedo,
    };
    let gpu = GpuContext::new().unwrap();
    let urp = crate::common::pair_kernel("vec4<f32>(blend_normal_rnm(a.xyz, b.xyz), detail_albedo_x2_urp(a.w, b.w))");
    // HDRP's overlay of a base colour (the first normal's components, made positive) by the albedo.
    let hdrp = crate::common::pair_kernel("vec4<f32>(hdrp_detail_albedo(abs(a.xyz), a.w, b.w), 0.0)");
    let source = crate::common::pair_kernel("vec4<f32>(blend_normals(a.xyz, b.xyz), detail_albedo_mulx2(a.w, b.w))");
    let normals = [[0.0, 0.0, 1.0], [0.3, -0.2, 0.93], [-0.6, 0.1, 0.79], [0.05, 0.7, 0.71]];
    let mut cases = Vec::new();
    for n1 in normals {
        for n2 in normals {
            for (albedo, mask) in [(0.214, 1.0), (0.1, 0.5), (0.4, 0.25), (0.3, 0.0)] {
                cases.push((n1, n2, albedo, mask));
            }
        }
    }
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|(a, b, albedo, mask)| {
            [
                [a[0] as f32, a[1] as f32, a[2] as f32, *albedo as f32],
                [b[0] as f32, b[1] as f32, b[2] as f32, *mask as f32],
            ]
        })
        .collect();
    let got = crate::common::run_kernel(&gpu, &source, &inputs, cases.len(), &[]);
    let got_urp = crate::common::run_kernel(&gpu, &urp, &inputs, cases.len(), &[]);
    let got_hdrp = crate::common::run_kernel(&gpu, &hdrp, &inputs, cases.len(), &[]);
    let mut worst = 0.0f64;
    for ((((a, b, albedo, mask), g), u), h) in cases.iter().zip(&got).zip(&got_urp).zip(&got_hdrp) {
        let base = a.map(|c| (c as f32).abs() as f64);
        let overlay = hdrp_detail_albedo(base, *albedo, *mask);
        for k in 0..3 {
            worst = worst.max((h[k] as f64 - overlay[k]).abs());
        }
        let n = blend_normals(*a, *b);
        let f = detail_albedo_mulx2(*albedo, *mask);
        let rnm = blend_normal_rnm(*a, *b);
        let f_urp = detail_albedo_x2_urp(*albedo, *mask);
        for k in 0..3 {
            worst = worst.max((g[k] as f64 - n[k]).abs()).max((u[k] as f64 - rnm[k]).abs());
        }
        worst = worst.max((g[3] as f64 - f).abs()).max((u[3] as f64 - f_urp).abs());
    }
    eprintln!("detail blends GPU vs twin: worst |Δ| {worst:.2e} over {} inputs", cases.len());
    assert!(worst < 1e-5, "{worst:e}");
}

/// In a run: a flat subject has no maps to blend into, so its cells along `detail` are twins; a
/// textured one changes its own pixels only, in each pipeline's lit shader.
#[test]
fn secondary_maps_change_only_a_textured_subject() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = r#"
name = "detail"
compositions = ["default"]
pipelines = ["builtin", "urp", "hdrp"]
shaders = ["standard", "lit"]
presets = ["brick"]
[sweep]
textured = [true, false]
[sweep.params]
detail = [0.0, 1.0]
[image]
width = 64
height = 64
"#;
    let out = crate::common::run_matrix(tmp.path(), body, "run");
    let run = shadematrix::report::run_data::RunData::load(&out).unwrap();
    // Each pipeline's textured cell compared; their flat ones twins.
    let checked = crate::common::check_map_parameter(&run, "detail", (1.0, 0.0), None);
    assert_eq!(checked, 3, "built-in Standard, URP Lit and HDRP Lit");
}
