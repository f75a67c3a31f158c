//! Timestamp and occlusion queries turned into per-pass times and per-light fragment counts.
//!
//! Occlusion queries count samples that passed the depth and stencil tests of a light's
//! shading draw: the fragments that reached the lighting shader. The ideal is counted with the
//! same kind of query around a full-screen draw that discards every sample whose G-buffer point
//! lies outside the light's true radius and cone.

use crate::gpu::Gpu;
use anyhow::Result;
use serde::{Deserialize, Serialize};

pub const LIGHTS_PER_QUERY_SET: usize = wgpu::QUERY_SET_MAX_QUERIES as usize;

/// A timed span of the frame, named where its pass is declared (`surfaces::gbuffer::SPAN`, a row
/// of `post::effects::EFFECTS`, …): a timestamp at its beginning and one at its end, at slots of
/// the frame's query set given out by name the first time a span is used in this process. A
/// span past [`MAX_SPANS`] gets no slot and is reported as not measured (null), never as
/// another span's time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Span(pub &'static str);

/// Spans the frame's timestamp query set holds (two timestamps each).
pub const MAX_SPANS: u32 = 32;

impl Span {
    /// The span's slot pair, given out on first use.
    fn slot(self) -> Option<u32> {
        static NAMES: std::sync::Mutex<Vec<&'static str>> = std::sync::Mutex::new(Vec::new());
        let mut names = NAMES.lock().unwrap_or_else(|e| e.into_inner());
        let i = match names.iter().position(|n| *n == self.0) {
            Some(i) => i,
            None if names.len() < MAX_SPANS as usize => {
                names.push(self.0);
                names.len() - 1
            }
            None => {
                log::error!("no timestamp slot left for the span '{}' (MAX_SPANS = {MAX_SPANS})", self.0);
                return None;
            }
        };
        Some(i as u32)
    }

    /// The index of the timestamp at its beginning.
    pub fn begin(self) -> Option<u32> {
        self.slot().map(|s| 2 * s)
    }

    /// The index of the timestamp at its end.
    pub fn end(self) -> Option<u32> {
        self.slot().map(|s| 2 * s + 1)
    }
}

/// Timestamps in the frame's query set.
const TIMESTAMPS: u32 = 2 * MAX_SPANS;

/// The forward pass's occlusion queries: one per peeled layer, and one for what is behind the
/// last ([`crate::renderer::options::MAX_PEEL_LAYERS`] + 1), within its 256-byte block.
const FORWARD_QUERIES: u32 = crate::renderer::options::MAX_PEEL_LAYERS + 1;
const _: () = assert!(FORWARD_QUERIES * 8 <= 256);

/// Byte offset of the light pre-pass's two occlusion counts (pass 1, pass 3) in the resolve
/// buffer: the 256-byte block after the forward pass's.
const PREPASS_QUERY_OFFSET: u64 = FORWARD_QUERY_OFFSET + 256;

/// Byte offset of the forward pass's occlusion count in the resolve buffer: the first 256-byte
/// boundary after the timestamps (resolve offsets are multiples of 256).
const FORWARD_QUERY_OFFSET: u64 = (TIMESTAMPS as u64 * 8).div_ceil(256) * 256;

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct GpuMs {
    pub gbuffer: Option<f64>,
    pub lighting: Option<f64>,
    /// The compose (and with blended surfaces the tonemap), without the forward pass.
    pub compose: Option<f64>,
    /// The forward pass of blended surfaces (`None` when the frame has none).
    #[serde(default)]
    pub forward: Option<f64>,
    /// The post chain's passes (`None` when a pass did not run).
    #[serde(default)]
    pub bloom: Option<f64>,
    #[serde(default)]
    pub exposure: Option<f64>,
    #[serde(default)]
    pub tonemap: Option<f64>,
    /// Each effect after tone mapping that ran and was timed, by its name in
    /// `post::effects::EFFECTS` (written beside the other passes: `"fog": 0.21`).
    #[serde(flatten)]
    pub effects: std::collections::BTreeMap<String, f64>,
    /// The GPU building the tiled or clustered light lists (part of `lighting`; `None` when
    /// the frame built none on the GPU).
    #[serde(default)]
    pub lists: Option<f64>,
    /// RIS's passes over kept reservoirs (`stochastic::reuse`), each part of `lighting`: the
    /// candidates (with temporal reuse), the spatial reuse, the denoiser (`None` when not run).
    #[serde(default)]
    pub ris_candidates: Option<f64>,
    #[serde(default)]
    pub ris_spatial: Option<f64>,
    #[serde(default)]
    pub ris_denoise: Option<f64>,
    /// The light pre-pass's final pass (pass 3; its passes 1 and 2 are `gbuffer` and
    /// `lighting`).
    #[serde(default)]
    pub prepass_final: Option<f64>,
    /// The shadow pass: the atlas's depth, before every path's first pass (`None`
    /// when no light cast). Part of `total`.
    #[serde(default)]
    pub shadows: Option<f64>,
    /// The frame: from the first pass to the last, plus the shadow pass before it.
    pub total: Option<f64>,
}

