//! Fuzzing the inputs a user hands the tool: matrix files, scene files, glTF/GLB meshes and user
//! models (WGSL + declaration). Each target mutates real seed files from the repository (byte flips,
//! inserted TOML/WGSL tokens and extreme numbers, deleted spans, duplicated lines) with proptest,
//! and asserts the loader neither panics nor fails any way but as bad input (exit 2, naming the
//! file). `cargo test` runs a short pass (FUZZ_CASES per target, 200 by default); a long run is
//! `FUZZ_CASES=20000 cargo test --release --test main fuzz -- --nocapture` (docs/checks.md).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};

use crate::common::{models, repo};

use shadematrix::error::Error;

/// One edit of a seed file.
#[derive(Debug, Clone)]
enum Mutation {
    /// XOR a byte at a position (fractions of the length keep mutations meaningful for any seed).
    Flip(f64, u8),
    Insert(f64, usize),
    Delete(f64, u16),
    DuplicateLine(f64),
    /// Replace the number at or after a position with an extreme one.
    Number(f64, usize),
}

const TOML_TOKENS: &[&str] = &[
    "=",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "\"",
    ",",
    "\n",
    "#",
    "\\",
    "'",
    ".",
    "-",
    "+",
    "\u{0}",
    "é",
    "\u{202e}",
    "true",
    "\"\"",
    "[]",
    "{}",
    "[[]]",
    "name",
    "kind",
    "compositions",
    "shaders",
    "pipelines",
    "presets",
    "smoothness",
    "metallic",
    "light_intensity",
    "light_range",
    "width",
    "height",
    "frames",
    "assert",
    "where",
    "along",
    "measure",
    "mesh",
    "uv_sphere",
    "plane",
    "gltf",
    "lathe",
    "point",
    "spot",
    "directional",
    "radius",
    "rings",
    "segments",
    "subdivisions",
    "position",
    "target",
    "range",
    "intensity",
    "sky",
    "constant",
    "procedural",
    "reference",
    "supersampled",
    "only",
    "exclude",
    "sweep",
    "params",
    "\"../\"",
    "\"/dev/zero\"",
    "\"a.gltf\"",
];
const WGSL_TOKENS: &[&str] = &[
    "fn",
    "(",
    ")",
    "{",
    "}",
    ";",
    ",",
    ":",
    "let",
    "var",
    "return",
    "vec3<f32>",
    "f32",
    "u32",
    "i32",
    "loop {",
    "while (true) {",
    "@",
    "<",
    ">",
    "->",
    "array<f32, 4294967295>",
    "normalize",
    "pow",
    "model_direct",
    "model_indirect",
    "Surface",
    "s.params0",
    "1e39",
    "0.0 / 0.0",
    "discard;",
    "\u{0}",
    "/*",
    "*/",
    "//",
    "override",
    "const",
    "struct",
    "ptr<function, f32>",
    "textureSample",
    "workgroupBarrier();",
];
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1e309",
    "-1e309",
    "nan",
    "inf",
    "-inf",
    "1e-320",
    "4294967296",
    "18446744073709551616",
    "-9223372036854775809",
    "65536",
    "4097",
    "8193",
    "0.0",
    "1e9",
    "3.4e38",
];

fn mutation(tokens: usize) -> impl Strategy<Value = Mutation> {
    let at = 0.0..1.0f64;
    prop_oneof![
        (at.clone(), 1..=255u8).prop_map(|(a, b)| Mutation::Flip(a, b)),
        (at.clone(), 0..tokens).prop_map(|(a, t)| Mutation::Insert(a, t)),
        (at.clone(), 1..64u16).prop_map(|(a, n)| Mutation::Delete(a, n)),
        at.clone().prop_map(Mutation::DuplicateLine),
        (at, 0..NUMBERS.len()).prop_map(|(a, n)| Mutation::Number(a, n)),
    ]
}

