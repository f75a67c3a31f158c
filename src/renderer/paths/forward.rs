//! Forward shading, single- and multi-pass (seed 002's comparison): no G-buffer (unless the
//! post chain reads one), the lit picture straight into the HDR colour (each object with its
//! light list in one draw, or one additive draw per object and light), then blended surfaces,
//! then the tonemap or the post chain.

use super::{finish, step, Step};
use crate::renderer::frame::passes::Passes;
use crate::renderer::inputs::FrameInputs;
use crate::renderer::paths::forward_pass::{post_reads_gbuffer, ForwardPaths};
use crate::renderer::RenderPath;

pub fn steps<'a>(p: &'a Passes, f: &FrameInputs<'_>, s: &mut Vec<Step<'a>>) {
    if post_reads_gbuffer(f.options.frame.debug_view, &f.options.post, f.shape.chain) {
        s.push(step("gbuffer (for the post chain)", &*p.gbuffer));
    }
    let name = if f.options.frame.path == RenderPath::Forward { "forward" } else { "forward multi-pass" };
    s.push(step(name, ForwardPaths { paths: &p.forward_paths, blended: &p.blended }));
    finish(p, f, s);
}
