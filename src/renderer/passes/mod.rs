//! The frame's passes, one file each. A pass is a struct that builds its own pipelines in
//! `new(&Shared)` and records itself in `encode(&self, encoder, &FrameInputs, …)`. `Shared`
//! holds what they have in common: the configuration they are built for ([`PipelineKey`]), the
//! shader module (generated constants, bindings and G-buffer layout, then the WGSL files) and
//! the bind-group layouts.
//!
//! Depth and stencil states are written as the seeds give them (standard depth: near = 0);
//! [`z`] flips the compare functions when reversed Z is on.

use super::bindings;
use super::gbuffer::{GBufferLayout, GBufferTargets};
use super::plan::FramePlan;
use super::records::{self, FrameBuffers};
use super::scene_gpu::SceneGpu;
use super::settings::{self, DebugView, Settings};
use super::stats::{Queries, Span};
use super::targets::Targets;
use super::volumes::Volumes;
use std::sync::{Arc, OnceLock};
use wgpu::CompareFunction as Cmp;

/// Format of the debug target (stencil diagram, light complexity).
pub const DEBUG_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the HDR scene colour that scenes with blended surfaces compose through.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Whether an accumulation target of `format` holds seed 004's logarithmic encoding
/// (`AccumFormat::Rgba8Log` is the only one stored as Rgba8Unorm).
pub fn log_accum(format: wgpu::TextureFormat) -> bool {
    format == wgpu::TextureFormat::Rgba8Unorm
}

/// WGSL constants generated from Rust, so the two never drift apart.
pub fn wgsl_constants() -> String {
    let mut s = String::new();
    let mut u = |name: &str, v: u32| s += &format!("const LS_{name}: u32 = {v}u;\n");
    u("LIGHT_POINT", records::LIGHT_KIND_POINT);
    u("LIGHT_SPOT", records::LIGHT_KIND_SPOT);
    u("MAT_NORMAL_MAP", records::MAT_NORMAL_MAP);
    u("MAT_METAL_ROUGH", records::MAT_METAL_ROUGH);
    u("MAT_UV_TRANSFORMED", records::MAT_UV_TRANSFORMED);
    u("MAT_METAL_BY_PIXEL", records::MAT_METAL_BY_PIXEL);
    u("NO_COOKIE", records::NO_COOKIE);
    u("COOKIE_ROW", records::COOKIE_ROW);
    for b in crate::scene::Brdf::ALL {
        u(&format!("BRDF_{}", b.name().to_uppercase().replace('-', "_")), b.id());
    }
    for v in DebugView::ALL {
        u(&format!("VIEW_{}", v.wgsl_name()), v as u32);
    }
    for t in super::post::Tonemap::ALL {
        u(&format!("TONEMAP_{}", t.wgsl_name()), t as u32);
    }
    u("HIST_BINS", super::post::HIST_BINS);
    u("NO_SHADOW", records::NO_SHADOW);
    u("SHADOW_TABLE_WIDTH", records::SHADOW_TABLE_WIDTH);
    u("TILE_CHUNK", super::tiles::SHADE_CHUNK);
    u("TILE_ALL", super::tiles::ALL_LIGHTS);
    u("TILE_MAX_LIGHTS", super::tiles::GPU_LIST_MAX_LIGHTS);
    for f in [
        super::shadows::ShadowFilter::Pcf2x2,
        super::shadows::ShadowFilter::Pcf3x3,
        super::shadows::ShadowFilter::Poisson16,
    ] {
        u(&format!("SHADOW_FILTER_{}", f.name().to_uppercase()), f as u32);
    }
    for a in [super::post::Aa::Off, super::post::Aa::Edge, super::post::Aa::Fxaa] {
        u(&format!("AA_{}", a.name().to_uppercase()), a as u32);
    }
    let mut f = |name: &str, v: f32| s += &format!("const LS_{name}: f32 = {v:?};\n");
    f("LOG_ACCUM_MAX", settings::LOG_ACCUM_MAX);
    f("FP16_MAX", records::FP16_MAX);
    f("TILE_HEAT_MAX", super::tiles::HEAT_MAX);
    f("METAL_THRESHOLD", crate::scene::import::METAL_THRESHOLD);
    f("MAX_COC", super::post::MAX_COC);
    f("TILE_PERSPECTIVE", super::shadows::TILE_PERSPECTIVE);
    f("TILE_ORTHOGRAPHIC", super::shadows::TILE_ORTHOGRAPHIC);
    f("TILE_CUBE_FACE", super::shadows::TILE_CUBE_FACE);
    // Specular exponents are stored as log2(exponent) / range: exponents 1 ..= 2^range.
    f("SPEC_EXP_LOG_RANGE", super::gbuffer::SPEC_EXP_LOG_RANGE);
    let [r, g, b] = crate::scene::LUMINANCE.map(|w| w as f32);
    s += &format!("const LS_LUMINANCE: vec3<f32> = vec3<f32>({r:?}, {g:?}, {b:?});\n");
    // The `material-id` view's colours (`Brdf::debug_color`; unknown IDs show magenta).
    s += "fn brdf_debug_color(id: u32) -> vec3<f32> {\n";
    for b in crate::scene::Brdf::ALL {
        let [r, g, bl] = b.debug_color();
        s += &format!("    if id == {}u {{ return vec3<f32>({r:?}, {g:?}, {bl:?}); }}\n", b.id());
    }
    s += "    return vec3<f32>(1.0, 0.0, 1.0);\n}\n";
    s
}

