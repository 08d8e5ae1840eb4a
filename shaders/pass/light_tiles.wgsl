// Joined to forward.wgsl (shading::wgsl): its bindings and the deferred lighting pass read these.
// HDRP's tiled light loop: a compute pass bins every light into the 16×16 screen tiles its
// range can reach (render::passes::deferred). The tile's depth bounds from the G-buffer, the tile frustum
// slice's world-space box, the light's sphere against it; directional lights reach every tile.

const LIGHT_TILE: u32 = 16u;
// 1: the deferred lighting pass reads the tile lists (HDRP)
override TILED_LIGHTS: u32 = 0u;

@group(3) @binding(2) var<storage, read> tile_masks: array<u32>;
@group(3) @binding(0) var tile_depth: texture_depth_2d;
@group(3) @binding(1) var<storage, read_write> tile_masks_out: array<atomic<u32>>;

var<workgroup> tile_min_depth: atomic<u32>;
var<workgroup> tile_max_depth: atomic<u32>;

fn world_at(ndc: vec3<f32>) -> vec3<f32> {
    let w = frame.inv_view_proj * vec4<f32>(ndc, 1.0);
    return w.xyz / w.w;
}

@compute @workgroup_size(16, 16)
fn cs_light_tiles(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) index: u32,
) {
    if (index == 0u) {
        atomicStore(&tile_min_depth, 0x7f7fffffu);
        atomicStore(&tile_max_depth, 0u);
    }
    workgroupBarrier();
    let size = textureDimensions(tile_depth);
    let px = group.xy * LIGHT_TILE + local.xy;
    if (px.x < size.x && px.y < size.y) {
        let d = textureLoad(tile_depth, vec2<i32>(px), 0);
        if (d < 1.0) {
            // Non-negative floats order like their bit patterns
            atomicMin(&tile_min_depth, bitcast<u32>(d));
            atomicMax(&tile_max_depth, bitcast<u32>(d));
        }
    }
    workgroupBarrier();
    let dmin = bitcast<f32>(atomicLoad(&tile_min_depth));
    let dmax = bitcast<f32>(atomicLoad(&tile_max_depth));
    if (dmin > dmax) {
        return; // only sky in this tile: nothing to light
    }
    let sizef = vec2<f32>(size);
    let lo = vec2<f32>(group.xy * LIGHT_TILE) / sizef;
    let hi = min(vec2<f32>((group.xy + 1u) * LIGHT_TILE) / sizef, vec2<f32>(1.0));
    var box_min = vec3<f32>(3.4e38);
    var box_max = vec3<f32>(-3.4e38);
    for (var k = 0u; k < 8u; k++) {
        let uv = vec2<f32>(select(lo.x, hi.x, (k & 1u) != 0u), select(lo.y, hi.y, (k & 2u) != 0u));
        let z = select(dmin, dmax, (k & 4u) != 0u);
        let q = world_at(vec3<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, z));
        box_min = min(box_min, q);
        box_max = max(box_max, q);
    }
    let words = frame.counts.z;
    let tile = group.y * frame.counts.w + group.x;
    for (var i = index; i < frame.counts.x; i += 256u) {
        let light = lights[i];
        var reaches = u32(light.position.w) == 0u;
        if (!reaches) {
            // Sphere (position, range) against the box: closest point distance ≤ range; an area
            // light's sphere holds its attenuation box (range + w/2, range + h/2, range)
            let closest = clamp(light.position.xyz, box_min, box_max);
            let d = light.position.xyz - closest;
            var radius = light.params.x;
            if (u32(light.position.w) >= LIGHT_RECT) {
                radius = length(vec3<f32>(light.params.x + light.params.y, light.params.x + light.params.z, light.params.x));
            }
            reaches = dot(d, d) <= radius * radius;
        }
        if (reaches) {
            atomicOr(&tile_masks_out[tile * words + i / 32u], 1u << (i % 32u));
        }
    }
}
