//! Seed 000's first pass: every attribute the lights need, in one pass with multiple render
//! targets (the layout decides which targets), for the opaque and alpha-masked surfaces.

use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{self, scene_pipeline, ScenePipe, Shared};
use crate::renderer::stats::Span;

/// The G-buffer pass's timing (`gpu_ms.gbuffer`; its beginning starts `gpu_ms.total`).
pub const SPAN: Span = Span("gbuffer");
use crate::renderer::kit::gbuffer::Attr;
pub use crate::renderer::kit::pipeline::{pipeline_index, topology_pipeline_index};
use crate::renderer::targets::attachment;
use crate::scene::Topology;
use wgpu::CompareFunction as Cmp;

/// What varies between the surface pipelines (scene vertices, frame + material groups): the
/// G-buffer's and the forward pass's for blended surfaces.
pub(crate) struct SurfacePipe<'a> {
    pub label: &'a str,
    /// Fragment entry point.
    pub fs: &'a str,
    pub double_sided: bool,
    pub depth_write: bool,
    pub topology: Topology,
    /// Samples per pixel (the light pre-pass's `--msaa 4` forward pass; 1 otherwise).
    pub samples: u32,
}

impl<'a> SurfacePipe<'a> {
    /// Triangles, one- or two-sided.
    pub fn triangles(label: &'a str, fs: &'a str, double_sided: bool, depth_write: bool) -> Self {
        Self { label, fs, double_sided, depth_write, topology: Topology::Triangles, samples: 1 }
    }
}

/// The pipeline `pipe` describes, writing `targets`.
pub(crate) fn surface_pipeline(
    device: &wgpu::Device,
    shared: &Shared,
    pipe: SurfacePipe<'_>,
    targets: &[Option<wgpu::ColorTargetState>],
) -> crate::renderer::kit::RenderPipe {
    let SurfacePipe { label, fs, double_sided, depth_write, topology, samples } = pipe;
    let compare = if depth_write { Cmp::Less } else { Cmp::LessEqual };
    let p = ScenePipe {
        label,
        layout: &shared.surface_layout,
        vs: "vs_geometry",
        fs: Some(fs),
        topology,
        double_sided,
        depth: (depth_write, compare, Default::default()),
        samples,
    };
    scene_pipeline(device, &shared.module, &shared.key, p, targets)
}

pub struct GBufferPass {
    /// By [`pipeline_index`], then lines and points ([`topology_pipeline_index`]).
    pub pipelines: [crate::renderer::kit::RenderPipe; 6],
    /// The depth pre-pass (`gbuffer_depth_prepass`): depth only, written (Less); masked
    /// surfaces keep the cutoff.
    depth: [crate::renderer::kit::RenderPipe; 6],
    /// The G-buffer after the depth pre-pass: depth tested (LessEqual), not written.
    kept: [crate::renderer::kit::RenderPipe; 6],
    /// The pass also writes the accumulation targets (ambient + sun).
    ambient_in_gbuffer: bool,
}

/// The six pipelines of one G-buffer stage, by [`topology_pipeline_index`]: opaque and masked
/// triangles, one- and two-sided, then lines and points (masked shader, two-sided). `fs`: the
/// opaque and masked fragment entry points (`None`: depth only, no cutoff).
fn stage(
    device: &wgpu::Device,
    shared: &Shared,
    label: &str,
    fs: (Option<&str>, &str),
    depth_write: bool,
    targets: &[Option<wgpu::ColorTargetState>],
) -> [crate::renderer::kit::RenderPipe; 6] {
    let (opaque, masked) = fs;
    let compare = if depth_write { Cmp::Less } else { Cmp::LessEqual };
    let p = |what: &str, fs: Option<&str>, topology, double_sided| {
        let label = format!("{label}{what}");
        let pipe = ScenePipe {
            label: &label,
            layout: &shared.surface_layout,
            vs: "vs_geometry",
            fs,
            topology,
            double_sided,
            depth: (depth_write, compare, Default::default()),
            samples: 1,
        };
        scene_pipeline(device, &shared.module, &shared.key, pipe, targets)
    };
    [
        p("", opaque, Topology::Triangles, false),
        p(" (two-sided)", opaque, Topology::Triangles, true),
        p(" (masked)", Some(masked), Topology::Triangles, false),
        p(" (masked, two-sided)", Some(masked), Topology::Triangles, true),
        p(" (lines)", Some(masked), Topology::Lines, true),
        p(" (points)", Some(masked), Topology::Points, true),
    ]
}

