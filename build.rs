//! Fingerprints of the tool's own code and pass shaders, for the cross-run cell cache
//! (`run::cell_key`): a cell's key must change when the code or a pass shader that draws it
//! changes, even without a version bump. The surface models (`shaders/brdf/`) are left out here:
//! each cell's key holds the source of the models it draws, so editing one re-renders only its
//! cells. Hand-written because it is a dozen lines over `std` and `sha2`.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

fn files(dir: &Path, skip: Option<&Path>, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if Some(p.as_path()) == skip {
            continue;
        }
        if p.is_dir() {
            files(&p, skip, out);
        } else {
            out.push(p);
        }
    }
}

fn digest(roots: &[&str], skip: Option<&str>) -> String {
    let mut paths = Vec::new();
    for r in roots {
        files(Path::new(r), skip.map(Path::new), &mut paths);
    }
    paths.sort();
    let mut h = Sha256::new();
    for p in paths {
        h.update(p.to_string_lossy().replace('\\', "/").as_bytes());
        h.update([0]);
        h.update(std::fs::read(&p).unwrap_or_default());
        h.update([0]);
    }
    h.finalize().iter().take(16).map(|b| format!("{b:02x}")).collect()
}

fn main() {
    for p in ["src", "shaders", "Cargo.lock", "build.rs"] {
        println!("cargo:rerun-if-changed={p}");
    }
    println!("cargo:rustc-env=SHADEMATRIX_CODE_DIGEST={}", digest(&["src", "Cargo.lock"], None));
    println!("cargo:rustc-env=SHADEMATRIX_PASS_SHADERS_DIGEST={}", digest(&["shaders"], Some("shaders/brdf")));
}
