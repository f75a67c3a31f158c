//! The `gbuffer` group: where the G-buffer span's time goes. One H200 run read the span at
//! 3.40–3.45 ms in every row, whatever the scene, mode or light count, so the span is split
//! into what a frame pays before it draws anything:
//! - an empty scene (no objects, no lights): its G-buffer span is the targets' clears alone, its
//!   total the frame's fixed passes;
//! - one triangle: the first draw's cost (pipeline and bind groups set, one small draw);
//! - the scene, as the bench draws it;
//! - the scene without timestamps (the wall clock alone), and without debug groups where the
//!   adapter pushes them;
//! - a bare wgpu pass outside the renderer that clears targets of the same formats and size,
//!   timed by its own two timestamps.
//!
//! Rounds are interleaved (every case once a round), the first round is a warm-up, and each
//! figure is the median of the rest with its standard error (the spread over the rounds / √n).
//! The wall clock runs from the frame's call to the end of its submission's work
//! (`Device::poll` waiting), the picture's read-back left out.

use super::options::BenchOptions;
use super::run::SceneFiles;
use crate::gpu::Gpu;
use crate::headless::Offscreen;
use crate::renderer::{Renderer, Settings, OUTPUT_FORMAT};
use crate::scene::builtin::BuiltinOptions;
use crate::scene::Scene;
use anyhow::Result;
use serde::Serialize;

/// The group's name for `--only` (apart from [`super::GROUPS`]: its rows are not configurations).
pub const GBUFFER_GROUP: &str = "gbuffer";

/// Rounds after the warm-up one (at least 5, as every regret and ledger figure).
pub const ROUNDS: usize = 7;

/// One case of the split: its median G-buffer span, frame total (GPU timestamps) and wall
/// clock, each with its standard error over the rounds.
#[derive(Clone, Debug, Serialize)]
pub struct SplitRow {
    pub label: String,
    pub gbuffer_ms: Option<f64>,
    pub gbuffer_se_ms: Option<f64>,
    pub total_ms: Option<f64>,
    pub wall_ms: f64,
    pub wall_se_ms: f64,
    pub rounds: usize,
}

/// A render pass outside the renderer that clears targets of the G-buffer's formats and the
/// depth-stencil buffer's, between two timestamps.
struct BarePass {
    views: Vec<wgpu::TextureView>,
    depth: wgpu::TextureView,
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
}

impl BarePass {
    fn new(gpu: &Gpu, renderer: &Renderer, size: (u32, u32)) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let view = |label: &str, format| {
            crate::renderer::kit::texture(&gpu.device, label, format, size, usage).create_view(&Default::default())
        };
        let views = renderer.layout().rendered().map(|t| view(t.name, t.format)).collect();
        let depth = view("bare depth", renderer.depth_format());
        let queries = gpu.has(wgpu::Features::TIMESTAMP_QUERY).then(|| {
            let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("bare pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            });
            let buffer = |label, usage| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: 16,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let resolve = buffer("bare pass resolve", wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
            let read = buffer("bare pass read", wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
            (set, resolve, read)
        });
        Self { views, depth, queries }
    }

    /// One pass: its span (ms, when timed) and the wall clock to its end.
    fn run(&self, gpu: &Gpu) -> Result<(Option<f64>, f64)> {
        let clock = std::time::Instant::now();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let colors: Vec<Option<wgpu::RenderPassColorAttachment>> = self
            .views
            .iter()
            .map(|v| crate::renderer::targets::attachment(v, Some(wgpu::Color::TRANSPARENT)))
            .collect();
        let timestamp_writes = self.queries.as_ref().map(|(set, _, _)| wgpu::RenderPassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        });
        drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("bare clears"),
            color_attachments: &colors,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0), store: wgpu::StoreOp::Store }),
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        }));
        if let Some((set, resolve, read)) = &self.queries {
            encoder.resolve_query_set(set, 0..2, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
        }
        gpu.queue.submit([encoder.finish()]);
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow::anyhow!("device poll failed: {e}"))?;
        let wall = clock.elapsed().as_secs_f64() * 1e3;
        let span = match &self.queries {
            Some((_, _, read)) => {
                let t: Vec<u64> = crate::renderer::kit::read_back(&gpu.device, read, 16)?;
                let period = gpu.queue.get_timestamp_period() as f64;
                Some(t[1].saturating_sub(t[0]) as f64 * period * 1e-6)
            }
            None => None,
        };
        Ok((span, wall))
    }
}

/// One case the split renders: a label, and a frame of the renderer or the bare pass.
enum Case {
    Frame { label: String, scene: Scene, settings: Settings, renderer: Renderer, out: Offscreen },
    Bare { label: String, pass: BarePass },
}

impl Case {
    fn label(&self) -> &str {
        match self {
            Case::Frame { label, .. } | Case::Bare { label, .. } => label,
        }
    }

    /// One frame: the G-buffer span, the frame's total (GPU) and the wall clock, in ms.
    fn run(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<(Option<f64>, Option<f64>, f64)> {
        match self {
            Case::Frame { scene, settings, renderer, out, .. } => {
                let clock = std::time::Instant::now();
                let stats = renderer.render(scene, settings, &out.view, size.0, size.1)?;
                gpu.device
                    .poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| anyhow::anyhow!("device poll failed: {e}"))?;
                let wall = clock.elapsed().as_secs_f64() * 1e3;
                Ok((stats.gpu_ms.gbuffer, stats.gpu_ms.total, wall))
            }
            Case::Bare { pass, .. } => {
                let (span, wall) = pass.run(gpu)?;
                Ok((span, span, wall))
            }
        }
    }
}

