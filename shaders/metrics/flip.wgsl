// FLIP (Andersson et al. 2020, NVIDIA FLIP v1.7) as compute passes: a port of flip-rs
// (`compare::flip`, the reference the tests hold these passes to), term by term and tap by tap in
// the same order. One evaluation = convert → color_h → color_v → feature_h → feature_v; HDR-FLIP
// runs it once per exposure and keeps the per-pixel maximum (`first` = 0).

struct FlipParams {
    width: u32,
    height: u32,
    spatial_radius: u32,
    feature_radius: u32,
    // 0: sRGB values in [0, 1] (LDR-FLIP); 1: linear values exposed by `multiplier`, ACES-tonemapped.
    mode: u32,
    multiplier: f32,
    // 1: the evaluation writes the map; 0: keeps the larger of it and the map (HDR exposures).
    first: u32,
    // color3::computeMaxDistance: HyAB(Lab(green), Lab(blue))^0.7, from the CPU.
    cmax: f32,
}

@group(0) @binding(0) var<uniform> p: FlipParams;
// Reference pixels, then test pixels (RGBA; alpha ignored).
@group(0) @binding(1) var<storage, read> images: array<vec4<f32>>;
// Y, Cx, Cz planes of the reference, then of the test (6 × n).
@group(0) @binding(2) var<storage, read_write> opponent: array<f32>;
// Horizontal filter results: 8 planes (colour), then 6 (features) reuse the first ones.
@group(0) @binding(3) var<storage, read_write> inter: array<f32>;
@group(0) @binding(4) var<storage, read_write> color_error: array<f32>;
@group(0) @binding(5) var<storage, read_write> flip_map: array<f32>;
// Spatial (CSF) weights per tap: Y, Cx, Cz first Gaussian, Cz second Gaussian.
@group(0) @binding(6) var<storage, read> spatial: array<vec4<f32>>;
// Feature weights per tap: Gaussian, first and second derivative (normalised).
@group(0) @binding(7) var<storage, read> feature: array<vec4<f32>>;

fn pixel_count() -> u32 {
    return p.width * p.height;
}

// color3::clamp: min(max(v, 0), 1), NaN to 0.
fn clamp01(v: f32) -> f32 {
    if v > 0.0 {
        return min(v, 1.0);
    }
    return 0.0;
}

// color3::sRGBToLinearRGB
fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        return v / 12.92;
    }
    return pow((v + 0.055) / 1.055, 2.4);
}

// color3::LinearRGBToXYZ
fn linear_to_xyz(v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        (10135552.0 / 24577794.0) * v.x + (8788810.0 / 24577794.0) * v.y + (4435075.0 / 24577794.0) * v.z,
        (2613072.0 / 12288897.0) * v.x + (8788810.0 / 12288897.0) * v.y + (887015.0 / 12288897.0) * v.z,
        (1425312.0 / 73733382.0) * v.x + (8788810.0 / 73733382.0) * v.y + (70074185.0 / 73733382.0) * v.z,
    );
}

// color3::XYZToYCxCz(LinearRGBToXYZ(v)), D65-normalised
fn linear_to_opponent(v: vec3<f32>) -> vec3<f32> {
    let xyz = linear_to_xyz(v);
    let x = xyz.x * 1.052156925;
    let y = xyz.y;
    let z = xyz.z * 0.918357670;
    return vec3<f32>(116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z));
}

// image::toneMap, ACES (Narkowicz's fit as FLIP scales it by 0.6)
fn tone_map_aces(c: f32) -> f32 {
    let a = 0.6 * 0.6 * 2.51;
    let b = 0.6 * 0.03;
    let d = 0.6 * 0.6 * 2.43;
    let e = 0.6 * 0.59;
    let f = 0.14;
    return ((c * c) * a + c * b + 0.0) / ((c * c) * d + c * e + f);
}

