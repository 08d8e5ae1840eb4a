// Background pass: the environment seen along each pixel's view ray, drawn behind everything
// (depth 1, test less-equal). Left out of the frame plan when the scene hides the environment.

struct BackgroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
};

@vertex
fn vs_background(@builtin(vertex_index) i: u32) -> BackgroundOut {
    // One triangle covering the viewport.
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
    var out: BackgroundOut;
    out.clip = vec4<f32>(xy, 1.0, 1.0);
    out.ndc = xy;
    return out;
}

struct BackgroundFragment {
    @location(0) color: vec4<f32>,
    @location(1) role: u32,
};

@fragment
fn fs_background(in: BackgroundOut) -> BackgroundFragment {
    let far = frame.inv_view_proj * vec4<f32>(in.ndc, 1.0, 1.0);
    let dir = normalize(far.xyz / far.w - frame.camera_pos.xyz);
    var out: BackgroundFragment;
    // The sky is light given off (pipelines::terms::EMISSION); nothing occludes it.
    let sky = probe_level(dir, 0.0) * frame.env.y;
    out.color = vec4<f32>(select(emitted(sky), vec3<f32>(1.0), TERMS == TERM_OCCLUSION), 1.0);
    out.role = 0u;
    return out;
}