/// The lookups a configuration's shaders compile in, from what the scene can need.
/// On lavapipe a fragment shader runs both sides of every branch under a lane mask, so a
/// lookup no light takes still costs every light at every pixel: with the shadow kernels and
/// the cookie compiled into `shade_light`, the clustered pass at 16,384 lights took 4.8× as
/// long as without them (`--shadows none` included, before this). A GPU that branches skips
/// them at run time; here they are left out when compiling. Each is a WGSL constant that the
/// shader's branches test (`LS_SUN_SHADOW`, `LS_TILE_SHADOWS`, `LS_CUBE_SHADOWS`,
/// `LS_CUBE_ARRAY`, `LS_SHADOW_KERNEL`, `LS_COOKIES`), so the compiler drops what is off;
/// `LS_CASTERS_APART` (`ShadowCode::casters_apart`) moves the few casting lights of a tile or
/// cluster list into a loop of their own. Named in the stats' `shader_lookups`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderFeatures {
    pub shadows: super::shadows::ShadowCode,
    /// Some light projects a cookie.
    pub cookies: bool,
    /// The per-pixel light loops read the lights from the light planes (`records::planes_hold`:
    /// at most `records::UNIFORM_LIGHTS` lights, no cookies), not the storage buffer.
    pub light_planes: bool,
    /// The forward loops (`fs_forward`, `forward_single`) take two lights an iteration: the
    /// scene has more lights than lavapipe's loop limit lets a loop walk one at a time
    /// (`plan::FORWARD_LOOP_LIGHTS`), so some list may be longer. Other scenes compile the
    /// plain loops.
    pub paired_loops: bool,
}

impl ShaderFeatures {
    /// The lookups on (the unrolled cubes, the 3x3 kernel), for checking the source: naga
    /// validates every branch, taken or not.
    pub const ALL: ShaderFeatures = ShaderFeatures {
        shadows: super::shadows::ShadowCode {
            sun: true,
            tiles: true,
            cubes: Some(super::shadows::ShadowCube::Unrolled),
            filter: super::shadows::ShadowFilter::Pcf3x3,
            casters_apart: true,
        },
        cookies: true,
        light_planes: true,
        paired_loops: true,
    };

    /// What `scene` can need under `settings`; with no scene, what the settings allow (no
    /// cookies: they come with a scene).
    pub fn of(scene: Option<&crate::scene::Scene>, settings: &Settings) -> ShaderFeatures {
        ShaderFeatures {
            shadows: super::shadows::ShadowCode::of(scene, settings),
            cookies: scene.is_some_and(|s| s.lights.iter().any(|l| l.cookie().is_some())),
            light_planes: scene.is_some_and(|s| super::records::planes_hold(&s.lights)),
            paired_loops: scene.is_some_and(|s| s.lights.len() > super::plan::FORWARD_LOOP_LIGHTS as usize),
        }
    }

