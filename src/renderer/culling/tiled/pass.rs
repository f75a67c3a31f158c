//! The `tiled` and `clustered` culling modes on the GPU, and their debug view.
//!
//! - `tiled` (Andersson 2011): a compute pass, one 16x16 workgroup per screen tile, takes the
//!   tile's depth bounds from the G-buffer, tests every light's sphere against the tile's
//!   frustum between them and writes the tile's list in light order (`cs_tile_lists`).
//! - `clustered` (Olsson et al. 2012): the lists come from the CPU (`tiles::cluster_lists`), or
//!   the GPU builds them from each light's span of clusters (`--cluster-build gpu`): a count
//!   pass, a prefix sum, a fill pass and a per-cluster sort into light order
//!   (`cs_cluster_{count,scan,fill,sort}`), the same tests as the CPU's.
//! - Both: ONE full-screen pass (`fs_tiled`) shades each valid pixel with its list through
//!   `shade_light_as` and the per-light clamp, adding into the same accumulation targets after
//!   the ambient + sun pass (with `ShadowCode::casters_apart`, a list's casting lights in a
//!   second loop, the only one with the shadow lookups). With `count_fragments` the frame uses
//!   `fs_tiled_counted`, which counts each evaluated light-pixel pair per light (`atomicAdd`),
//!   so `shaded` means what it means for the per-light methods.
//! - `tile-lights` view: each pixel's list length into the debug target (`fs_tile_count`).
//!
//! Buffers live here (they depend on the frame's size and light count), behind a mutex since
//! passes record through `&self`.

use super::scratch::{Buffers, Pending, TiledScratch};
use super::TileStats;
use crate::renderer::culling::zbin::ZBinJob;
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::bindings;
use crate::renderer::kit::{log_accum, Declared, Shared, ADDITIVE, DEBUG_FORMAT, MULTIPLY};
use crate::renderer::plan::{LightPlan, Method};
use crate::renderer::records::TileParams;
use crate::renderer::settings::DebugView;
use crate::renderer::stats::Span;
use crate::renderer::tiles::{ClusterBuild, ALL_LIGHTS, TILE};
use anyhow::Result;

/// The GPU building the light lists (`gpu_ms.lists`, inside the lighting's span).
pub const SPAN: Span = Span("light lists");

/// Average list entries per tile the GPU list buffer holds room for (tiles beyond it are
/// shaded with every light, correct but slower; the stats count them as `overflowed`).
pub const ENTRIES_PER_TILE: u32 = 1024;
/// Most u32 entries the list buffer holds: 128 MiB, WebGPU's guaranteed binding size.
pub const MAX_ENTRIES: u64 = (128 << 20) / 4;

/// The last frame's lists as the GPU held them (for tests and inspection): the parameters,
/// then a (first, count) pair per cell followed by the entries.
pub struct TileLists {
    pub params: TileParams,
    pub data: Vec<u32>,
    /// Z-binned: the tiles' masks as the GPU built them (`params.words` words a tile).
    pub masks: Vec<u32>,
}

impl TileLists {
    /// The cell of pixel (`x`, `y`) whose G-buffer point lies at view depth `depth`, as
    /// `tile_cell` in `tiled.wgsl` finds it.
    pub fn cell(&self, x: u32, y: u32, depth: f32) -> usize {
        let p = &self.params;
        let tile = (y / p.tile_size).min(p.tiles_y - 1) * p.tiles_x + (x / p.tile_size).min(p.tiles_x - 1);
        if p.mode == 0 {
            return tile as usize;
        }
        let k = (depth.max(1e-30).ln() * p.slice_scale + p.slice_bias).floor().clamp(0.0, (p.slices - 1) as f32);
        (k as u32 * p.tiles_x * p.tiles_y + tile) as usize
    }

    /// The cells pixel (`x`, `y`) at view depth `depth` may lie in when the GPU's logarithm and
    /// point differ from the caller's by up to `margin` of a slice: [`Self::cell`]'s, and the
    /// neighbouring slice's when the depth lies within `margin` of a boundary (for tests that
    /// rebuild the GPU's choice on the CPU).
    pub fn cells_near(&self, x: u32, y: u32, depth: f32, margin: f32) -> Vec<usize> {
        let p = &self.params;
        let cell = self.cell(x, y, depth);
        if p.mode == 0 {
            return vec![cell];
        }
        let tiles = (p.tiles_x * p.tiles_y) as usize;
        let t = depth.max(1e-30).ln() * p.slice_scale + p.slice_bias;
        let k = cell / tiles;
        let mut out = vec![cell];
        let f = t - t.floor();
        if f < margin && k > 0 && t < p.slices as f32 {
            out.push(cell - tiles);
        }
        if f > 1.0 - margin && k + 1 < p.slices as usize && t >= 0.0 {
            out.push(cell + tiles);
        }
        out
    }

