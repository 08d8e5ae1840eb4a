//! Lightmap UVs for a scene's static (fixed) objects, as Unity's "Generate Lightmap UVs" makes
//! them (UnwrapParam defaults: hard angle 88°, pack margin): each object is cut into charts where
//! neighbouring faces meet at more than the hard angle, each chart is laid flat by projecting it
//! onto the plane of its first face, scaled to the scene's texels per world unit, and the charts
//! are packed into one atlas on shelves with the scene's padding between them. The lightmap's
//! texels are then found by rasterising the charts: each texel whose centre a triangle covers
//! takes that point's world position and normal.
//!
//! Written here rather than taken from a crate: the one chart packer on the registry
//! (`xatlas-rs` 0.1.3) ships bindings with Windows-mangled symbols that do not link on Linux.
//! A chart also stops growing where a face turns more than CHART_CONE_DEG from its first face,
//! so that its projection does not fold: exact for the planar faces of rooms and boxes, a
//! flattening of curved ones that Unity's unwrapper would distort less.
//!
//! A mesh that brings its own lightmap UVs (a glTF file's TEXCOORD_1, read into `uv2`) keeps them:
//! its [0, 1]² square becomes one chart, scaled so that its texels cover the mesh's world area at
//! the scene's texels per unit, as Unity scales an imported lightmap UV set by the renderer's area.
//!
//! A texel that no triangle covers stays empty; the bake's dilation fills those beside charts
//! (render::gi::lightmaps).

use std::collections::HashMap;

use glam::{DMat4, DVec2, DVec3};

use super::{Mesh, Vertex};
use crate::declarations::gi::GiSettings;
use crate::declarations::scene::{Role, Scene};
use crate::error::Error;

/// The largest lightmap side; a scene that needs more at its texels per unit is refused.
pub const MAX_LIGHTMAP_SIDE: u32 = 4096;
/// Unity's UnwrapParam.hardAngle default: faces meeting at more than this start a new chart.
pub const HARD_ANGLE_DEG: f64 = 88.0;
/// The most a chart's face may turn from its first face.
pub const CHART_CONE_DEG: f64 = 60.0;

/// One texel of the lightmap that a chart covers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightmapTexel {
    pub x: u32,
    pub y: u32,
    /// The object (scene index) the texel lies on.
    pub object: usize,
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// The scene's lightmap atlas: its size and its covered texels.
#[derive(Debug, Clone, PartialEq)]
pub struct LightmapAtlas {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<LightmapTexel>,
    /// Per scene object: whether it has a lightmap (a fixed object with triangles).
    pub lightmapped: Vec<bool>,
}

/// A chart: its faces (triangle indices of one mesh), each corner's flat position in texels
/// (before packing) and its extent.
struct Chart {
    object: usize,
    faces: Vec<usize>,
    corners: Vec<[DVec2; 3]>,
    size: DVec2,
    offset: DVec2,
}

/// Cut one mesh (world positions `p`) into charts laid flat at `texels_per_unit`.
fn charts_of(object: usize, mesh: &Mesh, p: &[DVec3], texels_per_unit: f64) -> Vec<Chart> {
    let faces = mesh.indices.len() / 3;
    let corner = |f: usize, k: usize| mesh.indices[3 * f + k] as usize;
    let normal = |f: usize| {
        let [a, b, c] = [0, 1, 2].map(|k| p[corner(f, k)]);
        (b - a).cross(c - a).normalize_or_zero()
    };
    // Faces sharing an edge (by position, so split vertices still join).
    let key = |i: usize| p[i].to_array().map(|c| (c * 1e5).round() as i64);
    let mut edges: HashMap<([i64; 3], [i64; 3]), Vec<usize>> = HashMap::new();
    for f in 0..faces {
        for k in 0..3 {
            let (a, b) = (key(corner(f, k)), key(corner(f, (k + 1) % 3)));
            edges.entry(if a < b { (a, b) } else { (b, a) }).or_default().push(f);
        }
    }
    let (hard, cone) = (HARD_ANGLE_DEG.to_radians().cos(), CHART_CONE_DEG.to_radians().cos());
    let mut chart_of = vec![usize::MAX; faces];
    let mut charts = Vec::new();
    for seed in 0..faces {
        if chart_of[seed] != usize::MAX {
            continue;
        }
        let n0 = normal(seed);
        if n0 == DVec3::ZERO {
            chart_of[seed] = usize::MAX - 1;
            continue;
        }
        let id = charts.len();
        let mut members = vec![seed];
        chart_of[seed] = id;
        let mut next = 0;
        while next < members.len() {
            let f = members[next];
            next += 1;
            for k in 0..3 {
                let (a, b) = (key(corner(f, k)), key(corner(f, (k + 1) % 3)));
                for &g in &edges[&if a < b { (a, b) } else { (b, a) }] {
                    let ng = normal(g);
                    if chart_of[g] == usize::MAX && ng.dot(normal(f)) >= hard && ng.dot(n0) >= cone {
                        chart_of[g] = id;
                        members.push(g);
                    }
                }
            }
        }
        // Flat coordinates: the seed's plane, u along its first edge.
        let u_axis = (p[corner(seed, 1)] - p[corner(seed, 0)]).normalize_or_zero();
        let v_axis = n0.cross(u_axis);
        let flat = |i: usize| DVec2::new(p[i].dot(u_axis), p[i].dot(v_axis)) * texels_per_unit;
        let corners: Vec<[DVec2; 3]> = members.iter().map(|&f| [0, 1, 2].map(|k| flat(corner(f, k)))).collect();
        let lo = corners.iter().flatten().fold(DVec2::splat(f64::MAX), |m, c| m.min(*c));
        let hi = corners.iter().flatten().fold(DVec2::splat(f64::MIN), |m, c| m.max(*c));
        let corners = corners.into_iter().map(|c| c.map(|q| q - lo)).collect();
        charts.push(Chart { object, faces: members, corners, size: hi - lo, offset: DVec2::ZERO });
    }
    charts
}

