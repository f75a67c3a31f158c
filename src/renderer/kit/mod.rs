//! How a pass is built, importing no technique: the formats every pass shares, the blend and
//! stencil states the seeds' tables are written in, the per-light pipeline description, the
//! pipeline layouts and the shader module a configuration is compiled to ([`pipeline`]), the
//! bindings and G-buffer layout that write their own WGSL ([`bindings`], [`gbuffer`]), the WGSL
//! every entry point shares (`common.wgsl`), and [`Lazy`], a pass built the first time a frame
//! uses it.
//!
//! A pass is a struct in its technique's folder that builds its own pipelines in
//! `new(&Shared)` and records itself in `encode(&self, encoder, &FrameInputs, …)`.
//!
//! Depth and stencil states are written as the seeds give them (standard depth: near = 0);
//! [`z`] flips the compare functions when reversed Z is on.

pub mod adapter;
pub mod bindings;
pub mod cache;
pub mod description;
pub mod features;
pub mod gbuffer;
pub mod pipeline;
pub mod pool;
pub mod uploads;

pub use pipeline::{ambient_fits, scene_pipeline, screen_pipeline, PipelineKey, ScenePipe, Shared};
use std::sync::{Arc, OnceLock};
use wgpu::CompareFunction as Cmp;

/// Format of the debug target (stencil diagram, light complexity).
pub const DEBUG_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the HDR scene colour that scenes with blended surfaces compose through.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

pub fn texture(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    size: (u32, u32),
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    texture_2d(device, label, (format, &[]), size, 1, usage)
}

/// A 2D texture of `samples` samples, one mip level, of `format` and the other formats its
/// views may take.
pub fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    (format, view_formats): (wgpu::TextureFormat, &[wgpu::TextureFormat]),
    (width, height): (u32, u32),
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats,
    })
}

/// A vertex buffer holding `vertices` and an index buffer holding `indices` ("`label`
/// vertices", "`label` indices").
pub fn mesh_buffers<V: bytemuck::Pod>(
    device: &wgpu::Device,
    label: &str,
    vertices: &[V],
    indices: &[u32],
) -> (wgpu::Buffer, wgpu::Buffer) {
    use wgpu::util::DeviceExt;
    let buffer = |what: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label} {what}")),
            contents,
            usage,
        })
    };
    (
        buffer("vertices", bytemuck::cast_slice(vertices), wgpu::BufferUsages::VERTEX),
        buffer("indices", bytemuck::cast_slice(indices), wgpu::BufferUsages::INDEX),
    )
}

/// The first `bytes` of `buffer` (a `MAP_READ` buffer the submitted work wrote), read back as
/// `T`s once the device is idle.
pub fn read_back<T: bytemuck::Pod>(device: &wgpu::Device, buffer: &wgpu::Buffer, bytes: u64) -> anyhow::Result<Vec<T>> {
    let slice = buffer.slice(0..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow::anyhow!("device poll failed: {e}"))?;
    rx.recv()?.map_err(|e| anyhow::anyhow!("buffer read-back failed: {e}"))?;
    let values = {
        let data = slice.get_mapped_range().map_err(|e| anyhow::anyhow!("{e}"))?;
        bytemuck::pod_collect_to_vec::<u8, T>(&data)
    };
    buffer.unmap();
    Ok(values)
}

/// Whether an accumulation target of `format` holds seed 004's logarithmic encoding
/// (`AccumFormat::Rgba8Log` is the only one stored as Rgba8Unorm; the linear 8-bit
/// `AccumFormat::Rgba8Unorm` is stored as Bgra8Unorm).
pub fn log_accum(format: wgpu::TextureFormat) -> bool {
    format == wgpu::TextureFormat::Rgba8Unorm
}

/// Maps a compare function written for standard depth to reversed Z when `reversed`.
pub fn z(reversed: bool, c: Cmp) -> Cmp {
    if !reversed {
        return c;
    }
    match c {
        Cmp::Less => Cmp::Greater,
        Cmp::LessEqual => Cmp::GreaterEqual,
        Cmp::Greater => Cmp::Less,
        Cmp::GreaterEqual => Cmp::LessEqual,
        other => other,
    }
}