fn apply(seed: &[u8], edits: &[Mutation], tokens: &[&str]) -> Vec<u8> {
    let mut b = seed.to_vec();
    let pos = |b: &Vec<u8>, f: f64| ((b.len() as f64 * f) as usize).min(b.len());
    for m in edits {
        match *m {
            Mutation::Flip(f, x) => {
                let i = pos(&b, f);
                if i < b.len() {
                    b[i] ^= x;
                }
            }
            Mutation::Insert(f, t) => {
                let i = pos(&b, f);
                b.splice(i..i, tokens[t].bytes());
            }
            Mutation::Delete(f, n) => {
                let i = pos(&b, f);
                let end = (i + n as usize).min(b.len());
                b.drain(i..end);
            }
            Mutation::DuplicateLine(f) => {
                let i = pos(&b, f);
                let start = b[..i].iter().rposition(|&c| c == b'\n').map_or(0, |p| p + 1);
                let end = b[i..].iter().position(|&c| c == b'\n').map_or(b.len(), |p| i + p + 1);
                let line = b[start..end].to_vec();
                b.splice(end..end, line);
            }
            Mutation::Number(f, n) => {
                let i = pos(&b, f);
                if let Some(s) = b[i..].iter().position(|c| c.is_ascii_digit()).map(|p| i + p) {
                    let e = b[s..]
                        .iter()
                        .position(|c| !(c.is_ascii_digit() || *c == b'.' || *c == b'e'))
                        .map_or(b.len(), |p| s + p);
                    b.splice(s..e, NUMBERS[n].bytes());
                }
            }
        }
    }
    b
}

fn cases() -> u32 {
    std::env::var("FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(200)
}

/// What a target reports per input: loaded, or refused as bad input whose message names the file
/// at fault (`files`: the fuzzed file, or another file it references).
fn judge(result: std::thread::Result<Result<(), Error>>, files: &[&str]) -> Result<bool, TestCaseError> {
    match result {
        Err(_) => Err(TestCaseError::fail("panicked")),
        Ok(Ok(())) => Ok(true),
        Ok(Err(Error::Input(e))) => {
            let shown = e.to_string();
            if files.iter().any(|f| shown.contains(f)) {
                Ok(false)
            } else {
                Err(TestCaseError::fail(format!("bad input that names none of {files:?}: {shown}")))
            }
        }
        Ok(Err(other)) => Err(TestCaseError::fail(format!("not reported as bad input (exit 2): {other}"))),
    }
}

/// Run `target` over mutations of `seeds`; prints inputs tried, accepted and refused.
fn fuzz(
    name: &str,
    seeds: &[Vec<u8>],
    tokens: &'static [&'static str],
    target: impl Fn(&[u8]) -> Result<bool, TestCaseError>,
) {
    assert!(!seeds.is_empty());
    // The seeds themselves load.
    let seed_count = seeds.len();
    let accepted = std::cell::Cell::new(0usize);
    let tried = std::cell::Cell::new(0usize);
    // The short pass in `cargo test` is deterministic (the same inputs every run, so CI cannot turn
    // red at random); a long run (FUZZ_CASES set) draws new inputs each time.
    let config = Config { cases: cases(), failure_persistence: None, ..Config::default() };
    let mut runner = if std::env::var_os("FUZZ_CASES").is_some() {
        TestRunner::new(config)
    } else {
        TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
    };
    let strategy = (0..seed_count, proptest::collection::vec(mutation(tokens.len()), 1..6));
    let result = runner.run(&strategy, |(seed, edits)| {
        let input = apply(&seeds[seed], &edits, tokens);
        tried.set(tried.get() + 1);
        if target(&input)? {
            accepted.set(accepted.get() + 1);
        }
        Ok(())
    });
    eprintln!(
        "fuzz {name}: {} inputs from {seed_count} seeds, {} loaded, {} refused as bad input",
        tried.get(),
        accepted.get(),
        tried.get() - accepted.get()
    );
    if let Err(e) = result {
        panic!("fuzz {name}: {e}");
    }
}

fn read_all(paths: &[PathBuf]) -> Vec<Vec<u8>> {
    paths.iter().map(|p| std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).collect()
}

