//! Records on disk are typed and versioned: a record of another schema version is refused with the
//! file and both versions named, and `--resume` renders such a cell again rather than trusting it.
//! Twins whose original is resumed are copied from the original's files and record.

use shadematrix::record::{CellRecord, RunRecord, CELL_SCHEMA, RUN_SCHEMA};
use shadematrix::run::{run, RunOptions};

const MATRIX: &str = "name = \"v\"\ncompositions = [\"spikes\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"plastic\"]\nreference = { shader = \"lit\" }\n[sweep]\nsmoothness = [0.3, 0.8]\n[image]\nwidth = 16\nheight = 16\n";

fn set_schema(path: &std::path::Path, schema: u32) {
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["schema"] = serde_json::json!(schema);
    std::fs::write(path, serde_json::to_vec(&v).unwrap()).unwrap();
}

#[test]
fn other_schema_versions_are_refused_or_rerendered() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = crate::common::write_matrix(tmp.path(), "m.toml", MATRIX);
    let matrix = crate::common::load_matrix(&m);
    let out = tmp.path().join("run");
    let opts = RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() };
    let first = run(&matrix, &opts).unwrap();
    // lambert × 2 smoothness (one a twin) + lit × 2.
    assert_eq!((first.counts.cells, first.counts.rendered, first.counts.twins), (4, 3, 1));
    let run_record = RunRecord::load(&out).unwrap();
    assert_eq!(run_record.schema, RUN_SCHEMA);

    // Every cell compared with lit at its smoothness; the lit cells are their own reference.
    let cells = out.join("cells");
    let lambert_twin = cells.join("spikes__urp-forward__lambert__plastic__m0.00_s0.80_i1_r10");
    let twin = CellRecord::load(&lambert_twin.join("cell.json")).unwrap();
    assert_eq!(twin.schema, CELL_SCHEMA);
    assert!(twin.twin_of.is_some() && twin.note.is_some());
    // What rendering decided is its original's: lights, samples, shadow maps.
    let original =
        CellRecord::load(&cells.join("spikes__urp-forward__lambert__plastic__m0.00_s0.30_i1_r10/cell.json")).unwrap();
    assert_eq!(twin.antialiasing, original.antialiasing);
    assert_eq!(twin.shadow_maps, original.shadow_maps);
    assert_eq!(twin.lights.len(), original.lights.len());
    assert_eq!(
        twin.metrics.reference_cell().map(|c| c.0.as_str()),
        Some("spikes__urp-forward__lit__plastic__m0.00_s0.80_i1_r10"),
        "a twin is compared with its own reference, not its original's"
    );
    assert!(twin.metrics.ldr_flip().is_some());

    // A record from another version: `report` refuses it, naming the file and both versions.
    let victim = cells.join("spikes__urp-forward__lit__plastic__m0.00_s0.30_i1_r10");
    set_schema(&victim.join("cell.json"), CELL_SCHEMA + 7);
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["report", "run"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    let v = CELL_SCHEMA + 7;
    assert!(
        stderr.contains("s0.30_i1_r10/cell.json")
            && stderr.contains(&format!("schema version {v}"))
            && stderr.contains(&format!("reads version {CELL_SCHEMA}")),
        "{stderr}"
    );
    // `--resume` does not trust it: that cell is rendered again, the rest are kept.
    let again = run(&matrix, &RunOptions { resume: true, ..opts.clone() }).unwrap();
    assert_eq!((again.counts.rendered, again.counts.resumed), (1, 3));
    assert_eq!(CellRecord::load(&victim.join("cell.json")).unwrap().schema, CELL_SCHEMA);

    // A run record of another version is refused too.
    set_schema(&out.join("run.json"), 1);
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["report", "run"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("run.json") && stderr.contains("schema version 1"), "{stderr}");
}

#[test]
fn twins_of_a_resumed_original_are_copied_from_its_files() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = crate::common::write_matrix(tmp.path(), "m.toml", MATRIX);
    let matrix = crate::common::load_matrix(&m);
    let out = tmp.path().join("run");
    let opts = RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() };
    run(&matrix, &opts).unwrap();
    let twin = out.join("cells/spikes__urp-forward__lambert__plastic__m0.00_s0.80_i1_r10");
    let original = out.join("cells/spikes__urp-forward__lambert__plastic__m0.00_s0.30_i1_r10");
    std::fs::remove_dir_all(&twin).unwrap();
    let again = run(&matrix, &RunOptions { resume: true, ..opts }).unwrap();
    assert_eq!((again.counts.rendered, again.counts.resumed), (0, 3));
    assert_eq!(std::fs::read(twin.join("image.exr")).unwrap(), std::fs::read(original.join("image.exr")).unwrap());
    let record = CellRecord::load(&twin.join("cell.json")).unwrap();
    assert!(record.metrics.ldr_flip().is_some(), "the copied twin is compared with its reference");
}
