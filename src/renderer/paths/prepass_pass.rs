//! The light pre-pass's final pass (seeds 003/004, pass 3): the opaque and alpha-masked
//! geometry again, depth tested against pass 1's depth and not writing it, each fragment
//! combining its material's textures with the light buffer at its pixel, plus ambient + sun
//! and emission (`paths/prepass.wgsl`), into the HDR scene colour. Passes 1 and 2 are the
//! G-buffer and light passes built for `gbuffer::prepass_layout` (`PipelineKey::prepass`).
//! Timed as `gpu_ms.prepass_final` (`SPAN`).

use crate::renderer::frame::inputs::FrameInputs;
use crate::renderer::kit::{scene_pipeline, ScenePipe, Shared, HDR_FORMAT};
use crate::renderer::stats::Span;
use crate::renderer::surfaces::gbuffer::topology_pipeline_index;

/// Pass 3's timing (`gpu_ms.prepass_final`).
pub const SPAN: Span = Span("prepass final");
use crate::renderer::targets::attachment;
use crate::scene::Topology;
use wgpu::CompareFunction as Cmp;

pub struct PrepassFinalPass {
    /// By `gbuffer::topology_pipeline_index`, as the G-buffer pass's.
    pipelines: [wgpu::RenderPipeline; 6],
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
        // Single-sample: pass 1's depth, the same vertex shader, so only the visible surface
        // passes (less-equal, not written). Multisampled (`--msaa 4`): pass 1's depth has one
        // sample, so pass 3 resolves visibility itself in its own depth samples (less, written).
        let samples = shared.key.samples;
        let ms = samples > 1;
        let pipe = |label: &str, fs: &str, double_sided: bool, topology: Topology| {
            let compare = if ms { Cmp::Less } else { Cmp::LessEqual };
            let depth = (ms, compare, Default::default());
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
        Self { pipelines }
    }

    /// Clears the HDR scene colour to `background` and draws the G-buffer list again over it.
    /// Returns the draws issued.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>, background: wgpu::Color) -> u64 {
        let Some((hdr_view, _)) = &f.targets.hdr else { return 0 };
        // Multisampled: cleared colour and depth samples, resolved into the HDR colour (the
        // forward pass draws over the samples and resolves again).
        let (color, depth, depth_load) = match &f.targets.msaa {
            Some(ms) => {
                let far = wgpu::LoadOp::Clear(f.far_depth() as f32);
                (ms.color_attachment(hdr_view, Some(background)), &ms.depth, far)
            }
            None => (attachment(hdr_view, Some(background)), &f.targets.depth, wgpu::LoadOp::Load),
        };
        let stencil_ops = f
            .targets
            .msaa
            .as_ref()
            .filter(|_| f.targets.depth_format.has_stencil_aspect())
            .map(|_| wgpu::Operations { load: wgpu::LoadOp::Clear(0), store: wgpu::StoreOp::Discard });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("pre-pass final"),
            color_attachments: &[color],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: depth_load, store: wgpu::StoreOp::Store }),
                stencil_ops,
            }),
            timestamp_writes: f.timestamps(Some(SPAN), Some(SPAN)),
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
        lit.len() as u64
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
pub fn check(settings: &crate::renderer::Settings) -> anyhow::Result<()> {
    use crate::renderer::{AccumFormat, DebugView};
    if settings.accumulation == AccumFormat::Rg11b10Ufloat {
        anyhow::bail!(
            "the light-prepass path keeps its mono specular in the light buffer's alpha, which rg11b10-ufloat \
             lacks; use --accumulation rgba16-float (seed 003), rgba8-log (seed 004) or rgba32-float"
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
/// and the object draws of pass 1 (`base`) and pass 3 (`finals`; 0 when a debug view replaced it).
pub fn stats(key: &crate::renderer::kit::PipelineKey, base: u64, finals: u64) -> crate::renderer::stats::PrepassStats {
    let bytes = |f: wgpu::TextureFormat| f.block_copy_size(None).unwrap_or(0);
    let target = |name: &str| key.layout.targets.iter().find(|t| t.name == name).map_or(0, |t| bytes(t.format));
    crate::renderer::stats::PrepassStats {
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
        base_fragments: None,
        final_fragments: None,
    }
}