/// The chart of a mesh that brings its own lightmap UVs (every face's `uv2` of non-zero area),
/// scaled so that its UV area holds the mesh's world area at `texels_per_unit`.
fn own_chart(object: usize, mesh: &Mesh, p: &[DVec3], texels_per_unit: f64) -> Option<Chart> {
    let faces = mesh.indices.len() / 3;
    let corner = |f: usize, k: usize| mesh.indices[3 * f + k] as usize;
    let uv = |i: usize| DVec2::new(mesh.vertices[i].uv2[0] as f64, mesh.vertices[i].uv2[1] as f64);
    let (mut uv_area, mut world_area) = (0.0, 0.0);
    for f in 0..faces {
        let [a, b, c] = [0, 1, 2].map(|k| corner(f, k));
        let area = (uv(b) - uv(a)).perp_dot(uv(c) - uv(a)).abs() * 0.5;
        if area <= 0.0 {
            return None;
        }
        uv_area += area;
        world_area += (p[b] - p[a]).cross(p[c] - p[a]).length() * 0.5;
    }
    let scale = (world_area / uv_area).sqrt() * texels_per_unit;
    let corners: Vec<[DVec2; 3]> = (0..faces).map(|f| [0, 1, 2].map(|k| uv(corner(f, k)) * scale)).collect();
    let lo = corners.iter().flatten().fold(DVec2::splat(f64::MAX), |m, c| m.min(*c));
    let hi = corners.iter().flatten().fold(DVec2::splat(f64::MIN), |m, c| m.max(*c));
    let corners = corners.into_iter().map(|c| c.map(|q| q - lo)).collect();
    Some(Chart { object, faces: (0..faces).collect(), corners, size: hi - lo, offset: DVec2::ZERO })
}

/// Pack charts on shelves (tallest first) into a square-ish atlas; returns its size in texels.
fn pack(charts: &mut [Chart], padding: f64) -> (u32, u32) {
    let area: f64 = charts.iter().map(|c| (c.size.x + padding) * (c.size.y + padding)).sum();
    let widest = charts.iter().map(|c| c.size.x + 2.0 * padding).fold(1.0, f64::max);
    let width = (area.sqrt() * 1.15).max(widest).ceil();
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by(|&a, &b| charts[b].size.y.total_cmp(&charts[a].size.y).then(a.cmp(&b)));
    let (mut x, mut y, mut shelf) = (padding, padding, 0.0f64);
    for i in order {
        let c = &mut charts[i];
        if x + c.size.x + padding > width {
            x = padding;
            y += shelf + padding;
            shelf = 0.0;
        }
        // Whole-texel offsets keep each chart's texel grid where its rasterisation put it.
        c.offset = DVec2::new(x.ceil(), y.ceil());
        x = c.offset.x + c.size.x + padding;
        shelf = shelf.max(c.offset.y + c.size.y - y);
    }
    (width as u32, (y + shelf + padding).ceil() as u32)
}

