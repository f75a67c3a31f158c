//! The viewport: the rendered frame, the wireframe overlay, hover, click and drag.

use super::common::colour32;
use super::common::efficiency_colour;
use super::common::FrameInfo;
use super::common::UiOut;
use crate::app::state::UiState;
use crate::app::state::WireColour;
use crate::renderer::DebugView;
use egui::Color32;
use egui::Pos2;
use egui::Rect;
use egui::Sense;
use egui::Stroke;
use egui::Vec2;
use glam::Vec3;

pub(super) fn viewport(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    // Snapped to whole pixels: at resolution scale 1 the frame maps 1:1 onto the window only if
    // the rectangle starts and ends on pixel edges (a panel of fractional width would otherwise
    // make egui resample the whole image).
    let ppp = ui.ctx().pixels_per_point();
    let snap = |p: Pos2| Pos2::new((p.x * ppp).round() / ppp, (p.y * ppp).round() / ppp);
    let avail = ui.available_rect_before_wrap();
    let rect = Rect::from_min_max(snap(avail.min), snap(avail.max));
    out.viewport_rect = Some(rect);
    let resp = ui.allocate_rect(rect, Sense::click_and_drag());
    let painter = ui.painter_at(rect);
    let Some((id, [w, h])) = f.viewport else {
        painter.rect_filled(rect, 0.0, Color32::BLACK);
        painter.text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "no image",
            egui::FontId::proportional(14.0),
            Color32::GRAY,
        );
        return;
    };
    // The image is opaque and covers the rectangle: drawn by its own unblended draw where the
    // window has one, else by egui over black (its blend would show the window's clear colour
    // through any alpha below 1).
    match &f.viewport_paint {
        Some(paint) => {
            painter.add(egui_wgpu::Callback::new_paint_callback(rect, paint.clone()));
        }
        None => {
            painter.rect_filled(rect, 0.0, Color32::BLACK);
            painter.image(id, rect, Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)), Color32::WHITE);
        }
    }
    if st.split.on {
        super::compare::split_viewport(ui, rect, st, f);
    }
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
