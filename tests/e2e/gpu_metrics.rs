//! FLIP and SSIM on the GPU (`compare::gpu`) against their CPU references (flip-rs and
//! `compare::ssim`): the means within 1e-4, on the committed fixtures and on rendered cells.

use shadematrix::compare::gpu::GpuMetrics;
use shadematrix::compare::images::{compare_on, LoadedImage, MetricsBackend};
use shadematrix::gpu::GpuContext;

fn assert_parity(gpu: &GpuMetrics, a: &LoadedImage, b: &LoadedImage, what: &str) {
    let cpu = compare_on(a, b, what, false, MetricsBackend::Cpu).unwrap();
    let on_gpu = compare_on(a, b, what, false, MetricsBackend::Gpu(gpu)).unwrap();
    assert_eq!(on_gpu.computed_on, "gpu");
    let (f_cpu, f_gpu) = (cpu.flip.value.mean().unwrap(), on_gpu.flip.value.mean().unwrap());
    eprintln!("{what}: {} FLIP cpu {f_cpu:.7} gpu {f_gpu:.7} (Δ {:.1e})", cpu.flip.kind, (f_gpu - f_cpu).abs());
    assert!((f_gpu - f_cpu).abs() < 1e-4, "{what}: FLIP cpu {f_cpu} gpu {f_gpu}");
    assert!(f_cpu > 1e-3, "{what}: the images barely differ; the check would be weak");
    if let (Some(s_cpu), Some(s_gpu)) = (cpu.ssim.mean(), on_gpu.ssim.mean()) {
        eprintln!("{what}: SSIM cpu {s_cpu:.7} gpu {s_gpu:.7} (Δ {:.1e})", (s_gpu - s_cpu).abs());
        assert!((s_gpu - s_cpu).abs() < 1e-4, "{what}: SSIM cpu {s_cpu} gpu {s_gpu}");
    }
    assert_eq!(cpu.ssim.mean().is_some(), on_gpu.ssim.mean().is_some(), "{what}");
}

#[test]
fn gpu_flip_and_ssim_equal_the_cpu_references() {
    let _timer = crate::common::timed!();
    let ctx = GpuContext::new().unwrap();
    let gpu = GpuMetrics::new(&ctx.device, &ctx.queue, ctx.constants);
    let dir = crate::common::fixture("compare");
    for (a, b) in [("synthetic_a.png", "synthetic_b.png"), ("render_a.png", "render_b.png"), ("hdr_a.exr", "hdr_b.exr")]
    {
        let (ia, ib) = (LoadedImage::load(&dir.join(a)).unwrap(), LoadedImage::load(&dir.join(b)).unwrap());
        assert_parity(&gpu, &ia, &ib, a);
    }
    // The metric workers share one GpuMetrics: calls at once each borrow a buffer set of their
    // own and give the means one call at a time gives, to the bit.
    let pairs: Vec<_> = ["synthetic", "render", "hdr", "synthetic", "render", "hdr"]
        .iter()
        .map(|stem| {
            let ext = if *stem == "hdr" { "exr" } else { "png" };
            let load = |s: &str| LoadedImage::load(&dir.join(format!("{stem}_{s}.{ext}"))).unwrap();
            (load("a"), load("b"))
        })
        .collect();
    let means = |(a, b): &(LoadedImage, LoadedImage)| {
        let m = compare_on(a, b, "pair", false, MetricsBackend::Gpu(&gpu)).unwrap();
        (m.flip.value.mean().unwrap().to_bits(), m.ssim.mean().map(f64::to_bits))
    };
    let one_at_a_time: Vec<_> = pairs.iter().map(means).collect();
    let at_once: Vec<_> = std::thread::scope(|s| {
        let running: Vec<_> = pairs.iter().map(|pair| s.spawn(move || means(pair))).collect();
        running.into_iter().map(|r| r.join().unwrap()).collect()
    });
    assert_eq!(one_at_a_time, at_once);
    // Rendered cells: URP against HDRP Lit, sizes that are not multiples of the workgroup.
    let tmp = tempfile::tempdir().unwrap();
    let run = crate::common::run_matrix_with(
        tmp.path(),
        "name = \"g\"\ncompositions = [\"mitsuba\", \"spikes\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n[image]\nwidth = 75\nheight = 53\n",
        "g",
        &["--no-cache"],
    );
    for comp in ["mitsuba", "spikes"] {
        let cell = |p: &str| {
            run.join("cells").join(format!(
                "{comp}__{p}-forward__lit__gold__m1.00_s0.90_i{}_r{}",
                if comp == "mitsuba" { "1.5" } else { "1" },
                if comp == "mitsuba" { "12" } else { "10" }
            ))
        };
        let (u, h) = (cell("urp"), cell("hdrp"));
        for f in ["image.png", "image.exr"] {
            let (a, b) = (LoadedImage::load(&h.join(f)).unwrap(), LoadedImage::load(&u.join(f)).unwrap());
            assert_parity(&gpu, &a, &b, &format!("{comp} {f}"));
        }
    }
}

/// A run with `metrics = "gpu"` records the means a `metrics = "cpu"` run does, within 1e-4, for
/// every compared cell (LDR-FLIP, SSIM, HDR-FLIP of the exposed EXRs).
#[test]
fn a_gpu_metrics_run_records_the_cpu_runs_means() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = "compositions = [\"default\", \"medusa\"]\npipelines = [\"builtin\", \"hdrp\"]\nshaders = [\"lambert\", \"lit\", \"standard\"]\npresets = [\"plastic\"]\nreference = { pipeline = \"hdrp\", shader = \"lit\" }\n[image]\nwidth = 48\nheight = 40\n";
    let gpu = crate::common::run_matrix_with(
        tmp.path(),
        &format!("name = \"a\"\nmetrics = \"gpu\"\n{body}"),
        "gpu",
        &["--no-cache"],
    );
    let cpu = crate::common::run_matrix_with(
        tmp.path(),
        &format!("name = \"a\"\nmetrics = \"cpu\"\n{body}"),
        "cpu",
        &["--no-cache"],
    );
    let mut compared = 0;
    for e in std::fs::read_dir(gpu.join("cells")).unwrap() {
        let id = e.unwrap().file_name();
        let load = |run: &std::path::Path| {
            let v: serde_json::Value =
                serde_json::from_slice(&std::fs::read(run.join("cells").join(&id).join("cell.json")).unwrap()).unwrap();
            v["metrics"].clone()
        };
        let (g, c) = (load(&gpu), load(&cpu));
        if c["ldr"].is_null() {
            continue;
        }
        assert_eq!((g["ldr"]["computed_on"].as_str(), c["ldr"]["computed_on"].as_str()), (Some("gpu"), Some("cpu")));
        for (kind, metric) in [("ldr", "flip"), ("ldr", "ssim"), ("hdr", "flip")] {
            let value = |m: &serde_json::Value| {
                let v = &m[kind][metric];
                v["mean"].as_f64().unwrap_or_else(|| panic!("{id:?} {kind} {metric}: {v}"))
            };
            let (a, b) = (value(&g), value(&c));
            assert!((a - b).abs() < 1e-4, "{id:?} {kind} {metric}: gpu {a} cpu {b}");
        }
        compared += 1;
    }
    assert_eq!(compared, 6, "two compositions × three cells against HDRP Lit");
}
