//! Forward shading of blended surfaces (seeds 002-004: deferred shading cannot do
//! transparency): back to front (alpha blending), in scene order (seed 003's additive
//! blending, `BlendedMode`) or peeled in depth order per pixel ([`Peel`]) over the HDR scene
//! colour, depth tested against the G-buffer
//! pass's depth and not written, each fragment lit by the shorter of its object's and its
//! screen tile's light list (`plan::plan_draws`). Timed (`gpu_ms.forward`) and counted
//! (`forward.fragments`) as its own pass.

pub use super::peel::PeelTargets;
use super::peel::{PEELED_FORMAT, PEEL_DEPTH};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::pipeline::{scene_pipeline, ScenePipe};
use crate::renderer::kit::Declared;
use crate::renderer::kit::{Shared, HDR_FORMAT};
use crate::renderer::stats::Span;
use crate::renderer::surfaces::gbuffer::{surface_pipeline, SurfacePipe};
use wgpu::CompareFunction as Cmp;

/// The blended surfaces' forward pass's timing (`gpu_ms.forward`).
pub const SPAN: Span = Span("forward");
use crate::renderer::targets::attachment;

pub struct BlendedPass {
    /// One- and two-sided.
    pipelines: [crate::renderer::kit::RenderPipe; 2],
    /// The light pre-pass's opaque objects it cannot light (`DrawLists::forward_opaque`): the
    /// same shading written over pass 3's colour, one- and two-sided, then alpha-masked (which
    /// discard below the cutoff as pass 1 did); built for the light pre-pass only.
    opaque: Option<[crate::renderer::kit::RenderPipe; 4]>,
    /// Depth peeling's pipelines (`BlendedMode::Peeled`).
    peel: Option<Peel>,
}

/// Depth peeling (seed 002: "can use depth peeling"; Everitt 2001): per layer, a depth-only
/// pass finds each pixel's nearest blended fragment behind the previous layer and in front of
/// the opaque depth, and a colour pass shades the fragments at that depth and adds them under
/// the layers before (front to back, premultiplied); a last pass lays the layers over the scene
/// colour. `layers` passes composite each pixel's nearest `layers` fragments exactly in depth
/// order, interpenetrating objects included; fragments behind them are dropped, and counted
/// ([`ForwardStats::unpeeled`](crate::renderer::culling::stats::ForwardStats)) when the frame counts.
struct Peel {
    /// Depth only, then colour at equal depth; one- and two-sided each.
    depth: [crate::renderer::kit::RenderPipe; 2],
    colour: [crate::renderer::kit::RenderPipe; 2],
    /// The layers over the scene colour.
    over: crate::renderer::kit::RenderPipe,
}