/// Which faces of a volume a draw rasterises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Faces {
    Front,
    Back,
    Both,
}

impl Faces {
    pub fn cull_mode(self) -> Option<wgpu::Face> {
        match self {
            Faces::Front => Some(wgpu::Face::Back),
            Faces::Back => Some(wgpu::Face::Front),
            Faces::Both => None,
        }
    }
}

/// The depth bias of a volume draw, in units of the depth buffer's resolution at the
/// fragment (Vulkan's `r`: 2^-24 for 24-bit depth, 2^(e-23) for 32-bit float depth whose
/// exponent is e, so 2^-24 over [0.5, 1)).
///
/// A culling draw compares the volume's depth, rounded, with the G-buffer's stored depth, and
/// the lighting and brute force both shade the point that stored depth gives. So the only error
/// to cover is the volume fragment's own: the view-space vertex (`centre + p R`, covered by the
/// mesh's `VOLUME_MARGIN`), then in depth units the projection's row (two products and a sum,
/// at most 2 units), the perspective divide (1), and the rasteriser's plane interpolation at the
/// pixel centre (three terms, 3), plus the conversion to the format for the compare (0.5
/// for 24-bit): 6.5, rounded up to [`VOLUME_BIAS_UNITS`] = 8. On standard depth with a small near
/// plane one unit spans a long way at distance (a near plane of 0.05: 3.5 units of view
/// distance at 1,700), so a point inside a light's sphere near its rim as seen from the eye can
/// lie behind the back face by less than that error and fail the test while brute force lights
/// it. The count holds where the depth is at least 0.5 (and everywhere under reversed Z, whose
/// rounding is relative): on standard float depth nearer than twice the near plane the unit
/// shrinks while the six units of rounding stay near 6 x 2^-24 absolute, a view distance of at
/// most 6 x 2^-24 (2n)^2 / n = 1.4e-6 n there, which the mesh's `VOLUME_MARGIN` (0.2% of the
/// radius) covers for every light whose radius exceeds a thousandth of the near plane.
pub const VOLUME_BIAS_UNITS: i32 = 8;

/// The slope-scaled part of the volume bias, times the face's largest screen depth slope
/// (depth per pixel): snapping vertices to the rasteriser's sub-pixel grid moves the face's
/// plane by at most half a grid step in x and in y, 2^-bits pixel in all, and Vulkan guarantees
/// at least 4 sub-pixel bits (`subPixelPrecisionBits`).
pub const VOLUME_BIAS_SLOPE: f32 = 1.0 / 16.0;

/// The bias that makes a volume draw's depth test admit, never lose, the points its volume
/// holds: front faces drawn nearer, back faces farther (so LessEqual on front faces and
/// GreaterEqual on back faces pass more; Less on back faces fails more, which is what marks in
/// seed 002's REPLACE). Farther is larger depth on standard depth, smaller under reversed Z.
/// Culling may only skip work: a point the bias admits that lies outside the light's shape gets
/// the shader's zero (distance over radius at least 1). A draw of both faces gets none here (one
/// bias per pipeline): `MARK_BOTH_FACES` biases each face in the fragment instead.
pub fn volume_depth_bias(state: &DrawState, reversed: bool) -> wgpu::DepthBiasState {
    let farther = if reversed { -1 } else { 1 };
    let sign = match state.faces {
        _ if state.depth == Cmp::Always => 0,
        Faces::Front => -farther,
        Faces::Back => farther,
        Faces::Both => 0,
    };
    wgpu::DepthBiasState {
        constant: sign * VOLUME_BIAS_UNITS,
        slope_scale: sign as f32 * VOLUME_BIAS_SLOPE,
        clamp: 0.0,
    }
}

/// Whether a volume draw biases its depth in the fragment stage: a draw of both faces with a
/// depth test (seed 001's INVERT mark), drawn with `fs_mark_both_faces` (`fs_waste_mark_both_faces`
/// in the waste view), each face biased as `volume_depth_bias` biases single-faced draws.
pub fn biased_in_fragment(state: &DrawState) -> bool {
    state.faces == Faces::Both && state.depth != Cmp::Always
}

