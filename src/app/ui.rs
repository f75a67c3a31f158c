//! The panels. `draw` reads the last frame's figures (`FrameInfo`), edits the plain `UiState`
//! and reports what only the application can do (screenshots, picking) in `UiOut`; it never
//! touches a GPU object.

use super::camera;
use super::state::{self, Panels, Scope, Tab, UiState, WireColour, Wireframes, MAX_LIGHTS, MAX_SCALE, MIN_SCALE};
use crate::renderer::gbuffer::{Attr, GBufferLayout};
use crate::renderer::settings::AccumFormat;
use crate::renderer::{CullingMode, DebugView, FrameStats, LayoutChoice, Method, PixelProbe};
use crate::scene::builtin;
use crate::scene::{Light, Scene, Sun};
use egui::{Color32, Pos2, Rect, RichText, Sense, Stroke, Vec2};
use glam::Vec3;
use std::collections::{BTreeMap, HashMap, VecDeque};

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

impl History {
    pub fn push(&mut self, s: Sample) {
        if self.samples.len() == HISTORY {
            self.samples.pop_front();
        }
        self.samples.push_back(s);
    }
}

/// A status line message: what the last action did, or why it was rejected.
#[derive(Clone, Debug)]
pub struct Status {
    pub text: String,
    pub error: bool,
}

/// One thumbnail: a view that shows one buffer of the frame readably.
pub struct Thumb {
    pub view: DebugView,
    pub label: &'static str,
    /// The buffer it shows, e.g. "albedo+spec".
    pub buffer: String,
    pub format: String,
}

/// The thumbnail strip for a layout: each G-buffer target by the views that decode its
/// attributes (each view once), the light accumulation, then depth-stencil: stencil diagram
/// and light complexity.
pub fn thumbs(layout: &GBufferLayout, accum: Option<wgpu::TextureFormat>, depth: wgpu::TextureFormat) -> Vec<Thumb> {
    let mut out: Vec<Thumb> = Vec::new();
    let mut add = |view, label, buffer: &str, format: String| {
        if !out.iter().any(|t| t.view == view) {
            out.push(Thumb { view, label, buffer: buffer.to_string(), format });
        }
    };
    for t in &layout.targets {
        for slot in t.channels.iter().flatten() {
            let (view, label) = match slot.attr {
                Attr::Albedo => (DebugView::Albedo, "albedo"),
                Attr::SpecLevel | Attr::SpecExp => (DebugView::Specular, "specular"),
                Attr::Normal => (DebugView::Normal, "normal"),
                Attr::Emissive => (DebugView::Emissive, "emissive"),
                Attr::Depth => (DebugView::Depth, "depth"),
                Attr::Position => (DebugView::Depth, "position z"),
            };
            add(view, label, t.name, format!("{:?}", t.format));
        }
    }
    let accum = accum.map_or("-".into(), |a| format!("{a:?}"));
    add(DebugView::DiffuseLight, "diffuse light", "accumulation", accum.clone());
    add(DebugView::SpecularLight, "specular light", "accumulation", accum);
    add(DebugView::Depth, "depth", "depth-stencil", format!("{depth:?}"));
    add(DebugView::Stencil, "stencil", "depth-stencil", format!("{depth:?}"));
    add(DebugView::Complexity, "complexity", "lights per pixel", "heatmap".into());
    out
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
    pub adapter: &'a str,
    pub status: Option<&'a Status>,
    pub cpu_ms: f64,
    pub scripted: bool,
    /// Scroll the light list to this light (it was just picked in the viewport).
    pub scroll_to_light: Option<usize>,
    /// Per-light volume wireframes, in viewport pixels: (light, segments).
    pub wireframes: &'a [(usize, Vec<[glam::Vec2; 2]>)],
    /// A glTF file loading in the background.
    pub loading: Option<state::LoadProgress>,
}

