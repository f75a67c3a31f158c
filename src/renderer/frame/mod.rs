//! One frame, before any pass is recorded: what the frame is ([`Shape`], from its settings and
//! scene), then the CPU's part ([`Renderer::prepare`]): the records the shaders read, the
//! culling plan, the fp16 clamps, the shadow plan, and their upload. [`inputs`] is what the
//! passes read; [`passes`] every pass, built for one configuration.

pub mod last;
pub mod passes;

use super::key;
use super::kit::gbuffer;
use super::plan::{self, ForwardPathLists, FramePlan, PlanView};
use super::records::{FrameLists, FrameRecords};
use super::scene_gpu::{SceneFingerprint, SceneGpu};
use super::shadows::{self, ShadowPlan};
use super::stats::CpuMs;
use super::stochastic;
use super::targets::Targets;
use super::volumes::Volumes;
use super::{
    cputime, overlap, post, AccumFormat, BlendedMode, DebugView, DrawOrder, NearLights, RenderPath, Renderer, Settings,
};
use crate::renderer::inputs::FrameInputs;
pub use crate::renderer::inputs::Shape;
use crate::renderer::settings::CullingMode;
use crate::scene::Scene;
use anyhow::{bail, Result};
use passes::Needs;

impl Shape {
    /// The frame's shape, or why `settings` cannot draw `scene` at `size`; the lights are left
    /// unread when `lights_checked` (this very light list passed `Scene::validate_lights`).
    pub fn of_checked(scene: &Scene, settings: &Settings, size: (u32, u32), lights_checked: bool) -> Result<Shape> {
        let (width, height) = size;
        if width == 0 || height == 0 {
            bail!("cannot render a {width}x{height} frame");
        }
        settings.validate().map_err(anyhow::Error::msg)?;
        scene.validate_except_lights().map_err(anyhow::Error::msg)?;
        if !lights_checked {
            scene.validate_lights().map_err(anyhow::Error::msg)?;
        }
        let final_view = settings.debug_view == DebugView::Lit || post::post_view(settings.debug_view);
        let forward_path = !settings.path.keeps_gbuffer();
        if forward_path && !final_view {
            bail!(
                "the {} path has no G-buffer or light buffers to show the {} view; use --path deferred",
                settings.path.name(),
                settings.debug_view.name()
            );
        }
        // A clustered grid the knobs make finer than its lists can be held for (the cells'
        // (first, count) headers alone past 32 MiB).
        let grid = crate::renderer::culling::tiled::GridChoice::of(&settings.culling_options(), settings.cap_order);
        let tile = grid.tile(size).max(1);
        let slices = if grid.slices > 0 { grid.slices } else { crate::renderer::culling::tiled::SLICES };
        let cells = width.div_ceil(tile) as u64 * height.div_ceil(tile) as u64 * slices as u64;
        let clustered = matches!(settings.culling, CullingMode::Clustered | CullingMode::Auto) && !forward_path;
        if clustered && cells > crate::renderer::culling::tiled::MAX_GRID_CELLS {
            bail!(
                "a clustered grid of {tile}-pixel tiles and {slices} slices at {width}x{height} has {cells} cells (most {}); \
                 use a larger --cluster-tile or fewer --cluster-slices",
                crate::renderer::culling::tiled::MAX_GRID_CELLS
            );
        }
        let n = scene.lights.len();
        if n > crate::renderer::settings::MAX_LIGHTS_EVERY_MODE {
            let listed = matches!(
                settings.culling,
                CullingMode::Zbin | CullingMode::Clustered | CullingMode::Tiled | CullingMode::Auto
            );
            if forward_path || !listed {
                bail!(
                    "{n} lights: past {} only --culling zbin, clustered or tiled (or auto, which then takes zbin) on the \
                     deferred path or the light pre-pass take them; {} on the {} path draws or lists per light",
                    crate::renderer::settings::MAX_LIGHTS_EVERY_MODE,
                    settings.culling.name(),
                    settings.path.name()
                );
            }
        }
        let prepass = settings.path == RenderPath::LightPrepass;
        if prepass {
            super::paths::prepass_pass::check(&settings.frame_options())?;
        }
        Ok(Shape {
            size,
            forward_path,
            prepass_lit: prepass && final_view,
            blended: final_view && scene.any_blended(),
            chain: post::chain_active(settings.debug_view, &settings.post_options()),
        })
    }

