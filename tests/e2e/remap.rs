//! Carrying a material's look across pipelines (`remap`): a model matched to itself gives back its
//! own values, and URP Lit matched to HDRP Lit on a Lambert-like material in linear light gives
//! back the units between them.

use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::settings::HdrpLightUnit;
use shadematrix::pipelines::{Pipeline, Tonemap};
use shadematrix::plan::cell::CellSettings;
use shadematrix::remap::fit::{calibrate_exposure, fit, BasisCache, FitOptions, ParamAxis};
use shadematrix::remap::{frames, MatchSpace, MaterialValues, Side, Stage};
use shadematrix::render::Renderer;

fn stage(renderer: &mut Renderer, size: u32) -> Stage {
    let mut scene = Scene::load("default", None, "test", "composition").unwrap();
    // Bloom spreads the subject's light over its neighbours; the match reads the subject alone.
    scene.hdrp.bloom = false;
    let prepared = renderer.prepare_scene(&scene).unwrap();
    Stage { scenes: vec![(scene, prepared)], light_intensity: 2.0, light_range: 10.0, size }
}

fn side(pipeline: Pipeline, tonemap: Tonemap, settings: CellSettings) -> Side<'static> {
    Side { pipeline, model: crate::common::find_model(pipeline, "lit").unwrap(), tonemap, settings }
}

#[test]
fn a_model_matched_to_itself_keeps_its_values() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let stage = stage(&mut renderer, 48);
    let urp = side(Pipeline::Urp, Tonemap::None, CellSettings::default());
    let plastic = MaterialValues::new(0.75, 0.0, [0.284, 0.284, 0.284]);
    let source = frames(&mut renderer, &stage, &urp, &plastic).unwrap();
    let options = FitOptions { smoothness_steps: 4, refine_iterations: 0, ..Default::default() };
    let mut cache = BasisCache::default();
    let f = fit(&mut renderer, &stage, &plastic, &source, &urp, MatchSpace::Display, &options, &mut cache).unwrap();
    eprintln!("identity: {:?}, before {:?}, after {:?}", f.values, f.before, f.after);
    assert_eq!(f.before.flip, 0.0);
    assert!(f.after.flip < 1e-3, "{:?}", f.after);
    assert!((f.values.smoothness - 0.75).abs() < 1e-9 && f.values.metallic == 0.0, "{:?}", f.values);
    for c in f.values.color {
        assert!((c - 0.284).abs() < 2e-3, "{:?}", f.values);
    }
}

#[test]
fn urp_lit_carried_to_hdrp_lit_in_linear_light_takes_the_units_ratio() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let stage = stage(&mut renderer, 48);
    let urp = side(Pipeline::Urp, Tonemap::None, CellSettings::default());
    // HDRP reading URP's intensities as they are meant (π·I × 10⁴ candela, the sky × 10⁴): its
    // linear radiance is URP's × 10⁴ wherever both shade alike, so on the linear image a
    // Lambert-like material calibrates the pair's exposure to 10⁻⁴, and with it the material's
    // fitted colour stays near its own.
    let mut settings = CellSettings::default();
    settings.engine.hdrp.light_unit = HdrpLightUnit::Unity;
    let hdrp = side(Pipeline::Hdrp, Tonemap::Aces, settings);
    let matte = MaterialValues::new(0.0, 0.0, [0.5, 0.4, 0.3]);
    let source = frames(&mut renderer, &stage, &urp, &matte).unwrap();
    let k = calibrate_exposure(&mut renderer, &stage, &matte, &source, &hdrp).unwrap();
    let options = FitOptions { smoothness_steps: 4, refine_iterations: 0, exposure: Some(k), ..Default::default() };
    let mut cache = BasisCache::default();
    let f = fit(&mut renderer, &stage, &matte, &source, &hdrp, MatchSpace::Linear, &options, &mut cache).unwrap();
    eprintln!("URP → HDRP linear: exposure {k:.4e}; {:?}, before {:?}, after {:?}", f.values, f.before, f.after);
    // Measured 8.70e-5: HDRP's Lit is no Lambert at smoothness 0 (Disney diffuse, a
    // multiple-scattering GGX lobe on F0 0.04) and its sky lights 4 % more than URP's.
    assert!((k * 1e4 - 1.0).abs() < 0.2, "exposure {k} against 1e-4");
    assert_eq!(f.exposure, k);
    // Measured within 19 % of its own (the fit trades HDRP's specular lobe for a mirror's and
    // brightens the diffuse to match): the units went to the exposure, not to the colour.
    for c in 0..3 {
        assert!((f.values.color[c] / matte.color[c] - 1.0).abs() < 0.25, "{:?}", f.values);
    }
    assert!(f.after.rel_mse < 1e-3 * f.before.rel_mse, "{:?} against {:?}", f.after, f.before);
}

