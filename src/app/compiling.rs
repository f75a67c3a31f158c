//! The viewer never stalls on a switch. A configuration whose pipelines are not all compiled is
//! built on a thread of its own, on the viewport's device (so its renderer then finds every
//! pipeline built: `kit::pool`), while the viewport keeps drawing the configuration it drew
//! last, with the camera, the panels and the input live. It swaps when the set is ready.
//!
//! Whether a configuration is ready is asked of a renderer of its own on this thread
//! (`Renderer::pipelines_ready`: its declared set, compiled or not, computed without compiling
//! one), so a change that needs no new pipeline (an exposure, a light's colour) is drawn at once.
//!
//! Where the driver compiles a pipeline's machine code at its first draw and not when it is
//! created (`Quirks::jit_on_first_draw`: llvmpipe), the worker also draws the configuration
//! once on a second device of its own at the viewport's size: Mesa's shader cache then holds
//! that code, and the viewport's first draw reads it instead of compiling it (on `demo`, a
//! configuration's first frame came down from 0.3-0.6 s over its steady frame to within 50 ms
//! of it). The worker runs at a lower priority, and so do the second device's threads it
//! starts, so that the frames drawn meanwhile keep their pace.

pub use super::pipeline_rows::{config_name, remember, ConfigPipelines};
use crate::renderer::options::calibration::Calibration;
use crate::renderer::{Readiness, Renderer, Settings, OUTPUT_FORMAT};
use crate::scene::Scene;
use crate::Gpu;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Instant;

struct Job {
    id: u64,
    scene: Scene,
    settings: Settings,
    size: (u32, u32),
    config: String,
    calibration: Calibration,
}

/// A build that finished (or failed: the viewport then draws the configuration itself, and
/// says why it cannot).
pub struct Done {
    pub id: u64,
    /// The settings it built.
    pub settings: Settings,
    pub result: Result<ConfigPipelines, String>,
}

/// The build running.
pub struct Pending {
    pub id: u64,
    /// What it builds for: the frame's settings and scene.
    pub settings: Settings,
    pub scene: String,
    pub config: String,
    /// Pipelines the configuration is short of (`None`: its whole pass set is new).
    pub missing: Option<usize>,
    pub started: Instant,
}

/// The worker thread and the build it runs.
pub struct Compiler {
    /// `None` once dropped: the worker then ends after its build.
    jobs: Option<mpsc::Sender<Job>>,
    done: mpsc::Receiver<Done>,
    next_id: u64,
    pub pending: Option<Pending>,
    /// Builds that finished while [`Compiler::wait_pending`] waited.
    early: Vec<Done>,
    /// Milliseconds each build waits before it reports (a script's `compile-delay`: a
    /// deliberately slow compile, for tests).
    delay_ms: Arc<AtomicU64>,
}

impl Compiler {
    /// Starts the worker on `gpu`'s device; `warm`: the adapter to open the second device on,
    /// where its driver compiles at first draw.
    pub fn start(gpu: &Gpu, warm: Option<crate::gpu::AdapterChoice>) -> anyhow::Result<Self> {
        let (jobs, job_rx) = mpsc::channel::<Job>();
        let (done_tx, done) = mpsc::channel();
        let delay_ms = Arc::new(AtomicU64::new(0));
        let delay = delay_ms.clone();
        let gpu = gpu.share();
        std::thread::Builder::new().name("pipelines".into()).spawn(move || {
            lower_priority();
            let mut worker = Worker { gpu, renderer: None, warm, warm_device: None };
            while let Ok(mut job) = job_rx.recv() {
                // Only the newest request matters.
                while let Ok(newer) = job_rx.try_recv() {
                    job = newer;
                }
                let start = Instant::now();
                let result = worker.build(&job).map_err(|e| format!("{e:#}"));
                let wait = delay.load(Ordering::Relaxed);
                if wait > 0 {
                    std::thread::sleep(std::time::Duration::from_millis(wait));
                }
                let result = result.map(|mut c| {
                    c.wall_ms = start.elapsed().as_secs_f64() * 1e3;
                    c
                });
                if done_tx.send(Done { id: job.id, settings: job.settings, result }).is_err() {
                    break;
                }
            }
        })?;
        Ok(Self { jobs: Some(jobs), done, next_id: 0, pending: None, early: Vec::new(), delay_ms })
    }