    /// The passes beyond those every frame uses.
    pub fn needs(&self, plan: &FramePlan, settings: &Settings) -> Needs {
        Needs {
            blended: self.forward_path || self.blended || self.prepass_lit || self.chain,
            prepass: self.prepass_lit,
            tiled: !self.forward_path && (plan.tiled.is_some() || settings.debug_view == DebugView::TileLights),
            post: self.chain,
        }
    }
}

/// Whether a frame's pipelines are compiled ([`Renderer::pipelines_ready`]).
pub enum Readiness {
    /// All of them: the declared set, each with its compile time.
    Ready(super::kit::Declared),
    /// This many of the declared set are not.
    Missing(usize),
    /// Its pass set is not built (its shader module, layouts and every pipeline).
    NewSet,
}

/// The CPU's part of a frame: what the passes read, uploaded.
pub struct Prepared {
    pub records: FrameRecords,
    pub plan: FramePlan,
    /// The forward paths' object lists (and multi-pass's pairs); empty on the other paths.
    pub path_lists: ForwardPathLists,
    pub shadows: ShadowPlan,
    pub cpu_ms: CpuMs,
    /// Each technique's options, from the frame's settings.
    pub options: crate::renderer::options::Options,
    /// What it was computed from.
    pub key: FrameKey,
    /// Taken as it was from the frame before, whose upload the GPU still holds
    /// ([`FrameKey::matches`]): nothing was computed or written for it.
    pub reused: bool,
}

/// What a frame's CPU part ([`Renderer::prepare`]) is computed from. A frame whose inputs
/// match the last frame's takes that frame's records, plans and shadow plan as they are, and
/// what they uploaded stays on the GPU: its CPU work and upload then grow with the objects and
/// materials compared here, not with the lights. The lights are compared by identity:
/// `Scene::lights` is shared and copied on write, and the key holds the last frame's list, so
/// a list changed since is always another allocation. The rest is compared by value.
pub struct FrameKey {
    lights: std::sync::Arc<Vec<crate::scene::Light>>,
    camera: crate::scene::Camera,
    objects: Vec<crate::scene::Object>,
    materials: Vec<crate::scene::Material>,
    sun: Option<crate::scene::Sun>,
    ambient: glam::Vec3,
    background: glam::Vec3,
    cookies: Vec<u64>,
    fingerprint: super::scene_gpu::SceneFingerprint,
    settings: Settings,
    size: (u32, u32),
    pipeline: super::kit::pipeline::PipelineKey,
}

impl FrameKey {
    /// The light list the frame was computed from.
    pub fn lights(&self) -> &std::sync::Arc<Vec<crate::scene::Light>> {
        &self.lights
    }

    fn of(scene: &Scene, settings: &Settings, size: (u32, u32), pipeline: &super::kit::pipeline::PipelineKey) -> Self {
        Self {
            lights: scene.lights.clone(),
            camera: scene.camera,
            objects: scene.objects.clone(),
            materials: scene.materials.clone(),
            sun: scene.sun,
            ambient: scene.ambient,
            background: scene.background,
            cookies: scene.cookies.iter().map(|c| c.id()).collect(),
            fingerprint: super::scene_gpu::SceneFingerprint::of(scene),
            settings: settings.clone(),
            size,
            pipeline: pipeline.clone(),
        }
    }

    /// Whether a frame of `scene` with `settings` at `size` through `pipeline` has these inputs.
    pub fn matches(
        &self,
        scene: &Scene,
        settings: &Settings,
        size: (u32, u32),
        pipeline: &super::kit::pipeline::PipelineKey,
    ) -> bool {
        std::sync::Arc::ptr_eq(&self.lights, &scene.lights)
            && self.camera == scene.camera
            && self.size == size
            && self.sun == scene.sun
            && self.ambient == scene.ambient
            && self.background == scene.background
            && self.settings == *settings
            && self.objects == scene.objects
            && self.materials == scene.materials
            && self.cookies.iter().copied().eq(scene.cookies.iter().map(|c| c.id()))
            && self.pipeline == *pipeline
            && self.fingerprint == super::scene_gpu::SceneFingerprint::of(scene)
    }
}

/// What a frame kept for the next one beyond `LastFrame`'s own figures: its key, and the parts
/// of its [`Prepared`] the probe does not read.
pub struct Reusable {
    pub key: FrameKey,
    pub camera: super::records::CameraRecord,
    pub objects: Vec<super::records::ObjectRecord>,
    pub path_lists: ForwardPathLists,
}

