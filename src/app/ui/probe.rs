//! The pixel probe: the G-buffer values, lit value and lights of the pixel under the pointer.

use super::*;

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
