//! The G-buffer's textures for one size, and their binding for reading.

use super::{is_bits, is_depth_buffer, GBufferLayout};

/// The G-buffer's textures for one size.
pub struct GBufferTargets {
    pub layout: GBufferLayout,
    pub textures: Vec<wgpu::Texture>,
    pub views: Vec<wgpu::TextureView>,
}

impl GBufferTargets {
    /// The targets at `width`x`height`; a target that is the depth buffer
    /// ([`is_depth_buffer`]) is `depth`, the frame's depth-stencil texture, seen through its
    /// depth aspect.
    pub fn new(device: &wgpu::Device, layout: &GBufferLayout, width: u32, height: u32, depth: &wgpu::Texture) -> Self {
        let textures: Vec<wgpu::Texture> = layout
            .targets
            .iter()
            .map(|t| {
                use wgpu::TextureUsages as U;
                if is_depth_buffer(t) {
                    return depth.clone();
                }
                let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
                crate::renderer::kit::texture(device, t.name, t.format, (width, height), usage)
            })
            .collect();
        let views = textures
            .iter()
            .zip(&layout.targets)
            .map(|(tex, t)| {
                let aspect = if is_depth_buffer(t) { wgpu::TextureAspect::DepthOnly } else { wgpu::TextureAspect::All };
                tex.create_view(&wgpu::TextureViewDescriptor { aspect, ..Default::default() })
            })
            .collect();
        Self { layout: layout.clone(), textures, views }
    }

    /// The aspect target `i` is read back through (the depth buffer's depth, else the whole).
    pub fn aspect(&self, i: usize) -> wgpu::TextureAspect {
        match self.layout.targets.get(i) {
            Some(t) if is_depth_buffer(t) => wgpu::TextureAspect::DepthOnly,
            _ => wgpu::TextureAspect::All,
        }
    }

    /// Bind group layout entries for reading every target with `textureLoad`.
    pub fn bind_group_layout(device: &wgpu::Device, layout: &GBufferLayout) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = (layout.targets.iter().enumerate())
            .map(|(i, t)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                // Compute: the tiled pass reads each tile's depth bounds.
                visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: if is_bits(t.format) {
                        wgpu::TextureSampleType::Uint
                    } else {
                        wgpu::TextureSampleType::Float { filterable: false }
                    },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            })
            .collect();
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer read"),
            entries: &entries,
        })
    }

    pub fn bind_group(&self, device: &wgpu::Device, bgl: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = self
            .views
            .iter()
            .enumerate()
            .map(|(i, v)| wgpu::BindGroupEntry { binding: i as u32, resource: wgpu::BindingResource::TextureView(v) })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer read"),
            layout: bgl,
            entries: &entries,
        })
    }
}
