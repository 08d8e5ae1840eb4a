//! `shadematrix list`: the expanded cells, twins, pruned cells and each composition's passes.

use std::fmt::Write;
use std::path::Path;

use super::{load_matrix, print_out, registry_for, ModelsArg};
use crate::cells::expand;
use crate::declarations::matrix::Matrix;
use crate::error::Error;
use crate::pipelines::Pipeline;
use crate::plan::lights::{assign, LightMode};
use crate::plan::FramePlan;

pub fn list(matrix: Option<&Path>, limit: super::CellLimit, models: &ModelsArg) -> Result<(), Error> {
    let m = load_matrix(matrix, registry_for(models, matrix)?)?;
    crate::cells::check_size(&m, limit.max_cells)?;
    print_out(&text(&m));
    Ok(())
}

pub fn text(m: &Matrix) -> String {
    let mut out = String::new();
    let exp = expand(m);
    let _ = writeln!(out, "matrix `{}` ({}), sha256 {}", m.name, m.origin, &m.hash[..12]);
    for scene in &m.compositions {
        let plan = FramePlan::for_scene(scene);
        for p in &m.pipelines {
            for path in m.paths.iter().filter(|path| p.paths().contains(path)) {
                let passes: Vec<&str> =
                    plan.passes_for(*path, *p, &m.pipeline_settings, false).iter().map(|p| p.name()).collect();
                let passes = passes.join(" → ");
                let (samples, why_one) = m.antialiasing_for(*p).samples_on(*path);
                let aa = match (samples, why_one) {
                    (1, Some(why)) => format!("1 sample ({} asked: {why})", m.antialiasing_for(*p).name()),
                    (1, None) => "1 sample".to_string(),
                    (n, _) => format!("{n}× MSAA asked (cell.json says what the adapter rendered)"),
                };
                let _ =
                    writeln!(out, "composition {} ({}-{}): passes {passes}; {aa}", scene.name, p.name(), path.name());
            }
        }
        for (what, why) in &plan.left_out {
            let _ = writeln!(out, "  left out: {what}: {why}");
        }
        if let Some(key) = scene.key_light().map(|k| &scene.lights[k]) {
            for p in &m.pipelines {
                let _ = writeln!(out, "  key light in {}: {}", p.name(), p.intensity_unit(key.emitter()));
            }
        }
        let _ = write!(out, "{}", light_plan(m, scene));
        let _ = write!(out, "{}", bake_line(m, &exp.cells, scene));
        let _ = write!(out, "{}", fixed_maps_line(scene));
        if m.pipelines.contains(&Pipeline::Hdrp) {
            let x = &scene.hdrp.exposure;
            let _ = writeln!(
                out,
                "  HDRP exposure: {:?}, metering {:?}, limits {}..{} EV100, compensation {}",
                x.mode, x.metering, x.limit_min, x.limit_max, x.compensation
            );
        }
    }
    for p in &m.pipelines {
        let _ = writeln!(out, "pipeline {}: tonemap {}", p.name(), m.tonemap_for(*p).name());
    }
    if m.pipelines.contains(&Pipeline::Hdrp) {
        let _ = writeln!(out, "left out: {}", crate::pipelines::volume::LEFT_OUT_EFFECTS);
    }
    let _ = writeln!(out, "reference: {}", reference_line(m));
    if !m.approximations.is_empty() {
        let names: Vec<&str> = m.approximations.iter().map(|a| a.name()).collect();
        let _ = writeln!(
            out,
            "approximation study: {} (each cell rendered again without each, against its truth; the exact terms need per-pixel forward shading, MSAA a forward path)",
            names.join(", ")
        );
    }
    let rendered = exp.cells.iter().filter(|c| c.twin_of.is_none()).count();
    let _ = writeln!(
        out,
        "{} cells before twins, {} to render after twins ({} twins); {} pruned, {} filtered out",
        exp.cells.len(),
        rendered,
        exp.cells.len() - rendered,
        exp.pruned.len(),
        exp.filtered_out
    );
    for c in &exp.cells {
        let _ = match &c.twin_of {
            None => writeln!(out, "  {}", c.id),
            Some(t) => writeln!(out, "  {}  = {} ({} ignores the differing axes)", c.id, t, c.shader),
        };
    }
    for p in &exp.pruned {
        let _ = writeln!(out, "  pruned {}: {}", p.description, p.reason);
    }
    out
}

