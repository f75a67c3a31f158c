//! What every group's table is built from: the bench's options, the settings each row varies
//! one knob of, and the reference frame each row is measured against.

use crate::bench::options::{BenchOptions, Config};
use crate::renderer::{CullingMode, Settings, ShadowMode};

/// A reference frame is rendered with every light full-screen while lights x pixels stays under
/// this (about 40 s on lavapipe); above it the reference draws plain volumes, which every
/// culling test holds equal to full-screen within one 8-bit step (`tests/it/culling.rs`), so the
/// error figures stay those of the layout and accumulation, not of a culling approximation.
pub const REFERENCE_FULLSCREEN_BUDGET: f64 = 2.5e9;

/// The culling mode of the reference frame for `lights` lights at `size`.
pub fn reference_culling(lights: usize, size: (u32, u32)) -> CullingMode {
    if lights as f64 * size.0 as f64 * size.1 as f64 <= REFERENCE_FULLSCREEN_BUDGET {
        CullingMode::Fullscreen
    } else {
        CullingMode::Volume
    }
}

/// The sweep's common ground: the bench's options and the base settings.
pub struct Sweep<'a> {
    pub o: &'a BenchOptions,
    /// What every row changes one knob of.
    pub base: Settings,
}

impl<'a> Sweep<'a> {
    pub fn new(o: &'a BenchOptions) -> Self {
        // Timed frames do not count: counting splits every batch's shading draw into a draw per
        // light (its occlusion query). The counts come from a separate counted render. Unshadowed:
        // shadows are the `shadows` group's knob, so every other row differs from its (unshadowed)
        // reference in its own knob only, and the tables from before shadows were on by default
        // are reproduced by the same commands.
        let base = Settings {
            count_fragments: false,
            count_ideal: false,
            timestamps: true,
            shadows: ShadowMode::None,
            ..Settings::default()
        };
        Sweep { o, base }
    }

    /// A row of `group`: `settings` at `lights` lights, on the bench's scene at its size.
    pub fn row(&self, group: &'static str, label: String, settings: Settings, lights: usize) -> Config {
        Config { group, label, settings, lights, size: self.o.size, scene: None, radius_scale: 1.0, calibration: false }
    }
}
