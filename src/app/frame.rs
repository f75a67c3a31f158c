//! One frame of the viewer, as named steps. [`App::frame`] reads top to bottom: input changes
//! the plain `UiState`; the frame's scene is built from it; the renderer draws the viewport and
//! the thumbnails; egui lays the panels out around them and is drawn into the window; then what
//! the panels and the script asked for is done. Each step's outputs are passed to the next.

use super::gfx::{self, Acquired, Image};
use super::script::{Action, SCRIPT_DT};
use super::state::{self, Wireframes};
use super::ui::{self, Command, Sample, Thumb, UiOut};
use super::{camera, App};
use crate::renderer::{volume_wireframe_with, DebugView, Settings};
use anyhow::{anyhow, bail, Result};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::KeyCode;

/// Per-light volume outlines in viewport pixels: (light, segments).
type Wires = Vec<(usize, Vec<[glam::Vec2; 2]>)>;

/// Side of a G-buffer thumbnail, in pixels.
const THUMB_WIDTH: u32 = 224;
/// Least and greatest side of the shadow-atlas image in pixels: the atlas's own side within
/// these (one pixel a texel up to 2048).
const ATLAS_IMAGE: (u32, u32) = (64, 2048);

impl App {
    pub(super) fn frame(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let dt = self.tick();
        self.waits = Default::default();
        self.drew = None;
        self.render_ms = 0.0;
        // 1. Script actions and keys change the state; actions that read the drawn frame wait.
        let (post, commands) = self.input(dt);
        // 2. The frame's scene and settings.
        self.update_scene();
        let settings = self.state.frame_settings();
        if self.gfx.is_none() {
            return Ok(());
        }
        // 3. The scene into the viewport texture, at the viewport's size times the scale; none
        //    while a calibration measures (the viewport holds its last frame). A configuration
        //    whose pipelines build in the background leaves the last one drawn meanwhile.
        let calibrating = self.timed_finish_calibration();
        self.start_capture();
        let drawn = if calibrating { None } else { self.render_viewport(&settings) };
        let rendered = drawn.is_some();
        let settings = drawn.unwrap_or(settings);
        // No thumbnails from the stand-in (they wait for the configuration itself).
        let rendered = rendered && !self.drew.as_ref().is_some_and(|d| d.1);
        // 4. Thumbnails: the compose pass of this frame again, once per view.
        let tiles = self.render_thumbnails(&settings, rendered);
        // 4a. Configuration B beside it, while the split view is on.
        self.render_split(&settings, rendered);
        // 4b. The shadow atlas as an image, while its panel is open.
        self.render_atlas(rendered);
        // 5. The pixel under the pointer, 6. the light-volume wireframes, memory now and then.
        let probing = Instant::now();
        self.update_probe(rendered);
        self.waits.readback_ms += probing.elapsed().as_secs_f64() * 1e3;
        let wires = self.wireframes();
        self.sample_memory();
        // 7. The panels, around the viewport texture.
        let (full, out) = self.run_panels(&tiles, &wires);
        // 8. egui into the window, after the scene; captured when a screenshot asks.
        let capture = post.iter().any(|a| matches!(a, Action::Screenshot(_)));
        let window_image = self.present(full, capture)?;
        self.end_capture();
        self.log_frame();
        // 9. What the panels and keys asked for.
        self.apply_commands(out, commands);
        // 10. Scripted screenshots, memory and quit, after the frame is drawn.
        self.after_frame(post, window_image, event_loop)?;
        self.frame += 1;
        Ok(())
    }

    /// The time step: fixed in scripted runs, the wall clock's (at most 0.1 s) otherwise.
    fn tick(&mut self) -> f64 {
        let now = Instant::now();
        let since = now.duration_since(self.last_instant).as_secs_f64();
        self.cpu_ms = since * 1000.0;
        self.last_instant = now;
        if self.scripted() {
            SCRIPT_DT
        } else {
            since.min(0.1)
        }
    }

