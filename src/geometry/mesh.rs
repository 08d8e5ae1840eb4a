//! Indexed triangle meshes as the GPU receives them.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, Vec3};

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    /// xyz tangent, w handedness; zero when unknown.
    pub tangent: [f32; 4],
    /// The lightmap's uv (geometry::lightmap_uv; zero where the object has no lightmap).
    pub uv2: [f32; 2],
}

impl Vertex {
    pub fn new(position: DVec3, normal: DVec3, uv: [f64; 2]) -> Self {
        Self {
            position: position.as_vec3().to_array(),
            normal: normal.normalize_or_zero().as_vec3().to_array(),
            uv: [uv[0] as f32, uv[1] as f32],
            tangent: [0.0; 4],
            uv2: [0.0; 2],
        }
    }
}

/// Counter-clockwise front faces (glTF's and wgpu's default).
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounds (min, max) of the positions.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for v in &self.vertices {
            let p = Vec3::from(v.position);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (lo, hi)
    }

    /// MikkTSpace tangents (the space Unity and glTF bake normal maps in) for a mesh that has none;
    /// a mesh whose vertices all carry a tangent keeps its own. A vertex shared by faces that
    /// MikkTSpace would split takes the last face's tangent.
    pub fn ensure_tangents(&mut self) {
        if self.vertices.iter().all(|v| v.tangent[..3].iter().any(|c| *c != 0.0)) {
            return;
        }
        struct Faces<'a>(&'a mut Mesh);
        impl bevy_mikktspace::Geometry for Faces<'_> {
            fn num_faces(&self) -> usize {
                self.0.indices.len() / 3
            }
            fn num_vertices_of_face(&self, _: usize) -> usize {
                3
            }
            fn position(&self, face: usize, vert: usize) -> [f32; 3] {
                self.0.vertices[self.0.indices[face * 3 + vert] as usize].position
            }
            fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
                self.0.vertices[self.0.indices[face * 3 + vert] as usize].normal
            }
            fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
                self.0.vertices[self.0.indices[face * 3 + vert] as usize].uv
            }
            fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
                let i = self.0.indices[face * 3 + vert] as usize;
                // None (a degenerate face with no neighbour): zero, which the shader reads as "no
                // normal map here".
                self.0.vertices[i].tangent = t.map_or([0.0; 4], |t| t.tangent_encoded());
            }
        }
        // An error means no face could be processed (no triangles): nothing to write.
        let _ = bevy_mikktspace::generate_tangents(&mut Faces(self));
    }

    /// Append `other`, re-indexing it.
    pub fn append(&mut self, other: Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(other.vertices);
        self.indices.extend(other.indices.into_iter().map(|i| i + base));
    }

    /// Apply a transform to positions, normals (inverse transpose) and tangents.
    pub fn transformed(mut self, m: DMat4) -> Mesh {
        let normal_m = m.inverse().transpose();
        let flip = m.determinant() < 0.0;
        for v in &mut self.vertices {
            let p = m.transform_point3(DVec3::from(v.position.map(f64::from)));
            let n = normal_m.transform_vector3(DVec3::from(v.normal.map(f64::from))).normalize_or_zero();
            let t = m.transform_vector3(DVec3::new(v.tangent[0] as f64, v.tangent[1] as f64, v.tangent[2] as f64));
            v.position = p.as_vec3().to_array();
            v.normal = n.as_vec3().to_array();
            let t = t.normalize_or_zero().as_vec3();
            v.tangent = [t.x, t.y, t.z, v.tangent[3]];
        }
        if flip {
            for tri in self.indices.chunks_exact_mut(3) {
                tri.swap(1, 2);
            }
        }
        self
    }

    /// A regular grid of (rows+1)×(cols+1) vertices from `f(u, v)` → (position, normal), u, v ∈ [0, 1],
    /// triangulated counter-clockwise as seen from the side the normals point to.
    pub fn grid(rows: u32, cols: u32, f: impl Fn(f64, f64) -> (DVec3, DVec3)) -> Mesh {
        let mut mesh = Mesh::default();
        for r in 0..=rows {
            let v = r as f64 / rows as f64;
            for c in 0..=cols {
                let u = c as f64 / cols as f64;
                let (p, n) = f(u, v);
                mesh.vertices.push(Vertex::new(p, n, [u, v]));
            }
        }
        let stride = cols + 1;
        for r in 0..rows {
            for c in 0..cols {
                let i0 = r * stride + c;
                let i1 = i0 + 1;
                let i2 = i0 + stride;
                let i3 = i2 + 1;
                mesh.indices.extend_from_slice(&[i0, i2, i1, i1, i2, i3]);
            }
        }
        mesh.orient_to_normals();
        mesh
    }

    /// Flip triangles whose winding disagrees with their vertex normals, so generators need not
    /// track orientation by hand.
    pub fn orient_to_normals(&mut self) {
        for tri in self.indices.chunks_exact_mut(3) {
            let p = |i: u32| DVec3::from(self.vertices[i as usize].position.map(f64::from));
            let n = |i: u32| DVec3::from(self.vertices[i as usize].normal.map(f64::from));
            let face = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
            let avg = n(tri[0]) + n(tri[1]) + n(tri[2]);
            if face.dot(avg) < 0.0 {
                tri.swap(1, 2);
            }
        }
    }

    /// Area-weighted vertex normals, for imported meshes that have none.
    pub fn generate_normals(&mut self) {
        let mut acc = vec![DVec3::ZERO; self.vertices.len()];
        for tri in self.indices.chunks_exact(3) {
            let p = |i: u32| DVec3::from(self.vertices[i as usize].position.map(f64::from));
            let face = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
            for &i in tri {
                acc[i as usize] += face;
            }
        }
        for (v, n) in self.vertices.iter_mut().zip(acc) {
            v.normal = n.normalize_or_zero().as_vec3().to_array();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_winding_follows_normals() {
        let m = Mesh::grid(2, 3, |u, v| (DVec3::new(u, 0.0, v), DVec3::Y));
        assert_eq!(m.vertices.len(), 12);
        assert_eq!(m.triangle_count(), 12);
        for tri in m.indices.chunks_exact(3) {
            let p = |i: u32| Vec3::from(m.vertices[i as usize].position);
            let face = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
            assert!(face.y > 0.0);
        }
    }

    #[test]
    fn mirrored_transform_keeps_faces_outward() {
        let mut m = Mesh::grid(1, 1, |u, v| (DVec3::new(u, 0.0, v), DVec3::Y));
        m = m.transformed(DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)));
        let p = |i: u32| Vec3::from(m.vertices[i as usize].position);
        let tri = &m.indices[0..3];
        let face = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
        assert!(face.y > 0.0);
    }
}
