//! The deferred renderer: G-buffer, lights (each with its culling method), compose.
//! It renders into a `TextureView` it is handed, so the same code draws the viewer's viewport
//! and the headless image tests.

pub mod gbuffer;
pub mod inspect;
pub mod materials;
pub mod pipelines;
pub mod settings;
pub mod stats;
pub mod volumes;

use crate::gpu::Gpu;
use crate::scene::{Light, Scene};
use anyhow::{bail, Result};
use glam::{DMat4, Mat4, Vec3, Vec4};
pub use inspect::{volume_wireframe_with, PixelProbe};
use materials::DefaultTextures;
use pipelines::{PipelineKey, Pipelines, LIGHT_KIND_POINT, LIGHT_KIND_SPOT};
pub use settings::{AccumFormat, CullingMode, DebugView, DepthFormat, LayoutChoice, Settings};
pub use stats::{FrameStats, LightStats, Method};
use volumes::VolumeMesh;
use wgpu::util::DeviceExt;

/// Format of the headless output image.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Above this share of the screen, `auto` draws a light full-screen (see `plan_light`).
pub const AUTO_FULLSCREEN_SHARE: f32 = 0.5;
/// Volumes whose projected bounding rectangle covers at least this many pixels are stencil
/// culled by `auto` (the marking draw pays off); smaller ones are drawn as plain volumes.
pub const AUTO_STENCIL_MIN_PIXELS: f32 = 4096.0;
/// Stride of the compose-parameter slots (the dynamic-offset alignment).
const COMPOSE_SLOT: u64 = 256;
/// Pipeline sets kept for configurations other than the current one (layout, accumulation,
/// depth format and convention, depth clamp).
const PIPELINE_CACHE: usize = 8;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraRaw {
    proj: [[f32; 4]; 4],
    inv_proj: [[f32; 4]; 4],
    screen: [f32; 4],
    ambient: [f32; 4],
    sun_dir: [f32; 4],
    sun_color: [f32; 4],
    background: [f32; 4],
    params: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightRaw {
    pub position: [f32; 3],
    pub radius: f32,
    pub color: [f32; 3],
    pub kind: u32,
    pub direction: [f32; 3],
    pub cos_outer: f32,
    pub cos_inner: f32,
    pub tan_outer: f32,
    /// The radius the attenuation falls to zero at. `radius` is where the light is cut off and
    /// what its volume bounds: the same, or less under `Settings::light_cutoff`.
    pub falloff: f32,
    pub pad: f32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ObjectRaw {
    model_view: [[f32; 4]; 4],
    normal_view: [[f32; 4]; 4],
    albedo_spec: [f32; 4],
    emissive_exp: [f32; 4],
    material: [f32; 4],
    pbr: [f32; 4],
    info: [u32; 4],
}

/// The most one light (and the ambient + sun pass) may add to a channel of the accumulation
/// buffer: the format's largest finite value shared among all `lights + 1` contributions, so
/// even 10,000 overlapping bright lights cannot overflow fp16 into infinity (and NaN after it).
/// With 1024 lights and fp16 that is 63.9 per light, far above what the built-in scenes use.
pub fn light_clamp(format: wgpu::TextureFormat, lights: usize) -> f32 {
    let max = match format {
        wgpu::TextureFormat::Rgba16Float => 65504.0,
        wgpu::TextureFormat::Rg11b10Ufloat => 64512.0,
        // Rgba8Log's product of factors saturates at zero, which decodes to a finite maximum;
        // Rgba32Float's sums stay finite for any count Lampshade draws.
        _ => return f32::MAX,
    };
    max / (lights as f32 + 1.0)
}

/// What every pass of one frame reads.
#[derive(Clone, Copy)]
struct Frame<'a> {
    t: &'a Targets,
    geo: &'a SceneGeometry,
    n: usize,
    want_counts: bool,
    want_ideal: bool,
    want_times: bool,
    far_depth: f64,
    settings: &'a Settings,
}

/// Which bounding mesh a light uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeKind {
    Sphere,
    Cone,
}

impl VolumeKind {
    /// Spots narrower than [`volumes::CONE_MAX_ANGLE_DEG`] get a cone, everything else a sphere.
    pub fn of(raw: &LightRaw) -> Self {
        if raw.kind == LIGHT_KIND_SPOT && raw.cos_outer > volumes::CONE_MAX_ANGLE_DEG.to_radians().cos() {
            VolumeKind::Cone
        } else {
            VolumeKind::Sphere
        }
    }
}

/// What the CPU decided for one light this frame.
#[derive(Clone, Copy, Debug)]
pub struct LightPlan {
    pub method: Method,
    pub volume: VolumeKind,
    /// The volume reaches in front of the near plane (or holds the camera).
    pub crosses_near: bool,
    /// The volume reaches beyond the far plane.
    pub crosses_far: bool,
    /// Share of the screen covered by the volume's projected bounding rectangle.
    pub screen_share: f32,
}

struct SceneGeometry {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Per object: index range and base vertex of its mesh.
    draws: Vec<(std::ops::Range<u32>, i32)>,
    /// Per mesh: bounding sphere (centre, radius) in model space.
    bounds: Vec<(glam::DVec3, f64)>,
    /// Per material: its textures and sampler.
    materials: Vec<wgpu::BindGroup>,
    /// What was loaded, to notice a different scene.
    fingerprint: SceneFingerprint,
    /// The material textures' views, to rebuild the bind groups when the pipelines change.
    views: Vec<wgpu::TextureView>,
    _textures: Vec<wgpu::Texture>,
}

/// Enough of a scene to tell that `render` was handed a different one than was loaded.
#[derive(Clone, Debug, PartialEq)]
struct SceneFingerprint {
    name: String,
    meshes: usize,
    vertices: usize,
    objects: usize,
    materials: usize,
    textures: Vec<usize>,
}

impl SceneFingerprint {
    fn of(scene: &Scene) -> Self {
        Self {
            name: scene.name.clone(),
            meshes: scene.meshes.len(),
            vertices: scene.meshes.iter().map(|m| m.vertices.len()).sum(),
            objects: scene.objects.len(),
            materials: scene.materials.len(),
            textures: scene.textures.iter().map(|t| std::sync::Arc::as_ptr(t) as usize).collect(),
        }
    }
}

/// Objects of one frame by how they are drawn.
#[derive(Default)]
struct DrawLists {
    /// Into the G-buffer: (object, geometry pipeline index, material).
    gbuffer: Vec<(usize, usize, usize)>,
    /// Forward, blended, sorted back to front: (object, forward pipeline index, material).
    forward: Vec<(usize, usize, usize)>,
}

