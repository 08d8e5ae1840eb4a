//! Timing classes: one cell per class renders the timed frames, the others one frame and its
//! figures; their images are the same bytes as when every cell is timed.

use std::collections::BTreeMap;

const MATRIX: &str = "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lit\", \"simple_lit\"]\npresets = [\"gold\", \"plastic\", \"rubber\"]\n[sweep]\nsmoothness = [0.2, 0.9]\n[image]\nwidth = 32\nheight = 32\n[timing]\nframes = 3\nwarmup = 1\n";

fn records(run: &std::path::Path) -> BTreeMap<String, shadematrix::record::CellRecord> {
    std::fs::read_dir(run.join("cells"))
        .unwrap()
        .map(|e| {
            let d = e.unwrap().path();
            let r = shadematrix::record::CellRecord::load(&d.join("cell.json")).unwrap();
            (r.id.0.clone(), r)
        })
        .collect()
}

#[test]
fn one_cell_per_timing_class_is_timed_and_images_do_not_change() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let classes = crate::common::run_matrix_with(tmp.path(), MATRIX, "classes", &["--no-cache"]);
    let every = crate::common::run_matrix_with(
        tmp.path(),
        &MATRIX.replace("warmup = 1\n", "warmup = 1\nevery_cell = true\n"),
        "every",
        &["--no-cache"],
    );
    let (a, b) = (records(&classes), records(&every));
    assert_eq!(a.len(), 12);
    // Two shaders: two classes, each timed once; the others carry their class's figures (twins
    // their original's, whichever those are).
    let timed: Vec<&String> =
        a.iter().filter(|(_, r)| r.twin_of.is_none() && r.timing.timed_as.is_none()).map(|(id, _)| id).collect();
    assert_eq!(timed.len(), 2, "{timed:?}");
    for (id, r) in &a {
        assert_eq!(r.timing.frames, 3, "{id}");
        if let Some(t) = &r.timing.timed_as {
            let source = &a[&t.0];
            assert_eq!((&source.shader, source.timing.timed_as.as_ref()), (&r.shader, None), "{id} timed as {t}");
            assert_eq!(r.timing.cpu_wall, source.timing.cpu_wall, "{id}");
        }
        assert!(b[id].timing.timed_as.is_none(), "every_cell: {id} timed as another");
        for f in ["image.exr", "image.png"] {
            assert_eq!(
                std::fs::read(classes.join("cells").join(id).join(f)).unwrap(),
                std::fs::read(every.join("cells").join(id).join(f)).unwrap(),
                "{id}/{f}: one frame instead of warm-up and three"
            );
        }
    }
    let perf = std::fs::read_to_string(classes.join("tables/perf.md")).unwrap();
    assert!(perf.contains("(timed as `"), "{perf}");
}
