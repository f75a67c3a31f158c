//! The top bar (scene, culling mode, view, panels) and the status line.

use super::common::culling_help;
use super::common::Command;
use super::common::FrameInfo;
use super::common::Region;
use super::common::Status;
use super::common::UiOut;
use crate::app::state::Tab;
use crate::app::state::UiState;
use crate::renderer::CullingMode;
use crate::renderer::DebugView;
use crate::scene::builtin;
use egui::Color32;
use egui::RichText;

pub(super) fn top_bar(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    let r = egui::Panel::top("top").show(ui, |ui| {
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
                        let why = super::common::refused(f, &st.settings, "culling", m.name());
                        super::common::offer(ui, why, &mut st.settings.culling, m, m.name())
                            .on_hover_text(culling_help(m));
                    }
                },
            );
            // A seed's pipeline at once (`renderer::presets`); `custom` once a knob moves.
            ui.label("preset");
            let current = st.settings.get("preset").unwrap_or_default();
            egui::ComboBox::from_id_salt("preset").selected_text(&current).width(80.0).show_ui(ui, |ui| {
                for p in crate::renderer::presets::Preset::ALL {
                    let name = p.name();
                    let why = super::common::refused(f, &st.settings, "preset", &name);
                    let help = crate::renderer::settings::help_of(&p);
                    let mut chosen = current.clone();
                    let r = super::common::offer(ui, why, &mut chosen, name.clone(), &name).on_hover_text(help);
                    if r.clicked() && chosen != current {
                        if let Err(e) = st.settings.set("preset", &name) {
                            out.commands.push(Command::Status(Status { text: e, error: true }));
                        }
                    }
                }
            });
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
            panel_toggles(ui, st);
            // Last, so it wraps onto its own row rather than being drawn over the buttons.
            ui.separator();
            ui.label(RichText::new(f.adapter).weak());
        });
    });
    out.regions.push(Region { name: "top bar", parent: None, rect: r.response.rect });
}

pub(super) fn status_bar(ui: &mut egui::Ui, st: &UiState, f: &FrameInfo, out: &mut UiOut) {
    let r = egui::Panel::bottom("status").show(ui, |ui| {
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
            // The key is long: the line names the date, the hover the whole.
            let short = f.calibration.rsplit_once(", ").map_or(f.calibration.as_str(), |(_, date)| date);
            ui.label(format!("calibration: {short}")).on_hover_text(format!(
                "calibration: {}\nThe cost model's constants auto and the estimates weigh with (`lampshade calibrate`)",
                f.calibration
            ));
            if f.offer_calibration {
                ui.separator();
                ui.label("Measure this adapter's costs (about 20 s, the frame held)?");
                if ui.button("Calibrate").clicked() {
                    out.commands.push(Command::Calibrate);
                }
                if ui.button("Not now").clicked() {
                    out.commands.push(Command::DeclineCalibration);
                }
            }
            ui.separator();
            if let Some(note) = f.compiling.as_deref() {
                ui.label(RichText::new(note).color(Color32::LIGHT_BLUE));
                ui.separator();
            }
            if let Some(s) = f.status {
                let c = if s.error { Color32::from_rgb(255, 110, 90) } else { Color32::from_gray(200) };
                let label = ui.label(RichText::new(&s.text).color(c));
                if !f.warnings.is_empty() {
                    label.on_hover_text(f.warnings.join("\n"));
                }
            }
        });
    });
    out.regions.push(Region { name: "status bar", parent: None, rect: r.response.rect });
}

/// The top bar's panel and window toggles.
fn panel_toggles(ui: &mut egui::Ui, st: &mut UiState) {
    ui.label("panels");
    for (on, name, what) in [
        (&mut st.panels.left, "left", "scene, lights, materials, camera, help and the pixel probe"),
        (&mut st.panels.right, "right", "culling figures, GPU times, history"),
        (&mut st.panels.gbuffer, "g-buffer", "the G-buffer thumbnails"),
        (&mut st.panels.shadows, "shadows", "the shadow atlas window: tiles, figures and shadow settings"),
        (&mut st.panels.pipelines, "pipelines", "the pipelines window: each configuration's compiles"),
        (&mut st.split.on, "compare", "split view: configuration B right of a divider, their difference and FLIP"),
    ] {
        ui.toggle_value(on, name)
            .on_hover_text(format!("show or hide the {what}; a window too small for a panel hides it until it grows"));
    }
}
