//! The forward paths of seed 002, no G-buffer:
//!
//! - **single-pass** (`--path forward`): an optional depth pre-pass (seed 002's "Z-cull", so
//!   each pixel is shaded once; `--depth-prepass`), then every opaque and masked object shaded
//!   with its light list (`plan::forward_path_lists`) in one shader (`fs_forward_single`);
//! - **multi-pass** (`--path forward-multipass`): a depth pass, ambient + sun per object
//!   (`fs_forward_base`), then one additive draw per (object, light) pair, scissored to the
//!   light's screen rectangle (`fs_forward_pair`).
//!
//! Both write the HDR scene colour, which the blended surfaces' forward pass, then the tonemap
//! or the post chain, take as deferred shading's compose leaves it. With `--msaa 4` colour and
//! depth are multisampled and resolved into the HDR colour before post (the blended surfaces
//! are drawn multisampled too, with pipelines of their own here).
//!
//! The pipelines are built on a path's first frame (not with every configuration's passes: the
//! deferred path never needs them).

use super::forward_scratch::{Counted, ForwardScratch, Msaa, Queries};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{scene_pipeline, ScenePipe, Shared, ADDITIVE, HDR_FORMAT};
use crate::renderer::options::post::PostOptions;
use crate::renderer::options::{DebugView, RenderPath};
use crate::renderer::plan::{Draw, ForwardPathLists};
use crate::renderer::stats::Span;

/// The forward paths' passes' timings: the depth pass (pre-pass or multi-pass's), the shading
/// pass (single-pass, or multi-pass's ambient + sun), the (object, light) pairs.
pub const DEPTH: Span = Span("depth pass");
pub const SHADE: Span = Span("forward shading");
pub const PAIRS: Span = Span("forward pairs");
use crate::scene::Topology;
use anyhow::{bail, Result};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use wgpu::CompareFunction as Cmp;

/// Occlusion queries of the forward paths: depth pass, shading (single-pass, or multi-pass's
/// ambient + sun), the pairs.
const QUERIES: u32 = 3;

/// The most draws a counted frame queries one by one for the per-light counts (one query set,
/// wgpu's largest): single-pass's objects, multi-pass's (object, light) pairs. Past it the
/// passes are counted whole and the lights are not.
pub const MAX_DRAW_QUERIES: u32 = 4096;

pub use crate::renderer::inputs::pass::{ForwardPathStats, PathPass, PathTarget};

/// Whether the post chain as `s` sets it reads the G-buffer (depth, normals): fog, depth of
/// field, edge AA, distortion (its foreground test) and their views. The forward paths then run the G-buffer pass for it alone.
pub fn post_reads_gbuffer(view: DebugView, s: &PostOptions, chain: bool) -> bool {
    use crate::renderer::options::post::Aa;
    use DebugView as V;
    chain && (s.fog || s.dof || s.distortion || s.aa == Aa::Edge || matches!(view, V::Edges | V::Coc))
}

/// The pipelines of one sample count, by [`crate::renderer::kit::pipeline::topology_pipeline_index`] each.
struct Pipelines {
    depth: [crate::renderer::kit::RenderPipe; 6],
    /// Single-pass shading after the depth pre-pass (LessEqual, no depth write).
    single: [crate::renderer::kit::RenderPipe; 6],
    /// Single-pass shading without it (Less, depth written).
    single_no_prepass: [crate::renderer::kit::RenderPipe; 6],
    base: [crate::renderer::kit::RenderPipe; 6],
    pair: [crate::renderer::kit::RenderPipe; 6],
    /// Blended surfaces (`fs_forward`), one- and two-sided: multisampled frames only.
    blended: [crate::renderer::kit::RenderPipe; 2],
}

pub struct ForwardPathsPass {
    key: crate::renderer::kit::PipelineKey,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: Mutex<HashMap<u32, Arc<Pipelines>>>,
}

/// A counted frame's per-draw queries: their set (`None`: the passes are counted whole, or
/// not at all) and what each query covers, in query order.
struct DrawCounts<'a> {
    set: Option<&'a wgpu::QuerySet>,
    counted: Vec<Counted>,
}

impl ForwardScratch {
    /// Whether a counted frame has made the per-draw queries.
    pub fn draw_queries_made(&self) -> bool {
        self.draws.get().is_some()
    }

    fn queries(&self, device: &wgpu::Device) -> &Queries {
        self.queries.get_or_init(|| Queries::new(device, "forward path fragments", QUERIES))
    }

