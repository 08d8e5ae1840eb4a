//! A frame's render targets, made per image size and kept: colour, role and depth with their
//! read-backs, the G-buffer, the MSAA twins and the screen-space chains that read the frame.

use super::formats::{DEPTH_FORMAT, HDR_FORMAT, ROLE_FORMAT};
use super::gbuffer::GBuffer;
use crate::gpu::readback::TextureReadback;

pub(in crate::render) struct Targets {
    pub(in crate::render) width: u32,
    pub(in crate::render) height: u32,
    pub(in crate::render) gbuffer: GBuffer,
    pub(in crate::render) color: wgpu::Texture,
    pub(in crate::render) role: wgpu::Texture,
    pub(in crate::render) depth_view: wgpu::TextureView,
    pub(in crate::render) color_view: wgpu::TextureView,
    pub(in crate::render) role_view: wgpu::TextureView,
    pub(in crate::render) color_readback: TextureReadback,
    pub(in crate::render) role_readback: TextureReadback,
    /// The forward pass's multisampled targets, when a cell renders with MSAA.
    pub(in crate::render) msaa: Option<MsaaTargets>,
    /// HDRP's bloom chain on `color`, made on first use.
    pub(in crate::render) bloom: Option<crate::render::passes::bloom::BloomChain>,
    /// HDRP's SSAO on the prepass depth and normals, and the screen group reading its result.
    pub(in crate::render) ssao: Option<(crate::render::passes::ssao::SsaoChain, wgpu::BindGroup)>,
    /// The study's traced shadow mask, made for the first cell that traces visibility.
    pub(in crate::render) traced: Option<crate::render::passes::traced_shadows::TracedShadowMask>,
}

/// A forward frame's multisampled colour, role and depth, resolved into `Targets`' own at the end
/// of the pass (the role of sample 0: an integer target resolves by taking one sample).
pub(in crate::render) struct MsaaTargets {
    pub(in crate::render) samples: u32,
    pub(in crate::render) color: wgpu::TextureView,
    pub(in crate::render) role: wgpu::TextureView,
    pub(in crate::render) depth: wgpu::TextureView,
}

impl Targets {
    /// The targets of `width`×`height` frames.
    pub(in crate::render) fn new(
        device: &wgpu::Device,
        gbuffer_read_layout: &wgpu::BindGroupLayout,
        (width, height): (u32, u32),
    ) -> Targets {
        {
            let make = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
                crate::render::texture_2d(device, label, (width, height), format, usage)
            };
            let attach = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
            // Sampled too: HDRP's bloom reads the frame.
            let color = make("hdr", HDR_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
            let role = make("role", ROLE_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
            let depth = make(
                "depth",
                DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            );
            let role_view = role.create_view(&Default::default());
            let depth_view = depth.create_view(&Default::default());
            let gbuffer = GBuffer::new(device, gbuffer_read_layout, width, height, &role_view, &depth_view);
            Targets {
                width,
                height,
                gbuffer,
                color_view: color.create_view(&Default::default()),
                role_view,
                depth_view,
                color_readback: TextureReadback::new(device, "hdr readback", width, height, 16),
                role_readback: TextureReadback::new(device, "role readback", width, height, 1),
                color,
                role,
                msaa: None,
                bloom: None,
                ssao: None,
                traced: None,
            }
        }
    }

    /// Make the multisampled forward targets match `samples` (the single-sample targets exist).
    pub(in crate::render) fn ensure_msaa(&mut self, device: &wgpu::Device, samples: u32) {
        let t = self;
        if samples == 1 || t.msaa.as_ref().is_some_and(|m| m.samples == samples) {
            return;
        }
        let make = |label: &str, format| {
            crate::render::multisampled_2d(
                device,
                label,
                (t.width, t.height),
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
                samples,
            )
            .create_view(&Default::default())
        };
        t.msaa = Some(MsaaTargets {
            samples,
            color: make("hdr msaa", HDR_FORMAT),
            role: make("role msaa", ROLE_FORMAT),
            depth: make("depth msaa", DEPTH_FORMAT),
        });
    }
}
