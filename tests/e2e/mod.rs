//! One module per area, each driving the library or the `shadematrix` binary for real.

mod antialiasing;
mod bloom;
mod check;
mod cli;
mod compare;
mod conventions;
mod coverage;
mod flow;
mod fuzz;
mod gallery;
mod gltf_roundtrip;
mod invariants;
mod lights;
mod lod;
mod materials;
mod models;
mod paths;
mod probes;
mod records;
mod references;
mod render_ci;
mod resume;
mod shading;
mod shadows;
mod stability;
mod user_models;
