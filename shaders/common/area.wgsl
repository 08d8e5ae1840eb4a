// Area lights by linearly transformed cosines (Heitz et al. 2016) as HDRP evaluates them (Lit.hlsl
// EvaluateBSDF_Rect, core AreaLighting.hlsl); twin: shading::ltc, with the same names. The LTC
// tables (our own fit, shading::ltc_fit) are rows LTC_GGX_ROW and LTC_DISNEY_ROW on of the FGD
// texture (render::luts).

const LTC_GGX_ROW: i32 = 64;
const LTC_DISNEY_ROW: i32 = 128;

// M⁻¹ = [[m00, 0, m02], [0, m11, 0], [m20, 0, 1]] at u = pr, v = √(1 − NV), bilinear between texel
// centres i/63 (HDRP's Remap01ToHalfTexelCoord and hardware filter)
fn ltc_sample(lut: texture_2d<f32>, row: i32, clamped_nv: f32, pr: f32) -> mat3x3<f32> {
    let fx = clamp(clamp(pr, 0.0, 1.0) * 63.0, 0.0, 63.0);
    let fy = clamp(sqrt(clamp(1.0 - clamped_nv, 0.0, 1.0)) * 63.0, 0.0, 63.0);
    let x0 = min(floor(fx), 62.0);
    let y0 = min(floor(fy), 62.0);
    let tx = fx - x0;
    let ty = fy - y0;
    let i = vec2<i32>(i32(x0), i32(y0) + row);
    let a = mix(textureLoad(lut, i, 0), textureLoad(lut, i + vec2<i32>(1, 0), 0), tx);
    let b = mix(textureLoad(lut, i + vec2<i32>(0, 1), 0), textureLoad(lut, i + vec2<i32>(1, 1), 0), tx);
    let m = mix(a, b, ty);
    return mat3x3<f32>(vec3<f32>(m.x, 0.0, m.w), vec3<f32>(0.0, m.z, 0.0), vec3<f32>(m.y, 0.0, 1.0));
}

// acos(v₁·v₂)·(v₁ × v₂)/|v₁ × v₂| with HDRP's polynomial for acos(x)/√(1 − x²) (ComputeEdgeFactor)
fn compute_edge_factor(v1: vec3<f32>, v2: vec3<f32>) -> vec3<f32> {
    let v1ov2 = dot(v1, v2);
    let v1xv2 = cross(v1, v2);
    let sq_len = sat(1.0 - v1ov2 * v1ov2);
    let rcp_len = inverseSqrt(max(1.175494351e-38, sq_len));
    let x = abs(v1ov2);
    var y = HALF_PI + x * (-0.99991 + x * (0.783393 + x * (-0.649178 + x * (0.510589 + x * (-0.326137 + x * (0.137528 + x * -0.0270813))))));
    if (v1ov2 < 0.0) {
        y = rcp_len * PI - y;
    }
    return v1xv2 * y;
}

// (1/2π)·Σ edge factors of the unit corners: the vector form factor, no horizon clipping (PolygonFormFactor)
fn polygon_form_factor(q: array<vec3<f32>, 4>) -> vec3<f32> {
    let l0 = normalize(q[0]);
    let l1 = normalize(q[1]);
    let l2 = normalize(q[2]);
    let l3 = normalize(q[3]);
    let f = compute_edge_factor(l0, l1) + compute_edge_factor(l1, l2) + compute_edge_factor(l2, l3) + compute_edge_factor(l3, l0);
    return f * (0.5 * INV_PI);
}

// max(0, (|F|² + F.z)/(|F| + 1)): HDRP's horizon by the vector form factor (PolygonIrradianceFromVectorFormFactor,
// APPROXIMATE_POLY_LIGHT_AS_SPHERE_LIGHT). APPROXIMATION of F.z, exact when F is along the normal
fn polygon_irradiance(f: vec3<f32>) -> f32 {
    let l = length(f);
    return max(0.0, (l * l + f.z) / (l + 1.0));
}

// The exact (1/π)∫max(0, z)dω of a quad: clipped to z ≥ 0 (Sutherland–Hodgman), then the form factor's z
fn polygon_irradiance_clipped(q: array<vec3<f32>, 4>) -> f32 {
    var out: array<vec3<f32>, 5>;
    var n = 0u;
    for (var i = 0u; i < 4u; i++) {
        let a = q[i];
        let b = q[(i + 1u) % 4u];
        if (a.z >= 0.0) {
            out[n] = a;
            n++;
        }
        if ((a.z >= 0.0) != (b.z >= 0.0)) {
            out[n] = a + (b - a) * (a.z / (a.z - b.z));
            n++;
        }
    }
    if (n < 3u) {
        return 0.0;
    }
    var f = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let j = select(i + 1u, 0u, i + 1u == n);
        f += compute_edge_factor(normalize(out[i]), normalize(out[j]));
    }
    return max(0.0, f.z * (0.5 * INV_PI));
}

// GetOrthoBasisViewNormal as rows: x along V's projection on the surface, z = N
fn ortho_basis_view_normal(v: vec3<f32>, n: vec3<f32>, nv: f32) -> mat3x3<f32> {
    let t = v - n * nv;
    var x = vec3<f32>(0.0);
    if (dot(t, t) > 1e-12) {
        x = normalize(t);
    } else {
        // V along N: any tangent (the lobe is isotropic there)
        x = normalize(select(vec3<f32>(0.0, -n.z, n.y), vec3<f32>(n.z, 0.0, -n.x), abs(n.x) < abs(n.y)));
    }
    return transpose(mat3x3<f32>(x, cross(n, x), n));
}

// The corners in a frame (rows of `m`) then through M⁻¹ (`inv`)
fn ltc_transform(q: array<vec3<f32>, 4>, m: mat3x3<f32>) -> array<vec3<f32>, 4> {
    return array<vec3<f32>, 4>(m * q[0], m * q[1], m * q[2], m * q[3]);
}
