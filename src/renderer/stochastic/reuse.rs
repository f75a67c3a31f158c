//! ReSTIR's reuse of RIS samples (Bitterli et al. 2020, "Spatiotemporal reservoir resampling
//! for real-time ray tracing with dynamic direct lighting"), on the list modes: in place of the
//! one RIS pass, three passes over kept reservoirs (`reuse.wgsl`):
//!
//! 1. **candidates** (compute): each pixel's K fresh RIS samples; with `ris_temporal`, each
//!    combined with the last frame's final sample at the point reprojected through the last
//!    camera, rejected where depth or normal differ; ReSTIR's 1/M weights, the history's
//!    count capped at [`TEMPORAL_CAP`] x M (biased where the surface or the lights moved);
//! 2. **spatial** (compute): with `ris_spatial` neighbours, each sample combined with those
//!    of that many pixels within [`RADIUS`], with the unbiased 1/Z weights (Algorithm 6 of the
//!    paper); the result is the frame's final reservoirs, kept for the next frame;
//! 3. **resolve** (the tiled pass's shading): each final sample shaded with its shadow;
//!    with `ris_denoise`, into the denoiser's buffer instead, then its temporal accumulation
//!    and three a-trous steps (`denoise.wgsl`), and the tiled pass's shading adds the result;
//!    with the `converge` or `variance` view, each frame's light is also added to the sums
//!    those views draw from (`converge.wgsl`).
//!
//! The reservoirs are each renderer's ([`ReuseScratch`]): K a pixel, two regions of 32 bytes a
//! sample, so reuse takes at most [`MAX_SAMPLES`] samples; the denoiser's four regions add 48
//! bytes a pixel each, the averaging views' sums 32. Each region is a buffer and a binding of
//! its own (at most 118 MB at 1280x720).

use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::{ComputePipe, RenderPipe};
use crate::renderer::options::{DebugView, Options};
use crate::renderer::stats::Span;
use anyhow::{bail, Result};
use glam::DMat4;
use std::sync::{Mutex, OnceLock};

/// The most samples a pixel keeps with reuse: 32 bytes each a pixel in each of two buffers
/// (1280x720 at 4: 118 MB each, within WebGPU's 128 MiB binding).
pub const MAX_SAMPLES: u32 = 4;
/// The disc the spatial pass draws its neighbours from, in pixels (ReSTIR's 30 at 1920x1080,
/// scaled to 1280x720 and rounded down).
pub const RADIUS: u32 = 16;
/// The temporal history's count is capped at this many times M (ReSTIR's 20).
pub const TEMPORAL_CAP: u32 = 20;
/// Storage buffers a stage the reuse passes bind: the tiled pass's 8, the reservoirs' two, the
/// denoiser's four and the averaging views' sums (`bindings::REUSE`).
pub const STORAGE_BUFFERS: u32 = 15;
const _: () = assert!(crate::gpu::STORAGE_BUFFERS_PER_STAGE >= STORAGE_BUFFERS);
/// The buffer's header, in vec4<u32> (`reuse.wgsl`).
const HEADER_VEC4: u64 = 10;

/// The candidates pass's timestamps (part of the lighting span).
pub const CANDIDATES_SPAN: Span = Span("ris candidates");
/// The spatial pass's timestamps (part of the lighting span).
pub const SPATIAL_SPAN: Span = Span("ris spatial");
/// The denoiser's passes' timestamps, from its resolve to its last filter step (part of the
/// lighting span).
pub const DENOISE_SPAN: Span = Span("ris denoise");
/// The denoiser's passes: its resolve, the temporal accumulation, three a-trous steps.
const DENOISE_ENTRIES: [&str; 5] =
    ["cs_denoise_resolve", "cs_denoise_temporal", "cs_denoise_atrous1", "cs_denoise_atrous2", "cs_denoise_atrous4"];

/// The reuse passes' pipelines, each built when a frame first draws with it, on the tiled pass's
/// groups and the reservoirs' (`bindings::REUSE`).
pub struct ReusePipes {
    /// The tiled pass's groups 0-2.
    groups: [wgpu::BindGroupLayout; 3],
    /// The reservoirs' group and the four groups' layout, made on first use (an adapter that
    /// cannot bind them never makes them: `key::pipeline_key` refuses reuse there).
    layout: OnceLock<(wgpu::BindGroupLayout, wgpu::PipelineLayout)>,
    candidates: OnceLock<ComputePipe>,
    candidates_zbin: OnceLock<ComputePipe>,
    spatial: OnceLock<ComputePipe>,
    resolve: OnceLock<RenderPipe>,
    denoise: OnceLock<[ComputePipe; 5]>,
    denoised: OnceLock<RenderPipe>,
    converge: OnceLock<ComputePipe>,
    converged: OnceLock<RenderPipe>,
    variance: OnceLock<RenderPipe>,
}

