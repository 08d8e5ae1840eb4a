//! Fault injection (issue 25): each test does what a hostile but realistic user does — edits a
//! cached file, symlinks a run folder into itself, feeds NaN, tampers with a shard — and checks
//! that the tool refuses or repairs instead of reporting something that was not rendered as
//! labelled. Each was red before its fix.

use std::path::{Path, PathBuf};

use crate::common::{repo, shadematrix, write_matrix};

/// A one-cell matrix on the small textured-plane fixture (16², no reference).
fn small_matrix(dir: &Path, name: &str, extra: &str) -> PathBuf {
    std::fs::copy(crate::common::fixture("textured_plane.toml"), dir.join("plane.toml")).unwrap();
    write_matrix(
        dir,
        &format!("{name}.toml"),
        &format!(
            "name = \"{name}\"\ncompositions = [\"plane.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
             presets = [\"gold\"]\n[image]\nwidth = 16\nheight = 16\n{extra}"
        ),
    )
}

/// A matrix `NAME.toml` of one URP Lit gold cell (16²) on the composition file `composition`.
fn one_cell_matrix(dir: &Path, name: &str, composition: &str) -> PathBuf {
    write_matrix(
        dir,
        &format!("{name}.toml"),
        &format!(
            "name = \"{name}\"\ncompositions = [\"{composition}\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
             presets = [\"gold\"]\n[image]\nwidth = 16\nheight = 16\n"
        ),
    )
}

/// `scene.toml`: the textured-plane fixture with the glTF plane `plane.gltf` as its subject.
fn gltf_plane_scene(dir: &Path) {
    let scene = std::fs::read_to_string(crate::common::fixture("textured_plane.toml")).unwrap().replace(
        "mesh = { kind = \"plane\", size = [2.0, 2.0], subdivisions = 1 }",
        "mesh = { kind = \"gltf\", path = \"plane.gltf\" }",
    );
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
}

/// `m.toml` run as two shards into `s1` and `s2`.
fn run_two_shards(dir: &Path) {
    for k in 1..=2 {
        run_ok(dir, &["run", "m.toml", "--out", &format!("s{k}"), "--shard", &format!("{k}/2"), "--no-cache"]);
    }
}

fn run_ok(dir: &Path, args: &[&str]) -> String {
    let (rc, out, err) = shadematrix(dir, args, &[]);
    assert_eq!(rc, 0, "{args:?}\n{out}\n{err}");
    format!("{out}{err}")
}

fn refused(dir: &Path, args: &[&str], needles: &[&str]) -> String {
    let (rc, out, err) = shadematrix(dir, args, &[]);
    assert_eq!(rc, 2, "{args:?} should exit 2\n{out}\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: `{n}` not in the message:\n{err}");
    }
    err
}

fn counts(run: &Path) -> serde_json::Value {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("run.json")).unwrap()).unwrap();
    json["counts"].clone()
}

fn count(run: &Path, what: &str) -> u64 {
    counts(run)[what].as_u64().unwrap()
}

fn cell_dirs(run: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(run.join("cells"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| !p.file_name().unwrap().to_string_lossy().starts_with('.'))
        .collect();
    v.sort();
    v
}

/// Every file under `dir` (not following links), relative.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let t = e.file_type().unwrap();
            if t.is_dir() {
                stack.push(e.path());
            } else if t.is_file() {
                out.push(e.path());
            }
        }
    }
    out
}

/// The cache entry folder holding `file` (there is one cell in these tests).
fn cached(cache: &Path, file: &str) -> PathBuf {
    let found: Vec<PathBuf> = files_under(cache).into_iter().filter(|p| p.file_name().unwrap() == file).collect();
    assert_eq!(found.len(), 1, "{found:?}");
    found[0].clone()
}

fn make_writable(p: &Path) {
    let mut perm = std::fs::metadata(p).unwrap().permissions();
    #[allow(clippy::permissions_set_readonly_false)]
    perm.set_readonly(false);
    std::fs::set_permissions(p, perm).unwrap();
}

// 1. Cell ids ------------------------------------------------------------------------------------

#[test]
fn ids_are_exact_so_near_values_stay_distinct_cells() {
    let _timer = crate::common::timed!();
    let text =
        "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n\
                [sweep]\nsmoothness = [0.999, 1.0]\nmetallic = [0.0, 0.001]\nlight_intensity = [1.0, 1.00001]\n";
    let m = shadematrix::declarations::matrix::Matrix::from_text(
        "t.toml",
        text,
        None,
        std::sync::Arc::new(shadematrix::shading::Registry::builtin()),
    )
    .unwrap();
    let e = shadematrix::cells::expand(&m);
    assert_eq!(e.cells.len(), 8, "{:?}", e.cells.iter().map(|c| &c.id.0).collect::<Vec<_>>());
    for c in &e.cells {
        // The id's numbers read back as the cell's values.
        let s = c.id.0.split("_s").nth(1).unwrap().split('_').next().unwrap();
        assert_eq!(s.parse::<f64>().unwrap(), c.material.smoothness, "{}", c.id);
        let m = c.id.0.split("__m").nth(1).unwrap().split('_').next().unwrap();
        assert_eq!(m.parse::<f64>().unwrap(), c.material.metallic, "{}", c.id);
        let i = c.id.0.split("_i").nth(1).unwrap().split('_').next().unwrap();
        assert_eq!(i.parse::<f64>().unwrap(), c.light_intensity, "{}", c.id);
    }
    // Colours are named by their 8-bit code: two that share one are refused, naming both.
    let clash = text.replace("[sweep]\n", "[sweep]\ncolor = [[1.0, 0.5, 0.0], [1.0, 0.501, 0.0]]\n");
    let tmp = tempfile::tempdir().unwrap();
    write_matrix(tmp.path(), "c.toml", &clash);
    refused(tmp.path(), &["list", "c.toml"], &["sweep.color[1]", "ff8000", "0.501"]);
}

#[test]
fn the_stability_matrix_lists_and_renders_its_stiff_smoothness_values() {
    let _timer = crate::common::timed!();
    let (rc, out, err) = shadematrix(&repo(), &["list", "matrices/stability.toml"], &[]);
    assert_eq!(rc, 0, "{err}");
    let ids: Vec<&str> =
        out.lines().map(str::trim).filter(|l| l.starts_with("stability_lights__builtin-forward__standard__")).collect();
    for s in ["_s0.00_", "_s0.0001_", "_s0.50_", "_s0.999_", "_s1.00_"] {
        assert!(ids.iter().any(|id| id.contains(s)), "no {s} cell listed among {} ids", ids.len());
    }
    // The run renders the two ends the matrix exists for.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("r");
    let only =
        "composition=stability_lights,pipeline=builtin,path=forward,shader=standard,metallic=0,light_intensity=100,\
                light_range=40,color=ffffff,smoothness=0.0001|1";
    run_ok(&repo(), &["run", "matrices/stability.toml", "--out", out.to_str().unwrap(), "--only", only, "--no-cache"]);
    let mut smoothness: Vec<f64> = cell_dirs(&out)
        .iter()
        .map(|d| shadematrix::record::CellRecord::load(&d.join("cell.json")).unwrap().sliders.smoothness)
        .collect();
    smoothness.sort_by(f64::total_cmp);
    assert_eq!(smoothness, vec![1e-4, 1.0]);
}

// 2. The cache: immutable entries, verified on restore -------------------------------------------

