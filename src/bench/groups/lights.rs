//! The `lights` group: where each culling mode wins, over the light count.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{CullingMode, Settings};

/// The light counts the full sweep's `lights` group runs every mode at (plus the scene's spots),
/// up to Bevy's `many_lights` stress count.
pub const LIGHT_COUNTS: [usize; 6] = [64, 256, 1024, 4096, 16384, 100_000];
/// `fullscreen` runs in the `lights` group only up to this many lights: at 1280x720 each light is
/// 0.9 M fragments (~17 ns each on lavapipe), so 256 lights are ~4 s a frame and 16,384 would be
/// over four minutes.
pub const FULLSCREEN_MAX_LIGHTS: usize = 256;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, base) = (s.o, &s.base);
    let mut v = Vec::new();
    // Where each culling mode wins, over the light count: every mode at every count, but
    // `fullscreen` (every light over every pixel) only where a frame takes seconds, not minutes.
    // A file's added lights each reach past the model's centre (a dome around it), so their
    // cost grows much faster with the count than the demo's small lights.
    let counts: &[usize] = match (crate::scene::import::is_gltf_path(&o.scene), o.quick) {
        (_, _) if o.fixed_lights => &[],
        _ if !o.counts.is_empty() => &o.counts,
        (true, true) => &[16, 64],
        (true, false) => &[16, 64, 256],
        (false, true) => &[16, 1024],
        (false, false) => &LIGHT_COUNTS,
    };
    for &n in counts {
        for mode in CullingMode::ALL {
            if mode == CullingMode::Fullscreen && n > FULLSCREEN_MAX_LIGHTS {
                continue;
            }
            v.push(s.row("lights", format!("{} x{n}", mode.name()), Settings { culling: mode, ..base.clone() }, n));
        }
        // Clustered with its lists built on the GPU, so its culling share is measured (the
        // default CPU build's lists cost no GPU time).
        let gpu_lists = Settings {
            culling: CullingMode::Clustered,
            cluster_build: crate::renderer::settings::ClusterBuilder::Gpu,
            ..base.clone()
        };
        v.push(s.row("lights", format!("clustered gpu-lists x{n}"), gpu_lists, n));
    }
    v
}
