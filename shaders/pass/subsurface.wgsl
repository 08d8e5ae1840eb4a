// HDRP's screen-space subsurface scattering (render::passes::subsurface; twin: images::subsurface),
// as SubsurfaceScattering.compute runs it for the default diffusion profile: at every pixel that
// holds split diffuse lighting (TestLightingForSSS), n = min(⌊π(filterRadius·pixelsPerMm)²/4⌋,
// budget) samples along a golden-angle disc rotated by a hashed phase (SSS_RANDOM_ROTATION), each
// at the radius SampleBurleyDiffusionProfile gives for (i + ½)/n, weighted by the profile at the
// 3-D distance to the centre over its density (ComputeBilateralWeight, SSS_BILATERAL_FILTER 1,
// SSS_CLAMP_ARTIFACT 0), renormalised, times the post-scatter albedo; the result is added to the
// frame's colour (CombineLighting's additive blend). Composed after shaders/common/math.wgsl
// (PI, LOG2_E, jenkins_hash). The image plane, not the tangent plane
// (SSS_USE_TANGENT_PLANE 0). HDRP's LDS cache only saves bandwidth: every sample is a load here.

struct SubsurfaceFrame {
    // x, y: the frame's size; z: the sample budget; w: unused
    dims: vec4<u32>,
    // x: near, y: far, z: view units a pixel spans per unit of depth (2·tan(fovY/2)/height),
    // w: the subsurface mask (HDRP's distScale)
    camera: vec4<f32>,
    // xyz: the profile's shape parameter S per channel, 1/mm; w: its widest scattering distance, mm
    shape: vec4<f32>,
    // x: the filter radius, mm; y: metres per world unit (the profile's world scale); zw: unused
    kernel: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: SubsurfaceFrame;
@group(0) @binding(1) var diffuse_lighting: texture_2d<f32>;
@group(0) @binding(2) var sss_buffer: texture_2d<f32>;
// The frame's depth (wgpu's 0..1) in .r
@group(0) @binding(3) var depth_buffer: texture_2d<f32>;
@group(0) @binding(4) var color: texture_2d<f32>;
@group(0) @binding(5) var destination: texture_storage_2d<rgba32float, write>;

const GOLDEN_RATIO: f32 = 1.618033988749895;
const SSS_PIXELS_PER_SAMPLE: f32 = 4.0;
const MILLIMETERS_PER_METER: f32 = 1000.0;
const FLT_MIN: f32 = 1.175494351e-38;

// S/(8π)·(e^(−S·r/3) + e^(−S·r)): r·R(r) of Burley's normalised diffusion (DiffusionProfile.hlsl)
fn eval_burley_diffusion_profile(r: f32, s: vec3<f32>) -> vec3<f32> {
    let exp_13 = exp2(((LOG2_E * (-1.0 / 3.0)) * r) * s);
    let exp_sum = exp_13 * (1.0 + exp_13 * exp_13);
    return (s * (1.0 / (8.0 * PI))) * exp_sum;
}

// The radius where the radial CDF reaches u, and 1/pdf: the closed-form inverse
// (DiffusionProfile.hlsl SampleBurleyDiffusionProfile)
fn sample_burley_diffusion_profile(u_in: f32, rcp_s: f32) -> vec2<f32> {
    let u = 1.0 - u_in;
    let g = 1.0 + (4.0 * u) * (2.0 * u + sqrt(1.0 + (4.0 * u) * u));
    let n = exp2(log2(g) * (-1.0 / 3.0));
    let p = (g * n) * n;
    let c = 1.0 + p + n;
    let d = (3.0 / LOG2_E * 2.0) + (3.0 / LOG2_E) * log2(u);
    let x = (3.0 / LOG2_E) * log2(c) - d;
    let rcp_exp = ((c * c) * c) / ((4.0 * u) * ((c * c) + (4.0 * u) * (4.0 * u)));
    return vec2<f32>(x * rcp_s, (8.0 * PI * rcp_s) * rcp_exp);
}

// profile(√(xy² + (z·mmPerUnit)²))·(1/pdf) (SubsurfaceScattering.compute ComputeBilateralWeight)
fn compute_bilateral_weight(xy2: f32, z: f32, mm_per_unit: f32, s: vec3<f32>, rcp_pdf: f32) -> vec3<f32> {
    let r = sqrt(xy2 + (z * mm_per_unit) * (z * mm_per_unit));
    return eval_burley_diffusion_profile(r, s) * rcp_pdf;
}

// GenerateHashedRandomFloat(uint3): ConstructFloat(JenkinsHash(v.x ^ JenkinsHash(v.yz)))
fn generate_hashed_random_float(v: vec3<u32>) -> f32 {
    let h = jenkins_hash(v.x ^ jenkins_hash(v.y ^ jenkins_hash(v.z)));
    return bitcast<f32>((h & 0x007FFFFFu) | 0x3F800000u) - 1.0;
}

// SampleDiskGolden(i, n).y: 2π·frac(i/φ) (core Sampling.hlsl Golden2dSeq)
fn sample_disk_golden_angle(i: u32) -> f32 {
    return 2.0 * PI * fract(f32(i) * (1.0 / GOLDEN_RATIO));
}

// PreAndPostScatter: √albedo after the filter as before it (ApplySubsurfaceScatteringTexturingMode)
fn apply_subsurface_scattering_texturing_mode(albedo: vec3<f32>) -> vec3<f32> {
    return sqrt(albedo);
}

// TagLightingForSSS kept blue above 0 where split lighting was written
fn test_lighting_for_sss(irradiance: vec3<f32>) -> bool {
    return irradiance.b > 0.0;
}

// LinearEyeDepth of wgpu's 0..1 depth under the perspective projection
fn linear_eye_depth(d: f32) -> f32 {
    let near = frame.camera.x;
    let far = frame.camera.y;
    return near * far / (far - d * (far - near));
}

fn scattered(pixel: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(frame.dims.xy);
    let center_irradiance = textureLoad(diffuse_lighting, pixel, 0).rgb;
    if (!test_lighting_for_sss(center_irradiance)) {
        return vec3<f32>(0.0);
    }
    let albedo = apply_subsurface_scattering_texturing_mode(textureLoad(sss_buffer, pixel, 0).rgb);
    let center_depth = textureLoad(depth_buffer, pixel, 0).r;
    let linear_depth = linear_eye_depth(center_depth);
    let mask = frame.camera.w;
    let mm_per_unit = MILLIMETERS_PER_METER * (frame.kernel.y / mask);
    // The view-space width of the pixel at its depth (2·|cornerPosVS.x − centerPosVS.x|)
    let units_per_pixel = max(0.0001, frame.camera.z * linear_depth);
    let pixels_per_mm = (1.0 / units_per_pixel) * (1.0 / mm_per_unit);
    let filter_area = PI * (frame.kernel.x * pixels_per_mm) * (frame.kernel.x * pixels_per_mm);
    let sample_count = u32(filter_area * (1.0 / SSS_PIXELS_PER_SAMPLE));
    if (mask == 0.0 || sample_count < 1u) {
        return albedo * center_irradiance;
    }
    // HDRP hashes its reversed-Z device depth: 1 − wgpu's
    let phase = 2.0 * PI * generate_hashed_random_float(vec3<u32>(vec2<u32>(pixel), u32((1.0 - center_depth) * 16777216.0)));
    let n = min(sample_count, frame.dims.z);
    let scale = 1.0 / f32(n);
    let offset = scale * 0.5;
    let sin_phase = sin(phase);
    let cos_phase = cos(phase);
    var total_irradiance = vec3<f32>(0.0);
    var total_weight = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let sample = sample_burley_diffusion_profile(f32(i) * scale + offset, frame.shape.w);
        let r = sample.x;
        let phi = sample_disk_golden_angle(i);
        let sin_phi = sin(phi);
        let cos_phi = cos(phi);
        let sin_psi = cos_phase * sin_phi + sin_phase * cos_phi;
        let cos_psi = cos_phase * cos_phi - sin_phase * sin_phi;
        let position = pixel + vec2<i32>(round(pixels_per_mm * r * vec2<f32>(cos_psi, sin_psi)));
        // Off screen a load gives 0 in HDRP, which the test rejects
        if (any(position < vec2<i32>(0)) || any(position >= size)) {
            continue;
        }
        let irradiance = textureLoad(diffuse_lighting, position, 0).rgb;
        if (test_lighting_for_sss(irradiance)) {
            let rel_z = linear_eye_depth(textureLoad(depth_buffer, position, 0).r) - linear_depth;
            let weight = compute_bilateral_weight(r * r, rel_z, mm_per_unit, frame.shape.xyz, sample.y);
            total_irradiance += weight * irradiance;
            total_weight += weight;
        }
    }
    total_weight = max(total_weight, vec3<f32>(FLT_MIN));
    return albedo * (total_irradiance / total_weight);
}

@compute @workgroup_size(8, 8)
fn cs_subsurface(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= frame.dims.x || id.y >= frame.dims.y) {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let c = textureLoad(color, pixel, 0);
    textureStore(destination, pixel, vec4<f32>(c.rgb + scattered(pixel), c.a));
}
