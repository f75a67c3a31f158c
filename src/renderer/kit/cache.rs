//! A device's `wgpu::PipelineCache`, where the adapter has one (`Features::PIPELINE_CACHE`,
//! Vulkan): the device's pass pool holds it (`pool::PassPool::set_pipeline_cache`), each pass
//! set takes it when it is made (`Shared::pipeline_cache`), and the pipelines a set compiles
//! ([`super::Declared::build`] through `Passes::build_each`) are made through it: the set's
//! cache is this thread's for the length of the build ([`Scope`]). `crate::pipeline_cache`
//! loads and saves it for the viewer. A pipeline compiled outside a build (on its first draw)
//! is made without one.

use std::cell::RefCell;

thread_local! {
    static CURRENT: RefCell<Option<wgpu::PipelineCache>> = const { RefCell::new(None) };
}

/// While alive, pipelines compiled on this thread are made through its cache.
pub struct Scope(Option<wgpu::PipelineCache>);

/// Makes `cache` this thread's until the returned scope is dropped.
pub fn scope(cache: Option<wgpu::PipelineCache>) -> Scope {
    Scope(CURRENT.with(|c| c.replace(cache)))
}

impl Drop for Scope {
    fn drop(&mut self) {
        let before = self.0.take();
        CURRENT.with(|c| *c.borrow_mut() = before);
    }
}

/// The cache pipelines compiled on this thread now are made through.
pub fn current() -> Option<wgpu::PipelineCache> {
    CURRENT.with(|c| c.borrow().clone())
}