    /// Light indices of `cell` (every light when the GPU ran out of room for it). Z-binned,
    /// a cell is a tile at a bin (numbered as clusters are): the sorted lights of the bin's
    /// range whose bit the tile's mask holds, in the order the shading pass walks them.
    pub fn list(&self, cell: usize) -> Vec<u32> {
        let p = &self.params;
        if p.mode == 2 {
            let tiles = (p.tiles_x * p.tiles_y) as usize;
            let (k, tile) = (cell / tiles, cell % tiles);
            let (first, end) = (self.data[2 * k], self.data[2 * k + 1]);
            let base = tile * p.words as usize;
            return (first..end)
                .filter(|&j| self.masks.get(base + (j / 32) as usize).is_some_and(|w| w >> (j % 32) & 1 == 1))
                .filter_map(|j| self.data.get((p.order_base + j) as usize).copied())
                .collect();
        }
        let (first, count) = (self.data[2 * cell] as usize, self.data[2 * cell + 1]);
        if count == ALL_LIGHTS {
            return (0..self.params.light_count).collect();
        }
        self.data[first..first + count as usize].to_vec()
    }
}

pub struct TiledPass {
    bgl: wgpu::BindGroupLayout,
    build: crate::renderer::kit::ComputePipe,
    /// The GPU's clustered lists: count, scan, fill, sort.
    cluster: [crate::renderer::kit::ComputePipe; 4],
    /// `fs_tiled`.
    shade: crate::renderer::kit::RenderPipe,
    /// `fs_tiled_counted`, for frames that count each light's pairs (the ledger): built by the
    /// first such frame, so a configuration that never counts compiles no counter, from
    /// `counted_from` (the module, the layout and the targets).
    counted: std::sync::OnceLock<crate::renderer::kit::RenderPipe>,
    counted_from: (wgpu::ShaderModule, wgpu::PipelineLayout, [Option<wgpu::ColorTargetState>; 2]),
    count_view: crate::renderer::kit::RenderPipe,
    /// The ledger's waste view (`fs_tile_waste`) of frames the tiled pass shades.
    waste_view: crate::renderer::kit::RenderPipe,
    /// Z-binned frames' mask building (`cs_zbin_mask`) and shading (`fs_zbin`, and
    /// `fs_zbin_counted`), built by the first such frame.
    zbin: std::sync::OnceLock<([crate::renderer::kit::ComputePipe; 2], crate::renderer::kit::RenderPipe)>,
    zbin_counted: std::sync::OnceLock<crate::renderer::kit::RenderPipe>,
    /// The reservoir-resampled shading of either (`stochastic::ris`).
    ris: crate::renderer::stochastic::ris::RisPipes,
    /// RIS with reuse: the candidates and spatial passes and the resolve (`stochastic::reuse`).
    reuse: crate::renderer::stochastic::reuse::ReusePipes,
}

fn buffer(device: &wgpu::Device, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage,
        mapped_at_creation: false,
    })
}