    fn draw_queries(&self, device: &wgpu::Device) -> &Queries {
        self.draws.get_or_init(|| Queries::new(device, "forward draw fragments", MAX_DRAW_QUERIES))
    }

    /// Each light's evaluated samples in the last counted frame, from its draw queries: a
    /// single-pass object's samples count once for every light of its list, a pair's for its
    /// light. `None` when the frame counted its passes whole. Also fills the passes' sums.
    pub fn read_lights(
        &self,
        device: &wgpu::Device,
        stats: &mut ForwardPathStats,
        lists: &ForwardPathLists,
        light_lists: &[u32],
        lights: usize,
    ) -> Result<Option<Vec<u64>>> {
        let counted = self.counted.lock().map_err(|_| anyhow::anyhow!("forward counts lock poisoned"))?;
        let (Some(q), false) = (self.draws.get(), counted.is_empty()) else { return Ok(None) };
        let words: Vec<u64> = crate::renderer::kit::read_back(device, &q.readback, counted.len() as u64 * 8)?;
        for p in &mut stats.passes {
            if let Some(r) = p.draw_queries.clone() {
                p.fragments = Some(words[r.start as usize..r.end as usize].iter().sum());
            }
        }
        let spans: HashMap<usize, (u32, u32)> = lists.spans.iter().map(|&(o, first, n)| (o, (first, n))).collect();
        let mut per_light = vec![0u64; lights];
        for (c, &n) in counted.iter().zip(&words) {
            match *c {
                Counted::Object(o) => {
                    let Some(&(first, count)) = spans.get(&o) else { continue };
                    for &l in &light_lists[first as usize..(first + count) as usize] {
                        per_light[l as usize] += n;
                    }
                }
                Counted::Pair(j) => {
                    if let Some(p) = lists.pairs.get(j) {
                        per_light[p.light as usize] += n;
                    }
                }
            }
        }
        Ok(Some(per_light))
    }

    /// Reads the frame's occlusion counts into `stats` (after the frame was submitted).
    pub fn read(&self, device: &wgpu::Device, stats: &mut ForwardPathStats, count: bool) -> Result<()> {
        if !count {
            return Ok(());
        }
        let Some(q) = self.queries.get() else { return Ok(()) };
        let words: Vec<u64> = crate::renderer::kit::read_back(device, &q.readback, QUERIES as u64 * 8)?;
        for p in &mut stats.passes {
            if let Some(q) = p.query {
                p.fragments = words.get(q as usize).copied();
            }
        }
        Ok(())
    }
}

/// What the frame hands the forward paths besides [`FrameInputs`].
pub struct PathFrame<'a> {
    pub lists: &'a ForwardPathLists,
    /// The scene's background (the HDR colour is cleared to it).
    pub background: [f32; 4],
    /// The frame has blended surfaces (drawn after, forward).
    pub blended: bool,
    /// The G-buffer pass ran before, for the post chain.
    pub gbuffer_for_post: bool,
}

impl ForwardPathsPass {
    /// The pipelines are built per sample count by the first frame that needs them.
    pub fn new(_device: &wgpu::Device, shared: &Shared) -> Self {
        Self {
            key: shared.key.clone(),
            module: shared.module.clone(),
            layout: shared.surface_layout.clone(),
            pipelines: Mutex::new(HashMap::new()),
        }
    }

    /// One pipeline: the scene's vertices through `vs`, `fs` (none: depth only) into `targets`.
    #[allow(clippy::too_many_arguments)]
    fn pipeline(
        &self,
        device: &wgpu::Device,
        label: &str,
        vs: &str,
        fs: Option<&str>,
        topology: Topology,
        double_sided: bool,
        depth: (bool, Cmp, wgpu::StencilState),
        targets: &[Option<wgpu::ColorTargetState>],
        samples: u32,
    ) -> crate::renderer::kit::RenderPipe {
        let p = ScenePipe { label, layout: &self.layout, vs, fs, topology, double_sided, depth, samples };
        scene_pipeline(device, &self.module, &self.key, p, targets)
    }

