//! The shadow pass. Draws every caster into each shadow tile of the atlas
//! (`shadows::plan` decides the tiles and which objects touch each), one viewport per tile,
//! before the G-buffer pass (which already adds the sun's light through the atlas). With
//! `--shadow-cube array`, cube faces go to the layers of the cube array instead.

use super::scratch::{Owner, ShadowTimes, Timers};
use super::{ShadowPlan, TileDraw};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::bindings;
use crate::renderer::kit::Declared;
use crate::renderer::kit::Shared;
use crate::renderer::stats::Span;

/// The shadow pass's timing (`gpu_ms.shadows`, before every path's first pass).
pub const SPAN: Span = Span("shadows");

pub struct ShadowPass {
    pipeline: crate::renderer::kit::RenderPipe,
    caster_bgl: wgpu::BindGroupLayout,
}

impl ShadowPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let caster_bgl = bindings::FRAME.layout_of(device, |slot| bindings::SHADOW_CASTER_SLOTS.contains(&slot));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow casters"),
            bind_group_layouts: &[Some(&caster_bgl)],
            immediate_size: 0,
        });
        let pipeline = crate::renderer::kit::render_pipe(
            device,
            crate::renderer::kit::RenderPipeDesc {
                label: "shadow casters".to_owned(),
                layout,
                module: shared.module.clone(),
                vs: "vs_shadow".to_owned(),
                buffers: vec![crate::renderer::kit::VertexBuffer {
                    stride: std::mem::size_of::<crate::scene::Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: wgpu::vertex_attr_array![0 => Float32x3].to_vec(),
                }],
                // Both faces cast: a thin wall or an open mesh stops light from either side.
                primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: shared.key.features.shadows.format.texture(),
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(("fs_shadow".to_owned(), Vec::new())),
            },
        );
        Self { pipeline, caster_bgl }
    }

    /// Clears the atlas to the far depth and draws each tile's casters, then (with
    /// `--shadow-cube array`) each cube face into its layer of the cube array, one render pass a
    /// layer; nothing when no tile. The pass's timestamps span all of them. A frame that counts
    /// (the ledger) with timestamps draws each light's tiles (and the sun's) in render passes of
    /// their own instead, each timed ([`Self::encode_timed`]).
    ///
    /// A costly frame with a progress sink (`Chunks`) splits the same draws into parts of about
    /// a fiftieth of the caster triangles, each submitted and waited for (`FrameInputs::flush`),
    /// reporting the shadow-map passes drawn.
    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<()> {
        let plan = f.shadows;
        f.scratch.shadows.clear();
        if plan.tiles.is_empty() {
            return Ok(());
        }
        let group = f.frame.caster_group(f.device, &self.caster_bgl);
        let mut chunks = Chunks::of(f, plan);
        if timed(f) {
            return self.encode_timed(encoder, f, plan, &group, &mut chunks);
        }
        let atlas: Vec<&TileDraw> = plan.draws.iter().filter(|d| d.layer.is_none()).collect();
        let faces: Vec<&TileDraw> = plan.draws.iter().filter(|d| d.layer.is_some()).collect();
        // (target, its draws): the atlas when it has tiles, then each cube face.
        let mut targets: Vec<(&wgpu::TextureView, Vec<&TileDraw>)> = Vec::new();
        if !atlas.is_empty() {
            targets.push((&f.frame.shadow_view, atlas));
        }
        for d in faces {
            let Some(view) = d.layer.and_then(|l| f.frame.shadow_cube_layers.get(l as usize)) else { continue };
            targets.push((view, vec![d]));
        }
        // Each target's draws in parts (one part without a progress sink): the first clears.
        let parts: Vec<(&wgpu::TextureView, bool, &[&TileDraw])> = targets
            .iter()
            .flat_map(|(view, draws)| {
                chunks.split(f, draws).into_iter().enumerate().map(move |(i, d)| (*view, i == 0, d))
            })
            .collect();
        let last = parts.len().saturating_sub(1);
        for (k, (view, clear, draws)) in parts.into_iter().enumerate() {
            let begin = (k == 0).then_some(SPAN);
            let end = (k == last).then_some(SPAN);
            let mut pass = begin_pass(encoder, view, clear, f.timestamps(begin, end));
            self.draw_tiles(&mut pass, f, plan, &group, draws);
            drop(pass);
            chunks.drawn(encoder, f, draws)?;
        }
        Ok(())
    }

    /// Draws `draws`' casters into `pass`, each tile through its viewport.
    fn draw_tiles(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        f: &FrameInputs<'_>,
        plan: &ShadowPlan,
        group: &wgpu::BindGroup,
        draws: &[&TileDraw],
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_vertex_buffer(0, f.scene.vertices.slice(..));
        pass.set_index_buffer(f.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        let objects = plan.params.sun[3].max(1);
        for d in draws {
            if d.objects.is_empty() {
                continue;
            }
            let (x, y, s) = (d.x as f32, d.y as f32, d.size as f32);
            pass.set_viewport(x, y, s, s, 0.0, 1.0);
            pass.set_scissor_rect(d.x, d.y, d.size, d.size);
            for &o in &d.objects {
                let Some((range, base)) = f.scene.draws.get(o as usize) else { continue };
                let instance = d.tile * objects + o;
                pass.draw_indexed(range.clone(), *base, instance..instance + 1);
            }
        }
    }

    /// The ledger's shadow pass: the atlas cleared by an empty pass that starts the span, then
    /// each owner's tiles (a light's, or the sun's cascades), atlas tiles and cube faces apart,
    /// in a render pass of its own timed by a pair of timestamps of [`ShadowTimes`], then an
    /// empty pass that ends the span. The same draws into the same tiles as [`Self::encode`],
    /// only split into more passes (each loads what the last stored).
    fn encode_timed(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        plan: &ShadowPlan,
        group: &wgpu::BindGroup,
        chunks: &mut Chunks,
    ) -> anyhow::Result<()> {
        let runs = owner_runs(plan);
        drop(begin_pass(encoder, &f.frame.shadow_view, true, f.timestamps(Some(SPAN), None)));
        // Made by `prepare`, before the frame records.
        let Some(timers) = f.scratch.shadows.timers_for(runs.len() as u32 * 2) else { return Ok(()) };
        let mut owners = Vec::with_capacity(runs.len());
        for (k, (o, layer, draws)) in runs.iter().enumerate() {
            let view = match layer {
                None => &f.frame.shadow_view,
                Some(l) => match f.frame.shadow_cube_layers.get(*l as usize) {
                    Some(v) => v,
                    None => continue,
                },
            };
            let writes = wgpu::RenderPassTimestampWrites {
                query_set: &timers.set,
                beginning_of_pass_write_index: Some(2 * k as u32),
                end_of_pass_write_index: Some(2 * k as u32 + 1),
            };
            let mut pass = begin_pass(encoder, view, layer.is_some(), Some(writes));
            self.draw_tiles(&mut pass, f, plan, group, draws);
            drop(pass);
            owners.push((*o, k as u32));
            chunks.drawn(encoder, f, draws)?;
        }
        drop(begin_pass(encoder, &f.frame.shadow_view, false, f.timestamps(None, Some(SPAN))));
        let n = runs.len() as u32 * 2;
        encoder.resolve_query_set(&timers.set, 0..n, &timers.resolve, 0);
        encoder.copy_buffer_to_buffer(&timers.resolve, 0, &timers.readback, 0, n as u64 * 8);
        f.scratch.shadows.pending(owners);
        Ok(())
    }
}