#[derive(Clone, Debug)]
pub enum Command {
    Screenshot,
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

fn culling_help(m: CullingMode) -> &'static str {
    match m {
        CullingMode::Fullscreen => "Every light a full-screen triangle: the no-culling reference.",
        CullingMode::Volume => "Volume back faces, depth GreaterEqual, no stencil.",
        CullingMode::StencilTwoPass => "Seed 000: front faces mark on depth fail, back faces shade where stencil = 0.",
        CullingMode::StencilInvert => {
            "Seed 001: one double-sided draw inverts stencil on depth fail; shade where != 0."
        }
        CullingMode::StencilReplace => "Seed 002: depth-fail REPLACE of a per-light value; shade where equal.",
        CullingMode::Auto => "Per light, the cheapest correct method.",
    }
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
    top_bar(ui, st, f, out);
    status_bar(ui, st, f);
    let shown = fit_panels(st.panels, ui.available_width(), ui.available_height());
    let k = (ui.available_width() / 1280.0).min(1.0);
    let side = |w: f32| (w * k).max(MIN_SIDE_WIDTH).round();
    if shown.left {
        egui::Panel::left("left")
            .resizable(false)
            .exact_size(side(LEFT_WIDTH))
            .show(ui, |ui| left_panel(ui, st, f, out));
    }
    if shown.right {
        egui::Panel::right("right")
            .resizable(false)
            .exact_size(side(RIGHT_WIDTH))
            .show(ui, |ui| right_panel(ui, st, f));
    }
    if shown.gbuffer {
        egui::Panel::bottom("gbuffer")
            .resizable(false)
            .exact_size(GBUFFER_STRIP)
            .show(ui, |ui| gbuffer_strip(ui, st, f));
    }
    egui::CentralPanel::no_frame().show(ui, |ui| viewport(ui, st, f, out));
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

fn top_bar(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    egui::Panel::top("top").show(ui, |ui| {
        // Wraps onto more rows in a narrow window instead of running off its edge.
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new("Lampshade").strong().size(15.0));
            ui.separator();
            ui.label("scene");
            let before = st.scene.clone();
            let shown =
                std::path::Path::new(&st.scene).file_name().map_or(st.scene.clone(), |n| n.to_string_lossy().into());
            egui::ComboBox::from_id_salt("scene")
                .selected_text(shown)
                .width(90.0)
                .show_ui(ui, |ui| {
                    for (name, what) in builtin::NAMES {
                        ui.selectable_value(&mut st.scene, name.to_string(), *name).on_hover_text(*what);
                    }
                })
                .response
                .on_hover_text(&st.scene);
            // A glTF file by path; it loads in the background and the current scene stays until
            // it has (or for good, if it fails).
            let field = ui
                .add(egui::TextEdit::singleline(&mut st.open_path).hint_text("file.gltf / .glb").desired_width(130.0));
            let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("open").on_hover_text("load a .gltf or .glb file").clicked() || enter)
                && !st.open_path.trim().is_empty()
            {
                let path = st.open_path.trim().to_string();
                if crate::scene::import::is_gltf_path(&path) {
                    st.scene = path;
                } else {
                    out.commands.push(Command::Status(Status {
                        text: format!("'{path}' is not a .gltf or .glb file"),
                        error: true,
                    }));
                }
            }
            if let Some(p) = &f.loading {
                let frac = if p.total > 0 { p.done as f32 / p.total as f32 } else { 0.0 };
                ui.add(
                    egui::ProgressBar::new(frac)
                        .desired_width(150.0)
                        .text(format!("{} {}/{}", p.stage, p.done, p.total)),
                )
                .on_hover_text(format!("loading {}", p.name));
            }
            if st.scene != before {
                out.commands.push(Command::SceneChanged);
            }
            ui.label("culling");
            egui::ComboBox::from_id_salt("culling").selected_text(st.settings.culling.name()).width(120.0).show_ui(
                ui,
                |ui| {
                    for m in CullingMode::ALL {
                        ui.selectable_value(&mut st.settings.culling, m, m.name()).on_hover_text(culling_help(m));
                    }
                },
            );
            ui.label("view");
            egui::ComboBox::from_id_salt("view").selected_text(st.settings.debug_view.name()).width(110.0).show_ui(
                ui,
                |ui| {
                    for v in DebugView::ALL {
                        ui.selectable_value(&mut st.settings.debug_view, v, v.name());
                    }
                },
            );
            ui.separator();
            let anim = if st.animate { "pause (Space)" } else { "animate (Space)" };
            if ui.button(anim).clicked() {
                st.animate = !st.animate;
            }
            if ui.button("screenshot (F12)").clicked() {
                out.commands.push(Command::Screenshot);
            }
            if ui.selectable_label(st.tab == Tab::Help, "help (F1)").clicked() {
                st.tab = if st.tab == Tab::Help { Tab::Scene } else { Tab::Help };
            }
            ui.separator();
            ui.label("panels");
            for (on, name, what) in [
                (&mut st.panels.left, "left", "scene, lights, materials, camera, help and the pixel probe"),
                (&mut st.panels.right, "right", "culling figures, GPU times, history"),
                (&mut st.panels.gbuffer, "g-buffer", "the G-buffer thumbnails"),
            ] {
                ui.toggle_value(on, name).on_hover_text(format!(
                    "show or hide the {what}; a window too small for a panel hides it until it grows"
                ));
            }
            // Last, so it wraps onto its own row rather than being drawn over the buttons.
            ui.separator();
            ui.label(RichText::new(f.adapter).weak());
        });
    });
}

fn status_bar(ui: &mut egui::Ui, st: &UiState, f: &FrameInfo) {
    egui::Panel::bottom("status").show(ui, |ui| {
        ui.horizontal(|ui| {
            if let Some((_, [w, h])) = f.viewport {
                ui.label(format!("{w}x{h} px ({:.0}%)", st.resolution_scale * 100.0));
            }
            ui.label(format!("frame {:.1} ms", f.cpu_ms));
            if let Some(ms) = f.stats.and_then(|s| s.gpu_ms.total) {
                ui.label(format!("gpu {ms:.2} ms"));
            }
            ui.label(format!("t = {:.2} s{}", st.time, if st.animate { "" } else { " (paused)" }));
            if f.scripted {
                ui.label(RichText::new("scripted run").color(Color32::LIGHT_BLUE));
            }
            ui.separator();
            if let Some(s) = f.status {
                let c = if s.error { Color32::from_rgb(255, 110, 90) } else { Color32::from_gray(200) };
                ui.label(RichText::new(&s.text).color(c));
            }
        });
    });
}

fn left_panel(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    // The pixel inspector stays in view at the bottom while the tabs scroll above it, when the
    // panel is tall enough for both; in a short window it scrolls with the tab instead of
    // being drawn over it.
    let pinned = ui.available_height() >= PIXEL_PANEL + MIN_TAB_HEIGHT;
    if pinned {
        egui::Panel::bottom("pixel").resizable(false).exact_size(PIXEL_PANEL).show(ui, |ui| pixel_panel(ui, f));
    }
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 2.0;
        // Help has its own button in the top bar (F1).
        for t in Tab::ALL.into_iter().filter(|t| *t != Tab::Help) {
            ui.selectable_value(&mut st.tab, t, t.name());
        }
    });
    ui.separator();
    egui::ScrollArea::vertical().id_salt("left-scroll").auto_shrink([false, false]).show(ui, |ui| {
        match st.tab {
            Tab::Scene => scene_tab(ui, st, f),
            Tab::Lights => lights_tab(ui, st, f, out),
            Tab::Materials => materials_tab(ui, st, f, out),
            Tab::Camera => camera_tab(ui, st, f, out),
            Tab::Help => help_tab(ui),
        }
        if !pinned {
            ui.separator();
            pixel_panel(ui, f);
        }
    });
}