impl GBufferPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let mut targets: Vec<Option<wgpu::ColorTargetState>> =
            shared.key.layout.rendered().map(|t| Some(t.format.into())).collect();
        if shared.key.ambient_in_gbuffer {
            // Seed 000's RT1: the light accumulation starts with ambient + sun, written here.
            // Seed 000's one RT1: the second slot is empty, as in `Targets::accumulation`.
            let accum = Some(shared.key.accum_format.into());
            targets.extend([accum.clone(), accum.filter(|_| !shared.key.one_target())]);
        }
        let shading = (Some("fs_geometry"), "fs_geometry_masked");
        // A stored position sets the G-buffer pass's depth: the depth pre-pass writes the same
        // (`GBufferLayout::wgsl`), or the pass after it would fail where the rounding lands
        // farther than the rasteriser's plane.
        let depth_fs = shared.key.layout.position_depth().map(|_| "fs_geometry_depth");
        Self {
            pipelines: stage(device, shared, "geometry", shading, true, &targets),
            depth: stage(device, shared, "geometry depth", (depth_fs, "fs_geometry_depth_masked"), true, &[]),
            kept: stage(device, shared, "geometry after depth", shading, false, &targets),
            ambient_in_gbuffer: shared.key.ambient_in_gbuffer,
        }
    }

    /// Whether the frame draws the depth pre-pass first.
    fn depth_first(f: &FrameInputs<'_>) -> bool {
        f.options.surfaces.gbuffer_depth_prepass
    }

    /// The depth pre-pass: clears depth and stencil and writes the nearest surface's depth,
    /// in the frame's draw order (front to back with `--draw-order front-to-back`, the seed's
    /// "front-to-back-sorted"). It starts the G-buffer span.
    fn record_depth(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let far_depth = f.far_depth();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("g-buffer depth pre-pass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &f.targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(far_depth as f32),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0), store: wgpu::StoreOp::Store }),
            }),
            timestamp_writes: f.timestamps(Some(SPAN), None),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.frame.group, &[]);
        f.scene.draw(&mut pass, &f.plan.draws.gbuffer, &self.depth);
    }

    /// Clears the G-buffer (the depth copy to the far plane, the rest to zero), depth and
    /// stencil, and draws the frame's G-buffer list; with `ambient_in_gbuffer`, also clears the
    /// light accumulation to no light and writes ambient + sun into it where a surface is drawn.
    /// After the depth pre-pass it keeps that pass's depth and stencil and draws only the kept
    /// surfaces (LessEqual), in reverse: of coincident surfaces the first drawn is drawn last
    /// and wins, as the pre-pass's Less kept the first.
    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let t = f.targets;
        let far_depth = f.far_depth();
        let depth_first = Self::depth_first(f);
        let mut color: Vec<Option<wgpu::RenderPassColorAttachment>> = t
            .gbuffer
            .views
            .iter()
            .zip(&t.gbuffer.layout.targets)
            .filter(|(_, desc)| !kit::gbuffer::is_depth_buffer(desc))
            .map(|(view, desc)| {
                let has_depth = desc.channels.iter().flatten().any(|s| s.attr == Attr::Depth);
                // An integer target's clear value is the integer: the far depth's bits.
                let r = match (has_depth, kit::gbuffer::is_bits(desc.format)) {
                    (true, true) => f64::from((far_depth as f32).to_bits()),
                    (true, false) => far_depth,
                    (false, _) => 0.0,
                };
                attachment(view, Some(wgpu::Color { r, g: 0.0, b: 0.0, a: 0.0 }))
            })
            .collect();
        if self.ambient_in_gbuffer {
            color.extend(t.accumulation(true));
        }
        let (depth_load, stencil_load) = match depth_first {
            true => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
            false => (wgpu::LoadOp::Clear(far_depth as f32), wgpu::LoadOp::Clear(0)),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("g-buffer"),
            color_attachments: &color,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
                depth_ops: Some(wgpu::Operations { load: depth_load, store: wgpu::StoreOp::Store }),
                stencil_ops: Some(wgpu::Operations { load: stencil_load, store: wgpu::StoreOp::Store }),
            }),
            timestamp_writes: f.timestamps((!depth_first).then_some(SPAN), Some(SPAN)),
            // The pass counts the samples that pass its depth test (query 0 of
            // `Queries::prepass`): the fragments it writes, which the draw order and the depth
            // pre-pass change.
            occlusion_query_set: f.counts.then_some(&f.queries.prepass),
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.frame.group, &[]);
        if f.counts {
            pass.begin_occlusion_query(0);
        }
        if depth_first {
            let reversed: Vec<_> = f.plan.draws.gbuffer.iter().rev().copied().collect();
            f.scene.draw(&mut pass, &reversed, &self.kept);
        } else {
            f.scene.draw(&mut pass, &f.plan.draws.gbuffer, &self.pipelines);
        }
        if f.counts {
            pass.end_occlusion_query();
        }
    }
}

impl Pass for GBufferPass {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        let stages: &[&[crate::renderer::kit::RenderPipe; 6]] =
            if Self::depth_first(f) { &[&self.depth, &self.kept] } else { &[&self.pipelines] };
        for stage in stages {
            out.add_all(f.plan.draws.gbuffer.iter().filter_map(|d| stage.get(d.1)));
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        if Self::depth_first(f) {
            self.record_depth(encoder, f);
        }
        self.record(encoder, f);
        Ok(PassReport::default())
    }
}
