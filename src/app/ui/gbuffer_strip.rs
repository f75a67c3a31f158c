//! The G-buffer strip: a thumbnail per target (and the light, stencil and complexity views).

use super::common::FrameInfo;
use super::common::Thumb;
use crate::app::state::UiState;
use crate::renderer::kit::gbuffer::Attr;
use crate::renderer::kit::gbuffer::GBufferLayout;
use crate::renderer::DebugView;
use crate::renderer::LayoutChoice;
use crate::renderer::RenderPath;
use egui::Color32;
use egui::Pos2;
use egui::Rect;
use egui::RichText;
use egui::Sense;
use egui::Stroke;
use egui::Vec2;

/// The thumbnail strip for a layout: each G-buffer target by the views that decode its
/// attributes (each view once), the light accumulation, then depth-stencil: stencil diagram
/// and light complexity.
pub fn thumbs(layout: &GBufferLayout, accum: Option<wgpu::TextureFormat>, depth: wgpu::TextureFormat) -> Vec<Thumb> {
    let mut out: Vec<Thumb> = Vec::new();
    let mut add = |view, label, buffer: &str, format: String| {
        if !out.iter().any(|t| t.view == view) {
            out.push(Thumb { view, label, buffer: buffer.to_string(), format });
        }
    };
    for t in &layout.targets {
        for slot in t.channels.iter().flatten() {
            let (view, label) = match slot.attr {
                Attr::Albedo => (DebugView::Albedo, "albedo"),
                // The light pre-pass stores the exponent alone (green; red is its unit f0).
                Attr::SpecExp if layout.name == crate::renderer::kit::gbuffer::PREPASS_LAYOUT => {
                    (DebugView::Specular, "exponent")
                }
                Attr::SpecLevel | Attr::SpecExp => (DebugView::Specular, "specular"),
                Attr::Normal => (DebugView::Normal, "normal"),
                Attr::Emissive => (DebugView::Emissive, "emissive"),
                Attr::EmissiveScale => (DebugView::Emissive, "emissive x albedo"),
                Attr::Depth => (DebugView::Depth, "depth"),
                Attr::Position => (DebugView::Depth, "position z"),
                Attr::Material => (DebugView::MaterialId, "material ID"),
                Attr::MaterialExp => (DebugView::MaterialId, "material ID + exponent"),
                // The culling layer has no view of its own; the probe shows it.
                Attr::Layer => continue,
            };
            add(view, label, t.name, format!("{:?}", t.format));
        }
    }
    let accum = accum.map_or("-".into(), |a| format!("{a:?}"));
    if layout.name == crate::renderer::kit::gbuffer::PREPASS_LAYOUT {
        // The light pre-pass's one light buffer, decoded: RGB diffuse, A mono specular (grey).
        add(DebugView::DiffuseLight, "diffuse light", "light buffer RGB", accum.clone());
        add(DebugView::SpecularLight, "mono specular", "light buffer A", accum.clone());
    }
    add(DebugView::DiffuseLight, "diffuse light", "accumulation", accum.clone());
    add(DebugView::SpecularLight, "specular light", "accumulation", accum);
    add(DebugView::Depth, "depth", "depth-stencil", format!("{depth:?}"));
    add(DebugView::Stencil, "stencil", "depth-stencil", format!("{depth:?}"));
    add(DebugView::Complexity, "complexity", "lights per pixel", "heatmap".into());
    out
}

pub(super) fn gbuffer_strip(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    // In a horizontal scroll area the last items get little width: never wrap their labels.
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
    ui.horizontal(|ui| {
        ui.label(RichText::new("G-buffer").strong());
        if st.settings.path == RenderPath::LightPrepass {
            // The light pre-pass writes its own thin buffer whatever the layout setting says.
            ui.label("light pre-pass: normal + exponent");
        } else if !st.settings.path.keeps_gbuffer() {
            ui.label(format!("{}: no G-buffer (depth and the HDR colour only)", st.settings.path.name()));
            return;
        } else {
            egui::ComboBox::from_id_salt("layout").selected_text(st.settings.layout.name()).width(90.0).show_ui(
                ui,
                |ui| {
                    for l in LayoutChoice::ALL {
                        let why = super::common::refused(f, &st.settings, "layout", l.name());
                        super::common::offer(ui, why, &mut st.settings.layout, l, l.name());
                    }
                },
            );
        }
        ui.label(format!("{} B/pixel in colour targets + {}", f.gbuffer_bytes, f.depth_format));
        ui.label(RichText::new("click a view to show it full size").weak());
    });
    // As many tiles as fit side by side, in the viewport's aspect, as tall as the strip allows.
    let n = f.tiles.len().max(1) as f32;
    let gap = 6.0;
    let aspect = f.viewport.map_or(16.0 / 9.0, |(_, [w, h])| w as f32 / h.max(1) as f32);
    let max_h = (ui.available_height() - 40.0).clamp(24.0, 120.0);
    let thumb_w = ((ui.available_width() - gap * (n - 1.0)) / n).clamp(64.0, (max_h * aspect).max(64.0));
    let thumb_h = thumb_w / aspect;
    egui::ScrollArea::horizontal().id_salt("thumbs").auto_shrink([false, true]).show(ui, |ui| {
        ui.horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = gap;
            for t in f.tiles {
                ui.vertical(|ui| {
                    ui.set_width(thumb_w);
                    ui.spacing_mut().item_spacing.y = 1.0;
                    let selected = st.settings.debug_view == t.view;
                    let (rect, resp) = ui.allocate_exact_size(Vec2::new(thumb_w, thumb_h), Sense::click());
                    match f.thumbs.get(&t.view) {
                        Some(id) => {
                            let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
                            // The stencil and complexity views need passes of their own: the
                            // frame computes them only while shown, else the tile is stale.
                            let stale = matches!(t.view, DebugView::Stencil | DebugView::Complexity) && !selected;
                            let tint = if stale { Color32::from_gray(70) } else { Color32::WHITE };
                            ui.painter().image(*id, rect, uv, tint);
                        }
                        None => {
                            ui.painter().rect_filled(rect, 0.0, Color32::from_gray(10));
                        }
                    }
                    let stroke = if selected {
                        Stroke::new(2.0, Color32::from_rgb(255, 200, 60))
                    } else if resp.hovered() {
                        Stroke::new(1.0, Color32::from_gray(200))
                    } else {
                        Stroke::new(1.0, Color32::from_gray(60))
                    };
                    ui.painter().rect_stroke(rect, 0.0, stroke, egui::StrokeKind::Outside);
                    if matches!(t.view, DebugView::Stencil | DebugView::Complexity) && !selected {
                        ui.painter().text(
                            rect.center(),
                            egui::Align2::CENTER_CENTER,
                            "click to compute",
                            egui::FontId::proportional(10.0),
                            Color32::from_gray(150),
                        );
                    }
                    let resp = resp.on_hover_text(format!("{}: {} ({})", t.label, t.buffer, t.format));
                    if resp.clicked() {
                        st.settings.debug_view = if selected { DebugView::Lit } else { t.view };
                    }
                    ui.add(egui::Label::new(RichText::new(t.label).small()).truncate());
                    ui.add(egui::Label::new(RichText::new(&t.format).small().weak()).truncate());
                });
            }
        });
    });
}
