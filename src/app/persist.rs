//! The viewer's state across restarts: window size, which panels are shown, resolution scale,
//! culling mode, G-buffer layout and the last scene or file, in
//! `<config dir>/lampshade/viewer.json` (`dirs::config_dir()`: `$XDG_CONFIG_HOME` or
//! `~/.config` on Linux) or the file `--state` names. Read when the viewer starts, written when
//! it closes. A file that cannot be read or parsed is reported (stderr and the status line) and
//! replaced by the defaults; it is never a reason not to start. Scripted runs (`--script`) read
//! and write no state unless `--state` is given, so tests never touch a user's settings.

use super::state::Panels;
use crate::renderer::{CullingMode, LayoutChoice};
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What survives a restart. Every field has a default, so a file from an older version (or a
/// hand-edited one missing keys) still loads.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Persisted {
    /// Window size in logical pixels.
    pub window: [u32; 2],
    pub panels: Panels,
    pub resolution_scale: f32,
    pub culling: CullingMode,
    pub layout: LayoutChoice,
    /// The last built-in scene or glTF file shown.
    pub scene: String,
    /// The offer to calibrate (`lampshade calibrate`) was answered, either way: it is made once.
    pub calibration_answered: bool,
}

impl Default for Persisted {
    fn default() -> Self {
        Self {
            window: [1280, 720],
            panels: Panels::default(),
            resolution_scale: super::state::DEFAULT_SCALE,
            culling: CullingMode::default(),
            layout: LayoutChoice::default(),
            scene: "demo".into(),
            calibration_answered: false,
        }
    }
}

impl Persisted {
    /// Checks the values a hand-edited file could get wrong; the message names the key.
    fn validate(&self) -> Result<(), String> {
        let [w, h] = self.window;
        if !(64..=8192).contains(&w) || !(64..=8192).contains(&h) {
            return Err(format!("window {w}x{h} is outside 64x64 .. 8192x8192"));
        }
        let s = self.resolution_scale;
        if !s.is_finite() || !(super::state::MIN_SCALE..=super::state::MAX_SCALE).contains(&s) {
            return Err(format!(
                "resolution_scale {s} is outside [{}, {}]",
                super::state::MIN_SCALE,
                super::state::MAX_SCALE
            ));
        }
        if self.scene.trim().is_empty() {
            return Err("scene is empty".into());
        }
        Ok(())
    }
}

/// Where the state lives by default.
pub fn default_path() -> Option<PathBuf> {
    dirs::config_dir().map(|d| d.join("lampshade").join("viewer.json"))
}

/// Reads the state at `path`: the defaults and no warning when there is no file yet; the
/// defaults and a warning when it cannot be read or is not a valid state file.
pub fn load(path: &Path) -> (Persisted, Option<String>) {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return (Persisted::default(), None),
        Err(e) => return (Persisted::default(), Some(format!("cannot read {}: {e}; using defaults", path.display()))),
    };
    match serde_json::from_str::<Persisted>(&text).map_err(|e| e.to_string()).and_then(|p| p.validate().map(|_| p)) {
        Ok(p) => (p, None),
        Err(e) => (Persisted::default(), Some(format!("ignoring {}: {e}; using defaults", path.display()))),
    }
}

/// Writes the state to `path` (through a temporary file, so a crash mid-write leaves the old
/// file whole), creating its directory.
pub fn save(path: &Path, state: &Persisted) -> Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let tmp = path.with_extension("json.tmp");
    let text = serde_json::to_string_pretty(state)?;
    std::fs::write(&tmp, text).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("replacing {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        // Under target/, emptied first: one directory a test, reused by every run.
        let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/persist-tests").join(name);
        let _ = std::fs::remove_dir_all(&d);
        d.join("viewer.json")
    }

    #[test]
    fn the_state_round_trips_and_a_missing_file_is_the_defaults() {
        let p = scratch("round-trip");
        assert_eq!(load(&p), (Persisted::default(), None));
        let s = Persisted {
            window: [900, 500],
            panels: Panels {
                left: true,
                right: false,
                gbuffer: false,
                shadows: true,
                explain: false,
                check: false,
                advice: false,
                pipelines: true,
            },
            resolution_scale: 0.25,
            culling: CullingMode::StencilInvert,
            layout: LayoutChoice::Seed000,
            scene: "model.glb".into(),
            calibration_answered: true,
        };
        save(&p, &s).unwrap();
        assert_eq!(load(&p), (s, None));
    }

    #[test]
    fn a_bad_state_file_is_reported_and_replaced_by_the_defaults() {
        let p = scratch("bad");
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        for (text, says) in [
            ("{not json", "ignoring"),
            (r#"{"culling": "sideways"}"#, "sideways"),
            (r#"{"window": [10, 10]}"#, "window 10x10"),
            (r#"{"resolution_scale": 50}"#, "resolution_scale"),
            (r#"{"colour": 1}"#, "colour"),
            ("\u{0}\u{ff}", "ignoring"),
        ] {
            std::fs::write(&p, text).unwrap();
            let (state, warning) = load(&p);
            assert_eq!(state, Persisted::default(), "{text}");
            let w = warning.unwrap_or_else(|| panic!("no warning for {text:?}"));
            assert!(w.contains(says), "{text:?}: warning '{w}' does not mention '{says}'");
        }
        // A directory where the file should be cannot be read: a warning, not a failure.
        let d = scratch("dir");
        std::fs::create_dir_all(&d).unwrap();
        assert!(load(&d).1.is_some());
        // Keys written by an older version (a subset) load, the rest default.
        std::fs::write(&p, r#"{"culling": "volume"}"#).unwrap();
        assert_eq!(load(&p), (Persisted { culling: CullingMode::Volume, ..Persisted::default() }, None));
    }
}
