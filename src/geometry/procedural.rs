//! Procedural meshes for the four compositions (spec/scenes.md). Normals are analytic: from the
//! parametric surface (spheres, lathes) or from the height field's gradient (medusa, spikes).

use glam::DVec3;
use std::f64::consts::{PI, TAU};
use std::path::Path;

use super::mesh::Mesh;
use crate::declarations::scene::MeshSpec;
use crate::error::{Error, InputError};

/// Golden angle of the sunflower lattice (scenes.md: φ = 2.39996 rad).
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// Generate (or load) a mesh in object space. `base_dir` resolves glTF paths; `origin` names the scene.
pub fn build(spec: &MeshSpec, base_dir: Option<&Path>, origin: &str, key: &str) -> Result<Mesh, Error> {
    let resolve = |path: &str| -> Result<std::path::PathBuf, Error> {
        match base_dir {
            Some(d) => Ok(d.join(path)),
            None => Err(InputError::at_key(
                origin,
                format!("{key}.path"),
                format!("glTF path `{path}` cannot be resolved: the scene is embedded; load the scene from a file"),
            )
            .into()),
        }
    };
    Ok(match spec {
        MeshSpec::UvSphere { radius, rings, segments } => uv_sphere(*radius, *rings, *segments),
        MeshSpec::Box { size } => cuboid(DVec3::from(*size)),
        MeshSpec::Plane { size, subdivisions } => plane(size[0], size[1], *subdivisions),
        MeshSpec::Lathe { profile, segments } => lathe(profile, *segments),
        MeshSpec::KnobShell {
            center_height,
            outer_radius,
            inner_radius,
            window_half_angle_deg,
            window_azimuth_deg,
            rings,
            segments,
        } => knob_shell(
            *center_height,
            *outer_radius,
            *inner_radius,
            window_half_angle_deg.to_radians(),
            window_azimuth_deg.to_radians(),
            *rings,
            *segments,
        ),
        MeshSpec::Cyclorama { width, depth, height, bend_radius, segments } => {
            cyclorama(*width, *depth, *height, *bend_radius, *segments)
        }
        MeshSpec::Spikes { radius, count, bump_radius, bump_height, rings, segments } => {
            let field = SpikesField::new(*radius, *count, *bump_radius, *bump_height);
            height_disc(*radius, *rings, *segments, |x, z| field.eval(x, z))
        }
        MeshSpec::Medusa { radius, amplitude, k, n, m, rings, segments } => {
            let field = MedusaField { radius: *radius, amplitude: *amplitude, k: *k, n: *n as f64, m: *m };
            height_disc(*radius, *rings, *segments, |x, z| field.eval(x, z))
        }
        MeshSpec::Gltf { path, material } => super::gltf_io::load(&resolve(path)?, *material)?,
        MeshSpec::GltfPrimitive { path, mesh, primitive } => {
            super::gltf_io::load_primitive(&resolve(path)?, *mesh, *primitive)?
        }
    })
}

/// Every object's mesh of a scene in object space, in object order (generated in parallel).
pub fn build_scene(scene: &crate::declarations::scene::Scene) -> Result<Vec<Mesh>, Error> {
    build_scene_meshes(scene, true)
}

/// Every object's shape (positions and normals as `build_scene` gives them) for what reads only
/// where the objects are, their bounds and centres (`shadematrix list`): without the tangent
/// frames and texture coordinates their materials ask for, which on a dense mesh cost more than
/// the mesh itself.
pub fn build_scene_shapes(scene: &crate::declarations::scene::Scene) -> Result<Vec<Mesh>, Error> {
    build_scene_meshes(scene, false)
}