/// The LOD levels each camera distance of the matrix draws (the scene's own camera when the
/// matrix does not sweep it), as the renderer selects them.
fn lod_plan(m: &Matrix, scene: &crate::declarations::scene::Scene, meshes: &[crate::geometry::Mesh]) -> String {
    let mut out = String::new();
    if scene.objects.iter().all(|o| o.lod.is_none()) {
        return out;
    }
    let bounds: Vec<_> = scene
        .objects
        .iter()
        .zip(meshes)
        .map(|(o, mesh)| crate::geometry::placement::world_bounds_of(o, &mesh.bounds()))
        .collect();
    let distances: Vec<Option<f64>> = match m.sweep.numbers(crate::declarations::axes::Axis::CameraDistance).is_empty()
    {
        true => vec![None],
        false => m.sweep.numbers(crate::declarations::axes::Axis::CameraDistance).iter().copied().map(Some).collect(),
    };
    for (p, d) in m.pipelines.iter().flat_map(|p| distances.iter().map(move |d| (*p, *d))) {
        let view = crate::plan::camera::ViewAxes { camera_distance: d, light_angle: None };
        let camera = crate::plan::camera::posed_camera(&scene.camera, &view);
        let at = d.map_or("the scene's camera".to_string(), |d| format!("camera distance {d}"));
        for seen in crate::plan::lod::groups_seen(scene, &bounds, &camera, p.quality_lod_bias()) {
            // Built-in's shaders have no cross-fade variant: a band draws both levels whole.
            let how = if p == crate::pipelines::Pipeline::Builtin { "drawn whole" } else { "dithered" };
            let levels: Vec<String> = seen
                .drawn
                .iter()
                .map(|l| match l.fade {
                    f if f >= 1.0 => format!("level {}", l.level),
                    f => format!("level {} (fade {f:+.2}, {how})", l.level),
                })
                .collect();
            let drawn = if levels.is_empty() { "culled".to_string() } else { levels.join(" + ") };
            let name = &scene.objects[seen.object].name;
            let _ = writeln!(
                out,
                "  LOD at {at} ({}): {name} at {:.1} % of the screen: {drawn}",
                p.name(),
                seen.relative_height * 100.0
            );
        }
    }
    out
}

