//! The light pre-pass's final pass (seeds 003/004, pass 3): the opaque and alpha-masked
//! geometry again, depth tested against pass 1's depth and not writing it, each fragment
//! combining its material's textures with the light buffer at its pixel, plus ambient + sun
//! and emission (`paths/prepass.wgsl`), into the HDR scene colour. Passes 1 and 2 are the
//! G-buffer and light passes built for `gbuffer::prepass_layout` (`PipelineKey::prepass`).
//! Timed as `gpu_ms.prepass_final` (`SPAN`).

use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::pipeline::topology_pipeline_index;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{scene_pipeline, ScenePipe, Shared, HDR_FORMAT};
use crate::renderer::stats::Span;

/// Pass 3's timing (`gpu_ms.prepass_final`).
pub const SPAN: Span = Span("prepass final");
use crate::renderer::targets::attachment;
use crate::scene::Topology;
use wgpu::CompareFunction as Cmp;

pub struct PrepassFinalPass {
    /// By `gbuffer::topology_pipeline_index`, as the G-buffer pass's.
    pipelines: [crate::renderer::kit::RenderPipe; 6],
    /// Multisampled (`--msaa 4`): the depth-only draws that prime pass 3's samples.
    prime: Option<[crate::renderer::kit::RenderPipe; 6]>,
    key: crate::renderer::kit::PipelineKey,
}

impl PrepassFinalPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        // Frame, material, and the compose group whose `light_diffuse` is the light buffer.
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("pre-pass final"),
            bind_group_layouts: &[Some(&shared.frame_bgl), Some(&shared.material_bgl), Some(&shared.compose_bgl)],
            immediate_size: 0,
        });
        let targets = [Some(wgpu::ColorTargetState::from(HDR_FORMAT))];
        // Pass 1's depth (single-sample) or the primed samples (`--msaa 4`), drawn by the same
        // vertex shader (`@invariant` position): only the visible surface passes (less-equal,
        // not written), so each sample is shaded once whatever the draw order.
        let samples = shared.key.samples;
        let pipe = |label: &str, fs: &str, double_sided: bool, topology: Topology| {
            let depth = (false, Cmp::LessEqual, Default::default());
            let p = ScenePipe {
                label,
                layout: &layout,
                vs: "vs_geometry",
                fs: Some(fs),
                topology,
                double_sided,
                depth,
                samples,
            };
            scene_pipeline(device, &shared.module, &shared.key, p, &targets)
        };
        // The prime: depth only (less, written), masked surfaces discarding.
        let prime = |label: &str, fs: Option<&str>, double_sided: bool, topology: Topology| {
            let depth = (true, Cmp::Less, Default::default());
            let p = ScenePipe { label, layout: &layout, vs: "vs_geometry", fs, topology, double_sided, depth, samples };
            scene_pipeline(device, &shared.module, &shared.key, p, &[])
        };
        let t = Topology::Triangles;
        let pipelines = [
            pipe("pre-pass final", "fs_prepass", false, t),
            pipe("pre-pass final (two-sided)", "fs_prepass", true, t),
            pipe("pre-pass final (masked)", "fs_prepass_masked", false, t),
            pipe("pre-pass final (masked, two-sided)", "fs_prepass_masked", true, t),
            pipe("pre-pass final (lines)", "fs_prepass_masked", true, Topology::Lines),
            pipe("pre-pass final (points)", "fs_prepass_masked", true, Topology::Points),
        ];
        debug_assert_eq!(topology_pipeline_index(Topology::Points, false, false), 5);
        let masked = Some("fs_prepass_prime_masked");
        let prime = (samples > 1).then(|| {
            [
                prime("pre-pass prime", None, false, t),
                prime("pre-pass prime (two-sided)", None, true, t),
                prime("pre-pass prime (masked)", masked, false, t),
                prime("pre-pass prime (masked, two-sided)", masked, true, t),
                prime("pre-pass prime (lines)", masked, true, Topology::Lines),
                prime("pre-pass prime (points)", masked, true, Topology::Points),
            ]
        });
        Self { pipelines, prime, key: shared.key.clone() }
    }

    /// Clears the HDR scene colour to the background and draws the G-buffer list again over
    /// it. Returns the draws issued: pass 3's and, multisampled, the prime's.
    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> (u64, u64) {
        let [r, g, b, a] = f.background.map(f64::from);
        let background = wgpu::Color { r, g, b, a };
        let Some((hdr_view, _)) = &f.targets.hdr else { return (0, 0) };
        // The stencil aspect of the multisampled depth: cleared, never read.
        let stencil_ops = f
            .targets
            .msaa
            .as_ref()
            .filter(|_| f.targets.depth_format.has_stencil_aspect())
            .map(|_| wgpu::Operations { load: wgpu::LoadOp::Clear(0), store: wgpu::StoreOp::Discard });
        // Multisampled: the samples' depth primed with pass 1's draws (the forward pass after
        // this one then tests its objects against the same depth as single-sampled), colour
        // cleared and resolved into the HDR colour (the forward pass draws over the samples
        // and resolves again).
        let mut primed = 0;
        let (color, depth, first) = match (&f.targets.msaa, &self.prime) {
            (Some(ms), Some(prime)) => {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("pre-pass prime"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &ms.depth,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(f.far_depth() as f32),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops,
                    }),
                    timestamp_writes: f.timestamps(Some(SPAN), None),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_bind_group(0, &f.frame.group, &[]);
                pass.set_bind_group(2, &f.targets.compose_group, &[0]);
                f.scene.draw(&mut pass, &f.plan.draws.gbuffer, prime);
                primed = f.plan.draws.gbuffer.len() as u64;
                (ms.color_attachment(hdr_view, Some(background)), &ms.depth, false)
            }
            _ => (attachment(hdr_view, Some(background)), &f.targets.depth, true),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("pre-pass final"),
            color_attachments: &[color],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                stencil_ops,
            }),
            timestamp_writes: f.timestamps(first.then_some(SPAN), Some(SPAN)),
            occlusion_query_set: f.counts.then_some(&f.queries.prepass),
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.frame.group, &[]);
        // Slot 0 of the compose parameters (the shader reads only the light buffer).
        pass.set_bind_group(2, &f.targets.compose_group, &[0]);
        if f.counts {
            pass.begin_occlusion_query(1);
        }
        // Every pass-1 draw but the toon objects shaded forward after this pass.
        let lit = f.plan.draws.prepass_final();
        f.scene.draw(&mut pass, lit, &self.pipelines);
        if f.counts {
            pass.end_occlusion_query();
        }
        (lit.len() as u64, primed)
    }
}