impl ReusePipes {
    /// On the tiled pass's groups 0-2 (`groups`).
    pub fn new(groups: [&wgpu::BindGroupLayout; 3]) -> Self {
        Self {
            groups: groups.map(Clone::clone),
            layout: OnceLock::new(),
            candidates: OnceLock::new(),
            candidates_zbin: OnceLock::new(),
            spatial: OnceLock::new(),
            resolve: OnceLock::new(),
            denoise: OnceLock::new(),
            denoised: OnceLock::new(),
            converge: OnceLock::new(),
            converged: OnceLock::new(),
            variance: OnceLock::new(),
        }
    }

    /// The reservoirs' group layout and the passes' pipeline layout.
    fn layouts(&self, device: &wgpu::Device) -> &(wgpu::BindGroupLayout, wgpu::PipelineLayout) {
        self.layout.get_or_init(|| {
            let bgl = crate::renderer::kit::bindings::REUSE.layout(device);
            let g = &self.groups;
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ris reuse"),
                bind_group_layouts: &[Some(&g[0]), Some(&g[1]), Some(&g[2]), Some(&bgl)],
                immediate_size: 0,
            });
            (bgl, layout)
        })
    }

    /// The candidates pass (over z-bins or tile and cluster lists) and the spatial pass.
    pub fn compute(&self, device: &wgpu::Device, module: &wgpu::ShaderModule, zbin: bool) -> [&ComputePipe; 2] {
        let (cell, label, entry) = match zbin {
            true => (&self.candidates_zbin, "ris candidates, z-bins", "cs_ris_candidates_zbin"),
            false => (&self.candidates, "ris candidates", "cs_ris_candidates"),
        };
        let layout = Some(&self.layouts(device).1);
        let candidates = cell.get_or_init(|| crate::renderer::kit::compute_pipe(device, label, layout, module, entry));
        let spatial = self.spatial.get_or_init(|| {
            crate::renderer::kit::compute_pipe(device, "ris spatial", layout, module, "cs_ris_spatial")
        });
        [candidates, spatial]
    }

    /// The denoiser's compute passes ([`DENOISE_ENTRIES`]).
    pub fn denoise(&self, device: &wgpu::Device, module: &wgpu::ShaderModule) -> &[ComputePipe; 5] {
        self.denoise.get_or_init(|| {
            let layout = Some(&self.layouts(device).1);
            DENOISE_ENTRIES.map(|entry| crate::renderer::kit::compute_pipe(device, entry, layout, module, entry))
        })
    }

    /// The compute passes after the spatial pass for options `o`: the denoiser's; or, for the
    /// views that average frames, its resolve into region B alone; then the averaging.
    pub fn after_spatial(&self, device: &wgpu::Device, module: &wgpu::ShaderModule, o: &Options) -> Vec<&ComputePipe> {
        let converges = o.frame.debug_view.converges();
        let mut v: Vec<&ComputePipe> = match (o.stochastic.ris_denoise, converges) {
            (true, _) => self.denoise(device, module).iter().collect(),
            (false, true) => vec![&self.denoise(device, module)[0]],
            (false, false) => Vec::new(),
        };
        if converges {
            v.push(self.converge.get_or_init(|| {
                let layout = Some(&self.layouts(device).1);
                crate::renderer::kit::compute_pipe(device, "ris converge", layout, module, "cs_converge")
            }));
        }
        v
    }

    /// The resolve: the tiled pass's shading pipeline with reuse for options `o`: the mean of
    /// the frames averaged (the `converge` view), the light in region B (denoised, or for the
    /// `variance` view), or the final samples shaded.
    pub fn resolve(
        &self,
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        targets: &[Option<wgpu::ColorTargetState>],
        o: &Options,
    ) -> &RenderPipe {
        let (cell, label, fs) = match o.frame.debug_view {
            DebugView::Converge => (&self.converged, "ris converged", "fs_ris_converged"),
            _ if o.stochastic.ris_denoise || o.frame.debug_view.converges() => {
                (&self.denoised, "ris denoised", "fs_ris_denoised")
            }
            _ => (&self.resolve, "ris resolve", "fs_ris_resolve"),
        };
        cell.get_or_init(|| {
            let layout = &self.layouts(device).1;
            crate::renderer::kit::screen_pipeline(device, module, label, layout, ("vs_tiled", fs), targets)
        })
    }

    /// The `variance` view's pass into the debug target (`target`).
    pub fn variance(
        &self,
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        target: wgpu::ColorTargetState,
    ) -> &RenderPipe {
        self.variance.get_or_init(|| {
            let layout = &self.layouts(device).1;
            let stages = ("vs_tiled", "fs_ris_variance");
            crate::renderer::kit::screen_pipeline(device, module, "ris variance view", layout, stages, &[Some(target)])
        })
    }
}

