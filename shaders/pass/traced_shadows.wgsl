// Ray-traced visibility, the approximation study's `visibility` (render::passes::traced_shadows): from
// each pixel of the depth prepass, a shadow ray towards every light through the cell's BVH
// (rays.wgsl); bit i of the pixel's mask is set when light i is occluded. Screen-space, as HDRP's
// ray-traced shadows trace from the depth buffer into a mask the lighting reads; the forward pass
// (exact.wgsl `light_visibility`) loads it instead of sampling shadow maps. Composed after math,
// conventions, BRDF terms, scene.wgsl (group 0: the frame and its lights) and rays.wgsl.

@group(1) @binding(0) var traced_depth: texture_depth_2d;
// The prepass's shading normals, n·0.5 + 0.5
@group(1) @binding(1) var traced_normal: texture_2d<f32>;
// [0]: the frame's width; then one mask per pixel, row-major
@group(1) @binding(2) var<storage, read_write> traced_mask_out: array<u32>;

// The ray leaves the reconstructed surface along its normal by this share of the distance to the
// camera: depth reconstruction error grows with distance, and a ray that starts below the surface
// would shadow it.
const TRACED_OFFSET: f32 = 1e-3;

@compute @workgroup_size(8, 8)
fn cs_traced_shadows(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(traced_depth);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    if (id.x == 0u && id.y == 0u) {
        traced_mask_out[0] = size.x;
    }
    let depth = textureLoad(traced_depth, id.xy, 0);
    var mask = 0u;
    if (depth < 1.0) {
        let ndc = vec2<f32>((f32(id.x) + 0.5) / f32(size.x) * 2.0 - 1.0, 1.0 - (f32(id.y) + 0.5) / f32(size.y) * 2.0);
        let h = frame.inv_view_proj * vec4<f32>(ndc, depth, 1.0);
        let p = h.xyz / h.w;
        let n = safe_normalize(textureLoad(traced_normal, id.xy, 0).xyz * 2.0 - 1.0, 1e-30);
        let origin = p + n * (TRACED_OFFSET * max(1.0, length(frame.camera_pos.xyz - p)));
        for (var i = 0u; i < min(frame.counts.x, 32u); i++) {
            let light = lights[i];
            let inc = light_incidence(light, p);
            if (inc.w <= 0.0 || dot(n, inc.xyz) <= 0.0) {
                continue;
            }
            var distance = 3.4e38;
            if (u32(light.position.w) != 0u) {
                distance = light_distance(light, origin) * (1.0 - 1e-4);
            }
            if (occluded(origin, inc.xyz, distance)) {
                mask |= 1u << i;
            }
        }
    }
    traced_mask_out[1u + id.y * size.x + id.x] = mask;
}