#[test]
fn the_cache_holds_copies_and_drops_an_entry_that_changed() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    let run = |out: &str| {
        run_ok(d, &["run", "m.toml", "--out", out, "--cache", "cache"]);
        d.join(out)
    };
    let a = run("a");
    let cell = cell_dirs(&a).remove(0);
    let png = std::fs::read(cell.join("image.png")).unwrap();
    // A user overwrites a run's image (as `cp` does, through the path): the cache keeps its own.
    std::fs::write(cell.join("image.png"), b"not the image").unwrap();
    assert_eq!(std::fs::read(cached(&d.join("cache"), "image.png")).unwrap(), png, "the edit reached the cache");
    let b = run("b");
    assert_eq!(count(&b, "cached"), 1);
    assert_eq!(std::fs::read(cell_dirs(&b)[0].join("image.png")).unwrap(), png);

    // Each kind of damage to the entry: dropped with a warning, the cell renders, the images are right.
    type Damage<'a> = (&'a str, &'a dyn Fn(&Path));
    let damages: [Damage; 3] = [
        ("image.exr", &|p: &Path| {
            let bytes = std::fs::read(p).unwrap();
            std::fs::write(p, &bytes[..bytes.len() / 2]).unwrap();
        }),
        ("cell.json", &|p: &Path| {
            let text = std::fs::read_to_string(p).unwrap().replacen("\"lit\"", "\"lambert\"", 1);
            std::fs::write(p, text).unwrap();
        }),
        ("image.png", &|p: &Path| std::fs::remove_file(p).unwrap()),
    ];
    for (i, (file, damage)) in damages.iter().enumerate() {
        let p = cached(&d.join("cache"), file);
        make_writable(&p);
        damage(&p);
        let (rc, _, err) = shadematrix(d, &["run", "m.toml", "--out", &format!("damaged{i}"), "--cache", "cache"], &[]);
        assert_eq!(rc, 0, "{err}");
        let out = d.join(format!("damaged{i}"));
        assert!(err.contains("dropped"), "{file}: no warning\n{err}");
        assert_eq!((count(&out, "cached"), count(&out, "rendered")), (0, 1), "{file}");
        assert_eq!(std::fs::read(cell_dirs(&out)[0].join("image.png")).unwrap(), png, "{file}");
        // The re-rendered cell is stored again, whole.
        let again = run(&format!("again{i}"));
        assert_eq!(count(&again, "cached"), 1, "{file}");
    }
}

// 3. The key covers every input ------------------------------------------------------------------

#[test]
fn editing_any_input_the_render_reads_renders_again() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // A glTF subject whose buffer and image have percent-encoded names, as exporters write them.
    crate::common::write_textured_gltf(d);
    std::fs::rename(d.join("plane.bin"), d.join("my mesh.bin")).unwrap();
    std::fs::rename(d.join("base.png"), d.join("my base.png")).unwrap();
    let gltf = std::fs::read_to_string(d.join("plane.gltf"))
        .unwrap()
        .replace("\"plane.bin\"", "\"my%20mesh.bin\"")
        .replace("\"base.png\"", "\"my%20base.png\"");
    std::fs::write(d.join("plane.gltf"), gltf).unwrap();
    gltf_plane_scene(d);
    let brdf = d.join("shaders/brdf");
    std::fs::create_dir_all(&brdf).unwrap();
    for f in ["wrap_diffuse.wgsl", "wrap_diffuse.toml"] {
        std::fs::copy(repo().join("examples/user_models").join(f), brdf.join(f)).unwrap();
    }
    let matrix = "name = \"k\"\ncompositions = [\"scene.toml\"]\npipelines = [\"urp\"]\nshaders = [\"wrap_diffuse\"]\n\
                  presets = [\"own\"]\n[image]\nwidth = 16\nheight = 16\n";
    write_matrix(d, "m.toml", matrix);
    let mut n = 0;
    let mut run = || {
        n += 1;
        let out = format!("r{n}");
        run_ok(d, &["run", "m.toml", "--out", &out, "--cache", "cache"]);
        (count(&d.join(&out), "rendered"), count(&d.join(&out), "cached"))
    };
    assert_eq!(run(), (1, 0));
    assert_eq!(run(), (0, 1), "unchanged: from the cache");
    let edit = |path: &str, f: &dyn Fn(Vec<u8>) -> Vec<u8>| {
        let p = d.join(path);
        let bytes = std::fs::read(&p).unwrap();
        std::fs::write(&p, f(bytes)).unwrap();
    };
    let replace = |from: &'static str, to: &'static str| {
        move |b: Vec<u8>| {
            let t = String::from_utf8(b).unwrap();
            assert!(t.contains(from), "{from} not in {t}");
            t.replacen(from, to, 1).into_bytes()
        }
    };
    type Edit = Box<dyn Fn(Vec<u8>) -> Vec<u8>>;
    let inputs: [(&str, &str, Edit); 6] = [
        ("scene", "scene.toml", Box::new(replace("fov_y_deg = 40.0", "fov_y_deg = 41.0"))),
        (
            "glTF buffer",
            "my mesh.bin",
            Box::new(|mut b: Vec<u8>| {
                b[0] ^= 0x40; // the first vertex's x moves
                b
            }),
        ),
        (
            "glTF image",
            "my base.png",
            Box::new(|_| {
                let mut png = Vec::new();
                image::RgbaImage::from_pixel(8, 8, image::Rgba([0, 255, 0, 255]))
                    .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                    .unwrap();
                png
            }),
        ),
        (
            "user WGSL",
            "shaders/brdf/wrap_diffuse.wgsl",
            Box::new(replace("let w = s.params0.x;", "let w = 0.9 * s.params0.x;")),
        ),
        ("user declaration", "shaders/brdf/wrap_diffuse.toml", Box::new(replace("default = 0.5", "default = 0.25"))),
        ("matrix settings", "m.toml", Box::new(replace("[image]", "[outputs]\nmaps = false\n[image]"))),
    ];
    for (what, path, f) in &inputs {
        edit(path, f.as_ref());
        assert_eq!(run(), (1, 0), "{what} edited: the cell must render again");
    }
    // A preset is part of the cell: another preset is another cell, never a cached one.
    edit("m.toml", &replace("presets = [\"own\"]", "presets = [\"gold\"]"));
    assert_eq!(run(), (1, 0), "preset changed");
}

// 4. --resume removes only its own temporary names ------------------------------------------------

#[test]
fn resume_removes_only_its_own_temp_files_and_follows_no_link() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    run_ok(d, &["run", "m.toml", "--out", "r", "--no-cache"]);
    let run = d.join("r");
    let cell = cell_dirs(&run).remove(0);
    // The user's files outside the run, reached through links in it.
    let outside = d.join("outside");
    std::fs::create_dir_all(&outside).unwrap();
    for f in [".a.tmp1", ".b.cached2", ".c.merge3", "keep.txt"] {
        std::fs::write(outside.join(f), b"mine").unwrap();
    }
    std::os::unix::fs::symlink(&outside, run.join("link")).unwrap();
    std::os::unix::fs::symlink(&outside, cell.join("link")).unwrap();
    std::os::unix::fs::symlink(&outside, run.join("cells/.x.cached9")).unwrap();
    for i in 0..3 {
        std::os::unix::fs::symlink(".", run.join(format!("loop{i}"))).unwrap();
    }
    // Names like the tool's but not its own, and its own in a folder it does not write.
    std::fs::write(cell.join(".notes.tmpx"), b"mine").unwrap();
    std::fs::write(run.join(".tmp"), b"mine").unwrap();
    std::fs::create_dir_all(run.join("mine")).unwrap();
    std::fs::write(run.join("mine/.c.tmp3"), b"mine").unwrap();
    // What a killed run leaves: removed.
    std::fs::write(cell.join(".image.png.tmp999"), b"half").unwrap();
    std::fs::create_dir_all(run.join("cells/.y.cached12")).unwrap();

    let out = std::process::Command::new("timeout")
        .current_dir(d)
        .args(["120", env!("CARGO_BIN_EXE_shadematrix"), "run", "m.toml", "--out", "r", "--resume", "--no-cache"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    for f in [".a.tmp1", ".b.cached2", ".c.merge3", "keep.txt"] {
        assert!(outside.join(f).is_file(), "{f} outside the run was deleted");
    }
    assert!(cell.join(".notes.tmpx").is_file() && run.join(".tmp").is_file() && run.join("mine/.c.tmp3").is_file());
    assert!(run.join("cells/.x.cached9").symlink_metadata().is_ok(), "a link was removed");
    assert!(!cell.join(".image.png.tmp999").exists() && !run.join("cells/.y.cached12").exists());
}

// 5. Integer keys are range-checked ---------------------------------------------------------------

#[test]
fn warmup_is_range_checked() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    small_matrix(tmp.path(), "m", "[timing]\nframes = 1\nwarmup = 4294967295\n");
    refused(tmp.path(), &["list", "m.toml"], &["timing.warmup", "4294967295", "0..=10000"]);
    refused(tmp.path(), &["run", "m.toml", "--out", "r"], &["timing.warmup"]);
    assert!(!tmp.path().join("r").exists(), "nothing is written for bad input");
}

