//! An interrupted run loses nothing that finished: --resume renders only what is missing.

use shadematrix::run::runner::{run, RunOptions};

#[test]
fn resume_renders_only_unfinished_cells() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = crate::common::write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"r\"\ncompositions = [\"medusa\"]\npipelines = [\"builtin\"]\nshaders = [\"lambert\", \"standard\"]\npresets = [\"gold\", \"plastic\"]\n[image]\nwidth = 24\nheight = 24\n",
    );
    let matrix = crate::common::load_matrix(&m);
    let out = tmp.path().join("run");
    let opts = RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() };
    let first = run(&matrix, &opts).unwrap();
    assert_eq!(first.counts.rendered, 4);
    let cells = out.join("cells");
    let victim = cells.join("medusa__builtin-forward__standard__plastic__m0.00_s0.75_i1_r10");
    let before = std::fs::read(victim.join("image.exr")).unwrap();
    // Interrupted while writing this cell: its record never landed.
    std::fs::remove_file(victim.join("cell.json")).unwrap();
    std::fs::remove_file(victim.join("image.png")).unwrap();

    let again = run(&matrix, &RunOptions { resume: true, ..opts.clone() }).unwrap();
    assert_eq!((again.counts.rendered, again.counts.resumed), (1, 3));
    assert_eq!(std::fs::read(victim.join("image.exr")).unwrap(), before, "deterministic re-render");
    assert!(victim.join("cell.json").is_file() && victim.join("image.png").is_file());

    let run_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(run_json["status"], "complete");
    assert_eq!(run_json["counts"]["resumed"], 3);
}

/// The same matrix run twice into two folders: every cell's EXR and PNG byte for byte the same
/// (EXR blocks are written in a fixed order, whatever the encoder's threads do: 144² is several
/// blocks).
#[test]
fn two_runs_of_one_matrix_write_the_same_image_bytes() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"twice\"\ncompositions = [\"default\", \"mitsuba\"]\npipelines = [\"builtin\", \"hdrp\"]\nshaders = [\"lambert\", \"standard\", \"lit\"]\npresets = [\"gold\"]\n[image]\nwidth = 144\nheight = 144\n";
    // Rendered twice: the cell cache would otherwise hand the second run the first one's files.
    let a = crate::common::run_matrix_with(tmp.path(), body, "a", &["--no-cache"]);
    let b = crate::common::run_matrix_with(tmp.path(), body, "b", &["--no-cache"]);
    let mut compared = 0;
    for entry in std::fs::read_dir(a.join("cells")).unwrap() {
        let cell = entry.unwrap().file_name();
        for f in ["image.exr", "image.png"] {
            let (x, y) = (a.join("cells").join(&cell).join(f), b.join("cells").join(&cell).join(f));
            assert_eq!(std::fs::read(&x).unwrap(), std::fs::read(&y).unwrap(), "{}", x.display());
            compared += 1;
        }
    }
    assert_eq!(compared, 16, "2 compositions × 4 cells × 2 files");
}
