//! Deferred shading (Hargreaves & Harris, *Deferred Shading*, GDC 2004; seeds 000-002):
//! 1. the G-buffer: every attribute the lights need, in one pass with multiple targets;
//! 2. the lights: ambient + sun full-screen, then each light with its culling method
//!    (`culling`), then the tiled/clustered lights' lists and one full-screen shading;
//! 3. the stencil diagram or complexity heatmap, when that view is shown;
//! 4. compose: diffuse x albedo + specular + emissive, tonemapped, or a debug view. With
//!    blended surfaces or the post chain, compose in HDR, shade the blended surfaces forward
//!    over it back to front (deferred shading cannot do transparency), then finish.

use super::{finish, step, surfaces_and_lights, Step};
use crate::renderer::frame::passes::Passes;
use crate::renderer::inputs::FrameInputs;
use crate::renderer::surfaces::compose::ComposeHdr;

pub fn steps<'a>(p: &'a Passes, f: &FrameInputs<'_>, s: &mut Vec<Step<'a>>) {
    surfaces_and_lights(p, f, ("gbuffer", "lights"), s);
    if (f.shape.chain && f.targets.post.is_some()) || f.shape.blended {
        s.push(step("compose (HDR)", ComposeHdr(&p.compose)));
        s.push(step("blended surfaces", &*p.blended));
        finish(p, f, s);
    } else {
        s.push(step("compose", &*p.compose));
    }
}