fn reject(out: &mut UiOut, text: String) {
    out.commands.push(Command::Status(Status { text, error: true }));
}

fn scene_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    egui::Grid::new("scene-grid").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        ui.label("lights");
        if st.scene == "demo" {
            let mut n = st.lights.unwrap_or(1024);
            let r = ui
                .add(egui::DragValue::new(&mut n).range(0..=MAX_LIGHTS).speed(4.0))
                .on_hover_text("point lights in the demo (0..100000)");
            if r.changed() {
                st.lights = Some(n);
            }
        } else {
            ui.label(format!("{} (fixed)", f.scene.map_or(0, |s| s.lights.len())));
        }
        ui.end_row();
        ui.label("animate");
        ui.checkbox(&mut st.animate, "lights move (Space)");
        ui.end_row();
        ui.label("time");
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut st.time).range(-1e6..=1e6).speed(0.05).max_decimals(2).suffix(" s"));
            ui.add(egui::DragValue::new(&mut st.time_speed).range(-100.0..=100.0).speed(0.05).prefix("x"));
        });
        ui.end_row();
        ui.label("resolution");
        ui.add(egui::Slider::new(&mut st.resolution_scale, MIN_SCALE..=MAX_SCALE).fixed_decimals(2))
            .on_hover_text("share of the viewport's pixels the scene renders at");
        ui.end_row();
        ui.label("exposure");
        ui.add(egui::Slider::new(&mut st.settings.exposure, 0.05..=16.0).logarithmic(true));
        ui.end_row();
        ui.label("radius x");
        ui.add(egui::Slider::new(&mut st.radius_scale, 0.05..=8.0).logarithmic(true))
            .on_hover_text("every light's radius");
        ui.end_row();
        ui.label("intensity x");
        ui.add(egui::Slider::new(&mut st.intensity_scale, 0.0..=20.0)).on_hover_text("every light's intensity");
        ui.end_row();
        ui.label("depth");
        egui::ComboBox::from_id_salt("depth-format").selected_text(st.settings.depth_format.name()).show_ui(ui, |ui| {
            for d in crate::renderer::DepthFormat::ALL {
                ui.selectable_value(&mut st.settings.depth_format, d, d.name());
            }
        });
        ui.end_row();
        ui.label("light cut-off");
        ui.add(egui::Slider::new(&mut st.settings.light_cutoff, 0.0..=0.25).fixed_decimals(4))
            .on_hover_text("cut each light off where it falls below this fraction of its peak (0 = exact radius)");
        ui.end_row();
        ui.label("sphere / cone");
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut st.settings.sphere_subdivisions).range(0..=4).prefix("subdiv "));
            ui.add(egui::DragValue::new(&mut st.settings.cone_sides).range(3..=64).suffix(" sides"));
        })
        .response
        .on_hover_text("tessellation of the light volumes");
        ui.end_row();
        ui.label("accumulation");
        egui::ComboBox::from_id_salt("accum").selected_text(format!("{:?}", st.settings.accumulation)).show_ui(
            ui,
            |ui| {
                for a in AccumFormat::ALL {
                    ui.selectable_value(&mut st.settings.accumulation, a, format!("{a:?}"));
                }
            },
        );
        ui.end_row();
        ui.label("G-buffer");
        egui::ComboBox::from_id_salt("layout-left").selected_text(st.settings.layout.name()).show_ui(ui, |ui| {
            for l in LayoutChoice::ALL {
                ui.selectable_value(&mut st.settings.layout, l, l.name());
            }
        });
        ui.end_row();
    });
    ui.separator();
    ui.label(RichText::new("Ambient and sun").strong());
    let Some(scene) = f.scene else { return };
    egui::Grid::new("sun-grid").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        ui.label("ambient");
        let mut a = st.ambient.unwrap_or(scene.ambient).to_array();
        if ui.color_edit_button_rgb(&mut a).changed() {
            st.ambient = Some(Vec3::from(a));
        }
        ui.end_row();
        let mut sun = st.sun.unwrap_or(scene.sun);
        let mut on = sun.is_some();
        ui.label("sun");
        if ui.checkbox(&mut on, "on").changed() {
            sun = on.then(Sun::default_sun);
            st.sun = Some(sun);
        }
        ui.end_row();
        if let Some(mut s) = sun {
            // Only what a widget reports as changed is written back: widgets round values
            // (colour pickers, degrees), and merely showing them must not create an edit.
            let mut changed = false;
            ui.label("colour");
            let mut c = s.color.to_array();
            if ui.color_edit_button_rgb(&mut c).changed() {
                s.color = Vec3::from(c);
                changed = true;
            }
            ui.end_row();
            ui.label("intensity");
            changed |= ui.add(egui::DragValue::new(&mut s.intensity).range(0.0..=100.0).speed(0.01)).changed();
            ui.end_row();
            // Direction as azimuth / elevation of the direction the light comes from.
            let d = -s.direction.normalize_or(Vec3::NEG_Y);
            let mut elev = d.y.clamp(-1.0, 1.0).asin().to_degrees();
            let mut azim = d.z.atan2(d.x).to_degrees();
            ui.label("elevation");
            let e = ui.add(egui::DragValue::new(&mut elev).range(1.0..=90.0).suffix("°"));
            ui.end_row();
            ui.label("azimuth");
            let z = ui.add(egui::DragValue::new(&mut azim).range(-180.0..=180.0).suffix("°"));
            ui.end_row();
            if e.changed() || z.changed() {
                let (el, az) = (elev.to_radians(), azim.to_radians());
                s.direction = -Vec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin());
                changed = true;
            }
            if changed {
                st.sun = Some(Some(s));
            }
        }
    });
}

