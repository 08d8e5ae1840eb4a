//! The three kinds of reference: another cell (in render_ci), a supersampled render, an earlier run.

fn cell_json(run: &std::path::Path, id: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(run.join("cells").join(id).join("cell.json")).unwrap()).unwrap()
}

const BASE: &str = "name = \"r\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"plastic\"]\n[image]\nwidth = 40\nheight = 40\n";
const ID: &str = "default__urp-forward__lit__plastic__m0.00_s0.75_i2_r10";

#[test]
fn supersampled_and_earlier_run_references() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = crate::common::write_matrix(tmp.path(), "m.toml", &format!("reference = {{ supersampled = 3 }}\n{BASE}"));
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "ss"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    let ss = tmp.path().join("ss");
    let c = cell_json(&ss, ID);
    assert_eq!(c["metrics"]["reference"]["kind"], "supersampled");
    assert_eq!(c["metrics"]["reference"]["factor"], 3);
    let flip = c["metrics"]["ldr"]["flip"]["mean"].as_f64().unwrap();
    // Aliasing differs from the 3× render, but it is the same picture.
    assert!(flip > 0.0 && flip < 0.2, "FLIP against the supersampled render: {flip}");
    let reference = image::open(ss.join("cells").join(ID).join("reference.png")).unwrap();
    assert_eq!((reference.width(), reference.height()), (40, 40));

    // Against an earlier run of the same matrix: identical renders, FLIP exactly 0.
    let m2 = crate::common::write_matrix(tmp.path(), "m2.toml", &format!("reference = {{ run = \"ss\" }}\n{BASE}"));
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m2.to_str().unwrap(), "--out", "again"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    let c = cell_json(&tmp.path().join("again"), ID);
    assert_eq!(c["metrics"]["reference"]["kind"], "run");
    assert_eq!(c["metrics"]["ldr"]["flip"]["mean"].as_f64(), Some(0.0));
    assert_eq!(c["metrics"]["ldr"]["ssim"]["mean"].as_f64(), Some(1.0));

    // No reference: reported as such, never as error 0.
    let m3 = crate::common::write_matrix(tmp.path(), "m3.toml", BASE);
    assert_eq!(crate::common::shadematrix(tmp.path(), &["run", m3.to_str().unwrap(), "--out", "none"], &[]).0, 0);
    let c = cell_json(&tmp.path().join("none"), ID);
    assert_eq!(c["metrics"]["reference"]["missing"], "the matrix names no reference");
    assert!(c["metrics"]["ldr"].is_null());

    // A bad reference is bad input with the nearest name.
    let m4 = crate::common::write_matrix(tmp.path(), "m4.toml", &format!("reference = {{ shadr = \"lit\" }}\n{BASE}"));
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m4.to_str().unwrap(), "--out", "bad"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("did you mean `shader`?"), "{stderr}");
}
