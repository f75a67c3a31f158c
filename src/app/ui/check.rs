//! The culling check window: every culling mode of the current path held against brute force
//! (`oracle::check_scene`) at the current camera, a row a mode, and the chosen row's difference
//! image: grey within the rounding bound, red where the mode lacks light, blue where it has
//! more (as `lampshade check` writes them).

use super::common::CullingCheck;
use super::common::FrameInfo;
use crate::app::state::UiState;
use egui::Color32;
use egui::RichText;
use egui::Vec2;

impl CullingCheck {
    /// Frames that miss or add light.
    pub fn failed(&self) -> usize {
        self.rows.iter().filter(|r| r.failed()).count()
    }
}

pub(super) fn check_window(ctx: &egui::Context, st: &mut UiState, f: &FrameInfo) {
    let Some(check) = f.check else { return };
    let mut open = true;
    egui::Window::new("Culling against brute force").open(&mut open).default_size([460.0, 380.0]).resizable(true).show(
        ctx,
        |ui| {
            let c = match check {
                Ok(c) => c,
                Err(e) => {
                    ui.label(RichText::new(format!("no check: {e}")).color(Color32::from_rgb(255, 170, 80)));
                    return;
                }
            };
            let failed = c.failed();
            let verdict = if failed == 0 {
                RichText::new("no mode misses or adds light").color(Color32::from_rgb(120, 220, 120))
            } else {
                RichText::new(format!("{failed} frame(s) miss or add light")).color(Color32::from_rgb(255, 90, 90))
            };
            ui.label(verdict);
            ui.label(
                RichText::new(format!(
                    "at this camera, {}x{}, every light at every pixel in f32 as the reference ({:.1} s)",
                    c.size[0], c.size[1], c.seconds
                ))
                .weak(),
            );
            egui::Grid::new("check rows").num_columns(5).striped(true).spacing([8.0, 1.0]).show(ui, |ui| {
                for h in ["path / mode", "missed px", "extra px", "worst", "missed lights"] {
                    ui.label(RichText::new(h).strong());
                }
                ui.end_row();
                for (i, r) in c.rows.iter().enumerate() {
                    let colour = if r.refused.is_some() {
                        Color32::GRAY
                    } else if r.failed() {
                        Color32::from_rgb(255, 90, 90)
                    } else {
                        Color32::from_rgb(160, 220, 160)
                    };
                    let name = RichText::new(format!("{} / {}", r.path, r.mode)).color(colour);
                    if ui.selectable_label(st.check_row == i, name).clicked() {
                        st.check_row = i;
                    }
                    if let Some(why) = &r.refused {
                        ui.label("refused").on_hover_text(why);
                        ui.label("");
                        ui.label("");
                        ui.label("");
                    } else {
                        ui.label(r.missed.to_string());
                        ui.label(r.extra.to_string());
                        ui.label(r.worst.as_ref().map_or("-".into(), |w| {
                            format!(
                                "{},{}: {:.1}x bound",
                                w.x,
                                w.y,
                                w.difference.abs() / w.bound.max(f32::MIN_POSITIVE)
                            )
                        }));
                        let lights: Vec<String> = r
                            .worst
                            .as_ref()
                            .map(|w| w.missed_lights.iter().take(6).map(|l| l.to_string()).collect())
                            .unwrap_or_default();
                        ui.label(lights.join(" "));
                    }
                    ui.end_row();
                }
            });
            if let Some(t) = c.images.get(st.check_row) {
                ui.separator();
                ui.label(
                    RichText::new("grey: within the rounding bound; red: light missing; blue: extra light").weak(),
                );
                let w = ui.available_width().min(c.size[0] as f32 * 4.0);
                let h = w * c.size[1] as f32 / c.size[0].max(1) as f32;
                ui.image((t.id(), Vec2::new(w, h)));
            }
        },
    );
    st.panels.check = open;
}
