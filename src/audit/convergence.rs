//! Convergence of the tool's own numerics: error against run time as each integrator's sample
//! count (or resolution) grows, against a converged reference computed the same way with far more
//! samples. Three studies, all on the CPU in f64 (what the tool runs before it renders):
//!
//! - **FGD table** (HDRP's pre-integrated DFG, `shading::fgd`): samples per texel at 64², and the
//!   table's resolution at 4096 samples; error = largest |Δ| of (x, y, z) at scattered (N·V, pr)
//!   points through the bilinear lookup the renderer uses, so interpolation counts too;
//! - **probe prefilter** (`environment::prefilter`): the texels each output texel's convolution sums
//!   (the source's width w, w²/2 texels), per mip level of GGX α, on the procedural sky with its sun
//!   (mitsuba's); error = largest relative |Δ| over directions;
//! - **furnace** (`audit::twin_albedo`, the energy audit): MIS samples per directional albedo on
//!   smooth and medium metals at 60° and 85°; error = largest |Δ| of the albedo.
//!
//! Where a curve flattens (its knee) is the first count after which the next step of the sweep
//! gains less than half the error; the report says where each default sits against it.

use std::fmt::Write;
use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;

use crate::environment::filtered::{self, LobeWeight};
use crate::environment::prefilter::{
    level_alpha, source_width, EquirectImage, TexelTable, LEVELS, PROBE_WIDTH, SOURCE_WIDTH,
};
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::pipelines::Pipeline;
use crate::shading::fgd::{integrate, FgdTable, FGD_SAMPLES, FGD_SIZE};
use crate::shading::registry::{Registry, Sliders};

/// How far each study sweeps, and its reference.
#[derive(Debug, Clone)]
pub struct Settings {
    pub fgd_samples: Vec<u32>,
    pub fgd_sizes: Vec<usize>,
    pub fgd_reference_samples: u32,
    pub fgd_points: usize,
    pub prefilter_widths: Vec<usize>,
    pub prefilter_reference_width: usize,
    pub prefilter_directions: usize,
    pub furnace_samples: Vec<u32>,
    pub furnace_reference_samples: u32,
}

impl Settings {
    /// The sweep of `shadematrix convergence`: 256…65536 samples.
    pub fn full() -> Settings {
        Settings {
            fgd_samples: vec![256, 1024, 4096, 16384, 65536],
            fgd_sizes: vec![16, 32, 64, 128],
            fgd_reference_samples: 1 << 20,
            fgd_points: 256,
            // The reference is 4× finer than the finest point: an error measured against a
            // reference one halving away reads too small.
            prefilter_widths: vec![32, 64, 128, 256],
            prefilter_reference_width: 1024,
            prefilter_directions: 64,
            furnace_samples: vec![256, 1024, 4096, 16384, 65536],
            furnace_reference_samples: 1 << 20,
        }
    }

