//! `[[assert]]` invariants: matrices/invariants.toml's hold on this adapter and `check` reports them
//! in its JUnit; the same kinds stated falsely fail with the group that breaks them; a typo in an
//! assert is bad input.

use crate::common::{repo, shadematrix, write_matrix};

/// The invariants matrix, its compositions resolved from the repository, with `asserts` in place
/// of its own and its sweep narrowed to keep the run small.
fn matrix_with(dir: &std::path::Path, asserts: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("matrices/invariants.toml")).unwrap();
    let head =
        text.split("\n[[assert]]").next().unwrap().replace("../scenes/", &format!("{}/scenes/", repo().display()));
    write_matrix(dir, "m.toml", &format!("{head}\n{asserts}"))
}

#[test]
fn the_invariants_matrix_holds_and_check_reports_it_in_junit() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = repo().join("matrices/invariants.toml");
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let table = std::fs::read_to_string(tmp.path().join("r/tables/invariants.md")).unwrap();
    eprintln!("{table}");
    let (rc, out, err) = shadematrix(tmp.path(), &["check", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let junit = std::fs::read_to_string(tmp.path().join("r/junit.xml")).unwrap();
    let suite = junit.split("<testsuite name=\"shadematrix invariants\"").nth(1).and_then(|t| t.split('>').next());
    let suite = suite.unwrap_or_else(|| panic!("no invariants suite:\n{junit}"));
    assert!(suite.contains(" tests=\"5\"") && suite.contains(" failures=\"0\""), "{junit}");
    for kind in ["monotone", "linear", "invariant", "bounded"] {
        assert!(junit.contains(&format!("classname=\"assert.{kind}\"")), "{kind} missing:\n{junit}");
    }
    // The Lambert cells the invariant covers were rendered, not copied as twins of each other.
    let lambert_twins = std::fs::read_dir(tmp.path().join("r/cells"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().contains("__lambert__"))
        .filter(|p| std::fs::read_to_string(p.join("cell.json")).unwrap().contains("\"twin_of\": \"key_only"))
        .count();
    assert_eq!(lambert_twins, 0);
}

#[test]
fn false_invariants_fail_with_the_group_that_breaks_them() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let asserts = r#"
[[assert]]
name = "peak falls with smoothness"
kind = "monotone"
where = { composition = "key_only", shader = "standard" }
along = "smoothness"
direction = "decreasing"

[[assert]]
name = "standard ignores smoothness"
kind = "invariant"
where = { composition = "key_only", shader = "standard", pipeline = "builtin" }
along = "smoothness"

[[assert]]
name = "the furnace scales with a light it does not have"
kind = "linear"
where = { composition = "white_furnace", pipeline = "urp", shader = "lambert" }
along = "light_intensity"

[[assert]]
name = "the furnace is dark"
kind = "bounded"
where = { composition = "white_furnace", pipeline = "builtin" }
measure = "max_value"
max = 0.5

[[assert]]
name = "matches nothing"
kind = "bounded"
where = { composition = "key_only", shader = "simple_lit", pipeline = "hdrp" }
max = 1.0
"#;
    let m = matrix_with(tmp.path(), asserts);
    let only = "smoothness=0.2|0.95,light_intensity=1|2,metallic=1";
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r", "--only", only], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let (rc, out, err) = shadematrix(tmp.path(), &["check", "r"], &[]);
    assert_eq!(rc, 1, "{out}\n{err}");
    for name in [
        "peak falls with smoothness",
        "standard ignores smoothness",
        "the furnace scales with a light it does not have",
        "the furnace is dark",
        "matches nothing",
    ] {
        assert!(out.contains(&format!("assert `{name}`")) && err.contains(name), "{name}:\n{out}\n{err}");
    }
    assert!(out.contains("subject_peak") && out.contains("smoothness = 0.2"), "{out}");
    assert!(out.contains("no cell of the run matches"), "{out}");
    let junit = std::fs::read_to_string(tmp.path().join("r/junit.xml")).unwrap();
    assert!(junit.contains("tests=\"5\" failures=\"5\""), "{junit}");
}

#[test]
fn a_typo_in_an_assert_names_the_key_and_the_nearest_kind() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = matrix_with(tmp.path(), "[[assert]]\nkind = \"monotonic\"\nalong = \"smoothness\"\n");
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 2, "{out}\n{err}");
    assert!(err.contains("assert[0].kind") && err.contains("monotone"), "{err}");
    assert!(!tmp.path().join("r").exists(), "nothing is written for bad input");
    let m = matrix_with(tmp.path(), "[[assert]]\nkind = \"linear\"\nalong = \"smoothness\"\n");
    let (rc, _, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 2, "{err}");
    assert!(err.contains("assert[0].along") && err.contains("light_intensity"), "{err}");
    let m = matrix_with(tmp.path(), "[[assert]]\nkind = \"invariant\"\nalong = \"light_range\"\n");
    let (rc, _, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 2, "{err}");
    assert!(err.contains("assert[0].along") && err.contains("at least 2 values"), "{err}");
    let m = matrix_with(tmp.path(), "[[assert]]\nkind = \"bounded\"\nmax = 1\nalong = \"smoothness\"\n");
    let (rc, _, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 2, "{err}");
    assert!(err.contains("assert[0].along") && err.contains("does not apply"), "{err}");
}
