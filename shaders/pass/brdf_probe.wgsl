// Evaluates a model for a list of (n, v, l, material, ambient) inputs on the GPU, so each WGSL
// model can be compared with its f64 twin for exactly the same inputs.

struct ProbeInput {
    n: vec4<f32>,
    v: vec4<f32>,
    l: vec4<f32>,            // w: the light's HDRP minRoughness
    base_color: vec4<f32>,
    params: vec4<f32>,       // metallic, smoothness
    gi_diffuse: vec4<f32>,
    gi_specular: vec4<f32>,
    specular: vec4<f32>,
    model0: vec4<f32>,
    model1: vec4<f32>,
    model2: vec4<f32>,
    tangent: vec4<f32>,
};

@group(0) @binding(0) var<storage, read> probe_inputs: array<ProbeInput>;
@group(0) @binding(1) var<storage, read_write> probe_outputs: array<vec4<f32>>;
@group(0) @binding(2) var fgd_lut: texture_2d<f32>;

fn fgd_lookup(nv: f32, pr: f32) -> vec3<f32> {
    return fgd_sample(fgd_lut, nv, pr);
}

var<private> probe_gi_specular: vec3<f32>;
var<private> probe_env_dir: vec3<f32>;

// The probe stands in for the environment: the prefiltered radiance is given per input, and the
// direction the model fetched along is kept for the parity check of the lookup direction.
fn env_specular(r: vec3<f32>, perceptual_roughness: f32) -> vec3<f32> {
    probe_env_dir = r;
    return probe_gi_specular;
}

// The constant reflection of a material with environment reflections off: the input's too.
fn glossy_environment_color() -> vec3<f32> {
    probe_env_dir = vec3<f32>(0.0);
    return probe_gi_specular;
}

@compute @workgroup_size(64)
fn probe_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&probe_inputs)) {
        return;
    }
    let p = probe_inputs[i];
    var s: Surface;
    s.base_color = p.base_color.rgb;
    s.metallic = p.params.x;
    s.smoothness = p.params.y;
    s.specular = p.specular.rgb;
    s.params0 = p.model0;
    s.params1 = p.model1;
    s.params2 = p.model2;
    s.tangent = p.tangent.xyz;
    probe_gi_specular = p.gi_specular.rgb;
    probe_env_dir = vec3<f32>(0.0);
    light_min_roughness = p.l.w;
    main_light_color = vec3<f32>(1.0);
    probe_outputs[3u * i] = vec4<f32>(model_direct(s, p.n.xyz, p.v.xyz, p.l.xyz), 0.0);
    probe_outputs[3u * i + 1u] = vec4<f32>(model_indirect(s, p.n.xyz, p.v.xyz, p.gi_diffuse.rgb), 0.0);
    probe_outputs[3u * i + 2u] = vec4<f32>(probe_env_dir, 0.0);
}
