//! Deferred lighting, the light pre-pass (seed 003 on a tile GPU; seed 004, Unity's path):
//! 1. normals + specular exponent (and depth) into a thin buffer;
//! 2. every light into the light buffer, each with its culling method (the stencil methods
//!    use pass 1's depth; tiled/clustered shade their lists into it);
//! 3. the geometry again with its maps, reading the light buffer, ambient + sun, into the HDR
//!    colour; then blended surfaces forward and the tonemap or the post chain, as deferred
//!    shading does. A debug view composes the buffers instead.

use super::{compose, finish, surfaces_and_lights, Drawn, PathInputs};
use crate::renderer::paths::prepass_pass;

pub fn record(c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) -> Drawn {
    let (p, f) = (c.passes, c.f);
    let (draw_calls, cpu_ms) =
        surfaces_and_lights(c, encoder, ("normals and exponent", "lights into the light buffer"));
    let finals = if c.shape.prepass_lit {
        let bg = c.scene.background.as_dvec3();
        let background = wgpu::Color { r: bg.x, g: bg.y, b: bg.z, a: 1.0 };
        let finals = c.group(encoder, "geometry with the light buffer", |e| p.prepass.encode(e, f, background));
        c.group(encoder, "blended surfaces", |e| p.forward.encode(e, f));
        finish(c, encoder);
        finals
    } else {
        compose(c, encoder);
        (0, 0)
    };
    let stats = prepass_pass::stats(p.key(), c.prepared.plan.draws.gbuffer.len() as u64, finals);
    Drawn { draw_calls, cpu_ms, prepass: Some(stats), ..Default::default() }
}
