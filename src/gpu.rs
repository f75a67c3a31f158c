//! Adapter and device selection, feature negotiation and readback helpers.
//!
//! The core never opens a window: [`Gpu::headless`] picks an adapter on its own, and the viewer
//! hands in a surface through [`Gpu::for_surface`]. Optional features are requested when the
//! adapter has them and each missing one is logged once, so a run on a weaker driver says what
//! it cannot measure instead of failing.

use crate::renderer::kit::adapter::{feature_name, AdapterCaps, AdapterName, Profile};
use anyhow::{anyhow, bail, Context, Result};
use std::sync::{Arc, Mutex};

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
    (wgpu::Features::PIPELINE_CACHE, "the viewer keeps no compiled pipelines between runs"),
];

/// What every pass needs: the frame's shader module reads storage buffers in the vertex and
/// fragment stages, writes some in fragment shaders (counted tiled shading), declares the
/// shadows' cube array and has compute entry points. Without one of these nothing renders.
pub const REQUIRED_DOWNLEVEL: wgpu::DownlevelFlags = wgpu::DownlevelFlags::FRAGMENT_STORAGE
    .union(wgpu::DownlevelFlags::VERTEX_STORAGE)
    .union(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE)
    .union(wgpu::DownlevelFlags::CUBE_ARRAY_TEXTURES)
    .union(wgpu::DownlevelFlags::COMPUTE_SHADERS);

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

/// Which adapter to open (`--backend`, `--adapter`) and what to mask its table to.
#[derive(Clone, Debug, Default)]
pub struct AdapterChoice {
    /// Only this backend (else `WGPU_BACKEND`, else Vulkan, Metal and DX12).
    pub backend: Option<Backend>,
    /// The adapter's index in `lampshade adapters`' list, or a part of its name.
    pub adapter: Option<String>,
    /// Mask the adapter's capability table to another adapter class's.
    pub restrict: Option<Profile>,
}

/// A backend as `--backend` names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Backend {
    Vulkan,
    Gl,
    Metal,
    Dx12,
}

impl Backend {
    fn backends(self) -> wgpu::Backends {
        match self {
            Backend::Vulkan => wgpu::Backends::VULKAN,
            Backend::Gl => wgpu::Backends::GL,
            Backend::Metal => wgpu::Backends::METAL,
            Backend::Dx12 => wgpu::Backends::DX12,
        }
    }
}

impl AdapterChoice {
    /// The instance's options: `--backend`, else `WGPU_BACKEND`, else `default` (the primary
    /// backends headless: on a headless machine GL's EGL probe only logs errors before Vulkan is
    /// chosen anyway), and wgpu's other environment variables.
    fn descriptor(&self, desc: wgpu::InstanceDescriptor, default: wgpu::Backends) -> wgpu::InstanceDescriptor {
        let mut desc = wgpu::InstanceDescriptor { backends: default, ..desc }.with_env();
        if let Some(b) = self.backend {
            desc.backends = b.backends();
        }
        desc
    }
}

pub use crate::renderer::kit::describe;

/// The device's errors that no error scope caught (validation, out of memory): those outside a
/// frame (a frame catches its own, `Renderer::render`), kept for the commands and the viewer to
/// turn into error messages. Without a handler wgpu panics at the first one.
#[derive(Clone, Default)]
pub struct DeviceErrors(Arc<Mutex<Vec<String>>>);

impl DeviceErrors {
    fn push(&self, e: wgpu::Error) {
        let text = describe(&e);
        log::error!("wgpu: {text}");
        self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner).push(text);
    }

    /// The errors since the last call, as one error.
    pub fn check(&self) -> Result<()> {
        let errors = std::mem::take(&mut *self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner));
        match errors.first() {
            None => Ok(()),
            Some(first) if errors.len() == 1 => Err(anyhow!("wgpu error: {first}")),
            Some(first) => Err(anyhow!("wgpu error: {first} (and {} more)", errors.len() - 1)),
        }
    }
}