    /// A few seconds' worth, for tests (`--quick`).
    pub fn quick() -> Settings {
        Settings {
            fgd_samples: vec![64, 256, 1024],
            fgd_sizes: vec![8, 16, 32],
            fgd_reference_samples: 1 << 14,
            fgd_points: 32,
            prefilter_widths: vec![16, 32, 64],
            prefilter_reference_width: 256,
            prefilter_directions: 16,
            furnace_samples: vec![256, 1024, 4096],
            furnace_reference_samples: 1 << 16,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct ConvergencePoint {
    /// Samples, texels per side or texels summed: the curve's knob.
    pub knob: u64,
    /// Wall time of what this count costs (named by the curve).
    pub ms: f64,
    /// The largest error over the study's points (what the knee is judged on).
    pub error: f64,
    /// The root-mean-square error over them.
    pub rms: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Curve {
    /// fgd, prefilter or furnace: one plot each.
    pub study: &'static str,
    pub name: String,
    /// What the knob counts.
    pub knob: &'static str,
    /// What `ms` times.
    pub timed: &'static str,
    pub error: &'static str,
    pub reference: String,
    /// The count the tool uses.
    pub default: u64,
    /// Where the default comes from.
    pub default_why: &'static str,
    pub points: Vec<ConvergencePoint>,
}

impl Curve {
    /// The first count after which the next step of the sweep gains less than half the error.
    pub fn knee(&self) -> Option<u64> {
        let p = &self.points;
        (0..p.len().saturating_sub(1))
            .find(|&i| p[i + 1].error > 0.5 * p[i].error)
            .map(|i| p[i].knob)
            .or(p.last().map(|l| l.knob))
    }

    /// Where the default sits against the knee, in words.
    pub fn verdict(&self) -> String {
        let at = |k: u64| self.points.iter().find(|p| p.knob == k);
        let (Some(knee), Some(d)) = (self.knee(), at(self.default)) else {
            return format!("default {} is outside the sweep", self.default);
        };
        let k = at(knee).expect("the knee is a point");
        match self.default.cmp(&knee) {
            std::cmp::Ordering::Equal => {
                format!("default {} is at the knee (error {:.2e}, {:.1} ms)", self.default, d.error, d.ms)
            }
            std::cmp::Ordering::Greater => format!(
                "default {} is past the knee {knee}: {:.1}× its time for {:.1}× less error ({:.2e} vs {:.2e})",
                self.default,
                d.ms / k.ms.max(1e-9),
                k.error / d.error.max(1e-300),
                d.error,
                k.error
            ),
            std::cmp::Ordering::Less => format!(
                "default {} is before the knee {knee}: error {:.2e} where {knee} reaches {:.2e} in {:.1}× the time",
                self.default,
                d.error,
                k.error,
                k.ms / d.ms.max(1e-9)
            ),
        }
    }
}

/// HDRP's own: IntegrateGGXAndDisneyDiffuseFGD(NdotV, roughness, sampleCount = 4096) into a 64² LUT
/// (ImageBasedLighting.hlsl, preIntegratedFGD_GGXDisneyDiffuse.shader).
const HDRP_FGD: &str = "HDRP's own table: IntegrateGGXAndDisneyDiffuseFGD(…, sampleCount = 4096) into a 64² LUT \
                        (ImageBasedLighting.hlsl)";

/// The largest and the root-mean-square of some errors.
fn max_and_rms(errors: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut max, mut sq, mut n) = (0.0f64, 0.0, 0usize);
    for e in errors {
        max = if e.is_nan() { f64::NAN } else { max.max(e) };
        sq += e * e;
        n += 1;
    }
    (max, (sq / n.max(1) as f64).sqrt())
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Halton (2, 3) point i in [0, 1)².
fn halton(i: usize) -> (f64, f64) {
    let radical = |mut i: usize, b: usize| {
        let (mut f, mut r) = (1.0, 0.0);
        while i > 0 {
            f /= b as f64;
            r += f * (i % b) as f64;
            i /= b;
        }
        r
    };
    (radical(i + 1, 2), radical(i + 1, 3))
}

fn fgd_curves(s: &Settings) -> Vec<Curve> {
    // Scattered (N·V, pr): √NV and pr uniform, as the table's axes are.
    let points: Vec<(f64, f64)> = (0..s.fgd_points).map(halton).map(|(u, v)| (u * u, v)).collect();
    let reference: Vec<DVec3> =
        points.par_iter().map(|&(nv, pr)| DVec3::from(integrate(nv, pr, s.fgd_reference_samples))).collect();
    let error = |t: &FgdTable| {
        max_and_rms(points.iter().zip(&reference).map(|(&(nv, pr), r)| (t.lookup(nv, pr) - *r).abs().max_element()))
    };
    let reference_text =
        format!("{} Hammersley samples at {} scattered (N·V, pr) points", s.fgd_reference_samples, s.fgd_points);
    let sweep = |name: String, knob: &'static str, default: u64, values: Vec<u64>, build: &dyn Fn(u64) -> FgdTable| {
        let mut curve = Curve {
            study: "fgd",
            name,
            knob,
            timed: "building the table (all texels, every core)",
            error: "largest |Δ| of x, y, z through the bilinear lookup",
            reference: reference_text.clone(),
            default,
            default_why: HDRP_FGD,
            points: Vec::new(),
        };
        for knob in values {
            let t0 = Instant::now();
            let table = build(knob);
            let ms = ms_since(t0);
            let (error, rms) = error(&table);
            curve.points.push(ConvergencePoint { knob, ms, error, rms });
        }
        curve
    };
    vec![
        sweep(
            format!("FGD table {FGD_SIZE}², samples per texel"),
            "samples per texel",
            FGD_SAMPLES as u64,
            s.fgd_samples.iter().map(|&n| n as u64).collect(),
            &|n| FgdTable::build(FGD_SIZE, n as u32),
        ),
        sweep(
            format!("FGD table at {FGD_SAMPLES} samples, texels per side"),
            "texels per side",
            FGD_SIZE as u64,
            s.fgd_sizes.iter().map(|&n| n as u64).collect(),
            &|size| FgdTable::build(size as usize, FGD_SAMPLES),
        ),
    ]
}

/// Directions spread over the sphere (Fibonacci).
fn sphere_directions(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

fn prefilter_curves(s: &Settings) -> Result<Vec<Curve>, Error> {
    let scene = crate::declarations::scene::Scene::load("mitsuba", None, "convergence study", "composition")?;
    let sky = scene.environment.sky.clone();
    let radiance = |d: DVec3| crate::environment::sky::radiance(&sky, d);
    let mut image = EquirectImage::sample(&radiance, s.prefilter_reference_width, s.prefilter_reference_width / 2, 4);
    let reference_table = TexelTable::new(&image);
    let mut tables = Vec::new();
    while image.width > *s.prefilter_widths.iter().min().unwrap_or(&1) {
        image = image.half();
        if s.prefilter_widths.contains(&image.width) {
            tables.push((image.width, TexelTable::new(&image)));
        }
    }
    tables.sort_by_key(|(w, _)| *w);
    let dirs = sphere_directions(s.prefilter_directions);
    let level_texels = (PROBE_WIDTH * PROBE_WIDTH / 2) as f64;
    let mut curves = Vec::new();
    // Level 1's lobe is narrower than a texel: the renderer copies the mirror image (no convolution).
    for level in 2..LEVELS {
        let alpha = level_alpha(level);
        let reference: Vec<DVec3> = dirs.par_iter().map(|d| reference_table.convolve(*d, alpha)).collect();
        let default = source_width(alpha);
        let mut curve = Curve {
            study: "prefilter",
            name: format!("probe level {level} (α = {alpha:.3}), source texels summed"),
            knob: "source texels summed (w²/2)",
            timed: "one 128×64 level, from the time of the sampled directions (one core)",
            error: "largest relative |Δ| of the convolved radiance",
            reference: format!(
                "{}×{} source ({} texels), {} directions",
                s.prefilter_reference_width,
                s.prefilter_reference_width / 2,
                s.prefilter_reference_width * s.prefilter_reference_width / 2,
                dirs.len()
            ),
            default: (default * default / 2) as u64,
            default_why: "prefilter::source_width: the narrowest source whose error stays near 5e-3 on a sun-lit sky, \
                          from this study",
            points: Vec::new(),
        };
        for (w, table) in &tables {
            let t0 = Instant::now();
            let got: Vec<DVec3> = dirs.iter().map(|d| table.convolve(*d, alpha)).collect();
            let ms = ms_since(t0) / dirs.len() as f64 * level_texels;
            let (error, rms) = max_and_rms(
                got.iter().zip(&reference).map(|(g, r)| (*g - *r).abs().max_element() / r.max_element().max(1e-12)),
            );
            curve.points.push(ConvergencePoint { knob: (w * w / 2) as u64, ms, error, rms });
        }
        let reference_name = curve.reference.clone();
        curves.push(curve);
        // The captured probes' prefilter: filtered importance sampling of the 256-wide source's
        // mip chain, against the same reference lobe (D·N·L, the built-in and URP weight).
        let chain = filtered::mip_chain(&EquirectImage::sample(&radiance, SOURCE_WIDTH, SOURCE_WIDTH / 2, 4));
        let mut sampled = Curve {
            study: "prefilter",
            name: format!("probe level {level} (α = {alpha:.3}), filtered importance samples"),
            knob: "GGX samples per texel",
            timed: "one 128×64 level, from the time of the sampled directions (one core)",
            error: "largest relative |Δ| of the convolved radiance",
            reference: reference_name,
            default: filtered::sample_count(level) as u64,
            default_why: "HDRP's GetIBLRuntimeFilterSampleCount for this level (IntegrateLD), which the captured \
                          probes' prefilter uses",
            points: Vec::new(),
        };
        for n in [21u32, 34, 55, 89, 144, 233, 377] {
            let t0 = Instant::now();
            let got: Vec<DVec3> =
                dirs.iter().map(|d| filtered::integrate(&chain, *d, alpha, n, LobeWeight::CosineWeighted)).collect();
            let ms = ms_since(t0) / dirs.len() as f64 * level_texels;
            let (error, rms) = max_and_rms(
                got.iter().zip(&reference).map(|(g, r)| (*g - *r).abs().max_element() / r.max_element().max(1e-12)),
            );
            sampled.points.push(ConvergencePoint { knob: n as u64, ms, error, rms });
        }
        curves.push(sampled);
    }
    Ok(curves)
}

fn furnace_curve(s: &Settings) -> Curve {
    let registry = Registry::builtin();
    let mut cases = Vec::new();
    for (p, name) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit"), (Pipeline::Hdrp, "lit")] {
        let Some(model) = registry.find(p, name) else { continue };
        let Some(twin) = model.twin else { continue };
        for smoothness in [0.5, 0.9] {
            let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 1.0, smoothness };
            for deg in [60.0f64, 85.0] {
                let v = DVec3::new(deg.to_radians().sin(), deg.to_radians().cos(), 0.0);
                cases.push((twin, p, model.surface(p, &sliders), v, super::albedo_alpha(&sliders)));
            }
        }
    }
    let reference: Vec<f64> = cases
        .par_iter()
        .map(|(t, p, surface, v, alpha)| super::twin_albedo(*t, *p, surface, *v, *alpha, s.furnace_reference_samples))
        .collect();
    let mut curve = Curve {
        study: "furnace",
        name: "white-furnace albedo, MIS samples".into(),
        knob: "samples per albedo",
        timed: "one albedo estimate (one core)",
        error: "largest |Δ| of the directional albedo",
        reference: format!(
            "{} samples; built-in Standard, URP Lit, HDRP Lit twins; white metal, smoothness 0.5 and 0.9, view 60° and 85°",
            s.furnace_reference_samples
        ),
        default: super::ENERGY_SAMPLES_TWIN as u64,
        default_why: "the audit's energy check allows 5e-3 (ENERGY_TOLERANCE): the default keeps the estimate's \
                      error well inside it",
        points: Vec::new(),
    };
    for &n in &s.furnace_samples {
        let t0 = Instant::now();
        let got: Vec<f64> =
            cases.iter().map(|(t, p, surface, v, alpha)| super::twin_albedo(*t, *p, surface, *v, *alpha, n)).collect();
        let ms = ms_since(t0) / cases.len().max(1) as f64;
        let (error, rms) = max_and_rms(got.iter().zip(&reference).map(|(g, r)| (g - r).abs()));
        curve.points.push(ConvergencePoint { knob: n as u64, ms, error, rms });
    }
    curve
}

/// Every study.
pub fn study(s: &Settings) -> Result<Vec<Curve>, Error> {
    let mut curves = fgd_curves(s);
    curves.extend(prefilter_curves(s)?);
    curves.push(furnace_curve(s));
    Ok(curves)
}

pub fn markdown(curves: &[Curve], machine: &str) -> String {
    let mut md = format!(
        "# Convergence of the tool's own numerics\n\nOn {machine}. Error against a converged reference versus wall time, \
         per count; the knee is the first count after which the next step gains less than half the error. Plots: \
         plots/convergence_{{fgd,prefilter,furnace}}.svg.\n"
    );
    for c in curves {
        let _ = writeln!(
            md,
            "\n## {}\n\nError: {}; reference: {}; time: {}. Default: {}.\n\n**{}**.\n\n| {} | ms | error (largest) | error (RMS) |\n|---|---|---|---|",
            c.name,
            c.error,
            c.reference,
            c.timed,
            c.default_why,
            c.verdict(),
            c.knob
        );
        for p in &c.points {
            let mark = match (p.knob == c.default, Some(p.knob) == c.knee()) {
                (true, true) => " (default, knee)",
                (true, false) => " (default)",
                (false, true) => " (knee)",
                _ => "",
            };
            let _ = writeln!(md, "| {}{mark} | {:.2} | {:.3e} | {:.3e} |", p.knob, p.ms, p.error, p.rms);
        }
    }
    md
}

pub fn csv(curves: &[Curve]) -> String {
    let mut s = String::from("study,curve,knob,ms,error,rms,default,knee\n");
    for c in curves {
        for p in &c.points {
            let _ = writeln!(
                s,
                "{},\"{}\",{},{:.4},{:e},{:e},{},{}",
                c.study,
                c.name,
                p.knob,
                p.ms,
                p.error,
                p.rms,
                p.knob == c.default,
                Some(p.knob) == c.knee()
            );
        }
    }
    s
}

/// Error against milliseconds, log–log, one line per curve of the study, each point labelled with
/// its count, the default ringed; drawn with plotters in decades (log10 of both axes).
pub fn svg(curves: &[&Curve], title: &str) -> Result<String, Error> {
    use plotters::prelude::*;
    let what = format!("the plot `{title}`");
    let fail = |e: &dyn std::fmt::Display| crate::report::plot_style::failed(&what, e);
    let pts: Vec<&ConvergencePoint> =
        curves.iter().flat_map(|c| &c.points).filter(|p| p.ms > 0.0 && p.error > 0.0).collect();
    let span = |v: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
        if lo.is_finite() {
            (lo.log10().floor(), hi.log10().ceil().max(lo.log10().floor() + 1.0))
        } else {
            (0.0, 1.0)
        }
    };
    let (x0, x1) = span(&mut pts.iter().map(|p| p.ms));
    let (y0, y1) = span(&mut pts.iter().map(|p| p.error));
    let palette = &crate::report::plot_style::PALETTE[..7];
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (760, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(14)
            .x_label_area_size(42)
            .y_label_area_size(56)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| fail(&e))?;
        chart
            .configure_mesh()
            .x_desc("milliseconds, log scale")
            .y_desc("error, log scale")
            .x_labels((x1 - x0) as usize + 1)
            .x_label_formatter(&|d| format!("1e{}", d.round() as i32))
            .y_labels((y1 - y0) as usize + 1)
            .y_label_formatter(&|e| format!("1e{}", e.round() as i32))
            .light_line_style(WHITE)
            .draw()
            .map_err(|e| fail(&e))?;
        for (i, c) in curves.iter().enumerate() {
            let colour = palette[i % palette.len()];
            let shown: Vec<&ConvergencePoint> = c.points.iter().filter(|p| p.ms > 0.0 && p.error > 0.0).collect();
            let at = |p: &ConvergencePoint| (p.ms.log10(), p.error.log10());
            chart
                .draw_series(LineSeries::new(shown.iter().map(|p| at(p)), colour.stroke_width(2)))
                .map_err(|e| fail(&e))?
                .label(c.name.clone())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], colour.stroke_width(2)));
            chart
                .draw_series(shown.iter().map(|p| {
                    EmptyElement::at(at(p))
                        + Circle::new((0, 0), 3, colour.filled())
                        + Text::new(p.knob.to_string(), (4, -12), ("sans-serif", 9).into_font().color(&colour))
                }))
                .map_err(|e| fail(&e))?;
            chart
                .draw_series(
                    shown.iter().filter(|p| p.knob == c.default).map(|p| Circle::new(at(p), 6, colour.stroke_width(2))),
                )
                .map_err(|e| fail(&e))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 10))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| fail(&e))?;
        root.draw(&Text::new("ringed: the default", (600, 462), ("sans-serif", 10))).map_err(|e| fail(&e))?;
        root.present().map_err(|e| fail(&e))?;
    }
    Ok(out)
}

