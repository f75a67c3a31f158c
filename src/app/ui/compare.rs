//! The compare window and the split viewport (`app::split`): configuration B's knobs, the
//! view (split, difference, FLIP), each side's GPU time per pass, B against A, and the lights
//! whose ledger cost changed most.

use super::common::{FrameInfo, SplitInfo};
use crate::app::split::SplitView;
use crate::app::state::UiState;
use egui::{Color32, Pos2, Rect, RichText, Stroke, Vec2};

/// Draws the comparison over the viewport's image in `rect`: B right of the divider (which
/// drags), or the overlay over the whole of it; labels each side.
pub(super) fn split_viewport(ui: &mut egui::Ui, rect: Rect, st: &mut UiState, f: &FrameInfo) {
    let Some(split) = f.split.as_ref() else { return };
    let painter = ui.painter_at(rect);
    let label = |p: &egui::Painter, pos: Pos2, align: egui::Align2, text: String| {
        let font = egui::FontId::proportional(12.0);
        let r = p.text(pos, align, &text, font.clone(), Color32::TRANSPARENT);
        p.rect_filled(r.expand(3.0), 2.0, Color32::from_black_alpha(170));
        p.text(pos, align, text, font, Color32::WHITE);
    };
    match st.split.view {
        SplitView::Split => {
            let d = st.split.divider.clamp(0.0, 1.0);
            let x = rect.left() + d * rect.width();
            if let Some(b) = split.b {
                let right = Rect::from_min_max(Pos2::new(x, rect.top()), rect.max);
                painter.image(b, right, Rect::from_min_max(Pos2::new(d, 0.0), Pos2::new(1.0, 1.0)), Color32::WHITE);
            }
            let strip = Rect::from_center_size(Pos2::new(x, rect.center().y), Vec2::new(10.0, rect.height()));
            let resp = ui.interact(strip, ui.make_persistent_id("compare divider"), egui::Sense::drag());
            if resp.dragged() {
                if let Some(p) = resp.interact_pointer_pos() {
                    st.split.divider = ((p.x - rect.left()) / rect.width().max(1.0)).clamp(0.0, 1.0);
                }
            }
            let hot = resp.hovered() || resp.dragged();
            if hot {
                ui.ctx().set_cursor_icon(egui::CursorIcon::ResizeHorizontal);
            }
            painter.line_segment(
                [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
                Stroke::new(if hot { 3.0 } else { 1.5 }, Color32::from_rgb(255, 200, 60)),
            );
            label(&painter, rect.left_bottom() + Vec2::new(6.0, -6.0), egui::Align2::LEFT_BOTTOM, "A".into());
            let b = if split.b.is_some() { "B" } else { "B: drawing…" };
            label(&painter, rect.right_bottom() + Vec2::new(-6.0, -6.0), egui::Align2::RIGHT_BOTTOM, b.into());
        }
        view => {
            if let Some(o) = split.overlay {
                painter.image(o, rect, Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)), Color32::WHITE);
            }
            let what = match view {
                SplitView::Flip => format!(
                    "FLIP of B against A{}",
                    split.figures.flip_mean.map_or(String::new(), |m| format!(": mean {m:.5}"))
                ),
                _ => format!(
                    "|B − A| × {}{}",
                    crate::compare::DIFFERENCE_GAIN,
                    split.figures.max_steps.map_or(String::new(), |s| format!(": largest step {s}"))
                ),
            };
            label(&painter, rect.left_bottom() + Vec2::new(6.0, -6.0), egui::Align2::LEFT_BOTTOM, what);
        }
    }
}

