//! The shadow-atlas panel, a window beside the viewport. The last frame's atlas as
//! an image (`Last::draw_shadow_atlas`: linear depth stretched over the range present),
//! every tile outlined (the sun's cascades in the `cascades` view's colours, spots violet, cube
//! faces cyan), the selected light's tiles highlighted; hover a tile for its light, face or
//! cascade, resolution and texel size; click one to select its light (the light editor's
//! selection). Scroll zooms about the pointer, drag pans, double-click fits. Beside it the
//! frame's `ShadowStats` and the shadow knobs.

use super::common::colour32;
use super::common::fmt_count;
use super::common::AtlasInfo;
use super::common::Command;
use super::common::FrameInfo;
use super::common::Status;
use super::common::UiOut;
use crate::app::state;
use crate::app::state::Tab;
use crate::app::state::UiState;
use crate::renderer::inspect::{AtlasTile, TileOwner};
use crate::renderer::knobs;
use crate::renderer::shadows::{kind_casts, ShadowStats};
use crate::renderer::ShadowMode;
use crate::scene::Light;
use crate::scene::Scene;
use egui::Color32;
use egui::Pos2;
use egui::Rect;
use egui::RichText;
use egui::Sense;
use egui::Stroke;
use egui::Vec2;
use glam::Vec3;
use state::AtlasView;

/// The selected light's outline.
pub const SELECTED: Color32 = Color32::from_rgb(255, 150, 0);
/// A spot's tile and a cube face's: hues no grey of the depth image and no cascade colour
/// comes near.
pub const SPOT: Color32 = Color32::from_rgb(230, 60, 255);
pub const CUBE: Color32 = Color32::from_rgb(0, 230, 230);
/// Outline widths in points.
pub const WIDTH: f32 = 1.0;
pub const SELECTED_WIDTH: f32 = 3.0;
/// Most zoom: a texel of a 2048 atlas then spans several points.
pub const MAX_ZOOM: f32 = 64.0;
/// Cube face names, in `shadows::FACES` order (view-space axes).
pub const FACE_NAMES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// The `cascades` view's colour of cascade `i` (its linear tints, shown as sRGB).
pub fn cascade_colour(i: u32) -> Color32 {
    let tints =
        [Vec3::new(1.0, 0.25, 0.25), Vec3::new(0.25, 1.0, 0.25), Vec3::new(0.3, 0.45, 1.0), Vec3::new(1.0, 1.0, 0.25)];
    colour32(tints[(i as usize).min(3)])
}

/// One outline of the panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelTile {
    /// Index into the tiles given.
    pub index: usize,
    pub rect: Rect,
    pub colour: Color32,
    pub width: f32,
    pub selected: bool,
}

/// The part of the atlas the image shows, as [u0, v0, u1, v1] in atlas fractions: a window of
/// 1/zoom around the centre, kept inside the atlas.
pub fn visible(view: AtlasView) -> [f32; 4] {
    let zoom = view.zoom.clamp(1.0, MAX_ZOOM);
    let half = 0.5 / zoom;
    let c = |v: f32| if v.is_finite() { v.clamp(half, 1.0 - half) } else { 0.5 };
    let (cx, cy) = (c(view.centre[0]), c(view.centre[1]));
    [cx - half, cy - half, cx + half, cy + half]
}

/// Atlas texel coordinates of panel point `p` drawn into `image` under `view`.
pub fn to_atlas(p: Pos2, image: Rect, side: u32, view: AtlasView) -> [f32; 2] {
    let [u0, v0, u1, v1] = visible(view);
    let u = u0 + (p.x - image.min.x) / image.width().max(1e-6) * (u1 - u0);
    let v = v0 + (p.y - image.min.y) / image.height().max(1e-6) * (v1 - v0);
    [u * side as f32, v * side as f32]
}

