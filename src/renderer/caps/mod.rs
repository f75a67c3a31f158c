//! Engine-style caps: the shortcuts engines ship that change the picture, as knobs whose error
//! the bench measures against the reference (`bench::engines`).
//!
//! - **Lights per camera** (`max-lights`): the frame keeps at most N lights, chosen by
//!   [`CapOrder`]; the rest are not sent at all, as an engine's light limit does (Unity URP: 256
//!   visible lights on desktop, 32 on mobile; PlayCanvas: 255; Filament: 255; Bevy on WebGL2:
//!   256).
//! - **A distance cut-off** (`light-distance`): a light whose sphere lies wholly beyond D of the
//!   eye is dropped.
//! - **Lights per cluster** (`lights-per-cluster`): each cluster list of the clustered mode keeps
//!   at most K lights, chosen per cell by [`CapOrder`] (three.js's tiled lighting keeps the
//!   first 8 lights that touch a 32-pixel tile).
//! - **Lights per object** (`lights-per-object`): each object's list on the forward paths keeps
//!   at most K lights (Unity URP's forward path: 8 per object).
//! - **The cluster grid** (`cluster-tile`, `cluster-budget`, `cluster-slices`,
//!   `first-slice-depth`): tiles and slices as an engine lays them out (Bevy: 4,096 cells over
//!   24 slices, the first slice from the eye to 5 units). A grid alone never changes the picture
//!   (the lists are conservative in any grid); with a per-cluster cap it decides how many lights
//!   share a list.
//!
//! A cap that is not reached changes nothing: the same lights in the same order, the same
//! picture, bit for bit (`tests/it/caps.rs`). A cap that is reached drops exactly what it states
//! in [`CapStats`].

pub use crate::renderer::options::caps::CapOrder;
use crate::scene::{Camera, Light, Scene};
use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What the caps dropped in one frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CapStats {
    /// The scene's lights the frame kept, by index, when a camera cap dropped any (the frame's
    /// per-light figures index this list).
    pub kept: Option<Vec<u32>>,
    /// Lights dropped by `max-lights` and by `light-distance`.
    pub dropped_by_count: u32,
    pub dropped_by_distance: u32,
    /// (cell, light) entries the per-cluster cap left out of the lists.
    pub cluster_entries_dropped: u64,
    /// (object, light) entries the per-object cap left out of the forward lists.
    pub object_entries_dropped: u64,
}

impl CapStats {
    /// Whether any cap dropped anything.
    pub fn reached(&self) -> bool {
        self.dropped_by_count + self.dropped_by_distance > 0
            || self.cluster_entries_dropped > 0
            || self.object_entries_dropped > 0
    }
}

/// The peak luminance of a light (colour x intensity).
pub fn peak(light: &Light) -> f64 {
    let (c, i) = match light {
        Light::Point(p) => (p.color, p.intensity),
        Light::Spot(s) => (s.color, s.intensity),
    };
    (c * i).dot(crate::scene::luminance_weights()) as f64
}

/// Irradiance at distance `d` from a light of peak luminance `peak` and radius `r`, with the
/// renderer's falloff (1 - (d/r)^2)^2 (no cosine: the surface's facing is not known).
pub fn irradiance_at(peak: f64, d: f64, r: f64) -> f64 {
    if d >= r || r <= 0.0 {
        return 0.0;
    }
    let x = d / r;
    peak * (1.0 - x * x).powi(2)
}

/// Whether a sphere may be seen by `camera` at aspect ratio `aspect`: not wholly behind the
/// near plane, beyond the far plane or outside a side plane.
fn sphere_in_view(camera: &Camera, aspect: f64, centre: DVec3, r: f64) -> bool {
    let v = camera.to_view(centre);
    let depth = -v.z;
    if depth + r < camera.near || depth - r > camera.far {
        return false;
    }
    let ty = (camera.fov_y * 0.5).tan();
    let tx = ty * aspect;
    // Side planes through the eye with inward normals (cos, sin) in the xz and yz planes.
    let side = |t: f64, a: f64| {
        let n = (1.0 + t * t).sqrt();
        (depth * t - a.abs()) / n >= -r
    };
    side(tx, v.x) && side(ty, v.y)
}