/// One draw's raster state as the seeds' tables give it: faces drawn, depth test (standard
/// depth; never written), stencil.
#[derive(Clone, Debug)]
pub struct DrawState {
    pub faces: Faces,
    pub depth: Cmp,
    pub stencil: wgpu::StencilState,
}

/// Which colour targets a per-light pipeline writes.
#[derive(Clone, Copy)]
pub enum Out {
    /// Diffuse + specular accumulation, additive (multiplicative for the log encoding).
    Accumulate,
    /// Same targets, colour writes off (stencil marking, counting).
    NoColor,
    /// Same targets, replaced (the ambient + sun pass starts the accumulation).
    Replace,
    /// The debug target with a blend.
    Debug(wgpu::BlendState),
}

/// The vertex stage of a per-light pipeline.
#[derive(Clone, Copy)]
pub enum Vs {
    /// A full-screen triangle per light instance.
    Fullscreen,
    /// A full-screen triangle, no light.
    FullscreenPlain,
    /// The light's bounding volume.
    Volume,
}

pub struct LightPipe {
    pub label: &'static str,
    pub vs: Vs,
    pub fs: &'static str,
    pub state: DrawState,
    pub out: Out,
}

/// A stencil face state: compare, then the ops on stencil fail, depth fail and pass.
pub const fn face(
    compare: Cmp,
    fail_op: wgpu::StencilOperation,
    depth_fail_op: wgpu::StencilOperation,
    pass_op: wgpu::StencilOperation,
) -> wgpu::StencilFaceState {
    wgpu::StencilFaceState { compare, fail_op, depth_fail_op, pass_op }
}

/// A stencil state with full read and write masks.
pub const fn stencil(front: wgpu::StencilFaceState, back: wgpu::StencilFaceState) -> wgpu::StencilState {
    wgpu::StencilState { front, back, read_mask: 0xff, write_mask: 0xff }
}

/// Stencil off.
pub const NO_STENCIL: wgpu::StencilState = stencil(KEEP, KEEP);
/// A face that ignores the stencil.
pub const KEEP: wgpu::StencilFaceState = wgpu::StencilFaceState::IGNORE;

/// Seed 003's additive blending for blended surfaces (`BlendedMode::Additive`): the colour
/// times its alpha added to what is there, `src x alpha + dst`; the target's alpha kept. A
/// sum, so the draw order does not matter (up to the HDR target's rounding).
pub const ADD_BLENDED: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::SrcAlpha,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

pub const ADDITIVE: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// Seed 004's logarithmic accumulation: dst = src x dst, so the product of every light's
/// exp2(-light) is exp2(-sum).
pub const MULTIPLY: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Dst,
        dst_factor: wgpu::BlendFactor::Zero,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::DstAlpha,
        dst_factor: wgpu::BlendFactor::Zero,
        operation: wgpu::BlendOperation::Add,
    },
};

pub const MAX: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Max,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Max,
    },
};

/// A pass set up the first time a frame uses it (its layouts and bind group layouts; its
/// pipelines compile later still, on their first draw: [`OnFirstUse`]). The renderer keeps the
/// passes of recent configurations: a frame that never draws the light pre-pass, the
/// tiled/clustered shading, blended surfaces or the post chain should not pay for them.
pub struct Lazy<T> {
    cell: OnceLock<T>,
    device: wgpu::Device,
    shared: Arc<Shared>,
    build: fn(&wgpu::Device, &Shared) -> T,
}

impl<T> Lazy<T> {
    pub fn new(device: &wgpu::Device, shared: &Arc<Shared>, build: fn(&wgpu::Device, &Shared) -> T) -> Self {
        Self { cell: OnceLock::new(), device: device.clone(), shared: shared.clone(), build }
    }

    /// The pass if a frame has built it.
    pub fn get(&self) -> Option<&T> {
        self.cell.get()
    }

    /// Sets the pass up now if it is not, turning a validation error (a bad layout) into an
    /// error instead of a panic. Its pipelines compile on their first draw, inside the drawing
    /// call's error scopes (`renderer::scoped`).
    pub fn prepare(&self) -> anyhow::Result<()> {
        if self.cell.get().is_some() {
            return Ok(());
        }
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pass = (self.build)(&self.device, &self.shared);
        if let Some(e) = pollster::block_on(scope.pop()) {
            anyhow::bail!("building the pipelines failed: {e}");
        }
        let _ = self.cell.set(pass);
        Ok(())
    }
}

