//! Rendering without a window: into an offscreen texture, read back as an image.

use crate::gpu::Gpu;
use crate::renderer::{FrameStats, Renderer, Settings, OUTPUT_FORMAT};
use crate::scene::Scene;
use anyhow::{Context, Result};

pub struct Offscreen {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub width: u32,
    pub height: u32,
}

impl Offscreen {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Self {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen output"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: OUTPUT_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        Self { texture, view, width, height }
    }

    pub fn read(&self, gpu: &Gpu) -> Result<image::RgbaImage> {
        let data = gpu.read_texture(&self.texture, wgpu::TextureAspect::All)?;
        image::RgbaImage::from_raw(self.width, self.height, data).context("readback has the wrong size")
    }
}

/// Renders one frame of `scene` at `width`x`height` and returns the image and its statistics.
pub fn render_image(
    gpu: &Gpu,
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &Settings,
    width: u32,
    height: u32,
) -> Result<(image::RgbaImage, FrameStats)> {
    let out = Offscreen::new(gpu, width, height);
    let stats = renderer.render(scene, settings, &out.view, width, height)?;
    Ok((out.read(gpu)?, stats))
}