    /// Applies this frame's script actions and keys. Returns the actions that run after drawing
    /// (screenshots, memory, quit) and the commands the keys gave.
    fn input(&mut self, dt: f64) -> (Vec<Action>, Vec<Command>) {
        let mut post = Vec::new();
        let actions = match &mut self.script {
            Some(s) => s.take(self.frame),
            None => Vec::new(),
        };
        for a in actions {
            if a.is_post() {
                post.push(a);
            } else {
                self.apply(a);
            }
        }
        let mut commands = Vec::new();
        let egui_keys = self.gfx.as_ref().is_some_and(|g| g.egui_ctx.egui_wants_keyboard_input());
        let replaying = self.path_step();
        if !egui_keys && !replaying {
            if let Some(mut cam) = self.camera() {
                let held = |k: KeyCode| self.held(k);
                if camera::apply_keys(&mut cam, &held, self.state.move_speed, dt) {
                    self.state.camera = Some(cam);
                }
            }
        }
        self.taps(&mut commands);
        self.record_step(dt);
        if self.state.animate {
            self.state.time += dt * self.state.time_speed;
        }
        // The views that average RIS's frames need a new seed each frame to average anything.
        if self.state.animate_noise || self.state.settings.debug_view.converges() {
            let s = &mut self.state.settings;
            s.noise_seed = s.noise_seed.wrapping_add(1) % u32::MAX;
        }
        (post, commands)
    }

    /// Builds the frame's scene from the state; reports a file that finished loading or failed.
    fn update_scene(&mut self) {
        let frame_scene = self.cache.frame_scene(&self.state);
        if let Some((file, e)) = self.cache.take_failure() {
            // Keep the scene the viewer had: its name goes back, the user's edits stay.
            let previous = self.cache.current().unwrap_or("demo").to_string();
            self.say(format!("cannot load {file}: {e} (keeping {previous})"), true);
            self.state.scene = previous;
        } else if let Some(file) = self.cache.take_loaded() {
            self.reset_scene_edits();
            let n = self.cache.warnings.len();
            let first = self.cache.warnings.first().cloned().unwrap_or_default();
            match n {
                0 => self.say(format!("loaded {file}"), false),
                1 => self.say(format!("loaded {file} with a warning: {first}"), false),
                _ => self.say(format!("loaded {file} with {n} warnings (hover for all): {first}"), false),
            }
        }
        match frame_scene {
            Ok(s) => self.scene = Some(s),
            Err(e) if self.cache.progress().is_some() => log::debug!("{e}"),
            Err(e) => self.say(format!("scene rejected, showing the last good one: {e}"), true),
        }
        if self.state.selected_light.is_some_and(|k| self.scene.as_ref().is_none_or(|s| k >= s.lights.len())) {
            self.state.selected_light = None;
        }
    }

    /// Renders the scene into the viewport texture: with `settings`, or while their pipelines
    /// build in the background, with the last settings drawn (`compiling`). A setting the
    /// adapter cannot do (an accumulation format, say) is rejected: back to the last settings
    /// that rendered, with the reason on the status line. Returns the settings a frame was
    /// rendered with, if one was.
    fn render_viewport(&mut self, settings: &Settings) -> Option<Settings> {
        let size = self.viewport_size()?;
        let (draw, stand_in) = self.settings_to_draw(settings, size)?;
        // The stand-in draws the scene without its lights (put back after).
        let lights = stand_in.then(|| self.scene.as_mut().map(|s| std::mem::take(&mut s.lights))).flatten();
        let rendered = self.render_viewport_with(&draw, size, stand_in);
        if let (Some(lights), Some(scene)) = (lights, self.scene.as_mut()) {
            scene.lights = lights;
        }
        rendered.then_some(draw)
    }