fn light_label(i: usize, l: &Light) -> String {
    match l {
        Light::Point(_) => format!("#{i} point"),
        Light::Spot(_) => format!("#{i} spot"),
    }
}

fn lights_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let Some(scene) = f.scene else {
        ui.label("no scene");
        return;
    };
    ui.label(RichText::new("Selected light").strong());
    match st.selected_light.filter(|k| *k < scene.lights.len()) {
        None => {
            ui.label("none: click a light in the viewport or the list below");
        }
        Some(k) => {
            let light = scene.lights[k];
            ui.horizontal(|ui| {
                ui.label(light_label(k, &light));
                if ui.button("deselect").clicked() {
                    st.selected_light = None;
                }
                if st.light_edits.contains_key(&k) && ui.button("reset").clicked() {
                    st.light_edits.remove(&k);
                }
            });
            if let Some(ls) = f.stats.and_then(|s| s.per_light.get(k)) {
                ui.label(format!(
                    "{} | shaded {} | ideal {} | screen {:.1}%{}{}",
                    method_name(ls.method),
                    fmt_opt(ls.shaded),
                    fmt_opt(ls.ideal),
                    ls.screen_share * 100.0,
                    if ls.crosses_near { " | crosses near" } else { "" },
                    if ls.crosses_far { " | crosses far" } else { "" }
                ));
            }
            let p = light.position();
            ui.label(format!("position {:.2}, {:.2}, {:.2}", p.x, p.y, p.z));
            // Edit the un-scaled values (the global multipliers apply on top).
            let Some(edit) = st.light_edits.get(&k).copied().or_else(|| {
                let mut base = light;
                match &mut base {
                    Light::Point(p) => {
                        p.radius /= st.radius_scale.max(1e-6);
                        p.intensity /= st.intensity_scale.max(1e-6);
                    }
                    Light::Spot(s) => {
                        s.radius /= st.radius_scale.max(1e-6);
                        s.intensity /= st.intensity_scale.max(1e-6);
                    }
                }
                Some(state::LightEdit::of(&base))
            }) else {
                return;
            };
            let mut e = edit;
            let mut changed = false;
            egui::Grid::new("light-edit").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
                ui.label("colour");
                let mut c = e.color.to_array();
                if ui.color_edit_button_rgb(&mut c).changed() {
                    e.color = Vec3::from(c);
                    changed = true;
                }
                ui.end_row();
                ui.label("intensity");
                let w = egui::DragValue::new(&mut e.intensity).range(0.0..=10_000.0).speed(0.02).max_decimals(2);
                changed |= ui.add(w).changed();
                ui.end_row();
                ui.label("radius");
                let w = egui::DragValue::new(&mut e.radius).range(0.01..=10_000.0).speed(0.05).max_decimals(2);
                changed |= ui.add(w).changed();
                ui.end_row();
                if let Some((inner, outer)) = e.angles {
                    let (mut i_deg, mut o_deg) = (inner.to_degrees(), outer.to_degrees());
                    ui.label("inner angle");
                    let ri = ui.add(egui::DragValue::new(&mut i_deg).range(0.0..=90.0).suffix("°").max_decimals(1));
                    ui.end_row();
                    ui.label("outer angle");
                    let ro = ui.add(egui::DragValue::new(&mut o_deg).range(0.0..=90.0).suffix("°").max_decimals(1));
                    ui.end_row();
                    if ri.changed() || ro.changed() {
                        if i_deg > o_deg {
                            // Clamp visibly rather than hand the renderer an inverted cone.
                            i_deg = o_deg;
                            out.commands.push(Command::Status(Status {
                                text: "inner angle clamped to the outer angle".into(),
                                error: true,
                            }));
                        }
                        e.angles = Some((i_deg.to_radians(), o_deg.to_radians()));
                        changed = true;
                    }
                }
            });
            if changed {
                let mut l = light;
                e.apply(&mut l);
                match l.validate() {
                    Ok(()) => {
                        st.light_edits.insert(k, e);
                    }
                    Err(err) => reject(out, format!("light {k}: {err}")),
                }
            }
        }
    }
    ui.separator();
    ui.label(RichText::new(format!("All lights ({})", scene.lights.len())).strong());
    let row_h = 18.0;
    let per_light = f.stats.map(|s| s.per_light.as_slice()).unwrap_or(&[]);
    let mut list = egui::ScrollArea::vertical()
        .id_salt("light-list")
        .max_height(ui.available_height().max(120.0))
        .auto_shrink([false, true]);
    if let Some(k) = f.scroll_to_light {
        // A light picked in the viewport: bring its row into view, a few rows from the top.
        list = list.vertical_scroll_offset((k.saturating_sub(3)) as f32 * (row_h + ui.spacing().item_spacing.y));
    }
    list.show_rows(ui, row_h, scene.lights.len(), |ui, range| {
        for i in range {
            let l = &scene.lights[i];
            ui.horizontal(|ui| {
                let (r, _) = ui.allocate_exact_size(Vec2::new(12.0, 12.0), Sense::hover());
                ui.painter().rect_filled(r, 2.0, colour32(l.color()));
                let ls = per_light.get(i);
                let text = format!(
                    "{:<10}{:>8} {}",
                    light_label(i, l),
                    ls.and_then(|s| s.shaded).map_or("-".into(), fmt_count),
                    ls.map_or(String::new(), |s| method_name(s.method))
                );
                let sel = st.selected_light == Some(i);
                if ui.add(egui::Button::selectable(sel, RichText::new(text).monospace()).truncate()).clicked() {
                    st.selected_light = if sel { None } else { Some(i) };
                }
            });
        }
    });
}

