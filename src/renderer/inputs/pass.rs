//! The contract every pass of the frame keeps ([`Pass`]): it declares the pipelines the
//! frame's recording will draw with, so that the frame builds them all before it records
//! (`kit::Declared`), and it records with one signature and one report ([`PassReport`]).
//! Creating buffers, targets and pipelines happens before recording ([`Pass::prepare`],
//! [`Pass::declare`]), never inside [`Pass::encode`].

use super::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::options::RenderPath;
use crate::renderer::stats::Span;
use serde::{Deserialize, Serialize};

/// One pass of the frame (or a step of it that records several render or compute passes).
pub trait Pass {
    /// Makes or grows what the pass writes this frame (buffers, targets), before any pass of
    /// the frame records.
    fn prepare(&self, _f: &FrameInputs<'_>) -> anyhow::Result<()> {
        Ok(())
    }

    /// Adds every pipeline that [`Pass::encode`] will draw or dispatch with for `f`, and no
    /// other: the frame builds the declared set before it records, so recording compiles
    /// nothing, and a pipeline no frame of this shape draws is never built.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared);

    /// Records the pass.
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport>;
}

impl<T: Pass + ?Sized> Pass for &T {
    fn prepare(&self, f: &FrameInputs<'_>) -> anyhow::Result<()> {
        (**self).prepare(f)
    }

    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        (**self).declare(f, out)
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        (**self).encode(encoder, f)
    }
}

/// What a pass reports for the frame's statistics; the frame sums them ([`PassReport::add`]).
#[derive(Default)]
pub struct PassReport {
    /// Light draw calls (the light pass's marks, shades and stencil clears; a forward path's
    /// draws).
    pub light_draws: u64,
    /// CPU time of what the pass uploaded while it recorded: (over all threads, wall) in ms.
    pub upload_ms: (f64, f64),
    pub forward_path: Option<ForwardPathStats>,
    pub prepass: Option<PrepassStats>,
}

impl PassReport {
    pub fn add(&mut self, r: PassReport) {
        self.light_draws += r.light_draws;
        self.upload_ms.0 += r.upload_ms.0;
        self.upload_ms.1 += r.upload_ms.1;
        self.forward_path = self.forward_path.take().or(r.forward_path);
        self.prepass = self.prepass.take().or(r.prepass);
    }
}

/// One pass of a forward path as the frame's stats report it.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct PathPass {
    pub name: String,
    pub draw_calls: u64,
    /// Samples that passed the depth test (occlusion query; with MSAA, samples, not pixels),
    /// when counting.
    pub fragments: Option<u64>,
    pub gpu_ms: Option<f64>,
    /// The pass's timing.
    #[serde(skip)]
    pub span: Option<Span>,
    #[serde(skip)]
    pub(crate) query: Option<u32>,
    /// Counted draw by draw instead (the per-light counts): its draws' queries in the frame's
    /// draw-query set, summed into `fragments`.
    #[serde(skip)]
    pub(crate) draw_queries: Option<std::ops::Range<u32>>,
}

/// An intermediate target of a forward path and its bytes per pixel (all samples).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct PathTarget {
    pub name: String,
    pub bytes_per_pixel: u32,
}

/// What a forward path's frame did: its passes, its targets, its lists.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct ForwardPathStats {
    pub path: RenderPath,
    pub samples: u32,
    pub depth_prepass: bool,
    pub passes: Vec<PathPass>,
    pub targets: Vec<PathTarget>,
    /// Opaque and masked objects drawn, their light lists' entries summed, the longest.
    pub objects: usize,
    pub list_entries: u64,
    pub longest_list: u32,
    /// Multi-pass: (object, light) pairs drawn.
    pub pairs: u64,
    /// The post chain reads depth and normals (fog, depth of field, edge AA): the G-buffer pass
    /// ran for it alone (`gbuffer` in `frame::passes::Passes`).
    pub gbuffer_for_post: bool,
}

impl ForwardPathStats {
    /// Bytes per pixel of every intermediate target, summed.
    pub fn bytes_per_pixel(&self) -> u32 {
        self.targets.iter().map(|t| t.bytes_per_pixel).sum()
    }

    /// Draw calls of every pass, summed.
    pub fn draw_calls(&self) -> u64 {
        self.passes.iter().map(|p| p.draw_calls).sum()
    }
}

/// The light pre-pass's figures (`--path light-prepass`): its intermediate targets' bytes per
/// pixel and the draws and fragments of its geometry passes (1: normals + exponent, 3: final;
/// pass 2's are the frame's `draw_calls` and `shaded_fragments`).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct PrepassStats {
    /// Pass 1's normal + exponent target (Rgba8Unorm).
    pub normal_exp_bytes_per_pixel: u32,
    /// The depth copy pass 1 writes beside it (`gbuffer::prepass_layout`; R32Float, or R32Uint
    /// holding its bits where R32Float is not renderable).
    pub depth_copy_bytes_per_pixel: u32,
    /// The light buffer: format and bytes (Rgba16Float 8, seed 004's log Rgba8 4).
    pub light_buffer_format: String,
    pub light_buffer_bytes_per_pixel: u32,
    /// Pass 3's HDR scene colour (Rgba16Float).
    pub hdr_bytes_per_pixel: u32,
    /// Samples per pixel of pass 3 and the forward pass (`--msaa`).
    pub samples: u32,
    /// Their multisampled colour and depth (samples x (8 + depth's bytes), stencil not
    /// counted); 0 single-sampled.
    pub msaa_bytes_per_pixel: u32,
    /// Object draws of pass 1 and of pass 3.
    pub base_draw_calls: u64,
    pub final_draw_calls: u64,
    /// `--msaa 4`: the depth-only draws priming pass 3's samples with pass 1's list (pass 1's
    /// depth has one sample a pixel); 0 single-sampled, where pass 3 tests pass 1's depth.
    pub prime_draw_calls: u64,
    /// Samples that passed pass 1's and pass 3's depth tests (occlusion queries), when counting.
    pub base_fragments: Option<u64>,
    pub final_fragments: Option<u64>,
}
