//! The post chain's size-dependent images and buffers, and the sizes they are made with.

use crate::renderer::kit::{bindings, texture, Shared};
use crate::renderer::records::PostParams;

/// Bins of the luminance histogram: bin 0 holds pixels darker than `2^HIST_LOG_MIN` (black,
/// background), bins 1 ..= 63 split `HIST_LOG_MIN ..= HIST_LOG_MAX` stops evenly (0.33 stop
/// each); brighter pixels fall in the last.
pub const HIST_BINS: u32 = 64;

/// Words of the exposure state buffer: the bins, then the adapted and the measured log2
/// luminance (f32 bits), then 1 once a frame has been measured (the first frame starts at its
/// own luminance instead of adapting from an arbitrary one), then the last frame's bins (kept
/// for the histogram view; the first bins are cleared for the next frame).
pub const STATE_WORDS: u32 = 2 * HIST_BINS + 3;

/// Levels of the bloom chain (half, quarter, … 1/32 resolution).
pub const BLOOM_LEVELS: usize = 5;

/// Largest `.cube` LUT edge accepted (65 is the largest in common use).
pub const MAX_LUT_SIZE: u32 = 65;

/// The chain's size-dependent images, its buffers and bind groups (`bindings::POST`).
pub struct PostTargets {
    pub size: (u32, u32),
    /// Bloom's downsampled levels (1/2 … 1/32) and the upsampled ones (1/2 … 1/16).
    pub down: Vec<wgpu::TextureView>,
    pub up: Vec<wgpu::TextureView>,
    pub level_sizes: Vec<(u32, u32)>,
    /// The HDR colour with bloom added (full size).
    pub bloomed: wgpu::Texture,
    pub bloomed_view: wgpu::TextureView,
    /// The tonemapped colour before grading (full size), and a second image the passes after
    /// tone mapping alternate with.
    pub toned_view: wgpu::TextureView,
    pub second_view: wgpu::TextureView,
    /// Seed 002's distortion buffer (full size, Rgba16Float): the summed screen offsets of the
    /// distorting surfaces in .rg, the nearest one's 1 / view depth in .a (`distortion`). The
    /// effects after tone mapping read it as their second texture.
    pub distortion: wgpu::Texture,
    pub distortion_view: wgpu::TextureView,
    pub params: wgpu::Buffer,
    /// Histogram bins and the adapted / measured log2 luminance (`STATE_WORDS` words).
    pub state: wgpu::Buffer,
    pub lut: wgpu::Buffer,
    /// Bind groups: bright pass (from HDR), each further downsample, each upsample (level k
    /// from up k+1 or down 5, with down k), the combine (HDR with up 1), the histogram and the
    /// tonemap reading HDR or the bloomed colour, the grading reading the tonemapped colour.
    pub bright: wgpu::BindGroup,
    pub downs: Vec<wgpu::BindGroup>,
    pub ups: Vec<wgpu::BindGroup>,
    pub combine: wgpu::BindGroup,
    pub from_hdr: wgpu::BindGroup,
    pub from_bloomed: wgpu::BindGroup,
    pub from_toned: wgpu::BindGroup,
    pub from_second: wgpu::BindGroup,
}

impl PostTargets {
    pub fn new(device: &wgpu::Device, shared: &Shared, size: (u32, u32), hdr: &wgpu::TextureView) -> Self {
        use wgpu::TextureUsages as U;
        let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        let mut level_sizes = Vec::new();
        let mut s = size;
        for _ in 0..BLOOM_LEVELS {
            s = (s.0.div_ceil(2).max(1), s.1.div_ceil(2).max(1));
            level_sizes.push(s);
        }
        let view = |label: &str, s: (u32, u32)| {
            texture(device, label, shared.key.post_format, s, usage).create_view(&Default::default())
        };
        let down: Vec<_> = level_sizes.iter().map(|s| view("bloom down", *s)).collect();
        let up: Vec<_> = level_sizes[..BLOOM_LEVELS - 1].iter().map(|s| view("bloom up", *s)).collect();
        let bloomed = texture(device, "bloomed", shared.key.post_format, size, usage);
        let bloomed_view = bloomed.create_view(&Default::default());
        let toned_view = view("tonemapped", size);
        let second_view = view("post second", size);
        let distortion = texture(device, "distortion", DISTORTION_FORMAT, size, usage);
        let distortion_view = distortion.create_view(&Default::default());
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        use wgpu::BufferUsages as B;
        let params = buffer("post params", std::mem::size_of::<PostParams>() as u64, B::STORAGE | B::COPY_DST);
        let state = buffer("exposure state", STATE_WORDS as u64 * 4, B::STORAGE | B::COPY_DST | B::COPY_SRC);
        let lut = buffer("lut", (MAX_LUT_SIZE as u64).pow(3) * 16, B::STORAGE | B::COPY_DST);
        let group = |src: &wgpu::TextureView, aux: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("post"),
                layout: &shared.post_bgl,
                entries: &bindings::POST.entries(vec![
                    params.as_entire_binding(),
                    wgpu::BindingResource::TextureView(src),
                    wgpu::BindingResource::TextureView(aux),
                    state.as_entire_binding(),
                    lut.as_entire_binding(),
                ]),
            })
        };
        // A pass never reads the image it writes: the bright pass and the downsamples take the
        // tonemapped image as their unused second texture.
        let bright = group(hdr, &toned_view);
        let downs = (1..BLOOM_LEVELS).map(|k| group(&down[k - 1], &toned_view)).collect();
        // ups[k] writes up[k]: from up[k + 1] (or the last down level) with down[k].
        let ups = (0..BLOOM_LEVELS - 1)
            .map(|k| group(if k + 1 == BLOOM_LEVELS - 1 { &down[k + 1] } else { &up[k + 1] }, &down[k]))
            .collect();
        let combine = group(hdr, &up[0]);
        let from_hdr = group(hdr, &down[0]);
        let from_bloomed = group(&bloomed_view, &down[0]);
        let from_toned = group(&toned_view, &distortion_view);
        let from_second = group(&second_view, &distortion_view);
        Self {
            size,
            down,
            up,
            level_sizes,
            bloomed,
            bloomed_view,
            toned_view,
            second_view,
            distortion,
            distortion_view,
            params,
            state,
            lut,
            bright,
            downs,
            ups,
            combine,
            from_hdr,
            from_bloomed,
            from_toned,
            from_second,
        }
    }
}

/// The distortion buffer's format.
pub const DISTORTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
