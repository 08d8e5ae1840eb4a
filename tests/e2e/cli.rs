//! Bad input through the binary: a clear message, exit code 2 (3 for no adapter), no panic, and
//! no output folder left behind.

use crate::common::{fixture, shadematrix, write_matrix};
use std::path::Path;

const GOOD: &str = r#"
name = "t"
compositions = ["medusa"]
pipelines = ["builtin"]
shaders = ["lambert"]
presets = ["gold"]
[image]
width = 16
height = 16
"#;

/// Run `run MATRIX --out DIR` on a matrix derived from GOOD and check the failure.
fn expect_bad(body: &str, code: i32, needles: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(tmp.path(), "m.toml", body);
    let out = tmp.path().join("out");
    let (rc, _stdout, stderr) =
        shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()], &[]);
    assert_eq!(rc, code, "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for n in needles {
        assert!(stderr.contains(n), "missing `{n}` in: {stderr}");
    }
    assert!(!out.exists(), "bad input must not leave an output folder");
}

#[test]
fn good_matrix_runs() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(tmp.path(), "m.toml", GOOD);
    let (rc, stdout, stderr) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("1 rendered"), "{stdout}");
    assert!(tmp.path().join("o/cells/medusa__builtin-forward__lambert__gold__m1.00_s0.90_i1_r10/image.exr").is_file());
}

#[test]
fn toml_syntax_error_names_file_line_and_column() {
    let _timer = crate::common::timed!();
    expect_bad(&GOOD.replace("presets = [\"gold\"]", "presets = [\"gold\""), 2, &["m.toml:7:", "bad input"]);
}

#[test]
fn unknown_names_suggest_the_nearest() {
    let _timer = crate::common::timed!();
    expect_bad(
        &GOOD.replace("\"lambert\"", "\"lambret\""),
        2,
        &["unknown shader `lambret`", "did you mean `lambert`?", "shaders[0]"],
    );
    expect_bad(
        &GOOD.replace("\"medusa\"", "\"medusaa\""),
        2,
        &["unknown composition `medusaa`", "did you mean `medusa`?"],
    );
    expect_bad(&GOOD.replace("\"builtin\"", "\"urpp\""), 2, &["unknown pipeline `urpp`", "did you mean `urp`?"]);
    expect_bad(&GOOD.replace("\"gold\"", "\"gld\""), 2, &["unknown preset `gld`", "did you mean `gold`?", "rubber"]);
    expect_bad(
        &GOOD.replace("[image]", "pipeline = \"x\"\n[image]"),
        2,
        &["unknown field `pipeline`", "did you mean `pipelines`?"],
    );
    expect_bad(
        &format!("{GOOD}\n[[only]]\nshadr = \"lambert\"\n"),
        2,
        &["unknown filter axis `shadr`", "did you mean `shader`?"],
    );
}

#[test]
fn out_of_range_values_name_key_value_and_range() {
    let _timer = crate::common::timed!();
    expect_bad(&format!("{GOOD}[sweep]\nmetallic = [0.5, 1.5]\n"), 2, &["sweep.metallic[1]", "1.5", "0..=1"]);
    expect_bad(&format!("{GOOD}[sweep]\nsmoothness = [-0.1]\n"), 2, &["sweep.smoothness[0]", "-0.1"]);
    expect_bad(&format!("{GOOD}[sweep]\ncolor = [[0.2, 1.2, 0.0]]\n"), 2, &["sweep.color[0]", "0..=1"]);
    expect_bad(&format!("{GOOD}[sweep]\nlight_intensity = [-1.0]\n"), 2, &["sweep.light_intensity[0]", "-1"]);
    expect_bad(&format!("{GOOD}[sweep]\nlight_range = [-2.0]\n"), 2, &["sweep.light_range[0]", "-2"]);
    expect_bad(&GOOD.replace("width = 16", "width = 0"), 2, &["image.width", "value 0", "1..=8192"]);
    expect_bad(&GOOD.replace("height = 16", "height = 9000"), 2, &["image.height", "9000", "1..=8192"]);
}

fn gltf_matrix(dir: &Path, mesh_path: &str) -> String {
    let scene = std::fs::read_to_string(fixture("gltf_scene.toml")).unwrap().replace("MESH_PATH", mesh_path);
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    GOOD.replace("\"medusa\"", "\"scene.toml\"")
}

