//! Engine settings as sweep axes (`[sweep.settings.<pipeline>]`): in every pipeline a shadow
//! resolution moves the shadow's edge and nothing else, a value equal to the engine's own is the
//! cell without it, where no shadow is drawn its values are twins of one rendered cell, and the
//! viewer offers each setting as a slider.

use shadematrix::record::CellRecord;
use shadematrix::run::{run, RunOptions};

/// A box above a floor under a slanted sun, seen from above; `shadows`: whether the sun casts
/// (hard) shadows.
fn scene(name: &str, shadows: bool) -> String {
    format!(
        "name = \"{name}\"\n[camera]\nposition = [0.0, 4.5, 2.5]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 50.0\n\
         [[lights]]\nkind = \"directional\"\ndirection = [0.35, -1.0, 0.2]\nintensity = 1.5\nshadows = {shadows}\nshadow = {{ soft = false }}\nkey = true\n\
         [[objects]]\nname = \"floor\"\nrole = \"subject\"\nmesh = {{ kind = \"plane\", size = [8.0, 8.0], subdivisions = 4 }}\n\
         [[objects]]\nname = \"box\"\nrole = \"fixed\"\nmesh = {{ kind = \"box\", size = [1.2, 0.2, 1.2] }}\n\
         transform = {{ translate = [0.0, 1.0, 0.0] }}\nmaterial = {{ base_color_linear = [0.5, 0.5, 0.5] }}\nreceive_shadows = false\n\
         [environment]\nsky = {{ kind = \"constant\", color = [0.0, 0.0, 0.0] }}\nbackground = false\n\
         [hdrp]\nbloom = false\nssao = false\n"
    )
}

const MATRIX: &str = "name = \"settings\"\ncompositions = [\"sun_box.toml\", \"sun_box_unshadowed.toml\"]\n\
    pipelines = [\"builtin\", \"urp\", \"hdrp\"]\nshaders = [\"standard\", \"lit\"]\npresets = [\"plastic\"]\n\
    [image]\nwidth = 128\nheight = 128\n\
    [sweep.settings.builtin]\nshadow_resolution = [\"medium\", \"high\"]\n\
    [sweep.settings.urp]\nmain_light_shadow_resolution = [1024, 2048]\n\
    [sweep.settings.hdrp]\nshadow_resolution = [256, 512]\n";

fn luminance(img: &image::RgbaImage) -> Vec<f64> {
    img.pixels().map(|p| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0).collect()
}

