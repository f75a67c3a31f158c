//! The shader module and pipeline layouts a configuration ([`PipelineKey`]) is compiled to, and
//! the two pipeline shapes most passes are: a full-screen triangle into one target, and a
//! per-light draw against the G-buffer's depth.

use super::features::ShaderFeatures;
use super::gbuffer::{GBufferLayout, GBufferTargets};
use super::{bindings, log_accum, z, LightPipe, Out, RenderPipe, RenderPipeDesc, Vs, ADDITIVE, DEBUG_FORMAT, MULTIPLY};
use crate::scene::Topology;
use wgpu::CompareFunction as Cmp;

/// Key of everything the pipelines depend on.
#[derive(Clone, Debug, PartialEq)]
pub struct PipelineKey {
    pub layout: GBufferLayout,
    pub depth_format: wgpu::TextureFormat,
    pub output_format: wgpu::TextureFormat,
    pub reversed_z: bool,
    /// Format of the diffuse and specular light accumulation targets.
    pub accum_format: wgpu::TextureFormat,
    /// Format of the post chain's intermediate images (`post::post_format`).
    pub post_format: wgpu::TextureFormat,
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
    /// Blended surfaces are added (`BlendedMode::Additive`), not alpha blended.
    pub additive_blended: bool,
    /// Blended surfaces are depth peeled (`BlendedMode::Peeled`): the depth buffer is also
    /// sampled, and the peel pipelines are built.
    pub peeled_blended: bool,
}

impl PipelineKey {
    /// The light passes write one accumulation target: the light pre-pass's light buffer, or
    /// seed 000's RT1 (`GBufferLayout::one_accumulation`); the second is a 1x1 stand-in.
    pub fn one_target(&self) -> bool {
        self.prepass || self.layout.one_accumulation
    }
}

/// Whether the G-buffer pass can also write the two accumulation targets on a device with
/// `limits`: the colour attachments and their bytes per sample, G-buffer and accumulation
/// together, must fit (WebGPU's default 32 bytes do not take `compact`'s 24 plus two Rgba16Float
/// targets; lavapipe allows 128).
pub fn ambient_fits(layout: &GBufferLayout, accum_format: wgpu::TextureFormat, limits: &wgpu::Limits) -> bool {
    let accum = accum_format.block_copy_size(None).unwrap_or(16);
    let n = if layout.one_accumulation { 1 } else { 2 };
    (layout.rendered().count() + n) as u32 <= limits.max_color_attachments
        && layout.bytes_per_pixel() + n as u32 * accum <= limits.max_color_attachment_bytes_per_sample
}

/// [`Shared::screen_pipeline`] from `module`, for a pass that builds a pipeline after its
/// construction (when a frame first needs it).
pub fn screen_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    label: &str,
    layout: &wgpu::PipelineLayout,
    (vs, fs): (&str, &str),
    targets: &[Option<wgpu::ColorTargetState>],
) -> RenderPipe {
    super::render_pipe(
        device,
        RenderPipeDesc {
            label: label.to_owned(),
            layout: layout.clone(),
            module: module.clone(),
            vs: vs.to_owned(),
            buffers: Vec::new(),
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some((fs.to_owned(), targets.to_vec())),
        },
    )
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
    /// Depth peeling's groups ([`bindings::PEEL`], [`bindings::PEELED`]) and layouts: frame +
    /// material + peel for the layer passes, frame + peeled layers for the last.
    pub peel_bgl: wgpu::BindGroupLayout,
    pub peeled_bgl: wgpu::BindGroupLayout,
    pub peel_layout: wgpu::PipelineLayout,
    pub peeled_layout: wgpu::PipelineLayout,
    /// The device's pipeline cache when the set was made (`kit::cache`): the set's pipelines
    /// are compiled through it.
    pub pipeline_cache: Option<wgpu::PipelineCache>,
}

