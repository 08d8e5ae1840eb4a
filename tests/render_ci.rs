//! `matrices/ci.toml` renders for real on the available adapter (lavapipe in CI).

mod common;

use shadematrix::images::encode::read_exr;
use shadematrix::run::runner::{run, RunOptions};
use shadematrix::spec::matrix::Matrix;
use std::collections::BTreeSet;

#[test]
fn ci_matrix_renders_every_cell_at_the_requested_size() {
    let matrix = Matrix::load(&common::repo().join("matrices/ci.toml")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let summary =
        run(&matrix, &RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() })
            .unwrap();
    assert!(summary.counts.rendered > 0 && summary.counts.twins > 0, "{:?}", summary.counts);

    let run_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(run_json["status"], "complete");
    assert!(!run_json["adapter"]["name"].as_str().unwrap().is_empty());
    assert!(!run_json["adapter"]["backend"].as_str().unwrap().is_empty());

    let cells: Vec<_> = std::fs::read_dir(out.join("cells")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(cells.len(), summary.counts.cells);
    let mut compositions = BTreeSet::new();
    for dir in &cells {
        let cell: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("cell.json")).unwrap()).unwrap();
        compositions.insert(cell["composition"].as_str().unwrap().to_string());
        let png = image::open(dir.join("image.png")).unwrap();
        assert_eq!((png.width(), png.height()), (128, 128), "{}", dir.display());
        let (w, h, px) = read_exr(&dir.join("image.exr")).unwrap();
        assert_eq!((w, h), (128, 128));
        assert!(px.iter().all(|v| v.is_finite()), "{}: non-finite pixels", dir.display());
        assert!(px.chunks(4).any(|p| p[0] > 0.0), "{}: all black", dir.display());
        assert_eq!(cell["stats"]["nan"], 0);
        assert!(cell["stats"]["subject_pixels"].as_u64().unwrap() > 0, "{}: subject not visible", dir.display());
    }
    let expected: BTreeSet<String> = ["default", "mitsuba", "medusa", "spikes"].iter().map(|s| s.to_string()).collect();
    assert_eq!(compositions, expected);

    // Reports: maps where a reference exists, GPU times from timestamp queries, plots, sheets, gallery.
    let mut with_reference = 0;
    for dir in &cells {
        let cell: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("cell.json")).unwrap()).unwrap();
        if cell["metrics"]["ldr"].is_object() {
            with_reference += 1;
            assert!(dir.join("flip.png").is_file() && dir.join("ssim.png").is_file(), "{}", dir.display());
            assert!(cell["metrics"]["ldr"]["flip"]["mean"].as_f64().unwrap() >= 0.0);
        } else {
            assert_eq!(cell["metrics"]["reference"]["missing"], "this cell is the reference", "{}", dir.display());
        }
    }
    assert!(with_reference > cells.len() / 2);
    let perf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("tables/perf.json")).unwrap()).unwrap();
    if run_json["adapter"]["timestamp_queries"] == true {
        for c in perf["cells"].as_array().unwrap() {
            assert!(c["gpu_median_ms"].as_f64().unwrap() > 0.0, "{c}");
        }
    }
    assert!(!perf["groups"].as_array().unwrap().is_empty());
    for comp in &expected {
        let svg = std::fs::read_to_string(out.join(format!("plots/error_vs_time_{comp}.svg"))).unwrap();
        assert!(svg.contains("<circle") && svg.contains("Pareto"), "{comp}");
    }
    assert!(std::fs::read_dir(out.join("sheets")).unwrap().any(|e| e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .starts_with("diff_")));
    assert!(std::fs::read_to_string(out.join("index.html")).unwrap().contains("data-broken-images"));
}
