//! The deferred renderer: G-buffer, lights (each with its culling method), compose.
//! It renders into a `TextureView` it is handed, so the same code draws the viewer's viewport
//! and the headless image tests.
//!
//! `Renderer::render` reads as the frame. The rooms it calls on:
//! - `records` — the records the shaders read and the frame's storage buffers;
//! - `plan` — the culling decision per light and the object draw lists;
//! - `scene_gpu`, `targets`, `volumes` — what is uploaded once per scene, per size, per
//!   tessellation;
//! - `kit/` — how a pass is built (pipeline helpers, bindings, G-buffer layout, `common.wgsl`);
//! - `program` — the one shader module, assembled from every room's WGSL;
//! - `frame/` — the frame's shape, its CPU preparation, what the passes read, the pass set;
//! - `paths/`, `surfaces/`, `culling/`, `shadows/`, `post/` — the techniques, each with its
//!   passes and shaders;
//! - `stats`, `inspect` — what is read back: counts, times, pixels.

pub mod caps;
pub mod cputime;
pub mod culling;
pub mod explain;
mod frame;
pub mod inspect;
pub mod kit;
pub mod knobs;
pub mod materials;
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
pub mod support;
pub mod surfaces;
pub mod targets;

// The culling modules at the paths the rest of the crate and the tests name them by.
pub use culling::tiled as tiles;
pub use culling::{batches, overlap, plan, volumes};

use crate::gpu::Gpu;
use crate::scene::Scene;
use anyhow::{bail, Result};
use frame::passes::Passes;
use glam::DMat4;
pub use inspect::{volume_wireframe_with, PixelProbe};
use kit::{gbuffer, PipelineKey};
use plan::FramePlan;
pub use plan::{LightPlan, Method, AUTO_STENCIL_MIN_PIXELS};
pub use records::{light_clamp, LIGHT_KIND_POINT, LIGHT_KIND_SPOT};
use records::{FrameBuffers, LightRecord};
use scene_gpu::{MaterialDefaults, SceneFingerprint, SceneGpu};
pub use settings::{
    AccumFormat, BlendedMode, BrdfOverride, CullingMode, DebugView, DepthFormat, DepthRead, DrawOrder, ForwardLights,
    LayoutChoice, Msaa, NearLights, RenderPath, Settings, ShadowCube, ShadowFilter, ShadowFormat, ShadowMode,
};
pub use stats::{CpuMs, FrameStats, LightStats};
use std::sync::Arc;
pub use support::support;
use surfaces::compose::ComposeTarget;
use targets::Targets;
pub use volumes::VolumeKind;
use volumes::Volumes;

/// Format of the headless output image.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Pass sets kept for configurations other than the current one (layout, accumulation, depth
/// format and convention, depth clamp).
pub const PIPELINE_CACHE: usize = 8;

/// Pass sets a device keeps for its renderers ([`PassPool`]).
const POOL_SETS: usize = 32;

/// The pass sets built on a device, by configuration, shared by every renderer on it. On
/// lavapipe a pass set's first frame costs 0.7-1.8 s of pipeline compilation at 192x108, a frame
/// on built pipelines 10-150 ms, so a process that creates many renderers (the bench, one per
/// configuration, all alive at once; the test suite, on several threads) compiles each
/// configuration once. A set holds only pipelines and layouts, built once each (`kit::Lazy`);
/// what a frame writes and reads back is each renderer's own (`frame::scratch::Scratch`), so
/// renderers share sets freely. The pool keeps the [`POOL_SETS`] most recently used; a set
/// dropped from it lives on while a renderer draws with it.
#[derive(Default)]
pub struct PassPool {
    sets: std::sync::Mutex<Vec<Arc<Passes>>>,
    /// Sets kept at most; 0: [`POOL_SETS`].
    capacity: std::sync::atomic::AtomicUsize,
}

impl PassPool {
    /// Keeps at most `sets` sets from now on (a process with one long-lived renderer, the
    /// viewer, keeps few: each set's compiled pipelines hold up to 160 MiB on lavapipe).
    pub fn keep_at_most(&self, sets: usize) {
        self.capacity.store(sets.max(1), std::sync::atomic::Ordering::Relaxed);
    }

