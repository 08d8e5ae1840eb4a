// HDRP's screen-space ambient occlusion (render::passes::ssao; twin: images::ssao), its steps as
// HDRP's compute shaders run them without temporal history: the depth pyramid's closest-depth
// downsample (DepthPyramid.compute), the horizon search and cosine-weighted arc integral
// (GTAO.compute, GTAOCommon.hlsl), then at half resolution (Low, Medium) the 9-3-3-1 bilateral
// upsample (GTAOBlurAndUpsample.compute BilateralUpsampling) or at full resolution (High) the 4×4
// depth-weighted blur (GTAOSpatialDenoise.compute), each with the intensity power (OutputFinalAO).
//
// HDRP's render targets store rows bottom-up (Unity flips the projection when rendering into
// them); these textures store them top-down. GTAO mixes screen directions with view-space vectors,
// so its positions are taken in HDRP's bottom-up pixel coordinates (`hdrp_load`). Depth is wgpu's
// 0 (near) .. 1 (far): HDRP's reversed-Z minimum is a maximum here and the reverse.

struct SsaoStep {
    // xy: size this step writes; z: mode (1 closest downsample, 2 horizons, else upsample)
    dims: vec4<u32>,
};

struct SsaoFrame {
    // _AOBufferSize: running-resolution width and height (the frame's or half of it)
    buffer_size: vec4<f32>,
    // x: _AOFOVCorrection, y: _AORadius, z: _AOStepCount, w: _AOInvStepCountPlusOne
    params0: vec4<f32>,
    // x: _AOIntensity, y: _AOInvRadiusSq, z: _AODirectionCount, w: _AOMaxRadiusInPixels
    params1: vec4<f32>,
    // _AODepthToViewParams
    depth_to_view: vec4<f32>,
    // x: near, y: far (LinearEyeDepth), z: _AOSpatialBilateralAggressiveness (× 15)
    z_buffer: vec4<f32>,
    // Rows of the world-to-view rotation (right-handed, looking down −z)
    view_x: vec4<f32>,
    view_y: vec4<f32>,
    view_z: vec4<f32>,
};

@group(0) @binding(0) var<uniform> ssao_step: SsaoStep;
// Downsample: the finer level; horizons: pyramid level 1 (full resolution: level 0); upsample and
// denoise: the packed AO and depth
@group(0) @binding(1) var source: texture_2d<f32>;
// Horizons: pyramid level 2 (full resolution: level 1); upsample: the full-resolution depth
@group(0) @binding(2) var coarse: texture_2d<f32>;
// Horizons: the full-resolution normal buffer (n·0.5 + 0.5, world space)
@group(0) @binding(3) var normals: texture_2d<f32>;
@group(0) @binding(4) var destination: texture_storage_2d<rg32float, write>;
@group(0) @binding(5) var<uniform> frame: SsaoFrame;

// The depth copy's own bindings: the prepass depth into a float texture the steps can load.
@group(0) @binding(6) var depth_in: texture_depth_2d;
@group(0) @binding(7) var depth_out: texture_storage_2d<rg32float, write>;

const SSAO_CLOSEST: u32 = 1u;
const SSAO_HORIZONS: u32 = 2u;
const SSAO_UPSAMPLE: u32 = 3u;
const SSAO_HORIZONS_FULL: u32 = 4u;
const SSAO_SPATIAL_DENOISE: u32 = 5u;

@compute @workgroup_size(8, 8)
fn cs_depth_copy(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(depth_in);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(depth_out, id.xy, vec4<f32>(textureLoad(depth_in, id.xy, 0), 0.0, 0.0, 0.0));
}

fn load_clamped(t: texture_2d<f32>, p: vec2<i32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(t));
    return textureLoad(t, clamp(p, vec2<i32>(0), size - 1), 0).rg;
}

// The texel at HDRP's pixel p (rows counted from the bottom), edges clamped
fn hdrp_load(t: texture_2d<f32>, p: vec2<i32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(t));
    let c = clamp(p, vec2<i32>(0), size - 1);
    return textureLoad(t, vec2<i32>(c.x, size.y - 1 - c.y), 0).rg;
}

// round(x·(2ⁿ − 1))/(2ⁿ − 1): PackAOOutput's UnpackInt (AO in 8 bits, depth in 24)
fn quantise(x: f32, levels: f32) -> f32 {
    return floor(sat(x) * levels + 0.5) / levels;
}

