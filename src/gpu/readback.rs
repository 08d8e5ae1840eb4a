//! Copying textures and buffers back to the CPU.

use crate::error::Error;

/// wgpu requires rows of a texture→buffer copy to be 256-byte aligned.
pub fn padded_row_bytes(width: u32, bytes_per_texel: u32) -> u32 {
    let unpadded = width * bytes_per_texel;
    unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

/// A mappable buffer sized for one texture, and the copy command into it.
pub struct TextureReadback {
    pub buffer: wgpu::Buffer,
    pub width: u32,
    pub height: u32,
    pub bytes_per_texel: u32,
}

impl TextureReadback {
    pub fn new(device: &wgpu::Device, label: &str, width: u32, height: u32, bytes_per_texel: u32) -> Self {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (padded_row_bytes(width, bytes_per_texel) * height) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Self { buffer, width, height, bytes_per_texel }
    }

    pub fn encode_copy(&self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) {
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row_bytes(self.width, self.bytes_per_texel)),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d { width: self.width, height: self.height, depth_or_array_layers: 1 },
        );
    }

    /// Map (after the copy was submitted), strip row padding, unmap.
    pub fn read(&self, device: &wgpu::Device) -> Result<Vec<u8>, Error> {
        let bytes = map_read(device, &self.buffer)?;
        let row = (self.width * self.bytes_per_texel) as usize;
        let padded = padded_row_bytes(self.width, self.bytes_per_texel) as usize;
        let mut out = Vec::with_capacity(row * self.height as usize);
        for y in 0..self.height as usize {
            out.extend_from_slice(&bytes[y * padded..y * padded + row]);
        }
        Ok(out)
    }
}

/// Map a whole buffer for reading, wait, copy its bytes out and unmap it.
pub fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>, Error> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Device(format!("waiting for readback: {e}")))?;
    rx.recv()
        .map_err(|_| Error::Device("readback callback never ran".into()))?
        .map_err(|e| Error::Device(format!("mapping readback buffer: {e}")))?;
    let bytes = {
        let view = buffer.get_mapped_range(..).map_err(|e| Error::Device(format!("reading mapped buffer: {e}")))?;
        view.to_vec()
    };
    buffer.unmap();
    Ok(bytes)
}
