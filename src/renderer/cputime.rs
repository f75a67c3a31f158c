//! CPU time of the frame's preparation over all the threads that did it: the
//! budget is CPU time for planning and upload (2 ms a frame), so splitting work over threads must
//! not hide it.
//!
//! A [`Clock`] reads the calling thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`) plus the CPU
//! time of every helper thread [`crate::renderer::tiles::both`] ran for this thread since (each
//! helper measures itself and the caller adds it to a thread-local sum when it joins), so
//! concurrent renderers (the tests run several) do not count each other. Where the thread
//! clock is not available (not 64-bit Linux) it falls back to wall clock.

use std::cell::Cell;
use std::time::Instant;

thread_local! {
    /// CPU nanoseconds of helper threads joined by this thread.
    static HELPERS: Cell<u64> = const { Cell::new(0) };
}

#[cfg(all(target_os = "linux", target_pointer_width = "64"))]
fn thread_cpu_ns() -> Option<u64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable `timespec` that outlives the call, which writes only it.
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (r == 0 && ts.tv_sec >= 0 && ts.tv_nsec >= 0).then(|| ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64)
}

#[cfg(not(all(target_os = "linux", target_pointer_width = "64")))]
fn thread_cpu_ns() -> Option<u64> {
    None
}

/// Whether [`Clock`] measures CPU time (else wall clock).
pub fn measures_cpu() -> bool {
    thread_cpu_ns().is_some()
}

/// CPU time of the calling thread and its joined helpers, in nanoseconds.
fn now_ns() -> Option<u64> {
    thread_cpu_ns().map(|t| t + HELPERS.with(Cell::get))
}

/// Runs `f` on a helper thread's behalf: returns its result and the CPU nanoseconds it took
/// on this (the helper) thread, for [`add_helper`] on the joining thread.
pub fn measured<T>(f: impl FnOnce() -> T) -> (T, u64) {
    let t0 = thread_cpu_ns();
    let out = f();
    let spent = t0.zip(thread_cpu_ns()).map_or(0, |(a, b)| b.saturating_sub(a));
    (out, spent)
}

/// Adds a joined helper's CPU time to the calling thread's sum.
pub fn add_helper(ns: u64) {
    HELPERS.with(|h| h.set(h.get().saturating_add(ns)));
}

/// A started measurement: CPU time over this thread and its helpers, and wall clock.
pub struct Clock {
    cpu: Option<u64>,
    wall: Instant,
}

impl Clock {
    pub fn start() -> Self {
        Self { cpu: now_ns(), wall: Instant::now() }
    }

    /// Milliseconds since `start`: CPU time over all threads, or wall clock without a thread
    /// clock.
    pub fn ms(&self) -> f64 {
        match self.cpu.zip(now_ns()) {
            Some((a, b)) => b.saturating_sub(a) as f64 * 1e-6,
            None => self.wall_ms(),
        }
    }

    /// Wall-clock milliseconds since `start`.
    pub fn wall_ms(&self) -> f64 {
        self.wall.elapsed().as_secs_f64() * 1e3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spins until this thread has used `ms` of CPU time.
    fn spin(ms: f64) -> u64 {
        let t0 = thread_cpu_ns().unwrap_or(0);
        let mut x = 0u64;
        while (thread_cpu_ns().unwrap_or(u64::MAX) - t0) as f64 * 1e-6 < ms {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
        }
        x
    }

    #[test]
    fn the_clock_counts_a_helper_threads_work_and_not_sleep() {
        if !measures_cpu() {
            return;
        }
        let c = Clock::start();
        // Sleeping costs no CPU; a helper's 30 ms of CPU does, once joined.
        std::thread::sleep(std::time::Duration::from_millis(30));
        let slept = c.ms();
        let (_, spent) = std::thread::scope(|s| s.spawn(|| measured(|| spin(30.0))).join().unwrap());
        let before_join = c.ms();
        add_helper(spent);
        let after = c.ms();
        assert!(slept < 10.0, "sleeping 30 ms counted {slept} ms of CPU");
        assert!(before_join < 10.0, "the helper counted before it was joined: {before_join} ms");
        assert!(after - before_join >= 30.0, "the helper's 30 ms of CPU counted {} ms", after - before_join);
    }
}
