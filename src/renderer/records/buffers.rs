//! The frame's GPU buffers and textures that hold the records: the storage buffers of group 0,
//! the light planes, the compose parameters, the shadow tables, atlas and cubes, the cookies.

use super::*;

/// The frame's u32 lists, from the plan.
#[derive(Clone, Copy)]
pub struct FrameLists<'a> {
    /// The forward pass's light lists (`FramePlan::light_lists`).
    pub forward: &'a [u32],
    /// The light of each instance of a light draw (`batches::LightBatches::list`).
    pub draw: &'a [u32],
}

/// Stride of the compose-parameter slots (the dynamic-offset alignment).
pub const COMPOSE_SLOT: u64 = 256;

/// The frame's storage buffers (group 0), the light planes and the compose parameters. The
/// light planes are the only uniform buffers: Mesa 22.3's lavapipe recompiles shaders whose
/// branches read a uniform at a constant offset, and the planes are only read at a light's
/// index (`bindings.rs`, `tests/it/shader_contract.rs`).
pub struct FrameBuffers {
    min_cube_layers: u32,
    pub camera: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    pub objects: wgpu::Buffer,
    pub light_lists: wgpu::Buffer,
    /// The light of each instance of a light draw (`batches::LightBatches::list`).
    pub draw_lights: wgpu::Buffer,
    /// The scene's cookies' texels ([`cookie_words`] in rows of [`COOKIE_ROW`]), and which
    /// cookies they are (`CookieImage::id`s: uploaded again only when they change).
    pub cookie_texels: wgpu::Texture,
    cookie_view: wgpu::TextureView,
    cookie_key: Vec<u64>,
    /// One [`COMPOSE_SLOT`] per debug view and one for the frame's own compose.
    pub compose: wgpu::Buffer,
    /// The light planes ([`light_planes`]; `bindings::LIGHT_PLANES`), each [`LIGHT_PLANE_BYTES`]
    /// of one buffer; written only in frames whose shaders read them.
    pub light_planes: wgpu::Buffer,
    pub group: wgpu::BindGroup,
    /// The shadow atlas (`--shadow-format`, `shadow_side` square), its view and comparison
    /// sampler, the tiles (`ShadowTile`) and the frame's `ShadowParams`.
    pub shadow_atlas: wgpu::Texture,
    pub shadow_view: wgpu::TextureView,
    pub shadow_sampler: wgpu::Sampler,
    /// The shadow table (`bindings::FRAME`'s `shadow_table`): row 0 the `ShadowParams`, row
    /// 1 + i tile i, each as its bytes.
    pub shadow_table: wgpu::Texture,
    pub shadow_table_view: wgpu::TextureView,
    /// `--shadow-cube array`: the cube array (the atlas's format, `shadow_cube_side` square, 6 layers
    /// a cube, at least `Quirks::min_cube_layers`; a 1x1 stand-in when no cube casts), its
    /// CubeArray view (bound) and one 2D view per layer (the shadow pass renders into them).
    pub shadow_cubes: wgpu::Texture,
    pub shadow_cubes_view: wgpu::TextureView,
    pub shadow_cube_layers: Vec<wgpu::TextureView>,
    /// `--shadow-cube indirect`: the indirection cube (`shadows::indirection_texels`, a 1x1
    /// stand-in until a frame reads one), its Cube view and its nearest sampler.
    pub shadow_indirection: wgpu::Texture,
    pub shadow_indirection_view: wgpu::TextureView,
    pub indirection_sampler: wgpu::Sampler,
}

/// The shadow bindings of the frame group, in [`crate::renderer::kit::bindings::FRAME`]'s order.
struct ShadowViews<'a> {
    atlas: &'a wgpu::TextureView,
    sampler: &'a wgpu::Sampler,
    table: &'a wgpu::TextureView,
    cubes: &'a wgpu::TextureView,
    indirection: &'a wgpu::TextureView,
    indirection_sampler: &'a wgpu::Sampler,
}

