//! Seed 002's distortion, first half: the distortion buffer. Every object whose material has a
//! distortion strength (`Material::distortion`, `DrawLists::distorting`), opaque or blended, is
//! drawn again after the frame's surfaces, depth tested against the opaque depth and not
//! written, into one Rgba16Float image (`PostTargets::distortion`): .rg gets the surface's
//! view-space normal's x and y (its normal map applied) times the strength, in fractions of
//! the screen height, summed over the surfaces at the pixel (additive blending: layered glass
//! bends more); .a gets 1 / view depth, the greatest (the nearest surface) kept (max
//! blending). The second half is the chain's `distortion` effect (`fs_distort`, `effects`).

pub use super::targets::DISTORTION_FORMAT as FORMAT;
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::{Declared, Shared};
use crate::renderer::stats::Span;
use crate::renderer::surfaces::gbuffer::{surface_pipeline, SurfacePipe};
use crate::renderer::targets::attachment;

/// The buffer's draws open the effect's span (`gpu_ms` "distortion" covers both halves).
const SPAN: Span = Span("distortion");

pub struct DistortionPass {
    /// One- and two-sided.
    pipelines: [crate::renderer::kit::RenderPipe; 2],
}

impl DistortionPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        // Offsets summed; the nearest surface's 1 / depth kept.
        let blend = wgpu::BlendState {
            color: crate::renderer::kit::ADDITIVE.color,
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Max,
            },
        };
        let targets =
            [Some(wgpu::ColorTargetState { format: FORMAT, blend: Some(blend), write_mask: wgpu::ColorWrites::ALL })];
        let p = |label, two_sided| {
            surface_pipeline(device, shared, SurfacePipe::triangles(label, "fs_distortion", two_sided, false), &targets)
        };
        Self { pipelines: [p("distortion", false), p("distortion (two-sided)", true)] }
    }

    /// What [`Self::encode`] draws with.
    pub fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        out.add_all(f.plan.draws.distorting.iter().filter_map(|d| self.pipelines.get(d.1)));
    }

    /// Clears the buffer and draws the distorting objects into it, against the frame's opaque
    /// depth (the single-sampled depth buffer every path writes its opaque surfaces to).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>, pt: &super::PostTargets) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("distortion"),
            color_attachments: &[attachment(&pt.distortion_view, Some(wgpu::Color::TRANSPARENT))],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &f.targets.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: f.timestamps(Some(SPAN), None),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.frame.group, &[]);
        f.scene.draw(&mut pass, &f.plan.draws.distorting, &self.pipelines);
    }
}
