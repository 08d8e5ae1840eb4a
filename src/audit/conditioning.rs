//! Conditioning: where each model's GPU f32 result drifts from its f64 twin as the roughness
//! α = (1 − smoothness)² goes from 1 to 1e-4 and N·V from 1 to 1e-4. Every point sits at the
//! specular peak — L the mirror of V about N, so N·H = 1 and N·L = N·V — where the D and V terms are
//! stiffest; white metal, so the specular lobe is all there is. The twin receives the f32-rounded
//! inputs the GPU received, so the difference is the f32 arithmetic alone. Per model: α*, the
//! largest α at which some N·V of the grid has a relative error above 1e-3 (below α* precision is
//! lost somewhere), N·V* likewise over every α; and the guard (the WGSL function) that bounds the
//! stiff terms there.

use glam::DVec3;
use serde::Serialize;
use std::fmt::Write;

use crate::error::Error;
use crate::gpu::GpuContext;
use crate::pipelines::Pipeline;
use crate::render::probe::{BrdfProbe, ProbeInput};
use crate::shading::registry::{Registry, ShaderModel, Sliders};

/// Relative error that counts as lost precision.
pub const TOLERANCE: f64 = 1e-3;
/// Grid steps per decade and decades: 10^(−k/4), k = 0..=16.
const STEPS_PER_DECADE: i32 = 4;
const DECADES: i32 = 4;
/// The column the N·V plot shows: a moderately rough α.
pub const NV_COLUMN_ALPHA: f64 = 0.316_227_766_016_837_94;

/// The grid values, 1 down to 1e-4.
pub fn grid() -> Vec<f64> {
    (0..=STEPS_PER_DECADE * DECADES).map(|k| 10f64.powf(-k as f64 / STEPS_PER_DECADE as f64)).collect()
}

#[derive(Debug, Clone, Serialize)]
pub struct ConditioningPoint {
    pub alpha: f64,
    pub nv: f64,
    /// max over RGB of |gpu − twin| / |twin| (∞ when either is not finite; 0 when both are 0).
    pub relative_error: f64,
    pub twin: f64,
    pub gpu: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct ModelConditioning {
    /// `pipeline/name`.
    pub key: String,
    pub points: Vec<ConditioningPoint>,
    /// Largest α at which some grid point has a relative error above `TOLERANCE`; None: none
    /// down to 1e-4.
    pub alpha_threshold: Option<f64>,
    /// Largest N·V at which some grid point has a relative error above `TOLERANCE`.
    pub nv_threshold: Option<f64>,
    /// The function that bounds the stiff terms, as the model's WGSL names it.
    pub guard: String,
}

/// The conditioning grid of one model in one pipeline.
pub fn condition_model(
    gpu: &GpuContext,
    probe: &mut BrdfProbe,
    model: &ShaderModel,
    p: Pipeline,
) -> Result<Option<ModelConditioning>, Error> {
    let Some(twin) = model.twin else { return Ok(None) };
    let values = grid();
    let n = DVec3::Y;
    let mut cases = Vec::new();
    for &alpha in &values {
        for &nv in &values {
            let sin = (1.0 - nv * nv).max(0.0).sqrt();
            let v = DVec3::new(sin, nv, 0.0);
            let l = DVec3::new(-sin, nv, 0.0);
            let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 1.0, smoothness: 1.0 - alpha.sqrt() };
            cases.push((alpha, nv, model.surface(p, &sliders), v, l));
        }
    }
    let inputs: Vec<ProbeInput> =
        cases.iter().map(|(_, _, s, v, l)| ProbeInput::new(s, n, *v, *l, DVec3::ZERO, DVec3::ZERO)).collect();
    let out = probe.evaluate(gpu, p, model, &inputs)?;
    let points: Vec<ConditioningPoint> = cases
        .iter()
        .zip(&out)
        .map(|((alpha, nv, s, v, l), (direct, _))| {
            let r = |x: DVec3| x.as_vec3().as_dvec3();
            let expected = twin.direct(p, &s.rounded_f32(), n, r(*v), r(*l));
            let mut worst: f64 = 0.0;
            for k in 0..3 {
                let (g, c) = (direct[k] as f64, expected[k]);
                let e = if !g.is_finite() || !c.is_finite() {
                    f64::INFINITY
                } else if g == c {
                    0.0
                } else {
                    (g - c).abs() / c.abs().max(f64::MIN_POSITIVE)
                };
                worst = worst.max(e);
            }
            ConditioningPoint {
                alpha: *alpha,
                nv: *nv,
                relative_error: worst,
                twin: expected.max_element(),
                gpu: direct.iter().fold(f32::MIN, |a, b| a.max(*b)) as f64,
            }
        })
        .collect();
    let exceeds = |pt: &&ConditioningPoint| pt.relative_error > TOLERANCE;
    let alpha_threshold = points.iter().filter(exceeds).map(|pt| pt.alpha).reduce(f64::max);
    let nv_threshold = points.iter().filter(exceeds).map(|pt| pt.nv).reduce(f64::max);
    Ok(Some(ModelConditioning {
        key: format!("{}/{}", p.name(), model.name),
        points,
        alpha_threshold,
        nv_threshold,
        guard: model.stiff_terms.to_string(),
    }))
}