    /// The set built for `key`, built now (and kept) if the pool has none.
    fn get(&self, device: &wgpu::Device, key: PipelineKey) -> Result<Arc<Passes>> {
        let mut sets = self.sets.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = sets.iter().rposition(|p| *p.key() == key) {
            // Most recently used last.
            let set = sets.remove(i);
            sets.push(set.clone());
            return Ok(set);
        }
        let set = Arc::new(build_passes(device, key)?);
        sets.push(set.clone());
        let capacity = match self.capacity.load(std::sync::atomic::Ordering::Relaxed) {
            0 => POOL_SETS,
            n => n,
        };
        let excess = sets.len().saturating_sub(capacity);
        sets.drain(..excess);
        Ok(set)
    }

    /// Sets held now.
    pub fn len(&self) -> usize {
        self.sets.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The last light list a frame checked, by identity with the cookies it names
/// (`Scene::lights` is copied on write), and the shader features it needed with the sun and
/// settings then: a frame with the same list reads no light to validate it
/// (`Shape::of_checked`) or to pick its shaders' lookups (`ShaderFeatures::of`).
struct LightsSeen {
    lights: std::sync::Arc<Vec<crate::scene::Light>>,
    cookies: Vec<u64>,
    sun: Option<crate::scene::Sun>,
    settings: Settings,
    features: program::ShaderFeatures,
}

impl LightsSeen {
    fn same_list(&self, scene: &Scene) -> bool {
        std::sync::Arc::ptr_eq(&self.lights, &scene.lights)
            && self.cookies.iter().copied().eq(scene.cookies.iter().map(|c| c.id()))
    }
}

/// What the last frame left for the probe, the wireframes and the viewer's panels.
#[derive(Default)]
struct LastFrame {
    /// The lights (view space) as the shaders saw them.
    lights: Vec<LightRecord>,
    /// The most ambient + sun could add to a channel (`overlap::clamps`).
    ambient_clamp: f32,
    /// World to view rotation (world-space G-buffer layouts are turned back with it).
    view_rotation: glam::DMat3,
    plan: FramePlan,
    /// The shadow tiles and who casts.
    shadows: shadows::ShadowPlan,
    /// The path it was drawn with: the forward paths leave no G-buffer to read (what the
    /// targets hold is an older frame's).
    path: RenderPath,
    /// The culling mode it was drawn with.
    mode: CullingMode,
    /// The projection it was drawn with (the probe unprojects depth with its inverse).
    proj: DMat4,
    /// What the next frame may take as it is when its inputs are the same (`prepare`).
    reusable: Option<frame::Reusable>,
}

impl LastFrame {
    /// An error when the last frame left no G-buffer (`what` is what was asked for).
    fn gbuffer(&self, what: &str) -> Result<()> {
        if matches!(self.path, RenderPath::Forward | RenderPath::ForwardMultipass) {
            bail!("the {} path keeps no G-buffer: no {what} (use --path deferred or light-prepass)", self.path.name());
        }
        Ok(())
    }
}

/// The camera caps' last list: (the scene's list, the indices kept, the kept lights).
type CappedLights = (Arc<Vec<crate::scene::Light>>, Vec<u32>, Arc<Vec<crate::scene::Light>>);

pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    output_format: wgpu::TextureFormat,
    /// What the adapter can do: every choice asks it.
    caps: Arc<kit::caps::Caps>,
    limits: wgpu::Limits,
    /// The fallbacks already logged (each is said once).
    said: Vec<String>,
    /// The frame's steps are pushed as debug groups (`Gpu::encoder_debug_groups`).
    debug_groups: bool,
    /// The pass set of the current configuration, shared with the device's other renderers.
    passes: Arc<Passes>,
    /// Passes of recent other configurations, least recently used first: kept alive here even
    /// when the device's pool has let them go.
    pass_cache: Vec<Arc<Passes>>,
    /// The device's pass sets.
    pool: Arc<PassPool>,
    /// A frame has been configured with `passes`. The set `new` chooses before it sees a scene
    /// (so with the shader features the settings allow) is not kept in this renderer's cache
    /// when the first scene needs other ones.
    passes_used: bool,
    /// What this renderer's passes write and read back.
    scratch: frame::scratch::Scratch,
    frame: FrameBuffers,
    defaults: MaterialDefaults,
    volumes: Volumes,
    scene: Option<SceneGpu>,
    targets: Option<Targets>,
    queries: stats::Queries,
    last: LastFrame,
    /// The light list the last frame checked, and its shader features.
    lights_seen: Option<LightsSeen>,
    /// The camera caps' last list: (the scene's list, the indices kept, the kept lights).
    capped_lights: Option<CappedLights>,
    /// The allocations of the frame before last's light records and plans, for this frame's
    /// (`FrameRecords::reusing`, `FramePlan::reusing`).
    spare: (Vec<LightRecord>, Vec<plan::LightPlan>),
    /// The last frame's warnings of forward lists too long for lavapipe's loops: logged when
    /// they change, not at every frame of the viewer.
    long_list_warnings: Vec<String>,
    /// The grading LUT the post targets hold, by its `lut` setting (`None`: none uploaded).
    /// Keyed by the file's modification time too, so an edited file is read again.
    lut: Option<((String, Option<std::time::SystemTime>), post::Lut)>,
    /// The per-light cost model of the stats (`explain::cost`): a fitted one, by mode (tiled
    /// and clustered: the list modes; every other: the drawn ones), or the built-in constants.
    pub cost_models: Vec<(CullingMode, explain::cost::CostModel)>,
}

/// Runs `steps`, which encode and submit GPU work, inside error scopes: validation, out of
/// memory, and internal (a driver that fails to compile a pipeline reports it so). A pipeline
/// compiles on its first draw (`kit::OnFirstUse`), inside whichever call draws with it first,
/// so every call that draws runs in these scopes; an error caught turns into the call's error,
/// the innermost scope's (the compile's own message) first. A pipeline that failed to compile
/// stays invalid in its pass set, and each later draw with it fails here too.
pub fn scoped<R>(device: &wgpu::Device, steps: impl FnOnce() -> Result<R>) -> Result<R> {
    let scopes = [wgpu::ErrorFilter::Validation, wgpu::ErrorFilter::OutOfMemory, wgpu::ErrorFilter::Internal]
        .map(|filter| device.push_error_scope(filter));
    let out = steps();
    let caught: Vec<wgpu::Error> = scopes.into_iter().rev().filter_map(|s| pollster::block_on(s.pop())).collect();
    let out = out?;
    if let Some(e) = caught.first() {
        bail!("wgpu error: {}", crate::gpu::describe(e));
    }
    Ok(out)
}

/// Builds a configuration's shader module and layouts, turning validation errors (a bad
/// layout, a module that fails naga's validation) into an error instead of a panic; the
/// pipelines compile later, each on its first draw ([`scoped`]).
fn build_passes(device: &wgpu::Device, key: PipelineKey) -> Result<Passes> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let p = Passes::new(device, key);
    if let Some(e) = pollster::block_on(scope.pop()) {
        bail!("building the pipelines failed: {e}");
    }
    Ok(p)
}

