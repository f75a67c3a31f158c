//! The lights tab: the light list with per-light figures, and the selected light's editor.

use super::common::colour32;
use super::common::fmt_count;
use super::common::fmt_ms;
use super::common::fmt_opt;
use super::common::method_name;
use super::common::reject;
use super::common::Command;
use super::common::FrameInfo;
use super::common::Status;
use super::common::UiOut;
use crate::app::state;
use crate::app::state::UiState;
use crate::renderer::FrameStats;
use crate::scene::Light;
use crate::scene::Scene;
use egui::Color32;
use egui::Rect;
use egui::RichText;
use egui::Sense;
use egui::Stroke;
use egui::Vec2;
use glam::Vec3;

pub(super) fn light_label(i: usize, l: &Light) -> String {
    match l {
        Light::Point(_) => format!("#{i} point"),
        Light::Spot(_) => format!("#{i} spot"),
    }
}

pub(super) fn lights_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
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
                    "{} | shaded {} | ideal {} | wasted {} | cost {} | screen {:.1}%{}{}",
                    method_name(ls.method),
                    fmt_opt(ls.shaded),
                    fmt_opt(ls.ideal),
                    fmt_opt(ls.wasted),
                    ls.cost_ms.map_or("-".into(), |ms| format!("{ms:.3} ms (model)")),
                    ls.screen_share * 100.0,
                    if ls.crosses_near { " | crosses near" } else { "" },
                    if ls.crosses_far { " | crosses far" } else { "" }
                ));
                if ls.shadow_tiles > 0 {
                    ui.label(format!(
                        "shadow: {} tile{}, {} texels, {} caster draws{}",
                        ls.shadow_tiles,
                        if ls.shadow_tiles == 1 { "" } else { "s" },
                        fmt_count(ls.shadow_texels),
                        ls.caster_draws,
                        ls.shadow_ms.map_or(String::new(), |ms| format!(", {ms:.3} ms"))
                    ))
                    .on_hover_text("its share of the shadow maps this frame: the tiles (or cube faces) it holds and the casters drawn into them");
                }
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
            light_editor(ui, st, out, k, light, edit);
        }
    }
    light_list(ui, st, f, scene);
}

/// The selected light's colour, intensity, radius and cone angles; a valid edit is kept.
fn light_editor(ui: &mut egui::Ui, st: &mut UiState, out: &mut UiOut, k: usize, light: Light, edit: state::LightEdit) {
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
        // Whether this light casts (the `shadows` knob decides which kinds do).
        ui.label("shadow");
        changed |= ui.checkbox(&mut e.cast_shadows, "casts").changed();
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
        // Seed 004's culling mask: layers 0..3 as toggles (the others keep their bits; a
        // script's `set mask 0x...` sets all 32), and the whole mask in hex.
        ui.label("mask");
        ui.horizontal(|ui| {
            for bit in 0..4 {
                let mut on = e.mask & (1 << bit) != 0;
                if ui.checkbox(&mut on, bit.to_string()).on_hover_text(format!("lights layer {bit}")).changed() {
                    e.mask ^= 1 << bit;
                    changed = true;
                }
            }
            if ui.button("all").clicked() {
                e.mask = crate::scene::ALL_LAYERS;
                changed = true;
            }
            ui.monospace(format!("{:#010x}", e.mask));
        });
        ui.end_row();
    });
    cookie_picker(ui, st, out, k, &light);
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