fn materials_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let Some(scene) = f.scene else { return };
    let n = scene.materials.len();
    if n == 0 {
        ui.label("the scene has no materials");
        return;
    }
    st.material_index = st.material_index.min(n - 1);
    ui.horizontal(|ui| {
        ui.label("material");
        ui.add(egui::DragValue::new(&mut st.material_index).range(0..=n - 1));
        ui.label(format!("of {n}"));
    });
    let k = st.material_index;
    let mut m = scene.materials[k];
    let mut changed = false;
    egui::Grid::new("material").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        ui.label("diffuse");
        let mut c = m.diffuse.to_array();
        if ui.color_edit_button_rgb(&mut c).changed() {
            m.diffuse = Vec3::from(c);
            changed = true;
        }
        ui.end_row();
        ui.label("specular level");
        changed |= ui.add(egui::Slider::new(&mut m.specular_level, 0.0..=1.0)).changed();
        ui.end_row();
        ui.label("specular exponent");
        changed |= ui.add(egui::Slider::new(&mut m.specular_exponent, 1.0..=2048.0).logarithmic(true)).changed();
        ui.end_row();
        ui.label("emissive");
        let mut e = m.emissive.to_array();
        if ui.color_edit_button_rgb(&mut e).changed() {
            m.emissive = Vec3::from(e);
            changed = true;
        }
        ui.end_row();
    });
    if changed {
        if m.diffuse.is_finite() && m.emissive.is_finite() && m.emissive.min_element() >= 0.0 {
            st.material_edits.insert(k, m);
        } else {
            reject(out, format!("material {k}: values must be finite and non-negative"));
        }
    }
    if st.material_edits.contains_key(&k) && ui.button("reset material").clicked() {
        st.material_edits.remove(&k);
    }
}

fn camera_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let Some(scene) = f.scene else { return };
    if !scene.viewpoints.is_empty() {
        // The file's cameras, and a view that frames the whole scene.
        ui.horizontal_wrapped(|ui| {
            ui.label("viewpoints");
            for (name, camera) in &scene.viewpoints {
                if ui.button(name).clicked() {
                    st.camera = Some(*camera);
                }
            }
        });
    }
    let before = scene.camera;
    let mut c = before;
    let mut yaw = c.yaw.to_degrees();
    let mut pitch = c.pitch.to_degrees();
    let mut fov = c.fov_y.to_degrees();
    egui::Grid::new("camera").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        ui.label("position");
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut c.position.x).speed(0.1).max_decimals(2));
            ui.add(egui::DragValue::new(&mut c.position.y).speed(0.1).max_decimals(2));
            ui.add(egui::DragValue::new(&mut c.position.z).speed(0.1).max_decimals(2));
        });
        ui.end_row();
        ui.label("yaw");
        ui.add(egui::DragValue::new(&mut yaw).speed(0.5).suffix("°").max_decimals(1));
        ui.end_row();
        ui.label("pitch");
        ui.add(egui::DragValue::new(&mut pitch).range(-89.0..=89.0).speed(0.5).suffix("°").max_decimals(1));
        ui.end_row();
        ui.label("field of view");
        ui.add(egui::DragValue::new(&mut fov).range(5.0..=170.0).speed(0.5).suffix("°").max_decimals(1));
        ui.end_row();
        ui.label("near / far");
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut c.near).range(0.001..=1000.0).speed(0.01));
            ui.add(egui::DragValue::new(&mut c.far).range(0.01..=100_000.0).speed(1.0));
        });
        ui.end_row();
        ui.label("speed");
        ui.add(egui::DragValue::new(&mut st.move_speed).range(0.01..=1000.0).speed(0.1).suffix(" /s"));
        ui.end_row();
    });
    if yaw != before.yaw.to_degrees() {
        c.yaw = yaw.to_radians();
    }
    if pitch != before.pitch.to_degrees() {
        c.pitch = pitch.to_radians();
    }
    if fov != before.fov_y.to_degrees() {
        c.fov_y = fov.to_radians();
    }
    if c != before {
        match c.validate() {
            Ok(()) => st.camera = Some(c),
            Err(e) => reject(out, format!("camera: {e}")),
        }
    }
    if ui.button("reset camera").clicked() {
        out.commands.push(Command::ResetCamera);
    }
}

fn help_tab(ui: &mut egui::Ui) {
    ui.label(RichText::new("Controls").strong());
    egui::Grid::new("help").num_columns(2).striped(true).show(ui, |ui| {
        for (k, what) in camera::BINDINGS {
            ui.label(RichText::new(*k).strong());
            ui.label(*what);
            ui.end_row();
        }
    });
    ui.separator();
    ui.label(RichText::new("Views").strong());
    ui.label("Click a G-buffer thumbnail to show it full size; click 'lit' to return.");
    ui.label("Stencil view (seed 000): blue passed Z when marking, red passed Z when shading, green was lit.");
    ui.label("Complexity: how many lights shaded each pixel.");
    ui.separator();
    ui.label(RichText::new("Scripts").strong());
    ui.label("lampshade view SCENE --script FILE replays one 'FRAME ACTION ARGS' per line (src/app/script.rs).");
}