impl TiledPass {
    /// Whether a counted frame has built `fs_tiled_counted`.
    pub fn counter_built(&self) -> bool {
        self.counted.get().is_some()
    }

    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let bgl = bindings::TILES.layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tiled"),
            bind_group_layouts: &[Some(&shared.frame_bgl), Some(&shared.gbuffer_bgl), Some(&bgl)],
            immediate_size: 0,
        });
        let compute =
            |label, entry| crate::renderer::kit::compute_pipe(device, label, Some(&layout), &shared.module, entry);
        let build = compute("tile lists", "cs_tile_lists");
        let cluster = [
            compute("cluster count", "cs_cluster_count"),
            compute("cluster scan", "cs_cluster_scan"),
            compute("cluster fill", "cs_cluster_fill"),
            compute("cluster sort", "cs_cluster_sort"),
        ];
        let blend = if log_accum(shared.key.accum_format) { MULTIPLY } else { ADDITIVE };
        let accum = wgpu::ColorTargetState {
            format: shared.key.accum_format,
            blend: Some(blend),
            write_mask: wgpu::ColorWrites::ALL,
        };
        let debug = wgpu::ColorTargetState { format: DEBUG_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL };
        let pipe = |label, vs, fs, targets: &[Option<wgpu::ColorTargetState>]| {
            shared.screen_pipeline(device, label, &layout, (vs, fs), targets)
        };
        // The light pre-pass has one light buffer (`Targets::accumulation`).
        let second = Some(accum.clone()).filter(|_| !shared.key.one_target());
        let targets = [Some(accum), second];
        let shade = pipe("tiled shade", "vs_tiled", "fs_tiled", &targets);
        let count_view = pipe("tile lights view", "vs_compose", "fs_tile_count", &[Some(debug.clone())]);
        let waste_view = pipe("waste view (lists)", "vs_compose", "fs_tile_waste", &[Some(debug)]);
        let reuse = crate::renderer::stochastic::reuse::ReusePipes::new([&shared.frame_bgl, &shared.gbuffer_bgl, &bgl]);
        Self {
            bgl,
            build,
            cluster,
            shade,
            counted: std::sync::OnceLock::new(),
            counted_from: (shared.module.clone(), layout.clone(), targets),
            count_view,
            waste_view,
            zbin: std::sync::OnceLock::new(),
            zbin_counted: std::sync::OnceLock::new(),
            ris: Default::default(),
            reuse,
        }
    }

    /// The z-binned frame's mask pass and shading pipeline (`counted`: the one counting each
    /// light's pairs), built on first use.
    fn zbin_pipelines(
        &self,
        device: &wgpu::Device,
        counted: bool,
    ) -> (&[crate::renderer::kit::ComputePipe; 2], &crate::renderer::kit::RenderPipe) {
        let (module, layout, targets) = &self.counted_from;
        let (mask, shade) = self.zbin.get_or_init(|| {
            let compute = |label, entry| crate::renderer::kit::compute_pipe(device, label, Some(layout), module, entry);
            let mask = [compute("z-bin tile bounds", "cs_zbin_bounds"), compute("z-bin masks", "cs_zbin_mask")];
            let stages = ("vs_tiled", "fs_zbin");
            (mask, crate::renderer::kit::screen_pipeline(device, module, "z-bin shade", layout, stages, targets))
        });
        if !counted {
            return (mask, shade);
        }
        let shade = self.zbin_counted.get_or_init(|| {
            let stages = ("vs_tiled", "fs_zbin_counted");
            crate::renderer::kit::screen_pipeline(device, module, "z-bin shade, counted", layout, stages, targets)
        });
        (mask, shade)
    }

    /// The `tile-lights` view's pipeline, or the waste view's over the tiled lists, when shown.
    fn view(&self, f: &FrameInputs<'_>) -> Option<&crate::renderer::kit::RenderPipe> {
        match f.options.frame.debug_view {
            DebugView::TileLights => Some(&self.count_view),
            DebugView::Waste if f.plan.tiled.is_some() => Some(&self.waste_view),
            _ => None,
        }
    }

    /// The shading pipeline: z-binned or tiled/clustered, reservoir-resampled, or exact and
    /// counting each light's pairs or not (a resampled frame counts none).
    fn shade(&self, f: &FrameInputs<'_>, zbin: bool) -> &crate::renderer::kit::RenderPipe {
        if f.options.ris_passes() {
            let (module, _, targets) = &self.counted_from;
            return self.reuse.resolve(f.device, module, targets, f.options);
        }
        if f.options.stochastic.ris() {
            let (module, layout, targets) = &self.counted_from;
            return self.ris.get(f.device, (module, layout, targets), zbin);
        }
        match f.counts {
            _ if zbin => self.zbin_pipelines(f.device, f.counts).1,
            true => self.counted.get_or_init(|| {
                let (module, layout, targets) = &self.counted_from;
                let stages = ("vs_tiled", "fs_tiled_counted");
                crate::renderer::kit::screen_pipeline(f.device, module, "tiled shade, counted", layout, stages, targets)
            }),
            false => &self.shade,
        }
    }
}

/// What the tiled pass records for one frame, worked out from its inputs alone (so
/// `prepare`, `declare` and `encode` agree): the grid ([`grid`]), the lists' sizes, and where
/// they come from.
struct Frame<'f> {
    method: Method,
    clusters: Option<&'f ClusterBuild>,
    zbins: Option<&'f ZBinJob>,
    /// CPU-built lists as they fit one binding (`ClusterLists::fitted`).
    cpu_lists: Option<std::borrow::Cow<'f, [u32]>>,
    /// Tiled: the lights' rectangles of tiles ([`tile_rects`]), after the lists.
    rects: Option<Vec<u32>>,
    params: TileParams,
    entries: u64,
    cells: u64,
    mask_words: u64,
    list_words: u64,
    count_words: u64,
}