// LinearEyeDepth: view depth of a raw depth (wgpu's perspective, 0 at near, 1 at far)
fn linear_eye_depth(raw: f32) -> f32 {
    let n = frame.z_buffer.x;
    let f = frame.z_buffer.y;
    return n * f / (f - raw * (f - n));
}

// GetPositionVS: ((positionSS·xy − zw)·z, z), positionSS in running-resolution pixels
fn get_position_vs(position_ss: vec2<f32>, raw: f32) -> vec3<f32> {
    let z = linear_eye_depth(raw);
    return vec3<f32>((position_ss * frame.depth_to_view.xy - frame.depth_to_view.zw) * z, z);
}

// GTAOFastAcos: (−0.156583·|x| + π/2)·√(1 − |x|), mirrored for x < 0
fn gtao_fast_acos(x: f32) -> f32 {
    let out_val = (-0.156583 * abs(x) + HALF_PI) * sqrt(1.0 - abs(x));
    return select(PI - out_val, out_val, x >= 0.0);
}

// IntegrateArcCosWeighted: ¼·Σ_{h ∈ {2h1, 2h2}} (−cos(h − n) + cos n + h·sin n)
fn integrate_arc_cos_weighted(horizon1: f32, horizon2: f32, n: f32, cos_n: f32) -> f32 {
    let h1 = horizon1 * 2.0;
    let h2 = horizon2 * 2.0;
    let sin_n = sin(n);
    return 0.25 * ((-cos(h1 - n) + cos_n + h1 * sin_n) + (-cos(h2 - n) + cos_n + h2 * sin_n));
}

// UpdateHorizon: towards a higher candidate by the distance falloff sat(1 − d²/r²), else 3 % back down
fn update_horizon(max_h: f32, candidate_h: f32, dist_sq: f32) -> f32 {
    let falloff = sat(1.0 - dist_sq * frame.params1.y);
    return select(mix(max_h, candidate_h, 0.03), mix(max_h, candidate_h, falloff), candidate_h > max_h);
}

// InterleavedGradientNoise(positionSS, 0) (core Random.hlsl)
fn gtao_noise(p: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// GetDirection without temporal rotation: angle π·(noise + rotations[i]/360)
fn gtao_direction(p: vec2<u32>, i: u32) -> vec2<f32> {
    var rotations = array<f32, 6>(60.0, 300.0, 180.0, 240.0, 120.0, 0.0);
    let angle = (gtao_noise(vec2<f32>(p)) + rotations[i] / 360.0) * PI;
    return vec2<f32>(cos(angle), sin(angle));
}

// GetOffset without temporal offset: 0.25·((y − x) & 3)
fn gtao_offset(p: vec2<u32>) -> f32 {
    return fract(0.25 * f32((p.y - p.x) & 3u));
}

// GetDepthForCentral at half resolution (MIN_DEPTH_GATHERED_FOR_CENTRAL): the farthest of the four
// level-1 texels around the pixel's corner
fn depth_for_central(p: vec2<i32>) -> f32 {
    let a = hdrp_load(source, p + vec2<i32>(-1, -1)).r;
    let b = hdrp_load(source, p + vec2<i32>(0, -1)).r;
    let c = hdrp_load(source, p + vec2<i32>(-1, 0)).r;
    let d = hdrp_load(source, p).r;
    return max(max(a, b), max(c, d));
}

// GetDepthSample: at half resolution level 1, or level 2 for the later steps (LOWER_RES_SAMPLE); at
// full resolution always level 1 at half the position (HALF_RES_DEPTH_WHEN_FULL_RES): `coarse`
fn depth_sample(position_ss: vec2<f32>, lower_res: bool) -> f32 {
    let p = vec2<u32>(position_ss);
    if (lower_res) {
        return hdrp_load(coarse, vec2<i32>(p / 2u)).r;
    }
    return hdrp_load(source, vec2<i32>(p)).r;
}

// GetNormalVS: the buffer's world normal in view space with z flipped to look down +z
fn normal_vs(p: vec2<i32>) -> vec3<f32> {
    let n = hdrp_load_rgb(normals, p) * 2.0 - 1.0;
    let v = normalize(vec3<f32>(dot(frame.view_x.xyz, n), dot(frame.view_y.xyz, n), dot(frame.view_z.xyz, n)));
    return vec3<f32>(v.xy, -v.z);
}

fn hdrp_load_rgb(t: texture_2d<f32>, p: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t));
    let c = clamp(p, vec2<i32>(0), size - 1);
    return textureLoad(t, vec2<i32>(c.x, size.y - 1 - c.y), 0).rgb;
}

