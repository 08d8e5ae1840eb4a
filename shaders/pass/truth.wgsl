// Ground truth (render::truth): a path tracer over the cell's own scene, lights and materials, for
// the `same-brdf` and `physical` references. Composed after math, conventions, BRDF terms, scene.wgsl (group 0 is
// the cell's frame group: lights, subject material, maps), the subject's model, the fixed
// objects' model renamed with the prefix `fixed_`, and rays.wgsl (group 3: the BVH, the
// environment's tables, ray casting and surface sampling).
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
    // x: bounces; y: 1 when the background shows the sky (else black)
    settings: vec4<u32>,
};

// An object's material and flags (x: 1 subject, y: role id, z: 1 textured subject).
struct TruthObject {
    material: Material,
    flags: vec4<u32>,
};

@group(1) @binding(0) var<uniform> truth: TruthParams;
@group(1) @binding(1) var<storage, read> objects: array<TruthObject>;
// Per pixel: the sum of samples (rgb) and their count (w); then the sum of squares (rgb)
@group(1) @binding(2) var<storage, read_write> accum: array<vec4<f32>>;
// Per pixel: the role of the first hit (0 none)
@group(1) @binding(3) var<storage, read_write> first_roles: array<u32>;

// 0: `same-brdf` (each surface's own model, the pipeline's falloff); 1: `physical` (one physical
// model for every surface, inverse-square falloff; truth_physical.wgsl)
override TRUTH_KIND: u32 = 0u;
// 1 where the subject's (fixed objects') model is diffuse only (SurfaceTwin::diffuse_only)
override SUBJECT_DIFFUSE_ONLY: u32 = 0u;
override FIXED_DIFFUSE_ONLY: u32 = 0u;

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
    // A textured subject reads the frame's maps, a fixed object with maps its layers of fixed_maps.
    let subject_maps = subject && object.flags.z == 1u;
    let fixed_maps = !subject && m.params.w > 0.5;
    let textured = subject_maps || fixed_maps;
    var albedo = vec4<f32>(1.0);
    var mask = vec4<f32>(1.0, 1.0, 1.0, 0.5);
    var glow = vec3<f32>(1.0);
    var ts = vec3<f32>(0.0, 0.0, 1.0);
    if (subject_maps) {
        albedo = textureSampleLevel(material_albedo, material_sampler, sp.uv, 0.0);
        mask = textureSampleLevel(material_mask, material_sampler, sp.uv, 0.0);
        glow = textureSampleLevel(material_emission, material_sampler, sp.uv, 0.0).rgb;
        ts = textureSampleLevel(material_normal, material_sampler, sp.uv, 0.0).xyz;
        if (model_detail(m.model0, m.model1) > 0.5) {
            // Standard's secondary maps, as forward.wgsl `material_at` and `mapped_normal` blend them
            let d = textureSampleLevel(material_detail, material_sampler, sp.uv * DETAIL_TILING, 0.0);
            albedo = vec4<f32>(albedo.rgb * detail_albedo_mulx2(d.w, mask.b), albedo.a);
            ts = mix(ts, blend_normals(ts, d.xyz), mask.b);
        }
    } else if (fixed_maps) {
        albedo = fixed_map_level0(m, 0, sp.uv);
        ts = fixed_map_level0(m, 1, sp.uv).xyz;
        mask = fixed_map_level0(m, 2, sp.uv);
        glow = fixed_map_level0(m, 3, sp.uv).rgb;
    }
    if (textured) {
        let tangent = a.tangent * b0 + b.tangent * hit.b1 + c.tangent * hit.b2;
        n = tangent_to_world(n, vec4<f32>(tangent.xyz, select(1.0, -1.0, tangent.w < 0.0)), ts);
    }
    sp.n = n;
    sp.s = surface_from(m, sp.uv, albedo, mask, textured);
    // The subject's emission where its model emits; a fixed object's own (zero for most).
    sp.emission = m.emission.rgb * glow;
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
struct AreaSample {
    xyz_w: vec4<f32>,   // direction to the point drawn, attenuation
    distance: f32,
};

