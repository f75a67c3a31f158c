//! The camera paths shipped in `assets/paths/` (one per scene the bench replays) and replay:
//! each path is long enough for the bench, moves through or past its scene's light volumes
//! (`street` and `inside` through volumes that cross the near plane), and a path replayed twice
//! draws the same frames, byte for byte.

use crate::common::{gpu, scene};
use lampshade::headless::render_image;
use lampshade::renderer::{Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::camera_path::{CameraPath, DEFAULT_STEP, MIN_BENCH_FRAMES};

/// The scenes with a shipped path.
pub const PATHS: [&str; 6] = ["demo", "street", "inside", "sphere-wall", "railings", "many-lights"];

pub fn shipped(name: &str) -> CameraPath {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/paths/{name}.json"));
    CameraPath::load(&file).unwrap_or_else(|e| panic!("{e:#}"))
}

/// Each path: at least 10 s, at least the bench's 100 frames at 1/60 s, recorded in its own
/// scene; and at some quarter second the camera is within one unit of a light's volume (inside
/// it, or passing its surface): it moves through or past the lights, not around them.
#[test]
fn the_shipped_paths_are_long_enough_and_pass_the_lights() {
    for name in PATHS {
        let path = shipped(name);
        assert_eq!(path.scene.as_deref(), Some(name), "{name}: the file names another scene");
        assert!(path.duration() >= 10.0, "{name}: {} s long", path.duration());
        assert!(path.frames(DEFAULT_STEP) >= MIN_BENCH_FRAMES, "{name}: {} frames", path.frames(DEFAULT_STEP));
        let s = scene(name);
        let quarter = (path.duration() / 0.25) as usize;
        let closest = (0..=quarter)
            .map(|k| {
                let c = path.at(k as f64 * 0.25);
                c.validate().unwrap_or_else(|e| panic!("{name} at {} s: {e}", k as f64 * 0.25));
                s.lights
                    .iter()
                    .map(|l| (l.position() - c.position).length() - l.radius() as f64)
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(closest <= 1.0, "{name}: the camera keeps {closest:.2} units from every light's volume");
    }
}

/// `street` and `inside` cross the near plane: at some half second of the path, some light's
/// volume crosses it, as the renderer classifies the frame's lights (`crosses_near`).
#[test]
fn the_street_and_inside_paths_cross_the_near_plane() {
    for name in ["street", "inside"] {
        let path = shipped(name);
        let mut s = scene(name);
        let settings =
            Settings { per_light_stats: true, shadows: lampshade::renderer::ShadowMode::None, ..Settings::default() };
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
        let mut crossing = Vec::new();
        for k in 0..=(path.duration() / 0.5) as usize {
            s.camera = path.at(k as f64 * 0.5);
            let (_, stats) = render_image(gpu(), &mut r, &s, &settings, 32, 18).unwrap();
            assert!(stats.per_light_stats, "{name}: no per-light figures");
            if stats.per_light.iter().any(|l| l.crosses_near) {
                crossing.push(k as f64 * 0.5);
            }
        }
        assert!(!crossing.is_empty(), "{name}: no light volume crosses the near plane along the path");
        eprintln!("{name}: volumes cross the near plane at {crossing:?} s");
    }
}

/// A path replayed twice, each time by a renderer of its own, at 1/60 s a frame: every frame
/// the same bytes. Frame n is the camera at n/60 s, whatever the frame before it drew.
#[test]
fn a_replayed_path_draws_the_same_frames_byte_for_byte() {
    let path = shipped("demo");
    let mut s = crate::common::with_lights("demo", 64);
    let settings = Settings { culling: lampshade::renderer::CullingMode::Tiled, ..Settings::default() };
    // Every 60th frame (one a second) and a run of adjacent ones.
    let frames: Vec<usize> = (0..path.frames(DEFAULT_STEP)).step_by(60).chain(300..304).collect();
    let mut runs: Vec<Vec<image::RgbaImage>> = Vec::new();
    for _ in 0..2 {
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
        let mut images = Vec::new();
        for &n in &frames {
            s.camera = path.frame(n, DEFAULT_STEP);
            images.push(render_image(gpu(), &mut r, &s, &settings, 96, 54).unwrap().0);
        }
        runs.push(images);
    }
    for (k, (a, b)) in runs[0].iter().zip(&runs[1]).enumerate() {
        assert!(a == b, "frame {} differs between two replays", frames[k]);
    }
    // The frames are the path's: adjacent ones differ (the camera moves), and not all are dark.
    assert!(runs[0].windows(2).all(|w| w[0] != w[1]), "two replayed frames are the same picture");
    assert!(runs[0].iter().any(|i| crate::common::lit_share(i) > 0.2), "every replayed frame is dark");
}