/// Panel point of atlas texel coordinates `t`.
pub fn to_panel(t: [f32; 2], image: Rect, side: u32, view: AtlasView) -> Pos2 {
    let [u0, v0, u1, v1] = visible(view);
    let s = side.max(1) as f32;
    Pos2::new(
        image.min.x + (t[0] / s - u0) / (u1 - u0) * image.width(),
        image.min.y + (t[1] / s - v0) / (v1 - v0) * image.height(),
    )
}

/// Each tile's outline in the panel: its texel rectangle mapped into `image`, coloured by
/// owner (cascade colours, spot, cube face), the selected light's tiles in [`SELECTED`] and
/// wider, drawn last so no neighbour covers them. Tiles outside the visible part are left out.
pub fn panel_tiles(
    tiles: &[AtlasTile],
    side: u32,
    image: Rect,
    view: AtlasView,
    selected: Option<usize>,
) -> Vec<PanelTile> {
    let mut out: Vec<PanelTile> = tiles
        .iter()
        .enumerate()
        .filter_map(|(index, t)| {
            let a = to_panel([t.x as f32, t.y as f32], image, side, view);
            let b = to_panel([(t.x + t.size) as f32, (t.y + t.size) as f32], image, side, view);
            let rect = Rect::from_min_max(a, b);
            let shown = rect.intersect(image);
            if shown.width() <= 0.0 || shown.height() <= 0.0 {
                return None;
            }
            let is_selected = selected.is_some() && t.owner.light() == selected;
            let colour = match t.owner {
                _ if is_selected => SELECTED,
                TileOwner::Sun => cascade_colour(t.face),
                TileOwner::Spot(_) => SPOT,
                TileOwner::Cube(_) => CUBE,
            };
            let width = if is_selected { SELECTED_WIDTH } else { WIDTH };
            Some(PanelTile { index, rect, colour, width, selected: is_selected })
        })
        .collect();
    out.sort_by_key(|t| t.selected);
    out
}

/// The tile under panel point `p`, if any.
pub fn tile_at(tiles: &[AtlasTile], side: u32, image: Rect, view: AtlasView, p: Pos2) -> Option<usize> {
    if !image.contains(p) {
        return None;
    }
    let [x, y] = to_atlas(p, image, side, view);
    tiles
        .iter()
        .position(|t| x >= t.x as f32 && y >= t.y as f32 && x < (t.x + t.size) as f32 && y < (t.y + t.size) as f32)
}

/// A length in metres, readably.
fn metres(m: f32) -> String {
    if m >= 1.0 {
        format!("{m:.2} m")
    } else if m >= 0.01 {
        format!("{:.1} cm", m * 100.0)
    } else {
        format!("{:.2} mm", m * 1000.0)
    }
}

/// The hover text of a tile.
pub fn describe(t: &AtlasTile, scene: Option<&Scene>, cascades: u32) -> String {
    let who = match t.owner {
        TileOwner::Sun => format!("sun, cascade {} of {cascades}", t.face),
        TileOwner::Spot(i) => format!("light {i}: spot, one perspective tile"),
        TileOwner::Cube(i) => {
            let kind = match scene.and_then(|s| s.lights.get(i)) {
                Some(Light::Spot(_)) => "wide spot",
                _ => "point",
            };
            format!("light {i}: {kind}, cube face {} ({} of 6)", FACE_NAMES[(t.face as usize).min(5)], t.face + 1)
        }
    };
    let texel = if t.orthographic {
        format!("texel {} at every receiver", metres(t.texel))
    } else {
        format!("texel {} per metre from the light", metres(t.texel))
    };
    let click = if t.owner.light().is_some() { "\nclick: select the light" } else { "" };
    format!("{who}\n{0}x{0} texels at ({1}, {2})\n{texel}{click}", t.size, t.x, t.y)
}

pub(super) fn shadow_window(ctx: &egui::Context, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let mut open = st.panels.shadows;
    egui::Window::new("Shadow atlas")
        .open(&mut open)
        .default_pos(f.atlas_default_pos)
        .default_size([380.0, 560.0])
        .resizable(true)
        .scroll([false, true])
        .show(ctx, |ui| atlas_panel(ui, st, f, out));
    st.panels.shadows = open;
}

