//! Timestamp and occlusion queries turned into per-pass times and per-light fragment counts.
//!
//! Occlusion queries count samples that passed the depth and stencil tests of a light's
//! shading draw: the fragments that reached the lighting shader. The ideal is counted with the
//! same kind of query around a full-screen draw that discards every sample whose G-buffer point
//! lies outside the light's true radius and cone.

use super::culling::methods::{self, Covers};
use super::plan::{LightPlan, Method};
use super::settings::ForwardLights;
use super::{CullingMode, RenderPath};
use crate::gpu::Gpu;
use crate::scene::Scene;
use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

pub const LIGHTS_PER_QUERY_SET: usize = wgpu::QUERY_SET_MAX_QUERIES as usize;

/// What llvmpipe (lavapipe's rasteriser) may bin into one scene, in bytes, before our estimate
/// says a new render pass must start: half its `LP_SCENE_MAX_SIZE` of 36 MiB, for margin.
///
/// Why: llvmpipe bins every command into 64x64-pixel tiles and flushes ("rasterises") the
/// scene when its storage is full. An occlusion query's begin and end commands are binned
/// into *every* tile (2 x 240 commands at 1280x720, about 8.5 KiB per light), so thousands of
/// counted lights fill a scene by themselves. If the scene fills exactly while a query's begin
/// command is being binned, llvmpipe has already listed the query as active: the flushed
/// scene's tiles that did not get the begin command "end" the query at their tile end
/// (`lp_rast_tile_end`) with a start of 0, adding every sample the tile passed in the whole
/// scene. That was the `sphere-wall` report (light 3132, off screen, ideal 0, counted 3,315,608
/// fragments at 1280x720 with 4,096 lights; never at 640x360, 60 tiles, or 1,024 lights, where
/// the scene never fills); with this repository's `sphere-wall` it was light 2555, off screen,
/// counting 1,020,508 in `stencil-two-pass` (its volume: 0). The workaround keeps every scene
/// small: the lights are split into render passes whose estimated binned size stays under this
/// budget ([`light_pass_ranges`]). Observed: after the split no light is miscounted (every
/// off-screen light counts 0, two-pass never exceeds its volume, `tests/it/scale.rs`), so a render
/// pass boundary starts a new llvmpipe scene here.
pub const LLVMPIPE_SCENE_BUDGET: u64 = 18 << 20;

/// Bytes llvmpipe bins per command (its command blocks hold 29 in about 512 bytes).
const LP_COMMAND: u64 = 512 / 29 + 1;
/// Bytes of one binned triangle's record (planes and interpolation inputs; under 512).
const LP_TRIANGLE: u64 = 512;
/// llvmpipe's tile size in pixels.
const LP_TILE: u32 = 64;

/// Estimated bytes llvmpipe bins for one light's counted draws: its query's begin and end in
/// every tile, and for each of `draws` draws of `triangles` triangles every triangle in every
/// tile its screen rectangle touches (a triangle is binned only where its bounds fall; a
/// full-screen light's rectangle is the screen), with its record.
pub fn binned_bytes(plan: &LightPlan, size: (u32, u32), draws: u64, triangles: u64) -> u64 {
    let (w, h) = (size.0.max(1), size.1.max(1));
    let tiles = (w.div_ceil(LP_TILE) * h.div_ceil(LP_TILE)) as u64;
    let rect_tiles = match (plan.method, plan.screen_rect) {
        _ if methods::row(plan.method).covers == Covers::Screen => tiles,
        (_, None) => 0,
        (_, Some((lo, hi))) => {
            let t = |x: f32, n: u32| (((x + 1.0) * 0.5 * n as f32).clamp(0.0, n as f32 - 1.0) as u32) / LP_TILE;
            let (x0, x1, y0, y1) = (t(lo.x, w), t(hi.x, w), t(-hi.y, h), t(-lo.y, h));
            (((x1.saturating_sub(x0) + 2) * (y1.saturating_sub(y0) + 2)) as u64).min(tiles)
        }
    };
    2 * tiles * LP_COMMAND + draws * triangles * (rect_tiles * LP_COMMAND + LP_TRIANGLE)
}