#[test]
fn missing_or_empty_gltf_names_the_resolved_path() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = gltf_matrix(tmp.path(), "meshes/nope.glb");
    let m = write_matrix(tmp.path(), "m.toml", &body);
    let (rc, _, stderr) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("meshes/nope.glb") && stderr.contains("not found"), "{stderr}");
    assert!(stderr.contains(tmp.path().to_str().unwrap()), "the path as resolved: {stderr}");

    std::fs::copy(fixture("empty.gltf"), tmp.path().join("empty.gltf")).unwrap();
    let body = gltf_matrix(tmp.path(), "empty.gltf");
    let m = write_matrix(tmp.path(), "m.toml", &body);
    let (rc, _, stderr) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o2"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("empty.gltf") && stderr.contains("no triangles"), "{stderr}");
    assert!(!tmp.path().join("o2/run.json").exists());
}

#[test]
fn no_usable_adapter_exits_3_with_install_help() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(tmp.path(), "m.toml", GOOD);
    let (rc, _, stderr) = shadematrix(
        tmp.path(),
        &["run", m.to_str().unwrap(), "--out", "o"],
        &[("SHADEMATRIX_ADAPTER", "no-such-adapter-anywhere")],
    );
    assert_eq!(rc, 3, "{stderr}");
    assert!(stderr.contains("no usable GPU adapter") && stderr.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(!tmp.path().join("o").exists());
}

#[test]
fn missing_matrix_file_is_bad_input() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let (rc, _, stderr) = shadematrix(tmp.path(), &["run", "nope.toml"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("nope.toml") && stderr.contains("cannot read"), "{stderr}");
}

#[test]
fn a_new_run_refuses_a_folder_that_holds_a_run() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(tmp.path(), "m.toml", GOOD);
    let args = ["run", m.to_str().unwrap(), "--out", "o"];
    assert_eq!(shadematrix(tmp.path(), &args, &[]).0, 0);
    let (rc, _, stderr) = shadematrix(tmp.path(), &args, &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("--resume"), "{stderr}");
    let (rc, stdout, _) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o", "--resume"], &[]);
    assert_eq!(rc, 0);
    assert!(stdout.contains("0 rendered") && stdout.contains("1 resumed"), "{stdout}");
}

#[test]
fn scene_file_errors_name_the_scene_file() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(fixture("black_room.toml")).unwrap().replace("\"uv_sphere\"", "\"uv_sphre\"");
    std::fs::write(tmp.path().join("s.toml"), scene).unwrap();
    let m = write_matrix(tmp.path(), "m.toml", &GOOD.replace("\"medusa\"", "\"s.toml\""));
    let (rc, _, stderr) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(
        stderr.contains("s.toml:") && stderr.contains("uv_sphre") && stderr.contains("did you mean `uv_sphere`?"),
        "{stderr}"
    );

    let scene =
        std::fs::read_to_string(fixture("black_room.toml")).unwrap().replace("intensity = 2.0", "intensity = -2.0");
    std::fs::write(tmp.path().join("s.toml"), scene).unwrap();
    let (rc, _, stderr) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("lights[0].intensity") && stderr.contains("-2"), "{stderr}");
    assert!(!tmp.path().join("o").exists());
}

#[test]
fn tonemap_parameter_and_colour_errors_name_key_value_and_what_is_allowed() {
    let _timer = crate::common::timed!();
    expect_bad(
        &GOOD.replace("[image]", "tonemap = \"acse\"\n[image]"),
        2,
        &["tonemap", "`acse`", "did you mean `aces`?"],
    );
    expect_bad(
        &GOOD.replace("[image]", "tonemap = { hdrpp = \"aces\" }\n[image]"),
        2,
        &["tonemap.hdrpp", "did you mean `hdrp`?"],
    );
    expect_bad(
        &GOOD.replace("[image]", "antialiasing = { urp = \"msaa3\" }\n[image]"),
        2,
        &["antialiasing.urp", "`msaa3`", "none, msaa2, msaa4, msaa8"],
    );
    let ct = GOOD.replace("\"lambert\"", "\"cook_torrance\"");
    expect_bad(&format!("{ct}[sweep.params]\nirr = [1.5]\n"), 2, &["sweep.params.irr", "did you mean `ior`?"]);
    expect_bad(&format!("{ct}[sweep.params]\nior = [0.5]\n"), 2, &["sweep.params.ior[0]", "0.5", "1..=5"]);
    expect_bad(
        &format!("{GOOD}[sweep.params]\nior = [1.5]\n"),
        2,
        &["sweep.params.ior", "none of the matrix's shaders has parameters"],
    );
    expect_bad(
        &format!("{GOOD}[sweep]\ncolor = [[1.0, 0.0, 0.0]]\n[[only]]\ncolor = \"00ff00\"\n"),
        2,
        &["only[0].color", "`00ff00`", "ff0000"],
    );
    expect_bad(&format!("{GOOD}[[only]]\ncolor = \"red\"\n"), 2, &["only[0].color", "`red` is not a colour"]);
    expect_bad(&format!("{GOOD}[sweep]\nlight_angle = [200.0]\n"), 2, &["sweep.light_angle[0]", "200"]);
}

