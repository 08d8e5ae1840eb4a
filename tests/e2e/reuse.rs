//! Reuse across cells: untimed cells take the shadow maps, the depth prepass and SSAO, the probe
//! captures and the fixed objects' layer from the cell before where those passes' inputs are the
//! same; `--no-reuse` draws every pass of every cell. The images must be the same bytes.

/// Fixed objects, probes and shadows (default), SSAO and bloom (HDRP), MSAA 4 and ForwardAdd
/// (built-in), a scene with no fixed object (medusa), and the vertex-lit path.
const MATRIX: &str = r#"name = "reuse"
compositions = ["default", "medusa"]
pipelines = ["builtin", "hdrp"]
shaders = ["lambert", "standard", "lit"]
presets = ["gold", "plastic"]
paths = ["forward", "vertex_lit"]
[sweep]
smoothness = [0.2, 0.9]
[image]
width = 48
height = 48
[timing]
frames = 1
warmup = 0
"#;

fn image_files(run: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::new();
    for cell in std::fs::read_dir(run.join("cells")).unwrap() {
        let cell = cell.unwrap().path();
        for f in ["image.exr", "image.png"] {
            let name = format!("{}/{f}", cell.file_name().unwrap().to_string_lossy());
            files.push((name, std::fs::read(cell.join(f)).unwrap()));
        }
    }
    files.sort();
    files
}

#[test]
fn reusing_passes_across_cells_gives_the_same_bytes_as_drawing_every_pass() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let reused = crate::common::run_matrix_with(tmp.path(), MATRIX, "reused", &["--no-cache"]);
    let drawn = crate::common::run_matrix_with(tmp.path(), MATRIX, "drawn", &["--no-cache", "--no-reuse"]);
    let (a, b) = (image_files(&reused), image_files(&drawn));
    assert!(a.len() >= 40, "{} files", a.len());
    assert_eq!(a.iter().map(|(n, _)| n).collect::<Vec<_>>(), b.iter().map(|(n, _)| n).collect::<Vec<_>>());
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name} differs between a run that reuses passes and one that draws them all");
    }
}

/// The probe capture draws the shadows the subject casts on the room, and the subject's LOD level
/// (which mesh casts) changes with the camera distance: a capture is the same only when the same
/// meshes cast. (Both cells are timed, each its own class; only the capture could be reused.)
#[test]
fn a_probe_capture_is_reused_only_when_the_same_meshes_cast_into_it() {
    let _timer = crate::common::timed!();
    let scene = crate::common::repo().join("scenes/default_lod.toml");
    let matrix = format!(
        "name = \"lod_capture\"\ncompositions = [{scene:?}]\npipelines = [\"hdrp\"]\nshaders = [\"lit\"]\n\
         presets = [\"gold\"]\n[sweep]\ncamera_distance = [6.5, 14.0]\n[image]\nwidth = 48\nheight = 48\n"
    );
    let tmp = tempfile::tempdir().unwrap();
    let reused = crate::common::run_matrix_with(tmp.path(), &matrix, "reused", &["--no-cache"]);
    let drawn = crate::common::run_matrix_with(tmp.path(), &matrix, "drawn", &["--no-cache", "--no-reuse"]);
    let (a, b) = (image_files(&reused), image_files(&drawn));
    assert_eq!(a.len(), 4);
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name}: the capture of another LOD level's shadow was reused");
    }
}
