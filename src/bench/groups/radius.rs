//! The `radius` group: every culling mode over the light radius.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{CullingMode, Settings};

/// The radius factors of the `radius` group.
pub const RADIUS_SCALES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let mut v = Vec::new();
    // Over the light radius: every mode with each light's radius scaled (the bench's light
    // count; a file's own lights are scaled too).
    let scales: &[f64] = if q { &[0.5, 2.0] } else { &RADIUS_SCALES };
    for &radius_scale in scales {
        for mode in CullingMode::ALL {
            let label = format!("{} r x{radius_scale}", mode.name());
            let settings = Settings { culling: mode, ..base.clone() };
            v.push(Config { radius_scale, ..s.row("radius", label, settings, o.lights) });
        }
    }
    v
}