struct Targets {
    width: u32,
    height: u32,
    depth_format: wgpu::TextureFormat,
    gbuffer: gbuffer::GBufferTargets,
    depth: wgpu::TextureView,
    diffuse: wgpu::Texture,
    specular: wgpu::Texture,
    diffuse_view: wgpu::TextureView,
    specular_view: wgpu::TextureView,
    debug_view: wgpu::TextureView,
    gbuffer_group: wgpu::BindGroup,
    compose_group: wgpu::BindGroup,
    /// HDR scene colour and its bind group; only for scenes with blended surfaces.
    hdr: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,

    depth_format: wgpu::TextureFormat,
    output_format: wgpu::TextureFormat,
    clamp_available: bool,
    features: wgpu::Features,
    pipelines: Pipelines,
    /// Pipelines of recent other configurations, least recently used first.
    pipeline_cache: Vec<Pipelines>,
    camera_buf: wgpu::Buffer,
    lights_buf: wgpu::Buffer,
    objects_buf: wgpu::Buffer,
    light_lists_buf: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    /// The material sampler and the 1x1 textures that stand in for absent ones.
    sampler: wgpu::Sampler,
    defaults: DefaultTextures,
    draw_lists: DrawLists,
    volume_vertices: wgpu::Buffer,
    volume_indices: wgpu::Buffer,
    sphere: VolumeMesh,
    cone: VolumeMesh,
    /// (sphere subdivisions, cone sides) the volume meshes were built with.
    tessellation: (u32, u32),
    geometry: Option<SceneGeometry>,
    targets: Option<Targets>,
    queries: stats::Queries,
    /// One 256-byte slot per debug view: the compose pass's view and scale.
    compose_params: wgpu::Buffer,
    /// The last frame's lights (view space) and inverse projection, for `probe`.
    last_lights: Vec<LightRaw>,
    last_inv_proj: DMat4,
    /// Plans of the last frame, for the viewer's panels.
    pub plans: Vec<LightPlan>,
}

fn mat(m: DMat4) -> [[f32; 4]; 4] {
    m.as_mat4().to_cols_array_2d()
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    w: u32,
    h: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl Targets {
    /// The depth-stencil buffer as the G-buffer pass left its depth; the stencil cleared to
    /// zero or kept.
    fn depth_attachment(&self, clear_stencil: bool) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        let store = wgpu::StoreOp::Store;
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store }),
            stencil_ops: Some(wgpu::Operations {
                load: if clear_stencil { wgpu::LoadOp::Clear(0) } else { wgpu::LoadOp::Load },
                store,
            }),
        }
    }
}

