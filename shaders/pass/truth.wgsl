// Ground truth (render::truth): a path tracer over the cell's own scene, lights and materials, for
// the `same-brdf` and `physical` references. Composed after math, conventions, BRDF terms, scene.wgsl (group 0 is
// the cell's frame group: lights, subject material, maps), the subject's model and the fixed
// objects' model renamed with the prefix `fixed_`.
//
// Per pixel and sample: a camera ray jittered over the pixel's area; at every hit, each light
// exactly (hard visibility by a shadow ray, the pipeline's own attenuation), the environment by
// importance sampling of its texels, and a direction drawn from the surface (cosine or GGX) that
// continues the path, up to `bounces` times. Environment light is weighted between the two
// strategies by the power heuristic (Veach 1997). Every model is evaluated as its own
// model_direct, the cosine-weighted BRDF f·NL times the pipeline's irradiance per intensity.

struct TruthParams {
    // x, y: frame size; z: index of this batch's first sample; w: samples per pixel in this batch
    dims: vec4<u32>,
    // x: bounces; y: environment width; z: environment height; w: 1 when the background shows
    // the sky (else black)
    settings: vec4<u32>,
};

// A BVH node (obvhs Bvh2): min.w holds the primitive count (0: inner), max.w the first child or
// primitive index, both as bits.
struct BvhNode {
    min: vec4<f32>,
    max: vec4<f32>,
};

// World-space vertex: position (w: u), normal (w: v), tangent (w: bitangent sign, 0: none).
struct TruthVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
    tangent: vec4<f32>,
};

// An object's material and flags (x: 1 subject, y: role id, z: 1 textured subject).
struct TruthObject {
    material: Material,
    flags: vec4<u32>,
};

@group(1) @binding(0) var<uniform> truth: TruthParams;
@group(1) @binding(1) var<storage, read> nodes: array<BvhNode>;
// xyz: vertex indices; w: object
@group(1) @binding(2) var<storage, read> triangles: array<vec4<u32>>;
@group(1) @binding(3) var<storage, read> vertices: array<TruthVertex>;
@group(1) @binding(4) var<storage, read> objects: array<TruthObject>;
// The environment's radiance per texel (equirect, top row first), unscaled
@group(1) @binding(5) var<storage, read> env_texels: array<vec4<f32>>;
// Sampling tables: [0, h] the marginal CDF over rows, then per row its CDF over columns (w + 1 each)
@group(1) @binding(6) var<storage, read> env_cdf: array<f32>;
// Per pixel: the sum of samples (rgb) and their count (w); then the sum of squares (rgb)
@group(1) @binding(7) var<storage, read_write> accum: array<vec4<f32>>;
// Per pixel: the role of the first hit (0 none)
@group(1) @binding(8) var<storage, read_write> first_roles: array<u32>;

const TRUTH_STACK: u32 = 48u;

// 0: `same-brdf` (each surface's own model, the pipeline's falloff); 1: `physical` (one physical
// model for every surface, inverse-square falloff; truth_physical.wgsl)
override TRUTH_KIND: u32 = 0u;
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
    var stack: array<u32, TRUTH_STACK>;
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
            if (top + 2u <= TRUTH_STACK) {
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
    let w = truth.settings.y;
    let h = truth.settings.z;
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
    let w = truth.settings.y;
    let h = truth.settings.z;
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
    let w = truth.settings.y;
    let h = truth.settings.z;
    let y = find_bin(0u, h, random());
    let base = (h + 1u) + y * (w + 1u);
    let x = find_bin(base, w, random());
    let d = uv_direction((f32(x) + random()) / f32(w), (f32(y) + random()) / f32(h));
    return vec4<f32>(d, env_pdf(d));
}

// ---- Surfaces.

struct SurfacePoint {
    p: vec3<f32>,
    // Shading normal (mapped, facing the incoming ray's side) and geometric normal (same side)
    n: vec3<f32>,
    ng: vec3<f32>,
    uv: vec2<f32>,
    object: u32,
    s: Surface,
    emission: vec3<f32>,
};

