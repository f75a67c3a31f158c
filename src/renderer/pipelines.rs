//! Every pipeline of the frame, built from one shader module per G-buffer layout.
//! Depth and stencil states are written as the seeds give them (standard depth: near = 0);
//! [`Pipelines::z`] flips the compare functions when reversed Z is on.

use super::gbuffer::{GBufferLayout, GBufferTargets};
use super::settings::DebugView;
use wgpu::{CompareFunction as Cmp, StencilOperation as Op};

pub const DEBUG_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const LIGHT_KIND_POINT: u32 = 0;
pub const LIGHT_KIND_SPOT: u32 = 1;
/// Format of the HDR scene colour that scenes with blended surfaces compose through.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Material flags (`GpuObject.info.x`).
pub const MAT_NORMAL_MAP: u32 = 1;
pub const MAT_METAL_ROUGH: u32 = 2;

/// Whether an accumulation target of `format` holds seed 004's logarithmic encoding
/// (`AccumFormat::Rgba8Log` is the only one stored as Rgba8Unorm).
pub fn log_accum(format: wgpu::TextureFormat) -> bool {
    format == wgpu::TextureFormat::Rgba8Unorm
}

/// WGSL constants generated from Rust enums, so the two never drift apart.
pub fn wgsl_constants() -> String {
    let mut s =
        format!("const LS_LIGHT_POINT: u32 = {LIGHT_KIND_POINT}u;\nconst LS_LIGHT_SPOT: u32 = {LIGHT_KIND_SPOT}u;\n");
    s += &format!(
        "const LS_MAT_NORMAL_MAP: u32 = {MAT_NORMAL_MAP}u;\nconst LS_MAT_METAL_ROUGH: u32 = {MAT_METAL_ROUGH}u;\n"
    );
    s += &format!("const LS_LOG_ACCUM_MAX: f32 = {:?};\n", super::settings::LOG_ACCUM_MAX);
    for v in DebugView::ALL {
        s += &format!("const LS_VIEW_{}: u32 = {}u;\n", v.wgsl_name(), v as u32);
    }
    s
}

pub fn shader_source(layout: &GBufferLayout, accum_format: wgpu::TextureFormat) -> String {
    [
        wgsl_constants(),
        format!("const LS_ACCUM_LOG: bool = {};\n", log_accum(accum_format)),
        layout.wgsl(1),
        include_str!("../../shaders/common.wgsl").to_string(),
        include_str!("../../shaders/geometry.wgsl").to_string(),
        include_str!("../../shaders/lights.wgsl").to_string(),
        include_str!("../../shaders/compose.wgsl").to_string(),
    ]
    .join("\n")
}

/// Key of everything the pipelines depend on.
#[derive(Clone, Debug, PartialEq)]
pub struct PipelineKey {
    pub layout: GBufferLayout,
    pub depth_format: wgpu::TextureFormat,
    pub output_format: wgpu::TextureFormat,
    pub reversed_z: bool,
    /// Format of the diffuse and specular light accumulation targets.
    pub accum_format: wgpu::TextureFormat,
    /// Depth clamp (`unclipped_depth`) on light volumes.
    pub depth_clamp: bool,
}

pub struct Pipelines {
    pub key: PipelineKey,
    pub frame_bgl: wgpu::BindGroupLayout,
    pub gbuffer_bgl: wgpu::BindGroupLayout,
    pub compose_bgl: wgpu::BindGroupLayout,
    /// A material's textures and sampler (group 1 of the geometry and forward pipelines).
    pub material_bgl: wgpu::BindGroupLayout,
    /// The HDR scene colour for the tonemap pass (group 3).
    pub hdr_bgl: wgpu::BindGroupLayout,
    /// G-buffer pipelines by [`Pipelines::geometry_index`]: opaque or masked, one- or two-sided.
    pub geometry: [wgpu::RenderPipeline; 4],
    /// Forward pass for blended surfaces, one- and two-sided.
    pub forward: [wgpu::RenderPipeline; 2],
    pub compose_hdr: wgpu::RenderPipeline,
    pub tonemap: wgpu::RenderPipeline,
    pub ambient: wgpu::RenderPipeline,
    pub light_fullscreen: wgpu::RenderPipeline,
    pub light_volume: wgpu::RenderPipeline,
    pub two_pass_mark: wgpu::RenderPipeline,
    pub two_pass_shade: wgpu::RenderPipeline,
    pub invert_mark: wgpu::RenderPipeline,
    pub invert_shade: wgpu::RenderPipeline,
    pub replace_mark: wgpu::RenderPipeline,
    pub replace_shade_front: wgpu::RenderPipeline,
    pub replace_shade_back: wgpu::RenderPipeline,
    pub stencil_clear: wgpu::RenderPipeline,
    pub ideal: wgpu::RenderPipeline,
    pub classify_blue: wgpu::RenderPipeline,
    pub classify_red: wgpu::RenderPipeline,
    pub classify_green: wgpu::RenderPipeline,
    pub complexity: wgpu::RenderPipeline,
    pub coverage: wgpu::RenderPipeline,
    pub coverage_fullscreen: wgpu::RenderPipeline,
    pub complexity_fullscreen: wgpu::RenderPipeline,
    pub compose: wgpu::RenderPipeline,
}

