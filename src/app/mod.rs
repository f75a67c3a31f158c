//! The winit + egui viewer: the lit image in the central viewport, panels around it.
//!
//! A frame reads top to bottom in [`App::frame`]: script actions and keys change the plain
//! [`state::UiState`]; the scene for the frame is built from it; the renderer draws into the
//! viewport texture (and the thumbnails from the same frame); then egui lays out the panels around
//! that texture and is drawn into the window after the scene, in the same frame. Panel edits
//! reach the renderer on the next frame.

mod advice;
mod blit;
mod calibrating;
pub mod camera;
pub mod compiling;
mod frame;
mod frame_log;
pub mod gfx;
pub mod loading;
pub mod persist;
pub mod pipeline_rows;
mod replay;
pub mod script;
pub mod split;
mod split_step;
pub mod state;
pub mod ui;

use crate::renderer::{DebugView, FrameStats, PixelProbe, Renderer, OUTPUT_FORMAT};
use crate::scene::Scene;
use crate::Gpu;
use anyhow::{anyhow, Context, Result};
use gfx::{Image, Surface};
use loading::SceneCache;
use script::{Action, Script};
use state::UiState;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;
use ui::{Command, History, Status};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

pub use crate::cli::ViewArgs;

/// Opens the viewer. Everything a user controls is checked before the window opens: the scene
/// name, the light count, the script.
pub fn run(args: ViewArgs) -> Result<()> {
    let started = Instant::now();
    // The saved state, unless this run asks for none (scripted runs are reproducible: they
    // use a state file only when told which).
    let state_path = match (&args.state, args.no_state || args.script.is_some()) {
        (Some(p), _) => Some(p.clone()),
        (None, true) => None,
        (None, false) => persist::default_path(),
    };
    let (saved, state_warning) = match &state_path {
        Some(p) => persist::load(p),
        None => (persist::Persisted::default(), None),
    };
    if let Some(w) = &state_warning {
        eprintln!("warning: {w}");
    }
    let scale = args.scale.unwrap_or(saved.resolution_scale);
    if !(state::MIN_SCALE..=state::MAX_SCALE).contains(&scale) || !scale.is_finite() {
        anyhow::bail!("--scale {scale} must lie in [{}, {}]", state::MIN_SCALE, state::MAX_SCALE);
    }
    let mut scene = args.scene.clone().unwrap_or_else(|| saved.scene.clone());
    let mut scene_warning = None;
    if args.scene.is_none() && crate::scene::import::is_gltf_path(&scene) && !std::path::Path::new(&scene).is_file() {
        // The last file is gone: say so and start on the demo instead of failing.
        scene_warning = Some(format!("the last file {scene} is no longer there; showing demo"));
        scene = "demo".into();
    }
    let mut state = UiState {
        scene: scene.clone(),
        lights: crate::cli::requested_lights(args.lights, args.light_grid),
        resolution_scale: scale,
        panels: saved.panels,
        ..UiState::default()
    };
    if state_path.is_some() {
        state.settings.culling = saved.culling;
        state.settings.layout = saved.layout;
    }
    if let Some(e) = args.exposure {
        state.settings.set("exposure", &e.to_string()).map_err(|e| anyhow::anyhow!("--exposure: {e}"))?;
    }
    let size = args.size.unwrap_or((saved.window[0], saved.window[1]));
    let mut cache = SceneCache::default();
    if let Some(n) = crate::cli::requested_lights(args.lights, args.light_grid) {
        cache.import_options.lights = n;
    }
    if crate::scene::import::is_gltf_path(&scene) {
        // The first file loads before the window opens, with a progress bar on the terminal;
        // a bad file is an error and a non-zero exit, as in `render`.
        let bar = indicatif::ProgressBar::new(0);
        let imported = crate::scene::import::load(std::path::Path::new(&scene), &cache.import_options, &mut |p| {
            bar.set_message(p.stage.to_string());
            bar.set_length(p.total as u64);
            bar.set_position(p.done as u64);
        });
        bar.finish_and_clear();
        let mut imported = imported?;
        let requested = crate::cli::requested_lights(args.lights, args.light_grid);
        imported.warnings.extend(crate::scene::unused_light_count(&scene, requested, imported.stats.lights_from_file));
        for w in &imported.warnings {
            eprintln!("warning: {scene}: {w}");
        }
        cache.insert_loaded(&scene, imported.scene, imported.warnings);
    } else if let Some(w) =
        crate::scene::unused_light_count(&scene, crate::cli::requested_lights(args.lights, args.light_grid), 0)
    {
        // Printed with the other start-up warning below, and shown on the status line.
        scene_warning = Some(format!("{scene}: {w}"));
    }
    cache.frame_scene(&state).map_err(anyhow::Error::msg)?;
    let script = args.script.as_deref().map(Script::load).transpose()?;
    let camera_path = match &args.camera_path {
        Some(f) => Some((crate::scene::camera_path::CameraPath::load(f)?, f.clone())),
        None => None,
    };

    // Scripted runs load files on the spot, so that what follows sees the new scene.
    cache.blocking = script.is_some();
    if script.is_some() {
        // Scripted runs are deterministic: the lights hold still unless the script animates them.
        state.animate = false;
    }
    let event_loop = EventLoop::new().context("cannot open a window (is DISPLAY or WAYLAND_DISPLAY set?)")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    if let Some(w) = &scene_warning {
        eprintln!("warning: {w}");
    }
    let frame_log = args.frame_log.as_deref().map(frame_log::FrameLog::create).transpose()?;
    let live = compiling::live_from_start(script.as_ref());
    let mut app = App::new(args, state, cache, script);
    app.frame_log = frame_log;
    app.started = started;
    app.live_compiles = live;
    if let Some((path, file)) = camera_path {
        app.start_replay(path, Some(file));
    }
    app.size = size;
    app.calibration_answered = saved.calibration_answered;
    app.status = state_warning.or(scene_warning).map(|text| Status { text, error: true });
    event_loop.run_app(&mut app).context("the event loop failed")?;
    app.save_pipeline_cache();
    if let Some(p) = &state_path {
        let saved = persist::Persisted {
            window: [app.size.0, app.size.1],
            panels: app.state.panels,
            resolution_scale: app.state.resolution_scale,
            culling: app.state.settings.culling,
            layout: app.state.settings.layout,
            scene: app.state.scene.clone(),
            calibration_answered: app.calibration_answered,
        };
        if let Err(e) = persist::save(p, &saved) {
            eprintln!("warning: could not save the viewer's state: {e:#}");
        }
    }
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Everything that needs the window and the device.
/// The viewer's pass pool budget (`kit::pool`): its one renderer keeps its recent
/// configurations itself, so the pool keeps about as much again (a few pass sets on lavapipe).
const VIEWER_POOL_BYTES: u64 = 256 << 20;

struct Gfx {
    surface: Surface,
    gpu: Gpu,
    renderer: Renderer,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    viewport: Image,
    /// The viewport image's own draw into the window (`None`: egui draws it as an image).
    viewport_paint: Option<blit::Paint>,
    /// Asks whether a configuration's pipelines are compiled, for the viewport's renderer
    /// (`compiling`); it draws nothing.
    planner: Renderer,
    /// Builds a configuration's pipelines in the background (`None`: it could not start; the
    /// viewport then compiles what it draws itself).
    compiler: Option<compiling::Compiler>,
    thumbs: HashMap<DebugView, Image>,
    /// The shadow-atlas panel's image (registered with egui once, redrawn in place
    /// while the panel is open) and the depth range it was stretched over.
    atlas: Option<Image>,
    atlas_range: Option<(f32, f32)>,
    adapter: String,
    /// Configuration B's renderer and images while the split view is on.
    split: Option<split::SplitGfx>,
}

/// Keys, held and tapped, from the keyboard and from the script.
#[derive(Default)]
struct Keys {
    down: HashSet<KeyCode>,
    /// Scripted holds: key -> last frame it is held.
    holds: HashMap<KeyCode, u64>,
    /// Pressed this frame (edges).
    taps: Vec<KeyCode>,
}

struct App {
    args: ViewArgs,
    state: UiState,
    cache: SceneCache,
    script: Option<Script>,
    frame: u64,
    gfx: Option<Gfx>,
    error: Option<anyhow::Error>,
    keys: Keys,
    /// Events to hand egui next frame (scripted pointer input).
    injected: Vec<egui::Event>,
    /// Injected after `injected` (a scripted click's release).
    injected_next: Vec<egui::Event>,
    stats: Option<FrameStats>,
    history: History,
    status: Option<Status>,
    probe: Option<PixelProbe>,
    /// Why each light lit the last clicked pixel (`Last::explain`), or why it cannot say.
    explanation: Option<Result<crate::renderer::explain::Explanation, String>>,
    /// The last culling check (`oracle`), or why it could not run.
    check: Option<Result<ui::CullingCheck, String>>,
    /// The renderer the culling check draws with (its frames are not the viewport's).
    check_renderer: Option<crate::renderer::Renderer>,
    /// The advisor, running on its own thread or finished.
    advice: Option<advice::AdviceJob>,
    /// A calibration running on its own thread; the viewport holds its last frame meanwhile.
    calibrating: Option<calibrating::CalibrationJob>,
    /// The offer to calibrate is shown (the cache has none for this adapter, and the saved
    /// state has no answer yet).
    offer_calibration: bool,
    /// The offer was answered (either way): saved, so it is made once.
    calibration_answered: bool,
    scene: Option<Scene>,
    /// From the last frame's layout.
    viewport_rect: Option<egui::Rect>,
    hover_pixel: Option<[u32; 2]>,
    last_instant: Instant,
    /// The last settings that rendered.
    good_settings: Option<crate::renderer::Settings>,
    /// The viewport texture holds a rendered frame.
    have_image: bool,
    /// The light list scrolls to this light next frame.
    scroll_to_light: Option<usize>,
    cpu_ms: f64,
    screenshots: u32,
    /// The window's size in logical pixels (saved on exit).
    size: (u32, u32),
    /// Resident memory and wgpu's buffer + texture bytes, sampled every 30 frames.
    memory: Option<(u64, i64)>,
    /// The shadow-atlas image's rectangle in points, from the last frame's layout (panel open).
    atlas_rect: Option<egui::Rect>,
    /// Where each part of the window drew in the last frame (`ui::overlaps`).
    regions: Vec<ui::Region>,
    /// The settings and scene the viewport drew last.
    drawn: Option<(crate::renderer::Settings, String)>,
    /// A configuration whose background build failed: drawn directly (its frame says why).
    failed: Option<crate::renderer::Settings>,
    /// A new configuration builds in the background while the viewport draws the last one
    /// (scripted runs draw each change at once, compiling it, unless `compiles live`).
    live_compiles: bool,
    /// The worker has been asked to make its renderers (`Compiler::prime`).
    primed: bool,
    /// Each configuration's pipelines, built in the background or by a frame (the pipelines
    /// panel), most recent last.
    pipelines: Vec<compiling::ConfigPipelines>,
    /// This frame's waits on the viewer's thread (the frame log).
    waits: frame_log::Waits,
    /// This frame's viewport: the configuration drawn, and whether it is the stand-in.
    drew: Option<(String, bool)>,
    frame_log: Option<frame_log::FrameLog>,
    /// Milliseconds from the start to the window, device and renderers made (the first
    /// frame log line says it).
    init_ms: Option<f64>,
    /// Milliseconds this frame spent in the viewport's `Renderer::render`.
    render_ms: f64,
    /// When the viewer started and when it last presented (the frame log's times).
    started: Instant,
    last_present: Instant,
    /// A camera path being recorded (F9), replayed (F10), and the last one recorded or given.
    recorder: Option<crate::scene::camera_path::Recorder>,
    replay: Option<crate::scene::camera_path::Replay>,
    last_path: Option<(crate::scene::camera_path::CameraPath, Option<PathBuf>)>,
    /// F11 asked RenderDoc for the next frame; a capture is open during this frame.
    capture_next: bool,
    capturing: bool,
}

impl App {
    fn new(args: ViewArgs, state: UiState, cache: SceneCache, script: Option<Script>) -> Self {
        Self {
            args,
            state,
            cache,
            script,
            frame: 0,
            gfx: None,
            error: None,
            keys: Keys::default(),
            injected: Vec::new(),
            injected_next: Vec::new(),
            stats: None,
            history: History::default(),
            status: None,
            probe: None,
            explanation: None,
            check: None,
            check_renderer: None,
            advice: None,
            calibrating: None,
            offer_calibration: false,
            calibration_answered: false,
            scene: None,
            viewport_rect: None,
            hover_pixel: None,
            last_instant: Instant::now(),
            good_settings: None,
            have_image: false,
            scroll_to_light: None,
            cpu_ms: 0.0,
            screenshots: 0,
            size: (1280, 720),
            memory: None,
            atlas_rect: None,
            regions: Vec::new(),
            drawn: None,
            failed: None,
            live_compiles: false,
            primed: false,
            pipelines: Vec::new(),
            waits: Default::default(),
            drew: None,
            frame_log: None,
            init_ms: None,
            render_ms: 0.0,
            started: Instant::now(),
            last_present: Instant::now(),
            recorder: None,
            replay: None,
            last_path: None,
            capture_next: false,
            capturing: false,
        }
    }

    fn scripted(&self) -> bool {
        self.script.is_some()
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        event_loop.exit();
    }

    fn say(&mut self, text: impl Into<String>, error: bool) {
        let text = text.into();
        if error {
            log::warn!("{text}");
            if self.scripted() {
                eprintln!("frame {}: {text}", self.frame);
            }
        }
        self.status = Some(Status { text, error });
    }

    fn init(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let (w, h) = self.size;
        let attrs = Window::default_attributes()
            .with_title(format!("Lampshade — {}", self.state.scene))
            .with_inner_size(winit::dpi::LogicalSize::new(w, h));
        let window = Arc::new(event_loop.create_window(attrs).context("creating the window")?);
        let instance =
            Gpu::instance_for_window(&self.args.adapter.choice(), Box::new(event_loop.owned_display_handle()));
        let surface = instance.create_surface(window.clone()).context("creating the window surface")?;
        let gpu = Gpu::for_surface(instance, &surface, &self.args.adapter.choice())?;
        // One renderer draws the viewer's frames: it keeps its recent configurations itself.
        gpu.passes.keep_bytes_at_most(VIEWER_POOL_BYTES);
        // The pipelines compiled in earlier runs on this adapter, where it keeps them.
        match crate::pipeline_cache::load(&gpu) {
            Ok(Some((path, bytes))) => log::info!("pipeline cache {}: {bytes} bytes", path.display()),
            Ok(None) => {}
            Err(e) => self.say(format!("{e:#}; compiling without the pipeline cache"), true),
        }
        let surface = Surface::new(&gpu, window.clone(), surface, !self.scripted())?;
        let settings = self.state.frame_settings();
        let mut renderer = Renderer::new(&gpu, OUTPUT_FORMAT, &settings)?;
        let planner = Renderer::new(&gpu, OUTPUT_FORMAT, &settings)?;
        // The cache's calibration for this adapter (or the file asked for); a file asked for
        // that cannot be read is said on the status line, and the defaults are used.
        match crate::calibration::resolve(&gpu.info, self.args.calibration.calibration.as_deref()) {
            Ok(c) => renderer.set_calibration(c),
            Err(e) => self.say(format!("{e:#}; using the built-in defaults"), true),
        }
        let warm = gpu.caps.quirks.jit_on_first_draw.then(|| self.args.adapter.choice());
        let mut compiler = match compiling::Compiler::start(&gpu, warm) {
            Ok(c) => Some(c),
            Err(e) => {
                log::warn!("no background compiles: {e:#}");
                None
            }
        };
        // With live compiles the first frame is the stand-in: the first configuration starts
        // building now, while the window's first frame lays the panels out.
        if let (Some(c), true, Ok(scene)) = (compiler.as_mut(), self.live_compiles, self.cache.frame_scene(&self.state))
        {
            let size = window.inner_size();
            c.request(&scene, &settings, (size.width.max(1) / 2, size.height.max(1) / 2), None, renderer.calibration());
        }
        self.offer_calibration = !self.calibration_answered && !self.scripted() && renderer.calibration().is_builtin();
        let egui_ctx = egui::Context::default();
        ui::style(&egui_ctx);
        let max_side = gpu.device.limits().max_texture_dimension_2d as usize;
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(max_side),
        );
        let mut egui_renderer =
            egui_wgpu::Renderer::new(&gpu.device, surface.format(), egui_wgpu::RendererOptions::default());
        let views = gpu.caps.has_downlevel(wgpu::DownlevelFlags::VIEW_FORMATS);
        let viewport =
            Image::new(&gpu.device, &mut egui_renderer, "viewport", (64, 36), wgpu::FilterMode::Linear, views);
        let viewport_paint = blit::Blit::new(&gpu.device, surface.format()).map(|b| {
            let paint = b.paint(&gpu.device, &viewport.shown_view);
            egui_renderer.callback_resources.insert(b);
            paint
        });
        let adapter = format!("{} ({:?})", gpu.info.name, gpu.info.backend);
        self.gfx = Some(Gfx {
            surface,
            gpu,
            renderer,
            egui_ctx,
            egui_state,
            egui_renderer,
            viewport,
            viewport_paint,
            planner,
            compiler,
            thumbs: HashMap::new(),
            atlas: None,
            atlas_range: None,
            adapter,
            split: None,
        });
        Ok(())
    }

    fn held(&self, k: KeyCode) -> bool {
        self.keys.down.contains(&k)
            || self.keys.holds.get(&k).is_some_and(|last| *last >= self.frame)
            || self.keys.taps.contains(&k)
    }

    /// Applies one scripted action that runs before drawing. Rejections are reported, not fatal.
    fn apply(&mut self, action: Action) {
        let frame = self.frame;
        let st = &mut self.state;
        match action {
            Action::Key(k) => self.keys.taps.push(k),
            Action::Hold(k, n) => {
                self.keys.taps.push(k);
                self.keys.holds.insert(k, frame.saturating_add(n - 1));
            }
            Action::Scene(name) => {
                let file = crate::scene::import::is_gltf_path(&name);
                st.scene = name;
                // A file's edits are reset once it has loaded (a failed load keeps them).
                if !file {
                    self.reset_scene_edits();
                }
            }
            Action::Culling(m) => st.settings.culling = m,
            Action::View(v) => st.settings.debug_view = v,
            Action::Layout(l) => st.settings.layout = l,
            Action::Select(k) => {
                let n = self.scene.as_ref().map_or(0, |s| s.lights.len());
                match k {
                    Some(k) if k >= n => self.say(format!("select {k}: the scene has {n} lights"), true),
                    _ => st.selected_light = k,
                }
            }
            Action::Scope(s) => st.scope = s,
            Action::Wireframes(w) => st.wireframes = w,
            Action::WireColour(c) => st.wire_colour = c,
            Action::Tab(t) => st.tab = t,
            Action::Set(name, value) => {
                let scene = match &self.scene {
                    Some(s) => s.clone(),
                    None => match self.cache.frame_scene(st) {
                        Ok(s) => s,
                        Err(e) => return self.say(e, true),
                    },
                };
                match self.state.set(&name, &value, &scene) {
                    Ok(msg) => self.say(msg, false),
                    Err(e) => self.say(format!("rejected: {e}"), true),
                }
            }
            Action::Hover(u, v) | Action::Click(u, v) | Action::AtlasHover(u, v) | Action::AtlasClick(u, v) => {
                let atlas = matches!(action, Action::AtlasHover(..) | Action::AtlasClick(..));
                let rect = if atlas { self.atlas_rect } else { self.viewport_rect };
                let Some(r) = rect else {
                    let what = if atlas {
                        "atlas-hover/atlas-click before the shadow-atlas panel was laid out (set panel-shadows on)"
                    } else {
                        "hover/click before the viewport was laid out"
                    };
                    return self.say(what, true);
                };
                let pos = r.min + egui::vec2(u * r.width(), v * r.height());
                self.injected.push(egui::Event::PointerMoved(pos));
                if matches!(action, Action::Click(..) | Action::AtlasClick(..)) {
                    let button = |pressed| egui::Event::PointerButton {
                        pos,
                        button: egui::PointerButton::Primary,
                        pressed,
                        modifiers: egui::Modifiers::NONE,
                    };
                    self.injected.push(button(true));
                    self.injected_next.push(button(false));
                }
            }
            Action::Leave => self.injected.push(egui::Event::PointerGone),
            Action::Resize(w, h) => {
                if let Some(g) = &self.gfx {
                    let _ = g.surface.window.request_inner_size(winit::dpi::LogicalSize::new(w, h));
                }
            }
            Action::Minimize => {
                if let Some(g) = &self.gfx {
                    g.surface.window.set_minimized(true);
                }
            }
            Action::Restore => {
                if let Some(g) = &self.gfx {
                    g.surface.window.set_minimized(false);
                    g.surface.window.focus_window();
                }
            }
            Action::CompareSet(name, value) => {
                let a = self.state.frame_settings();
                match self.state.split.set(&a, &name, &value) {
                    Ok(()) => self.say(format!("B: {name} = {value}"), false),
                    Err(e) => self.say(format!("rejected: {e}"), true),
                }
            }
            Action::CompareFile(path) => {
                let a = self.state.frame_settings();
                match self.state.split.load(&a, &path) {
                    Ok(n) => self.say(format!("B: {n} knob(s) from {}", path.display()), false),
                    Err(e) => self.say(format!("rejected: {e}"), true),
                }
            }
            Action::Replay(path) => match crate::scene::camera_path::CameraPath::load(&path) {
                Ok(p) => self.start_replay(p, Some(path)),
                Err(e) => self.say(format!("{e:#}"), true),
            },
            Action::Compiles(_) | Action::CompileDelay(_) | Action::WaitCompiles | Action::FrameLog(_) => {
                self.apply_compile_action(action)
            }
            Action::Screenshot(_)
            | Action::Memory
            | Action::Overlaps
            | Action::Check
            | Action::Advise
            | Action::Calibrate
            | Action::Pipelines(_)
            | Action::Quit => {}
        }
    }

    /// Keys that act once per press.
    fn taps(&mut self, commands: &mut Vec<Command>) {
        for k in std::mem::take(&mut self.keys.taps) {
            match k {
                KeyCode::Space => {
                    self.state.animate = !self.state.animate;
                    let s = if self.state.animate { "animating" } else { "paused" };
                    self.say(s, false);
                }
                KeyCode::F12 => commands.push(Command::Screenshot),
                KeyCode::F9 => self.toggle_recording(),
                KeyCode::F10 => self.toggle_replay(),
                KeyCode::F11 => self.ask_capture(),
                KeyCode::F1 => {
                    self.state.tab =
                        if self.state.tab == state::Tab::Help { state::Tab::Scene } else { state::Tab::Help };
                }
                _ => {}
            }
        }
    }

    /// The camera the frame starts from: the user's, or the scene's own.
    fn camera(&mut self) -> Option<crate::scene::Camera> {
        if let Some(c) = self.state.camera {
            return Some(c);
        }
        self.cache.base(&self.state).ok().map(|s| s.camera)
    }

    /// Screen position (viewport pixels) of a light's centre, if in front of the camera.
    fn project(scene: &Scene, p: glam::DVec3, w: u32, h: u32) -> Option<glam::Vec2> {
        let v = scene.camera.to_view(p);
        if -v.z <= scene.camera.near {
            return None;
        }
        let c = scene.camera.projection(w as f64 / h as f64, false) * v.extend(1.0);
        let n = c.truncate().truncate() / c.w;
        Some(glam::Vec2::new(((n.x * 0.5 + 0.5) * w as f64) as f32, ((0.5 - n.y * 0.5) * h as f64) as f32))
    }

    /// Selects the light whose centre is nearest the click (within a few pixels), else the
    /// smallest light touching the clicked point, else nothing.
    fn pick(&mut self, px: [f32; 2]) {
        let (Some(scene), Some(g)) = (&self.scene, &self.gfx) else { return };
        let (w, h) = (g.viewport.width, g.viewport.height);
        let reach = 14.0 * w as f32 / self.viewport_rect.map_or(w as f32, |r| r.width().max(1.0));
        let click = glam::Vec2::from(px);
        let nearest = scene
            .lights
            .iter()
            .enumerate()
            .filter_map(|(i, l)| Some((i, Self::project(scene, l.position(), w, h)?.distance(click))))
            .filter(|(_, d)| *d <= reach)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i);
        let touching = || -> Option<usize> {
            let probe =
                g.renderer.last_frame().probe(&g.gpu, (px[0] as u32).min(w - 1), (px[1] as u32).min(h - 1)).ok()?;
            probe.lights.iter().copied().min_by(|a, b| scene.lights[*a].radius().total_cmp(&scene.lights[*b].radius()))
        };
        let chosen = nearest.or_else(touching);
        let (x, y) = ((px[0] as u32).min(w - 1), (px[1] as u32).min(h - 1));
        self.explanation = Some(g.renderer.last_frame().explain(&g.gpu, x, y).map_err(|e| format!("{e:#}")));
        self.state.panels.explain = true;
        self.state.selected_light = chosen;
        if chosen.is_some() {
            // Show the picked light's editor, its row in view.
            self.state.tab = state::Tab::Lights;
            self.scroll_to_light = chosen;
        }
        match chosen {
            Some(k) => self.say(format!("selected light {k}"), false),
            None => self.say("no light there", false),
        }
    }

    /// Holds every culling mode of the current path against brute force (a forward path: its
    /// light lists against itself unculled) at the current camera and settings, at a quarter of
    /// the viewport's size (at most 320x180), and opens the check's window. Blocks the viewer
    /// while it runs: up to 8 frames and a lightless one at that size.
    fn check_culling(&mut self) {
        let (Some(scene), Some(g)) = (&self.scene, &self.gfx) else { return };
        let start = Instant::now();
        let settings = self.state.frame_settings();
        let (w, h) = (g.viewport.width, g.viewport.height);
        let scale = (320.0 / w.max(1) as f64).min(180.0 / h.max(1) as f64).min(0.25);
        let size = (((w as f64 * scale).round() as u32).max(8), ((h as f64 * scale).round() as u32).max(8));
        let scope = crate::oracle::Scope { paths: vec![settings.path], ..Default::default() };
        let renderer = match self.check_renderer.take() {
            Some(r) => Ok(r),
            None => crate::oracle::renderer(&g.gpu),
        };
        let result = renderer.and_then(|mut r| {
            let rows = crate::oracle::check_scene(&g.gpu, &mut r, scene, &settings, size, &scope, true);
            self.check_renderer = Some(r);
            rows
        });
        self.check = Some(match result {
            Ok(rows) => {
                let images = rows
                    .iter()
                    .enumerate()
                    .map(|(i, (_, d))| {
                        let img = crate::oracle::difference_image(d.as_deref().unwrap_or(&[]), size.0, size.1);
                        let colour =
                            egui::ColorImage::from_rgba_unmultiplied([size.0 as usize, size.1 as usize], img.as_raw());
                        g.egui_ctx.load_texture(format!("check difference {i}"), colour, egui::TextureOptions::NEAREST)
                    })
                    .collect();
                let rows: Vec<crate::oracle::ModeResult> = rows.into_iter().map(|(m, _)| m).collect();
                // Show the first frame that fails, else the first.
                self.state.check_row = rows.iter().position(|r| r.failed()).unwrap_or(0);
                Ok(ui::CullingCheck { size: [size.0, size.1], rows, images, seconds: start.elapsed().as_secs_f64() })
            }
            Err(e) => Err(format!("{e:#}")),
        });
        self.state.panels.check = true;
        match &self.check {
            Some(Ok(c)) => {
                let failed = c.failed();
                self.say(format!("culling check: {} frames, {failed} miss or add light", c.rows.len()), failed > 0)
            }
            Some(Err(e)) => self.say(format!("culling check failed: {e}"), true),
            None => {}
        }
    }

    /// Starts the advisor (`lampshade advise`) on the current scene, camera and settings at the
    /// viewport's size (at most 320x180), unless it is already running; its window opens.
    fn start_advice(&mut self) {
        if self.advice.as_ref().is_some_and(|j| j.running()) {
            return;
        }
        let (Some(scene), Some(g)) = (&self.scene, &self.gfx) else { return };
        let size = advice::size((g.viewport.width, g.viewport.height));
        let settings = self.state.frame_settings();
        self.advice = Some(advice::AdviceJob::start(scene.clone(), settings, size));
        self.state.panels.advice = true;
        self.say(format!("advising on {} lights at {}x{}", scene.lights.len(), size.0, size.1), false);
    }

    /// Starts a calibration on the viewer's adapter (unless one runs): `options`, written to the
    /// cache; the viewport holds its last frame until it ends ([`App::finish_calibration`]).
    fn start_calibration(&mut self, options: crate::bench::calibrate::CalibrateOptions) {
        self.offer_calibration = false;
        self.calibration_answered = true;
        if self.calibrating.is_some() {
            return;
        }
        self.calibrating = Some(calibrating::CalibrationJob::start(self.args.adapter.choice(), options));
    }

    /// Once the calibration has ended: its constants are the renderer's from the next frame
    /// (when measured on this window's adapter), and the status line says so. Returns whether
    /// one is still running.
    fn finish_calibration(&mut self) -> bool {
        let Some(answer) = self.calibrating.as_ref().map(|j| j.answer()) else { return false };
        let Some(answer) = answer else {
            if let Some(text) = self.calibrating.as_ref().map(|j| j.status()) {
                self.status = Some(Status { text, error: false });
            }
            return true;
        };
        self.calibrating = None;
        match answer {
            Ok((c, path)) => {
                let Some(g) = self.gfx.as_mut() else { return false };
                if c.key == crate::calibration::key(&g.gpu.info) {
                    let text = format!("calibration: {} -> {path}", c.describe());
                    g.renderer.set_calibration(c);
                    if self.scripted() {
                        println!("frame {}: {text}", self.frame);
                    }
                    self.say(text, false);
                } else {
                    self.say(
                        format!("calibrated another adapter ({}) -> {path}; this window keeps its constants", c.key),
                        true,
                    );
                }
            }
            Err(e) => self.say(format!("calibration failed: {e}"), true),
        }
        false
    }

    fn reset_scene_edits(&mut self) {
        let st = &mut self.state;
        st.camera = None;
        st.lights = None;
        st.light_edits.clear();
        st.light_cookies.clear();
        st.material_edits.clear();
        st.ambient = None;
        st.sun = None;
        st.selected_light = None;
        st.scope = state::Scope::All;
        st.material_index = 0;
        if let Some(g) = &self.gfx {
            g.surface.window.set_title(&format!("Lampshade — {}", st.scene));
        }
    }

    /// Writes the viewport image and its settings file (`stem.png`, `stem.json`).
    fn save_viewport(&self, png: &Path) -> Result<PathBuf> {
        let g = self.gfx.as_ref().ok_or_else(|| anyhow!("no window"))?;
        let img = g.viewport.read(&g.gpu)?;
        gfx::save_png(&img, png)?;
        let json = png.with_extension("json");
        let scene_camera = self.scene.as_ref().map(|s| s.camera);
        let doc = ScreenshotSettings {
            settings: self.state.frame_settings(),
            scene: &self.state.scene,
            lights: self.state.lights,
            time: self.state.time,
            camera: scene_camera,
            size: [g.viewport.width, g.viewport.height],
            light_cookies: &self.state.light_cookies,
            light_masks: self.state.light_edits.iter().map(|(k, e)| (*k, e.mask)).collect(),
            light_shadows: self.state.light_edits.iter().map(|(k, e)| (*k, e.cast_shadows)).collect(),
            viewer: &self.state,
            shadow_atlas: self.atlas_shot(),
            compare: self.compare_shot(png)?,
        };
        let text = serde_json::to_string_pretty(&doc)?;
        std::fs::write(&json, text).with_context(|| format!("writing {}", json.display()))?;
        Ok(json)
    }
}

