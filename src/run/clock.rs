//! Stage clocks: wall time each stage spends on its jobs, summed across its threads, and the
//! process's CPU time and peak memory from the OS.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use crate::record::run::StageTimes;
use crate::record::Maybe;

/// One counter per stage, in nanoseconds; shared by the threads of a run.
#[derive(Default)]
pub struct StageClock {
    pub prepare: AtomicU64,
    pub render: AtomicU64,
    pub readback: AtomicU64,
    pub encode: AtomicU64,
    pub metrics: AtomicU64,
    pub render_blocked: AtomicU64,
}

/// CPU time of the calling thread: what a CPU stage costs, whatever else competes for the cores.
/// Falls back to wall time where the OS has no per-thread clock.
#[derive(Clone, Copy)]
pub struct ThreadTimer {
    wall: Instant,
    cpu_ns: Option<u64>,
}

impl ThreadTimer {
    pub fn start() -> ThreadTimer {
        ThreadTimer { wall: Instant::now(), cpu_ns: thread_cpu_ns() }
    }

    pub fn elapsed_ns(&self) -> u64 {
        match (self.cpu_ns, thread_cpu_ns()) {
            (Some(a), Some(b)) => b.saturating_sub(a),
            _ => self.wall.elapsed().as_nanos() as u64,
        }
    }
}

#[cfg(unix)]
fn thread_cpu_ns() -> Option<u64> {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes only into the timespec we pass.
    (unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0)
        .then(|| t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64)
}

#[cfg(not(unix))]
fn thread_cpu_ns() -> Option<u64> {
    None
}

impl StageClock {
    /// Wall time since `since` (the render stage: submit and wait for the device).
    pub fn add(counter: &AtomicU64, since: Instant) {
        counter.fetch_add(since.elapsed().as_nanos() as u64, Ordering::Relaxed);
    }

    /// CPU time of this thread since `timer` started (the CPU stages).
    pub fn add_cpu(counter: &AtomicU64, timer: ThreadTimer) {
        counter.fetch_add(timer.elapsed_ns(), Ordering::Relaxed);
    }

    pub fn add_ms(counter: &AtomicU64, ms: f64) {
        counter.fetch_add((ms * 1e6).max(0.0) as u64, Ordering::Relaxed);
    }

    pub fn times(&self, encode_workers: usize, metrics_workers: usize, queue_depth: usize) -> StageTimes {
        let ms = |c: &AtomicU64| c.load(Ordering::Relaxed) as f64 / 1e6;
        let usage = ProcessUsage::now();
        StageTimes {
            prepare_ms: ms(&self.prepare),
            render_ms: ms(&self.render),
            readback_ms: ms(&self.readback),
            encode_ms: ms(&self.encode),
            metrics_ms: ms(&self.metrics),
            render_blocked_ms: ms(&self.render_blocked),
            encode_workers,
            metrics_workers,
            queue_depth,
            process_cpu: usage.cpu_seconds,
            peak_rss_bytes: usage.peak_rss_bytes,
        }
    }
}

/// What the OS says about this process so far.
pub struct ProcessUsage {
    /// User + system CPU seconds.
    pub cpu_seconds: Maybe<f64>,
    pub peak_rss_bytes: Maybe<u64>,
}

impl ProcessUsage {
    #[cfg(unix)]
    pub fn now() -> ProcessUsage {
        // SAFETY: getrusage writes only into the struct we pass.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } != 0 {
            let why = format!("getrusage failed: {}", std::io::Error::last_os_error());
            return ProcessUsage { cpu_seconds: Maybe::missing(&why), peak_rss_bytes: Maybe::missing(why) };
        }
        let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        // ru_maxrss is in kilobytes on Linux and in bytes on macOS.
        let rss_unit = if cfg!(target_os = "macos") { 1 } else { 1024 };
        ProcessUsage {
            cpu_seconds: Maybe::Value(secs(u.ru_utime) + secs(u.ru_stime)),
            peak_rss_bytes: Maybe::Value(u.ru_maxrss as u64 * rss_unit),
        }
    }

    #[cfg(not(unix))]
    pub fn now() -> ProcessUsage {
        let why = "not measured on this OS (getrusage is Unix only)";
        ProcessUsage { cpu_seconds: Maybe::missing(why), peak_rss_bytes: Maybe::missing(why) }
    }
}
