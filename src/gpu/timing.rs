//! GPU pass timing with timestamp queries, when the adapter has them (lavapipe does).

use crate::error::Error;
use crate::gpu::readback::map_read;

/// Up to `frames` (begin, end) timestamp pairs, one per frame, resolved and read back at once.
pub struct PassTimer {
    pub query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    capacity: u32,
    /// Nanoseconds per tick.
    period_ns: f64,
}

impl PassTimer {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, frames: u32) -> PassTimer {
        let count = 2 * frames.max(1);
        let size = count as u64 * 8;
        PassTimer {
            query_set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            staging: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            capacity: frames.max(1),
            period_ns: queue.get_timestamp_period() as f64,
        }
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// The writes for frame `slot` of a pass.
    pub fn writes(&self, slot: u32) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(2 * slot),
            end_of_pass_write_index: Some(2 * slot + 1),
        }
    }

    /// The begin write of frame `slot`, for the first of several passes.
    pub fn begin_write(&self, slot: u32) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(2 * slot),
            end_of_pass_write_index: None,
        }
    }

    /// The end write of frame `slot`, for the last of several passes.
    pub fn end_write(&self, slot: u32) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: Some(2 * slot + 1),
        }
    }

    /// Resolve the first `frames` pairs into the readback buffer (encode after the last pass).
    pub fn encode_resolve(&self, encoder: &mut wgpu::CommandEncoder, frames: u32) {
        encoder.resolve_query_set(&self.query_set, 0..2 * frames, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, frames as u64 * 16);
    }

    /// Milliseconds per frame, after the resolve was submitted.
    pub fn read_ms(&self, device: &wgpu::Device, frames: u32) -> Result<Vec<f64>, Error> {
        let bytes = map_read(device, &self.staging)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        Ok((0..frames as usize)
            .map(|f| ticks[2 * f + 1].saturating_sub(ticks[2 * f]) as f64 * self.period_ns * 1e-6)
            .collect())
    }
}
