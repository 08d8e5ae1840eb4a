//! GPU pass timing with timestamp queries, when the adapter has them (lavapipe does).

use crate::error::Error;
use crate::gpu::readback::map_read;

/// Up to `capacity` (begin, end) timestamp pairs — one per timed pass of every frame — resolved
/// and read back at once. Every pair that is resolved must have been written.
pub struct PassTimer {
    pub query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    capacity: u32,
    /// Nanoseconds per tick.
    period_ns: f64,
}

impl PassTimer {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, pairs: u32) -> PassTimer {
        let count = 2 * pairs.max(1);
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
            capacity: pairs.max(1),
            period_ns: queue.get_timestamp_period() as f64,
        }
    }

    /// How many pairs it holds.
    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// The writes of pair `pair` for a render pass: its begin, its end, or both (a timed span of
    /// several passes writes begin on the first and end on the last).
    pub fn writes(&self, pair: u32, begin: bool, end: bool) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: begin.then_some(2 * pair),
            end_of_pass_write_index: end.then_some(2 * pair + 1),
        }
    }

    /// Both writes of pair `pair` for a compute pass.
    pub fn compute_writes(&self, pair: u32) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(2 * pair),
            end_of_pass_write_index: Some(2 * pair + 1),
        }
    }

    /// Resolve the first `pairs` pairs into the readback buffer (encode after the last pass).
    pub fn encode_resolve(&self, encoder: &mut wgpu::CommandEncoder, pairs: u32) {
        encoder.resolve_query_set(&self.query_set, 0..2 * pairs, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, pairs as u64 * 16);
    }

    /// Milliseconds of each of the first `pairs` pairs, after the resolve was submitted.
    pub fn read_ms(&self, device: &wgpu::Device, pairs: u32) -> Result<Vec<f64>, Error> {
        let bytes = map_read(device, &self.staging)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        Ok((0..pairs as usize)
            .map(|f| ticks[2 * f + 1].saturating_sub(ticks[2 * f]) as f64 * self.period_ns * 1e-6)
            .collect())
    }
}
