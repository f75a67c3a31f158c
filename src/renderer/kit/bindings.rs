//! The bind groups the shaders declare, as data: each table below writes both the WGSL
//! declarations (prepended to the shader source) and the `wgpu::BindGroupLayout`, so a binding
//! number or a type is written once. The G-buffer's group is generated the same way by
//! `GBufferLayout::wgsl`.
//!
//! Uniform buffers are kept to one use: Mesa 22.3's lavapipe recompiles a shader whose
//! branches read a uniform buffer *at a constant offset* every time that buffer is written, and
//! keeps the old compilation (about 0.4 MB per draw; `tests/it/soak.rs`). Everything the shaders
//! read per frame is read-only storage, except the light planes ([`Kind::LightPlane`]), which
//! are only ever read at a light's index, an offset no compiler can inline;
//! `tests/it/shader_contract.rs` checks that no other `var<uniform>` appears.

use std::fmt::Write;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `var<storage, read>`; `dynamic` with a dynamic offset of `min_size` bytes' binding.
    Storage { dynamic: bool, min_size: u64 },
    /// `var<uniform>`: one of the [`LIGHT_PLANES`] arrays of `UNIFORM_LIGHTS` vec4s, the
    /// per-light loops' copy of the light records (`light_at` in common.wgsl). On lavapipe a
    /// storage-buffer load at a per-pixel index is a loop over the 8 lanes with a branch in each,
    /// once per scalar; a uniform load is one gather (`records::LightPlanes`).
    LightPlane,
    /// `var<storage, read_write>`: written by a compute pass or counted into with atomics
    /// (compute and fragment stages only).
    StorageReadWrite,
    /// A 2D float texture, filterable or not.
    Texture { filterable: bool },
    /// A filtering sampler.
    Sampler,
    /// A 2D depth texture (`texture_depth_2d`), read through a comparison sampler.
    DepthTexture,
    /// A cube-array depth texture (`texture_depth_cube_array`), read through a comparison
    /// sampler (`--shadow-cube array`).
    DepthCubeArray,
    /// A float cube texture (`texture_cube<f32>`; `--shadow-cube indirect`'s indirection).
    CubeTexture,
    /// A comparison sampler (`sampler_comparison`): hardware 2x2 PCF.
    ComparisonSampler,
    /// A 2D unsigned-integer texture (`texture_2d<u32>`) of records, read with `textureLoad` in
    /// every stage: a table that does not take a storage-buffer slot (WebGPU's default limit of
    /// 8 per stage is already met by the frame and post groups).
    UintTexture,
}

#[derive(Clone, Copy, Debug)]
pub struct Binding {
    pub slot: u32,
    pub name: &'static str,
    /// The WGSL type: a struct, `array<…>`, `texture_2d<f32>`, `sampler`.
    pub wgsl_type: &'static str,
    pub kind: Kind,
}

/// A bind group: its index in the pipeline layouts and its bindings.
pub struct Group {
    pub label: &'static str,
    pub index: u32,
    pub bindings: &'static [Binding],
}

const fn storage(slot: u32, name: &'static str, wgsl_type: &'static str) -> Binding {
    Binding { slot, name, wgsl_type, kind: Kind::Storage { dynamic: false, min_size: 0 } }
}

const fn light_plane(slot: u32, name: &'static str) -> Binding {
    Binding { slot, name, wgsl_type: "array<vec4<u32>, 4096>", kind: Kind::LightPlane }
}

// `light_plane`'s WGSL array length is [`UNIFORM_LIGHTS`].
const _: () = assert!(UNIFORM_LIGHTS == 4096);

/// The light planes' slots in [`FRAME`], plane by plane.
pub const LIGHT_PLANES: [u32; 4] = [6, 7, 8, 9];

const fn texture(slot: u32, name: &'static str, filterable: bool) -> Binding {
    Binding { slot, name, wgsl_type: "texture_2d<f32>", kind: Kind::Texture { filterable } }
}

