//! Textured presets (`materials`): the textured form differs from the flat one while keeping its
//! mean, and the normal map shapes the light.

use crate::common::{repo, shadematrix, write_matrix};
use shadematrix::images::encode::read_exr;
use shadematrix::record::cell::CellRecord;

fn cell(dir: &std::path::Path, id: &str) -> (CellRecord, Vec<f32>, u32) {
    let d = dir.join("cells").join(id);
    let record = CellRecord::load(&d.join("cell.json")).unwrap_or_else(|e| panic!("{id}: {e:?}"));
    let (w, _, rgba) = read_exr(&d.join("image.exr")).unwrap();
    (record, rgba, w)
}

/// Luminance of the central `frac` square of an RGBA image (inside the subject in these scenes).
fn centre(rgba: &[f32], w: u32, frac: f64) -> (Vec<f64>, usize) {
    let w = w as usize;
    let side = (w as f64 * frac) as usize;
    let start = (w - side) / 2;
    let mut out = Vec::with_capacity(side * side);
    for y in start..start + side {
        for x in start..start + side {
            let p = &rgba[(y * w + x) * 4..];
            out.push(0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64);
        }
    }
    (out, side)
}

#[test]
fn textured_presets_differ_from_flat_and_keep_its_mean() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let furnace = repo().join("scenes/invariants/furnace.toml");
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        &format!(
            "name = \"t\"\ncompositions = [\"{}\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\"]\npresets = \"all\"\n\
             [sweep]\ntextured = [false, true]\n[image]\nwidth = 96\nheight = 96\n",
            furnace.display()
        )
        .replace("presets = \"all\"", "presets = [\"all\"]"),
    );
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let dir = tmp.path().join("r");
    for p in shadematrix::declarations::presets::PRESETS {
        let base =
            format!("white_furnace__urp-forward__lambert__{}__m{:.2}_s{:.2}_i0_r0", p.name, p.metallic, p.smoothness);
        let (flat, flat_px, w) = cell(&dir, &base);
        let (tex, tex_px, _) = cell(&dir, &format!("{base}_tex"));
        assert!(tex.textured && !flat.textured);
        // Lambert in a white furnace: each pixel is albedo × occlusion; the means agree within 5 %.
        let (a, b) = (flat.stats.subject_mean_luminance.unwrap(), tex.stats.subject_mean_luminance.unwrap());
        eprintln!("{}: flat {a:.4}, textured {b:.4} ({:+.2} %)", p.name, (b / a - 1.0) * 100.0);
        assert!((b / a - 1.0).abs() < 0.05, "{}: flat {a}, textured {b}", p.name);
        // …and the images differ: SSIM of the subject's centre (scaled to the flat one's peak).
        let (fa, side) = centre(&flat_px, w, 0.5);
        let (ta, _) = centre(&tex_px, w, 0.5);
        let peak = fa.iter().chain(&ta).fold(0.0f64, |m, v| m.max(*v)).max(1e-9);
        let s = shadematrix::compare::ssim::ssim(
            &fa.iter().map(|v| v / peak).collect::<Vec<_>>(),
            &ta.iter().map(|v| v / peak).collect::<Vec<_>>(),
            side,
            side,
        )
        .unwrap()
        .mean;
        eprintln!("{}: SSIM {s:.4}", p.name);
        assert!(s < 0.98, "{}: textured and flat look alike (SSIM {s})", p.name);
    }
}