    /// The six pipelines of one stage (by [`crate::renderer::kit::pipeline::topology_pipeline_index`]): opaque and masked
    /// triangles, one- and two-sided, then lines and points (masked shader, two-sided).
    #[allow(clippy::too_many_arguments)]
    fn stage(
        &self,
        device: &wgpu::Device,
        label: &str,
        vs: &str,
        fs: Option<(&str, &str)>,
        depth_fs_masked: bool,
        depth: (bool, Cmp, wgpu::StencilState),
        targets: &[Option<wgpu::ColorTargetState>],
        samples: u32,
    ) -> [crate::renderer::kit::RenderPipe; 6] {
        let (opaque, masked) = match fs {
            Some((o, m)) => (Some(o), Some(m)),
            None => (None, depth_fs_masked.then_some("fs_forward_depth_masked")),
        };
        let p = |fs, topology, two_sided| {
            self.pipeline(device, label, vs, fs, topology, two_sided, depth.clone(), targets, samples)
        };
        [
            p(opaque, Topology::Triangles, false),
            p(opaque, Topology::Triangles, true),
            p(masked, Topology::Triangles, false),
            p(masked, Topology::Triangles, true),
            p(masked, Topology::Lines, true),
            p(masked, Topology::Points, true),
        ]
    }

    /// The pipelines for `samples`, each compiled on its first draw (`kit::OnFirstUse`).
    fn build(&self, device: &wgpu::Device, samples: u32) -> Pipelines {
        let replace =
            [Some(wgpu::ColorTargetState { format: HDR_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL })];
        let add = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(ADDITIVE),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        // Blended surfaces: alpha blended, or added (seed 003; `BlendedMode::Additive`).
        let blended = if self.key.additive_blended {
            crate::renderer::kit::ADD_BLENDED
        } else {
            wgpu::BlendState::ALPHA_BLENDING
        };
        let alpha = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(blended),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        use wgpu::StencilOperation as Op;
        let none = crate::renderer::kit::NO_STENCIL;
        let tested = (false, Cmp::LessEqual, none.clone());
        let written = (true, Cmp::Less, none.clone());
        // Multi-pass: the ambient + sun draw marks its pixels with the object's stencil
        // reference (its index mod 256; drawn in reverse, the surface the depth pass kept marks
        // last), and a pair's draw lights only its object's pixels: of coincident surfaces
        // (equal depth) only the kept one adds lights, as deferred shading lights one surface.
        let owner = crate::renderer::kit::face(Cmp::Always, Op::Keep, Op::Keep, Op::Replace);
        let marked = (false, Cmp::LessEqual, crate::renderer::kit::stencil(owner, owner));
        let mine = crate::renderer::kit::face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep);
        let owned = (false, Cmp::LessEqual, crate::renderer::kit::stencil(mine, mine));
        let single = Some(("fs_forward_single", "fs_forward_single_masked"));
        Pipelines {
            depth: self.stage(device, "forward depth", "vs_forward", None, true, written.clone(), &[], samples),
            single: self.stage(
                device,
                "forward single-pass",
                "vs_forward",
                single,
                false,
                tested.clone(),
                &replace,
                samples,
            ),
            single_no_prepass: self.stage(
                device,
                "forward single-pass (no pre-pass)",
                "vs_forward",
                single,
                false,
                written,
                &replace,
                samples,
            ),
            base: self.stage(
                device,
                "forward multi-pass ambient + sun",
                "vs_forward",
                Some(("fs_forward_base", "fs_forward_base_masked")),
                false,
                marked,
                &replace,
                samples,
            ),
            pair: self.stage(
                device,
                "forward multi-pass light",
                "vs_forward_pair",
                Some(("fs_forward_pair", "fs_forward_pair_masked")),
                false,
                owned,
                &add,
                samples,
            ),
            blended: [false, true].map(|two_sided| {
                self.pipeline(
                    device,
                    "forward (blended, multisampled)",
                    "vs_geometry",
                    Some("fs_forward"),
                    Topology::Triangles,
                    two_sided,
                    tested.clone(),
                    &alpha,
                    samples,
                )
            }),
        }
    }

    fn pipelines(&self, device: &wgpu::Device, samples: u32) -> Result<Arc<Pipelines>> {
        let mut map = self.pipelines.lock().map_err(|_| anyhow::anyhow!("forward pipelines lock poisoned"))?;
        if let Some(p) = map.get(&samples) {
            return Ok(p.clone());
        }
        let p = Arc::new(self.build(device, samples));
        map.insert(samples, p.clone());
        Ok(p)
    }

    fn msaa_targets(&self, device: &wgpu::Device, scratch: &ForwardScratch, size: (u32, u32)) -> Result<()> {
        let mut slot = scratch.msaa.lock().map_err(|_| anyhow::anyhow!("MSAA targets lock poisoned"))?;
        if slot.as_ref().is_some_and(|m| m.size == size) {
            return Ok(());
        }
        let make = |label, format| {
            crate::renderer::kit::texture_2d(
                device,
                label,
                (format, &[]),
                size,
                4,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&Default::default())
        };
        let m = Arc::new(Msaa {
            size,
            color: make("hdr colour (4x MSAA)", HDR_FORMAT),
            depth: make("depth (4x MSAA)", self.key.depth_format),
        });
        *slot = Some(m);
        Ok(())
    }

    /// Records the path's passes into the HDR scene colour (resolved there with MSAA), the
    /// blended surfaces after them, and the compose span's first stamp; returns what the
    /// frame's stats report (fragments and times are filled in by [`Self::read`] and
    /// `Queries::read`). The steps:
    /// 1. depth (the pre-pass, or multi-pass's depth pass);
    /// 2. shading: single-pass (each object with its light list), or multi-pass's ambient +
    ///    sun per object;
    /// 3. multi-pass: one additive draw per (object, light) pair, scissored to the light's
    ///    screen rectangle;
    /// 4. blended surfaces, back to front; multisampled with MSAA (and resolved).
    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        pf: &PathFrame<'_>,
        blended_pass: &crate::renderer::surfaces::blended::BlendedPass,
    ) -> Result<ForwardPathStats> {
        let device = f.device;
        let (s, surfaces) = (&f.options.frame, &f.options.surfaces);
        let samples = s.msaa.samples();
        let Some((hdr_view, _)) = &f.targets.hdr else { bail!("internal: the forward paths need the HDR colour") };
        let pipes = self.pipelines(device, samples)?;
        let msaa = match samples > 1 {
            true => {
                let slot = f.scratch.forward.msaa.lock().map_err(|_| anyhow::anyhow!("MSAA targets lock poisoned"))?;
                let made = slot.clone().filter(|m| m.size == (f.targets.width, f.targets.height));
                Some(made.ok_or_else(|| anyhow::anyhow!("internal: the MSAA targets were not made before recording"))?)
            }
            false => None,
        };
        let (color, depth) = match &msaa {
            Some(m) => (&m.color, &m.depth),
            None => (hdr_view, &f.targets.depth),
        };
        let [r, g, b, a] = pf.background.map(f64::from);
        let at = Attachments {
            color,
            depth,
            hdr: hdr_view,
            msaa: msaa.is_some(),
            background: wgpu::Color { r, g, b, a },
            far: f.far_depth() as f32,
        };
        let multipass = s.path == RenderPath::ForwardMultipass;
        let prepass = multipass || surfaces.depth_prepass;
        let mut stats = self.path_stats(f, pf, samples, prepass);
        if s.count_fragments {
            f.scratch.forward.queries(device);
        }
        // The lights' counts: the shading draws queried one by one (single-pass's objects,
        // multi-pass's pairs) when they fit one query set.
        let draws = if multipass { pf.lists.pairs.len() } else { f.plan.draws.gbuffer.len() };
        let set = (s.count_fragments && draws as u32 <= MAX_DRAW_QUERIES)
            .then(|| &f.scratch.forward.draw_queries(device).set);
        let mut counts = DrawCounts { set, counted: Vec::new() };
        // The last pass over the multisampled colour resolves it (the blended pass, when the
        // frame has one).
        let resolve_in_blended = at.msaa && pf.blended;
        if prepass {
            self.depth_pass(encoder, f, &at, &pipes, &mut stats);
        }
        let last = at.msaa && !resolve_in_blended && !multipass;
        let shape = (multipass, prepass, last);
        self.shading_pass(encoder, f, &at, &pipes, shape, &mut counts, &mut stats);
        if multipass {
            let last = at.msaa && !resolve_in_blended;
            self.pairs_pass(encoder, f, pf.lists, &at, &pipes, last, &mut counts, &mut stats);
        }
        // The compose span starts here, as deferred's HDR compose starts it: blended surfaces,
        // then tonemap or the post chain.
        if f.times {
            drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("forward compose begin"),
                color_attachments: &[crate::renderer::targets::attachment(hdr_view, None)],
                depth_stencil_attachment: None,
                timestamp_writes: f.timestamps(Some(crate::renderer::surfaces::compose::SPAN), None),
                occlusion_query_set: None,
                multiview_mask: None,
            }));
        }
        if pf.blended {
            if at.msaa {
                let blended = crate::renderer::surfaces::blended::SPAN;
                let query = f.forward_counts.then_some((&f.queries.forward, 0));
                let (label, colour) = ("forward (blended, multisampled)", [at.color(false, true)]);
                let mut pass = begin(encoder, f, label, &colour, at.depth(false), blended, query.into());
                f.scene.draw(&mut pass, &f.plan.draws.forward, &pipes.blended);
                if query.is_some() {
                    pass.end_occlusion_query();
                }
            } else {
                blended_pass.encode(encoder, f)?;
            }
        }
        if s.count_fragments {
            let q = f.scratch.forward.queries(device);
            encoder.resolve_query_set(&q.set, 0..QUERIES, &q.resolve, 0);
            encoder.copy_buffer_to_buffer(&q.resolve, 0, &q.readback, 0, QUERIES as u64 * 8);
        }
        let counted = counts.counted;
        if set.is_some() && !counted.is_empty() {
            let q = f.scratch.forward.draw_queries(device);
            let n = counted.len() as u32;
            encoder.resolve_query_set(&q.set, 0..n, &q.resolve, 0);
            encoder.copy_buffer_to_buffer(&q.resolve, 0, &q.readback, 0, n as u64 * 8);
        }
        *f.scratch.forward.counted.lock().map_err(|_| anyhow::anyhow!("forward counts lock poisoned"))? = counted;
        Ok(stats)
    }

    /// The path's figures before its passes are recorded: its lists and its targets.
    fn path_stats(&self, f: &FrameInputs<'_>, pf: &PathFrame<'_>, samples: u32, prepass: bool) -> ForwardPathStats {
        let lists = pf.lists;
        let depth_bytes = self.key.depth_format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)).unwrap_or(4)
            + self.key.depth_format.block_copy_size(Some(wgpu::TextureAspect::StencilOnly)).unwrap_or(0);
        let hdr_bytes = HDR_FORMAT.block_copy_size(None).unwrap_or(8);
        let mut stats = ForwardPathStats {
            path: f.options.frame.path,
            samples,
            depth_prepass: prepass,
            objects: lists.objects,
            list_entries: lists.list_entries,
            longest_list: lists.longest_list,
            pairs: lists.pairs.len() as u64,
            gbuffer_for_post: pf.gbuffer_for_post,
            ..Default::default()
        };
        if pf.gbuffer_for_post {
            stats.passes.push(PathPass {
                name: "g-buffer (post inputs)".into(),
                draw_calls: f.plan.draws.gbuffer.len() as u64,
                span: Some(crate::renderer::surfaces::gbuffer::SPAN),
                ..Default::default()
            });
            stats.targets.push(PathTarget {
                name: "g-buffer (post inputs)".into(),
                bytes_per_pixel: self.key.layout.bytes_per_pixel(),
            });
        }
        stats
            .targets
            .push(PathTarget { name: format!("depth-stencil x{samples}"), bytes_per_pixel: depth_bytes * samples });
        stats.targets.push(PathTarget { name: format!("hdr colour x{samples}"), bytes_per_pixel: hdr_bytes * samples });
        if samples > 1 {
            stats.targets.push(PathTarget { name: "hdr colour (resolved)".into(), bytes_per_pixel: hdr_bytes });
        }
        stats
    }

    /// Occlusion query `index` of the path's set when the frame counts fragments.
    /// (`encode` makes the renderer's query set before the passes when the frame counts.)
    fn query<'f>(f: &'f FrameInputs<'_>, index: u32) -> Option<(&'f wgpu::QuerySet, u32)> {
        let queries = f.scratch.forward.queries.get().filter(|_| f.options.frame.count_fragments)?;
        Some((&queries.set, index))
    }

    /// Draws `list` into `pass` as `SceneGpu::draw` does, each draw inside an occlusion query of
    /// its own (numbered on from `counted`'s length), what it covers recorded in `counted`
    /// (`what`: from the object); returns the queries' range.
    fn draw_counted(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        f: &FrameInputs<'_>,
        list: &[Draw],
        pipelines: &[crate::renderer::kit::RenderPipe],
        counted: &mut Vec<Counted>,
        what: impl Fn(usize) -> Counted,
    ) -> std::ops::Range<u32> {
        let first = counted.len() as u32;
        pass.set_vertex_buffer(0, f.scene.vertices.slice(..));
        pass.set_index_buffer(f.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        let (mut pipe, mut mat) = (usize::MAX, usize::MAX);
        for &(i, p, m) in list {
            let Some((range, base)) = f.scene.draws.get(i) else { continue };
            if p != pipe {
                pass.set_pipeline(&pipelines[p]);
                pipe = p;
            }
            if m != mat {
                if let Some(g) = f.scene.materials.get(m) {
                    pass.set_bind_group(1, g, &[]);
                }
                mat = m;
            }
            pass.begin_occlusion_query(counted.len() as u32);
            counted.push(what(i));
            pass.draw_indexed(range.clone(), *base, i as u32..i as u32 + 1);
            pass.end_occlusion_query();
        }
        first..counted.len() as u32
    }

    /// Step 1: the opaque objects' depth (query 0).
    fn depth_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        at: &Attachments<'_>,
        pipes: &Pipelines,
        stats: &mut ForwardPathStats,
    ) {
        let opaque = &f.plan.draws.gbuffer;
        let query = Self::query(f, 0);
        let mut pass = begin(encoder, f, "forward depth", &[], at.depth(true), DEPTH, query.into());
        f.scene.draw(&mut pass, opaque, &pipes.depth);
        stats.passes.push(end(pass, query, "depth", opaque.len() as u64, DEPTH));
    }

    /// Step 2: single-pass shading, or multi-pass's ambient + sun (query 1). `last`: this pass
    /// resolves the multisampled colour.
    #[allow(clippy::too_many_arguments)]
    fn shading_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        at: &Attachments<'_>,
        pipes: &Pipelines,
        (multipass, prepass, last): (bool, bool, bool),
        counts: &mut DrawCounts<'_>,
        stats: &mut ForwardPathStats,
    ) {
        let opaque = &f.plan.draws.gbuffer;
        let label = if multipass { "forward ambient + sun" } else { "forward single-pass" };
        let colour = [at.color(true, last)];
        let pipelines = match (multipass, prepass) {
            (true, _) => &pipes.base,
            (false, true) => &pipes.single,
            (false, false) => &pipes.single_no_prepass,
        };
        if let Some(set) = counts.set.filter(|_| !multipass) {
            // Counted object by object (the lights' counts: each object's samples, once for
            // every light of its list), drawn in the order below.
            let mut pass = begin(encoder, f, label, &colour, at.depth(!prepass), SHADE, Occlusion::Set(set));
            let order: Vec<Draw> = if prepass { opaque.iter().rev().copied().collect() } else { opaque.clone() };
            let queries = self.draw_counted(&mut pass, f, &order, pipelines, &mut counts.counted, Counted::Object);
            drop(pass);
            stats.passes.push(PathPass {
                name: "shading".into(),
                draw_calls: opaque.len() as u64,
                span: Some(SHADE),
                draw_queries: Some(queries),
                ..Default::default()
            });
            return;
        }
        let query = Self::query(f, 1);
        let mut pass = begin(encoder, f, label, &colour, at.depth(!prepass), SHADE, query.into());
        let pipelines = match (multipass, prepass) {
            (true, _) => &pipes.base,
            (false, true) => &pipes.single,
            (false, false) => &pipes.single_no_prepass,
        };
        // After a depth pass, every surface at the kept depth passes LessEqual: of coincident
        // surfaces (equal depth) the last drawn would win, where the depth pass (Less) and the
        // G-buffer pass keep the first. Drawn in reverse, the first is drawn last and wins, as
        // in deferred shading.
        if multipass {
            // Each object's stencil reference marks its pixels for its pairs.
            pass.set_vertex_buffer(0, f.scene.vertices.slice(..));
            pass.set_index_buffer(f.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
            for &(i, p, m) in opaque.iter().rev() {
                let Some((range, base)) = f.scene.draws.get(i) else { continue };
                pass.set_pipeline(&pipelines[p]);
                if let Some(g) = f.scene.materials.get(m) {
                    pass.set_bind_group(1, g, &[]);
                }
                pass.set_stencil_reference(i as u32 & 0xff);
                pass.draw_indexed(range.clone(), *base, i as u32..i as u32 + 1);
            }
        } else if prepass {
            let reversed: Vec<Draw> = opaque.iter().rev().copied().collect();
            f.scene.draw(&mut pass, &reversed, pipelines);
        } else {
            f.scene.draw(&mut pass, opaque, pipelines);
        }
        stats.passes.push(end(
            pass,
            query,
            if multipass { "ambient + sun" } else { "shading" },
            opaque.len() as u64,
            SHADE,
        ));
    }

    /// Step 3: multi-pass's (object, light) pairs, each scissored to its light's rectangle and
    /// stencil-tested against its object's mark (query 2). `last`: this pass resolves the
    /// multisampled colour.
    #[allow(clippy::too_many_arguments)]
    fn pairs_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        lists: &ForwardPathLists,
        at: &Attachments<'_>,
        pipes: &Pipelines,
        last: bool,
        counts: &mut DrawCounts<'_>,
        stats: &mut ForwardPathStats,
    ) {
        let (per_draw, counted) = (counts.set, &mut counts.counted);
        let colour = [at.color(false, last)];
        let label = "forward lights (object, light) pairs";
        // Counted pair by pair (the lights' counts), or the pass whole.
        let query = Self::query(f, 2).filter(|_| per_draw.is_none());
        let mut pass = match per_draw {
            Some(set) => begin(encoder, f, label, &colour, at.depth(false), PAIRS, Occlusion::Set(set)),
            None => begin(encoder, f, label, &colour, at.depth(false), PAIRS, query.into()),
        };
        let first = counted.len() as u32;
        pass.set_vertex_buffer(0, f.scene.vertices.slice(..));
        pass.set_index_buffer(f.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        let (mut pipe, mut mat) = (usize::MAX, usize::MAX);
        for (j, pair) in lists.pairs.iter().enumerate() {
            let (i, p, m) = pair.draw;
            let Some((range, base)) = f.scene.draws.get(i) else { continue };
            if p != pipe {
                pass.set_pipeline(&pipes.pair[p]);
                pipe = p;
            }
            if m != mat {
                if let Some(g) = f.scene.materials.get(m) {
                    pass.set_bind_group(1, g, &[]);
                }
                mat = m;
            }
            pass.set_stencil_reference(i as u32 & 0xff);
            let [x, y, w, h] = pair.scissor;
            pass.set_scissor_rect(x, y, w, h);
            let instance = lists.pair_base + j as u32;
            if per_draw.is_some() {
                pass.begin_occlusion_query(counted.len() as u32);
                counted.push(Counted::Pair(j));
            }
            pass.draw_indexed(range.clone(), *base, instance..instance + 1);
            if per_draw.is_some() {
                pass.end_occlusion_query();
            }
        }
        let mut p = end(pass, query, "lights (object, light) pairs", lists.pairs.len() as u64, PAIRS);
        p.draw_queries = per_draw.map(|_| first..counted.len() as u32);
        stats.passes.push(p);
    }
}

