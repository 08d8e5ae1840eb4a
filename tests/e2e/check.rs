//! `check` against a baseline: a run against itself passes; altering one shader's images in the
//! baseline fails exactly those cells, named in junit.xml.

use std::path::Path;

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

#[test]
fn check_passes_against_itself_and_names_exactly_the_altered_cells() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = crate::common::write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"c\"\ncompositions = [\"default\", \"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"plastic\", \"gold\"]\n[image]\nwidth = 48\nheight = 48\n",
    );
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "run"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(tmp.path().join("run/tables/perf.md").is_file());

    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &["check", "run", "--baseline", "run"], &[]);
    assert_eq!(rc, 0, "{stdout}{stderr}");
    assert!(stdout.contains("0 of 8 cells regressed"), "{stdout}");
    let junit = std::fs::read_to_string(tmp.path().join("run/junit.xml")).unwrap();
    assert_eq!(junit.matches("<testcase ").count(), 8);
    assert!(!junit.contains("<failure"));

    // Baseline where the `lit` shader's output was different: brighten its PNGs.
    copy_dir(&tmp.path().join("run"), &tmp.path().join("baseline"));
    let mut altered = Vec::new();
    for e in std::fs::read_dir(tmp.path().join("baseline/cells")).unwrap() {
        let dir = e.unwrap().path();
        let id = dir.file_name().unwrap().to_string_lossy().to_string();
        if id.contains("__lit__") {
            let mut img = image::open(dir.join("image.png")).unwrap().to_rgba8();
            for p in img.pixels_mut() {
                p.0[0] = p.0[0].saturating_add(60);
            }
            img.save(dir.join("image.png")).unwrap();
            altered.push(id);
        }
    }
    assert_eq!(altered.len(), 4);
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &["check", "run", "--baseline", "baseline"], &[]);
    assert_eq!(rc, 1, "{stdout}{stderr}");
    let junit = std::fs::read_to_string(tmp.path().join("run/junit.xml")).unwrap();
    let failed: Vec<&str> = junit
        .split("<testcase ")
        .skip(1)
        .filter(|t| t.contains("<failure"))
        .map(|t| {
            // `name` is the attribute itself, not the end of `classname`.
            let at = if t.starts_with("name=\"") { 0 } else { t.find(" name=\"").unwrap() + 1 };
            t[at + 6..].split('"').next().unwrap()
        })
        .collect();
    let mut failed: Vec<String> = failed.iter().map(|s| s.to_string()).collect();
    failed.sort();
    altered.sort();
    assert_eq!(failed, altered, "junit.xml names exactly the altered cells");
    let summary = std::fs::read_to_string(tmp.path().join("run/summary.md")).unwrap();
    assert!(summary.contains("4 of 8 cells regressed"), "{summary}");
}
