//! Brute force: every light of the last frame evaluated at every pixel of its G-buffer, in f32,
//! on the GPU, whatever the culling decided (`cs_brute_force`): the reference the culling
//! oracle holds each mode against. A light the culling skipped at a pixel where this adds light
//! is a missed pair.
//!
//! Each pixel sums the lights in one invocation. Under a loop limit (`Quirks::loop_limit`:
//! gallivm ends an invocation's loops after 65,535 iterations between them) the lights are
//! shaded in chunks, one compute pass each, every chunk adding onto the last: a light costs at
//! most [`ITERATIONS_PER_LIGHT`] iterations, so a chunk holds
//! `gpu_loop_budget(limit) / ITERATIONS_PER_LIGHT` lights. Without a limit one pass shades all.

use super::super::kit::Shared;
use super::super::{RenderPath, Renderer};
use crate::gpu::Gpu;
use anyhow::{bail, Result};

/// Loop iterations one light takes in `cs_brute_force`: one of the light loop, and the shadow
/// filter's taps: at most 16 (the Poisson kernel's one loop; PCF 3x3 takes 3 + 9 = 12).
pub const ITERATIONS_PER_LIGHT: u64 = 17;

/// vec4s `cs_brute_force` writes a pixel.
const WORDS: usize = 3;

pub struct BrutePass {
    pipeline: crate::renderer::kit::ComputePipe,
    bgl: wgpu::BindGroupLayout,
}

impl BrutePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let (pipeline, bgl) = super::compute_pipeline(device, shared, "brute force", "cs_brute_force");
        Self { pipeline, bgl }
    }
}

/// Every light at every pixel of the last frame, summed in f32: per pixel, row by row.
#[derive(Clone, Debug, Default)]
pub struct BruteForce {
    pub width: u32,
    pub height: u32,
    /// RGB diffuse light (before albedo), as the diffuse target accumulates it.
    pub diffuse: Vec<[f32; 3]>,
    /// RGB specular light, as the specular target accumulates it.
    pub specular: Vec<[f32; 3]>,
    /// The lit colour (diffuse x albedo + specular): what seed 000's one target accumulates.
    pub lit: Vec<[f32; 3]>,
    /// How many lights add light at the pixel.
    pub adding: Vec<u32>,
}

/// The lights a chunk of `cs_brute_force` shades under loop limit `limit` (all of them without
/// one).
pub fn chunk_lights(limit: Option<u64>, lights: usize) -> usize {
    match limit {
        Some(l) => (crate::renderer::culling::tiled::gpu_loop_budget(l) / ITERATIONS_PER_LIGHT).max(1) as usize,
        None => lights.max(1),
    }
}

impl Renderer {
    /// Brute force over the last frame's G-buffer (deferred path or light pre-pass): every
    /// light of the frame at every pixel, in f32.
    pub fn brute_force(&self, gpu: &Gpu) -> Result<BruteForce> {
        crate::renderer::scoped(&self.device, || self.brute_force_unscoped(gpu))
    }

    fn brute_force_unscoped(&self, _gpu: &Gpu) -> Result<BruteForce> {
        if !matches!(self.last.path, RenderPath::Deferred | RenderPath::LightPrepass) {
            bail!(
                "brute force shades a G-buffer: the last frame drew the {} path, which keeps none",
                self.last.path.name()
            );
        }
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        let (w, h) = (t.width, t.height);
        let n = self.last.lights.len();
        let pixels = w as usize * h as usize;
        let bytes = (WORDS * 16 * pixels) as u64;
        let device = &self.device;
        self.passes.brute.prepare()?;
        let Some(pass) = self.passes.brute.get() else { bail!("the brute-force pipeline was not built") };
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("brute force out"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("brute force read"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let chunk = chunk_lights(self.caps.quirks.loop_limit, n);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("brute force") });
        encoder.clear_buffer(&out, 0, None);
        let mut first = 0;
        // Each chunk in a compute pass of its own, so each reads what the last one wrote.
        let mut params_buffers = Vec::new();
        while first < n {
            let count = chunk.min(n - first);
            let params = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("brute force params"),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.queue.write_buffer(&params, 0, bytemuck::cast_slice(&[w, h, first as u32, count as u32]));
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("brute force"),
                layout: &pass.bgl,
                entries: &[
                    wgpu::BindGroupEntry { binding: 70, resource: params.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 71, resource: out.as_entire_binding() },
                ],
            });
            {
                let mut cpass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("brute force"),
                    timestamp_writes: None,
                });
                cpass.set_pipeline(&pass.pipeline);
                cpass.set_bind_group(0, &self.frame.group, &[]);
                cpass.set_bind_group(1, &t.gbuffer_group, &[]);
                cpass.set_bind_group(2, &group, &[]);
                cpass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
            }
            params_buffers.push(params);
            first += count;
        }
        encoder.copy_buffer_to_buffer(&out, 0, &read, 0, bytes);
        self.queue.submit([encoder.finish()]);
        let raw: Vec<[f32; 4]> = super::super::kit::read_back(device, &read, bytes)?;
        let mut b = BruteForce { width: w, height: h, ..Default::default() };
        for p in raw.chunks_exact(WORDS) {
            b.diffuse.push([p[0][0], p[0][1], p[0][2]]);
            b.adding.push(p[0][3] as u32);
            b.specular.push([p[1][0], p[1][1], p[1][2]]);
            b.lit.push([p[2][0], p[2][1], p[2][2]]);
        }
        Ok(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_stays_inside_the_loop_limit() {
        let limit = crate::renderer::kit::caps::GALLIVM_LOOP_LIMIT;
        let chunk = chunk_lights(Some(limit), 100_000) as u64;
        assert!(chunk * ITERATIONS_PER_LIGHT <= crate::renderer::culling::tiled::gpu_loop_budget(limit));
        assert!((chunk + 1) * ITERATIONS_PER_LIGHT > crate::renderer::culling::tiled::gpu_loop_budget(limit));
        assert_eq!(chunk_lights(None, 100_000), 100_000);
    }
}
