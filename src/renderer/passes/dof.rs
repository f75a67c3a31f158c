//! Depth of field (seed 003's fifth pass; after fog in seed 002's order): each pixel's circle of confusion from its view depth, CoC = aperture × |z − focus| / z px (at most `post::MAX_COC`), and a gather over a 32-tap disc of that diameter, taking only neighbours whose own CoC reaches the pixel (a sharp foreground does not smear over what is behind it). A pixel whose CoC is under half a pixel is copied unchanged.

use super::{post_draw, FrameInputs, LdrPipelines, Shared};
use crate::renderer::stats::Stamp;

pub struct DofPass {
    pipelines: LdrPipelines,
    view: wgpu::RenderPipeline,
}

impl DofPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let out = shared.key.output_format;
        Self {
            pipelines: LdrPipelines::new(device, shared, "dof", "fs_dof"),
            view: shared.fullscreen_pipeline(device, "dof view", &shared.post_layout, "fs_view_coc", out),
        }
    }

    /// Records the pass from `group`'s source into `view` (`last`: the frame's output).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        group: &wgpu::BindGroup,
        view: &wgpu::TextureView,
        last: bool,
    ) {
        let stamps = f.timestamps(Some(Stamp::DofBegin), Some(Stamp::DofEnd));
        post_draw(encoder, f, "dof", self.pipelines.get(last), view, group, stamps);
    }

    /// Records the pass's debug view into the output.
    pub fn encode_view(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        group: &wgpu::BindGroup,
        target: &wgpu::TextureView,
    ) {
        let stamps = f.timestamps(Some(Stamp::DofBegin), Some(Stamp::DofEnd));
        post_draw(encoder, f, "dof view", &self.view, target, group, stamps);
    }
}