/// Group 0: what every pass reads once per frame (`records::FrameBuffers`).
pub const FRAME: Group = Group {
    label: "frame",
    index: 0,
    bindings: &[
        storage(0, "camera", "Camera"),
        storage(1, "lights", "array<GpuLight>"),
        storage(2, "objects", "array<GpuObject>"),
        // Per forward-shaded object, the lights that reach it (indices into `lights`).
        storage(3, "light_lists", "array<u32>"),
        // The light of each instance of a light draw (`batches::LightBatches::list`).
        storage(4, "draw_lights", "array<u32>"),
        // The light records again, for scenes of up to `UNIFORM_LIGHTS` lights without cookies:
        // plane k holds vec4 k of every light (`records::LightPlanes`, `light_at` in
        // common.wgsl). Slots 6-9.
        light_plane(6, "light_plane0"),
        light_plane(7, "light_plane1"),
        light_plane(8, "light_plane2"),
        light_plane(9, "light_plane3"),
        // Every cookie's texels, one after the other in rows of `records::COOKIE_ROW` (an
        // Rgba8Unorm texture read with textureLoad: a storage buffer would pass the 8 a stage
        // may bind in the post passes; `records::cookie_words`, seed 004).
        texture(5, "cookie_texels", false),
        // The shadow atlas, its comparison sampler, and the shadow table: row 0 the
        // frame's `ShadowParams`, row 1 + i tile i's `ShadowTile`, as their bytes
        // (`records::SHADOW_TABLE_WIDTH` Rgba32Uint texels a row; `shadow_params_load` and
        // `shadow_tile_load` in common.wgsl). Slots from 50.
        Binding { slot: 50, name: "shadow_atlas", wgsl_type: "texture_depth_2d", kind: Kind::DepthTexture },
        Binding { slot: 51, name: "shadow_sampler", wgsl_type: "sampler_comparison", kind: Kind::ComparisonSampler },
        Binding { slot: 52, name: "shadow_table", wgsl_type: "texture_2d<u32>", kind: Kind::UintTexture },
        // `--shadow-cube array`: the cubes' faces, six layers a light (a 1x1 stand-in of
        // `Quirks::min_cube_layers` layers otherwise; `ls_shadow`'s `shadow_cube_lookup`). A sampled texture, not a storage
        // buffer; the fragment stage's sampled textures stay within WebGPU's default 16.
        Binding { slot: 53, name: "shadow_cubes", wgsl_type: "texture_depth_cube_array", kind: Kind::DepthCubeArray },
        // `--shadow-cube indirect`: seed 002's indirection cube (`shadows::indirection_texels`;
        // a 1x1 stand-in otherwise) and its nearest-filtering sampler.
        Binding { slot: 54, name: "shadow_indirection", wgsl_type: "texture_cube<f32>", kind: Kind::CubeTexture },
        Binding { slot: 55, name: "indirection_sampler", wgsl_type: "sampler", kind: Kind::Sampler },
    ],
};

/// The frame bindings the shadow pass's casters read (objects and the shadow table): its
/// group 0 is this subset of [`FRAME`], without the atlas it renders into.
pub const SHADOW_CASTER_SLOTS: [u32; 2] = [2, 52];

/// Group 1 of the surface passes: a material's maps and sampler. The G-buffer takes group 1 in
/// the lighting passes; the material's slots start at 10 so the two never share a number.
pub const MATERIAL: Group = Group {
    label: "material",
    index: 1,
    bindings: &[
        texture(10, "base_color_tex", true),
        texture(11, "normal_tex", true),
        texture(12, "emissive_tex", true),
        texture(13, "metal_rough_tex", true),
        Binding { slot: 14, name: "material_sampler", wgsl_type: "sampler", kind: Kind::Sampler },
        // Seed 004's lightmap (`scene::Lightmap`), read at TEXCOORD_1, level 0.
        texture(15, "lightmap_tex", true),
    ],
};

/// Size of one compose-parameter record as bound (a dynamic offset selects the slot).
pub const COMPOSE_PARAMS_SIZE: u64 = std::mem::size_of::<crate::renderer::records::ComposeParams>() as u64;

/// Group 2 of the compose passes: the light accumulation, the debug target and the parameters.
pub const COMPOSE: Group = Group {
    label: "compose",
    index: 2,
    bindings: &[
        texture(0, "light_diffuse", false),
        texture(1, "light_specular", false),
        texture(2, "debug_tex", false),
        Binding {
            slot: 3,
            name: "compose",
            wgsl_type: "ComposeParams",
            kind: Kind::Storage { dynamic: true, min_size: COMPOSE_PARAMS_SIZE },
        },
    ],
};