    pub fn set_delay_ms(&self, ms: u64) {
        self.delay_ms.store(ms, Ordering::Relaxed);
    }

    /// Has the worker build `settings` on `scene` at `size` with nothing pending meanwhile:
    /// the configuration a first frame drew itself, so that the worker's renderers (and its
    /// second device) are made before the first switch.
    pub fn prime(&mut self, scene: &Scene, settings: &Settings, size: (u32, u32), calibration: &Calibration) {
        self.next_id += 1;
        let job = Job {
            id: self.next_id,
            scene: scene.clone(),
            settings: settings.clone(),
            size,
            config: config_name(settings),
            calibration: calibration.clone(),
        };
        if let Some(jobs) = &self.jobs {
            let _ = jobs.send(job);
        }
    }

    /// Waits at most `timeout` for the pending build to finish (the script's `wait-compiles`);
    /// whether it did. Its answer is then [`Compiler::poll`]'s.
    pub fn wait_pending(&mut self, timeout: std::time::Duration) -> bool {
        let end = Instant::now() + timeout;
        loop {
            let Some(id) = self.pending.as_ref().map(|p| p.id) else { return true };
            if self.early.iter().any(|d| d.id == id) {
                return true;
            }
            let left = end.saturating_duration_since(Instant::now());
            match self.done.recv_timeout(left) {
                Ok(d) => self.early.push(d),
                Err(_) => return false,
            }
        }
    }

    /// Asks for `settings` on `scene` at `size` to be built, unless that is what runs.
    pub fn request(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        size: (u32, u32),
        missing: Option<usize>,
        calibration: &Calibration,
    ) {
        if self.pending.as_ref().is_some_and(|p| p.settings == *settings && p.scene == scene.name) {
            return;
        }
        self.next_id += 1;
        let config = config_name(settings);
        let job = Job {
            id: self.next_id,
            scene: scene.clone(),
            settings: settings.clone(),
            size,
            config: config.clone(),
            calibration: calibration.clone(),
        };
        if self.jobs.as_ref().is_some_and(|j| j.send(job).is_ok()) {
            self.pending = Some(Pending {
                id: self.next_id,
                settings: settings.clone(),
                scene: scene.name.clone(),
                config,
                missing,
                started: Instant::now(),
            });
        }
    }

    /// The build that finished since the last call, if it is the one pending (an older
    /// request's answer is dropped).
    pub fn poll(&mut self) -> Option<Done> {
        let mut answer = None;
        let early = std::mem::take(&mut self.early);
        for d in early.into_iter().chain(std::iter::from_fn(|| self.done.try_recv().ok())) {
            if self.pending.as_ref().is_some_and(|p| p.id == d.id) {
                self.pending = None;
                answer = Some(d);
            }
        }
        answer
    }

    /// Whether the pending build is for `settings` on the scene named `scene`.
    pub fn building(&self, settings: &Settings, scene: &str) -> bool {
        self.pending.as_ref().is_some_and(|p| p.settings == *settings && p.scene == scene)
    }
}

impl Drop for Compiler {
    /// Lets the worker finish the build it runs (at most 30 s) before the device goes, so the
    /// process does not end under a driver call on its thread.
    fn drop(&mut self) {
        self.jobs = None;
        let end = Instant::now() + std::time::Duration::from_secs(30);
        while let Some(left) = end.checked_duration_since(Instant::now()) {
            if let Err(mpsc::RecvTimeoutError::Disconnected) = self.done.recv_timeout(left) {
                return;
            }
        }
        log::warn!("the pipeline worker was still building after 30 s; closing anyway");
    }
}

struct Worker {
    gpu: Gpu,
    renderer: Option<Renderer>,
    warm: Option<crate::gpu::AdapterChoice>,
    warm_device: Option<(Gpu, Renderer)>,
}