/// A forward path's passes, with the blended surfaces' pass that ends them single-sampled.
pub struct ForwardPaths<'a> {
    pub paths: &'a ForwardPathsPass,
    pub blended: &'a crate::renderer::surfaces::blended::BlendedPass,
}

impl ForwardPaths<'_> {
    /// What the frame hands the path besides [`FrameInputs`].
    fn frame<'f>(f: &'f FrameInputs<'_>) -> PathFrame<'f> {
        PathFrame {
            lists: f.path_lists,
            background: f.background,
            blended: f.shape.blended,
            gbuffer_for_post: post_reads_gbuffer(f.options.frame.debug_view, &f.options.post, f.shape.chain),
        }
    }
}

impl Pass for ForwardPaths<'_> {
    /// The multisampled targets (`--msaa 4`) and the fragment-count queries.
    fn prepare(&self, f: &FrameInputs<'_>) -> Result<()> {
        let s = &f.options.frame;
        if s.msaa.samples() > 1 {
            self.paths.msaa_targets(f.device, &f.scratch.forward, (f.targets.width, f.targets.height))?;
        }
        if s.count_fragments {
            f.scratch.forward.queries(f.device);
            let draws = if s.path == RenderPath::ForwardMultipass {
                f.path_lists.pairs.len()
            } else {
                f.plan.draws.gbuffer.len()
            };
            if draws as u32 <= MAX_DRAW_QUERIES {
                f.scratch.forward.draw_queries(f.device);
            }
        }
        Ok(())
    }

    /// Steps 1-4 as [`ForwardPathsPass::record`] takes them: the depth pass's, the shading's
    /// and the pairs' pipelines of the objects drawn, then the blended surfaces'.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        let s = &f.options.frame;
        let Ok(pipes) = self.paths.pipelines(f.device, s.msaa.samples()) else { return };
        if f.targets.hdr.is_none() {
            return;
        }
        let multipass = s.path == RenderPath::ForwardMultipass;
        let prepass = multipass || f.options.surfaces.depth_prepass;
        let of = |pipes: &[crate::renderer::kit::RenderPipe], list: &[Draw]| {
            list.iter().filter_map(|d| pipes.get(d.1)).cloned().collect::<Vec<_>>()
        };
        let opaque = &f.plan.draws.gbuffer;
        if prepass {
            out.add_all(&of(&pipes.depth, opaque));
        }
        let shading = match (multipass, prepass) {
            (true, _) => &pipes.base,
            (false, true) => &pipes.single,
            (false, false) => &pipes.single_no_prepass,
        };
        out.add_all(&of(shading, opaque));
        if multipass {
            out.add_all(f.path_lists.pairs.iter().filter_map(|p| pipes.pair.get(p.draw.1)));
        }
        if f.shape.blended {
            match s.msaa.samples() > 1 {
                true => out.add_all(&of(&pipes.blended, &f.plan.draws.forward)),
                false => self.blended.declare(f, out),
            }
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> Result<PassReport> {
        let stats = self.paths.record(encoder, f, &Self::frame(f), self.blended)?;
        Ok(PassReport { light_draws: stats.draw_calls(), forward_path: Some(stats), ..Default::default() })
    }
}