// An area light at one point drawn uniformly on it: a point light of intensity L·cos θ'·A, so the
// attenuation is cos θ'·A/d², times HDRP's box window for a same-BRDF truth of a rect (cpu.rs `area_incidence`)
fn area_incidence(light: Light, p: vec3<f32>) -> AreaSample {
    let forward = normalize(light.direction.xyz);
    let right = light.shape.xyz;
    let up = cross(forward, right);
    let hw = light.params.y;
    let hh = light.params.z;
    let u1 = random();
    let u2 = random();
    var q = vec3<f32>(0.0);
    var area = 0.0;
    if (u32(light.position.w) == LIGHT_DISC) {
        let r = hw * sqrt(u1);
        let phi = 2.0 * PI * u2;
        q = light.position.xyz + right * (r * cos(phi)) + up * (r * sin(phi));
        area = PI * hw * hw;
    } else {
        q = light.position.xyz + right * (hw * (2.0 * u1 - 1.0)) + up * (hh * (2.0 * u2 - 1.0));
        area = 4.0 * hw * hh;
    }
    let to = q - p;
    let d2 = max(dot(to, to), 1e-12);
    let d = sqrt(d2);
    let l = to / d;
    let cos_light = dot(-l, forward);
    var out: AreaSample;
    out.distance = d;
    if (cos_light <= 0.0) {
        out.xyz_w = vec4<f32>(l, 0.0);
        return out;
    }
    var atten = cos_light * area / d2;
    if (TRUTH_KIND == 0u && u32(light.position.w) == LIGHT_RECT) {
        atten *= rect_attenuation(light, p);
    }
    out.xyz_w = vec4<f32>(l, atten);
    return out;
}

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

// ---- The light at a point: every light and the environment, sampled once each.

fn direct_light(sp: SurfacePoint, v: vec3<f32>) -> vec3<f32> {
    var c = vec3<f32>(0.0);
    let origin = sp.p + sp.ng * RAY_EPSILON;
    for (var i = 0u; i < frame.counts.x; i++) {
        let light = lights[i];
        var inc = vec4<f32>(0.0);
        var distance = 3.4e38;
        if (u32(light.position.w) >= LIGHT_RECT) {
            let a = area_incidence(light, sp.p);
            inc = a.xyz_w;
            distance = a.distance * (1.0 - 1e-4);
        } else {
            inc = light_incidence(light, sp.p);
            if (TRUTH_KIND == 1u) {
                inc.w = physical_attenuation(light, sp.p, inc.xyz);
            }
            if (u32(light.position.w) != 0u) {
                distance = length(light.position.xyz - sp.p) * (1.0 - 1e-4);
            }
        }
        if (inc.w <= 0.0) {
            continue;
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
            c += f * env_radiance(l) / e.w * power_heuristic(e.w, surface_pdf(sp.s, lobe_share(sp), sp.n, v, l));
        }
    }
    return c;
}

// The GGX share of a point's continuations: none for a same-brdf truth's diffuse-only model,
// else specular_share — each bounce sampled from the model's own lobes (cpu.rs `lobe_share`)
fn lobe_share(sp: SurfacePoint) -> f32 {
    let subject = objects[sp.object].flags.x == 1u;
    let diffuse = select(FIXED_DIFFUSE_ONLY, SUBJECT_DIFFUSE_ONLY, subject) == 1u;
    return select(specular_share(sp.s), 0.0, TRUTH_KIND == 0u && diffuse);
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
    // settings.z: Russian roulette past the budget, up to MAX_ROULETTE_BOUNCES (spec::matrix)
    let last = select(truth.settings.x + 1u, 1024u, truth.settings.z == 1u);
    for (var bounce = 0u; bounce <= last; bounce++) {
        let hit = trace(o, d, 3.4e38, false);
        if (hit.triangle == 0xffffffffu) {
            if (bounce == 0u) {
                if (truth.settings.y == 1u) {
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
        if (bounce == last) {
            break;
        }
        let v = -d;
        c += throughput * direct_light(sp, v);
        let k = lobe_share(sp);
        let l = sample_surface(sp.s, k, sp.n, v);
        let pdf = surface_pdf(sp.s, k, sp.n, v, l);
        if (pdf <= 0.0) {
            break;
        }
        light_min_roughness = 4.617e-5;
        throughput *= response(sp, v, l) / pdf;
        if (all(throughput <= vec3<f32>(0.0))) {
            break;
        }
        // Past the budget, the continuation survives Russian roulette or the path ends
        if (truth.settings.z == 1u && bounce >= truth.settings.x) {
            let q = min(max(throughput.x, max(throughput.y, throughput.z)), 0.95);
            if (random() >= q) {
                break;
            }
            throughput /= q;
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