fn build_scene_meshes(scene: &crate::declarations::scene::Scene, materials: bool) -> Result<Vec<Mesh>, Error> {
    use rayon::prelude::*;
    // A glTF scene's primitives: each file read once, not once per object.
    let mut files: std::collections::HashMap<&str, std::collections::HashMap<(usize, usize), Mesh>> =
        std::collections::HashMap::new();
    for o in &scene.objects {
        if let (MeshSpec::GltfPrimitive { path, .. }, Some(dir)) = (&o.mesh, &scene.base_dir) {
            if !files.contains_key(path.as_str()) {
                files.insert(path, super::gltf_io::load_primitives(&dir.join(path))?);
            }
        }
    }
    scene
        .objects
        .par_iter()
        .enumerate()
        .map(|(i, o)| {
            let key = format!("objects[{i}].mesh");
            let read = match &o.mesh {
                MeshSpec::GltfPrimitive { path, mesh, primitive } => {
                    files.get(path.as_str()).and_then(|f| f.get(&(*mesh, *primitive))).cloned()
                }
                _ => None,
            };
            let mut mesh = match read {
                Some(m) => m,
                None => build(&o.mesh, scene.base_dir.as_deref(), &scene.origin, &key)?,
            };
            if materials {
                with_material_uvs(o, &mut mesh);
            }
            Ok(mesh)
        })
        .collect()
}

/// What an object's material asks of its mesh: the subject may wear a textured preset, a fixed
/// object its own maps, and a normal map needs a tangent frame, made from the mesh's own UVs
/// before the material's tiling and offset move them.
fn with_material_uvs(o: &crate::declarations::scene::Object, mesh: &mut Mesh) {
    let material = o.material.as_ref();
    if o.role == crate::declarations::scene::Role::Subject || material.is_some_and(|m| m.has_maps()) {
        mesh.ensure_tangents();
    }
    if let Some(m) = material.filter(|m| m.map_tiling != [1.0; 2] || m.map_offset != [0.0; 2]) {
        for v in &mut mesh.vertices {
            v.uv = [0, 1].map(|k| (v.uv[k] as f64 * m.map_tiling[k] + m.map_offset[k]) as f32);
        }
    }
}

/// The LOD levels after the first of every object that has them, in scene order: (object index,
/// level, mesh). The renderer draws them after the scene's own objects, in this order.
pub fn lod_meshes(scene: &crate::declarations::scene::Scene) -> Result<Vec<(usize, usize, Mesh)>, Error> {
    let mut out = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        let Some(lod) = &o.lod else { continue };
        for (j, spec) in lod.meshes.iter().enumerate() {
            let key = format!("objects[{i}].lod.meshes[{j}]");
            let mut mesh = build(spec, scene.base_dir.as_deref(), &scene.origin, &key)?;
            with_material_uvs(o, &mut mesh);
            out.push((i, j + 1, mesh));
        }
    }
    Ok(out)
}

pub fn uv_sphere(radius: f64, rings: u32, segments: u32) -> Mesh {
    Mesh::grid(rings, segments, |u, v| {
        let (theta, phi) = (v * PI, u * TAU);
        let n = DVec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
        (n * radius, n)
    })
}

/// Axis-aligned box centred at the origin, flat faces.
pub fn cuboid(size: DVec3) -> Mesh {
    let h = size * 0.5;
    let mut mesh = Mesh::default();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut n = DVec3::ZERO;
            n[axis] = sign;
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            mesh.append(Mesh::grid(1, 1, |u, v| {
                let mut p = DVec3::ZERO;
                p[axis] = sign * h[axis];
                p[a] = (u * 2.0 - 1.0) * h[a];
                p[b] = (v * 2.0 - 1.0) * h[b];
                (p, n)
            }));
        }
    }
    mesh
}

/// XZ plane, normal +Y; UVs in metres so checkerboards have a physical size.
pub fn plane(size_x: f64, size_z: f64, subdivisions: u32) -> Mesh {
    let mut m = Mesh::grid(subdivisions, subdivisions, |u, v| {
        (DVec3::new((u - 0.5) * size_x, 0.0, (v - 0.5) * size_z), DVec3::Y)
    });
    for vert in &mut m.vertices {
        vert.uv = [vert.position[0], vert.position[2]];
    }
    m
}

