//! A WGSL model dropped into shaders/brdf/ (with its declaration) is a shader name in any matrix,
//! with no recompilation; a broken one is bad input naming the file and line.

use std::path::Path;

fn install_example(dir: &Path) {
    let brdf = dir.join("shaders/brdf");
    std::fs::create_dir_all(&brdf).unwrap();
    for f in ["wrap_diffuse.wgsl", "wrap_diffuse.toml"] {
        std::fs::copy(crate::common::repo().join("examples/user_models").join(f), brdf.join(f)).unwrap();
    }
}

const MATRIX: &str = "name = \"u\"\ncompositions = [\"default\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"wrap_diffuse\", \"lambert\"]\npresets = [\"plastic\"]\n[image]\nwidth = 48\nheight = 48\n";

#[test]
fn user_model_renders_in_a_matrix_and_is_audited() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    install_example(tmp.path());
    let m = crate::common::write_matrix(tmp.path(), "m.toml", MATRIX);
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("4 rendered"), "{stdout}");
    let cell = tmp.path().join("o/cells/default__urp-forward__wrap_diffuse__plastic__m0.00_s0.75_i2_r10");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cell.join("cell.json")).unwrap()).unwrap();
    assert_eq!(json["shader_inputs"]["params"]["wrap"], 0.5);
    // Wrapped light reaches past the terminator: brighter than Lambert on average.
    let wrap = image::open(cell.join("image.png")).unwrap().to_rgb8();
    let lambert =
        image::open(tmp.path().join("o/cells/default__urp-forward__lambert__plastic__m0.00_s0.75_i2_r10/image.png"))
            .unwrap()
            .to_rgb8();
    let sum = |im: &image::RgbImage| im.pixels().map(|p| p.0[0] as u64).sum::<u64>();
    assert!(sum(&wrap) > sum(&lambert), "wrap {} vs lambert {}", sum(&wrap), sum(&lambert));

    let (rc, stdout, stderr) =
        crate::common::shadematrix(tmp.path(), &["audit", "--shader", "wrap_diffuse", "--out", "audit"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("`urp/wrap_diffuse`") && stdout.contains("no twin") && stdout.contains("gpu"), "{stdout}");
    let (_, shaders, _) = crate::common::shadematrix(tmp.path(), &["shaders"], &[]);
    assert!(shaders.contains("wrap_diffuse") && shaders.contains("wrap = 0.5"), "{shaders}");
}

#[test]
fn broken_user_model_names_file_line_and_column() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    install_example(tmp.path());
    let wgsl = tmp.path().join("shaders/brdf/wrap_diffuse.wgsl");
    let text = std::fs::read_to_string(&wgsl).unwrap().replace("let w = s.params0.x;", "let w = s.params0.x");
    std::fs::write(&wgsl, text).unwrap();
    let m = crate::common::write_matrix(tmp.path(), "m.toml", MATRIX);
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "o"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("shaders/brdf/wrap_diffuse.wgsl:9:") || stderr.contains("shaders/brdf/wrap_diffuse.wgsl:8:"),
        "{stderr}"
    );
    assert!(stderr.contains("WGSL"), "{stderr}");
    assert!(!tmp.path().join("o").exists());

    // A model without its entry points.
    std::fs::write(&wgsl, "fn something_else() -> f32 { return 1.0; }\n").unwrap();
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("wrap_diffuse.wgsl") && stderr.contains("model_direct"), "{stderr}");

    // A type error, found by validation rather than parsing.
    std::fs::write(
        &wgsl,
        std::fs::read_to_string(crate::common::repo().join("examples/user_models/wrap_diffuse.wgsl"))
            .unwrap()
            .replace("max(0.0, (dot(n, l) + w) / (1.0 + w))", "vec2<f32>(1.0)"),
    )
    .unwrap();
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("wrap_diffuse.wgsl"), "{stderr}");
}

#[test]
fn models_come_from_the_folder_the_user_names() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let mine = tmp.path().join("my_models");
    std::fs::create_dir_all(&mine).unwrap();
    for f in ["wrap_diffuse.wgsl", "wrap_diffuse.toml"] {
        std::fs::copy(crate::common::repo().join("examples/user_models").join(f), mine.join(f)).unwrap();
    }
    // Not in ./shaders/brdf: unknown without being named.
    let m = crate::common::write_matrix(tmp.path(), "m.toml", MATRIX);
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("wrap_diffuse"), "{stderr}");
    // --models DIR names them.
    let (rc, stdout, stderr) =
        crate::common::shadematrix(tmp.path(), &["list", m.to_str().unwrap(), "--models", "my_models"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("__wrap_diffuse__"), "{stdout}");
    // So does the matrix's `models` key, relative to the matrix file.
    let keyed = crate::common::write_matrix(tmp.path(), "keyed.toml", &format!("models = \"my_models\"\n{MATRIX}"));
    let (rc, stdout, stderr) = crate::common::shadematrix(tmp.path(), &["list", keyed.to_str().unwrap()], &[]);
    assert_eq!(rc, 0, "{stderr}");
    assert!(stdout.contains("__wrap_diffuse__"), "{stdout}");
    let wrong = crate::common::write_matrix(tmp.path(), "wrong.toml", &format!("models = \"nope\"\n{MATRIX}"));
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["list", wrong.to_str().unwrap()], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("wrong.toml") && stderr.contains("models") && stderr.contains("nope"), "{stderr}");
}

#[test]
fn an_unstable_user_model_is_reported_with_its_pixel_and_fails_the_run_on_request() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let models = crate::common::fixture("unstable_models");
    let m = crate::common::write_matrix(
        tmp.path(),
        "m.toml",
        &format!(
            "name = \"unstable\"\nmodels = \"{}\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\n\
             shaders = [\"unstable\"]\npresets = [\"plastic\"]\n[image]\nwidth = 32\nheight = 32\n",
            models.display()
        ),
    );
    // Reported, not a crash: the run succeeds and the record names the first NaN.
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "a"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    let run = shadematrix::report::run_data::RunData::load(&tmp.path().join("a")).unwrap();
    let stats = &run.cells[0].stats;
    assert!(stats.nan > 0, "{stats:?}");
    let first = stats.first.iter().find(|d| d.kind == shadematrix::images::stats::Defect::Nan).unwrap();
    assert_eq!((first.role.as_str(), first.pass.as_str(), first.value.as_str()), ("subject", "forward", "NaN"));
    eprintln!("unstable model: {} NaN values, first at ({}, {}) {}", stats.nan, first.x, first.y, first.channel);
    // --fail-on nan: exit 1 with the cell, the pixel and the pass.
    let (rc, _, stderr) = crate::common::shadematrix(
        tmp.path(),
        &["run", m.to_str().unwrap(), "--out", "b", "--fail-on", "nan,overflow"],
        &[],
    );
    assert_eq!(rc, 1, "{stderr}");
    let pixel = format!("pixel ({}, {})", first.x, first.y);
    assert!(stderr.contains("nan value(s)") && stderr.contains(&pixel) && stderr.contains("forward"), "{stderr}");
    // A typo in the kinds is bad input.
    let (rc, _, stderr) =
        crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "c", "--fail-on", "nann"], &[]);
    assert_eq!(rc, 2, "{stderr}");
    assert!(stderr.contains("--fail-on") && stderr.contains("did you mean `nan`?"), "{stderr}");
    assert!(!tmp.path().join("c").exists());
}
