//! Anti-aliasing, last in the chain: seed 002's edge-detect "intelligent blur" (edges where the second difference of 1/depth — zero across any plane — or the turn of the normal to a neighbour is large; the pixel blended with its four neighbours by the edge's strength) or FXAA (Lottes; the minimal console form: a luma contrast test, then a blend along the edge). Pixels off the mask are copied unchanged.

use super::{post_draw, FrameInputs, LdrPipelines, Shared};
use crate::renderer::stats::Stamp;

pub struct AaPass {
    pipelines: LdrPipelines,
    view: wgpu::RenderPipeline,
}

impl AaPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let out = shared.key.output_format;
        Self {
            pipelines: LdrPipelines::new(device, shared, "aa", "fs_aa"),
            view: shared.fullscreen_pipeline(device, "aa view", &shared.post_layout, "fs_view_edges", out),
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
        let stamps = f.timestamps(Some(Stamp::AaBegin), Some(Stamp::AaEnd));
        post_draw(encoder, f, "aa", self.pipelines.get(last), view, group, stamps);
    }

    /// Records the pass's debug view into the output.
    pub fn encode_view(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        group: &wgpu::BindGroup,
        target: &wgpu::TextureView,
    ) {
        let stamps = f.timestamps(Some(Stamp::AaBegin), Some(Stamp::AaEnd));
        post_draw(encoder, f, "aa view", &self.view, target, group, stamps);
    }
}
