//! The thread pool: `BRDF_RS_NUM_THREADS`, else the CPU count; `set_num_threads` to change.

use std::sync::{Arc, RwLock};

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::error::BrdfError;

static POOL: RwLock<Option<Arc<ThreadPool>>> = RwLock::new(None);

/// Returns the thread count the environment asks for: `BRDF_RS_NUM_THREADS` if it is a
/// positive integer, else the number of CPUs available to the process.
pub fn default_num_threads() -> usize {
    std::env::var("BRDF_RS_NUM_THREADS")
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

fn build(n: usize) -> Result<Arc<ThreadPool>, BrdfError> {
    ThreadPoolBuilder::new()
        .num_threads(n)
        .thread_name(|i| format!("brdf-rs-{i}"))
        .build()
        .map(Arc::new)
        .map_err(|e| BrdfError::InvalidArgument(format!("cannot start {n} threads: {e}")))
}

fn pool() -> Arc<ThreadPool> {
    if let Some(p) = POOL.read().unwrap_or_else(|e| e.into_inner()).as_ref() {
        return p.clone();
    }
    let mut guard = POOL.write().unwrap_or_else(|e| e.into_inner());
    if guard.is_none() {
        let n = default_num_threads();
        // Fall back to one thread rather than fail if the OS refuses more.
        *guard = Some(build(n).or_else(|_| build(1)).expect("a one-thread pool"));
    }
    guard.as_ref().expect("pool just set").clone()
}

/// The largest thread count a pool can have (rayon's limit: it would silently use
/// fewer).
pub fn max_num_threads() -> usize {
    rayon::max_num_threads()
}

/// Sets the number of worker threads for later calls.
///
/// # Errors
/// `n` is 0 or above [`max_num_threads`], or the OS refuses to start the threads.
pub fn set_num_threads(n: usize) -> Result<(), BrdfError> {
    let max = max_num_threads();
    if n == 0 || n > max {
        return Err(BrdfError::InvalidArgument(format!(
            "n: expected a thread count from 1 to {max}, got {n}"
        )));
    }
    let new = build(n)?;
    *POOL.write().unwrap_or_else(|e| e.into_inner()) = Some(new);
    Ok(())
}

/// Returns the number of worker threads.
pub fn num_threads() -> usize {
    pool().current_num_threads()
}

/// Runs `f` inside the pool (its parallel iterators use the pool's threads).
pub fn install<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    pool().install(f)
}