/// One renderer's reservoirs and the camera of the frame that wrote them.
#[derive(Default)]
pub struct ReuseScratch {
    state: Mutex<Option<ReuseState>>,
}

struct ReuseState {
    /// The header and this frame's reservoirs; the final ones; the denoiser's four regions.
    buffers: Vec<wgpu::Buffer>,
    group: wgpu::BindGroup,
    /// Width, height, samples a pixel, whether the denoiser's regions are made (for the
    /// denoiser or the averaging views), and the averaging views' sums.
    size: (u32, u32, u32, bool, bool),
    /// The last frame's world-to-view and projection, its light count (the history is read
    /// only when the lights are the same list), and whether it denoised.
    last: Option<(DMat4, DMat4, usize, bool)>,
    /// Which of the denoiser's histories the next frame reads.
    parity: bool,
    /// What the averaging views' sums hold.
    averaged: Option<Averaged>,
}

/// The frames the averaging views' sums hold: their camera, lights and options (the noise seed
/// set to 0), and how many.
struct Averaged {
    view: DMat4,
    proj: DMat4,
    lights: std::sync::Arc<Vec<crate::scene::Light>>,
    options: Options,
    frames: u32,
}

/// The header `reuse.wgsl` reads: the matrices as f32 bits, the mode, the size.
/// `size`: width, height, samples a pixel, and the denoiser's flags.
fn header(to_last: DMat4, last_proj: DMat4, mode: [u32; 4], size: [u32; 4]) -> Vec<u32> {
    let mut words = Vec::with_capacity(HEADER_VEC4 as usize * 4);
    words.extend(to_last.as_mat4().to_cols_array().iter().map(|v| v.to_bits()));
    words.extend(last_proj.as_mat4().to_cols_array().iter().map(|v| v.to_bits()));
    words.extend(mode);
    words.extend(size);
    words
}

impl ReuseScratch {
    /// Makes the reservoirs anew for `size` (forgetting the history) when they are missing or
    /// of another size; refuses an adapter that cannot bind them.
    pub fn fit(&self, f: &FrameInputs<'_>, pipes: &ReusePipes) -> Result<()> {
        let limit = f.device.limits().max_storage_buffers_per_shader_stage;
        if limit < STORAGE_BUFFERS {
            bail!(
                "RIS reuse binds {STORAGE_BUFFERS} storage buffers a stage and this adapter allows {limit}: \
                 use ris-spatial 0 and ris-temporal off"
            );
        }
        let o = &f.options.stochastic;
        let converges = f.options.frame.debug_view.converges();
        let size = (
            f.targets.width,
            f.targets.height,
            o.ris_samples.clamp(1, MAX_SAMPLES),
            o.ris_denoise || converges,
            converges,
        );
        let mut state = self.state.lock().map_err(|_| anyhow::anyhow!("reservoirs lock poisoned"))?;
        if state.as_ref().is_some_and(|s| s.size == size) {
            return Ok(());
        }
        let pixels = size.0 as u64 * size.1 as u64;
        let reservoirs = 32 * pixels * size.2 as u64;
        let denoised = if size.3 { 48 * pixels } else { 16 };
        let sums = if size.4 { 32 * pixels } else { 16 };
        let bytes = [16 * HEADER_VEC4 + reservoirs, reservoirs, denoised, denoised, denoised, denoised, sums];
        let most = f.device.limits().max_storage_buffer_binding_size;
        if bytes[0] > most {
            bail!(
                "RIS reuse keeps {} MB of reservoirs a region at {}x{} with {} samples, past the adapter's {} MB a \
                 binding: use fewer ris-samples or a smaller frame",
                bytes[0] >> 20,
                size.0,
                size.1,
                size.2,
                most >> 20
            );
        }
        let buffers: Vec<wgpu::Buffer> = bytes
            .iter()
            .map(|&size| {
                f.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("ris reservoirs"),
                    size,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let group = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ris reservoirs"),
            layout: &pipes.layouts(f.device).0,
            entries: &crate::renderer::kit::bindings::REUSE
                .entries(buffers.iter().map(|b| b.as_entire_binding()).collect()),
        });
        *state = Some(ReuseState { buffers, group, size, last: None, parity: false, averaged: None });
        Ok(())
    }