// 6. One writer per run folder ---------------------------------------------------------------------

#[test]
fn a_second_writer_of_a_run_folder_is_refused() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    run_ok(d, &["run", "m.toml", "--out", "r", "--no-cache"]);
    // Another process holds the folder's lock, as a running run does.
    let lock = std::fs::OpenOptions::new().write(true).open(d.join("r/.shadematrix.lock")).unwrap();
    lock.try_lock().unwrap();
    let before = files_under(&d.join("r")).len();
    refused(d, &["run", "m.toml", "--out", "r", "--resume", "--no-cache"], &["another shadematrix process"]);
    refused(d, &["report", "r"], &["another shadematrix process"]);
    std::fs::create_dir_all(d.join("fresh")).unwrap();
    let lock2 = std::fs::File::create(d.join("fresh/.shadematrix.lock")).unwrap();
    lock2.try_lock().unwrap();
    refused(d, &["run", "m.toml", "--out", "fresh", "--no-cache"], &["another shadematrix process"]);
    assert_eq!(files_under(&d.join("r")).len(), before);
    drop(lock);
    run_ok(d, &["run", "m.toml", "--out", "r", "--resume", "--no-cache"]);
}

// 7. A folder the tool did not make ----------------------------------------------------------------

#[test]
fn a_non_empty_folder_that_holds_no_run_is_refused() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    std::fs::create_dir_all(d.join("site/tables")).unwrap();
    std::fs::write(d.join("site/index.html"), b"my page").unwrap();
    std::fs::write(d.join("site/tables/perf.md"), b"my table").unwrap();
    refused(d, &["run", "m.toml", "--out", "site"], &["not empty", "index.html"]);
    assert_eq!(std::fs::read(d.join("site/index.html")).unwrap(), b"my page");
    assert_eq!(std::fs::read(d.join("site/tables/perf.md")).unwrap(), b"my table");
    // An empty folder is fine.
    std::fs::create_dir_all(d.join("empty")).unwrap();
    run_ok(d, &["run", "m.toml", "--out", "empty", "--no-cache"]);
}

// 8. --resume continues the same matrix only -------------------------------------------------------

#[test]
fn resume_refuses_another_matrix_and_sets_aside_cells_outside_the_expansion() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let m = small_matrix(d, "m", "");
    let text = std::fs::read_to_string(&m).unwrap().replace("[\"gold\"]", "[\"gold\", \"plastic\"]");
    std::fs::write(&m, &text).unwrap();
    run_ok(d, &["run", "m.toml", "--out", "r", "--no-cache"]);
    assert_eq!(cell_dirs(&d.join("r")).len(), 2);
    std::fs::write(&m, text.replace("width = 16", "width = 24")).unwrap();
    refused(d, &["run", "m.toml", "--out", "r", "--resume", "--no-cache"], &["matrix.sha256", "--resume"]);
    std::fs::write(&m, &text).unwrap();
    let said = run_ok(d, &["run", "m.toml", "--out", "r", "--resume", "--no-cache", "--only", "preset=gold"]);
    assert!(said.contains("not in this expansion"), "{said}");
    let run = d.join("r");
    let cells = cell_dirs(&run);
    assert_eq!(cells.len() as u64, count(&run, "cells"), "the reports list what run.json counts");
    assert!(cells.iter().all(|c| c.to_string_lossy().contains("__gold__")));
    assert!(std::fs::read_dir(run.join("cells-not-in-expansion")).unwrap().count() == 1);
    let viewer = std::fs::read_to_string(run.join("viewer-data.js")).unwrap();
    assert!(!viewer.contains("__plastic__"), "the viewer still lists the plastic cell");
}

// 9. merge checks every shard's cells ---------------------------------------------------------------

#[test]
fn merge_refuses_a_shard_missing_a_cell_or_with_a_tampered_label() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.4, 0.6, 0.8]\n");
    run_two_shards(d);
    let s1 = d.join("s1");
    let gone = cell_dirs(&s1).remove(0);
    let name = gone.file_name().unwrap().to_string_lossy().to_string();
    std::fs::rename(&gone, d.join("moved")).unwrap();
    refused(d, &["merge", "s1", "s2", "--out", "merged"], &[&name, "missing"]);
    std::fs::rename(d.join("moved"), &gone).unwrap();
    let record = std::fs::read_to_string(s1.join("run.json")).unwrap();
    for label in ["0/0", "5/3", "3/2"] {
        std::fs::write(s1.join("run.json"), record.replace("\"1/2\"", &format!("\"{label}\""))).unwrap();
        refused(d, &["merge", "s1", "s2", "--out", &format!("merged-{}", label.replace('/', "-"))], &["matrix.shard"]);
    }
    std::fs::write(s1.join("run.json"), &record).unwrap();
    let said = run_ok(d, &["merge", "s1", "s2", "--out", "merged"]);
    assert!(said.contains("4 cells"), "{said}");
}

#[test]
fn an_interrupted_merge_can_be_run_again() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    run_two_shards(d);
    run_ok(d, &["merge", "s1", "s2", "--out", "merged"]);
    // As a merge killed after its first cells leaves it: its record running, a cell half-placed.
    let path = d.join("merged/run.json");
    let text = std::fs::read_to_string(&path).unwrap().replace("\"status\": \"complete\"", "\"status\": \"running\"");
    std::fs::write(&path, text).unwrap();
    std::fs::create_dir_all(d.join("merged/cells/.x.merge77")).unwrap();
    let said = run_ok(d, &["merge", "s1", "s2", "--out", "merged"]);
    assert!(said.contains("2 cells"), "{said}");
    assert!(!d.join("merged/cells/.x.merge77").exists());
    let status: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(status["status"], "complete");
    // A merge into a folder holding another run says what to do, with flags merge has.
    let err = refused(d, &["merge", "s1", "s2", "--out", "s1"], &["already holds a run"]);
    assert!(!err.contains("--resume"), "{err}");
}

// 10. A matrix too large to expand ------------------------------------------------------------------

#[test]
fn a_matrix_of_a_billion_cells_is_refused_before_expanding() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let values: Vec<String> = (0..1000).map(|i| format!("{}", i as f64 / 1000.0)).collect();
    let list = values.join(", ");
    let intensities: Vec<String> = (0..1000).map(|i| format!("{}", i as f64 / 10.0)).collect();
    small_matrix(
        tmp.path(),
        "m",
        &format!(
            "[sweep]\nsmoothness = [{list}]\nmetallic = [{list}]\nlight_intensity = [{}]\n",
            intensities.join(", ")
        ),
    );
    for cmd in [vec!["list", "m.toml"], vec!["run", "m.toml", "--out", "r"]] {
        refused(tmp.path(), &cmd, &["1000000000 cells", "sweep.smoothness 1000", "--max-cells"]);
    }
    // The limit is a flag: a small matrix under a smaller limit is refused, raised it runs.
    small_matrix(tmp.path(), "s", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    refused(tmp.path(), &["list", "s.toml", "--max-cells", "1"], &["2 cells"]);
    run_ok(tmp.path(), &["list", "s.toml", "--max-cells", "2"]);
}

// 11. glTF files read with bounds -----------------------------------------------------------------

