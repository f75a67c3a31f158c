//! The left panel: its tabs (scene, materials, camera, help; lights in `lights_tab`) and the pixel probe below them.

use super::common::reject;
use super::common::Command;
use super::common::FrameInfo;
use super::common::Region;
use super::common::Status;
use super::common::UiOut;
use super::common::MIN_TAB_HEIGHT;
use super::common::PIXEL_PANEL;
use super::lights_tab::lights_tab;
use super::probe::pixel_panel;
use crate::app::camera;
use crate::app::state::Tab;
use crate::app::state::UiState;
use crate::app::state::MAX_LIGHTS;
use crate::app::state::MAX_SCALE;
use crate::app::state::MIN_SCALE;
use crate::renderer::knobs;
use crate::renderer::settings::AccumFormat;
use crate::renderer::settings::Focus;
use crate::renderer::settings::{CONE_SIDES_RANGE, MAX_SPHERE_SUBDIVISIONS};
use crate::renderer::LayoutChoice;
use crate::scene::Scene;
use crate::scene::Sun;
use egui::Rect;
use egui::RichText;
use glam::Vec3;

pub(super) fn left_panel(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    // The pixel inspector stays in view at the bottom while the tabs scroll above it, when the
    // panel is tall enough for both; in a short window it scrolls with the tab instead of
    // being drawn over it. Laid out top to bottom: the tab row, the tab's scroll area sized to
    // what the probe leaves, then the probe.
    let pinned = ui.available_height() >= PIXEL_PANEL + MIN_TAB_HEIGHT;
    let inner = ui.max_rect();
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 2.0;
        // Help has its own button in the top bar (F1).
        for t in Tab::ALL.into_iter().filter(|t| *t != Tab::Help) {
            ui.selectable_value(&mut st.tab, t, t.name());
        }
    });
    ui.separator();
    let spacing = ui.spacing().item_spacing.y;
    let tab_height = if pinned { ui.available_height() - PIXEL_PANEL - spacing } else { ui.available_height() };
    let tab = egui::ScrollArea::vertical()
        .id_salt("left-scroll")
        .auto_shrink([false, false])
        .max_height(tab_height.max(0.0))
        .show(ui, |ui| {
            match st.tab {
                Tab::Scene => scene_tab(ui, st, f, out),
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
    out.regions.push(Region { name: "left tab", parent: Some("left panel"), rect: tab.inner_rect });
    if pinned {
        // The panel's last PIXEL_PANEL points: a probe taller than that scrolls inside them,
        // never drawn over the tab above or out of the panel.
        let rect = Rect::from_min_max(egui::pos2(inner.left(), inner.bottom() - PIXEL_PANEL), inner.max);
        ui.scope_builder(egui::UiBuilder::new().max_rect(rect), |ui| {
            ui.separator();
            egui::ScrollArea::vertical()
                .id_salt("probe-scroll")
                .auto_shrink([false, false])
                .show(ui, |ui| pixel_panel(ui, f));
        });
        out.regions.push(Region { name: "pixel probe", parent: Some("left panel"), rect });
    }
}

/// The scene tab: the scene's and the frame's knobs in one grid ([`scene_rows`],
/// [`pipeline_rows`]), then ambient and sun, the engine caps, shadows and post.
pub(super) fn scene_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    egui::Grid::new("scene-grid").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        scene_rows(ui, st, f, out);
        pipeline_rows(ui, st, f);
    });
    ui.separator();
    ui.label(RichText::new("Ambient and sun").strong());
    if let Some(scene) = f.scene {
        ambient_and_sun(ui, st, scene);
    }
    ui.separator();
    egui::CollapsingHeader::new(RichText::new("Engine caps").strong()).id_salt("engine-caps").show(ui, |ui| {
        engine_caps(ui, st, f, out);
    });
    super::stochastic::section(ui, st, f);
    ui.separator();
    // The shadow knobs (also in the shadow-atlas window, top bar "shadows").
    ui.label(RichText::new("Shadows").strong());
    super::shadow_atlas::shadow_knobs(ui, st, "scene");
    ui.separator();
    ui.label(RichText::new("Post (bloom → exposure → tone map → grading → fog → DOF → vignette → AA)").strong());
    post_panel(ui, st, f);
}

