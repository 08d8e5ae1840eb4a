//! HDRP's rectangle lights by linearly transformed cosines (Heitz et al. 2016), as HDRP evaluates
//! them (Lit.hlsl EvaluateBSDF_Rect, core AreaLighting.hlsl): the f64 twin of
//! shaders/common/area.wgsl, with the same names.
//!
//! The tables are our own fit (`ltc_fit`, `shadematrix fit-ltc`, embedded from
//! shaders/data/ltc.bin) in HDRP's parametrisation: 64×64, u = perceptual roughness,
//! v = √(1 − NV) (Lit.hlsl GetPreLightData's cosThetaParam), texel centres at i/63
//! (Remap01ToHalfTexelCoord), each texel M⁻¹ normalised to m22 = 1 as [m00, m02, m11, m20].
//! Unity's table data is not copied.

use glam::{DMat3, DVec2, DVec3};
use std::f64::consts::{PI, TAU};
use std::sync::OnceLock;

pub const LTC_SIZE: usize = 64;

/// M⁻¹/m22 of one texel: [m00, m02, m11, m20] (m01 = m10 = m12 = m21 = 0).
pub type LtcTexel = [f32; 4];

/// The two lobes HDRP Lit's area lights read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LtcLobe {
    /// GGX with V_SmithJointGGX, no Fresnel (its magnitude is specularFGD).
    Ggx,
    /// The renormalised Disney diffuse (its magnitude is diffuseFGD).
    DisneyDiffuse,
}

pub struct LtcTables {
    pub ggx: Vec<LtcTexel>,
    pub disney: Vec<LtcTexel>,
}

/// The file's first bytes: a name and a layout version.
const MAGIC: &[u8; 8] = b"SMLTC\x00\x00\x01";
static EMBEDDED: &[u8] = include_bytes!("../../shaders/data/ltc.bin");

impl LtcTables {
    /// The embedded tables, parsed once per process.
    pub fn get() -> &'static LtcTables {
        static TABLES: OnceLock<LtcTables> = OnceLock::new();
        TABLES.get_or_init(|| LtcTables::from_bytes(EMBEDDED).expect("shaders/data/ltc.bin is written by fit-ltc"))
    }

    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        for t in self.ggx.iter().chain(&self.disney) {
            for x in t {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        out
    }

    pub fn from_bytes(bytes: &[u8]) -> Result<LtcTables, String> {
        let n = LTC_SIZE * LTC_SIZE;
        if bytes.len() != MAGIC.len() + 2 * n * 16 || &bytes[..8] != MAGIC {
            return Err(format!("not an LTC table of 2×{LTC_SIZE}² texels ({} bytes)", bytes.len()));
        }
        let floats: Vec<f32> =
            bytes[8..].chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        let texels: Vec<LtcTexel> = floats.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
        Ok(LtcTables { ggx: texels[..n].to_vec(), disney: texels[n..].to_vec() })
    }

    pub fn table(&self, lobe: LtcLobe) -> &[LtcTexel] {
        match lobe {
            LtcLobe::Ggx => &self.ggx,
            LtcLobe::DisneyDiffuse => &self.disney,
        }
    }

    /// M⁻¹ at (NV, perceptual roughness), bilinear between texel centres as the hardware filter
    /// HDRP samples with (the same arithmetic as WGSL `ltc_sample`).
    pub fn lookup(&self, lobe: LtcLobe, clamped_nv: f64, pr: f64) -> DMat3 {
        let t = self.table(lobe);
        let max = (LTC_SIZE - 1) as f64;
        let fx = (pr.clamp(0.0, 1.0) * max).clamp(0.0, max);
        let fy = ((1.0 - clamped_nv).clamp(0.0, 1.0).sqrt() * max).clamp(0.0, max);
        let (x0, y0) = (fx.floor().min(max - 1.0), fy.floor().min(max - 1.0));
        let (tx, ty) = (fx - x0, fy - y0);
        let at = |x: f64, y: f64| t[y as usize * LTC_SIZE + x as usize].map(|v| v as f64);
        let lerp = |a: [f64; 4], b: [f64; 4], s: f64| [0, 1, 2, 3].map(|k| a[k] + (b[k] - a[k]) * s);
        let m = lerp(lerp(at(x0, y0), at(x0 + 1.0, y0), tx), lerp(at(x0, y0 + 1.0), at(x0 + 1.0, y0 + 1.0), tx), ty);
        inverse_matrix(m)
    }
}

