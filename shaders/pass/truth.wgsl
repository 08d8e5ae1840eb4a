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
    // x: bounces; y: 1 when the background shows the sky (else black); z: Russian roulette;
    // w: the truth's first row in this dispatch, a probe's samples in the bake
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

// ---- The bake (render::truth::bake): the points it gathers light at and what each light gives it.

// A lightmap texel (position.w = 0: its normal in `normal`) or a light probe (position.w = 1)
struct BakePoint {
    position: vec4<f32>,
    normal: vec4<f32>,
};

// Per light: weights (x: direct at a texel, y: direct at a probe, z: bounced light, w: shadow-mask
// channel, −1 none) and shape (x: baked shadow radius, y: tan of half the baked shadow angle)
struct BakeLight {
    weights: vec4<f32>,
    shape: vec4<f32>,
};

@group(1) @binding(4) var<storage, read> bake_points: array<BakePoint>;
@group(1) @binding(5) var<storage, read> bake_lights: array<BakeLight>;

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
        if (model_detail(m.model0, m.model1, m.model2) > 0.5) {
            // The secondary maps, as forward.wgsl `material_at` and `mapped_normal` blend them
            let d = textureSampleLevel(material_detail, material_sampler, sp.uv * DETAIL_TILING, 0.0);
            albedo = vec4<f32>(albedo.rgb * detail_albedo_factor(d.w, mask.b), albedo.a);
            ts = detail_blended_normal(ts, d.xyz, mask.b);
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
    if (PIPELINE == PIPELINE_HDRP && subject_maps && model_detail(m.model0, m.model1, m.model2) > 0.5) {
        let d = textureSampleLevel(material_detail, material_sampler, sp.uv * DETAIL_TILING, 0.0);
        sp.s.base_color = hdrp_detail_albedo(sp.s.base_color, d.w, mask.b);
    }
    sp.s = carried_specular(sp.s, m);
    sp.s.tangent = (a.tangent * b0 + b.tangent * hit.b1 + c.tangent * hit.b2).xyz;
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
    if (sp.object == BAKE_TEXEL) {
        // A lightmap texel gathers irradiance/π: a white Lambertian surface's NL/π
        return vec3<f32>(max(dot(sp.n, l), 0.0) * INV_PI);
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
    let flags = u32(light.features.w);
    // HDRP's box is a collimated beam through its window: no falloff with distance
    if ((flags & LIGHT_BOX) != 0u) {
        return light_projector_window(light, p);
    }
    var atten = 1.0 / max(dot(to_light, to_light), 1e-4);
    if ((flags & LIGHT_PYRAMID) != 0u) {
        atten *= light_projector_window(light, p);
    } else if (kind == 2u) {
        atten *= angle_attenuation(dot(normalize(light.direction.xyz), -l), light.params.y, light.params.z);
    }
    return atten;
}

// The lightmapper's falloff of the pipeline's punctual lights (conventions.wgsl
// `baked_distance_attenuation`); spots keep the pipeline's cone
fn baked_attenuation(light: Light, p: vec3<f32>, l: vec3<f32>) -> f32 {
    let kind = u32(light.position.w);
    if (kind == 0u) {
        return 1.0;
    }
    var atten = baked_distance_attenuation(PIPELINE == PIPELINE_BUILTIN, length(light.position.xyz - p), light.params.x);
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
        let weight = light_weight(i);
        if (weight <= 0.0) {
            continue;
        }
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
            } else if (bake_kind != 0u) {
                inc.w = baked_attenuation(light, sp.p, inc.xyz);
            }
            if (u32(light.position.w) != 0u) {
                distance = light_distance(light, sp.p) * (1.0 - 1e-4);
            }
        }
        if (inc.w <= 0.0) {
            continue;
        }
        light_min_roughness = light.params.w;
        let f = response(sp, v, inc.xyz);
        let shadow_l = soft_shadow_direction(i, light, sp.p, inc.xyz);
        if (any(f > vec3<f32>(0.0)) && !occluded(origin, shadow_l, distance)) {
            // Lights are in the pipeline's units: the model's own factor is taken back out
            let e = f * irradiance_per_intensity() * light.color.rgb * inc.w * weight;
            c += e;
            note_direction(inc.xyz, e);
        }
    }
    light_min_roughness = 4.617e-5;
    if (frame.env.y > 0.0) {
        let e = sample_env();
        let l = e.xyz;
        let f = response(sp, v, l);
        if (e.w > 0.0 && any(f > vec3<f32>(0.0)) && !occluded(origin, l, 3.4e38)) {
            let radiance = f * env_radiance(l) / e.w * power_heuristic(e.w, surface_pdf(sp.s, lobe_share(sp), sp.n, v, l));
            c += radiance;
            note_direction(l, radiance);
        }
    }
    return c;
}

