//! The frame's statistics, assembled from what each part reports: the configuration, the
//! plan (CPU), the path's passes, then the GPU's counts and times read back.

use super::culling::stats::{ForwardStats, LightStats};
use super::culling::tiled::TileStats;
use super::frame::{Prepared, Shape};
use super::inputs::pass::PassReport;
use super::kit::PipelineKey;
use super::paths::prepass_pass::PrepassStats;
use super::plan::LightPlan;
use super::post::effects::EFFECTS;
use super::post::PostStats;
use super::stats::{CpuMs, GpuMs, Readback, Span};
use super::CullingMode;
use super::{tiles, DebugView, Renderer, Settings, ShadowMode};
use crate::scene::Scene;
use anyhow::Result;
use serde::{Deserialize, Serialize};

impl Renderer {
    /// The statistics of the frame just submitted, its counts and times read back when
    /// `settings` asks for them.
    pub(super) fn report(
        &self,
        scene: &Scene,
        settings: &Settings,
        shape: &Shape,
        prepared: &Prepared,
        drawn: PassReport,
    ) -> Result<FrameStats> {
        let key = self.sets.current.key();
        let plan = &prepared.plan;
        let (forward_path, lit) = (shape.forward_path, settings.debug_view == DebugView::Lit);
        let post_options = settings.post_options();
        let mut cpu_ms = prepared.cpu_ms;
        (cpu_ms.upload, cpu_ms.wall) = (cpu_ms.upload + drawn.upload_ms.0, cpu_ms.wall + drawn.upload_ms.1);
        let mut stats = FrameStats {
            adapter: self.caps.report(super::support::fallbacks(&self.caps, key, settings, shape.chain)),
            size: [shape.size.0, shape.size.1],
            culling: settings.culling,
            lights: plan.lights.len(),
            calibration: self.calibration.describe(),
            gbuffer_layout: key.layout.name.to_string(),
            gbuffer_bytes_per_pixel: key.layout.bytes_per_pixel(),
            depth_stencil_format: format!("{:?}", key.depth_format),
            depth_read: self.depth_read(settings, key, forward_path),
            depth_clamp: key.depth_clamp,
            ambient_in_gbuffer: key.ambient_in_gbuffer,
            accumulation_format: format!("{:?}", key.accum_format),
            accumulation_bytes_per_pixel: key.accum_format.block_copy_size(None).unwrap_or(0)
                * if key.one_target() { 1 } else { 2 },
            light_cutoff: settings.light_cutoff,
            sphere_triangles: (self.volumes.sphere.indices.len() / 3) as u32,
            cone_triangles: (self.volumes.cone.indices.len() / 3) as u32,
            volume_meshes: plan.volume_meshes_drawn(),
            forward: plan.forward.clone().filter(|_| shape.blended).map(|f| ForwardStats {
                peel_layers: (settings.blended == crate::renderer::settings::BlendedMode::Peeled)
                    .then_some(settings.peel_layers),
                ..f
            }),
            draw_calls: drawn.light_draws,
            light_batches: if forward_path { 0 } else { plan.batches.batches.len() as u64 },
            forward_path: drawn.forward_path,
            lists_on_gpu: !forward_path && tiles::lists_on_gpu(plan),
            post: shape.chain.then_some(PostStats {
                bloom: settings.bloom,
                auto_exposure: settings.auto_exposure,
                tonemap: settings.tonemap,
                effects: match lit {
                    true => EFFECTS.iter().filter(|e| (e.on)(&post_options)).map(|e| e.name.to_string()).collect(),
                    false => Vec::new(),
                },
            }),
            cpu_ms,
            cpu_reused: prepared.reused,
            shadow: (settings.shadows != ShadowMode::None).then(|| prepared.shadows.stats.clone()),
            shader_lookups: key.features.names(),
            path: settings.path,
            prepass: drawn.prepass,
            stochastic: crate::renderer::stochastic::StochasticStats::of(
                &settings.stochastic_options(),
                &prepared.records.lights,
            ),
            ..Default::default()
        };
        let m = self.measured(settings, shape, prepared);
        // The per-light table only where the frame counts (its counts are per light) or asks.
        stats.per_light_stats = settings.count_fragments || settings.count_ideal || settings.per_light_stats;
        let plans = if stats.per_light_stats { &plan.lights[..] } else { &[] };
        let read = self.queries.read(&self.device, m.counts, m.ideal, m.times, m.forward)?;
        fill_from_queries(&mut stats, plans, scene, &read);
        for l in &mut stats.per_light {
            (l.shadow_tiles, l.shadow_texels, l.caster_draws) = prepared.shadows.light_share(l.index);
        }
        self.read_shadow_times(&mut stats)?;
        if let Some(fp) = stats.forward_path.as_mut() {
            self.scratch.forward.read(&self.device, fp, settings.count_fragments)?;
            let lists = (&prepared.path_lists, &plan.light_lists[..]);
            if let Some(counts) =
                self.scratch.forward.read_lights(&self.device, fp, lists.0, lists.1, plan.lights.len())?
            {
                for (l, n) in stats.per_light.iter_mut().zip(counts) {
                    l.shaded = Some(n);
                }
                stats.shaded_fragments = Some(stats.per_light.iter().filter_map(|l| l.shaded).sum());
            }
        } else {
            if let Some((tiles, pairs)) = self.scratch.tiled.read(&self.device)? {
                stats.tiles = Some(tiles);
                // The tile or cluster lists are the shading: each light's pairs are its shaded
                // count, replacing the empty occlusion counts of lights the light pass did not draw.
                if let Some(pairs) = pairs.filter(|_| plan.tiled.is_some()) {
                    for l in &mut stats.per_light {
                        l.shaded = pairs.get(l.index).copied();
                        l.coverage = None;
                    }
                    stats.shaded_fragments = Some(stats.per_light.iter().filter_map(|l| l.shaded).sum());
                    stats.coverage_fragments = None;
                    if let (Some(s), Some(i)) = (stats.shaded_fragments, stats.ideal_fragments) {
                        stats.efficiency = Some(if s == 0 { 1.0 } else { i as f64 / s as f64 });
                    }
                }
            }
        }
        self.ledger(&mut stats, plan.tiled);
        Ok(stats)
    }

