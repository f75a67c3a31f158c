//! The viewer's calibration: `lampshade calibrate` (`bench::calibrate`) on a thread of its own
//! with its own device on the viewer's adapter, written to the cache. While it runs the viewer
//! holds its last frame (it renders no frame of its own), so the window's rendering does not
//! skew the constants; its progress is on the status line.

use crate::bench::calibrate::{self, CalibrateOptions};
use crate::renderer::options::calibration::Calibration;
use std::sync::{Arc, Mutex};

/// A finished calibration: the constants and the file they were written to, or why not.
pub type Answer = Result<(Calibration, String), String>;

/// A running or finished calibration.
pub struct CalibrationJob {
    /// (points done, points in all, what is being drawn).
    pub progress: Arc<Mutex<(usize, usize, String)>>,
    result: Arc<Mutex<Option<Answer>>>,
    handle: Option<std::thread::JoinHandle<()>>,
}

impl CalibrationJob {
    /// Starts calibrating on the adapter `choice` names, with `options`; the result is written
    /// to the cache folder.
    pub fn start(choice: crate::gpu::AdapterChoice, options: CalibrateOptions) -> Self {
        let progress = Arc::new(Mutex::new((0, 0, "starting".to_string())));
        let result = Arc::new(Mutex::new(None));
        let (p, r) = (progress.clone(), result.clone());
        let handle = std::thread::spawn(move || {
            let answer = (|| -> anyhow::Result<(Calibration, String)> {
                let dir = crate::calibration::cache_dir()
                    .ok_or_else(|| anyhow::anyhow!("no cache folder (neither XDG_CACHE_HOME nor HOME is set)"))?;
                let gpu = crate::gpu::Gpu::open(&choice)?;
                let key = crate::calibration::key(&gpu.info);
                let run = calibrate::calibrate(&gpu, &key, &options, &mut |done, total, what| {
                    if let Ok(mut g) = p.lock() {
                        *g = (done, total, what.to_string());
                    }
                })?;
                gpu.errors.check()?;
                let path = crate::calibration::write(&dir, &run.calibration)?;
                Ok((run.calibration, path.display().to_string()))
            })();
            if let Ok(mut g) = r.lock() {
                *g = Some(answer.map_err(|e| format!("{e:#}")));
            }
        });
        Self { progress, result, handle: Some(handle) }
    }

    /// The calibration and its file once the thread has finished (`None` while it runs).
    pub fn answer(&self) -> Option<Answer> {
        self.result.lock().ok().and_then(|g| g.clone())
    }

    /// Waits for the thread (a script's `calibrate` action).
    pub fn wait(&mut self) {
        if let Some(h) = self.handle.take() {
            if h.join().is_err() {
                if let Ok(mut g) = self.result.lock() {
                    *g = Some(Err("the calibration's thread panicked".into()));
                }
            }
        }
    }

    /// The status line while it runs.
    pub fn status(&self) -> String {
        let (done, total, what) = self.progress.lock().map(|g| g.clone()).unwrap_or_default();
        format!("calibrating ({done}/{total}: {what}); the frame is held until it ends")
    }
}

impl Drop for CalibrationJob {
    fn drop(&mut self) {
        // Left to finish on its own (joining would block the viewer's exit).
        self.handle.take();
    }
}
