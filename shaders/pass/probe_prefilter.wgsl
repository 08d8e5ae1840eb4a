// Reflection-probe prefilter on the GPU (render::passes::probes); twin: environment::prefilter,
// the same steps in the same order. A captured cube (six 90° faces) is resampled into an
// equirectangular source, halved twice, and each of Unity's seven levels (mip = pr'·6,
// pr' = pr(1.7 − 0.7pr)) is the GGX lobe of its α convolved over the source width the level needs.

// Composed after shaders/common/math.wgsl (PI, cube_face).
const TAU: f32 = 6.28318530717959;

struct PrefilterParams {
    // x: output width, y: output height, z: unused, w: mode (0 faces → equirect, 1 halve, 2 convolve, 3 copy)
    dims: vec4<u32>,
    // x: GGX α of the level; y: 1 / sub-samples per side (cube → equirect); z: source width; w: source height
    level: vec4<f32>,
    // the six faces' view-projections from the probe's position (render::passes::probes::face_view_proj)
    faces: array<mat4x4<f32>, 6>,
    probe_position: vec4<f32>,
};

@group(0) @binding(0) var<uniform> params: PrefilterParams;
@group(0) @binding(1) var cube_faces: texture_2d_array<f32>;
@group(0) @binding(2) var source: texture_2d<f32>;
// Nearest: the faces are 32-bit float, which need not be filterable
@group(0) @binding(3) var face_sampler: sampler;
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;
// The source's texel directions (xyz) and solid angles (w), row-major (twin: TexelTable)
@group(0) @binding(5) var<storage, read> source_table: array<vec4<f32>>;

// Equirectangular texel centre → direction (u: azimuth from −Z towards +X, v: polar angle from +Y);
// twin: environment::uv_to_dir
fn uv_to_dir(u: f32, v: f32) -> vec3<f32> {
    let phi = (u - 0.5) * TAU;
    let theta = v * PI;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// The captured radiance along d: the face of d's major axis, at d's projection into it.
fn cube_radiance(d: vec3<f32>) -> vec3<f32> {
    let face = cube_face(d);
    let clip = params.faces[face] * vec4<f32>(params.probe_position.xyz + d, 1.0);
    let ndc = clip.xy / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    return textureSampleLevel(cube_faces, face_sampler, uv, face, 0.0).rgb;
}

@compute @workgroup_size(8, 8)
fn cs_prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = params.dims.x;
    let h = params.dims.y;
    if (id.x >= w || id.y >= h) {
        return;
    }
    var c = vec3<f32>(0.0);
    switch params.dims.w {
        // Cube → equirect: sub-samples weighted by sin θ (twin: EquirectImage::sample)
        case 0u: {
            let step = params.level.y;
            var wsum = 0.0;
            for (var sy = step * 0.5; sy < 1.0; sy += step) {
                for (var sx = step * 0.5; sx < 1.0; sx += step) {
                    let u = (f32(id.x) + sx) / f32(w);
                    let v = (f32(id.y) + sy) / f32(h);
                    let wt = sin(v * PI);
                    c += cube_radiance(uv_to_dir(u, v)) * wt;
                    wsum += wt;
                }
            }
            c /= max(wsum, 1e-12);
        }
        // 2×2 halving weighted by solid angle ∝ sin θ (twin: EquirectImage::half)
        case 1u: {
            let sh = f32(h * 2u);
            var wsum = 0.0;
            for (var dy = 0u; dy < 2u; dy++) {
                let y = id.y * 2u + dy;
                let wt = sin((f32(y) + 0.5) / sh * PI);
                for (var dx = 0u; dx < 2u; dx++) {
                    c += textureLoad(source, vec2<u32>(id.x * 2u + dx, y), 0).rgb * wt;
                    wsum += wt;
                }
            }
            c /= max(wsum, 1e-12);
        }
        // ∫ L·D(h)·(R·ω) dω / ∫ D(h)·(R·ω) dω with N = V = R (twin: TexelTable::convolve)
        case 2u: {
            let r = uv_to_dir((f32(id.x) + 0.5) / f32(w), (f32(id.y) + 0.5) / f32(h));
            let a2 = params.level.x * params.level.x;
            let sw = u32(params.level.z);
            let count = sw * u32(params.level.w);
            var wsum = 0.0;
            for (var i = 0u; i < count; i++) {
                let t = source_table[i];
                let nl = dot(r, t.xyz);
                if (nl <= 0.0) {
                    continue;
                }
                // N·H² = (1 + N·L)/2 when N = V
                let k = (1.0 + nl) * 0.5 * (a2 - 1.0) + 1.0;
                let wt = a2 / (PI * k * k) * nl * t.w;
                c += textureLoad(source, vec2<u32>(i % sw, i / sw), 0).rgb * wt;
                wsum += wt;
            }
            c /= max(wsum, 1e-30);
        }
        // Copy (the mirror levels)
        default: {
            c = textureLoad(source, id.xy, 0).rgb;
        }
    }
    textureStore(output, id.xy, vec4<f32>(c, 1.0));
}