    /// The viewport's size in pixels (its rectangle times the scale), or `None` when there is
    /// nothing to draw into (no layout yet, or the window minimised).
    fn viewport_size(&mut self) -> Option<(u32, u32)> {
        let g = self.gfx.as_mut()?;
        let ppp = g.egui_ctx.pixels_per_point();
        let scale = self.state.resolution_scale.clamp(state::MIN_SCALE, state::MAX_SCALE);
        let size = self.viewport_rect.map(|r| {
            let s = scale * ppp;
            (((r.width() * s).round() as u32).clamp(1, 8192), ((r.height() * s).round() as u32).clamp(1, 8192))
        });
        // Before the panels are first laid out, the stand-in is drawn at the window's size, so
        // the window's first frame shows it (the next frame draws it at the viewport's).
        let size = size.or_else(|| {
            let w = g.surface.window.inner_size();
            let first = self.live_compiles && self.drawn.is_none() && g.compiler.is_some();
            let side = |n: u32| ((n as f32 * scale).round() as u32).clamp(1, 8192);
            first.then(|| (side(w.width), side(w.height)))
        });
        let minimised = g.surface.window.is_minimized().unwrap_or(false) || {
            let s = g.surface.window.inner_size();
            s.width == 0 || s.height == 0
        };
        if minimised {
            // Nothing to draw into: do not spin while the window is away.
            std::thread::sleep(std::time::Duration::from_millis(50));
            return None;
        }
        size
    }

    /// Renders `settings` into the viewport at `(w, h)`; whether a frame was rendered.
    fn render_viewport_with(&mut self, settings: &Settings, (w, h): (u32, u32), stand_in: bool) -> bool {
        let (Some(g), Some(scene)) = (self.gfx.as_mut(), &self.scene) else { return false };
        if g.viewport.resize(&g.gpu.device, &mut g.egui_renderer, w, h, wgpu::FilterMode::Linear) {
            self.have_image = false;
            if let Some(b) = g.egui_renderer.callback_resources.get::<super::blit::Blit>() {
                g.viewport_paint = Some(b.paint(&g.gpu.device, &g.viewport.shown_view));
            }
        }
        let rendering = Instant::now();
        let result = g.renderer.render(scene, settings, &g.viewport.target, w, h);
        self.render_ms = rendering.elapsed().as_secs_f64() * 1e3;
        match result {
            Ok(stats) => {
                self.waits.compile_ms += stats.pipelines.build_us as f64 / 1e3;
                self.drew = Some((super::compiling::config_name(settings), stand_in));
                if let Some((declared, now)) = g.renderer.last_compiles().filter(|_| stats.pipelines.built > 0) {
                    let name = super::compiling::config_name(settings);
                    let built = super::compiling::ConfigPipelines::of(name, "frame", declared, now);
                    super::compiling::remember(&mut self.pipelines, built);
                }
                if !stand_in {
                    self.drawn = Some((settings.clone(), scene.name.clone()));
                }
                g.viewport.publish(&g.gpu);
                self.history.push(Sample {
                    gpu_total: stats.gpu_ms.total,
                    lighting: stats.gpu_ms.lighting,
                    shaded: stats.shaded_fragments,
                    ideal: stats.ideal_fragments,
                });
                self.stats = Some(stats);
                if self.drawn.as_ref().is_some_and(|(s, _)| *s == self.state.frame_settings()) {
                    self.good_settings = Some(self.state.settings.clone());
                }
                self.have_image = true;
                true
            }
            Err(e) => {
                let text = match &self.good_settings {
                    Some(good) if *good != self.state.settings => {
                        self.state.settings = good.clone();
                        format!("rejected: {e:#}")
                    }
                    _ => format!("render failed: {e:#}"),
                };
                // Said once while it lasts, not at every frame.
                if self.status.as_ref().is_none_or(|s| s.text != text) {
                    self.say(text, true);
                }
                false
            }
        }
    }