impl<'f> Frame<'f> {
    fn of(f: &'f FrameInputs<'_>) -> Frame<'f> {
        let method = match (f.plan.tiled, &f.plan.clusters, &f.plan.zbins) {
            (Some(Method::Clustered), Some(_), _) => Method::Clustered,
            (Some(Method::Zbin), _, Some(_)) => Method::Zbin,
            _ => Method::Tiled,
        };
        let n = f.plan.lights.len();
        let clusters = f.plan.clusters.as_ref().filter(|_| method == Method::Clustered);
        let zbins = f.plan.zbins.as_ref().filter(|_| method == Method::Zbin);
        let cpu_lists = match clusters {
            Some(ClusterBuild::Cpu(c)) => Some(c.fitted(MAX_ENTRIES as usize)),
            _ => None,
        };
        let rects = (method == Method::Tiled).then(|| tile_rects(&f.plan.lights, (f.targets.width, f.targets.height)));
        let (params, entries) = grid(f, clusters, cpu_lists.as_deref(), zbins, rects.as_deref());
        // Z-binned: the stats' cells are the masks' tiles (a tile's entries, its mask's bits).
        let cells = match zbins {
            Some(_) => (params.tiles_x * params.tiles_y) as u64,
            None => (params.tiles_x * params.tiles_y * params.slices) as u64,
        };
        // GPU-built clusters: the lights' spans after the lists, a counter per cluster after
        // the lights' counts.
        // Z-binned: the masks after the lights' counts, then two words a tile (depth bounds).
        let mask_words = zbins.map_or(0, |z| (z.grid.tiles_x * z.grid.tiles_y) as u64 * z.words as u64);
        // Each tile's summary (a bit per mask word holding a bit) and its depth bounds.
        let summary_words = zbins.map_or(0, |z| (z.grid.tiles_x * z.grid.tiles_y) as u64 * z.words.div_ceil(32) as u64);
        let bound_words = zbins.map_or(0, |z| 2 * (z.grid.tiles_x * z.grid.tiles_y) as u64);
        let (list_words, count_words) = match (clusters, &rects) {
            (Some(ClusterBuild::Gpu(_)), _) => (entries + 4 * n as u64, n as u64 + 1 + cells),
            (_, Some(r)) => (entries + r.len() as u64, n as u64 + 1),
            _ => (entries, n as u64 + 1 + mask_words + summary_words + bound_words),
        };
        Frame { method, clusters, zbins, cpu_lists, rects, params, entries, cells, mask_words, list_words, count_words }
    }

    fn gpu_job(&self) -> Option<&'f crate::renderer::tiles::ClusterJob> {
        match self.clusters {
            Some(ClusterBuild::Gpu(j)) => Some(j),
            _ => None,
        }
    }
}

impl Pass for TiledPass {
    /// The lists' buffers, grown to this frame's lists.
    fn prepare(&self, f: &FrameInputs<'_>) -> Result<()> {
        if f.plan.tiled.is_none() && self.view(f).is_none() {
            return Ok(());
        }
        let fr = Frame::of(f);
        if f.plan.tiled.is_some() && f.options.ris_passes() {
            f.scratch.reuse.fit(f, &self.reuse)?;
        }
        let mut state = f.scratch.tiled.state.lock().map_err(|_| anyhow::anyhow!("tile lists lock poisoned"))?;
        self.fit_buffers(f.device, &mut state.0, fr.list_words, fr.count_words);
        Ok(())
    }