impl<T> std::ops::Deref for Lazy<T> {
    type Target = T;

    /// The pass, built here if no frame has built it ([`Passes::prepare`] builds what a frame
    /// needs first, inside an error scope).
    fn deref(&self) -> &T {
        self.cell.get_or_init(|| (self.build)(&self.device, &self.shared))
    }
}

/// One pipeline, compiled the first time a frame draws with it: a pass holds every variant it
/// may draw (six per surface pass for the topologies and sidedness, the views, the
/// multisampled copies), a frame draws a few. On lavapipe a compile is tens of milliseconds of
/// CPU (`spirv_to_nir` and its passes run even when Mesa's shader cache holds the machine code)
/// and 2 to 9 MiB of heap. Built when their pass was, the culling oracle's pipelines came to 74
/// a case, 85% of its CPU time; built on first draw, 23 (stream 4, cases 8900-8949: 3,691
/// pipelines and 113 s before, 1,163 and 35 s after). It dereferences to the pipeline, so a draw
/// passes `&pipe` where it passed `&pipeline`. Every call that draws runs inside error scopes
/// (`renderer::scoped`: the frame, the thumbnails, the explanation, brute force, the atlas
/// view), so an error in the compile becomes that call's error, never a panic.
/// Clones share the one pipeline.
pub struct OnFirstUse<T>(Arc<FirstUse<T>>);

struct FirstUse<T> {
    cell: OnceLock<T>,
    build: Box<dyn Fn() -> T + Send + Sync>,
    /// What the pipeline is, where its maker said (`render_pipe`, `compute_pipe`).
    description: Option<description::PipelineDescription>,
    /// How long its compile took (wgpu's and the driver's pipeline creation), once compiled.
    compiled_in: OnceLock<std::time::Duration>,
}

impl<T> Clone for OnFirstUse<T> {
    fn clone(&self) -> Self {
        Self(self.0.clone())
    }
}

/// A render pipeline built on first use.
pub type RenderPipe = OnFirstUse<wgpu::RenderPipeline>;
/// A compute pipeline built on first use.
pub type ComputePipe = OnFirstUse<wgpu::ComputePipeline>;

impl<T> OnFirstUse<T> {
    pub fn new(build: impl Fn() -> T + Send + Sync + 'static) -> Self {
        Self(Arc::new(FirstUse {
            cell: OnceLock::new(),
            build: Box::new(build),
            description: None,
            compiled_in: OnceLock::new(),
        }))
    }

    /// [`OnFirstUse::new`] with what the pipeline is.
    pub fn described(
        description: description::PipelineDescription,
        build: impl Fn() -> T + Send + Sync + 'static,
    ) -> Self {
        Self(Arc::new(FirstUse {
            cell: OnceLock::new(),
            build: Box::new(build),
            description: Some(description),
            compiled_in: OnceLock::new(),
        }))
    }
}

impl<T> std::ops::Deref for OnFirstUse<T> {
    type Target = T;

    fn deref(&self) -> &T {
        self.0.cell.get_or_init(|| self.0.compile())
    }
}

impl<T> FirstUse<T> {
    fn compile(&self) -> T {
        COMPILED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        COMPILED_HERE.with(|c| c.set(c.get() + 1));
        let start = std::time::Instant::now();
        let pipeline = (self.build)();
        let _ = self.compiled_in.set(start.elapsed());
        pipeline
    }
}

static COMPILED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

