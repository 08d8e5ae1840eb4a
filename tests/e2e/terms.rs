//! Term outputs (pipelines::terms, `[outputs] terms = true`): a cell's image.exr carries its
//! direct and indirect diffuse and specular, emission and occlusion as extra layers, and the
//! additive ones sum to the image (or, where the cell blooms, to the frame before bloom) within
//! float error, on every pipeline and path; cells of a run that does not ask have none.

use shadematrix::images::encode::{read_exr, read_exr_layer};
use shadematrix::record::cell::CellRecord;

/// The worst difference between the sum of a cell's additive layers and what they sum to,
/// relative to the larger of that pixel's value and the sum of the layers' magnitudes; and the
/// layers read.
fn sum_error(cell: &std::path::Path) -> (f64, CellRecord) {
    let record: CellRecord = serde_json::from_slice(&std::fs::read(cell.join("cell.json")).unwrap()).unwrap();
    let terms = record.terms.clone().expect("the run asked for terms");
    assert!(terms.missing.is_none(), "{}: {:?}", cell.display(), terms.missing);
    let exr = cell.join("image.exr");
    let target = match terms.sum_of.as_str() {
        "image" => read_exr(&exr).unwrap().2,
        layer => read_exr_layer(&exr, layer).unwrap(),
    };
    let mut sum = vec![0f64; target.len()];
    let mut magnitude = vec![0f64; target.len()];
    for layer in terms.layers.iter().filter(|l| l.additive) {
        assert!(cell.join(&layer.png).is_file(), "{} has no {}", cell.display(), layer.png);
        let px = read_exr_layer(&exr, &layer.name).unwrap();
        for (i, v) in px.iter().enumerate() {
            sum[i] += *v as f64;
            magnitude[i] += v.abs() as f64;
        }
    }
    let mut worst = 0.0f64;
    for i in (0..target.len()).filter(|i| i % 4 != 3) {
        let scale = (target[i].abs() as f64).max(magnitude[i]).max(1e-3);
        worst = worst.max((sum[i] - target[i] as f64).abs() / scale);
    }
    (worst, record)
}

#[test]
fn terms_sum_to_the_image_on_every_pipeline_and_path() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    // 32-bit channels: the sum is checked against float error, not the half EXR's rounding.
    let body = r#"
name = "terms"
compositions = ["mitsuba"]
pipelines = ["builtin", "urp", "hdrp"]
paths = ["forward", "deferred"]
shaders = ["standard", "lit", "simple_lit", "phong", "unlit", "lambert_vertex"]
presets = ["plastic"]

[sweep]
smoothness = [0.8]
surface = ["opaque", "fade", "transparent"]
alpha = [0.4]

[outputs]
terms = true
exr = "float"

[image]
width = 48
height = 48
"#;
    let out = crate::common::run_matrix(tmp.path(), body, "run");
    let mut seen = std::collections::BTreeMap::new();
    for entry in std::fs::read_dir(out.join("cells")).unwrap() {
        let cell = entry.unwrap().path();
        let (worst, record) = sum_error(&cell);
        let terms = record.terms.as_ref().unwrap();
        let names: Vec<&str> = terms.layers.iter().map(|l| l.name.as_str()).collect();
        // Deferred paths keep the ambient and emission in a half-float RT3 (its 11-bit mantissa),
        // forward ones sum 32-bit floats.
        let limit = if record.coords.path == shadematrix::pipelines::RenderPath::Deferred { 2e-3 } else { 1e-5 };
        assert!(worst <= limit, "{}: terms sum to the frame within {worst:e} (limit {limit:e})", cell.display());
        for name in
            ["direct_diffuse", "direct_specular", "indirect_diffuse", "indirect_specular", "emission", "occlusion"]
        {
            assert!(names.contains(&name), "{}: layers {names:?}", cell.display());
        }
        // The occlusion is a factor in 0..1 wherever a surface is, whatever passes draw it (for an
        // opaque subject: a transparent one's blends over the background as its colour does).
        if matches!(record.coords.surface, None | Some(shadematrix::pipelines::surface::SurfaceType::Opaque)) {
            let ao = read_exr_layer(&cell.join("image.exr"), "occlusion").unwrap();
            let top = ao.chunks_exact(4).map(|p| p[0]).fold(0f32, f32::max);
            assert!(top <= 1.0 + 1e-6, "{}: occlusion up to {top}", cell.display());
        }
        let key = format!("{}/{}", record.coords.pipeline.name(), record.coords.path.name());
        let entry = seen.entry(key).or_insert((0usize, 0.0f64, Vec::new()));
        entry.0 += 1;
        entry.1 = entry.1.max(worst);
        entry.2 = names.iter().map(|s| s.to_string()).collect();
    }
    eprintln!("{seen:#?}");
    assert!(seen.len() >= 5, "pipelines × paths seen: {:?}", seen.keys());
}

