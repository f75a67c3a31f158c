//! Forward shading of blended surfaces (seeds 002-004: deferred shading cannot do
//! transparency): back to front (alpha blending) or in scene order (seed 003's additive
//! blending, `BlendedMode`) over the HDR scene colour, depth tested against the G-buffer
//! pass's depth and not written, each fragment lit by the shorter of its object's and its
//! screen tile's light list (`plan::plan_draws`). Timed (`gpu_ms.forward`) and counted
//! (`forward.fragments`) as its own pass.

use crate::renderer::frame::inputs::FrameInputs;
use crate::renderer::kit::{Shared, HDR_FORMAT};
use crate::renderer::stats::Span;
use crate::renderer::surfaces::gbuffer::{surface_pipeline, SurfacePipe};

/// The blended surfaces' forward pass's timing (`gpu_ms.forward`).
pub const SPAN: Span = Span("forward");
use crate::renderer::targets::attachment;

pub struct ForwardPass {
    /// One- and two-sided.
    pipelines: [wgpu::RenderPipeline; 2],
    /// The light pre-pass's opaque toon objects (`DrawLists::forward_opaque`): the same shading
    /// written over pass 3's colour, one- and two-sided; built for the light pre-pass only.
    opaque: Option<[wgpu::RenderPipeline; 2]>,
}

impl ForwardPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let blended = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(if shared.key.additive_blended {
                crate::renderer::kit::ADD_BLENDED
            } else {
                wgpu::BlendState::ALPHA_BLENDING
            }),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        // The light pre-pass's `--msaa 4` draws blended surfaces into its multisampled colour.
        let samples = shared.key.samples;
        let p = |label, two_sided| {
            let pipe = SurfacePipe { samples, ..SurfacePipe::triangles(label, "fs_forward", two_sided, false) };
            surface_pipeline(device, shared, pipe, &blended)
        };
        let replace =
            [Some(wgpu::ColorTargetState { format: HDR_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL })];
        let o = |label, two_sided| {
            let pipe = SurfacePipe { samples, ..SurfacePipe::triangles(label, "fs_forward", two_sided, false) };
            surface_pipeline(device, shared, pipe, &replace)
        };
        Self {
            pipelines: [p("forward (blended)", false), p("forward (blended, two-sided)", true)],
            opaque: shared.key.prepass.then(|| [o("forward (opaque)", false), o("forward (opaque, two-sided)", true)]),
        }
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let Some((hdr_view, _)) = &f.targets.hdr else { return };
        // Multisampled (the light pre-pass's `--msaa 4`): over its samples, resolved again.
        let (color, depth) = match &f.targets.msaa {
            Some(ms) => (ms.color_attachment(hdr_view, None), &ms.depth),
            None => (attachment(hdr_view, None), &f.targets.depth),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward (blended)"),
            color_attachments: &[color],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: f.timestamps(Some(SPAN), Some(SPAN)),
            occlusion_query_set: f.forward_counts.then_some(&f.queries.forward),
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.frame.group, &[]);
        if f.forward_counts {
            pass.begin_occlusion_query(0);
        }
        if let Some(opaque) = &self.opaque {
            f.scene.draw(&mut pass, &f.plan.draws.forward_opaque, opaque);
        }
        f.scene.draw(&mut pass, &f.plan.draws.forward, &self.pipelines);
        if f.forward_counts {
            pass.end_occlusion_query();
        }
    }
}
