//! The panels. `draw` reads the last frame's figures (`FrameInfo`), edits the plain `UiState`
//! and reports what only the application can do (screenshots, picking) in `UiOut`; it never
//! touches a GPU object.

use super::state::{Panels, UiState};
use egui::{Color32, Rect, Vec2};

mod advice;
mod common;
mod compare;
mod pipelines;
pub(crate) use common::method_name;
pub use common::{
    efficiency_colour, AtlasInfo, Command, CullingCheck, FrameInfo, History, Region, Sample, SplitInfo, Status, Thumb,
    UiOut, HISTORY, MAX_WIREFRAMES,
};
use common::{GBUFFER_STRIP, LEFT_WIDTH, MIN_SIDE_WIDTH, RIGHT_WIDTH};
mod check;
mod figures;
mod gbuffer_strip;
mod lights_tab;
mod overlaps;
mod probe;
mod shadow_atlas;
mod stochastic;
mod tabs;
mod top_bar;
mod viewport;

use figures::right_panel;
use gbuffer_strip::gbuffer_strip;
pub use gbuffer_strip::thumbs;
pub use overlaps::overlaps;
use shadow_atlas::shadow_window;
pub use shadow_atlas::{cascade_colour, visible as atlas_visible, CUBE, SELECTED, SPOT};
use tabs::left_panel;
use top_bar::{status_bar, top_bar};
use viewport::viewport;

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
    if st.panels.pipelines {
        pipelines::pipelines_window(ui.ctx(), st, f);
    }
    if st.split.on {
        compare::compare_window(ui.ctx(), st, f);
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
