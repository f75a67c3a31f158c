//! The panels. `draw` reads the last frame's figures (`FrameInfo`), edits the plain `UiState`
//! and reports what only the application can do (screenshots, picking) in `UiOut`; it never
//! touches a GPU object.

use super::camera;
use super::state::{self, Panels, Scope, Tab, UiState, WireColour, Wireframes, MAX_LIGHTS, MAX_SCALE, MIN_SCALE};
use crate::renderer::kit::gbuffer::{Attr, GBufferLayout};
use crate::renderer::settings::AccumFormat;
use crate::renderer::{CullingMode, DebugView, FrameStats, LayoutChoice, Method, PixelProbe, RenderPath};
use crate::scene::builtin;
use crate::scene::{Light, Scene, Sun};
use egui::{Color32, Pos2, Rect, RichText, Sense, Stroke, Vec2};
use glam::Vec3;
use std::collections::{BTreeMap, HashMap, VecDeque};

mod advice;
mod check;
pub use check::CullingCheck;
mod figures;
mod gbuffer_strip;
mod lights_tab;
mod overlaps;
mod probe;
mod shadow_atlas;
mod tabs;
mod top_bar;
mod viewport;

use figures::right_panel;
pub use figures::{History, Sample};
use gbuffer_strip::gbuffer_strip;
pub use gbuffer_strip::{thumbs, Thumb};
use lights_tab::lights_tab;
pub use overlaps::{overlaps, Region};
use probe::pixel_panel;
use shadow_atlas::shadow_window;
pub use shadow_atlas::{cascade_colour, visible as atlas_visible, AtlasInfo, CUBE, SELECTED, SPOT};
use tabs::left_panel;
use top_bar::{status_bar, top_bar};
use viewport::viewport;

/// Frames kept for the history plot.
pub const HISTORY: usize = 240;
/// "All" wireframes draws at most this many volumes (the largest on screen).
pub const MAX_WIREFRAMES: usize = 256;
/// Fixed panel sizes in points: the viewport keeps its size whatever the panels show.
const GBUFFER_STRIP: f32 = 128.0;
/// Side panel widths at a 1280-point window; narrower windows shrink them down to the minimum.
const LEFT_WIDTH: f32 = 272.0;
const RIGHT_WIDTH: f32 = 292.0;
const MIN_SIDE_WIDTH: f32 = 170.0;
const PIXEL_PANEL: f32 = 236.0;
/// The left panel pins the pixel probe below the tabs only when the tabs keep this much height.
const MIN_TAB_HEIGHT: f32 = 200.0;

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

/// A status line message: what the last action did, or why it was rejected.
#[derive(Clone, Debug)]
pub struct Status {
    pub text: String,
    pub error: bool,
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
    pub adapter: &'a str,
    /// What the adapter can do: choices it cannot give are greyed out with the reason.
    pub caps: &'a crate::renderer::kit::caps::Caps,
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
    pub loading: Option<super::loading::LoadProgress>,
    /// The shadow-atlas panel's image, tiles and depth range (`None`: panel closed or
    /// nothing rendered yet).
    pub atlas: Option<AtlasInfo<'a>>,
    /// Where the shadow-atlas window opens first (points).
    pub atlas_default_pos: Pos2,
}

#[derive(Clone, Debug)]
pub enum Command {
    Screenshot,
    /// Hold every culling mode against brute force at the current camera.
    CheckCulling,
    /// Start the advisor on the current scene and camera.
    Advise,
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

fn colour32(c: Vec3) -> Color32 {
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
fn method_name(m: Method) -> String {
    serde_json::to_value(m).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_else(|| format!("{m:?}"))
}

/// The culling mode's one-line description: its doc comment in `settings.rs`.
fn culling_help(m: CullingMode) -> String {
    crate::renderer::settings::help_of(&m)
}

fn fmt_opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or("-".into(), |v| v.to_string())
}

fn fmt_ms(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.2} ms"))
}

