//! `shadematrix brdf`: one model, one set of directions, from the f64 twin and optionally the GPU.

use glam::DVec3;
use serde_json::json;

use crate::error::{Error, InputError};
use crate::gpu::GpuContext;
use crate::input::names::unknown_name;
use crate::pipelines::Pipeline;
use crate::render::probe::{evaluate, ProbeInput};
use crate::shading::registry::{Registry, Sliders};

pub struct BrdfRequest {
    pub pipeline: String,
    pub shader: String,
    pub params: Vec<String>,
    pub n: String,
    pub l: String,
    pub v: String,
    pub gpu: bool,
}

const ORIGIN: &str = "command line";

fn vec3(key: &str, text: &str) -> Result<DVec3, InputError> {
    let parts: Vec<f64> =
        text.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| {
            InputError::at_key(ORIGIN, key, format!("`{text}` is not three comma-separated numbers X,Y,Z"))
        })?;
    match parts.as_slice() {
        [x, y, z] if [x, y, z].iter().all(|c| c.is_finite()) => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(InputError::at_key(ORIGIN, key, format!("`{text}` is not three finite numbers X,Y,Z"))),
    }
}

fn direction(key: &str, text: &str) -> Result<DVec3, InputError> {
    let d = vec3(key, text)?;
    if d.length_squared() < 1e-24 {
        return Err(InputError::at_key(ORIGIN, key, "a direction must be non-zero"));
    }
    Ok(d.normalize())
}

pub fn print(req: &BrdfRequest, json_out: bool, models: &super::ModelsArg) -> Result<(), Error> {
    super::outln!("{}", evaluate_request(req, json_out, &*super::registry(models)?)?);
    Ok(())
}

pub fn evaluate_request(req: &BrdfRequest, json_out: bool, registry: &Registry) -> Result<String, Error> {
    let pipeline = Pipeline::from_name(&req.pipeline)
        .ok_or_else(|| unknown_name(ORIGIN, "--pipeline", "pipeline", &req.pipeline, &Pipeline::names()))?;
    let model = registry.find(pipeline, &req.shader).ok_or_else(|| {
        if registry.names().contains(&req.shader.as_str()) {
            InputError::at_key(
                ORIGIN,
                "--shader",
                format!(
                    "`{}` is not a shader of {} (it has: {})",
                    req.shader,
                    pipeline.name(),
                    registry.names_for(pipeline).join(", ")
                ),
            )
        } else {
            unknown_name(ORIGIN, "--shader", "shader", &req.shader, &registry.names_for(pipeline))
        }
    })?;
    let (n, l, v) = (direction("--n", &req.n)?, direction("--l", &req.l)?, direction("--v", &req.v)?);
    // As the shader receives them: start from the model's defaults, then apply --param as given.
    let mut s = model.surface(pipeline, &Sliders { base_color_linear: [0.5; 3], metallic: 0.0, smoothness: 0.5 });
    s.metallic = 0.0;
    let mut keys: Vec<&str> = vec!["albedo", "metallic", "smoothness", "specular"];
    keys.extend(model.params.iter().map(|p| p.name.as_ref()));
    for kv in &req.params {
        let (k, val) = kv
            .split_once('=')
            .ok_or_else(|| InputError::at_key(ORIGIN, "--param", format!("`{kv}` is not key=value")))?;
        let key = format!("--param {k}");
        let unit = |x: f64| -> Result<f64, InputError> {
            if (0.0..=1.0).contains(&x) {
                Ok(x)
            } else {
                Err(InputError::at_key(ORIGIN, &key, format!("value {x} is out of range; allowed 0..=1")))
            }
        };
        let number = || {
            val.trim().parse::<f64>().map_err(|_| InputError::at_key(ORIGIN, &key, format!("`{val}` is not a number")))
        };
        match k {
            "albedo" => s.base_color = vec3(&key, val)?,
            "specular" => s.specular = vec3(&key, val)?,
            "metallic" => s.metallic = unit(number()?)?,
            "smoothness" => s.smoothness = unit(number()?)?,
            other => {
                let spec = model
                    .params
                    .iter()
                    .find(|p| p.name == other)
                    .ok_or_else(|| unknown_name(ORIGIN, "--param", "parameter", other, &keys))?;
                let x = number()?;
                if !(spec.min..=spec.max).contains(&x) {
                    return Err(InputError::at_key(
                        ORIGIN,
                        &key,
                        format!("value {x} is out of range; allowed {}..={}", spec.min, spec.max),
                    )
                    .into());
                }
                s.params[spec.slot] = x;
            }
        }
    }
    let nl = n.dot(l).max(1e-6);
    let cpu = model.twin.map(|t| t.direct(pipeline, &s, n, v, l));
    let gpu = if req.gpu {
        let ctx = GpuContext::new()?;
        let out = evaluate(&ctx, pipeline, model, &[ProbeInput::new(&s, n, v, l, DVec3::ZERO, DVec3::ZERO)])?;
        Some((DVec3::new(out[0].0[0] as f64, out[0].0[1] as f64, out[0].0[2] as f64), ctx.record.name.clone()))
    } else {
        None
    };
    let params: serde_json::Map<String, serde_json::Value> =
        model.params.iter().map(|p| (p.name.to_string(), json!(s.params[p.slot]))).collect();
    let mut out = json!({
        "pipeline": pipeline.name(),
        "shader": model.name,
        "inputs": {
            "n": n.to_array(), "l": l.to_array(), "v": v.to_array(),
            "albedo": s.base_color.to_array(), "metallic": s.metallic, "smoothness": s.smoothness,
            "specular": s.specular.to_array(), "params": params,
        },
        "convention": "radiance for a white light of intensity 1 at attenuation 1, direct light only, in the pipeline's units; brdf = radiance / max(N·L, 1e-6)",
    });
    match cpu {
        Some(c) => {
            out["radiance"] = json!(c.to_array());
            out["brdf"] = json!((c / nl).to_array());
        }
        None => out["radiance_missing"] = json!("no f64 twin: a user-supplied model; use --gpu"),
    }
    if let Some((g, adapter)) = gpu {
        out["gpu"] = json!({ "adapter": adapter, "radiance": g.to_array(), "brdf": (g / nl).to_array() });
        if let Some(c) = cpu {
            out["gpu"]["abs_diff"] = json!((g - c).abs().to_array());
            out["gpu"]["rel_diff"] = json!(((g - c).abs() / c.abs().max(DVec3::splat(1e-12))).to_array());
        }
        if cpu.is_none() {
            out["radiance"] = json!(g.to_array());
            out["brdf"] = json!((g / nl).to_array());
        }
    }
    if json_out {
        return Ok(serde_json::to_string_pretty(&out).unwrap_or_default());
    }
    let f = |v: &serde_json::Value| {
        v.as_array()
            .map(|a| a.iter().map(|x| format!("{:.6e}", x.as_f64().unwrap_or(f64::NAN))).collect::<Vec<_>>().join(", "))
            .unwrap_or_else(|| "—".into())
    };
    let mut text =
        format!("{}/{}: radiance [{}], brdf [{}]", pipeline.name(), model.name, f(&out["radiance"]), f(&out["brdf"]));
    if out.get("gpu").is_some() {
        text.push_str(&format!(
            "\nGPU ({}): radiance [{}], rel diff [{}]",
            out["gpu"]["adapter"].as_str().unwrap_or(""),
            f(&out["gpu"]["radiance"]),
            f(&out["gpu"]["rel_diff"])
        ));
    }
    Ok(text)
}
