//! Forward shading, single- and multi-pass (seed 002's comparison): no G-buffer (unless the
//! post chain reads one), the lit picture straight into the HDR colour (each object with its
//! light list in one draw, or one additive draw per object and light), then blended surfaces,
//! then the tonemap or the post chain.

use super::{finish, Drawn, PathInputs};
use crate::renderer::paths::forward_pass::{post_reads_gbuffer, PathFrame};
use crate::renderer::RenderPath;
use anyhow::Result;

pub fn record(c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) -> Result<Drawn> {
    let (p, f) = (c.passes, c.f);
    let gbuffer_for_post = post_reads_gbuffer(f.options.frame.debug_view, &f.options.post, c.shape.chain);
    if gbuffer_for_post {
        c.group(encoder, "gbuffer (for the post chain)", |e| p.gbuffer.encode(e, f));
    }
    let frame = PathFrame {
        lists: &c.prepared.path_lists,
        background: c.prepared.records.camera.background,
        blended: c.shape.blended,
        gbuffer_for_post,
    };
    let name = if f.options.frame.path == RenderPath::Forward { "forward" } else { "forward multi-pass" };
    let stats = c.group(encoder, name, |e| p.forward_paths.encode(c.device, e, f, &frame, &p.forward))?;
    finish(c, encoder);
    Ok(Drawn { draw_calls: stats.draw_calls(), forward_path: Some(stats), ..Default::default() })
}