/// How each light reaches each object in every pipeline × path of the matrix, at the scene's own
/// key-light values (a cell's sweep values can reorder lights by brightness; `cell.json` has each
/// cell's).
fn light_plan(m: &Matrix, scene: &crate::declarations::scene::Scene) -> String {
    let mut out = String::new();
    let meshes = match crate::geometry::procedural::build_scene_shapes(scene) {
        Ok(meshes) => meshes,
        Err(e) => {
            let _ = writeln!(out, "  lights: cannot place the objects ({e})");
            return out;
        }
    };
    out.push_str(&lod_plan(m, scene, &meshes));
    if scene.lights.is_empty() {
        let _ = writeln!(out, "  lights: none");
        return out;
    }
    let centres = crate::geometry::placement::object_centres(scene, &meshes);
    let key = scene.key_light().map(|k| &scene.lights[k]);
    let (intensity, range) = key.map_or((0.0, 0.0), |k| (k.intensity, k.range));
    let lights = crate::plan::camera::cell_lights(scene, intensity, range, &scene.camera, &Default::default());
    // A ForwardBase-only shader (the forum shader `torrance_sparrow`) is lit by the main
    // directional light alone: where the composition has none, no light reaches it.
    for s in &m.shaders {
        for p in &m.pipelines {
            let base_only = m.registry.find(*p, s).is_some_and(|model| model.main_light_only);
            if base_only && crate::plan::lights::main_light(*p, &lights).is_none() {
                let _ = writeln!(
                    out,
                    "  {s} ({}): a ForwardBase-only shader and {} has no directional light, so none of its lights \
                     reaches it: it shows only its ambient (× the absent main light's colour: none) and its \
                     reflection, and adds no emission",
                    p.name(),
                    scene.name
                );
            }
        }
    }
    for p in &m.pipelines {
        for path in &m.paths {
            // Planned for a model that draws rect lights; the shaders that have no area-light BSDF
            // are named below.
            let main = crate::plan::lights::main_light(*p, &lights);
            let gi = scene.gi.as_ref().map(|g| crate::plan::gi::GiPlan::new(g, *p, &lights, main));
            let plan = assign(*p, *path, &m.light_budget, &lights, &centres, |i| {
                let dynamic = scene.objects[i].role == crate::declarations::scene::Role::Subject;
                let baked = gi.as_ref().map_or_else(Vec::new, |g| g.baked_alone(dynamic));
                let lightmapped = gi.is_some() && !dynamic;
                crate::plan::lights::ModelLighting { forward_only: false, area_lights: true, baked, lightmapped }
            });
            if let Some(gi) = &gi {
                let _ = writeln!(out, "  baked lighting in {}: {}", p.name(), gi.summary());
            }
            let label = format!("{}-{}", p.name(), path.name());
            let rects: Vec<String> = (0..lights.len())
                .filter(|&i| crate::plan::lights::area_left_out(*p, &lights[i], true).is_none() && lights[i].is_area())
                .map(|i| i.to_string())
                .collect();
            let no_area: Vec<&str> = m
                .shaders
                .iter()
                .filter(|s| m.registry.find(*p, s).is_some_and(|model| !model.area_lights()))
                .map(|s| s.as_str())
                .collect();
            if !rects.is_empty() && !no_area.is_empty() {
                let _ = writeln!(
                    out,
                    "  {label}: {} ha{} no area-light BSDF: rect lights [{}] are left out of their frames",
                    no_area.join(", "),
                    if no_area.len() == 1 { "s" } else { "ve" },
                    rects.join(", ")
                );
            }
            let forward_only: Vec<&str> = m
                .shaders
                .iter()
                .filter(|s| m.registry.find(*p, s).is_some_and(|model| !model.deferrable()))
                .map(|s| s.as_str())
                .collect();
            if *path == crate::pipelines::RenderPath::Deferred && !forward_only.is_empty() {
                let _ = writeln!(
                    out,
                    "  {label}: {} cannot be drawn into the G-buffer: the subject draws forward after the \
                     lighting, with {}-forward's light budget",
                    forward_only.join(", "),
                    p.name()
                );
            }
            if plan.iter().all(|o| o.lights.iter().all(|u| u.mode == LightMode::PerPixel)) {
                let _ = writeln!(out, "  lights in {label}: all {} per-pixel on every object", lights.len());
                continue;
            }
            let _ = writeln!(out, "  lights in {label}:");
            for o in &plan {
                let group = |mode: LightMode| -> Vec<String> {
                    o.lights.iter().filter(|u| u.mode == mode).map(|u| u.light.to_string()).collect()
                };
                let parts: Vec<String> = [
                    LightMode::PerPixel,
                    LightMode::PerVertex,
                    LightMode::Sh,
                    LightMode::Dropped,
                    LightMode::LeftOut,
                    LightMode::Baked,
                ]
                .into_iter()
                .filter_map(|mode| {
                    let g = group(mode);
                    (!g.is_empty()).then(|| format!("{} [{}]", mode.name(), g.join(", ")))
                })
                .collect();
                let _ = writeln!(out, "    {}: {}", o.object, parts.join("; "));
                for u in o.lights.iter().filter(|u| matches!(u.mode, LightMode::Dropped | LightMode::LeftOut)) {
                    let _ = writeln!(out, "      lights[{}] {}: {}", u.light, u.mode.name(), u.reason);
                }
            }
        }
    }
    out
}