    /// The G-buffer strip's tiles; when a frame was rendered, each tile's view composed again
    /// from it at thumbnail size.
    fn render_thumbnails(&mut self, settings: &Settings, rendered: bool) -> Vec<Thumb> {
        let Some(g) = self.gfx.as_mut() else { return Vec::new() };
        if !settings.path.keeps_gbuffer() {
            // No G-buffer to show (the strip says so).
            return Vec::new();
        }
        let accum = settings.accumulation.format(&g.gpu.caps).ok();
        let tiles = ui::thumbs(g.renderer.layout(), accum, g.renderer.depth_format());
        if rendered {
            let (vw, vh) = (g.viewport.width, g.viewport.height);
            let tw = THUMB_WIDTH;
            let th = ((tw as f32 * vh as f32 / vw.max(1) as f32).round() as u32).clamp(16, THUMB_WIDTH);
            for v in tiles.iter().map(|t| t.view) {
                let views = g.gpu.caps.has_downlevel(wgpu::DownlevelFlags::VIEW_FORMATS);
                let img = g.thumbs.entry(v).or_insert_with(|| {
                    let linear = wgpu::FilterMode::Linear;
                    Image::new(&g.gpu.device, &mut g.egui_renderer, "thumbnail", (tw, th), linear, views)
                });
                img.resize(&g.gpu.device, &mut g.egui_renderer, tw, th, wgpu::FilterMode::Linear);
                match g.renderer.last_frame().compose_view(v, &img.target, tw, th) {
                    Ok(()) => img.publish(&g.gpu),
                    Err(e) => log::warn!("thumbnail {v:?}: {e:#}"),
                }
            }
        }
        tiles
    }

    /// Redraws the shadow-atlas image from the frame just rendered, while the panel
    /// is open. The image is made (and registered with egui) once; a new atlas size resizes it
    /// in place under the same egui id.
    fn render_atlas(&mut self, rendered: bool) {
        let Some(g) = self.gfx.as_mut() else { return };
        if !self.state.panels.shadows || !rendered {
            return;
        }
        let (atlas_side, _) = g.renderer.last_frame().shadow_atlas_tiles();
        let side = atlas_side.clamp(ATLAS_IMAGE.0, ATLAS_IMAGE.1);
        let views = g.gpu.caps.has_downlevel(wgpu::DownlevelFlags::VIEW_FORMATS);
        let img = g.atlas.get_or_insert_with(|| {
            let nearest = wgpu::FilterMode::Nearest;
            Image::new(&g.gpu.device, &mut g.egui_renderer, "shadow atlas", (side, side), nearest, views)
        });
        img.resize(&g.gpu.device, &mut g.egui_renderer, side, side, wgpu::FilterMode::Nearest);
        g.atlas_range = match g.renderer.last_frame().draw_shadow_atlas(&g.gpu, &img.target, side) {
            Ok(r) => {
                img.publish(&g.gpu);
                r
            }
            Err(e) => {
                log::warn!("shadow atlas image: {e:#}");
                None
            }
        };
    }

    /// Reads the G-buffer and lights of the pixel under the pointer (kept while not rendering).
    fn update_probe(&mut self, rendered: bool) {
        let Some(g) = self.gfx.as_ref() else { return };
        self.probe = match (self.hover_pixel, rendered) {
            (Some([x, y]), true) if x < g.viewport.width && y < g.viewport.height => {
                g.renderer.last_frame().probe(&g.gpu, x, y).ok()
            }
            (Some(_), _) => self.probe.take(),
            (None, _) => None,
        };
    }

    /// The light-volume outlines the overlay draws: every light's (the largest on screen first,
    /// at most `ui::MAX_WIREFRAMES`), the selected light's, or none.
    fn wireframes(&self) -> Wires {
        let (Some(scene), Some(g)) = (&self.scene, &self.gfx) else { return Vec::new() };
        let (w, h) = (g.viewport.width, g.viewport.height);
        let outline = |i: usize| (i, volume_wireframe_with(scene, i, w, h, &self.state.settings));
        match self.state.wireframes {
            Wireframes::All => {
                let mut order: Vec<(usize, f32)> = match &self.stats {
                    Some(s) => {
                        s.per_light.iter().filter(|l| l.screen_share > 0.0).map(|l| (l.index, l.screen_share)).collect()
                    }
                    None => (0..scene.lights.len()).map(|i| (i, 1.0)).collect(),
                };
                order.sort_by(|a, b| b.1.total_cmp(&a.1));
                order.into_iter().take(ui::MAX_WIREFRAMES).map(|(i, _)| outline(i)).collect()
            }
            Wireframes::Selected => self.state.selected_light.map(|i| vec![outline(i)]).unwrap_or_default(),
            Wireframes::Off => Vec::new(),
        }
    }