/// Rgba32Uint texels a shadow-table row holds: a `ShadowTile` (112 bytes) or the
/// `ShadowParams` (64).
pub const SHADOW_TABLE_WIDTH: u32 = 7;
const _: () = assert!(std::mem::size_of::<ShadowTile>() == 16 * SHADOW_TABLE_WIDTH as usize);
const _: () = assert!(std::mem::size_of::<ShadowParams>() <= 16 * SHADOW_TABLE_WIDTH as usize);

fn shadow_table(device: &wgpu::Device, rows: u32) -> (wgpu::Texture, wgpu::TextureView) {
    use wgpu::TextureUsages as U;
    let size = (SHADOW_TABLE_WIDTH, rows);
    let t = texture(device, "shadow table", wgpu::TextureFormat::Rgba32Uint, size, U::TEXTURE_BINDING | U::COPY_DST);
    let v = t.create_view(&Default::default());
    (t, v)
}

/// The shadow atlas of `side` texels square in `format`; COPY_SRC where the format can be copied
/// (Depth24Plus cannot).
fn shadow_atlas(device: &wgpu::Device, side: u32, format: wgpu::TextureFormat) -> (wgpu::Texture, wgpu::TextureView) {
    use wgpu::TextureUsages as U;
    let mut usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
    if format != wgpu::TextureFormat::Depth24Plus {
        usage |= U::COPY_SRC;
    }
    let t = texture(device, "shadow atlas", format, (side, side), usage);
    let v = t.create_view(&Default::default());
    (t, v)
}

