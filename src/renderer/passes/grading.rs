//! Colour grading (seed 003's fifth pass; after tone mapping in seed 002's order): the
//! tonemapped colour through a 3D LUT (`--lut FILE.cube`, or `identity`), trilinear, in the
//! sRGB encoding LUTs are made for, into the output.

use super::{post_draw, FrameInputs, Shared};
use crate::renderer::post::PostTargets;
use crate::renderer::stats::Stamp;

pub struct GradingPass {
    grade: wgpu::RenderPipeline,
}

impl GradingPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let out = shared.key.output_format;
        Self { grade: shared.fullscreen_pipeline(device, "grading", &shared.post_layout, "fs_grade", out) }
    }

    /// Records the grading of `post.toned` into `target`, when a LUT is set.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        post: &PostTargets,
        target: &wgpu::TextureView,
    ) {
        if f.settings.lut.is_none() {
            return;
        }
        let stamps = f.timestamps(Some(Stamp::GradingBegin), Some(Stamp::GradingEnd));
        post_draw(encoder, f, "grading", &self.grade, target, &post.from_toned, stamps);
    }
}