/// The light's cookie (seed 004): none, a built-in (`window`, `flashlight`) or a PNG file
/// (square for a spot, a strip of six faces for a point light). A file is read once here to
/// check it; a bad one is refused with the reason on the status line.
fn cookie_picker(ui: &mut egui::Ui, st: &mut UiState, out: &mut UiOut, k: usize, light: &Light) {
    let cube = matches!(light, Light::Point(_));
    let current = st.light_cookies.get(&k).cloned();
    let shown = match &current {
        Some(Some(name)) => name.clone(),
        Some(None) => "none".into(),
        None if light.cookie().is_some() => "the scene's".into(),
        None => "none".into(),
    };
    let mut pick: Option<Option<String>> = None;
    ui.horizontal(|ui| {
        ui.label("cookie");
        egui::ComboBox::from_id_salt(("cookie", k)).selected_text(shown).show_ui(ui, |ui| {
            if ui.selectable_label(false, "none").clicked() {
                pick = Some(None);
            }
            for name in crate::scene::cookie::BUILTIN {
                if ui.selectable_label(false, name).clicked() {
                    pick = Some(Some(name.to_string()));
                }
            }
        });
        let id = ui.scope_id().with(("cookie-file", k));
        let mut path: String = ui.data_mut(|d| d.get_temp(id).unwrap_or_default());
        let r = ui.add(egui::TextEdit::singleline(&mut path).hint_text("file.png").desired_width(120.0));
        if r.changed() {
            ui.data_mut(|d| d.insert_temp(id, path.clone()));
        }
        if ui.button("load").clicked() || (r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter))) {
            pick = Some(Some(path));
        }
    });
    if let Some(choice) = pick {
        if let Some(spec) = &choice {
            if let Err(e) = crate::scene::cookie::CookieImage::resolve(spec, cube) {
                reject(out, format!("light {k}: {e}"));
                return;
            }
        }
        st.light_cookies.insert(k, choice);
    }
}

/// Every light with its shaded count and method, or (the ledger's order) costliest first with
/// bars of its evaluated, ideal and wasted pairs and its cost; a click selects it.
fn light_list(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, scene: &Scene) {
    ui.separator();
    let per_light = f.stats.map(|s| s.per_light.as_slice()).unwrap_or(&[]);
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("All lights ({})", scene.lights.len())).strong());
        ui.checkbox(&mut st.lights_by_cost, "costliest first")
            .on_hover_text("the light ledger: each light's evaluated pairs (ideal in green, wasted in red) and its cost in the light pass by the cost model; needs the fragment counts (and the ideal counts for the waste)");
    });
    let by_cost = st.lights_by_cost && per_light.iter().any(|l| l.cost_ms.is_some());
    if st.lights_by_cost {
        ledger_summary(ui, f.stats);
    }
    // The rows' order: the scene's, or by cost.
    let order: Vec<usize> = if by_cost {
        let mut v: Vec<usize> = (0..scene.lights.len()).collect();
        let cost = |i: usize| per_light.get(i).and_then(|l| l.cost_ms).unwrap_or(0.0);
        v.sort_by(|&a, &b| cost(b).total_cmp(&cost(a)));
        v
    } else {
        Vec::new()
    };
    let widest = per_light.iter().filter_map(|l| l.shaded).max().unwrap_or(0).max(1);
    let row_h = 18.0;
    let mut list = egui::ScrollArea::vertical()
        .id_salt("light-list")
        .max_height(ui.available_height().max(120.0))
        .auto_shrink([false, true]);
    if let Some(k) = f.scroll_to_light {
        // A light picked in the viewport: bring its row into view, a few rows from the top.
        let row = if by_cost { order.iter().position(|&i| i == k).unwrap_or(k) } else { k };
        list = list.vertical_scroll_offset((row.saturating_sub(3)) as f32 * (row_h + ui.spacing().item_spacing.y));
    }
    list.show_rows(ui, row_h, scene.lights.len(), |ui, range| {
        for row in range {
            let i = if by_cost { order[row] } else { row };
            let l = &scene.lights[i];
            ui.horizontal(|ui| {
                let (r, _) = ui.allocate_exact_size(Vec2::new(12.0, 12.0), Sense::hover());
                ui.painter().rect_filled(r, 2.0, colour32(l.color()));
                let ls = per_light.get(i);
                let text = if by_cost {
                    // Its share of the measured pass where the frame was timed, else the model's ms.
                    let ms = ls.and_then(|s| s.share_ms.or(s.cost_ms));
                    format!("{:<10}{:>9}", light_label(i, l), ms.map_or("-".into(), |ms| format!("{ms:.3} ms")))
                } else {
                    format!(
                        "{:<10}{:>8} {}",
                        light_label(i, l),
                        ls.and_then(|s| s.shaded).map_or("-".into(), fmt_count),
                        ls.map_or(String::new(), |s| method_name(s.method))
                    )
                };
                let sel = st.selected_light == Some(i);
                if ui.add(egui::Button::selectable(sel, RichText::new(text).monospace()).truncate()).clicked() {
                    st.selected_light = if sel { None } else { Some(i) };
                }
                if let (true, Some(ls)) = (by_cost, ls) {
                    pair_bar(ui, ls, widest);
                }
            });
        }
    });
}