impl Worker {
    fn build(&mut self, job: &Job) -> anyhow::Result<ConfigPipelines> {
        let renderer = match &mut self.renderer {
            Some(r) => r,
            None => self.renderer.insert(Renderer::new(&self.gpu, OUTPUT_FORMAT, &job.settings)?),
        };
        renderer.set_calibration(job.calibration.clone());
        let (declared, now) = renderer.build_pipelines_each(&job.scene, &job.settings, job.size)?;
        let mut built = ConfigPipelines::of(job.config.clone(), "background", &declared, &now);
        // The G-buffer strip's thumbnails compose with one more pipeline.
        let thumbnails = job.settings.path.keeps_gbuffer();
        if thumbnails {
            let (declared, now) = renderer.build_view_pipeline()?;
            built.add(ConfigPipelines::of(String::new(), "background", &declared, &now));
        }
        if let Some(choice) = &self.warm {
            let start = Instant::now();
            let (gpu, r) = match &mut self.warm_device {
                Some(w) => w,
                None => {
                    let gpu = Gpu::open(choice)?;
                    let r = Renderer::new(&gpu, OUTPUT_FORMAT, &job.settings)?;
                    self.warm_device.insert((gpu, r))
                }
            };
            r.set_calibration(job.calibration.clone());
            let (w, h) = job.size;
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
            let formats = (OUTPUT_FORMAT, &[][..]);
            let target = crate::renderer::kit::texture_2d(&gpu.device, "warm-up", formats, (w, h), 1, usage)
                .create_view(&Default::default());
            r.render(&job.scene, &job.settings, &target, w, h)?;
            if thumbnails {
                r.last_frame().compose_view(crate::renderer::DebugView::Albedo, &target, w, h)?;
            }
            gpu.wait()?;
            built.warm_ms = Some(start.elapsed().as_secs_f64() * 1e3);
        }
        Ok(built)
    }
}

/// The calling thread, and the threads it starts, yield to the viewer's (Linux: a nice value
/// of 10 for this thread alone; elsewhere nothing).
fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: `setpriority` on this thread's id changes only its scheduling priority; it reads
    // no memory of ours.
    unsafe {
        let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
        if libc::setpriority(libc::PRIO_PROCESS, tid, 10) != 0 {
            log::debug!("could not lower the pipeline worker's priority");
        }
    }
}

/// Whether the viewport may draw `wanted` now: its pipelines are all compiled, or it cannot be
/// drawn at all (its frame then says why). Otherwise its build is requested.
pub enum Choice {
    /// Draw the settings asked for.
    Wanted,
    /// Keep drawing the last configuration drawn while this one builds.
    Keep,
}

/// Asks `planner` whether `wanted` is ready; requests its build when it is not.
pub fn choose(
    planner: &mut Renderer,
    compiler: &mut Compiler,
    scene: &Scene,
    wanted: &Settings,
    size: (u32, u32),
    calibration: &Calibration,
) -> (Choice, Option<ConfigPipelines>) {
    if compiler.building(wanted, &scene.name) {
        return (Choice::Keep, None);
    }
    planner.set_calibration(calibration.clone());
    match planner.pipelines_ready(scene, wanted, size) {
        Ok(Readiness::Ready(declared)) => {
            let all = vec![false; declared.len()];
            (Choice::Wanted, Some(ConfigPipelines::of(config_name(wanted), "background", &declared, &all)))
        }
        Ok(Readiness::Missing(n)) => {
            compiler.request(scene, wanted, size, Some(n), calibration);
            (Choice::Keep, None)
        }
        Ok(Readiness::NewSet) => {
            compiler.request(scene, wanted, size, None, calibration);
            (Choice::Keep, None)
        }
        Err(_) => (Choice::Wanted, None),
    }
}

