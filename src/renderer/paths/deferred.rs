//! Deferred shading (Hargreaves & Harris, *Deferred Shading*, GDC 2004; seeds 000-002):
//! 1. the G-buffer: every attribute the lights need, in one pass with multiple targets;
//! 2. the lights: ambient + sun full-screen, then each light with its culling method
//!    (`culling`), then the tiled/clustered lights' lists and one full-screen shading;
//! 3. the stencil diagram or complexity heatmap, when that view is shown;
//! 4. compose: diffuse x albedo + specular + emissive, tonemapped, or a debug view. With
//!    blended surfaces or the post chain, compose in HDR, shade the blended surfaces forward
//!    over it back to front (deferred shading cannot do transparency), then finish.

use super::{compose, finish, surfaces_and_lights, Drawn, PathInputs};

pub fn record(c: &PathInputs<'_>, encoder: &mut wgpu::CommandEncoder) -> Drawn {
    let (p, f) = (c.passes, c.f);
    let (draw_calls, cpu_ms) = surfaces_and_lights(c, encoder, ("gbuffer", "lights"));
    if (c.shape.chain && f.targets.post.is_some()) || c.shape.blended {
        c.group(encoder, "compose (HDR)", |e| p.compose.encode_hdr(e, c.queue, f));
        c.group(encoder, "blended surfaces", |e| p.forward.encode(e, f));
        finish(c, encoder);
    } else {
        compose(c, encoder);
    }
    Drawn { draw_calls, cpu_ms, ..Default::default() }
}
