// SSIM (Wang et al. 2004) on the luma of two sRGB images, as `compare::ssim` computes it (the CPU
// reference the tests hold this to): an 11-tap Gaussian window (σ = 1.5) applied separably with
// scipy's `reflect` boundary, K1 = 0.01, K2 = 0.03, population covariance. The mean over the
// window-valid region is taken from the map on the CPU.

struct SsimParams {
    width: u32,
    height: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> p: SsimParams;
// Reference pixels, then test pixels: sRGB values in [0, 1].
@group(0) @binding(1) var<storage, read> images: array<vec4<f32>>;
// Horizontal results: μx, μy, E[x²], E[y²], E[xy] (5 × n).
@group(0) @binding(2) var<storage, read_write> inter: array<f32>;
@group(0) @binding(3) var<storage, read_write> ssim_map: array<f32>;
// The 11 normalised Gaussian weights.
@group(0) @binding(4) var<storage, read> window: array<f32>;

const RADIUS: i32 = 5;
const C1: f32 = 0.0001; // (K1·L)², K1 = 0.01, L = 1
const C2: f32 = 0.0009; // (K2·L)², K2 = 0.03

// Y′ = 0.2126 R′ + 0.7152 G′ + 0.0722 B′ of the sRGB-encoded values
fn luma(c: vec4<f32>) -> f32 {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// scipy's `reflect`: (d c b a | a b c d | d c b a)
fn reflect_coord(i: i32, size: u32) -> u32 {
    let n = i32(size);
    let period = 2 * n;
    let m = ((i % period) + period) % period;
    if m < n {
        return u32(m);
    }
    return u32(period - 1 - m);
}

@compute @workgroup_size(256)
fn ssim_h(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = p.width * p.height;
    let i = gid.x;
    if i >= n {
        return;
    }
    let x = i32(i % p.width);
    let row = i - i % p.width;
    var mx = 0.0;
    var my = 0.0;
    var xx = 0.0;
    var yy = 0.0;
    var xy = 0.0;
    for (var k = -RADIUS; k <= RADIUS; k++) {
        let w = window[u32(k + RADIUS)];
        let j = row + reflect_coord(x + k, p.width);
        let a = luma(images[j]);
        let b = luma(images[n + j]);
        mx += w * a;
        my += w * b;
        xx += w * (a * a);
        yy += w * (b * b);
        xy += w * (a * b);
    }
    inter[i] = mx;
    inter[n + i] = my;
    inter[2u * n + i] = xx;
    inter[3u * n + i] = yy;
    inter[4u * n + i] = xy;
}

@compute @workgroup_size(256)
fn ssim_v(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = p.width * p.height;
    let i = gid.x;
    if i >= n {
        return;
    }
    let x = i % p.width;
    let y = i32(i / p.width);
    var s: array<f32, 5>;
    for (var k = -RADIUS; k <= RADIUS; k++) {
        let w = window[u32(k + RADIUS)];
        let j = reflect_coord(y + k, p.height) * p.width + x;
        for (var c = 0u; c < 5u; c++) {
            s[c] += w * inter[c * n + j];
        }
    }
    let ux = s[0];
    let uy = s[1];
    let vx = s[2] - ux * ux;
    let vy = s[3] - uy * uy;
    let vxy = s[4] - ux * uy;
    ssim_map[i] = ((2.0 * ux * uy + C1) * (2.0 * vxy + C2)) / ((ux * ux + uy * uy + C1) * (vx + vy + C2));
}
