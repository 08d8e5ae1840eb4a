//! The command line: parse, call into the library, map errors to exit codes (DESIGN.md):
//! 0 ok, 1 failure, 2 bad input, 3 no usable adapter or a device error.

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use shadematrix::error::{Error, InputError};
use shadematrix::geometry::{gltf_io, procedural};
use shadematrix::run::cells::expand;
use shadematrix::run::plan::FramePlan;
use shadematrix::run::runner::{self, RunOptions};
use shadematrix::spec::matrix::{Axis, Filter, FilterValue, Matrix};
use shadematrix::spec::names::unknown_name;
use shadematrix::spec::scene::{Role, Scene};

#[derive(Parser)]
#[command(
    name = "shadematrix",
    version,
    about = "Render a TOML matrix of pipelines × shaders × materials × compositions headlessly with wgpu"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render every cell of a matrix (default: the embedded default matrix).
    Run {
        /// Matrix TOML file.
        matrix: Option<PathBuf>,
        /// Run folder (default: results/<matrix>-<timestamp>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Continue an interrupted run: cells already finished are kept.
        #[arg(long)]
        resume: bool,
        /// Render shard K of N (e.g. 2/4).
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Only cells matching, e.g. `composition=medusa,shader=standard`.
        #[arg(long, value_name = "FILTER")]
        only: Option<String>,
    },
    /// List the expanded cells, the pruned ones and the passes each composition needs.
    List { matrix: Option<PathBuf> },
    /// Every shader: pipelines, parameters, the sweep axes it reads and how they map.
    Shaders,
    /// Evaluate one model for one set of directions (f64 twin; --gpu adds the WGSL on the adapter).
    Brdf {
        #[arg(long)]
        pipeline: String,
        #[arg(long)]
        shader: String,
        /// As the shader receives it: albedo=R,G,B (linear), metallic=X, smoothness=X, specular=R,G,B, or a model parameter.
        #[arg(long = "param", value_name = "K=V")]
        params: Vec<String>,
        #[arg(long, allow_hyphen_values = true)]
        n: String,
        #[arg(long, allow_hyphen_values = true)]
        l: String,
        #[arg(long, allow_hyphen_values = true)]
        v: String,
        #[arg(long)]
        gpu: bool,
        #[arg(long)]
        json: bool,
    },
    /// BRDF property audit: GPU-vs-f64 parity, positivity, reciprocity, energy. Exit 1 on a failed check.
    Audit {
        /// Only the models of this name (every pipeline that has it).
        #[arg(long)]
        shader: Option<String>,
        /// Print the JSON report instead of the table.
        #[arg(long)]
        json: bool,
        /// Where audit.md, .csv and .json go (default results/audit-<time>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// FLIP and SSIM (and RMSE, PSNR, bad-value counts) of two PNGs or two EXRs; A is the reference.
    Diff {
        a: PathBuf,
        b: PathBuf,
        #[arg(long)]
        json: bool,
        /// Write flip.png and ssim.png (1 − SSIM) here.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also SSIM of R, G and B separately.
        #[arg(long)]
        per_channel: bool,
    },
    /// Compare a run with a baseline run: junit.xml and summary.md into the run; exit 1 on a regression.
    Check {
        run: PathBuf,
        #[arg(long)]
        baseline: PathBuf,
        /// Largest FLIP mean a cell may have against its baseline (default 0.01).
        #[arg(long)]
        flip_mean: Option<f64>,
        /// Smallest SSIM a cell may have against its baseline (default 0.99).
        #[arg(long)]
        ssim_min: Option<f64>,
    },
    /// Rebuild the reports of a run (tables) from its recorded files, without rendering.
    Report { run: PathBuf },
    /// Write a composition's meshes (world space) as a GLB file.
    ExportMesh {
        /// A built-in composition name or a scene TOML path.
        composition: String,
        out: PathBuf,
    },
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("error")).init();
    let cli = Cli::parse();
    match dispatch(cli.command.unwrap_or(Command::Run {
        matrix: None,
        out: None,
        resume: false,
        shard: None,
        only: None,
    })) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shadematrix: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

fn load_matrix(path: Option<&Path>) -> Result<Matrix, Error> {
    match path {
        Some(p) => Matrix::load(p),
        None => Matrix::load_default(),
    }
}