/// The layers are the terms they name: Phong lit by a sun with no environment light has no
/// indirect light, its diffuse is where its base colour shows and its highlight is white; an
/// unlit cell is all emission; HDRP's occlusion layer holds its SSAO (below 1 in the corners).
#[test]
fn each_layer_holds_its_term() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = r#"
name = "terms_split"
compositions = ["default"]
pipelines = ["builtin", "hdrp"]
shaders = ["phong", "unlit", "lit"]
presets = ["plastic"]

[outputs]
terms = true
exr = "float"

[image]
width = 48
height = 48
"#;
    let out = crate::common::run_matrix(tmp.path(), body, "run");
    let mut checked = 0;
    for entry in std::fs::read_dir(out.join("cells")).unwrap() {
        let cell = entry.unwrap().path();
        let (worst, record) = sum_error(&cell);
        assert!(worst <= 1e-5, "{}: {worst:e}", cell.display());
        let exr = cell.join("image.exr");
        let layer = |name: &str| read_exr_layer(&exr, name).unwrap();
        let total = |px: &[f32]| px.chunks_exact(4).map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>();
        match record.coords.shader.as_str() {
            "unlit" => {
                // The subject's colour is all emitted: no reflected light anywhere on it.
                let roles = record.stats.subject_pixels;
                assert!(roles > 0);
                assert!(total(&layer("emission")) > 0.0);
                checked += 1;
            }
            "phong" => {
                assert!(total(&layer("direct_diffuse")) > 0.0 && total(&layer("direct_specular")) > 0.0);
                checked += 1;
            }
            "lit" if record.coords.pipeline == shadematrix::pipelines::Pipeline::Hdrp => {
                let ao = layer("occlusion");
                let (lo, hi) = ao.chunks_exact(4).fold((1f32, 0f32), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
                assert!(hi <= 1.0 + 1e-6 && lo < 0.99, "HDRP's SSAO in the occlusion layer: {lo}..{hi}");
                checked += 1;
            }
            _ => {}
        }
    }
    assert!(checked >= 3, "cells checked: {checked}");
}

/// A run that does not ask draws no layers: image.exr holds RGBA alone, no terms/ folder, no
/// record; the layers' reader says which layer is missing.
#[test]
fn terms_are_drawn_only_when_asked() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = r#"
name = "no_terms"
compositions = ["default"]
pipelines = ["urp"]
shaders = ["lit"]
presets = ["plastic"]

[image]
width = 32
height = 32
"#;
    let out = crate::common::run_matrix(tmp.path(), body, "run");
    let cell = std::fs::read_dir(out.join("cells")).unwrap().next().unwrap().unwrap().path();
    let record: CellRecord = serde_json::from_slice(&std::fs::read(cell.join("cell.json")).unwrap()).unwrap();
    assert!(record.terms.is_none());
    assert!(!cell.join("terms").exists());
    let err = read_exr_layer(&cell.join("image.exr"), "direct_diffuse").unwrap_err().to_string();
    assert!(err.contains("direct_diffuse"), "{err}");
}

/// A sheet of terms in a run that draws none, or of a layer that does not exist, is refused
/// before anything renders: exit 2, the key, the value and what is allowed.
#[test]
fn term_sheets_are_checked_against_the_outputs() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let matrix = |name: &str, extra: &str| {
        let body = format!(
            "name = \"{name}\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"plastic\"]\n{extra}"
        );
        crate::common::write_matrix(tmp.path(), &format!("{name}.toml"), &body)
    };
    let refused = |path: std::path::PathBuf, needles: &[&str]| {
        let (code, _, err) = crate::common::shadematrix(tmp.path(), &["list", path.to_str().unwrap()], &[]);
        assert_eq!(code, 2, "{err}");
        for n in needles {
            assert!(err.contains(n), "`{n}` not in: {err}");
        }
    };
    refused(
        matrix("no_terms", "sheets = [{ rows = \"pipeline\", cols = \"term\" }]\n"),
        &["no_terms.toml", "sheets[0].cols", "[outputs] terms = true"],
    );
    refused(
        matrix("typo", "sheets = [{ rows = \"pipeline\", cols = \"preset\", image = \"direct_specualr\" }]\n[outputs]\nterms = true\n"),
        &["typo.toml", "sheets[0].image", "direct_specualr", "direct_specular"],
    );
}

