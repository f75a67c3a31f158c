//! The pixel probe: the G-buffer values, lit value and lights of the pixel under the pointer.

use super::common::FrameInfo;
use crate::renderer::explain::LightWhy;
use egui::Color32;
use egui::RichText;
use glam::Vec3;

pub(super) fn v3(v: Vec3) -> String {
    format!("{:.3} {:.3} {:.3}", v.x, v.y, v.z)
}

pub(super) fn pixel_panel(ui: &mut egui::Ui, f: &FrameInfo) {
    ui.label(RichText::new("Pixel under the cursor").strong());
    let Some(p) = f.probe else {
        ui.label("hover the viewport");
        return;
    };
    egui::Grid::new("probe").num_columns(2).striped(true).spacing([10.0, 2.0]).show(ui, |ui| {
        let row = |ui: &mut egui::Ui, k: &str, v: String| {
            ui.label(k);
            // Truncated: an exact-size panel must never be pushed wider by its content.
            ui.add(egui::Label::new(RichText::new(v).monospace()).truncate());
            ui.end_row();
        };
        row(ui, "pixel", format!("{}, {}", p.x, p.y));
        if !p.valid {
            row(ui, "surface", "background".into());
        } else {
            let id = p.material_id.map_or("one for the scene".to_string(), |id| format!("ID {id}"));
            row(ui, "model", format!("{} ({id})", p.brdf.name()));
            row(ui, "layer", p.layer.to_string());
            row(ui, "albedo", v3(p.albedo));
            row(ui, "spec level / exp", format!("{:.3} / {:.1}", p.specular_level, p.specular_exponent));
            row(ui, "normal (view)", v3(p.normal));
            row(ui, "emissive", v3(p.emissive));
            let q = p.position;
            row(ui, "position (view)", format!("{:.2} {:.2} {:.2}", q.x, q.y, q.z));
            row(ui, "diffuse light", v3(p.diffuse_light));
            row(ui, "specular light", v3(p.specular_light));
            row(ui, "lit (linear)", v3(p.lit));
        }
        let shown: Vec<String> = p.lights.iter().take(12).map(|i| i.to_string()).collect();
        let more = if p.lights.len() > 12 { format!(" +{}", p.lights.len() - 12) } else { String::new() };
        let list = if p.lights.is_empty() {
            "none".to_string()
        } else {
            format!("{}: {}{more}", p.lights.len(), shown.join(" "))
        };
        row(ui, "lights touching", list);
    });
    ui.label(RichText::new("raw G-buffer channels (hover)").weak()).on_hover_ui(|ui| {
        for (name, format, v) in &p.raw {
            ui.label(RichText::new(format!("{name} ({format})")).weak());
            ui.label(RichText::new(format!("{:.4} {:.4} {:.4} {:.4}", v[0], v[1], v[2], v[3])).monospace());
        }
    });
}

/// The colour of what the culling did: green admitted and adding light, amber admitted for
/// nothing (wasted), grey culled, red light the culling dropped (missed).
fn culling_colour(l: &LightWhy) -> Color32 {
    if l.missed {
        Color32::from_rgb(255, 80, 80)
    } else if l.wasted {
        Color32::from_rgb(255, 180, 60)
    } else if l.culling.admitted() {
        Color32::from_rgb(110, 220, 110)
    } else {
        Color32::GRAY
    }
}

/// Why each light lit the last clicked pixel (`Last::explain`; `render --probe X,Y` gives
/// the same): one row a light, the culling's verdict as a short coloured word, the shader
/// test that zeroed it, what it adds. As of the click: the frame may have changed since.
pub(super) fn explanation_panel(ui: &mut egui::Ui, f: &FrameInfo) {
    let Some(e) = f.explanation else {
        ui.label(RichText::new("click a pixel: why each light lit it").weak());
        return;
    };
    let e = match e {
        Ok(e) => e,
        Err(msg) => {
            ui.label(RichText::new(format!("no explanation: {msg}")).color(Color32::from_rgb(255, 170, 80)));
            return;
        }
    };
    ui.label(RichText::new(format!("Why each light: pixel {}, {} (at the click)", e.x, e.y)).strong());
    if !e.valid {
        ui.label("background: nothing is lit");
        return;
    }
    let cell = e.cell.as_ref().map_or(String::new(), |c| format!(", cell {} holds {}", c.index, c.lights));
    ui.label(format!(
        "{} culling{cell}: {} listed, {} wasted, {} missed",
        e.culling_mode,
        e.lights.len(),
        e.wasted,
        e.missed
    ))
    .on_hover_text(
        "listed: lights whose screen bounds cover the pixel, that the culling admitted, or that add light. \
             wasted: evaluated, adding nothing. missed: culled though they add light (never, in a correct mode)",
    );
    ui.label(
        RichText::new(format!(
            "accumulated {}  = lights {} + rest {}",
            v3(e.accumulated_diffuse),
            v3(e.lights_diffuse),
            v3(e.rest_diffuse)
        ))
        .small(),
    )
    .on_hover_text(if e.prepass {
        "the light pre-pass's buffer: diffuse light with unit reflectance; the rest is ambient and sun as its pass 2 began"
    } else {
        "diffuse light (seed 000: the lit colour); the rest is ambient and sun as the G-buffer pass wrote them"
    });
    egui::ScrollArea::vertical().id_salt("explanation").show(ui, |ui| {
        egui::Grid::new("explanation rows").num_columns(4).striped(true).spacing([8.0, 1.0]).show(ui, |ui| {
            for h in ["light", "culling", "shading", "adds (lit colour)"] {
                ui.label(RichText::new(h).weak());
            }
            ui.end_row();
            for l in &e.lights {
                ui.label(RichText::new(format!("{} {}", l.index, l.kind)).monospace());
                ui.label(RichText::new(l.culling.word()).color(culling_colour(l))).on_hover_text(format!(
                    "{}: {}",
                    l.method.name(),
                    if l.missed {
                        "MISSED: culled, but adds light"
                    } else if l.wasted {
                        "wasted: evaluated for nothing"
                    } else {
                        ""
                    }
                ));
                ui.label(format!("{:?}", l.shading).to_lowercase()).on_hover_text(format!(
                    "distance / radius {:.3}, spot {:.3}, N.L {:.3}, shadow {:.3}{}, cookie {:.3}",
                    l.distance_over_radius,
                    l.spot,
                    l.n_dot_l,
                    l.shadow,
                    if l.shadow_tile { "" } else { " (no shadow map)" },
                    l.cookie
                ));
                ui.label(RichText::new(v3(l.lit)).monospace());
                ui.end_row();
            }
        });
    });
}