/// The file F12 writes beside its PNG: a `Settings` (so `lampshade render --settings FILE`
/// reads it) plus the scene, light count, time, camera and size of the image, and the viewer's
/// whole state.
#[derive(serde::Serialize)]
struct ScreenshotSettings<'a> {
    #[serde(flatten)]
    settings: crate::renderer::Settings,
    scene: &'a str,
    lights: Option<usize>,
    time: f64,
    camera: Option<crate::scene::Camera>,
    size: [u32; 2],
    /// Seed 004: the cookies picked and the masks of the lights edited in the viewer, as
    /// `settings_file::SceneKeys` reads them.
    light_cookies: &'a std::collections::BTreeMap<usize, Option<String>>,
    light_masks: std::collections::BTreeMap<usize, u32>,
    /// The shadow flags of the lights edited in the viewer.
    light_shadows: std::collections::BTreeMap<usize, bool>,
    viewer: &'a UiState,
    /// Where the shadow-atlas panel drew the atlas and the plan's tiles (panel open).
    #[serde(skip_serializing_if = "Option::is_none")]
    shadow_atlas: Option<AtlasShot>,
    /// The split view's configuration B, written beside as `stem-b.png` (split view on).
    #[serde(skip_serializing_if = "Option::is_none")]
    compare: Option<CompareShot>,
}

