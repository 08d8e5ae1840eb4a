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
}
