//! Height maps (Standard's and URP Lit's `_Parallax`, registry PARALLAX): the WGSL
//! ParallaxOffset1Step against its f64 twin, the subject's maps moved by it in both pipelines'
//! frames, and cells without maps twins along the parameter.

use shadematrix::gpu::GpuContext;
use shadematrix::materials::parallax_offset;
use shadematrix::pipelines::Pipeline;

#[test]
fn parallax_offset_matches_its_twin() {
    let _timer = crate::common::timed!();
    let source = crate::common::pair_kernel("vec4<f32>(parallax_offset(a.x, a.y, b.xyz), 0.0, 0.0)");
    let mut cases = Vec::new();
    for h in [0.0, 0.25, 0.5, 0.9, 1.0] {
        for height in [0.005, 0.02, 0.08] {
            for v in [[0.0, 0.0, 1.0], [0.3, -0.2, 0.9], [0.9, 0.1, 0.1], [-0.5, 0.7, 0.02], [2.0, 1.0, 3.0]] {
                cases.push((h, height, v));
            }
        }
    }
    let inputs: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|(h, height, v)| {
            [[*h as f32, *height as f32, 0.0, 0.0], [v[0] as f32, v[1] as f32, v[2] as f32, 0.0]]
        })
        .collect();
    let gpu = GpuContext::new().unwrap();
    let got = crate::common::run_kernel(&gpu, &source, &inputs, cases.len(), &[]);
    let mut worst = 0.0f64;
    for ((h, height, v), g) in cases.iter().zip(&got) {
        let want = parallax_offset(*h, *height, *v);
        for k in 0..2 {
            worst = worst.max((g[k] as f64 - want[k]).abs() / height.max(1e-9));
        }
    }
    // At h = ½ nothing moves; looking straight down nothing moves.
    assert_eq!(parallax_offset(0.5, 0.08, [0.3, 0.2, 0.9]), [0.0, 0.0]);
    assert_eq!(parallax_offset(1.0, 0.08, [0.0, 0.0, 1.0]), [0.0, 0.0]);
    eprintln!("parallax offset GPU vs twin: worst |Δ|/scale {worst:.2e} over {} inputs", cases.len());
    assert!(worst < 1e-5, "{worst:e}");
}

/// A textured subject with a height scale is drawn with its maps moved (built-in Standard, URP
/// Lit), the fixed objects and the sky not; a flat subject's cells along the scale are twins;
/// HDRP Lit, whose pixel displacement is a different technique, does not take the parameter.
#[test]
fn height_maps_move_the_subjects_maps_only() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = r#"
name = "parallax"
compositions = ["default"]
pipelines = ["builtin", "urp", "hdrp"]
shaders = ["standard", "lit"]
presets = ["brick"]
[sweep]
textured = [true, false]
[sweep.params]
parallax = [0.0, 0.08]
[image]
width = 64
height = 64
"#;
    let out = crate::common::run_matrix(tmp.path(), body, "run");
    let run = shadematrix::report::run_data::RunData::load(&out).unwrap();
    let checked = crate::common::check_map_parameter(&run, "parallax", (0.08, 0.0), Some(Pipeline::Hdrp));
    assert_eq!(checked, 2, "built-in Standard and URP Lit");
}
