//! FLIP and SSIM against values measured with the reference implementations (NVIDIA's
//! flip-evaluator, scikit-image) on committed fixture pairs; see tests/fixtures/compare/make_fixtures.py.

use shadematrix::compare::{compare, LoadedImage};

fn fixture(name: &str) -> std::path::PathBuf {
    crate::common::fixture(&format!("compare/{name}"))
}

fn expected() -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(fixture("expected.json")).unwrap()).unwrap()
}

#[test]
fn ldr_flip_and_ssim_match_the_reference_implementations() {
    let _timer = crate::common::timed!();
    let want = expected();
    for pair in ["render", "synthetic"] {
        let a = LoadedImage::load(&fixture(&format!("{pair}_a.png"))).unwrap();
        let b = LoadedImage::load(&fixture(&format!("{pair}_b.png"))).unwrap();
        let c = compare(&a, &b, pair).unwrap();
        let flip = c.flip.value.mean().unwrap();
        let ssim = c.ssim.mean().unwrap();
        let (flip_ref, ssim_ref) =
            (want[pair]["flip_mean"].as_f64().unwrap(), want[pair]["ssim_mean"].as_f64().unwrap());
        eprintln!("{pair}: FLIP {flip} (flip-evaluator {flip_ref}), SSIM {ssim} (scikit-image {ssim_ref})");
        assert!((flip - flip_ref).abs() <= 1e-5, "{pair}: FLIP {flip} vs {flip_ref}");
        assert!((ssim - ssim_ref).abs() <= 1e-4, "{pair}: SSIM {ssim} vs {ssim_ref}");
        assert!(c.flip_map_rgba8.is_some() && c.ssim_map_rgba8.is_some());
    }
}

#[test]
fn hdr_flip_matches_the_reference_implementation() {
    let _timer = crate::common::timed!();
    let want = expected()["hdr"]["flip_mean"].as_f64().unwrap();
    let c = compare(
        &LoadedImage::load(&fixture("hdr_a.exr")).unwrap(),
        &LoadedImage::load(&fixture("hdr_b.exr")).unwrap(),
        "hdr",
    )
    .unwrap();
    let got = c.flip.value.mean().unwrap();
    eprintln!("hdr: FLIP {got} (flip-evaluator {want})");
    assert_eq!(c.flip.kind, "hdr");
    assert!((got - want).abs() <= 1e-5, "HDR-FLIP {got} vs {want}");
    assert!(c.ssim.mean().is_none(), "SSIM on EXR is reported missing, never 0");
}

#[test]
fn identical_images_have_zero_error() {
    let _timer = crate::common::timed!();
    let a = LoadedImage::load(&fixture("synthetic_a.png")).unwrap();
    let c = compare(&a, &a, "same").unwrap();
    assert_eq!(c.flip.value.mean(), Some(0.0));
    assert!((c.ssim.mean().unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(c.psnr_db, None);
}

#[test]
fn diff_command_prints_json_and_writes_maps() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (fixture("render_a.png"), fixture("render_b.png"));
    let out = tmp.path().join("maps");
    let (rc, stdout, stderr) = crate::common::shadematrix(
        tmp.path(),
        &["diff", a.to_str().unwrap(), b.to_str().unwrap(), "--json", "--out", out.to_str().unwrap()],
        &[],
    );
    assert_eq!(rc, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let want = expected();
    assert!((v["flip"]["mean"].as_f64().unwrap() - want["render"]["flip_mean"].as_f64().unwrap()).abs() <= 1e-5);
    assert!((v["ssim"]["mean"].as_f64().unwrap() - want["render"]["ssim_mean"].as_f64().unwrap()).abs() <= 1e-4);
    for map in ["flip.png", "ssim.png"] {
        let img = image::open(out.join(map)).unwrap();
        assert_eq!((img.width(), img.height()), (96, 80), "{map}");
    }
    // Per-channel SSIM on request; a grey-world check: the mean of the channels is near the luma SSIM.
    let (rc, stdout, _) = crate::common::shadematrix(
        tmp.path(),
        &["diff", a.to_str().unwrap(), b.to_str().unwrap(), "--json", "--per-channel"],
        &[],
    );
    assert_eq!(rc, 0);
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let channels: Vec<f64> =
        v["ssim_channels"].as_array().unwrap().iter().map(|c| c["mean"].as_f64().unwrap()).collect();
    assert_eq!(channels.len(), 3);
    assert!(channels.iter().all(|c| *c > 0.5 && *c <= 1.0), "{channels:?}");
    // Mixed kinds and missing files are bad input.
    let exr = fixture("hdr_a.exr");
    let (rc, _, stderr) =
        crate::common::shadematrix(tmp.path(), &["diff", a.to_str().unwrap(), exr.to_str().unwrap()], &[]);
    assert_eq!(rc, 2, "{stderr}");
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["diff", "nope.png", a.to_str().unwrap()], &[]);
    assert_eq!(rc, 2);
    assert!(stderr.contains("nope.png") && stderr.contains("not found"), "{stderr}");
}

/// Across pipelines, HDR metrics compare images as they are shown before tonemapping (each EXR
/// times its own display exposure), never raw EXRs of different units.
#[test]
fn hdr_metrics_across_pipelines_compare_exposed_images() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"x\"\ncompositions = [\"mitsuba\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lit\"]\npresets = [\"plastic\"]\nreference = { pipeline = \"hdrp\" }\n[image]\nwidth = 48\nheight = 48\n";
    let m = crate::common::write_matrix(tmp.path(), "m.toml", body);
    let out = tmp.path().join("run");
    let (code, _, err) =
        crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
    let id = "mitsuba__urp-forward__lit__plastic__m0.00_s0.75_i1.5_r12";
    let record = shadematrix::record::cell::CellRecord::load(&out.join("cells").join(id).join("cell.json")).unwrap();
    let hdr = record.metrics.hdr.as_ref().and_then(|h| h.value()).expect("HDR metrics");
    let (kt, kr) = hdr.exposed.expect("exposed before comparing: URP's units are not HDRP's");
    assert_eq!(kt, 1.0, "URP shows its EXR as it is");
    assert!(kr < 1e-2, "HDRP's metered exposure brings its ×10000 light down: {kr}");
    let flip = hdr.flip.value.mean().unwrap();
    eprintln!("URP vs HDRP Lit, mitsuba: HDR-FLIP {flip:.3} exposed (cell ×{kt}, reference ×{kr:.3e})");
    assert!(flip < 0.9, "HDR-FLIP {flip} of exposed images");
}