/// The camera caps' choice for one frame: the indices of the lights kept (in scene order), and
/// how many each cap dropped. `None` when no camera cap is set.
pub fn camera_cut(scene: &Scene, max_lights: u32, distance: f32, order: CapOrder, aspect: f64) -> Option<CapStats> {
    if max_lights == 0 && distance <= 0.0 {
        return None;
    }
    let eye = scene.camera.position;
    let mut kept: Vec<u32> = (0..scene.lights.len() as u32).collect();
    let mut stats = CapStats::default();
    if distance > 0.0 {
        let before = kept.len();
        kept.retain(|&i| {
            let l = &scene.lights[i as usize];
            (l.position() - eye).length() - l.radius() as f64 <= distance as f64
        });
        stats.dropped_by_distance = (before - kept.len()) as u32;
    }
    if max_lights > 0 && kept.len() > max_lights as usize {
        // Lights out of view go last: an engine culls them before its limit counts.
        let key = |i: u32| -> (bool, f64) {
            let l = &scene.lights[i as usize];
            let (c, r) = (l.position(), l.radius() as f64);
            let seen = sphere_in_view(&scene.camera, aspect, c, r);
            let d = (c - eye).length();
            let score = match order {
                CapOrder::Scene => -(i as f64),
                CapOrder::Nearest => -(d - r).max(0.0),
                CapOrder::Brightest => {
                    let s = if d <= r { 1.0 } else { (r / d).powi(2).min(1.0) };
                    peak(l) * s
                }
            };
            (seen, score)
        };
        let mut ranked: Vec<(bool, f64, u32)> = kept.iter().map(|&i| (key(i).0, key(i).1, i)).collect();
        // Seen first, then the higher score, then the lower index.
        ranked.sort_by(|a, b| b.0.cmp(&a.0).then(b.1.total_cmp(&a.1)).then(a.2.cmp(&b.2)));
        let before = kept.len();
        kept = ranked.into_iter().take(max_lights as usize).map(|(_, _, i)| i).collect();
        kept.sort_unstable();
        stats.dropped_by_count = (before - kept.len()) as u32;
    }
    if stats.dropped_by_count + stats.dropped_by_distance > 0 {
        stats.kept = Some(kept);
    }
    Some(stats)
}

/// `scene` with only the lights `kept` (in their order).
pub fn with_lights(scene: &Scene, kept: &[u32]) -> Scene {
    let mut out = scene.clone();
    let lights: Vec<Light> = kept.iter().map(|&i| scene.lights[i as usize]).collect();
    out.set_lights(lights);
    out
}

/// Ranks `candidates` (light indices, ascending) by `order` for a cell or object centred at
/// `centre` and keeps `cap` of them, returned in ascending index order (the order the lists are
/// walked in, so the kept lights add in the same order as without the cap). `at(i)` gives light
/// i's (centre, radius, peak luminance) in the space `centre` is in.
pub fn keep_nearest_or_brightest(
    candidates: &[u32],
    cap: usize,
    order: CapOrder,
    centre: Vec3,
    at: impl Fn(u32) -> (Vec3, f32, f64),
) -> Vec<u32> {
    if candidates.len() <= cap {
        return candidates.to_vec();
    }
    let mut kept: Vec<u32> = match order {
        CapOrder::Scene => candidates[..cap].to_vec(),
        CapOrder::Nearest | CapOrder::Brightest => {
            let mut scored: Vec<(f64, u32)> = candidates
                .iter()
                .map(|&i| {
                    let (c, r, peak) = at(i);
                    let d = (c - centre).length() as f64;
                    let s = if order == CapOrder::Nearest { -d } else { irradiance_at(peak, d, r as f64) };
                    (s, i)
                })
                .collect();
            scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            scored.into_iter().take(cap).map(|(_, i)| i).collect()
        }
    };
    kept.sort_unstable();
    kept
}

/// The square tile side Bevy's `ClusterConfig::FixedZ { total, z_slices }` comes to at `size`:
/// Bevy takes y = sqrt(total / z_slices / aspect) rows and x = y x aspect columns (both
/// truncated, at least 1), then tiles of ceil(size / (x, y)) pixels. Lampshade's tiles are
/// square: the larger side, so each tile covers at least Bevy's.
pub fn budget_tile(total: u32, slices: u32, (w, h): (u32, u32)) -> u32 {
    let slices = slices.clamp(1, total.max(1));
    let per_layer = total as f64 / slices as f64;
    let aspect = w.max(1) as f64 / h.max(1) as f64;
    let yf = (per_layer / aspect).sqrt();
    let (mut x, mut y) = ((yf * aspect) as u32, yf as u32);
    if x == 0 {
        (x, y) = (1, per_layer as u32);
    }
    if y == 0 {
        (x, y) = (per_layer as u32, 1);
    }
    let (x, y) = (x.max(1), y.max(1));
    w.div_ceil(x).max(h.div_ceil(y)).max(1)
}

/// An engine's caps and grid as a preset: one bench row each.
pub struct Engine {
    pub name: &'static str,
    /// Where the figures come from.
    pub source: &'static str,
    /// (knob, value) pairs applied over the row's settings.
    pub knobs: &'static [(&'static str, &'static str)],
}