/// A device and what it can do.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// The optional features the device was made with (`caps.features`).
    pub features: wgpu::Features,
    pub info: wgpu::AdapterInfo,
    /// What the adapter can do, as every choice asks it.
    pub caps: Arc<AdapterCaps>,
    /// Errors wgpu reported outside an error scope.
    pub errors: DeviceErrors,
    /// Pass sets of dropped renderers, for the next renderer on this device.
    pub passes: Arc<crate::renderer::kit::pool::PassPool>,
    /// Material textures, shared by the renderers on this device that draw the same images.
    pub uploads: Arc<crate::renderer::kit::uploads::Uploads>,
    /// The pipeline that reads back depth WebGPU does not copy ([`Gpu::read_depth`]), made by
    /// its first use.
    depth_reader: std::sync::OnceLock<(wgpu::BindGroupLayout, wgpu::RenderPipeline)>,
}

/// What a device on `adapter` is made with: the optional features it has (less those
/// `restrict` masks), the limits, and each missing feature's name with what is lost without it.
/// Storage buffers a shader stage the device asks for where the adapter has them: the most any
/// pass binds, RIS's passes over kept reservoirs (the tiled pass's 8 and their 7,
/// `stochastic::reuse::STORAGE_BUFFERS`); an adapter with fewer refuses those passes alone.
pub const STORAGE_BUFFERS_PER_STAGE: u32 = 15;

fn request(adapter: &wgpu::Adapter, restrict: Option<Profile>) -> (wgpu::Features, wgpu::Limits, Vec<String>) {
    let masked = restrict.map_or(wgpu::Features::empty(), |p| p.missing_features());
    let available = adapter.features() - masked;
    let mut features = wgpu::Features::empty();
    let mut lacks = Vec::new();
    for (feature, consequence) in OPTIONAL_FEATURES {
        if available.contains(*feature) {
            features |= *feature;
        } else {
            lacks.push(format!("{} ({consequence})", feature_name(*feature)));
        }
    }
    let adapter_limits = adapter.limits();
    let limits = wgpu::Limits {
        // Seed 000's layout alone is 4 x Rgba16Float = 32 bytes; a depth copy needs more.
        max_color_attachment_bytes_per_sample: adapter_limits.max_color_attachment_bytes_per_sample,
        max_color_attachments: adapter_limits.max_color_attachments,
        max_storage_buffer_binding_size: adapter_limits.max_storage_buffer_binding_size,
        max_buffer_size: adapter_limits.max_buffer_size,
        max_storage_buffers_per_shader_stage: adapter_limits
            .max_storage_buffers_per_shader_stage
            .min(STORAGE_BUFFERS_PER_STAGE)
            .max(wgpu::Limits::default().max_storage_buffers_per_shader_stage),
        ..wgpu::Limits::default()
    };
    (features, limits, lacks)
}

/// The capability table a device on `adapter` would have.
pub fn caps_of(adapter: &wgpu::Adapter, restrict: Option<Profile>) -> AdapterCaps {
    let (features, limits, _) = request(adapter, restrict);
    AdapterCaps::read(adapter, features, limits, restrict)
}

/// The adapters `choice`'s backends offer, in the order `--adapter INDEX` counts them.
/// Every backend unless `--backend` or `WGPU_BACKEND` names one.
pub fn adapters(choice: &AdapterChoice) -> Vec<wgpu::Adapter> {
    let desc = choice.descriptor(wgpu::InstanceDescriptor::new_without_display_handle(), wgpu::Backends::all());
    let instance = wgpu::Instance::new(desc);
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
}

/// The headless instance: the primary backends, or every backend when `--adapter` names one (its
/// index counts `lampshade adapters`' list, which spans every backend).
fn instance(choice: &AdapterChoice) -> wgpu::Instance {
    let default = if choice.adapter.is_some() { wgpu::Backends::all() } else { wgpu::Backends::PRIMARY };
    let desc = choice.descriptor(wgpu::InstanceDescriptor::new_without_display_handle(), default);
    wgpu::Instance::new(desc)
}