/// M⁻¹ of `lobe` at (clampedNV, pr) from the embedded tables (hdrp_lit.wgsl `ltc_lookup`).
pub fn ltc_lookup(lobe: LtcLobe, clamped_nv: f64, pr: f64) -> DMat3 {
    LtcTables::get().lookup(lobe, clamped_nv, pr)
}

/// [[m00, 0, m02], [0, m11, 0], [m20, 0, 1]] from a texel.
pub fn inverse_matrix([m00, m02, m11, m20]: [f64; 4]) -> DMat3 {
    DMat3::from_cols(DVec3::new(m00, 0.0, m20), DVec3::new(0.0, m11, 0.0), DVec3::new(m02, 0.0, 1.0))
}

/// acos(v̂₁·v̂₂)·(v̂₁ × v̂₂)/|v̂₁ × v̂₂|: one edge of the vector form factor, before its 1/2π
/// (ComputeEdgeFactor; HDRP fits acos(x)/√(1 − x²) by a polynomial of relative error 8.7e-7)
pub fn compute_edge_factor(v1: DVec3, v2: DVec3) -> DVec3 {
    let c = v1.dot(v2).clamp(-1.0, 1.0);
    let cross = v1.cross(v2);
    let len = cross.length();
    if len <= 1e-300 {
        return DVec3::ZERO;
    }
    cross * (c.acos() / len)
}

/// (1/2π)·Σ edge factors of the unit vertices: the polygon's vector form factor, no horizon
/// clipping (PolygonFormFactor); its z is the clamped-cosine integral when the polygon is above it
pub fn polygon_form_factor(verts: &[DVec3]) -> DVec3 {
    let n = verts.len();
    let unit: Vec<DVec3> = verts.iter().map(|v| v.normalize()).collect();
    (0..n).map(|i| compute_edge_factor(unit[i], unit[(i + 1) % n])).sum::<DVec3>() / TAU
}

/// max(0, (|F|² + F.z)/(|F| + 1)): HDRP's horizon handling of a polygon by its vector form factor
/// (PolygonIrradianceFromVectorFormFactor, APPROXIMATE_POLY_LIGHT_AS_SPHERE_LIGHT, defined by default
/// in AreaLighting.hlsl). APPROXIMATION of F.z, exact when F is along the normal.
pub fn polygon_irradiance(f: DVec3) -> f64 {
    let l = f.length();
    ((l * l + f.z) / (l + 1.0)).max(0.0)
}

/// The exact clamped-cosine integral (1/π)∫max(0, z)dω of a polygon: clipped to z ≥ 0
/// (Sutherland–Hodgman against the horizon), then the form factor's z.
pub fn polygon_irradiance_clipped(verts: &[DVec3]) -> f64 {
    let mut clipped = Vec::with_capacity(verts.len() + 1);
    for i in 0..verts.len() {
        let (a, b) = (verts[i], verts[(i + 1) % verts.len()]);
        if a.z >= 0.0 {
            clipped.push(a);
        }
        if (a.z >= 0.0) != (b.z >= 0.0) {
            let t = a.z / (a.z - b.z);
            clipped.push(a + (b - a) * t);
        }
    }
    if clipped.len() < 3 {
        return 0.0;
    }
    polygon_form_factor(&clipped).z.max(0.0)
}

/// A rectangle light as the shaders read it (scene.wgsl `Light` of kind 3).
#[derive(Debug, Clone, Copy)]
pub struct RectLight {
    pub center: DVec3,
    /// The direction it shines (its normal).
    pub forward: DVec3,
    pub right: DVec3,
    pub half_size: DVec2,
    pub range: f64,
}

impl RectLight {
    /// up = forward × right: with the corners in `vertices`' order the form factor of a light
    /// facing the point is positive.
    pub fn up(&self) -> DVec3 {
        self.forward.cross(self.right)
    }

    /// The corners relative to p: −right−up, −right+up, +right+up, +right−up (HDRP's LL, UL, UR, LR).
    pub fn vertices(&self, p: DVec3) -> [DVec3; 4] {
        let (r, u) = (self.right * self.half_size.x, self.up() * self.half_size.y);
        let c = self.center - p;
        [c - r - u, c - r + u, c + r + u, c + r - u]
    }

