//! Bloom (seed 002's "glow", first in its post chain): a bright pass (the part of each pixel
//! above `bloom_threshold`'s luminance) at half size, a 2×2-box downsample chain to 1/32, an
//! upsample chain back (each level half its own downsample, half the coarser result, 2×
//! bilinear), and the HDR colour plus `bloom_intensity` × the result. The chain conserves the
//! bright pass's light (see `post::bloom_energy_bound`).

use super::post_draw;
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::{Declared, Shared};
use crate::renderer::post::{PostTargets, BLOOM_LEVELS};
use crate::renderer::stats::Span;

/// Bloom's timing (`gpu_ms.bloom`).
pub const SPAN: Span = Span("bloom");

pub struct BloomPass {
    bright: crate::renderer::kit::RenderPipe,
    down: crate::renderer::kit::RenderPipe,
    up: crate::renderer::kit::RenderPipe,
    combine: crate::renderer::kit::RenderPipe,
}

impl BloomPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe =
            |label, fs| shared.fullscreen_pipeline(device, label, &shared.post_layout, fs, shared.key.post_format);
        Self {
            bright: pipe("bloom bright pass", "fs_bloom_bright"),
            down: pipe("bloom down", "fs_bloom_down"),
            up: pipe("bloom up", "fs_bloom_up"),
            combine: pipe("bloom combine", "fs_bloom_combine"),
        }
    }

    fn runs(f: &FrameInputs<'_>) -> bool {
        f.options.post.bloom || f.options.frame.debug_view == crate::renderer::DebugView::Bloom
    }

    /// What [`Self::encode`] draws with.
    pub fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if Self::runs(f) {
            out.add_all([&self.bright, &self.down, &self.up, &self.combine]);
        }
    }

    /// Records the chain when bloom is on; the result is `post.bloomed`.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>, post: &PostTargets) {
        if !Self::runs(f) {
            return;
        }
        post_draw(
            encoder,
            f,
            "bloom bright pass",
            &self.bright,
            &post.down[0],
            &post.bright,
            f.timestamps(Some(SPAN), None),
        );
        for k in 1..BLOOM_LEVELS {
            post_draw(encoder, f, "bloom down", &self.down, &post.down[k], &post.downs[k - 1], None);
        }
        for k in (0..BLOOM_LEVELS - 1).rev() {
            post_draw(encoder, f, "bloom up", &self.up, &post.up[k], &post.ups[k], None);
        }
        let end = f.timestamps(None, Some(SPAN));
        post_draw(encoder, f, "bloom combine", &self.combine, &post.bloomed_view, &post.combine, end);
    }
}
