//! The shadow pass. Draws every caster into each shadow tile of the atlas
//! (`shadows::plan` decides the tiles and which objects touch each), one viewport per tile,
//! before the G-buffer pass (which already adds the sun's light through the atlas). With
//! `--shadow-cube array`, cube faces go to the layers of the cube array instead.

use super::{ShadowPlan, TileDraw};
use crate::renderer::frame::inputs::FrameInputs;
use crate::renderer::kit::bindings;
use crate::renderer::kit::Shared;
use crate::renderer::stats::Span;

/// The shadow pass's timing (`gpu_ms.shadows`, before every path's first pass).
pub const SPAN: Span = Span("shadows");

pub struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    caster_bgl: wgpu::BindGroupLayout,
}

impl ShadowPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let caster_bgl = bindings::FRAME.layout_of(device, |slot| bindings::SHADOW_CASTER_SLOTS.contains(&slot));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow casters"),
            bind_group_layouts: &[Some(&caster_bgl)],
            immediate_size: 0,
        });
        let vertex_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<crate::scene::Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        })];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow casters"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &shared.module,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &vertex_buffers,
            },
            // Both faces cast: a thin wall or an open mesh stops light from either side.
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: shared.key.features.shadows.format.texture(),
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shared.module,
                entry_point: Some("fs_shadow"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self { pipeline, caster_bgl }
    }

    /// Clears the atlas to the far depth and draws each tile's casters, then (with
    /// `--shadow-cube array`) each cube face into its layer of the cube array, one render pass a
    /// layer; nothing when no tile. The pass's timestamps span all of them.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        plan: &ShadowPlan,
    ) {
        if plan.tiles.is_empty() {
            return;
        }
        let group = f.frame.caster_group(device, &self.caster_bgl);
        let atlas: Vec<&TileDraw> = plan.draws.iter().filter(|d| d.layer.is_none()).collect();
        let faces: Vec<&TileDraw> = plan.draws.iter().filter(|d| d.layer.is_some()).collect();
        // (target, its draws): the atlas when it has tiles, then each cube face.
        let mut targets: Vec<(&wgpu::TextureView, Vec<&TileDraw>)> = Vec::new();
        if !atlas.is_empty() {
            targets.push((&f.frame.shadow_view, atlas));
        }
        for d in faces {
            let Some(view) = d.layer.and_then(|l| f.frame.shadow_cube_layers.get(l as usize)) else { continue };
            targets.push((view, vec![d]));
        }
        let last = targets.len().saturating_sub(1);
        for (k, (view, draws)) in targets.into_iter().enumerate() {
            let begin = (k == 0).then_some(SPAN);
            let end = (k == last).then_some(SPAN);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadows"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: f.timestamps(begin, end),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.set_vertex_buffer(0, f.scene.vertices.slice(..));
            pass.set_index_buffer(f.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
            let objects = plan.params.sun[3].max(1);
            for d in draws {
                if d.objects.is_empty() {
                    continue;
                }
                let (x, y, s) = (d.x as f32, d.y as f32, d.size as f32);
                pass.set_viewport(x, y, s, s, 0.0, 1.0);
                pass.set_scissor_rect(d.x, d.y, d.size, d.size);
                for &o in &d.objects {
                    let Some((range, base)) = f.scene.draws.get(o as usize) else { continue };
                    let instance = d.tile * objects + o;
                    pass.draw_indexed(range.clone(), *base, instance..instance + 1);
                }
            }
        }
    }
}
