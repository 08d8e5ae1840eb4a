//! The run: cells streamed through render → encode → metrics, each stage on its own threads,
//! writing one typed record per cell.

pub mod cell_cache;
pub mod cell_key;
mod clock;
mod describe;
mod encode;
pub mod merge;
mod metrics;
pub mod runner;
pub mod shard;
pub mod study;
pub mod truth_cache;

pub use clock::ProcessUsage;
pub use runner::{run, RunOptions, RunSummary, Workers};
