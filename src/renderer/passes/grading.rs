//! Colour grading (seed 003's fifth pass; after tone mapping in seed 002's order): the
//! tonemapped colour through a 3D LUT (`--lut FILE.cube`, or `identity`), trilinear, in the
//! sRGB encoding LUTs are made for.

use super::{post_draw, FrameInputs, LdrPipelines, Shared};
use crate::renderer::stats::Stamp;

pub struct GradingPass {
    grade: LdrPipelines,
}

impl GradingPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        Self { grade: LdrPipelines::new(device, shared, "grading", "fs_grade") }
    }

    /// Records the grading of `group`'s source into `view` (`last`: the frame's output).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        group: &wgpu::BindGroup,
        view: &wgpu::TextureView,
        last: bool,
    ) {
        let stamps = f.timestamps(Some(Stamp::GradingBegin), Some(Stamp::GradingEnd));
        post_draw(encoder, f, "grading", self.grade.get(last), view, group, stamps);
    }
}
