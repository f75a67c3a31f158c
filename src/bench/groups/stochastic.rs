//! The `stochastic` group: the stochastic estimators (`renderer::stochastic`) against the exact
//! modes and the engines' caps, over layouts from under one light a pixel to about forty, each
//! held against the bench's reference (brute force where it costs at most
//! `REFERENCE_FULLSCREEN_BUDGET` light-pixel pairs, plain volumes above).

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{CullingMode, Settings};

/// The group's name.
pub const STOCHASTIC_GROUP: &str = "stochastic";

/// RIS's samples a pixel the group sweeps.
pub const RIS_SAMPLES: [u32; 5] = [1, 2, 4, 8, 16];

/// RIS's candidates a sample: eight, so a sample's cost (eight unshadowed evaluations) is a
/// z-bin's or a cluster's walk at about eight lights a pixel.
pub const RIS_CANDIDATES: u32 = 8;

/// A layout of the group: its label, built-in scene, light count and radius factor.
pub struct Layout {
    pub label: &'static str,
    pub scene: &'static str,
    pub lights: usize,
    pub radius_scale: f64,
}

const fn wall(label: &'static str, lights: usize, radius_scale: f64) -> Layout {
    Layout { label, scene: "sphere-wall", lights, radius_scale }
}

/// The sphere wall's count sweep at range 5, its radius sweep at 1,024 lights, a dense wall,
/// `demo`, `railings` and `many-lights`.
pub const LAYOUTS: [Layout; 11] = [
    wall("wall 64", 64, 1.0),
    wall("wall 256", 256, 1.0),
    wall("wall 1024", 1024, 1.0),
    wall("wall 4096", 4096, 1.0),
    wall("wall 1024 r x0.5", 1024, 0.5),
    wall("wall 1024 r x2", 1024, 2.0),
    wall("wall 1024 r x4", 1024, 4.0),
    wall("wall 16384", 16384, 1.0),
    Layout { label: "demo", scene: "demo", lights: 1024, radius_scale: 1.0 },
    Layout { label: "railings", scene: "railings", lights: 1024, radius_scale: 1.0 },
    Layout { label: "many-lights", scene: "many-lights", lights: 100_000, radius_scale: 1.0 },
];

/// The exact modes of the group, each also with stochastic culling.
pub const EXACT_MODES: [CullingMode; 4] =
    [CullingMode::StencilInvert, CullingMode::Tiled, CullingMode::Clustered, CullingMode::Zbin];

pub fn rows(s: &Sweep) -> Vec<Config> {
    let base = &s.base;
    let mut v = Vec::new();
    let quick = s.o.quick;
    for l in LAYOUTS.iter().filter(|l| !quick || l.lights <= 1024) {
        let row = |label: String, settings: Settings| Config {
            scene: Some(l.scene),
            radius_scale: l.radius_scale,
            ..s.row(STOCHASTIC_GROUP, format!("{}: {label}", l.label), settings, l.lights)
        };
        for mode in EXACT_MODES {
            v.push(row(mode.name(), Settings { culling: mode, ..base.clone() }));
            let culled = Settings { culling: mode, stochastic_culling: true, ..base.clone() };
            v.push(row(format!("{} stochastic culling", mode.name()), culled));
        }
        for mode in [CullingMode::Clustered, CullingMode::Zbin] {
            for k in RIS_SAMPLES {
                let ris = Settings { culling: mode, ris_samples: k, ris_candidates: RIS_CANDIDATES, ..base.clone() };
                v.push(row(format!("{} RIS K{k}", mode.name()), ris));
            }
        }
        for e in crate::renderer::caps::ENGINES {
            if let Ok(settings) = crate::renderer::presets::engine_settings(e, base) {
                v.push(row(e.name.into(), settings));
            }
        }
    }
    v
}