    /// The lookups compiled in, by name (the stats and the viewer's shadow figures): `sun
    /// cascades`, `spot tiles`, `cubes unrolled` or `cubes array`, the kernel, `casters apart`,
    /// `cookies`.
    pub fn names(&self) -> Vec<String> {
        let sh = &self.shadows;
        let mut v = Vec::new();
        if sh.sun {
            v.push("sun cascades".to_string());
        }
        if sh.tiles {
            v.push("spot tiles".to_string());
        }
        if let Some(c) = sh.cubes {
            v.push(format!("cubes {}", c.name()));
        }
        if sh.sun || sh.tiles || sh.cubes.is_some() {
            v.push(format!("kernel {}", sh.filter.name()));
        }
        if sh.casters_apart {
            v.push("casters apart".to_string());
        }
        if self.cookies {
            v.push("cookies".to_string());
        }
        if self.light_planes {
            v.push("light planes".to_string());
        }
        if self.paired_loops {
            v.push("paired light loops".to_string());
        }
        v
    }

    fn wgsl(&self) -> String {
        let sh = &self.shadows;
        let cube_array = sh.cubes == Some(super::shadows::ShadowCube::Array);
        format!(
            "const LS_SUN_SHADOW: bool = {};\nconst LS_TILE_SHADOWS: bool = {};\n\
             const LS_CUBE_SHADOWS: bool = {};\nconst LS_CUBE_ARRAY: bool = {cube_array};\n\
             const LS_SHADOW_KERNEL: u32 = {}u;\nconst LS_COOKIES: bool = {};\n\
             const LS_CASTERS_APART: bool = {};\nconst LS_LIGHT_PLANES: bool = {};\n\
             const LS_PAIRED_LOOPS: bool = {};\n",
            sh.sun,
            sh.tiles,
            sh.cubes.is_some(),
            sh.filter as u32,
            self.cookies,
            sh.casters_apart,
            self.light_planes,
            self.paired_loops
        )
    }
}

/// The whole shader source for a G-buffer layout and accumulation format, every lookup
/// compiled in: generated constants, binding declarations and G-buffer layout, then the WGSL
/// files.
pub fn shader_source(layout: &GBufferLayout, accum_format: wgpu::TextureFormat, ambient_in_gbuffer: bool) -> String {
    shader_source_for(layout, accum_format, ambient_in_gbuffer, false, ShaderFeatures::ALL)
}

/// [`shader_source`] for the deferred path or (`prepass`) the light pre-pass, whose light pass
/// writes one light buffer (RGB diffuse, mono specular in A) shaded with unit reflectance, with
/// the lookups `features` name.
pub fn shader_source_for(
    layout: &GBufferLayout,
    accum_format: wgpu::TextureFormat,
    ambient_in_gbuffer: bool,
    prepass: bool,
    features: ShaderFeatures,
) -> String {
    let mut parts = vec![
        wgsl_constants(),
        format!("const LS_ACCUM_LOG: bool = {};\n", log_accum(accum_format)),
        format!("const LS_PREPASS: bool = {prepass};\n"),
        features.wgsl(),
    ];
    parts.push(layout.wgsl(1, ambient_in_gbuffer));
    parts.extend(bindings::GROUPS.iter().map(|g| g.wgsl()));
    parts.extend(
        [
            include_str!("../../../shaders/common.wgsl"),
            include_str!("../shadows/lookup.wgsl"),
            include_str!("../../../shaders/geometry.wgsl"),
            include_str!("../../../shaders/forward.wgsl"),
            include_str!("../culling/lights.wgsl"),
            include_str!("../../../shaders/compose.wgsl"),
            include_str!("../culling/tiled/tiled.wgsl"),
            include_str!("../post/post.wgsl"),
            include_str!("../shadows/casters.wgsl"),
            include_str!("../../../shaders/prepass.wgsl"),
            include_str!("../shadows/atlas_view.wgsl"),
        ]
        .map(String::from),
    );
    parts.join("\n")
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
    /// The G-buffer pass also writes ambient + sun into the accumulation targets (seed 000's
    /// RT1); otherwise the light pass starts with a full-screen ambient + sun draw.
    pub ambient_in_gbuffer: bool,
    /// The light pre-pass (seeds 003/004): `layout` is `gbuffer::prepass_layout`, the light
    /// passes write one light buffer (RGB diffuse + mono specular), ambient + sun go to pass 3.
    pub prepass: bool,
    /// Samples per pixel of the light pre-pass's pass 3 and the forward pass after it (1, or 4
    /// with `--msaa 4`; passes 1 and 2 stay single-sample).
    pub samples: u32,
    /// The shadow and cookie lookups compiled in.
    pub features: ShaderFeatures,
}