fn files_in(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

#[test]
fn fuzz_matrix_files() {
    let _timer = crate::common::timed!();
    let seeds = read_all(&files_in(&repo().join("matrices"), "toml"));
    let registry = Arc::new(shadematrix::shading::Registry::builtin());
    let base = repo().join("matrices");
    {
        fuzz("matrix", &seeds, TOML_TOKENS, |input| {
            let text = String::from_utf8_lossy(input);
            let r = catch_unwind(AssertUnwindSafe(|| {
                shadematrix::declarations::matrix::Matrix::from_text("fuzz.toml", &text, Some(&base), registry.clone())
                    .map(|_| ())
            }));
            // A composition the matrix references names its own file.
            judge(r, &["fuzz.toml", "scenes/", "<built-in scene"])
        })
    }
}

#[test]
fn fuzz_scene_files() {
    let _timer = crate::common::timed!();
    let mut paths = files_in(&repo().join("scenes"), "toml");
    paths.extend(files_in(&repo().join("scenes/stability"), "toml"));
    paths.extend(files_in(&repo().join("scenes/invariants"), "toml"));
    paths.extend(files_in(&repo().join("tests/fixtures"), "toml"));
    let seeds = read_all(&paths);
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("fuzz_scene.toml");
    {
        fuzz("scene", &seeds, TOML_TOKENS, |input| {
            std::fs::write(&file, input).unwrap();
            let r = catch_unwind(AssertUnwindSafe(|| {
                shadematrix::declarations::scene::Scene::load_file(&file).map(|_| ())
            }));
            judge(r, &["fuzz_scene.toml"])
        })
    }
}

#[test]
fn fuzz_gltf_import() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    // Seeds: the repository's glTF files and a GLB the tool exports (binary chunk, accessors, nodes).
    let glb = tmp.path().join("spikes.glb");
    let (rc, out, err) = crate::common::shadematrix(tmp.path(), &["export-mesh", "spikes", glb.to_str().unwrap()], &[]);
    assert_eq!(rc, 0, "{out}{err}");
    let mut seeds =
        read_all(&[repo().join("scenes/stability/degenerate.gltf"), repo().join("tests/fixtures/empty.gltf")]);
    seeds.push(std::fs::read(&glb).unwrap());
    let gltf = tmp.path().join("fuzz_mesh.gltf");
    let binary = tmp.path().join("fuzz_mesh.glb");
    {
        fuzz("gltf", &seeds, TOML_TOKENS, |input| {
            let path = if input.starts_with(b"glTF") { &binary } else { &gltf };
            std::fs::write(path, input).unwrap();
            let r = catch_unwind(AssertUnwindSafe(|| shadematrix::geometry::gltf_io::load(path, None).map(|_| ())));
            judge(r, &["fuzz_mesh.gl"])
        })
    }
}

#[test]
fn fuzz_user_models() {
    let _timer = crate::common::timed!();
    let seeds_dir = [repo().join("examples/user_models"), repo().join("tests/fixtures/unstable_models")];
    let mut wgsl = Vec::new();
    let mut decl = Vec::new();
    for d in &seeds_dir {
        wgsl.extend(read_all(&files_in(d, "wgsl")));
        decl.extend(read_all(&files_in(d, "toml")));
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("models");
    std::fs::create_dir_all(&dir).unwrap();
    let registry = models();
    // The WGSL mutated under a valid declaration, then the declaration under a valid WGSL.
    for (what, seeds, tokens) in
        [("user model WGSL", &wgsl, WGSL_TOKENS), ("user model declaration", &decl, TOML_TOKENS)]
    {
        {
            fuzz(what, seeds, tokens, |input| {
                let (w, t) = if what.ends_with("WGSL") { (input, &decl[0][..]) } else { (&wgsl[0][..], input) };
                std::fs::write(dir.join("fuzzed.wgsl"), w).unwrap();
                std::fs::write(dir.join("fuzzed.toml"), t).unwrap();
                let r =
                    catch_unwind(AssertUnwindSafe(|| shadematrix::shading::user::load_dir(&dir, registry).map(|_| ())));
                judge(r, &["fuzzed."])
            })
        }
    }
}
