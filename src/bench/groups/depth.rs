//! The `depth` group: depth format x depth convention, the depth read, and the G-buffer's
//! z-only pass in each draw order.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{DepthFormat, Settings};

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let mut v = Vec::new();
    // Depth format x depth convention, on the bench's scene and on the far-origin hard case.
    let scenes: &[Option<&'static str>] = if q { &[None] } else { &[None, Some("far-origin")] };
    for &scene in scenes {
        for depth_format in DepthFormat::ALL {
            for reversed_z in [false, true] {
                if q && depth_format == DepthFormat::default() && !reversed_z {
                    continue; // the `volume` row
                }
                let label = format!(
                    "{}{}{}",
                    scene.map_or(String::new(), |s| format!("{s} ")),
                    depth_format.name(),
                    if reversed_z { " reversed-z" } else { "" }
                );
                let settings = Settings { depth_format, reversed_z, ..base.clone() };
                v.push(Config { scene, ..s.row("depth", label, settings, o.lights) });
            }
        }
    }
    // Seed 004's depth read: the depth buffer itself in place of the R32F copy (the base's
    // volume culling allows it; `key::depth_read_refusal`).
    let settings = Settings { depth_read: crate::renderer::DepthRead::Buffer, ..base.clone() };
    v.push(s.row("depth", "depth read buffer".into(), settings, o.lights));
    // Seed 003's 24-bit z-buffer read as a texture.
    let settings = Settings {
        depth_read: crate::renderer::DepthRead::Buffer,
        depth_format: DepthFormat::Depth24PlusStencil8,
        ..base.clone()
    };
    v.push(s.row("depth", "depth read buffer depth24".into(), settings, o.lights));
    // Seed 002's z-only pass before the G-buffer, in each draw order.
    for draw_order in [crate::renderer::DrawOrder::Material, crate::renderer::DrawOrder::FrontToBack] {
        for gbuffer_depth_prepass in [false, true] {
            let label = format!(
                "g-buffer z-only pass {} ({})",
                if gbuffer_depth_prepass { "on" } else { "off" },
                crate::renderer::settings::name_of(&draw_order)
            );
            let settings = Settings { gbuffer_depth_prepass, draw_order, ..base.clone() };
            v.push(s.row("depth", label, settings, o.lights));
        }
    }
    v
}
