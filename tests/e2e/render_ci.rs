//! `matrices/ci.toml` renders for real on the available adapter (lavapipe in CI), and its reports
//! rebuilt from the records are byte for byte the ones the run wrote.

use shadematrix::images::encode::read_exr;
use shadematrix::record::{CellRecord, RunRecord};
use shadematrix::run::{run, RunOptions};
use std::collections::BTreeSet;

#[test]
fn ci_matrix_renders_every_cell_at_the_requested_size() {
    let _timer = crate::common::timed!();
    let matrix = crate::common::load_matrix(&crate::common::repo().join("matrices/ci.toml"));
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let summary =
        run(&matrix, &RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() })
            .unwrap();
    assert!(summary.counts.rendered > 0 && summary.counts.twins > 0, "{:?}", summary.counts);
    shadematrix::report::build(&out).unwrap();
    // The matrix's [[assert]] invariants hold, and check's JUnit says so.
    let checked = shadematrix::report::check::check(&out, None, Default::default()).unwrap();
    let failed: Vec<_> =
        checked.invariants.iter().filter_map(|i| i.message().map(|m| format!("{}: {m}", i.name))).collect();
    assert!(checked.invariants.len() >= 3 && failed.is_empty(), "{failed:#?}");

    let run_record = RunRecord::load(&out).unwrap();
    assert_eq!(run_record.status.name(), "complete");
    assert!(!run_record.adapter.name.is_empty() && !run_record.adapter.backend.is_empty());
    let stages = run_record.stages.as_ref().expect("a finished run records its stage times");
    assert!(stages.render_ms > 0.0 && stages.encode_ms > 0.0 && stages.metrics_ms > 0.0, "{stages:?}");

    let cells: Vec<_> = std::fs::read_dir(out.join("cells")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(cells.len(), summary.counts.cells);
    let mut compositions = BTreeSet::new();
    for dir in &cells {
        let cell = CellRecord::load(&dir.join("cell.json")).unwrap();
        compositions.insert(cell.composition.clone());
        let png = image::open(dir.join("image.png")).unwrap();
        assert_eq!((png.width(), png.height()), (128, 128), "{}", dir.display());
        let (w, h, px) = read_exr(&dir.join("image.exr")).unwrap();
        assert_eq!((w, h), (128, 128));
        assert!(px.iter().all(|v| v.is_finite()), "{}: non-finite pixels", dir.display());
        assert!(px.chunks(4).any(|p| p[0] > 0.0), "{}: all black", dir.display());
        assert_eq!(cell.stats.nan, 0);
        assert!(cell.stats.subject_pixels > 0, "{}: subject not visible", dir.display());
        crate::e2e::passes::timed_passes_match_the_record(&cell);
    }
    let expected: BTreeSet<String> = ["default", "mitsuba", "medusa", "spikes"].iter().map(|s| s.to_string()).collect();
    assert_eq!(compositions, expected);

    // Reports: maps where a reference exists, GPU times from timestamp queries, plots, sheets, gallery.
    let mut with_reference = 0;
    for dir in &cells {
        let cell = CellRecord::load(&dir.join("cell.json")).unwrap();
        if cell.metrics.ldr.is_some() {
            with_reference += 1;
            assert!(dir.join("flip.png").is_file() && dir.join("ssim.png").is_file(), "{}", dir.display());
            assert!(cell.metrics.ldr_flip().unwrap() >= 0.0);
            assert!(cell.timing.metrics_ms.unwrap() > 0.0);
        } else {
            assert_eq!(cell.metrics.reference.why_missing(), Some("this cell is the reference"), "{}", dir.display());
        }
    }
    assert!(with_reference > cells.len() / 2);
    let perf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("tables/perf.json")).unwrap()).unwrap();
    if run_record.adapter.timestamp_queries {
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
    assert!(std::fs::read_to_string(out.join("gallery.html")).unwrap().contains("data-broken-images"));

    // `report` rebuilds every table, plot, sheet and the gallery from the records: the same bytes.
    let outputs = |dir: &std::path::Path| -> Vec<(String, Vec<u8>)> {
        let mut files = Vec::new();
        for sub in ["tables", "plots", "sheets"] {
            for e in std::fs::read_dir(dir.join(sub)).unwrap() {
                let p = e.unwrap().path();
                files.push((format!("{sub}/{}", p.file_name().unwrap().to_string_lossy()), std::fs::read(&p).unwrap()));
            }
        }
        for page in ["index.html", "gallery.html", "viewer-data.js"] {
            files.push((page.into(), std::fs::read(dir.join(page)).unwrap()));
        }
        files.sort();
        files
    };
    let first = outputs(&out);
    assert!(first.iter().any(|(n, _)| n == "tables/perf.md") && first.iter().any(|(n, _)| n.starts_with("sheets/")));
    for sub in ["tables", "plots", "sheets"] {
        std::fs::remove_dir_all(out.join(sub)).unwrap();
    }
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &["report", "run"], &[]);
    assert_eq!(rc, 0, "{stdout}{stderr}");
    let again = outputs(&out);
    assert_eq!(first.len(), again.len());
    for ((name, a), (_, b)) in first.iter().zip(&again) {
        assert!(a == b, "{name} differs when rebuilt from the records");
    }
}