/// The split view in a screenshot's settings file: B's settings and image file, the viewport's
/// rectangle in window pixels ([x, y, width, height]), the divider, and B against A (the
/// largest step and FLIP's mean where the view computed them).
#[derive(serde::Serialize)]
struct CompareShot {
    b: crate::renderer::Settings,
    image: PathBuf,
    viewport: [f32; 4],
    view: split::SplitView,
    divider: f32,
    max_steps: Option<u8>,
    flip_mean: Option<f32>,
    a_ms: Vec<(String, f64)>,
    b_ms: Vec<(String, f64)>,
    ledger_delta: Vec<crate::bench::LightDelta>,
}

/// The shadow-atlas panel in a screenshot's settings file: the image's rectangle in window
/// pixels ([x, y, width, height]), the part of the atlas it shows ([u0, v0, u1, v1]), the
/// atlas's side and the last frame's tiles, as the renderer planned them.
#[derive(serde::Serialize)]
struct AtlasShot {
    image: [f32; 4],
    visible: [f32; 4],
    side: u32,
    range: Option<(f32, f32)>,
    tiles: Vec<crate::renderer::inspect::AtlasTile>,
}

impl App {
    /// B's image beside `png` (`stem-b.png`) and its figures, while the split view shows B.
    fn compare_shot(&self, png: &Path) -> Result<Option<CompareShot>> {
        let (Some(g), Some(r)) = (self.gfx.as_ref(), self.viewport_rect) else { return Ok(None) };
        let Some(s) = g.split.as_ref().filter(|s| self.state.split.on && s.stats.is_some()) else { return Ok(None) };
        let stem = png.file_stem().map_or("viewport".into(), |s| s.to_string_lossy().into_owned());
        let image = png.with_file_name(format!("{stem}-b.png"));
        gfx::save_png(&s.image.read(&g.gpu)?, &image)?;
        let ppp = g.egui_ctx.pixels_per_point();
        let a = self.state.frame_settings();
        Ok(Some(CompareShot {
            b: self.state.split.b_settings(&a).unwrap_or(a),
            image,
            viewport: [r.min.x * ppp, r.min.y * ppp, r.width() * ppp, r.height() * ppp],
            view: self.state.split.view,
            divider: self.state.split.divider,
            max_steps: s.figures.max_steps,
            flip_mean: s.figures.flip_mean,
            a_ms: s.figures.a_ms.clone(),
            b_ms: s.figures.b_ms.clone(),
            ledger_delta: s.figures.ledger_delta.clone(),
        }))
    }

