// The scene as rays see it, shared by the truth's tracer (truth.wgsl) and the real-time passes'
// exact alternatives (exact.wgsl): the cell's triangles in a BVH, the environment with its
// importance-sampling tables and its exact irradiance, random numbers, ray casting, and the
// surface sampling that both estimators weigh against the environment's. Group 3 of either
// module (render::truth::RayScene); bindings from 10 so that they never meet the deferred
// lighting's tile group, which is group 3 of the forward module.

// A BVH node (obvhs Bvh2): min.w holds the primitive count (0: inner), max.w the first child or
// primitive index, both as bits.
struct BvhNode {
    min: vec4<f32>,
    max: vec4<f32>,
};

// World-space vertex: position (w: u), normal (w: v), tangent (w: bitangent sign, 0: none).
struct RayVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
    tangent: vec4<f32>,
};

// Sizes: x, y the environment table's; z, w the irradiance map's
struct RaySceneInfo {
    env_size: vec4<u32>,
};

@group(3) @binding(10) var<uniform> rays: RaySceneInfo;
@group(3) @binding(11) var<storage, read> nodes: array<BvhNode>;
// xyz: vertex indices; w: object
@group(3) @binding(12) var<storage, read> triangles: array<vec4<u32>>;
@group(3) @binding(13) var<storage, read> vertices: array<RayVertex>;
// The environment's radiance per texel (equirect, top row first), unscaled
@group(3) @binding(14) var<storage, read> env_texels: array<vec4<f32>>;
// Sampling tables: [0, h] the marginal CDF over rows, then per row its CDF over columns (w + 1 each)
@group(3) @binding(15) var<storage, read> env_cdf: array<f32>;
// E(n)/π of the unscaled environment per texel of an equirect map (environment::irradiance)
@group(3) @binding(16) var<storage, read> irradiance_texels: array<vec4<f32>>;
// The traced shadow mask of the frame (traced_shadows.wgsl): [0] its width, then per pixel bit i
// set when light i is occluded
@group(3) @binding(17) var<storage, read> traced_mask: array<u32>;

const RAY_STACK: u32 = 48u;
const RAY_EPSILON: f32 = 1e-4;

// ---- Random numbers: PCG (O'Neill 2014) hashed from pixel, sample and dimension.

var<private> rng_state: u32;

fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn rng_seed(pixel: u32, sample: u32) {
    rng_state = pcg_hash(pixel ^ pcg_hash(sample * 9781u + 1u));
}

fn random() -> f32 {
    rng_state = pcg_hash(rng_state);
    return f32(rng_state >> 8u) * (1.0 / 16777216.0);
}

// ---- Intersection.

struct Hit {
    t: f32,
    triangle: u32,
    b1: f32,
    b2: f32,
};