/// Whether the G-buffer pass can also write the two accumulation targets on a device with
/// `limits`: the colour attachments and their bytes per sample, G-buffer and accumulation
/// together, must fit (WebGPU's default 32 bytes do not take `compact`'s 24 plus two Rgba16Float
/// targets; lavapipe allows 128).
pub fn ambient_fits(layout: &GBufferLayout, accum_format: wgpu::TextureFormat, limits: &wgpu::Limits) -> bool {
    let accum = accum_format.block_copy_size(None).unwrap_or(16);
    (layout.targets.len() + 2) as u32 <= limits.max_color_attachments
        && layout.bytes_per_pixel() + 2 * accum <= limits.max_color_attachment_bytes_per_sample
}

/// What every pass's pipelines are built from.
pub struct Shared {
    pub key: PipelineKey,
    pub module: wgpu::ShaderModule,
    pub frame_bgl: wgpu::BindGroupLayout,
    pub gbuffer_bgl: wgpu::BindGroupLayout,
    pub material_bgl: wgpu::BindGroupLayout,
    pub compose_bgl: wgpu::BindGroupLayout,
    pub hdr_bgl: wgpu::BindGroupLayout,
    pub post_bgl: wgpu::BindGroupLayout,
    /// Frame + G-buffer + post: the post chain's passes.
    pub post_layout: wgpu::PipelineLayout,
    /// Frame + material: the surface passes (G-buffer, forward).
    pub surface_layout: wgpu::PipelineLayout,
    /// Frame + G-buffer: everything drawn per light.
    pub light_layout: wgpu::PipelineLayout,
    /// Frame + G-buffer + compose.
    pub compose_layout: wgpu::PipelineLayout,
    /// Frame + G-buffer + compose + HDR colour.
    pub tonemap_layout: wgpu::PipelineLayout,
}