/// The ledger's totals: the lights' costs by the model, its fixed part and the measured light
/// pass, and the wasted pairs.
fn ledger_summary(ui: &mut egui::Ui, stats: Option<&FrameStats>) {
    let Some(s) = stats else { return };
    match (&s.cost_model, s.light_cost_ms) {
        (Some(m), Some(sum)) => {
            ui.label(format!(
                "model: lights {sum:.2} ms + fixed {:.2} ms; measured pass {}",
                m.fixed_ms,
                fmt_ms(s.gpu_ms.lighting)
            ))
            .on_hover_text(format!(
                "cost = draws x {:.4} ms + evaluated pairs x {:.1} ns{}; {}. Each row shows the light's share of the measured pass (the measured time split in proportion to the model's costs, fixed part included), or the model's ms where the frame was not timed. `lampshade bench --only ledger` fits the model on this adapter and checks it by removing lights.",
                m.draw_ms,
                m.pair_ns,
                m.reject_ns.map_or(String::new(), |r| format!(" (a rejected pair {r:.1} ns)")),
                m.source
            ));
        }
        _ => {
            ui.label("no costs: the frame counted no pairs (turn on fragment counting), or it is a forward frame (its lights' samples are counted; the cost model is the deferred light pass's)");
        }
    }
    if let (Some(w), Some(sh)) = (s.wasted_fragments, s.shaded_fragments) {
        ui.label(format!("wasted pairs {} of {}", fmt_count(w), fmt_count(sh)));
    } else {
        ui.label("wasted pairs: count the ideal fragments to see them");
    }
}

/// A bar of light `ls`'s evaluated pairs, to scale against `widest`: green the part in its
/// true shape (ideal), red the wasted rest; grey when the ideal was not counted.
fn pair_bar(ui: &mut egui::Ui, ls: &crate::renderer::LightStats, widest: u64) {
    let (r, resp) = ui.allocate_exact_size(Vec2::new(120.0, 10.0), Sense::hover());
    let p = ui.painter();
    p.rect_stroke(r, 1.0, Stroke::new(0.5, Color32::DARK_GRAY), egui::StrokeKind::Inside);
    let Some(shaded) = ls.shaded else { return };
    let w = r.width() * (shaded as f32 / widest as f32);
    let bar = Rect::from_min_size(r.min, Vec2::new(w, r.height()));
    match ls.ideal {
        Some(ideal) => {
            let g = w * (ideal.min(shaded) as f32 / shaded.max(1) as f32);
            p.rect_filled(bar, 1.0, Color32::from_rgb(200, 60, 60));
            p.rect_filled(Rect::from_min_size(r.min, Vec2::new(g, r.height())), 1.0, Color32::from_rgb(70, 180, 90));
        }
        None => {
            p.rect_filled(bar, 1.0, Color32::GRAY);
        }
    }
    resp.on_hover_text(format!(
        "evaluated {} | ideal {} | wasted {}",
        fmt_count(shaded),
        fmt_opt(ls.ideal),
        fmt_opt(ls.wasted)
    ));
}
