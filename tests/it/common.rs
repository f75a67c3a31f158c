#![allow(dead_code)]
//! Shared by the integration tests: one GPU for the whole suite, small renders, readbacks, and
//! a memo of rendered frames so that tests checking different properties of the same frame
//! (a built-in scene, settings and size) render it once.

use lampshade::headless::render_image;
use lampshade::renderer::{FrameStats, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::{Gpu, Scene};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::headless().expect("these tests need a GPU adapter (mesa-vulkan-drivers provides one)"))
}

/// The hard cases (built-in scenes that stress precision, culling and counting), which every
/// culling mode and path must survive: `tests/it/hard_cases.rs`, `tests/it/paths.rs`,
/// `tests/it/prepass.rs`.
pub const HARD_CASES: &[&str] = &[
    "inside",
    "near",
    "far",
    "occluded",
    "floating",
    "on-surface",
    "grazing",
    "far-origin",
    "tiny-radius",
    "overflow",
    "normals",
    "spot-extremes",
    "coincident",
    "street",
];

/// The size a hard case renders at (`overflow`'s many lights at a smaller one).
pub fn hard_case_size(name: &str) -> (u32, u32) {
    if name == "overflow" {
        (96, 54)
    } else {
        (160, 90)
    }
}

/// The default settings without shadows (the default casts the sun's and the spots'). The f64
/// reference (`src/reference.rs`) and every bound derived from it model unshadowed light, so
/// the tests that compare with it, or across paths whose normals differ (a shadow edge moves
/// with the lookup's normal offset), render unshadowed. Shadows are checked on their own:
/// against rays through the scene's triangles, every culling mode and every path, in
/// `tests/it/shadows.rs`.
pub fn unshadowed() -> Settings {
    Settings { shadows: lampshade::renderer::ShadowMode::None, ..Settings::default() }
}

/// Deferred shading at full precision (the reference layout, an Rgba32Float accumulation),
/// unshadowed and without the ideal count, and the light pre-pass with the same settings: the
/// pair a pre-pass frame's forward-shaded objects are held against.
pub fn full_precision_and_prepass() -> (Settings, Settings) {
    let deferred = Settings {
        layout: lampshade::LayoutChoice::Reference,
        accumulation: lampshade::renderer::AccumFormat::Rgba32Float,
        count_ideal: false,
        ..unshadowed()
    };
    let prepass = Settings { path: lampshade::renderer::RenderPath::LightPrepass, ..deferred.clone() };
    (deferred, prepass)
}

pub fn scene(name: &str) -> Scene {
    builtin::build(name, BuiltinOptions::default()).expect("built-in scene")
}

/// Built-in scene `name` with `n` lights (a scene that takes a count).
pub fn with_lights(name: &str, n: usize) -> Scene {
    builtin::build(name, BuiltinOptions { lights: Some(n), ..Default::default() }).expect("built-in scene")
}

pub struct Frame {
    pub image: image::RgbaImage,
    pub stats: FrameStats,
    pub diffuse: Vec<f32>,
    pub specular: Vec<f32>,
}

pub fn render(scene: &Scene, settings: &Settings, w: u32, h: u32) -> Frame {
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, settings).expect("renderer");
    let (image, stats) = render_image(gpu, &mut r, scene, settings, w, h).expect("render");
    let (diffuse, specular) = r.last_frame().read_accumulation(gpu).expect("accumulation readback");
    Frame { image, stats, diffuse, specular }
}

/// Fails on NaN or infinity anywhere in the linear accumulation buffers.
pub fn assert_finite(frame: &Frame, what: &str) {
    let bad = frame.diffuse.iter().chain(frame.specular.iter()).filter(|v| !v.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite values in the accumulation buffers");
}

/// Share of pixels that are not (near) black: an image test's guard against blank frames.
pub fn lit_share(img: &image::RgbaImage) -> f64 {
    let lit = img.pixels().filter(|p| p[0] as u32 + p[1] as u32 + p[2] as u32 > 24).count();
    lit as f64 / (img.width() * img.height()) as f64
}

/// The frame of built-in scene `name` (default options) under `settings` at `w`x`h`: see
/// [`frame_of`].
pub fn frame(name: &str, settings: &Settings, w: u32, h: u32) -> Arc<Frame> {
    frame_of(name, || scene(name), settings, w, h)
}

/// The frame of the scene `make` builds, known by `key` (the built-in scene's name, or a name
/// for how a test changed it: "demo, 200 lights"), under `settings` at `w`x`h`, rendered by a
/// fresh renderer the first time any test asks for it and shared after that: the same pixels,
/// counts and accumulation as [`render`] gives, since a frame of a fresh renderer is a function
/// of scene, settings and size alone. Two tests asking at once render it once; the other waits.
pub fn frame_of(key: &str, make: impl FnOnce() -> Scene, settings: &Settings, w: u32, h: u32) -> Arc<Frame> {
    type Key = (String, String, u32, u32);
    type Memo = Mutex<HashMap<Key, Arc<OnceLock<Arc<Frame>>>>>;
    static FRAMES: OnceLock<Memo> = OnceLock::new();
    let key = (key.to_string(), serde_json::to_string(settings).expect("settings serialise"), w, h);
    let cell = {
        let mut map = FRAMES.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
        map.entry(key).or_default().clone()
    };
    cell.get_or_init(|| Arc::new(render(&make(), settings, w, h))).clone()
}

/// An empty folder for the user's cache (`XDG_CACHE_HOME`) of every test that starts the
/// `lampshade` binary: the CLI and the viewer read their calibration from there, so no test
/// depends on whether someone ran `lampshade calibrate` (the calibration tests plant theirs in
/// folders of their own).
pub fn empty_cache_home() -> std::path::PathBuf {
    static DIR: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("empty-cache-home");
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("creating the empty cache folder");
        d
    })
    .clone()
}
