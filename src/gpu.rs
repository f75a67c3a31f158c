//! Adapter and device selection, feature negotiation and readback helpers.
//!
//! The core never opens a window: [`Gpu::headless`] picks an adapter on its own, and the viewer
//! hands in a surface through [`Gpu::for_surface`]. Optional features are requested when the
//! adapter has them and each missing one is logged once, so a run on a weaker driver says what
//! it cannot measure instead of failing.

use anyhow::{anyhow, Context, Result};

/// Features Lampshade uses when present, with what is lost without each.
pub const OPTIONAL_FEATURES: &[(wgpu::Features, &str)] = &[
    (wgpu::Features::TIMESTAMP_QUERY, "per-pass GPU times are reported as null"),
    (wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES, "no timestamps inside passes"),
    (wgpu::Features::DEPTH_CLIP_CONTROL, "no depth clamp: light volumes crossing the far plane are drawn full-screen"),
    (wgpu::Features::PIPELINE_STATISTICS_QUERY, "rasterised light-volume coverage is not reported"),
    (wgpu::Features::DEPTH32FLOAT_STENCIL8, "depth falls back to Depth24PlusStencil8"),
    (wgpu::Features::FLOAT32_BLENDABLE, "Rgba32Float accumulation is unavailable"),
    (wgpu::Features::RG11B10UFLOAT_RENDERABLE, "Rg11b10Ufloat accumulation is unavailable"),
    (wgpu::Features::TEXTURE_FORMAT_16BIT_NORM, "the oct16 G-buffer layout (Rg16Unorm normals) is unavailable"),
    // Rendering to Rg16Unorm is an adapter-specific capability beyond the feature above.
    (
        wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES,
        "the oct16 G-buffer layout (rendering to Rg16Unorm) is unavailable",
    ),
];

/// Keeps Mesa's Vulkan device-select layer from connecting to a Wayland display when there is
/// none: without `XDG_RUNTIME_DIR` that layer prints "error: XDG_RUNTIME_DIR is invalid or not
/// set" twice per run, although a headless run needs no display. The layer only orders the
/// adapters by the display's GPU, so it is switched off (`NODEVICE_SELECT=1`) when there is no
/// runtime directory and the user has not asked it for a device (`MESA_VK_DEVICE_SELECT`).
///
/// Call it at the start of `main`, before any thread exists: it sets an environment variable.
pub fn quiet_headless_device_select() {
    let has = |k: &str| std::env::var_os(k).is_some_and(|v| !v.is_empty());
    if !has("XDG_RUNTIME_DIR") && !has("MESA_VK_DEVICE_SELECT") && !has("NODEVICE_SELECT") {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// See [`Gpu::encoder_debug_groups`].
pub fn encoder_debug_groups(info: &wgpu::AdapterInfo) -> bool {
    !(info.backend == wgpu::Backend::Vulkan && info.driver == "llvmpipe")
}

/// A device and what it can do.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub features: wgpu::Features,
    pub info: wgpu::AdapterInfo,
    /// Pass sets of dropped renderers, for the next renderer on this device.
    pub passes: std::sync::Arc<crate::renderer::PassPool>,
}

impl Gpu {
    /// A device with no window, for the CLI, the tests and the bench.
    ///
    /// Only the primary backends (Vulkan, Metal, DX12) unless `WGPU_BACKEND` says otherwise:
    /// OpenGL needs a display connection and, on a headless machine, only logs EGL errors
    /// before Vulkan is chosen anyway.
    pub fn headless() -> Result<Self> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::PRIMARY;
        let instance = wgpu::Instance::new(desc.with_env());
        Self::from_instance(instance, None)
    }

    /// A device able to present to `surface`.
    pub fn for_surface(instance: wgpu::Instance, surface: &wgpu::Surface<'_>) -> Result<Self> {
        Self::from_instance(instance, Some(surface))
    }

    fn from_instance(instance: wgpu::Instance, surface: Option<&wgpu::Surface<'_>>) -> Result<Self> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        }))
        .map_err(|e| {
            anyhow!(
                "no graphics adapter found ({e}). On a headless Linux machine install Mesa's software \
                 Vulkan driver: `apt-get install mesa-vulkan-drivers libvulkan1`"
            )
        })?;
        let info = adapter.get_info();
        log::info!(
            "adapter: {} ({:?}, {:?}; driver {} {})",
            info.name,
            info.backend,
            info.device_type,
            info.driver,
            info.driver_info
        );
        let available = adapter.features();
        let mut features = wgpu::Features::empty();
        for (feature, consequence) in OPTIONAL_FEATURES {
            if available.contains(*feature) {
                features |= *feature;
            } else {
                log::warn!("adapter lacks {feature:?}: {consequence}");
            }
        }
        let adapter_limits = adapter.limits();
        let limits = wgpu::Limits {
            // Seed 000's layout alone is 4 x Rgba16Float = 32 bytes; a depth copy needs more.
            max_color_attachment_bytes_per_sample: adapter_limits.max_color_attachment_bytes_per_sample,
            max_color_attachments: adapter_limits.max_color_attachments,
            max_storage_buffer_binding_size: adapter_limits.max_storage_buffer_binding_size,
            max_buffer_size: adapter_limits.max_buffer_size,
            ..wgpu::Limits::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("lampshade"),
            required_features: features,
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .context("the adapter refused to create a device")?;
        Ok(Self { instance, adapter, device, queue, features, info, passes: Default::default() })
    }

    /// Whether debug groups may be pushed on a command encoder (outside a pass): Mesa's
    /// lavapipe crashes in `vkCmdBeginDebugUtilsLabelEXT` there (seen with Mesa 22.3.6; its
    /// render-pass labels work, and every pass is labelled), so on lavapipe the frame's steps
    /// are not grouped.
    pub fn encoder_debug_groups(&self) -> bool {
        encoder_debug_groups(&self.info)
    }

    pub fn has(&self, feature: wgpu::Features) -> bool {
        self.features.contains(feature)
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait(&self) -> Result<()> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow!("device poll failed: {e}"))?;
        Ok(())
    }

    /// Reads a whole buffer back to the CPU.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
        crate::renderer::kit::read_back(&self.device, buffer, buffer.size())
    }

    /// Copies a 2-D texture (one aspect, mip 0) to the CPU, tightly packed rows.
    pub fn read_texture(&self, texture: &wgpu::Texture, aspect: wgpu::TextureAspect) -> Result<Vec<u8>> {
        let size = texture.size();
        let bpp = texture
            .format()
            .block_copy_size(Some(aspect))
            .ok_or_else(|| anyhow!("format {:?} cannot be copied", texture.format()))?;
        let unpadded = size.width * bpp;
        let padded = unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: (padded * size.height) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(size.height),
                },
            },
            wgpu::Extent3d { width: size.width, height: size.height, depth_or_array_layers: 1 },
        );
        self.queue.submit([encoder.finish()]);
        let data = self.read_buffer(&buffer)?;
        let mut out = Vec::with_capacity((unpadded * size.height) as usize);
        for row in data.chunks(padded as usize).take(size.height as usize) {
            out.extend_from_slice(&row[..unpadded as usize]);
        }
        Ok(out)
    }
}