/// `empty` with one small triangle two units in front of its camera, facing it, in its first
/// material (`None` when it has none).
fn one_triangle(empty: &Scene) -> Option<Scene> {
    let material = (!empty.materials.is_empty()).then_some(0)?;
    let c = &empty.camera;
    let (f, r) = (c.forward(), c.right());
    let u = r.cross(f);
    let at = c.position + f * 2.0;
    let normal = (-f).as_vec3().to_array();
    let v = |p: glam::DVec3, uv| crate::scene::Vertex::new(p.as_vec3().to_array(), normal, uv);
    let mut s = empty.clone();
    s.meshes = vec![crate::scene::Mesh {
        name: "one triangle".into(),
        // Counter-clockwise as the camera sees it (the front face).
        vertices: vec![
            v(at - r * 0.2 - u * 0.2, [0.0, 0.0]),
            v(at + r * 0.2 - u * 0.2, [1.0, 0.0]),
            v(at + u * 0.2, [0.5, 1.0]),
        ],
        indices: vec![0, 1, 2],
        topology: crate::scene::Topology::Triangles,
    }];
    s.objects = vec![crate::scene::Object { mesh: 0, material, transform: glam::DMat4::IDENTITY, layer: 0 }];
    Some(s)
}

/// The split on the bench's scene at its size and light count.
pub fn gbuffer_split(
    gpu: &Gpu,
    o: &BenchOptions,
    files: &mut SceneFiles,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<SplitRow>> {
    let lights = (!o.fixed_lights).then_some(o.lights);
    let scene = files.open(&o.scene, BuiltinOptions { lights, time: o.time })?;
    let base = Settings { count_fragments: false, count_ideal: false, ..Settings::default() };
    let mut empty = scene.clone();
    empty.objects.clear();
    empty.lights_mut().clear();
    let triangle = one_triangle(&empty);
    let untimed = Settings { timestamps: false, ..base.clone() };
    let mut cases = Vec::new();
    let frame = |label: &str, scene: &Scene, settings: &Settings, debug_groups: Option<bool>| -> Result<Case> {
        let mut renderer = Renderer::new(gpu, OUTPUT_FORMAT, settings)?;
        if let Some(on) = debug_groups {
            renderer.set_debug_groups(on);
        }
        let out = Offscreen::new(gpu, o.size.0, o.size.1);
        Ok(Case::Frame { label: label.into(), scene: scene.clone(), settings: settings.clone(), renderer, out })
    };
    cases.push(frame("empty scene (G-buffer: the clears alone)", &empty, &base, None)?);
    if let Some(triangle) = &triangle {
        cases.push(frame("one triangle", triangle, &base, None)?);
    }
    cases.push(frame("the scene", &scene, &base, None)?);
    cases.push(frame("the scene, no timestamps", &scene, &untimed, None)?);
    if gpu.encoder_debug_groups() {
        cases.push(frame("the scene, no debug groups", &scene, &base, Some(false))?);
    }
    // The bare pass takes the formats the scene's renderer resolved.
    if let Some(Case::Frame { renderer, .. }) = cases.iter().find(|c| c.label() == "the scene") {
        let pass = BarePass::new(gpu, renderer, o.size);
        cases.push(Case::Bare { label: "bare wgpu pass, the same targets cleared".into(), pass });
    }
    let mut times: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = vec![Default::default(); cases.len()];
    for round in 0..=ROUNDS {
        progress(&format!("g-buffer split: round {round}/{ROUNDS}"));
        for (case, t) in cases.iter_mut().zip(&mut times) {
            let (g, total, wall) = case.run(gpu, o.size)?;
            if round == 0 {
                continue;
            }
            t.0.extend(g);
            t.1.extend(total);
            t.2.push(wall);
        }
    }
    Ok(cases
        .iter()
        .zip(times)
        .map(|(case, (g, total, wall))| {
            let (gm, gse) = super::run::median_se(&g);
            let (wm, wse) = super::run::median_se(&wall);
            SplitRow {
                label: case.label().into(),
                gbuffer_ms: (!g.is_empty()).then_some(gm),
                gbuffer_se_ms: (!g.is_empty()).then_some(gse),
                total_ms: (!total.is_empty()).then(|| super::run::median(total)),
                wall_ms: wm,
                wall_se_ms: wse,
                rounds: ROUNDS,
            }
        })
        .collect())
}

/// The split as a markdown section of the report.
pub fn split_markdown(rows: &[SplitRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let ms = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
    let mut s = String::from(
        "\n## The G-buffer span, split\n\nMedians of interleaved rounds, ± the standard error; the \
         G-buffer span and the frame's total from GPU timestamps, the wall clock from the frame's call to \
         the end of its work.\n\n| case | G-buffer span ms | frame total ms | wall ms |\n|---|---|---|---|\n",
    );
    for r in rows {
        let g = match (r.gbuffer_ms, r.gbuffer_se_ms) {
            (Some(g), Some(se)) => format!("{g:.3} ± {se:.3}"),
            _ => "-".into(),
        };
        s += &format!("| {} | {g} | {} | {:.3} ± {:.3} |\n", r.label, ms(r.total_ms), r.wall_ms, r.wall_se_ms);
    }
    s
}
