//! The window's GPU objects: surface, the offscreen images egui shows (viewport, thumbnails),
//! and captures of both.

use crate::Gpu;
use anyhow::{anyhow, bail, Context, Result};
use std::path::Path;
use std::sync::Arc;
use winit::window::Window;

/// An offscreen image the renderer draws into and egui shows. The texture is
/// `Rgba8UnormSrgb` (the renderer's output format, so it writes sRGB-encoded bytes); egui reads
/// it through an `Rgba8Unorm` view, i.e. gets those encoded bytes, which is what it expects of a
/// user texture. The bytes in the window are then exactly the bytes of a headless render.
///
/// An adapter without view formats (`DownlevelFlags::VIEW_FORMATS`: wgpu's GL backend) cannot
/// view one texture in both formats: egui then reads an `Rgba8Unorm` copy, which
/// [`Image::publish`] refreshes after each draw (a copy between the two formats keeps the bytes).
pub struct Image {
    pub texture: wgpu::Texture,
    /// The `Rgba8Unorm` copy egui reads where views cannot reinterpret the format.
    shown: Option<wgpu::Texture>,
    /// For the renderer.
    pub target: wgpu::TextureView,
    /// For egui.
    pub id: egui::TextureId,
    /// The view egui reads (also the viewport blit's: `app::blit`).
    pub shown_view: wgpu::TextureView,
    pub width: u32,
    pub height: u32,
}

/// The texture the renderer draws into and, where `views`, egui's view of it; else also the
/// copy egui reads.
fn image_textures(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    views: bool,
) -> (wgpu::Texture, Option<wgpu::Texture>) {
    use wgpu::TextureUsages as U;
    let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
    let unorm = [wgpu::TextureFormat::Rgba8Unorm];
    let formats = (crate::renderer::OUTPUT_FORMAT, if views { unorm.as_slice() } else { &[] });
    let texture = crate::renderer::kit::texture_2d(device, label, formats, (width, height), 1, usage);
    let shown = (!views).then(|| {
        let usage = U::TEXTURE_BINDING | U::COPY_DST;
        crate::renderer::kit::texture(device, label, wgpu::TextureFormat::Rgba8Unorm, (width, height), usage)
    });
    (texture, shown)
}

fn egui_view(texture: &wgpu::Texture, shown: Option<&wgpu::Texture>) -> wgpu::TextureView {
    shown.unwrap_or(texture).create_view(&wgpu::TextureViewDescriptor {
        format: Some(wgpu::TextureFormat::Rgba8Unorm),
        ..Default::default()
    })
}

impl Image {
    /// `views`: the device can view a texture in another format (`DownlevelFlags::VIEW_FORMATS`).
    pub fn new(
        device: &wgpu::Device,
        egui: &mut egui_wgpu::Renderer,
        label: &str,
        (width, height): (u32, u32),
        filter: wgpu::FilterMode,
        views: bool,
    ) -> Self {
        let (texture, shown) = image_textures(device, label, width, height, views);
        let target = texture.create_view(&Default::default());
        let shown_view = egui_view(&texture, shown.as_ref());
        let id = egui.register_native_texture(device, &shown_view, filter);
        Self { texture, shown, target, id, shown_view, width, height }
    }

    /// Brings the copy egui reads up to what was drawn (where there is one).
    pub fn publish(&self, gpu: &Gpu) {
        let Some(shown) = &self.shown else { return };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_texture(
            self.texture.as_image_copy(),
            shown.as_image_copy(),
            wgpu::Extent3d { width: self.width, height: self.height, depth_or_array_layers: 1 },
        );
        gpu.queue.submit([encoder.finish()]);
    }

    /// Recreates the texture at a new size, keeping its egui id. Returns whether it changed.
    pub fn resize(
        &mut self,
        device: &wgpu::Device,
        egui: &mut egui_wgpu::Renderer,
        width: u32,
        height: u32,
        filter: wgpu::FilterMode,
    ) -> bool {
        if (width, height) == (self.width, self.height) {
            return false;
        }
        (self.texture, self.shown) = image_textures(device, "viewer image", width, height, self.shown.is_none());
        self.target = self.texture.create_view(&Default::default());
        self.shown_view = egui_view(&self.texture, self.shown.as_ref());
        egui.update_egui_texture_from_wgpu_texture(device, &self.shown_view, filter, self.id);
        self.width = width;
        self.height = height;
        true
    }

