//! Measurement only, after the frame (outside its timestamps): the ideal count (the G-buffer
//! points inside each light's true shape) and the rasterised coverage of each light's volume.
//!
//! The ideal is counted over the light's bounding volume (its back faces, depth test off, every
//! fragment outside the true shape discarded), not over the whole screen: the volume
//! circumscribes the light (`volumes.rs` tests), so every point inside the light lies on a ray
//! that leaves the volume through a back face behind it, and the count is the same, at the cost
//! of the volume's footprint instead of the screen's (16,384 lights at 1280x720 were 15 G
//! full-screen fragments, minutes of lavapipe time). Lights drawn full-screen are counted
//! full-screen, so `fullscreen` mode counts the ideal without any volume, and
//! `every_culling_mode_gives_the_fullscreen_picture` holds the two counts equal, light by light.

use crate::renderer::culling::binning::{binned_bytes, pass_ranges};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{DrawState, Faces, LightPipe, Out, Shared, Vs, NO_STENCIL};
use crate::renderer::plan::Method;
use crate::renderer::stats::LIGHTS_PER_QUERY_SET;
use crate::renderer::volumes::VolumeKind;
use wgpu::CompareFunction as Cmp;

pub struct MeasurePass {
    ideal: crate::renderer::kit::RenderPipe,
    ideal_volume: crate::renderer::kit::RenderPipe,
    coverage: crate::renderer::kit::RenderPipe,
    coverage_fullscreen: crate::renderer::kit::RenderPipe,
}

impl MeasurePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe =
            |label, vs, fs, state| shared.light_pipeline(device, LightPipe { label, vs, fs, state, out: Out::NoColor });
        let fullscreen = DrawState { faces: Faces::Both, depth: Cmp::Always, stencil: NO_STENCIL };
        Self {
            ideal: pipe("ideal count", Vs::Fullscreen, "fs_ideal", fullscreen.clone()),
            ideal_volume: pipe(
                "ideal count (volume)",
                Vs::Volume,
                "fs_ideal",
                DrawState { faces: Faces::Back, depth: Cmp::Always, stencil: NO_STENCIL },
            ),
            // What the volume methods rasterise: the back faces, untested.
            coverage: pipe(
                "coverage",
                Vs::Volume,
                "fs_no_color",
                DrawState { faces: Faces::Back, depth: Cmp::Always, stencil: NO_STENCIL },
            ),
            coverage_fullscreen: pipe("coverage (full-screen)", Vs::Fullscreen, "fs_no_color", fullscreen),
        }
    }

    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        if !f.ideal {
            return;
        }
        let t = f.targets;
        let n = f.plan.lights.len();
        let chunk = LIGHTS_PER_QUERY_SET;
        // Render passes small enough for llvmpipe (`culling::binning::LLVMPIPE_SCENE_BUDGET`): every
        // light's full-screen draw and its query are binned into every tile.
        let size = (t.width, t.height);
        let ideal_ranges = pass_ranges(n, |_| full_screen(size));
        for lights in ideal_ranges {
            let b = lights.start / chunk;
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("ideal count"),
                color_attachments: &t.accumulation(false),
                depth_stencil_attachment: Some(t.depth_attachment(false)),
                timestamp_writes: None,
                occlusion_query_set: f.queries.ideal.get(b),
                multiview_mask: None,
            });
            f.bind_light_inputs(&mut pass);
            for i in lights.clone() {
                let li = i as u32..i as u32 + 1;
                let plan = f.plan.lights[i];
                pass.begin_occlusion_query((i - b * chunk) as u32);
                // A tiled light crossing the far plane without depth clamp would lose its volume's
                // far side: counted full-screen like a light drawn so.
                let fullscreen =
                    plan.method == Method::Fullscreen || plan.method.listed() && plan.crosses_far && !f.depth_clamp;
                match plan.method {
                    _ if fullscreen => {
                        pass.set_pipeline(&self.ideal);
                        pass.draw(0..3, li);
                    }
                    // Outside the frustum: no visible point can be inside it (count zero).
                    Method::Skipped => {}
                    _ => {
                        let (range, base) = f.volumes.range(plan.volume);
                        pass.set_pipeline(&self.ideal_volume);
                        pass.draw_indexed(range, base, li);
                    }
                }
                pass.end_occlusion_query();
            }
        }
        // Rasterised coverage of each volume's back faces (what the volume methods rasterise),
        // from pipeline statistics, in passes of their own: lavapipe returns wrong occlusion
        // counts when pipeline-statistics queries share their pass.
        let triangles = (f.volumes.sphere.indices.len() as u64 / 3, f.volumes.cone.indices.len() as u64 / 3);
        let coverage_ranges = pass_ranges(n, |i| {
            let p = &f.plan.lights[i];
            let t = if p.volume == VolumeKind::Sphere { triangles.0 } else { triangles.1 };
            binned_bytes(p, size, 1, t)
        });
        for lights in coverage_ranges {
            let b = lights.start / chunk;
            let Some(set) = f.queries.coverage.get(b) else { continue };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("coverage count"),
                color_attachments: &t.accumulation(false),
                depth_stencil_attachment: Some(t.depth_attachment(false)),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            f.bind_light_inputs(&mut pass);
            for i in lights {
                let li = i as u32..i as u32 + 1;
                let plan = f.plan.lights[i];
                pass.begin_pipeline_statistics_query(set, (i - b * chunk) as u32);
                if plan.method == Method::Fullscreen {
                    pass.set_pipeline(&self.coverage_fullscreen);
                    pass.draw(0..3, li);
                } else if plan.method != Method::Skipped {
                    let (range, base) = f.volumes.range(plan.volume);
                    pass.set_pipeline(&self.coverage);
                    pass.draw_indexed(range, base, li);
                }
                pass.end_pipeline_statistics_query();
            }
        }
    }
}

impl Pass for MeasurePass {
    /// Per light, as [`MeasurePass::record`] draws it: the ideal count full-screen or as its
    /// volume, and its coverage where the frame has the block's statistics queries.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if !f.ideal {
            return;
        }
        for (i, plan) in f.plan.lights.iter().enumerate() {
            let fullscreen =
                plan.method == Method::Fullscreen || plan.method.listed() && plan.crosses_far && !f.depth_clamp;
            match plan.method {
                _ if fullscreen => out.add(&self.ideal),
                Method::Skipped => {}
                _ => out.add(&self.ideal_volume),
            }
            if f.queries.coverage.get(i / LIGHTS_PER_QUERY_SET).is_some() {
                match plan.method {
                    Method::Fullscreen => out.add(&self.coverage_fullscreen),
                    Method::Skipped => {}
                    _ => out.add(&self.coverage),
                }
            }
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.record(encoder, f);
        Ok(PassReport::default())
    }
}

/// What a full-screen draw bins (one triangle in every tile, with its query).
fn full_screen(size: (u32, u32)) -> u64 {
    let plan = crate::renderer::plan::LightPlan {
        method: Method::Fullscreen,
        volume: VolumeKind::Sphere,
        crosses_near: false,
        crosses_far: false,
        screen_share: 1.0,
        screen_rect: None,
        depths: (f32::INFINITY, f32::NEG_INFINITY),
    };
    binned_bytes(&plan, size, 1, 1)
}
