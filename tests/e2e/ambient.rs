//! The `ambient_intensity` axis: the scene's environment light scaled per cell. The frame is
//! linear in it where nothing feeds the environment back into itself (sky reflections, no probes):
//! I(2) − I(1) = I(1) − I(0) on every pixel, and the ambient changes the image.

use crate::common::cell_params;
use shadematrix::declarations::scene::{Reflections, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;

#[test]
fn the_frame_is_linear_in_the_ambient_axis() {
    let _timer = crate::common::timed!();
    let mut scene = Scene::load("default", None, "test", "composition").unwrap();
    scene.environment.reflections = Reflections::Sky;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let plastic =
        shadematrix::shading::registry::Sliders { base_color_linear: [0.284; 3], metallic: 0.0, smoothness: 0.75 };
    let mut frame = |ambient: f64| {
        let mut cell = cell_params(Pipeline::Builtin, "standard", plastic, (2.0, 10.0), 64, RenderPath::Forward);
        cell.settings.ambient_intensity = Some(ambient);
        renderer.render(&prepared, &cell, 1, 0).unwrap().hdr
    };
    let (i0, i1, i2) = (frame(0.0), frame(1.0), frame(2.0));
    let peak = i1.iter().fold(0.0f32, |m, v| m.max(v.abs())) as f64;
    let mut worst: f64 = 0.0;
    let mut changed = 0;
    for k in (0..i0.len()).filter(|k| k % 4 != 3) {
        let (a, b, c) = (i0[k] as f64, i1[k] as f64, i2[k] as f64);
        worst = worst.max(((c - b) - (b - a)).abs() / peak);
        changed += ((b - a).abs() > 1e-4 * peak) as usize;
    }
    eprintln!("ambient 0/1/2: worst second difference {worst:.2e} of the peak; {changed} channels change");
    assert!(worst < 1e-4, "not linear in the ambient: {worst}");
    assert!(changed > i0.len() / 4, "the ambient changes {changed} channels only");
    // The default scene's own ambient is the axis's 1.
    let own = {
        let cell = cell_params(Pipeline::Builtin, "standard", plastic, (2.0, 10.0), 64, RenderPath::Forward);
        renderer.render(&prepared, &cell, 1, 0).unwrap().hdr
    };
    assert_eq!(own, i1, "unswept is the scene's ambient, × 1");
}

#[test]
fn a_matrix_sweeps_the_ambient_into_its_own_cells() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let text = "name = \"amb\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
                presets = [\"plastic\"]\n[sweep]\nambient_intensity = [0.5, 2.0]\n";
    std::fs::write(tmp.path().join("amb.toml"), text).unwrap();
    let (rc, out, err) = crate::common::shadematrix(tmp.path(), &["list", "amb.toml"], &[]);
    assert_eq!(rc, 0, "{err}");
    for id in ["default__urp-forward__lit__plastic__m0.00_s0.75_i2_r10_amb0.5", "_amb2"] {
        assert!(out.contains(id), "no {id} in:\n{out}");
    }
    // Out of its row's range: refused with the key, the value and what is allowed.
    std::fs::write(tmp.path().join("bad.toml"), text.replace("2.0]", "20.0]")).unwrap();
    let (rc, _, err) = crate::common::shadematrix(tmp.path(), &["list", "bad.toml"], &[]);
    assert_eq!(rc, 2, "{err}");
    assert!(err.contains("sweep.ambient_intensity[1]") && err.contains("20"), "{err}");
}
