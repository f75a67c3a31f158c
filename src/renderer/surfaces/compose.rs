//! Compose (seed 002's final pass): diffuse x albedo + specular + emissive, tonemapped, or one
//! of the debug views. Scenes with blended surfaces compose into the HDR scene colour instead,
//! the forward pass draws over it, and `tonemap` finishes the frame.

use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{Shared, HDR_FORMAT};
use crate::renderer::records::{ComposeParams, FrameBuffers};
use crate::renderer::settings::DebugView;
use crate::renderer::stats::Span;

/// The compose's timing (`gpu_ms.compose`): from the compose to the frame's last pass (the
/// tonemap or the post chain's last), which ends it and `gpu_ms.total`.
pub const SPAN: Span = Span("compose");
use crate::renderer::targets::{attachment, Targets};

pub struct ComposePass {
    /// The lit picture only (`fs_compose`): the frame's own compose.
    compose: crate::renderer::kit::RenderPipe,
    /// The lit picture or any debug view (`fs_compose_view`).
    compose_view: crate::renderer::kit::RenderPipe,
    compose_hdr: crate::renderer::kit::RenderPipe,
    tonemap: crate::renderer::kit::RenderPipe,
}

/// Where and how to compose: the target, its size, the view and its parameter slot.
pub struct ComposeTarget<'a> {
    pub view: &'a wgpu::TextureView,
    pub size: (u32, u32),
    pub debug_view: DebugView,
    /// Slot 0 is the frame's own compose; the viewer's thumbnails use one slot per view.
    pub slot: u64,
}

impl ComposePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let out = shared.key.output_format;
        let pipe = |label, fs, format| shared.fullscreen_pipeline(device, label, &shared.compose_layout, fs, format);
        Self {
            compose: pipe("compose", "fs_compose", out),
            compose_view: pipe("compose (views)", "fs_compose_view", out),
            compose_hdr: pipe("compose (HDR)", "fs_compose_hdr", HDR_FORMAT),
            tonemap: shared.fullscreen_pipeline(device, "tonemap", &shared.tonemap_layout, "fs_tonemap", out),
        }
    }

    /// The pipeline that composes `view`.
    pub fn pipeline(&self, view: DebugView) -> &crate::renderer::kit::RenderPipe {
        if view == DebugView::Lit {
            &self.compose
        } else {
            &self.compose_view
        }
    }

    /// Records the compose into `to` (scaled from the G-buffer's size); its pipeline
    /// ([`ComposePass::pipeline`]) built before.
    pub fn encode_to(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        queue: &wgpu::Queue,
        targets: &Targets,
        frame: &FrameBuffers,
        to: &ComposeTarget<'_>,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let scale = [targets.width as f32 / to.size.0 as f32, targets.height as f32 / to.size.1 as f32];
        let offset = frame.compose_slot(queue, to.slot, ComposeParams { view: to.debug_view as u32, pad0: 0, scale });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("compose"),
            color_attachments: &[attachment(to.view, Some(wgpu::Color::BLACK))],
            depth_stencil_attachment: None,
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(self.pipeline(to.debug_view));
        pass.set_bind_group(0, &frame.group, &[]);
        pass.set_bind_group(1, &targets.gbuffer_group, &[]);
        pass.set_bind_group(2, &targets.compose_group, &[offset]);
        pass.draw(0..3, 0..1);
    }

    /// Composes the lit frame into the HDR scene colour (the start of the compose timing).
    fn encode_hdr(&self, encoder: &mut wgpu::CommandEncoder, queue: &wgpu::Queue, f: &FrameInputs<'_>) {
        let Some((hdr_view, _)) = &f.targets.hdr else { return };
        let offset =
            f.frame.compose_slot(queue, 0, ComposeParams { view: DebugView::Lit as u32, pad0: 0, scale: [1.0; 2] });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("compose (HDR)"),
            color_attachments: &[attachment(hdr_view, Some(wgpu::Color::BLACK))],
            depth_stencil_attachment: None,
            timestamp_writes: f.timestamps(Some(SPAN), None),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.compose_hdr);
        pass.set_bind_group(0, &f.frame.group, &[]);
        pass.set_bind_group(1, &f.targets.gbuffer_group, &[]);
        pass.set_bind_group(2, &f.targets.compose_group, &[offset]);
        pass.draw(0..3, 0..1);
    }

    /// Exposure and tonemapping of the HDR scene colour into `target` (the end of the compose
    /// timing).
    fn encode_tonemap(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>, target: &wgpu::TextureView) {
        let Some((_, hdr_group)) = &f.targets.hdr else { return };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("tonemap"),
            color_attachments: &[attachment(target, Some(wgpu::Color::BLACK))],
            depth_stencil_attachment: None,
            timestamp_writes: f.timestamps(None, Some(SPAN)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.tonemap);
        pass.set_bind_group(0, &f.frame.group, &[]);
        pass.set_bind_group(1, &f.targets.gbuffer_group, &[]);
        pass.set_bind_group(2, &f.targets.compose_group, &[0]);
        pass.set_bind_group(3, hdr_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The frame's compose straight into the output: the lit picture from the G-buffer and light
/// buffers, or the debug view the settings name.
impl Pass for ComposePass {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        out.add(self.pipeline(f.options.frame.debug_view));
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        let to = ComposeTarget { view: f.output, size: f.shape.size, debug_view: f.options.frame.debug_view, slot: 0 };
        let stamps = f.timestamps(Some(SPAN), Some(SPAN));
        self.encode_to(encoder, f.queue, f.targets, f.frame, &to, stamps);
        Ok(PassReport::default())
    }
}

/// The lit frame composed into the HDR scene colour, for blended surfaces and the post chain
/// to finish.
pub struct ComposeHdr<'a>(pub &'a ComposePass);

impl Pass for ComposeHdr<'_> {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if f.targets.hdr.is_some() {
            out.add(&self.0.compose_hdr);
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.0.encode_hdr(encoder, f.queue, f);
        Ok(PassReport::default())
    }
}

/// Exposure and tone mapping of the HDR scene colour into the output, when no post chain runs.
pub struct Tonemap<'a>(pub &'a ComposePass);

impl Pass for Tonemap<'_> {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if f.targets.hdr.is_some() {
            out.add(&self.0.tonemap);
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.0.encode_tonemap(encoder, f, f.output);
        Ok(PassReport::default())
    }
}
