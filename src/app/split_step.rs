//! The frame step that draws the split view's configuration B (`app::split`) after A.

use super::split::{overlay, SplitGfx, SplitView};
use crate::renderer::Settings;

impl super::App {
    /// Draws configuration B after A (`a`, drawn this frame when `rendered`) into its image at
    /// the viewport's size, and, in the difference and FLIP views, the overlay of the pair.
    /// With the split view off, B's renderer and images are let go.
    pub(super) fn render_split(&mut self, a: &Settings, rendered: bool) {
        let Some(g) = self.gfx.as_mut() else { return };
        if !self.state.split.on {
            if let Some(s) = g.split.take() {
                g.egui_renderer.free_texture(&s.image.id);
            }
            return;
        }
        let Some(scene) = self.scene.as_ref().filter(|_| rendered) else { return };
        let (w, h) = (g.viewport.width, g.viewport.height);
        let b = match self.state.split.b_settings(a) {
            Ok(b) => b,
            Err(e) => {
                if let Some(s) = g.split.as_mut() {
                    s.figures.error = Some(e);
                }
                return;
            }
        };
        if g.split.is_none() {
            match SplitGfx::new(&g.gpu, &mut g.egui_renderer, &b, (w, h)) {
                Ok(s) => {
                    let mut s = s;
                    s.renderer.set_calibration(g.renderer.calibration().clone());
                    g.split = Some(s);
                }
                Err(e) => {
                    self.state.split.on = false;
                    let text = format!("compare: {e:#}");
                    self.say(text, true);
                    return;
                }
            }
        }
        let Some(s) = g.split.as_mut() else { return };
        s.image.resize(&g.gpu.device, &mut g.egui_renderer, w, h, wgpu::FilterMode::Linear);
        match s.renderer.render(scene, &b, &s.image.target, w, h) {
            Ok(stats) => {
                s.image.publish(&g.gpu);
                let a_stats = self.stats.as_ref();
                s.figures.a_ms = a_stats.map_or(Vec::new(), |st| crate::bench::median_passes(std::slice::from_ref(st)));
                s.figures.b_ms = crate::bench::median_passes(std::slice::from_ref(&stats));
                let costs = crate::bench::light_costs;
                s.figures.ledger_delta = crate::bench::ledger_delta(&a_stats.map_or(Vec::new(), costs), &costs(&stats));
                s.figures.error = None;
                s.stats = Some(stats);
            }
            Err(e) => {
                s.figures.error = Some(format!("{e:#}"));
                return;
            }
        }
        let view = self.state.split.view;
        if view == SplitView::Split {
            s.figures.max_steps = None;
            s.figures.flip_mean = None;
            return;
        }
        let pair = g.viewport.read(&g.gpu).and_then(|ia| Ok((ia, s.image.read(&g.gpu)?)));
        match pair.and_then(|(ia, ib)| overlay(view, &ia, &ib)) {
            Ok((img, steps, flip)) => {
                s.figures.max_steps = Some(steps);
                s.figures.flip_mean = flip;
                let size = [img.width() as usize, img.height() as usize];
                let colour = egui::ColorImage::from_rgba_unmultiplied(size, img.as_raw());
                match &mut s.overlay {
                    Some(t) => t.set(colour, egui::TextureOptions::LINEAR),
                    None => {
                        s.overlay =
                            Some(g.egui_ctx.load_texture("compare overlay", colour, egui::TextureOptions::LINEAR))
                    }
                }
            }
            Err(e) => s.figures.error = Some(format!("{e:#}")),
        }
    }
}