// The GGX share of a point's continuations: none for a same-brdf truth's diffuse-only model,
// else specular_share — each bounce sampled from the model's own lobes (cpu.rs `lobe_share`)
fn lobe_share(sp: SurfacePoint) -> f32 {
    if (sp.object == BAKE_TEXEL) {
        return 0.0;
    }
    let subject = objects[sp.object].flags.x == 1u;
    let diffuse = select(FIXED_DIFFUSE_ONLY, SUBJECT_DIFFUSE_ONLY, subject) == 1u;
    return select(specular_share(sp.s), 0.0, TRUTH_KIND == 0u && diffuse);
}

// The light arriving at o from −d along one path: `first` is the index of the first surface vertex
// it meets (0 for a camera ray, whose vertex 0 is directly lit; 1 for a probe's, whose first surface
// already bounces the light), `mis_pdf` the density d was drawn with at o against the environment's
// sampling there (< 0: o does not sample the environment, so a miss counts whole)
fn incoming(o_in: vec3<f32>, d_in: vec3<f32>, first: u32, mis_pdf: f32) -> vec3<f32> {
    var o = o_in;
    var d = d_in;
    var throughput = vec3<f32>(1.0);
    var c = vec3<f32>(0.0);
    var last_pdf = mis_pdf;
    // settings.z: Russian roulette past the budget, up to MAX_ROULETTE_BOUNCES (spec::matrix)
    let last = select(truth.settings.x + 1u, 1024u, truth.settings.z == 1u);
    for (var bounce = first; bounce <= last; bounce++) {
        path_vertex = bounce;
        let hit = trace(o, d, 3.4e38, false);
        if (hit.triangle == 0xffffffffu) {
            if (last_pdf < 0.0) {
                // A camera ray sees the sky where the background shows it; a probe's always does
                if (!camera_path || truth.settings.y == 1u) {
                    c += throughput * env_radiance(d);
                }
            } else if (frame.env.y > 0.0) {
                c += throughput * env_radiance(d) * power_heuristic(last_pdf, env_pdf(d));
            }
            break;
        }
        let sp = surface_at(hit, d);
        if (bounce == 0u && camera_path) {
            first_roles[path_pixel] = objects[sp.object].flags.y;
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

// One path from the camera through pixel `pixel`
fn path(pixel: vec2<u32>) -> vec3<f32> {
    let size = vec2<f32>(truth.dims.xy);
    let jitter = vec2<f32>(random(), random());
    let ndc = vec2<f32>((f32(pixel.x) + jitter.x) / size.x * 2.0 - 1.0, 1.0 - (f32(pixel.y) + jitter.y) / size.y * 2.0);
    let far = frame.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    let o = frame.camera_pos.xyz;
    camera_path = true;
    path_pixel = pixel.y * truth.dims.x + pixel.x;
    return incoming(o, normalize(far.xyz / far.w - o), 0u, -1.0);
}

@compute @workgroup_size(8, 8)
fn cs_truth(@builtin(global_invocation_id) gid: vec3<u32>) {
    // settings.w: this dispatch's first row (render::truth cuts a batch into bands of rows)
    let id = vec3<u32>(gid.x, gid.y + truth.settings.w, gid.z);
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

// ---- The bake: light gathered at lightmap texels and light probes (render::truth::bake), with the
// tracer's own paths. Each light is weighed by what the bake holds of it (plan::gi): its direct light
// at the bake point itself, its bounced light at every later vertex; the sky is always baked.

// The object index a lightmap texel's own surface point carries (no scene object has it)
const BAKE_TEXEL: u32 = 0xfffffffeu;
// Per point: BAKE_STRIDE vec4 sums in `accum`
const BAKE_STRIDE: u32 = 12u;

// 0: the truth (every light whole); 1: a texel; 2: a probe
var<private> bake_kind: u32 = 0u;
// The index of the surface vertex being lit along the current path (0: the bake point's own)
var<private> path_vertex: u32 = 0u;
var<private> camera_path: bool = false;
var<private> path_pixel: u32 = 0u;
// A texel's incoming light weighted by luminance, summed by direction (xyz) and alone (w)
var<private> dominant: vec4<f32> = vec4<f32>(0.0);

// What light i gives at this vertex: 1 in the truth; in the bake its direct weight at the bake point
// itself and its bounced weight (Indirect Multiplier, or 0 when realtime) further along
fn light_weight(i: u32) -> f32 {
    if (bake_kind == 0u) {
        return 1.0;
    }
    let w = bake_lights[i].weights;
    if (path_vertex == 0u) {
        return select(w.y, w.x, bake_kind == 1u);
    }
    return w.z;
}

// The shadow ray's direction towards light i: in the bake, towards a point drawn on its baked
// shadow radius (a sphere about a point or spot light) or within its baked shadow angle (a cone
// about a directional light's direction), which softens baked shadows as Unity's lightmapper does
fn soft_shadow_direction(i: u32, light: Light, p: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    if (bake_kind == 0u || u32(light.position.w) >= LIGHT_RECT) {
        return l;
    }
    let shape = bake_lights[i].shape;
    let u = vec2<f32>(random(), random());
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = 2.0 * PI * u.y;
    let sphere = vec3<f32>(r * cos(phi), r * sin(phi), z);
    if (u32(light.position.w) == 0u) {
        if (shape.y <= 0.0) {
            return l;
        }
        // A uniform point on the disc of radius tan(angle/2) at unit distance
        let b = basis(l);
        let rr = shape.y * sqrt(u.x);
        return normalize(l + b[0] * (rr * cos(phi)) + b[1] * (rr * sin(phi)));
    }
    if (shape.x <= 0.0) {
        return l;
    }
    return normalize(light.position.xyz + sphere * shape.x - p);
}

// A texel's dominant direction: the luminance-weighted sum of where its light comes from
fn note_direction(l: vec3<f32>, c: vec3<f32>) {
    if (bake_kind == 1u && path_vertex == 0u) {
        let y = dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
        dominant += vec4<f32>(l * y, y);
    }
}

// The light at a texel (its position and normal) for one sample: its direct light, then one
// cosine-sampled continuation; irradiance/π in the pipeline's units
fn texel_sample(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    var sp: SurfacePoint;
    sp.p = p;
    sp.n = n;
    sp.ng = n;
    sp.object = BAKE_TEXEL;
    sp.s.base_color = vec3<f32>(1.0);
    path_vertex = 0u;
    var c = direct_light(sp, n);
    let l = sample_surface(sp.s, 0.0, n, n);
    let pdf = surface_pdf(sp.s, 0.0, n, n, l);
    if (pdf <= 0.0 || dot(l, n) <= 0.0) {
        return c;
    }
    let indirect = incoming(p + n * RAY_EPSILON, l, 1u, pdf);
    // The continuation's weight response/pdf is 1 for a white Lambertian surface sampled by its cosine
    c += indirect;
    let y = dot(indirect, vec3<f32>(0.2126, 0.7152, 0.0722));
    dominant += vec4<f32>(l * y, y);
    return c;
}

// The real SH basis Y_0..Y_8 in scene.wgsl's `sh_eval` order (twin: environment::sh::basis)
fn sh_basis(d: vec3<f32>) -> array<f32, 9> {
    return array<f32, 9>(
        0.282095,
        0.488603 * d.y,
        0.488603 * d.z,
        0.488603 * d.x,
        1.092548 * d.x * d.y,
        1.092548 * d.y * d.z,
        0.315392 * (3.0 * d.z * d.z - 1.0),
        1.092548 * d.x * d.z,
        0.546274 * (d.x * d.x - d.y * d.y),
    );
}

// The visibility of light i from p along a soft shadow ray (the shadow mask's texel or probe value)
fn light_visible(i: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let light = lights[i];
    let inc = light_incidence(light, p);
    var distance = 3.4e38;
    if (u32(light.position.w) != 0u) {
        distance = light_distance(light, p) * (1.0 - 1e-4);
    }
    return select(1.0, 0.0, occluded(p + n * RAY_EPSILON, soft_shadow_direction(i, light, p, inc.xyz), distance));
}

@compute @workgroup_size(64)
fn cs_bake(@builtin(global_invocation_id) id: vec3<u32>) {
    // dims: x the end of the points taken, y this dispatch's first point, z its first sample, w its samples
    let index = id.x + truth.dims.y;
    if (index >= truth.dims.x) {
        return;
    }
    main_light_color = vec3<f32>(0.0);
    if (frame.counts.y > 0u) {
        main_light_color = lights[frame.counts.y - 1u].color.rgb;
    }
    let point = bake_points[index];
    let p = point.position.xyz;
    let base = index * BAKE_STRIDE;
    var sums: array<vec4<f32>, 12>;
    for (var k = 0u; k < BAKE_STRIDE; k++) {
        sums[k] = accum[base + k];
    }
    for (var k = 0u; k < truth.dims.w; k++) {
        rng_seed(index, truth.dims.z + k);
        if (point.position.w < 0.5) {
            bake_kind = 1u;
            dominant = vec4<f32>(0.0);
            let n = normalize(point.normal.xyz);
            var c = texel_sample(p, n);
            if (any(c != c) || any(abs(c) > vec3<f32>(1e30))) {
                c = vec3<f32>(0.0);
                dominant = vec4<f32>(0.0);
            }
            sums[0] += vec4<f32>(c, 1.0);
            sums[1] += vec4<f32>(c * c, 0.0);
            sums[2] += dominant;
            var mask = vec4<f32>(0.0);
            for (var i = 0u; i < frame.counts.x; i++) {
                let channel = bake_lights[i].weights.w;
                if (channel >= 0.0) {
                    mask[u32(channel)] = light_visible(i, p, n);
                }
            }
            sums[3] += mask;
        } else {
            bake_kind = 2u;
            // Sample j of the probe's settings.w: the spherical Fibonacci point j (uniform over the
            // sphere, stratified) and the radiance arriving along it, then each light's direct
            // light as a delta at its direction (its irradiance E, projected as E·Y)
            let j = truth.dims.z + k;
            let z = 1.0 - (2.0 * f32(j) + 1.0) / f32(max(truth.settings.w, 1u));
            let r = sqrt(max(0.0, 1.0 - z * z));
            let phi = 2.0 * PI * fract(f32(j) * 0.618033988749895);
            let d = vec3<f32>(r * cos(phi), r * sin(phi), z);
            var radiance = incoming(p, d, 1u, -1.0) * (4.0 * PI);
            if (any(radiance != radiance) || any(abs(radiance) > vec3<f32>(1e30))) {
                radiance = vec3<f32>(0.0);
            }
            var y = sh_basis(d);
            for (var b = 0u; b < 9u; b++) {
                sums[b] += vec4<f32>(radiance * y[b], 0.0);
            }
            path_vertex = 0u;
            var occlusion = vec4<f32>(0.0);
            for (var i = 0u; i < frame.counts.x; i++) {
                let light = lights[i];
                let w = light_weight(i);
                let channel = bake_lights[i].weights.w;
                if (channel >= 0.0) {
                    occlusion[u32(channel)] = light_visible(i, p, vec3<f32>(0.0));
                }
                if (w <= 0.0) {
                    continue;
                }
                var inc = vec4<f32>(0.0);
                var distance = 3.4e38;
                if (u32(light.position.w) >= LIGHT_RECT) {
                    let a = area_incidence(light, p);
                    inc = a.xyz_w;
                    distance = a.distance * (1.0 - 1e-4);
                } else {
                    inc = light_incidence(light, p);
                    inc.w = baked_attenuation(light, p, inc.xyz);
                    if (u32(light.position.w) != 0u) {
                        distance = length(light.position.xyz - p) * (1.0 - 1e-4);
                    }
                }
                if (inc.w <= 0.0 || occluded(p, soft_shadow_direction(i, light, p, inc.xyz), distance)) {
                    continue;
                }
                let e = irradiance_per_intensity() * light.color.rgb * inc.w * w;
                let yl = sh_basis(inc.xyz);
                for (var b = 0u; b < 9u; b++) {
                    sums[b] += vec4<f32>(e * yl[b], 0.0);
                }
            }
            sums[9] += vec4<f32>(0.0, 0.0, 0.0, 1.0);
            sums[10] += occlusion;
        }
    }
    for (var k = 0u; k < BAKE_STRIDE; k++) {
        accum[base + k] = sums[k];
    }
}
