//! Shards merged equal one unsharded run, and a run killed at a random point and resumed equals an
//! uninterrupted one: the same cells, the same image bytes, the same records and metrics (timings
//! aside: they are measurements).

use std::collections::BTreeMap;
use std::path::Path;

/// Reference cells and twins (Lambert ignores smoothness) that fall in other shards than the
/// cells that need them.
const MATRIX: &str = "name = \"sh\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"gold\", \"plastic\"]\nreference = { pipeline = \"hdrp\", shader = \"lit\" }\n[sweep]\nsmoothness = [0.3, 0.8]\n[image]\nwidth = 32\nheight = 32\n";

/// Every file under the run's cells/, by path; records without their timings.
fn cell_files(run: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![run.join("cells")];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let rel = p.strip_prefix(run).unwrap().display().to_string();
            let mut bytes = std::fs::read(&p).unwrap();
            if rel.ends_with("cell.json") {
                let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                v.as_object_mut().unwrap().remove("timing");
                bytes = serde_json::to_vec_pretty(&v).unwrap();
            }
            out.insert(rel, bytes);
        }
    }
    out
}

fn assert_same_cells(a: &Path, b: &Path) {
    let (x, y) = (cell_files(a), cell_files(b));
    let names = |m: &BTreeMap<String, Vec<u8>>| m.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&x), names(&y), "{} vs {}", a.display(), b.display());
    for (k, v) in &x {
        if &y[k] == v {
            continue;
        }
        // Say which fields of a record differ, so a rare failure can be told apart.
        let keys = match (serde_json::from_slice::<serde_json::Value>(v), serde_json::from_slice(&y[k])) {
            (Ok(serde_json::Value::Object(p)), Ok(serde_json::Value::Object(q))) => {
                let differ: Vec<String> = p
                    .iter()
                    .filter(|(f, w)| q.get(*f) != Some(w))
                    .map(|(f, w)| format!("{f}: {} vs {}", w, q.get(f).map_or("absent".into(), |x| x.to_string())))
                    .collect();
                differ.join("; ")
            }
            _ => "bytes".into(),
        };
        panic!("{k} differs between {} and {}: {keys}", a.display(), b.display());
    }
}

#[test]
fn three_shards_merged_equal_one_unsharded_run() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let whole = crate::common::run_matrix_with(tmp.path(), MATRIX, "whole", &["--no-cache"]);
    let mut support = 0;
    for k in 1..=3 {
        let s = crate::common::run_matrix_with(
            tmp.path(),
            MATRIX,
            &format!("s{k}"),
            &["--no-cache", "--shard", &format!("{k}/3")],
        );
        let r: serde_json::Value = serde_json::from_slice(&std::fs::read(s.join("run.json")).unwrap()).unwrap();
        assert_eq!(r["matrix"]["shard"], format!("{k}/3"));
        support += r["counts"]["support"].as_u64().unwrap();
    }
    // Twins of another group's original need it: the shards rendered some cells twice.
    assert!(support > 0, "no support cell: the test does not exercise them");
    let (rc, stdout, stderr) =
        crate::common::shadematrix(tmp.path(), &["merge", "s1", "s2", "s3", "--out", "merged"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("16 cells from 3 shards"), "{stdout}");
    let merged = tmp.path().join("merged");
    assert_same_cells(&whole, &merged);
    assert!(merged.join("index.html").is_file() && merged.join("tables/perf.md").is_file());
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(merged.join("run.json")).unwrap()).unwrap();
    assert_eq!((r["counts"]["cells"].as_u64(), r["counts"]["twins"].as_u64()), (Some(16), Some(4)), "{r}");

    // A missing shard, or a shard of another matrix, is refused (exit 2) naming what is wrong.
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["merge", "s1", "s3", "--out", "m2"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("2/3") && stderr.contains("missing"), "{stderr}");
    let other = crate::common::run_matrix_with(
        tmp.path(),
        &MATRIX.replace("width = 32", "width = 24"),
        "o2",
        &["--no-cache", "--shard", "2/3"],
    );
    let (rc, _, stderr) =
        crate::common::shadematrix(tmp.path(), &["merge", "s1", other.to_str().unwrap(), "s3", "--out", "m3"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("matrix.sha256") && stderr.contains("o2"), "{stderr}");
    assert!(!tmp.path().join("m2/run.json").exists() && !tmp.path().join("m3/run.json").exists());
}

#[test]
fn a_run_killed_at_a_random_point_and_resumed_equals_an_uninterrupted_one() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let whole = crate::common::run_matrix_with(tmp.path(), MATRIX, "whole", &["--no-cache"]);
    let wall: f64 = serde_json::from_slice::<serde_json::Value>(&std::fs::read(whole.join("run.json")).unwrap())
        .unwrap()["wall_seconds"]
        .as_f64()
        .unwrap();
    // A random point of the run (the clock's nanoseconds), printed for a failure to be replayed.
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().subsec_nanos();
    let delay = (0.1 + 0.8 * (nanos % 1000) as f64 / 1000.0) * wall;
    let m = crate::common::write_matrix(tmp.path(), "k.toml", MATRIX);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_shadematrix"))
        .current_dir(tmp.path())
        .args(["run", m.to_str().unwrap(), "--out", "killed", "--no-cache"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs_f64(delay));
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let status = std::fs::read_to_string(tmp.path().join("killed/run.json")).unwrap_or_default();
    let finished = status.contains("\"complete\"");
    let (rc, stdout, stderr) = crate::common::shadematrix(
        tmp.path(),
        &["run", m.to_str().unwrap(), "--out", "killed", "--resume", "--no-cache"],
        &[],
    );
    assert_eq!(rc, 0, "killed after {delay:.2} s: {stderr}");
    assert_same_cells(&whole, &tmp.path().join("killed"));
    println!(
        "killed after {delay:.2} s of a {wall:.2} s run (it had {}finished); resumed: {}",
        if finished { "" } else { "not " },
        stdout.lines().next().unwrap_or("")
    );
}
