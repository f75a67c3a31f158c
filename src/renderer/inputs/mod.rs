//! What the frame's passes read: the targets, the scene's and the frame's buffers, the plan,
//! each technique's options, and this renderer's scratch (`scratch.rs`).

pub mod pass;
pub mod scratch;

use crate::renderer::options::Options;
use crate::renderer::plan::{ForwardPathLists, FramePlan};
use crate::renderer::records::{self, FrameBuffers};
use crate::renderer::scene_gpu::SceneGpu;
use crate::renderer::shadows::ShadowPlan;
use crate::renderer::stats::{Queries, Span};
use crate::renderer::targets::Targets;
use crate::renderer::volumes::Volumes;

/// Where a long frame reports its progress: (what, units done, units in all), called as the GPU
/// finishes each part (`FrameInputs::flush`). `Renderer::set_progress` sets it; `None`, the
/// default, keeps every frame one submission.
pub type Progress = std::sync::Arc<dyn Fn(&str, u64, u64) + Send + Sync>;

/// What a frame draws, decided from its settings and scene before anything is built
/// (`Shape::of_checked`, in `frame/`).
pub struct Shape {
    pub size: (u32, u32),
    /// A forward path (single- or multi-pass): no G-buffer unless the post chain reads one.
    pub forward_path: bool,
    /// The light pre-pass's lit pass 3 runs (the lit picture or a post view, not a buffer view).
    pub prepass_lit: bool,
    /// Blended surfaces are shaded forward over the HDR picture, in the final view only (the
    /// debug views show the G-buffer and its lighting, which hold no transparent surface).
    pub blended: bool,
    /// The post chain runs.
    pub chain: bool,
}

impl Shape {
    /// The frame draws into the HDR scene colour: the forward paths and the light pre-pass's
    /// pass 3 shade into it, blended surfaces are shaded over it, and the tonemap finishes it.
    pub fn hdr(&self) -> bool {
        self.blended || self.forward_path || self.prepass_lit
    }
}

/// What the frame's passes read: targets, scene, frame buffers, plan and what to measure.
pub struct FrameInputs<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub shape: &'a Shape,
    /// The frame's output, of the renderer's output format and the frame's size.
    pub output: &'a wgpu::TextureView,
    /// The scene's background colour (linear RGB, alpha 1).
    pub background: [f32; 4],
    /// The forward paths' object lists (and multi-pass's pairs); empty on the other paths.
    pub path_lists: &'a ForwardPathLists,
    /// Which lights cast into which tiles of the shadow atlas this frame.
    pub shadows: &'a ShadowPlan,
    pub targets: &'a Targets,
    pub scene: &'a SceneGpu,
    pub frame: &'a FrameBuffers,
    pub volumes: &'a Volumes,
    pub plan: &'a FramePlan,
    pub queries: &'a Queries,
    pub options: &'a Options,
    /// Count each light's shaded fragments (occlusion queries).
    pub counts: bool,
    /// Count the ideal and the coverage (measurement passes).
    pub ideal: bool,
    /// Write timestamps.
    pub times: bool,
    /// Count the forward pass's fragments (an occlusion query over the pass).
    pub forward_counts: bool,
    pub depth_clamp: bool,
    /// Per light, its first shadow tile and tile count this frame (`shadows::ShadowPlan::lights`;
    /// `records::NO_SHADOW` first: unshadowed).
    pub shadowed: &'a [(u32, u32)],
    /// This renderer's buffers the passes write and read back (the pass set is shared).
    pub scratch: &'a scratch::Scratch,
    /// The CPU's part is the frame before's, taken as it was (`Prepared::reused`): what the
    /// passes uploaded from it is on the GPU still, unless a buffer was made anew.
    pub reused: bool,
    /// Where a long step reports its progress (`None`: the frame is one submission).
    pub progress: Option<&'a Progress>,
    /// The steps are recorded inside debug groups (`paths::record`), which `flush` closes and
    /// reopens around its cut.
    pub debug_groups: bool,
    /// The frame's world to view and projection (RIS's temporal reuse reprojects with them).
    pub view: glam::DMat4,
    pub proj: glam::DMat4,
    /// The scene's light list (shared, copied on write: another list is another allocation).
    pub scene_lights: &'a std::sync::Arc<Vec<crate::scene::Light>>,
}

