// The `physical` truth's one model for every surface (render::truth; twin: render::truth::physical):
// Lambert diffuse, height-correlated Smith GGX with multiple-scattering energy compensation, and
// Schlick's Fresnel from F0 = lerp(0.04, base colour, metallic). α = (1 − smoothness)². D and F are
// the shared terms of common/brdf.wgsl (d_ggx, f_schlick).

// V = 0.5/(NL·√(NV²(1 − α²) + α²) + NV·√(NL²(1 − α²) + α²)), height-correlated Smith (Heitz 2014)
fn physical_v_smith_correlated(nv: f32, nl: f32, a: f32) -> f32 {
    let a2 = a * a;
    let gv = nl * sqrt(nv * nv * (1.0 - a2) + a2);
    let gl = nv * sqrt(nl * nl * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-12);
}

// Multiple scattering (Turquin 2019): the single-scattering lobe × (1 + F0·(1/E(NV) − 1)), E the
// lobe's directional albedo with F = 1 (the FGD table's y)
fn physical_energy_compensation(f0: vec3<f32>, nv: f32, pr: f32) -> vec3<f32> {
    let e = max(fgd_lookup(nv, pr).y, 1e-4);
    return vec3<f32>(1.0) + f0 * (1.0 / e - 1.0);
}

// f·NL of the physical model
fn physical_response(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(n, l);
    let nv = dot(n, v);
    if (nl <= 0.0 || nv <= 0.0) {
        return vec3<f32>(0.0);
    }
    let h = normalize(v + l);
    let pr = 1.0 - s.smoothness;
    let a = max(pr * pr, 1e-4);
    let f0 = mix(vec3<f32>(0.04), s.base_color, s.metallic);
    let spec = f_schlick(f0, sat(dot(v, h))) * d_ggx(sat(dot(n, h)), a) * physical_v_smith_correlated(nv, nl, a)
        * physical_energy_compensation(f0, nv, pr);
    let diffuse = s.base_color * (1.0 - s.metallic) * INV_PI;
    return (diffuse + spec) * nl;
}