/// Profile normals: each segment's own 2-D normal (dh, −dr), averaged with its neighbour's where
/// the profile turns by less than 30° (smooth), kept apart where it turns more (a crease).
pub fn lathe(profile: &[[f64; 2]], segments: u32) -> Mesh {
    let seg_normal = |i: usize| {
        let (a, b) = (profile[i], profile[i + 1]);
        let (dr, dh) = (b[0] - a[0], b[1] - a[1]);
        let len = (dr * dr + dh * dh).sqrt().max(1e-12);
        [dh / len, -dr / len]
    };
    let smooth = |n0: [f64; 2], n1: [f64; 2]| {
        if n0[0] * n1[0] + n0[1] * n1[1] > 30f64.to_radians().cos() {
            let s = [n0[0] + n1[0], n0[1] + n1[1]];
            let l = (s[0] * s[0] + s[1] * s[1]).sqrt();
            [s[0] / l, s[1] / l]
        } else {
            n0
        }
    };
    let mut mesh = Mesh::default();
    let total: f64 =
        profile.windows(2).map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt()).sum();
    let mut travelled = 0.0;
    for i in 0..profile.len() - 1 {
        let own = seg_normal(i);
        let n_start = if i > 0 { smooth(own, seg_normal(i - 1)) } else { own };
        let n_end = if i + 2 < profile.len() { smooth(own, seg_normal(i + 1)) } else { own };
        let (a, b) = (profile[i], profile[i + 1]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if len < 1e-12 {
            continue;
        }
        let v0 = travelled / total.max(1e-12);
        travelled += len;
        let v1 = travelled / total.max(1e-12);
        let mut strip = Mesh::grid(1, segments, |u, t| {
            let phi = u * TAU;
            let (r, h) = (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t);
            let n2 = if t < 0.5 { n_start } else { n_end };
            let (c, s) = (phi.cos(), -phi.sin());
            (DVec3::new(r * c, h, r * s), DVec3::new(n2[0] * c, n2[1], n2[0] * s))
        });
        for vert in &mut strip.vertices {
            vert.uv[1] = (v0 + (v1 - v0) * vert.uv[1] as f64) as f32;
        }
        mesh.append(strip);
    }
    mesh
}

/// A sphere shell (outer and inner surfaces) with a circular window of half-angle `window` around
/// the horizontal axis at `azimuth`, and the rim band joining the two radii at the window's edge.
pub fn knob_shell(
    center_height: f64,
    outer: f64,
    inner: f64,
    window: f64,
    azimuth: f64,
    rings: u32,
    segments: u32,
) -> Mesh {
    let c = DVec3::new(0.0, center_height, 0.0);
    let w = DVec3::new(azimuth.sin(), 0.0, azimuth.cos());
    let b1 = DVec3::Y;
    let b2 = w.cross(b1);
    let dir = |theta: f64, phi: f64| w * theta.cos() + (b1 * phi.cos() + b2 * phi.sin()) * theta.sin();
    let e_theta = |theta: f64, phi: f64| -w * theta.sin() + (b1 * phi.cos() + b2 * phi.sin()) * theta.cos();
    let theta_of = |v: f64| window + (PI - window) * v;
    let mut mesh = Mesh::grid(rings, segments, |u, v| {
        let d = dir(theta_of(v), u * TAU);
        (c + d * outer, d)
    });
    mesh.append(Mesh::grid(rings, segments, |u, v| {
        let d = dir(theta_of(v), u * TAU);
        (c + d * inner, -d)
    }));
    mesh.append(Mesh::grid(2, segments, |u, t| {
        let phi = u * TAU;
        let r = outer + (inner - outer) * t;
        (c + dir(window, phi) * r, -e_theta(window, phi))
    }));
    mesh
}

/// Floor from z = +depth/2 back to a quarter-circle bend rising into a wall of `height`.
pub fn cyclorama(width: f64, depth: f64, height: f64, bend: f64, segments: u32) -> Mesh {
    let z_bend = -depth / 2.0 + bend;
    let floor_len = depth - bend;
    let arc_len = bend * PI / 2.0;
    let wall_len = height - bend;
    let total = floor_len + arc_len + wall_len;
    // Point and normal at arc length s along the profile, in the (z, y) plane.
    let profile = move |s: f64| -> (f64, f64, f64, f64) {
        if s <= floor_len {
            (depth / 2.0 - s, 0.0, 0.0, 1.0)
        } else if s <= floor_len + arc_len {
            let a = (s - floor_len) / bend;
            (z_bend - bend * a.sin(), bend - bend * a.cos(), a.sin(), a.cos())
        } else {
            (z_bend - bend, bend + (s - floor_len - arc_len), 1.0, 0.0)
        }
    };
    let mut m = Mesh::grid(segments, 1, |u, v| {
        let (z, y, nz, ny) = profile(v * total);
        (DVec3::new((u - 0.5) * width, y, z), DVec3::new(0.0, ny, nz))
    });
    for vert in &mut m.vertices {
        vert.uv = [vert.position[0], (vert.uv[1] as f64 * total) as f32];
    }
    m
}

