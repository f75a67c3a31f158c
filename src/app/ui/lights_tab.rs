//! The lights tab: the light list with per-light figures, and the selected light's editor.

use super::*;

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
                    "{} | shaded {} | ideal {} | screen {:.1}%{}{}",
                    method_name(ls.method),
                    fmt_opt(ls.shaded),
                    fmt_opt(ls.ideal),
                    ls.screen_share * 100.0,
                    if ls.crosses_near { " | crosses near" } else { "" },
                    if ls.crosses_far { " | crosses far" } else { "" }
                ));
                if ls.shadow_tiles > 0 {
                    ui.label(format!(
                        "shadow: {} tile{}, {} texels, {} caster draws",
                        ls.shadow_tiles,
                        if ls.shadow_tiles == 1 { "" } else { "s" },
                        fmt_count(ls.shadow_texels),
                        ls.caster_draws
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

/// Every light with its shaded count and method; a click selects it.
fn light_list(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, scene: &Scene) {
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
