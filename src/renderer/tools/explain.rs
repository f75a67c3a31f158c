//! Why each light did or did not light a pixel of the last frame: the explanation, beside what the frame's culling did.

use crate::gpu::Gpu;
use crate::renderer::explain::*;
use crate::renderer::frame::last::Last;
use crate::renderer::inspect::PixelProbe;
use crate::renderer::plan::Method;
use crate::renderer::records::LIGHT_KIND_SPOT;
use anyhow::{bail, Result};
use glam::{Vec2, Vec3};

impl<'a> Last<'a> {
    /// Why each light did or did not light pixel (`x`, `y`) of the last frame (deferred path).
    pub fn explain(&self, gpu: &Gpu, x: u32, y: u32) -> Result<Explanation> {
        if !self.last.path.keeps_gbuffer() {
            bail!(
                "light explanations cover the deferred path and the light pre-pass (the last frame drew {}): \
                 the forward paths keep no G-buffer to shade the pixel from",
                self.last.path.name()
            );
        }
        let probe: PixelProbe = self.probe(gpu, x, y)?;
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        let n = self.last.lights.len();
        let raw = crate::renderer::scoped(&self.device, || self.explain_raw(x, y, n))?;
        let lists = if self.last.plan.lights.iter().any(|p| p.method.listed()) { self.tile_lists(gpu)? } else { None };
        let depth = -probe.position.z;
        let (cell, list): (Option<Cell>, Option<Vec<u32>>) = match (&lists, probe.valid) {
            (Some(l), true) => {
                let c = l.cell(x, y, depth);
                let list = l.list(c);
                (Some(Cell { index: c, lights: list.len() }), Some(list))
            }
            _ => (None, None),
        };
        let ndc =
            Vec2::new((x as f32 + 0.5) / t.width as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / t.height as f32 * 2.0);
        let t_s = probe.position.length();
        let dir = probe.position / t_s.max(1e-30);
        let mut lights = Vec::new();
        let (mut lights_d, mut lights_s) = (Vec3::ZERO, Vec3::ZERO);
        for (i, rec) in self.last.lights.iter().enumerate() {
            let Some(plan) = self.last.plan.lights.get(i) else { continue };
            let Some(w) = raw.get(4 * WORDS * i..4 * WORDS * (i + 1)) else { continue };
            let culling = match plan.method {
                Method::Fullscreen => Culling::FullScreen,
                Method::Skipped => Culling::Skipped,
                m if m.listed() => match &list {
                    Some(l) if l.contains(&(i as u32)) => Culling::InList,
                    _ => Culling::NotInList,
                },
                m => match self.volume_planes(i) {
                    Some(faces) if probe.valid => volume_culling(m, ray_interval(&faces, dir), t_s, plan.crosses_near),
                    _ => Culling::VolumeMissed,
                },
            };
            let (diffuse, specular, lit) =
                (Vec3::from_slice(&w[0..3]), Vec3::from_slice(&w[4..7]), Vec3::from_slice(&w[8..11]));
            let (shadow, cookie) = (w[3], w[7]);
            let (dr, spot, ndl, reaches) = (w[12], w[13], w[14], w[15] > 0.5);
            let shading = shading_of(reaches, dr, spot, ndl, shadow, cookie);
            let covers = plan
                .screen_rect
                .is_some_and(|(lo, hi)| ndc.x >= lo.x && ndc.x <= hi.x && ndc.y >= lo.y && ndc.y <= hi.y);
            let why = LightWhy {
                index: i,
                kind: if rec.kind == LIGHT_KIND_SPOT { "spot" } else { "point" },
                method: plan.method,
                culling,
                shading,
                diffuse,
                specular,
                lit,
                shadow,
                shadow_tile: rec.shadow[0] != crate::renderer::records::NO_SHADOW,
                cookie,
                distance_over_radius: dr,
                spot,
                n_dot_l: ndl,
                wasted: false,
                missed: false,
            };
            let adds = why.contributes();
            let admitted = culling.admitted() && probe.valid;
            if admitted {
                if t.prepass {
                    // The light pre-pass's buffer: RGB diffuse, A the specular's luminance, both
                    // with unit reflectance (`encode_light_buffer`).
                    lights_d += diffuse;
                    lights_s += Vec3::splat(specular.dot(luminance()));
                } else if t.one_target {
                    lights_d += lit;
                } else {
                    lights_d += diffuse;
                    lights_s += specular;
                }
            }
            if covers || admitted || adds {
                lights.push(LightWhy { wasted: admitted && !adds, missed: !admitted && adds, ..why });
            }
        }
        lights.sort_by(|a, b| b.lit.max_element().total_cmp(&a.lit.max_element()).then(a.index.cmp(&b.index)));
        let (acc_d, acc_s) = (probe.diffuse_light, probe.specular_light);
        Ok(Explanation {
            x,
            y,
            valid: probe.valid,
            culling_mode: self.last.mode.name(),
            path: self.last.path.name(),
            position: probe.position,
            cell,
            accumulated_diffuse: acc_d,
            accumulated_specular: acc_s,
            lights_diffuse: lights_d,
            lights_specular: lights_s,
            rest_diffuse: acc_d - lights_d,
            rest_specular: acc_s - lights_s,
            one_target: t.one_target && !t.prepass,
            prepass: t.prepass,
            wasted: lights.iter().filter(|l| l.wasted).count(),
            missed: lights.iter().filter(|l| l.missed).count(),
            lights,
        })
    }

    /// `cs_explain` at pixel (`x`, `y`) for the `n` lights of the last frame: [`WORDS`] x 4
    /// floats a light.
    fn explain_raw(&self, x: u32, y: u32, n: usize) -> Result<Vec<f32>> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        if n == 0 {
            return Ok(Vec::new());
        }
        self.passes.explain.prepare()?;
        let Some(pass) = self.passes.explain.get() else { bail!("the explanation's pipeline was not built") };
        let device = &self.device;
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("explain params"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue.write_buffer(&params, 0, bytemuck::cast_slice(&[x, y, n as u32, 0]));
        let bytes = (WORDS * 16 * n) as u64;
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("explain out"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("explain read"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("explain"),
            layout: &pass.bgl,
            entries: &[
                wgpu::BindGroupEntry { binding: 70, resource: params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 71, resource: out.as_entire_binding() },
            ],
        });
        // Its one pipeline, built before recording.
        let mut declared = crate::renderer::kit::Declared::default();
        declared.add(&pass.pipeline);
        self.passes.build(&declared);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("explain") });
        {
            let mut cpass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("explain"), timestamp_writes: None });
            cpass.set_pipeline(&pass.pipeline);
            cpass.set_bind_group(0, &self.frame.group, &[]);
            cpass.set_bind_group(1, &t.gbuffer_group, &[]);
            cpass.set_bind_group(2, &group, &[]);
            cpass.dispatch_workgroups((n as u32).div_ceil(WORKGROUP), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &read, 0, bytes);
        self.queue.submit([encoder.finish()]);
        crate::renderer::kit::read_back(device, &read, bytes)
    }
}
