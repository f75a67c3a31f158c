//! The `near` group: seed 004's near-plane rule on a street-level camera.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::settings::NearLights;
use crate::renderer::{CullingMode, Settings};

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (q, base) = (s.o.quick, &s.base);
    // Seed 004's near-plane rule (lights crossing the near plane drawn full-screen) against
    // `auto` and plain volumes, on `street` (a street-level camera among 64 lights, several
    // crossing the near plane); `--quick` keeps the rule under `auto`. The last row is `auto`
    // without depth clamp, where the plan draws near-crossing volumes full-screen whatever the
    // rule (their faces clipped at the near plane have no depth bound).
    let near: &[(CullingMode, NearLights, bool)] = if q {
        &[(CullingMode::Auto, NearLights::Fullscreen, true)]
    } else {
        &[
            (CullingMode::Auto, NearLights::Volume, true),
            (CullingMode::Auto, NearLights::Fullscreen, true),
            (CullingMode::Volume, NearLights::Volume, true),
            (CullingMode::Volume, NearLights::Fullscreen, true),
            (CullingMode::Auto, NearLights::Volume, false),
        ]
    };
    let mut v = Vec::new();
    for &(mode, near_lights, depth_clamp) in near {
        let clamp = if depth_clamp { "" } else { ", no depth clamp" };
        let label = format!("street {} near {}{clamp}", mode.name(), near_lights.name());
        let settings = Settings { culling: mode, near_lights, depth_clamp, ..base.clone() };
        v.push(Config { scene: Some("street"), ..s.row("near", label, settings, 64) });
    }
    v
}