#[test]
fn a_shadow_resolution_moves_the_shadow_edge_only_and_its_default_is_the_plain_cell() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("sun_box.toml"), scene("sun_box", true)).unwrap();
    std::fs::write(tmp.path().join("sun_box_unshadowed.toml"), scene("sun_box_unshadowed", false)).unwrap();
    let m = crate::common::write_matrix(tmp.path(), "m.toml", MATRIX);
    let matrix = crate::common::load_matrix(&m);
    let out = tmp.path().join("run");
    let opts = RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() };
    let summary = run(&matrix, &opts).unwrap();
    // Two values per pipeline and composition; without shadows each pipeline's second is a twin.
    assert_eq!((summary.counts.cells, summary.counts.twins), (12, 3));
    // The viewer gives each swept setting its own slider, `own` where a cell keeps its engine's.
    let data = shadematrix::report::viewer::data(&shadematrix::report::run_data::RunData::load(&out).unwrap(), vec![]);
    let slider = |name: &str| data.axes.iter().find(|a| a.name == name).map(|a| a.values.clone());
    assert_eq!(slider("settings.main_light_shadow_resolution"), Some(vec!["1024".to_string(), "own".to_string()]));
    assert_eq!(slider("settings.shadow_resolution").map(|v| v.len()), Some(3), "built-in's medium, HDRP's 256, own");
    assert!(slider("settings").is_none(), "no slider over the combinations");
    let cells = out.join("cells");
    let image = |id: &str| image::open(cells.join(id).join("image.png")).unwrap().to_rgba8();
    let record = |id: &str| CellRecord::load(&cells.join(id).join("cell.json")).unwrap();
    for (pipeline, shader, setting) in [
        ("builtin", "standard", "shadow_resolution.medium"),
        ("urp", "lit", "main_light_shadow_resolution.1024"),
        ("hdrp", "lit", "shadow_resolution.256"),
    ] {
        let plain = |comp: &str| format!("{comp}__{pipeline}-forward__{shader}__plastic__m0.00_s0.75_i1.5_r10");
        let coarse = |comp: &str| format!("{}_{setting}", plain(comp));
        // The engine's own value names nothing: its cell is the plain one, rendered.
        assert!(cells.join(plain("sun_box")).join("cell.json").exists(), "{}", plain("sun_box"));
        assert!(record(&plain("sun_box")).twin_of.is_none());
        // Without a shadow the resolution changes nothing: the later-listed value (the engine's
        // own) is a twin of the first, drawn once.
        let twin = record(&plain("sun_box_unshadowed"));
        assert_eq!(twin.twin_of.as_ref().map(|t| t.0.clone()), Some(coarse("sun_box_unshadowed")), "{pipeline}");
        // The coarse map renders, at its own resolution.
        let (fine_maps, coarse_maps) = (record(&plain("sun_box")).shadow_maps, record(&coarse("sun_box")).shadow_maps);
        assert!(coarse_maps[0].resolution < fine_maps[0].resolution, "{pipeline}: {coarse_maps:?} vs {fine_maps:?}");
        let (fine, rough, unshadowed) = (
            luminance(&image(&plain("sun_box"))),
            luminance(&image(&coarse("sun_box"))),
            luminance(&image(&plain("sun_box_unshadowed"))),
        );
        // The shadow: where either map darkens the frame; its core: shadowed with both maps and
        // farther than a coarse texel (at most 5 px in these frames) from any pixel either leaves lit.
        let shadowed = |img: &[f64], i: usize| unshadowed[i] - img[i] > 2.0;
        let side = 128usize;
        let in_either = |i: usize| shadowed(&fine, i) || shadowed(&rough, i);
        let core = |i: usize| {
            let (x, y) = ((i % side) as i64, (i / side) as i64);
            (-6..=6).all(|dy| {
                (-6..=6).all(|dx| {
                    let (u, v) = (x + dx, y + dy);
                    (0..side as i64).contains(&u)
                        && (0..side as i64).contains(&v)
                        && shadowed(&fine, (v as usize) * side + u as usize)
                        && shadowed(&rough, (v as usize) * side + u as usize)
                })
            })
        };
        if let Ok(dir) = std::env::var("SETTINGS_AXES_KEEP") {
            for id in [plain("sun_box"), coarse("sun_box")] {
                image(&id).save(format!("{dir}/{id}.png")).unwrap();
            }
        }
        let changed: Vec<usize> = (0..fine.len()).filter(|&i| (fine[i] - rough[i]).abs() > 2.0).collect();
        let area = (0..fine.len()).filter(|&i| in_either(i)).count();
        let cores = (0..fine.len()).filter(|&i| core(i)).count();
        eprintln!("{pipeline}: {} pixels changed, shadow {area}, core {cores}", changed.len());
        assert!(!changed.is_empty(), "{pipeline}: the coarse map changed nothing");
        assert!(cores > 0, "{pipeline}: the shadow has no core to hold");
        for &i in &changed {
            assert!(in_either(i), "{pipeline}: pixel {} {} changed outside the shadow", i % side, i / side);
            assert!(!core(i), "{pipeline}: pixel {} {} changed inside the shadow's core", i % side, i / side);
        }
    }
}

#[test]
fn the_quality_report_tiers_each_pipelines_settings_beside_unitys_presets() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("sun_box.toml"), scene("sun_box", true)).unwrap();
    let body = "name = \"quality\"\ncompositions = [\"sun_box.toml\"]\npipelines = [\"builtin\", \"urp\", \"hdrp\"]\n\
        shaders = [\"standard\", \"lit\"]\npresets = [\"plastic\", \"gold\"]\n\
        reference = { truth = \"physical\", spp = 4, noise = 0.0, bounces = 1 }\n[image]\nwidth = 48\nheight = 48\n\
        [sweep.settings.builtin]\nquality_level = [\"low\", \"ultra\"]\n\
        [sweep.settings.urp]\nasset = [\"default\", \"high_fidelity\"]\nmain_light_shadow_resolution = [256, 2048]\n\
        [sweep.settings.hdrp]\nssao = [false, true]\nssao_quality = [\"low\", \"medium\"]\n";
    let run = crate::common::run_matrix(tmp.path(), body, "run");
    let md = std::fs::read_to_string(run.join("tables/quality.md")).unwrap();
    let csv = std::fs::read_to_string(run.join("tables/quality.csv")).unwrap();
    // Built-in: low and ultra (its own); URP: two assets × two resolutions, the default asset's
    // 2048 being its own (`engine`); each a row of the CSV.
    let rows: Vec<Vec<String>> = csv.lines().skip(1).map(csv_fields).collect();
    let settings = |p: &str| -> Vec<&str> { rows.iter().filter(|r| r[0] == p).map(|r| r[1].as_str()).collect() };
    assert_eq!(settings("builtin").len(), 2, "{csv}");
    assert_eq!(settings("urp").len(), 4, "{csv}");
    // HDRP: the scene turns SSAO off, so its settings make twins of the engine's own frames: one
    // combination, the three others left out as repeats.
    assert_eq!(settings("hdrp"), vec!["engine"], "{csv}");
    assert!(md.contains("3 whose frames are another's"), "{md}");
    // Unity's presets are named, whatever the sweep lists with them.
    for preset in ["quality level low", "quality level ultra (own)", "URP asset default (own)"] {
        assert!(md.contains(&format!("| {preset} |")), "{preset}:\n{md}");
    }
    // Three budgets per pipeline in the tiers; the best combination is 0 from itself.
    assert_eq!(md.matches("| builtin | 0.0").count() + md.matches("| builtin | 0.1 |").count(), 3, "{md}");
    let from_best: Vec<f64> = rows.iter().filter(|r| r[0] == "urp").filter_map(|r| r[8].parse().ok()).collect();
    assert_eq!(from_best.len(), 4, "{csv}");
    assert!(from_best.contains(&0.0) && from_best.iter().any(|f| *f > 0.0), "{from_best:?}");
    // A plot per pipeline: every combination named on hover, the budgets drawn.
    for p in ["builtin", "urp", "hdrp"] {
        let svg = std::fs::read_to_string(run.join(format!("plots/quality_{p}.svg"))).unwrap();
        assert_eq!(svg.matches("<title>").count(), settings(p).len(), "{p}");
        assert!(svg.contains(">FLIP 0.02<") && svg.contains(">FLIP 0.1<"), "{p}");
    }
    assert!(std::fs::read_to_string(run.join("gallery.html")).unwrap().contains("tables/quality.md"));
}