// XYZToCIELab's companding: cube root above (6/29)³, linear below
fn lab_f(v: f32) -> f32 {
    let delta = 6.0 / 29.0;
    let delta_square = delta * delta;
    if v > delta * delta_square {
        return pow(v, 1.0 / 3.0);
    }
    return (1.0 / (3.0 * delta_square)) * v + 4.0 / 29.0;
}

// Filtered YCxCz → XYZ → linear RGB (clamped) → XYZ → CIELab → Hunt-adjusted Lab
fn filtered_lab(yp: f32, cx: f32, cz: f32) -> vec3<f32> {
    let y = (yp + 16.0) / 116.0;
    let x = (y + cx / 500.0) * 0.950428545;
    let z = (y - cz / 200.0) * 1.088900371;
    let rgb = vec3<f32>(
        clamp01(3.241003275 * x + -1.537398934 * y + -0.498615861 * z),
        clamp01(-0.969224334 * x + 1.875930071 * y + 0.041554224 * z),
        clamp01(0.055639423 * x + -0.204011202 * y + 1.057148933 * z),
    );
    let xyz = linear_to_xyz(rgb);
    let fx = lab_f(xyz.x * 1.052156925);
    let fy = lab_f(xyz.y);
    let fz = lab_f(xyz.z * 0.918357670);
    let l = 116.0 * fy - 16.0;
    return vec3<f32>(l, 0.01 * l * (500.0 * (fx - fy)), 0.01 * l * (200.0 * (fy - fz)));
}

// color3::HyAB: |ΔL| + ‖Δ(a, b)‖
fn hyab(r: vec3<f32>, t: vec3<f32>) -> f32 {
    let a = r.y - t.y;
    let b = r.z - t.z;
    return abs(r.x - t.x) + sqrt(a * a + b * b);
}

fn clamp_coord(v: i32, size: u32) -> u32 {
    return u32(clamp(v, 0, i32(size) - 1));
}

@compute @workgroup_size(256)
fn convert(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = pixel_count();
    let i = gid.x;
    if i >= 2u * n {
        return;
    }
    let image = i / n;
    let px = i % n;
    let c = images[i].rgb;
    var lin: vec3<f32>;
    if p.mode == 0u {
        lin = vec3<f32>(srgb_to_linear(clamp01(c.x)), srgb_to_linear(clamp01(c.y)), srgb_to_linear(clamp01(c.z)));
    } else {
        let e = c * p.multiplier;
        lin = vec3<f32>(clamp01(tone_map_aces(e.x)), clamp01(tone_map_aces(e.y)), clamp01(tone_map_aces(e.z)));
    }
    let o = linear_to_opponent(lin);
    let base = image * 3u * n;
    opponent[base + px] = o.x;
    opponent[base + n + px] = o.y;
    opponent[base + 2u * n + px] = o.z;
}

// image::computeColorDifference, horizontal: 8 planes (per image: Y, Cx, Cz with the first and
// the second Cz Gaussian), taps at clamped columns.
@compute @workgroup_size(256)
fn color_h(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = pixel_count();
    let i = gid.x;
    if i >= n {
        return;
    }
    let x = i32(i % p.width);
    let row = i - i % p.width;
    let r = i32(p.spatial_radius);
    for (var c = 0u; c < 8u; c++) {
        let image = c / 4u;
        let plane = min(c % 4u, 2u);
        let base = (image * 3u + plane) * n + row;
        var sum = 0.0;
        for (var k = -r; k <= r; k++) {
            sum += spatial[u32(k + r)][c % 4u] * opponent[base + clamp_coord(x + k, p.width)];
        }
        inter[c * n + i] = sum;
    }
}

