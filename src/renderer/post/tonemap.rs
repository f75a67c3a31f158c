//! Tone mapping (seed 002's chain, after auto-exposure): the exposure (the knob, times target /
//! adapted luminance with auto-exposure) and the chosen curve (`post::Tonemap`; formulas and
//! their sources in `post.wgsl`), into the output or, when grading follows, into
//! `post.toned`.

use super::post_draw;
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Shared;
use crate::renderer::stats::Span;

/// The tone mapping's timing (`gpu_ms.tonemap`).
pub const SPAN: Span = Span("tonemap");

pub struct TonemapPass {
    to_output: crate::renderer::kit::RenderPipe,
    to_post: crate::renderer::kit::RenderPipe,
    view_bloom: crate::renderer::kit::RenderPipe,
    view_histogram: crate::renderer::kit::RenderPipe,
}

impl TonemapPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let out = shared.key.output_format;
        let pipe = |label, fs, format| shared.fullscreen_pipeline(device, label, &shared.post_layout, fs, format);
        Self {
            to_output: pipe("post tonemap", "fs_post_tonemap", out),
            to_post: pipe("post tonemap (graded)", "fs_post_tonemap", shared.key.post_format),
            view_bloom: pipe("bloom view", "fs_view_bloom", out),
            view_histogram: pipe("histogram view", "fs_view_histogram", out),
        }
    }

    /// The bloom or histogram debug view's pipeline.
    pub fn view_pipeline(&self, f: &FrameInputs<'_>) -> &crate::renderer::kit::RenderPipe {
        if f.options.frame.debug_view == crate::renderer::DebugView::Bloom {
            &self.view_bloom
        } else {
            &self.view_histogram
        }
    }

    /// The tonemap's pipeline into the output (`last`) or into the chain's next image.
    pub fn pipeline(&self, last: bool) -> &crate::renderer::kit::RenderPipe {
        if last {
            &self.to_output
        } else {
            &self.to_post
        }
    }

    /// Records the bloom or histogram debug view into the output.
    pub fn encode_view(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        group: &wgpu::BindGroup,
        target: &wgpu::TextureView,
    ) {
        let pipeline = self.view_pipeline(f);
        let stamps = f.timestamps(Some(SPAN), Some(SPAN));
        post_draw(encoder, f, "post view", pipeline, target, group, stamps);
    }

    /// Records the tonemap of `group`'s source into `view` (`last`: the frame's output).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        group: &wgpu::BindGroup,
        view: &wgpu::TextureView,
        last: bool,
    ) {
        let pipeline = self.pipeline(last);
        let stamps = f.timestamps(Some(SPAN), Some(SPAN));
        post_draw(encoder, f, "post tonemap", pipeline, view, group, stamps);
    }
}