impl Renderer {
    pub fn new(gpu: &Gpu, output_format: wgpu::TextureFormat, settings: &Settings) -> Result<Self> {
        let device = gpu.device.clone();
        settings.validate().map_err(anyhow::Error::msg)?;
        let limits = device.limits();
        let caps = gpu.caps.clone();
        let features = program::ShaderFeatures::of(None, settings, &caps.quirks);
        let key = Self::key(None, settings, settings.layout.layout(), &caps, (output_format, features))?;
        let passes = gpu.passes.get(&device, key)?;
        Ok(Self {
            pool: gpu.passes.clone(),
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
            passes,
            pass_cache: Vec::new(),
            passes_used: false,
            scratch: Default::default(),
            scene: None,
            targets: None,
            last: LastFrame::default(),
            lights_seen: None,
            capped_lights: None,
            spare: Default::default(),
            long_list_warnings: Vec::new(),
            lut: None,
            cost_models: Vec::new(),
            device,
        })
    }

    /// The pipeline configuration `settings` ask for with G-buffer `layout` for `scene` (its
    /// shader features; `None` before the renderer is handed one), or why the adapter cannot
    /// give it. Asks only the capability table: [`support`] calls it without a device.
    fn key(
        scene: Option<&Scene>,
        settings: &Settings,
        layout: gbuffer::GBufferLayout,
        caps: &kit::caps::Caps,
        (output_format, features): (wgpu::TextureFormat, program::ShaderFeatures),
    ) -> Result<PipelineKey> {
        // The light pre-pass's pass 1 writes its own thin buffer, whatever `--layout` says.
        let prepass = settings.path == RenderPath::LightPrepass;
        let layout = if prepass && layout.name != gbuffer::PREPASS_LAYOUT { gbuffer::prepass_layout() } else { layout };
        let layout = layout.for_caps(caps);
        let depth_format = settings.depth_format.format(caps.features);
        let layout = match gbuffer::depth_read_refusal(settings, caps, depth_format) {
            None => layout.reading_depth_buffer(),
            Some(_) => layout,
        };
        layout.validate().map_err(anyhow::Error::msg)?;
        layout.check_caps(caps)?;
        let accum_format = settings.accumulation.format(caps)?;
        let samples = if prepass && settings.msaa == Msaa::X4 { 4 } else { 1 };
        // `--msaa 4` multisamples the light pre-pass's pass 3 and the forward paths: their HDR
        // colour and depth.
        let forward = matches!(settings.path, RenderPath::Forward | RenderPath::ForwardMultipass);
        if settings.msaa == Msaa::X4 && (prepass || forward) && !caps.multisample_x4(kit::HDR_FORMAT) {
            return Err(caps.refuse("--msaa 4", &format!("4-sample {:?} targets", kit::HDR_FORMAT), "use --msaa 1"));
        }
        // A layout without an emissive target (seed 000's, `packed`) carries the surfaces'
        // emission in the accumulation the G-buffer pass starts (`gbuffer_store`): that pass
        // must write ambient + sun, whatever `ambient_in_gbuffer` says, or the emission is lost.
        let fits = kit::ambient_fits(&layout, accum_format, &caps.limits);
        let emission_in_accumulation = !prepass && !layout.has(gbuffer::Attr::Emissive);
        if emission_in_accumulation && !fits {
            return Err(caps.refuse(
                &format!("layout {} (no emissive target: emission goes into the light accumulation)", layout.name),
                &format!(
                    "{} colour attachments of {} bytes per sample in all",
                    layout.targets.len() + 2,
                    layout.bytes_per_pixel() + 2 * accum_format.block_copy_size(None).unwrap_or(16)
                ),
                "choose a layout with an emissive target (compact)",
            ));
        }
        // Seed 004's lightmaps are read at the surface's second texture coordinates, which only
        // the G-buffer pass has: on the deferred path it must start the accumulation.
        let lightmapped = !prepass && !forward && settings.lightmaps && scene.is_some_and(crate::scene::lightmap::any);
        if lightmapped && !fits {
            return Err(caps.refuse(
                "lightmaps on the deferred path (the G-buffer pass applies them as it starts the light accumulation)",
                &format!(
                    "{} colour attachments of {} bytes per sample in all",
                    layout.targets.len() + 2,
                    layout.bytes_per_pixel() + 2 * accum_format.block_copy_size(None).unwrap_or(16)
                ),
                "use --lightmaps off, or the light-prepass or forward paths",
            ));
        }
        Ok(PipelineKey {
            ambient_in_gbuffer: !prepass
                && (settings.ambient_in_gbuffer || emission_in_accumulation || lightmapped)
                && fits,
            prepass,
            samples,
            layout,
            depth_format,
            output_format,
            reversed_z: settings.reversed_z,
            accum_format,
            post_format: post::post_format(caps),
            depth_clamp: settings.depth_clamp && caps.has(wgpu::Features::DEPTH_CLIP_CONTROL),
            features,
            additive_blended: settings.blended == BlendedMode::Additive,
            peeled_blended: settings.blended == BlendedMode::Peeled,
        })
    }