fn dispatch(cmd: Command) -> Result<(), Error> {
    // User-supplied models (shaders/brdf/*.wgsl with a .toml beside) become shader names.
    shadematrix::shading::user::load_dir(Path::new(shadematrix::shading::user::USER_MODEL_DIR))?;
    match cmd {
        Command::Shaders => {
            let _ = std::io::Write::write_all(&mut std::io::stdout(), shadematrix::cli::shaders::table().as_bytes());
            Ok(())
        }
        Command::Brdf { pipeline, shader, params, n, l, v, gpu, json } => {
            let req = shadematrix::cli::brdf::BrdfRequest { pipeline, shader, params, n, l, v, gpu };
            println!("{}", shadematrix::cli::brdf::run(&req, json)?);
            Ok(())
        }
        Command::Audit { shader, json, out } => audit(shader.as_deref(), json, out),
        Command::Diff { a, b, json, out, per_channel } => diff(&a, &b, json, out.as_deref(), per_channel),
        Command::Check { run, baseline, flip_mean, ssim_min } => {
            use shadematrix::report::check::{check, Thresholds};
            let d = Thresholds::default();
            let t =
                Thresholds { flip_mean: flip_mean.unwrap_or(d.flip_mean), ssim_min: ssim_min.unwrap_or(d.ssim_min) };
            let r = check(&run, &baseline, t)?;
            println!(
                "{} of {} cells regressed (junit.xml and summary.md in {})",
                r.failures(),
                r.cells.len(),
                run.display()
            );
            if r.failures() > 0 {
                return Err(Error::CheckFailed(format!(
                    "{} cells regressed against {}",
                    r.failures(),
                    baseline.display()
                )));
            }
            Ok(())
        }
        Command::Report { run } => {
            shadematrix::report::build(&run)?;
            println!("reports rebuilt in {}", run.display());
            Ok(())
        }
        Command::Run { matrix, out, resume, shard, only } => {
            let m = load_matrix(matrix.as_deref())?;
            let opts = RunOptions {
                results_root: runner::default_results_root(),
                out,
                resume,
                shard: shard.as_deref().map(parse_shard).transpose()?,
                only: only.as_deref().map(parse_only).transpose()?,
                progress: std::io::IsTerminal::is_terminal(&std::io::stderr()),
            };
            let s = runner::run(&m, &opts)?;
            println!(
                "{} cells ({} rendered, {} twins copied, {} resumed; {} pruned, {} filtered out) in {:.1} s on {}",
                s.counts.cells,
                s.counts.rendered,
                s.counts.twins,
                s.counts.resumed,
                s.counts.pruned,
                s.counts.filtered_out,
                s.wall_seconds,
                s.adapter
            );
            println!("results: {}", s.dir.display());
            Ok(())
        }
        Command::List { matrix } => {
            let m = load_matrix(matrix.as_deref())?;
            // A closed pipe (`| head`) is not an error of ours.
            let _ = std::io::Write::write_all(&mut std::io::stdout(), list(&m).as_bytes());
            Ok(())
        }
        Command::ExportMesh { composition, out } => export_mesh(&composition, &out),
    }
}

fn diff(a: &Path, b: &Path, json: bool, out: Option<&Path>, per_channel: bool) -> Result<(), Error> {
    use shadematrix::compare::images::compare_with;
    use shadematrix::compare::LoadedImage;
    let what = format!("{} vs {}", a.display(), b.display());
    let c = compare_with(&LoadedImage::load(a)?, &LoadedImage::load(b)?, &what, per_channel)?;
    if let Some(dir) = out {
        let png = |name: &str, px: &Option<Vec<u8>>| -> Result<(), Error> {
            if let Some(px) = px {
                let bytes = shadematrix::images::encode::png_bytes(c.width, c.height, px)?;
                shadematrix::fsutil::write_atomic(&dir.join(name), &bytes)?;
            }
            Ok(())
        };
        png("flip.png", &c.flip_map_rgba8)?;
        png("ssim.png", &c.ssim_map_rgba8)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&c).unwrap_or_default());
    } else {
        let show = |m: &shadematrix::compare::images::Metric| match m {
            shadematrix::compare::images::Metric::Value { mean } => format!("{mean:.6}"),
            shadematrix::compare::images::Metric::Missing { missing } => format!("missing ({missing})"),
        };
        println!(
            "{}×{}: {}-FLIP mean {}, SSIM mean {}, RMSE {:.6}, PSNR {}",
            c.width,
            c.height,
            c.flip.kind.to_uppercase(),
            show(&c.flip.value),
            show(&c.ssim),
            c.rmse,
            c.psnr_db.map(|p| format!("{p:.2} dB")).unwrap_or_else(|| "—".into())
        );
    }
    Ok(())
}