fn horizon_loop(position_vs: vec3<f32>, v: vec3<f32>, ray_start: vec2<f32>, ray_dir: vec2<f32>, ray_offset: f32, ray_step: f32, full: bool) -> f32 {
    var max_horizon = -1.0;
    var t = ray_offset * ray_step + ray_step;
    let step_count = u32(frame.params0.z);
    let start_with_lower_res = u32(min(max(0, i32(step_count / 2u) - 2), 3));
    for (var i = 0u; i < step_count; i++) {
        let sample_pos = max(vec2<f32>(2.0), min(ray_start + t * ray_dir, frame.buffer_size.xy - 2.0));
        let sample_depth = depth_sample(sample_pos, full || i > start_with_lower_res);
        let sample_vs = get_position_vs(sample_pos, sample_depth);
        let delta = sample_vs - position_vs;
        let delta_len_sq = dot(delta, delta);
        let curr_horizon = dot(delta, v) * inverseSqrt(delta_len_sq);
        max_horizon = update_horizon(max_horizon, curr_horizon, delta_len_sq);
        t += ray_step;
    }
    return max_horizon;
}

fn is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// GTAOMain (HALF_RES or FULL_RES, no TEMPORAL): the integral's mean over the directions, packed
// with the depth (PackAOOutput)
fn gtao(id: vec2<u32>, full: bool) -> vec2<f32> {
    let size = textureDimensions(destination);
    // HDRP's dispatch id: rows from the bottom
    let p = vec2<u32>(id.x, size.y - 1u - id.y);
    // Full resolution: level 0 at the pixel (HALF_RES_DEPTH_WHEN_FULL_RES_FOR_CENTRAL 0)
    let curr_depth = select(depth_for_central(vec2<i32>(p)), hdrp_load(source, vec2<i32>(p)).r, full);
    let position_vs = get_position_vs(vec2<f32>(p), curr_depth);
    let offset = gtao_offset(p);
    let ray_start = vec2<f32>(p);
    let v = normalize(-position_vs);
    let step_count = frame.params0.z;
    let radius_ss = clamp(frame.params0.y * frame.params0.x / position_vs.z, step_count, frame.params1.w);
    let ray_step = max(1.0, radius_ss * frame.params0.w);
    let dir_count = u32(frame.params1.z);
    let n_vs = normal_vs(vec2<i32>(select(p * 2u, p, full)));
    var integral = 0.0;
    for (var i = 0u; i < dir_count; i++) {
        let dir = gtao_direction(p, i);
        let neg_dir = -dir + 1e-30;
        var horizons = vec2<f32>(
            horizon_loop(position_vs, v, ray_start, dir, offset, ray_step, full),
            horizon_loop(position_vs, v, ray_start, neg_dir, offset, ray_step, full),
        );
        let slice_n = normalize(cross(vec3<f32>(dir, 0.0), v));
        let proj_n = n_vs - slice_n * dot(n_vs, slice_n);
        let proj_n_len = length(proj_n);
        let cos_n = dot(proj_n / proj_n_len, v);
        let tangent = cross(v, slice_n);
        let n = -sign(dot(proj_n, tangent)) * gtao_fast_acos(cos_n);
        horizons.x = -gtao_fast_acos(horizons.x);
        horizons.y = gtao_fast_acos(horizons.y);
        horizons.x = n + max(horizons.x - n, -HALF_PI);
        horizons.y = n + min(horizons.y - n, HALF_PI);
        if (is_nan(horizons.x) || is_nan(horizons.y)) {
            integral += 1.0;
        } else {
            integral += integrate_arc_cos_weighted(horizons.x, horizons.y, n, cos_n);
        }
    }
    integral /= f32(dir_count);
    if (curr_depth >= 1.0 || integral < -1e-2) {
        integral = 1.0;
    }
    // Full resolution packs as today's GTAOCommon.hlsl does (depth in 23 bits); the
    // half-resolution path keeps the 24 bits of the HDRP release its central depth follows.
    return vec2<f32>(quantise(integral, 255.0), quantise(curr_depth, select(16777215.0, 8388607.0, full)));
}