/// Splits lights `0..n` into ranges, one per render pass, such that no range crosses a query
/// set (of [`LIGHTS_PER_QUERY_SET`]) and each range's summed `cost` (bytes llvmpipe bins,
/// [`binned_bytes`]) stays under [`LLVMPIPE_SCENE_BUDGET`] (a light costing more is alone).
pub fn pass_ranges(n: usize, cost: impl Fn(usize) -> u64) -> Vec<std::ops::Range<usize>> {
    let mut ranges = Vec::new();
    let (mut start, mut bytes) = (0, 0u64);
    for i in 0..n {
        let c = cost(i);
        if i > start && (i % LIGHTS_PER_QUERY_SET == 0 || bytes + c > LLVMPIPE_SCENE_BUDGET) {
            ranges.push(start..i);
            (start, bytes) = (i, 0);
        }
        bytes += c;
    }
    ranges.push(start..n);
    ranges
}

/// The light accumulation's ranges: by query set only when no fragment is counted (a scene
/// that fills without queries is harmless), else kept under the budget (see
/// [`LLVMPIPE_SCENE_BUDGET`]). `triangles` is the sphere's and the cone's triangle count.
pub fn light_pass_ranges(
    plans: &[LightPlan],
    size: (u32, u32),
    counts: bool,
    triangles: (u64, u64),
) -> Vec<std::ops::Range<usize>> {
    pass_ranges(plans.len(), |i| {
        let p = &plans[i];
        if !counts {
            return 0;
        }
        let t = match p.volume {
            super::volumes::VolumeKind::Sphere => triangles.0,
            super::volumes::VolumeKind::Cone => triangles.1,
        };
        let row = methods::row(p.method);
        match row.covers {
            Covers::Screen => binned_bytes(p, size, row.draws_per_light as u64, 1),
            Covers::Volume => binned_bytes(p, size, row.draws_per_light as u64, t),
            Covers::Nothing => binned_bytes(p, size, 0, 0),
        }
    })
}

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
/// last ([`crate::renderer::settings::MAX_PEEL_LAYERS`] + 1), within its 256-byte block.
const FORWARD_QUERIES: u32 = crate::renderer::settings::MAX_PEEL_LAYERS + 1;
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
    /// Samples the forward pass shaded (passed the depth test; occlusion query), when counting;
    /// peeled, every layer's together (the light pre-pass's forward-shaded opaque objects, which
    /// the unpeeled count includes, left out).
    pub fragments: Option<u64>,
    /// Layers depth peeling peeled (`--blended peeled`), and the blended samples behind the
    /// last one, which it dropped (when counting).
    pub peel_layers: Option<u32>,
    pub unpeeled: Option<u64>,
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