/// A CSV line's fields, quotes removed (a quoted field may hold commas).
fn csv_fields(line: &str) -> Vec<String> {
    let (mut fields, mut field, mut quoted) = (Vec::new(), String::new(), false);
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(std::mem::take(&mut field)),
            _ => field.push(ch),
        }
    }
    fields.push(field);
    fields
}

#[test]
fn hdrps_filtering_quality_widens_the_shadows_edge_from_low_to_medium_and_high_draws_pcss() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("sun_box.toml"), scene("sun_box", true)).unwrap();
    std::fs::write(tmp.path().join("sun_box_unshadowed.toml"), scene("sun_box_unshadowed", false)).unwrap();
    let body = "name = \"filtering\"\ncompositions = [\"sun_box.toml\", \"sun_box_unshadowed.toml\"]\npipelines = [\"hdrp\"]\n\
        shaders = [\"lit\"]\npresets = [\"plastic\"]\n[image]\nwidth = 128\nheight = 128\n\
        [pipeline_settings.hdrp]\nshadow_resolution = 128\n[sweep.settings.hdrp]\nshadow_filtering = [\"low\", \"medium\", \"high\"]\n";
    let run = crate::common::run_matrix(tmp.path(), body, "run");
    let cells = run.join("cells");
    let plain = |comp: &str| format!("{comp}__hdrp-forward__lit__plastic__m0.00_s0.75_i1.5_r10");
    let image = |id: &str| luminance(&image::open(cells.join(id).join("image.png")).unwrap().to_rgba8());
    let (medium, low, high, lit) = (
        image(&plain("sun_box")),
        image(&format!("{}_shadow_filtering.low", plain("sun_box"))),
        image(&format!("{}_shadow_filtering.high", plain("sun_box"))),
        image(&plain("sun_box_unshadowed")),
    );
    // Without a shadow the filtering is a twin; the records name the tent each read its map with.
    let record = |id: &str| CellRecord::load(&cells.join(id).join("cell.json")).unwrap();
    assert!(record(&plain("sun_box_unshadowed")).twin_of.is_some());
    // The umbra's depth: the darkest a pixel gets; a pixel is in the penumbra between 10 % and 90 %.
    let depth = (0..lit.len()).map(|i| lit[i] - medium[i]).fold(0.0f64, f64::max);
    assert!(depth > 20.0, "the shadow is {depth} deep");
    let partial = |img: &[f64]| (0..lit.len()).filter(|&i| (0.1..0.9).contains(&((lit[i] - img[i]) / depth))).count();
    let (p_low, p_medium, p_high) = (partial(&low), partial(&medium), partial(&high));
    let moved = (0..lit.len()).filter(|&i| (high[i] - medium[i]).abs() > 2.0).count();
    eprintln!(
        "penumbra pixels: low (5×5 tent) {p_low}, medium (7×7) {p_medium}, high (PCSS) {p_high}; \
         {moved} pixels differ between high and medium"
    );
    assert!(p_medium as f64 > 1.15 * p_low as f64, "{p_medium} vs {p_low}");
    assert!(moved > 20, "PCSS draws another edge than the tent: {moved} pixels");
    // Only the edge moves: a pixel two levels differ in is partly shadowed in one of them.
    for other in [&low, &high] {
        for i in 0..lit.len() {
            if (other[i] - medium[i]).abs() > 2.0 {
                let f = |img: &[f64]| (lit[i] - img[i]) / depth;
                assert!((0.01..0.99).contains(&f(other)) || (0.01..0.99).contains(&f(&medium)), "pixel {i}");
            }
        }
    }
    // The record says how the map was read.
    let style = |id: &str| record(id).shadow_maps[0].style.unwrap();
    assert!(style(&format!("{}_shadow_filtering.high", plain("sun_box"))).pcss);
    assert_eq!(style(&plain("sun_box")).tent, 7);
}
