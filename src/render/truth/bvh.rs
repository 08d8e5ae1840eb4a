//! The truth's geometry: the cell's drawn meshes in world space as one triangle list with a BVH
//! over it (obvhs: PLOC build, SAH reinsertion, leaves collapsed), laid out as the tracer reads it
//! (shaders/pass/truth.wgsl `BvhNode`, `TruthVertex`, triangles as (i0, i1, i2, object)).

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3};

use crate::geometry::mesh::Mesh;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuBvhNode {
    /// xyz minimum; w the primitive count's bits (0: inner node).
    pub min: [f32; 4],
    /// xyz maximum; w the first child's or primitive's index, as bits.
    pub max: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct TruthVertex {
    /// World position; w the texture coordinate u.
    pub position: [f32; 4],
    /// World normal (unnormalised where the mesh has none: zero); w the coordinate v.
    pub normal: [f32; 4],
    /// World tangent; w the bitangent sign (0: none).
    pub tangent: [f32; 4],
}

/// Triangles in the BVH's primitive order, with their vertices and the node array.
pub struct TruthGeometry {
    pub nodes: Vec<GpuBvhNode>,
    /// (i0, i1, i2, object index).
    pub triangles: Vec<[u32; 4]>,
    pub vertices: Vec<TruthVertex>,
}

impl TruthGeometry {
    /// The meshes `(object index, mesh, object-to-world)` as one scene.
    pub fn build<'a>(meshes: impl IntoIterator<Item = (u32, &'a Mesh, DMat4)>) -> TruthGeometry {
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for (object, mesh, model) in meshes {
            let normal_matrix = model.inverse().transpose();
            let base = vertices.len() as u32;
            for v in &mesh.vertices {
                let p = model.transform_point3(DVec3::from(v.position.map(f64::from)));
                let n = normal_matrix.transform_vector3(DVec3::from(v.normal.map(f64::from)));
                let t =
                    model.transform_vector3(DVec3::new(v.tangent[0] as f64, v.tangent[1] as f64, v.tangent[2] as f64));
                let f = |d: DVec3, w: f32| [d.x as f32, d.y as f32, d.z as f32, w];
                vertices.push(TruthVertex {
                    position: f(p, v.uv[0]),
                    normal: f(n, v.uv[1]),
                    tangent: f(t, v.tangent[3]),
                });
            }
            for tri in mesh.indices.chunks_exact(3) {
                triangles.push([base + tri[0], base + tri[1], base + tri[2], object]);
            }
        }
        let prims: Vec<obvhs::triangle::Triangle> = triangles
            .iter()
            .map(|t| {
                let p = |i: u32| {
                    let q = vertices[i as usize].position;
                    glam_obvhs::Vec3A::new(q[0], q[1], q[2])
                };
                obvhs::triangle::Triangle { v0: p(t[0]), v1: p(t[1]), v2: p(t[2]) }
            })
            .collect();
        if prims.is_empty() {
            // An empty scene: one empty leaf that no ray enters.
            let node =
                GpuBvhNode { min: [1.0, 1.0, 1.0, f32::from_bits(0)], max: [-1.0, -1.0, -1.0, f32::from_bits(0)] };
            return TruthGeometry { nodes: vec![node], triangles, vertices };
        }
        let mut build_time = std::time::Duration::ZERO;
        let bvh =
            obvhs::bvh2::builder::build_bvh2_from_tris(&prims, obvhs::BvhBuildParams::medium_build(), &mut build_time);
        // Leaves index primitives through primitive_indices: lay the triangles out in that order.
        let ordered: Vec<[u32; 4]> = bvh.primitive_indices.iter().map(|&i| triangles[i as usize]).collect();
        let nodes = bvh
            .nodes
            .iter()
            .map(|n| GpuBvhNode {
                min: [n.aabb.min.x, n.aabb.min.y, n.aabb.min.z, f32::from_bits(n.prim_count)],
                max: [n.aabb.max.x, n.aabb.max.y, n.aabb.max.z, f32::from_bits(n.first_index)],
            })
            .collect();
        TruthGeometry { nodes, triangles: ordered, vertices }
    }

    /// The deepest path from the root (the tracer's traversal stack must hold it).
    pub fn depth(&self) -> usize {
        fn walk(nodes: &[GpuBvhNode], i: usize) -> usize {
            let n = &nodes[i];
            if n.min[3].to_bits() != 0 {
                return 1;
            }
            let first = n.max[3].to_bits() as usize;
            1 + walk(nodes, first).max(walk(nodes, first + 1))
        }
        walk(&self.nodes, 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_triangle_sits_in_exactly_one_leaf_inside_its_box() {
        let sphere = crate::geometry::procedural::uv_sphere(1.0, 24, 48);
        let shifted = DMat4::from_translation(DVec3::new(3.0, 0.0, 0.0));
        let g = TruthGeometry::build([(0, &sphere, DMat4::IDENTITY), (1, &sphere, shifted)]);
        assert_eq!(g.triangles.len(), 2 * sphere.triangle_count());
        let mut seen = vec![0u32; g.triangles.len()];
        for n in &g.nodes {
            let count = n.min[3].to_bits();
            if count == 0 {
                continue;
            }
            let first = n.max[3].to_bits();
            for k in first..first + count {
                seen[k as usize] += 1;
                for &i in &g.triangles[k as usize][..3] {
                    let p = g.vertices[i as usize].position;
                    for ((c, lo), hi) in p.iter().zip(&n.min).zip(&n.max).take(3) {
                        assert!(*c >= lo - 1e-5 && *c <= hi + 1e-5);
                    }
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "each triangle in one leaf");
        assert!(g.depth() < 48, "fits the tracer's stack: depth {}", g.depth());
    }
}