#[test]
fn light_shape_keys_belong_to_their_kind() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(fixture("black_room.toml"))
        .unwrap()
        .replace("intensity = 2.0", "intensity = 2.0\nangular_diameter_deg = 0.5");
    std::fs::write(tmp.path().join("s.toml"), scene).unwrap();
    let m = write_matrix(tmp.path(), "m.toml", &GOOD.replace("\"medusa\"", "\"s.toml\""));
    let (rc, _, stderr) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("lights[0].angular_diameter_deg") && stderr.contains("directional"), "{stderr}");
}

/// A sweep list may name the scene's own value (`"scene"`, numeric axes that have one) and the
/// preset's colour (`"preset"`); filters match them, so one matrix can sweep the camera distance
/// of some compositions and keep the scene's camera in the others.
#[test]
fn sweep_lists_can_name_the_scenes_and_the_presets_own_value() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let text = "name = \"own\"\ncompositions = [\"default\", \"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\n\
                presets = [\"gold\"]\n[sweep]\ncamera_distance = [\"scene\", 0.3, 0.8]\ncolor = [\"preset\", [1.0, 1.0, 1.0]]\n\
                [[exclude]]\ncomposition = [\"default\"]\ncamera_distance = [0.3, 0.8]\n\
                [[exclude]]\ncomposition = [\"medusa\"]\ncamera_distance = [\"scene\"]\n";
    std::fs::write(tmp.path().join("own.toml"), text).unwrap();
    let (rc, out, err) = crate::common::shadematrix(tmp.path(), &["list", "own.toml"], &[]);
    assert_eq!(rc, 0, "{err}");
    for id in [
        "default__urp-forward__lit__gold__m1.00_s0.90_i2_r10\n",
        "default__urp-forward__lit__gold__m1.00_s0.90_cffffff_i2_r10\n",
        "medusa__urp-forward__lit__gold__m1.00_s0.90_i1_r10_d0.3\n",
        "medusa__urp-forward__lit__gold__m1.00_s0.90_cffffff_i1_r10_d0.8\n",
    ] {
        assert!(out.contains(id), "no {id} in:\n{out}");
    }
    assert!(out.contains("6 cells before twins"), "{out}");
    // Only an axis with a scene value takes "scene".
    std::fs::write(tmp.path().join("bad.toml"), text.replace("[sweep]\n", "[sweep]\nmetallic = [\"scene\"]\n"))
        .unwrap();
    let (rc, _, err) = crate::common::shadematrix(tmp.path(), &["list", "bad.toml"], &[]);
    assert_eq!(rc, 2, "{err}");
    assert!(err.contains("sweep.metallic") && err.contains("\"scene\""), "{err}");
}

/// Every shipped matrix loads and lists (names, scenes, textures, axes and parameters valid):
/// a matrix in `matrices/` that no longer parses fails here rather than in a user's hands.
/// `thesis.toml` is the largest (194400 cells): listed too, with its furnished-room cells.
#[test]
fn every_shipped_matrix_lists() {
    let _timer = crate::common::timed!();
    let repo = crate::common::repo();
    let mut names: Vec<_> = std::fs::read_dir(repo.join("matrices"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 10, "{names:?}");
    for m in &names {
        let (code, out, err) = crate::common::shadematrix(&repo, &["list", m.to_str().unwrap()], &[]);
        assert_eq!(code, 0, "{}: {err}", m.display());
        assert!(out.contains("cells before twins"), "{}: {out}", m.display());
        if m.ends_with("fig3_10.toml") {
            assert!(out.contains("_specular_setup1"), "the specular cells: {out}");
        }
        if m.ends_with("thesis.toml") {
            assert!(out.contains("\n  composite__hdrp-forward__lit__"), "the furnished room's cells");
        }
        if m.ends_with("sliders.toml") {
            // One slider at a time stays affordable where the grid of its lists (267 300 per
            // pipeline × shader × preset) would not.
            let total: usize = out
                .lines()
                .find_map(|l| l.split_once(" cells before twins").and_then(|(n, _)| n.trim().parse().ok()))
                .expect("a count");
            assert!((10_000..40_000).contains(&total), "{total} cells");
            assert!(
                out.contains("\n  medusa__hdrp-forward__lit__gold__") && out.contains("_d0.425"),
                "distance slides: {out}"
            );
        }
        if m.ends_with("hdrp_materials.toml") {
            assert!(out.contains("_iridescence") && out.contains("_anisotropy"), "the material types: {out}");
        }
    }
}