/// The forward passes' attachments this frame: the colour (multisampled with MSAA) with the
/// HDR colour it resolves into, and the depth-stencil.
struct Attachments<'a> {
    color: &'a wgpu::TextureView,
    depth: &'a wgpu::TextureView,
    hdr: &'a wgpu::TextureView,
    msaa: bool,
    background: wgpu::Color,
    /// The far plane's depth (the clear value).
    far: f32,
}

impl<'a> Attachments<'a> {
    /// The colour attachment, cleared to the background or loaded; `last` resolves it into
    /// the HDR colour (with MSAA).
    fn color(&self, clear: bool, last: bool) -> Option<wgpu::RenderPassColorAttachment<'a>> {
        Some(wgpu::RenderPassColorAttachment {
            view: self.color,
            depth_slice: None,
            resolve_target: if last && self.msaa { Some(self.hdr) } else { None },
            ops: wgpu::Operations {
                load: if clear { wgpu::LoadOp::Clear(self.background) } else { wgpu::LoadOp::Load },
                store: wgpu::StoreOp::Store,
            },
        })
    }

    /// The depth-stencil, cleared (to the far plane and zero) or loaded.
    fn depth(&self, clear: bool) -> wgpu::RenderPassDepthStencilAttachment<'a> {
        wgpu::RenderPassDepthStencilAttachment {
            view: self.depth,
            depth_ops: Some(wgpu::Operations {
                load: if clear { wgpu::LoadOp::Clear(self.far) } else { wgpu::LoadOp::Load },
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: Some(wgpu::Operations {
                load: if clear { wgpu::LoadOp::Clear(0) } else { wgpu::LoadOp::Load },
                store: wgpu::StoreOp::Store,
            }),
        }
    }
}