/// Whether a run compiles in the background from its start: an interactive one does; a
/// script does when its first frame says `compiles live` (the first frame's stand-in then
/// included).
pub fn live_from_start(script: Option<&super::script::Script>) -> bool {
    script.is_none_or(|s| {
        s.actions.iter().take_while(|(f, _)| *f <= 1).fold(false, |live, (_, a)| match a {
            super::script::Action::Compiles(on) => *on,
            _ => live,
        })
    })
}

/// What the viewport draws while the first configuration builds: `wanted` without shadows,
/// drawn with no lights (the viewport takes the lights out of the scene for it), so ambient and
/// sun only. Its frame compiles the G-buffer and compose pipelines alone; on lavapipe the first
/// configuration's light volumes, shadow casters and thumbnails cost a second more of compiles
/// before a first picture.
pub fn stand_in(wanted: &Settings) -> Settings {
    Settings { shadows: crate::renderer::ShadowMode::None, ..wanted.clone() }
}

impl super::App {
    /// The settings the viewport draws this frame and whether they are the stand-in: `wanted`
    /// when its pipelines are compiled (or cannot be: its frame says why), else the last
    /// settings drawn while `wanted` builds; before any frame, the stand-in. `None`: no scene
    /// or window yet.
    pub(super) fn settings_to_draw(&mut self, wanted: &Settings, size: (u32, u32)) -> Option<(Settings, bool)> {
        let (g, scene) = (self.gfx.as_mut()?, self.scene.as_ref()?);
        if let Some(done) = g.compiler.as_mut().and_then(Compiler::poll) {
            match done.result {
                Ok(built) => remember(&mut self.pipelines, built),
                Err(e) => {
                    log::warn!("background compile: {e}");
                    self.failed = Some(done.settings);
                }
            }
        }
        let same = self.drawn.as_ref().is_some_and(|(s, n)| s == wanted && *n == scene.name);
        // Another scene: the last one is gone, so there is nothing to keep drawing; its frame
        // compiles what it needs.
        let other_scene = self.drawn.as_ref().is_some_and(|(_, n)| *n != scene.name);
        // Before the first frame there is nothing to keep showing: with live compiles, the
        // stand-in is drawn while the first configuration builds; else the first frame compiles
        // what it draws, and the worker then makes its renderers with that configuration.
        let first = self.drawn.is_none();
        if !first && !self.primed && self.live_compiles {
            if let (Some(c), Some((s, _))) = (g.compiler.as_mut(), &self.drawn) {
                c.prime(scene, s, size, g.renderer.calibration());
                self.primed = true;
            }
        }
        let direct = same || other_scene || !self.live_compiles || self.failed.as_ref() == Some(wanted);
        let Some(compiler) = g.compiler.as_mut().filter(|_| !direct) else {
            return Some((wanted.clone(), false));
        };
        let calibration = g.renderer.calibration().clone();
        let asking = Instant::now();
        let choice = choose(&mut g.planner, compiler, scene, wanted, size, &calibration);
        self.waits.check_ms += asking.elapsed().as_secs_f64() * 1e3;
        match choice {
            (Choice::Wanted, ready) => {
                if let Some(mut r) = ready {
                    r.built_by = "earlier";
                    remember(&mut self.pipelines, r);
                }
                Some((wanted.clone(), false))
            }
            (Choice::Keep, _) => {
                self.primed = true;
                match &self.drawn {
                    Some((s, _)) => Some((s.clone(), false)),
                    None => Some((stand_in(wanted), true)),
                }
            }
        }
    }

    /// What a background build shows on the status line: `compiling N pipelines for …`, and
    /// what the viewport shows meanwhile.
    pub(super) fn compiling_note(&self) -> Option<String> {
        let p = self.gfx.as_ref()?.compiler.as_ref()?.pending.as_ref()?;
        let what = match p.missing {
            Some(n) => format!("{n} pipeline{}", if n == 1 { "" } else { "s" }),
            None => "a new pass set".to_string(),
        };
        let showing = match self.drawn {
            Some(_) => "showing the last configuration",
            None => "showing a stand-in: ambient and sun, no lights or shadows",
        };
        Some(format!("compiling {what} for {} ({:.1} s); {showing}", p.config, p.started.elapsed().as_secs_f64()))
    }