#[test]
fn a_gltf_buffer_that_is_a_device_is_refused_unread() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    crate::common::write_textured_gltf(d);
    let original = std::fs::read_to_string(d.join("plane.gltf")).unwrap();
    gltf_plane_scene(d);
    one_cell_matrix(d, "m", "scene.toml");
    let depth = d.canonicalize().unwrap().components().count();
    let relative_zero = format!("{}dev/zero", "../".repeat(depth));
    for uri in ["file:///dev/zero", relative_zero.as_str(), "missing%20file.bin"] {
        std::fs::write(d.join("plane.gltf"), original.replace("\"plane.bin\"", &format!("\"{uri}\""))).unwrap();
        let started = std::time::Instant::now();
        refused(d, &["run", "m.toml", "--out", "r", "--no-cache"], &["plane.gltf", "buffers[0]"]);
        assert!(started.elapsed().as_secs() < 60, "{uri}: read for {:?}", started.elapsed());
    }
}

// 12. Non-finite scene values ---------------------------------------------------------------------

#[test]
fn non_finite_scene_values_are_refused_and_a_frame_without_its_subject_fails_fail_on() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let scene = std::fs::read_to_string(crate::common::fixture("textured_plane.toml")).unwrap();
    one_cell_matrix(d, "m", "s.toml");
    let cases = [
        ("camera.position", "position = [0.0, 2.6, 0.001]", "position = [nan, 2.6, 0.001]"),
        ("camera.target", "target = [0.0, 0.0, 0.0]", "target = [0.0, inf, 0.0]"),
        ("camera.far", "fov_y_deg = 40.0", "fov_y_deg = 40.0\nfar = nan"),
        ("lights[0].position", "kind = \"directional\"", "kind = \"directional\"\nposition = [nan, 0.0, 0.0]"),
        (
            "objects[0].transform.translate",
            "role = \"subject\"",
            "role = \"subject\"\ntransform = { translate = [0.0, -inf, 0.0] }",
        ),
        (
            "objects[0].transform.rotate_deg",
            "role = \"subject\"",
            "role = \"subject\"\ntransform = { rotate_deg = [nan, 0.0, 0.0] }",
        ),
    ];
    for (key, from, to) in cases {
        assert!(scene.contains(from), "{from}");
        std::fs::write(d.join("s.toml"), scene.replacen(from, to, 1)).unwrap();
        refused(d, &["list", "m.toml"], &[key, "finite"]);
    }
    // A camera that looks away from the subject: no NaN anywhere, and still not a result.
    std::fs::write(d.join("s.toml"), scene.replace("target = [0.0, 0.0, 0.0]", "target = [0.0, 5.0, 0.0]")).unwrap();
    let (rc, _, err) = shadematrix(d, &["run", "m.toml", "--out", "r", "--no-cache", "--fail-on", "nan,inf"], &[]);
    assert_eq!(rc, 1, "{err}");
    assert!(err.contains("no subject pixel"), "{err}");
}

// 13. CI thresholds -------------------------------------------------------------------------------

#[test]
fn check_refuses_non_finite_thresholds() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    run_ok(d, &["run", "m.toml", "--out", "r", "--no-cache"]);
    for (flag, v) in [("--flip-mean", "nan"), ("--ssim-min", "nan"), ("--flip-mean", "inf"), ("--ssim-min", "-inf")] {
        refused(d, &["check", "r", "--baseline", "r", &format!("{flag}={v}")], &[flag]);
    }
    run_ok(d, &["check", "r", "--baseline", "r", "--flip-mean", "0.01"]);
}

// 14. User model declarations ---------------------------------------------------------------------

#[test]
fn a_user_model_with_two_params_in_one_slot_or_one_name_twice_is_refused() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let brdf = tmp.path().join("models");
    std::fs::create_dir_all(&brdf).unwrap();
    std::fs::copy(repo().join("examples/user_models/wrap_diffuse.wgsl"), brdf.join("wrap_diffuse.wgsl")).unwrap();
    let decl = std::fs::read_to_string(repo().join("examples/user_models/wrap_diffuse.toml")).unwrap();
    let second = |name: &str, slot: u32| {
        format!("{decl}\n[[params]]\nname = \"{name}\"\nslot = {slot}\ndefault = 0.0\nmin = 0.0\nmax = 1.0\n")
    };
    std::fs::write(brdf.join("wrap_diffuse.toml"), second("tint", 0)).unwrap();
    refused(tmp.path(), &["shaders", "--models", "models"], &["wrap_diffuse.toml", "params[1].slot", "slot 0"]);
    std::fs::write(brdf.join("wrap_diffuse.toml"), second("wrap", 1)).unwrap();
    refused(tmp.path(), &["shaders", "--models", "models"], &["wrap_diffuse.toml", "params[1].name", "twice"]);
    std::fs::write(brdf.join("wrap_diffuse.toml"), second("tint", 1)).unwrap();
    run_ok(tmp.path(), &["shaders", "--models", "models"]);
    // A binding of its own matches no bind group of the passes: bad input naming the file, not a
    // device error.
    let wgsl = std::fs::read_to_string(brdf.join("wrap_diffuse.wgsl")).unwrap();
    std::fs::write(
        brdf.join("wrap_diffuse.wgsl"),
        format!("@group(3) @binding(0) var<storage, read> extra: array<f32>;\n{wgsl}"),
    )
    .unwrap();
    refused(tmp.path(), &["shaders", "--models", "models"], &["wrap_diffuse.wgsl", "@group(3) @binding(0)"]);
}

// Low: the rest of the issue's list ----------------------------------------------------------------

#[test]
fn records_are_byte_stable_through_a_read_and_a_write() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    small_matrix(tmp.path(), "m", "[sweep]\nsmoothness = [0.1, 0.3, 0.7]\nlight_intensity = [0.3]\n");
    run_ok(tmp.path(), &["run", "m.toml", "--out", "r", "--no-cache"]);
    for cell in cell_dirs(&tmp.path().join("r")) {
        let bytes = std::fs::read(cell.join("cell.json")).unwrap();
        let record = shadematrix::record::CellRecord::load(&cell.join("cell.json")).unwrap();
        assert_eq!(serde_json::to_vec_pretty(&record).unwrap(), bytes, "{}", cell.display());
    }
}

#[test]
fn bad_paths_and_filters_are_refused_up_front() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    refused(d, &["list", "m.toml", "--models", "no-such-folder"], &["--models", "no-such-folder"]);
    let text = std::fs::read_to_string(d.join("m.toml")).unwrap();
    std::fs::write(d.join("r.toml"), text.replace("[image]", "reference = { run = \"not-a-run\" }\n[image]")).unwrap();
    std::fs::create_dir_all(d.join("not-a-run")).unwrap();
    refused(d, &["list", "r.toml"], &["reference.run", "not a run folder"]);
    small_matrix(d, "n", "[[only]]\nsmoothness = nan\n");
    refused(d, &["list", "n.toml"], &["only[0].smoothness", "finite"]);
    // A composition name as long as a file name allows makes ids longer than one: refused before
    // anything renders or is written.
    let long = "p".repeat(250);
    let scene = std::fs::read_to_string(crate::common::fixture("textured_plane.toml"))
        .unwrap()
        .replace("name = \"textured_plane\"", &format!("name = \"{long}\""));
    std::fs::write(d.join("long.toml"), scene).unwrap();
    one_cell_matrix(d, "l", "long.toml");
    refused(d, &["run", "l.toml", "--out", "long"], &["longer than a file name"]);
    assert!(!d.join("long").exists());
    // A FIFO would block the reader forever: it is not a scene.
    let fifo = d.join("fifo.toml");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    one_cell_matrix(d, "f", "fifo.toml");
    refused(d, &["list", "f.toml"], &["fifo.toml", "not a regular file"]);
}