/// tables/convergence.{md,csv} and plots/convergence_{fgd,prefilter,furnace}.svg under `dir`.
pub fn write(dir: &std::path::Path, curves: &[Curve], machine: &str) -> Result<(), Error> {
    write_atomic(&dir.join("tables/convergence.md"), markdown(curves, machine).as_bytes())?;
    write_atomic(&dir.join("tables/convergence.csv"), csv(curves).as_bytes())?;
    for (study, title) in [
        ("fgd", "FGD table: error against build time"),
        ("prefilter", "Probe prefilter: error against time per level"),
        ("furnace", "Furnace albedo: error against time per estimate"),
    ] {
        let of: Vec<&Curve> = curves.iter().filter(|c| c.study == study).collect();
        write_atomic(&dir.join(format!("plots/convergence_{study}.svg")), svg(&of, title)?.as_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(errors: &[f64]) -> Curve {
        Curve {
            study: "fgd",
            name: "t".into(),
            knob: "n",
            timed: "t",
            error: "e",
            reference: "r".into(),
            default: 4,
            default_why: "t",
            points: errors
                .iter()
                .enumerate()
                .map(|(i, &e)| ConvergencePoint { knob: 1 << i, ms: (1 << i) as f64, error: e, rms: e })
                .collect(),
        }
    }

    #[test]
    fn the_knee_is_where_the_next_step_gains_less_than_half() {
        assert_eq!(curve(&[1.0, 0.25, 0.06, 0.05, 0.049]).knee(), Some(4));
        assert!(curve(&[1.0, 0.25, 0.06, 0.05, 0.049]).verdict().contains("at the knee"));
        // Still falling fast at the end: the knee is the last count.
        assert_eq!(curve(&[1.0, 0.25, 0.06, 0.015]).knee(), Some(8));
        assert!(curve(&[1.0, 0.25, 0.06, 0.015]).verdict().contains("before the knee 8"));
        assert!(curve(&[1.0, 0.9, 0.85]).verdict().contains("past the knee 1"));
    }
}
