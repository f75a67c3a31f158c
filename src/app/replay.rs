//! Camera paths in the viewer: F9 starts and stops a recording (saved as JSON beside the
//! screenshots), F10 replays the last path recorded or given (`--camera-path`, the script's
//! `replay`) and stops it. A replay advances the path by a fixed step of path time a frame
//! (`scene::camera_path`, 1/60 s unless the file says), never by the wall clock, and loops; the
//! keys do not move the camera meanwhile. And F11: RenderDoc's capture of the next frame through
//! wgpu's capture hooks, when RenderDoc is attached.

use super::App;
use crate::scene::camera_path::{CameraPath, Recorder, Replay};
use std::path::PathBuf;

/// Whether RenderDoc's library is loaded into this process (it injects itself when it launches
/// or attaches to the viewer), from the process's own memory map; `None` where that cannot be
/// told.
pub fn renderdoc_attached() -> Option<bool> {
    if cfg!(target_os = "linux") {
        let maps = std::fs::read_to_string("/proc/self/maps").ok()?;
        Some(maps.contains("librenderdoc"))
    } else {
        None
    }
}

impl App {
    /// F9: starts a recording at the current camera, or stops one and saves it as
    /// `path-N.json` in the screenshot folder.
    pub(super) fn toggle_recording(&mut self) {
        if let Some(r) = self.recorder.take() {
            let path = r.finish(Some(self.state.scene.clone()));
            let dir = self.args.screenshot_dir.clone();
            let file = (1..).map(|k| dir.join(format!("path-{k}.json"))).find(|p| !p.exists());
            let Some(file) = file else { return };
            match path.save(&file) {
                Ok(()) => {
                    let text = format!(
                        "recorded {:.1} s ({} keys) -> {}; F10 replays it",
                        path.duration(),
                        path.keys.len(),
                        file.display()
                    );
                    if self.scripted() {
                        println!("frame {}: {text}", self.frame);
                    }
                    self.say(text, false);
                    self.last_path = Some((path, Some(file)));
                }
                Err(e) => self.say(format!("{e:#}"), true),
            }
            return;
        }
        let Some(camera) = self.camera() else { return };
        self.replay = None;
        self.recorder = Some(Recorder::start(camera));
        self.say("recording the camera path (F9 stops)", false);
    }

    /// F10: replays the last path (recorded, or given), or stops the replay.
    pub(super) fn toggle_replay(&mut self) {
        if self.replay.take().is_some() {
            self.say("replay stopped", false);
            return;
        }
        match self.last_path.clone() {
            Some((path, file)) => self.start_replay(path, file),
            None => self.say("no camera path to replay: F9 records one, --camera-path gives one", true),
        }
    }

    pub(super) fn start_replay(&mut self, path: CameraPath, file: Option<PathBuf>) {
        if self.recorder.is_some() {
            self.toggle_recording();
        }
        let r = Replay::new(path.clone());
        self.say(
            format!(
                "replaying {} ({:.1} s, {} frames at {:.4} s a frame; F10 stops)",
                file.as_ref().map_or("the recorded path".into(), |f| f.display().to_string()),
                path.duration(),
                path.frames(r.step),
                r.step
            ),
            false,
        );
        self.last_path = Some((path, file));
        self.replay = Some(r);
    }

    /// The camera path's part of a frame's input: the replayed camera (true: the keys do not
    /// move it), or the recording's next key.
    pub(super) fn path_step(&mut self) -> bool {
        if let Some(r) = self.replay.as_mut() {
            self.state.camera = Some(r.advance());
            return true;
        }
        false
    }

    /// After the keys moved the camera: the recording takes its key.
    pub(super) fn record_step(&mut self, dt: f64) {
        if self.recorder.is_none() {
            return;
        }
        let camera = self.camera();
        if let (Some(r), Some(c)) = (self.recorder.as_mut(), camera) {
            r.push(dt, c);
        }
    }

    /// F11: captures the next frame in RenderDoc, or says it is not attached.
    pub(super) fn ask_capture(&mut self) {
        match renderdoc_attached() {
            Some(false) => self.say("RenderDoc is not attached: start the viewer from RenderDoc to capture", true),
            Some(true) => {
                self.capture_next = true;
                self.say("RenderDoc: capturing the next frame", false);
            }
            None => {
                self.capture_next = true;
                self.say("asked wgpu to capture the next frame (if RenderDoc is attached)", false);
            }
        }
    }

    /// Opens the capture F11 asked for, before the frame's first GPU work.
    pub(super) fn start_capture(&mut self) {
        let Some(g) = self.gfx.as_ref().filter(|_| self.capture_next) else { return };
        self.capture_next = false;
        // SAFETY: wgpu's capture hooks call RenderDoc's in-application API (or do nothing when
        // it is not loaded); the capture is closed in this same frame, after its present.
        unsafe { g.gpu.device.start_graphics_debugger_capture() };
        self.capturing = true;
    }

    /// Closes the capture after the frame is presented.
    pub(super) fn end_capture(&mut self) {
        let Some(g) = self.gfx.as_ref().filter(|_| self.capturing) else { return };
        // SAFETY: closes the capture `start_capture` opened this frame.
        unsafe { g.gpu.device.stop_graphics_debugger_capture() };
        self.capturing = false;
        self.say(format!("captured frame {} (RenderDoc)", self.frame), false);
    }
}