// Möller–Trumbore: (t, b1, b2), t < 0 for a miss
fn intersect_triangle(o: vec3<f32>, d: vec3<f32>, tri: vec4<u32>) -> vec3<f32> {
    let p0 = vertices[tri.x].position.xyz;
    let e1 = vertices[tri.y].position.xyz - p0;
    let e2 = vertices[tri.z].position.xyz - p0;
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if (abs(det) < 1e-12) {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    let inv = 1.0 / det;
    let tv = o - p0;
    let b1 = dot(tv, pv) * inv;
    if (b1 < 0.0 || b1 > 1.0) {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    let qv = cross(tv, e1);
    let b2 = dot(d, qv) * inv;
    if (b2 < 0.0 || b1 + b2 > 1.0) {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    return vec3<f32>(dot(e2, qv) * inv, b1, b2);
}

// Slab test: the entry distance, or a huge value for a miss
fn intersect_box(o: vec3<f32>, inv_d: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>, t_max: f32) -> f32 {
    let a = (lo - o) * inv_d;
    let b = (hi - o) * inv_d;
    let t0 = max(max(min(a.x, b.x), min(a.y, b.y)), max(min(a.z, b.z), 0.0));
    let t1 = min(min(max(a.x, b.x), max(a.y, b.y)), min(max(a.z, b.z), t_max));
    return select(3.4e38, t0, t0 <= t1);
}

// The nearest hit along o + t·d for t in (0, t_max); t_max when nothing is hit. `any`: stop at
// the first hit (shadow rays).
fn trace(o: vec3<f32>, d: vec3<f32>, t_max: f32, any: bool) -> Hit {
    var hit = Hit(t_max, 0xffffffffu, 0.0, 0.0);
    let inv_d = 1.0 / select(d, vec3<f32>(1e-30), abs(d) < vec3<f32>(1e-30));
    var stack: array<u32, RAY_STACK>;
    var top = 1u;
    stack[0] = 0u;
    while (top > 0u) {
        top -= 1u;
        let node = nodes[stack[top]];
        if (intersect_box(o, inv_d, node.min.xyz, node.max.xyz, hit.t) >= hit.t) {
            continue;
        }
        let count = bitcast<u32>(node.min.w);
        let first = bitcast<u32>(node.max.w);
        if (count == 0u) {
            if (top + 2u <= RAY_STACK) {
                stack[top] = first;
                stack[top + 1u] = first + 1u;
                top += 2u;
            }
            continue;
        }
        for (var k = 0u; k < count; k++) {
            let r = intersect_triangle(o, d, triangles[first + k]);
            if (r.x > RAY_EPSILON && r.x < hit.t) {
                hit = Hit(r.x, first + k, r.y, r.z);
                if (any) {
                    return hit;
                }
            }
        }
    }
    return hit;
}

fn occluded(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> bool {
    return trace(o, d, t_max, true).triangle != 0xffffffffu;
}

// ---- The environment.

fn env_texel_index(d: vec3<f32>) -> u32 {
    let w = rays.env_size.x;
    let h = rays.env_size.y;
    let uv = equirect_uv(d);
    let x = min(u32(uv.x * f32(w)), w - 1u);
    let y = min(u32(uv.y * f32(h)), h - 1u);
    return y * w + x;
}

// Radiance from direction d, in the pipeline's units (the sky's scale applied)
fn env_radiance(d: vec3<f32>) -> vec3<f32> {
    return env_texels[env_texel_index(d)].rgb * frame.env.y;
}

// The first index i in [start, start + n] with cdf[i] > u, less one: the bin u falls in
fn find_bin(start: u32, n: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = n;
    while (lo + 1u < hi) {
        let mid = (lo + hi) / 2u;
        if (env_cdf[start + mid] <= u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

fn uv_direction(u: f32, v: f32) -> vec3<f32> {
    let phi = (u - 0.5) * 2.0 * PI;
    let theta = v * PI;
    // Inverse of equirect_uv: atan2(x, −z) = phi, acos(y) = theta
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// Solid-angle density of sampling d from the environment's table
fn env_pdf(d: vec3<f32>) -> f32 {
    let w = rays.env_size.x;
    let h = rays.env_size.y;
    let i = env_texel_index(d);
    let x = i % w;
    let y = i / w;
    let row = env_cdf[y + 1u] - env_cdf[y];
    let base = (h + 1u) + y * (w + 1u);
    let col = env_cdf[base + x + 1u] - env_cdf[base + x];
    let sin_theta = sqrt(max(1.0 - d.y * d.y, 1e-12));
    return row * col * f32(w * h) / (2.0 * PI * PI * sin_theta);
}

// A direction drawn from the table: (direction, pdf)
fn sample_env() -> vec4<f32> {
    let w = rays.env_size.x;
    let h = rays.env_size.y;
    let y = find_bin(0u, h, random());
    let base = (h + 1u) + y * (w + 1u);
    let x = find_bin(base, w, random());
    let d = uv_direction((f32(x) + random()) / f32(w), (f32(y) + random()) / f32(h));
    return vec4<f32>(d, env_pdf(d));
}
// ---- Sampling the surface: cosine, or GGX visible normals (Heitz 2018) for the specular lobe.

fn basis(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    return mat3x3<f32>(t, bt, n);
}

fn specular_share(s: Surface) -> f32 {
    return clamp(0.25 + 0.5 * s.smoothness * (0.5 + 0.5 * s.metallic), 0.1, 0.9);
}

fn ggx_alpha(s: Surface) -> f32 {
    let pr = 1.0 - s.smoothness;
    return max(pr * pr, 1e-3);
}

fn ggx_g1(nv: f32, a: f32) -> f32 {
    let a2 = a * a;
    return 2.0 * nv / (nv + sqrt(a2 + (1.0 - a2) * nv * nv));
}

// The density of `sample_surface` for l (solid angle), k the GGX share
fn surface_pdf(s: Surface, k: f32, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> f32 {
    let nl = dot(n, l);
    let nv = dot(n, v);
    if (nl <= 0.0 || nv <= 0.0) {
        return 0.0;
    }
    let a = ggx_alpha(s);
    let h = normalize(v + l);
    let spec = select(0.0, d_ggx(dot(n, h), a) * ggx_g1(nv, a) / (4.0 * nv), k > 0.0);
    return k * spec + (1.0 - k) * nl * INV_PI;
}

// A continuation: the cosine lobe, or GGX visible normals with probability k
fn sample_surface(s: Surface, k: f32, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let frame_n = basis(n);
    let u1 = random();
    let u2 = random();
    if (random() >= k) {
        let r = sqrt(u1);
        let phi = 2.0 * PI * u2;
        return frame_n * vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)));
    }
    let a = ggx_alpha(s);
    let vl = transpose(frame_n) * v;
    if (vl.z <= 0.0) {
        return reflect(-v, n);
    }
    let vh = normalize(vec3<f32>(a * vl.x, a * vl.y, vl.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(-vh.y, vh.x, 0.0) * inverseSqrt(lensq), lensq > 0.0);
    let t2 = cross(vh, t1);
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let p1 = r * cos(phi);
    let blend = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - blend) * sqrt(1.0 - p1 * p1) + blend * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    let m = normalize(vec3<f32>(a * nh.x, a * nh.y, max(0.0, nh.z)));
    return frame_n * reflect(-vl, m);
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    return a * a / max(a * a + b * b, 1e-30);
}