/// The light pre-pass's figures (`--path light-prepass`): its intermediate targets' bytes per
/// pixel and the draws and fragments of its geometry passes (1: normals + exponent, 3: final;
/// pass 2's are the frame's `draw_calls` and `shaded_fragments`).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct PrepassStats {
    /// Pass 1's normal + exponent target (Rgba8Unorm).
    pub normal_exp_bytes_per_pixel: u32,
    /// The depth copy pass 1 writes beside it (`gbuffer::prepass_layout`; R32Float, or R32Uint
    /// holding its bits where R32Float is not renderable).
    pub depth_copy_bytes_per_pixel: u32,
    /// The light buffer: format and bytes (Rgba16Float 8, seed 004's log Rgba8 4).
    pub light_buffer_format: String,
    pub light_buffer_bytes_per_pixel: u32,
    /// Pass 3's HDR scene colour (Rgba16Float).
    pub hdr_bytes_per_pixel: u32,
    /// Samples per pixel of pass 3 and the forward pass (`--msaa`).
    pub samples: u32,
    /// Their multisampled colour and depth (samples x (8 + depth's bytes), stencil not
    /// counted); 0 single-sampled.
    pub msaa_bytes_per_pixel: u32,
    /// Object draws of pass 1 and of pass 3.
    pub base_draw_calls: u64,
    pub final_draw_calls: u64,
    /// `--msaa 4`: the depth-only draws priming pass 3's samples with pass 1's list (pass 1's
    /// depth has one sample a pixel); 0 single-sampled, where pass 3 tests pass 1's depth.
    pub prime_draw_calls: u64,
    /// Samples that passed pass 1's and pass 3's depth tests (occlusion queries), when counting.
    pub base_fragments: Option<u64>,
    pub final_fragments: Option<u64>,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct LightStats {
    pub index: usize,
    /// "point" or "spot", borrowed: an allocated name per light made the per-light stats cost
    /// 1.1-1.3 ms of CPU a frame at 16,384 lights (0.16-0.62 ms borrowed; docs/measurements.md).
    pub kind: Cow<'static, str>,
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
    /// Its shadow maps this frame (`ShadowPlan::light_share`): tiles (atlas tiles or cube-array
    /// faces), their texels, and the caster draws into them; 0 when it casts no shadow.
    #[serde(default)]
    pub shadow_tiles: u32,
    #[serde(default)]
    pub shadow_texels: u64,
    #[serde(default)]
    pub caster_draws: u64,
    /// Its shadow maps' drawing time (ms): the render passes of its tiles in a ledger frame
    /// (counted, with timestamps), each timed on its own; `None` otherwise or when it casts none.
    #[serde(default)]
    pub shadow_ms: Option<f64>,
    /// Evaluated pairs that the light's true shape does not hold: `shaded - ideal`, when
    /// both were counted (the culling's false positives for this light).
    #[serde(default)]
    pub wasted: Option<u64>,
    /// Its cost in the light pass by the frame's [`CostModel`](crate::renderer::explain::cost::CostModel)
    /// (ms): its draws and its evaluated pairs.
    #[serde(default)]
    pub cost_ms: Option<f64>,
    /// Its share of the light pass's measured time (ms): the measured pass times its cost over
    /// the model's whole pass (fixed part + every light's cost). The shares and the fixed part's
    /// add up to the measured pass by construction; the model only weighs them.
    #[serde(default)]
    pub share_ms: Option<f64>,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct FrameStats {
    /// The adapter, its capability table and the fallbacks this frame took.
    pub adapter: crate::renderer::kit::caps::CapsReport,
    pub size: [u32; 2],
    pub culling: CullingMode,
    pub lights: usize,
    pub gpu_ms: GpuMs,
    /// The CPU's part of the frame: records, plan, upload.
    pub cpu_ms: CpuMs,
    /// The CPU's part (records, plans, clamps, shadow plan) and its upload were the frame
    /// before's, taken as they were: its inputs were the same (`frame::FrameKey`).
    #[serde(default)]
    pub cpu_reused: bool,
    pub shaded_fragments: Option<u64>,
    pub ideal_fragments: Option<u64>,
    /// Rasterised coverage of the shading draws (pipeline statistics), where supported.
    pub coverage_fragments: Option<u64>,
    /// ideal / shaded.
    pub efficiency: Option<f64>,
    /// shaded - ideal, summed over the lights (when both were counted).
    pub wasted_fragments: Option<u64>,
    /// The model the per-light `cost_ms` come from, and its sum over the lights with the
    /// fixed part apart (`light_cost_ms` + `cost_model.fixed_ms` against `gpu_ms.lighting`).
    pub cost_model: Option<crate::renderer::explain::cost::CostModel>,
    pub light_cost_ms: Option<f64>,
    /// The forward pass of blended surfaces, when the frame drew one.
    pub forward: Option<ForwardStats>,
    /// The tiled pass's light lists, when the frame (or the `tile-lights` view) built them.
    pub tiles: Option<TileStats>,
    pub gbuffer_layout: String,
    /// Colour targets of the G-buffer (the depth-stencil buffer is named apart).
    pub gbuffer_bytes_per_pixel: u32,
    /// Samples that passed the G-buffer pass's depth test (deferred shading; the light
    /// pre-pass's pass 1): the fragments it wrote, overdraw included, which the draw order
    /// (`--draw-order`) changes. `None` without counting and on the forward paths.
    pub gbuffer_fragments: Option<u64>,
    pub depth_stencil_format: String,
    /// Where the passes after the G-buffer read depth: "depth buffer", or the copy and why
    /// (`kit::gbuffer::depth_read_refusal`), or none (a layout storing positions; the forward
    /// paths).
    pub depth_read: String,
    pub depth_clamp: bool,
    /// Ambient + sun were written by the G-buffer pass (`Settings::ambient_in_gbuffer`, where
    /// the device allows), not by a full-screen pass of their own.
    pub ambient_in_gbuffer: bool,
    /// Format of the light accumulation targets.
    pub accumulation_format: String,
    /// Bytes per pixel of the accumulation targets: two (diffuse, specular), or one (the light
    /// pre-pass's light buffer, seed 000's RT1).
    pub accumulation_bytes_per_pixel: u32,
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
    /// The GPU built light lists this frame (tiled, zbin's masks, or clustered with
    /// `--cluster-build gpu`).
    #[serde(default)]
    pub lists_on_gpu: bool,
    /// Which post-chain passes ran (`None`: the frame was tonemapped by compose, no chain).
    pub post: Option<PostStats>,
    /// One entry per light when the frame counted or asked for them
    /// (`Settings::per_light_stats`); empty otherwise, and `per_light_stats` says which.
    pub per_light: Vec<LightStats>,
    /// Whether `per_light` was built this frame.
    #[serde(default)]
    pub per_light_stats: bool,
    /// The shadow and cookie lookups compiled into this frame's shaders, by name
    /// (`program::ShaderFeatures::names`): only those some light of the scene can need.
    #[serde(default)]
    pub shader_lookups: Vec<String>,
    /// The shadow atlas and who casts (`None` with `--shadows none`).
    #[serde(default)]
    pub shadow: Option<crate::renderer::shadows::ShadowStats>,
    /// The forward paths' passes, targets and lists (`None` on the other paths).
    pub forward_path: Option<super::paths::forward_pass::ForwardPathStats>,
    /// The render path the frame was drawn with.
    pub path: crate::renderer::RenderPath,
    /// The light pre-pass's own figures (`None` on the other paths).
    pub prepass: Option<PrepassStats>,
    /// What the engine-style caps dropped (`caps`); `None` with no cap set.
    #[serde(default)]
    pub caps: Option<crate::renderer::caps::CapStats>,
}

/// The post chain of a frame: which effects ran (the tonemap always runs in the chain) and,
/// with auto-exposure, the exposure state after the frame is read by `Renderer::exposure_state`.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct PostStats {
    pub bloom: bool,
    pub auto_exposure: bool,
    pub tonemap: crate::renderer::post::Tonemap,
    /// The effects after tone mapping that ran, by name, in the chain's order
    /// (`post::effects::EFFECTS`).
    pub effects: Vec<String>,
}

