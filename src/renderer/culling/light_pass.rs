//! The light accumulation (seeds 000-002): ambient + sun full-screen, then every light with the
//! method its plan chose, additively into the diffuse and specular targets, in instanced
//! batches (`renderer::batches`).
//!
//! Each culling method's draws are its row of [`METHODS`] (`culling/methods.rs`).

use super::binning::{binned_bytes, LLVMPIPE_SCENE_BUDGET};
use crate::renderer::culling::methods::{self, Covers, Reference, StencilMethod, METHODS};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::{
    biased_in_fragment, face, stencil, Declared, DrawState, Faces, LightPipe, Out, Shared, Vs, NO_STENCIL,
};
use crate::renderer::plan::Method;
use crate::renderer::stats::{Span, LIGHTS_PER_QUERY_SET};
use wgpu::{CompareFunction as Cmp, StencilOperation as Op};

/// The lighting's timing (`gpu_ms.lighting`): from the first light draw to the last, or to
/// the end of the tiled pass when it shades the frame.
pub const SPAN: Span = Span("lights");

/// One method's pipelines.
struct MethodPipelines {
    method: &'static StencilMethod,
    mark: Option<crate::renderer::kit::RenderPipe>,
    /// Shading with the lights' shadow lookups (`fs_light`), and, with
    /// `ShadowCode::casters_apart`, without them (`fs_light_plain`) for lights that cast none
    /// this frame: `[plain, with lookups]`, the same pipeline twice otherwise.
    shade: [crate::renderer::kit::RenderPipe; 2],
    shade_crossing_near: Option<[crate::renderer::kit::RenderPipe; 2]>,
}

pub struct LightPass {
    ambient: crate::renderer::kit::RenderPipe,
    /// The G-buffer pass wrote ambient + sun: the accumulation is loaded, not started here.
    ambient_in_gbuffer: bool,
    /// By [`METHODS`]' order; `None` for the methods the light pass does not draw.
    methods: Vec<Option<MethodPipelines>>,
    /// Zeroes the stencil (REPLACE, every 255 batches).
    stencil_clear: crate::renderer::kit::RenderPipe,
    /// `ShadowCode::casters_apart`: lights that cast no shadow this frame draw with
    /// `fs_light_plain`.
    casters_apart: bool,
}

/// A batch's instances in runs of lights that cast a shadow this frame or not, in their order
/// (so every pixel still sums its lights in the same order), each run drawn with its own
/// pipeline. Without `apart`, one run, drawn with the lookups.
fn casting_runs(
    instances: std::ops::Range<u32>,
    lights: &[u32],
    f: &FrameInputs<'_>,
    apart: bool,
) -> Vec<(std::ops::Range<u32>, bool)> {
    if !apart {
        return vec![(instances, true)];
    }
    debug_assert_eq!(instances.len(), lights.len(), "a batch's instances are its lights");
    let mut runs: Vec<(std::ops::Range<u32>, bool)> = Vec::new();
    for (k, &light) in instances.zip(lights) {
        let casts = f.casts(light);
        match runs.last_mut() {
            Some((run, c)) if *c == casts => run.end = k + 1,
            _ => runs.push((k..k + 1, casts)),
        }
    }
    runs
}