    fn atlas_shot(&self) -> Option<AtlasShot> {
        let (g, r) = (self.gfx.as_ref()?, self.atlas_rect?);
        let ppp = g.egui_ctx.pixels_per_point();
        let (side, tiles) = g.renderer.last_frame().shadow_atlas_tiles();
        Some(AtlasShot {
            image: [r.min.x * ppp, r.min.y * ppp, r.width() * ppp, r.height() * ppp],
            visible: ui::atlas_visible(self.state.atlas_view),
            side,
            range: g.atlas_range,
            tiles,
        })
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_none() {
            if let Err(e) = self.init(event_loop) {
                self.fail(event_loop, e);
            }
            self.init_ms = Some(self.started.elapsed().as_secs_f64() * 1e3);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let scripted = self.scripted();
        let Some(g) = self.gfx.as_mut() else { return };
        // In a scripted run the real pointer and keyboard are ignored: only the script acts.
        let input = matches!(
            event,
            WindowEvent::KeyboardInput { .. }
                | WindowEvent::ModifiersChanged(_)
                | WindowEvent::CursorMoved { .. }
                | WindowEvent::CursorEntered { .. }
                | WindowEvent::CursorLeft { .. }
                | WindowEvent::MouseInput { .. }
                | WindowEvent::MouseWheel { .. }
                | WindowEvent::Touch(_)
                | WindowEvent::Ime(_)
        );
        if scripted && input {
            return;
        }
        let consumed = g.egui_state.on_window_event(&g.surface.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                g.surface.resize(&g.gpu, size.width, size.height);
                let logical = size.to_logical::<f64>(g.surface.window.scale_factor());
                if size.width > 0 && size.height > 0 && !g.surface.window.is_minimized().unwrap_or(false) {
                    self.size = ((logical.width.round() as u32).max(64), (logical.height.round() as u32).max(64));
                }
            }
            WindowEvent::KeyboardInput { event: k, .. } => {
                if let PhysicalKey::Code(code) = k.physical_key {
                    match k.state {
                        ElementState::Pressed => {
                            let text_focus = g.egui_ctx.egui_wants_keyboard_input();
                            if !(k.repeat || consumed && text_focus) {
                                self.keys.taps.push(code);
                            }
                            if !text_focus {
                                self.keys.down.insert(code);
                            }
                        }
                        ElementState::Released => {
                            self.keys.down.remove(&code);
                        }
                    }
                }
            }
            WindowEvent::Focused(false) => self.keys.down.clear(),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.frame(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.gfx {
            g.surface.window.request_redraw();
        }
    }
}
