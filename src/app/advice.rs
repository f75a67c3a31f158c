//! The viewer's advisor: `lampshade advise` (`bench::advise`) on the current scene, camera and
//! settings, on a thread of its own with its own device, so the viewer keeps drawing while it
//! runs; its progress and then its answer are shown in the "Advice" window.

use crate::bench::advise::{self, Advice};
use crate::renderer::Settings;
use crate::Scene;
use std::sync::{Arc, Mutex};

/// A running or finished advice.
pub struct AdviceJob {
    /// (frames done, frames in all, what is being drawn).
    pub progress: Arc<Mutex<(usize, usize, String)>>,
    result: Arc<Mutex<Option<Result<Advice, String>>>>,
    handle: Option<std::thread::JoinHandle<()>>,
    pub started: std::time::Instant,
}

/// The light counts the viewer advises at for `n` lights: a sixteenth, a quarter and all of
/// them (distinct, at least one).
pub fn counts(n: usize) -> Vec<usize> {
    let mut v: Vec<usize> = [n / 16, n / 4, n].into_iter().map(|k| k.max(1)).collect();
    v.dedup();
    v
}

/// The frame size the viewer advises at: the viewport's, at most 320x180.
pub fn size(viewport: (u32, u32)) -> (u32, u32) {
    let (w, h) = viewport;
    let scale = (320.0 / w.max(1) as f64).min(180.0 / h.max(1) as f64).min(1.0);
    (((w as f64 * scale).round() as u32).max(8), ((h as f64 * scale).round() as u32).max(8))
}

impl AdviceJob {
    /// Starts advising on `scene` (its lights strided down to each count) with `settings` under
    /// every candidate, at `size`.
    pub fn start(scene: Scene, settings: Settings, size: (u32, u32)) -> Self {
        let progress = Arc::new(Mutex::new((0, 0, "starting".to_string())));
        let result = Arc::new(Mutex::new(None));
        let (p, r) = (progress.clone(), result.clone());
        let handle = std::thread::spawn(move || {
            let answer = (|| -> anyhow::Result<Advice> {
                let gpu = crate::gpu::Gpu::headless()?;
                let counts = counts(scene.lights.len());
                let candidates = advise::candidates(&settings);
                let name = scene.name.clone();
                let scene_at: Box<dyn FnMut(usize) -> anyhow::Result<Scene>> =
                    Box::new(move |n| Ok(advise::strided(&scene, n)));
                let mut frames = advise::GpuFrames::new(&gpu, candidates.clone(), scene_at, size, 5);
                advise::advise(&mut frames, &name, size, &candidates, &counts, &mut |done, total, what| {
                    if let Ok(mut g) = p.lock() {
                        *g = (done, total, what.to_string());
                    }
                })
            })();
            if let Ok(mut g) = r.lock() {
                *g = Some(answer.map_err(|e| format!("{e:#}")));
            }
        });
        Self { progress, result, handle: Some(handle), started: std::time::Instant::now() }
    }

    /// The answer once the thread has finished (`None` while it runs).
    pub fn answer(&self) -> Option<Result<Advice, String>> {
        self.result.lock().ok().and_then(|g| g.clone())
    }

    pub fn running(&self) -> bool {
        self.answer().is_none()
    }

    /// Waits for the thread (a script's `advise` action).
    pub fn wait(&mut self) {
        if let Some(h) = self.handle.take() {
            if h.join().is_err() {
                if let Ok(mut g) = self.result.lock() {
                    *g = Some(Err("the advisor's thread panicked".into()));
                }
            }
        }
    }
}

impl Drop for AdviceJob {
    fn drop(&mut self) {
        // The thread holds its own device and scene; it is left to finish on its own (joining
        // here would block the viewer on exit for up to the advice's length).
        self.handle.take();
    }
}

/// One line for the status bar or a script's output: the best measured at each count.
pub fn summary(a: &Advice) -> String {
    let per: Vec<String> = a
        .counts
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let (p, m) = a.best(k);
            let name = |c: Option<usize>| c.and_then(|c| a.candidates.get(c).cloned()).unwrap_or_else(|| "-".into());
            format!("{n} lights: {} (predicted {})", name(m), name(p))
        })
        .collect();
    format!("advice at {}x{}: {}", a.size.0, a.size.1, per.join("; "))
}
