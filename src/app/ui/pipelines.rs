//! The pipelines window: each configuration the viewer has drawn or built, with every pipeline
//! it declares and its compile time, and the totals. It answers "why did that switch take a
//! second?": the configuration's compiles, whether they ran in the background or held a frame,
//! and the driver's warm-up draw where it needs one (`app::compiling`).

use super::common::FrameInfo;
use crate::app::state::UiState;
use egui::{Color32, RichText};

pub(super) fn pipelines_window(ctx: &egui::Context, st: &mut UiState, f: &FrameInfo) {
    let mut open = true;
    egui::Window::new("Pipelines").open(&mut open).default_size([520.0, 380.0]).resizable(true).show(ctx, |ui| {
        if let Some(note) = f.compiling.as_deref() {
            ui.label(RichText::new(note).color(Color32::LIGHT_BLUE));
        }
        let all: usize = f.pipelines.iter().map(|c| c.pipelines.len()).sum();
        let ms: f64 = f.pipelines.iter().map(|c| c.compile_ms).sum();
        ui.label(
            RichText::new(format!(
                "{} configurations, {all} pipelines declared, {ms:.0} ms compiling; most recent first",
                f.pipelines.len()
            ))
            .weak(),
        );
        egui::ScrollArea::vertical().auto_shrink([false, false]).show(ui, |ui| {
            for (i, c) in f.pipelines.iter().enumerate().rev() {
                let warm = c.warm_ms.map_or(String::new(), |w| format!(", warm-up draw {w:.0} ms"));
                let head = format!(
                    "{}: {} of {} compiled {} in {:.0} ms{warm}",
                    c.config,
                    c.compiled(),
                    c.pipelines.len(),
                    match c.built_by {
                        "background" => "in the background",
                        "frame" => "by the frame (it waited)",
                        _ => "earlier",
                    },
                    c.compile_ms
                );
                egui::CollapsingHeader::new(head)
                    .id_salt(("pipelines", i))
                    .default_open(i + 1 == f.pipelines.len())
                    .show(ui, |ui| {
                        egui::Grid::new(("pipeline rows", i)).num_columns(2).striped(true).show(ui, |ui| {
                            for p in &c.pipelines {
                                let t = match p.ms {
                                    Some(ms) => format!("{ms:.1} ms{}", if p.now { "" } else { " (before)" }),
                                    None => "not compiled".into(),
                                };
                                ui.label(&p.label);
                                ui.label(t);
                                ui.end_row();
                            }
                        });
                    });
            }
        });
    });
    st.panels.pipelines = open;
}
