//! Fog (seed 002's chain, after grading): distance fog with an exponential height falloff towards the background colour, by `post::fog_amount`'s formula from the G-buffer's view-space point. Background pixels are left as they are.

use super::{post_draw, FrameInputs, LdrPipelines, Shared};
use crate::renderer::stats::Stamp;

pub struct FogPass {
    pipelines: LdrPipelines,
}

impl FogPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        Self { pipelines: LdrPipelines::new(device, shared, "fog", "fs_fog") }
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
        let stamps = f.timestamps(Some(Stamp::FogBegin), Some(Stamp::FogEnd));
        post_draw(encoder, f, "fog", self.pipelines.get(last), view, group, stamps);
    }
}