/// How a costly frame's shadow draws are cut into parts for its progress: `None` without a
/// progress sink or under both `COSTLY_TRIANGLES` and `COSTLY_PASSES` (one part, one
/// submission, as always).
struct Chunks {
    /// Caster triangles a part holds, at least.
    part: Option<u64>,
    /// Triangles and passes (tiles and faces) drawn since the last cut, and in all.
    since: u64,
    drawn: u64,
    total: u64,
}

impl Chunks {
    fn of(f: &FrameInputs<'_>, plan: &ShadowPlan) -> Chunks {
        let triangles: u64 = plan.draws.iter().map(|d| triangles(f, d)).sum();
        let passes = plan.draws.len() as u64;
        let costly = f.progress.is_some() && (triangles > super::COSTLY_TRIANGLES || passes > super::COSTLY_PASSES);
        let part = costly.then_some(triangles.div_ceil(50).max(1));
        Chunks { part, since: 0, drawn: 0, total: plan.draws.len() as u64 }
    }

    /// `draws` in parts of at least `part` triangles (each part one render pass).
    fn split<'d>(&self, f: &FrameInputs<'_>, draws: &'d [&'d TileDraw]) -> Vec<&'d [&'d TileDraw]> {
        let Some(part) = self.part else { return vec![draws] };
        let mut out = Vec::new();
        let (mut start, mut sum) = (0, 0);
        for (i, d) in draws.iter().enumerate() {
            sum += triangles(f, d);
            if sum >= part {
                out.push(&draws[start..=i]);
                (start, sum) = (i + 1, 0);
            }
        }
        if start < draws.len() {
            out.push(&draws[start..]);
        }
        out
    }

    /// Counts `draws` as drawn, and cuts the frame when the part is full.
    fn drawn(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        draws: &[&TileDraw],
    ) -> anyhow::Result<()> {
        let Some(part) = self.part else { return Ok(()) };
        self.since += draws.iter().map(|d| triangles(f, d)).sum::<u64>();
        self.drawn += draws.len() as u64;
        if self.since >= part || self.drawn == self.total {
            self.since = 0;
            f.flush(encoder, "shadows", ("shadow-map passes", self.drawn, self.total))?;
        }
        Ok(())
    }
}

/// Caster triangles of one tile's draws.
fn triangles(f: &FrameInputs<'_>, d: &TileDraw) -> u64 {
    d.objects.iter().filter_map(|&o| f.scene.draws.get(o as usize)).map(|(r, _)| r.len() as u64 / 3).sum()
}