/// The scene grid's rows of the scene: its lights, the checks against brute force and the
/// advice, time, resolution, exposure, the lights' radius and intensity.
fn scene_rows(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
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
    ui.label("culling");
    if ui
        .button("check against brute force")
        .on_hover_text(
            "every culling mode of this path at this camera against every light evaluated at every pixel: \
             pixels that miss light or get extra, with a difference image (lampshade check)",
        )
        .clicked()
    {
        out.commands.push(Command::CheckCulling);
    }
    ui.end_row();
    ui.label("advise");
    if ui
        .button("which path and mode?")
        .on_hover_text(
            "every path and culling mode at this camera, at a sixteenth, a quarter and all of the lights: \
             a cost model fitted on short calibration frames predicts the fastest, then each is measured \
             (lampshade advise); runs beside the viewer",
        )
        .clicked()
    {
        out.commands.push(Command::Advise);
    }
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
    ui.add(
        egui::Slider::new(&mut st.settings.exposure, slider("exposure"))
            .clamping(egui::SliderClamping::Edits)
            .logarithmic(true),
    );
    ui.end_row();
    ui.label("radius x");
    ui.add(egui::Slider::new(&mut st.radius_scale, 0.05..=8.0).logarithmic(true)).on_hover_text("every light's radius");
    ui.end_row();
    ui.label("intensity x");
    ui.add(egui::Slider::new(&mut st.intensity_scale, 0.0..=20.0)).on_hover_text("every light's intensity");
    ui.end_row();
}

/// The scene grid's rows of how the frame is drawn and stored: depth format and read, light
/// cut-off, volume tessellation, accumulation, G-buffer layout, blended surfaces, lightmaps.
fn pipeline_rows(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    ui.label("depth");
    egui::ComboBox::from_id_salt("depth-format").selected_text(st.settings.depth_format.name()).show_ui(ui, |ui| {
        for d in crate::renderer::DepthFormat::ALL {
            ui.selectable_value(&mut st.settings.depth_format, d, d.name());
        }
    });
    ui.end_row();
    ui.label("depth read");
    ui.horizontal(|ui| {
        use crate::renderer::DepthRead;
        egui::ComboBox::from_id_salt("depth-read").selected_text(st.settings.depth_read.name()).show_ui(ui, |ui| {
            for &d in <DepthRead as clap::ValueEnum>::value_variants() {
                ui.selectable_value(&mut st.settings.depth_read, d, d.name()).on_hover_text(knob_help(&d));
            }
        });
        // What the frame did, in short; the buffer, or the copy and why, on hover.
        if let Some(s) = f.stats {
            let short = if s.depth_read.starts_with("depth buffer") { "no copy" } else { "copy kept" };
            ui.label(RichText::new(short).weak()).on_hover_text(&s.depth_read);
        }
    });
    ui.end_row();
    ui.label("light cut-off");
    ui.add(
        egui::Slider::new(&mut st.settings.light_cutoff, slider("light-cutoff"))
            .clamping(egui::SliderClamping::Edits)
            .fixed_decimals(4),
    )
    .on_hover_text("cut each light off where it falls below this fraction of its peak (0 = exact radius)");
    ui.end_row();
    ui.label("sphere / cone");
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(&mut st.settings.sphere_subdivisions)
                .range(0..=MAX_SPHERE_SUBDIVISIONS)
                .prefix("subdiv "),
        );
        ui.add(egui::DragValue::new(&mut st.settings.cone_sides).range(CONE_SIDES_RANGE).suffix(" sides"));
    })
    .response
    .on_hover_text("tessellation of the light volumes");
    ui.end_row();
    ui.label("accumulation");
    egui::ComboBox::from_id_salt("accum").selected_text(st.settings.accumulation.name()).show_ui(ui, |ui| {
        for a in AccumFormat::ALL {
            let why = super::common::refused(f, &st.settings, "accumulation", a.name());
            super::common::offer(ui, why, &mut st.settings.accumulation, a, a.name());
        }
    });
    ui.end_row();
    ui.label("G-buffer");
    egui::ComboBox::from_id_salt("layout-left").selected_text(st.settings.layout.name()).show_ui(ui, |ui| {
        for l in LayoutChoice::ALL {
            let why = super::common::refused(f, &st.settings, "layout", l.name());
            super::common::offer(ui, why, &mut st.settings.layout, l, l.name());
        }
    });
    ui.end_row();
    ui.label("blended");
    ui.horizontal(|ui| {
        use crate::renderer::settings::{BlendedMode, MAX_PEEL_LAYERS};
        egui::ComboBox::from_id_salt("blended").selected_text(st.settings.blended.name()).show_ui(ui, |ui| {
            for &b in <BlendedMode as clap::ValueEnum>::value_variants() {
                let why = super::common::refused(f, &st.settings, "blended", b.name());
                super::common::offer(ui, why, &mut st.settings.blended, b, b.name()).on_hover_text(knob_help(&b));
            }
        });
        if st.settings.blended == BlendedMode::Peeled {
            ui.add(egui::DragValue::new(&mut st.settings.peel_layers).range(1..=MAX_PEEL_LAYERS).suffix(" layers"))
                .on_hover_text("each pixel's nearest N blended fragments, in depth order; any behind them dropped");
        }
    });
    ui.end_row();
    if f.scene.is_some_and(crate::scene::lightmap::any) {
        // Seed 004's lightmaps (`courtyard`, or a file's): realtime near, baked far.
        ui.label("lightmaps");
        ui.horizontal(|ui| {
            ui.checkbox(&mut st.settings.lightmaps, "on");
            ui.add_enabled(
                st.settings.lightmaps,
                egui::Slider::new(&mut st.settings.lightmap_distance, slider("lightmap-distance"))
                    .logarithmic(true)
                    .text("baked from"),
            )
            .on_hover_text(
                "view distance from which lightmapped surfaces are fully baked; the crossfade starts at 0.8 of it",
            );
        });
        ui.end_row();
    }
}