impl Gpu {
    /// A device with no window, for the CLI, the tests and the bench: the default adapter.
    pub fn headless() -> Result<Self> {
        Self::open(&AdapterChoice::default())
    }

    /// A device with no window on the adapter `choice` names.
    pub fn open(choice: &AdapterChoice) -> Result<Self> {
        let instance = instance(choice);
        Self::from_instance(instance, None, choice)
    }

    /// A device able to present to `surface`.
    pub fn for_surface(instance: wgpu::Instance, surface: &wgpu::Surface<'_>, choice: &AdapterChoice) -> Result<Self> {
        Self::from_instance(instance, Some(surface), choice)
    }

    /// The instance the viewer makes its surface with.
    pub fn instance_for_window(
        choice: &AdapterChoice,
        display: Box<dyn wgpu::wgt::WgpuHasDisplayHandle>,
    ) -> wgpu::Instance {
        let desc = choice.descriptor(wgpu::InstanceDescriptor::new_with_display_handle(display), wgpu::Backends::all());
        wgpu::Instance::new(desc)
    }

    fn pick(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
        choice: &AdapterChoice,
    ) -> Result<wgpu::Adapter> {
        let fits = |a: &wgpu::Adapter| surface.is_none_or(|s| a.is_surface_supported(s));
        let Some(wanted) = choice.adapter.as_deref() else {
            return pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: surface,
                apply_limit_buckets: false,
            }))
            .map_err(|e| {
                let backend = choice.backend.map(|b| format!(" on the {b:?} backend")).unwrap_or_default();
                anyhow!(
                    "no graphics adapter found{backend} ({e}). On a headless Linux machine install Mesa's \
                     software Vulkan driver: `apt-get install mesa-vulkan-drivers libvulkan1`; \
                     `lampshade adapters` lists what is found"
                )
            });
        };
        let all = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let names: Vec<String> =
            all.iter().enumerate().map(|(i, a)| format!("{i}: {}", AdapterName::of(&a.get_info()))).collect();
        let found = match wanted.parse::<usize>() {
            Ok(i) => all.into_iter().nth(i),
            Err(_) => {
                let w = wanted.to_lowercase();
                all.into_iter().find(|a| a.get_info().name.to_lowercase().contains(&w))
            }
        };
        let adapter = found.ok_or_else(|| {
            anyhow!(
                "no adapter '{wanted}'; the adapters found are: {}",
                if names.is_empty() { "none".into() } else { names.join(", ") }
            )
        })?;
        if !fits(&adapter) {
            bail!("adapter {} cannot present to this window", AdapterName::of(&adapter.get_info()));
        }
        Ok(adapter)
    }

    fn from_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
        choice: &AdapterChoice,
    ) -> Result<Self> {
        let adapter = Self::pick(&instance, surface, choice)?;
        let info = adapter.get_info();
        log::info!(
            "adapter: {} ({:?}, {:?}; driver {} {})",
            info.name,
            info.backend,
            info.device_type,
            info.driver,
            info.driver_info
        );
        let missing = REQUIRED_DOWNLEVEL - adapter.get_downlevel_capabilities().flags;
        if !missing.is_empty() {
            bail!(
                "adapter {} lacks {missing:?} (wgpu downlevel flags), which the one shader module every Lampshade \
                 pass is compiled from needs; `lampshade adapters` lists the others",
                AdapterName::of(&info)
            );
        }
        let (features, limits, lacks) = request(&adapter, choice.restrict);
        if !lacks.is_empty() {
            log::warn!("adapter {} lacks: {}", AdapterName::of(&info), lacks.join("; "));
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("lampshade"),
            required_features: features,
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .with_context(|| format!("adapter {} refused to create a device", AdapterName::of(&info)))?;
        let errors = DeviceErrors::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e| sink.push(e)));
        let caps = AdapterCaps::read(&adapter, features, limits, choice.restrict);
        if info.backend == wgpu::Backend::Gl {
            log::warn!(
                "adapter {}: wgpu's GL backend; docs/adapters.md lists what it renders differently",
                caps.adapter
            );
        }
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            features,
            info,
            passes: Arc::new(crate::renderer::kit::pool::PassPool::new(caps.quirks.pipeline_bytes())),
            caps: Arc::new(caps),
            errors,
            uploads: Default::default(),
            depth_reader: Default::default(),
        })
    }

    /// The same device, queue and pass pool, for another thread: what one thread compiles
    /// there the other draws with (the viewer's background compiles). wgpu's handles are
    /// shared, not copied.
    pub fn share(&self) -> Self {
        Self {
            instance: self.instance.clone(),
            adapter: self.adapter.clone(),
            device: self.device.clone(),
            queue: self.queue.clone(),
            features: self.features,
            info: self.info.clone(),
            caps: self.caps.clone(),
            errors: self.errors.clone(),
            passes: self.passes.clone(),
            uploads: self.uploads.clone(),
            depth_reader: Default::default(),
        }
    }

    /// Whether debug groups may be pushed on a command encoder (outside a pass): not on
    /// lavapipe ([`Quirks::no_encoder_debug_groups`]; its render-pass labels work, and every
    /// pass is labelled).
    pub fn encoder_debug_groups(&self) -> bool {
        !self.caps.quirks.no_encoder_debug_groups
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

    /// Copies a 2-D texture (one aspect, mip 0) to the CPU, tightly packed rows. A depth aspect
    /// WebGPU does not copy (Depth24Plus's) comes back as f32 texels ([`Gpu::read_depth`]), as
    /// Depth32Float's does.
    pub fn read_texture(&self, texture: &wgpu::Texture, aspect: wgpu::TextureAspect) -> Result<Vec<u8>> {
        if aspect == wgpu::TextureAspect::DepthOnly && texture.format().block_copy_size(Some(aspect)).is_none() {
            return self.read_depth(texture);
        }
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

    /// A depth texture's depth as f32 texels, tightly packed rows, for a format whose depth
    /// WebGPU does not copy (Depth24Plus): a full-screen draw loads each texel (`textureLoad` of
    /// a `texture_depth_2d`, the stored value exactly as the depth test and the lights read it)
    /// into an R32Float target, which is then copied.
    pub fn read_depth(&self, texture: &wgpu::Texture) -> Result<Vec<u8>> {
        const SHADER: &str = "@group(0) @binding(0) var depth: texture_depth_2d;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(p * 2.0 - 1.0, 0.0, 1.0);
}
@fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureLoad(depth, vec2<i32>(p.xy), 0), 0.0, 0.0, 1.0);
}";
        if !texture.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) {
            return Err(anyhow!(
                "the {:?} depth texture cannot be read: it is not bound for reading",
                texture.format()
            ));
        }
        let device = &self.device;
        let size = texture.size();
        let (layout, pipeline) = self.depth_reader.get_or_init(|| {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("depth read"),
                source: wgpu::ShaderSource::Wgsl(SHADER.into()),
            });
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("depth read"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                }],
            });
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("depth read"),
                layout: Some(&device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("depth read"),
                    bind_group_layouts: &[Some(&layout)],
                    immediate_size: 0,
                })),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::TextureFormat::R32Float.into())],
                }),
                multiview_mask: None,
                cache: None,
            });
            (layout, pipeline)
        });
        let view = texture
            .create_view(&wgpu::TextureViewDescriptor { aspect: wgpu::TextureAspect::DepthOnly, ..Default::default() });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("depth read"),
            layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) }],
        });
        let target = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth read"),
            size: wgpu::Extent3d { width: size.width, height: size.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let target_view = target.create_view(&Default::default());
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("depth read"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target_view,
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
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        self.queue.submit([encoder.finish()]);
        self.read_texture(&target, wgpu::TextureAspect::All)
    }
}