impl Shared {
    pub fn new(device: &wgpu::Device, key: PipelineKey) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(key.layout.name),
            source: wgpu::ShaderSource::Wgsl(
                shader_source_for(&key.layout, key.accum_format, key.ambient_in_gbuffer, key.prepass, key.features)
                    .into(),
            ),
        });
        let frame_bgl = bindings::FRAME.layout(device);
        let gbuffer_bgl = GBufferTargets::bind_group_layout(device, &key.layout);
        let material_bgl = bindings::MATERIAL.layout(device);
        let compose_bgl = bindings::COMPOSE.layout(device);
        let hdr_bgl = bindings::HDR.layout(device);
        let post_bgl = bindings::POST.layout(device);
        let layout = |label, groups: &[&wgpu::BindGroupLayout]| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().map(|g| Some(*g)).collect();
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
        };
        let surface_layout = layout("surfaces", &[&frame_bgl, &material_bgl]);
        let light_layout = layout("lights", &[&frame_bgl, &gbuffer_bgl]);
        let compose_layout = layout("compose", &[&frame_bgl, &gbuffer_bgl, &compose_bgl]);
        let tonemap_layout = layout("tonemap", &[&frame_bgl, &gbuffer_bgl, &compose_bgl, &hdr_bgl]);
        let post_layout = layout("post", &[&frame_bgl, &gbuffer_bgl, &post_bgl]);
        Self {
            key,
            module,
            frame_bgl,
            gbuffer_bgl,
            material_bgl,
            compose_bgl,
            hdr_bgl,
            post_bgl,
            post_layout,
            surface_layout,
            light_layout,
            compose_layout,
            tonemap_layout,
        }
    }

    /// Maps a compare function written for standard depth to the depth convention in use.
    pub fn z(&self, c: Cmp) -> Cmp {
        z(self.key.reversed_z, c)
    }

    /// A pipeline drawing a full-screen triangle (`vs_compose`) into one target, no depth.
    pub fn fullscreen_pipeline(
        &self,
        device: &wgpu::Device,
        label: &str,
        layout: &wgpu::PipelineLayout,
        fs: &str,
        format: wgpu::TextureFormat,
    ) -> wgpu::RenderPipeline {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_compose"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// A pipeline of the per-light passes (lights, debug views, measurement): a volume or a
    /// full-screen triangle against the G-buffer's depth, with the draw's faces, depth and
    /// stencil state.
    pub fn light_pipeline(&self, device: &wgpu::Device, p: LightPipe) -> wgpu::RenderPipeline {
        let key = &self.key;
        let accum = |blend: Option<wgpu::BlendState>, write_mask| {
            let t = wgpu::ColorTargetState { format: key.accum_format, blend, write_mask };
            // The light pre-pass has one light buffer (`Targets::accumulation`).
            vec![Some(t.clone()), Some(t).filter(|_| !key.prepass)]
        };
        let targets = match p.out {
            Out::Accumulate => {
                accum(Some(if log_accum(key.accum_format) { MULTIPLY } else { ADDITIVE }), wgpu::ColorWrites::ALL)
            }
            Out::NoColor => accum(None, wgpu::ColorWrites::empty()),
            Out::Replace => accum(None, wgpu::ColorWrites::ALL),
            Out::Debug(blend) => vec![Some(wgpu::ColorTargetState {
                format: DEBUG_FORMAT,
                blend: Some(blend),
                write_mask: wgpu::ColorWrites::ALL,
            })],
        };
        let volume_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: 16,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4],
        })];
        let (entry, buffers): (&str, &[Option<wgpu::VertexBufferLayout>]) = match p.vs {
            Vs::Fullscreen => ("vs_fullscreen", &[]),
            Vs::FullscreenPlain => ("vs_fullscreen_plain", &[]),
            Vs::Volume => ("vs_volume", &volume_buffers),
        };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(p.label),
            layout: Some(&self.light_layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                buffers,
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: p.state.faces.cull_mode(),
                unclipped_depth: key.depth_clamp && matches!(p.vs, Vs::Volume),
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: key.depth_format,
                depth_write_enabled: Some(false),
                depth_compare: Some(self.z(p.state.depth)),
                stencil: p.state.stencil,
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(p.fs),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
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
    fn cull_mode(self) -> Option<wgpu::Face> {
        match self {
            Faces::Front => Some(wgpu::Face::Back),
            Faces::Back => Some(wgpu::Face::Front),
            Faces::Both => None,
        }
    }
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

/// What the frame's passes read: targets, scene, frame buffers, plan and what to measure.
pub struct FrameInputs<'a> {
    pub targets: &'a Targets,
    pub scene: &'a SceneGpu,
    pub frame: &'a FrameBuffers,
    pub volumes: &'a Volumes,
    pub plan: &'a FramePlan,
    pub queries: &'a Queries,
    pub settings: &'a Settings,
    /// Count each light's shaded fragments (occlusion queries).
    pub counts: bool,
    /// Count the ideal and the coverage (measurement passes).
    pub ideal: bool,
    /// Write timestamps.
    pub times: bool,
    /// Count the forward pass's fragments (an occlusion query over the pass).
    pub forward_counts: bool,
    pub depth_clamp: bool,
    /// Per light, its first shadow tile and tile count this frame (`shadows::ShadowPlan::lights`;
    /// `records::NO_SHADOW` first: unshadowed).
    pub shadowed: &'a [(u32, u32)],
}

impl FrameInputs<'_> {
    /// Whether light `i` casts a shadow this frame.
    pub fn casts(&self, i: u32) -> bool {
        self.shadowed.get(i as usize).is_some_and(|&(first, _)| first != records::NO_SHADOW)
    }

    /// Timestamp writes when the frame is timed: the beginning of span `begin` at the start of
    /// the pass and/or the end of span `end` at its end (a span may begin in one pass and end
    /// in a later one).
    pub fn timestamps(&self, begin: Option<Span>, end: Option<Span>) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let (begin, end) = (begin.and_then(Span::begin), end.and_then(Span::end));
        if !self.times || (begin.is_none() && end.is_none()) {
            return None;
        }
        self.queries.timestamps.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        })
    }

    /// Span `span` over one compute pass.
    pub fn compute_timestamps(&self, span: Span) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let (begin, end) = (span.begin(), span.end());
        if !self.times || begin.is_none() {
            return None;
        }
        self.queries.timestamps.as_ref().map(|q| wgpu::ComputePassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        })
    }

    /// Frame buffers, the G-buffer and the light-volume meshes: what every light draw reads.
    pub fn bind_light_inputs(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.frame.group, &[]);
        pass.set_bind_group(1, &self.targets.gbuffer_group, &[]);
        self.volumes.bind(pass);
    }

    /// Depth value of the far plane (1, or 0 with reversed Z).
    pub fn far_depth(&self) -> f64 {
        if self.settings.reversed_z {
            0.0
        } else {
            1.0
        }
    }
}

