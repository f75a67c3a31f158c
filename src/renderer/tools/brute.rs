//! Brute force over the last frame's G-buffer: every light at every pixel, in f32.

use crate::gpu::Gpu;
use crate::renderer::explain::brute::*;
use crate::renderer::frame::last::Last;
use anyhow::{bail, Result};

impl<'a> Last<'a> {
    /// Brute force over the last frame's G-buffer (deferred path or light pre-pass): every
    /// light of the frame at every pixel, in f32.
    pub fn brute_force(&self, gpu: &Gpu) -> Result<BruteForce> {
        crate::renderer::scoped(&self.device, || self.brute_force_unscoped(gpu))
    }

    fn brute_force_unscoped(&self, _gpu: &Gpu) -> Result<BruteForce> {
        if !self.last.path.keeps_gbuffer() {
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
        // Its one pipeline, built before recording.
        let mut declared = crate::renderer::kit::Declared::default();
        declared.add(&pass.pipeline);
        self.passes.build(&declared);
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
        let raw: Vec<[f32; 4]> = crate::renderer::kit::read_back(device, &read, bytes)?;
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