#[test]
fn a_closed_stdout_ends_quietly() {
    let _timer = crate::common::timed!();
    // `| head` that has read enough: the reader is gone before the tool writes its first line.
    let compare = crate::common::fixture("compare");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_shadematrix"))
        .args(["diff", compare.join("render_a.png").to_str().unwrap(), compare.join("render_b.png").to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // And a long listing cut short.
    let out = std::process::Command::new("bash")
        .current_dir(repo())
        .args([
            "-c",
            &format!(
                "'{}' list matrices/stability.toml | head -c 100 > /dev/null; echo \"rc=${{PIPESTATUS[0]}}\"",
                env!("CARGO_BIN_EXE_shadematrix")
            ),
        ])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("rc=0"), "{said}\n{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn reports_say_complete_only_once_written_and_report_clears_a_killed_reports_temp_files() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    run_ok(d, &["run", "m.toml", "--out", "r", "--no-cache"]);
    let run = d.join("r");
    let status = |run: &Path| -> String {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(run.join("run.json")).unwrap()).unwrap();
        v["status"].as_str().unwrap().to_string()
    };
    assert_eq!(status(&run), "complete");
    assert!(run.join("index.html").is_file());
    std::fs::write(run.join("tables/.perf.md.tmp4242"), b"half").unwrap();
    std::fs::write(run.join(".index.html.tmp4242"), b"half").unwrap();
    run_ok(d, &["report", "r"]);
    assert!(!run.join("tables/.perf.md.tmp4242").exists() && !run.join(".index.html.tmp4242").exists());
}

// Issue 46: one spine for every cache and every input --------------------------------------------

/// `args` exits 2 within `secs` with each of `needles` in its message: a read that blocks or never
/// ends fails the test instead of hanging it.
fn refused_soon(dir: &Path, args: &[&str], needles: &[&str], secs: u64) -> String {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_shadematrix"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed().as_secs() > secs {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} still running after {secs} s: it blocked on, or read without end, an input");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(2), "{args:?} should exit 2\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: `{n}` not in the message:\n{err}");
    }
    err
}

fn mkfifo(path: &Path) {
    let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
}

/// Edit `run.json` of `run` as text.
fn edit_run_json(run: &Path, edit: impl Fn(&str) -> String) {
    let p = run.join("run.json");
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, edit(&text)).unwrap();
}

#[test]
fn merge_takes_no_path_and_no_cell_outside_the_expansion_from_a_shard() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    run_two_shards(d);
    std::fs::create_dir_all(d.join("victim")).unwrap();
    std::fs::write(d.join("victim/keep.txt"), b"the user's").unwrap();
    let own = cell_dirs(&d.join("s1"))[0].file_name().unwrap().to_string_lossy().to_string();
    let original = std::fs::read_to_string(d.join("s1/run.json")).unwrap();
    // An id that is a path: refused as no id, and nothing outside --out is touched.
    std::fs::rename(d.join("s1/cells").join(&own), d.join("s1/cells/a")).unwrap();
    edit_run_json(&d.join("s1"), |t| t.replace(&format!("\"{own}\""), "\"a/../../../victim\""));
    refused(d, &["merge", "s1", "s2", "--out", "merged"], &["s1/run.json", "a/../../../victim", "not a cell id"]);
    assert!(d.join("victim/keep.txt").is_file(), "merge removed a folder outside --out");
    // An id of the alphabet that is not a cell of the shard's expansion.
    edit_run_json(&d.join("s1"), |_| original.replace(&format!("\"{own}\""), "\"a\""));
    refused(d, &["merge", "s1", "s2", "--out", "merged2"], &["`a` is not a cell of shard 1/2"]);
    std::fs::rename(d.join("s1/cells/a"), d.join("s1/cells").join(&own)).unwrap();
    std::fs::write(d.join("s1/run.json"), &original).unwrap();
    run_ok(d, &["merge", "s1", "s2", "--out", "merged3"]);
}

#[test]
fn merge_refuses_shards_rendered_from_other_inputs_naming_the_input() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    run_ok(d, &["run", "m.toml", "--out", "s1", "--shard", "1/2", "--no-cache"]);
    // The scene changes between the shards: its light comes from another direction.
    let scene = std::fs::read_to_string(d.join("plane.toml")).unwrap();
    std::fs::write(
        d.join("plane.toml"),
        scene.replace("direction = [0.0, -1.0, -0.2]", "direction = [0.0, -1.0, -0.3]"),
    )
    .unwrap();
    run_ok(d, &["run", "m.toml", "--out", "s2", "--shard", "2/2", "--no-cache"]);
    refused(d, &["merge", "s1", "s2", "--out", "merged"], &["s1/cells", "the composition as parsed", "differs"]);
    assert!(!d.join("merged/run.json").exists());
    // With the scene the first shard read, the second is the odd one out.
    std::fs::write(d.join("plane.toml"), &scene).unwrap();
    refused(d, &["merge", "s1", "s2", "--out", "merged2"], &["s2/cells", "the composition as parsed"]);
}

#[test]
fn inputs_that_are_fifos_or_devices_are_refused_without_blocking() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // The matrix itself.
    mkfifo(&d.join("fifo-matrix.toml"));
    refused_soon(d, &["list", "fifo-matrix.toml"], &["fifo-matrix.toml", "not a regular file"], 60);
    // A user model's WGSL (a FIFO), its declaration (a FIFO), a WGSL linked to /dev/zero.
    small_matrix(d, "m", "");
    for (name, wgsl_fifo) in [("fifo_wgsl", true), ("fifo_decl", false)] {
        let models = d.join(name);
        std::fs::create_dir_all(&models).unwrap();
        let (fifo, regular) = match wgsl_fifo {
            true => (models.join("mine.wgsl"), models.join("mine.toml")),
            false => (models.join("mine.toml"), models.join("mine.wgsl")),
        };
        mkfifo(&fifo);
        std::fs::write(regular, "").unwrap();
        refused_soon(d, &["list", "m.toml", "--models", name], &["mine.", "not a regular file"], 60);
    }
    let zero = d.join("zero");
    std::fs::create_dir_all(&zero).unwrap();
    std::os::unix::fs::symlink("/dev/zero", zero.join("mine.wgsl")).unwrap();
    std::fs::write(zero.join("mine.toml"), "").unwrap();
    refused_soon(d, &["list", "m.toml", "--models", "zero"], &["mine.wgsl", "not a regular file"], 60);
    // A fixed material's glTF maps, and a LOD level's glTF file.
    mkfifo(&d.join("fifo.gltf"));
    let scene = std::fs::read_to_string(crate::common::fixture("textured_plane.toml")).unwrap();
    let material = scene.clone()
        + "\n[[objects]]\nname = \"back\"\nrole = \"fixed\"\nmesh = { kind = \"plane\", size = [1.0, 1.0], subdivisions = 1 }\n\
           material = { base_color_linear = [0.5, 0.5, 0.5], gltf_material = { path = \"fifo.gltf\", index = 0 } }\n";
    std::fs::write(d.join("material.toml"), material).unwrap();
    one_cell_matrix(d, "mat", "material.toml");
    refused_soon(d, &["run", "mat.toml", "--out", "r1", "--no-cache"], &["fifo.gltf", "not a regular file"], 60);
    let lod = scene.replace(
        "mesh = { kind = \"plane\", size = [2.0, 2.0], subdivisions = 1 }",
        "mesh = { kind = \"plane\", size = [2.0, 2.0], subdivisions = 1 }\n\
         lod = { meshes = [{ kind = \"gltf\", path = \"fifo.gltf\" }], transitions = [0.5, 0.1], fade_width = 0.0 }",
    );
    std::fs::write(d.join("lod.toml"), lod).unwrap();
    one_cell_matrix(d, "lodm", "lod.toml");
    refused_soon(d, &["run", "lodm.toml", "--out", "r2", "--no-cache"], &["fifo.gltf", "not a regular file"], 60);
}

