//! The `culling` group: every culling mode at the bench's light count.

use super::sweep::{Sweep, REFERENCE_FULLSCREEN_BUDGET};
use crate::bench::options::Config;
use crate::renderer::{CullingMode, Settings};

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, base) = (s.o, &s.base);
    let mut v = Vec::new();
    // `fullscreen` only while its frame stays within the reference's budget of light-pixel
    // pairs: at 100,000 lights and 1920x1080 it is 2e11 pairs, about 45 s a frame even on an
    // NVIDIA H200 (0.22 ns a pair measured there), and the reference is then `volume` anyway.
    let pairs = o.lights as f64 * o.size.0 as f64 * o.size.1 as f64;
    for mode in CullingMode::ALL {
        if mode == CullingMode::Fullscreen && pairs > REFERENCE_FULLSCREEN_BUDGET {
            continue;
        }
        v.push(s.row("culling", mode.name(), Settings { culling: mode, ..base.clone() }, o.lights));
    }
    v
}