    /// How the light passes read depth, in words: the depth buffer itself, a copy (and why
    /// not the buffer), or none.
    fn depth_read(&self, settings: &Settings, key: &PipelineKey, forward_path: bool) -> String {
        if forward_path {
            "none: the forward paths keep no G-buffer".into()
        } else if key.layout.reads_depth_buffer() {
            "depth buffer (its depth aspect; no copy)".into()
        } else if let Some(copy) = key
            .layout
            .targets
            .iter()
            .find(|t| t.channels.iter().flatten().any(|s| s.attr == super::kit::gbuffer::Attr::Depth))
        {
            let why = super::key::depth_read_refusal(settings, &self.caps).unwrap_or_else(|| "the layout".into());
            format!("{:?} copy ({why})", copy.format)
        } else {
            "none: the layout stores positions".into()
        }
    }

    /// Each shadowed light's and the sun's shadow time, from the shadow pass's timestamps.
    fn read_shadow_times(&self, stats: &mut FrameStats) -> Result<()> {
        for (owner, ms) in self.scratch.shadows.read(&self.device, self.queue.get_timestamp_period())? {
            use super::shadows::scratch::Owner;
            match owner {
                Owner::Light(i) => {
                    if let Some(l) = stats.per_light.get_mut(i) {
                        l.shadow_ms = Some(ms);
                    }
                }
                Owner::Sun => {
                    if let Some(sh) = stats.shadow.as_mut() {
                        sh.sun_ms = Some(ms);
                    }
                }
            }
        }
        Ok(())
    }

