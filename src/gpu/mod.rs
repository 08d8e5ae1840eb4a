//! Device-level GPU code: adapter choice, device errors, readback. Knows nothing of matrices.

pub mod constants;
pub mod context;
pub mod layout;
pub mod readback;
pub mod timing;

pub use constants::ConstantSpace;
pub use context::{AdapterRecord, GpuContext};