#[test]
fn the_refinement_on_rendered_frames_never_ends_worse_than_its_start() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let stage = stage(&mut renderer, 32);
    let builtin = Side {
        pipeline: Pipeline::Builtin,
        model: crate::common::find_model(Pipeline::Builtin, "standard").unwrap(),
        tonemap: Tonemap::None,
        settings: CellSettings::default(),
    };
    let urp = side(Pipeline::Urp, Tonemap::None, CellSettings::default());
    let gold = MaterialValues::new(0.9, 1.0, [1.0, 0.766, 0.336]);
    let source = frames(&mut renderer, &stage, &builtin, &gold).unwrap();
    let coarse = FitOptions { smoothness_steps: 2, refine_iterations: 0, ..Default::default() };
    let mut cache = BasisCache::default();
    let start = fit(&mut renderer, &stage, &gold, &source, &urp, MatchSpace::Display, &coarse, &mut cache).unwrap();
    let refined = FitOptions { refine_iterations: 12, ..coarse };
    let f = fit(&mut renderer, &stage, &gold, &source, &urp, MatchSpace::Display, &refined, &mut cache).unwrap();
    eprintln!(
        "built-in Standard → URP Lit gold: copied {:.4}, grid {:.4}, refined {:.4} ({:?}, {} renders)",
        f.before.flip, start.after.flip, f.after.flip, f.values, f.renders
    );
    // The second fit found the grid's basis frames in the cache: it renders only the copied
    // values, the three best nodes and the refinement's evaluations.
    assert!(f.after.flip <= start.after.flip, "{f:?} against {start:?}");
    assert!(start.renders > 2 * 6 && (1 + 3..=1 + 3 + 40).contains(&f.renders), "{f:?} against {start:?}");
    assert!(f.after.flip <= f.before.flip, "{f:?}");
}

#[test]
fn the_match_command_writes_its_tables_and_refuses_a_mistyped_side() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"m\"\ncompositions = [\"default\"]\npipelines = [\"builtin\"]\nshaders = [\"standard\"]\n\
        presets = [\"plastic\"]\n[sweep]\nsmoothness = [0.2, 0.8]\n";
    let matrix = crate::common::write_matrix(tmp.path(), "m", body);
    let m = matrix.to_str().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let args = ["match", "--from", "builtin/standard", "--to", "urp/lit", m, "--out", o, "--size", "24"];
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &[&args[..], &["--iterations", "3"]].concat(), &[]);
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("tables/match.json")).unwrap()).unwrap();
    assert_eq!(json["schema"], 2);
    let rows = json["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2, "one row per swept smoothness");
    for r in rows {
        let (copied, fitted) =
            (r["copied_error"]["flip"].as_f64().unwrap(), r["fitted_error"]["flip"].as_f64().unwrap());
        assert!(fitted <= copied, "{r}");
    }
    let csv = std::fs::read_to_string(out.join("tables/match.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(std::fs::read_to_string(out.join("tables/match.md")).unwrap().contains("| plastic | 0.200 |"));
    // The pictures: every row's frames, the preset's sheet, the curves and the page naming them.
    for r in rows {
        for kind in ["source", "copied", "fitted"] {
            let png = out.join(format!("{}/default-{kind}.png", r["frames"].as_str().unwrap()));
            assert_eq!(image::image_dimensions(&png).unwrap(), (24, 24), "{}", png.display());
        }
    }
    assert!(image::image_dimensions(out.join("sheets/plastic.png")).unwrap().1 > 2 * 24);
    let svg = std::fs::read_to_string(out.join("plots/smoothness.svg")).unwrap();
    assert!(svg.contains("plastic") && svg.contains("source smoothness"));
    // The template escapes `/` in attributes as `&#x2f;`, which a browser reads back as `/`.
    let page = std::fs::read_to_string(out.join("index.html")).unwrap().replace("&#x2f;", "/");
    assert!(
        page.contains("sheets/plastic.png") && page.contains("plots/smoothness.svg") && page.contains("frames/001")
    );
    let bad = ["match", "--from", "builtin/standrd", "--to", "urp/lit", m, "--out", o];
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &bad, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--from") && err.contains("did you mean `standard`?"), "{err}");
    // Values kept from the source stay as they are; the rest is fitted.
    let kept = out.join("kept");
    let k = kept.to_str().unwrap();
    let args = ["match", "--from", "builtin/standard", "--to", "urp/lit", m, "--out", k, "--size", "24"];
    let (code, _, err) = crate::common::shadematrix(
        tmp.path(),
        &[&args[..], &["--iterations", "3", "--keep", "metallic,color"]].concat(),
        &[],
    );
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(kept.join("tables/match.json")).unwrap()).unwrap();
    assert_eq!(json["kept"], serde_json::json!(["metallic", "color"]));
    for r in json["rows"].as_array().unwrap() {
        assert_eq!(r["fitted"]["metallic"], r["source"]["metallic"], "{r}");
        assert_eq!(r["fitted"]["color"], r["source"]["color"], "{r}");
    }
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &[&args[..], &["--keep", "metalic"]].concat(), &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--keep") && err.contains("did you mean `metallic`?"), "{err}");
}

#[test]
fn a_models_own_swept_parameter_is_fitted_too() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let stage = stage(&mut renderer, 32);
    let urp = |name| Side {
        pipeline: Pipeline::Urp,
        model: crate::common::find_model(Pipeline::Urp, name).unwrap(),
        tonemap: Tonemap::None,
        settings: CellSettings::default(),
    };
    // Oren–Nayar at σ = 0 is Lambert: a Lambert source matched in Oren–Nayar whose σ the matrix
    // sweeps at 0.5 and 1 (σ = 1 − smoothness = 0.5 copied) is fitted towards σ = 0.
    let matte = MaterialValues::new(0.5, 0.0, [0.6, 0.5, 0.4]);
    let source = frames(&mut renderer, &stage, &urp("lambert"), &matte).unwrap();
    let sigma = ParamAxis { name: "sigma".into(), values: vec![0.5, 1.0], range: Some((0.0, 1.5)) };
    let options = FitOptions { smoothness_steps: 1, refine_iterations: 30, params: vec![sigma], ..Default::default() };
    let mut cache = BasisCache::default();
    let oren_nayar = urp("oren_nayar");
    let f =
        fit(&mut renderer, &stage, &matte, &source, &oren_nayar, MatchSpace::Display, &options, &mut cache).unwrap();
    eprintln!(
        "Lambert → Oren–Nayar: {:?}, before {:?}, after {:?}, {} renders",
        f.values, f.before, f.after, f.renders
    );
    let fitted_sigma = f.values.params["sigma"];
    assert!(fitted_sigma < 0.5, "σ {fitted_sigma}: {:?}", f.values);
    assert!(f.after.flip < f.before.flip, "{:?} against {:?}", f.after, f.before);
}

