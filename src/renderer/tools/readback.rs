//! The read-backs of the last frame: its debug target, light buffer and accumulation, its
//! post images and exposure, its plans, lists and records.

use crate::gpu::Gpu;
use crate::renderer::culling::plan::LightPlan;
use crate::renderer::frame::last::Last;
use crate::renderer::inspect;
use crate::renderer::kit;
use crate::renderer::options::log_accum_decode;
use crate::renderer::options::DebugView;
use crate::renderer::records::LightRecord;
use crate::renderer::surfaces::compose::ComposeTarget;
use crate::renderer::{culling, post, shadows};
use anyhow::{bail, Result};

impl<'a> Last<'a> {
    /// The last frame's debug target, its red channel per pixel: the counts of the complexity,
    /// tile-lights and waste views (exact integers up to 2048 in its Rgba16Float).
    pub fn read_debug_view(&self, gpu: &Gpu) -> Result<Vec<f32>> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        let format = t.debug_texture.format();
        let bpp = format.block_copy_size(None).unwrap_or(8) as usize;
        let bytes = gpu.read_texture(&t.debug_texture, wgpu::TextureAspect::All)?;
        bytes.chunks_exact(bpp).map(|c| Ok(inspect::texel(format, c)?[0])).collect()
    }

    /// The light pre-pass's light buffer of the last frame, decoded (`-log2` for seed 004's
    /// log encoding) to f32 RGBA: RGB the diffuse light, A the mono specular.
    pub fn read_light_buffer(&self, gpu: &Gpu) -> Result<Vec<f32>> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        if !t.prepass {
            bail!("the last frame was not drawn with the light pre-pass (--path light-prepass)");
        }
        let format = t.diffuse.format();
        let bpp = format.block_copy_size(None).unwrap_or(8) as usize;
        let log = kit::log_accum(format);
        let bytes = gpu.read_texture(&t.diffuse, wgpu::TextureAspect::All)?;
        let mut out = Vec::with_capacity(bytes.len() / bpp * 4);
        for c in bytes.chunks_exact(bpp) {
            let v = inspect::texel(format, c)?;
            out.extend(if log { v.map(log_accum_decode) } else { v });
        }
        Ok(out)
    }

    /// The last frame's fp16 clamps (`overlap::clamps`): what ambient + sun and what each light
    /// could add to a channel at most. The f64 reference applies the same values.
    pub fn light_clamps(&self) -> (f32, Vec<f32>) {
        (self.last.ambient_clamp, self.last.lights.iter().map(|l| l.clamp).collect())
    }

    /// The last frame's shadow plan: the atlas's tiles as the shaders read them,
    /// each light's (first tile, count), the sun's cascades and the stats.
    pub fn shadow_plan(&self) -> &'a shadows::ShadowPlan {
        &self.last.shadows
    }

    /// The last frame's per-light plans (method, volume, planes crossed, screen share).
    pub fn plans(&self) -> &'a [LightPlan] {
        &self.last.plan.lights
    }

    /// The blended objects of the last frame in the order the forward pass drew them (back to
    /// front), for the viewer and the tests.
    pub fn forward_order(&self) -> Vec<usize> {
        self.last.plan.draws.forward.iter().map(|d| d.0).collect()
    }

    /// The last frame's tile or cluster light lists as the GPU held them (`tiled`, `clustered`
    /// or the `tile-lights` view), read back; `None` when the frame built none.
    pub fn tile_lists(&self, gpu: &Gpu) -> Result<Option<culling::tiled::pass::TileLists>> {
        self.scratch.tiled.lists(&gpu.device, &gpu.queue)
    }

    /// The last frame's z-binned job (sorted lights, bins, rectangles), when it was z-binned.
    pub fn zbin_job(&self) -> Option<&'a culling::zbin::ZBinJob> {
        self.last.plan.zbins.as_ref()
    }

    /// The last frame's lights as the shaders saw them (view space, cut-off radius applied).
    pub fn light_records(&self) -> &'a [LightRecord] {
        &self.last.lights
    }

    /// The auto-exposure state after the last frame: (adapted, measured) log2 luminance, the
    /// measured one from the frame's histogram (bin centres; see `post::HIST_BINS`). `None`
    /// when the last frame ran no post chain.
    pub fn exposure_state(&self, gpu: &Gpu) -> Result<Option<(f32, f32)>> {
        let Some(pt) = self.targets.as_ref().and_then(|t| t.post.as_ref()) else { return Ok(None) };
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("exposure state readback"),
            size: pt.state.size(),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&pt.state, 0, &staging, 0, pt.state.size());
        self.queue.submit([encoder.finish()]);
        let words = gpu.read_buffer(&staging)?;
        let w: &[u32] = bytemuck::cast_slice(&words);
        let at = |i: u32| f32::from_bits(w.get(i as usize).copied().unwrap_or(0));
        Ok(Some((at(post::HIST_BINS), at(post::HIST_BINS + 1))))
    }

    /// Reads one of the last frame's HDR images as f32 RGBA: the scene colour before the post
    /// chain, or the colour with bloom added. `None` when the last frame had no such image.
    pub fn read_post_image(&self, gpu: &Gpu, image: post::PostImage) -> Result<Option<Vec<f32>>> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        let texture = match image {
            post::PostImage::Hdr => t.hdr_texture.as_ref(),
            post::PostImage::Bloomed => t.post.as_ref().map(|p| &p.bloomed),
            post::PostImage::Distortion => t.post.as_ref().map(|p| &p.distortion),
        };
        let Some(texture) = texture else { return Ok(None) };
        let format = texture.format();
        let bpp = format.block_copy_size(None).unwrap_or(8) as usize;
        let bytes = gpu.read_texture(texture, wgpu::TextureAspect::All)?;
        let mut out = Vec::with_capacity(bytes.len() / bpp * 4);
        for c in bytes.chunks_exact(bpp) {
            out.extend(inspect::texel(format, c)?);
        }
        Ok(Some(out))
    }

    /// Whether the last frame's lights read depth from the depth buffer itself, not its copy.
    pub fn reads_depth_buffer(&self) -> bool {
        self.targets.as_ref().is_some_and(|t| t.gbuffer.layout.reads_depth_buffer())
    }

    /// Whether the last frame accumulated into one target (seed 000's RT1 of lit colour, or the
    /// light pre-pass's light buffer).
    pub fn one_target(&self) -> bool {
        self.targets.as_ref().is_some_and(|t| t.one_target)
    }

    /// The GPU objects only the ledger uses that this renderer (or the pass sets it holds) has
    /// made: each is built by the first frame that counts or shows the ledger, so a renderer
    /// that never does lists none.
    pub fn ledger_objects(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        let sets = || std::iter::once(self.passes).chain(self.pass_cache.iter().map(|p| &**p));
        if sets().any(|p| p.tiled.get().is_some_and(|t| t.counter_built())) {
            out.push("the tiled pass's per-light counter");
        }
        if sets().any(|p| p.waste.get().is_some()) {
            out.push("the waste view's passes");
        }
        if self.scratch.forward.draw_queries_made() {
            out.push("the forward paths' per-draw queries");
        }
        if self.scratch.shadows.made() {
            out.push("the per-light shadow timers");
        }
        out
    }

    /// Reads the linear HDR accumulation (diffuse, specular) as f32 RGBA, for NaN/Inf checks
    /// (decoded, for the logarithmic Rgba8 format). On the light pre-pass: its one light buffer
    /// decoded, as (RGB diffuse, A mono specular) and the mono specular as grey RGB. With seed
    /// 000's one RT1: (the lit colour, zeros).
    pub fn read_accumulation(&self, gpu: &Gpu) -> Result<(Vec<f32>, Vec<f32>)> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        if t.prepass {
            let buffer = self.read_light_buffer(gpu)?;
            let mono = buffer.chunks_exact(4).flat_map(|c| [c[3], c[3], c[3], 0.0]).collect();
            return Ok((buffer, mono));
        }
        let format = t.diffuse.format();
        let bpp = format.block_copy_size(None).unwrap_or(8) as usize;
        let one = t.one_target;
        let to_f32 = |bytes: Vec<u8>| -> Result<Vec<f32>> {
            let mut out = Vec::with_capacity(bytes.len() / bpp * 4);
            let log = kit::log_accum(format);
            for c in bytes.chunks_exact(bpp) {
                let v = inspect::texel(format, c)?;
                out.extend(if log { v.map(log_accum_decode) } else { v });
            }
            Ok(out)
        };
        let light = to_f32(gpu.read_texture(&t.diffuse, wgpu::TextureAspect::All)?)?;
        if one {
            let zeros = vec![0.0; light.len()];
            return Ok((light, zeros));
        }
        Ok((light, to_f32(gpu.read_texture(&t.specular, wgpu::TextureAspect::All)?)?))
    }

    /// Re-runs only the compose pass of the last frame with another view, into `target` of the
    /// output format at any size (the G-buffer is point-sampled): the viewer's thumbnails.
    /// The stencil and complexity views show what the last frame computed for them.
    pub fn compose_view(&self, view: DebugView, target: &wgpu::TextureView, width: u32, height: u32) -> Result<()> {
        let Some(targets) = &self.targets else { bail!("nothing rendered yet") };
        if width == 0 || height == 0 {
            bail!("cannot compose a {width}x{height} view");
        }
        self.last.gbuffer(&format!("{} view", view.name()))?;
        // Set up here if no frame has (a frame that failed after configure).
        self.passes.compose.prepare()?;
        crate::renderer::kit::scoped(self.device, || {
            let mut encoder =
                self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("compose view") });
            let to = ComposeTarget { view: target, size: (width, height), debug_view: view, slot: view as u64 + 1 };
            // Its pipeline built before it records.
            let mut declared = crate::renderer::kit::Declared::default();
            declared.add(self.passes.compose.pipeline(view));
            self.passes.build(&declared);
            self.passes.compose.encode_to(&mut encoder, self.queue, targets, self.frame, &to, None);
            self.queue.submit([encoder.finish()]);
            Ok(())
        })
    }
}