fn surface_at(hit: Hit, d: vec3<f32>) -> SurfacePoint {
    let tri = triangles[hit.triangle];
    let a = vertices[tri.x];
    let b = vertices[tri.y];
    let c = vertices[tri.z];
    let b0 = 1.0 - hit.b1 - hit.b2;
    var sp: SurfacePoint;
    sp.p = a.position.xyz * b0 + b.position.xyz * hit.b1 + c.position.xyz * hit.b2;
    let uv_a = vec2<f32>(a.position.w, a.normal.w);
    let uv_b = vec2<f32>(b.position.w, b.normal.w);
    let uv_c = vec2<f32>(c.position.w, c.normal.w);
    sp.uv = uv_a * b0 + uv_b * hit.b1 + uv_c * hit.b2;
    var ng = normalize(cross(b.position.xyz - a.position.xyz, c.position.xyz - a.position.xyz));
    let front = dot(ng, d) < 0.0;
    ng = select(-ng, ng, front);
    let interpolated = a.normal.xyz * b0 + b.normal.xyz * hit.b1 + c.normal.xyz * hit.b2;
    var n = ng;
    if (dot(interpolated, interpolated) > 1e-30) {
        n = normalize(interpolated);
        // Flipped on back faces, as the rasteriser's shading normal is
        n = select(-n, n, front);
    }
    sp.ng = ng;
    sp.object = tri.w;
    let object = objects[tri.w];
    var m = object.material;
    let subject = object.flags.x == 1u;
    if (subject) {
        m = frame.subject;
    }
    let textured = subject && object.flags.z == 1u;
    var albedo = vec4<f32>(1.0);
    var mask = vec4<f32>(1.0, 1.0, 1.0, 0.5);
    var glow = vec3<f32>(1.0);
    if (textured) {
        albedo = textureSampleLevel(material_albedo, material_sampler, sp.uv, 0.0);
        mask = textureSampleLevel(material_mask, material_sampler, sp.uv, 0.0);
        glow = textureSampleLevel(material_emission, material_sampler, sp.uv, 0.0).rgb;
        let tangent = a.tangent * b0 + b.tangent * hit.b1 + c.tangent * hit.b2;
        let ts = textureSampleLevel(material_normal, material_sampler, sp.uv, 0.0).xyz;
        n = tangent_to_world(n, vec4<f32>(tangent.xyz, select(1.0, -1.0, tangent.w < 0.0)), ts);
    }
    sp.n = n;
    sp.s = surface_from(m, sp.uv, albedo, mask, textured);
    sp.emission = select(vec3<f32>(0.0), frame.subject.emission.rgb * glow, subject);
    return sp;
}

// The cosine-weighted BRDF f·NL at a point: the subject's model or the fixed objects' (their
// model_direct without the pipeline's irradiance per intensity), or the physical model
fn response(sp: SurfacePoint, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    if (dot(sp.ng, l) <= 0.0) {
        return vec3<f32>(0.0);
    }
    if (TRUTH_KIND == 1u) {
        return physical_response(sp.s, sp.n, v, l);
    }
    var c: vec3<f32>;
    if (objects[sp.object].flags.x == 1u) {
        c = model_direct(sp.s, sp.n, v, l);
    } else {
        c = fixed_model_direct(sp.s, sp.n, v, l);
    }
    return max(c, vec3<f32>(0.0)) / irradiance_per_intensity();
}

// Physical falloff: inverse square (HDRP's 1 cm floor), no range window; spots keep their cone
fn physical_attenuation(light: Light, p: vec3<f32>, l: vec3<f32>) -> f32 {
    let kind = u32(light.position.w);
    if (kind == 0u) {
        return 1.0;
    }
    let to_light = light.position.xyz - p;
    var atten = 1.0 / max(dot(to_light, to_light), 1e-4);
    if (kind == 2u) {
        atten *= angle_attenuation(dot(normalize(light.direction.xyz), -l), light.params.y, light.params.z);
    }
    return atten;
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

// The density of `sample_surface` for l (solid angle)
fn surface_pdf(sp: SurfacePoint, v: vec3<f32>, l: vec3<f32>) -> f32 {
    let nl = dot(sp.n, l);
    let nv = dot(sp.n, v);
    if (nl <= 0.0 || nv <= 0.0) {
        return 0.0;
    }
    let a = ggx_alpha(sp.s);
    let h = normalize(v + l);
    let spec = d_ggx(dot(sp.n, h), a) * ggx_g1(nv, a) / (4.0 * nv);
    let k = specular_share(sp.s);
    return k * spec + (1.0 - k) * nl * INV_PI;
}

fn sample_surface(sp: SurfacePoint, v: vec3<f32>) -> vec3<f32> {
    let frame_n = basis(sp.n);
    let u1 = random();
    let u2 = random();
    if (random() >= specular_share(sp.s)) {
        let r = sqrt(u1);
        let phi = 2.0 * PI * u2;
        return frame_n * vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)));
    }
    let a = ggx_alpha(sp.s);
    let vl = transpose(frame_n) * v;
    if (vl.z <= 0.0) {
        return reflect(-v, sp.n);
    }
    let vh = normalize(vec3<f32>(a * vl.x, a * vl.y, vl.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(-vh.y, vh.x, 0.0) * inverseSqrt(lensq), lensq > 0.0);
    let t2 = cross(vh, t1);
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(1.0 - p1 * p1) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    let m = normalize(vec3<f32>(a * nh.x, a * nh.y, max(0.0, nh.z)));
    return frame_n * reflect(-vl, m);
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    return a * a / max(a * a + b * b, 1e-30);
}