/// A pass built the first time a frame uses it. On lavapipe every pipeline is compiled to
/// machine code by LLVM when it is created, 2 to 9 MiB of heap each for the shading passes
/// (measured: a full set of passes took about 160 MiB), and the renderer keeps the passes of
/// recent configurations: a frame that never draws the light pre-pass, the tiled/clustered
/// shading, blended surfaces or the post chain should not pay for them.
pub struct Lazy<T> {
    cell: OnceLock<T>,
    device: wgpu::Device,
    shared: Arc<Shared>,
    build: fn(&wgpu::Device, &Shared) -> T,
}

impl<T> Lazy<T> {
    fn new(device: &wgpu::Device, shared: &Arc<Shared>, build: fn(&wgpu::Device, &Shared) -> T) -> Self {
        Self { cell: OnceLock::new(), device: device.clone(), shared: shared.clone(), build }
    }

    /// The pass if a frame has built it.
    pub fn get(&self) -> Option<&T> {
        self.cell.get()
    }

    /// Builds the pass now if it is not built, turning a validation error (a shader that fails
    /// to compile for this configuration) into an error instead of a panic.
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

/// What a frame draws with, beyond the passes every frame uses (G-buffer, lights, debug,
/// compose, the forward paths' passes, measure, shadows).
#[derive(Clone, Copy, Debug, Default)]
pub struct Needs {
    /// Blended surfaces, a forward path, or the post chain (which runs after the forward pass).
    pub forward: bool,
    /// The light pre-pass's lit pass 3.
    pub prepass: bool,
    /// Tiled or clustered shading, or the tile-lights view.
    pub tiled: bool,
    /// The post chain or one of its views.
    pub post: bool,
}

/// Every pass of the frame, built for one [`PipelineKey`].
pub struct Passes {
    pub shared: Arc<Shared>,
    pub gbuffer: Lazy<crate::renderer::surfaces::gbuffer::GBufferPass>,
    pub lights: Lazy<crate::renderer::culling::light_pass::LightPass>,
    pub debug: Lazy<crate::renderer::surfaces::debug::DebugPass>,
    pub compose: Lazy<crate::renderer::surfaces::compose::ComposePass>,
    pub forward: Lazy<crate::renderer::surfaces::blended::ForwardPass>,
    pub forward_paths: Lazy<crate::renderer::paths::forward_pass::ForwardPathsPass>,
    pub measure: Lazy<crate::renderer::surfaces::measure::MeasurePass>,
    pub prepass: Lazy<crate::renderer::paths::prepass_pass::PrepassFinalPass>,
    pub tiled: Lazy<crate::renderer::culling::tiled::pass::TiledPass>,
    pub bloom: Lazy<crate::renderer::post::bloom::BloomPass>,
    pub exposure: Lazy<crate::renderer::post::exposure::ExposurePass>,
    pub tonemap: Lazy<crate::renderer::post::tonemap::TonemapPass>,
    /// The effects after tone mapping (`effects::EFFECTS`).
    pub effects: Lazy<crate::renderer::post::effects::EffectsPass>,
    pub shadows: Lazy<crate::renderer::shadows::pass::ShadowPass>,
    /// The viewer's shadow-atlas image (not part of the frame).
    pub atlas_view: Lazy<crate::renderer::shadows::atlas_view::AtlasViewPass>,
}

impl Passes {
    /// The shader module and layouts only; no pipeline is compiled here. The passes every frame
    /// may use (G-buffer, lights, debug, compose, the forward paths', measure, shadows) are built
    /// by the first frame ([`Passes::prepare`]), the others by the first frame that needs them,
    /// so a set whose configuration is replaced before it draws (`Renderer::new` builds one
    /// before it has seen a scene, whose shader features it guesses) compiles nothing.
    pub fn new(device: &wgpu::Device, key: PipelineKey) -> Self {
        let shared = Arc::new(Shared::new(device, key));
        Self {
            gbuffer: Lazy::new(device, &shared, crate::renderer::surfaces::gbuffer::GBufferPass::new),
            lights: Lazy::new(device, &shared, crate::renderer::culling::light_pass::LightPass::new),
            debug: Lazy::new(device, &shared, crate::renderer::surfaces::debug::DebugPass::new),
            compose: Lazy::new(device, &shared, crate::renderer::surfaces::compose::ComposePass::new),
            forward: Lazy::new(device, &shared, crate::renderer::surfaces::blended::ForwardPass::new),
            forward_paths: Lazy::new(device, &shared, crate::renderer::paths::forward_pass::ForwardPathsPass::new),
            measure: Lazy::new(device, &shared, crate::renderer::surfaces::measure::MeasurePass::new),
            prepass: Lazy::new(device, &shared, crate::renderer::paths::prepass_pass::PrepassFinalPass::new),
            tiled: Lazy::new(device, &shared, crate::renderer::culling::tiled::pass::TiledPass::new),
            bloom: Lazy::new(device, &shared, crate::renderer::post::bloom::BloomPass::new),
            exposure: Lazy::new(device, &shared, crate::renderer::post::exposure::ExposurePass::new),
            tonemap: Lazy::new(device, &shared, crate::renderer::post::tonemap::TonemapPass::new),
            effects: Lazy::new(device, &shared, crate::renderer::post::effects::EffectsPass::new),
            shadows: Lazy::new(device, &shared, crate::renderer::shadows::pass::ShadowPass::new),
            atlas_view: Lazy::new(device, &shared, crate::renderer::shadows::atlas_view::AtlasViewPass::new),
            shared,
        }
    }