/// The occlusion queries a forward pass is begun with.
#[derive(Clone, Copy)]
enum Occlusion<'q> {
    /// No query set: the pass counts nothing.
    Off,
    /// The query set, no query begun: the pass queries its draws.
    Set(&'q wgpu::QuerySet),
    /// Query `.1` of set `.0` begun with the pass (the caller ends it, see [`end`]).
    Begin(&'q wgpu::QuerySet, u32),
}

impl<'q> From<Option<(&'q wgpu::QuerySet, u32)>> for Occlusion<'q> {
    fn from(query: Option<(&'q wgpu::QuerySet, u32)>) -> Self {
        query.map_or(Occlusion::Off, |(set, i)| Occlusion::Begin(set, i))
    }
}

/// Begins one of the forward passes with the frame's bind group, timed as `span`, with the
/// occlusion queries of `occlusion`.
fn begin<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    f: &FrameInputs<'_>,
    label: &str,
    color: &[Option<wgpu::RenderPassColorAttachment<'_>>],
    depth: wgpu::RenderPassDepthStencilAttachment<'_>,
    span: Span,
    occlusion: Occlusion<'_>,
) -> wgpu::RenderPass<'e> {
    let set = match occlusion {
        Occlusion::Off => None,
        Occlusion::Set(set) | Occlusion::Begin(set, _) => Some(set),
    };
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: color,
        depth_stencil_attachment: Some(depth),
        timestamp_writes: f.timestamps(Some(span), Some(span)),
        occlusion_query_set: set,
        multiview_mask: None,
    });
    pass.set_bind_group(0, &f.frame.group, &[]);
    if let Occlusion::Begin(_, i) = occlusion {
        pass.begin_occlusion_query(i);
    }
    pass
}

/// Ends `pass` (its occlusion query first, when begun) and describes it for the stats.
fn end(
    mut pass: wgpu::RenderPass<'_>,
    query: Option<(&wgpu::QuerySet, u32)>,
    name: impl Into<String>,
    draw_calls: u64,
    span: Span,
) -> PathPass {
    if query.is_some() {
        pass.end_occlusion_query();
    }
    PathPass { name: name.into(), draw_calls, span: Some(span), query: query.map(|(_, i)| i), ..Default::default() }
}