/// The engines' presets the bench measures (`bench --only engines`).
pub const ENGINES: &[Engine] = &[
    Engine {
        name: "bevy-default",
        source: "Bevy 0.19 ClusterConfig::default(): FixedZ { total: 4096, z_slices: 24 }, first slice to 5.0; no light cap with storage buffers",
        knobs: &[("culling", "clustered"), ("cluster-budget", "4096"), ("cluster-slices", "24"), ("first-slice-depth", "5")],
    },
    Engine {
        name: "bevy-webgl2",
        source: "Bevy on WebGL2: its default grid, and 256 clusterable objects in uniform buffers (kept in the order it walks them)",
        knobs: &[
            ("culling", "clustered"),
            ("cluster-budget", "4096"),
            ("cluster-slices", "24"),
            ("first-slice-depth", "5"),
            ("max-lights", "256"),
            ("cap-order", "scene"),
        ],
    },
    Engine {
        name: "three-tiled",
        source: "three.js TiledLightsNode (examples/jsm/tsl/lighting): 32-px tiles without depth, the first 8 lights touching a tile, 1,024 lights",
        knobs: &[
            ("culling", "clustered"),
            ("cluster-tile", "32"),
            ("cluster-slices", "1"),
            ("lights-per-cluster", "8"),
            ("max-lights", "1024"),
            ("cap-order", "scene"),
        ],
    },
    Engine {
        name: "urp-forward",
        source: "Unity URP forward: 8 lights per object, 256 visible lights on desktop, ranked by brightness",
        knobs: &[("path", "forward"), ("lights-per-object", "8"), ("max-lights", "256"), ("cap-order", "brightest")],
    },
    Engine {
        name: "urp-mobile",
        source: "Unity URP forward on mobile: 8 lights per object, 32 visible lights",
        knobs: &[("path", "forward"), ("lights-per-object", "8"), ("max-lights", "32"), ("cap-order", "brightest")],
    },
    Engine {
        name: "filament",
        source: "Filament: 255 lights (sorted by distance to the camera), none beyond 100 m",
        knobs: &[("culling", "clustered"), ("max-lights", "255"), ("cap-order", "nearest"), ("light-distance", "100")],
    },
    Engine {
        name: "playcanvas",
        source: "PlayCanvas clustered lighting: 255 visible lights",
        knobs: &[("culling", "clustered"), ("max-lights", "255"), ("cap-order", "scene")],
    },
];

/// The camera caps' last list: the scene's list, the indices kept, the kept lights.
type CappedLights = (Arc<Vec<Light>>, Vec<u32>, Arc<Vec<Light>>);

/// A scene with only the lights the camera caps keep, kept for the next frame.
#[derive(Default)]
pub struct CappedScene {
    last: Option<CappedLights>,
}

impl CappedScene {
    /// `scene` with only the lights `kept`, built again only when the scene's lights or the
    /// kept set changed (a still frame under a camera cap keeps its list's identity, so the
    /// frame's CPU part is reused as without the cap). The rest of the scene is copied each
    /// frame.
    pub fn scene(&mut self, scene: &Scene, kept: &[u32]) -> Scene {
        let lights = match &self.last {
            Some((source, k, lights)) if Arc::ptr_eq(source, &scene.lights) && k == kept => lights.clone(),
            _ => {
                let lights: Arc<Vec<Light>> = Arc::new(kept.iter().map(|&i| scene.lights[i as usize]).collect());
                self.last = Some((scene.lights.clone(), kept.to_vec(), lights.clone()));
                lights
            }
        };
        Scene { lights, ..scene.clone() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bevys_default_grid_at_720p_is_17_by_9_tiles_of_76_by_80_made_square_at_80() {
        // per layer 4096 / 24 = 170.7; y = sqrt(170.7 / 1.778) = 9.8 -> 9 rows, x = 17.4 -> 17
        // columns; tiles ceil(1280 / 17) = 76 by ceil(720 / 9) = 80.
        assert_eq!(budget_tile(4096, 24, (1280, 720)), 80);
        assert_eq!(budget_tile(4096, 4096, (1280, 720)), 1280);
        assert_eq!(budget_tile(1, 24, (100, 100)), 100);
    }

    #[test]
    fn a_cell_cap_keeps_the_first_nearest_or_brightest_in_index_order() {
        let lights =
            [(Vec3::new(5.0, 0.0, 0.0), 10.0, 1.0), (Vec3::new(1.0, 0.0, 0.0), 10.0, 0.1), (Vec3::ZERO, 1.0, 5.0)];
        let at = |i: u32| lights[i as usize];
        let all = [0, 1, 2];
        assert_eq!(keep_nearest_or_brightest(&all, 2, CapOrder::Scene, Vec3::ZERO, at), vec![0, 1]);
        assert_eq!(keep_nearest_or_brightest(&all, 2, CapOrder::Nearest, Vec3::ZERO, at), vec![1, 2]);
        // Irradiance at the centre: 1 x (1 - 0.25)^2 = 0.5625, 0.1 x 0.99^2 = 0.098, 5 x 1 = 5.
        assert_eq!(keep_nearest_or_brightest(&all, 2, CapOrder::Brightest, Vec3::ZERO, at), vec![0, 2]);
        assert_eq!(keep_nearest_or_brightest(&all, 3, CapOrder::Brightest, Vec3::ZERO, at), vec![0, 1, 2]);
    }

    #[test]
    fn every_engine_preset_is_made_of_knobs_that_exist() {
        for e in ENGINES {
            let s = crate::renderer::presets::engine_settings(e, &crate::renderer::Settings::default()).unwrap();
            s.validate().unwrap();
        }
    }
}