impl Renderer {
    /// Uploads the scene's meshes and textures. Call once per scene (`render` calls it when it
    /// is handed a different scene); `render` uploads camera, objects and lights every frame.
    pub fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        let material_bgl = &self.sets.current.shared.material_bgl;
        self.scene =
            Some(SceneGpu::upload(&self.device, &self.queue, scene, material_bgl, (&self.defaults, &self.uploads))?);
        Ok(())
    }

    /// Brings passes, volume meshes, the scene's upload and the targets up to what this frame
    /// asks for.
    pub(in crate::renderer) fn configure(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        size: (u32, u32),
        hdr: bool,
        post: bool,
    ) -> Result<()> {
        let tessellation = (settings.sphere_subdivisions, settings.cone_sides);
        if tessellation != self.volumes.tessellation {
            self.volumes = Volumes::new(&self.device, tessellation);
        }
        let key = self.frame_key(scene, settings)?;
        if let Some(only_features) = self.sets.switch(&self.device, key)? {
            let shared = &self.sets.current.shared;
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
                gpu_scene.rebind_materials(&self.device, scene, &self.sets.current.shared.material_bgl, &self.defaults);
            }
        }
        if self.scene.as_ref().is_none_or(|g| g.fingerprint != SceneFingerprint::of(scene)) {
            self.load_scene(scene)?;
        }
        if !self.targets.as_ref().is_some_and(|t| t.fit(&self.sets.current.shared, size, hdr, post)) {
            self.targets =
                Some(Targets::new(&self.device, &self.sets.current.shared, size, hdr, post, &self.frame.compose));
            self.lut = Default::default();
        }
        // The post chain's parameters, and its LUT when the setting names another one.
        if let Some(pt) = self.targets.as_ref().and_then(|t| t.post.as_ref()) {
            // The auto focus's fallback walks the objects: only for a frame that focuses.
            let focuses = settings.focus_distance == super::options::post::Focus::Auto
                && (settings.dof || settings.debug_view == super::options::DebugView::Coc);
            let fallback = match (&self.scene, focuses) {
                (Some(g), true) => post::focus_fallback(scene, &g.bounds),
                _ => scene.camera.far as f32,
            };
            self.lut.upload(&self.queue, pt, &settings.post_options(), fallback)?;
        }
        Ok(())
    }

    /// Builds the frame's records and plans and uploads them. The renderer is configured for
    /// the frame (`configure`).
    pub(super) fn prepare(&mut self, scene: &Scene, settings: &Settings, shape: &Shape) -> Result<Prepared> {
        let size = shape.size;
        let whole = cputime::Clock::start();
        if let Some(last) = self.reuse_last(scene, settings, size, &whole) {
            return Ok(last);
        }
        let Some(gpu_scene) = &self.scene else { bail!("internal: scene missing after configure") };
        let key = self.sets.current.key().clone();
        let clock = cputime::Clock::start();
        let (spare_lights, spare_plans) = std::mem::take(&mut self.spare);
        let mut records = FrameRecords::reusing(scene, &settings.options(), size, key.accum_format, spare_lights);
        super::records::stored_position_pads(&mut records.lights, key.layout.position_rounding(), &records.proj);
        // Stochastic culling's ranges for this frame, before anything culls with them.
        stochastic::randomise_ranges(&mut records.lights, &settings.stochastic_options());
        let records_ms = clock.ms();
        let view =
            plan_view(scene, settings, &records, (&key, self.caps.quirks.loop_limit), size, self.calibration.costs);
        let clock = cputime::Clock::start();
        let mut plan = FramePlan::reusing(scene, &mut records, &gpu_scene.bounds, &self.volumes, &view, spare_plans);
        // The forward paths' object lists (and multi-pass's pairs) follow the frame's lists.
        let path_lists = if shape.forward_path {
            plan::forward_path_lists(
                scene,
                &mut records.objects,
                &gpu_scene.bounds,
                &plan.lights,
                &plan.draws.gbuffer,
                size,
                &mut plan.light_lists,
                (
                    settings.path == RenderPath::ForwardMultipass,
                    settings.forward_lights == crate::renderer::ForwardLights::All,
                ),
                view.object_cap,
            )
            .map_err(anyhow::Error::msg)?
        } else {
            Default::default()
        };
        warn_long_lists(self.caps.quirks.loop_limit, &mut self.long_list_warnings, settings, shape, &plan, &path_lists);
        // The fp16 clamp by what can overlap a pixel (see `overlap`).
        let clamps = overlap::clamps(&plan.lights, size, key.accum_format);
        records.camera.light_clamp = clamps.ambient;
        // Who casts, and each caster's tiles in the atlas (`shadows`).
        let shadow_plan = shadows::plan(
            scene,
            &shadows::ShadowInputs {
                options: &settings.shadow_options(),
                bounds: &gpu_scene.bounds,
                footprints: plan.lights.iter().map(|l| (l.screen_share, l.screen_rect.is_some())).collect(),
                size,
                proj: records.proj,
                max_texture: self.limits.max_texture_dimension_2d,
                max_layers: self.limits.max_texture_array_layers,
            },
        );
        // The clamps and shadow tiles into the records in one walk over them (1.8 MB at 16,384
        // lights: a walk costs more in memory traffic than the stores).
        for ((l, c), &(first, count)) in records.lights.iter_mut().zip(&clamps.lights).zip(&shadow_plan.lights) {
            l.clamp = *c;
            l.shadow = [first, count, 0, 0];
        }
        let plan_ms = clock.ms();
        let clock = cputime::Clock::start();
        let lists = FrameLists { forward: &plan.light_lists, draw: &plan.batches.list };
        let bgl = &self.sets.current.shared.frame_bgl;
        self.frame.upload(&self.device, &self.queue, bgl, &records, lists, scene);
        if key.features.light_planes {
            self.frame.upload_light_planes(&self.queue, &records.lights)?;
        }
        let (side, tiles, params) = (shadow_plan.side, &shadow_plan.tiles, &shadow_plan.params);
        let format = shadow_plan.stats.format.texture();
        self.frame.upload_shadows(&self.device, &self.queue, bgl, (side, format), tiles, params, &shadow_plan.casters);
        let cubes = (shadow_plan.cube_side, shadow_plan.cube_layers);
        self.frame.ensure_shadow_cubes(&self.device, bgl, cubes, format);
        self.frame.ensure_shadow_indirection(&self.device, &self.queue, bgl, shadow_plan.indirection_side);
        let cpu_ms = CpuMs { records: records_ms, plan: plan_ms, upload: clock.ms(), wall: whole.wall_ms() };
        self.queries.ensure_lights(&self.device, plan.lights.len());
        let key = FrameKey::of(scene, settings, size, &key);
        Ok(Prepared {
            records,
            plan,
            path_lists,
            shadows: shadow_plan,
            cpu_ms,
            options: settings.options(),
            key,
            reused: false,
        })
    }

    /// The frame before's CPU part as it is, when this frame has the same inputs (taken, so a
    /// frame that fails after this leaves nothing to reuse; `keep` puts it back).
    fn reuse_last(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        size: (u32, u32),
        whole: &cputime::Clock,
    ) -> Option<Prepared> {
        let pipeline = self.sets.current.key();
        let r = self.last.reusable.take_if(|r| r.key.matches(scene, settings, size, pipeline))?;
        let last = &mut self.last;
        let records = FrameRecords {
            camera: r.camera,
            lights: std::mem::take(&mut last.lights),
            objects: r.objects,
            proj: last.proj,
            view: last.view,
        };
        let (plan, shadows) = (std::mem::take(&mut last.plan), std::mem::take(&mut last.shadows));
        self.queries.ensure_lights(&self.device, plan.lights.len());
        let cpu_ms = CpuMs { records: 0.0, plan: whole.ms(), upload: 0.0, wall: whole.wall_ms() };
        Some(Prepared {
            records,
            plan,
            path_lists: r.path_lists,
            shadows,
            cpu_ms,
            options: settings.options(),
            key: r.key,
            reused: true,
        })
    }

    /// Builds, on this thread, every pipeline a frame of `scene` with `settings` at `size`
    /// declares, without recording it: that frame then compiles nothing while it records.
    /// Returns (declared, built now).
    pub fn build_pipelines(&mut self, scene: &Scene, settings: &Settings, size: (u32, u32)) -> Result<(usize, usize)> {
        let (declared, now) = self.build_pipelines_each(scene, settings, size)?;
        Ok((declared.len(), now.into_iter().filter(|b| *b).count()))
    }

    /// The pass set a frame of `scene` with `settings` draws with.
    fn frame_key(&mut self, scene: &Scene, settings: &Settings) -> Result<super::kit::PipelineKey> {
        let layout = if settings.path == RenderPath::LightPrepass {
            // One layer for the whole buffer (the thin buffer has no channel for it); objects on
            // layers the lights tell apart from it are shaded forward (`Scene::shared_layers`).
            gbuffer::GBufferLayout { uniform_layer: Some(scene.shared_layers().0), ..gbuffer::prepass_layout() }
        } else {
            settings.layout.layout_for(scene, settings.brdf.brdf()).map_err(anyhow::Error::msg)?
        };
        let features = self.features.of(scene, settings, &self.caps.quirks);
        key::pipeline_key(Some(scene), settings, layout, &self.caps, (self.output_format, features))
    }

    /// Whether a frame of `scene` with `settings` at `size` would find every pipeline it
    /// declares compiled, asked without compiling any: a set not built yet is not made (its
    /// shader module alone is a parse and validation of the whole program). It reconfigures
    /// this renderer for that frame, so the viewer asks a renderer of its own that draws
    /// nothing. `Err`: the frame cannot be drawn (its drawing says why).
    pub fn pipelines_ready(&mut self, scene: &Scene, settings: &Settings, size: (u32, u32)) -> Result<Readiness> {
        Shape::of_checked(scene, settings, size, false)?;
        let key = self.frame_key(scene, settings)?;
        if !self.sets.has(&key) {
            return Ok(Readiness::NewSet);
        }
        let declared = self.declared(scene, settings, size)?;
        Ok(match declared.missing() {
            0 => Readiness::Ready(declared),
            n => Readiness::Missing(n),
        })
    }

    /// The pipelines a frame of `scene` with `settings` at `size` declares (each with its label
    /// and compile time), built on this thread, and for each whether this call compiled it
    /// (see [`Renderer::build_pipelines`]).
    pub fn build_pipelines_each(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        size: (u32, u32),
    ) -> Result<(super::kit::Declared, Vec<bool>)> {
        let declared = self.declared(scene, settings, size)?;
        // Inside error scopes: a compile's error is this call's error.
        let now = super::kit::scoped(&self.device.clone(), || Ok(self.sets.current.build_each(&declared)))?;
        Ok((declared, now))
    }

    /// The pipeline the viewer's thumbnails compose with (`Last::compose_view`, every view
    /// but the lit one) in this renderer's current pass set, built on this thread: after
    /// [`Renderer::build_pipelines_each`], the thumbnails of that configuration compile
    /// nothing either. Returns it declared, and whether this call compiled it.
    pub fn build_view_pipeline(&self) -> Result<(super::kit::Declared, Vec<bool>)> {
        let compose = &self.sets.current.compose;
        compose.prepare()?;
        let mut declared = super::kit::Declared::default();
        declared.add(compose.pipeline(DebugView::Albedo));
        let now = super::kit::scoped(&self.device, || Ok(self.sets.current.build_each(&declared)))?;
        Ok((declared, now))
    }

    /// What each pipeline a frame of `scene` with `settings` at `size` declares is, in the
    /// order its passes declare them; nothing is compiled or recorded.
    pub fn describe_pipelines(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        size: (u32, u32),
    ) -> Result<Vec<super::kit::description::PipelineDescription>> {
        Ok(self.declared(scene, settings, size)?.descriptions())
    }

    /// The pipelines a frame of `scene` with `settings` at `size` declares, the renderer
    /// configured for it.
    fn declared(&mut self, scene: &Scene, settings: &Settings, size: (u32, u32)) -> Result<super::kit::Declared> {
        let device = self.device.clone();
        let target = super::kit::texture_2d(
            &device,
            "pipelines only",
            (self.output_format, &[]),
            size,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&Default::default());
        super::kit::scoped(&device, || {
            let shape = Shape::of_checked(scene, settings, size, false)?;
            self.configure(scene, settings, shape.size, shape.hdr(), shape.chain)?;
            let prepared = self.prepare(scene, settings, &shape)?;
            self.sets.current.prepare(shape.needs(&prepared.plan, settings))?;
            let f = self.inputs(settings, &shape, &prepared, &target)?;
            let steps = super::paths::steps(&self.sets.current, &f);
            Ok(super::paths::declare(&steps, &f))
        })
    }

    /// What the frame measures, by what `settings` ask for and the frame draws.
    pub(super) fn measured(&self, settings: &Settings, shape: &Shape, prepared: &Prepared) -> Measured {
        let lit = !prepared.plan.lights.is_empty();
        Measured {
            // Per-light counts are the deferred light pass's (the forward paths count per pass).
            counts: settings.count_fragments && lit && !shape.forward_path,
            ideal: settings.count_ideal && lit && !shape.forward_path,
            times: settings.timestamps && self.queries.timestamps.is_some(),
            forward: match (settings.count_fragments && shape.blended, settings.blended) {
                (false, _) => 0,
                (true, crate::renderer::settings::BlendedMode::Peeled) => settings.peel_layers + 1,
                (true, _) => 1,
            },
        }
    }

    /// What the frame's passes read: the renderer's targets and buffers with `prepared`.
    pub(super) fn inputs<'a>(
        &'a self,
        settings: &'a Settings,
        shape: &'a Shape,
        prepared: &'a Prepared,
        output: &'a wgpu::TextureView,
    ) -> Result<FrameInputs<'a>> {
        let (Some(targets), Some(scene)) = (&self.targets, &self.scene) else {
            bail!("internal: targets or scene missing after configure");
        };
        let m = self.measured(settings, shape, prepared);
        Ok(FrameInputs {
            device: &self.device,
            queue: &self.queue,
            shape,
            output,
            background: prepared.records.camera.background,
            path_lists: &prepared.path_lists,
            shadows: &prepared.shadows,
            targets,
            scene,
            frame: &self.frame,
            volumes: &self.volumes,
            plan: &prepared.plan,
            queries: &self.queries,
            options: &prepared.options,
            counts: m.counts,
            ideal: m.ideal,
            times: m.times,
            forward_counts: m.forward > 0,
            depth_clamp: self.sets.current.key().depth_clamp,
            shadowed: &prepared.shadows.lights,
            scratch: &self.scratch,
            reused: prepared.reused,
            progress: self.progress.as_ref(),
            debug_groups: self.debug_groups,
            view: prepared.records.view,
            proj: prepared.records.proj,
            scene_lights: prepared.key.lights(),
        })
    }
}