    /// The shader features of a frame of `scene` with `settings` (`ShaderFeatures::of`), read
    /// from the lights only when they are another list than the last frame's (or the sun or
    /// settings changed). Called once the frame's lights passed validation: the list is kept as
    /// checked.
    fn shader_features(&mut self, scene: &Scene, settings: &Settings) -> program::ShaderFeatures {
        if let Some(s) = &self.lights_seen {
            if s.same_list(scene) && s.sun == scene.sun && s.settings == *settings {
                // The materials' part is read afresh: it is not the lights'.
                return program::ShaderFeatures {
                    colour_maps: program::ShaderFeatures::samples_colour_maps(scene),
                    ..s.features
                };
            }
        }
        let features = program::ShaderFeatures::of(Some(scene), settings, &self.caps.quirks);
        self.lights_seen = Some(LightsSeen {
            lights: scene.lights.clone(),
            cookies: scene.cookies.iter().map(|c| c.id()).collect(),
            sun: scene.sun,
            settings: settings.clone(),
            features,
        });
        features
    }

    pub fn depth_format(&self) -> wgpu::TextureFormat {
        self.passes.key().depth_format
    }

    pub fn depth_clamp(&self) -> bool {
        self.passes.key().depth_clamp
    }

    pub fn layout(&self) -> &gbuffer::GBufferLayout {
        &self.passes.key().layout
    }