/// A height field y = h(x, z) over a disc of `radius` in the XZ plane (the spec's base plane
/// "z = 0" is y = 0 here, Y being up). `h` returns (height, ∂h/∂x, ∂h/∂z).
pub fn height_disc(radius: f64, rings: u32, segments: u32, h: impl Fn(f64, f64) -> (f64, f64, f64)) -> Mesh {
    let mut m = Mesh::grid(rings, segments, |u, v| {
        let (r, phi) = (v * radius, u * TAU);
        let (x, z) = (r * phi.cos(), -r * phi.sin());
        let (y, dx, dz) = h(x, z);
        (DVec3::new(x, y, z), DVec3::new(-dx, 1.0, -dz))
    });
    for vert in &mut m.vertices {
        vert.uv = [
            (vert.position[0] as f64 / radius * 0.5 + 0.5) as f32,
            (vert.position[2] as f64 / radius * 0.5 + 0.5) as f32,
        ];
    }
    m
}

/// Bumps h(d) = H·cos²(πd/2ρ) for d < ρ on a sunflower lattice; the surface is the max over bumps.
pub struct SpikesField {
    centres: Vec<(f64, f64)>,
    rho: f64,
    height: f64,
}

impl SpikesField {
    pub fn new(radius: f64, count: u32, rho: f64, height: f64) -> Self {
        let centres = (0..count)
            .map(|i| {
                let r = radius * 0.9 * ((i as f64 + 0.5) / count as f64).sqrt();
                let a = i as f64 * GOLDEN_ANGLE;
                (r * a.cos(), r * a.sin())
            })
            .collect();
        Self { centres, rho, height }
    }

    pub fn eval(&self, x: f64, z: f64) -> (f64, f64, f64) {
        let mut best = (0.0, 0.0, 0.0);
        for &(cx, cz) in &self.centres {
            let (dx, dz) = (x - cx, z - cz);
            let d = (dx * dx + dz * dz).sqrt();
            if d >= self.rho {
                continue;
            }
            let a = PI * d / (2.0 * self.rho);
            let h = self.height * a.cos().powi(2);
            if h > best.0 {
                // dh/dd = −H·(π/2ρ)·sin(πd/ρ)
                let dh = -self.height * PI / (2.0 * self.rho) * (2.0 * a).sin();
                let (gx, gz) = if d > 1e-12 { (dh * dx / d, dh * dz / d) } else { (0.0, 0.0) };
                best = (h, gx, gz);
            }
        }
        best
    }
}

/// h(r, φ) = A·sin²(πr/R)·sin(2πkr/R)·(1 + m·cos nφ) (scenes.md, medusa).
pub struct MedusaField {
    pub radius: f64,
    pub amplitude: f64,
    pub k: f64,
    pub n: f64,
    pub m: f64,
}

