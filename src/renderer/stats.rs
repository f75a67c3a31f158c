//! Timestamp and occlusion queries turned into per-pass times and per-light fragment counts.
//!
//! Occlusion queries count samples that passed the depth and stencil tests of a light's
//! shading draw: the fragments that reached the lighting shader. The ideal is counted with the
//! same kind of query around a full-screen draw that discards every sample whose G-buffer point
//! lies outside the light's true radius and cone.

use super::plan::{LightPlan, Method};
use super::settings::ForwardLights;
use super::CullingMode;
use crate::gpu::Gpu;
use crate::scene::Scene;
use anyhow::Result;
use serde::{Deserialize, Serialize};

pub const LIGHTS_PER_QUERY_SET: usize = wgpu::QUERY_SET_MAX_QUERIES as usize;

/// The frame's timestamp slots: the beginning and end of each timed pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Stamp {
    GBufferBegin = 0,
    GBufferEnd = 1,
    LightsBegin = 2,
    LightsEnd = 3,
    /// The compose, or with blended surfaces the HDR compose, forward pass and tonemap (the
    /// forward pass's own span is taken out of `gpu_ms.compose`).
    ComposeBegin = 4,
    ComposeEnd = 5,
    /// The forward pass of blended surfaces.
    ForwardBegin = 6,
    ForwardEnd = 7,
}

impl Stamp {
    pub const COUNT: u32 = 8;
}

/// Byte offset of the forward pass's occlusion count in the resolve buffer: the 256-byte block
/// after the timestamps' (resolve offsets are multiples of 256).
const FORWARD_QUERY_OFFSET: u64 = 256;

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct GpuMs {
    pub gbuffer: Option<f64>,
    pub lighting: Option<f64>,
    /// The compose (and with blended surfaces the tonemap), without the forward pass.
    pub compose: Option<f64>,
    /// The forward pass of blended surfaces (`None` when the frame has none).
    #[serde(default)]
    pub forward: Option<f64>,
    pub total: Option<f64>,
}

/// The forward pass's work: its light lists (from the plan) and the fragments it shaded.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct ForwardStats {
    /// Which lists the pass walked (`Settings::forward_lights`).
    pub lights: ForwardLights,
    /// Blended objects drawn.
    pub objects: usize,
    /// Entries of the objects' lists, summed, and the longest.
    pub object_list_entries: u64,
    pub longest_object_list: u32,
    /// Screen tiles (`tiled` only), their lists' entries summed, and the longest.
    pub tiles: u64,
    pub tile_list_entries: u64,
    pub longest_tile_list: u32,
    /// Samples the forward pass shaded (passed the depth test; occlusion query), when counting.
    pub fragments: Option<u64>,
}