/// Give the fixed objects' meshes (the first `scene.objects.len()` of `meshes`) lightmap UVs:
/// each mesh is split where its charts' seams cut it, its vertices carrying `uv2` in the atlas.
pub fn unwrap(scene: &Scene, meshes: &mut [Mesh], gi: &GiSettings) -> Result<LightmapAtlas, Error> {
    let fixed: Vec<usize> = (0..scene.objects.len())
        .filter(|&i| scene.objects[i].role == Role::Fixed && !meshes[i].indices.is_empty())
        .collect();
    let mut lightmapped = vec![false; scene.objects.len()];
    if fixed.is_empty() {
        return Ok(LightmapAtlas { width: 1, height: 1, texels: Vec::new(), lightmapped });
    }
    let models: Vec<DMat4> = scene.objects.iter().map(|o| o.transform.matrix()).collect();
    let world: Vec<Vec<DVec3>> = (0..scene.objects.len())
        .map(|i| {
            meshes[i]
                .vertices
                .iter()
                .map(|v| models[i].transform_point3(DVec3::from(v.position.map(f64::from))))
                .collect()
        })
        .collect();
    let mut charts: Vec<Chart> = fixed
        .iter()
        .flat_map(|&i| match own_chart(i, &meshes[i], &world[i], gi.texels_per_unit) {
            Some(chart) => vec![chart],
            None => charts_of(i, &meshes[i], &world[i], gi.texels_per_unit),
        })
        .collect();
    let (width, height) = pack(&mut charts, gi.padding as f64);
    if width > MAX_LIGHTMAP_SIDE || height > MAX_LIGHTMAP_SIDE {
        return Err(crate::error::InputError::at_key(
            &scene.origin,
            "gi.texels_per_unit",
            format!(
                "{}: the lightmap would be {width}×{height} texels; at most {MAX_LIGHTMAP_SIDE} a side: lower \
                 texels_per_unit",
                gi.texels_per_unit
            ),
        )
        .into());
    }
    let mut texels = Vec::new();
    let mut taken = vec![false; (width * height) as usize];
    let mut rebuilt: Vec<Mesh> = vec![Mesh::default(); scene.objects.len()];
    let mut faces = Vec::new();
    for c in &charts {
        let i = c.object;
        let normal_matrix = models[i].inverse().transpose();
        let mesh = &meshes[i];
        for (f, flat) in c.faces.iter().zip(&c.corners) {
            let ids = [0, 1, 2].map(|k| mesh.indices[3 * f + k] as usize);
            let uv = flat.map(|q| q + c.offset);
            let out = &mut rebuilt[i];
            for (k, id) in ids.iter().enumerate() {
                out.indices.push(out.vertices.len() as u32);
                out.vertices.push(Vertex {
                    uv2: [(uv[k].x / width as f64) as f32, (uv[k].y / height as f64) as f32],
                    ..mesh.vertices[*id]
                });
            }
            let p = ids.map(|id| world[i][id]);
            let n = ids.map(|id| normal_matrix.transform_vector3(DVec3::from(mesh.vertices[id].normal.map(f64::from))));
            faces.push((i, uv.map(|q| (q.x, q.y)), p, n));
        }
    }
    // Texels whose centre a face covers first; then, conservatively, texels a face only overlaps
    // (a thin face, a chart's rim) take the face's nearest point, so that no chart is left
    // without texels to read.
    for margin in [0.0, std::f64::consts::FRAC_1_SQRT_2] {
        for (i, uv, p, n) in &faces {
            rasterise(*uv, (width, height), margin, |x, y, bary| {
                let at = (y * width + x) as usize;
                if taken[at] {
                    return;
                }
                let position = p[0] * bary[0] + p[1] * bary[1] + p[2] * bary[2];
                let mut normal = n[0] * bary[0] + n[1] * bary[1] + n[2] * bary[2];
                if normal.length_squared() < 1e-20 {
                    normal = (p[1] - p[0]).cross(p[2] - p[0]);
                }
                taken[at] = true;
                texels.push(LightmapTexel {
                    x,
                    y,
                    object: *i,
                    position: position.as_vec3().to_array(),
                    normal: normal.normalize_or_zero().as_vec3().to_array(),
                });
            });
        }
    }
    for &i in &fixed {
        meshes[i] = std::mem::take(&mut rebuilt[i]);
        lightmapped[i] = true;
    }
    Ok(LightmapAtlas { width, height, texels, lightmapped })
}