    /// The view's pipeline; the GPU's cluster building (with lights), the tile building
    /// (tiled), the z-bin masks (with visible lights); the shading when the plan shades with
    /// the lists.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        let view = self.view(f);
        if f.plan.tiled.is_none() && view.is_none() {
            return;
        }
        out.add_all(view);
        let fr = Frame::of(f);
        if fr.gpu_job().is_some() && !f.plan.lights.is_empty() {
            out.add_all(&self.cluster);
        }
        if fr.method == Method::Tiled {
            out.add(&self.build);
        }
        if fr.zbins.is_some_and(|z| z.visible > 0) {
            out.add_all(self.zbin_pipelines(f.device, f.counts).0);
        }
        if f.plan.tiled.is_some() {
            out.add(self.shade(f, fr.zbins.is_some()));
            if f.options.ris_passes() {
                let module = &self.counted_from.0;
                out.add_all(self.reuse.compute(f.device, module, fr.zbins.is_some()));
                out.add_all(self.reuse.after_spatial(f.device, module, f.options));
                if f.options.frame.debug_view == DebugView::Variance {
                    out.add(self.reuse.variance(f.device, module, debug_target()));
                }
            }
        }
    }

    /// Records the tiled pass when the frame's plan shades with it (lists, then one
    /// full-screen shading pass that ends the lighting's timestamps) and the `tile-lists` view
    /// when shown. It uploads the parameters and the clustered lists (or the lights' spans
    /// the GPU builds them from) into the buffers `prepare` made, and reports the ms that
    /// upload took, CPU over all threads and wall clock (`cputime`; part of the frame's
    /// `cpu_ms.upload` and `cpu_ms.wall`). The steps:
    /// 1. the grid and the lists' sizes ([`Frame::of`]);
    /// 2. the upload: parameters, and the CPU-built lists or the spans the GPU lists from;
    /// 3. the passes ([`TiledPass::record`]): the GPU's list building, the shading, the view.
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        let view = self.view(f);
        let Ok(mut state) = f.scratch.tiled.state.lock() else { return Ok(PassReport::default()) };
        state.1 = None;
        if f.plan.tiled.is_none() && view.is_none() {
            return Ok(PassReport::default());
        }
        let fr = Frame::of(f);
        let (n, queue) = (f.plan.lights.len(), f.queue);
        let Some(b) = state.0.as_mut().filter(|b| b.lists.size() >= fr.list_words * 4) else {
            return Ok(PassReport::default());
        };
        let made = std::mem::replace(&mut b.fresh, false);
        let b = &*b;
        let clock = crate::renderer::cputime::Clock::start();
        queue.write_buffer(&b.params, 0, bytemuck::bytes_of(&fr.params));
        // The lists and spans the CPU built, unless the buffer holds this very frame's already
        // (the frame before had the same inputs, and nothing wrote the lists since: the GPU
        // writes only the counts, and its own lists before the spans).
        if made || !f.reused {
            if let Some(d) = &fr.cpu_lists {
                queue.write_buffer(&b.lists, 0, bytemuck::cast_slice(d));
            }
            if let Some(j) = fr.gpu_job() {
                queue.write_buffer(&b.lists, fr.entries * 4, bytemuck::cast_slice(&j.spans));
            }
            if let Some(z) = fr.zbins {
                queue.write_buffer(&b.lists, 0, bytemuck::cast_slice(&z.data));
            }
            if let Some(r) = fr.rects.as_ref().filter(|r| !r.is_empty()) {
                queue.write_buffer(&b.lists, fr.entries * 4, bytemuck::cast_slice(r));
            }
        }
        let upload_ms = (clock.ms(), clock.wall_ms());
        encoder.clear_buffer(&b.counts, 0, Some(fr.count_words * 4));
        let shade = self.shade(f, fr.zbins.is_some());
        let zbin = fr.zbins.map(|z| (self.zbin_pipelines(f.device, f.counts).0, z));
        let (method, cells) = (fr.method, fr.cells);
        self.record(encoder, f, b, (method, fr.gpu_job().is_some(), view), (shade, &fr.params, zbin), cells)?;
        if f.counts {
            if fr.zbins.is_none() {
                encoder.copy_buffer_to_buffer(&b.lists, 0, &b.lists_read, 0, cells * 8);
            }
            encoder.copy_buffer_to_buffer(&b.counts, 0, &b.counts_read, 0, fr.count_words * 4);
        }
        state.1 = Some(Pending {
            method,
            cells,
            lights: n,
            counted: f.counts,
            tile_size: fr.params.tile_size,
            slices: fr.params.slices,
            params: fr.params,
            words: fr.entries,
            mask_words: fr.mask_words,
        });
        Ok(PassReport { upload_ms, ..Default::default() })
    }
}

