//! Reading any declarative input (matrices, scenes, model declarations): TOML with line and
//! column in errors, nearest-name suggestions for typos, and range checks naming the key; and
//! `read`, the bounded reader every file read of the crate goes through.

pub mod gltf_file;
pub mod gltf_scene;
pub mod guard;
pub mod names;
pub mod read;
pub mod sky_image;
pub mod source;
pub mod texture_file;
pub mod texture_transform;
pub mod validate;