/// Every model with a twin (or those of one name), every pipeline it has.
pub fn condition_all(
    gpu: &GpuContext,
    registry: &Registry,
    shader: Option<&str>,
) -> Result<Vec<ModelConditioning>, Error> {
    let mut probe = BrdfProbe::new(gpu);
    let mut out = Vec::new();
    for model in registry.models() {
        if shader.is_some_and(|s| s != model.name) {
            continue;
        }
        for &p in &model.pipelines {
            out.extend(condition_model(gpu, &mut probe, model, p)?);
        }
    }
    Ok(out)
}

fn threshold(v: Option<f64>) -> String {
    v.map_or_else(|| "none down to 1e-4".into(), |x| format!("{x:.3e}"))
}

pub fn markdown(models: &[ModelConditioning], adapter: &str) -> String {
    let mut s = format!(
        "# Conditioning: GPU f32 against the f64 twin\n\nAdapter: {adapter}. At the specular peak (L the mirror of V, \
         N·H = 1), white metal. α*: the largest α at which some N·V of the grid has a relative error above \
         {TOLERANCE:e}; N·V*: the largest N·V at which some α does. The grid runs 1 → 1e-4, four \
         steps a decade; tables/conditioning.csv has every point, plots/conditioning_*.svg the rows and columns.\n\n\
         | model | α* | N·V* | worst relative error (at α, N·V) | guard |\n|---|---|---|---|---|\n"
    );
    for m in models {
        let worst = m.points.iter().max_by(|a, b| a.relative_error.total_cmp(&b.relative_error));
        let w = worst
            .map_or_else(String::new, |p| format!("{:.2e} (α {:.1e}, N·V {:.1e})", p.relative_error, p.alpha, p.nv));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {w} | {} |",
            m.key,
            threshold(m.alpha_threshold),
            threshold(m.nv_threshold),
            m.guard
        );
    }
    s
}

pub fn csv(models: &[ModelConditioning]) -> String {
    let mut s = String::from("model,alpha,nv,relative_error,twin_max,gpu_max\n");
    for m in models {
        for p in &m.points {
            let _ = writeln!(s, "{},{:e},{:e},{:e},{:e},{:e}", m.key, p.alpha, p.nv, p.relative_error, p.twin, p.gpu);
        }
    }
    s
}