fn stencil_face(compare: Cmp, fail: Op, depth_fail: Op, pass: Op) -> wgpu::StencilFaceState {
    wgpu::StencilFaceState { compare, fail_op: fail, depth_fail_op: depth_fail, pass_op: pass }
}

fn stencil(front: wgpu::StencilFaceState, back: wgpu::StencilFaceState) -> wgpu::StencilState {
    wgpu::StencilState { front, back, read_mask: 0xff, write_mask: 0xff }
}

const KEEP: wgpu::StencilFaceState = wgpu::StencilFaceState::IGNORE;

const ADDITIVE: wgpu::BlendState = wgpu::BlendState {
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
const MULTIPLY: wgpu::BlendState = wgpu::BlendState {
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

const MAX: wgpu::BlendState = wgpu::BlendState {
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

/// Which colour targets a light-pass pipeline writes.
#[derive(Clone, Copy)]
enum Out {
    /// Diffuse + specular accumulation, additive.
    Accumulate,
    /// Same targets, colour writes off (stencil marking).
    NoColor,
    /// Same targets, replace (the ambient + sun pass starts the accumulation).
    Replace,
    /// The debug target with a blend.
    Debug(wgpu::BlendState),
}

#[derive(Clone, Copy)]
enum Vs {
    Fullscreen,
    FullscreenPlain,
    Volume,
}

struct LightPipe {
    label: &'static str,
    vs: Vs,
    fs: &'static str,
    cull: Option<wgpu::Face>,
    depth: Cmp,
    stencil: wgpu::StencilState,
    out: Out,
}

impl Pipelines {
    pub fn geometry_index(masked: bool, double_sided: bool) -> usize {
        masked as usize * 2 + double_sided as usize
    }

    /// Maps a compare function written for standard depth to the depth convention in use.
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

    pub fn new(device: &wgpu::Device, key: PipelineKey) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(key.layout.name),
            source: wgpu::ShaderSource::Wgsl(shader_source(&key.layout, key.accum_format).into()),
        });
        let vis = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: vis,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let frame_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                // The camera: read-only storage rather than uniform (see shaders/common.wgsl).
                storage(0),
                storage(1),
                storage(2),
                storage(3),
            ],
        });
        let gbuffer_bgl = GBufferTargets::bind_group_layout(device, &key.layout);
        let tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let compose_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("compose"),
            entries: &[
                tex(0),
                tex(1),
                tex(2),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(16),
                    },
                    count: None,
                },
            ],
        });
        let material_tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let material_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material"),
            entries: &[
                material_tex(10),
                material_tex(11),
                material_tex(12),
                material_tex(13),
                wgpu::BindGroupLayoutEntry {
                    binding: 14,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let hdr_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hdr colour"),
            entries: &[tex(0)],
        });
        let geometry_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("geometry"),
            bind_group_layouts: &[Some(&frame_bgl), Some(&material_bgl)],
            immediate_size: 0,
        });
        let tonemap_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tonemap"),
            bind_group_layouts: &[Some(&frame_bgl), Some(&gbuffer_bgl), Some(&compose_bgl), Some(&hdr_bgl)],
            immediate_size: 0,
        });
        let light_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lights"),
            bind_group_layouts: &[Some(&frame_bgl), Some(&gbuffer_bgl)],
            immediate_size: 0,
        });
        let compose_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("compose"),
            bind_group_layouts: &[Some(&frame_bgl), Some(&gbuffer_bgl), Some(&compose_bgl)],
            immediate_size: 0,
        });

        let z = |c| Self::z(key.reversed_z, c);
        let vertex_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<crate::scene::Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4],
        })];
        // Surfaces: the G-buffer pass (opaque and masked) and the forward pass (blended).
        let surface = |label: &str, fs: &str, double_sided: bool, targets: &[Option<wgpu::ColorTargetState>], write| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&geometry_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_geometry"),
                    compilation_options: Default::default(),
                    buffers: &vertex_buffers,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: if double_sided { None } else { Some(wgpu::Face::Back) },
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: key.depth_format,
                    depth_write_enabled: Some(write),
                    depth_compare: Some(z(if write { Cmp::Less } else { Cmp::LessEqual })),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let gbuffer_targets: Vec<Option<wgpu::ColorTargetState>> =
            key.layout.targets.iter().map(|t| Some(t.format.into())).collect();
        let geometry = [
            surface("geometry", "fs_geometry", false, &gbuffer_targets, true),
            surface("geometry (two-sided)", "fs_geometry", true, &gbuffer_targets, true),
            surface("geometry (masked)", "fs_geometry_masked", false, &gbuffer_targets, true),
            surface("geometry (masked, two-sided)", "fs_geometry_masked", true, &gbuffer_targets, true),
        ];
        let blended = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let forward = [
            surface("forward (blended)", "fs_forward", false, &blended, false),
            surface("forward (blended, two-sided)", "fs_forward", true, &blended, false),
        ];
        let fullscreen_pass = |label: &str, layout: &wgpu::PipelineLayout, fs: &str, format: wgpu::TextureFormat| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_compose"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(format.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };

        let volume_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: 16,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4],
        })];
        let light = |p: LightPipe| {
            let accum_targets = |blend: Option<wgpu::BlendState>, mask| {
                vec![
                    Some(wgpu::ColorTargetState { format: key.accum_format, blend, write_mask: mask }),
                    Some(wgpu::ColorTargetState { format: key.accum_format, blend, write_mask: mask }),
                ]
            };
            let targets = match p.out {
                Out::Accumulate => accum_targets(
                    Some(if log_accum(key.accum_format) { MULTIPLY } else { ADDITIVE }),
                    wgpu::ColorWrites::ALL,
                ),
                Out::NoColor => accum_targets(None, wgpu::ColorWrites::empty()),
                Out::Replace => accum_targets(None, wgpu::ColorWrites::ALL),
                Out::Debug(blend) => vec![Some(wgpu::ColorTargetState {
                    format: DEBUG_FORMAT,
                    blend: Some(blend),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            };
            let (entry, buffers): (&str, &[Option<wgpu::VertexBufferLayout>]) = match p.vs {
                Vs::Fullscreen => ("vs_fullscreen", &[]),
                Vs::FullscreenPlain => ("vs_fullscreen_plain", &[]),
                Vs::Volume => ("vs_volume", &volume_buffers),
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(p.label),
                layout: Some(&light_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: p.cull,
                    unclipped_depth: key.depth_clamp && matches!(p.vs, Vs::Volume),
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: key.depth_format,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(z(p.depth)),
                    stencil: p.stencil,
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(p.fs),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let none = stencil(KEEP, KEEP);
        // Seed 000 pass 1: front faces, no colour, Z LessEqual, Z-fail increments (saturate).
        let two_pass_mark_stencil = stencil(stencil_face(Cmp::Always, Op::Keep, Op::IncrementClamp, Op::Keep), KEEP);
        // Seed 000 pass 2: back faces, Z GreaterEqual, stencil Equal 0, always writes zero.
        let two_pass_shade_stencil = {
            let f = stencil_face(Cmp::Equal, Op::Zero, Op::Zero, Op::Zero);
            stencil(f, f)
        };
        let invert = stencil_face(Cmp::Always, Op::Keep, Op::Invert, Op::Keep);
        let ll =
            |label, vs, fs, cull, depth, stencil, out| light(LightPipe { label, vs, fs, cull, depth, stencil, out });
        use wgpu::Face::{Back, Front};
        Self {
            ambient: ll(
                "ambient+sun",
                Vs::FullscreenPlain,
                "fs_ambient",
                None,
                Cmp::Always,
                none.clone(),
                Out::Replace,
            ),
            light_fullscreen: ll(
                "light fullscreen",
                Vs::Fullscreen,
                "fs_light",
                None,
                Cmp::Always,
                none.clone(),
                Out::Accumulate,
            ),
            // Back faces at or behind the scene point: the point is in front of the far side.
            light_volume: ll(
                "light volume",
                Vs::Volume,
                "fs_light",
                Some(Front),
                Cmp::GreaterEqual,
                none.clone(),
                Out::Accumulate,
            ),
            two_pass_mark: ll(
                "two-pass mark",
                Vs::Volume,
                "fs_no_color",
                Some(Back),
                Cmp::LessEqual,
                two_pass_mark_stencil.clone(),
                Out::NoColor,
            ),
            two_pass_shade: ll(
                "two-pass shade",
                Vs::Volume,
                "fs_light",
                Some(Front),
                Cmp::GreaterEqual,
                two_pass_shade_stencil.clone(),
                Out::Accumulate,
            ),
            // Seed 001: double-sided, Z Less, Z-fail inverts on both faces. A scene point inside
            // the volume fails only against the back face: odd count, non-zero stencil.
            invert_mark: ll(
                "invert mark",
                Vs::Volume,
                "fs_no_color",
                None,
                Cmp::Less,
                stencil(invert, invert),
                Out::NoColor,
            ),
            // Back faces, depth test off, stencil NotEqual 0, pass op Zero clears for the next light.
            invert_shade: ll(
                "invert shade",
                Vs::Volume,
                "fs_light",
                Some(Front),
                Cmp::Always,
                {
                    let f = stencil_face(Cmp::NotEqual, Op::Keep, Op::Keep, Op::Zero);
                    stencil(f, f)
                },
                Out::Accumulate,
            ),
            // Seed 002 with REPLACE. Which faces: the mark draws BACK faces with Z Less, so Z
            // fails (REPLACE X) exactly where the scene point is at or in front of the far
            // side. The shade draws FRONT faces with Z LessEqual and stencil Equal X: the point
            // is also at or behind the near side, i.e. inside. Where no front face exists
            // (camera inside, volume crossing the near plane) the shade draws back faces with
            // the depth test off instead; stencil Equal X alone is then exact. Values X = 1..255
            // differ per light, so the stencil is cleared only once every 255 lights.
            replace_mark: ll(
                "replace mark",
                Vs::Volume,
                "fs_no_color",
                Some(Front),
                Cmp::Less,
                {
                    let f = stencil_face(Cmp::Always, Op::Keep, Op::Replace, Op::Keep);
                    stencil(f, f)
                },
                Out::NoColor,
            ),
            replace_shade_front: ll(
                "replace shade (front faces)",
                Vs::Volume,
                "fs_light",
                Some(Back),
                Cmp::LessEqual,
                {
                    let f = stencil_face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep);
                    stencil(f, f)
                },
                Out::Accumulate,
            ),
            replace_shade_back: ll(
                "replace shade (back faces)",
                Vs::Volume,
                "fs_light",
                Some(Front),
                Cmp::Always,
                {
                    let f = stencil_face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep);
                    stencil(f, f)
                },
                Out::Accumulate,
            ),
            stencil_clear: ll(
                "stencil clear",
                Vs::FullscreenPlain,
                "fs_no_color",
                None,
                Cmp::Always,
                {
                    let f = stencil_face(Cmp::Always, Op::Zero, Op::Zero, Op::Zero);
                    stencil(f, f)
                },
                Out::NoColor,
            ),
            ideal: ll("ideal count", Vs::Fullscreen, "fs_ideal", None, Cmp::Always, none.clone(), Out::NoColor),
            classify_blue: ll(
                "classify: pass 1 Z",
                Vs::Volume,
                "fs_blue",
                Some(Back),
                Cmp::LessEqual,
                two_pass_mark_stencil.clone(),
                Out::Debug(MAX),
            ),
            classify_red: ll(
                "classify: pass 2 Z",
                Vs::Volume,
                "fs_red",
                Some(Front),
                Cmp::GreaterEqual,
                none.clone(),
                Out::Debug(MAX),
            ),
            classify_green: ll(
                "classify: pass 2 stencil",
                Vs::Volume,
                "fs_green",
                Some(Front),
                Cmp::GreaterEqual,
                two_pass_shade_stencil.clone(),
                Out::Debug(MAX),
            ),
            // Light complexity counts the points inside each light's true shape (the shader
            // discards the rest), drawn as the plain volume method draws the light.
            complexity: ll(
                "light complexity",
                Vs::Volume,
                "fs_complexity",
                Some(Front),
                Cmp::GreaterEqual,
                none.clone(),
                Out::Debug(ADDITIVE),
            ),
            coverage: ll("coverage", Vs::Volume, "fs_no_color", Some(Front), Cmp::Always, none.clone(), Out::NoColor),
            coverage_fullscreen: ll(
                "coverage (full-screen)",
                Vs::Fullscreen,
                "fs_no_color",
                None,
                Cmp::Always,
                none.clone(),
                Out::NoColor,
            ),
            complexity_fullscreen: ll(
                "light complexity (full-screen)",
                Vs::Fullscreen,
                "fs_complexity",
                None,
                Cmp::Always,
                none.clone(),
                Out::Debug(ADDITIVE),
            ),
            compose: fullscreen_pass("compose", &compose_layout, "fs_compose", key.output_format),
            compose_hdr: fullscreen_pass("compose (HDR)", &compose_layout, "fs_compose_hdr", HDR_FORMAT),
            tonemap: fullscreen_pass("tonemap", &tonemap_layout, "fs_tonemap", key.output_format),
            forward,
            material_bgl,
            hdr_bgl,
            geometry,
            frame_bgl,
            gbuffer_bgl,
            compose_bgl,
            key,
        }
    }
}
