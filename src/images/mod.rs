//! Images: display transforms, encoding (OpenEXR linear float, PNG 8-bit sRGB) and pixel statistics.

pub mod aces;
pub mod bloom;
pub mod encode;
pub mod exposure;
pub mod pixels;
pub mod ssao;
pub mod stats;
pub mod subsurface;
pub mod target;
pub mod tonemap;
pub mod urp_ssao;