/// How many bakes the composition's cells need (render::gi): one per pipeline and per value of
/// the axes a baked or mixed key light takes (intensity, range, angle) and of the ambient axis;
/// every other axis (the subject's material above all: the subject is dynamic) shares one.
fn bake_line(m: &Matrix, cells: &[crate::cells::Cell], scene: &crate::declarations::scene::Scene) -> String {
    let Some(gi) = &scene.gi else { return String::new() };
    let Some(index) = m.compositions.iter().position(|s| std::ptr::eq(s, scene)) else { return String::new() };
    let key_baked = scene.key_light().is_some_and(|k| {
        let l = &scene.lights[k];
        !l.mode.is_realtime() || l.is_area()
    });
    let mut keys = std::collections::BTreeSet::new();
    let mut count = 0usize;
    for c in cells.iter().filter(|c| c.composition_index == index && c.twin_of.is_none()) {
        count += 1;
        let key_values =
            key_baked.then(|| [c.light_intensity, c.light_range, c.light_angle.unwrap_or(f64::NAN)].map(f64::to_bits));
        keys.insert((c.pipeline.name(), key_values, c.ambient_intensity.map(f64::to_bits)));
    }
    format!(
        "  bakes: {} for its {count} rendered cells ({} texels per unit, {} samples, {} bounces{}); each is made once per run and shared\n",
        keys.len(),
        gi.texels_per_unit,
        gi.samples,
        gi.bounces,
        if gi.probes.is_some() { ", a light-probe grid" } else { "" }
    )
}

/// What each cell is compared against, in words.
fn reference_line(m: &crate::declarations::matrix::Matrix) -> String {
    use crate::declarations::matrix::ReferenceSpec;
    match &m.reference {
        None => "none (no metrics)".into(),
        Some(ReferenceSpec::Cell(terms)) => {
            use crate::declarations::matrix::FilterValue;
            let value = |v: &FilterValue| match v {
                FilterValue::Name(n) | FilterValue::Color(n) => n.clone(),
                FilterValue::Number(x) => x.to_string(),
            };
            let t: Vec<String> = terms.iter().map(|(a, v)| format!("{} = {}", a.name(), value(v))).collect();
            format!("the cell with {}", t.join(", "))
        }
        Some(ReferenceSpec::Supersampled(k)) => format!("the same cell at {k}× the resolution, box-filtered down"),
        Some(ReferenceSpec::Run(dir)) => format!("the cell of the same id in {}", dir.display()),
        Some(ReferenceSpec::Truth(t)) => {
            let s = &t.settings;
            format!(
                "the cell's path-traced {} truth: until the subject's relative standard error is {} % or {} samples per pixel, {} bounces; cached beside the run folders",
                s.kind.name(),
                s.noise * 100.0,
                s.spp,
                s.bounces
            )
        }
    }
}

/// Which fixed objects draw maps of their own and from where (`FixedMaterial::base_color_map`,
/// `gltf_material`); nothing when none does.
fn fixed_maps_line(scene: &crate::declarations::scene::Scene) -> String {
    let named: Vec<String> = scene
        .objects
        .iter()
        .filter_map(|o| {
            let m = o.material.as_ref()?;
            let from = match (&m.base_color_map, &m.gltf_material) {
                (Some(path), _) => path.clone(),
                (None, Some(r)) => format!("{} material {}", r.path, r.index),
                (None, None) => return None,
            };
            Some(format!("{} ({from})", o.name))
        })
        .collect();
    match named.len() {
        0 => String::new(),
        n if n > 6 => format!("  fixed objects with maps of their own: {n}, {} …\n", named[..6].join(", ")),
        n => format!("  fixed objects with maps of their own: {n}, {}\n", named.join(", ")),
    }
}