// ---- The light at a point: every light and the environment, sampled once each.

fn direct_light(sp: SurfacePoint, v: vec3<f32>) -> vec3<f32> {
    var c = vec3<f32>(0.0);
    let origin = sp.p + sp.ng * RAY_EPSILON;
    for (var i = 0u; i < frame.counts.x; i++) {
        let light = lights[i];
        var inc = light_incidence(light, sp.p);
        if (TRUTH_KIND == 1u) {
            inc.w = physical_attenuation(light, sp.p, inc.xyz);
        }
        if (inc.w <= 0.0) {
            continue;
        }
        var distance = 3.4e38;
        if (u32(light.position.w) != 0u) {
            distance = length(light.position.xyz - sp.p) * (1.0 - 1e-4);
        }
        light_min_roughness = light.params.w;
        let f = response(sp, v, inc.xyz);
        if (any(f > vec3<f32>(0.0)) && !occluded(origin, inc.xyz, distance)) {
            // Lights are in the pipeline's units: the model's own factor is taken back out
            c += f * irradiance_per_intensity() * light.color.rgb * inc.w;
        }
    }
    light_min_roughness = 4.617e-5;
    if (frame.env.y > 0.0) {
        let e = sample_env();
        let l = e.xyz;
        let f = response(sp, v, l);
        if (e.w > 0.0 && any(f > vec3<f32>(0.0)) && !occluded(origin, l, 3.4e38)) {
            c += f * env_radiance(l) / e.w * power_heuristic(e.w, surface_pdf(sp, v, l));
        }
    }
    return c;
}

// One path from the camera through pixel `pixel`
fn path(pixel: vec2<u32>) -> vec3<f32> {
    let size = vec2<f32>(truth.dims.xy);
    let jitter = vec2<f32>(random(), random());
    let ndc = vec2<f32>((f32(pixel.x) + jitter.x) / size.x * 2.0 - 1.0, 1.0 - (f32(pixel.y) + jitter.y) / size.y * 2.0);
    let far = frame.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    var o = frame.camera_pos.xyz;
    var d = normalize(far.xyz / far.w - o);
    var throughput = vec3<f32>(1.0);
    var c = vec3<f32>(0.0);
    var last_pdf = 0.0;
    for (var bounce = 0u; bounce <= truth.settings.x + 1u; bounce++) {
        let hit = trace(o, d, 3.4e38, false);
        if (hit.triangle == 0xffffffffu) {
            if (bounce == 0u) {
                if (truth.settings.w == 1u) {
                    c += env_radiance(d);
                }
            } else if (frame.env.y > 0.0) {
                c += throughput * env_radiance(d) * power_heuristic(last_pdf, env_pdf(d));
            }
            break;
        }
        let sp = surface_at(hit, d);
        if (bounce == 0u) {
            first_roles[pixel.y * truth.dims.x + pixel.x] = objects[sp.object].flags.y;
        }
        c += throughput * sp.emission;
        // The last vertex only receives the environment along the continued ray (its weight)
        if (bounce == truth.settings.x + 1u) {
            break;
        }
        let v = -d;
        c += throughput * direct_light(sp, v);
        let l = sample_surface(sp, v);
        let pdf = surface_pdf(sp, v, l);
        if (pdf <= 0.0) {
            break;
        }
        light_min_roughness = 4.617e-5;
        throughput *= response(sp, v, l) / pdf;
        if (all(throughput <= vec3<f32>(0.0))) {
            break;
        }
        last_pdf = pdf;
        o = sp.p + sp.ng * RAY_EPSILON;
        d = l;
    }
    return c;
}

@compute @workgroup_size(8, 8)
fn cs_truth(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= truth.dims.x || id.y >= truth.dims.y) {
        return;
    }
    let index = id.y * truth.dims.x + id.x;
    // counts.y: 1 + the main directional light (models that read its colour)
    main_light_color = vec3<f32>(0.0);
    if (frame.counts.y > 0u) {
        main_light_color = lights[frame.counts.y - 1u].color.rgb;
    }
    var sum = accum[2u * index];
    var squares = accum[2u * index + 1u];
    for (var k = 0u; k < truth.dims.w; k++) {
        rng_seed(index, truth.dims.z + k);
        var c = path(id.xy);
        // A NaN or infinite sample (a model's singularity) would poison the pixel; counted as 0
        if (any(c != c) || any(abs(c) > vec3<f32>(1e30))) {
            c = vec3<f32>(0.0);
        }
        sum += vec4<f32>(c, 1.0);
        squares += vec4<f32>(c * c, 0.0);
    }
    accum[2u * index] = sum;
    accum[2u * index + 1u] = squares;
}
