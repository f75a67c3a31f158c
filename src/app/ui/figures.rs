//! The right panel: the frame's figures (lights drawn, fragments, efficiency, GPU ms per pass), their history plot, the culling modes and views.

use super::common::culling_help;
use super::common::fmt_count;
use super::common::fmt_ms;
use super::common::method_name;
use super::common::FrameInfo;
use super::common::HISTORY;
use super::common::{History, Sample};
use crate::app::state::Scope;
use crate::app::state::UiState;
use crate::app::state::WireColour;
use crate::app::state::Wireframes;
use crate::renderer::post::effects::EFFECTS;
use crate::renderer::CullingMode;
use crate::renderer::DebugView;
use crate::renderer::FrameStats;
use crate::renderer::RenderPath;
use egui::Color32;
use egui::Pos2;
use egui::RichText;
use egui::Sense;
use egui::Stroke;
use egui::Vec2;
use std::collections::BTreeMap;

impl History {
    pub fn push(&mut self, s: Sample) {
        if self.samples.len() == HISTORY {
            self.samples.pop_front();
        }
        self.samples.push_back(s);
    }
}

pub(super) fn right_panel(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    egui::ScrollArea::vertical().id_salt("right-scroll").auto_shrink([false, false]).show(ui, |ui| {
        if let Some((resident, gpu)) = f.memory {
            ui.label(format!("memory: {} MiB resident, {} MiB in GPU buffers and textures", resident >> 20, gpu >> 20))
                .on_hover_text("sampled every 30 frames; it should stay flat while the viewer runs");
        }
        ui.label(RichText::new("Light culling").strong());
        egui::Grid::new("modes").num_columns(2).spacing([8.0, 2.0]).show(ui, |ui| {
            for (i, m) in CullingMode::ALL.into_iter().enumerate() {
                match super::common::refused(f, &st.settings, "culling", m.name()) {
                    Some(why) => {
                        let checked = st.settings.culling == m;
                        ui.add_enabled(false, egui::RadioButton::new(checked, m.name())).on_disabled_hover_text(why);
                    }
                    None => {
                        ui.radio_value(&mut st.settings.culling, m, m.name()).on_hover_text(culling_help(m));
                    }
                }
                if i % 2 == 1 {
                    ui.end_row();
                }
            }
        });
        // The render path, next to the culling modes: every path is listed; one the
        // renderer cannot draw is rejected with its error in the status line.
        ui.label(RichText::new("Render path").strong());
        egui::Grid::new("paths").num_columns(2).spacing([8.0, 2.0]).show(ui, |ui| {
            for (i, p) in RenderPath::ALL.into_iter().enumerate() {
                ui.radio_value(&mut st.settings.path, p, p.name())
                    .on_hover_text(crate::renderer::settings::help_of(&p));
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
        // Wrapped: six views do not fit the panel's width on one row.
        ui.horizontal_wrapped(|ui| {
            ui.label("view");
            for v in [
                DebugView::Lit,
                DebugView::Stencil,
                DebugView::Complexity,
                DebugView::TileLights,
                DebugView::Waste,
                DebugView::Shadow,
                DebugView::Cascades,
            ] {
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
        if st.settings.debug_view == DebugView::TileLights {
            tile_legend(ui);
            let tiles = f.stats.and_then(|s| s.tiles.as_ref());
            if tiles.is_some_and(|t| t.slices > 1) {
                // A slice through the clusters at one view depth (Unity HDRP's cluster display).
                ui.horizontal(|ui| {
                    ui.label("cluster slice at");
                    let range = super::tabs::slider("tile-view-depth");
                    ui.add(egui::Slider::new(&mut st.settings.tile_view_depth, range).logarithmic(true).suffix(" m"))
                        .on_hover_text(
                            "0: each pixel's own cluster, at its surface; a depth: every pixel shows its tile's \
                             cluster at that view depth",
                        );
                });
            }
        }
        if st.settings.debug_view == DebugView::Waste {
            // Lights evaluated at each pixel for nothing: the light ledger's waste.
            tile_legend(ui);
        }
        if st.settings.debug_view == DebugView::MaterialId {
            brdf_legend(ui);
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

/// The right panel's figures of the last frame: one row per figure, in the order the panel
/// shows them (each path's and pass's own rows in [`pass_rows`]).
pub(super) fn figures(ui: &mut egui::Ui, st: &UiState, f: &FrameInfo) {
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
        // Draws the light pass issued (marks, shades, stencil clears) and the instanced batches
        // the lights were grouped into; counting splits each batch's shading draw per light.
        row(ui, "light draws", format!("{} in {} batches", s.draw_calls, s.light_batches));
        row(ui, "GPU g-buffer", fmt_ms(s.gpu_ms.gbuffer));
        row(ui, "GPU shadows", fmt_ms(s.gpu_ms.shadows));
        row(ui, "GPU lighting", fmt_ms(s.gpu_ms.lighting));
        row(ui, "GPU compose", fmt_ms(s.gpu_ms.compose));
        pass_rows(ui, s);
        row(ui, "GPU total", fmt_ms(s.gpu_ms.total));
        let c = &s.cpu_ms;
        row(ui, "CPU records / plan / upload", format!("{:.2} / {:.2} / {:.2} ms", c.records, c.plan, c.upload));
    });
}

/// One row of the figures' grid: a name and its value.
fn row(ui: &mut egui::Ui, k: &str, v: String) {
    ui.label(k);
    // Truncated: an exact-size panel must never be pushed wider by its content.
    ui.add(egui::Label::new(RichText::new(v).monospace()).truncate());
    ui.end_row();
}

/// The figures' rows of what this frame ran: the light pre-pass's passes, the forward pass,
/// the forward paths' passes, the tiled pass's lists, the post chain's passes.
fn pass_rows(ui: &mut egui::Ui, s: &FrameStats) {
    if let Some(p) = &s.prepass {
        // The light pre-pass: pass 1 is the g-buffer row, pass 2 the lighting row.
        row(ui, "GPU pass 3 (final)", fmt_ms(s.gpu_ms.prepass_final));
        row(ui, "pass 1 / 3 draws", format!("{} / {}", p.base_draw_calls, p.final_draw_calls));
        let frags = |v: Option<u64>| v.map_or("-".into(), fmt_count);
        row(ui, "pass 1 / 3 fragments", format!("{} / {}", frags(p.base_fragments), frags(p.final_fragments)));
        row(
            ui,
            "B/pixel",
            format!(
                "normal+exp {}, depth copy {}, light buffer {} ({}), HDR {}",
                p.normal_exp_bytes_per_pixel,
                p.depth_copy_bytes_per_pixel,
                p.light_buffer_bytes_per_pixel,
                p.light_buffer_format,
                p.hdr_bytes_per_pixel
            ),
        );
        if p.samples > 1 {
            row(ui, "pass 3 MSAA", format!("{} samples, {} B/pixel", p.samples, p.msaa_bytes_per_pixel));
        }
    }
    if let Some(fw) = &s.forward {
        // Blended surfaces: the forward pass, its fragments and the lights per fragment it
        // may walk (the longest list).
        row(ui, "GPU forward", fmt_ms(s.gpu_ms.forward));
        row(ui, "forward fragments", fw.fragments.map_or("-".into(), fmt_count));
        let longest =
            if fw.tiles > 0 { fw.longest_tile_list.min(fw.longest_object_list) } else { fw.longest_object_list };
        row(ui, "forward lights", format!("{} ≤ {longest}/fragment", fw.lights.name()));
        if let Some(n) = fw.peel_layers {
            // Depth peeling: samples behind the last layer are dropped.
            let dropped = fw.unpeeled.map_or("-".into(), fmt_count);
            row(ui, "peeled layers", format!("{n} · {dropped} dropped"));
        }
    }
    if let Some(fp) = &s.forward_path {
        // The forward paths: each pass's draws, samples shaded and time, the
        // intermediate targets' bytes per pixel and the object light lists.
        row(ui, "path", format!("{} (x{} samples)", fp.path.name(), fp.samples));
        for p in &fp.passes {
            let frags = p.fragments.map_or("-".into(), fmt_count);
            row(
                ui,
                &format!("GPU {}", p.name),
                format!("{} · {} draws · {frags} frag", fmt_ms(p.gpu_ms), p.draw_calls),
            );
        }
        row(ui, "target bytes/pixel", format!("{}", fp.bytes_per_pixel()));
        row(ui, "object light lists", format!("{} entries (longest {})", fmt_count(fp.list_entries), fp.longest_list));
    }
    if let Some(t) = &s.tiles {
        // The tiled pass's lists: cells, summed and longest length (read back when counting).
        let cells = if t.slices > 1 {
            format!("{} clusters ({} px x {} slices)", fmt_count(t.cells), t.tile_size, t.slices)
        } else {
            format!("{} tiles ({} px)", fmt_count(t.cells), t.tile_size)
        };
        row(ui, "light lists", cells);
        if t.entries > 0 || s.shaded_fragments.is_some() {
            let over = if t.overflowed > 0 { format!(", {} full", t.overflowed) } else { String::new() };
            row(ui, "list entries", format!("{} (longest {}){over}", fmt_count(t.entries), t.longest));
        }
    }
    if let Some(post) = &s.post {
        // The post chain's passes, each when it ran.
        if post.bloom {
            row(ui, "GPU bloom", fmt_ms(s.gpu_ms.bloom));
        }
        if post.auto_exposure {
            row(ui, "GPU auto-exposure", fmt_ms(s.gpu_ms.exposure));
        }
        row(ui, "GPU tonemap", format!("{} ({})", fmt_ms(s.gpu_ms.tonemap), post.tonemap.name()));
        for e in EFFECTS.iter().filter(|e| post.ran(e.name)) {
            row(ui, &format!("GPU {}", e.title), fmt_ms(s.gpu_ms.effect(e.name)));
        }
    }
}

/// The legend of the `material-id` view: each reflectance model's colour (`Brdf::debug_color`,
/// linear, shown as the sRGB output shows it).
fn brdf_legend(ui: &mut egui::Ui) {
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 3.0;
        for b in crate::scene::Brdf::ALL {
            let [r, g, bl] = b.debug_color();
            let (rect, _) = ui.allocate_exact_size(Vec2::splat(10.0), Sense::hover());
            ui.painter().rect_filled(rect, 1.0, egui::Rgba::from_rgb(r, g, bl));
            ui.label(RichText::new(b.name()).small());
        }
    });
}

/// The legend of the `tile-lights` view: a colour bar from 0 to `tiles::HEAT_MAX` lights per
/// list (longer lists saturate at the right end), with counts under it.
fn tile_legend(ui: &mut egui::Ui) {
    heat_legend(ui, "lights per tile / cluster list", crate::renderer::tiles::HEAT_MAX, 0);
}

/// The heatmap views' scale: `title`, 0 to `max` (the last label `max+`), `decimals` places.
pub(super) fn heat_legend(ui: &mut egui::Ui, title: &str, max: f32, decimals: usize) {
    ui.label(RichText::new(title).small());
    let width = ui.available_width().clamp(120.0, 260.0);
    let (rect, _) = ui.allocate_exact_size(Vec2::new(width, 26.0), Sense::hover());
    let p = ui.painter_at(rect);
    let bar = egui::Rect::from_min_size(rect.min, Vec2::new(width, 12.0));
    let steps = 64;
    for k in 0..steps {
        let [r, g, b] = crate::renderer::tiles::heat((k as f32 + 0.5) / steps as f32);
        let x0 = bar.left() + bar.width() * k as f32 / steps as f32;
        let cell = egui::Rect::from_min_max(
            Pos2::new(x0, bar.top()),
            Pos2::new(x0 + bar.width() / steps as f32 + 0.5, bar.bottom()),
        );
        p.rect_filled(cell, 0.0, Color32::from_rgb((r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8));
    }
    for k in 0..=4 {
        let v = max * k as f32 / 4.0;
        let x = bar.left() + bar.width() * k as f32 / 4.0;
        let align = match k {
            0 => egui::Align2::LEFT_TOP,
            4 => egui::Align2::RIGHT_TOP,
            _ => egui::Align2::CENTER_TOP,
        };
        let label = if k == 4 { format!("{v:.decimals$}+") } else { format!("{v:.decimals$}") };
        p.text(
            Pos2::new(x, bar.bottom() + 1.0),
            align,
            label,
            egui::FontId::proportional(10.0),
            Color32::from_gray(200),
        );
    }
}

pub(super) fn plot(ui: &mut egui::Ui, title: &str, series: &[(&str, Color32, Vec<Option<f64>>)], unit: &str) {
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

pub(super) fn plots(ui: &mut egui::Ui, h: &History) {
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