impl Shared {
    /// The layouts for `key`, and `source` (the program assembled for `key`,
    /// `program::shader_source_for`) compiled to one module.
    pub fn new(device: &wgpu::Device, key: PipelineKey, source: String) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(key.layout.name),
            source: wgpu::ShaderSource::Wgsl(source.into()),
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
        let peel_bgl = bindings::PEEL.layout(device);
        let peeled_bgl = bindings::PEELED.layout(device);
        let peel_layout = layout("peel", &[&frame_bgl, &material_bgl, &peel_bgl]);
        let peeled_layout = layout("peeled layers", &[&frame_bgl, &peeled_bgl]);
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
            peel_bgl,
            peeled_bgl,
            peel_layout,
            peeled_layout,
            pipeline_cache: None,
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
    ) -> RenderPipe {
        self.screen_pipeline(device, label, layout, ("vs_compose", fs), &[Some(format.into())])
    }

    /// A pipeline of vertex stage `vs` without vertex buffers (a full-screen triangle, or
    /// instances of one) and fragment stage `fs` into `targets`, no depth.
    pub fn screen_pipeline(
        &self,
        device: &wgpu::Device,
        label: &str,
        layout: &wgpu::PipelineLayout,
        (vs, fs): (&str, &str),
        targets: &[Option<wgpu::ColorTargetState>],
    ) -> RenderPipe {
        screen_pipeline(device, &self.module, label, layout, (vs, fs), targets)
    }

    /// A pipeline of the per-light passes (lights, debug views, measurement): a volume or a
    /// full-screen triangle against the G-buffer's depth, with the draw's faces, depth and
    /// stencil state.
    pub fn light_pipeline(&self, device: &wgpu::Device, p: LightPipe) -> RenderPipe {
        let key = &self.key;
        let accum = |blend: Option<wgpu::BlendState>, write_mask| {
            let t = wgpu::ColorTargetState { format: key.accum_format, blend, write_mask };
            // The light pre-pass's one light buffer, seed 000's one RT1 (`Targets::accumulation`).
            vec![Some(t.clone()), Some(t).filter(|_| !key.one_target())]
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
        let volume_buffers = vec![super::VertexBuffer {
            stride: 16,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: wgpu::vertex_attr_array![0 => Float32x4].to_vec(),
        }];
        let bias = match p.vs {
            Vs::Volume => super::volume_depth_bias(&p.state, key.reversed_z),
            _ => Default::default(),
        };
        let (entry, buffers) = match p.vs {
            Vs::Fullscreen => ("vs_fullscreen", Vec::new()),
            Vs::FullscreenPlain => ("vs_fullscreen_plain", Vec::new()),
            Vs::Volume => ("vs_volume", volume_buffers),
        };
        super::render_pipe(
            device,
            RenderPipeDesc {
                label: p.label.to_owned(),
                layout: self.light_layout.clone(),
                module: self.module.clone(),
                vs: entry.to_owned(),
                buffers,
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
                    bias,
                }),
                multisample: Default::default(),
                fragment: Some((p.fs.to_owned(), targets)),
            },
        )
    }
}

/// A pipeline drawing the scene's vertices (`scene::Vertex`): what every surface pass (the
/// G-buffer, the forward paths, the light pre-pass's pass 3, blended surfaces) is built from.
pub struct ScenePipe<'a> {
    pub label: &'a str,
    pub layout: &'a wgpu::PipelineLayout,
    pub vs: &'a str,
    /// `None`: depth only.
    pub fs: Option<&'a str>,
    pub topology: crate::scene::Topology,
    pub double_sided: bool,
    /// Depth written, its compare (written for standard depth, flipped under reversed Z), the
    /// stencil state.
    pub depth: (bool, Cmp, wgpu::StencilState),
    pub samples: u32,
}

/// The pipeline `p` describes from `module`, for `key`'s depth format and convention, writing
/// `targets`. Triangles cull back faces unless two-sided; lines and points cull nothing.
pub fn scene_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    key: &PipelineKey,
    p: ScenePipe<'_>,
    targets: &[Option<wgpu::ColorTargetState>],
) -> RenderPipe {
    use crate::scene::Topology;
    let triangles = p.topology == Topology::Triangles;
    super::render_pipe(
        device,
        RenderPipeDesc {
            label: p.label.to_owned(),
            layout: p.layout.clone(),
            module: module.clone(),
            vs: p.vs.to_owned(),
            buffers: vec![super::VertexBuffer {
                stride: std::mem::size_of::<crate::scene::Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x2].to_vec(),
            }],
            primitive: wgpu::PrimitiveState {
                topology: match p.topology {
                    Topology::Triangles => wgpu::PrimitiveTopology::TriangleList,
                    Topology::Lines => wgpu::PrimitiveTopology::LineList,
                    Topology::Points => wgpu::PrimitiveTopology::PointList,
                },
                cull_mode: if p.double_sided || !triangles { None } else { Some(wgpu::Face::Back) },
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: key.depth_format,
                depth_write_enabled: Some(p.depth.0),
                depth_compare: Some(z(key.reversed_z, p.depth.1)),
                stencil: p.depth.2,
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: p.samples, ..Default::default() },
            fragment: p.fs.map(|fs| (fs.to_owned(), targets.to_vec())),
        },
    )
}

/// Index into the G-buffer pass's pipelines (`surfaces::gbuffer::GBufferPass::pipelines`):
/// opaque or masked, one- or two-sided.
pub fn pipeline_index(masked: bool, double_sided: bool) -> usize {
    masked as usize * 2 + double_sided as usize
}

/// Index into the G-buffer pass's pipelines of a mesh of `topology`: lines and points have one
/// pipeline each (no faces to cull; the masked fragment shader, whose cutoff is 0 for opaque
/// materials).
pub fn topology_pipeline_index(topology: Topology, masked: bool, double_sided: bool) -> usize {
    match topology {
        Topology::Triangles => pipeline_index(masked, double_sided),
        Topology::Lines => 4,
        Topology::Points => 5,
    }
}
