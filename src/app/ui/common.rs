//! What every panel shares: the frame's figures (`FrameInfo`), the commands and status a
//! panel reports (`UiOut`), the panel sizes and the small formatting helpers.

use crate::oracle::ModeResult;
use crate::renderer::inspect::AtlasTile;
use crate::renderer::CullingMode;
use crate::renderer::DebugView;
use crate::renderer::FrameStats;
use crate::renderer::Method;
use crate::renderer::PixelProbe;
use crate::scene::Scene;
use egui::Color32;
use egui::Pos2;
use egui::Rect;
use egui::Vec2;
use glam::Vec3;
use std::collections::HashMap;
use std::collections::VecDeque;

/// Frames kept for the history plot.
pub const HISTORY: usize = 240;
/// "All" wireframes draws at most this many volumes (the largest on screen).
pub const MAX_WIREFRAMES: usize = 256;
/// Fixed panel sizes in points: the viewport keeps its size whatever the panels show.
pub(crate) const GBUFFER_STRIP: f32 = 128.0;
/// Side panel widths at a 1280-point window; narrower windows shrink them down to the minimum.
pub(crate) const LEFT_WIDTH: f32 = 272.0;
pub(crate) const RIGHT_WIDTH: f32 = 292.0;
pub(crate) const MIN_SIDE_WIDTH: f32 = 170.0;
pub(crate) const PIXEL_PANEL: f32 = 236.0;
/// The left panel pins the pixel probe below the tabs only when the tabs keep this much height.
pub(crate) const MIN_TAB_HEIGHT: f32 = 200.0;

/// Why the adapter cannot give knob `knob` = `name` on top of `settings`, if it cannot.
pub(super) fn refused(
    f: &FrameInfo,
    settings: &crate::renderer::Settings,
    knob: &str,
    name: impl AsRef<str>,
) -> Option<String> {
    crate::renderer::support::refusal(f.caps, settings, knob, name.as_ref())
}

/// `value` as a selectable entry, greyed out with `why` as its tooltip when the adapter cannot
/// give it.
pub(super) fn offer<T: PartialEq>(
    ui: &mut egui::Ui,
    why: Option<String>,
    current: &mut T,
    value: T,
    text: impl AsRef<str>,
) -> egui::Response {
    let text = text.as_ref();
    match why {
        Some(w) => ui.add_enabled(false, egui::Button::selectable(*current == value, text)).on_disabled_hover_text(w),
        None => ui.selectable_value(current, value, text),
    }
}

/// A choice box of every value of knob type `T` (its one name, its doc comment as the tooltip),
/// selecting into `value`.
pub(super) fn knob_choice<T: clap::ValueEnum + Copy + PartialEq>(
    ui: &mut egui::Ui,
    id: impl std::hash::Hash + std::fmt::Debug,
    value: &mut T,
) {
    use crate::renderer::settings::{help_of, name_of};
    egui::ComboBox::from_id_salt(id).selected_text(name_of(value)).show_ui(ui, |ui| {
        for &v in T::value_variants() {
            ui.selectable_value(value, v, name_of(&v)).on_hover_text(help_of(&v));
        }
    });
}

/// A status line message: what the last action did, or why it was rejected.
#[derive(Clone, Debug)]
pub struct Status {
    pub text: String,
    pub error: bool,
}

/// What the viewport needs to draw the comparison.
pub struct SplitInfo<'a> {
    /// B's image (`None` until B has drawn).
    pub b: Option<egui::TextureId>,
    /// The difference or FLIP image (`None` until computed).
    pub overlay: Option<egui::TextureId>,
    pub figures: &'a crate::app::split::SplitFigures,
}

/// What the UI shows this frame (read only).
pub struct FrameInfo<'a> {
    /// Resident memory of the process and wgpu's live buffer + texture bytes.
    pub memory: Option<(u64, i64)>,
    pub stats: Option<&'a FrameStats>,
    pub history: &'a History,
    pub scene: Option<&'a Scene>,
    /// The viewport image and its size in pixels.
    pub viewport: Option<(egui::TextureId, [u32; 2])>,
    /// The viewport image's own draw (`app::blit`), where the window has one: drawn instead of
    /// egui's image of it.
    pub viewport_paint: Option<crate::app::blit::Paint>,
    pub thumbs: &'a HashMap<DebugView, egui::TextureId>,
    pub tiles: &'a [Thumb],
    pub depth_format: String,
    pub gbuffer_bytes: u32,
    pub probe: Option<&'a PixelProbe>,
    /// Why each light lit the last clicked pixel.
    pub explanation: Option<&'a Result<crate::renderer::explain::Explanation, String>>,
    /// The last culling check against brute force.
    pub check: Option<&'a Result<CullingCheck, String>>,
    /// The advisor, running or finished.
    pub advice: Option<&'a crate::app::advice::AdviceJob>,
    /// The calibration the renderer weighs with (`Calibration::describe`).
    pub calibration: String,
    /// Offer to calibrate (a dismissable note on the status line).
    pub offer_calibration: bool,
    pub adapter: &'a str,
    /// What the adapter can do: choices it cannot give are greyed out with the reason.
    pub caps: &'a crate::renderer::kit::adapter::AdapterCaps,
    pub status: Option<&'a Status>,
    /// The loaded file's warnings, in full (the status line shows the first; hovering it, all).
    pub warnings: &'a [String],
    pub cpu_ms: f64,
    pub scripted: bool,
    /// Scroll the light list to this light (it was just picked in the viewport).
    pub scroll_to_light: Option<usize>,
    /// Per-light volume wireframes, in viewport pixels: (light, segments).
    pub wireframes: &'a [(usize, Vec<[glam::Vec2; 2]>)],
    /// A glTF file loading in the background.
    pub loading: Option<crate::app::loading::LoadProgress>,
    /// The shadow-atlas panel's image, tiles and depth range (`None`: panel closed or
    /// nothing rendered yet).
    pub atlas: Option<AtlasInfo<'a>>,
    /// Where the shadow-atlas window opens first (points).
    pub atlas_default_pos: Pos2,
    /// A configuration building in the background (`compiling N pipelines for …`).
    pub compiling: Option<String>,
    /// Each configuration's pipelines and compile times (the pipelines window).
    pub pipelines: &'a [crate::app::pipeline_rows::ConfigPipelines],
    /// The split view's configuration B (`None` while it is off).
    pub split: Option<SplitInfo<'a>>,
}