/// The engine-style caps (`renderer::caps`): an engine's preset at once, each cap and the
/// clustered grid, and what the last frame's caps dropped.
fn engine_caps(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
    ui.horizontal_wrapped(|ui| {
        ui.label("as");
        for e in crate::renderer::caps::ENGINES {
            if ui.small_button(e.name).on_hover_text(e.source).clicked() {
                for (k, v) in e.knobs {
                    if let Err(err) = st.settings.set(k, v) {
                        out.commands.push(Command::Status(Status { text: err, error: true }));
                    }
                }
            }
        }
        if ui.small_button("none").on_hover_text("every cap off, the default grid").clicked() {
            for k in [
                "max-lights",
                "light-distance",
                "lights-per-cluster",
                "lights-per-object",
                "cluster-tile",
                "cluster-budget",
                "cluster-slices",
                "first-slice-depth",
            ] {
                let _ = st.settings.set(k, "0");
            }
        }
    });
    let s = &mut st.settings;
    egui::Grid::new("caps-grid").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        let whole = |ui: &mut egui::Ui, v: &mut u32, what: &str| {
            ui.add(egui::DragValue::new(v).range(0..=1 << 20).speed(1.0)).on_hover_text(what);
        };
        ui.label("lights per camera");
        whole(ui, &mut s.max_lights, "keep at most this many lights, by the cap order (0: all)");
        ui.end_row();
        ui.label("light distance");
        ui.add(egui::DragValue::new(&mut s.light_distance).range(0.0..=1e9).speed(0.5))
            .on_hover_text("drop lights whose sphere lies wholly beyond this distance (0: none)");
        ui.end_row();
        ui.label("lights per cluster");
        whole(ui, &mut s.lights_per_cluster, "clustered: keep at most this many lights per cell (0: all)");
        ui.end_row();
        ui.label("lights per object");
        whole(ui, &mut s.lights_per_object, "forward paths: keep at most this many lights per object (0: all)");
        ui.end_row();
        ui.label("cap order");
        super::common::knob_choice(ui, "cap-order", &mut s.cap_order);
        ui.end_row();
        ui.label("cluster grid");
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut s.cluster_tile).range(0..=512).prefix("tile "))
                .on_hover_text("tile side in pixels (0: 32, or what the budget gives)");
            ui.add(egui::DragValue::new(&mut s.cluster_budget).range(0..=1 << 20).prefix("cells "))
                .on_hover_text("a cell budget laid out as Bevy's FixedZ (0: none)");
            ui.add(egui::DragValue::new(&mut s.cluster_slices).range(0..=1024).prefix("slices "))
                .on_hover_text("depth slices (0: 64)");
            ui.add(egui::DragValue::new(&mut s.first_slice_depth).range(0.0..=1e6).prefix("first "))
                .on_hover_text("the first slice ends at this depth, the rest exponential (0: all exponential)");
        });
        ui.end_row();
    });
    if let Some(c) = f.stats.and_then(|s| s.caps.as_ref()) {
        ui.label(
            RichText::new(format!(
                "last frame: {} lights dropped ({} by count, {} by distance), {} cluster and {} object list entries",
                c.dropped_by_count + c.dropped_by_distance,
                c.dropped_by_count,
                c.dropped_by_distance,
                c.cluster_entries_dropped,
                c.object_entries_dropped
            ))
            .weak(),
        );
    }
}

