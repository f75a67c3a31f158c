//! Every pass of the frame, by technique, built lazily for one configuration.

use crate::renderer::kit::{Lazy, PipelineKey, Shared};
use std::sync::Arc;

/// What a frame draws with, beyond the passes every frame uses (G-buffer, lights, debug,
/// compose, the forward paths' passes, measure, shadows).
#[derive(Clone, Copy, Debug, Default)]
pub struct Needs {
    /// Blended surfaces, a forward path, or the post chain (which runs after the forward pass).
    pub forward: bool,
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
    pub forward: Lazy<crate::renderer::surfaces::blended::ForwardPass>,
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
    pub fn new(device: &wgpu::Device, key: PipelineKey) -> Self {
        let source = crate::renderer::program::shader_source_for(
            &key.layout,
            key.accum_format,
            key.ambient_in_gbuffer,
            key.prepass,
            key.features,
        );
        let shared = Arc::new(Shared::new(device, key, source));
        Self {
            gbuffer: Lazy::new(device, &shared, crate::renderer::surfaces::gbuffer::GBufferPass::new),
            lights: Lazy::new(device, &shared, crate::renderer::culling::light_pass::LightPass::new),
            debug: Lazy::new(device, &shared, crate::renderer::surfaces::debug::DebugPass::new),
            compose: Lazy::new(device, &shared, crate::renderer::surfaces::compose::ComposePass::new),
            forward: Lazy::new(device, &shared, crate::renderer::surfaces::blended::ForwardPass::new),
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
            shared,
        }
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
        if needs.forward {
            self.forward.prepare()?;
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
