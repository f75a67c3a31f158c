//! Scene loading for the viewer: the frame's scene built from the state, built-in scenes
//! rebuilt when their parameters change, glTF files loaded once on a background thread (with
//! progress), and a failed load reported while the previous scene stays.

use super::state::UiState;
use crate::scene::builtin::{self, BuiltinOptions};
use crate::scene::import::{self, ImportOptions, Imported};
use crate::scene::{Light, Scene};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// Builds the frame's scene: the built-in scene at the state's time (or a loaded glTF file),
/// then the user's edits. The base is cached and rebuilt only when scene, light count or time
/// change; a glTF file is loaded once, on a background thread unless `blocking` is set.
#[derive(Default)]
pub struct SceneCache {
    key: Option<(String, Option<usize>, u64)>,
    base: Option<Scene>,
    /// The file being loaded, with its progress.
    loading: Option<Loading>,
    /// A load that failed: (file, error). The viewer reports it and returns to `base`'s scene.
    failed: Option<(String, String)>,
    /// A file that finished loading since the viewer last asked.
    loaded: Option<String>,
    /// Warnings of the last load, for the status line.
    pub warnings: Vec<String>,
    /// Load files on the calling thread (scripted runs, for determinism).
    pub blocking: bool,
    pub import_options: ImportOptions,
}

struct Loading {
    name: String,
    progress: Arc<Mutex<LoadProgress>>,
    handle: std::thread::JoinHandle<anyhow::Result<Imported>>,
}

/// What the status bar shows while a file loads.
#[derive(Clone, Debug, Default)]
pub struct LoadProgress {
    pub name: String,
    pub stage: String,
    pub done: usize,
    pub total: usize,
}

impl SceneCache {
    /// The name of the scene the cache holds (the last one that loaded).
    pub fn current(&self) -> Option<&str> {
        self.key.as_ref().map(|k| k.0.as_str())
    }

    /// A file load that failed since the last call: (file, error).
    pub fn take_failure(&mut self) -> Option<(String, String)> {
        self.failed.take()
    }

    /// A file that finished loading since the last call.
    pub fn take_loaded(&mut self) -> Option<String> {
        self.loaded.take()
    }

    /// The file being loaded and how far it has got.
    pub fn progress(&self) -> Option<LoadProgress> {
        let l = self.loading.as_ref()?;
        l.progress.lock().ok().map(|p| p.clone())
    }

    /// Puts an already loaded scene in the cache under `name` (the CLI loads the first file
    /// before the window opens, with its own progress bar).
    pub fn insert_loaded(&mut self, name: &str, scene: Scene, warnings: Vec<String>) {
        self.key = Some((name.to_string(), None, 0));
        self.base = Some(scene);
        self.warnings = warnings;
    }

    pub fn base(&mut self, state: &UiState) -> Result<&Scene, String> {
        if import::is_gltf_path(&state.scene) {
            return self.file_base(&state.scene);
        }
        let key = (state.scene.clone(), state.lights, state.time.to_bits());
        if self.key.as_ref() != Some(&key) || self.base.is_none() {
            let scene = builtin::build(&state.scene, BuiltinOptions { lights: state.lights, time: state.time })?;
            self.base = Some(scene);
            self.key = Some(key);
            self.warnings.clear();
        }
        self.base.as_ref().ok_or_else(|| "no scene".to_string())
    }

    /// A glTF file's scene: cached once loaded; while it loads, the previous scene.
    fn file_base(&mut self, name: &str) -> Result<&Scene, String> {
        let key = (name.to_string(), None, 0);
        if self.key.as_ref() == Some(&key) && self.base.is_some() {
            return self.base.as_ref().ok_or_else(|| "no scene".to_string());
        }
        if self.failed.as_ref().is_some_and(|(f, _)| f == name) {
            return self.base.as_ref().ok_or_else(|| format!("{name} failed to load"));
        }
        if self.loading.as_ref().is_some_and(|l| l.name != name) {
            // Another file is still loading; its result is dropped when it ends.
            self.loading = None;
        }
        if self.blocking {
            // Scripted runs: load on this thread, so the next action sees the result.
            let result = import::load(std::path::Path::new(name), &self.import_options, &mut |_| {});
            self.finish_load(name, Ok(result));
        } else if self.loading.is_none() {
            let progress = Arc::new(Mutex::new(LoadProgress { name: name.to_string(), ..Default::default() }));
            let (p, path, options) = (progress.clone(), PathBuf::from(name), self.import_options.clone());
            let handle = std::thread::spawn(move || {
                import::load(&path, &options, &mut |pr| {
                    if let Ok(mut g) = p.lock() {
                        g.stage = pr.stage.to_string();
                        g.done = pr.done;
                        g.total = pr.total;
                    }
                })
            });
            self.loading = Some(Loading { name: name.to_string(), progress, handle });
        }
        if self.loading.as_ref().is_some_and(|l| l.handle.is_finished()) {
            if let Some(l) = self.loading.take() {
                self.finish_load(name, l.handle.join());
            }
        }
        self.base.as_ref().ok_or_else(|| format!("loading {name}"))
    }

    /// Takes a finished load: the new base scene, or a failure the viewer reports.
    fn finish_load(&mut self, name: &str, result: std::thread::Result<anyhow::Result<Imported>>) {
        match result {
            Ok(Ok(imported)) => {
                self.insert_loaded(name, imported.scene, imported.warnings);
                self.loaded = Some(name.to_string());
            }
            Ok(Err(e)) => self.failed = Some((name.to_string(), format!("{e:#}"))),
            Err(_) => self.failed = Some((name.to_string(), "the loader stopped unexpectedly".into())),
        }
    }

    /// The scene as the renderer should draw it this frame.
    pub fn frame_scene(&mut self, state: &UiState) -> Result<Scene, String> {
        let mut scene = self.base(state)?.clone();
        if let Some(c) = state.camera {
            scene.camera = c;
        }
        for (i, l) in scene.lights_mut().iter_mut().enumerate() {
            if let Some(e) = state.light_edits.get(&i) {
                e.apply(l);
            }
            match l {
                Light::Point(p) => {
                    p.radius *= state.radius_scale;
                    p.intensity *= state.intensity_scale;
                }
                Light::Spot(s) => {
                    s.radius *= state.radius_scale;
                    s.intensity *= state.intensity_scale;
                }
            }
        }
        // Cookies picked in the lights tab: each image is read once and kept in the base scene
        // (the clone finds it there by name next frame).
        for (i, spec) in &state.light_cookies {
            if *i < scene.lights.len() {
                scene.set_light_cookie(*i, spec.as_deref())?;
            }
        }
        if let Some(base) = self.base.as_mut() {
            if scene.cookies.len() > base.cookies.len() {
                base.cookies.extend(scene.cookies[base.cookies.len()..].iter().cloned());
            }
        }
        for (i, m) in &state.material_edits {
            if let Some(slot) = scene.materials.get_mut(*i) {
                *slot = *m;
            }
        }
        if let Some(a) = state.ambient {
            scene.ambient = a;
        }
        if let Some(s) = state.sun {
            scene.sun = s;
        }
        scene.validate()?;
        Ok(scene)
    }
}
