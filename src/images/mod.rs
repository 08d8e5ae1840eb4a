//! Images: display transforms and encoding (OpenEXR linear float, PNG 8-bit sRGB).

pub mod encode;
pub mod tonemap;