impl TiledPass {
    /// Makes the buffers anew when they are missing or too small (`list_words` list words and
    /// `count_words` count words), with their bind group and read-backs.
    fn fit_buffers(&self, device: &wgpu::Device, slot: &mut Option<Buffers>, list_words: u64, count_words: u64) {
        let fits = |b: &Buffers| b.lists.size() >= list_words * 4 && b.counts.size() >= count_words * 4;
        if slot.as_ref().is_some_and(fits) {
            return;
        }
        use wgpu::BufferUsages as U;
        // Rounded up to a power of two to grow less often, but never past what one binding may
        // hold (the lists and spans were sized to fit it).
        let lists = buffer(
            device,
            "tile lists",
            (list_words * 4).next_power_of_two().min(MAX_ENTRIES * 4).max(list_words * 4),
            U::STORAGE | U::COPY_DST | U::COPY_SRC,
        );
        let counts = buffer(
            device,
            "tile counts",
            (count_words * 4).next_power_of_two().min(MAX_ENTRIES * 4).max(count_words * 4),
            U::STORAGE | U::COPY_DST | U::COPY_SRC,
        );
        let params = buffer(device, "tile params", std::mem::size_of::<TileParams>() as u64, U::STORAGE | U::COPY_DST);
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tiles"),
            layout: &self.bgl,
            entries: &bindings::TILES.entries(vec![
                params.as_entire_binding(),
                lists.as_entire_binding(),
                counts.as_entire_binding(),
            ]),
        });
        let lists_read = buffer(device, "tile lists readback", lists.size(), U::COPY_DST | U::MAP_READ);
        let counts_read = buffer(device, "tile counts readback", counts.size(), U::COPY_DST | U::MAP_READ);
        *slot = Some(Buffers { params, lists, counts, group, lists_read, counts_read, fresh: true });
    }

    /// Records the passes over the lists in `b`: the GPU's cluster building (`gpu_lists`) or
    /// tile building (`method` tiled), the shading when the plan shades with them, and the
    /// `tile-lights` view (`view`).
    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        b: &Buffers,
        (method, gpu_lists, view): (Method, bool, Option<&crate::renderer::kit::RenderPipe>),
        (shade, params, zbin): (
            &crate::renderer::kit::RenderPipe,
            &TileParams,
            Option<(&[crate::renderer::kit::ComputePipe; 2], &ZBinJob)>,
        ),
        cells: u64,
    ) -> Result<()> {
        let n = f.plan.lights.len();
        let bind = |pass: &mut dyn SetGroups| {
            pass.groups(&f.frame.group, &f.targets.gbuffer_group, &b.group);
        };
        if gpu_lists && n > 0 {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("cluster lists"),
                timestamp_writes: f.compute_timestamps(SPAN),
            });
            bind(&mut pass);
            let [count, scan, fill, sort] = &self.cluster;
            let lights = (n as u32).div_ceil(64);
            pass.set_pipeline(count);
            pass.dispatch_workgroups(lights, 1, 1);
            pass.set_pipeline(scan);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(fill);
            pass.dispatch_workgroups(lights, 1, 1);
            pass.set_pipeline(sort);
            let groups = (cells as u32).div_ceil(64);
            pass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
        }
        if let Some(([bounds, mask], z)) = zbin.filter(|(_, z)| z.visible > 0) {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("z-bin masks"),
                timestamp_writes: f.compute_timestamps(SPAN),
            });
            bind(&mut pass);
            // The tiles' depth bounds, a 16x16 workgroup per 16x16 pixels, then the masks.
            pass.set_pipeline(bounds);
            pass.dispatch_workgroups(f.targets.width.div_ceil(16), f.targets.height.div_ceil(16), 1);
            pass.set_pipeline(mask);
            let groups = z.visible.div_ceil(64);
            pass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
        }
        if method == Method::Tiled {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("tile lists"),
                timestamp_writes: f.compute_timestamps(SPAN),
            });
            pass.set_pipeline(&self.build);
            bind(&mut pass);
            pass.dispatch_workgroups(params.tiles_x, params.tiles_y, 1);
        }
        // RIS with reuse: the candidates and spatial passes, then the resolve with the
        // reservoirs bound.
        let reservoirs = match f.plan.tiled.is_some() && f.options.ris_passes() {
            true => {
                let module = &self.counted_from.0;
                let pipes = self.reuse.compute(f.device, module, zbin.is_some());
                let after = self.reuse.after_spatial(f.device, module, f.options);
                Some(f.scratch.reuse.record(encoder, f, (pipes, after), &|pass| bind(pass))?)
            }
            false => None,
        };
        if f.plan.tiled.is_some() {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tiled shade"),
                color_attachments: &f.targets.accumulation(false),
                depth_stencil_attachment: None,
                timestamp_writes: f.timestamps(None, Some(crate::renderer::culling::light_pass::SPAN)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(shade);
            bind(&mut pass);
            if let Some(group) = &reservoirs {
                pass.set_bind_group(3, group, &[]);
            }
            // One instance per `SHADE_CHUNK` list entries (lavapipe's loop limit), or per
            // `ZBinJob::chunk` sorted lights.
            // A resampled frame visits M x K entries a pixel, in one instance.
            let draws = match zbin {
                _ if f.options.stochastic.ris() => 1,
                None => crate::renderer::tiles::shade_chunks(n),
                Some((_, z)) => z.draws(),
            };
            pass.draw(0..3, 0..draws);
        }
        if let Some(group) = reservoirs.as_ref().filter(|_| f.options.frame.debug_view == DebugView::Variance) {
            let pipe = self.reuse.variance(f.device, &self.counted_from.0, debug_target());
            let mut pass = f.debug_target_pass(encoder, "ris variance view");
            pass.set_pipeline(pipe);
            bind(&mut pass);
            pass.set_bind_group(3, group, &[]);
            pass.draw(0..3, 0..1);
        }
        if let Some(pipeline) = view {
            let mut pass = f.debug_target_pass(encoder, "tile lights view");
            pass.set_pipeline(pipeline);
            bind(&mut pass);
            pass.draw(0..3, 0..1);
        }
        Ok(())
    }
}