impl Peel {
    fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let key = crate::renderer::kit::PipelineKey { depth_format: PEEL_DEPTH, ..shared.key.clone() };
        let pipe = |label, fs, two_sided, depth, targets: &[Option<wgpu::ColorTargetState>]| {
            let p = ScenePipe {
                label,
                layout: &shared.peel_layout,
                vs: "vs_geometry",
                fs: Some(fs),
                topology: crate::scene::Topology::Triangles,
                double_sided: two_sided,
                depth,
                samples: 1,
            };
            scene_pipeline(device, &shared.module, &key, p, targets)
        };
        // Front to back: each layer only adds where the layers before left coverage (1 - dst.a).
        let under = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let layer = [Some(wgpu::ColorTargetState {
            format: PEELED_FORMAT,
            blend: Some(wgpu::BlendState { color: under, alpha: under }),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let nearest = (true, Cmp::Less, wgpu::StencilState::default());
        let at = (false, Cmp::Equal, wgpu::StencilState::default());
        // Premultiplied layers over the scene: c + (1 - a) x scene; the scene's alpha kept.
        let over = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let scene = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(over),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        Self {
            depth: [false, true].map(|two| pipe("peel depth", "fs_peel_depth", two, nearest.clone(), &[])),
            colour: [false, true].map(|two| pipe("peel colour", "fs_peel_colour", two, at.clone(), &layer)),
            over: shared.screen_pipeline(
                device,
                "peeled layers",
                &shared.peeled_layout,
                ("vs_compose", "fs_peeled"),
                &scene,
            ),
        }
    }

    /// Peels `f`'s blended draws in `layers` layers and lays them over `hdr`; with the frame's
    /// fragment counts, occlusion query k counts layer k's shaded samples and query `layers`
    /// the samples behind the last layer.
    /// `begin`: the first pass opens the forward span (no pass before it did).
    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        hdr: &wgpu::TextureView,
        layers: u32,
        begin: bool,
    ) {
        let Some(t) = &f.targets.peel else { return };
        let near = 1.0 - f.far_depth() as f32;
        let depth_pass = |encoder: &mut wgpu::CommandEncoder, k: u32, clear: f32, query: bool, first: bool| {
            encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("peel depth"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &t.depth[k as usize % 2].0,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: f.timestamps(first.then_some(SPAN), None),
                    occlusion_query_set: query.then_some(&f.queries.forward),
                    multiview_mask: None,
                })
                .forget_lifetime()
        };
        // Layer 0's "previous layer" is the near plane: nothing is peeled yet.
        drop(depth_pass(encoder, 1, near, false, begin));
        for k in 0..=layers {
            // Pass `layers` only counts what is left behind the last layer.
            let leftover = k == layers;
            if leftover && !f.forward_counts {
                break;
            }
            {
                let mut pass = depth_pass(encoder, k, f.far_depth() as f32, leftover, false);
                pass.set_bind_group(0, &f.frame.group, &[]);
                pass.set_bind_group(2, &t.groups[k as usize % 2], &[]);
                if leftover {
                    pass.begin_occlusion_query(k);
                }
                f.scene.draw(&mut pass, &f.plan.draws.forward, &self.depth);
                if leftover {
                    pass.end_occlusion_query();
                }
            }
            if leftover {
                break;
            }
            let load = if k == 0 { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) } else { wgpu::LoadOp::Load };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("peel colour"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &t.peeled,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth[k as usize % 2].0,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: f.forward_counts.then_some(&f.queries.forward),
                multiview_mask: None,
            });
            pass.set_bind_group(0, &f.frame.group, &[]);
            pass.set_bind_group(2, &t.groups[k as usize % 2], &[]);
            if f.forward_counts {
                pass.begin_occlusion_query(k);
            }
            f.scene.draw(&mut pass, &f.plan.draws.forward, &self.colour);
            if f.forward_counts {
                pass.end_occlusion_query();
            }
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("peeled layers"),
            color_attachments: &[attachment(hdr, None)],
            depth_stencil_attachment: None,
            timestamp_writes: f.timestamps(None, Some(SPAN)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.over);
        pass.set_bind_group(0, &f.frame.group, &[]);
        pass.set_bind_group(1, &t.peeled_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

impl BlendedPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let blended = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(if shared.key.additive_blended {
                crate::renderer::kit::ADD_BLENDED
            } else {
                wgpu::BlendState::ALPHA_BLENDING
            }),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        // The light pre-pass's `--msaa 4` draws blended surfaces into its multisampled colour.
        let samples = shared.key.samples;
        let p = |label, two_sided| {
            let pipe = SurfacePipe { samples, ..SurfacePipe::triangles(label, "fs_forward", two_sided, false) };
            surface_pipeline(device, shared, pipe, &blended)
        };
        let replace =
            [Some(wgpu::ColorTargetState { format: HDR_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL })];
        let o = |label, fs, two_sided| {
            let pipe = SurfacePipe { samples, ..SurfacePipe::triangles(label, fs, two_sided, false) };
            surface_pipeline(device, shared, pipe, &replace)
        };
        Self {
            pipelines: [p("forward (blended)", false), p("forward (blended, two-sided)", true)],
            opaque: shared.key.prepass.then(|| {
                [
                    o("forward (opaque)", "fs_forward", false),
                    o("forward (opaque, two-sided)", "fs_forward", true),
                    o("forward (masked)", "fs_forward_masked", false),
                    o("forward (masked, two-sided)", "fs_forward_masked", true),
                ]
            }),
            peel: shared.key.peeled_blended.then(|| Peel::new(device, shared)),
        }
    }

    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let Some((hdr_view, _)) = &f.targets.hdr else { return };
        // Peeling is single-sampled (`Settings::validate` refuses it with MSAA): this pass then
        // draws only the light pre-pass's opaque objects (if any), and the layers follow.
        let peel = self.peel.as_ref().filter(|_| f.targets.msaa.is_none());
        let opaque = self.opaque.as_ref().filter(|_| !f.plan.draws.forward_opaque.is_empty());
        if let (Some(peel), None) = (peel, opaque) {
            peel.encode(encoder, f, hdr_view, f.options.surfaces.peel_layers, true);
            return;
        }
        // Multisampled (the light pre-pass's `--msaa 4`): over its samples, resolved again.
        let (color, depth) = match &f.targets.msaa {
            Some(ms) => (ms.color_attachment(hdr_view, None), &ms.depth),
            None => (attachment(hdr_view, None), &f.targets.depth),
        };
        // Peeled, the layers' passes count the fragments and close the span.
        let (counts, end) = (f.forward_counts && peel.is_none(), peel.is_none().then_some(SPAN));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward (blended)"),
            color_attachments: &[color],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: f.timestamps(Some(SPAN), end),
            occlusion_query_set: counts.then_some(&f.queries.forward),
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.frame.group, &[]);
        if counts {
            pass.begin_occlusion_query(0);
        }
        if let Some(opaque) = opaque {
            f.scene.draw(&mut pass, &f.plan.draws.forward_opaque, opaque);
        }
        if peel.is_none() {
            f.scene.draw(&mut pass, &f.plan.draws.forward, &self.pipelines);
        }
        if counts {
            pass.end_occlusion_query();
        }
        drop(pass);
        if let Some(peel) = peel {
            peel.encode(encoder, f, hdr_view, f.options.surfaces.peel_layers, false);
        }
    }
}