/// Every built-in model's lobes as the GPU draws them under each term mask against its f64
/// twin's (`SurfaceTwin::direct_lobes`, `indirect_lobes`), for the same inputs: the split is part
/// of each formula. The premultiplied surfaces' diffuse weight is checked on the lit models,
/// whose twins keep it: the specular masks give the twin at weight 0.
#[test]
fn lobe_masks_split_every_model_as_its_twin_does() {
    let _timer = crate::common::timed!();
    use glam::DVec3;
    use shadematrix::pipelines::terms::{
        DIRECT_DIFFUSE, DIRECT_SPECULAR, EMISSION, INDIRECT_DIFFUSE, INDIRECT_SPECULAR,
    };
    use shadematrix::render::probe::{BrdfProbe, ProbeInput};
    use shadematrix::shading::twin::Surface;
    let gpu = shadematrix::gpu::GpuContext::new().unwrap();
    let mut probe = BrdfProbe::new(&gpu);
    let dir = |t: f64, p: f64| DVec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
    let (gi_d, gi_s) = (DVec3::new(0.3, 0.25, 0.2), DVec3::new(0.6, 0.5, 0.7));
    let mut checked = 0;
    for model in crate::common::models().models() {
        let Some(twin) = model.twin else { continue };
        for &pipeline in &model.pipelines {
            let mut surfaces = Vec::new();
            let mut inputs = Vec::new();
            for (k, (m, sm)) in [(0.0, 0.3), (0.0, 0.85), (0.5, 0.6), (1.0, 0.9), (0.2, 0.1)].into_iter().enumerate() {
                let sliders = shadematrix::shading::registry::Sliders {
                    base_color_linear: [0.7, 0.4, 0.2],
                    metallic: m,
                    smoothness: sm,
                };
                let mut s = model.surface(pipeline, &sliders);
                s.specular = DVec3::new(0.5, 0.45, 0.4);
                if model.name == "simple_lit" {
                    s.params[0] = 1.0;
                }
                let s = s.rounded_f32();
                for j in 0..6 {
                    let (n, v, l) =
                        (DVec3::Y, dir(0.2 + 0.2 * j as f64, 0.3 * k as f64), dir(0.9 - 0.12 * j as f64, 2.0));
                    inputs.push(ProbeInput::new(&s, n, v, l, gi_d, gi_s));
                    surfaces.push((s, n, v, l));
                }
            }
            let mut worst = 0.0f64;
            let masks = [DIRECT_DIFFUSE, DIRECT_SPECULAR, INDIRECT_DIFFUSE, INDIRECT_SPECULAR, EMISSION];
            for bits in masks {
                let got = probe.evaluate_terms(&gpu, pipeline, model, &inputs, bits).unwrap();
                for (i, (s, n, v, l)) in surfaces.iter().enumerate() {
                    let d = twin.direct_lobes(pipeline, s, *n, *v, *l);
                    let ind = twin.indirect_lobes(pipeline, s, *n, *v, gi_d, gi_s);
                    let (want_d, want_i) = match bits {
                        DIRECT_DIFFUSE => (d.diffuse, DVec3::ZERO),
                        DIRECT_SPECULAR => (d.specular, DVec3::ZERO),
                        INDIRECT_DIFFUSE => (DVec3::ZERO, ind.diffuse),
                        INDIRECT_SPECULAR => (DVec3::ZERO, ind.specular),
                        _ => (d.emitted, ind.emitted),
                    };
                    let scale = d.sum().abs().max_element().max(ind.sum().abs().max_element()).max(1e-2);
                    let as_d = |c: [f32; 3]| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64);
                    let err = (as_d(got[i].0) - want_d)
                        .abs()
                        .max_element()
                        .max((as_d(got[i].1) - want_i).abs().max_element());
                    worst = worst.max(err / scale);
                }
            }
            // The lit models keep the premultiplied surfaces' diffuse weight in the diffuse lobe.
            if model.splits_diffuse() {
                let got =
                    probe.evaluate_terms(&gpu, pipeline, model, &inputs, DIRECT_SPECULAR | INDIRECT_SPECULAR).unwrap();
                for (i, (s, n, v, l)) in surfaces.iter().enumerate() {
                    let none = Surface { diffuse_weight: 0.0, ..*s };
                    let spec = twin.direct(pipeline, &none, *n, *v, *l);
                    let scale = twin.direct(pipeline, s, *n, *v, *l).abs().max_element().max(1e-2);
                    let g = DVec3::new(got[i].0[0] as f64, got[i].0[1] as f64, got[i].0[2] as f64);
                    worst = worst.max((g - spec).abs().max_element() / scale);
                }
            }
            eprintln!("{}/{}: lobes against the twin within {worst:e}", pipeline.name(), model.name);
            assert!(worst <= 2e-4, "{}/{}: lobes differ from the twin's by {worst:e}", pipeline.name(), model.name);
            checked += 1;
        }
    }
    assert!(checked >= 40, "every (pipeline, model) with a twin: {checked}");
}
