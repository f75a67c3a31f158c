//! Auto-exposure (seed 002's chain, after bloom): a compute pass builds the frame's luminance
//! histogram (`post::HIST_BINS` bins of log2 luminance), a second one takes its mean log2 and
//! moves the adapted value one fixed time step (`post::FRAME_DT`) towards it; the tonemap pass
//! multiplies the exposure by target / adapted. Stepped per frame, so runs are deterministic.

use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::{Declared, Shared};
use crate::renderer::post::PostTargets;
use crate::renderer::stats::Span;

/// Auto-exposure's timing (`gpu_ms.exposure`).
pub const SPAN: Span = Span("exposure");

pub struct ExposurePass {
    histogram: crate::renderer::kit::ComputePipe,
    adapt: crate::renderer::kit::ComputePipe,
}

impl ExposurePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe = |label, entry| {
            crate::renderer::kit::compute_pipe(device, label, Some(&shared.post_layout), &shared.module, entry)
        };
        Self { histogram: pipe("luminance histogram", "cs_histogram"), adapt: pipe("adapt exposure", "cs_adapt") }
    }

    fn runs(f: &FrameInputs<'_>) -> bool {
        f.options.post.auto_exposure || f.options.frame.debug_view == crate::renderer::DebugView::Histogram
    }

    /// What [`Self::encode`] dispatches with.
    pub fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if Self::runs(f) {
            out.add_all([&self.histogram, &self.adapt]);
        }
    }

    /// Records the histogram of `group`'s source image and the adaptation, when auto-exposure
    /// is on.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        post: &PostTargets,
        group: &wgpu::BindGroup,
    ) {
        if !Self::runs(f) {
            return;
        }
        let timestamp_writes = f.compute_timestamps(SPAN);
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("auto-exposure"), timestamp_writes });
        pass.set_bind_group(0, &f.frame.group, &[]);
        pass.set_bind_group(1, &f.targets.gbuffer_group, &[]);
        pass.set_bind_group(2, group, &[]);
        pass.set_pipeline(&self.histogram);
        pass.dispatch_workgroups(post.size.0.div_ceil(16), post.size.1.div_ceil(16), 1);
        pass.set_pipeline(&self.adapt);
        pass.dispatch_workgroups(1, 1, 1);
    }
}