fn fmt_count(v: u64) -> String {
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
fn reject(out: &mut UiOut, text: String) {
    out.commands.push(Command::Status(Status { text, error: true }));
}

pub fn style(ctx: &egui::Context) {
    ctx.all_styles_mut(|s| {
        s.spacing.item_spacing = Vec2::new(6.0, 4.0);
        s.spacing.interact_size.y = 18.0;
        s.visuals.panel_fill = Color32::from_gray(30);
        s.visuals.extreme_bg_color = Color32::from_gray(14);
    });
}

/// Draws every panel and the viewport.
pub fn draw(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    // egui may run a frame's UI twice (a discarded first pass): the regions are this pass's.
    out.regions.clear();
    top_bar(ui, st, f, out);
    status_bar(ui, st, f, out);
    let shown = fit_panels(st.panels, ui.available_width(), ui.available_height());
    let k = (ui.available_width() / 1280.0).min(1.0);
    let side = |w: f32| (w * k).max(MIN_SIDE_WIDTH).round();
    // A panel's response reaches past what it was given when its content is wider than it
    // (that part is clipped, not drawn): its region is the part within.
    let region = |name, rect: Rect, given: Rect| Region { name, parent: None, rect: rect.intersect(given) };
    if shown.left {
        let given = ui.available_rect_before_wrap();
        let r = egui::Panel::left("left")
            .resizable(false)
            .exact_size(side(LEFT_WIDTH))
            .show(ui, |ui| left_panel(ui, st, f, out));
        out.regions.push(region("left panel", r.response.rect, given));
    }
    if shown.right {
        let given = ui.available_rect_before_wrap();
        let r = egui::Panel::right("right")
            .resizable(false)
            .exact_size(side(RIGHT_WIDTH))
            .show(ui, |ui| right_panel(ui, st, f));
        out.regions.push(region("right panel", r.response.rect, given));
    }
    if shown.gbuffer {
        let given = ui.available_rect_before_wrap();
        let r = egui::Panel::bottom("gbuffer")
            .resizable(false)
            .exact_size(GBUFFER_STRIP)
            .show(ui, |ui| gbuffer_strip(ui, st, f));
        out.regions.push(region("G-buffer strip", r.response.rect, given));
    }
    let given = ui.available_rect_before_wrap();
    let r = egui::CentralPanel::no_frame().show(ui, |ui| viewport(ui, st, f, out));
    out.regions.push(region("viewport", r.response.rect, given));
    if st.panels.shadows {
        shadow_window(ui.ctx(), st, f, out);
    }
    if st.panels.check {
        check::check_window(ui.ctx(), st, f);
    }
    if st.panels.advice {
        advice::advice_window(ui.ctx(), st, f);
    }
    if st.panels.explain && f.explanation.is_some() {
        let mut open = true;
        egui::Window::new("Why each light")
            .open(&mut open)
            .default_size([420.0, 320.0])
            .resizable(true)
            .show(ui.ctx(), |ui| probe::explanation_panel(ui, f));
        st.panels.explain = open;
    }
}

/// The smallest viewport (points) the panels leave: a window too small for the panels the user
/// wants hides the right panel first, then the left one, then the G-buffer strip, so that the
/// viewport keeps at least this size while the window can give it (side panels shrink with the
/// window down to `MIN_SIDE_WIDTH` first). Below `MIN_WINDOW` (points) every panel is hidden
/// and the viewport takes what the top and status bars leave.
pub const MIN_VIEWPORT: [f32; 2] = [320.0, 180.0];
pub const MIN_WINDOW: [f32; 2] = [MIN_VIEWPORT[0] + 2.0 * MIN_SIDE_WIDTH, MIN_VIEWPORT[1] + GBUFFER_STRIP + 90.0];

/// The panels shown in a central area of `width` x `height` points (below the top bar, above
/// the status bar): the wanted ones, less those that would leave the viewport smaller than
/// `MIN_VIEWPORT`.
pub fn fit_panels(want: Panels, width: f32, height: f32) -> Panels {
    let k = (width / 1280.0).min(1.0);
    let side = |w: f32| (w * k).max(MIN_SIDE_WIDTH).round();
    let mut shown = want;
    let used =
        |p: Panels| (if p.left { side(LEFT_WIDTH) } else { 0.0 }) + if p.right { side(RIGHT_WIDTH) } else { 0.0 };
    if width - used(shown) < MIN_VIEWPORT[0] {
        shown.right = false;
    }
    if width - used(shown) < MIN_VIEWPORT[0] {
        shown.left = false;
    }
    if shown.gbuffer && height - GBUFFER_STRIP < MIN_VIEWPORT[1] {
        shown.gbuffer = false;
    }
    shown
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_give_way_to_a_usable_viewport() {
        let all = Panels::default();
        // A full-size window keeps every panel.
        assert_eq!(fit_panels(all, 1280.0, 640.0), all);
        // Every central area from 200 to 2000 points wide keeps the viewport at least
        // MIN_VIEWPORT wide where the window can give it, and never hides a panel it has room for.
        for w in (200..2000).step_by(10) {
            for h in (100..1200).step_by(20) {
                let (w, h) = (w as f32, h as f32);
                let p = fit_panels(all, w, h);
                let k = (w / 1280.0).min(1.0);
                let side = |x: f32| (x * k).max(MIN_SIDE_WIDTH).round();
                let used = if p.left { side(LEFT_WIDTH) } else { 0.0 } + if p.right { side(RIGHT_WIDTH) } else { 0.0 };
                if p.left || p.right {
                    assert!(w - used >= MIN_VIEWPORT[0], "{w}x{h}: viewport {} wide", w - used);
                }
                if p.gbuffer {
                    assert!(h - GBUFFER_STRIP >= MIN_VIEWPORT[1], "{w}x{h}");
                }
                if w >= MIN_VIEWPORT[0] + side(LEFT_WIDTH) + side(RIGHT_WIDTH) {
                    assert!(p.left && p.right, "{w}x{h}: a panel was hidden with room for it");
                }
            }
        }
        // The user's choice stands: a hidden panel is not shown by a large window.
        let no_right = Panels { right: false, ..all };
        assert_eq!(fit_panels(no_right, 1920.0, 1000.0), no_right);
    }
}
