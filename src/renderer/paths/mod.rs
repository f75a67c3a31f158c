//! The rendering paths, a list of steps each ([`steps`]). A path's own passes come between the
//! shadows (which every path draws first) and the measurement passes (which every path ends
//! with); every step is a [`Pass`], so the frame declares the pipelines of all of them, builds
//! those, and only then records ([`record`]):
//! - [`deferred`]: deferred shading (Hargreaves & Harris, *Deferred Shading*, GDC 2004; seeds
//!   000-002): a G-buffer, lights as volumes over it, compose;
//! - [`light_prepass`]: deferred lighting (seeds 003, 004): normals + exponent, lights into a
//!   light buffer, the geometry again with its maps;
//! - [`forward`]: forward single- and multi-pass (seed 002): each object with its lights.
//!
//! The steps they share: the surfaces and lights ([`surfaces_and_lights`]), compose to the
//! output, and tone mapping or the post chain ([`finish`]).

pub mod deferred;
pub mod forward;
pub mod forward_pass;
pub mod forward_scratch;
pub mod light_prepass;
pub mod prepass_pass;

use crate::renderer::frame::passes::Passes;
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::options::{DebugView, RenderPath};
use anyhow::Result;

/// One step of the frame: a pass, and the debug group a capture shows it in.
pub struct Step<'a> {
    pub group: &'static str,
    pub pass: Box<dyn Pass + 'a>,
}

pub fn step<'a>(group: &'static str, pass: impl Pass + 'a) -> Step<'a> {
    Step { group, pass: Box::new(pass) }
}

/// The frame's steps: the shadows (each casting light's depth into its tiles of the atlas, on
/// every path), the path's own passes into the output, then the measurement passes (outside
/// the frame's timestamps: the ideal count and coverage).
pub fn steps<'a>(p: &'a Passes, f: &FrameInputs<'_>) -> Vec<Step<'a>> {
    let mut s = vec![step("shadows", &*p.shadows)];
    match f.options.frame.path {
        RenderPath::Deferred => deferred::steps(p, f, &mut s),
        RenderPath::LightPrepass => light_prepass::steps(p, f, &mut s),
        RenderPath::Forward | RenderPath::ForwardMultipass => forward::steps(p, f, &mut s),
    }
    s.push(step("measure", &*p.measure));
    s
}

/// The pipelines `steps` draw with.
pub fn declare(steps: &[Step<'_>], f: &FrameInputs<'_>) -> Declared {
    let mut out = Declared::default();
    for s in steps {
        s.pass.declare(f, &mut out);
    }
    out
}

/// Makes each step's buffers and targets, then records the steps, each inside its debug group
/// when `debug_groups` (a capture in RenderDoc, PIX or Xcode then shows the frame as these
/// named steps, each holding its labelled passes; `Gpu::encoder_debug_groups`).
pub fn record(
    steps: &[Step<'_>],
    f: &FrameInputs<'_>,
    encoder: &mut wgpu::CommandEncoder,
    debug_groups: bool,
) -> Result<PassReport> {
    for s in steps {
        s.pass.prepare(f)?;
    }
    let mut report = PassReport::default();
    for s in steps {
        if debug_groups {
            encoder.push_debug_group(s.group);
        }
        report.add(s.pass.encode(encoder, f)?);
        if debug_groups {
            encoder.pop_debug_group();
        }
    }
    Ok(report)
}

/// The first half both deferred paths share: the surface pass (the G-buffer, or the light
/// pre-pass's normals and exponent), every light with its culling method, the tiled and
/// clustered lights (lists, shading, the tile-lights view), and the stencil, complexity and
/// waste views; `labels` name the first two for a capture.
pub fn surfaces_and_lights<'a>(
    p: &'a Passes,
    f: &FrameInputs<'_>,
    (surfaces, lights): (&'static str, &'static str),
    s: &mut Vec<Step<'a>>,
) {
    s.push(step(surfaces, &*p.gbuffer));
    s.push(step(lights, &*p.lights));
    match p.tiled.get() {
        Some(t) => s.push(step("tiled and clustered lights", t)),
        None => f.scratch.tiled.clear(),
    }
    s.push(step("stencil and complexity views", &*p.debug));
    if f.options.frame.debug_view == DebugView::Waste && f.plan.tiled.is_none() {
        s.push(step("waste view", &*p.waste));
    }
}

/// From the HDR scene colour to the output: the post chain (seed 002's order: bloom,
/// auto-exposure, tone mapping, grading, fog, depth of field, vignette, anti-aliasing; each
/// skips itself when off, the last one writes the output) or the tonemap alone.
pub fn finish<'a>(p: &'a Passes, f: &FrameInputs<'_>, s: &mut Vec<Step<'a>>) {
    if f.targets.post.is_some() && f.shape.chain {
        s.push(step("post chain", super::post::Chain(p.chain())));
    } else {
        s.push(step("tonemap", super::surfaces::compose::Tonemap(&p.compose)));
    }
}