// image::computeColorDifference, vertical: Lab of both filtered images, HyAB^0.7, mapped to [0, 1]
// with the knee at 0.4·cmax.
@compute @workgroup_size(256)
fn color_v(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = pixel_count();
    let i = gid.x;
    if i >= n {
        return;
    }
    let x = i % p.width;
    let y = i32(i / p.width);
    let r = i32(p.spatial_radius);
    var s: array<f32, 8>;
    for (var k = -r; k <= r; k++) {
        let w = spatial[u32(k + r)];
        let j = clamp_coord(y + k, p.height) * p.width + x;
        for (var c = 0u; c < 8u; c++) {
            s[c] += w[c % 4u] * inter[c * n + j];
        }
    }
    let lr = filtered_lab(s[0], s[1], s[2] + s[3]);
    let lt = filtered_lab(s[4], s[5], s[6] + s[7]);
    let cmax = p.cmax;
    let pccmax = 0.4 * cmax;
    let d = pow(hyab(lr, lt), 0.7);
    var e: f32;
    if d < pccmax {
        e = d * (0.95 / pccmax);
    } else {
        e = 0.95 + ((d - pccmax) / (cmax - pccmax)) * (1.0 - 0.95);
    }
    color_error[i] = e;
}

// Y normalised to [0, 1]: (Y + 16)/116, in flip-rs's order (a product, then a sum).
fn normalized_y(image: u32, j: u32) -> f32 {
    return opponent[image * 3u * pixel_count() + j] * (1.0 / 116.0) + (16.0 / 116.0);
}

// image::computeFeatureDifferenceAndFinalError, horizontal: per image the first and second
// derivative and the Gaussian along the row.
@compute @workgroup_size(256)
fn feature_h(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = pixel_count();
    let i = gid.x;
    if i >= n {
        return;
    }
    let x = i32(i % p.width);
    let row = i - i % p.width;
    let r = i32(p.feature_radius);
    for (var image = 0u; image < 2u; image++) {
        var dg = 0.0;
        var ddg = 0.0;
        var g = 0.0;
        for (var k = -r; k <= r; k++) {
            let w = feature[u32(k + r)];
            let v = normalized_y(image, row + clamp_coord(x + k, p.width));
            dg += w.y * v;
            ddg += w.z * v;
            g += w.x * v;
        }
        inter[(image * 3u) * n + i] = dg;
        inter[(image * 3u + 1u) * n + i] = ddg;
        inter[(image * 3u + 2u) * n + i] = g;
    }
}

// image::computeFeatureDifferenceAndFinalError, vertical: edges (first derivatives) and points
// (second), their larger difference ^0.5, and the final error colour^(1 − feature).
@compute @workgroup_size(256)
fn feature_v(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = pixel_count();
    let i = gid.x;
    if i >= n {
        return;
    }
    let x = i % p.width;
    let y = i32(i / p.width);
    let r = i32(p.feature_radius);
    // dx, ddx, dy, ddy of the reference, then of the test.
    var s: array<f32, 8>;
    for (var k = -r; k <= r; k++) {
        let w = feature[u32(k + r)];
        let j = clamp_coord(y + k, p.height) * p.width + x;
        for (var image = 0u; image < 2u; image++) {
            let b = image * 3u * n;
            s[image * 4u] += w.x * inter[b + j];
            s[image * 4u + 1u] += w.x * inter[b + n + j];
            s[image * 4u + 2u] += w.y * inter[b + 2u * n + j];
            s[image * 4u + 3u] += w.z * inter[b + 2u * n + j];
        }
    }
    let edge_r = sqrt(s[0] * s[0] + s[2] * s[2]);
    let edge_t = sqrt(s[4] * s[4] + s[6] * s[6]);
    let point_r = sqrt(s[1] * s[1] + s[3] * s[3]);
    let point_t = sqrt(s[5] * s[5] + s[7] * s[7]);
    let f = sqrt((1.0 / sqrt(2.0)) * max(abs(edge_r - edge_t), abs(point_r - point_t)));
    let exponent = 1.0 - f;
    let c = color_error[i];
    var e = 1.0;
    if exponent != 0.0 {
        e = pow(c, exponent);
    }
    if p.first == 1u {
        flip_map[i] = e;
    } else {
        flip_map[i] = max(flip_map[i], e);
    }
}
