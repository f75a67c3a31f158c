//! The advisor's window: its progress while it runs, then prediction against measurement per
//! light count and candidate, the best of each, the answer with its regret, and the crossovers
//! (as `lampshade advise` prints them).

use super::common::FrameInfo;
use crate::app::state::UiState;
use egui::Color32;
use egui::RichText;

pub(super) fn advice_window(ctx: &egui::Context, st: &mut UiState, f: &FrameInfo) {
    let Some(job) = f.advice else { return };
    let mut open = true;
    egui::Window::new("Advice: which path and mode").open(&mut open).default_size([520.0, 360.0]).resizable(true).show(
        ctx,
        |ui| {
            let a = match job.answer() {
                None => {
                    let (done, total, what) = job.progress.lock().map(|g| g.clone()).unwrap_or_default();
                    let frac = if total > 0 { done as f32 / total as f32 } else { 0.0 };
                    ui.add(egui::ProgressBar::new(frac).text(format!("{done}/{total}: {what}")));
                    ui.label(
                        RichText::new(format!(
                            "{:.0} s; the viewer keeps running",
                            job.started.elapsed().as_secs_f64()
                        ))
                        .weak(),
                    );
                    ctx.request_repaint();
                    return;
                }
                Some(Err(e)) => {
                    ui.label(RichText::new(format!("no advice: {e}")).color(Color32::from_rgb(255, 170, 80)));
                    return;
                }
                Some(Ok(a)) => a,
            };
            ui.label(
                RichText::new(format!(
                    "{} at {}x{}: calibrated on {} frames per candidate below the counts asked, then measured",
                    a.scene,
                    a.size.0,
                    a.size.1,
                    a.calibration.len()
                ))
                .weak(),
            );
            let fmt = |v: f64| if v.is_finite() { format!("{v:.1}") } else { "-".into() };
            egui::Grid::new("advice rows").num_columns(1 + a.counts.len()).striped(true).spacing([10.0, 1.0]).show(
                ui,
                |ui| {
                    ui.label(RichText::new("ms predicted / measured").strong());
                    for n in &a.counts {
                        ui.label(RichText::new(format!("{n} lights")).strong());
                    }
                    ui.end_row();
                    for (c, name) in a.candidates.iter().enumerate() {
                        ui.label(name).on_hover_text(a.refused[c].as_deref().unwrap_or(""));
                        for k in 0..a.counts.len() {
                            let best = a.best(k).1 == Some(c);
                            let t = RichText::new(format!("{} / {}", fmt(a.predicted[c][k]), fmt(a.measured[c][k])));
                            ui.label(if best { t.strong().color(Color32::from_rgb(120, 220, 120)) } else { t });
                        }
                        ui.end_row();
                    }
                    ui.label(RichText::new("predicted best").strong());
                    for k in 0..a.counts.len() {
                        let (p, m) = a.best(k);
                        let name = p.and_then(|c| a.candidates.get(c).cloned()).unwrap_or_else(|| "-".into());
                        let colour =
                            if p == m { Color32::from_rgb(120, 220, 120) } else { Color32::from_rgb(255, 170, 80) };
                        ui.label(RichText::new(name).color(colour));
                    }
                    ui.end_row();
                    // The answer: of the three predicted fastest, the one measured fastest, and
                    // its regret against the measured best of all.
                    ui.label(RichText::new("answer (regret)").strong()).on_hover_text(
                        "of the three candidates predicted fastest, the one measured fastest; its regret is its measured ms over the measured best's, met (green) where it is the best or the two differ by less than two combined standard errors of their rounds",
                    );
                    for k in 0..a.counts.len() {
                        let name = a.answer(k).and_then(|c| a.candidates.get(c).cloned()).unwrap_or_else(|| "-".into());
                        let t = match a.regret(k) {
                            Some((r, met)) => RichText::new(format!("{name} ({r:.2})")).color(if met {
                                Color32::from_rgb(120, 220, 120)
                            } else {
                                Color32::from_rgb(255, 170, 80)
                            }),
                            None => RichText::new(name),
                        };
                        ui.label(t);
                    }
                    ui.end_row();
                },
            );
            let cross = |v: &[(f64, usize, usize)]| {
                if v.is_empty() {
                    "none in this range".to_string()
                } else {
                    v.iter()
                        .map(|(n, x, y)| {
                            let name = |c: usize| a.candidates.get(c).cloned().unwrap_or_default();
                            format!("{} -> {} at {n:.0}", name(*x), name(*y))
                        })
                        .collect::<Vec<_>>()
                        .join("; ")
                }
            };
            ui.label(format!("predicted crossovers: {}", cross(&a.predicted_crossovers)));
            ui.label(format!("measured crossovers: {}", cross(&a.measured_crossovers)));
            let _ = &st;
        },
    );
    st.panels.advice = open;
}