/// Group 3 of the tonemap pass: the HDR scene colour (only scenes with blended surfaces compose
/// through it).
pub const HDR: Group = Group { label: "hdr colour", index: 3, bindings: &[texture(0, "hdr_color", false)] };

/// Group 2 of the tiled and clustered passes (`culling::tiled::pass`): their parameters, the light
/// lists (a (first, count) pair per tile or cluster, then the entries) and the counters (the
/// list allocator, then one light-pixel pair count per light). Clustered lists built on the
/// GPU keep a counter per cluster after the lights' counts, and each light's span of clusters
/// (`tiles::Span`, 4 words) after the list entries. Slots from 20, apart from the compose
/// group's.
pub const TILES: Group = Group {
    label: "tiles",
    index: 2,
    bindings: &[
        storage(20, "tile_params", "TileParams"),
        Binding { slot: 21, name: "tile_lists", wgsl_type: "array<u32>", kind: Kind::StorageReadWrite },
        Binding { slot: 22, name: "tile_counts", wgsl_type: "array<atomic<u32>>", kind: Kind::StorageReadWrite },
    ],
};

/// Group 2 of the post chain's passes (`post::{bloom, exposure, tonemap}` and the effects): its
/// parameters, the image a pass reads and a second one (bloom's levels), the exposure state
/// (histogram bins, adapted and measured log2 luminance, `post::STATE_WORDS`) and the grading
/// LUT (`size`³ entries, red fastest). Slots from 30.
pub const POST: Group = Group {
    label: "post",
    index: 2,
    bindings: &[
        storage(30, "post_params", "PostParams"),
        texture(31, "post_src", false),
        texture(32, "post_aux", false),
        Binding { slot: 33, name: "post_state", wgsl_type: "array<atomic<u32>>", kind: Kind::StorageReadWrite },
        storage(34, "post_lut", "array<vec4<f32>>"),
    ],
};

/// Group 1 of the viewer's shadow-atlas view (`shadows::atlas_view`): the depth range
/// present in the atlas (`atlas_range[0]` least, `[1]` greatest stored depth below the clear
/// value, as f32 bits: positive floats order as their bits) and, in `[2]`, the side of the
/// image drawn. The atlas itself is `FRAME`'s `shadow_atlas`. Slots from 60.
pub const ATLAS_VIEW: Group = Group {
    label: "atlas view",
    index: 1,
    bindings: &[Binding {
        slot: 60,
        name: "atlas_range",
        wgsl_type: "array<atomic<u32>>",
        kind: Kind::StorageReadWrite,
    }],
};

/// Group 2 of depth peeling's layer passes (`surfaces::blended`): the opaque surfaces' depth
/// (fragments behind it are hidden) and the previous layer's (fragments at or in front of it
/// are peeled already), read with `textureLoad` as unfilterable float textures (depth in .r;
/// naga's GLSL backend declares a `texture_depth_2d` a shadow sampler, which cannot be
/// loaded from). Slots from 70.
pub const PEEL: Group = Group {
    label: "peel",
    index: 2,
    bindings: &[texture(70, "peel_opaque", false), texture(71, "peel_previous", false)],
};

/// Group 1 of depth peeling's last pass: the layers composited front to back (premultiplied
/// colour, coverage in alpha), laid over the scene colour.
pub const PEELED: Group = Group { label: "peeled layers", index: 1, bindings: &[texture(72, "peeled", false)] };

/// Every group above, in the order the shader source declares them.
/// Group 2 of the per-pixel light explanation (`explain`): the pixel and the light count
/// (`explain_params`: x, y, lights, a pad) and, per light, four vec4 of what its shading gave
/// there (`explain_out`, `explain::Raw`). Slots from 70.
pub const EXPLAIN: Group = Group {
    label: "explain",
    index: 2,
    bindings: &[
        storage(70, "explain_params", "array<u32>"),
        Binding { slot: 71, name: "explain_out", wgsl_type: "array<vec4<f32>>", kind: Kind::StorageReadWrite },
    ],
};