#[test]
fn every_file_read_of_the_crate_goes_through_the_bounded_reader() {
    let _timer = crate::common::timed!();
    // What opens a file for reading. The reader (`input::read`) is the one place allowed to.
    let patterns = [
        "fs::read(",
        "fs::read_to_string(",
        "File::open(",
        "image::open(",
        "Gltf::open(",
        "gltf::import(",
        "_from_file(",
        "ImageReader::open(",
        "OpenOptions::new()",
    ];
    // The reader itself, and the run folder's lock (opened to lock, its content never read).
    let allowed = [("src/input/read.rs", ""), ("src/record/layout.rs", "OpenOptions::new()")];
    let mut found = Vec::new();
    for (rel, code) in crate::common::crate_code() {
        if allowed.contains(&(rel.as_str(), "")) {
            continue;
        }
        for (i, line) in code.lines().enumerate() {
            let line = line.split("//").next().unwrap_or("");
            let bypass = patterns.iter().find(|pat| line.contains(*pat) && !allowed.contains(&(rel.as_str(), **pat)));
            if let Some(pat) = bypass {
                found.push(format!("{rel}:{}: `{pat}`", i + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "file reads outside input::read (use it: regular files only, bounded):\n{}",
        found.join("\n")
    );
}

/// `args` run with every file it writes limited to `max_bytes` (as a full disk refuses writes:
/// EFBIG, the signal ignored); returns (exit code, stderr).
fn shadematrix_with_small_disk(dir: &Path, args: &[&str], max_bytes: u64) -> (i32, String) {
    use std::os::unix::process::CommandExt;
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_shadematrix"));
    cmd.current_dir(dir).args(args);
    unsafe {
        cmd.pre_exec(move || {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit { rlim_cur: max_bytes, rlim_max: max_bytes };
            match libc::setrlimit(libc::RLIMIT_FSIZE, &limit) {
                0 => Ok(()),
                _ => Err(std::io::Error::last_os_error()),
            }
        });
    }
    let out = cmd.output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).to_string())
}

#[test]
fn a_write_error_while_restoring_keeps_every_valid_cache_entry() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.4, 0.6, 0.8]\n");
    run_ok(d, &["run", "m.toml", "--out", "a", "--cache", "cache"]);
    let entries = files_under(&d.join("cache")).len();
    // The run folder's disk takes run.json (2 KB) but no cell record (5 KB): restoring fails.
    let (rc, err) = shadematrix_with_small_disk(d, &["run", "m.toml", "--out", "full", "--cache", "cache"], 4096);
    assert_ne!(rc, 0, "{err}");
    assert!(!err.contains("dropped"), "a write error at the destination dropped a cache entry:\n{err}");
    assert_eq!(files_under(&d.join("cache")).len(), entries, "cache files were removed\n{err}");
    let b = d.join("b");
    run_ok(d, &["run", "m.toml", "--out", "b", "--cache", "cache"]);
    assert_eq!(count(&b, "cached"), 4);
}

#[test]
fn a_cache_folder_that_cannot_be_written_warns_once_and_the_run_goes_on() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    // A file where the cache folder would be: nothing can be stored there (as a full or read-only
    // folder refuses writes, which root's permissions would not show).
    std::fs::write(d.join("cache"), b"not a folder").unwrap();
    let (rc, out, err) = shadematrix(d, &["run", "m.toml", "--out", "a", "--cache", "cache"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    assert_eq!(err.matches("cannot be written").count(), 1, "one warning, not one per cell:\n{err}");
    assert_eq!(count(&d.join("a"), "rendered"), 2);
}

/// A one-cell truth matrix: URP Lambert on the textured plane against a same-BRDF truth.
fn truth_matrix(dir: &Path) {
    std::fs::copy(crate::common::fixture("textured_plane.toml"), dir.join("plane.toml")).unwrap();
    write_matrix(
        dir,
        "t.toml",
        "name = \"t\"\ncompositions = [\"plane.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\"]\n\
         presets = [\"plastic\"]\nreference = { truth = \"same-brdf\", spp = 16, noise = 0.05, bounces = 1 }\n\
         [image]\nwidth = 16\nheight = 16\n",
    );
}

fn flip_mean(cell: &Path) -> f64 {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cell.join("cell.json")).unwrap()).unwrap();
    json["metrics"]["ldr"]["flip"]["value"]["mean"]
        .as_f64()
        .or_else(|| json["metrics"]["ldr"]["flip"]["mean"].as_f64())
        .unwrap_or_else(|| panic!("no FLIP mean in {}", json["metrics"]))
}

#[test]
fn a_tampered_truth_is_dropped_and_traced_again_and_cells_follow_their_truth() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    truth_matrix(d);
    run_ok(d, &["run", "t.toml", "--out", "a", "--cache", "cache"]);
    let a = cell_dirs(&d.join("a")).remove(0);
    let truth_png = std::fs::read(a.join("reference.png")).unwrap();
    let exr = cached(&d.join(".truth-cache"), "truth.exr");
    // The truth scaled (a swapped file would do as well): twice the radiance, its noise kept.
    make_writable(&exr);
    let (w, h, mut px) = shadematrix::images::encode::read_exr(&exr).unwrap();
    px.chunks_exact_mut(4).for_each(|p| p[..3].iter_mut().for_each(|v| *v *= 2.0));
    std::fs::write(&exr, shadematrix::images::encode::exr_bytes(w, h, &px).unwrap()).unwrap();
    // A cell not in the cell cache reads the truth: the swapped one is not served.
    let (rc, _, err) = shadematrix(d, &["run", "t.toml", "--out", "c", "--cache", "other-cache"], &[]);
    assert_eq!(rc, 0, "{err}");
    assert!(err.contains("truth cache entry") && err.contains("dropped"), "no warning:\n{err}");
    let c = cell_dirs(&d.join("c")).remove(0);
    assert_eq!(std::fs::read(c.join("reference.png")).unwrap(), truth_png, "the tampered truth was served");
    assert!((flip_mean(&c) - flip_mean(&a)).abs() < 1e-9, "{} vs {}", flip_mean(&c), flip_mean(&a));
    let exr2 = cached(&d.join(".truth-cache"), "truth.exr");
    assert_ne!(shadematrix::images::encode::read_exr(&exr2).unwrap().2, px, "the scaled truth is still stored");
    // The truth the cached cell was compared with is gone: the cell is measured again, not taken.
    std::fs::remove_dir_all(exr2.parent().unwrap()).unwrap();
    run_ok(d, &["run", "t.toml", "--out", "e", "--cache", "cache"]);
    assert_eq!((count(&d.join("e"), "cached"), count(&d.join("e"), "rendered")), (0, 1));
    // …and its entry replaced: the next run takes it.
    run_ok(d, &["run", "t.toml", "--out", "f", "--cache", "cache"]);
    assert_eq!(count(&d.join("f"), "cached"), 1);
}

#[test]
fn a_scaled_bake_is_dropped_not_served() {
    let _timer = crate::common::timed!();
    use shadematrix::render::gi::cache::{BakeCache, BakeCacheRecord, BAKE_CACHE_SCHEMA};
    use shadematrix::render::truth::bake::BAKE_STRIDE;
    let tmp = tempfile::tempdir().unwrap();
    let cache = BakeCache::new(tmp.path().join("bakes"));
    let points = 3;
    let sums: Vec<[[f32; 4]; BAKE_STRIDE]> = (0..points).map(|i| [[i as f32 + 1.0; 4]; BAKE_STRIDE]).collect();
    let key = "ab".repeat(32);
    let record = BakeCacheRecord {
        schema: BAKE_CACHE_SCHEMA,
        key: key.clone(),
        points,
        samples: 8,
        texel_samples: 8,
        bounces: 1,
        seconds: 0.1,
        adapter: "test".into(),
    };
    cache.store(&record, &sums).unwrap();
    assert_eq!(cache.load(&key, points).map(|(s, _)| s), Some(sums.clone()));
    // Every sum doubled, as a scaled file would be.
    let path = tmp.path().join("bakes").join(&key).join("sums.bin");
    make_writable(&path);
    let scaled: Vec<u8> = std::fs::read(&path)
        .unwrap()
        .chunks_exact(4)
        .flat_map(|b| (2.0 * f32::from_le_bytes([b[0], b[1], b[2], b[3]])).to_le_bytes())
        .collect();
    std::fs::write(&path, scaled).unwrap();
    assert!(cache.load(&key, points).is_none(), "a scaled bake was served");
    // Dropped, so a new bake takes its place rather than the broken one staying forever.
    assert!(!path.exists());
    cache.store(&record, &sums).unwrap();
    assert_eq!(cache.load(&key, points).map(|(s, _)| s), Some(sums));
}