/// The post chain's knobs: bloom, auto-exposure, the tone curve and the grading LUT.
fn post_panel(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    let s = &mut st.settings;
    egui::Grid::new("post-grid").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        ui.label("bloom");
        ui.checkbox(&mut s.bloom, "on");
        ui.end_row();
        ui.label("threshold");
        ui.add(
            egui::Slider::new(&mut s.bloom_threshold, slider("bloom-threshold")).clamping(egui::SliderClamping::Edits),
        )
        .on_hover_text("luminance above which pixels bloom");
        ui.end_row();
        ui.label("intensity");
        ui.add(
            egui::Slider::new(&mut s.bloom_intensity, slider("bloom-intensity")).clamping(egui::SliderClamping::Edits),
        );
        ui.end_row();
        ui.label("auto-exposure");
        match super::common::refused(f, s, "auto-exposure", "on") {
            Some(why) if !s.auto_exposure => {
                ui.add_enabled(false, egui::Checkbox::new(&mut false, "on")).on_disabled_hover_text(why);
            }
            _ => {
                ui.checkbox(&mut s.auto_exposure, "on").on_hover_text("adapt to the frame's luminance histogram");
            }
        }
        ui.end_row();
        ui.label("target");
        ui.add(
            egui::Slider::new(&mut s.target_luminance, slider("target-luminance"))
                .clamping(egui::SliderClamping::Edits)
                .logarithmic(true),
        )
        .on_hover_text("luminance the frame's geometric mean is exposed to");
        ui.end_row();
        ui.label("speed");
        ui.add(
            egui::Slider::new(&mut s.adaptation_speed, slider("adaptation-speed"))
                .clamping(egui::SliderClamping::Edits)
                .logarithmic(true)
                .suffix(" /s"),
        )
        .on_hover_text("adaptation speed (fixed 1/60 s per frame)");
        ui.end_row();
        ui.label("tonemap");
        super::common::knob_choice(ui, "tonemap", &mut s.tonemap);
        ui.end_row();
        ui.label("distortion");
        ui.checkbox(&mut s.distortion, "on")
            .on_hover_text("seed 002: the picture behind a distorting material shifted by its normal");
        ui.end_row();
        ui.label("fog");
        ui.checkbox(&mut s.fog, "on").on_hover_text("distance fog with a height falloff, towards the background");
        ui.end_row();
        ui.label("fog density");
        ui.add(
            egui::Slider::new(&mut s.fog_density, slider("fog-density"))
                .clamping(egui::SliderClamping::Edits)
                .fixed_decimals(3),
        );
        ui.end_row();
        ui.label("height falloff");
        ui.add(
            egui::Slider::new(&mut s.fog_height_falloff, slider("fog-height-falloff"))
                .clamping(egui::SliderClamping::Edits),
        );
        ui.end_row();
        ui.label("depth of field");
        ui.checkbox(&mut s.dof, "on");
        ui.end_row();
        ui.label("focus distance");
        focus_distance(ui, &mut s.focus_distance);
        ui.end_row();
        ui.label("aperture");
        ui.add(
            egui::Slider::new(&mut s.aperture, slider("aperture")).clamping(egui::SliderClamping::Edits).suffix(" px"),
        )
        .on_hover_text("circle of confusion at infinity");
        ui.end_row();
        ui.label("vignette");
        ui.add(egui::Slider::new(&mut s.vignette, slider("vignette")).clamping(egui::SliderClamping::Edits));
        ui.end_row();
        ui.label("anti-aliasing");
        super::common::knob_choice(ui, "aa", &mut s.aa);
        ui.end_row();
        ui.label("grading LUT");
        let id = ui.scope_id().with("lut-path");
        let mut text: String =
            ui.data_mut(|d| d.get_temp(id)).unwrap_or_else(|| s.lut.clone().unwrap_or_else(|| "none".into()));
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut text).desired_width(140.0))
                .on_hover_text(".cube file, identity or none");
            if ui.button("load").clicked() {
                let result = s.set("lut", &text);
                ui.data_mut(|d| d.insert_temp(id.with("error"), result.err()));
            }
        });
        ui.data_mut(|d| d.insert_temp(id, text));
        ui.end_row();
        if let Some(e) = ui.data(|d| d.get_temp::<Option<String>>(id.with("error"))).flatten() {
            ui.label("");
            ui.colored_label(egui::Color32::LIGHT_RED, e);
            ui.end_row();
        }
    });
}