#[test]
fn a_normal_map_shapes_grazing_light() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        &format!(
            "name = \"t\"\ncompositions = [\"{}\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\"]\npresets = [\"concrete\"]\n\
             antialiasing = \"none\"\n[sweep]\ntextured = [false, true]\nlight_angle = [0.0, 80.0]\n[image]\nwidth = 96\nheight = 96\n",
            repo().join("tests/fixtures/textured_plane.toml").display()
        ),
    );
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let dir = tmp.path().join("r");
    // textured / flat per pixel: the albedo modulation alone under light along the normal (the
    // normal map changes N·L only to second order there); at 80° the normal map's slopes change
    // N·L to first order, so the ratio varies far more. Ignore the map and both vary alike.
    let spread = |angle: &str| {
        let id = format!("textured_plane__urp-forward__lambert__concrete__m0.00_s0.30_i1_r10_a{angle}");
        let (_, flat, w) = cell(&dir, &id);
        let (_, tex, _) = cell(&dir, &format!("{id}_tex"));
        let (f, _) = centre(&flat, w, 0.6);
        let (t, _) = centre(&tex, w, 0.6);
        let ratio: Vec<f64> = f.iter().zip(&t).filter(|(f, _)| **f > 1e-6).map(|(f, t)| t / f).collect();
        let mean = ratio.iter().sum::<f64>() / ratio.len() as f64;
        (ratio.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / ratio.len() as f64).sqrt() / mean
    };
    let (frontal, grazing) = (spread("0"), spread("80"));
    eprintln!("relative spread of textured/flat: light along the normal {frontal:.4}, at 80° {grazing:.4}");
    assert!(grazing > 2.0 * frontal, "the normal map does not shape grazing light: {frontal} vs {grazing}");
}

#[test]
fn emission_adds_the_subjects_colour_in_models_that_have_it() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    // The emitted colour at the subject's centre: HDRP's bloom, which mixes the dark background
    // into the edge, is turned off in a copy of the scene.
    let scene = std::fs::read_to_string(repo().join("scenes/invariants/key_only.toml")).unwrap()
        + "\n[hdrp]\nbloom = false\nssao = false\n";
    std::fs::write(tmp.path().join("key_only.toml"), scene).unwrap();
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        &format!(
            "name = \"t\"\ncompositions = [\"{}\"]\npipelines = [\"builtin\", \"urp\", \"hdrp\"]\n\
             shaders = [\"standard\", \"lit\", \"simple_lit\", \"lambert\"]\npresets = [\"blue_paint\"]\nantialiasing = \"none\"\n\
             [sweep]\nemission = [0.0, 2.0]\n[image]\nwidth = 48\nheight = 48\n",
            tmp.path().join("key_only.toml").display()
        ),
    );
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let dir = tmp.path().join("r");
    let preset = shadematrix::declarations::presets::find_preset("blue_paint").unwrap();
    let luminance = |c: [f64; 3]| 0.2126729 * c[0] + 0.7151522 * c[1] + 0.0721750 * c[2];
    for (pipeline, shader, scale) in
        [("builtin", "standard", 1.0), ("urp", "lit", 1.0), ("urp", "simple_lit", 1.0), ("hdrp", "lit", 1e4)]
    {
        let id = |e: &str| format!("key_only__{pipeline}-forward__{shader}__blue_paint__m0.00_s0.60_i1_r10_e{e}");
        let (_, off, w) = cell(&dir, &id("0"));
        let (_, on, _) = cell(&dir, &id("2"));
        // The centre of the subject: emission adds colour × 2 (× the pipeline's light unit) there.
        let (a, _) = centre(&off, w, 0.2);
        let (b, _) = centre(&on, w, 0.2);
        let added = b.iter().zip(&a).map(|(b, a)| b - a).sum::<f64>() / a.len() as f64;
        let expected = 2.0 * scale * luminance(preset.base_color);
        eprintln!("{pipeline}/{shader}: emission added {added:.5}, expected {expected:.5}");
        assert!((added / expected - 1.0).abs() < 1e-3, "{pipeline}/{shader}: {added} vs {expected}");
    }
    // Lambert has no emission: its emission cells are twins, one image.
    let lambert = CellRecord::load(
        &dir.join("cells/key_only__urp-forward__lambert__blue_paint__m0.00_s0.60_i1_r10_e2/cell.json"),
    )
    .unwrap();
    assert!(lambert.twin_of.is_some(), "Lambert rendered its emission cell");
}