impl Pass for PrepassFinalPass {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        if f.targets.hdr.is_none() {
            return;
        }
        if let (Some(_), Some(prime)) = (&f.targets.msaa, &self.prime) {
            out.add_all(f.plan.draws.gbuffer.iter().filter_map(|d| prime.get(d.1)));
        }
        out.add_all(f.plan.draws.prepass_final().iter().filter_map(|d| self.pipelines.get(d.1)));
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        let finals = self.record(encoder, f);
        let prepass = stats(&self.key, f.plan.draws.gbuffer.len() as u64, finals);
        Ok(PassReport { prepass: Some(prepass), ..Default::default() })
    }
}

/// What the light pre-pass cannot draw, refused before the frame with what to use instead
/// (never a silent wrong picture):
/// - an accumulation format without alpha (`rg11b10-ufloat`): no channel for the mono specular;
/// - debug views of attributes the thin buffer does not hold (albedo, emissive, material ID).
///
/// What its buffer cannot light is drawn, not refused: toon and Phong objects
/// (`Brdf::prepass_lit`) and objects on a layer the lights' culling masks tell apart from the
/// buffer's (`Scene::shared_layers`), opaque or alpha-masked, are shaded forward after pass 3
/// (`DrawLists::forward_opaque`, seed 004).
pub fn check(settings: &crate::renderer::options::FrameOptions) -> anyhow::Result<()> {
    use crate::renderer::options::{AccumFormat, DebugView};
    if settings.accumulation == AccumFormat::Rg11b10Ufloat {
        anyhow::bail!(
            "the light-prepass path keeps its mono specular in the light buffer's alpha, which rg11b10-ufloat \
             lacks; use --accumulation rgba8-unorm (seed 003), rgba8-log (seed 004), rgba16-float or rgba32-float"
        );
    }
    if matches!(settings.debug_view, DebugView::Albedo | DebugView::Emissive | DebugView::MaterialId) {
        anyhow::bail!(
            "the light-prepass path stores no {} (its buffer holds normal + exponent; the material is read in pass 3); \
             views: lit, normal, depth, specular, diffuse-light, specular-light, stencil, complexity, tile-lights",
            settings.debug_view.name()
        );
    }
    Ok(())
}

/// The light pre-pass's figures for a frame drawn with `key`: bytes per pixel of its targets
/// and the object draws of pass 1 (`base`), pass 3 (`finals`; 0 when a debug view replaced it)
/// and the multisampled prime (`primed`).
pub fn stats(key: &crate::renderer::kit::PipelineKey, base: u64, (finals, primed): (u64, u64)) -> PrepassStats {
    let bytes = |f: wgpu::TextureFormat| f.block_copy_size(None).unwrap_or(0);
    // Rendered targets only: a depth read from the depth buffer costs no bytes of its own.
    let target = |name: &str| key.layout.rendered().find(|t| t.name == name).map_or(0, |t| bytes(t.format));
    PrepassStats {
        normal_exp_bytes_per_pixel: target("normal+exp"),
        depth_copy_bytes_per_pixel: target("depth"),
        light_buffer_format: format!("{:?}", key.accum_format),
        light_buffer_bytes_per_pixel: bytes(key.accum_format),
        hdr_bytes_per_pixel: if finals > 0 { bytes(HDR_FORMAT) } else { 0 },
        samples: key.samples,
        msaa_bytes_per_pixel: if finals > 0 && key.samples > 1 {
            key.samples
                * (bytes(HDR_FORMAT)
                    + key.depth_format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)).unwrap_or(4))
        } else {
            0
        },
        base_draw_calls: base,
        final_draw_calls: finals,
        prime_draw_calls: primed,
        base_fragments: None,
        final_fragments: None,
    }
}

pub use crate::renderer::inputs::pass::PrepassStats;