    /// Writes this frame's line to the frame log, if one is open.
    pub(super) fn log_frame(&mut self) {
        let now = Instant::now();
        let wall_ms = now.duration_since(self.last_present).as_secs_f64() * 1e3;
        self.last_present = now;
        let Some(log) = self.frame_log.as_mut() else { return };
        let building = self.gfx.as_ref().and_then(|g| g.compiler.as_ref()?.pending.as_ref().map(|p| p.config.clone()));
        let line = super::frame_log::FrameLine {
            frame: self.frame,
            at_ms: now.duration_since(self.started).as_secs_f64() * 1e3,
            wall_ms,
            gpu_ms: self.drew.as_ref().and_then(|_| self.stats.as_ref()?.gpu_ms.total),
            render_ms: self.render_ms,
            init_ms: self.init_ms.take(),
            config: self.drew.as_ref().map(|d| d.0.clone()),
            building,
            stand_in: self.drew.as_ref().is_some_and(|d| d.1),
            waited_on: self.waits.main(),
            waits: self.waits,
            camera: self.scene.as_ref().map_or([0.0; 3], |s| s.camera.position.to_array()),
            size: self.drew.as_ref().and_then(|_| Some(self.stats.as_ref()?.size)),
            passes: self.drew.as_ref().and_then(|_| Some(self.stats.as_ref()?.gpu_ms.clone())),
            methods: self.drew.as_ref().and_then(|_| {
                let mut m = std::collections::BTreeMap::new();
                for l in &self.stats.as_ref()?.per_light {
                    *m.entry(super::ui::method_name(l.method)).or_insert(0) += 1;
                }
                Some(m)
            }),
        };
        if let Err(e) = log.write(&line) {
            self.frame_log = None;
            self.say(format!("the frame log stopped: {e:#}"), true);
        }
    }

    /// The script's `compiles`, `compile-delay`, `wait-compiles` and `frame-log`.
    pub(super) fn apply_compile_action(&mut self, action: super::script::Action) {
        use super::script::Action;
        match action {
            Action::Compiles(live) => self.live_compiles = live,
            Action::CompileDelay(ms) => {
                if let Some(c) = self.gfx.as_ref().and_then(|g| g.compiler.as_ref()) {
                    c.set_delay_ms(ms);
                }
            }
            Action::WaitCompiles => {
                if let Some(c) = self.gfx.as_mut().and_then(|g| g.compiler.as_mut()) {
                    if !c.wait_pending(std::time::Duration::from_secs(120)) {
                        self.say("wait-compiles: the background build did not finish in 120 s", true);
                    }
                }
            }
            Action::FrameLog(path) => match super::frame_log::FrameLog::create(&path) {
                Ok(log) => self.frame_log = Some(log),
                Err(e) => self.say(format!("{e:#}"), true),
            },
            _ => {}
        }
    }

    /// The pipelines panel's rows, as JSON, to `path` (the script's `pipelines`).
    pub(super) fn write_pipelines(&self, path: &std::path::Path) -> anyhow::Result<()> {
        use anyhow::Context;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&self.pipelines)?;
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
    }

    /// Writes the device's pipeline cache (`crate::pipeline_cache`) as the viewer closes.
    pub(super) fn save_pipeline_cache(&self) {
        let Some(g) = &self.gfx else { return };
        match crate::pipeline_cache::save(&g.gpu) {
            Ok(Some((path, bytes))) => log::info!("pipeline cache {}: {bytes} bytes written", path.display()),
            Ok(None) => {}
            Err(e) => eprintln!("warning: could not save the pipeline cache: {e:#}"),
        }
    }

    /// [`super::App::finish_calibration`], its time counted as the frame's wait on it.
    pub(super) fn timed_finish_calibration(&mut self) -> bool {
        let start = Instant::now();
        let holding = self.finish_calibration();
        self.waits.calibration_ms += start.elapsed().as_secs_f64() * 1e3;
        holding
    }
}