#[test]
fn ids_leave_room_for_their_temporary_names() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // An id of 245 bytes: a file name, but `.ID.cachedPID` beside it would not be.
    let prefix_len = "__urp-forward__lit__gold__m1.00_s0.20_i1_r10".len();
    for (len, ok) in [(shadematrix::cells::MAX_ID_BYTES, true), (245, false)] {
        let name = "p".repeat(len - prefix_len);
        let scene = std::fs::read_to_string(crate::common::fixture("textured_plane.toml"))
            .unwrap()
            .replace("name = \"textured_plane\"", &format!("name = \"{name}\""));
        std::fs::write(d.join(format!("s{len}.toml")), scene).unwrap();
        write_matrix(
            d,
            &format!("m{len}.toml"),
            &format!(
                "name = \"m{len}\"\ncompositions = [\"s{len}.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
                 presets = [\"gold\"]\n[image]\nwidth = 16\nheight = 16\n[sweep]\nsmoothness = [0.2]\n"
            ),
        );
        let m = format!("m{len}.toml");
        if !ok {
            refused(d, &["run", &m, "--out", "long"], &["longer than a file name"]);
            continue;
        }
        run_ok(d, &["run", &m, "--out", "a", "--cache", "cache"]);
        assert_eq!(cell_dirs(&d.join("a"))[0].file_name().unwrap().len(), len);
        run_ok(d, &["run", &m, "--out", "b", "--cache", "cache"]);
        assert_eq!(count(&d.join("b"), "cached"), 1, "an id at the limit was not taken from the cache");
        for k in 1..=2 {
            run_ok(d, &["run", &m, "--out", &format!("s{k}"), "--shard", &format!("{k}/2"), "--cache", "cache"]);
        }
        run_ok(d, &["merge", "s1", "s2", "--out", "merged"]);
    }
}

#[test]
fn check_fails_a_run_that_did_not_finish() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    run_ok(d, &["run", "m.toml", "--out", "a", "--no-cache"]);
    // As a killed run leaves it: status running, a cell without its record.
    edit_run_json(&d.join("a"), |t| t.replace("\"status\": \"complete\"", "\"status\": \"running\""));
    std::fs::remove_file(cell_dirs(&d.join("a"))[0].join("cell.json")).unwrap();
    let (rc, out, err) = shadematrix(d, &["check", "a"], &[]);
    assert_eq!(rc, 1, "{out}\n{err}");
    assert!(out.contains("INCOMPLETE") && out.contains("running") && out.contains("1 of its 2 cells"), "{out}");
    let junit = std::fs::read_to_string(d.join("a/junit.xml")).unwrap();
    assert!(junit.contains("complete") && junit.contains("<failure"), "{junit}");
}

#[test]
fn declared_sizes_are_not_trusted_before_reading() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    crate::common::write_textured_gltf(d);
    gltf_plane_scene(d);
    one_cell_matrix(d, "m", "scene.toml");
    let original = std::fs::read_to_string(d.join("plane.gltf")).unwrap();
    // A buffer of 2⁴⁰ declared bytes (the file holds 152): refused, not allocated (it aborted).
    let declared = original.replace("\"byteLength\": 152", "\"byteLength\": 1099511627776");
    assert_ne!(declared, original);
    std::fs::write(d.join("plane.gltf"), declared).unwrap();
    refused_soon(d, &["run", "m.toml", "--out", "r1", "--no-cache"], &["plane.gltf", "buffers[0]"], 60);
    // A GLB whose header claims 3.9 GB: read as the file is (a few bytes), refused.
    let mut glb = b"glTF".to_vec();
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&3_900_000_000u32.to_le_bytes());
    glb.extend_from_slice(&[0; 8]);
    std::fs::write(d.join("plane.glb"), &glb).unwrap();
    let scene = std::fs::read_to_string(d.join("scene.toml")).unwrap().replace("plane.gltf", "plane.glb");
    std::fs::write(d.join("glb.toml"), scene).unwrap();
    one_cell_matrix(d, "g", "glb.toml");
    refused_soon(d, &["run", "g.toml", "--out", "r2", "--no-cache"], &["plane.glb"], 60);
}

#[test]
fn non_finite_negative_or_unbounded_material_and_light_values_are_refused() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let base = std::fs::read_to_string(crate::common::fixture("textured_plane.toml")).unwrap();
    let fixed = |material: &str| {
        format!(
            "{base}\n[[objects]]\nname = \"back\"\nrole = \"fixed\"\nmesh = {{ kind = \"plane\", size = [1.0, 1.0], \
             subdivisions = 1 }}\nmaterial = {{ base_color_linear = [0.5, 0.5, 0.5], {material} }}\n"
        )
    };
    let cases = [
        (fixed("emission_linear = [nan, 0.0, 0.0]"), "material.emission_linear[0]"),
        (fixed("emission_linear = [-1.0, 0.0, 0.0]"), "material.emission_linear[0]"),
        (fixed("map_tiling = [inf, 1.0]"), "material.map_tiling[0]"),
        (fixed("map_offset = [0.0, nan]"), "material.map_offset[1]"),
        (fixed("alpha = 1.5"), "material.alpha"),
        (fixed("surface = \"fade\""), "material.surface"),
        // A transparent fixed object casts no shadow here; the default casts.
        (fixed("surface = \"transparent\", alpha = 0.3"), "objects[1].cast_shadows"),
        (base.replace("intensity = 1.0", "intensity = 1e308"), "lights[0].intensity"),
        (
            base.replace(
                "sky = { kind = \"constant\", color = [0.0, 0.0, 0.0] }\nambient_intensity = 0.0",
                "sky = { kind = \"constant\", color = [0.0, 0.0, 0.0] }\nambient_intensity = 1e308",
            ),
            "environment.ambient_intensity",
        ),
    ];
    for (i, (scene, key)) in cases.iter().enumerate() {
        std::fs::write(d.join(format!("s{i}.toml")), scene).unwrap();
        one_cell_matrix(d, &format!("m{i}"), &format!("s{i}.toml"));
        refused(d, &["list", &format!("m{i}.toml")], &[&format!("s{i}.toml"), key]);
    }
    // A glTF subject's emissive strength and texture transform.
    crate::common::write_textured_gltf(d);
    gltf_plane_scene(d);
    one_cell_matrix(d, "g", "scene.toml");
    let original = std::fs::read_to_string(d.join("plane.gltf")).unwrap();
    for (edit, needle) in [
        (
            original.replace(
                "\"emissiveFactor\": [1, 1, 1]",
                "\"emissiveFactor\": [1, 1, 1], \"extensions\": {\"KHR_materials_emissive_strength\": {\"emissiveStrength\": -5}}",
            ),
            "emissive_strength",
        ),
        (
            original.replace(
                "\"baseColorTexture\": {\"index\": 0}",
                "\"baseColorTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\": {\"scale\": [1e30, 1]}}}",
            ),
            "KHR_texture_transform",
        ),
    ] {
        assert_ne!(edit, original);
        std::fs::write(d.join("plane.gltf"), edit).unwrap();
        refused(d, &["run", "g.toml", "--out", "r", "--no-cache"], &["plane.gltf", needle]);
    }
}

#[test]
fn twins_under_a_truth_get_the_comparison_their_truth_allows() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::copy(crate::common::fixture("textured_plane.toml"), d.join("plane.toml")).unwrap();
    for kind in ["same-brdf", "physical"] {
        let name = format!("t-{kind}");
        write_matrix(
            d,
            &format!("{name}.toml"),
            &format!(
                "name = \"{name}\"\ncompositions = [\"plane.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\"]\n\
                 presets = [\"plastic\"]\nreference = {{ truth = \"{kind}\", spp = 16, noise = 0.05, bounces = 1 }}\n\
                 [image]\nwidth = 16\nheight = 16\n[sweep]\nsmoothness = [0.2, 0.8]\n"
            ),
        );
        run_ok(d, &["run", &format!("{name}.toml"), "--out", &name, "--no-cache"]);
        let run = d.join(&name);
        // Lambert ignores smoothness: under a same-BRDF truth (which ignores it too) the second cell
        // is a twin with the original's comparison; a physical truth reads it, so each cell is
        // compared with its own truth.
        // A `--no-cache` run's truths lived in a private folder inside the run, removed at its end
        // (they were in /tmp, where a killed run left them).
        let hidden: Vec<_> = std::fs::read_dir(&run)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .filter(|n| n.starts_with(".truth-cache"))
            .collect();
        assert!(hidden.is_empty(), "{hidden:?}");
        let twins = count(&run, "twins");
        assert_eq!(twins, if kind == "same-brdf" { 1 } else { 0 }, "{kind}");
        let means: Vec<f64> = cell_dirs(&run).iter().map(|c| flip_mean(c)).collect();
        if kind == "same-brdf" {
            assert_eq!(means[0], means[1], "{kind}: {means:?}");
        }
    }
}

