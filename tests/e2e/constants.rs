//! gpu::constants: on lavapipe the passes' constants live in read-only storage buffers (uniform
//! buffers there compile a shader variant per new value). Both spaces must give the same pixels.

const MATRIX: &str = "name = \"k\"\ncompositions = [\"default\"]\npipelines = [\"builtin\", \"urp\", \"hdrp\"]\nshaders = [\"standard\", \"lit\", \"blinn_phong\"]\npresets = [\"gold\", \"plastic\"]\n[sweep]\nsmoothness = [0.3, 0.8]\nlight_intensity = [1.0, 3.0]\n[image]\nwidth = 32\nheight = 32\n[timing]\nframes = 1\nwarmup = 0\n";

fn run(dir: &std::path::Path, out: &str, space: &str) -> (std::path::PathBuf, shadematrix::record::RunRecord) {
    let m = crate::common::write_matrix(dir, &format!("{out}.toml"), MATRIX);
    let path = dir.join(out);
    let args = ["run", m.to_str().unwrap(), "--out", path.to_str().unwrap(), "--no-cache"];
    let (code, _, err) = crate::common::shadematrix(dir, &args, &[("SHADEMATRIX_CONSTANTS", space)]);
    assert_eq!(code, 0, "{err}");
    let record = shadematrix::record::RunRecord::load(&path).unwrap();
    (path, record)
}

#[test]
fn storage_and_uniform_constants_render_the_same_bytes() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let (storage, s) = run(tmp.path(), "storage", "storage");
    let (uniform, u) = run(tmp.path(), "uniform", "uniform");
    use shadematrix::gpu::ConstantSpace;
    assert_eq!((s.adapter.constants, u.adapter.constants), (ConstantSpace::ReadOnlyStorage, ConstantSpace::Uniform));
    let json = std::fs::read_to_string(storage.join("run.json")).unwrap();
    assert!(json.contains("\"constants\": \"storage\""), "run.json names the space: {json}");
    let mut compared = 0;
    for e in std::fs::read_dir(storage.join("cells")).unwrap() {
        let id = e.unwrap().file_name();
        for f in ["image.exr", "image.png"] {
            let a = std::fs::read(storage.join("cells").join(&id).join(f)).unwrap();
            let b = std::fs::read(uniform.join("cells").join(&id).join(f)).unwrap();
            assert!(a == b, "{id:?}/{f}: the constant space changed the pixels");
            compared += 1;
        }
    }
    assert!(compared >= 90, "{compared} files compared");
}

#[test]
fn an_unknown_constant_space_is_refused_with_the_nearest_name() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = crate::common::write_matrix(tmp.path(), "k.toml", MATRIX);
    let out = tmp.path().join("out");
    let args = ["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()];
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &args, &[("SHADEMATRIX_CONSTANTS", "storag")]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("SHADEMATRIX_CONSTANTS") && err.contains("storage"), "{err}");
    assert!(!out.join("run.json").exists());
}