fn atlas_panel(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let stats = f.stats.and_then(|s| s.shadow.as_ref());
    let Some(a) = f.atlas.as_ref() else {
        ui.label("no frame yet");
        return;
    };
    if st.settings.shadows == ShadowMode::None {
        ui.label(RichText::new("shadows are off: pick sun, spots or all below").color(Color32::from_rgb(255, 170, 80)));
    }
    atlas_sizes(ui, a, stats);
    // Contrast, stated: what grey means in this frame's image.
    match a.range {
        Some((lo, hi)) => ui.label(
            RichText::new(format!(
                "grey: stored linear depth, near white to far black, stretched over {lo:.4} … {hi:.4} of each \
                 tile's far distance; dark blue: nothing cast"
            ))
            .small(),
        ),
        None => ui.label(RichText::new("no depth in the atlas this frame (nothing cast)").small()),
    };
    ui.horizontal(|ui| {
        if ui.button("fit").on_hover_text("the whole atlas (double-click the image)").clicked() {
            st.atlas_view = AtlasView::default();
        }
        if ui.button("1:1").on_hover_text("one atlas texel a screen pixel").clicked() {
            let w = ui.available_width().max(1.0) * ui.ctx().pixels_per_point();
            st.atlas_view.zoom = (a.side as f32 / w).clamp(1.0, MAX_ZOOM);
        }
        ui.label(RichText::new(format!("zoom x{:.1}: scroll zooms, drag pans", st.atlas_view.zoom)).small().weak());
    });
    // The image: square, as wide as the window allows.
    let w = ui.available_width().clamp(120.0, 1200.0);
    let (image, resp) = ui.allocate_exact_size(Vec2::splat(w), Sense::click_and_drag());
    out.atlas_rect = Some(image);
    let painter = ui.painter_at(image);
    painter.rect_filled(image, 0.0, Color32::from_gray(10));
    let view = st.atlas_view;
    if let Some(id) = a.image {
        let [u0, v0, u1, v1] = visible(view);
        painter.image(id, image, Rect::from_min_max(Pos2::new(u0, v0), Pos2::new(u1, v1)), Color32::WHITE);
    }
    for t in panel_tiles(a.tiles, a.side, image, view, st.selected_light) {
        painter.rect_stroke(t.rect, 0.0, Stroke::new(t.width, t.colour), egui::StrokeKind::Inside);
    }
    navigate(ui, &mut st.atlas_view, &resp, image, a.side);
    let cascades = stats.map_or(0, |s| s.sun_cascades);
    if let Some(p) = resp.hover_pos() {
        if let Some(k) = tile_at(a.tiles, a.side, image, view, p) {
            let text = describe(&a.tiles[k], f.scene, cascades);
            resp.clone().on_hover_ui_at_pointer(|ui| {
                ui.label(text);
            });
        }
    }
    if resp.clicked() {
        if let Some(p) = resp.interact_pointer_pos() {
            if let Some(i) = tile_at(a.tiles, a.side, image, view, p).and_then(|k| a.tiles[k].owner.light()) {
                st.selected_light = Some(i);
                st.tab = Tab::Lights;
                out.commands.push(Command::Status(Status { text: format!("selected light {i}"), error: false }));
            }
        }
    }
    legend(ui, cascades);
    ui.separator();
    atlas_figures(ui, st, f, a, stats);
    ui.separator();
    egui::CollapsingHeader::new("Shadow settings").id_salt("atlas-knobs").default_open(true).show(ui, |ui| {
        shadow_knobs(ui, st, "atlas");
    });
}

