//! The viewport's image drawn into the window by a draw of its own inside egui's pass (an egui
//! paint callback): one triangle over the viewport's rectangle, sampling the image, no blending.
//!
//! egui would draw the same image as a textured mesh through its general shader (a colour
//! multiply, its dithering and the premultiplied-alpha blend), over a black fill, and both cover
//! every viewport pixel: on lavapipe at 1280x720 each of the two cost about 28 ms a frame, a
//! third of a 64-light frame. The image is opaque (the renderer writes alpha 1), so the fill
//! adds nothing and one unblended draw gives the same bytes: at resolution scale 1 the
//! rectangle maps 1:1 onto the image and each pixel loads its own texel (the bytes unchanged,
//! which `viewer::the_window_shows_the_rendered_bytes_unchanged` holds exactly); at other
//! scales it is the same bilinear filter egui's image used.
//!
//! The image is read through egui's own view of it (the `Rgba8Unorm` reinterpretation, or its
//! copy on the GL backend: `gfx::Image`), so the sampled values are the sRGB-encoded bytes and
//! are written as they are into the window's non-sRGB target. Where the window's only format is
//! an sRGB one there is no blit and egui draws the image as before.

/// The pipeline and sampler, kept in egui's callback resources.
pub struct Blit {
    /// Filtered (`fs_blit`) and texel for pixel (`fs_blit_texel`).
    pipeline: wgpu::RenderPipeline,
    texel: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
}

const SHADER: &str = r#"
@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var image_sampler: sampler;

struct Out {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

// One triangle covering the viewport (egui sets it to the callback's rectangle): uv 0..1
// across it, (0, 0) at its top left.
@vertex
fn vs_blit(@builtin(vertex_index) i: u32) -> Out {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return Out(vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0), uv);
}

@fragment
fn fs_blit(in: Out) -> @location(0) vec4<f32> {
    return vec4<f32>(textureSampleLevel(image, image_sampler, in.uv, 0.0).rgb, 1.0);
}

// The rectangle as large as the image: each pixel's own texel, loaded, with no filtering (what
// a bilinear sample at a texel's centre gives, for less work per pixel on a CPU rasteriser).
@fragment
fn fs_blit_texel(in: Out) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(image));
    let texel = min(vec2<u32>(in.uv * size), vec2<u32>(size) - 1u);
    return vec4<f32>(textureLoad(image, texel, 0).rgb, 1.0);
}
"#;

impl Blit {
    /// The blit into a window of `format`, or `None` where that format is sRGB (the sampled
    /// bytes would be encoded twice).
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Option<Self> {
        if format.is_srgb() {
            return None;
        }
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewport blit"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewport blit"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewport blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let make = |entry: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("viewport blit"),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_blit"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                multiview_mask: None,
                cache: None,
            })
        };
        let (pipeline, texel) = (make("fs_blit"), make("fs_blit_texel"));
        // Egui's image sampler: linear, clamped to the edge.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("viewport blit"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Some(Self { pipeline, texel, layout, sampler })
    }

    /// What the callback draws from: `view`, the image as egui reads it.
    pub fn paint(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> Paint {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport blit"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.sampler) },
            ],
        });
        let t = view.texture();
        Paint { group, size: [t.width(), t.height()] }
    }
}

/// The viewport's draw for one image (rebuilt when the image is).
#[derive(Clone)]
pub struct Paint {
    group: wgpu::BindGroup,
    /// The image's size in pixels.
    size: [u32; 2],
}

impl egui_wgpu::CallbackTrait for Paint {
    fn paint(
        &self,
        info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        let Some(blit) = resources.get::<Blit>() else { return };
        let px = info.viewport_in_pixels();
        let one_to_one = [px.width_px as u32, px.height_px as u32] == self.size;
        pass.set_pipeline(if one_to_one { &blit.texel } else { &blit.pipeline });
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}