impl LightPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe = |label, vs, fs, state, out| shared.light_pipeline(device, LightPipe { label, vs, fs, state, out });
        let fullscreen = DrawState { faces: Faces::Both, depth: Cmp::Always, stencil: NO_STENCIL };
        let apart = shared.key.features.shadows.casters_apart;
        let methods = METHODS
            .iter()
            .map(|row| {
                let s = row.draws.as_ref()?;
                let [label, mark_label, near_label] = row.labels;
                let vs = if s.fullscreen { Vs::Fullscreen } else { Vs::Volume };
                let shades = |label, vs, state: &DrawState| {
                    let lookups = pipe(label, vs, "fs_light", state.clone(), Out::Accumulate);
                    let plain = match apart {
                        true => pipe(label, vs, "fs_light_plain", state.clone(), Out::Accumulate),
                        false => lookups.clone(),
                    };
                    [plain, lookups]
                };
                Some(MethodPipelines {
                    method: s,
                    mark: s.mark.clone().map(|d| {
                        let fs = if biased_in_fragment(&d) { "fs_mark_both_faces" } else { "fs_no_color" };
                        pipe(mark_label, Vs::Volume, fs, d, Out::NoColor)
                    }),
                    shade: shades(label, vs, &s.shade),
                    shade_crossing_near: s.shade_crossing_near.as_ref().map(|d| shades(near_label, Vs::Volume, d)),
                })
            })
            .collect();
        let clear = face(Cmp::Always, Op::Zero, Op::Zero, Op::Zero);
        Self {
            ambient: pipe("ambient+sun", Vs::FullscreenPlain, "fs_ambient", fullscreen.clone(), Out::Replace),
            ambient_in_gbuffer: shared.key.ambient_in_gbuffer,
            methods,
            casters_apart: apart,
            stencil_clear: pipe(
                "stencil clear",
                Vs::FullscreenPlain,
                "fs_no_color",
                DrawState { stencil: stencil(clear, clear), ..fullscreen },
                Out::NoColor,
            ),
        }
    }

    fn pipelines(&self, m: Method) -> Option<&MethodPipelines> {
        self.methods.get(methods::order(m) as usize)?.as_ref()
    }

    /// Begins one render pass of the accumulation over query set `block` (when counting): the
    /// frame's `first` (which starts the accumulation and its time), a block's first (which
    /// clears the stencil: `clear_stencil`), or one that goes on where the last left off.
    fn begin<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        f: &'e FrameInputs<'_>,
        block: usize,
        (first, clear_stencil, end): (bool, bool, bool),
    ) -> wgpu::RenderPass<'e> {
        let t = f.targets;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("lights"),
            color_attachments: &t.accumulation(first && !self.ambient_in_gbuffer),
            depth_stencil_attachment: Some(t.depth_attachment(clear_stencil)),
            // The tiled pass ends the lighting's span when it shades the frame.
            timestamp_writes: f.timestamps(first.then_some(SPAN), (end && f.plan.tiled.is_none()).then_some(SPAN)),
            occlusion_query_set: if f.counts { f.queries.occlusion.get(block) } else { None },
            multiview_mask: None,
        });
        f.bind_light_inputs(&mut pass);
        if first && !self.ambient_in_gbuffer {
            pass.push_debug_group("ambient + sun");
            pass.set_pipeline(&self.ambient);
            pass.draw(0..3, 0..1);
            pass.pop_debug_group();
        }
        pass
    }

    /// Records the accumulation, the first render pass starting with ambient + sun unless the
    /// G-buffer pass wrote them, then the lights batch by batch (`FramePlan::batches`): per batch
    /// one instanced marking draw (stencil methods) and one instanced shading draw (with
    /// `casters_apart`, one per run of casting or other lights: [`casting_runs`]). A render
    /// pass holds one block of lights (an occlusion query set holds 4096).
    ///
    /// When counting, the shading draw is split into one draw per light (an instance range of
    /// one, same pipeline and stencil) inside the light's occlusion query: the batch's marks are
    /// already in the stencil and its lights' pixels are disjoint, so each light shades what it
    /// shades in the batched draw. Counting also starts a new render pass (stencil and
    /// accumulation kept) before any draw or query that would take llvmpipe's binned scene past
    /// `binning::LLVMPIPE_SCENE_BUDGET` (see there: a scene that fills while a query begins
    /// miscounts it), and the light pass's end time is then written by an empty pass of its own.
    /// Returns the light draws issued (marks, shades and stencil clears; not the ambient + sun
    /// draw).
    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> u64 {
        let n = f.plan.lights.len();
        let chunk = LIGHTS_PER_QUERY_SET;
        let blocks = n.div_ceil(chunk).max(1);
        let batches = &f.plan.batches;
        let cost = |i: usize, draws: u64| light_binned_bytes(f, i, draws);
        let mut replace_counter = 0u32;
        let mut draws = 0u64;
        for b in 0..blocks {
            let (first, last) = (b == 0, b + 1 == blocks);
            let block_start = b * chunk;
            // Without counting, one pass per block: the last one ends the lighting's time.
            let mut pass = self.begin(encoder, f, b, (first, true, last && !f.counts));
            let mut bytes = 0u64;
            // Starts a new pass of the same block when `more` bytes would overfill the scene.
            macro_rules! room_for {
                ($more:expr) => {
                    if f.counts {
                        let more = $more;
                        if bytes > 0 && bytes + more > LLVMPIPE_SCENE_BUDGET {
                            drop(pass);
                            pass = self.begin(encoder, f, b, (false, false, false));
                            bytes = 0;
                        }
                        bytes += more;
                    }
                };
            }
            if f.counts {
                // Skipped lights (outside the frustum) shade nothing here, nor do lights the
                // tiled pass shades (its own counts replace these): their count is zero.
                for i in block_start..((b + 1) * chunk).min(n) {
                    if methods::row(f.plan.lights[i].method).draws.is_none() {
                        room_for!(cost(i, 0));
                        pass.begin_occlusion_query((i - block_start) as u32);
                        pass.end_occlusion_query();
                    }
                }
            }
            let range = batches.blocks.get(b).cloned().unwrap_or_default();
            for batch in &batches.batches[range] {
                let Some(m) = self.pipelines(batch.method) else { continue };
                let (indices, base) = f.volumes.range(batch.volume);
                let instances = batch.instances();
                // Lights crossing the near plane are drawn as plain volumes, unmarked
                // (`methods::CROSSING_NEAR`).
                let near = m.shade_crossing_near.as_ref().filter(|_| batch.crosses_near);
                if let Some(mark) = m.mark.as_ref().filter(|_| near.is_none()) {
                    // The marking draw's triangles, binned where each light's rectangle falls.
                    room_for!(batches.lights_of(batch).iter().map(|&l| cost(l as usize, 1)).sum::<u64>());
                    if m.method.reference == Reference::PerLight {
                        // One value per batch: its lights never meet (see `batches.rs`).
                        if replace_counter == 255 {
                            pass.set_pipeline(&self.stencil_clear);
                            pass.draw(0..3, 0..1);
                            draws += 1;
                            replace_counter = 0;
                        }
                        replace_counter += 1;
                        pass.set_stencil_reference(replace_counter);
                    }
                    pass.set_pipeline(mark);
                    pass.draw_indexed(indices.clone(), base, instances.clone());
                    draws += 1;
                    if m.method.reference == Reference::Zero {
                        pass.set_stencil_reference(0);
                    }
                }
                let shade = near.unwrap_or(&m.shade);
                // Runs of the batch's lights that cast or not, in order, each with its pipeline
                // (without `casters_apart` both are the same: one run).
                let draw = |pass: &mut wgpu::RenderPass<'_>, instances: std::ops::Range<u32>, casts: bool| {
                    pass.set_pipeline(&shade[casts as usize]);
                    if m.method.reference == Reference::PerLight {
                        pass.set_stencil_reference(replace_counter);
                    }
                    if m.method.fullscreen {
                        pass.draw(0..3, instances);
                    } else {
                        pass.draw_indexed(indices.clone(), base, instances);
                    }
                };
                if f.counts {
                    // The occlusion query counts the shading draw's samples only.
                    for (k, &light) in instances.clone().zip(batches.lights_of(batch)) {
                        room_for!(cost(light as usize, 1));
                        pass.begin_occlusion_query(light - block_start as u32);
                        draw(&mut pass, k..k + 1, f.casts(light));
                        draws += 1;
                        pass.end_occlusion_query();
                    }
                } else {
                    for (run, casts) in casting_runs(instances, batches.lights_of(batch), f, self.casters_apart) {
                        draw(&mut pass, run, casts);
                        draws += 1;
                    }
                }
            }
            drop(pass);
            if last && f.counts {
                // The lighting's end time, after however many passes the budget asked for.
                drop(self.begin(encoder, f, b, (false, false, true)));
            }
        }
        draws
    }
}