impl Peel {
    /// What [`Peel::encode`] draws with: the depth and colour layers, the lay-over.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if f.targets.peel.is_none() {
            return;
        }
        let used = |pipes: &[crate::renderer::kit::RenderPipe]| {
            f.plan.draws.forward.iter().filter_map(|d| pipes.get(d.1)).cloned().collect::<Vec<_>>()
        };
        let layers = f.options.surfaces.peel_layers;
        if layers > 0 || f.forward_counts {
            out.add_all(&used(&self.depth));
        }
        if layers > 0 {
            out.add_all(&used(&self.colour));
        }
        out.add(&self.over);
    }
}

impl Pass for BlendedPass {
    /// As [`BlendedPass::record`] draws: the light pre-pass's opaque forward objects, then the
    /// blended surfaces, directly or peeled.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if f.targets.hdr.is_none() {
            return;
        }
        let peel = self.peel.as_ref().filter(|_| f.targets.msaa.is_none());
        let opaque = self.opaque.as_ref().filter(|_| !f.plan.draws.forward_opaque.is_empty());
        if let Some(opaque) = opaque {
            out.add_all(f.plan.draws.forward_opaque.iter().filter_map(|d| opaque.get(d.1)));
        }
        match peel {
            Some(peel) => peel.declare(f, out),
            None => out.add_all(f.plan.draws.forward.iter().filter_map(|d| self.pipelines.get(d.1))),
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.record(encoder, f);
        Ok(PassReport::default())
    }
}