thread_local! {
    /// Pipelines compiled on this thread: a frame's recording tells from it whether a pipeline
    /// it drew with had not been declared (and so was compiled inside the recording).
    static COMPILED_HERE: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Pipelines compiled on the calling thread so far.
pub fn pipelines_compiled_here() -> u64 {
    COMPILED_HERE.with(|c| c.get())
}

/// A pipeline a pass declares, built ahead of its first draw on whichever thread calls
/// [`Compile::build`].
pub trait Compile: Send + Sync {
    /// Compiles it unless it is compiled; whether this call compiled it.
    fn build(&self) -> bool;
    /// Whether it is compiled.
    fn is_built(&self) -> bool;
    /// What it is, where its maker said.
    fn description(&self) -> Option<&description::PipelineDescription>;
    /// How long its compile took, once compiled.
    fn compile_time(&self) -> Option<std::time::Duration>;
}

impl<T: Send + Sync> Compile for FirstUse<T> {
    fn build(&self) -> bool {
        let mut now = false;
        self.cell.get_or_init(|| {
            now = true;
            self.compile()
        });
        now
    }

    fn is_built(&self) -> bool {
        self.cell.get().is_some()
    }

    fn description(&self) -> Option<&description::PipelineDescription> {
        self.description.as_ref()
    }

    fn compile_time(&self) -> Option<std::time::Duration> {
        self.compiled_in.get().copied()
    }
}

/// The pipelines a frame declared (`inputs::pass::Pass::declare`), each once.
#[derive(Clone, Default)]
pub struct Declared(Vec<Arc<dyn Compile>>);

impl Declared {
    /// Adds `pipe` unless it is declared already.
    pub fn add<T: Send + Sync + 'static>(&mut self, pipe: &OnFirstUse<T>) {
        let p: Arc<dyn Compile> = pipe.0.clone();
        if !self.0.iter().any(|q| std::ptr::addr_eq(Arc::as_ptr(q), Arc::as_ptr(&p))) {
            self.0.push(p);
        }
    }

    /// Adds each of `pipes`.
    pub fn add_all<'a, T: Send + Sync + 'static>(&mut self, pipes: impl IntoIterator<Item = &'a OnFirstUse<T>>) {
        for p in pipes {
            self.add(p);
        }
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Those not compiled yet.
    pub fn missing(&self) -> usize {
        self.0.iter().filter(|p| !p.is_built()).count()
    }

    /// What each declared pipeline is (those whose maker said), in the order declared.
    pub fn descriptions(&self) -> Vec<description::PipelineDescription> {
        self.0.iter().filter_map(|p| p.description().cloned()).collect()
    }

    /// Each declared pipeline's label (its description's; `?` where its maker gave none) and
    /// compile time (`None`: not compiled yet), in the order declared.
    pub fn timings(&self) -> Vec<(String, Option<std::time::Duration>)> {
        let label = |p: &Arc<dyn Compile>| p.description().map_or_else(|| "?".to_string(), |d| d.label().to_string());
        self.0.iter().map(|p| (label(p), p.compile_time())).collect()
    }

    /// Compiles those not compiled yet, on this thread; how many it compiled. A compile's error
    /// reaches the caller's error scopes (`scoped`).
    pub fn build(&self) -> usize {
        self.build_each().into_iter().filter(|b| *b).count()
    }

    /// [`Declared::build`], saying for each pipeline whether this call compiled it.
    pub fn build_each(&self) -> Vec<bool> {
        self.0.iter().map(|p| p.build()).collect()
    }
}

/// Pipelines this process has compiled ([`OnFirstUse`]): a soak tells the memory they take,
/// one-off, from a leak (`memory::without_compiles`).
pub fn pipelines_compiled() -> u64 {
    COMPILED.load(std::sync::atomic::Ordering::Relaxed)
}

/// A render pipeline from an owned descriptor, built on first use.
pub fn render_pipe(device: &wgpu::Device, d: RenderPipeDesc) -> RenderPipe {
    let device = device.clone();
    let description = description::PipelineDescription::Render(description::RenderDescription {
        label: d.label.clone(),
        vertex: d.vs.clone(),
        fragment: d.fragment.as_ref().map(|f| f.0.clone()),
        targets: d.fragment.as_ref().map(|f| f.1.clone()).unwrap_or_default(),
        primitive: d.primitive,
        depth_stencil: d.depth_stencil.clone(),
        samples: d.multisample.count,
    });
    OnFirstUse::described(description, move || d.create(&device))
}

/// A compute pipeline (`entry` of `module` with `layout`), built on first use.
pub fn compute_pipe(
    device: &wgpu::Device,
    label: &str,
    layout: Option<&wgpu::PipelineLayout>,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> ComputePipe {
    let (device, label, layout, module, entry) =
        (device.clone(), label.to_owned(), layout.cloned(), module.clone(), entry.to_owned());
    let description = description::PipelineDescription::Compute { label: label.clone(), entry: entry.clone() };
    OnFirstUse::described(description, move || {
        let cache = cache::current();
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(&label),
            layout: layout.as_ref(),
            module: &module,
            entry_point: Some(&entry),
            compilation_options: Default::default(),
            cache: cache.as_ref(),
        })
    })
}