/// A log–log plot of relative error against one grid axis, a line per model: the N·V = 1 row
/// against α, or the α = `NV_COLUMN_ALPHA` column against N·V. Drawn with plotters in decades
/// (x = −log10 of the axis, so 1 is on the left; y = log10 of the error, clamped to 1e−8…1e2,
/// non-finite errors at the top) with the tolerance dashed.
pub fn svg(models: &[ModelConditioning], against_alpha: bool) -> Result<String, Error> {
    use plotters::prelude::*;
    let axis = if against_alpha { "α (N·V = 1)" } else { "N·V (α = 0.316)" };
    let what = format!("the conditioning plot against {axis}");
    let fail = |e: &dyn std::fmt::Display| crate::report::plot_style::failed(&what, e);
    let (lo_e, hi_e) = (-8.0f64, 2.0f64);
    let decade = |e: f64| if e.is_finite() { e.max(1e-8).log10().min(hi_e) } else { hi_e };
    let palette = crate::report::plot_style::PALETTE;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (760, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        // The models' names beside the plot, not over it: thirty lines would hide the curves.
        let (plot, legend) = root.split_horizontally(540);
        let mut chart = ChartBuilder::on(&plot)
            .caption(format!("GPU f32 vs f64 twin: relative error against {axis}"), ("sans-serif", 15))
            .margin(14)
            .x_label_area_size(42)
            .y_label_area_size(56)
            .build_cartesian_2d(0f64..DECADES as f64, lo_e..hi_e)
            .map_err(|e| fail(&e))?;
        chart
            .configure_mesh()
            .x_desc(format!("{axis}, log scale"))
            .y_desc("relative error")
            .x_labels(DECADES as usize + 1)
            .x_label_formatter(&|d| format!("1e-{}", d.round() as i32))
            .y_labels(6)
            .y_label_formatter(&|e| format!("1e{}", e.round() as i32))
            .light_line_style(WHITE)
            .draw()
            .map_err(|e| fail(&e))?;
        let tolerance = decade(TOLERANCE);
        chart
            .draw_series(DashedLineSeries::new(
                [(0.0, tolerance), (DECADES as f64, tolerance)],
                4,
                3,
                RGBColor(0x99, 0x99, 0x99).into(),
            ))
            .map_err(|e| fail(&e))?;
        let mut shown = 0;
        for m in models {
            let line: Vec<&ConditioningPoint> = m
                .points
                .iter()
                .filter(|p| if against_alpha { p.nv == 1.0 } else { (p.alpha - NV_COLUMN_ALPHA).abs() < 1e-12 })
                .collect();
            if line.iter().all(|p| p.relative_error == 0.0) {
                continue;
            }
            let colour = palette[shown % palette.len()];
            let xy =
                line.iter().map(|p| (-(if against_alpha { p.alpha } else { p.nv }).log10(), decade(p.relative_error)));
            let series = if (shown / palette.len()) % 2 == 1 {
                chart.draw_series(DashedLineSeries::new(xy, 5, 2, colour.stroke_width(2)))
            } else {
                chart.draw_series(LineSeries::new(xy, colour.stroke_width(2)))
            };
            series.map_err(|e| fail(&e))?;
            let y = 30 + 11 * shown as i32;
            legend.draw(&PathElement::new([(4, y), (20, y)], colour.stroke_width(2))).map_err(|e| fail(&e))?;
            legend
                .draw(&Text::new(m.key.clone(), (24, y - 5), ("sans-serif", 10).into_font().color(&colour)))
                .map_err(|e| fail(&e))?;
            shown += 1;
        }
        root.present().map_err(|e| fail(&e))?;
    }
    Ok(out)
}

/// tables/conditioning.{md,csv} and plots/conditioning_{alpha,nv}.svg under `dir`.
pub fn write(dir: &std::path::Path, models: &[ModelConditioning], adapter: &str) -> Result<(), Error> {
    use crate::fsutil::write_atomic;
    write_atomic(&dir.join("tables/conditioning.md"), markdown(models, adapter).as_bytes())?;
    write_atomic(&dir.join("tables/conditioning.csv"), csv(models).as_bytes())?;
    write_atomic(&dir.join("plots/conditioning_alpha.svg"), svg(models, true)?.as_bytes())?;
    write_atomic(&dir.join("plots/conditioning_nv.svg"), svg(models, false)?.as_bytes())
}