impl PostStats {
    /// Whether effect `name` ran.
    pub fn ran(&self, name: &str) -> bool {
        self.effects.iter().any(|e| e == name)
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
    /// The occlusion queries count samples (`Caps::occlusion`).
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
            exact: gpu.caps.occlusion == crate::renderer::kit::caps::Occlusion::Exact,
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

    /// Reads the frame's queries back into `stats`. Long (about 150 lines) because it fills each
    /// measured figure in turn (the spans, the forward and pre-pass counts, each light's counts),
    /// each a few lines that read its slots.
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
        forward: u32,
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
                ..Default::default()
            })
            .collect();
        // Occlusion queries that only say 0 or 1 (wgpu's GL backend) count nothing: the counts
        // they would give are left out, not reported wrong.
        let forward = if self.exact { forward } else { 0 };
        let (counts, ideal) = (counts && self.exact, ideal && self.exact);
        if !(counts || ideal || times || forward > 0) {
            return Ok(());
        }
        let Some(readback) = &self.readback else {
            return Ok(());
        };
        let words: Vec<u64> = crate::renderer::kit::read_back(device, readback, readback.size())?;
        {
            let words = &words[..];
            let (occ_off, ideal_off, cov_off, _) = Self::offsets(self.capacity);
            if times && self.timestamps.is_some() {
                let ms = |a: usize, b: usize| {
                    let (t0, t1) = (words[a], words[b]);
                    (t1 >= t0 && t0 != 0).then(|| (t1 - t0) as f64 * self.period_ns as f64 / 1e6)
                };
                // From one timestamp to another (`Span::begin`, `Span::end`), and a span's own.
                let between = |a: Option<u32>, b: Option<u32>| ms(a? as usize, b? as usize);
                let span = |s: Span| between(s.begin(), s.end());
                use crate::renderer::paths::prepass_pass as prepass;
                use crate::renderer::surfaces::{blended as forward, compose, gbuffer};
                use crate::renderer::{culling, post, shadows};
                let (gbuffer, compose) = (gbuffer::SPAN, compose::SPAN);
                stats.gpu_ms.gbuffer = span(gbuffer);
                stats.gpu_ms.lighting = span(culling::light_pass::SPAN);
                stats.gpu_ms.compose = span(compose);
                stats.gpu_ms.lists = span(culling::tiled::pass::SPAN).filter(|_| stats.lists_on_gpu);
                if stats.prepass.is_some() {
                    // The light pre-pass has no compose: its pass 3 writes the HDR colour, and
                    // what follows it (forward pass, tonemap or post chain) is the compose span.
                    stats.gpu_ms.prepass_final = span(prepass::SPAN);
                    stats.gpu_ms.compose = between(prepass::SPAN.end(), compose.end());
                }
                if stats.forward.is_some() {
                    stats.gpu_ms.forward = span(forward::SPAN);
                    // The forward pass runs between the HDR compose and the tonemap.
                    if let (Some(c), Some(f)) = (stats.gpu_ms.compose, stats.gpu_ms.forward) {
                        stats.gpu_ms.compose = Some((c - f).max(0.0));
                    }
                }
                stats.gpu_ms.total = between(gbuffer.begin(), compose.end());
                if let Some(sh) = stats.shadow.as_mut().filter(|s| s.tiles > 0) {
                    sh.gpu_ms = span(shadows::pass::SPAN);
                    stats.gpu_ms.shadows = sh.gpu_ms;
                }
                if let Some(fp) = stats.forward_path.as_mut() {
                    // The forward paths: each pass's own span; no light pass, and the G-buffer
                    // only when the post chain needed it (one of the passes then).
                    for p in &mut fp.passes {
                        p.gpu_ms = p.span.and_then(span);
                    }
                    stats.gpu_ms.lighting = None;
                    stats.gpu_ms.gbuffer = None;
                    stats.gpu_ms.total =
                        fp.passes.first().and_then(|p| p.span).and_then(|s| between(s.begin(), compose.end()));
                }
                if let (Some(t), Some(s)) = (stats.gpu_ms.total, stats.gpu_ms.shadows) {
                    stats.gpu_ms.total = Some(t + s);
                }
                if let Some(p) = &stats.post {
                    // The chain runs inside the compose span (HDR compose … its last pass).
                    let g = &mut stats.gpu_ms;
                    g.bloom = span(post::bloom::SPAN).filter(|_| p.bloom);
                    g.exposure = span(post::exposure::SPAN).filter(|_| p.auto_exposure);
                    g.tonemap = span(post::tonemap::SPAN);
                    g.effects = post::effects::EFFECTS
                        .iter()
                        .filter(|e| p.ran(e.name))
                        .filter_map(|e| Some((e.name.to_string(), span(Span(e.name))?)))
                        .collect();
                    let chain: f64 = [g.bloom, g.exposure, g.tonemap].iter().flatten().sum::<f64>()
                        + g.effects.values().sum::<f64>();
                    g.compose = g.compose.map(|c| (c - chain).max(0.0));
                }
            }
            if let Some(f) = stats.forward.as_mut().filter(|_| forward > 0) {
                let at = (FORWARD_QUERY_OFFSET / 8) as usize;
                let layers = f.peel_layers.map_or(1, |n| n as usize);
                f.fragments = Some(words[at..at + layers].iter().sum());
                if f.peel_layers.is_some() {
                    f.unpeeled = Some(words[at + layers]);
                }
            }
            if counts && matches!(stats.path, RenderPath::Deferred | RenderPath::LightPrepass) {
                stats.gbuffer_fragments = Some(words[(PREPASS_QUERY_OFFSET / 8) as usize]);
            }
            if let Some(p) = stats.prepass.as_mut().filter(|_| counts) {
                p.base_fragments = Some(words[(PREPASS_QUERY_OFFSET / 8) as usize]);
                p.final_fragments = Some(words[(PREPASS_QUERY_OFFSET / 8) as usize + 1]);
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