    /// Every 30 frames: resident memory and wgpu's live buffer + texture bytes.
    fn sample_memory(&mut self) {
        let Some(g) = self.gfx.as_ref() else { return };
        if self.frame.is_multiple_of(30) {
            let hal = g.gpu.device.get_internal_counters().hal;
            let gpu_bytes = hal.buffer_memory.read() as i64 + hal.texture_memory.read() as i64;
            self.memory = crate::memory::resident_bytes().map(|r| (r, gpu_bytes));
        }
    }

    /// Lays out the panels (egui) from this frame's figures; they edit the state and return what
    /// only the application can do.
    fn run_panels(&mut self, tiles: &[Thumb], wires: &Wires) -> (egui::FullOutput, UiOut) {
        let compiling = self.compiling_note();
        let Some(g) = self.gfx.as_mut() else { return (Default::default(), UiOut::default()) };
        let mut raw = g.egui_state.take_egui_input(&g.surface.window);
        raw.events.append(&mut self.injected);
        self.injected = std::mem::take(&mut self.injected_next);
        let thumb_ids: HashMap<DebugView, egui::TextureId> = g.thumbs.iter().map(|(v, i)| (*v, i.id)).collect();
        let layout = g.renderer.layout();
        let (atlas_side, atlas_tiles) = g.renderer.last_frame().shadow_atlas_tiles();
        let atlas = self.state.panels.shadows.then(|| ui::AtlasInfo {
            image: g.atlas.as_ref().map(|i| i.id),
            side: atlas_side,
            format: g.renderer.last_frame().shadow_plan().stats.format.texture(),
            tiles: &atlas_tiles,
            range: g.atlas_range,
        });
        let atlas_default_pos = self.viewport_rect.map_or(egui::pos2(300.0, 60.0), |r| r.min + egui::vec2(8.0, 24.0));
        let info = ui::FrameInfo {
            stats: self.stats.as_ref(),
            history: &self.history,
            scene: self.scene.as_ref(),
            viewport: self.have_image.then_some((g.viewport.id, [g.viewport.width, g.viewport.height])),
            viewport_paint: g.viewport_paint.clone(),
            thumbs: &thumb_ids,
            tiles,
            depth_format: format!("{:?}", g.renderer.depth_format()),
            gbuffer_bytes: layout.bytes_per_pixel(),
            probe: self.probe.as_ref(),
            explanation: self.explanation.as_ref(),
            check: self.check.as_ref(),
            advice: self.advice.as_ref(),
            calibration: g.renderer.calibration().describe(),
            offer_calibration: self.offer_calibration,
            adapter: &g.adapter,
            caps: &g.gpu.caps,
            status: self.status.as_ref(),
            warnings: &self.cache.warnings,
            cpu_ms: self.cpu_ms,
            scripted: self.script.is_some(),
            wireframes: wires,
            scroll_to_light: self.scroll_to_light.take(),
            loading: self.cache.progress(),
            memory: self.memory,
            atlas,
            atlas_default_pos,
            compiling,
            pipelines: &self.pipelines,
            split: g.split.as_ref().filter(|_| self.state.split.on).map(|s| ui::SplitInfo {
                b: s.stats.is_some().then_some(s.image.id),
                overlay: s.overlay.as_ref().map(|t| t.id()),
                figures: &s.figures,
            }),
        };
        let mut out = UiOut::default();
        let state = &mut self.state;
        let mut full = g.egui_ctx.run_ui(raw, |ui| ui::draw(ui, state, &info, &mut out));
        g.egui_state.handle_platform_output(&g.surface.window, std::mem::take(&mut full.platform_output));
        if out.viewport_rect.is_some() {
            self.viewport_rect = out.viewport_rect;
        }
        self.hover_pixel = out.hover_pixel;
        self.atlas_rect = out.atlas_rect;
        self.regions = std::mem::take(&mut out.regions);
        (full, out)
    }