    /// The ledger's per-frame figures from the counts read back: each light's wasted pairs
    /// and its cost by the model for the frame's mode (`listed`: shaded from tile or cluster
    /// lists).
    fn ledger(&self, stats: &mut FrameStats, listed: Option<super::plan::Method>) {
        for l in &mut stats.per_light {
            l.wasted = l.shaded.zip(l.ideal).map(|(s, i)| s.saturating_sub(i));
        }
        let wasted: Option<u64> = stats.per_light.iter().map(|l| l.wasted).sum();
        stats.wasted_fragments = wasted.filter(|_| !stats.per_light.is_empty());
        if stats.shaded_fragments.is_none() || stats.forward_path.is_some() {
            return;
        }
        let pixels = stats.size[0] as f64 * stats.size[1] as f64;
        let model = self
            .cost_models
            .iter()
            .find(|(m, _)| *m == stats.culling)
            .map(|(_, c)| c.clone())
            .unwrap_or_else(|| super::explain::cost::CostModel::of(&self.calibration, listed, pixels));
        let mut sum = 0.0;
        for l in &mut stats.per_light {
            l.cost_ms = model.light_ms(l);
            sum += l.cost_ms.unwrap_or(0.0);
        }
        if let Some(measured) = stats.gpu_ms.lighting.filter(|_| sum + model.fixed_ms > 0.0) {
            let scale = measured / (sum + model.fixed_ms);
            for l in &mut stats.per_light {
                l.share_ms = l.cost_ms.map(|c| c * scale);
            }
        }
        stats.light_cost_ms = Some(sum);
        stats.cost_model = Some(model);
    }
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct FrameStats {
    /// The adapter, its capability table and the fallbacks this frame took.
    pub adapter: crate::renderer::kit::adapter::CapsReport,
    pub size: [u32; 2],
    pub culling: CullingMode,
    pub lights: usize,
    pub gpu_ms: GpuMs,
    /// The CPU's part of the frame: records, plan, upload.
    pub cpu_ms: CpuMs,
    /// The CPU's part (records, plans, clamps, shadow plan) and its upload were the frame
    /// before's, taken as they were: its inputs were the same (`frame::FrameKey`).
    #[serde(default)]
    pub cpu_reused: bool,
    pub shaded_fragments: Option<u64>,
    pub ideal_fragments: Option<u64>,
    /// Rasterised coverage of the shading draws (pipeline statistics), where supported.
    pub coverage_fragments: Option<u64>,
    /// ideal / shaded.
    pub efficiency: Option<f64>,
    /// shaded - ideal, summed over the lights (when both were counted).
    pub wasted_fragments: Option<u64>,
    /// The model the per-light `cost_ms` come from, and its sum over the lights with the
    /// fixed part apart (`light_cost_ms` + `cost_model.fixed_ms` against `gpu_ms.lighting`).
    pub cost_model: Option<crate::renderer::explain::cost::CostModel>,
    /// The cost model's constants `auto` and the ledger weighed with: "built-in defaults" or
    /// "<adapter key>, measured <date>" (`Calibration::describe`).
    pub calibration: String,
    pub light_cost_ms: Option<f64>,
    /// The forward pass of blended surfaces, when the frame drew one.
    pub forward: Option<ForwardStats>,
    /// The tiled pass's light lists, when the frame (or the `tile-lights` view) built them.
    pub tiles: Option<TileStats>,
    pub gbuffer_layout: String,
    /// Colour targets of the G-buffer (the depth-stencil buffer is named apart).
    pub gbuffer_bytes_per_pixel: u32,
    /// Samples that passed the G-buffer pass's depth test (deferred shading; the light
    /// pre-pass's pass 1): the fragments it wrote, overdraw included, which the draw order
    /// (`--draw-order`) changes. `None` without counting and on the forward paths.
    pub gbuffer_fragments: Option<u64>,
    pub depth_stencil_format: String,
    /// Where the passes after the G-buffer read depth: "depth buffer", or the copy and why
    /// (`key::depth_read_refusal`), or none (a layout storing positions; the forward
    /// paths).
    pub depth_read: String,
    pub depth_clamp: bool,
    /// Ambient + sun were written by the G-buffer pass (`Settings::ambient_in_gbuffer`, where
    /// the device allows), not by a full-screen pass of their own.
    pub ambient_in_gbuffer: bool,
    /// Format of the light accumulation targets.
    pub accumulation_format: String,
    /// Bytes per pixel of the accumulation targets: two (diffuse, specular), or one (the light
    /// pre-pass's light buffer, seed 000's RT1).
    pub accumulation_bytes_per_pixel: u32,
    /// `Settings::light_cutoff` this frame was drawn with.
    pub light_cutoff: f32,
    /// Triangles of the point lights' bounding sphere and of the spots' pyramid.
    pub sphere_triangles: u32,
    pub cone_triangles: u32,
    /// The bounding meshes the frame drew ("sphere", "cone"): only the kinds its lights need.
    pub volume_meshes: Vec<String>,
    /// Draws the light pass issued for lights: marking and shading draws and REPLACE's stencil
    /// clears (not the ambient + sun draw). With `count_fragments` each light's shading is a
    /// draw of its own (its occlusion query), so counted frames issue more.
    pub draw_calls: u64,
    /// Instanced draws (batches) the lights were grouped into (`batches.rs`); one per drawn
    /// light with `light_batching` off.
    pub light_batches: u64,
    /// The GPU built light lists this frame (tiled, zbin's masks, or clustered with
    /// `--cluster-build gpu`).
    #[serde(default)]
    pub lists_on_gpu: bool,
    /// Which post-chain passes ran (`None`: the frame was tonemapped by compose, no chain).
    pub post: Option<PostStats>,
    /// One entry per light when the frame counted or asked for them
    /// (`Settings::per_light_stats`); empty otherwise, and `per_light_stats` says which.
    pub per_light: Vec<LightStats>,
    /// Whether `per_light` was built this frame.
    #[serde(default)]
    pub per_light_stats: bool,
    /// The shadow and cookie lookups compiled into this frame's shaders, by name
    /// (`program::ShaderFeatures::names`): only those some light of the scene can need.
    #[serde(default)]
    pub shader_lookups: Vec<String>,
    /// The shadow atlas and who casts (`None` with `--shadows none`).
    #[serde(default)]
    pub shadow: Option<crate::renderer::shadows::ShadowStats>,
    /// The forward paths' passes, targets and lists (`None` on the other paths).
    pub forward_path: Option<super::paths::forward_pass::ForwardPathStats>,
    /// The render path the frame was drawn with.
    pub path: crate::renderer::RenderPath,
    /// The light pre-pass's own figures (`None` on the other paths).
    pub prepass: Option<PrepassStats>,
    /// What the engine-style caps dropped (`caps`); `None` with no cap set.
    #[serde(default)]
    pub caps: Option<crate::renderer::caps::CapStats>,
    /// The stochastic estimators the frame was drawn with (`stochastic`); `None` with neither.
    #[serde(default)]
    pub stochastic: Option<crate::renderer::stochastic::StochasticStats>,
    /// The frame's pipelines: declared by its passes, built before it recorded, and compiled
    /// while it recorded (a pipeline no pass declared; none when the declarations are whole).
    pub pipelines: Pipelines,
}

/// The frame's queries, read back, turned into its figures: the spans ([`fill_gpu_ms`]), the
/// forward and pre-pass counts, each light's counts.
fn fill_from_queries(stats: &mut FrameStats, plans: &[LightPlan], scene: &Scene, q: &Readback) {
    stats.per_light = plans
        .iter()
        .enumerate()
        .map(|(i, p)| LightStats {
            index: i,
            kind: match scene.lights[i] {
                crate::scene::Light::Point(_) => "point".into(),
                crate::scene::Light::Spot(_) => "spot".into(),
            },
            method: p.method,
            crosses_near: p.crosses_near,
            crosses_far: p.crosses_far,
            screen_share: p.screen_share,
            shaded: None,
            ideal: None,
            coverage: None,
            ..Default::default()
        })
        .collect();
    if !q.any() {
        return;
    }
    let (counts, ideal) = (q.counts, q.ideal);
    if q.times {
        fill_gpu_ms(stats, q);
    }
    if let Some(f) = stats.forward.as_mut().filter(|_| q.forward > 0) {
        let layers = f.peel_layers.map_or(1, |n| n as usize);
        f.fragments = Some((0..layers).map(|i| q.forward(i)).sum());
        if f.peel_layers.is_some() {
            f.unpeeled = Some(q.forward(layers));
        }
    }
    if counts && stats.path.keeps_gbuffer() {
        stats.gbuffer_fragments = Some(q.prepass(0));
    }
    if let Some(p) = stats.prepass.as_mut().filter(|_| counts) {
        p.base_fragments = Some(q.prepass(0));
        p.final_fragments = Some(q.prepass(1));
    }
    for (i, l) in stats.per_light.iter_mut().enumerate() {
        let (shaded, ideal_n, coverage) = q.light(i);
        if counts {
            l.shaded = Some(shaded);
        }
        if ideal {
            l.ideal = Some(ideal_n);
            if q.coverage {
                l.coverage = Some(coverage);
            }
        }
    }
    if counts {
        stats.shaded_fragments = Some(stats.per_light.iter().filter_map(|l| l.shaded).sum());
    }
    if ideal && q.coverage {
        stats.coverage_fragments = Some(stats.per_light.iter().filter_map(|l| l.coverage).sum());
    }
    if ideal {
        stats.ideal_fragments = Some(stats.per_light.iter().filter_map(|l| l.ideal).sum());
    }
    if let (Some(s), Some(i)) = (stats.shaded_fragments, stats.ideal_fragments) {
        stats.efficiency = Some(if s == 0 { 1.0 } else { i as f64 / s as f64 });
    }
}

/// The frame's GPU times from its timestamps: each pass's span, the light pre-pass's and the
/// forward pass's shares of the compose span, the forward paths' passes, the post chain's.
fn fill_gpu_ms(stats: &mut FrameStats, q: &Readback) {
    let span = |s: Span| q.span(s);
    let between = |a: Option<u32>, b: Option<u32>| q.between(a, b);
    use crate::renderer::paths::prepass_pass as prepass;
    use crate::renderer::surfaces::{blended as forward, compose, gbuffer};
    use crate::renderer::{culling, post, shadows};
    let (gbuffer, compose) = (gbuffer::SPAN, compose::SPAN);
    stats.gpu_ms.gbuffer = span(gbuffer);
    stats.gpu_ms.lighting = span(culling::light_pass::SPAN);
    stats.gpu_ms.compose = span(compose);
    stats.gpu_ms.lists = span(culling::tiled::pass::SPAN).filter(|_| stats.lists_on_gpu);
    if stats.stochastic.as_ref().is_some_and(|s| s.reuse) {
        use crate::renderer::stochastic::reuse;
        stats.gpu_ms.ris_candidates = span(reuse::CANDIDATES_SPAN);
        stats.gpu_ms.ris_spatial = span(reuse::SPATIAL_SPAN);
        stats.gpu_ms.ris_denoise =
            span(reuse::DENOISE_SPAN).filter(|_| stats.stochastic.as_ref().is_some_and(|s| s.denoise));
    }
    if stats.prepass.is_some() {
        // The light pre-pass has no compose: its pass 3 writes the HDR colour, and
        // what follows it (forward pass, tonemap or post chain) is the compose span.
        stats.gpu_ms.prepass_final = span(prepass::SPAN);
        stats.gpu_ms.compose = between(prepass::SPAN.end(), compose.end());
    }
    if stats.forward.is_some() {
        stats.gpu_ms.forward = span(forward::SPAN);
        // The forward pass runs between the HDR compose and the tonemap.
        if let (Some(c), Some(f)) = (stats.gpu_ms.compose, stats.gpu_ms.forward) {
            stats.gpu_ms.compose = Some((c - f).max(0.0));
        }
    }
    stats.gpu_ms.total = between(gbuffer.begin(), compose.end());
    if let Some(sh) = stats.shadow.as_mut().filter(|s| s.tiles > 0) {
        sh.gpu_ms = span(shadows::pass::SPAN);
        stats.gpu_ms.shadows = sh.gpu_ms;
    }
    if let Some(fp) = stats.forward_path.as_mut() {
        // The forward paths: each pass's own span; no light pass, and the G-buffer
        // only when the post chain needed it (one of the passes then).
        for p in &mut fp.passes {
            p.gpu_ms = p.span.and_then(span);
        }
        stats.gpu_ms.lighting = None;
        stats.gpu_ms.gbuffer = None;
        stats.gpu_ms.total = fp.passes.first().and_then(|p| p.span).and_then(|s| between(s.begin(), compose.end()));
    }
    if let (Some(t), Some(s)) = (stats.gpu_ms.total, stats.gpu_ms.shadows) {
        stats.gpu_ms.total = Some(t + s);
    }
    if let Some(p) = &stats.post {
        // The chain runs inside the compose span (HDR compose … its last pass).
        let g = &mut stats.gpu_ms;
        g.bloom = span(post::bloom::SPAN).filter(|_| p.bloom);
        g.exposure = span(post::exposure::SPAN).filter(|_| p.auto_exposure);
        g.tonemap = span(post::tonemap::SPAN);
        g.effects = post::effects::EFFECTS
            .iter()
            .filter(|e| p.ran(e.name))
            .filter_map(|e| Some((e.name.to_string(), span(Span(e.name))?)))
            .collect();
        let chain: f64 =
            [g.bloom, g.exposure, g.tonemap].iter().flatten().sum::<f64>() + g.effects.values().sum::<f64>();
        g.compose = g.compose.map(|c| (c - chain).max(0.0));
    }
}

/// The engine caps' figures of a frame: the camera caps' cut, and the entries the per-cluster
/// and per-object caps left out (`None` when no cap is set).
pub(super) fn cap_stats(
    cut: Option<crate::renderer::caps::CapStats>,
    settings: &Settings,
    prepared: &Prepared,
) -> Option<crate::renderer::caps::CapStats> {
    if cut.is_none() && settings.lights_per_cluster == 0 && settings.lights_per_object == 0 {
        return None;
    }
    let mut cut = cut.unwrap_or_default();
    if let Some(tiles::ClusterBuild::Cpu(lists)) = &prepared.plan.clusters {
        cut.cluster_entries_dropped = lists.capped;
    }
    cut.object_entries_dropped = prepared.path_lists.capped;
    Some(cut)
}

/// The pipelines of one frame (`FrameStats::pipelines`).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(default)]
pub struct Pipelines {
    /// Declared by the frame's passes (`inputs::pass::Pass::declare`).
    pub declared: usize,
    /// Of those, compiled by this frame before it recorded (the rest were built already).
    pub built: usize,
    /// Compiled while the frame recorded: a draw with a pipeline its pass did not declare.
    pub while_recording: usize,
    /// Microseconds this frame spent compiling the `built` ones (on the thread that drew it).
    pub build_us: u64,
}