    /// HDRP's BoxDistanceAttenuation with rangeAttenuationScale = bias = 1 (rect lights use the
    /// normalised range, HDAdditionalLightData/LightLoop): the light-space vector to the light
    /// over (range + w/2, range + h/2, range), mapped from the cube to the sphere, windowed by
    /// sat(1 − d²)²; 0 outside the box and behind the light (dot(forward, unL) ≥ FLT_EPS).
    pub fn attenuation(&self, p: DVec3) -> f64 {
        let un_l = self.center - p;
        if self.forward.dot(un_l) >= f32::EPSILON as f64 {
            return 0.0;
        }
        let q = DVec3::new(
            un_l.dot(self.right) / (self.range + self.half_size.x),
            un_l.dot(self.up()) / (self.range + self.half_size.y),
            un_l.dot(-self.forward) / self.range,
        );
        if q.abs().max_element() > 1.0 {
            return 0.0;
        }
        let q2 = q * q;
        let sq = q.dot(q) - q2.x * q2.y - q2.y * q2.z - q2.z * q2.x + q2.x * q2.y * q2.z;
        let w = (1.0 - sq * sq).clamp(0.0, 1.0);
        w * w
    }
}

/// GetOrthoBasisViewNormal: x along V's projection on the surface, z = N (its rows).
pub fn ortho_basis_view_normal(v: DVec3, n: DVec3, nv: f64) -> DMat3 {
    let t = v - n * nv;
    let x = if t.length_squared() > 1e-20 { t.normalize() } else { n.any_orthonormal_vector() };
    DMat3::from_cols(x, n.cross(x), n).transpose()
}

/// The clamped-cosine integral of a light's corners as HDRP Lit takes it through one lobe's
/// inverse transform (`inv`): PolygonIrradiance of M⁻¹·corners in the view–normal frame.
pub fn ltc_evaluate(corners: &[DVec3; 4], basis: &DMat3, inv: &DMat3) -> f64 {
    let local: Vec<DVec3> = corners.iter().map(|c| *inv * (*basis * *c)).collect();
    polygon_irradiance(polygon_form_factor(&local))
}

/// Diffuse and specular LTC values (before diffuseFGD/specularFGD, the colour and the light) of a
/// rect light at p for HDRP Lit with perceptual roughness `pr`.
pub fn hdrp_rect_ltc(light: &RectLight, p: DVec3, n: DVec3, v: DVec3, pr: f64) -> (f64, f64) {
    let nv = n.dot(v);
    let clamped_nv = nv.max(1e-4);
    let basis = ortho_basis_view_normal(v, n, nv);
    let corners = light.vertices(p);
    let d = ltc_evaluate(&corners, &basis, &ltc_lookup(LtcLobe::DisneyDiffuse, clamped_nv, pr));
    let s = ltc_evaluate(&corners, &basis, &ltc_lookup(LtcLobe::Ggx, clamped_nv, pr));
    (d, s)
}

/// ∫ f(l)·NL dω over a rectangle by a `k`×`k` midpoint rule on its area: the numerical integral the
/// LTCs approximate (f takes l and returns the cosine-weighted BRDF value).
pub fn integrate_rect(light: &RectLight, p: DVec3, k: usize, f: impl Fn(DVec3) -> f64) -> f64 {
    let (r, u) = (light.right, light.up());
    let area = 4.0 * light.half_size.x * light.half_size.y;
    let mut sum = 0.0;
    for i in 0..k {
        for j in 0..k {
            let s = ((i as f64 + 0.5) / k as f64) * 2.0 - 1.0;
            let t = ((j as f64 + 0.5) / k as f64) * 2.0 - 1.0;
            let q = light.center + r * (s * light.half_size.x) + u * (t * light.half_size.y);
            let d = q - p;
            let dist2 = d.length_squared();
            let l = d / dist2.sqrt();
            let cos_light = (-l).dot(light.forward);
            if cos_light > 0.0 {
                sum += f(l) * cos_light / dist2;
            }
        }
    }
    sum * area / (k * k) as f64
}