#[derive(Clone, Debug)]
pub enum Command {
    Screenshot,
    /// Hold every culling mode against brute force at the current camera.
    CheckCulling,
    /// Start the advisor on the current scene and camera.
    Advise,
    /// Measure the cost model's constants on this adapter (the offer taken).
    Calibrate,
    /// The offer to calibrate declined.
    DeclineCalibration,
    ResetCamera,
    SceneChanged,
    Status(Status),
}

/// What the UI asks of the application.
#[derive(Default)]
pub struct UiOut {
    /// The viewport's rectangle in points.
    pub viewport_rect: Option<Rect>,
    /// The viewport pixel under the pointer.
    pub hover_pixel: Option<[u32; 2]>,
    /// A click (not a drag) on the viewport, in viewport pixels.
    pub click_pixel: Option<[f32; 2]>,
    /// Drag on the viewport in points (look around).
    pub drag: Vec2,
    pub commands: Vec<Command>,
    /// The shadow-atlas image's rectangle in points (the panel is open).
    pub atlas_rect: Option<Rect>,
    /// Where each part of the window drew (`overlaps`).
    pub regions: Vec<Region>,
}

pub(crate) fn colour32(c: Vec3) -> Color32 {
    let m = c.max_element().max(1e-6);
    let c = if m > 1.0 { c / m } else { c };
    Color32::from_rgb(
        (c.x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8,
        (c.y.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8,
        (c.z.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8,
    )
}

/// Red (wasted work) to green (only useful work).
pub fn efficiency_colour(e: f64) -> Color32 {
    let e = e.clamp(0.0, 1.0) as f32;
    Color32::from_rgb(((1.0 - e) * 255.0) as u8, (e * 220.0 + 35.0) as u8, 40)
}

/// The method's serde name (kebab-case), so new methods in the core need no change here.
pub(crate) fn method_name(m: Method) -> String {
    serde_json::to_value(m).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_else(|| format!("{m:?}"))
}

/// The culling mode's one-line description: its doc comment in `options/culling.rs`.
pub(crate) fn culling_help(m: CullingMode) -> String {
    crate::renderer::settings::help_of(&m)
}

pub(crate) fn fmt_opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or("-".into(), |v| v.to_string())
}

pub(crate) fn fmt_ms(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.2} ms"))
}

pub(crate) fn fmt_count(v: u64) -> String {
    let s = v.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
}

/// Reports a rejected edit on the status line.
pub(crate) fn reject(out: &mut UiOut, text: String) {
    out.commands.push(Command::Status(Status { text, error: true }));
}

#[derive(Clone, Copy, Debug, Default)]
pub struct Sample {
    pub gpu_total: Option<f64>,
    pub lighting: Option<f64>,
    pub shaded: Option<u64>,
    pub ideal: Option<u64>,
}

#[derive(Default)]
pub struct History {
    pub samples: VecDeque<Sample>,
}

/// One thumbnail: a view that shows one buffer of the frame readably.
pub struct Thumb {
    pub view: DebugView,
    pub label: &'static str,
    /// The buffer it shows, e.g. "albedo+spec".
    pub buffer: String,
    pub format: String,
}

/// The last check: a row a (path, mode) and each row's difference image.
pub struct CullingCheck {
    /// The frame size the check rendered at.
    pub size: [u32; 2],
    pub rows: Vec<ModeResult>,
    pub images: Vec<egui::TextureHandle>,
    pub seconds: f64,
}

/// What the panel shows of the last frame (read only).
pub struct AtlasInfo<'a> {
    /// The atlas image (`None` until first drawn).
    pub image: Option<egui::TextureId>,
    /// Side of the atlas in texels.
    pub side: u32,
    /// Its depth format (`--shadow-format`).
    pub format: wgpu::TextureFormat,
    pub tiles: &'a [AtlasTile],
    /// Least and greatest stored depth (fractions of each tile's far distance).
    pub range: Option<(f32, f32)>,
}

/// A part of the window, as drawn this frame: where its widgets may appear (a scroll area's
/// visible rectangle, a panel's outer rectangle).
#[derive(Clone, Debug)]
pub struct Region {
    pub name: &'static str,
    /// The region it is part of (`None`: the window).
    pub parent: Option<&'static str>,
    pub rect: Rect,
}
