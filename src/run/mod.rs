//! Matrix expansion, frame plans, the results store and the run loop.

pub mod cells;
pub mod metrics;
pub mod plan;
pub mod runner;
pub mod store;