impl TiledScratch {
    /// Forgets the last frame's lists (a frame that builds none).
    pub fn clear(&self) {
        if let Ok(mut state) = self.state.lock() {
            state.1 = None;
        }
    }

    /// The last frame's lists, read back from the GPU; `None` when it built none.
    pub fn lists(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Option<TileLists>> {
        let Ok(state) = self.state.lock() else { return Ok(None) };
        let (Some(b), Some(p)) = (&state.0, state.1) else { return Ok(None) };
        let bytes = p.words * 4;
        let mask_bytes = p.mask_words * 4;
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("tile lists readback") });
        encoder.copy_buffer_to_buffer(&b.lists, 0, &b.lists_read, 0, bytes);
        if mask_bytes > 0 {
            encoder.copy_buffer_to_buffer(&b.counts, p.params.mask_base as u64 * 4, &b.counts_read, 0, mask_bytes);
        }
        queue.submit([encoder.finish()]);
        let data = crate::renderer::kit::read_back(device, &b.lists_read, bytes)?;
        let masks = match mask_bytes {
            0 => Vec::new(),
            _ => crate::renderer::kit::read_back(device, &b.counts_read, mask_bytes)?,
        };
        Ok(Some(TileLists { params: p.params, data, masks }))
    }

    /// After the frame's submission: the list sizes and, where the frame counted them, each
    /// light's pairs (light `i`'s at `pairs[i]`); `None` when the frame built no lists.
    pub fn read(&self, device: &wgpu::Device) -> Result<Option<(TileStats, Option<Vec<u64>>)>> {
        let Ok(state) = self.state.lock() else { return Ok(None) };
        let (Some(b), Some(p)) = (&state.0, state.1) else { return Ok(None) };
        if !p.counted {
            let t = TileStats {
                method: p.method,
                tile_size: p.tile_size,
                slices: p.slices,
                cells: p.cells,
                ..Default::default()
            };
            return Ok(Some((t, None)));
        }
        let zbinned = p.method == Method::Zbin;
        let headers: Vec<u32> = match zbinned {
            true => Vec::new(),
            false => crate::renderer::kit::read_back(device, &b.lists_read, p.cells * 8)?,
        };
        let count_words = p.lights as u64 + 1 + p.mask_words;
        let counts: Vec<u32> = crate::renderer::kit::read_back(device, &b.counts_read, count_words * 4)?;
        let mut t = TileStats {
            method: p.method,
            tile_size: p.tile_size,
            slices: p.slices,
            cells: p.cells,
            ..Default::default()
        };
        // Z-binned: a tile's entries are its mask's bits.
        let words = p.params.words.max(1) as usize;
        for tile in counts.get(p.lights + 1..).unwrap_or_default().chunks_exact(words).filter(|_| zbinned) {
            let len: u32 = tile.iter().map(|w| w.count_ones()).sum();
            t.entries += len as u64;
            t.longest = t.longest.max(len);
        }
        for c in headers.chunks_exact(2) {
            let len = if c[1] == ALL_LIGHTS {
                t.overflowed += 1;
                p.lights as u32
            } else {
                c[1]
            };
            t.entries += len as u64;
            t.longest = t.longest.max(len);
        }
        let pairs = counts.get(1..).unwrap_or_default().iter().take(p.lights).map(|&c| c as u64).collect();
        Ok(Some((t, Some(pairs))))
    }
}