/// π: the clamped-cosine integral's normalisation (D₀ = z/π).
pub const COSINE_NORM: f64 = PI;

#[cfg(test)]
mod tests {
    use super::*;

    fn overhead(h: f64, w: f64) -> RectLight {
        RectLight {
            center: DVec3::new(0.0, 0.0, h),
            forward: -DVec3::Z,
            right: DVec3::X,
            half_size: DVec2::new(w, w),
            range: 10.0,
        }
    }

    #[test]
    fn a_rectangle_over_a_lambert_plane_is_its_numerical_integral() {
        // (1/π)∫cos dω of a rectangle, against a 400² midpoint rule on its area; above the
        // horizon, tilted, and cut by it.
        for (light, p) in [
            (overhead(1.0, 0.5), DVec3::ZERO),
            (overhead(0.7, 0.3), DVec3::new(0.4, -0.2, 0.0)),
            (
                RectLight {
                    center: DVec3::new(0.8, 0.1, 0.5),
                    forward: DVec3::new(-1.0, 0.0, -0.4).normalize(),
                    right: DVec3::Y,
                    half_size: DVec2::new(0.4, 0.6),
                    range: 10.0,
                },
                DVec3::ZERO,
            ),
            (
                RectLight {
                    center: DVec3::new(1.0, 0.0, 0.1),
                    forward: -DVec3::X,
                    right: DVec3::Y,
                    half_size: DVec2::new(0.5, 0.5),
                    range: 10.0,
                },
                DVec3::ZERO,
            ),
        ] {
            let exact = polygon_irradiance_clipped(&light.vertices(p));
            let numeric = integrate_rect(&light, p, 400, |l| l.z.max(0.0)) / COSINE_NORM;
            assert!((exact - numeric).abs() <= 1e-3 * numeric, "{exact} vs {numeric}");
        }
    }

    #[test]
    fn the_sphere_approximation_is_exact_only_along_the_normal() {
        let straight = overhead(1.0, 0.5).vertices(DVec3::ZERO);
        let f = polygon_form_factor(&straight);
        assert!((polygon_irradiance(f) - f.z).abs() < 1e-12);
        let tilted = overhead(0.5, 0.5).vertices(DVec3::new(0.9, 0.0, 0.0));
        let f = polygon_form_factor(&tilted);
        assert!(polygon_irradiance(f) > f.z * 1.01, "{} vs {}", polygon_irradiance(f), f.z);
    }

    #[test]
    fn the_ggx_fit_follows_the_brdf_over_a_rectangle() {
        // The fitted lobe's exact integral over a rectangle (horizon-clipped, so that HDRP's sphere
        // approximation is not measured) × the FGD magnitude, against the numerical integral of
        // the GGX lobe, on and off the specular peak: the fit's own error (measured ≤ 4.3%).
        for (px, vx) in [(0.3, -0.5), (-0.3, -0.5), (0.0, 0.0), (0.0, -0.2)] {
            let light = overhead(1.0, 0.4);
            let p = DVec3::new(px, 0.0, 0.0);
            let v = DVec3::new(vx, 0.0, 0.8).normalize();
            for pr in [0.3, 0.6, 0.9] {
                let a: f64 = pr * pr;
                let lobe = |l: DVec3| {
                    let h = (v + l).normalize();
                    let a2 = a * a;
                    let s = (h.z * a2 - h.z) * h.z + 1.0;
                    a2 / (PI * s * s) * crate::shading::fgd::v_smith_joint_ggx(l.z, v.z, a) * l.z.max(0.0)
                };
                let numeric = integrate_rect(&light, p, 300, lobe);
                let fgd = crate::shading::fgd::FgdTable::get().lookup(v.z, pr).y;
                let basis = ortho_basis_view_normal(v, DVec3::Z, v.z);
                let inv = LtcTables::get().lookup(LtcLobe::Ggx, v.z, pr);
                let local: Vec<DVec3> = light.vertices(p).iter().map(|c| inv * (basis * *c)).collect();
                let ltc = polygon_irradiance_clipped(&local) * fgd;
                let rel = (ltc - numeric).abs() / numeric;
                assert!(rel < 0.05, "p.x {px}, v.x {vx}, pr {pr}: LTC {ltc} vs {numeric} (rel {rel})");
            }
        }
    }
}
