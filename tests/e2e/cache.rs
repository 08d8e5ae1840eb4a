//! The cell cache across runs (`--cache`): an unchanged matrix run into a new folder takes every
//! cell from the cache; editing one user shader re-renders exactly the cells drawn with it.

use std::path::Path;

fn counts(run: &Path) -> serde_json::Value {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("run.json")).unwrap()).unwrap();
    json["counts"].clone()
}

fn run(dir: &Path, out: &str) -> std::path::PathBuf {
    let (rc, _, stderr) = crate::common::shadematrix(dir, &["run", "m.toml", "--out", out, "--cache", "cache"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    dir.join(out)
}

#[test]
fn editing_one_user_shader_re_renders_exactly_its_cells() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let brdf = tmp.path().join("shaders/brdf");
    std::fs::create_dir_all(&brdf).unwrap();
    for f in ["wrap_diffuse.wgsl", "wrap_diffuse.toml"] {
        std::fs::copy(crate::common::repo().join("examples/user_models").join(f), brdf.join(f)).unwrap();
    }
    // Smoothness is ignored by both diffuse models: half their cells are twins.
    crate::common::write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"k\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"wrap_diffuse\", \"lambert\", \"lit\"]\npresets = [\"gold\", \"plastic\"]\nreference = { shader = \"lit\" }\n[sweep]\nsmoothness = [0.3, 0.8]\n[image]\nwidth = 32\nheight = 32\n",
    );
    let cold = run(tmp.path(), "cold");
    let c = counts(&cold);
    assert_eq!(
        (c["cells"].as_u64(), c["rendered"].as_u64(), c["cached"].as_u64()),
        (Some(12), Some(8), Some(0)),
        "{c}"
    );

    // Unchanged, into a new folder: nothing renders, and the folder holds the same files.
    let warm = run(tmp.path(), "warm");
    let c = counts(&warm);
    assert_eq!((c["rendered"].as_u64(), c["cached"].as_u64()), (Some(0), Some(12)), "{c}");
    let cells: Vec<String> = std::fs::read_dir(cold.join("cells"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    for id in &cells {
        for f in ["image.exr", "image.png", "cell.json"] {
            let (a, b) = (cold.join("cells").join(id).join(f), warm.join("cells").join(id).join(f));
            assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap(), "{}", b.display());
        }
    }

    // One shader edited: its 4 cells (2 of them twins) change, nothing else renders.
    let wgsl = brdf.join("wrap_diffuse.wgsl");
    let text = std::fs::read_to_string(&wgsl).unwrap().replace("let w = s.params0.x;", "let w = 0.5 * s.params0.x;");
    std::fs::write(&wgsl, text).unwrap();
    let edited = run(tmp.path(), "edited");
    let c = counts(&edited);
    assert_eq!((c["rendered"].as_u64(), c["cached"].as_u64()), (Some(2), Some(8)), "{c}");
    let wrap: Vec<&String> = cells.iter().filter(|id| id.contains("__wrap_diffuse__")).collect();
    assert_eq!(wrap.len(), 4);
    for id in &cells {
        let changed = std::fs::read(cold.join("cells").join(id).join("image.exr")).unwrap()
            != std::fs::read(edited.join("cells").join(id).join("image.exr")).unwrap();
        assert_eq!(changed, wrap.contains(&id), "{id}");
    }
}

/// `--retime`: cells from the cache keep their images and metrics and get newly measured timings.
#[test]
fn retime_measures_cached_cells_again_without_changing_their_images() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    crate::common::write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"r\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"gold\"]\nreference = { shader = \"lit\" }\n[image]\nwidth = 24\nheight = 24\n[timing]\nframes = 3\nwarmup = 1\nevery_cell = true\n",
    );
    let cold = run(tmp.path(), "cold");
    let (rc, _, stderr) = crate::common::shadematrix(
        tmp.path(),
        &["run", "m.toml", "--out", "again", "--cache", "cache", "--retime"],
        &[],
    );
    assert_eq!(rc, 0, "{stderr}");
    let again = tmp.path().join("again");
    let c = counts(&again);
    assert_eq!((c["rendered"].as_u64(), c["cached"].as_u64()), (Some(0), Some(2)), "{c}");
    for id in
        ["medusa__urp-forward__lambert__gold__m1.00_s0.90_i1_r10", "medusa__urp-forward__lit__gold__m1.00_s0.90_i1_r10"]
    {
        let load =
            |run: &Path| shadematrix::record::CellRecord::load(&run.join("cells").join(id).join("cell.json")).unwrap();
        let (a, b) = (load(&cold), load(&again));
        assert_eq!(b.timing.frames, 3);
        assert_ne!(a.timing.cpu_wall, b.timing.cpu_wall, "{id}: the timings were not measured again");
        assert_eq!(serde_json::to_string(&a.metrics).unwrap(), serde_json::to_string(&b.metrics).unwrap(), "{id}");
        for f in ["image.exr", "image.png"] {
            let (x, y) = (cold.join("cells").join(id).join(f), again.join("cells").join(id).join(f));
            assert_eq!(std::fs::read(x).unwrap(), std::fs::read(y).unwrap(), "{id}/{f}");
        }
    }
    // The cache still holds the first run's record: retiming wrote through no link.
    let cached = cold.join("cells/medusa__urp-forward__lit__gold__m1.00_s0.90_i1_r10/cell.json");
    let first = shadematrix::record::CellRecord::load(&cached).unwrap();
    let again_record = shadematrix::record::CellRecord::load(
        &again.join("cells/medusa__urp-forward__lit__gold__m1.00_s0.90_i1_r10/cell.json"),
    )
    .unwrap();
    assert_ne!(first.timing.cpu_wall, again_record.timing.cpu_wall);
}