/// A vertex buffer layout that owns its attributes.
#[derive(Clone)]
pub struct VertexBuffer {
    pub stride: u64,
    pub step_mode: wgpu::VertexStepMode,
    pub attributes: Vec<wgpu::VertexAttribute>,
}

/// `wgpu::RenderPipelineDescriptor` with its borrows owned, so the compile can wait for the
/// first draw ([`render_pipe`]).
#[derive(Clone)]
pub struct RenderPipeDesc {
    pub label: String,
    pub layout: wgpu::PipelineLayout,
    pub module: wgpu::ShaderModule,
    pub vs: String,
    pub buffers: Vec<VertexBuffer>,
    pub primitive: wgpu::PrimitiveState,
    pub depth_stencil: Option<wgpu::DepthStencilState>,
    pub multisample: wgpu::MultisampleState,
    /// The fragment stage and its targets; `None`: depth only.
    pub fragment: Option<(String, Vec<Option<wgpu::ColorTargetState>>)>,
}

impl RenderPipeDesc {
    fn create(&self, device: &wgpu::Device) -> wgpu::RenderPipeline {
        let buffers: Vec<Option<wgpu::VertexBufferLayout>> = self
            .buffers
            .iter()
            .map(|b| {
                Some(wgpu::VertexBufferLayout {
                    array_stride: b.stride,
                    step_mode: b.step_mode,
                    attributes: &b.attributes,
                })
            })
            .collect();
        let cache = cache::current();
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&self.label),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(&self.vs),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: self.primitive,
            depth_stencil: self.depth_stencil.clone(),
            multisample: self.multisample,
            fragment: self.fragment.as_ref().map(|(fs, targets)| wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets,
            }),
            multiview_mask: None,
            cache: cache.as_ref(),
        })
    }
}

/// Runs `steps`, which encode and submit GPU work, inside error scopes: validation, out of
/// memory, and internal (a driver that fails to compile a pipeline reports it so). A pipeline
/// compiles on its first draw ([`OnFirstUse`]), inside whichever call draws with it first,
/// so every call that draws runs in these scopes; an error caught turns into the call's error,
/// the innermost scope's (the compile's own message) first. A pipeline that failed to compile
/// stays invalid in its pass set, and each later draw with it fails here too.
pub fn scoped<R>(device: &wgpu::Device, steps: impl FnOnce() -> anyhow::Result<R>) -> anyhow::Result<R> {
    let scopes = [wgpu::ErrorFilter::Validation, wgpu::ErrorFilter::OutOfMemory, wgpu::ErrorFilter::Internal]
        .map(|filter| device.push_error_scope(filter));
    let out = steps();
    let caught: Vec<wgpu::Error> = scopes.into_iter().rev().filter_map(|s| pollster::block_on(s.pop())).collect();
    let out = out?;
    if let Some(e) = caught.first() {
        anyhow::bail!("wgpu error: {}", describe(e));
    }
    Ok(out)
}

/// A wgpu error in words: its kind and the causes below it (wgpu's `Display` says only
/// "Validation Error"; the causes name the call and what was wrong).
pub fn describe(e: &wgpu::Error) -> String {
    let mut causes = Vec::new();
    let mut next = std::error::Error::source(e);
    while let Some(c) = next {
        let t = c.to_string();
        if !t.trim().is_empty() && !causes.contains(&t) {
            causes.push(t);
        }
        next = c.source();
    }
    let kind = match e {
        wgpu::Error::OutOfMemory { .. } => "the GPU ran out of memory",
        wgpu::Error::Validation { .. } => "validation error",
        wgpu::Error::Internal { .. } => "internal error",
    };
    if causes.is_empty() {
        kind.to_string()
    } else {
        format!("{kind}: {}", causes.join(": "))
    }
}
