//! The scene tab's "Stochastic shading" section: RIS's samples and candidates on the list
//! modes, its spatial and temporal reuse and its denoiser, stochastic light culling and its threshold on every mode, the noise seed (and a
//! new seed each frame), and what the last frame drew with (`FrameStats::stochastic`).

use super::common::FrameInfo;
use crate::app::state::UiState;
use crate::renderer::DebugView;
use egui::RichText;

pub(super) fn section(ui: &mut egui::Ui, st: &mut UiState, f: &FrameInfo) {
    egui::CollapsingHeader::new(RichText::new("Stochastic shading").strong()).id_salt("stochastic").show(ui, |ui| {
        let s = &mut st.settings;
        ui.add_enabled_ui(s.culling.can_list(), |ui| {
            ui.horizontal(|ui| {
                ui.label("RIS samples K");
                ui.add(egui::Slider::new(&mut s.ris_samples, 0..=64))
                    .on_hover_text("samples each pixel keeps from its list and shades with its shadow; 0: exact");
            });
            ui.horizontal(|ui| {
                ui.label("candidates M");
                ui.add(egui::Slider::new(&mut s.ris_candidates, 1..=256).logarithmic(true))
                    .on_hover_text("lights drawn uniformly from the pixel's list for each sample");
            });
            let reuse = s.ris_samples > 0 && s.ris_samples <= crate::renderer::stochastic::reuse::MAX_SAMPLES;
            ui.add_enabled_ui(reuse, |ui| {
                ui.horizontal(|ui| {
                    ui.label("spatial reuse");
                    ui.add(egui::Slider::new(&mut s.ris_spatial, 0..=16)).on_hover_text(
                        "neighbours each sample is combined with (ReSTIR, unbiased 1/Z weights); 0: off",
                    );
                });
                ui.checkbox(&mut s.ris_temporal, "temporal reuse").on_hover_text(
                    "combine each sample with the last frame's at the reprojected point (biased where things move)",
                );
                ui.checkbox(&mut s.ris_denoise, "denoise").on_hover_text(
                    "temporal accumulation and an edge-aware filter guided by the variance (SVGF; biased)",
                );
            })
            .response
            .on_disabled_hover_text(format!(
                "reuse and the denoiser keep 1 to {} RIS samples a pixel",
                crate::renderer::stochastic::reuse::MAX_SAMPLES
            ));
        })
        .response
        .on_disabled_hover_text("RIS draws from light lists: culling tiled, clustered, zbin or auto");
        ui.add_enabled_ui(s.ris_samples > 0, |ui| {
            ui.horizontal(|ui| {
                ui.label("view");
                for v in [DebugView::Lit, DebugView::Converge, DebugView::Variance] {
                    ui.selectable_value(&mut s.debug_view, v, v.name());
                }
            })
            .response
            .on_hover_text(
                "converge: RIS's frames averaged while the camera, the lights and the settings hold still (a new seed \
                 each frame); variance: how much each pixel's light varies from frame to frame over them",
            );
        });
        if s.debug_view == DebugView::Variance {
            super::figures::heat_legend(ui, "RIS's light: deviation over mean, frame to frame", 2.0, 1);
        }
        ui.checkbox(&mut s.stochastic_culling, "stochastic light culling (every mode)");
        ui.add_enabled_ui(s.stochastic_culling, |ui| {
            ui.horizontal(|ui| {
                ui.label("threshold");
                ui.add(egui::Slider::new(&mut s.stochastic_threshold, 0.01..=1.0))
                    .on_hover_text("attenuation below which a light's range is drawn at random each frame");
            });
        });
        ui.horizontal(|ui| {
            ui.label("noise seed");
            ui.add(egui::DragValue::new(&mut s.noise_seed));
            ui.checkbox(&mut st.animate_noise, "a new seed each frame");
        });
        match f.stats.and_then(|s| s.stochastic.as_ref()) {
            Some(x) => {
                let culled = x.culling_threshold.map_or("off".to_string(), |t| {
                    format!(
                        "{} ranges cut at threshold {t}, {:.0}% of the radius kept on average",
                        x.ranges_cut,
                        x.mean_range * 100.0
                    )
                });
                let reuse = match (x.ris_spatial, x.ris_temporal) {
                    (0, false) => String::new(),
                    (n, t) => format!(
                        ", reuse {}{}{}",
                        if n > 0 { format!("{n} neighbours") } else { String::new() },
                        if n > 0 && t { " and " } else { "" },
                        if t { "temporal" } else { "" }
                    ),
                };
                let denoised = if x.denoise { ", denoised" } else { "" };
                ui.label(format!(
                    "last frame: seed {}, RIS {} x {}{reuse}{denoised}, culling {culled}",
                    x.noise_seed, x.ris_samples, x.ris_candidates
                ));
            }
            None => {
                ui.label("last frame: exact");
            }
        }
    });
}
