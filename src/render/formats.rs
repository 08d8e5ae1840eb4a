//! The formats of a frame's targets, shared by the passes that draw into them, the pipelines
//! that write them and the captures that draw the same scene (reflection probes).

/// The linear colour target: what every emulated pipeline's camera target holds, before display.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The role mask (`plan::roles`).
pub const ROLE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Uint;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The shadow maps' depth (passes::shadow).
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The prepass's normal buffer: HDRP's is octahedral in 8-bit channels, APPROXIMATED by 10:10:10:2
/// as the deferred G-buffer's is (render::gbuffer::normal_format).
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgb10a2Unorm;