#[test]
fn report_and_resume_write_through_no_link_and_a_refused_out_is_left_as_found() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "");
    run_ok(d, &["run", "m.toml", "--out", "a", "--no-cache"]);
    // A finished run's pages say so (they said `reporting`, the status while they were written).
    let gallery = std::fs::read_to_string(d.join("a/gallery.html")).unwrap();
    assert!(gallery.contains("Status: complete"), "{gallery}");
    // A matrix name too long for its run folder is bad input, found before anything is written.
    small_matrix(d, &"n".repeat(240), "");
    refused(d, &["list", &format!("{}.toml", "n".repeat(240))], &["name", "at most 200"]);
    // tables/ made a link to a user's folder: report and --resume refuse to write through it.
    std::fs::create_dir_all(d.join("user")).unwrap();
    std::fs::write(d.join("user/cells.csv"), b"the user's").unwrap();
    std::fs::remove_dir_all(d.join("a/tables")).unwrap();
    std::os::unix::fs::symlink(d.join("user"), d.join("a/tables")).unwrap();
    refused(d, &["report", "a"], &["tables", "symbolic link"]);
    refused(d, &["run", "m.toml", "--out", "a", "--resume", "--no-cache"], &["tables", "symbolic link"]);
    assert_eq!(std::fs::read(d.join("user/cells.csv")).unwrap(), b"the user's");
    // A refused --out keeps no lock file of ours.
    std::fs::create_dir_all(d.join("other")).unwrap();
    std::fs::write(d.join("other/notes.txt"), b"x").unwrap();
    refused(d, &["run", "m.toml", "--out", "other", "--no-cache"], &["not empty"]);
    let names: Vec<String> =
        std::fs::read_dir(d.join("other")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    assert_eq!(names, vec!["notes.txt".to_string()]);
}

#[test]
fn gltf_node_graphs_must_be_forests_and_gltf_lights_are_named_as_theirs() {
    let _timer = crate::common::timed!();
    use crate::e2e::gltf_scene::{room_gltf, scene_text, TILE};
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::write(d.join("room.toml"), scene_text("Vase")).unwrap();
    one_cell_matrix(d, "m", "room.toml");
    let room = room_gltf(TILE, "");
    let floor = "{ \"name\": \"Floor\", \"mesh\": 0,";
    let vase = "{ \"name\": \"Vase\", \"mesh\": 1,";
    assert!(room.contains(floor) && room.contains(vase));
    // The deepest chain: 50 000 empty nodes under the eye. Walked without recursion, it loads.
    let n = 50_000;
    let chain: Vec<String> =
        (0..n).map(|i| if i + 1 < n { format!("{{ \"children\": [{}] }}", 6 + i) } else { "{}".into() }).collect();
    let deep = room
        .replace("{ \"name\": \"Eye\", \"camera\": 0,", "{ \"name\": \"Eye\", \"camera\": 0, \"children\": [5],")
        .replace("\n  ],\n  \"scenes\"", &format!(",\n    {}\n  ],\n  \"scenes\"", chain.join(",\n    ")));
    assert_ne!(deep, room);
    std::fs::write(d.join("room.gltf"), &deep).unwrap();
    run_ok(d, &["list", "m.toml"]);
    let cases = [
        (room.replace(floor, "{ \"name\": \"Floor\", \"children\": [0], \"mesh\": 0,"), "its own child"),
        (
            room.replace(floor, "{ \"name\": \"Floor\", \"children\": [1], \"mesh\": 0,")
                .replace(vase, "{ \"name\": \"Vase\", \"children\": [0], \"mesh\": 1,"),
            "node 0",
        ),
        (
            room.replace(floor, "{ \"name\": \"Floor\", \"children\": [2], \"mesh\": 0,")
                .replace(vase, "{ \"name\": \"Vase\", \"children\": [2], \"mesh\": 1,"),
            "at most one parent",
        ),
        // A spot whose cone is 180°: the message names the glTF light, not a `lights[0]` the
        // scene file does not have.
        (
            room.replace(
                "{ \"name\": \"SunLight\", \"type\": \"directional\",",
                "{ \"name\": \"SunLight\", \"type\": \"spot\", \"spot\": { \"outerConeAngle\": 1.5707963 },",
            ),
            "light `SunLight`",
        ),
    ];
    for (i, (text, needle)) in cases.iter().enumerate() {
        assert_ne!(text, &room, "case {i}");
        std::fs::write(d.join("room.gltf"), text).unwrap();
        let err = refused_soon(d, &["list", "m.toml"], &["room.gltf", needle], 60);
        assert!(!err.contains("lights["), "{err}");
    }
}

#[test]
fn bad_input_found_at_render_time_before_is_refused_up_front() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // A bake past what the adapter binds: exit 2 before any folder is made (a device error failed
    // the run half-way before).
    let cornell = std::fs::read_to_string(crate::common::fixture("cornell_gi.toml")).unwrap();
    std::fs::write(d.join("big.toml"), cornell.replace("texels_per_unit = 4", "texels_per_unit = 200")).unwrap();
    one_cell_matrix(d, "gi", "big.toml");
    refused(
        d,
        &["run", "gi.toml", "--out", "gi", "--no-cache"],
        &["big.toml", "gi.texels_per_unit", "lower texels_per_unit"],
    );
    assert!(!d.join("gi").exists());
    // truth_scene of a composition whose fixed objects have maps: the export cannot carry them.
    crate::common::write_textured_gltf(d);
    let base = std::fs::read_to_string(crate::common::fixture("textured_plane.toml")).unwrap();
    let mapped = format!(
        "{base}\n[[objects]]\nname = \"back\"\nrole = \"fixed\"\nmesh = {{ kind = \"plane\", size = [1.0, 1.0], \
         subdivisions = 1 }}\nmaterial = {{ base_color_linear = [0.5, 0.5, 0.5], base_color_map = \"base.png\" }}\n"
    );
    std::fs::write(d.join("mapped.toml"), mapped).unwrap();
    write_matrix(
        d,
        "ts.toml",
        "name = \"ts\"\ncompositions = [\"mapped.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n\
         reference = { truth = \"physical\", spp = 16 }\n[outputs]\ntruth_scene = true\n[image]\nwidth = 16\nheight = 16\n",
    );
    refused(d, &["list", "ts.toml"], &["outputs.truth_scene", "back", "material maps"]);
}

#[test]
fn report_says_what_it_draws_without_and_a_reference_run_of_another_matrix_is_named() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    small_matrix(d, "m", "[sweep]\nsmoothness = [0.2, 0.8]\n");
    run_ok(d, &["run", "m.toml", "--out", "a", "--no-cache"]);
    let cell = cell_dirs(&d.join("a")).remove(0);
    std::fs::remove_file(cell.join("image.png")).unwrap();
    let said = run_ok(d, &["report", "a"]);
    assert!(said.contains("warning") && said.contains("no image.png"), "{said}");
    // A reference run of another matrix: compared by id, and said so.
    small_matrix(d, "other", "[sweep]\nsmoothness = [0.2, 0.5]\n");
    let text = std::fs::read_to_string(d.join("other.toml"))
        .unwrap()
        .replace("[image]", "reference = { run = \"a\" }\n[image]");
    std::fs::write(d.join("other.toml"), text).unwrap();
    let said = run_ok(d, &["run", "other.toml", "--out", "b", "--no-cache"]);
    assert!(said.contains("another matrix") && said.contains("1 of this run's 2 cells"), "{said}");
}
