//! shadematrix: a declarative batch comparison harness for real-time shading models.
//!
//! Data flows one way: matrix → cells → plan → render → images → report.
//! `spec` reads input, `run` expands and schedules, `render`/`gpu` draw, `images` encode.

pub mod audit;
pub mod cli;
pub mod color;
pub mod compare;
pub mod environment;
pub mod error;
pub mod fsutil;
pub mod geometry;
pub mod gpu;
pub mod images;
pub mod pipelines;
pub mod render;
pub mod report;
pub mod run;
pub mod shading;
pub mod spec;

pub use error::{Error, InputError, Result};
