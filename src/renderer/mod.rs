//! The deferred renderer: G-buffer, lights (each with its culling method), compose. It renders
//! into a `TextureView` it is handed, so the same code draws the viewer's viewport and the
//! headless image tests. `Renderer::render` reads as the frame; the layers it sits on, and
//! which imports which, are in `docs/architecture.md`: `kit/` and `options/` at the bottom, the
//! frame's inputs and records, the technique rooms, then the frame's assembly and this file.

pub mod caps;
pub mod cputime;
pub mod culling;
pub mod explain;
mod frame;
pub mod inputs;
pub mod inspect;
mod key;
pub mod kit;
pub mod knobs;
pub mod materials;
pub mod options;
mod paths;
pub mod post;
pub mod presets;
pub mod program;
pub mod records;
mod report;
pub mod scene_gpu;
pub mod settings;
pub mod shadows;
pub mod stats;
pub mod stochastic;
pub mod support;
pub mod surfaces;
pub mod targets;
mod tools;

// The culling modules at the paths the rest of the crate and the tests name them by.
pub use culling::tiled as tiles;
pub use culling::{batches, overlap, plan, volumes};

use crate::gpu::Gpu;
use crate::scene::Scene;
use anyhow::Result;
pub use culling::stats::LightStats;
pub use inspect::{volume_wireframe_with, PixelProbe};
use kit::gbuffer;
pub use plan::{LightPlan, Method, AUTO_STENCIL_MIN_PIXELS};
pub use records::{light_clamp, LIGHT_KIND_POINT, LIGHT_KIND_SPOT};
use records::{FrameBuffers, LightRecord};
pub use report::FrameStats;
use scene_gpu::{MaterialDefaults, SceneGpu};
pub use settings::{
    AccumFormat, BlendedMode, BrdfOverride, CullingMode, DebugView, DepthFormat, DepthRead, DrawOrder, ForwardLights,
    LayoutChoice, Msaa, NearLights, RenderPath, Settings, ShadowCube, ShadowFilter, ShadowFormat, ShadowMode,
};
pub use stats::{CpuMs, GpuMs};
use std::sync::Arc;
pub use support::support;
use targets::Targets;
pub use volumes::VolumeKind;
use volumes::Volumes;

/// Format of the headless output image.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub use frame::passes::PIPELINE_CACHE;
pub use frame::Readiness;
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    output_format: wgpu::TextureFormat,
    /// What the adapter can do: every choice asks it.
    caps: Arc<kit::adapter::AdapterCaps>,
    limits: wgpu::Limits,
    /// The fallbacks already logged (each is said once).
    said: Vec<String>,
    /// The frame's steps are pushed as debug groups (`Gpu::encoder_debug_groups`).
    debug_groups: bool,
    /// The pass set of the current configuration and of recent ones.
    sets: frame::passes::PassSets,
    /// What this renderer's passes write and read back.
    scratch: inputs::scratch::Scratch,
    frame: FrameBuffers,
    defaults: MaterialDefaults,
    volumes: Volumes,
    scene: Option<SceneGpu>,
    targets: Option<Targets>,
    queries: stats::Queries,
    last: frame::last::LastFrame,
    /// The light list the last frame checked, and its shader features.
    features: program::FeatureCache,
    /// The camera caps' last list.
    capped: caps::CappedScene,
    /// The allocations of the frame before last's light records and plans, for this frame's
    /// (`FrameRecords::reusing`, `FramePlan::reusing`).
    spare: (Vec<LightRecord>, Vec<plan::LightPlan>),
    /// The last frame's warnings of forward lists too long for lavapipe's loops: logged when
    /// they change, not at every frame of the viewer.
    long_list_warnings: Vec<String>,
    /// The grading LUT the post targets hold.
    lut: post::LutCache,
    /// The device's material textures, shared with its other renderers.
    uploads: Arc<kit::uploads::Uploads>,
    /// The per-light cost model of the stats (`explain::cost`): a fitted one, by mode (tiled
    /// and clustered: the list modes; every other: the drawn ones), or the built-in constants.
    pub cost_models: Vec<(CullingMode, explain::cost::CostModel)>,
    /// The cost model's constants `auto` and the ledger weigh with: the built-in defaults
    /// unless given a calibration (`set_calibration`).
    calibration: options::calibration::Calibration,
    /// Where a costly frame reports its progress (`set_progress`).
    progress: Option<inputs::Progress>,
    /// The last frame that compiled pipelines: its declared set and which it compiled.
    last_compiles: Option<(kit::Declared, Vec<bool>)>,
}

