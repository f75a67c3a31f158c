//! The pass sets built on a device, by configuration, shared by every renderer on it.
//!
//! On lavapipe a pass set's first frame costs 0.7-1.8 s of pipeline compilation at 192x108, a
//! frame on built pipelines 10-150 ms, so a process that creates many renderers (the bench, one
//! per configuration, all alive at once; the test suite, on several threads) compiles each
//! configuration once. A set holds only pipelines and layouts, built once each (`kit::Lazy`,
//! `kit::Declared`); what a frame writes and reads back is each renderer's own, so renderers
//! share sets freely. The pool keeps the most recently used sets while their estimated host
//! memory stays within its budget ([`POOL_BYTES`] unless set): a set's estimate is its compiled
//! pipelines times the adapter's bytes per pipeline (`caps::Quirks::pipeline_bytes`) plus
//! [`SET_BYTES`]. A set dropped from the pool lives on while a renderer holds it, and is found
//! again by key while it does: a set one renderer built (the viewer's background compiles)
//! reaches another that asks for its key even when the pool has let it go in between.
//!
//! The device (`gpu.rs`) holds the pool without knowing what a pass set is: the sets are kept
//! as [`PoolSet`] and handed back as the type the renderer built them as.

use super::PipelineKey;
use anyhow::{anyhow, Result};
use std::any::Any;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// The pool's default budget: estimated host memory of the sets it keeps.
pub const POOL_BYTES: u64 = 512 << 20;
/// A set's own share of the estimate, beyond its pipelines (its shader module and layouts).
pub const SET_BYTES: u64 = 1 << 20;

/// What the pool keeps: a pass set that tells how many of its pipelines are compiled.
pub trait PoolSet: Any + Send + Sync {
    fn compiled(&self) -> u64;
    fn into_any(self: Arc<Self>) -> Arc<dyn Any + Send + Sync>;
}

type Set = (PipelineKey, Arc<dyn PoolSet>);

pub struct PassPool {
    sets: Mutex<Vec<Set>>,
    /// Sets let go, still held by a renderer while their handle upgrades.
    gone: Mutex<Vec<(PipelineKey, std::sync::Weak<dyn PoolSet>)>>,
    /// The budget in bytes; 0: [`POOL_BYTES`].
    budget: AtomicU64,
    /// Host memory a compiled pipeline holds on this adapter (an estimate).
    pipeline_bytes: u64,
    /// The device's pipeline cache, for the sets made from now on (`kit::cache`).
    pipeline_cache: Mutex<Option<wgpu::PipelineCache>>,
}

impl PassPool {
    pub fn new(pipeline_bytes: u64) -> Self {
        Self {
            sets: Mutex::default(),
            gone: Mutex::default(),
            budget: AtomicU64::new(0),
            pipeline_bytes,
            pipeline_cache: Mutex::default(),
        }
    }

    /// Keeps sets of at most `bytes` estimated host memory from now on (a process with one
    /// long-lived renderer, the viewer, keeps little: that renderer keeps its recent
    /// configurations itself).
    pub fn keep_bytes_at_most(&self, bytes: u64) {
        self.budget.store(bytes.max(1), Ordering::Relaxed);
    }

    fn budget(&self) -> u64 {
        match self.budget.load(Ordering::Relaxed) {
            0 => POOL_BYTES,
            n => n,
        }
    }

    /// A set's estimated host memory.
    fn set_bytes(&self, set: &dyn PoolSet) -> u64 {
        SET_BYTES + set.compiled() * self.pipeline_bytes
    }

    /// The set built for `key`, built now by `build` (and kept) if the pool has none. Sets
    /// used least recently are let go while the kept ones' estimate is over the budget (the
    /// one handed back always stays).
    pub fn get<T: PoolSet>(&self, key: PipelineKey, build: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
        let mut sets = self.sets.lock().unwrap_or_else(|e| e.into_inner());
        let mut gone = self.gone.lock().unwrap_or_else(|e| e.into_inner());
        gone.retain(|(_, w)| w.strong_count() > 0);
        let held = || gone.iter().find(|(k, _)| *k == key).and_then(|(_, w)| w.upgrade());
        let set = match sets.iter().rposition(|(k, _)| *k == key) {
            // Most recently used last.
            Some(i) => sets.remove(i).1,
            None => match held() {
                Some(set) => set,
                None => Arc::new(build()?) as Arc<dyn PoolSet>,
            },
        };
        gone.retain(|(k, _)| *k != key);
        sets.push((key, set.clone()));
        let mut total: u64 = sets.iter().map(|(_, s)| self.set_bytes(s.as_ref())).sum();
        while sets.len() > 1 && total > self.budget() {
            let (k, dropped) = sets.remove(0);
            total -= self.set_bytes(dropped.as_ref());
            gone.push((k, Arc::downgrade(&dropped)));
        }
        set.into_any().downcast::<T>().map_err(|_| anyhow!("the device's pass set for this key is of another type"))
    }

    /// Makes `cache` the one the sets made from now on compile through (`kit::cache`).
    pub fn set_pipeline_cache(&self, cache: Option<wgpu::PipelineCache>) {
        *self.pipeline_cache.lock().unwrap_or_else(|e| e.into_inner()) = cache;
    }

    /// The device's pipeline cache, if it has one.
    pub fn pipeline_cache(&self) -> Option<wgpu::PipelineCache> {
        self.pipeline_cache.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// Whether a set for `key` is held, by the pool or by a renderer it was handed to.
    pub fn has(&self, key: &PipelineKey) -> bool {
        let sets = self.sets.lock().unwrap_or_else(|e| e.into_inner());
        let gone = self.gone.lock().unwrap_or_else(|e| e.into_inner());
        sets.iter().any(|(k, _)| k == key) || gone.iter().any(|(k, w)| k == key && w.strong_count() > 0)
    }

    /// Sets held now.
    pub fn len(&self) -> usize {
        self.sets.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The estimated host memory of the sets held now.
    pub fn bytes(&self) -> u64 {
        let sets = self.sets.lock().unwrap_or_else(|e| e.into_inner());
        sets.iter().map(|(_, s)| self.set_bytes(s.as_ref())).sum()
    }
}