    pub fn read(&self, gpu: &Gpu) -> Result<image::RgbaImage> {
        let data = gpu.read_texture(&self.texture, wgpu::TextureAspect::All)?;
        image::RgbaImage::from_raw(self.width, self.height, data).context("image readback has the wrong size")
    }
}

/// The window surface, reconfigured on resize and recreated when lost.
pub struct Surface {
    pub window: Arc<Window>,
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    /// Configured with a non-zero size.
    pub configured: bool,
    pub can_capture: bool,
}

pub enum Acquired {
    Frame(wgpu::SurfaceTexture),
    /// Nothing to draw into this time (minimised, zero-sized, timed out, reconfigured).
    Skip,
}

impl Surface {
    pub fn new(gpu: &Gpu, window: Arc<Window>, surface: wgpu::Surface<'static>, vsync: bool) -> Result<Self> {
        let caps = surface.get_capabilities(&gpu.adapter);
        if caps.formats.is_empty() {
            bail!("the adapter cannot present to this window");
        }
        // egui wants a gamma-space (non-sRGB) target.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| matches!(f, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm))
            .unwrap_or(caps.formats[0]);
        let can_capture = caps.usages.contains(wgpu::TextureUsages::COPY_SRC);
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | if can_capture { wgpu::TextureUsages::COPY_SRC } else { wgpu::TextureUsages::empty() },
            format,
            present_mode: if vsync { wgpu::PresentMode::AutoVsync } else { wgpu::PresentMode::AutoNoVsync },
            alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
            ..surface
                .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
                .ok_or_else(|| anyhow!("the surface is not supported by the adapter"))?
        };
        let mut s = Self { window, surface, config, configured: false, can_capture };
        s.resize(gpu, size.width, size.height);
        Ok(s)
    }

    pub fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// Reconfigures for a new size; a zero size (minimised) leaves the surface unconfigured.
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.configured = false;
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&gpu.device, &self.config);
        self.configured = true;
    }

    pub fn acquire(&mut self, gpu: &Gpu) -> Result<Acquired> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            self.configured = false;
            return Ok(Acquired::Skip);
        }
        if !self.configured || (size.width, size.height) != (self.config.width, self.config.height) {
            self.resize(gpu, size.width, size.height);
        }
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => Ok(Acquired::Frame(t)),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => {
                // Draw this one, reconfigure before the next.
                self.configured = false;
                Ok(Acquired::Frame(t))
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => Ok(Acquired::Skip),
            wgpu::CurrentSurfaceTexture::Outdated => {
                log::info!("surface outdated: reconfiguring");
                self.configured = false;
                Ok(Acquired::Skip)
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                log::warn!("surface lost: recreating it");
                self.surface =
                    gpu.instance.create_surface(self.window.clone()).context("recreating the lost surface")?;
                self.configured = false;
                Ok(Acquired::Skip)
            }
            other => {
                log::warn!("could not acquire a frame ({other:?}); skipping it");
                self.configured = false;
                Ok(Acquired::Skip)
            }
        }
    }

    /// Reads a presented-to-be surface texture back as RGBA.
    pub fn capture(&self, gpu: &Gpu, frame: &wgpu::SurfaceTexture) -> Result<image::RgbaImage> {
        if !self.can_capture {
            bail!("this surface does not allow reading the window back (no COPY_SRC)");
        }
        let t = &frame.texture;
        let mut data = gpu.read_texture(t, wgpu::TextureAspect::All)?;
        match t.format() {
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb => {
                data.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
            }
            wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb => {}
            f => bail!("cannot capture a {f:?} surface"),
        }
        // The window is opaque: ignore whatever alpha the compositor left.
        data.chunks_exact_mut(4).for_each(|p| p[3] = 255);
        image::RgbaImage::from_raw(t.width(), t.height(), data).context("window readback has the wrong size")
    }
}

pub fn save_png(img: &image::RgbaImage, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    img.save(path).with_context(|| format!("writing {}", path.display()))
}