pub use kit::scoped;

impl Renderer {
    /// The last frame, for the tools that read it (`tools/`).
    pub fn last_frame(&self) -> frame::last::Last<'_> {
        frame::last::Last {
            device: &self.device,
            queue: &self.queue,
            caps: &self.caps,
            passes: &self.sets.current,
            pass_cache: &self.sets.cache,
            targets: &self.targets,
            frame: &self.frame,
            volumes: &self.volumes,
            scratch: &self.scratch,
            last: &self.last,
        }
    }

    pub fn new(gpu: &Gpu, output_format: wgpu::TextureFormat, settings: &Settings) -> Result<Self> {
        let device = gpu.device.clone();
        settings.validate().map_err(anyhow::Error::msg)?;
        let limits = device.limits();
        let caps = gpu.caps.clone();
        let features = program::ShaderFeatures::of(None, settings, &caps.quirks);
        let key = key::pipeline_key(None, settings, settings.layout.layout(), &caps, (output_format, features))?;
        let sets = frame::passes::PassSets::new(&device, &gpu.passes, key)?;
        let passes = &sets.current;
        Ok(Self {
            frame: FrameBuffers::new(&device, &passes.shared.frame_bgl, caps.quirks.min_cube_layers()),
            defaults: MaterialDefaults::new(&device, &gpu.queue),
            volumes: Volumes::new(&device, (settings.sphere_subdivisions, settings.cone_sides)),
            queries: stats::Queries::new(gpu),
            queue: gpu.queue.clone(),
            output_format,
            caps,
            limits,
            said: Vec::new(),
            debug_groups: gpu.encoder_debug_groups(),
            sets,
            scratch: Default::default(),
            scene: None,
            targets: None,
            last: Default::default(),
            features: Default::default(),
            capped: Default::default(),
            spare: Default::default(),
            long_list_warnings: Vec::new(),
            lut: Default::default(),
            cost_models: Vec::new(),
            calibration: Default::default(),
            progress: None,
            last_compiles: None,
            uploads: gpu.uploads.clone(),
            device,
        })
    }

    /// Reports a costly frame's progress to `progress`: a frame whose shadow passes draw more
    /// than `shadows::COSTLY_TRIANGLES` caster triangles, or are more than
    /// `shadows::COSTLY_PASSES`, submits them in parts, waiting for each, and reports the
    /// shadow-map passes done. `None` (the default): every frame is one
    /// submission.
    pub fn set_progress(&mut self, progress: Option<inputs::Progress>) {
        self.progress = progress;
    }

    /// The cost model's constants `auto`'s frame rule and the ledger's estimates use from the
    /// next frame on (a frame kept for reuse is planned again).
    pub fn set_calibration(&mut self, calibration: options::calibration::Calibration) {
        if calibration != self.calibration {
            self.last.reusable = None;
        }
        self.calibration = calibration;
    }

    pub fn calibration(&self) -> &options::calibration::Calibration {
        &self.calibration
    }

    pub fn depth_format(&self) -> wgpu::TextureFormat {
        self.sets.current.key().depth_format
    }

    pub fn depth_clamp(&self) -> bool {
        self.sets.current.key().depth_clamp
    }

    /// Pushes the frame's steps as debug groups (`on`, where the adapter takes them:
    /// `Gpu::encoder_debug_groups`) or not (the bench's G-buffer split times both).
    pub fn set_debug_groups(&mut self, on: bool) {
        self.debug_groups = on && !self.caps.quirks.no_encoder_debug_groups;
    }

    pub fn layout(&self) -> &gbuffer::GBufferLayout {
        &self.sets.current.key().layout
    }

    /// Renders one frame of `scene` into `target` (of the renderer's output format and the
    /// given size). Returns the frame's statistics; counts and times are read back only when
    /// `settings` asks for them.
    pub fn render(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) -> Result<FrameStats> {
        // The frame's own wgpu errors (validation, out of memory) are caught here, on this
        // thread, and become its error: no other renderer's frame, and no error the viewer's UI
        // made, is blamed on it.
        // The camera caps: the frame is drawn with the lights they keep, as an engine sends
        // only those to the GPU.
        let cut = caps::camera_cut(
            scene,
            settings.max_lights,
            settings.light_distance,
            settings.cap_order,
            width as f64 / height.max(1) as f64,
        );
        let capped;
        let scene = match cut.as_ref().and_then(|c| c.kept.as_deref()) {
            Some(kept) => {
                capped = self.capped.scene(scene, kept);
                &capped
            }
            None => scene,
        };
        let device = self.device.clone();
        let (shape, prepared, drawn, pipelines) =
            scoped(&device, || self.encode_frame(scene, settings, target, (width, height)))?;
        let mut stats = self.report(scene, settings, &shape, &prepared, drawn)?;
        // Every pass declares what it draws with (`inputs::pass::Pass::declare`); a pipeline
        // compiled while recording is a pass drawing with one it did not declare.
        debug_assert_eq!(pipelines.while_recording, 0, "a pass drew with a pipeline it did not declare");
        if pipelines.while_recording > 0 {
            log::warn!(
                "{} pipeline(s) compiled while the frame recorded: a pass's declaration is short",
                pipelines.while_recording
            );
        }
        stats.pipelines = pipelines;
        stats.caps = report::cap_stats(cut, settings, &prepared);
        for f in &stats.adapter.fallbacks {
            if !self.said.contains(f) {
                log::warn!("on {}: {f}", self.caps.adapter);
                self.said.push(f.clone());
            }
        }
        // What the probe, the wireframes and the panels read of the frame just drawn; the
        // allocations of the one before for the next frame's records and plans.
        let reused = prepared.reused;
        let before = std::mem::replace(&mut self.last, frame::last::LastFrame::new(scene, settings, prepared));
        // A reused frame took the last one's lists: the spare allocations stay those from before.
        if !reused {
            self.spare = (before.lights, before.plan.lights);
        }
        Ok(stats)
    }

    /// The frame's steps up to its submission: its shape, the targets it draws into, the CPU's
    /// part, then the passes (`paths::steps`): each declares its pipelines, the declared set
    /// is built, and only then are the passes recorded.
    fn encode_frame(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        target: &wgpu::TextureView,
        (width, height): (u32, u32),
    ) -> Result<(frame::Shape, frame::Prepared, inputs::pass::PassReport, report::Pipelines)> {
        let checked = self.features.same_list(scene);
        let shape = frame::Shape::of_checked(scene, settings, (width, height), checked)?;
        self.configure(scene, settings, shape.size, shape.hdr(), shape.chain)?;
        // The CPU's part: records, the culling plan, clamps, the shadow plan, their upload.
        let prepared = self.prepare(scene, settings, &shape)?;
        self.sets.current.prepare(shape.needs(&prepared.plan, settings))?;
        let f = self.inputs(settings, &shape, &prepared, target)?;
        let p = &self.sets.current;
        let steps = paths::steps(p, &f);
        let declared = paths::declare(&steps, &f);
        let clock = std::time::Instant::now();
        let now = p.build_each(&declared);
        let build_us = clock.elapsed().as_micros() as u64;
        let built = now.iter().filter(|b| **b).count();
        let compiles = (built > 0).then(|| (declared.clone(), now));
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let before = kit::pipelines_compiled_here();
        let mut drawn = paths::record(&steps, &f, &mut encoder, self.debug_groups)?;
        let pipelines = report::Pipelines {
            declared: declared.len(),
            built,
            while_recording: (kit::pipelines_compiled_here() - before) as usize,
            build_us,
        };
        if settings.path == RenderPath::LightPrepass && drawn.prepass.is_none() {
            // A buffer view: pass 3 did not run.
            let base = prepared.plan.draws.gbuffer.len() as u64;
            drawn.prepass = Some(paths::prepass_pass::stats(p.key(), base, (0, 0)));
        }
        let (n, m) = (prepared.plan.lights.len(), self.measured(settings, &shape, &prepared));
        // The geometry passes' counts: the G-buffer pass (deferred shading) or passes 1 and 3.
        let geometry = if drawn.prepass.is_some() { 2 } else { u32::from(settings.path.keeps_gbuffer()) };
        self.queries.resolve(&mut encoder, n, m.counts, m.ideal, m.times, m.forward, geometry);
        self.queue.submit([encoder.finish()]);
        self.last_compiles = compiles;
        Ok((shape, prepared, drawn, pipelines))
    }

    /// The declared set of the last frame that compiled pipelines itself, and for each whether
    /// that frame compiled it.
    pub fn last_compiles(&self) -> Option<&(kit::Declared, Vec<bool>)> {
        self.last_compiles.as_ref()
    }

    /// Size of the last frame.
    pub fn size(&self) -> Option<(u32, u32)> {
        self.targets.as_ref().map(|t| (t.width, t.height))
    }

    pub fn output_format(&self) -> wgpu::TextureFormat {
        self.output_format
    }
}