impl Pass for ShadowPass {
    /// The ledger's timestamp queries, when the frame times each light's shadows.
    fn prepare(&self, f: &FrameInputs<'_>) -> anyhow::Result<()> {
        if !f.shadows.tiles.is_empty() && timed(f) {
            f.scratch.shadows.make_timers(f.device, owner_runs(f.shadows).len() as u32 * 2);
        }
        Ok(())
    }

    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if !f.shadows.tiles.is_empty() && !f.shadows.draws.is_empty() {
            out.add(&self.pipeline);
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.record(encoder, f)?;
        Ok(PassReport::default())
    }
}

/// The frame times each light's shadow draws apart (the ledger: counting with timestamps).
fn timed(f: &FrameInputs<'_>) -> bool {
    f.counts && f.times && f.queries.timestamps.is_some()
}

/// The plan's draws in runs of one owner and one target (the atlas, or one cube face).
fn owner_runs(plan: &ShadowPlan) -> Vec<(Owner, Option<u32>, Vec<&TileDraw>)> {
    let mut owner = vec![Owner::Sun; plan.draws.len()];
    for (i, &(first, count)) in plan.lights.iter().enumerate() {
        if first != super::NO_SHADOW {
            for o in owner.iter_mut().skip(first as usize).take(count as usize) {
                *o = Owner::Light(i);
            }
        }
    }
    let mut runs: Vec<(Owner, Option<u32>, Vec<&TileDraw>)> = Vec::new();
    for (d, &o) in plan.draws.iter().zip(&owner) {
        match runs.last_mut() {
            Some((ro, layer, draws)) if *ro == o && *layer == d.layer && d.layer.is_none() => draws.push(d),
            _ => runs.push((o, d.layer, vec![d])),
        }
    }
    runs
}

/// A render pass into shadow depth `view`, cleared to the far depth or loaded, timed by `writes`.
fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    clear: bool,
    writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    let load = if clear { wgpu::LoadOp::Clear(1.0) } else { wgpu::LoadOp::Load };
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("shadows"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations { load, store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: writes,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

impl ShadowTimes {
    /// Whether a timed frame has made the timestamp queries.
    pub fn made(&self) -> bool {
        self.timers.lock().map(|t| t.is_some()).unwrap_or(true)
    }

    fn clear(&self) {
        if let Ok(mut o) = self.owners.lock() {
            o.clear();
        }
    }

    fn pending(&self, owners: Vec<(Owner, u32)>) {
        if let Ok(mut o) = self.owners.lock() {
            *o = owners;
        }
    }

    /// The timestamp queries, if they hold `count` writes.
    fn timers_for(&self, count: u32) -> Option<std::sync::Arc<Timers>> {
        let slot = self.timers.lock().unwrap_or_else(|p| p.into_inner());
        slot.as_ref().filter(|t| t.capacity >= count).cloned()
    }

    /// Makes timestamp queries for at least `count` writes, unless those held are enough.
    fn make_timers(&self, device: &wgpu::Device, count: u32) {
        let mut slot = self.timers.lock().unwrap_or_else(|p| p.into_inner());
        if slot.as_ref().is_some_and(|t| t.capacity >= count) {
            return;
        }
        // wgpu's largest query set; a frame's passes stay far below it (two per casting light).
        let capacity = count.next_power_of_two().clamp(16, wgpu::QUERY_SET_MAX_QUERIES);
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: capacity as u64 * 8,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as B;
        let t = std::sync::Arc::new(Timers {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("shadow times"),
                ty: wgpu::QueryType::Timestamp,
                count: capacity,
            }),
            resolve: buffer("shadow times resolve", B::QUERY_RESOLVE | B::COPY_SRC),
            readback: buffer("shadow times readback", B::COPY_DST | B::MAP_READ),
            capacity,
        });
        *slot = Some(t);
    }

    /// Each owner's shadow ms in the last frame (its passes summed); empty when the frame did
    /// not time them. `period_ns`: the queue's timestamp period.
    pub fn read(&self, device: &wgpu::Device, period_ns: f32) -> anyhow::Result<Vec<(Owner, f64)>> {
        let owners = self.owners.lock().map_err(|_| anyhow::anyhow!("shadow times lock poisoned"))?.clone();
        let timers = self.timers.lock().map_err(|_| anyhow::anyhow!("shadow times lock poisoned"))?.clone();
        let (Some(t), Some(last)) = (timers, owners.iter().map(|o| o.1).max()) else { return Ok(Vec::new()) };
        let words: Vec<u64> = crate::renderer::kit::read_back(device, &t.readback, (2 * last as u64 + 2) * 8)?;
        let mut out: Vec<(Owner, f64)> = Vec::new();
        for &(o, k) in &owners {
            let (a, b) = (words[2 * k as usize], words[2 * k as usize + 1]);
            let ms = b.saturating_sub(a) as f64 * period_ns as f64 / 1e6;
            match out.iter_mut().find(|(w, _)| *w == o) {
                Some((_, sum)) => *sum += ms,
                None => out.push((o, ms)),
            }
        }
        Ok(out)
    }
}
