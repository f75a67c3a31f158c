//! The debug views that need a pass of their own: seed 000's stencil diagram (blue: passed Z in
//! the marking pass; red: passed Z in the shading pass; green: passed the stencil test, lit),
//! drawn with the two-pass method's own states, and the light-complexity heatmap.

use crate::renderer::culling::methods::{FULLSCREEN, STENCIL_TWO_PASS, VOLUME};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{LightPipe, Out, Shared, Vs, ADDITIVE, MAX};
use crate::renderer::plan::Method;
use crate::renderer::settings::DebugView;

pub struct DebugPass {
    /// Seed 000's diagram: the two-pass mark, the volume test alone, the two-pass shade.
    classify: [crate::renderer::kit::RenderPipe; 3],
    complexity: crate::renderer::kit::RenderPipe,
    complexity_fullscreen: crate::renderer::kit::RenderPipe,
}

impl DebugPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe = |label, vs, fs, state, out| shared.light_pipeline(device, LightPipe { label, vs, fs, state, out });
        let mark = STENCIL_TWO_PASS.mark.clone().unwrap_or_else(|| VOLUME.shade.clone());
        Self {
            classify: [
                pipe("classify: pass 1 Z", Vs::Volume, "fs_blue", mark, Out::Debug(MAX)),
                pipe("classify: pass 2 Z", Vs::Volume, "fs_red", VOLUME.shade.clone(), Out::Debug(MAX)),
                pipe(
                    "classify: pass 2 stencil",
                    Vs::Volume,
                    "fs_green",
                    STENCIL_TWO_PASS.shade.clone(),
                    Out::Debug(MAX),
                ),
            ],
            // Light complexity counts the points inside each light's true shape (the shader
            // discards the rest), drawn as the plain volume method draws the light.
            complexity: pipe(
                "light complexity",
                Vs::Volume,
                "fs_complexity",
                VOLUME.shade.clone(),
                Out::Debug(ADDITIVE),
            ),
            complexity_fullscreen: pipe(
                "light complexity (full-screen)",
                Vs::Fullscreen,
                "fs_complexity",
                FULLSCREEN.shade.clone(),
                Out::Debug(ADDITIVE),
            ),
        }
    }

    /// Records the stencil diagram or the complexity heatmap into the debug target, for all
    /// lights or the selected one; nothing for the other views.
    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let view = f.options.frame.debug_view;
        if !matches!(view, DebugView::Stencil | DebugView::Complexity) {
            return;
        }
        let mut pass = f.debug_view_pass(encoder, "debug view");
        let n = f.plan.lights.len();
        // Frames the tiled pass shades have no batches: their lights are drawn one by one below.
        if view == DebugView::Complexity && f.options.frame.selected_light.is_none() && f.plan.tiled.is_none() {
            // Additive and stencil-free: the frame's batches draw it (`batches.rs`), full-screen
            // batches full-screen, the others as plain volumes. Either way the shader keeps only
            // the points inside the light's true shape, which the volume holds; skipped lights
            // reach no visible point.
            for batch in &f.plan.batches.batches {
                if batch.method == Method::Fullscreen {
                    pass.set_pipeline(&self.complexity_fullscreen);
                    pass.draw(0..3, batch.instances());
                } else {
                    let (range, base) = f.volumes.range(batch.volume);
                    pass.set_pipeline(&self.complexity);
                    pass.draw_indexed(range, base, batch.instances());
                }
            }
            return;
        }
        let selected: Vec<usize> = match f.options.frame.selected_light {
            Some(k) if k < n => vec![k],
            Some(_) => Vec::new(),
            None => (0..n).collect(),
        };
        for i in selected {
            let li = i as u32..i as u32 + 1;
            let plan = f.plan.lights[i];
            let (range, base) = f.volumes.range(plan.volume);
            if view == DebugView::Complexity {
                if plan.crosses_far && !f.depth_clamp {
                    pass.set_pipeline(&self.complexity_fullscreen);
                    pass.draw(0..3, li);
                } else {
                    pass.set_pipeline(&self.complexity);
                    pass.draw_indexed(range, base, li);
                }
                continue;
            }
            pass.set_stencil_reference(0);
            for pipe in &self.classify {
                pass.set_pipeline(pipe);
                pass.draw_indexed(range.clone(), base, li.clone());
            }
        }
    }
}

impl Pass for DebugPass {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        let view = f.options.frame.debug_view;
        let n = f.plan.lights.len();
        match view {
            DebugView::Complexity if f.options.frame.selected_light.is_none() && f.plan.tiled.is_none() => {
                for batch in &f.plan.batches.batches {
                    out.add(if batch.method == Method::Fullscreen {
                        &self.complexity_fullscreen
                    } else {
                        &self.complexity
                    });
                }
            }
            DebugView::Complexity => {
                let lights = match f.options.frame.selected_light {
                    Some(k) => f.plan.lights.get(k..k + 1).unwrap_or_default(),
                    None => &f.plan.lights[..],
                };
                for plan in lights {
                    let full = plan.crosses_far && !f.depth_clamp;
                    out.add(if full { &self.complexity_fullscreen } else { &self.complexity });
                }
            }
            DebugView::Stencil if f.options.frame.selected_light.is_none_or(|k| k < n) && n > 0 => {
                out.add_all(&self.classify);
            }
            _ => {}
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.record(encoder, f);
        Ok(PassReport::default())
    }
}
