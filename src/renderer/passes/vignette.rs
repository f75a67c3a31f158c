//! Vignette (seed 003's fifth pass): the picture darkened towards the corners by `vignette` (a smoothstep in the distance from the centre, 1 - strength at the corners).

use super::{post_draw, FrameInputs, LdrPipelines, Shared};
use crate::renderer::stats::Stamp;

pub struct VignettePass {
    pipelines: LdrPipelines,
}

impl VignettePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        Self { pipelines: LdrPipelines::new(device, shared, "vignette", "fs_vignette") }
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
        let stamps = f.timestamps(Some(Stamp::VignetteBegin), Some(Stamp::VignetteEnd));
        post_draw(encoder, f, "vignette", self.pipelines.get(last), view, group, stamps);
    }
}
