//! The `forward` group: the forward pass's light lists and how blended surfaces are composited.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{BlendedMode, ForwardLights, Settings};

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, base) = (s.o, &s.base);
    let mut v = Vec::new();
    // The forward pass's light lists (the same picture each; its time is `forward_ms`; only
    // scenes with blended surfaces, e.g. `glass`, have a forward pass).
    for forward_lights in ForwardLights::ALL {
        let label = format!("forward {}", forward_lights.name());
        v.push(s.row("forward", label, Settings { forward_lights, ..base.clone() }, o.lights));
    }
    // How blended surfaces are composited: the rows above sort them (alpha); seed 003's
    // additive blending needs no sort, depth peeling (seed 002) a pass pair per layer.
    v.push(s.row(
        "forward",
        "blended additive".into(),
        Settings { blended: BlendedMode::Additive, ..base.clone() },
        o.lights,
    ));
    for peel_layers in [2, 4, 8] {
        let settings = Settings { blended: BlendedMode::Peeled, peel_layers, ..base.clone() };
        v.push(s.row("forward", format!("blended peeled x{peel_layers}"), settings, o.lights));
    }
    v
}