impl FrameInputs<'_> {
    /// Cuts the frame's recording in step `group`: submits what `encoder` holds, waits for the
    /// GPU to finish it, reports `done` of `total` units of `what` to `progress` (a step reports
    /// only with a sink), and goes on in a fresh encoder. The queue keeps the order, so the
    /// frame draws what it would in one submission; the wait is the progress's price, paid only
    /// by a frame with a sink whose step chose to report.
    pub fn flush(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &str,
        (what, done, total): (&str, u64, u64),
    ) -> anyhow::Result<()> {
        let Some(progress) = self.progress else { return Ok(()) };
        let next = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let mut done_part = std::mem::replace(encoder, next);
        if self.debug_groups {
            done_part.pop_debug_group();
            encoder.push_debug_group(group);
        }
        self.queue.submit([done_part.finish()]);
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| anyhow::anyhow!("device poll failed: {e}"))?;
        progress(what, done, total);
        Ok(())
    }

    /// Whether light `i` casts a shadow this frame.
    pub fn casts(&self, i: u32) -> bool {
        self.shadowed.get(i as usize).is_some_and(|&(first, _)| first != records::NO_SHADOW)
    }

    /// Timestamp writes when the frame is timed: the beginning of span `begin` at the start of
    /// the pass and/or the end of span `end` at its end (a span may begin in one pass and end
    /// in a later one).
    pub fn timestamps(&self, begin: Option<Span>, end: Option<Span>) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let (begin, end) = (begin.and_then(Span::begin), end.and_then(Span::end));
        if !self.times || (begin.is_none() && end.is_none()) {
            return None;
        }
        self.queries.timestamps.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        })
    }

    /// Span `span` over one compute pass.
    /// Timestamps for one of a run of compute passes that `span` covers: its beginning written
    /// by the `first`, its end by the `last`, none by those between.
    pub fn compute_timestamps_of_run(
        &self,
        span: Span,
        (first, last): (bool, bool),
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.compute_timestamps(span)
            .map(|t| wgpu::ComputePassTimestampWrites {
                beginning_of_pass_write_index: t.beginning_of_pass_write_index.filter(|_| first),
                end_of_pass_write_index: t.end_of_pass_write_index.filter(|_| last),
                ..t
            })
            .filter(|t| t.beginning_of_pass_write_index.is_some() || t.end_of_pass_write_index.is_some())
    }

    pub fn compute_timestamps(&self, span: Span) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let (begin, end) = (span.begin(), span.end());
        if !self.times || begin.is_none() {
            return None;
        }
        self.queries.timestamps.as_ref().map(|q| wgpu::ComputePassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        })
    }

    /// A full-screen render pass into the debug target (cleared), nothing else attached.
    pub fn debug_target_pass<'e>(&self, encoder: &'e mut wgpu::CommandEncoder, label: &str) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[crate::renderer::targets::attachment(
                &self.targets.debug_view,
                Some(wgpu::Color::TRANSPARENT),
            )],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// A render pass of per-light draws into the debug target (cleared), against the scene's
    /// depth with the stencil cleared, the light inputs bound: the debug views' and the waste
    /// view's.
    pub fn debug_view_pass<'e>(&self, encoder: &'e mut wgpu::CommandEncoder, label: &str) -> wgpu::RenderPass<'e> {
        let t = self.targets;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[crate::renderer::targets::attachment(&t.debug_view, Some(wgpu::Color::TRANSPARENT))],
            depth_stencil_attachment: Some(t.depth_attachment(true)),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.bind_light_inputs(&mut pass);
        pass
    }

    /// Frame buffers, the G-buffer and the light-volume meshes: what every light draw reads.
    pub fn bind_light_inputs(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.frame.group, &[]);
        pass.set_bind_group(1, &self.targets.gbuffer_group, &[]);
        self.volumes.bind(pass);
    }

    /// Depth value of the far plane (1, or 0 with reversed Z).
    pub fn far_depth(&self) -> f64 {
        if self.options.frame.reversed_z {
            0.0
        } else {
            1.0
        }
    }
}