// BilateralUpsample: weights (9, 3, 3, 1)/(|hi − lo| + 1e-7) over the four half-resolution texels
// nearest the pixel, plus the noise filter's neutral sample; then OutputFinalAO's AO^intensity.
// The result is the visibility the lighting reads (HDRP stores 1 − it in an 8-bit texture).
fn upsample(id: vec2<u32>) -> f32 {
    let p = vec2<i32>(id);
    let low = p / 2;
    let side = select(vec2<i32>(-1), vec2<i32>(1), (p & vec2<i32>(1)) == vec2<i32>(1));
    let hi = load_clamped(coarse, p).r;
    let t0 = load_clamped(source, low);
    let t1 = load_clamped(source, low + vec2<i32>(side.x, 0));
    let t2 = load_clamped(source, low + vec2<i32>(0, side.y));
    let t3 = load_clamped(source, low + side);
    let tolerance = 1e-7;
    let noise_filter = 1.0 / (1.0 + tolerance);
    let w = vec4<f32>(9.0, 3.0, 3.0, 1.0) / (abs(vec4<f32>(hi) - vec4<f32>(t0.g, t1.g, t2.g, t3.g)) + tolerance);
    let ao = (dot(vec4<f32>(t0.r, t1.r, t2.r, t3.r), w) + noise_filter) / (dot(w, vec4<f32>(1.0)) + noise_filter);
    let visibility = pow(max(abs(ao), 1.192092896e-7), frame.params1.x);
    return 1.0 - quantise(1.0 - visibility, 255.0);
}

// BilateralWeight: sat(1 − (aggressiveness·|LinearEyeDepth(d) − central| + 0.01)) (GTAOSpatialDenoise)
fn bilateral_weight(sample_depth: f32, linear_central_depth: f32) -> f32 {
    let delta = abs(linear_eye_depth(sample_depth) - linear_central_depth);
    return sat(1.0 - (frame.z_buffer.z * delta + 0.01));
}

// SpatialDenoise (no TO_TEMPORAL): the packed AO over the 4×4 texels HDRP's four point gathers at
// the pixel + (0, 0), (2, 0), (0, 2), (2, 2) cover (offsets −1 .. 2, edges clamped), the pixel's own
// weighted 1 and the others by their depth; then OutputFinalAO into HDRP's 8-bit texture. The
// result is the visibility the lighting reads, as `upsample`'s.
fn spatial_denoise(id: vec2<u32>) -> f32 {
    let size = textureDimensions(source);
    let p = vec2<i32>(i32(id.x), i32(size.y) - 1 - i32(id.y));
    let central = hdrp_load(source, p);
    let linear_central_depth = linear_eye_depth(central.g);
    var total = 0.0;
    var total_weight = 0.0;
    for (var dy = -1; dy <= 2; dy++) {
        for (var dx = -1; dx <= 2; dx++) {
            let t = hdrp_load(source, p + vec2<i32>(dx, dy));
            let w = select(bilateral_weight(t.g, linear_central_depth), 1.0, dx == 0 && dy == 0);
            total += w * t.r;
            total_weight += w;
        }
    }
    let visibility = pow(max(abs(total / total_weight), 1.192092896e-7), frame.params1.x);
    return 1.0 - quantise(1.0 - visibility, 255.0);
}

@compute @workgroup_size(8, 8)
fn cs_ssao(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ssao_step.dims.x || id.y >= ssao_step.dims.y) {
        return;
    }
    var out = vec2<f32>(0.0);
    switch ssao_step.dims.z {
        case SSAO_CLOSEST: {
            // DepthPyramid's downsample: the closest of the 2×2 finer texels (edges clamped)
            let p = vec2<i32>(id.xy) * 2;
            let a = load_clamped(source, p).r;
            let b = load_clamped(source, p + vec2<i32>(1, 0)).r;
            let c = load_clamped(source, p + vec2<i32>(0, 1)).r;
            let d = load_clamped(source, p + vec2<i32>(1, 1)).r;
            out = vec2<f32>(min(min(a, b), min(c, d)), 0.0);
        }
        case SSAO_HORIZONS, SSAO_HORIZONS_FULL: {
            out = gtao(id.xy, ssao_step.dims.z == SSAO_HORIZONS_FULL);
        }
        case SSAO_UPSAMPLE: {
            out = vec2<f32>(upsample(id.xy), 0.0);
        }
        default: {
            out = vec2<f32>(spatial_denoise(id.xy), 0.0);
        }
    }
    textureStore(destination, id.xy, vec4<f32>(out, 0.0, 0.0));
}
