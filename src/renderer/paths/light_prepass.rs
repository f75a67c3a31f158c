//! Deferred lighting, the light pre-pass (seed 003 on a tile GPU; seed 004, Unity's path):
//! 1. normals + specular exponent (and depth) into a thin buffer;
//! 2. every light into the light buffer, each with its culling method (the stencil methods
//!    use pass 1's depth; tiled/clustered shade their lists into it);
//! 3. the geometry again with its maps, reading the light buffer, ambient + sun, into the HDR
//!    colour; then blended surfaces forward and the tonemap or the post chain, as deferred
//!    shading does. A debug view composes the buffers instead.

use super::{finish, step, surfaces_and_lights, Step};
use crate::renderer::frame::passes::Passes;
use crate::renderer::inputs::FrameInputs;

pub fn steps<'a>(p: &'a Passes, f: &FrameInputs<'_>, s: &mut Vec<Step<'a>>) {
    surfaces_and_lights(p, f, ("normals and exponent", "lights into the light buffer"), s);
    if f.shape.prepass_lit {
        s.push(step("geometry with the light buffer", &*p.prepass));
        s.push(step("blended surfaces", &*p.blended));
        finish(p, f, s);
    } else {
        s.push(step("compose", &*p.compose));
    }
}