/// The atlas's size and format, its memory and use, and the cube array's and indirection
/// cube's where there are.
fn atlas_sizes(ui: &mut egui::Ui, a: &AtlasInfo, stats: Option<&ShadowStats>) {
    ui.horizontal(|ui| {
        ui.label(format!("{0}x{0} {1:?}", a.side, a.format));
        if let Some(s) = stats {
            ui.label(format!("{:.1} MiB, {:.0}% used", s.atlas_bytes as f64 / 1048576.0, s.atlas_used * 100.0));
            if s.cube_bytes > 0 {
                ui.label(format!(
                    "+ cube array {0}x{0} x{1}: {2:.1} MiB",
                    s.cube_side,
                    s.cube_layers,
                    s.cube_bytes as f64 / 1048576.0
                ));
            }
            if s.indirection_bytes > 0 {
                ui.label(format!(
                    "+ indirection cube {0}x{0}: {1:.1} MiB",
                    s.indirection_side,
                    s.indirection_bytes as f64 / 1048576.0
                ))
                .on_hover_text(
                    "seed 002's G16R16 cube: the face and face coordinates of every direction, read \
                         nearest; lookups within about half a texel of the face pick's (frame.md)",
                );
            }
        }
    });
}

/// The image's navigation: zoom about the pointer, pan by dragging, fit on double-click; the
/// centre kept where `visible` puts it.
fn navigate(ui: &mut egui::Ui, atlas_view: &mut AtlasView, resp: &egui::Response, image: Rect, side: u32) {
    let view = *atlas_view;
    if let Some(p) = resp.hover_pos() {
        // Taken, so the window's own scroll area does not scroll too.
        let scroll = ui.input_mut(|i| std::mem::take(&mut i.smooth_scroll_delta.y));
        if scroll != 0.0 {
            let before = to_atlas(p, image, side, view);
            let zoom = (view.zoom * (scroll / 200.0).exp()).clamp(1.0, MAX_ZOOM);
            let mut next = AtlasView { zoom, ..view };
            let after = to_atlas(p, image, side, next);
            let s = side.max(1) as f32;
            let c = visible(view);
            next.centre =
                [(c[0] + c[2]) / 2.0 + (before[0] - after[0]) / s, (c[1] + c[3]) / 2.0 + (before[1] - after[1]) / s];
            *atlas_view = next;
        }
    }
    if resp.dragged() {
        let d = resp.drag_delta();
        let c = visible(view);
        let span = (c[2] - c[0], c[3] - c[1]);
        atlas_view.centre = [
            (c[0] + c[2]) / 2.0 - d.x / image.width().max(1.0) * span.0,
            (c[1] + c[3]) / 2.0 - d.y / image.height().max(1.0) * span.1,
        ];
    }
    if resp.double_clicked() {
        *atlas_view = AtlasView::default();
    }
    // The centre kept where `visible` puts it.
    let c = visible(*atlas_view);
    atlas_view.centre = [(c[0] + c[2]) / 2.0, (c[1] + c[3]) / 2.0];
}

fn legend(ui: &mut egui::Ui, cascades: u32) {
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 3.0;
        let mut key = |c: Color32, t: &str| {
            let (r, _) = ui.allocate_exact_size(Vec2::splat(10.0), Sense::hover());
            ui.painter().rect_stroke(r, 0.0, Stroke::new(2.0, c), egui::StrokeKind::Inside);
            ui.label(RichText::new(t).small());
        };
        for i in 0..cascades.min(4) {
            key(cascade_colour(i), &format!("cascade {i}"));
        }
        key(SPOT, "spot");
        key(CUBE, "cube face");
        key(SELECTED, "selected light");
    });
}

