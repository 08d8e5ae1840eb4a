//! Reading any declarative input (matrices, scenes, model declarations): TOML with line and
//! column in errors, nearest-name suggestions for typos, and range checks naming the key.

pub mod gltf_scene;
pub mod guard;
pub mod names;
pub mod sky_image;
pub mod source;
pub mod texture_file;
pub mod texture_transform;
pub mod validate;