    /// Records the candidates and spatial passes (`pipes`, from [`ReusePipes::compute`]) and
    /// those after (`after`, from [`ReusePipes::after_spatial`]: the denoiser's, the averaging),
    /// with groups 0-2 bound by `bind`, after writing the header; returns the reservoirs' group
    /// for the resolve. The frame's camera becomes the history's.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        (pipes, after): ([&ComputePipe; 2], Vec<&ComputePipe>),
        bind: &dyn Fn(&mut wgpu::ComputePass<'_>),
    ) -> Result<wgpu::BindGroup> {
        let mut state = self.state.lock().map_err(|_| anyhow::anyhow!("reservoirs lock poisoned"))?;
        let Some(s) = state.as_mut() else { bail!("internal: the reservoirs were not made before recording") };
        let o = &f.options.stochastic;
        let lights = f.plan.lights.len();
        let last = s.last.filter(|l| l.2 == lights);
        let temporal = last.filter(|_| o.ris_temporal);
        let denoising = o.ris_denoise;
        let denoise_history = last.filter(|l| denoising && l.3);
        let (to_last, last_proj) =
            last.map_or((DMat4::IDENTITY, DMat4::IDENTITY), |(view, proj, ..)| (view * f.view.inverse(), proj));
        let mode = [u32::from(temporal.is_some()), o.ris_spatial.min(16), RADIUS, TEMPORAL_CAP];
        let averaged = match f.options.frame.debug_view.converges() {
            true => s.average(f),
            false => {
                s.averaged = None;
                0
            }
        };
        let flags =
            u32::from(denoising) | u32::from(denoise_history.is_some()) << 1 | u32::from(s.parity) << 2 | averaged << 8;
        let size = [s.size.0, s.size.1, s.size.2, flags];
        f.queue.write_buffer(&s.buffers[0], 0, bytemuck::cast_slice(&header(to_last, last_proj, mode, size)));
        s.last = Some((f.view, f.proj, lights, denoising));
        if denoising {
            s.parity = !s.parity;
        }
        let groups = (s.size.0.div_ceil(8), s.size.1.div_ceil(8));
        let mut run: Vec<(&ComputePipe, Option<wgpu::ComputePassTimestampWrites<'_>>)> =
            vec![(pipes[0], f.compute_timestamps(CANDIDATES_SPAN)), (pipes[1], f.compute_timestamps(SPATIAL_SPAN))];
        let timed = if denoising { DENOISE_ENTRIES.len() } else { 0 };
        for (i, pipe) in after.into_iter().enumerate() {
            let timestamps = match i < timed {
                true => f.compute_timestamps_of_run(DENOISE_SPAN, (i == 0, i + 1 == timed)),
                false => None,
            };
            run.push((pipe, timestamps));
        }
        for (pipe, timestamp_writes) in run {
            let mut pass =
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("ris reuse"), timestamp_writes });
            pass.set_pipeline(pipe);
            bind(&mut pass);
            pass.set_bind_group(3, &s.group, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        }
        Ok(s.group.clone())
    }
}

impl ReuseState {
    /// The averaging views' count of frames with this frame's: one more when the camera, the
    /// lights (the same list, or an equal one: the viewer builds its scene's list anew each
    /// frame) and every option but the noise seed are the last frame's, else 1 (the sums start
    /// anew).
    fn average(&mut self, f: &FrameInputs<'_>) -> u32 {
        let mut options = f.options.clone();
        options.stochastic.noise_seed = 0;
        let n = match &self.averaged {
            Some(a)
                if a.view == f.view
                    && a.proj == f.proj
                    && (std::sync::Arc::ptr_eq(&a.lights, f.scene_lights) || *a.lights == **f.scene_lights)
                    && a.options == options =>
            {
                a.frames.saturating_add(1).min(1 << 23)
            }
            _ => 1,
        };
        let lights = f.scene_lights.clone();
        self.averaged = Some(Averaged { view: f.view, proj: f.proj, lights, options, frames: n });
        n
    }
}
