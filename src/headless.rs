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
        use wgpu::TextureUsages as U;
        let usage = U::RENDER_ATTACHMENT | U::COPY_SRC | U::TEXTURE_BINDING;
        let texture =
            crate::renderer::kit::texture(&gpu.device, "offscreen output", OUTPUT_FORMAT, (width, height), usage);
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
