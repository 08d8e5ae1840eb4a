//! Device-level GPU code: adapter choice, device errors, readback. Knows nothing of matrices.

pub mod context;
pub mod readback;
pub mod timing;

pub use context::{AdapterRecord, GpuContext};
