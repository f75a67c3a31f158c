//! The pass sets built on a device, by configuration, shared by every renderer on it.
//!
//! On lavapipe a pass set's first frame costs 0.7-1.8 s of pipeline compilation at 192x108, a
//! frame on built pipelines 10-150 ms, so a process that creates many renderers (the bench, one
//! per configuration, all alive at once; the test suite, on several threads) compiles each
//! configuration once. A set holds only pipelines and layouts, built once each (`kit::Lazy`);
//! what a frame writes and reads back is each renderer's own, so renderers share sets freely.
//! The pool keeps the [`POOL_SETS`] most recently used; a set dropped from it lives on while a
//! renderer draws with it.
//!
//! The device (`gpu.rs`) holds the pool without knowing what a pass set is: the sets are kept
//! as `Any` and handed back as the type the renderer built them as.

use super::PipelineKey;
use anyhow::{anyhow, Result};
use std::any::Any;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Pass sets a device keeps for its renderers.
pub const POOL_SETS: usize = 32;

type Set = (PipelineKey, Arc<dyn Any + Send + Sync>);

#[derive(Default)]
pub struct PassPool {
    sets: Mutex<Vec<Set>>,
    /// Sets kept at most; 0: [`POOL_SETS`].
    capacity: AtomicUsize,
}

impl PassPool {
    /// Keeps at most `sets` sets from now on (a process with one long-lived renderer, the
    /// viewer, keeps few: each set's compiled pipelines hold up to 160 MiB on lavapipe).
    pub fn keep_at_most(&self, sets: usize) {
        self.capacity.store(sets.max(1), Ordering::Relaxed);
    }

    /// The set built for `key`, built now by `build` (and kept) if the pool has none.
    pub fn get<T: Any + Send + Sync>(&self, key: PipelineKey, build: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
        let mut sets = self.sets.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = sets.iter().rposition(|(k, _)| *k == key) {
            // Most recently used last.
            let set = sets.remove(i);
            sets.push(set.clone());
            return set.1.downcast::<T>().map_err(|_| anyhow!("the device's pass set for this key is of another type"));
        }
        let set = Arc::new(build()?);
        sets.push((key, set.clone()));
        let capacity = match self.capacity.load(Ordering::Relaxed) {
            0 => POOL_SETS,
            n => n,
        };
        let excess = sets.len().saturating_sub(capacity);
        sets.drain(..excess);
        Ok(set)
    }

    /// Sets held now.
    pub fn len(&self) -> usize {
        self.sets.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