/// Group 3 of RIS's passes over kept reservoirs (`stochastic::reuse`): the header and this
/// frame's reservoirs, the final reservoirs (`reuse.wgsl`), and the denoiser's four regions
/// (`denoise.wgsl`), and the sums the views that average RIS's frames keep (`converge.wgsl`);
/// 16-byte stand-ins for those a frame does not use. Each its own binding, as one region may
/// fill WebGPU's 128 MiB binding at 1280x720: with the tiled pass's 8 that is 15 storage
/// buffers a stage (`reuse::STORAGE_BUFFERS`). Slots from 80.
pub const REUSE: Group = Group {
    label: "reuse",
    index: 3,
    bindings: &[
        Binding { slot: 80, name: "reuse", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
        Binding { slot: 81, name: "reuse_final", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
        Binding { slot: 82, name: "denoise_a", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
        Binding { slot: 83, name: "denoise_b", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
        Binding { slot: 84, name: "denoise_h0", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
        Binding { slot: 85, name: "denoise_h1", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
        Binding { slot: 86, name: "converge", wgsl_type: "array<vec4<u32>>", kind: Kind::StorageReadWrite },
    ],
};

pub const GROUPS: [&Group; 11] =
    [&FRAME, &MATERIAL, &COMPOSE, &HDR, &TILES, &POST, &ATLAS_VIEW, &PEEL, &PEELED, &EXPLAIN, &REUSE];

impl Group {
    /// The WGSL declarations of the group's bindings.
    pub fn wgsl(&self) -> String {
        let mut s = String::new();
        for b in self.bindings {
            let var = match b.kind {
                Kind::Storage { .. } => "var<storage, read>",
                Kind::StorageReadWrite => "var<storage, read_write>",
                Kind::LightPlane => "var<uniform>",
                Kind::Texture { .. }
                | Kind::Sampler
                | Kind::DepthTexture
                | Kind::DepthCubeArray
                | Kind::CubeTexture
                | Kind::ComparisonSampler
                | Kind::UintTexture => "var",
            };
            let _ = writeln!(s, "@group({}) @binding({}) {var} {}: {};", self.index, b.slot, b.name, b.wgsl_type);
        }
        s
    }

    pub fn layout(&self, device: &wgpu::Device) -> wgpu::BindGroupLayout {
        self.layout_of(device, |_| true)
    }

    /// The layout of the bindings whose slots `keep` accepts.
    pub fn layout_of(&self, device: &wgpu::Device, keep: impl Fn(u32) -> bool) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = self
            .bindings
            .iter()
            .filter(|b| keep(b.slot))
            .map(|b| wgpu::BindGroupLayoutEntry {
                binding: b.slot,
                visibility: match b.kind {
                    Kind::Storage { .. } => {
                        wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE
                    }
                    Kind::StorageReadWrite => wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    Kind::UintTexture | Kind::LightPlane => {
                        wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE
                    }
                    _ => wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                },
                ty: match b.kind {
                    Kind::Storage { dynamic, min_size } => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: dynamic,
                        min_binding_size: wgpu::BufferSize::new(min_size),
                    },
                    Kind::StorageReadWrite => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    Kind::LightPlane => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(LIGHT_PLANE_BYTES),
                    },
                    Kind::Texture { filterable } => wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    Kind::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    Kind::DepthTexture => wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    Kind::DepthCubeArray => wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::CubeArray,
                        multisampled: false,
                    },
                    Kind::CubeTexture => wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::Cube,
                        multisampled: false,
                    },
                    Kind::ComparisonSampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    Kind::UintTexture => wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Uint,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                },
                count: None,
            })
            .collect();
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(self.label), entries: &entries })
    }

    /// Bind group entries for `resources`, given in the table's order.
    pub fn entries<'a>(&self, resources: Vec<wgpu::BindingResource<'a>>) -> Vec<wgpu::BindGroupEntry<'a>> {
        debug_assert_eq!(resources.len(), self.bindings.len(), "{}: one resource per binding", self.label);
        self.bindings
            .iter()
            .zip(resources)
            .map(|(b, resource)| wgpu::BindGroupEntry { binding: b.slot, resource })
            .collect()
    }
}

/// The most lights the light planes hold (`bindings::Kind::LightPlane`): 4,096 vec4s a plane,
/// WebGPU's 64 KiB uniform binding.
pub const UNIFORM_LIGHTS: usize = 4096;

/// Bytes of one light plane.
pub const LIGHT_PLANE_BYTES: u64 = (UNIFORM_LIGHTS * 16) as u64;
