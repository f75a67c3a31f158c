//! Every pass of the frame, by technique, built lazily for one configuration.

use crate::renderer::kit::pool::{PassPool, PoolSet};
use crate::renderer::kit::{Declared, Lazy, PipelineKey, Shared};
use anyhow::{bail, Result};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// What a frame draws with, beyond the passes every frame uses (G-buffer, lights, debug,
/// compose, the forward paths' passes, measure, shadows).
#[derive(Clone, Copy, Debug, Default)]
pub struct Needs {
    /// The blended surfaces' pass: blended surfaces, a forward path (which ends with it), or the
    /// post chain (which runs after it).
    pub blended: bool,
    /// The light pre-pass's lit pass 3.
    pub prepass: bool,
    /// Tiled or clustered shading, or the tile-lights view.
    pub tiled: bool,
    /// The post chain or one of its views.
    pub post: bool,
}

/// Every pass of the frame, built for one [`PipelineKey`].
pub struct Passes {
    pub shared: Arc<Shared>,
    pub gbuffer: Lazy<crate::renderer::surfaces::gbuffer::GBufferPass>,
    pub lights: Lazy<crate::renderer::culling::light_pass::LightPass>,
    pub debug: Lazy<crate::renderer::surfaces::debug::DebugPass>,
    pub compose: Lazy<crate::renderer::surfaces::compose::ComposePass>,
    pub blended: Lazy<crate::renderer::surfaces::blended::BlendedPass>,
    pub forward_paths: Lazy<crate::renderer::paths::forward_pass::ForwardPathsPass>,
    pub measure: Lazy<crate::renderer::surfaces::measure::MeasurePass>,
    pub prepass: Lazy<crate::renderer::paths::prepass_pass::PrepassFinalPass>,
    pub tiled: Lazy<crate::renderer::culling::tiled::pass::TiledPass>,
    pub bloom: Lazy<crate::renderer::post::bloom::BloomPass>,
    pub exposure: Lazy<crate::renderer::post::exposure::ExposurePass>,
    pub tonemap: Lazy<crate::renderer::post::tonemap::TonemapPass>,
    /// The effects after tone mapping (`effects::EFFECTS`).
    pub effects: Lazy<crate::renderer::post::effects::EffectsPass>,
    /// The distortion buffer's draws (`post::distortion`).
    pub distortion: Lazy<crate::renderer::post::distortion::DistortionPass>,
    pub shadows: Lazy<crate::renderer::shadows::pass::ShadowPass>,
    /// The viewer's shadow-atlas image (not part of the frame).
    pub atlas_view: Lazy<crate::renderer::shadows::atlas_view::AtlasViewPass>,
    /// Why each light lit a pixel (`explain`; not part of the frame).
    pub explain: Lazy<crate::renderer::explain::ExplainPass>,
    /// The ledger's waste view of the lights drawn one by one (built by the first frame that
    /// shows it).
    pub waste: Lazy<crate::renderer::explain::waste::WastePass>,
    /// Every light at every pixel, the culling oracle's reference (`explain::brute`; not part of
    /// the frame).
    pub brute: Lazy<crate::renderer::explain::brute::BrutePass>,
    /// Pipelines of this set compiled so far ([`Passes::build`]): the pool's estimate of the
    /// set's memory.
    compiled: AtomicU64,
}

impl PoolSet for Passes {
    fn compiled(&self) -> u64 {
        self.compiled.load(Ordering::Relaxed)
    }

    fn into_any(self: Arc<Self>) -> Arc<dyn std::any::Any + Send + Sync> {
        self
    }
}