    pub fn key(&self) -> &PipelineKey {
        &self.shared.key
    }

    /// Builds the passes every frame uses and those `needs` names, where not built yet, inside
    /// an error scope (see [`Lazy::prepare`]).
    pub fn prepare(&self, needs: Needs) -> anyhow::Result<()> {
        self.gbuffer.prepare()?;
        self.lights.prepare()?;
        self.debug.prepare()?;
        self.compose.prepare()?;
        self.forward_paths.prepare()?;
        self.measure.prepare()?;
        self.shadows.prepare()?;
        if needs.forward {
            self.forward.prepare()?;
        }
        if needs.prepass {
            self.prepass.prepare()?;
        }
        if needs.tiled {
            self.tiled.prepare()?;
        }
        if needs.post {
            self.bloom.prepare()?;
            self.exposure.prepare()?;
            self.tonemap.prepare()?;
            self.effects.prepare()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cookie_feature_is_set_only_for_scenes_with_cookies() {
        use crate::scene::builtin::{build, BuiltinOptions};
        let st = Settings::default();
        let features = |name: &str| {
            let scene = build(name, BuiltinOptions::default()).expect("built-in scene");
            ShaderFeatures::of(Some(&scene), &st)
        };
        assert!(features("cookies").cookies);
        assert!(!features("demo").cookies && !features("shadows").cookies);
        assert!(!ShaderFeatures::of(None, &st).cookies);
        // The stats name what is compiled in: `demo` under the default `spots` has the sun and
        // narrow spots casting, no cube and no cookie, and its 1,028 lights read from the light
        // planes; a scene with cookies reads the storage buffer.
        assert_eq!(
            features("demo").names(),
            ["sun cascades", "spot tiles", "kernel pcf3x3", "casters apart", "light planes"]
        );
        assert!(features("cookies").names().iter().any(|n| n == "cookies"));
        assert!(features("demo").light_planes && !features("cookies").light_planes);
        // The constant the shader's branches test follows the feature.
        let on = ShaderFeatures { cookies: true, ..ShaderFeatures::ALL };
        assert!(on.wgsl().contains("const LS_COOKIES: bool = true;"));
        assert!(ShaderFeatures { cookies: false, ..on }.wgsl().contains("const LS_COOKIES: bool = false;"));
    }
}