/// Call `texel` for each texel whose centre lies within `margin` texels of the triangle (in texel
/// units; 0: inside it), with the barycentric weights of the triangle's point nearest the centre.
fn rasterise(uv: [(f64, f64); 3], (width, height): (u32, u32), margin: f64, mut texel: impl FnMut(u32, u32, [f64; 3])) {
    let [(x0, y0), (x1, y1), (x2, y2)] = uv;
    let area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    if area.abs() < 1e-12 {
        return;
    }
    let bary = |px: f64, py: f64| {
        let w0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) / area;
        let w1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) / area;
        [w0, w1, 1.0 - w0 - w1]
    };
    let lo_x = (x0.min(x1).min(x2) - margin).floor().max(0.0) as u32;
    let hi_x = ((x0.max(x1).max(x2) + margin).ceil().max(0.0) as u32).min(width);
    let lo_y = (y0.min(y1).min(y2) - margin).floor().max(0.0) as u32;
    let hi_y = ((y0.max(y1).max(y2) + margin).ceil().max(0.0) as u32).min(height);
    let corners = [DVec2::new(x0, y0), DVec2::new(x1, y1), DVec2::new(x2, y2)];
    for y in lo_y..hi_y {
        for x in lo_x..hi_x {
            let c = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let w = bary(c.x, c.y);
            if w.iter().all(|&v| v >= -1e-9) {
                texel(x, y, w);
                continue;
            }
            if margin <= 0.0 {
                continue;
            }
            // The nearest point on the triangle's edges.
            let mut best = (f64::MAX, c);
            for k in 0..3 {
                let (a, b) = (corners[k], corners[(k + 1) % 3]);
                let t = ((c - a).dot(b - a) / (b - a).length_squared().max(1e-30)).clamp(0.0, 1.0);
                let q = a + (b - a) * t;
                if q.distance(c) < best.0 {
                    best = (q.distance(c), q);
                }
            }
            if best.0 <= margin {
                let w = bary(best.1.x, best.1.y).map(|v| v.clamp(0.0, 1.0));
                let sum = w[0] + w[1] + w[2];
                texel(x, y, w.map(|v| v / sum));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn room() -> (Scene, Vec<Mesh>) {
        let mut scene = Scene::load("default", None, "t", "k").unwrap();
        scene.gi = Some(toml::from_str("texels_per_unit = 4").unwrap());
        let meshes = crate::geometry::procedural::build_scene(&scene).unwrap();
        (scene, meshes)
    }

    #[test]
    fn charts_cover_each_fixed_surface_at_the_texel_density_and_do_not_overlap() {
        let (scene, mut meshes) = room();
        let gi = scene.gi.clone().unwrap();
        let atlas = unwrap(&scene, &mut meshes, &gi).unwrap();
        // The floor is 8 × 8 m: at 4 texels per unit 32 × 32 texels, and its rim conservatively.
        let floor = scene.objects.iter().position(|o| o.name == "floor").unwrap();
        let on_floor = atlas.texels.iter().filter(|t| t.object == floor).count();
        assert!((1024..=34 * 34).contains(&on_floor), "{on_floor} floor texels");
        assert!(atlas.lightmapped[floor] && !atlas.lightmapped[0], "subjects have no lightmap");
        // Every floor texel lies on the floor, facing up.
        for t in atlas.texels.iter().filter(|t| t.object == floor) {
            assert!(t.position[1].abs() < 1e-4 && t.normal[1] > 0.999, "{t:?}");
        }
        // No texel twice; every uv2 inside the atlas.
        let mut seen = std::collections::HashSet::new();
        assert!(atlas.texels.iter().all(|t| seen.insert((t.x, t.y))));
        for i in (0..scene.objects.len()).filter(|&i| atlas.lightmapped[i]) {
            assert!(meshes[i].vertices.iter().all(|v| v.uv2.iter().all(|c| (0.0..=1.0).contains(c))));
        }
    }

    #[test]
    fn a_mesh_with_its_own_lightmap_uvs_keeps_them() {
        // The floor brings uv2 mirrored in u (as a glTF TEXCOORD_1 would): one chart, its texels
        // laid out by those UVs at the scene's density.
        let (scene, mut meshes) = room();
        let gi = scene.gi.clone().unwrap();
        let floor = scene.objects.iter().position(|o| o.name == "floor").unwrap();
        for v in &mut meshes[floor].vertices {
            v.uv2 = [1.0 - (v.position[0] / 8.0 + 0.5), v.position[2] / 8.0 + 0.5];
        }
        let atlas = unwrap(&scene, &mut meshes, &gi).unwrap();
        let texels: Vec<_> = atlas.texels.iter().filter(|t| t.object == floor).collect();
        assert!((1024..=34 * 34).contains(&texels.len()), "{} floor texels", texels.len());
        // Mirrored: further right in the lightmap is further left in the world.
        let (a, b) = (texels.iter().min_by_key(|t| t.x).unwrap(), texels.iter().max_by_key(|t| t.x).unwrap());
        assert!(a.position[0] > 3.5 && b.position[0] < -3.5, "{a:?} {b:?}");
    }

    #[test]
    fn the_unwrap_is_deterministic() {
        let (scene, meshes) = room();
        let gi = scene.gi.clone().unwrap();
        let (mut a, mut b) = (meshes.clone(), meshes);
        let first = unwrap(&scene, &mut a, &gi).unwrap();
        let second = unwrap(&scene, &mut b, &gi).unwrap();
        assert_eq!(first, second);
        assert!(a.iter().zip(&b).all(|(x, y)| x.indices == y.indices));
    }
}