/// The grid the frame's lists are built over (tiles of the screen, or clusters when `clusters`
/// builds them) and the words its lists take: a header of two words per cell, then at most
/// `capacity` entries (`cpu_lists`: the CPU-built lists, which set it; tiled, `rects`: the
/// lights' rectangles of tiles, which bound it and follow it).
fn grid(
    f: &FrameInputs<'_>,
    clusters: Option<&ClusterBuild>,
    cpu_lists: Option<&[u32]>,
    zbins: Option<&ZBinJob>,
    rects: Option<&[u32]>,
) -> (TileParams, u64) {
    let (w, h) = (f.targets.width, f.targets.height);
    let n = f.plan.lights.len();
    let mut params = TileParams {
        mode: 0,
        tile_size: TILE,
        tiles_x: w.div_ceil(TILE),
        tiles_y: h.div_ceil(TILE),
        slices: 1,
        light_count: n as u32,
        capacity: 0,
        slice_scale: 0.0,
        slice_bias: 0.0,
        near: 0.0,
        far: 0.0,
        view_depth: f.options.culling.tile_view_depth,
        selected: f.options.frame.selected_light.map_or(u32::MAX, |k| k as u32),
        words: 0,
        mask_base: 0,
        order_base: 0,
        rect_base: 0,
        chunk: 0,
    };
    let entries: u64 = if let Some(z) = zbins {
        let g = &z.grid;
        params.mode = 2;
        params.tile_size = g.tile;
        (params.tiles_x, params.tiles_y, params.slices) = (g.tiles_x, g.tiles_y, g.slices);
        (params.slice_scale, params.slice_bias, params.near, params.far) = (g.scale, g.bias, g.near, g.far);
        params.capacity = z.visible;
        params.words = z.words;
        params.mask_base = n as u32 + 1;
        (params.order_base, params.rect_base) = (z.order_base(), z.rect_base());
        params.chunk = z.chunk;
        z.data.len() as u64
    } else if let Some((c, g)) = clusters.and_then(|c| c.grid().map(|g| (c, g))) {
        params.mode = 1;
        params.tile_size = g.tile;
        (params.tiles_x, params.tiles_y, params.slices) = (g.tiles_x, g.tiles_y, g.slices);
        (params.slice_scale, params.slice_bias, params.near, params.far) = (g.scale, g.bias, g.near, g.far);
        let header = 2 * g.cells() as u64;
        let capacity = match c {
            ClusterBuild::Cpu(_) => cpu_lists.map_or(0, |d| d.len() as u64 - header),
            // The spans bound what the GPU can list; past the binding limit (the spans' 4 words
            // a light follow the entries in the same binding), cells walk every light (counted
            // as overflowed).
            ClusterBuild::Gpu(j) => j.bound.min(MAX_ENTRIES.saturating_sub(header + 4 * n as u64)),
        };
        params.capacity = capacity as u32;
        header + capacity
    } else {
        // Room for what the rectangles allow, within one binding with the rectangles after.
        let cells = (params.tiles_x * params.tiles_y) as u64;
        let room = tile_room(rects.unwrap_or_default());
        let capacity = room.min(MAX_ENTRIES.saturating_sub(2 * cells + 2 * n as u64));
        params.capacity = capacity as u32;
        params.rect_base = (2 * cells + capacity) as u32;
        2 * cells + capacity
    };
    (params, entries)
}

/// Each light's rectangle of tiles, as the tiled compute pass reads it before testing the
/// light against a tile (`x0 | x1 << 16`, `y0 | y1 << 16`, inclusive): the tiles of its pixel
/// rectangle (`zbin::pixel_rect`, which bounds every visible point it reaches, widened by a
/// pixel), or none (`x0` past `x1`) for a light reaching no visible point.
pub fn tile_rects(plans: &[LightPlan], size: (u32, u32)) -> Vec<u32> {
    let mut out = Vec::with_capacity(2 * plans.len());
    for p in plans {
        match crate::renderer::culling::zbin::pixel_rect(p, size) {
            Some((x0, x1, y0, y1)) => {
                out.push(x0 / TILE | (x1 / TILE) << 16);
                out.push(y0 / TILE | (y1 / TILE) << 16);
            }
            None => out.extend([0xffff, 0xffff]),
        }
    }
    out
}

/// The entries the tiled mode's lists can hold at most: the tiles of each light's rectangle
/// ([`tile_rects`]), since the compute pass lists a light only in those.
pub fn tile_room(rects: &[u32]) -> u64 {
    let span = |w: u32| ((w >> 16) + 1).saturating_sub(w & 0xffff) as u64;
    rects.chunks_exact(2).map(|r| span(r[0]) * span(r[1])).sum()
}

/// The three bind groups every tiled pass reads (frame, G-buffer, tiles), for render and
/// compute passes alike.
/// The debug target's colour state (the views' passes write it unblended).
fn debug_target() -> wgpu::ColorTargetState {
    wgpu::ColorTargetState { format: DEBUG_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL }
}

trait SetGroups {
    fn groups(&mut self, frame: &wgpu::BindGroup, gbuffer: &wgpu::BindGroup, tiles: &wgpu::BindGroup);
}

impl SetGroups for wgpu::RenderPass<'_> {
    fn groups(&mut self, frame: &wgpu::BindGroup, gbuffer: &wgpu::BindGroup, tiles: &wgpu::BindGroup) {
        self.set_bind_group(0, frame, &[]);
        self.set_bind_group(1, gbuffer, &[]);
        self.set_bind_group(2, tiles, &[]);
    }
}

impl SetGroups for wgpu::ComputePass<'_> {
    fn groups(&mut self, frame: &wgpu::BindGroup, gbuffer: &wgpu::BindGroup, tiles: &wgpu::BindGroup) {
        self.set_bind_group(0, frame, &[]);
        self.set_bind_group(1, gbuffer, &[]);
        self.set_bind_group(2, tiles, &[]);
    }
}