impl MedusaField {
    pub fn eval(&self, x: f64, z: f64) -> (f64, f64, f64) {
        let r = (x * x + z * z).sqrt();
        let phi = z.atan2(x);
        let (a, rr) = (self.amplitude, self.radius);
        let s1 = (PI * r / rr).sin();
        let c1 = (PI * r / rr).cos();
        let s2 = (TAU * self.k * r / rr).sin();
        let c2 = (TAU * self.k * r / rr).cos();
        let ang = 1.0 + self.m * (self.n * phi).cos();
        let h = a * s1 * s1 * s2 * ang;
        let dh_dr = a * ang * (2.0 * s1 * c1 * (PI / rr) * s2 + s1 * s1 * c2 * (TAU * self.k / rr));
        let dh_dphi_over_r =
            if r > 1e-12 { a * s1 * s1 * s2 * (-self.m * self.n * (self.n * phi).sin()) / r } else { 0.0 };
        let (cp, sp) = (phi.cos(), phi.sin());
        (h, dh_dr * cp - dh_dphi_over_r * sp, dh_dr * sp + dh_dphi_over_r * cp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_are_the_scene_meshes_where_they_stand() {
        // What `list` places lights and LOD groups by: the same positions, normals and triangles
        // as the meshes the renderer draws, on compositions whose materials ask for tangents and
        // tiled maps (the subject's, and composite's mapped fixed objects).
        for name in ["default", "mitsuba", "composite"] {
            let scene = crate::declarations::scene::Scene::load(name, None, "t", "k").unwrap();
            let (shapes, meshes) = (build_scene_shapes(&scene).unwrap(), build_scene(&scene).unwrap());
            assert_eq!(shapes.len(), meshes.len());
            let mut dressed = 0;
            for (shape, mesh) in shapes.iter().zip(&meshes) {
                assert_eq!(shape.indices, mesh.indices, "{name}");
                let at = |m: &Mesh| m.vertices.iter().map(|v| (v.position, v.normal)).collect::<Vec<_>>();
                assert_eq!(at(shape), at(mesh), "{name}");
                assert_eq!(shape.bounds(), mesh.bounds());
                dressed +=
                    shape.vertices.iter().zip(&mesh.vertices).any(|(a, b)| a.tangent != b.tangent || a.uv != b.uv)
                        as usize;
            }
            assert!(dressed > 0, "{name}: no mesh the materials change");
        }
    }

    fn check_gradient(f: impl Fn(f64, f64) -> (f64, f64, f64), points: &[(f64, f64)]) {
        let e = 1e-7;
        for &(x, z) in points {
            let (_, gx, gz) = f(x, z);
            let nx = (f(x + e, z).0 - f(x - e, z).0) / (2.0 * e);
            let nz = (f(x, z + e).0 - f(x, z - e).0) / (2.0 * e);
            assert!((gx - nx).abs() < 1e-4 * (1.0 + nx.abs()), "∂h/∂x at ({x},{z}): {gx} vs {nx}");
            assert!((gz - nz).abs() < 1e-4 * (1.0 + nz.abs()), "∂h/∂z at ({x},{z}): {gz} vs {nz}");
        }
    }

    const POINTS: [(f64, f64); 5] = [(0.013, 0.021), (-0.05, 0.031), (0.071, -0.002), (-0.02, -0.066), (0.004, 0.09)];

    #[test]
    fn medusa_gradient_is_analytic_derivative() {
        let f = MedusaField { radius: 0.1, amplitude: 0.008, k: 4.0, n: 7.0, m: 0.5 };
        check_gradient(|x, z| f.eval(x, z), &POINTS);
    }

    #[test]
    fn spikes_gradient_and_tilt() {
        let f = SpikesField::new(0.1, 100, 0.012, 0.021);
        check_gradient(|x, z| f.eval(x, z), &POINTS);
        // scenes.md: steepest tilt atan(Hπ/2ρ) ≈ 70° for H/ρ = 1.75.
        let tilt = (0.021 * PI / (2.0 * 0.012)).atan().to_degrees();
        assert!((tilt - 70.0).abs() < 1.0, "{tilt}");
    }

    #[test]
    fn sphere_normals_are_radial_and_outward() {
        let m = uv_sphere(2.0, 8, 16);
        for v in &m.vertices {
            let p = DVec3::from(v.position.map(f64::from));
            let n = DVec3::from(v.normal.map(f64::from));
            assert!((p.length() - 2.0).abs() < 1e-5);
            if p.length() > 0.0 && n.length() > 0.5 {
                assert!(p.normalize().dot(n) > 0.999);
            }
        }
    }

    #[test]
    fn lathe_of_a_cylinder_has_outward_normals() {
        let m = lathe(&[[1.0, 0.0], [1.0, 1.0]], 16);
        for v in &m.vertices {
            let radial = DVec3::new(v.position[0] as f64, 0.0, v.position[2] as f64).normalize();
            assert!(radial.dot(DVec3::from(v.normal.map(f64::from))) > 0.999);
        }
    }

    #[test]
    fn knob_shell_has_a_window_towards_its_azimuth() {
        let m = knob_shell(1.0, 0.875, 0.7, 24f64.to_radians(), 0.0, 32, 64);
        let axis_point = DVec3::new(0.0, 1.0, 0.875);
        let nearest = m
            .vertices
            .iter()
            .map(|v| (DVec3::from(v.position.map(f64::from)) - axis_point).length())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest > 0.3, "the window must leave the +Z pole open, nearest vertex {nearest}");
    }
}
