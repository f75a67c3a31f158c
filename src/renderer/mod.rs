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
pub mod support;
pub mod surfaces;
pub mod targets;
mod tools;

// The culling modules at the paths the rest of the crate and the tests name them by.
pub use culling::tiled as tiles;
pub use culling::{batches, overlap, plan, volumes};

use crate::gpu::Gpu;
use crate::scene::Scene;
use anyhow::{bail, Result};
pub use culling::stats::LightStats;
use frame::passes::Passes;
pub use inspect::{volume_wireframe_with, PixelProbe};
use kit::{gbuffer, PipelineKey};
pub use plan::{LightPlan, Method, AUTO_STENCIL_MIN_PIXELS};
pub use records::{light_clamp, LIGHT_KIND_POINT, LIGHT_KIND_SPOT};
use records::{FrameBuffers, LightRecord};
pub use report::FrameStats;
use scene_gpu::{MaterialDefaults, SceneFingerprint, SceneGpu};
pub use settings::{
    AccumFormat, BlendedMode, BrdfOverride, CullingMode, DebugView, DepthFormat, DepthRead, DrawOrder, ForwardLights,
    LayoutChoice, Msaa, NearLights, RenderPath, Settings, ShadowCube, ShadowFilter, ShadowFormat, ShadowMode,
};
pub use stats::CpuMs;
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
    pool: Arc<kit::pool::PassPool>,
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
    last: frame::last::LastFrame,
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

pub use kit::scoped;

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
    /// The last frame, for the tools that read it (`tools/`).
    pub fn last_frame(&self) -> frame::last::Last<'_> {
        frame::last::Last {
            device: &self.device,
            queue: &self.queue,
            caps: &self.caps,
            passes: &self.passes,
            pass_cache: &self.pass_cache,
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
        let passes = gpu.passes.get(key.clone(), || build_passes(&device, key))?;
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
            last: Default::default(),
            lights_seen: None,
            capped_lights: None,
            spare: Default::default(),
            long_list_warnings: Vec::new(),
            lut: None,
            cost_models: Vec::new(),
            device,
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
        let key = key::pipeline_key(Some(scene), settings, layout, &self.caps, (self.output_format, features))?;
        if key != *self.passes.key() {
            // Whether only the shader features differ from the set this renderer drew with.
            let only_features = self.passes_used
                && PipelineKey { features: self.passes.key().features, ..key.clone() } == *self.passes.key();
            // Switching back to a configuration seen recently reuses its passes instead of
            // compiling them again (and on lavapipe, leaving the old compilation's memory behind).
            let next = match self.pass_cache.iter().position(|p| *p.key() == key) {
                Some(i) => self.pass_cache.remove(i),
                None => self.pool.get(key.clone(), || build_passes(&self.device, key))?,
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
            self.queue.write_buffer(&pt.params, 0, bytemuck::bytes_of(&post::params(&settings.post_options(), lut)));
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
        let last = frame::last::LastFrame {
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

    /// Size of the last frame.
    pub fn size(&self) -> Option<(u32, u32)> {
        self.targets.as_ref().map(|t| (t.width, t.height))
    }

    pub fn output_format(&self) -> wgpu::TextureFormat {
        self.output_format
    }
}