/// Mean linear RGB over the pixels of `rgba` (width `w`) where `keep(x, y)` and the role is the subject.
fn mean_rgb(rgba: &[f32], w: usize, keep: impl Fn(usize, usize) -> bool) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for (i, p) in rgba.chunks(4).enumerate() {
        if keep(i % w, i / w) {
            for c in 0..3 {
                sum[c] += p[c] as f64;
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn a_gltf_subject_renders_with_its_own_textured_material() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    crate::common::write_textured_gltf(tmp.path());
    let scene = std::fs::read_to_string(crate::common::fixture("textured_plane.toml"))
        .unwrap()
        .replace(
            "mesh = { kind = \"plane\", size = [2.0, 2.0], subdivisions = 1 }",
            "mesh = { kind = \"gltf\", path = \"plane.gltf\" }",
        )
        .replace(
            "color = [0.0, 0.0, 0.0] }\nambient_intensity = 0.0",
            "color = [1.0, 1.0, 1.0] }\nambient_intensity = 1.0",
        )
        .replace("intensity = 1.0\nkey = true", "intensity = 0.0\nkey = true");
    std::fs::write(tmp.path().join("scene.toml"), scene).unwrap();
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"t\"\ncompositions = [\"scene.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"own\"]\n\
         [sweep]\ntextured = [false, true]\n[image]\nwidth = 64\nheight = 64\n",
    );
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let dir = tmp.path().join("r");
    // The file's factors: white, metallic 0, roughness 1 (smoothness 0).
    let base = "textured_plane__urp-forward__lit__own__m0.00_s0.00_i0_r10";
    let (flat, flat_px, w) = cell(&dir, base);
    let (tex, tex_px, _) = cell(&dir, &format!("{base}_tex"));
    assert!(tex.textured && !flat.textured);
    let w = w as usize;
    // The plane fills the frame's centre; sample its four quadrants, away from the seams.
    let quadrant = |px: &[f32], left: bool, top: bool| {
        mean_rgb(px, w, |x, y| {
            let (fx, fy) = (x as f64 / w as f64, y as f64 / w as f64);
            let inside = |f: f64, low: bool| if low { (0.25..0.45).contains(&f) } else { (0.55..0.75).contains(&f) };
            inside(fx, left) && inside(fy, top)
        })
    };
    let q = [(true, true), (false, true), (true, false), (false, false)].map(|(l, t)| quadrant(&tex_px, l, t));
    let f = [(true, true), (false, true), (true, false), (false, false)].map(|(l, t)| quadrant(&flat_px, l, t));
    eprintln!("textured quadrants {q:?}\nflat quadrants {f:?}");
    // Flat: the factors alone, the same everywhere (white base, white emission).
    for c in &f {
        assert!((c[0] - f[0][0]).abs() < 1e-3 && (c[2] - c[0]).abs() < 1e-3, "{f:?}");
    }
    // Textured: one side red, the other blue (the base colour texture), whichever way the camera maps u.
    let red_left = q[0][0] > q[0][2];
    for (i, c) in q.iter().enumerate() {
        let left = i % 2 == 0;
        let (r, b) = (c[0], c[2]);
        if left == red_left {
            assert!(r > 5.0 * b, "quadrant {i} should be red: {c:?}");
        } else {
            assert!(b > 5.0 * r, "quadrant {i} should be blue: {c:?}");
        }
    }
    // The emissive texture: green glows in one half (v < 0.5) only.
    let green_top = q[0][1] > q[2][1];
    let (glow, dark) = if green_top {
        (q[0][1].min(q[1][1]), q[2][1].max(q[3][1]))
    } else {
        (q[2][1].min(q[3][1]), q[0][1].max(q[1][1]))
    };
    assert!(glow > 0.5 && dark < 0.05, "emission map: glowing half {glow}, dark half {dark}");
}