#[test]
fn an_interrupted_match_resumes_from_its_journal() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"m\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
        presets = [\"gold\"]\n[sweep]\nsmoothness = [0.3, 0.6, 0.9]\n";
    let matrix = crate::common::write_matrix(tmp.path(), "m", body);
    let out = tmp.path().join("out");
    let args = |resume: bool| {
        let mut a = vec!["match", "--from", "urp/lit", "--to", "hdrp/lit", matrix.to_str().unwrap()];
        a.extend(["--out", out.to_str().unwrap(), "--size", "20", "--iterations", "2"]);
        a.extend(resume.then_some("--resume"));
        a
    };
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &args(false), &[]);
    assert_eq!(code, 0, "{err}");
    let read = || -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(out.join("tables/match.json")).unwrap()).unwrap()
    };
    let first = read();
    // Interrupted while writing the second row's frames, before the tables: the journal holds all
    // three rows, but the second's frames are not all there.
    std::fs::remove_file(out.join("tables/match.json")).unwrap();
    std::fs::remove_file(out.join("frames/001/medusa-fitted.png")).unwrap();
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &args(true), &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err.matches("taken from the earlier match").count(), 1, "only the first row is whole: {err}");
    // The same rows, but for the renders they took: the resumed match's grid cache starts cold.
    let without_renders = |v: serde_json::Value| {
        let mut rows = v["rows"].as_array().unwrap().clone();
        rows.iter_mut().for_each(|r| _ = r.as_object_mut().unwrap().remove("renders"));
        rows
    };
    assert_eq!(without_renders(read()), without_renders(first), "the rows fitted again are the same");
    assert!(out.join("frames/001/medusa-fitted.png").is_file());
    // Without --resume every row is fitted again, and what a bigger match left is removed.
    let (stale_frames, stale_sheet) = (out.join("frames/009"), out.join("sheets/brick.png"));
    std::fs::create_dir_all(&stale_frames).unwrap();
    std::fs::write(stale_frames.join("medusa-source.png"), b"old").unwrap();
    std::fs::write(&stale_sheet, b"old").unwrap();
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &args(false), &[]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("taken from the earlier match"), "{err}");
    assert!(!stale_frames.exists() && !stale_sheet.exists());
    assert!(out.join("frames/002/medusa-fitted.png").is_file() && out.join("sheets/gold.png").is_file());
}

#[test]
fn the_match_command_sets_the_pipelines_up_as_the_matrix_does() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    // HDRP reading URP's intensities as they are meant: on the linear image the calibrated
    // exposure is the units' ratio, about 1e-4 (8.70e-5 measured through `fit` above).
    let body = "name = \"m\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
        presets = [\"plastic\"]\n[pipeline_settings.hdrp]\nlight_unit = \"unity\"\n";
    let matrix = crate::common::write_matrix(tmp.path(), "m", body);
    let out = tmp.path().join("out");
    let args =
        ["match", "--from", "urp/lit", "--to", "hdrp/lit", matrix.to_str().unwrap(), "--out", out.to_str().unwrap()];
    let (code, _, err) = crate::common::shadematrix(
        tmp.path(),
        &[&args[..], &["--space", "linear", "--size", "32", "--iterations", "0"]].concat(),
        &[],
    );
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("tables/match.json")).unwrap()).unwrap();
    let k = json["exposure"].as_f64().unwrap();
    eprintln!("URP → HDRP (light_unit unity) through the command: exposure {k:.4e}");
    assert!((k * 1e4 - 1.0).abs() < 0.25, "exposure {k} against 1e-4");
}