/// The frame's `ShadowStats`, every fallback named, and the lights that cast but have no tile.
fn atlas_figures(ui: &mut egui::Ui, st: &UiState, f: &FrameInfo, a: &AtlasInfo, stats: Option<&ShadowStats>) {
    let Some(s) = stats else {
        ui.label("no shadow figures (shadows off)");
        return;
    };
    egui::Grid::new("shadow-figures").num_columns(2).striped(true).spacing([12.0, 2.0]).show(ui, |ui| {
        let mut row = |k: &str, v: String| {
            ui.label(k);
            ui.add(egui::Label::new(RichText::new(v).monospace()).truncate());
            ui.end_row();
        };
        row("casters", format!("{} (mode {}, filter {})", s.casting, s.mode.name(), s.filter.name()));
        row("sun cascades", s.sun_cascades.to_string());
        row("tiles", s.tiles.to_string());
        row("fallback: off screen", s.fallback_off_screen.to_string());
        row("fallback: budget", s.fallback_budget.to_string());
        row("flag off", s.flag_off.to_string());
        row("atlas use", format!("{:.1}% of {}x{}", s.atlas_used * 100.0, s.atlas_side, s.atlas_side));
        row("caster draws", fmt_count(s.caster_draws));
        row("shadow pass", s.gpu_ms.map_or("- (timestamps off)".into(), |ms| format!("{ms:.2} ms")));
        // What the shaders compile in: only the lookups some light can need (a mode or scene
        // edit that needs another compiles a new pipeline set).
        let lookups = f.stats.map(|fs| fs.shader_lookups.join(", ")).filter(|l| !l.is_empty());
        row("compiled lookups", lookups.unwrap_or_else(|| "none".into()));
    });
    // Lights asked to cast that have no tile in the atlas: off screen, over the budget, or
    // shadowed outside it (a cube array): listed, never silently dropped.
    let Some(scene) = f.scene else { return };
    let in_atlas: std::collections::BTreeSet<usize> = a.tiles.iter().filter_map(|t| t.owner.light()).collect();
    let mut missing: Vec<String> = Vec::new();
    let mut flag_off: Vec<usize> = Vec::new();
    for (i, l) in scene.lights.iter().enumerate() {
        if !kind_casts(l, s.mode) || in_atlas.contains(&i) {
            continue;
        }
        if !l.cast_shadows() {
            flag_off.push(i);
            continue;
        }
        let on_screen = f.stats.and_then(|s| s.per_light.get(i)).is_some_and(|p| p.screen_share > 0.0);
        missing.push(format!(
            "light {i}: not in the atlas ({})",
            if on_screen { "atlas full, or shadowed outside it" } else { "off screen" }
        ));
    }
    if let Some(k) = st.selected_light.filter(|k| !in_atlas.contains(k)) {
        let why = match scene.lights.get(k) {
            Some(l) if !kind_casts(l, s.mode) => format!("its kind does not cast under --shadows {}", s.mode.name()),
            Some(l) if !l.cast_shadows() => "its 'casts' flag is off".into(),
            Some(_) => "not in the atlas".into(),
            None => "no such light".into(),
        };
        ui.label(RichText::new(format!("selected light {k}: no tile ({why})")).color(SELECTED));
    }
    if !missing.is_empty() || !flag_off.is_empty() {
        egui::CollapsingHeader::new(format!("lights without a tile ({})", missing.len() + flag_off.len()))
            .id_salt("atlas-missing")
            .show(ui, |ui| {
                for m in missing.iter().take(64) {
                    ui.label(RichText::new(m).small());
                }
                if missing.len() > 64 {
                    ui.label(RichText::new(format!("… and {} more", missing.len() - 64)).small());
                }
                if !flag_off.is_empty() {
                    let list: Vec<String> = flag_off.iter().take(64).map(|i| i.to_string()).collect();
                    ui.label(RichText::new(format!("'casts' off: lights {}", list.join(", "))).small());
                }
            });
    }
}