impl Pass for LightPass {
    /// Walks the batches as [`Self::record`] draws them: ambient + sun unless the G-buffer
    /// pass wrote them, each batch's mark (unless it crosses the near plane) and its shading
    /// pipelines by which of its lights cast, and the stencil clear once REPLACE's references
    /// wrap past 255.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if !self.ambient_in_gbuffer {
            out.add(&self.ambient);
        }
        let batches = &f.plan.batches;
        let mut references = 0u32;
        for batch in &batches.batches {
            let Some(m) = self.pipelines(batch.method) else { continue };
            let near = m.shade_crossing_near.as_ref().filter(|_| batch.crosses_near);
            if let Some(mark) = m.mark.as_ref().filter(|_| near.is_none()) {
                if m.method.reference == Reference::PerLight {
                    if references == 255 {
                        out.add(&self.stencil_clear);
                        references = 0;
                    }
                    references += 1;
                }
                out.add(mark);
            }
            let shade = near.unwrap_or(&m.shade);
            if f.counts || self.casters_apart {
                for &light in batches.lights_of(batch) {
                    out.add(&shade[f.casts(light) as usize]);
                }
            } else {
                out.add(&shade[1]);
            }
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        Ok(PassReport { light_draws: self.record(encoder, f), ..Default::default() })
    }
}

/// Estimated bytes llvmpipe bins for light `i`'s `draws` draws (its query included): its
/// method's triangles over its screen rectangle (`binning::binned_bytes`).
fn light_binned_bytes(f: &FrameInputs<'_>, i: usize, draws: u64) -> u64 {
    let p = &f.plan.lights[i];
    let size = (f.targets.width, f.targets.height);
    let mesh = match p.volume {
        crate::renderer::VolumeKind::Sphere => &f.volumes.sphere,
        crate::renderer::VolumeKind::Cone => &f.volumes.cone,
    };
    match methods::row(p.method).covers {
        Covers::Screen => binned_bytes(p, size, draws, 1),
        Covers::Nothing => binned_bytes(p, size, 0, 0),
        Covers::Volume => binned_bytes(p, size, draws, mesh.indices.len() as u64 / 3),
    }
}