pub(super) fn compare_window(ctx: &egui::Context, st: &mut UiState, f: &FrameInfo) {
    let mut open = true;
    egui::Window::new("Compare").open(&mut open).default_size([380.0, 420.0]).resizable(true).show(ctx, |ui| {
        ui.horizontal(|ui| {
            ui.label("view");
            for v in [SplitView::Split, SplitView::Difference, SplitView::Flip] {
                ui.selectable_value(&mut st.split.view, v, v.name());
            }
        });
        ui.label(RichText::new("A: the panels' settings. B: A with these knobs:").weak());
        let a = st.frame_settings();
        let mut remove = None;
        for (k, v) in &st.split.b {
            ui.horizontal(|ui| {
                let was = a.get(k).unwrap_or_default();
                ui.label(format!("{k} = {v}"));
                ui.label(RichText::new(format!("(A: {was})")).weak());
                if ui.small_button("×").on_hover_text("B takes A's value again").clicked() {
                    remove = Some(k.clone());
                }
            });
        }
        if let Some(k) = remove {
            st.split.b.remove(&k);
        }
        let mut message = None;
        ui.horizontal(|ui| {
            egui::ComboBox::from_id_salt("compare knob").selected_text(st.split.edit.0.clone()).show_ui(ui, |ui| {
                for k in crate::renderer::knobs::KNOBS {
                    ui.selectable_value(&mut st.split.edit.0, k.name.to_string(), k.name);
                }
            });
            let names = crate::renderer::knobs::find(&st.split.edit.0).map(|k| k.names()).unwrap_or_default();
            if names.is_empty() {
                ui.add(egui::TextEdit::singleline(&mut st.split.edit.1).desired_width(70.0));
            } else {
                egui::ComboBox::from_id_salt("compare value").selected_text(st.split.edit.1.clone()).show_ui(
                    ui,
                    |ui| {
                        for n in names {
                            ui.selectable_value(&mut st.split.edit.1, n.clone(), n);
                        }
                    },
                );
            }
            if ui.button("set B").clicked() {
                let (k, v) = st.split.edit.clone();
                let mut split = st.split.clone();
                message = Some(split.set(&a, &k, &v).map(|_| format!("B: {k} = {v}")));
                st.split = split;
            }
        });
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut st.split.file).hint_text("settings file").desired_width(200.0));
            if ui.button("load B").clicked() {
                let path = std::path::PathBuf::from(st.split.file.trim());
                let mut split = st.split.clone();
                message = Some(split.load(&a, &path).map(|n| format!("B: {n} knob(s) from {}", path.display())));
                st.split = split;
            }
        });
        if let Some(Err(e)) = &message {
            ui.label(RichText::new(e).color(Color32::LIGHT_RED));
        }
        match f.split.as_ref() {
            Some(split) => figures(ui, split),
            None => {
                ui.label(RichText::new("B draws with the next frame").weak());
            }
        }
    });
    if !open {
        st.split.on = false;
    }
}

/// The comparison's figures: B's error, each side's GPU ms per pass, B against A, the ledger's
/// delta.
fn figures(ui: &mut egui::Ui, split: &SplitInfo) {
    {
        let fig = split.figures;
        if let Some(e) = &fig.error {
            ui.label(RichText::new(e).color(Color32::LIGHT_RED));
        }
        ui.separator();
        egui::Grid::new("compare passes").striped(true).show(ui, |ui| {
            ui.label(RichText::new("GPU ms").strong());
            ui.label("A");
            ui.label("B");
            ui.end_row();
            let mut passes: Vec<&str> = fig.a_ms.iter().map(|p| p.0.as_str()).collect();
            for (p, _) in &fig.b_ms {
                if !passes.contains(&p.as_str()) {
                    passes.push(p);
                }
            }
            let ms = |v: &[(String, f64)], p: &str| {
                v.iter().find(|q| q.0 == p).map_or("-".into(), |q| format!("{:.2}", q.1))
            };
            for p in passes {
                ui.label(p);
                ui.label(ms(&fig.a_ms, p));
                ui.label(ms(&fig.b_ms, p));
                ui.end_row();
            }
        });
        if let Some(s) = fig.max_steps {
            ui.label(format!(
                "B against A: largest step {s}{}",
                fig.flip_mean.map_or(String::new(), |m| format!(", FLIP mean {m:.5}"))
            ));
        }
        if !fig.ledger_delta.is_empty() {
            ui.separator();
            ui.label(RichText::new("lights whose cost changed most (ledger, ms)").strong());
            egui::Grid::new("compare ledger").striped(true).show(ui, |ui| {
                for h in ["light", "A", "B", "change"] {
                    ui.label(h);
                }
                ui.end_row();
                for d in &fig.ledger_delta {
                    ui.label(d.light.to_string());
                    ui.label(format!("{:.4}", d.a_ms));
                    ui.label(format!("{:.4}", d.b_ms));
                    ui.label(format!("{:+.4}", d.b_ms - d.a_ms));
                    ui.end_row();
                }
            });
        }
    }
}
