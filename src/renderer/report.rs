//! The frame's statistics, assembled from what each part reports: the configuration, the
//! plan (CPU), the path's passes, then the GPU's counts and times read back.

use super::frame::{Prepared, Shape};
use super::paths::Drawn;
use super::plan::Method;
use super::post::effects::EFFECTS;
use super::stats::{self, FrameStats};
use super::{tiles, DebugView, Renderer, Settings, ShadowMode};
use crate::scene::Scene;
use anyhow::Result;

impl Renderer {
    /// The statistics of the frame just submitted, its counts and times read back when
    /// `settings` asks for them.
    pub(super) fn report(
        &self,
        scene: &Scene,
        settings: &Settings,
        shape: &Shape,
        prepared: &Prepared,
        drawn: Drawn,
    ) -> Result<FrameStats> {
        let key = self.passes.key();
        let plan = &prepared.plan;
        let (forward_path, lit) = (shape.forward_path, settings.debug_view == DebugView::Lit);
        let mut cpu_ms = prepared.cpu_ms;
        (cpu_ms.upload, cpu_ms.wall) = (cpu_ms.upload + drawn.cpu_ms.0, cpu_ms.wall + drawn.cpu_ms.1);
        let mut stats = FrameStats {
            adapter: self.caps.report(super::support::fallbacks(&self.caps, key, settings, shape.chain)),
            size: [shape.size.0, shape.size.1],
            culling: settings.culling,
            lights: plan.lights.len(),
            gbuffer_layout: key.layout.name.to_string(),
            gbuffer_bytes_per_pixel: key.layout.bytes_per_pixel(),
            depth_stencil_format: format!("{:?}", key.depth_format),
            depth_read: if forward_path {
                "none: the forward paths keep no G-buffer".into()
            } else if key.layout.reads_depth_buffer() {
                "depth buffer (its depth aspect; no copy)".into()
            } else if let Some(copy) = key
                .layout
                .targets
                .iter()
                .find(|t| t.channels.iter().flatten().any(|s| s.attr == super::kit::gbuffer::Attr::Depth))
            {
                let why = super::kit::gbuffer::depth_read_refusal(settings, &self.caps, key.depth_format)
                    .unwrap_or_else(|| "the layout".into());
                format!("{:?} copy ({why})", copy.format)
            } else {
                "none: the layout stores positions".into()
            },
            depth_clamp: key.depth_clamp,
            ambient_in_gbuffer: key.ambient_in_gbuffer,
            accumulation_format: format!("{:?}", key.accum_format),
            accumulation_bytes_per_pixel: key.accum_format.block_copy_size(None).unwrap_or(0)
                * if key.one_target() { 1 } else { 2 },
            light_cutoff: settings.light_cutoff,
            sphere_triangles: (self.volumes.sphere.indices.len() / 3) as u32,
            cone_triangles: (self.volumes.cone.indices.len() / 3) as u32,
            volume_meshes: plan.volume_meshes_drawn(),
            forward: plan.forward.clone().filter(|_| shape.blended).map(|f| stats::ForwardStats {
                peel_layers: (settings.blended == crate::renderer::settings::BlendedMode::Peeled)
                    .then_some(settings.peel_layers),
                ..f
            }),
            draw_calls: drawn.draw_calls,
            light_batches: if forward_path { 0 } else { plan.batches.batches.len() as u64 },
            forward_path: drawn.forward_path,
            lists_on_gpu: !forward_path
                && (plan.tiled == Some(Method::Tiled)
                    || matches!(plan.clusters, Some(tiles::ClusterBuild::Gpu(_))) && plan.tiled.is_some()
                    || plan.tiled == Some(Method::Zbin) && plan.zbins.as_ref().is_some_and(|z| z.visible > 0)),
            post: shape.chain.then_some(stats::PostStats {
                bloom: settings.bloom,
                auto_exposure: settings.auto_exposure,
                tonemap: settings.tonemap,
                effects: match lit {
                    true => EFFECTS.iter().filter(|e| (e.on)(settings)).map(|e| e.name.to_string()).collect(),
                    false => Vec::new(),
                },
            }),
            cpu_ms,
            cpu_reused: prepared.reused,
            shadow: (settings.shadows != ShadowMode::None).then(|| prepared.shadows.stats.clone()),
            shader_lookups: key.features.names(),
            path: settings.path,
            prepass: drawn.prepass,
            ..Default::default()
        };
        let m = self.measured(settings, shape, prepared);
        // The per-light table only where the frame counts (its counts are per light) or asks.
        stats.per_light_stats = settings.count_fragments || settings.count_ideal || settings.per_light_stats;
        let plans = if stats.per_light_stats { &plan.lights[..] } else { &[] };
        self.queries.read(&self.device, &mut stats, plans, scene, m.counts, m.ideal, m.times, m.forward)?;
        for l in &mut stats.per_light {
            (l.shadow_tiles, l.shadow_texels, l.caster_draws) = prepared.shadows.light_share(l.index);
        }
        for (owner, ms) in self.scratch.shadows.read(&self.device, self.queue.get_timestamp_period())? {
            use super::shadows::pass::Owner;
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
            self.scratch.tiled.read(&self.device, &mut stats, plan.tiled)?;
        }
        self.ledger(&mut stats, plan.tiled.is_some());
        Ok(stats)
    }

    /// The ledger's per-frame figures from the counts read back: each light's wasted pairs
    /// and its cost by the model for the frame's mode (`listed`: shaded from tile or cluster
    /// lists).
    fn ledger(&self, stats: &mut FrameStats, listed: bool) {
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
            .unwrap_or_else(|| super::explain::cost::CostModel::builtin(listed, pixels));
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
