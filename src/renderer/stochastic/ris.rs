//! Reservoir-resampled lighting's pipelines: the list modes' shading pass with `fs_tiled_ris`
//! (tile and cluster lists) or `fs_zbin_ris` (z-bins) instead of the exact walk (`ris.wgsl`).
//! They draw into the same targets with the same bindings as the exact shading, once per
//! frame (no chunks: a pixel visits M x K entries, not its list).

use crate::renderer::kit::RenderPipe;
use std::sync::OnceLock;

/// The two RIS shading pipelines, each built when a frame first draws with it.
#[derive(Default)]
pub struct RisPipes {
    lists: OnceLock<RenderPipe>,
    zbin: OnceLock<RenderPipe>,
}

impl RisPipes {
    /// The shading pipeline for z-bins (`zbin`) or tile and cluster lists, built from the list
    /// modes' module, layout and targets.
    pub fn get(
        &self,
        device: &wgpu::Device,
        (module, layout, targets): (&wgpu::ShaderModule, &wgpu::PipelineLayout, &[Option<wgpu::ColorTargetState>]),
        zbin: bool,
    ) -> &RenderPipe {
        let (cell, label, fs) = match zbin {
            true => (&self.zbin, "z-bin shade, RIS", "fs_zbin_ris"),
            false => (&self.lists, "tiled shade, RIS", "fs_tiled_ris"),
        };
        cell.get_or_init(|| {
            crate::renderer::kit::screen_pipeline(device, module, label, layout, ("vs_tiled", fs), targets)
        })
    }
}