/// What the culling plan needs of the frame beyond the scene: the camera's projection, the
/// culling knobs and the adapter's loop limit.
fn plan_view(
    scene: &Scene,
    settings: &Settings,
    records: &FrameRecords,
    (key, loop_limit): (&super::kit::pipeline::PipelineKey, Option<u64>),
    size: (u32, u32),
    costs: crate::renderer::options::calibration::CostConstants,
) -> PlanView {
    PlanView {
        proj: records.proj.as_mat4(),
        near: scene.camera.near as f32,
        far: scene.camera.far as f32,
        size,
        mode: settings.culling,
        depth_clamp: key.depth_clamp,
        forward_lights: settings.forward_lights,
        // Seed 004's log encoding rounds every blend to 8 bits, so its sum depends on the
        // order lights are blended in far more than fp16's: batching reorders them (up to 3
        // 8-bit steps on demo with stencil-two-pass), so those frames stay unbatched.
        light_batching: settings.light_batching && settings.accumulation != AccumFormat::Rgba8Log,
        cluster_build: settings.cluster_build,
        grid: crate::renderer::culling::tiled::GridChoice::of(&settings.culling_options(), settings.cap_order),
        object_cap: (settings.lights_per_object, settings.cap_order),
        loop_limit: loop_limit,
        near_fullscreen: settings.near_lights == NearLights::Fullscreen,
        front_to_back: settings.draw_order == DrawOrder::FrontToBack,
        sort_blended: settings.blended == BlendedMode::Alpha,
        prepass_models: (settings.path == RenderPath::LightPrepass).then(|| settings.brdf.brdf()),
        costs,
    }
}

/// Logs lists longer than the forward loops walk under `loop_limit` (lavapipe's; multi-pass
/// draws a pair a light) when they change (`last`: the warnings logged before), not at every
/// frame of the viewer.
fn warn_long_lists(
    loop_limit: Option<u64>,
    last: &mut Vec<String>,
    settings: &Settings,
    shape: &Shape,
    plan: &FramePlan,
    lists: &ForwardPathLists,
) {
    if loop_limit.is_none() {
        return;
    }
    let warnings = plan::long_forward_list_warnings(
        (settings.path == RenderPath::Forward).then_some(lists.longest_list),
        plan.forward.as_ref().filter(|_| shape.blended),
    );
    if warnings != *last {
        for w in &warnings {
            log::warn!("{w}");
        }
        *last = warnings;
    }
}

/// What a frame counts and times on the GPU.
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    /// Each light's shaded fragments (occlusion queries).
    pub counts: bool,
    /// The ideal fragments and the coverage (measurement passes).
    pub ideal: bool,
    /// Timestamps.
    pub times: bool,
    /// The forward pass's occlusion queries (0: not counted; peeled, one per layer and one
    /// behind the last).
    pub forward: u32,
}