fn right_panel(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    egui::ScrollArea::vertical().id_salt("right-scroll").auto_shrink([false, false]).show(ui, |ui| {
        if let Some((resident, gpu)) = f.memory {
            ui.label(format!("memory: {} MiB resident, {} MiB in GPU buffers and textures", resident >> 20, gpu >> 20))
                .on_hover_text("sampled every 30 frames; it should stay flat while the viewer runs");
        }
        ui.label(RichText::new("Light culling").strong());
        egui::Grid::new("modes").num_columns(2).spacing([8.0, 2.0]).show(ui, |ui| {
            for (i, m) in CullingMode::ALL.into_iter().enumerate() {
                ui.radio_value(&mut st.settings.culling, m, m.name()).on_hover_text(culling_help(m));
                if i % 2 == 1 {
                    ui.end_row();
                }
            }
        });
        ui.separator();
        figures(ui, st, f);
        ui.separator();
        plots(ui, f.history);
        ui.separator();
        ui.horizontal(|ui| {
            ui.label("view");
            for v in [DebugView::Lit, DebugView::Stencil, DebugView::Complexity] {
                ui.selectable_value(&mut st.settings.debug_view, v, v.name());
            }
        });
        ui.horizontal(|ui| {
            ui.label("of lights");
            ui.selectable_value(&mut st.scope, Scope::All, "all");
            ui.add_enabled_ui(st.selected_light.is_some(), |ui| {
                ui.selectable_value(&mut st.scope, Scope::Selected, "selected");
            });
        });
        if st.settings.debug_view == DebugView::Stencil {
            ui.horizontal(|ui| {
                ui.spacing_mut().item_spacing.x = 3.0;
                for (c, t) in [(Color32::BLUE, "Z pass mark"), (Color32::RED, "Z pass shade"), (Color32::GREEN, "lit")]
                {
                    let (r, _) = ui.allocate_exact_size(Vec2::splat(10.0), Sense::hover());
                    ui.painter().rect_filled(r, 1.0, c);
                    ui.label(RichText::new(t).small());
                }
            });
        }
        ui.horizontal(|ui| {
            ui.label("wireframes");
            ui.selectable_value(&mut st.wireframes, Wireframes::Off, "off");
            ui.selectable_value(&mut st.wireframes, Wireframes::All, "all");
            ui.selectable_value(&mut st.wireframes, Wireframes::Selected, "selected");
        });
        ui.horizontal(|ui| {
            ui.label("colour by");
            ui.selectable_value(&mut st.wire_colour, WireColour::Light, "light");
            ui.selectable_value(&mut st.wire_colour, WireColour::Efficiency, "efficiency");
        });
        if st.wire_colour == WireColour::Efficiency && !st.settings.count_ideal {
            ui.label(RichText::new("efficiency needs 'count ideal'").color(Color32::from_rgb(255, 170, 80)));
        }
        ui.separator();
        egui::CollapsingHeader::new("Counters and depth").default_open(false).show(ui, |ui| {
            ui.checkbox(&mut st.settings.count_fragments, "count shaded fragments");
            ui.checkbox(&mut st.settings.count_ideal, "count ideal (full-screen pass per light)");
            ui.checkbox(&mut st.settings.timestamps, "GPU timestamps");
            ui.checkbox(&mut st.settings.depth_clamp, "depth clamp on volumes");
            ui.checkbox(&mut st.settings.reversed_z, "reversed Z");
        });
    });
}

fn figures(ui: &mut egui::Ui, st: &UiState, f: &FrameInfo) {
    let Some(s) = f.stats else {
        ui.label("no frame yet");
        return;
    };
    let drawn = s.per_light.iter().filter(|l| l.shaded.is_some_and(|v| v > 0)).count();
    let mut methods: BTreeMap<String, usize> = BTreeMap::new();
    for l in &s.per_light {
        *methods.entry(method_name(l.method)).or_default() += 1;
    }
    egui::Grid::new("figures").num_columns(2).striped(true).spacing([12.0, 2.0]).show(ui, |ui| {
        let row = |ui: &mut egui::Ui, k: &str, v: String| {
            ui.label(k);
            // Truncated: an exact-size panel must never be pushed wider by its content.
            ui.add(egui::Label::new(RichText::new(v).monospace()).truncate());
            ui.end_row();
        };
        row(
            ui,
            "lights shading",
            if s.shaded_fragments.is_some() {
                format!("{drawn} of {}", s.lights)
            } else {
                format!("? of {} (counts off)", s.lights)
            },
        );
        let m: Vec<String> = methods.iter().map(|(k, v)| format!("{k} {v}")).collect();
        row(ui, "methods", m.join(", "));
        row(ui, "shaded fragments", s.shaded_fragments.map_or("-".into(), fmt_count));
        row(
            ui,
            "ideal fragments",
            s.ideal_fragments.map_or(if st.settings.count_ideal { "-".into() } else { "off".into() }, fmt_count),
        );
        row(ui, "efficiency", s.efficiency.map_or("-".into(), |e| format!("{:.1} %", e * 100.0)));
        row(ui, "GPU g-buffer", fmt_ms(s.gpu_ms.gbuffer));
        row(ui, "GPU lighting", fmt_ms(s.gpu_ms.lighting));
        row(ui, "GPU compose", fmt_ms(s.gpu_ms.compose));
        row(ui, "GPU total", fmt_ms(s.gpu_ms.total));
    });
}