impl Passes {
    /// The post chain's passes.
    pub fn chain(&self) -> crate::renderer::post::ChainPasses<'_> {
        crate::renderer::post::ChainPasses {
            bloom: &self.bloom,
            exposure: &self.exposure,
            tonemap: &self.tonemap,
            effects: &self.effects,
            distortion: &self.distortion,
        }
    }

    /// The shader module and layouts only; no pipeline is compiled here. The passes every frame
    /// may use (G-buffer, lights, debug, compose, the forward paths', measure, shadows) are built
    /// by the first frame ([`Passes::prepare`]), the others by the first frame that needs them,
    /// so a set whose configuration is replaced before it draws (`Renderer::new` builds one
    /// before it has seen a scene, whose shader features it guesses) compiles nothing.
    pub fn new(device: &wgpu::Device, key: PipelineKey, pipeline_cache: Option<wgpu::PipelineCache>) -> Self {
        let source = crate::renderer::program::shader_source_for(
            &key.layout,
            key.accum_format,
            key.ambient_in_gbuffer,
            key.prepass,
            key.features,
        );
        let shared = Arc::new(Shared { pipeline_cache, ..Shared::new(device, key, source) });
        Self {
            gbuffer: Lazy::new(device, &shared, crate::renderer::surfaces::gbuffer::GBufferPass::new),
            lights: Lazy::new(device, &shared, crate::renderer::culling::light_pass::LightPass::new),
            debug: Lazy::new(device, &shared, crate::renderer::surfaces::debug::DebugPass::new),
            compose: Lazy::new(device, &shared, crate::renderer::surfaces::compose::ComposePass::new),
            blended: Lazy::new(device, &shared, crate::renderer::surfaces::blended::BlendedPass::new),
            forward_paths: Lazy::new(device, &shared, crate::renderer::paths::forward_pass::ForwardPathsPass::new),
            measure: Lazy::new(device, &shared, crate::renderer::surfaces::measure::MeasurePass::new),
            prepass: Lazy::new(device, &shared, crate::renderer::paths::prepass_pass::PrepassFinalPass::new),
            tiled: Lazy::new(device, &shared, crate::renderer::culling::tiled::pass::TiledPass::new),
            bloom: Lazy::new(device, &shared, crate::renderer::post::bloom::BloomPass::new),
            exposure: Lazy::new(device, &shared, crate::renderer::post::exposure::ExposurePass::new),
            tonemap: Lazy::new(device, &shared, crate::renderer::post::tonemap::TonemapPass::new),
            effects: Lazy::new(device, &shared, crate::renderer::post::effects::EffectsPass::new),
            distortion: Lazy::new(device, &shared, crate::renderer::post::distortion::DistortionPass::new),
            shadows: Lazy::new(device, &shared, crate::renderer::shadows::pass::ShadowPass::new),
            atlas_view: Lazy::new(device, &shared, crate::renderer::shadows::atlas_view::AtlasViewPass::new),
            explain: Lazy::new(device, &shared, crate::renderer::explain::ExplainPass::new),
            waste: Lazy::new(device, &shared, crate::renderer::explain::waste::WastePass::new),
            brute: Lazy::new(device, &shared, crate::renderer::explain::brute::BrutePass::new),
            compiled: AtomicU64::new(0),
            shared,
        }
    }

    /// Compiles the pipelines of `declared` not compiled yet (declared by this set's passes),
    /// on this thread; how many it compiled.
    pub fn build(&self, declared: &Declared) -> usize {
        self.build_each(declared).into_iter().filter(|b| *b).count()
    }

    /// [`Passes::build`], saying for each declared pipeline whether this call compiled it.
    pub fn build_each(&self, declared: &Declared) -> Vec<bool> {
        let _cache = crate::renderer::kit::cache::scope(self.shared.pipeline_cache.clone());
        let now = declared.build_each();
        let n = now.iter().filter(|b| **b).count();
        self.compiled.fetch_add(n as u64, Ordering::Relaxed);
        now
    }

    pub fn key(&self) -> &PipelineKey {
        &self.shared.key
    }

    /// Builds the passes every frame uses and those `needs` names, where not built yet, inside
    /// an error scope (see [`Lazy::prepare`]).
    pub fn prepare(&self, needs: Needs) -> anyhow::Result<()> {
        self.gbuffer.prepare()?;
        self.lights.prepare()?;
        self.debug.prepare()?;
        self.compose.prepare()?;
        self.forward_paths.prepare()?;
        self.measure.prepare()?;
        self.shadows.prepare()?;
        if needs.blended {
            self.blended.prepare()?;
        }
        if needs.prepass {
            self.prepass.prepare()?;
        }
        if needs.tiled {
            self.tiled.prepare()?;
        }
        if needs.post {
            self.bloom.prepare()?;
            self.exposure.prepare()?;
            self.tonemap.prepare()?;
            self.effects.prepare()?;
        }
        Ok(())
    }
}

/// Pass sets kept for configurations other than the current one (layout, accumulation, depth
/// format and convention, depth clamp).
pub const PIPELINE_CACHE: usize = 8;

/// Builds a configuration's shader module and layouts, turning validation errors (a bad
/// layout, a module that fails naga's validation) into an error instead of a panic; the
/// pipelines compile later, each on its first draw (`kit::scoped`).
fn build_passes(device: &wgpu::Device, key: PipelineKey, pool: &PassPool) -> Result<Passes> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let p = Passes::new(device, key, pool.pipeline_cache());
    if let Some(e) = pollster::block_on(scope.pop()) {
        bail!("building the pipelines failed: {e}");
    }
    Ok(p)
}

/// A renderer's pass sets: the current configuration's, shared with the device's other
/// renderers, and those of recent other configurations.
pub struct PassSets {
    pub current: Arc<Passes>,
    /// Passes of recent other configurations, least recently used first: kept alive here even
    /// when the device's pool has let them go.
    pub cache: Vec<Arc<Passes>>,
    /// The device's pass sets.
    pool: Arc<PassPool>,
    /// A frame has been configured with `current`. The set `new` chooses before it sees a scene
    /// (so with the shader features the settings allow) is not kept in this renderer's cache
    /// when the first scene needs other ones.
    used: bool,
}

impl PassSets {
    pub fn new(device: &wgpu::Device, pool: &Arc<PassPool>, key: PipelineKey) -> Result<Self> {
        let current = pool.get(key.clone(), || build_passes(device, key, pool))?;
        Ok(Self { current, cache: Vec::new(), pool: pool.clone(), used: false })
    }

    /// Whether a set for `key` is built: this renderer's, or one the device's pool knows.
    pub fn has(&self, key: &PipelineKey) -> bool {
        self.current.key() == key || self.cache.iter().any(|p| p.key() == key) || self.pool.has(key)
    }

    /// Makes the set for `key` current. `None` when it already was; else whether only the
    /// shader features differ from the set drawn with before (the targets then stay).
    pub fn switch(&mut self, device: &wgpu::Device, key: PipelineKey) -> Result<Option<bool>> {
        let was_used = std::mem::replace(&mut self.used, true);
        if key == *self.current.key() {
            return Ok(None);
        }
        let only_features =
            was_used && PipelineKey { features: self.current.key().features, ..key.clone() } == *self.current.key();
        // Switching back to a configuration seen recently reuses its passes instead of
        // compiling them again (and on lavapipe, leaving the old compilation's memory behind).
        let next = match self.cache.iter().position(|p| *p.key() == key) {
            Some(i) => self.cache.remove(i),
            None => self.pool.get(key.clone(), || build_passes(device, key, &self.pool))?,
        };
        let previous = std::mem::replace(&mut self.current, next);
        // The set `new` chose before it saw a scene stays in the pool only.
        if was_used {
            self.cache.push(previous);
        }
        if self.cache.len() > PIPELINE_CACHE {
            self.cache.remove(0);
        }
        Ok(Some(only_features))
    }
}