    /// Uploads the scene's meshes and textures. Call once per scene (`render` calls it when it
    /// is handed a different scene); `render` uploads camera, objects and lights every frame.
    pub fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        let material_bgl = &self.passes.shared.material_bgl;
        self.scene = Some(SceneGpu::upload(&self.device, &self.queue, scene, material_bgl, &self.defaults)?);
        Ok(())
    }

    /// Brings passes, volume meshes, the scene's upload and the targets up to what this frame
    /// asks for.
    fn configure(&mut self, scene: &Scene, settings: &Settings, size: (u32, u32), hdr: bool, post: bool) -> Result<()> {
        let tessellation = (settings.sphere_subdivisions, settings.cone_sides);
        if tessellation != self.volumes.tessellation {
            self.volumes = Volumes::new(&self.device, tessellation);
        }
        let layout = if settings.path == RenderPath::LightPrepass {
            // One layer for the whole buffer (the thin buffer has no channel for it); objects on
            // layers the lights tell apart from it are shaded forward (`Scene::shared_layers`).
            gbuffer::GBufferLayout { uniform_layer: Some(scene.shared_layers().0), ..gbuffer::prepass_layout() }
        } else {
            settings.layout.layout_for(scene, settings.brdf.brdf()).map_err(anyhow::Error::msg)?
        };
        let features = self.shader_features(scene, settings);
        let key = Self::key(Some(scene), settings, layout, &self.caps, (self.output_format, features))?;
        if key != *self.passes.key() {
            // Whether only the shader features differ from the set this renderer drew with.
            let only_features = self.passes_used
                && PipelineKey { features: self.passes.key().features, ..key.clone() } == *self.passes.key();
            // Switching back to a configuration seen recently reuses its passes instead of
            // compiling them again (and on lavapipe, leaving the old compilation's memory behind).
            let next = match self.pass_cache.iter().position(|p| *p.key() == key) {
                Some(i) => self.pass_cache.remove(i),
                None => self.pool.get(&self.device, key)?,
            };
            let previous = std::mem::replace(&mut self.passes, next);
            // The set `new` chose before it saw a scene stays in the pool only.
            if self.passes_used {
                self.pass_cache.push(previous);
            }
            if self.pass_cache.len() > PIPELINE_CACHE {
                self.pass_cache.remove(0);
            }
            let shared = &self.passes.shared;
            self.frame.rebind(&self.device, &shared.frame_bgl);
            // The targets depend on the layout, formats and samples, not on which lookups the
            // shaders compile in (and wgpu gives identical bind-group layouts one identity), so
            // a change of shader features alone (a light's shadow flag, the sun, the first
            // cookie) keeps them, and with them the auto-exposure's adaptation and the LUT.
            if !only_features {
                self.targets = None;
            }
            if let Some(gpu_scene) = &mut self.scene {
                gpu_scene.rebind_materials(&self.device, scene, &shared.material_bgl, &self.defaults);
            }
        }
        if self.defaults.set_anisotropy(&self.device, settings.anisotropy as u16) {
            if let Some(gpu_scene) = &mut self.scene {
                gpu_scene.rebind_materials(&self.device, scene, &self.passes.shared.material_bgl, &self.defaults);
            }
        }
        if self.scene.as_ref().is_none_or(|g| g.fingerprint != SceneFingerprint::of(scene)) {
            self.load_scene(scene)?;
        }
        if !self.targets.as_ref().is_some_and(|t| t.fit(&self.passes.shared, size, hdr, post)) {
            self.targets = Some(Targets::new(&self.device, &self.passes.shared, size, hdr, post, &self.frame.compose));
            self.lut = None;
        }
        // The post chain's parameters, and its LUT when the setting names another one.
        if let Some(pt) = self.targets.as_ref().and_then(|t| t.post.as_ref()) {
            if let Some(name) = &settings.lut {
                let key = (name.clone(), std::fs::metadata(name).and_then(|m| m.modified()).ok());
                if self.lut.as_ref().is_none_or(|(k, _)| *k != key) {
                    let lut = post::Lut::load(name).map_err(anyhow::Error::msg)?;
                    let data: Vec<[f32; 4]> = lut.table.iter().map(|e| [e[0], e[1], e[2], 0.0]).collect();
                    self.queue.write_buffer(&pt.lut, 0, bytemuck::cast_slice(&data));
                    self.lut = Some((key, lut));
                }
            }
            let lut = settings.lut.as_ref().and(self.lut.as_ref().map(|(_, l)| l));
            self.queue.write_buffer(&pt.params, 0, bytemuck::bytes_of(&post::params(settings, lut)));
        }
        self.passes_used = true;
        Ok(())
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
                capped = self.capped_scene(scene, kept);
                &capped
            }
            None => scene,
        };
        let device = self.device.clone();
        let (shape, prepared, drawn) = scoped(&device, || self.encode_frame(scene, settings, target, (width, height)))?;
        let mut stats = self.report(scene, settings, &shape, &prepared, drawn)?;
        if cut.is_some() || settings.lights_per_cluster > 0 || settings.lights_per_object > 0 {
            let mut cut = cut.unwrap_or_default();
            if let Some(culling::tiled::ClusterBuild::Cpu(lists)) = &prepared.plan.clusters {
                cut.cluster_entries_dropped = lists.capped;
            }
            cut.object_entries_dropped = prepared.path_lists.capped;
            stats.caps = Some(cut);
        }
        for f in &stats.adapter.fallbacks {
            if !self.said.contains(f) {
                log::warn!("on {}: {f}", self.caps.adapter);
                self.said.push(f.clone());
            }
        }
        self.keep(scene, settings, prepared);
        Ok(stats)
    }

    /// `scene` with only the lights `kept`, built again only when the scene's lights or the
    /// kept set changed (a still frame under a camera cap keeps its list's identity, so the
    /// frame's CPU part is reused as without the cap). The rest of the scene is copied each
    /// frame.
    fn capped_scene(&mut self, scene: &Scene, kept: &[u32]) -> Scene {
        let lights = match &self.capped_lights {
            Some((source, k, lights)) if Arc::ptr_eq(source, &scene.lights) && k == kept => lights.clone(),
            _ => {
                let lights: Arc<Vec<crate::scene::Light>> =
                    Arc::new(kept.iter().map(|&i| scene.lights[i as usize]).collect());
                self.capped_lights = Some((scene.lights.clone(), kept.to_vec(), lights.clone()));
                lights
            }
        };
        Scene { lights, ..scene.clone() }
    }

    /// The frame's steps up to its submission.
    fn encode_frame(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        target: &wgpu::TextureView,
        (width, height): (u32, u32),
    ) -> Result<(frame::Shape, frame::Prepared, paths::Drawn)> {
        let checked = self.lights_seen.as_ref().is_some_and(|s| s.same_list(scene));
        let shape = frame::Shape::of_checked(scene, settings, (width, height), checked)?;
        self.configure(scene, settings, shape.size, shape.hdr(), shape.chain)?;
        // The CPU's part: records, the culling plan, clamps, the shadow plan, their upload.
        let prepared = self.prepare(scene, settings, &shape)?;
        self.passes.prepare(shape.needs(&prepared.plan, settings))?;
        let f = self.inputs(settings, &shape, &prepared)?;
        let p = &self.passes;
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let c = paths::PathInputs {
            device: &self.device,
            queue: &self.queue,
            passes: p,
            f: &f,
            shape: &shape,
            prepared: &prepared,
            scene,
            target,
            debug_groups: self.debug_groups,
        };
        // 0. Shadows: each casting light's depth into its tiles of the atlas, on every path.
        c.group(&mut encoder, "shadows", |e| p.shadows.encode(&self.device, e, &f, &prepared.shadows));
        // 1-3. The path's own passes, into `target`.
        let drawn = paths::record(settings.path, &c, &mut encoder)?;
        // 4. Measurement only, outside the frame's timestamps: the ideal count and coverage.
        c.group(&mut encoder, "measure", |e| p.measure.encode(e, &f));
        let (n, m) = (prepared.plan.lights.len(), self.measured(settings, &shape, &prepared));
        // The geometry passes' counts: the G-buffer pass (deferred shading) or passes 1 and 3.
        let geometry = if drawn.prepass.is_some() { 2 } else { u32::from(settings.path == RenderPath::Deferred) };
        self.queries.resolve(&mut encoder, n, m.counts, m.ideal, m.times, m.forward, geometry);
        self.queue.submit([encoder.finish()]);
        Ok((shape, prepared, drawn))
    }

    /// Keeps what the probe, the wireframes and the panels read of the frame just drawn, and
    /// the allocations of the one before for the next frame's records and plans.
    fn keep(&mut self, scene: &Scene, settings: &Settings, prepared: frame::Prepared) {
        let frame::Prepared { records, plan, path_lists, shadows, key, reused, .. } = prepared;
        let last = LastFrame {
            view_rotation: scene.camera.rotation(),
            lights: records.lights,
            ambient_clamp: records.camera.light_clamp,
            plan,
            shadows,
            path: settings.path,
            mode: settings.culling,
            proj: records.proj,
            reusable: Some(frame::Reusable { key, camera: records.camera, objects: records.objects, path_lists }),
        };
        let before = std::mem::replace(&mut self.last, last);
        // A reused frame took the last one's lists: the spare allocations stay those from before.
        if !reused {
            self.spare = (before.lights, before.plan.lights);
        }
    }

    /// Re-runs only the compose pass of the last frame with another view, into `target` of the
    /// output format at any size (the G-buffer is point-sampled): the viewer's thumbnails.
    /// The stencil and complexity views show what the last frame computed for them.
    pub fn compose_view(&mut self, view: DebugView, target: &wgpu::TextureView, width: u32, height: u32) -> Result<()> {
        let Some(targets) = &self.targets else { bail!("nothing rendered yet") };
        if width == 0 || height == 0 {
            bail!("cannot compose a {width}x{height} view");
        }
        self.last.gbuffer(&format!("{} view", view.name()))?;
        // Set up here if no frame has (a frame that failed after configure).
        self.passes.compose.prepare()?;
        scoped(&self.device, || {
            let mut encoder =
                self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("compose view") });
            let to = ComposeTarget { view: target, size: (width, height), debug_view: view, slot: view as u64 + 1 };
            self.passes.compose.encode(&mut encoder, &self.queue, targets, &self.frame, &to, None);
            self.queue.submit([encoder.finish()]);
            Ok(())
        })
    }

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
            out.extend(if log { v.map(settings::log_accum_decode) } else { v });
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
    pub fn shadow_plan(&self) -> &shadows::ShadowPlan {
        &self.last.shadows
    }

    /// The last frame's per-light plans (method, volume, planes crossed, screen share).
    pub fn plans(&self) -> &[LightPlan] {
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
    pub fn zbin_job(&self) -> Option<&culling::zbin::ZBinJob> {
        self.last.plan.zbins.as_ref()
    }

    /// The last frame's lights as the shaders saw them (view space, cut-off radius applied).
    pub fn light_records(&self) -> &[LightRecord] {
        &self.last.lights
    }

    /// Size of the last frame.
    pub fn size(&self) -> Option<(u32, u32)> {
        self.targets.as_ref().map(|t| (t.width, t.height))
    }

    pub fn output_format(&self) -> wgpu::TextureFormat {
        self.output_format
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
        let sets = || std::iter::once(&self.passes).chain(&self.pass_cache);
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
                out.extend(if log { v.map(settings::log_accum_decode) } else { v });
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
}