fn plot(ui: &mut egui::Ui, title: &str, series: &[(&str, Color32, Vec<Option<f64>>)], unit: &str) {
    let width = ui.available_width().max(100.0);
    let (rect, _) = ui.allocate_exact_size(Vec2::new(width, 52.0), Sense::hover());
    let p = ui.painter_at(rect);
    p.rect_filled(rect, 2.0, Color32::from_gray(18));
    let max = series.iter().flat_map(|(_, _, v)| v.iter().flatten()).fold(0.0f64, |a, b| a.max(*b)).max(1e-9);
    for (_, colour, values) in series {
        let n = values.len().max(2);
        let mut run: Vec<Pos2> = Vec::new();
        for (i, v) in values.iter().enumerate() {
            match v {
                Some(v) => run.push(Pos2::new(
                    rect.left() + rect.width() * i as f32 / (n - 1) as f32,
                    rect.bottom() - 2.0 - (rect.height() - 14.0) * (*v / max) as f32,
                )),
                None => {
                    if run.len() > 1 {
                        p.line(std::mem::take(&mut run), Stroke::new(1.2, *colour));
                    }
                    run.clear();
                }
            }
        }
        if run.len() > 1 {
            p.line(run, Stroke::new(1.2, *colour));
        }
    }
    let legend: Vec<String> = series
        .iter()
        .map(|(name, _, v)| {
            format!("{name} {}", v.iter().rev().flatten().next().map_or("-".into(), |x| format!("{x:.1}")))
        })
        .collect();
    p.text(
        rect.left_top() + Vec2::new(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{title}: {}   (max {max:.1}{unit})", legend.join(", ")),
        egui::FontId::proportional(10.0),
        Color32::from_gray(190),
    );
}

fn plots(ui: &mut egui::Ui, h: &History) {
    let ms = |g: fn(&Sample) -> Option<f64>| h.samples.iter().map(g).collect::<Vec<_>>();
    plot(
        ui,
        "GPU ms",
        &[
            ("total", Color32::from_rgb(250, 200, 80), ms(|s| s.gpu_total)),
            ("lights", Color32::from_rgb(120, 180, 255), ms(|s| s.lighting)),
        ],
        " ms",
    );
    let k =
        |g: fn(&Sample) -> Option<u64>| h.samples.iter().map(|s| g(s).map(|v| v as f64 / 1000.0)).collect::<Vec<_>>();
    plot(
        ui,
        "k fragments",
        &[
            ("shaded", Color32::from_rgb(255, 120, 90), k(|s| s.shaded)),
            ("ideal", Color32::from_rgb(110, 220, 110), k(|s| s.ideal)),
        ],
        "k",
    );
}

fn v3(v: Vec3) -> String {
    format!("{:.3} {:.3} {:.3}", v.x, v.y, v.z)
}

fn pixel_panel(ui: &mut egui::Ui, f: &FrameInfo) {
    ui.label(RichText::new("Pixel under the cursor").strong());
    let Some(p) = f.probe else {
        ui.label("hover the viewport");
        return;
    };
    egui::Grid::new("probe").num_columns(2).striped(true).spacing([10.0, 2.0]).show(ui, |ui| {
        let row = |ui: &mut egui::Ui, k: &str, v: String| {
            ui.label(k);
            // Truncated: an exact-size panel must never be pushed wider by its content.
            ui.add(egui::Label::new(RichText::new(v).monospace()).truncate());
            ui.end_row();
        };
        row(ui, "pixel", format!("{}, {}", p.x, p.y));
        if !p.valid {
            row(ui, "surface", "background".into());
        } else {
            row(ui, "albedo", v3(p.albedo));
            row(ui, "spec level / exp", format!("{:.3} / {:.1}", p.specular_level, p.specular_exponent));
            row(ui, "normal (view)", v3(p.normal));
            row(ui, "emissive", v3(p.emissive));
            let q = p.position;
            row(ui, "position (view)", format!("{:.2} {:.2} {:.2}", q.x, q.y, q.z));
            row(ui, "diffuse light", v3(p.diffuse_light));
            row(ui, "specular light", v3(p.specular_light));
            row(ui, "lit (linear)", v3(p.lit));
        }
        let shown: Vec<String> = p.lights.iter().take(12).map(|i| i.to_string()).collect();
        let more = if p.lights.len() > 12 { format!(" +{}", p.lights.len() - 12) } else { String::new() };
        let list = if p.lights.is_empty() {
            "none".to_string()
        } else {
            format!("{}: {}{more}", p.lights.len(), shown.join(" "))
        };
        row(ui, "lights touching", list);
    });
    ui.label(RichText::new("raw G-buffer channels (hover)").weak()).on_hover_ui(|ui| {
        for (name, format, v) in &p.raw {
            ui.label(RichText::new(format!("{name} ({format})")).weak());
            ui.label(RichText::new(format!("{:.4} {:.4} {:.4} {:.4}", v[0], v[1], v[2], v[3])).monospace());
        }
    });
}

fn gbuffer_strip(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    // In a horizontal scroll area the last items get little width: never wrap their labels.
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
    ui.horizontal(|ui| {
        ui.label(RichText::new("G-buffer").strong());
        egui::ComboBox::from_id_salt("layout").selected_text(st.settings.layout.name()).width(90.0).show_ui(ui, |ui| {
            for l in LayoutChoice::ALL {
                ui.selectable_value(&mut st.settings.layout, l, l.name());
            }
        });
        ui.label(format!("{} B/pixel in colour targets + {}", f.gbuffer_bytes, f.depth_format));
        ui.label(RichText::new("click a view to show it full size").weak());
    });
    // As many tiles as fit side by side, in the viewport's aspect, as tall as the strip allows.
    let n = f.tiles.len().max(1) as f32;
    let gap = 6.0;
    let aspect = f.viewport.map_or(16.0 / 9.0, |(_, [w, h])| w as f32 / h.max(1) as f32);
    let max_h = (ui.available_height() - 40.0).clamp(24.0, 120.0);
    let thumb_w = ((ui.available_width() - gap * (n - 1.0)) / n).clamp(64.0, (max_h * aspect).max(64.0));
    let thumb_h = thumb_w / aspect;
    egui::ScrollArea::horizontal().id_salt("thumbs").auto_shrink([false, true]).show(ui, |ui| {
        ui.horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = gap;
            for t in f.tiles {
                ui.vertical(|ui| {
                    ui.set_width(thumb_w);
                    ui.spacing_mut().item_spacing.y = 1.0;
                    let selected = st.settings.debug_view == t.view;
                    let (rect, resp) = ui.allocate_exact_size(Vec2::new(thumb_w, thumb_h), Sense::click());
                    match f.thumbs.get(&t.view) {
                        Some(id) => {
                            let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
                            // The stencil and complexity views need passes of their own: the
                            // frame computes them only while shown, else the tile is stale.
                            let stale = matches!(t.view, DebugView::Stencil | DebugView::Complexity) && !selected;
                            let tint = if stale { Color32::from_gray(70) } else { Color32::WHITE };
                            ui.painter().image(*id, rect, uv, tint);
                        }
                        None => {
                            ui.painter().rect_filled(rect, 0.0, Color32::from_gray(10));
                        }
                    }
                    let stroke = if selected {
                        Stroke::new(2.0, Color32::from_rgb(255, 200, 60))
                    } else if resp.hovered() {
                        Stroke::new(1.0, Color32::from_gray(200))
                    } else {
                        Stroke::new(1.0, Color32::from_gray(60))
                    };
                    ui.painter().rect_stroke(rect, 0.0, stroke, egui::StrokeKind::Outside);
                    if matches!(t.view, DebugView::Stencil | DebugView::Complexity) && !selected {
                        ui.painter().text(
                            rect.center(),
                            egui::Align2::CENTER_CENTER,
                            "click to compute",
                            egui::FontId::proportional(10.0),
                            Color32::from_gray(150),
                        );
                    }
                    let resp = resp.on_hover_text(format!("{}: {} ({})", t.label, t.buffer, t.format));
                    if resp.clicked() {
                        st.settings.debug_view = if selected { DebugView::Lit } else { t.view };
                    }
                    ui.add(egui::Label::new(RichText::new(t.label).small()).truncate());
                    ui.add(egui::Label::new(RichText::new(&t.format).small().weak()).truncate());
                });
            }
        });
    });
}

