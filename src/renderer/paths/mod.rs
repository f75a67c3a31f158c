//! The rendering paths, a function each. A path records its own passes between the shadows
//! (which every path draws first) and the measurement passes (which every path ends with):
//! - [`deferred`]: deferred shading (Hargreaves & Harris, *Deferred Shading*, GDC 2004; seeds
//!   000-002): a G-buffer, lights as volumes over it, compose;
//! - [`light_prepass`]: deferred lighting (seeds 003, 004): normals + exponent, lights into a
//!   light buffer, the geometry again with its maps;
//! - [`forward`]: forward single- and multi-pass (seed 002): each object with its lights.
//!
//! The tail they share: the tiled/clustered shading after the drawn lights ([`tiled`]),
//! compose to the output ([`compose`]), and tone mapping or the post chain ([`finish`]).

pub mod deferred;
pub mod forward;
pub mod forward_pass;
pub mod forward_scratch;
pub mod light_prepass;
pub mod prepass_pass;

use super::frame::{Prepared, Shape};
use super::paths::forward_pass::ForwardPathStats;
use super::surfaces::compose::ComposeTarget;
use super::surfaces::compose::SPAN as COMPOSE;
use super::{post, RenderPath};
use crate::renderer::frame::passes::Passes;
use crate::renderer::inputs::FrameInputs;
use crate::scene::Scene;
use anyhow::Result;
use prepass_pass::PrepassStats;

/// What a path records from: the device, the passes, the frame's inputs and where it ends.
pub struct PathInputs<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub passes: &'a Passes,
    pub f: &'a FrameInputs<'a>,
    pub shape: &'a Shape,
    pub prepared: &'a Prepared,
    pub scene: &'a Scene,
    /// The output view, of the renderer's output format and the frame's size.
    pub target: &'a wgpu::TextureView,
    /// Group the frame's steps for captures ([`PathInputs::group`]).
    pub debug_groups: bool,
}

/// What a path's passes report for the frame's statistics.
#[derive(Default)]
pub struct Drawn {
    /// Light draw calls (the forward paths': their draws).
    pub draw_calls: u64,
    pub forward_path: Option<ForwardPathStats>,
    pub prepass: Option<PrepassStats>,
    /// CPU time the tiled/clustered lists cost while recording: (upload, wall) in ms.
    pub cpu_ms: (f64, f64),
}

/// Records `path`'s passes.
pub fn record(path: RenderPath, c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) -> Result<Drawn> {
    match path {
        RenderPath::Deferred => Ok(deferred::record(c, encoder)),
        RenderPath::LightPrepass => Ok(light_prepass::record(c, encoder)),
        // The same steps; the pass draws a list per object or a pair per (object, light).
        RenderPath::Forward | RenderPath::ForwardMultipass => forward::record(c, encoder),
    }
}

impl PathInputs<'_> {
    /// Records `steps` inside a debug group `name`: a capture (RenderDoc, PIX, Xcode) shows the
    /// frame as these named steps, each holding its labelled passes (where the adapter takes
    /// encoder debug groups: `Gpu::encoder_debug_groups`).
    pub fn group<R>(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        name: &str,
        steps: impl FnOnce(&mut wgpu::CommandEncoder) -> R,
    ) -> R {
        if !self.debug_groups {
            return steps(encoder);
        }
        encoder.push_debug_group(name);
        let out = steps(encoder);
        encoder.pop_debug_group();
        out
    }
}

/// Tiled / clustered shading: per-tile or per-cluster light lists, one full-screen shading
/// (when the plan has such lights). Returns the CPU ms it took (upload, wall).
fn tiled(c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) -> (f64, f64) {
    match c.passes.tiled.get() {
        Some(t) => c.group(encoder, "tiled and clustered lights", |e| t.encode(c.device, c.queue, e, c.f)),
        None => {
            c.f.scratch.tiled.clear();
            (0.0, 0.0)
        }
    }
}

/// The first half both deferred paths share: the surface pass (the G-buffer, or the light
/// pre-pass's normals and exponent), every light with its culling method, the tiled and
/// clustered lights, and the stencil and complexity views; `labels` name the first two for a
/// capture. Returns the light draws and the CPU ms the tiled lists' upload took.
pub fn surfaces_and_lights(
    c: &PathInputs<'_>,
    encoder: &mut wgpu::CommandEncoder,
    (surfaces, lights): (&str, &str),
) -> (u64, (f64, f64)) {
    let (p, f) = (c.passes, c.f);
    c.group(encoder, surfaces, |e| p.gbuffer.encode(e, f));
    let draw_calls = c.group(encoder, lights, |e| p.lights.encode(e, f));
    let cpu_ms = tiled(c, encoder);
    c.group(encoder, "stencil and complexity views", |e| p.debug.encode(e, f));
    if f.options.frame.debug_view == crate::renderer::DebugView::Waste && f.plan.tiled.is_none() {
        c.group(encoder, "waste view", |e| p.waste.encode(e, f));
    }
    (draw_calls, cpu_ms)
}

/// Compose straight into the output: the lit picture from the G-buffer and light buffers, or
/// the debug view the settings name.
pub fn compose(c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) {
    let to = ComposeTarget { view: c.target, size: c.shape.size, debug_view: c.f.options.frame.debug_view, slot: 0 };
    let stamps = c.f.timestamps(Some(COMPOSE), Some(COMPOSE));
    c.group(encoder, "compose", |e| c.passes.compose.encode(e, c.queue, c.f.targets, c.f.frame, &to, stamps));
}

/// From the HDR scene colour to the output: the post chain (seed 002's order: bloom,
/// auto-exposure, tone mapping, grading, fog, depth of field, vignette, anti-aliasing; each
/// skips itself when off, the last one writes the output) or the tonemap alone.
pub fn finish(c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) {
    if let Some(pt) = c.f.targets.post.as_ref().filter(|_| c.shape.chain) {
        let stamps = c.f.timestamps(None, Some(COMPOSE));
        c.group(encoder, "post chain", |e| post::encode_chain(e, c.f, &c.passes.chain(), pt, c.target, stamps));
    } else {
        c.group(encoder, "tonemap", |e| c.passes.compose.encode_tonemap(e, c.f, c.target));
    }
}