fn knob_help<T: clap::ValueEnum>(v: &T) -> String {
    crate::renderer::settings::help_of(v)
}

/// Ambient colour, the sun on or off, its colour, intensity and direction.
fn ambient_and_sun(ui: &mut egui::Ui, st: &mut UiState, scene: &Scene) {
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

pub(super) fn materials_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
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
        let most = crate::scene::max_specular_level(m.specular_exponent);
        changed |= ui.add(egui::Slider::new(&mut m.specular_level, 0.0..=most).logarithmic(most > 10.0)).changed();
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
        // The reflectance model (seed 002's material ID); a scene of several gets the G-buffer's
        // ID channel. For a metal, `diffuse` is the specular colour.
        ui.label("model");
        egui::ComboBox::from_id_salt("brdf").selected_text(m.brdf.name()).show_ui(ui, |ui| {
            for b in crate::scene::Brdf::ALL {
                changed |= ui.selectable_value(&mut m.brdf, b, b.name()).changed();
            }
        });
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

pub(super) fn camera_tab(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo, out: &mut UiOut) {
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

pub(super) fn help_tab(ui: &mut egui::Ui) {
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
    ui.label("Tile lights: how many lights each pixel's tile (tiled) or cluster (clustered) list holds.");
    ui.label("Bloom: the bloom the post chain adds. Histogram: auto-exposure's bins of log2 luminance, the adapted (yellow) and the frame's mean (white).");
    ui.label("Shadow: the shadow factor (white lit, black shadowed). Cascades: the sun's cascades, red, green, blue, yellow. The shadow atlas itself: top bar, panels, 'shadows'.");
    ui.label("Edges: where anti-aliasing may change pixels (edge blur or FXAA). CoC: depth of field's circle of confusion, green in focus.");
    ui.separator();
    ui.label(RichText::new("Scripts").strong());
    ui.label("lampshade view SCENE --script FILE replays one 'FRAME ACTION ARGS' per line (src/app/script.rs).");
}

/// The slider span of knob `name` from the knob table.
/// A knob's slider span. Sliders using it clamp only what the user drags or types
/// (`SliderClamping::Edits`): a value set beyond the span by the CLI, a script or a settings
/// file (the knob's own range is wider) stays as it is, never silently clamped by drawing.
/// Depth of field's focus: `auto` (the surface at the screen's centre) or, unticked, a slider
/// for a fixed distance, starting from the last one set (10 the first time).
fn focus_distance(ui: &mut egui::Ui, focus: &mut Focus) {
    let id = ui.scope_id().with("manual-focus");
    let mut last: f32 = ui.data_mut(|d| d.get_temp(id)).unwrap_or(10.0);
    ui.horizontal(|ui| {
        let mut auto = *focus == Focus::Auto;
        if ui.checkbox(&mut auto, "auto").on_hover_text("focus on the surface at the screen's centre").changed() {
            *focus = if auto { Focus::Auto } else { Focus::Distance(last) };
        }
        if let Focus::Distance(d) = focus {
            ui.add(
                egui::Slider::new(d, slider("focus-distance")).clamping(egui::SliderClamping::Edits).logarithmic(true),
            );
            last = *d;
        }
    });
    ui.data_mut(|d| d.insert_temp(id, last));
}

pub(super) fn slider(name: &str) -> std::ops::RangeInclusive<f32> {
    // The names are this file's literals; `every_slider_knob_has_a_span` checks them.
    knobs::find(name).and_then(|k| k.slider()).unwrap_or(0.0..=1.0)
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_slider_knob_has_a_span() {
        for name in [
            "exposure",
            "light-cutoff",
            "tile-view-depth",
            "bloom-threshold",
            "bloom-intensity",
            "target-luminance",
            "adaptation-speed",
            "fog-density",
            "fog-height-falloff",
            "focus-distance",
            "aperture",
            "vignette",
        ] {
            assert!(super::knobs::find(name).and_then(|k| k.slider()).is_some(), "{name}");
        }
    }
}