    /// Draws egui into the window (the viewport texture inside it) and presents; returns the
    /// window's pixels when `capture` asks (a scripted screenshot), `None` if nothing was drawn.
    fn present(&mut self, mut full: egui::FullOutput, capture: bool) -> Result<Option<Result<image::RgbaImage>>> {
        let g = self.gfx.as_mut().ok_or_else(|| anyhow!("no window"))?;
        let mut window_image = None;
        let mut ui_error = None;
        // egui assumes every delta is applied, whether or not this frame reaches the window.
        for (id, deltas) in full.textures_delta.set.drain() {
            for d in &deltas {
                g.egui_renderer.update_texture(&g.gpu.device, &g.gpu.queue, id, d);
            }
        }
        let freed: Vec<egui::TextureId> = full.textures_delta.free.drain().collect();
        let jobs = g.egui_ctx.tessellate(full.shapes, full.pixels_per_point);
        if let Acquired::Frame(frame) = g.surface.acquire(&g.gpu)? {
            let size = frame.texture.size();
            let screen = egui_wgpu::ScreenDescriptor {
                size_in_pixels: [size.width, size.height],
                pixels_per_point: full.pixels_per_point,
            };
            let mut encoder =
                g.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("egui") });
            let user = g.egui_renderer.update_buffers(&g.gpu.device, &g.gpu.queue, &mut encoder, &jobs, &screen);
            {
                let view = frame.texture.create_view(&Default::default());
                let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color { r: 0.05, g: 0.05, b: 0.05, a: 1.0 }),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                g.egui_renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
            }
            g.gpu.queue.submit(user.into_iter().chain([encoder.finish()]));
            // The window's own wgpu errors (egui, the images it shows): said on the status line.
            ui_error = g.gpu.errors.check().err();
            if capture && g.surface.can_capture {
                let reading = Instant::now();
                window_image = Some(g.surface.capture(&g.gpu, &frame));
                self.waits.readback_ms += reading.elapsed().as_secs_f64() * 1e3;
            }
            g.surface.window.pre_present_notify();
            g.gpu.queue.present(frame);
        }
        for id in &freed {
            g.egui_renderer.free_texture(id);
        }
        if let Some(e) = ui_error {
            self.say(format!("the window: {e:#}"), true);
        }
        Ok(window_image)
    }

    /// Does what the panels and keys asked for: screenshots, camera reset, scene change, status,
    /// picking a light, looking around.
    fn apply_commands(&mut self, out: UiOut, commands: Vec<Command>) {
        for c in out.commands.into_iter().chain(commands) {
            match c {
                Command::Screenshot => {
                    self.screenshots += 1;
                    let stamp = std::time::SystemTime::now()
                        .duration_since(std::time::UNIX_EPOCH)
                        .map(|d| d.as_secs())
                        .unwrap_or(0);
                    let png = self.args.screenshot_dir.join(format!("lampshade-{stamp}-{}.png", self.screenshots));
                    match self.save_viewport(&png) {
                        Ok(json) => self.say(format!("saved {} and {}", png.display(), json.display()), false),
                        Err(e) => self.say(format!("screenshot failed: {e:#}"), true),
                    }
                }
                Command::ResetCamera => self.state.camera = None,
                Command::CheckCulling => self.check_culling(),
                Command::Advise => self.start_advice(),
                Command::Calibrate => self.start_calibration(Default::default()),
                Command::DeclineCalibration => {
                    self.offer_calibration = false;
                    self.calibration_answered = true;
                }
                Command::SceneChanged => {
                    if !crate::scene::import::is_gltf_path(&self.state.scene) {
                        self.reset_scene_edits();
                    }
                }
                Command::Status(s) => self.say(s.text, s.error),
            }
        }
        if let Some(px) = out.click_pixel {
            self.pick(px);
        }
        if out.drag != egui::Vec2::ZERO {
            if let Some(mut cam) = self.camera() {
                camera::look(&mut cam, out.drag.x as f64 * camera::DRAG_SPEED, -out.drag.y as f64 * camera::DRAG_SPEED);
                self.state.camera = Some(cam);
            }
        }
    }

    /// The script's actions that read the drawn frame: screenshots (window and viewport),
    /// memory, quit.
    fn after_frame(
        &mut self,
        post: Vec<Action>,
        mut window_image: Option<Result<image::RgbaImage>>,
        event_loop: &ActiveEventLoop,
    ) -> Result<()> {
        for a in post {
            match a {
                Action::Screenshot(path) => {
                    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("screenshot");
                    let vp: PathBuf = path.with_file_name(format!("{stem}-viewport.png"));
                    if self.gfx.as_ref().is_some_and(|g| !g.surface.can_capture) {
                        // wgpu's GL backend: the window's texture cannot be copied from.
                        self.save_viewport(&vp)?;
                        println!(
                            "frame {}: this window cannot be read back (its surface lacks COPY_SRC); saved the viewport only: {}",
                            self.frame,
                            vp.display()
                        );
                        continue;
                    }
                    let img = window_image
                        .take()
                        .ok_or_else(|| anyhow!("frame {}: the window was not drawn (minimised?)", self.frame))??;
                    gfx::save_png(&img, &path)?;
                    self.save_viewport(&vp)?;
                    println!("frame {}: screenshot {} and {}", self.frame, path.display(), vp.display());
                }
                Action::Pipelines(path) => {
                    self.write_pipelines(&path)?;
                    println!(
                        "frame {}: pipelines {} ({} configurations)",
                        self.frame,
                        path.display(),
                        self.pipelines.len()
                    );
                }
                Action::Memory => {
                    match crate::memory::resident_bytes() {
                        Some(b) => println!("frame {}: resident {b} bytes", self.frame),
                        None => println!("frame {}: resident memory unavailable on this system", self.frame),
                    }
                    let compiled = crate::renderer::kit::pipelines_compiled();
                    println!("frame {}: pipelines compiled {compiled}", self.frame);
                }
                Action::Overlaps => {
                    let found = ui::overlaps(&self.regions);
                    if !found.is_empty() {
                        let all: Vec<String> =
                            self.regions.iter().map(|r| format!("{} {:?}", r.name, r.rect)).collect();
                        bail!(
                            "frame {}: the window's regions overlap:\n{}\n(regions: {})",
                            self.frame,
                            found.join("\n"),
                            all.join(", ")
                        );
                    }
                    let names: Vec<String> = self.regions.iter().map(|r| format!("{} {:?}", r.name, r.rect)).collect();
                    println!("frame {}: no overlapping regions ({})", self.frame, names.join(", "));
                }
                Action::Check => {
                    self.check_culling();
                    match &self.check {
                        Some(Ok(c)) => {
                            let failing: Vec<String> = c
                                .rows
                                .iter()
                                .filter(|r| r.failed())
                                .map(|r| format!("{}/{} ({} missed, {} extra)", r.path, r.mode, r.missed, r.extra))
                                .collect();
                            println!(
                                "frame {}: culling check at {}x{}: {} frames, {} miss or add light{}{}",
                                self.frame,
                                c.size[0],
                                c.size[1],
                                c.rows.len(),
                                failing.len(),
                                if failing.is_empty() { "" } else { ": " },
                                failing.join(", ")
                            );
                        }
                        Some(Err(e)) => bail!("frame {}: the culling check failed: {e}", self.frame),
                        None => bail!("frame {}: no scene to check", self.frame),
                    }
                }
                Action::Advise => {
                    self.start_advice();
                    let Some(job) = self.advice.as_mut() else { bail!("frame {}: no scene to advise on", self.frame) };
                    job.wait();
                    match job.answer() {
                        Some(Ok(a)) => println!("frame {}: {}", self.frame, super::advice::summary(&a)),
                        Some(Err(e)) => bail!("frame {}: the advisor failed: {e}", self.frame),
                        None => bail!("frame {}: the advisor gave no answer", self.frame),
                    }
                }
                Action::Calibrate => {
                    let small = crate::bench::calibrate::CalibrateOptions {
                        size: (96, 54),
                        counts: vec![256, 512],
                        frames: 1,
                        ..Default::default()
                    };
                    self.start_calibration(small);
                    if let Some(job) = self.calibrating.as_mut() {
                        job.wait();
                    }
                    if let Some(Err(e)) = self.calibrating.as_ref().and_then(|j| j.answer()) {
                        bail!("frame {}: the calibration failed: {e}", self.frame);
                    }
                    self.finish_calibration();
                }
                Action::Quit => event_loop.exit(),
                _ => {}
            }
        }
        Ok(())
    }
}