/// The shadow knobs (rows of `knobs.rs`): casters, budget, biases, filter, cascades, split.
/// `salt` keeps the widgets' ids apart where the group is shown twice.
pub(super) fn shadow_knobs(ui: &mut egui::Ui, st: &mut UiState, salt: &str) {
    let s = &mut st.settings;
    egui::Grid::new((salt, "shadow-knobs")).num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        ui.label("casters");
        super::common::knob_choice(ui, (salt, "shadows"), &mut s.shadows);
        ui.end_row();
        ui.label("filter");
        super::common::knob_choice(ui, (salt, "filter"), &mut s.shadow_filter);
        ui.end_row();
        ui.label("format");
        super::common::knob_choice(ui, (salt, "format"), &mut s.shadow_format);
        ui.end_row();
        for (label, name, value) in [
            ("budget", "shadow-budget", &mut s.shadow_budget_mb),
            ("depth bias", "shadow-bias", &mut s.shadow_bias),
            ("slope bias", "shadow-slope-bias", &mut s.shadow_slope_bias),
            ("normal offset", "shadow-normal-offset", &mut s.shadow_normal_offset),
            ("split λ", "shadow-split-lambda", &mut s.shadow_split_lambda),
        ] {
            let knob = knobs::find(name);
            ui.label(label);
            let span = knob.and_then(|k| k.slider()).unwrap_or(0.0..=1.0);
            let mut slider = egui::Slider::new(value, span).clamping(egui::SliderClamping::Edits);
            if name == "shadow-budget" {
                slider = slider.logarithmic(true).suffix(" MiB");
            }
            ui.add(slider).on_hover_text(knob.map_or("", |k| k.help));
            ui.end_row();
        }
        ui.label("cascades");
        let range = knobs::find("shadow-cascades").and_then(|k| k.whole_range()).unwrap_or(1..=4);
        ui.add(egui::DragValue::new(&mut s.shadow_cascades).range(range));
        ui.end_row();
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile(owner: TileOwner, face: u32, x: u32, y: u32, size: u32) -> AtlasTile {
        AtlasTile { owner, face, x, y, size, texel: 0.01, orthographic: owner == TileOwner::Sun }
    }

    /// A 2048 atlas: two sun cascades, a spot (light 3), a point light's six faces (light 5).
    fn plan() -> Vec<AtlasTile> {
        let mut t = vec![tile(TileOwner::Sun, 0, 0, 0, 512), tile(TileOwner::Sun, 1, 512, 0, 512)];
        t.push(tile(TileOwner::Spot(3), 0, 1024, 0, 256));
        for f in 0..6 {
            t.push(tile(TileOwner::Cube(5), f, 1280 + 128 * (f % 2), 128 * (f / 2), 128));
        }
        t
    }

    fn close(a: Rect, b: Rect) -> bool {
        (a.min - b.min).length() < 1e-3 && (a.max - b.max).length() < 1e-3
    }

    #[test]
    fn tiles_map_to_panel_rectangles_and_the_selected_light_is_highlighted() {
        let tiles = plan();
        // 400 points for 2048 texels: 0.1953125 points a texel.
        let image = Rect::from_min_size(Pos2::new(100.0, 50.0), Vec2::splat(400.0));
        let k = 400.0 / 2048.0;
        let out = panel_tiles(&tiles, 2048, image, AtlasView::default(), Some(5));
        assert_eq!(out.len(), tiles.len(), "every tile is visible at zoom 1");
        for p in &out {
            let t = &tiles[p.index];
            let want = Rect::from_min_size(
                Pos2::new(100.0 + t.x as f32 * k, 50.0 + t.y as f32 * k),
                Vec2::splat(t.size as f32 * k),
            );
            assert!(close(p.rect, want), "tile {:?}: {:?}, want {want:?}", t, p.rect);
            // The selected light's tiles (all six faces of light 5) and only those are
            // highlighted; the others keep their owner's colour.
            let selected = t.owner == TileOwner::Cube(5);
            assert_eq!(p.selected, selected, "{t:?}");
            let colour = match t.owner {
                TileOwner::Cube(5) => SELECTED,
                TileOwner::Sun => cascade_colour(t.face),
                TileOwner::Spot(_) => SPOT,
                TileOwner::Cube(_) => CUBE,
            };
            assert_eq!((p.colour, p.width), (colour, if selected { SELECTED_WIDTH } else { WIDTH }), "{t:?}");
        }
        // The highlight is drawn last (nothing covers it).
        let first_selected = out.iter().position(|p| p.selected).expect("a highlighted tile");
        assert!(out[first_selected..].iter().all(|p| p.selected));
        assert_eq!(out.iter().filter(|p| p.selected).count(), 6);
        // The cascades keep the `cascades` view's colours, distinct from the highlight.
        assert_eq!(cascade_colour(0), colour32(Vec3::new(1.0, 0.25, 0.25)));
        assert_ne!(cascade_colour(0), cascade_colour(1));
        assert!([SPOT, CUBE, cascade_colour(0), cascade_colour(3)].iter().all(|c| *c != SELECTED));

        // Another selection moves the highlight; no selection highlights nothing.
        let spot = panel_tiles(&tiles, 2048, image, AtlasView::default(), Some(3));
        assert_eq!(spot.iter().filter(|p| p.selected).map(|p| p.index).collect::<Vec<_>>(), vec![2]);
        assert!(panel_tiles(&tiles, 2048, image, AtlasView::default(), None).iter().all(|p| !p.selected));
        // The sun is nobody's selection.
        assert!(panel_tiles(&tiles, 2048, image, AtlasView::default(), Some(0)).iter().all(|p| !p.selected));
    }

    #[test]
    fn zoom_and_pan_move_the_rectangles_and_hover_finds_the_tile() {
        let tiles = plan();
        let image = Rect::from_min_size(Pos2::new(10.0, 20.0), Vec2::splat(256.0));
        // x4 around (0.125, 0.125): the window [0, 0.25]² shows texels 0..512, so cascade 0
        // fills the image.
        let view = AtlasView { zoom: 4.0, centre: [0.125, 0.125] };
        assert_eq!(visible(view), [0.0, 0.0, 0.25, 0.25]);
        let out = panel_tiles(&tiles, 2048, image, view, None);
        let sun0 = out.iter().find(|p| p.index == 0).expect("cascade 0 visible");
        assert!(close(sun0.rect, image), "{:?}", sun0.rect);
        // Cascade 1 starts at the image's right edge: it, the spot and the cube are out of view.
        assert_eq!(out.iter().map(|p| p.index).collect::<Vec<_>>(), vec![0]);
        // A centre past the edge is held inside the atlas.
        assert_eq!(visible(AtlasView { zoom: 4.0, centre: [-3.0, 9.0] }), [0.0, 0.75, 0.25, 1.0]);
        assert_eq!(visible(AtlasView { zoom: 0.1, centre: [0.2, 0.2] }), [0.0, 0.0, 1.0, 1.0]);
        // Panel <-> atlas round trip, and hover over each tile's centre finds it.
        for view in [AtlasView::default(), AtlasView { zoom: 3.0, centre: [0.6, 0.1] }] {
            for (i, t) in tiles.iter().enumerate() {
                let c = [t.x as f32 + t.size as f32 / 2.0, t.y as f32 + t.size as f32 / 2.0];
                let p = to_panel(c, image, 2048, view);
                let back = to_atlas(p, image, 2048, view);
                assert!((back[0] - c[0]).abs() < 0.01 && (back[1] - c[1]).abs() < 0.01);
                let want = image.contains(p).then_some(i);
                assert_eq!(tile_at(&tiles, 2048, image, view, p), want, "{t:?} at {p:?}");
            }
        }
        // Off the image, or on a texel no tile holds: nothing.
        assert_eq!(tile_at(&tiles, 2048, image, AtlasView::default(), Pos2::new(5.0, 5.0)), None);
        let empty = to_panel([1800.0, 1800.0], image, 2048, AtlasView::default());
        assert_eq!(tile_at(&tiles, 2048, image, AtlasView::default(), empty), None);
    }
}