impl Renderer {
    pub fn new(gpu: &Gpu, output_format: wgpu::TextureFormat, settings: &Settings) -> Result<Self> {
        let device = gpu.device.clone();
        settings.validate().map_err(anyhow::Error::msg)?;
        let depth_format = settings.depth_format.format(gpu.features);
        let layout = settings.layout.layout();
        layout.validate().map_err(anyhow::Error::msg)?;
        layout.check_features(gpu.features).map_err(anyhow::Error::msg)?;
        let key = PipelineKey {
            layout,
            depth_format,
            output_format,
            reversed_z: settings.reversed_z,
            accum_format: settings.accumulation.format(gpu.features)?,
            depth_clamp: settings.depth_clamp && gpu.has(wgpu::Features::DEPTH_CLIP_CONTROL),
        };
        let pipelines = Self::build_pipelines(&device, key)?;
        let camera_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("camera"),
            size: std::mem::size_of::<CameraRaw>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let storage = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let lights_buf = storage("lights", 64 * 64);
        let objects_buf = storage("objects", 256 * 64);
        let light_lists_buf = storage("light lists", 4 * 64);
        let frame_group =
            Self::frame_group(&device, &pipelines, [&camera_buf, &lights_buf, &objects_buf, &light_lists_buf]);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let defaults = DefaultTextures::new(&device, &gpu.queue);
        let tessellation = (settings.sphere_subdivisions, settings.cone_sides);
        let (sphere, cone, volume_vertices, volume_indices) = Self::volume_meshes(&device, tessellation);
        let queries = stats::Queries::new(gpu);
        let compose_params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("compose params"),
            size: COMPOSE_SLOT * (DebugView::ALL.len() as u64 + 1),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Self {
            compose_params,
            last_lights: Vec::new(),
            last_inv_proj: DMat4::IDENTITY,
            queue: gpu.queue.clone(),

            depth_format,
            output_format,
            clamp_available: gpu.has(wgpu::Features::DEPTH_CLIP_CONTROL),
            features: gpu.features,
            pipelines,
            pipeline_cache: Vec::new(),
            camera_buf,
            lights_buf,
            objects_buf,
            light_lists_buf,
            frame_group,
            sampler,
            defaults,
            draw_lists: DrawLists::default(),
            volume_vertices,
            volume_indices,
            sphere,
            cone,
            tessellation,
            geometry: None,
            targets: None,
            queries,
            plans: Vec::new(),
            device,
        })
    }

    /// Builds pipelines, turning validation errors (a bad layout, a shader that fails to
    /// compile) into an error instead of a panic.
    fn build_pipelines(device: &wgpu::Device, key: PipelineKey) -> Result<Pipelines> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let p = Pipelines::new(device, key);
        if let Some(e) = pollster::block_on(scope.pop()) {
            bail!("building the pipelines failed: {e}");
        }
        Ok(p)
    }

    /// The sphere and cone at a tessellation, and one vertex and index buffer holding both.
    fn volume_meshes(
        device: &wgpu::Device,
        (subdivisions, sides): (u32, u32),
    ) -> (VolumeMesh, VolumeMesh, wgpu::Buffer, wgpu::Buffer) {
        let sphere = VolumeMesh::sphere(subdivisions);
        let cone = VolumeMesh::cone(sides);
        let all_vertices: Vec<Vec4> = sphere.vertices.iter().chain(cone.vertices.iter()).copied().collect();
        let all_indices: Vec<u32> = sphere.indices.iter().chain(cone.indices.iter()).copied().collect();
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light volumes"),
            contents: bytemuck::cast_slice(&all_vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light volume indices"),
            contents: bytemuck::cast_slice(&all_indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        (sphere, cone, vertices, indices)
    }

    /// Camera uniforms, lights, objects and the forward pass's light lists.
    fn frame_group(device: &wgpu::Device, p: &Pipelines, buffers: [&wgpu::Buffer; 4]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &p.frame_bgl,
            entries: &entries,
        })
    }

    fn rebuild_frame_group(&mut self) {
        self.frame_group = Self::frame_group(
            &self.device,
            &self.pipelines,
            [&self.camera_buf, &self.lights_buf, &self.objects_buf, &self.light_lists_buf],
        );
    }

    pub fn depth_format(&self) -> wgpu::TextureFormat {
        self.depth_format
    }

    pub fn depth_clamp(&self) -> bool {
        self.pipelines.key.depth_clamp
    }

    pub fn layout(&self) -> &gbuffer::GBufferLayout {
        &self.pipelines.key.layout
    }

    /// Uploads the scene's meshes and textures. Call once per scene (`render` calls it when it
    /// is handed a different scene); `render` uploads camera, objects and lights every frame.
    pub fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        scene.validate().map_err(anyhow::Error::msg)?;
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut ranges = Vec::new();
        let mut bounds = Vec::new();
        for m in &scene.meshes {
            let base = vertices.len() as i32;
            let start = indices.len() as u32;
            vertices.extend_from_slice(&m.vertices);
            indices.extend_from_slice(&m.indices);
            ranges.push((start..indices.len() as u32, base));
            let (mut lo, mut hi) = (glam::DVec3::splat(f64::INFINITY), glam::DVec3::splat(f64::NEG_INFINITY));
            for v in &m.vertices {
                let p = Vec3::from(v.position).as_dvec3();
                lo = lo.min(p);
                hi = hi.max(p);
            }
            let centre = if lo.x <= hi.x { (lo + hi) * 0.5 } else { glam::DVec3::ZERO };
            let radius =
                m.vertices.iter().map(|v| (Vec3::from(v.position).as_dvec3() - centre).length()).fold(0.0, f64::max);
            bounds.push((centre, radius));
        }
        if vertices.is_empty() {
            vertices.push(Default::default());
            indices.extend([0, 0, 0]);
        }
        let vb = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let ib = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let limit = self.device.limits().max_texture_dimension_2d;
        if let Some(t) = scene.textures.iter().find(|t| t.width > limit || t.height > limit) {
            bail!("texture {} is {}x{}, larger than this GPU's limit of {limit}", t.name, t.width, t.height);
        }
        let textures: Vec<wgpu::Texture> =
            scene.textures.iter().map(|t| materials::upload(&self.device, &self.queue, t)).collect();
        let views: Vec<wgpu::TextureView> = textures.iter().map(|t| t.create_view(&Default::default())).collect();
        let material_groups = materials::bind_groups(
            &self.device,
            &self.pipelines.material_bgl,
            scene,
            &views,
            &self.defaults,
            &self.sampler,
        );
        let draws = scene.objects.iter().map(|o| ranges[o.mesh].clone()).collect();
        self.geometry = Some(SceneGeometry {
            vertices: vb,
            indices: ib,
            draws,
            bounds,
            materials: material_groups,
            fingerprint: SceneFingerprint::of(scene),
            views,
            _textures: textures,
        });
        Ok(())
    }

    /// (Re)creates the size-dependent targets when the size or layout changed.
    fn ensure_targets(&mut self, width: u32, height: u32, hdr: bool) {
        if let Some(t) = &self.targets {
            if t.width == width
                && t.height == height
                && t.depth_format == self.depth_format
                && t.gbuffer.layout == self.pipelines.key.layout
                && t.diffuse.format() == self.pipelines.key.accum_format
                && t.hdr.is_some() == hdr
            {
                return;
            }
        }
        let d = &self.device;
        use wgpu::TextureUsages as U;
        let gbuffer = gbuffer::GBufferTargets::new(d, &self.pipelines.key.layout, width, height);
        let depth = texture(d, "depth-stencil", self.depth_format, width, height, U::RENDER_ATTACHMENT)
            .create_view(&Default::default());
        let read = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        let accum = self.pipelines.key.accum_format;
        let diffuse = texture(d, "light diffuse", accum, width, height, read);
        let specular = texture(d, "light specular", accum, width, height, read);
        let debug = texture(d, "debug", pipelines::DEBUG_FORMAT, width, height, read);
        let diffuse_view = diffuse.create_view(&Default::default());
        let specular_view = specular.create_view(&Default::default());
        let debug_view = debug.create_view(&Default::default());
        let gbuffer_group = gbuffer.bind_group(d, &self.pipelines.gbuffer_bgl);
        let compose_group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("compose"),
            layout: &self.pipelines.compose_bgl,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&diffuse_view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&specular_view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&debug_view) },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.compose_params,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
            ],
        });
        // Only scenes with blended surfaces need the HDR scene colour (model what the scene needs).
        let hdr = hdr.then(|| {
            let view =
                texture(d, "hdr colour", pipelines::HDR_FORMAT, width, height, read).create_view(&Default::default());
            let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hdr colour"),
                layout: &self.pipelines.hdr_bgl,
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) }],
            });
            (view, group)
        });
        self.targets = Some(Targets {
            hdr,
            width,
            height,
            depth_format: self.depth_format,
            gbuffer,
            depth,
            diffuse,
            specular,
            diffuse_view,
            specular_view,
            debug_view,
            gbuffer_group,
            compose_group,
        });
    }

    /// Rebuilds pipelines when the settings change something they depend on.
    fn ensure_pipelines(&mut self, settings: &Settings, scene: &Scene) -> Result<()> {
        let layout = settings.layout.layout_for(scene);
        let depth_clamp = settings.depth_clamp && self.clamp_available;
        let k = &self.pipelines.key;
        let accum_format = settings.accumulation.format(self.features)?;
        let depth_format = settings.depth_format.format(self.features);
        let tessellation = (settings.sphere_subdivisions, settings.cone_sides);
        if tessellation != self.tessellation {
            (self.sphere, self.cone, self.volume_vertices, self.volume_indices) =
                Self::volume_meshes(&self.device, tessellation);
            self.tessellation = tessellation;
        }
        if layout != k.layout
            || settings.reversed_z != k.reversed_z
            || depth_clamp != k.depth_clamp
            || accum_format != k.accum_format
            || depth_format != k.depth_format
        {
            layout.validate().map_err(anyhow::Error::msg)?;
            layout.check_features(self.features).map_err(anyhow::Error::msg)?;
            self.depth_format = depth_format;
            let key = PipelineKey {
                layout,
                reversed_z: settings.reversed_z,
                depth_clamp,
                accum_format,
                depth_format,
                ..k.clone()
            };
            // Switching back to a configuration seen recently reuses its pipelines instead of
            // compiling them again (and on lavapipe, leaving the old compilation's memory behind).
            let next = match self.pipeline_cache.iter().position(|p| p.key == key) {
                Some(i) => self.pipeline_cache.remove(i),
                None => Self::build_pipelines(&self.device, key)?,
            };
            let previous = std::mem::replace(&mut self.pipelines, next);
            self.pipeline_cache.push(previous);
            if self.pipeline_cache.len() > PIPELINE_CACHE {
                self.pipeline_cache.remove(0);
            }
            self.rebuild_frame_group();
            self.targets = None;
            // Material bind groups belong to the old layout; the textures stay uploaded.
            if let Some(geo) = &mut self.geometry {
                geo.materials = materials::bind_groups(
                    &self.device,
                    &self.pipelines.material_bgl,
                    scene,
                    &geo.views,
                    &self.defaults,
                    &self.sampler,
                );
            }
        }
        Ok(())
    }

    fn grow(&mut self, lights: usize, objects: usize, list_entries: usize) {
        let need_l = (lights.max(1) * std::mem::size_of::<LightRaw>()) as u64;
        let need_o = (objects.max(1) * std::mem::size_of::<ObjectRaw>()) as u64;
        let need_ll = (list_entries.max(1) * 4) as u64;
        let mut changed = false;
        let make = |d: &wgpu::Device, label, size: u64| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.next_power_of_two(),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        if self.lights_buf.size() < need_l {
            self.lights_buf = make(&self.device, "lights", need_l);
            changed = true;
        }
        if self.objects_buf.size() < need_o {
            self.objects_buf = make(&self.device, "objects", need_o);
            changed = true;
        }
        if self.light_lists_buf.size() < need_ll {
            self.light_lists_buf = make(&self.device, "light lists", need_ll);
            changed = true;
        }
        if changed {
            self.rebuild_frame_group();
        }
    }

    /// The light in view space, as the shaders see it, cut off at `cutoff` of its peak
    /// (`Settings::light_cutoff`).
    pub(crate) fn light_raw(scene: &Scene, light: &Light, cutoff: f32) -> LightRaw {
        let cam = &scene.camera;
        let rot = cam.rotation();
        match light {
            Light::Point(p) => LightRaw {
                position: cam.to_view(p.position).as_vec3().into(),
                radius: settings::cutoff_radius(p.radius, cutoff),
                falloff: p.radius,
                color: (p.color * p.intensity).into(),
                kind: LIGHT_KIND_POINT,
                direction: [0.0, 0.0, -1.0],
                cos_outer: -1.0,
                cos_inner: -1.0,
                tan_outer: 0.0,
                pad: 0.0,
            },
            Light::Spot(s) => LightRaw {
                position: cam.to_view(s.position).as_vec3().into(),
                radius: settings::cutoff_radius(s.radius, cutoff),
                falloff: s.radius,
                color: (s.color * s.intensity).into(),
                kind: LIGHT_KIND_SPOT,
                direction: (rot * s.direction.as_dvec3()).normalize().as_vec3().into(),
                cos_outer: s.outer_angle.cos(),
                cos_inner: s.inner_angle.cos(),
                tan_outer: s.outer_angle.tan(),
                pad: 0.0,
            },
        }
    }

    /// Which mesh bounds the light, where it sits against the near and far planes, and how
    /// much of the screen it covers; then which method draws it.
    ///
    /// `auto`'s rule, per light: outside the frustum, skip it; covering more than
    /// [`AUTO_FULLSCREEN_SHARE`] of the screen, draw it full-screen (rasterising its faces buys
    /// nothing); a screen rectangle of at least [`AUTO_STENCIL_MIN_PIXELS`], seed 000's two-pass
    /// stencil (the marking draw saves thousands of shaded fragments); else the plain volume (one
    /// draw, back faces, GreaterEqual), since for small volumes the extra marking draw costs more
    /// than the fragments it saves. Thresholds from `lampshade bench --only culling` on lavapipe
    /// at 320x180, 640x360 and 1280x720 (README, "Measurements").
    pub(crate) fn plan_light(
        &self,
        raw: &LightRaw,
        proj: &Mat4,
        near: f32,
        far: f32,
        size: (u32, u32),
        mode: CullingMode,
    ) -> LightPlan {
        let volume = VolumeKind::of(raw);
        let pos = Vec3::from(raw.position);
        let dir = Vec3::from(raw.direction);
        let mesh = self.volume_mesh(volume);
        let mut crosses_near = false;
        let mut crosses_far = false;
        // Clip-space side planes: a convex volume with every vertex outside one of them is
        // outside the frustum.
        let mut outside = [true; 4];
        let (mut all_before_near, mut all_beyond_far) = (true, true);
        let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::splat(f32::NEG_INFINITY));
        for v in &mesh.vertices {
            let p = volumes::place(*v, pos, raw.radius, dir, raw.tan_outer);
            let dist = -p.z;
            crosses_near |= dist <= near * 1.01;
            crosses_far |= dist >= far * 0.99;
            all_before_near &= dist < near;
            all_beyond_far &= dist > far;
            let c = *proj * p.extend(1.0);
            for (k, d) in [c.w - c.x, c.w + c.x, c.w - c.y, c.w + c.y].into_iter().enumerate() {
                outside[k] &= d < 0.0;
            }
            if c.w > 0.0 {
                let n = glam::Vec2::new(c.x, c.y) / c.w;
                lo = lo.min(n);
                hi = hi.max(n);
            }
        }
        let off_screen = outside.iter().any(|&o| o)
            || all_before_near
            || all_beyond_far
            || !(crosses_near || lo.x < 1.0 && lo.y < 1.0 && hi.x > -1.0 && hi.y > -1.0);
        let crosses_near = crosses_near && !off_screen;
        let screen_share = if off_screen {
            0.0
        } else if crosses_near {
            1.0
        } else {
            let a = (hi.min(glam::Vec2::ONE) - lo.max(-glam::Vec2::ONE)).max(glam::Vec2::ZERO);
            a.x * a.y / 4.0
        };
        let pixels = screen_share * (size.0 * size.1) as f32;
        let method = if crosses_far && !self.depth_clamp() && !(mode == CullingMode::Auto && off_screen) {
            // Without depth clamp the far side would be clipped away: no volume method is
            // correct, so the light is drawn full-screen.
            Method::Fullscreen
        } else {
            match mode {
                CullingMode::Fullscreen => Method::Fullscreen,
                CullingMode::Volume => Method::Volume,
                CullingMode::StencilTwoPass => Method::TwoPass,
                CullingMode::StencilInvert => Method::Invert,
                CullingMode::StencilReplace => Method::Replace,
                CullingMode::Auto if off_screen => Method::Skipped,
                CullingMode::Auto if screen_share > AUTO_FULLSCREEN_SHARE => Method::Fullscreen,
                CullingMode::Auto if pixels >= AUTO_STENCIL_MIN_PIXELS => Method::TwoPass,
                CullingMode::Auto => Method::Volume,
            }
        };
        LightPlan { method, volume, crosses_near, crosses_far, screen_share }
    }

    fn upload(&mut self, scene: &Scene, settings: &Settings, width: u32, height: u32) -> Vec<LightRaw> {
        let cam = &scene.camera;
        let aspect = width as f64 / height as f64;
        let proj = cam.projection(aspect, settings.reversed_z);
        let view = DMat4::from_mat3(cam.rotation()) * DMat4::from_translation(-cam.position);
        let rot = cam.rotation();
        let sun = scene.sun.map(|s| {
            let d = (rot * (-s.direction.as_dvec3())).normalize().as_vec3();
            (d.extend(1.0), (s.color * s.intensity).extend(0.0))
        });
        let (sun_dir, sun_color) = sun.unwrap_or((Vec4::ZERO, Vec4::ZERO));
        let raw = CameraRaw {
            proj: mat(proj),
            inv_proj: mat(proj.inverse()),
            screen: [width as f32, height as f32, 1.0 / width as f32, 1.0 / height as f32],
            ambient: scene.ambient.extend(0.0).into(),
            sun_dir: sun_dir.into(),
            sun_color: sun_color.into(),
            background: scene.background.extend(1.0).into(),
            params: [
                settings.exposure,
                if settings.reversed_z { 0.0 } else { 1.0 },
                settings.debug_view as u32 as f32,
                light_clamp(self.pipelines.key.accum_format, scene.lights.len()),
            ],
        };
        self.queue.write_buffer(&self.camera_buf, 0, bytemuck::bytes_of(&raw));
        let objects: Vec<ObjectRaw> = scene
            .objects
            .iter()
            .map(|o| {
                let mv = view * o.transform;
                let nm = glam::DMat4::from_mat3(glam::DMat3::from_mat4(mv).inverse().transpose());
                let m = &scene.materials[o.material];
                let mut flags = 0;
                if m.textures.normal.is_some() {
                    flags |= pipelines::MAT_NORMAL_MAP;
                }
                if m.textures.metallic_roughness.is_some() {
                    flags |= pipelines::MAT_METAL_ROUGH;
                }
                let cutoff = match m.alpha_mode {
                    crate::scene::AlphaMode::Mask { cutoff } => cutoff,
                    _ => 0.0,
                };
                ObjectRaw {
                    model_view: mat(mv),
                    normal_view: mat(nm),
                    albedo_spec: m.diffuse.extend(m.specular_level).into(),
                    emissive_exp: m.emissive.extend(m.specular_exponent).into(),
                    material: [m.alpha, cutoff, m.normal_scale, 0.0],
                    // With a metallic-roughness map the importer keeps f0 in specular_level.
                    pbr: [m.metallic, m.roughness, m.specular_level, 0.0],
                    info: [flags, 0, 0, 0],
                }
            })
            .collect();
        let mut objects = objects;
        let lights: Vec<LightRaw> =
            scene.lights.iter().map(|l| Self::light_raw(scene, l, settings.light_cutoff)).collect();
        let lists = self.plan_draws(scene, &mut objects);
        self.grow(lights.len(), objects.len(), lists.len());
        if !objects.is_empty() {
            self.queue.write_buffer(&self.objects_buf, 0, bytemuck::cast_slice(&objects));
        }
        if !lists.is_empty() {
            self.queue.write_buffer(&self.light_lists_buf, 0, bytemuck::cast_slice(&lists));
        }
        if !lights.is_empty() {
            self.queue.write_buffer(&self.lights_buf, 0, bytemuck::cast_slice(&lights));
        }
        let proj32 = proj.as_mat4();
        let (near, far) = (cam.near as f32, cam.far as f32);
        self.plans =
            lights.iter().map(|l| self.plan_light(l, &proj32, near, far, (width, height), settings.culling)).collect();
        self.last_lights = lights.clone();
        self.last_inv_proj = proj.inverse();
        lights
    }

    /// Sorts the objects into the G-buffer pass (opaque, masked) and the forward pass (blended,
    /// back to front by the view depth of their bounding sphere's centre), and builds each
    /// blended object's light list: the lights whose sphere reaches its bounding sphere.
    /// Returns the concatenated lists; each object's `info` gets its offset and count.
    fn plan_draws(&mut self, scene: &Scene, objects: &mut [ObjectRaw]) -> Vec<u32> {
        let mut lists = Vec::new();
        let mut draws = DrawLists::default();
        let Some(geo) = &self.geometry else { return lists };
        let mut forward: Vec<(f64, usize, usize, usize)> = Vec::new();
        for (i, o) in scene.objects.iter().enumerate() {
            let m = &scene.materials[o.material];
            match m.alpha_mode {
                crate::scene::AlphaMode::Blend => {
                    let (c, r) = geo.bounds.get(o.mesh).copied().unwrap_or((glam::DVec3::ZERO, 0.0));
                    let centre = o.transform.transform_point3(c);
                    let scale = (0..3).map(|k| o.transform.col(k).truncate().length()).fold(0.0, f64::max);
                    let radius = r * scale;
                    let first = lists.len() as u32;
                    for (k, l) in scene.lights.iter().enumerate() {
                        if (l.position() - centre).length() < radius + l.radius() as f64 {
                            lists.push(k as u32);
                        }
                    }
                    objects[i].info[1] = first;
                    objects[i].info[2] = lists.len() as u32 - first;
                    let depth = scene.camera.to_view(centre).z;
                    forward.push((depth, i, m.double_sided as usize, o.material));
                }
                mode => {
                    let masked = matches!(mode, crate::scene::AlphaMode::Mask { .. });
                    draws.gbuffer.push((i, Pipelines::geometry_index(masked, m.double_sided), o.material));
                }
            }
        }
        // View space looks down -z: the farthest has the most negative z and is drawn first.
        forward.sort_by(|a, b| a.0.total_cmp(&b.0));
        draws.forward = forward.into_iter().map(|(_, i, p, m)| (i, p, m)).collect();
        // Fewer pipeline and material switches in the G-buffer pass.
        draws.gbuffer.sort_by_key(|&(_, p, m)| (p, m));
        self.draw_lists = draws;
        lists
    }

    /// The bounding meshes this frame's plans draw ("sphere", "cone"): volume kinds are drawn
    /// only for the light types present (a scene without narrow spots draws no cone).
    fn volume_meshes_drawn(&self) -> Vec<String> {
        let drawn = |kind| {
            self.plans.iter().any(|p| p.volume == kind && !matches!(p.method, Method::Fullscreen | Method::Skipped))
        };
        [(VolumeKind::Sphere, "sphere"), (VolumeKind::Cone, "cone")]
            .into_iter()
            .filter(|&(k, _)| drawn(k))
            .map(|(_, name)| name.to_string())
            .collect()
    }

    pub(crate) fn volume_mesh(&self, kind: VolumeKind) -> &VolumeMesh {
        match kind {
            VolumeKind::Sphere => &self.sphere,
            VolumeKind::Cone => &self.cone,
        }
    }

    fn volume_range(&self, kind: VolumeKind) -> (std::ops::Range<u32>, i32) {
        let ns = self.sphere.indices.len() as u32;
        match kind {
            VolumeKind::Sphere => (0..ns, 0),
            VolumeKind::Cone => (ns..ns + self.cone.indices.len() as u32, self.sphere.vertices.len() as i32),
        }
    }

    /// Renders one frame of `scene` into `target` (of the renderer's output format and the
    /// given size). Returns the frame's statistics; counts and times are read back only when
    /// `settings` asks for them.
    pub fn render(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) -> Result<FrameStats> {
        if width == 0 || height == 0 {
            bail!("cannot render a {width}x{height} frame");
        }
        settings.validate().map_err(anyhow::Error::msg)?;
        scene.validate().map_err(anyhow::Error::msg)?;
        self.ensure_pipelines(settings, scene)?;
        if self.geometry.as_ref().is_none_or(|g| g.fingerprint != SceneFingerprint::of(scene)) {
            self.load_scene(scene)?;
        }
        // Transparency is shaded forward over the HDR picture, in the final view only (the
        // debug views show the G-buffer and its lighting, which hold no transparent surface).
        let forward = settings.debug_view == DebugView::Lit && scene.any_blended();
        self.ensure_targets(width, height, forward);
        let lights = self.upload(scene, settings, width, height);
        let n = lights.len();
        let want_counts = settings.count_fragments && n > 0;
        let want_ideal = settings.count_ideal && n > 0;
        let want_times = settings.timestamps && self.queries.timestamps.is_some();
        self.queries.ensure_lights(&self.device, n);

        let (Some(t), Some(geo)) = (&self.targets, &self.geometry) else {
            bail!("internal: targets or geometry missing");
        };
        let f = Frame {
            t,
            geo,
            n,
            want_counts,
            want_ideal,
            want_times,
            far_depth: if settings.reversed_z { 0.0 } else { 1.0 },
            settings,
        };
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });

        // The frame as the seeds draw it:
        // 1. G-buffer: every attribute the lights need, in one pass with multiple targets.
        self.gbuffer_pass(&mut encoder, &f);
        // 2. Lights: ambient + sun full-screen, then each light with its culling method.
        self.light_pass(&mut encoder, &f);
        self.debug_pass(&mut encoder, &f);
        // 3. Compose: diffuse x albedo + specular + emissive, tonemapped (or a debug view).
        if forward {
            // 3'. With blended surfaces: compose in HDR, shade them forward over it back to
            //     front, then tonemap (seeds 002-004: deferred shading cannot do transparency).
            self.forward_pass(&mut encoder, &f, target);
        } else {
            self.encode_compose(
                &mut encoder,
                settings.debug_view,
                0,
                target,
                width,
                height,
                self.pass_timestamps(want_times, 4),
            );
        }
        // 4. Measurement only: the ideal count.
        self.ideal_pass(&mut encoder, &f);

        self.queries.resolve(&mut encoder, n, want_counts, want_ideal, want_times);
        self.queue.submit([encoder.finish()]);

        let mut stats = FrameStats {
            size: [width, height],
            culling: settings.culling,
            lights: n,
            gbuffer_layout: self.pipelines.key.layout.name.to_string(),
            gbuffer_bytes_per_pixel: self.pipelines.key.layout.bytes_per_pixel(),
            depth_stencil_format: format!("{:?}", self.depth_format),
            depth_clamp: self.depth_clamp(),
            accumulation_format: format!("{:?}", self.pipelines.key.accum_format),
            light_cutoff: settings.light_cutoff,
            sphere_triangles: (self.sphere.indices.len() / 3) as u32,
            cone_triangles: (self.cone.indices.len() / 3) as u32,
            volume_meshes: self.volume_meshes_drawn(),
            ..Default::default()
        };
        self.queries.read(&self.device, &mut stats, &self.plans, scene, want_counts, want_ideal, want_times)?;
        Ok(stats)
    }

    /// Records the G-buffer pass.
    fn gbuffer_pass(&self, encoder: &mut wgpu::CommandEncoder, f: &Frame<'_>) {
        let p = &self.pipelines;
        let Frame { t, geo, want_times, far_depth, .. } = *f;
        // 1. G-buffer: every attribute the lights need, in one pass with multiple targets.
        {
            let color: Vec<Option<wgpu::RenderPassColorAttachment>> = t
                .gbuffer
                .views
                .iter()
                .zip(&t.gbuffer.layout.targets)
                .map(|(v, desc)| {
                    // Background: the depth copy holds the far plane's depth, the rest zero.
                    let has_depth = desc.channels.iter().flatten().any(|s| s.attr == gbuffer::Attr::Depth);
                    let r = if has_depth { far_depth } else { 0.0 };
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color { r, g: 0.0, b: 0.0, a: 0.0 }),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                })
                .collect();
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("g-buffer"),
                color_attachments: &color,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(far_depth as f32),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0), store: wgpu::StoreOp::Store }),
                }),
                timestamp_writes: self.pass_timestamps(want_times, 0),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_group, &[]);
            self.draw_surfaces(&mut pass, geo, &self.draw_lists.gbuffer, &p.geometry);
        }
    }

    /// Draws objects with their material bind groups, switching pipelines as the list asks.
    fn draw_surfaces(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        geo: &SceneGeometry,
        list: &[(usize, usize, usize)],
        pipes: &[wgpu::RenderPipeline],
    ) {
        pass.set_vertex_buffer(0, geo.vertices.slice(..));
        pass.set_index_buffer(geo.indices.slice(..), wgpu::IndexFormat::Uint32);
        let (mut pipe, mut mat) = (usize::MAX, usize::MAX);
        for &(i, p, m) in list {
            if p != pipe {
                pass.set_pipeline(&pipes[p]);
                pipe = p;
            }
            if m != mat {
                if let Some(g) = geo.materials.get(m) {
                    pass.set_bind_group(1, g, &[]);
                }
                mat = m;
            }
            let (range, base) = &geo.draws[i];
            pass.draw_indexed(range.clone(), *base, i as u32..i as u32 + 1);
        }
    }

    /// Compose into the HDR scene colour, blended surfaces forward over it (back to front, depth
    /// tested against the G-buffer's depth, not written), then exposure and tonemapping.
    fn forward_pass(&self, encoder: &mut wgpu::CommandEncoder, f: &Frame<'_>, target: &wgpu::TextureView) {
        let Frame { t, geo, want_times, .. } = *f;
        let Some((hdr_view, hdr_group)) = &t.hdr else { return };
        let p = &self.pipelines;
        let timestamps = |begin: Option<u32>, end: Option<u32>| {
            if !want_times {
                return None;
            }
            self.queries.timestamps.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: begin,
                end_of_pass_write_index: end,
            })
        };
        let params: [u32; 4] = [DebugView::Lit as u32, 0, 1f32.to_bits(), 1f32.to_bits()];
        self.queue.write_buffer(&self.compose_params, 0, bytemuck::cast_slice(&params));
        let color = |view| {
            [Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
            })]
        };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("compose (HDR)"),
                color_attachments: &color(hdr_view),
                depth_stencil_attachment: None,
                timestamp_writes: timestamps(Some(4), None),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&p.compose_hdr);
            pass.set_bind_group(0, &self.frame_group, &[]);
            pass.set_bind_group(1, &t.gbuffer_group, &[]);
            pass.set_bind_group(2, &t.compose_group, &[0]);
            pass.draw(0..3, 0..1);
        }
        {
            let mut attach = color(hdr_view);
            if let Some(a) = &mut attach[0] {
                a.ops.load = wgpu::LoadOp::Load;
            }
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("forward (blended)"),
                color_attachments: &attach,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_group, &[]);
            self.draw_surfaces(&mut pass, geo, &self.draw_lists.forward, &p.forward);
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("tonemap"),
            color_attachments: &color(target),
            depth_stencil_attachment: None,
            timestamp_writes: timestamps(None, Some(5)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&p.tonemap);
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.set_bind_group(1, &t.gbuffer_group, &[]);
        pass.set_bind_group(2, &t.compose_group, &[0]);
        pass.set_bind_group(3, hdr_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Records the light accumulation: ambient + sun, then each light by its planned method.
    fn light_pass(&self, encoder: &mut wgpu::CommandEncoder, f: &Frame<'_>) {
        let p = &self.pipelines;
        let Frame { t, n, want_counts, want_times, .. } = *f;
        // 2. Lights: ambient + sun full-screen, then each light by its method, additively.
        //    One render pass per block of lights (an occlusion query set holds 4096).
        let chunk = stats::LIGHTS_PER_QUERY_SET;
        let blocks = n.div_ceil(chunk).max(1);
        let mut replace_counter = 0u32;
        for b in 0..blocks {
            let first = b == 0;
            let last = b + 1 == blocks;
            let accum_ops = wgpu::Operations {
                load: if first { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) } else { wgpu::LoadOp::Load },
                store: wgpu::StoreOp::Store,
            };
            let timestamp_writes = if want_times && (first || last) {
                self.queries.timestamps.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: first.then_some(2),
                    end_of_pass_write_index: last.then_some(3),
                })
            } else {
                None
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("lights"),
                color_attachments: &[
                    Some(wgpu::RenderPassColorAttachment {
                        view: &t.diffuse_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: accum_ops,
                    }),
                    Some(wgpu::RenderPassColorAttachment {
                        view: &t.specular_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: accum_ops,
                    }),
                ],
                depth_stencil_attachment: Some(t.depth_attachment(true)),
                timestamp_writes,
                occlusion_query_set: if want_counts { self.queries.occlusion.get(b) } else { None },
                multiview_mask: None,
            });
            self.bind_light_inputs(&mut pass, t);
            if first {
                pass.push_debug_group("ambient + sun");
                pass.set_pipeline(&p.ambient);
                pass.draw(0..3, 0..1);
                pass.pop_debug_group();
            }
            for i in b * chunk..((b + 1) * chunk).min(n) {
                let plan = self.plans[i];
                let li = i as u32..i as u32 + 1;
                let (range, base) = self.volume_range(plan.volume);
                let q = (i - b * chunk) as u32;
                let shade = |pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline, fullscreen: bool| {
                    pass.set_pipeline(pipeline);
                    if want_counts {
                        pass.begin_occlusion_query(q);
                    }
                    if fullscreen {
                        pass.draw(0..3, li.clone());
                    } else {
                        pass.draw_indexed(range.clone(), base, li.clone());
                    }
                    if want_counts {
                        pass.end_occlusion_query();
                    }
                };
                match plan.method {
                    Method::Skipped => {
                        // Outside the frustum: nothing to shade, the count is zero.
                        if want_counts {
                            pass.begin_occlusion_query(q);
                            pass.end_occlusion_query();
                        }
                    }
                    Method::Fullscreen => shade(&mut pass, &p.light_fullscreen, true),
                    Method::Volume => shade(&mut pass, &p.light_volume, false),
                    Method::TwoPass => {
                        pass.set_pipeline(&p.two_pass_mark);
                        pass.draw_indexed(range.clone(), base, li.clone());
                        pass.set_stencil_reference(0);
                        shade(&mut pass, &p.two_pass_shade, false);
                    }
                    Method::Invert => {
                        pass.set_pipeline(&p.invert_mark);
                        pass.draw_indexed(range.clone(), base, li.clone());
                        pass.set_stencil_reference(0);
                        shade(&mut pass, &p.invert_shade, false);
                    }
                    Method::Replace => {
                        if replace_counter == 255 {
                            pass.set_pipeline(&p.stencil_clear);
                            pass.draw(0..3, 0..1);
                            replace_counter = 0;
                        }
                        replace_counter += 1;
                        pass.set_stencil_reference(replace_counter);
                        pass.set_pipeline(&p.replace_mark);
                        pass.draw_indexed(range.clone(), base, li.clone());
                        let shade_pipe = if plan.crosses_near { &p.replace_shade_back } else { &p.replace_shade_front };
                        shade(&mut pass, shade_pipe, false);
                    }
                }
            }
        }
    }

    /// Records the passes some debug views need (stencil diagram, light complexity).
    fn debug_pass(&self, encoder: &mut wgpu::CommandEncoder, f: &Frame<'_>) {
        let p = &self.pipelines;
        let Frame { t, n, settings, .. } = *f;
        // 2b. Debug views that need their own pass: seed 000's stencil diagram, light complexity.
        if matches!(settings.debug_view, DebugView::Stencil | DebugView::Complexity) {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("debug view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &t.debug_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(t.depth_attachment(true)),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.bind_light_inputs(&mut pass, t);
            let selected: Vec<usize> = match settings.selected_light {
                Some(k) if k < n => vec![k],
                Some(_) => Vec::new(),
                None => (0..n).collect(),
            };
            for i in selected {
                let li = i as u32..i as u32 + 1;
                let (range, base) = self.volume_range(self.plans[i].volume);
                if settings.debug_view == DebugView::Complexity {
                    if self.plans[i].crosses_far && !self.depth_clamp() {
                        pass.set_pipeline(&p.complexity_fullscreen);
                        pass.draw(0..3, li);
                    } else {
                        pass.set_pipeline(&p.complexity);
                        pass.draw_indexed(range, base, li);
                    }
                    continue;
                }
                pass.set_stencil_reference(0);
                for pipe in [&p.classify_blue, &p.classify_red, &p.classify_green] {
                    pass.set_pipeline(pipe);
                    pass.draw_indexed(range.clone(), base, li.clone());
                }
            }
        }
    }

    /// Records the ideal count (measurement only, after the frame's timestamps).
    fn ideal_pass(&self, encoder: &mut wgpu::CommandEncoder, f: &Frame<'_>) {
        let p = &self.pipelines;
        let Frame { t, n, want_ideal, .. } = *f;
        // 4. Measurement only, after the frame (outside its timestamps): the ideal count, the
        //    G-buffer points inside each light's true shape.
        if want_ideal {
            let chunk = stats::LIGHTS_PER_QUERY_SET;
            let blocks = n.div_ceil(chunk).max(1);
            for b in 0..blocks {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("ideal count"),
                    color_attachments: &[
                        Some(wgpu::RenderPassColorAttachment {
                            view: &t.diffuse_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                        }),
                        Some(wgpu::RenderPassColorAttachment {
                            view: &t.specular_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                        }),
                    ],
                    depth_stencil_attachment: Some(t.depth_attachment(false)),
                    timestamp_writes: None,
                    occlusion_query_set: self.queries.ideal.get(b),
                    multiview_mask: None,
                });
                self.bind_light_inputs(&mut pass, t);
                pass.set_pipeline(&p.ideal);
                for i in b * chunk..((b + 1) * chunk).min(n) {
                    pass.begin_occlusion_query((i - b * chunk) as u32);
                    pass.draw(0..3, i as u32..i as u32 + 1);
                    pass.end_occlusion_query();
                }
                drop(pass);
                let load_accum = [&t.diffuse_view, &t.specular_view].map(|view| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                    })
                });
                // Rasterised coverage of each volume's back faces (what the volume methods
                // rasterise), from pipeline statistics, in a pass of its own: lavapipe returns
                // wrong occlusion counts when pipeline-statistics queries share their pass.
                let Some(set) = self.queries.coverage.get(b) else { continue };
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("coverage count"),
                    color_attachments: &load_accum,
                    depth_stencil_attachment: Some(t.depth_attachment(false)),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                self.bind_light_inputs(&mut pass, t);
                for i in b * chunk..((b + 1) * chunk).min(n) {
                    let li = i as u32..i as u32 + 1;
                    let plan = self.plans[i];
                    pass.begin_pipeline_statistics_query(set, (i - b * chunk) as u32);
                    if plan.method == Method::Fullscreen {
                        pass.set_pipeline(&p.coverage_fullscreen);
                        pass.draw(0..3, li);
                    } else if plan.method != Method::Skipped {
                        let (range, base) = self.volume_range(plan.volume);
                        pass.set_pipeline(&p.coverage);
                        pass.draw_indexed(range, base, li);
                    }
                    pass.end_pipeline_statistics_query();
                }
            }
        }
    }

    /// Frame uniforms, the G-buffer and the light-volume meshes: what every light draw reads.
    fn bind_light_inputs(&self, pass: &mut wgpu::RenderPass<'_>, t: &Targets) {
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.set_bind_group(1, &t.gbuffer_group, &[]);
        pass.set_vertex_buffer(0, self.volume_vertices.slice(..));
        pass.set_index_buffer(self.volume_indices.slice(..), wgpu::IndexFormat::Uint32);
    }

    fn pass_timestamps(&self, want: bool, begin: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        if !want {
            return None;
        }
        self.queries.timestamps.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: Some(begin),
            end_of_pass_write_index: Some(begin + 1),
        })
    }

    /// Records the compose pass into `target` (`w`x`h`, scaled from the G-buffer's size),
    /// with the view's parameters in compose slot `slot`.
    #[allow(clippy::too_many_arguments)]
    fn encode_compose(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        view: DebugView,
        slot: u64,
        target: &wgpu::TextureView,
        w: u32,
        h: u32,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let Some(t) = &self.targets else { return };
        let params: [u32; 4] =
            [view as u32, 0, (t.width as f32 / w as f32).to_bits(), (t.height as f32 / h as f32).to_bits()];
        self.queue.write_buffer(&self.compose_params, slot * COMPOSE_SLOT, bytemuck::cast_slice(&params));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("compose"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipelines.compose);
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.set_bind_group(1, &t.gbuffer_group, &[]);
        pass.set_bind_group(2, &t.compose_group, &[(slot * COMPOSE_SLOT) as u32]);
        pass.draw(0..3, 0..1);
    }

    /// Re-runs only the compose pass of the last frame with another view, into `target` of the
    /// output format at any size (the G-buffer is point-sampled): the viewer's thumbnails.
    /// The stencil and complexity views show what the last frame computed for them.
    pub fn compose_view(&mut self, view: DebugView, target: &wgpu::TextureView, width: u32, height: u32) -> Result<()> {
        if self.targets.is_none() {
            bail!("nothing rendered yet");
        }
        if width == 0 || height == 0 {
            bail!("cannot compose a {width}x{height} view");
        }
        let mut encoder =
            self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("compose view") });
        self.encode_compose(&mut encoder, view, view as u64 + 1, target, width, height, None);
        self.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// The blended objects of the last frame in the order the forward pass drew them (back to
    /// front), for the viewer and the tests.
    pub fn forward_order(&self) -> Vec<usize> {
        self.draw_lists.forward.iter().map(|d| d.0).collect()
    }

    /// The last frame's lights as the shaders saw them (view space, cut-off radius applied).
    pub fn light_records(&self) -> &[LightRaw] {
        &self.last_lights
    }

    /// Size of the last frame.
    pub fn size(&self) -> Option<(u32, u32)> {
        self.targets.as_ref().map(|t| (t.width, t.height))
    }

    pub fn output_format(&self) -> wgpu::TextureFormat {
        self.output_format
    }

    /// Reads the linear HDR accumulation (diffuse, specular) as f32 RGBA, for NaN/Inf checks
    /// (decoded, for the logarithmic Rgba8 format).
    pub fn read_accumulation(&self, gpu: &Gpu) -> Result<(Vec<f32>, Vec<f32>)> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        let format = t.diffuse.format();
        let bpp = format.block_copy_size(None).unwrap_or(8) as usize;
        let to_f32 = |bytes: Vec<u8>| -> Result<Vec<f32>> {
            let mut out = Vec::with_capacity(bytes.len() / bpp * 4);
            let log = pipelines::log_accum(format);
            for c in bytes.chunks_exact(bpp) {
                let v = inspect::texel(format, c)?;
                out.extend(if log { v.map(settings::log_accum_decode) } else { v });
            }
            Ok(out)
        };
        Ok((
            to_f32(gpu.read_texture(&t.diffuse, wgpu::TextureAspect::All)?)?,
            to_f32(gpu.read_texture(&t.specular, wgpu::TextureAspect::All)?)?,
        ))
    }
}