fn viewport(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let rect = ui.available_rect_before_wrap();
    out.viewport_rect = Some(rect);
    let resp = ui.allocate_rect(rect, Sense::click_and_drag());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::BLACK);
    let Some((id, [w, h])) = f.viewport else {
        painter.text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "no image",
            egui::FontId::proportional(14.0),
            Color32::GRAY,
        );
        return;
    };
    painter.image(id, rect, Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)), Color32::WHITE);
    let to_screen = |p: glam::Vec2| rect.min + Vec2::new(p.x / w as f32 * rect.width(), p.y / h as f32 * rect.height());
    // Light-volume wireframes, coloured by light colour or by the light's efficiency.
    if let Some(scene) = f.scene {
        for (i, segs) in f.wireframes {
            let colour = match st.wire_colour {
                WireColour::Light => colour32(scene.lights.get(*i).map_or(Vec3::ONE, |l| l.color())),
                WireColour::Efficiency => {
                    match f.stats.and_then(|s| s.per_light.get(*i)).and_then(|l| Some((l.shaded?, l.ideal?))) {
                        Some((s, i)) => efficiency_colour(if s == 0 { 1.0 } else { i as f64 / s as f64 }),
                        None => Color32::GRAY,
                    }
                }
            };
            let width = if st.selected_light == Some(*i) { 1.8 } else { 0.8 };
            for [a, b] in segs {
                painter.line_segment([to_screen(*a), to_screen(*b)], Stroke::new(width, colour));
            }
        }
    }
    let to_pixel = |pos: Pos2| -> [f32; 2] {
        [(pos.x - rect.left()) / rect.width() * w as f32, (pos.y - rect.top()) / rect.height() * h as f32]
    };
    if let Some(pos) = resp.hover_pos() {
        let [x, y] = to_pixel(pos);
        if x >= 0.0 && y >= 0.0 && (x as u32) < w && (y as u32) < h {
            out.hover_pixel = Some([x as u32, y as u32]);
            let c = Color32::from_rgba_unmultiplied(255, 255, 255, 120);
            painter.line_segment([Pos2::new(pos.x - 8.0, pos.y), Pos2::new(pos.x + 8.0, pos.y)], Stroke::new(1.0, c));
            painter.line_segment([Pos2::new(pos.x, pos.y - 8.0), Pos2::new(pos.x, pos.y + 8.0)], Stroke::new(1.0, c));
        }
    }
    if resp.clicked() {
        if let Some(pos) = resp.interact_pointer_pos() {
            out.click_pixel = Some(to_pixel(pos));
        }
    }
    if resp.dragged() {
        out.drag += resp.drag_delta();
    }
    if st.settings.debug_view != DebugView::Lit {
        painter.text(
            rect.left_top() + Vec2::new(6.0, 4.0),
            egui::Align2::LEFT_TOP,
            format!("view: {}", st.settings.debug_view.name()),
            egui::FontId::proportional(12.0),
            Color32::from_rgb(255, 200, 60),
        );
    }
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