/// CPU time of the frame's preparation, in milliseconds, over all the threads that did it
/// (`cputime`: the calling thread's CPU clock plus its helper threads'; wall clock where no
/// thread clock exists): building the records (`FrameRecords::reusing`), planning the lights and
/// draws (`FramePlan::reusing`) and writing the frame's buffers (`FrameBuffers::upload` and the
/// clustered lists, the `write_buffer` calls only). `plan` includes the fp16 clamps and, for
/// `clustered`, the cluster lists (built on the CPU, they run on two threads from 1,024 lights;
/// the rest runs on the rendering thread).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct CpuMs {
    pub records: f64,
    pub plan: f64,
    pub upload: f64,
    /// Wall clock of the three on the calling thread (what the frame waited for them).
    pub wall: f64,
}

impl CpuMs {
    pub fn total(&self) -> f64 {
        self.records + self.plan + self.upload
    }
}

impl GpuMs {
    /// The time of effect `name` (`None`: it did not run, or the frame was not timed).
    pub fn effect(&self, name: &str) -> Option<f64> {
        self.effects.get(name).copied()
    }
}

pub struct Queries {
    pub timestamps: Option<wgpu::QuerySet>,
    /// One occlusion query over the whole forward pass; peeled, one per layer and one for
    /// the fragments behind the last (`FORWARD_QUERIES`).
    pub forward: wgpu::QuerySet,
    /// The light pre-pass's pass 1 (query 0) and pass 3 (query 1), one occlusion query each.
    pub prepass: wgpu::QuerySet,
    period_ns: f32,
    pub occlusion: Vec<wgpu::QuerySet>,
    pub ideal: Vec<wgpu::QuerySet>,
    /// Fragment-shader invocations of each shading draw (pipeline statistics), when the
    /// adapter has them. On lavapipe this is rasterised coverage before the depth and stencil
    /// tests, not the fragments shaded.
    pub coverage: Vec<wgpu::QuerySet>,
    coverage_supported: bool,
    /// The occlusion queries count samples (`AdapterCaps::occlusion`).
    exact: bool,
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
                count: TIMESTAMPS,
            })
        });
        let forward = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("forward fragments"),
            ty: wgpu::QueryType::Occlusion,
            count: FORWARD_QUERIES,
        });
        let prepass = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pre-pass fragments"),
            ty: wgpu::QueryType::Occlusion,
            count: 2,
        });
        Self {
            timestamps,
            forward,
            prepass,
            period_ns: gpu.queue.get_timestamp_period(),
            occlusion: Vec::new(),
            ideal: Vec::new(),
            coverage: Vec::new(),
            coverage_supported: gpu.has(wgpu::Features::PIPELINE_STATISTICS_QUERY),
            exact: gpu.caps.occlusion == crate::renderer::kit::adapter::Occlusion::Exact,
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
        let occ = PREPASS_QUERY_OFFSET + 256;
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

    /// Resolves the frame's queries; `forward`: the forward pass's occlusion queries (0: it did
    /// not count; peeled, one per layer and one behind the last),
    /// `geometry`: how many geometry passes counted theirs (1: the G-buffer pass; 2: the light
    /// pre-pass's passes 1 and 3).
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        n: usize,
        counts: bool,
        ideal: bool,
        times: bool,
        forward: u32,
        geometry: u32,
    ) {
        let (Some(resolve), Some(readback)) = (&self.resolve, &self.readback) else {
            return;
        };
        let (occ_off, ideal_off, cov_off, size) = Self::offsets(self.capacity);
        if times {
            if let Some(ts) = &self.timestamps {
                encoder.resolve_query_set(ts, 0..TIMESTAMPS, resolve, 0);
            }
        }
        if forward > 0 {
            encoder.resolve_query_set(&self.forward, 0..forward, resolve, FORWARD_QUERY_OFFSET);
        }
        if geometry > 0 && counts {
            encoder.resolve_query_set(&self.prepass, 0..geometry, resolve, PREPASS_QUERY_OFFSET);
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
        if counts || ideal || times || forward > 0 {
            encoder.copy_buffer_to_buffer(resolve, 0, readback, 0, size);
        }
    }

    /// Reads the frame's queries back: `None` when nothing was measured (or the queries only
    /// say 0 or 1, wgpu's GL backend: the counts they would give are left out, not reported
    /// wrong). `forward`: occlusion queries of the forward pass read (its peeled layers).
    pub fn read(
        &self,
        device: &wgpu::Device,
        counts: bool,
        ideal: bool,
        times: bool,
        forward: u32,
    ) -> Result<Readback> {
        let forward = if self.exact { forward } else { 0 };
        let (counts, ideal) = (counts && self.exact, ideal && self.exact);
        let mut out = Readback {
            words: Vec::new(),
            period_ns: self.period_ns,
            capacity: self.capacity,
            counts,
            ideal,
            times: times && self.timestamps.is_some(),
            forward,
            coverage: self.coverage_supported,
        };
        if !(counts || ideal || times || forward > 0) {
            return Ok(out);
        }
        let Some(readback) = &self.readback else {
            return Ok(out);
        };
        out.words = crate::renderer::kit::read_back(device, readback, readback.size())?;
        Ok(out)
    }
}