fn audit(shader: Option<&str>, json: bool, out: Option<PathBuf>) -> Result<(), Error> {
    use shadematrix::audit;
    if let Some(name) = shader {
        let names = shadematrix::shading::registry::all_model_names();
        if !names.contains(&name) {
            return Err(unknown_name("command line", "--shader", "shader", name, &names).into());
        }
    }
    let gpu = shadematrix::gpu::GpuContext::new()?;
    let audits = audit::audit_all(&gpu, shader)?;
    let dir = out.unwrap_or_else(|| {
        PathBuf::from("results").join(format!("audit-{}", chrono::Local::now().format("%Y%m%d-%H%M%S")))
    });
    audit::report::write(&dir, &audits, &gpu.record.name)?;
    let text = if json {
        serde_json::to_string_pretty(&serde_json::json!({ "adapter": gpu.record.name, "models": audits }))
            .unwrap_or_default()
    } else {
        audit::report::markdown(&audits, &gpu.record.name)
    };
    let _ = std::io::Write::write_all(&mut std::io::stdout(), text.as_bytes());
    eprintln!("audit written to {}", dir.display());
    let failed: Vec<&str> = audits.iter().filter(|a| !a.failures.is_empty()).map(|a| a.key.as_str()).collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(Error::CheckFailed(format!("audit failed for {}", failed.join(", "))))
    }
}

fn parse_shard(s: &str) -> Result<(u32, u32), Error> {
    let bad = || InputError::at_key("command line", "--shard", format!("`{s}` is not K/N with 1 <= K <= N"));
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n): (u32, u32) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if k == 0 || n == 0 || k > n {
        return Err(bad().into());
    }
    Ok((k, n))
}

fn parse_only(s: &str) -> Result<Filter, Error> {
    let axes: Vec<&str> = Axis::ALL.iter().map(|a| a.name()).collect();
    let mut filter = Filter::default();
    for term in s.split(',').filter(|t| !t.trim().is_empty()) {
        let (k, v) = term
            .split_once('=')
            .ok_or_else(|| InputError::at_key("command line", "--only", format!("`{term}` is not axis=value")))?;
        let axis = Axis::ALL
            .into_iter()
            .find(|a| a.name() == k.trim())
            .ok_or_else(|| unknown_name("command line", "--only", "axis", k.trim(), &axes))?;
        let values = v
            .split('|')
            .map(|x| {
                if axis.is_numeric() {
                    x.trim().parse::<f64>().map(FilterValue::Number).map_err(|_| {
                        InputError::at_key(
                            "command line",
                            format!("--only {}", axis.name()),
                            format!("`{x}` is not a number"),
                        )
                    })
                } else {
                    Ok(FilterValue::Name(x.trim().to_string()))
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        filter.terms.push((axis, values));
    }
    Ok(filter)
}

fn list(m: &Matrix) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let exp = expand(m);
    let _ = writeln!(out, "matrix `{}` ({}), sha256 {}", m.name, m.origin, &m.hash[..12]);
    for scene in &m.compositions {
        let plan = FramePlan::for_scene(scene);
        let _ = writeln!(out, "composition {}: passes {}", scene.name, plan.passes.join(" → "));
        for (what, why) in &plan.left_out {
            let _ = writeln!(out, "  left out: {what}: {why}");
        }
    }
    let rendered = exp.cells.iter().filter(|c| c.twin_of.is_none()).count();
    let _ = writeln!(
        out,
        "{} cells, {} rendered, {} twins, {} pruned, {} filtered out",
        exp.cells.len(),
        rendered,
        exp.cells.len() - rendered,
        exp.pruned.len(),
        exp.filtered_out
    );
    for c in &exp.cells {
        match &c.twin_of {
            None => {
                let _ = writeln!(out, "  {}", c.id);
            }
            Some(t) => {
                let _ = writeln!(out, "  {}  = {} ({} ignores the differing axes)", c.id, t, c.shader);
            }
        }
    }
    for p in &exp.pruned {
        let _ = writeln!(out, "  pruned {}: {}", p.description, p.reason);
    }
    out
}

fn export_mesh(composition: &str, out: &Path) -> Result<(), Error> {
    let scene = Scene::load(composition, Some(Path::new(".")), "command line", "composition")?;
    let mut meshes = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        let mesh = procedural::build(&o.mesh, scene.base_dir.as_deref(), &scene.origin, &format!("objects[{i}].mesh"))?
            .transformed(o.transform.matrix());
        meshes.push((o, mesh));
    }
    let parts: Vec<gltf_io::ExportMesh> = meshes
        .iter()
        .map(|(o, mesh)| {
            let (color, metallic, smoothness) = match (&o.material, o.role) {
                (Some(m), _) => (m.base_color_linear, m.metallic, m.smoothness),
                (None, Role::Subject) => ([0.8; 3], 0.0, 0.5),
                (None, Role::Fixed) => ([0.5; 3], 0.0, 0.0),
            };
            gltf_io::ExportMesh { name: &o.name, mesh, base_color_linear: color, metallic, roughness: 1.0 - smoothness }
        })
        .collect();
    let bytes = gltf_io::to_glb(&parts)?;
    shadematrix::fsutil::write_atomic(out, &bytes)?;
    let tris: usize = meshes.iter().map(|(_, m)| m.triangle_count()).sum();
    println!("wrote {} ({} objects, {} triangles)", out.display(), meshes.len(), tris);
    Ok(())
}
