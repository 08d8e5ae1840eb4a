//! Numerical stability: the stability matrix's extreme cells keep every built-in shader free of
//! NaN, Inf and negative values (`--fail-on`), tables/stability.md sums them, and the conditioning
//! table finds where f32 loses precision against the f64 twin.

use crate::common::{repo, shadematrix};
use shadematrix::gpu::GpuContext;
use shadematrix::images::encode::read_exr;
use shadematrix::pipelines::Pipeline;
use shadematrix::record::cell::CellRecord;

#[test]
fn the_stability_matrix_extremes_leave_no_nan_inf_or_negative_value() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let matrix = repo().join("matrices/stability.toml");
    let out = tmp.path().join("run");
    // The stiffest corner of every shader × pipeline × path: mirror-smooth and fully rough white
    // metal under the strongest key light at the shortest and longest range (the full matrix:
    // `shadematrix run matrices/stability.toml`, docs/checks.md).
    let only = "metallic=1,color=ffffff,light_intensity=100,light_range=0.001|40,smoothness=0|1";
    let (rc, stdout, stderr) = shadematrix(
        tmp.path(),
        &[
            "run",
            matrix.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--only",
            only,
            "--fail-on",
            "nan,inf,negative",
        ],
        &[],
    );
    assert_eq!(rc, 0, "{stdout}\n{stderr}");
    eprintln!("{}", stdout.lines().next().unwrap_or_default());
    let table = std::fs::read_to_string(out.join("tables/stability.md")).unwrap();
    for shader in ["standard", "lit", "simple_lit", "cook_torrance_1982", "oren_nayar_057", "lambert_vertex"] {
        assert!(table.contains(&format!("| {shader} |")), "{shader} missing from\n{table}");
    }
    // The final images: no value above the half-float maximum (after pre-exposure) in any EXR, though
    // the passes wrote some (a mirror-smooth Cook-Torrance at grazing under 100 W) — the store saturated them.
    let (mut overflowed, mut cells) = (0, 0);
    for entry in std::fs::read_dir(out.join("cells")).unwrap() {
        let dir = entry.unwrap().path();
        let record = CellRecord::load(&dir.join("cell.json")).unwrap();
        let pre_exposure = record.display.exposure.as_ref().map_or(1.0, |e| e.exposure);
        let (_, _, rgba) = read_exr(&dir.join("image.exr")).unwrap();
        let largest = rgba.chunks_exact(4).flat_map(|p| &p[..3]).fold(0f64, |m, &v| m.max(v as f64));
        assert!(largest * pre_exposure <= 65504.0 * (1.0 + 1e-6), "{}: {largest}", dir.display());
        overflowed += (record.stats.overflow > 0) as usize;
        cells += 1;
    }
    eprintln!("{overflowed} of {cells} cells saturated at the half-float maximum");
    assert!(overflowed > 0, "the corner no longer reaches the half-float range: the check above is vacuous");
}

#[test]
fn conditioning_finds_where_f32_loses_the_twin() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let registry = shadematrix::shading::Registry::builtin();
    let mut probe = shadematrix::render::probe::BrdfProbe::new(&gpu);
    let at = |probe: &mut shadematrix::render::probe::BrdfProbe, p: Pipeline, name: &str| {
        let model = registry.find(p, name).unwrap();
        shadematrix::audit::conditioning::condition_model(&gpu, probe, model, p).unwrap().unwrap()
    };
    // HDRP Lit: 1 − α² rounds to 1 in f32 near the mirror direction, its denominator cancels.
    let hdrp = at(&mut probe, Pipeline::Hdrp, "lit");
    // Built-in Standard: α ≥ 0.002 (roughness_clamped) keeps it within 1e-3 everywhere.
    let standard = at(&mut probe, Pipeline::Builtin, "standard");
    eprintln!("α* hdrp/lit {:?}, builtin/standard {:?}", hdrp.alpha_threshold, standard.alpha_threshold);
    assert!(hdrp.alpha_threshold.is_some_and(|a| a > 1e-3), "{:?}", hdrp.alpha_threshold);
    assert_eq!(standard.alpha_threshold, None);
    assert_eq!(hdrp.points.len(), 17 * 17);
}

#[test]
fn convergence_errors_fall_with_samples_and_the_report_places_each_default() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let (rc, stdout, stderr) = shadematrix(tmp.path(), &["convergence", "--quick", "--out", "c"], &[]);
    assert_eq!(rc, 0, "{stdout}\n{stderr}");
    let dir = tmp.path().join("c");
    for study in ["fgd", "prefilter", "furnace"] {
        let svg = std::fs::read_to_string(dir.join(format!("plots/convergence_{study}.svg"))).unwrap();
        assert!(svg.contains("<polyline"), "{study}");
    }
    let csv = std::fs::read_to_string(dir.join("tables/convergence.csv")).unwrap();
    // Per curve, the error at the largest count is below the error at the smallest.
    let mut curves: std::collections::BTreeMap<String, Vec<f64>> = Default::default();
    for line in csv.lines().skip(1) {
        let (study, rest) = line.split_once(",\"").unwrap();
        let (name, rest) = rest.split_once("\",").unwrap();
        let error: f64 = rest.split(',').nth(2).unwrap().parse().unwrap();
        curves.entry(format!("{study}: {name}")).or_default().push(error);
    }
    assert!(curves.len() >= 7, "{curves:?}");
    for (name, errors) in &curves {
        if name.contains("resolution") || name.contains("texels per side") {
            continue;
        }
        assert!(errors.last().unwrap() < errors.first().unwrap(), "{name}: {errors:?}");
    }
    let md = std::fs::read_to_string(dir.join("tables/convergence.md")).unwrap();
    assert!(md.contains("knee") && md.contains("FGD table") && md.contains("probe level 2"), "{md}");
}