/// The tiled pass's lists (`tiled`, `clustered`, or the `tile-lights` view's): cells (tiles, or
/// tiles x slices), their entries summed and the longest (read back when counting).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct TileStats {
    pub method: Method,
    /// Tile size in pixels and depth slices (1 when tiled).
    pub tile_size: u32,
    pub slices: u32,
    pub cells: u64,
    pub entries: u64,
    pub longest: u32,
    /// Tiles the GPU list buffer had no room for (shaded with every light).
    pub overflowed: u64,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct LightStats {
    pub index: usize,
    pub kind: String,
    pub method: Method,
    pub crosses_near: bool,
    pub crosses_far: bool,
    pub screen_share: f32,
    /// Samples that reached the lighting shader.
    pub shaded: Option<u64>,
    /// Samples whose G-buffer point lies inside the light's true shape.
    pub ideal: Option<u64>,
    /// Rasterised coverage of the light's bounding volume (its back faces, or the screen for
    /// full-screen lights): fragment-shader invocations from pipeline statistics, counted with
    /// the ideal.
    pub coverage: Option<u64>,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct FrameStats {
    pub size: [u32; 2],
    pub culling: CullingMode,
    pub lights: usize,
    pub gpu_ms: GpuMs,
    pub shaded_fragments: Option<u64>,
    pub ideal_fragments: Option<u64>,
    /// Rasterised coverage of the shading draws (pipeline statistics), where supported.
    pub coverage_fragments: Option<u64>,
    /// ideal / shaded.
    pub efficiency: Option<f64>,
    /// The forward pass of blended surfaces, when the frame drew one.
    pub forward: Option<ForwardStats>,
    /// The tiled pass's light lists, when the frame (or the `tile-lights` view) built them.
    pub tiles: Option<TileStats>,
    pub gbuffer_layout: String,
    /// Colour targets of the G-buffer (the depth-stencil buffer is named apart).
    pub gbuffer_bytes_per_pixel: u32,
    pub depth_stencil_format: String,
    pub depth_clamp: bool,
    /// Ambient + sun were written by the G-buffer pass (`Settings::ambient_in_gbuffer`, where
    /// the device allows), not by a full-screen pass of their own.
    pub ambient_in_gbuffer: bool,
    /// Format of the light accumulation targets.
    pub accumulation_format: String,
    /// `Settings::light_cutoff` this frame was drawn with.
    pub light_cutoff: f32,
    /// Triangles of the point lights' bounding sphere and of the spots' pyramid.
    pub sphere_triangles: u32,
    pub cone_triangles: u32,
    /// The bounding meshes the frame drew ("sphere", "cone"): only the kinds its lights need.
    pub volume_meshes: Vec<String>,
    /// Draws the light pass issued for lights: marking and shading draws and REPLACE's stencil
    /// clears (not the ambient + sun draw). With `count_fragments` each light's shading is a
    /// draw of its own (its occlusion query), so counted frames issue more.
    pub draw_calls: u64,
    /// Instanced draws (batches) the lights were grouped into (`batches.rs`); one per drawn
    /// light with `light_batching` off.
    pub light_batches: u64,
    pub per_light: Vec<LightStats>,
}

pub struct Queries {
    pub timestamps: Option<wgpu::QuerySet>,
    /// One occlusion query over the whole forward pass.
    pub forward: wgpu::QuerySet,
    period_ns: f32,
    pub occlusion: Vec<wgpu::QuerySet>,
    pub ideal: Vec<wgpu::QuerySet>,
    /// Fragment-shader invocations of each shading draw (pipeline statistics), when the
    /// adapter has them. On lavapipe this is rasterised coverage before the depth and stencil
    /// tests, not the fragments shaded.
    pub coverage: Vec<wgpu::QuerySet>,
    coverage_supported: bool,
    resolve: Option<wgpu::Buffer>,
    readback: Option<wgpu::Buffer>,
    capacity: usize,
}

impl Queries {
    pub fn new(gpu: &Gpu) -> Self {
        let timestamps = gpu.has(wgpu::Features::TIMESTAMP_QUERY).then(|| {
            gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: Stamp::COUNT,
            })
        });
        let forward = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("forward fragments"),
            ty: wgpu::QueryType::Occlusion,
            count: 1,
        });
        Self {
            timestamps,
            forward,
            period_ns: gpu.queue.get_timestamp_period(),
            occlusion: Vec::new(),
            ideal: Vec::new(),
            coverage: Vec::new(),
            coverage_supported: gpu.has(wgpu::Features::PIPELINE_STATISTICS_QUERY),
            resolve: None,
            readback: None,
            capacity: 0,
        }
    }

    /// Layout of the resolve buffer: [timestamps (256 B)] [forward pass (256 B)] [occlusion]
    /// [ideal] [coverage] [end].
    fn offsets(capacity: usize) -> (u64, u64, u64, u64) {
        let block = (LIGHTS_PER_QUERY_SET * 8) as u64;
        let blocks = capacity.div_ceil(LIGHTS_PER_QUERY_SET) as u64;
        let occ = FORWARD_QUERY_OFFSET + 256;
        let ideal = occ + blocks * block;
        let coverage = ideal + blocks * block;
        (occ, ideal, coverage, coverage + blocks * block)
    }

    pub fn ensure_lights(&mut self, device: &wgpu::Device, n: usize) {
        let blocks = n.div_ceil(LIGHTS_PER_QUERY_SET).max(1);
        while self.occlusion.len() < blocks {
            let make = |label| {
                device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some(label),
                    ty: wgpu::QueryType::Occlusion,
                    count: LIGHTS_PER_QUERY_SET as u32,
                })
            };
            self.occlusion.push(make("shaded fragments"));
            self.ideal.push(make("ideal fragments"));
            if self.coverage_supported {
                self.coverage.push(device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("coverage"),
                    ty: wgpu::QueryType::PipelineStatistics(wgpu::PipelineStatisticsTypes::FRAGMENT_SHADER_INVOCATIONS),
                    count: LIGHTS_PER_QUERY_SET as u32,
                }));
            }
        }
        let capacity = blocks * LIGHTS_PER_QUERY_SET;
        if capacity > self.capacity {
            let (_, _, _, size) = Self::offsets(capacity);
            self.resolve = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("query resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }));
            self.readback = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("query readback"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }));
            self.capacity = capacity;
        }
    }

    /// Resolves the frame's queries; `forward` when the forward pass counted its fragments.
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        n: usize,
        counts: bool,
        ideal: bool,
        times: bool,
        forward: bool,
    ) {
        let (Some(resolve), Some(readback)) = (&self.resolve, &self.readback) else {
            return;
        };
        let (occ_off, ideal_off, cov_off, size) = Self::offsets(self.capacity);
        if times {
            if let Some(ts) = &self.timestamps {
                encoder.resolve_query_set(ts, 0..Stamp::COUNT, resolve, 0);
            }
        }
        if forward {
            encoder.resolve_query_set(&self.forward, 0..1, resolve, FORWARD_QUERY_OFFSET);
        }
        let block = (LIGHTS_PER_QUERY_SET * 8) as u64;
        for b in 0..n.div_ceil(LIGHTS_PER_QUERY_SET) {
            let count = (n - b * LIGHTS_PER_QUERY_SET).min(LIGHTS_PER_QUERY_SET) as u32;
            if counts {
                encoder.resolve_query_set(&self.occlusion[b], 0..count, resolve, occ_off + b as u64 * block);
            }
            if ideal {
                encoder.resolve_query_set(&self.ideal[b], 0..count, resolve, ideal_off + b as u64 * block);
                if let Some(set) = self.coverage.get(b) {
                    encoder.resolve_query_set(set, 0..count, resolve, cov_off + b as u64 * block);
                }
            }
        }
        if counts || ideal || times || forward {
            encoder.copy_buffer_to_buffer(resolve, 0, readback, 0, size);
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub fn read(
        &self,
        device: &wgpu::Device,
        stats: &mut FrameStats,
        plans: &[LightPlan],
        scene: &Scene,
        counts: bool,
        ideal: bool,
        times: bool,
        forward: bool,
    ) -> Result<()> {
        stats.per_light = plans
            .iter()
            .enumerate()
            .map(|(i, p)| LightStats {
                index: i,
                kind: match scene.lights[i] {
                    crate::scene::Light::Point(_) => "point".into(),
                    crate::scene::Light::Spot(_) => "spot".into(),
                },
                method: p.method,
                crosses_near: p.crosses_near,
                crosses_far: p.crosses_far,
                screen_share: p.screen_share,
                shaded: None,
                ideal: None,
                coverage: None,
            })
            .collect();
        if !(counts || ideal || times || forward) {
            return Ok(());
        }
        let Some(readback) = &self.readback else {
            return Ok(());
        };
        let slice = readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow::anyhow!("device poll failed: {e}"))?;
        rx.recv()?.map_err(|e| anyhow::anyhow!("query readback failed: {e}"))?;
        {
            let data = slice.get_mapped_range().map_err(|e| anyhow::anyhow!("{e}"))?;
            let words: &[u64] = bytemuck::cast_slice(&data);
            let (occ_off, ideal_off, cov_off, _) = Self::offsets(self.capacity);
            if times && self.timestamps.is_some() {
                let ms = |a: usize, b: usize| {
                    let (t0, t1) = (words[a], words[b]);
                    (t1 >= t0 && t0 != 0).then(|| (t1 - t0) as f64 * self.period_ns as f64 / 1e6)
                };
                let span = |a: Stamp, b: Stamp| ms(a as usize, b as usize);
                stats.gpu_ms.gbuffer = span(Stamp::GBufferBegin, Stamp::GBufferEnd);
                stats.gpu_ms.lighting = span(Stamp::LightsBegin, Stamp::LightsEnd);
                stats.gpu_ms.compose = span(Stamp::ComposeBegin, Stamp::ComposeEnd);
                if stats.forward.is_some() {
                    stats.gpu_ms.forward = span(Stamp::ForwardBegin, Stamp::ForwardEnd);
                    // The forward pass runs between the HDR compose and the tonemap.
                    if let (Some(c), Some(f)) = (stats.gpu_ms.compose, stats.gpu_ms.forward) {
                        stats.gpu_ms.compose = Some((c - f).max(0.0));
                    }
                }
                stats.gpu_ms.total = span(Stamp::GBufferBegin, Stamp::ComposeEnd);
            }
            if let Some(f) = stats.forward.as_mut().filter(|_| forward) {
                f.fragments = Some(words[(FORWARD_QUERY_OFFSET / 8) as usize]);
            }
            let block = LIGHTS_PER_QUERY_SET;
            let at = |base: u64, i: usize| {
                let b = i / block;
                words[(base / 8) as usize + b * block + i % block]
            };
            for (i, l) in stats.per_light.iter_mut().enumerate() {
                if counts {
                    l.shaded = Some(at(occ_off, i));
                }
                if ideal {
                    l.ideal = Some(at(ideal_off, i));
                    if self.coverage_supported {
                        l.coverage = Some(at(cov_off, i));
                    }
                }
            }
        }
        readback.unmap();
        if counts {
            stats.shaded_fragments = Some(stats.per_light.iter().filter_map(|l| l.shaded).sum());
        }
        if ideal && self.coverage_supported {
            stats.coverage_fragments = Some(stats.per_light.iter().filter_map(|l| l.coverage).sum());
        }
        if ideal {
            stats.ideal_fragments = Some(stats.per_light.iter().filter_map(|l| l.ideal).sum());
        }
        if let (Some(s), Some(i)) = (stats.shaded_fragments, stats.ideal_fragments) {
            stats.efficiency = Some(if s == 0 { 1.0 } else { i as f64 / s as f64 });
        }
        Ok(())
    }
}