/// The cube array for `layers` (a multiple of 6, at least 6) faces of `side` texels: the
/// texture, its CubeArray view and a 2D view per layer.
fn shadow_cubes(
    device: &wgpu::Device,
    side: u32,
    layers: u32,
    format: wgpu::TextureFormat,
) -> (wgpu::Texture, wgpu::TextureView, Vec<wgpu::TextureView>) {
    let layers = layers.max(6).div_ceil(6) * 6;
    let t = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("shadow cube array"),
        size: wgpu::Extent3d { width: side, height: side, depth_or_array_layers: layers },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let cubes = t.create_view(&wgpu::TextureViewDescriptor {
        label: Some("shadow cube array"),
        dimension: Some(wgpu::TextureViewDimension::CubeArray),
        ..Default::default()
    });
    let faces = (0..layers)
        .map(|layer| {
            t.create_view(&wgpu::TextureViewDescriptor {
                label: Some("shadow cube face"),
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    (t, cubes, faces)
}

/// The indirection cube of `side` texels a face (`shadows::indirection_texels`), written, and
/// its Cube view. `side` 0: a 1x1 stand-in, left unwritten.
fn shadow_indirection(
    device: &wgpu::Device,
    queue: Option<&wgpu::Queue>,
    side: u32,
) -> (wgpu::Texture, wgpu::TextureView) {
    let n = side.max(1);
    let size = wgpu::Extent3d { width: n, height: n, depth_or_array_layers: 6 };
    let t = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("shadow cube indirection"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    if let (Some(queue), true) = (queue, side > 0) {
        queue.write_texture(
            t.as_image_copy(),
            &indirection_texels(n),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * n), rows_per_image: Some(n) },
            size,
        );
    }
    let v = t.create_view(&wgpu::TextureViewDescriptor {
        label: Some("shadow cube indirection"),
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    });
    (t, v)
}

/// The cookie texels' texture: `width` x `rows` Rgba8Unorm (read with textureLoad, exact).
fn cookie_texture(device: &wgpu::Device, width: u32, rows: u32) -> wgpu::Texture {
    use wgpu::TextureUsages as U;
    let size = (width.max(1), rows.max(1));
    texture(device, "cookie texels", wgpu::TextureFormat::Rgba8Unorm, size, U::TEXTURE_BINDING | U::COPY_DST)
}

fn storage(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl FrameBuffers {
    /// `min_cube_layers`: the fewest layers the cube array is made with (`Quirks::min_cube_layers`).
    pub fn new(device: &wgpu::Device, frame_bgl: &wgpu::BindGroupLayout, min_cube_layers: u32) -> Self {
        let camera = storage(device, "camera", std::mem::size_of::<CameraRecord>() as u64);
        let lights = storage(device, "lights", 64 * std::mem::size_of::<LightRecord>() as u64);
        let objects = storage(device, "objects", 64 * std::mem::size_of::<ObjectRecord>() as u64);
        let light_lists = storage(device, "light lists", 4 * 64);
        let draw_lights = storage(device, "draw lights", 4 * 64);
        let views = crate::renderer::DebugView::ALL.len() as u64;
        let compose = storage(device, "compose params", COMPOSE_SLOT * (views + 1));
        let light_planes = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("light planes"),
            size: LIGHT_PLANE_COUNT as u64 * LIGHT_PLANE_BYTES,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let cookie_texels = cookie_texture(device, 1, 1);
        let cookie_view = cookie_texels.create_view(&Default::default());
        let (shadow_atlas, shadow_view) = shadow_atlas(device, 1, wgpu::TextureFormat::Depth32Float);
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow comparison"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let (shadow_table, shadow_table_view) = shadow_table(device, 16);
        let (shadow_cubes, shadow_cubes_view, shadow_cube_layers) =
            shadow_cubes(device, 1, min_cube_layers, wgpu::TextureFormat::Depth32Float);
        let (shadow_indirection, shadow_indirection_view) = shadow_indirection(device, None, 0);
        let indirection_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow cube indirection"),
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let group = Self::bind(
            device,
            frame_bgl,
            [&camera, &lights, &objects, &light_lists, &draw_lights],
            &light_planes,
            &cookie_view,
            ShadowViews {
                atlas: &shadow_view,
                sampler: &shadow_sampler,
                table: &shadow_table_view,
                cubes: &shadow_cubes_view,
                indirection: &shadow_indirection_view,
                indirection_sampler: &indirection_sampler,
            },
        );
        Self {
            min_cube_layers,
            group,
            camera,
            lights,
            objects,
            light_lists,
            draw_lights,
            cookie_texels,
            cookie_view,
            cookie_key: Vec::new(),
            compose,
            light_planes,
            shadow_atlas,
            shadow_view,
            shadow_sampler,
            shadow_table,
            shadow_table_view,
            shadow_cubes,
            shadow_cubes_view,
            shadow_cube_layers,
            shadow_indirection,
            shadow_indirection_view,
            indirection_sampler,
        }
    }

    fn shadow_views(&self) -> ShadowViews<'_> {
        ShadowViews {
            atlas: &self.shadow_view,
            sampler: &self.shadow_sampler,
            table: &self.shadow_table_view,
            cubes: &self.shadow_cubes_view,
            indirection: &self.shadow_indirection_view,
            indirection_sampler: &self.indirection_sampler,
        }
    }

    fn bind(
        device: &wgpu::Device,
        bgl: &wgpu::BindGroupLayout,
        buffers: [&wgpu::Buffer; 5],
        planes: &wgpu::Buffer,
        cookies: &wgpu::TextureView,
        shadow: ShadowViews<'_>,
    ) -> wgpu::BindGroup {
        let mut resources: Vec<wgpu::BindingResource<'_>> = buffers.iter().map(|b| b.as_entire_binding()).collect();
        resources.extend((0..LIGHT_PLANE_COUNT as u64).map(|k| {
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: planes,
                offset: k * LIGHT_PLANE_BYTES,
                size: wgpu::BufferSize::new(LIGHT_PLANE_BYTES),
            })
        }));
        resources.extend([
            wgpu::BindingResource::TextureView(cookies),
            wgpu::BindingResource::TextureView(shadow.atlas),
            wgpu::BindingResource::Sampler(shadow.sampler),
            wgpu::BindingResource::TextureView(shadow.table),
            wgpu::BindingResource::TextureView(shadow.cubes),
            wgpu::BindingResource::TextureView(shadow.indirection),
            wgpu::BindingResource::Sampler(shadow.indirection_sampler),
        ]);
        let entries = crate::renderer::kit::bindings::FRAME.entries(resources);
        device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("frame"), layout: bgl, entries: &entries })
    }

    /// Binds the buffers again for another pipeline configuration's layout.
    pub fn rebind(&mut self, device: &wgpu::Device, frame_bgl: &wgpu::BindGroupLayout) {
        let buffers = [&self.camera, &self.lights, &self.objects, &self.light_lists, &self.draw_lights];
        self.group = Self::bind(device, frame_bgl, buffers, &self.light_planes, &self.cookie_view, self.shadow_views());
    }

    /// The shadow pass's group 0 (`bindings::SHADOW_CASTER_SLOTS`) for `bgl`.
    pub fn caster_group(&self, device: &wgpu::Device, bgl: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
        let entries = [
            wgpu::BindGroupEntry { binding: 2, resource: self.objects.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 52, resource: wgpu::BindingResource::TextureView(&self.shadow_table_view) },
        ];
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow casters"),
            layout: bgl,
            entries: &entries,
        })
    }

    /// Side of the shadow atlas as allocated.
    pub fn shadow_side(&self) -> u32 {
        self.shadow_atlas.width()
    }

    /// Reallocates the cube array (`--shadow-cube array`) when its face side, layer count or
    /// format differs from `side` x `layers` in `format` (0 layers: the 1x1 stand-in),
    /// rebinding the frame group.
    pub fn ensure_shadow_cubes(
        &mut self,
        device: &wgpu::Device,
        frame_bgl: &wgpu::BindGroupLayout,
        (side, layers): (u32, u32),
        format: wgpu::TextureFormat,
    ) {
        let min = self.min_cube_layers;
        let (side, layers) = if layers == 0 { (1, min) } else { (side.max(1), (layers.div_ceil(6) * 6).max(min)) };
        let t = &self.shadow_cubes;
        if t.width() != side || t.depth_or_array_layers() != layers || t.format() != format {
            (self.shadow_cubes, self.shadow_cubes_view, self.shadow_cube_layers) =
                shadow_cubes(device, side, layers, format);
            self.rebind(device, frame_bgl);
        }
    }

    /// Makes the indirection cube (`--shadow-cube indirect`) at `side` texels a face when it has
    /// another side, rebinding the frame group; `side` 0 (no cube read through it this frame)
    /// keeps what there is, so that a cube leaving and entering the view writes it once.
    pub fn ensure_shadow_indirection(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame_bgl: &wgpu::BindGroupLayout,
        side: u32,
    ) {
        if side > 0 && self.shadow_indirection.width() != side {
            (self.shadow_indirection, self.shadow_indirection_view) = shadow_indirection(device, Some(queue), side);
            self.rebind(device, frame_bgl);
        }
    }

    /// Reallocates the shadow atlas at `side` texels square in `format` when it has another
    /// size or format, and
    /// writes the frame's shadow parameters, tiles and casters (their light indices, four a
    /// texel, after the tiles: `ShadowParams::counts`).
    #[allow(clippy::too_many_arguments)]
    pub fn upload_shadows(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame_bgl: &wgpu::BindGroupLayout,
        (side, format): (u32, wgpu::TextureFormat),
        tiles: &[ShadowTile],
        params: &ShadowParams,
        casters: &[u32],
    ) {
        let mut rebind = false;
        if self.shadow_atlas.width() != side || self.shadow_atlas.format() != format {
            (self.shadow_atlas, self.shadow_view) = shadow_atlas(device, side.max(1), format);
            rebind = true;
        }
        let per_row = 4 * SHADOW_TABLE_WIDTH as usize;
        debug_assert_eq!(params.counts[2] as usize, tiles.len() + 1);
        let rows = (tiles.len() + 1 + casters.len().div_ceil(per_row)) as u32;
        if self.shadow_table.height() < rows {
            (self.shadow_table, self.shadow_table_view) = shadow_table(device, rows.next_power_of_two());
            rebind = true;
        }
        let row = 16 * SHADOW_TABLE_WIDTH as usize;
        let mut bytes = vec![0u8; row * rows as usize];
        bytes[..std::mem::size_of::<ShadowParams>()].copy_from_slice(bytemuck::bytes_of(params));
        let tiles_end = row * (tiles.len() + 1);
        bytes[row..tiles_end].copy_from_slice(bytemuck::cast_slice(tiles));
        bytes[tiles_end..tiles_end + 4 * casters.len()].copy_from_slice(bytemuck::cast_slice(casters));
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.shadow_table,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &bytes,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row as u32), rows_per_image: Some(rows) },
            wgpu::Extent3d { width: SHADOW_TABLE_WIDTH, height: rows, depth_or_array_layers: 1 },
        );
        if rebind {
            self.rebind(device, frame_bgl);
        }
    }

    /// Writes the frame's records, growing the buffers (to the next power of two) as needed.
    pub fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame_bgl: &wgpu::BindGroupLayout,
        records: &FrameRecords,
        lists: FrameLists<'_>,
        scene: &Scene,
    ) {
        let mut grown = false;
        let mut fit = |buffer: &mut wgpu::Buffer, label: &str, bytes: &[u8]| {
            let need = bytes.len().max(1) as u64;
            if buffer.size() < need {
                *buffer = storage(device, label, need.next_power_of_two());
                grown = true;
            }
            if !bytes.is_empty() {
                queue.write_buffer(buffer, 0, bytes);
            }
        };
        fit(&mut self.lights, "lights", bytemuck::cast_slice(&records.lights));
        fit(&mut self.objects, "objects", bytemuck::cast_slice(&records.objects));
        fit(&mut self.light_lists, "light lists", bytemuck::cast_slice(lists.forward));
        fit(&mut self.draw_lights, "draw lights", bytemuck::cast_slice(lists.draw));
        let key: Vec<u64> = scene.cookies.iter().map(|c| c.id()).collect();
        if key != self.cookie_key {
            let mut words = cookie_words(scene);
            let rows = (words.len() as u32).div_ceil(COOKIE_ROW);
            let width = if rows > 1 { COOKIE_ROW } else { words.len() as u32 };
            words.resize((width * rows) as usize, 0);
            let size = self.cookie_texels.size();
            if size.width != width || size.height != rows {
                self.cookie_texels = cookie_texture(device, width, rows);
                self.cookie_view = self.cookie_texels.create_view(&Default::default());
                grown = true;
            }
            queue.write_texture(
                self.cookie_texels.as_image_copy(),
                bytemuck::cast_slice(&words),
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(width * 4), rows_per_image: Some(rows) },
                wgpu::Extent3d { width, height: rows, depth_or_array_layers: 1 },
            );
            self.cookie_key = key;
        }
        if grown {
            self.rebind(device, frame_bgl);
        }
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&records.camera));
    }

    /// Writes the light planes ([`light_planes`]) for a frame whose shaders read them
    /// (`ShaderFeatures::light_planes`); an error if the frame's lights do not fit them.
    pub fn upload_light_planes(&self, queue: &wgpu::Queue, lights: &[LightRecord]) -> anyhow::Result<()> {
        if lights.is_empty() {
            return Ok(());
        }
        let packed = light_planes(lights)
            .filter(|_| lights.len() <= UNIFORM_LIGHTS)
            .ok_or_else(|| anyhow::anyhow!("the light planes cannot hold this frame's {} lights", lights.len()))?;
        for (k, plane) in packed.chunks_exact(lights.len()).enumerate() {
            queue.write_buffer(&self.light_planes, k as u64 * LIGHT_PLANE_BYTES, bytemuck::cast_slice(plane));
        }
        Ok(())
    }

    /// Writes compose slot `slot` and returns its dynamic offset.
    pub fn compose_slot(&self, queue: &wgpu::Queue, slot: u64, params: ComposeParams) -> u32 {
        queue.write_buffer(&self.compose, slot * COMPOSE_SLOT, bytemuck::bytes_of(&params));
        (slot * COMPOSE_SLOT) as u32
    }
}