/// A frame's queries as read back ([`Queries::read`]): each figure's slots, for the report.
pub struct Readback {
    words: Vec<u64>,
    period_ns: f32,
    capacity: usize,
    /// Each light's shaded fragments were counted (exactly).
    pub counts: bool,
    /// Each light's ideal (and coverage, where the adapter has pipeline statistics).
    pub ideal: bool,
    /// The spans were timed.
    pub times: bool,
    /// Occlusion queries of the forward pass read.
    pub forward: u32,
    /// The adapter counts coverage (pipeline statistics).
    pub coverage: bool,
}

impl Readback {
    /// Whether anything was read.
    pub fn any(&self) -> bool {
        !self.words.is_empty()
    }

    /// Milliseconds from timestamp `a` to timestamp `b` (`Span::begin`, `Span::end`).
    pub fn between(&self, a: Option<u32>, b: Option<u32>) -> Option<f64> {
        let (t0, t1) = (*self.words.get(a? as usize)?, *self.words.get(b? as usize)?);
        (self.times && t1 >= t0 && t0 != 0).then(|| (t1 - t0) as f64 * self.period_ns as f64 / 1e6)
    }

    /// A span's own milliseconds.
    pub fn span(&self, s: Span) -> Option<f64> {
        self.between(s.begin(), s.end())
    }

    /// The forward pass's occlusion counts: query `i` (a peeled layer, or what is behind the
    /// last).
    pub fn forward(&self, i: usize) -> u64 {
        self.words[(FORWARD_QUERY_OFFSET / 8) as usize + i]
    }

    /// The light pre-pass's counts: pass 1 (`0`, also the G-buffer's) and pass 3 (`1`).
    pub fn prepass(&self, i: usize) -> u64 {
        self.words[(PREPASS_QUERY_OFFSET / 8) as usize + i]
    }

    /// Light `i`'s counts: (shaded, ideal, coverage).
    pub fn light(&self, i: usize) -> (u64, u64, u64) {
        let (occ_off, ideal_off, cov_off, _) = Queries::offsets(self.capacity);
        let block = LIGHTS_PER_QUERY_SET;
        let at = |base: u64| {
            let b = i / block;
            self.words[(base / 8) as usize + b * block + i % block]
        };
        (at(occ_off), at(ideal_off), at(cov_off))
    }
}
