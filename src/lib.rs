//! shadematrix: a declarative batch comparison harness for real-time shading models.
//!
//! Data flows one way: matrix → cells → plan → render → images → metrics → report. Each top-level
//! module is one stage or part of the vocabulary below the stages, and imports only from modules
//! earlier in that order:
//!
//! error, color, fsutil, input, pipelines, gpu, shading (vocabulary) → spec, geometry, environment
//! (the matrix and its scenes) → cells → plan → render → images → compare (metrics) → record →
//! run (streams cells through the stages) → report → audit → cli.
//!
//! `STAGES` in `tests/e2e/flow.rs` holds that order, and the test fails when an import points back.

pub mod adapter;
pub mod audit;
pub mod cells;
pub mod cli;
pub mod color;
pub mod compare;
pub mod declarations;
pub mod environment;
pub mod error;
pub mod fsutil;
pub mod geometry;
pub mod gpu;
pub mod images;
pub mod input;
pub mod materials;
pub mod pipelines;
pub mod plan;
pub mod record;
pub mod remap;
pub mod render;
pub mod report;
pub mod run;
pub mod shading;
pub mod store;

pub use error::{Error, InputError, Result};
