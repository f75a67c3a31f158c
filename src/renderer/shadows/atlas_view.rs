//! The viewer's shadow-atlas panel: the last frame's shadow atlas (any depth format) as an
//! image of the output format, its linear depth stretched over the range actually present
//! (`atlas_view.wgsl` beside it). Not part of the frame: `Last::draw_shadow_atlas` runs it
//! on demand, after a frame, into a texture the caller keeps (the viewer registers it with
//! egui once and has it redrawn in place).

use super::scratch::AtlasScratch;
use crate::renderer::kit::bindings;
use crate::renderer::kit::Shared;
use crate::renderer::records::FrameBuffers;

/// Invocations per workgroup side of `cs_atlas_range`, and texels per invocation side
/// (`ATLAS_BLOCK` in the shader).
const WORKGROUP: u32 = 8;
const BLOCK: u32 = 4;

pub struct AtlasViewPass {
    range: crate::renderer::kit::ComputePipe,
    view: crate::renderer::kit::RenderPipe,
    atlas_bgl: wgpu::BindGroupLayout,
    range_bgl: wgpu::BindGroupLayout,
}

impl AtlasScratch {
    fn buffers(&self, device: &wgpu::Device) -> &(wgpu::Buffer, wgpu::Buffer) {
        self.buffers.get_or_init(|| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("atlas range"),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let staging = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("atlas range readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            (buffer, staging)
        })
    }

    /// The depth range the last [`AtlasViewPass::encode`] found (after its submission): least
    /// and greatest stored depth below the clear value, `None` when every texel is clear.
    pub fn read(&self, gpu: &crate::Gpu) -> anyhow::Result<Option<(f32, f32)>> {
        let Some((_, staging)) = self.buffers.get() else { return Ok(None) };
        let bytes = gpu.read_buffer(staging)?;
        let w: &[u32] = bytemuck::cast_slice(&bytes);
        Ok(range_of(w.first().copied().unwrap_or(u32::MAX), w.get(1).copied().unwrap_or(0)))
    }
}

impl AtlasViewPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let atlas_bgl = bindings::FRAME.layout_of(device, |slot| slot == ATLAS_SLOT);
        let range_bgl = bindings::ATLAS_VIEW.layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("atlas view"),
            bind_group_layouts: &[Some(&atlas_bgl), Some(&range_bgl)],
            immediate_size: 0,
        });
        let range = crate::renderer::kit::compute_pipe(
            device,
            "atlas depth range",
            Some(&layout),
            &shared.module,
            "cs_atlas_range",
        );
        let view = shared.fullscreen_pipeline(device, "atlas view", &layout, "fs_atlas_view", shared.key.output_format);
        Self { range, view, atlas_bgl, range_bgl }
    }

    /// Records the range search and the image into `target` (`side` pixels square, the
    /// output format), and the copy of the range into the staging buffer ([`Self::read`]).
    /// `empty`: the last frame drew no tile, so the atlas holds nothing of it (a stand-in or an
    /// older frame's depths): the image is cleared to the "nothing cast" colour and the range
    /// left empty.
    /// What [`Self::encode`] draws and dispatches with (`empty`: it only clears).
    pub fn declared(&self, empty: bool) -> crate::renderer::kit::Declared {
        let mut out = crate::renderer::kit::Declared::default();
        if !empty {
            out.add(&self.range);
            out.add(&self.view);
        }
        out
    }

    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (frame, scratch): (&FrameBuffers, &AtlasScratch),
        target: &wgpu::TextureView,
        side: u32,
        empty: bool,
    ) {
        let (buffer, staging) = scratch.buffers(device);
        queue.write_buffer(buffer, 0, bytemuck::cast_slice(&[u32::MAX, 0, side.max(1), 0]));
        if empty {
            let [r, g, b] = EMPTY;
            // A pass that only clears.
            drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("atlas view (empty)"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            }));
            encoder.copy_buffer_to_buffer(buffer, 0, staging, 0, 16);
            return;
        }
        let atlas = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("atlas view: atlas"),
            layout: &self.atlas_bgl,
            entries: &[wgpu::BindGroupEntry {
                binding: ATLAS_SLOT,
                resource: wgpu::BindingResource::TextureView(&frame.shadow_view),
            }],
        });
        let range = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("atlas view: range"),
            layout: &self.range_bgl,
            entries: &bindings::ATLAS_VIEW.entries(vec![buffer.as_entire_binding()]),
        });
        let texels = frame.shadow_side();
        let groups = texels.div_ceil(WORKGROUP * BLOCK);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("atlas depth range"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.range);
            pass.set_bind_group(0, &atlas, &[]);
            pass.set_bind_group(1, &range, &[]);
            pass.dispatch_workgroups(groups, groups, 1);
        }
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("atlas view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.view);
            pass.set_bind_group(0, &atlas, &[]);
            pass.set_bind_group(1, &range, &[]);
            pass.draw(0..3, 0..1);
        }
        encoder.copy_buffer_to_buffer(buffer, 0, staging, 0, 16);
    }
}

/// `FRAME`'s slot of the shadow atlas.
const ATLAS_SLOT: u32 = 50;
/// `ATLAS_EMPTY` of the shader: texels nothing was cast into (linear).
const EMPTY: [f64; 3] = [0.02, 0.03, 0.10];

/// The range from the shader's two words (f32 bits of non-negative depths); `None` when no
/// texel below the clear value was found (the words keep their initial values).
pub fn range_of(lo: u32, hi: u32) -> Option<(f32, f32)> {
    (hi >= lo).then(|| (f32::from_bits(lo), f32::from_bits(hi)))
}

#[cfg(test)]
mod tests {
    #[test]
    fn depth_bits_order_as_the_depths_and_an_empty_atlas_has_no_range() {
        // The shader's atomics compare bit patterns; for non-negative floats they order as the
        // floats (the range search relies on it).
        let depths = [0.0f32, 1e-30, 0.001, 0.25, 0.5, 0.999_999];
        for w in depths.windows(2) {
            assert!(w[0].to_bits() < w[1].to_bits(), "{} vs {}", w[0], w[1]);
        }
        assert_eq!(super::range_of(u32::MAX, 0), None);
        assert_eq!(super::range_of(0.25f32.to_bits(), 0.5f32.to_bits()), Some((0.25, 0.5)));
    }
}
