//! A frame's render targets, made per image size and kept: colour, role and depth with their
//! read-backs, the G-buffer, the MSAA twins and the forward pass's fixed-object layer. The passes
//! that read the frame (SSAO, bloom, traced shadows) keep their own textures, made again when the
//! targets' `generation` changes.

use super::formats::{DEPTH_FORMAT, HDR_FORMAT, ROLE_FORMAT};
use super::gbuffer::GBuffer;
use crate::gpu::readback::TextureReadback;

pub(in crate::render) struct Targets {
    pub(in crate::render) width: u32,
    pub(in crate::render) height: u32,
    /// Which targets these are (a new size makes new ones): what the passes' own textures follow.
    pub(in crate::render) generation: u64,
    pub(in crate::render) gbuffer: GBuffer,
    pub(in crate::render) color: wgpu::Texture,
    pub(in crate::render) role: wgpu::Texture,
    pub(in crate::render) depth: wgpu::Texture,
    pub(in crate::render) depth_view: wgpu::TextureView,
    pub(in crate::render) color_view: wgpu::TextureView,
    pub(in crate::render) role_view: wgpu::TextureView,
    pub(in crate::render) color_readback: TextureReadback,
    pub(in crate::render) role_readback: TextureReadback,
    /// The forward pass's multisampled targets, when a cell renders with MSAA.
    pub(in crate::render) msaa: Option<MsaaTargets>,
    /// The fixed objects and background of the last forward frame that drew them apart.
    pub(in crate::render) layer: Option<FixedLayer>,
}

/// A forward frame's fixed objects and background (passes::forward::ForwardDraw::FixedLayer):
/// drawn once for the inputs `key` names, then copied into the frame's targets for each cell that
/// differs from it only in the subject, which is drawn over it.
pub(in crate::render) struct FixedLayer {
    pub(in crate::render) key: Option<u64>,
    pub(in crate::render) targets: ColorRoleDepth,
}

/// Colour, role and depth textures of one sample count, with their views.
pub(in crate::render) struct ColorRoleDepth {
    pub(in crate::render) samples: u32,
    pub(in crate::render) textures: [wgpu::Texture; 3],
    pub(in crate::render) color: wgpu::TextureView,
    pub(in crate::render) role: wgpu::TextureView,
    pub(in crate::render) depth: wgpu::TextureView,
}

impl ColorRoleDepth {
    fn new(device: &wgpu::Device, label: &str, (width, height): (u32, u32), samples: u32) -> ColorRoleDepth {
        let usage =
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST;
        let make = |what: &str, format| {
            crate::render::resources::multisampled_2d(
                device,
                &format!("{label} {what}"),
                (width, height),
                format,
                usage,
                samples,
            )
        };
        let textures = [make("hdr", HDR_FORMAT), make("role", ROLE_FORMAT), make("depth", DEPTH_FORMAT)];
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        ColorRoleDepth {
            samples,
            color: view(&textures[0]),
            role: view(&textures[1]),
            depth: view(&textures[2]),
            textures,
        }
    }
}

/// A forward frame's multisampled colour, role and depth, resolved into `Targets`' own at the end
/// of the pass (the role of sample 0: an integer target resolves by taking one sample).
pub(in crate::render) type MsaaTargets = ColorRoleDepth;

impl Targets {
    /// The targets of `width`×`height` frames, the `generation`th made.
    pub(in crate::render) fn new(
        device: &wgpu::Device,
        gbuffer_read_layout: &wgpu::BindGroupLayout,
        (width, height): (u32, u32),
        generation: u64,
    ) -> Targets {
        {
            let make = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
                crate::render::resources::texture_2d(device, label, (width, height), format, usage)
            };
            // Copy destinations too: a fixed-object layer is copied in (passes::forward).
            let attach =
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST;
            // Sampled too: HDRP's bloom reads the frame.
            let color = make("hdr", HDR_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
            let role = make("role", ROLE_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
            let depth = make(
                "depth",
                DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_DST,
            );
            let role_view = role.create_view(&Default::default());
            let depth_view = depth.create_view(&Default::default());
            let gbuffer = GBuffer::new(device, gbuffer_read_layout, width, height, &role_view, &depth_view);
            Targets {
                width,
                height,
                generation,
                gbuffer,
                color_view: color.create_view(&Default::default()),
                role_view,
                depth_view,
                color_readback: TextureReadback::new(device, "hdr readback", width, height, 16),
                role_readback: TextureReadback::new(device, "role readback", width, height, 1),
                color,
                role,
                depth,
                msaa: None,
                layer: None,
            }
        }
    }

    /// Make the multisampled forward targets match `samples` (the single-sample targets exist).
    pub(in crate::render) fn ensure_msaa(&mut self, device: &wgpu::Device, samples: u32) {
        let t = self;
        if samples == 1 || t.msaa.as_ref().is_some_and(|m| m.samples == samples) {
            return;
        }
        t.msaa = Some(ColorRoleDepth::new(device, "msaa", (t.width, t.height), samples));
    }

    /// The fixed-object layer for frames of `samples` samples, holding nothing until drawn.
    pub(in crate::render) fn ensure_layer(&mut self, device: &wgpu::Device, samples: u32) -> &mut FixedLayer {
        if self.layer.as_ref().is_none_or(|l| l.targets.samples != samples) {
            let targets = ColorRoleDepth::new(device, "fixed layer", (self.width, self.height), samples);
            self.layer = Some(FixedLayer { key: None, targets });
        }
        self.layer.as_mut().expect("just made")
    }

    /// Copy the fixed-object layer into the targets a forward frame of `samples` samples draws in.
    pub(in crate::render) fn restore_layer(&self, encoder: &mut wgpu::CommandEncoder, samples: u32) {
        let Some(layer) = &self.layer else { return };
        let into: [&wgpu::Texture; 3] = match self.msaa.as_ref().filter(|_| samples > 1) {
            Some(m) => [&m.textures[0], &m.textures[1], &m.textures[2]],
            None => [&self.color, &self.role, &self.depth],
        };
        let size = wgpu::Extent3d { width: self.width, height: self.height, depth_or_array_layers: 1 };
        for (from, to) in layer.targets.textures.iter().zip(into) {
            encoder.copy_texture_to_texture(from.as_image_copy(), to.as_image_copy(), size);
        }
    }
}
