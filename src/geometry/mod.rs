//! Meshes: procedural generators with analytic normals and UVs, and glTF import/export.

pub mod gltf_files;
pub mod gltf_io;
pub mod lightmap_uv;
pub mod mesh;
pub mod placement;
pub mod procedural;

pub use mesh::{Mesh, Vertex};
