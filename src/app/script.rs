//! Scripted runs: `lampshade view SCENE --script FILE` replays frame-numbered actions in the real
//! window, so tests can drive the viewer under Xvfb and assert on its screenshots.
//!
//! One action per line, `FRAME ACTION [ARGS]`; `#` starts a comment. Actions on the same frame
//! run in file order, before that frame is drawn; `screenshot` and `quit` run after it is drawn.
//!
//! ```text
//! key NAME               tap a key (down this frame, up the next): W A S D E Q Z X Up Down
//!                        Left Right Shift Space F1 F9 F10 F11 F12
//! hold NAME FRAMES       hold a key for FRAMES frames
//! scene NAME             switch to another built-in scene (as the scene selector does)
//! culling MODE           fullscreen | volume | stencil-two-pass | stencil-invert | stencil-replace | auto
//! view VIEW              lit | albedo | normal | depth | specular | emissive | diffuse-light |
//!                        specular-light | stencil | complexity (the viewport's view, as a G-buffer click)
//! layout LAYOUT          compact | seed000 | packed
//! select K | none        select light K (as a click in the light list)
//! scope all | selected   stencil / complexity views for all lights or the selected one
//! wireframes off | all | selected
//! wire-colour light | efficiency
//! tab NAME               left panel tab: scene | lights | materials | camera | help
//! set NAME VALUE         a panel value, validated as the panel does (see `UiState::set`):
//!                        lights scale exposure time speed move-speed animate animate-noise counts ideal
//!                        costliest-first (the light list as the ledger's cost table)
//!                        panel-left panel-right panel-gbuffer panel-shadows panel-pipelines
//!                        timestamps reversed-z depth-clamp accumulation radius-scale intensity-scale
//!                        ambient sun radius intensity colour inner outer cast mask cookie
//!                        (colours as linear r,g,b: `set colour 1,0.2,0`)
//!                        compare on|off, compare-view split|difference|flip, divider U:
//!                        the split view (configuration B right of the divider at U)
//! compare-set NAME VALUE set knob NAME of configuration B (the split view's right side)
//! compare-file PATH      B's knobs from a settings file (every renderer key it gives)
//! replay PATH            replay the camera path in PATH (as F10 does a recorded one),
//!                        1/60 s of path time a frame, from its start, looping
//! hover U V              put the pointer over the viewport at (U, V) in [0, 1] (pixel probe)
//! click U V              click the viewport at (U, V) (selects the light there)
//! atlas-hover U V        put the pointer over the shadow-atlas panel's image at (U, V) in
//!                        [0, 1] (the panel must be open: `set panel-shadows on`)
//! atlas-click U V        click the atlas image there (selects the light whose tile it is)
//! leave                  take the pointer out of the window
//! resize W H             ask for a window of W x H logical pixels
//! minimize | restore     minimise / restore the window
//! screenshot PATH        after drawing: the whole window to PATH, the viewport image to
//!                        PATH-stem + "-viewport.png" and its settings to PATH-stem + "-viewport.json"
//! memory                 after drawing: print the frame number and the resident memory
//!                        (`frame N: resident BYTES bytes`), then the pipelines compiled so
//!                        far (`frame N: pipelines compiled P`) to stdout, for soak runs
//! overlaps               after drawing: end the run with an error naming them when two
//!                        widgets of the drawn UI overlap (`ui::overlaps`)
//! compiles wait | live   wait: each change is drawn at once, its pipelines compiled by the
//!                        frame that draws it (a scripted run's default); live: as in an
//!                        interactive run, a configuration whose pipelines are not compiled
//!                        builds in the background while the last one is drawn (on
//!                        frame 1, from the start: the first frame is then the stand-in)
//! compile-delay MS       each background build waits MS milliseconds more before it is
//!                        ready (a deliberately slow compile)
//! wait-compiles          wait (at most 120 s) for the background build to finish; the
//!                        frame after then draws the configuration it built
//! frame-log PATH         from this frame on, write the frame log (`--frame-log`) to PATH
//! pipelines PATH         after drawing: write the pipelines panel's rows (each
//!                        configuration's pipelines and compile times) to PATH as JSON
//! calibrate              after drawing: measure the cost model's constants at a small size
//!                        (`lampshade calibrate`), write them to the cache and use them; the
//!                        script waits, and prints `frame N: calibration: …`
//! quit                   after drawing: exit with status 0
//! ```
//!
//! In a scripted run real mouse and keyboard input is ignored, time advances by exactly
//! 1/30 s per frame, and a failing action (an unwritable path) ends the run with an error.

use crate::renderer::{CullingMode, DebugView, LayoutChoice};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use winit::keyboard::KeyCode;

use super::state::{Scope, Tab, WireColour, Wireframes};

/// Seconds per frame in a scripted run.
pub const SCRIPT_DT: f64 = 1.0 / 30.0;

/// Largest frame number and `hold` length a script may use: 2^32 frames, over four years at 30
/// frames a second. The viewer computes a hold's last frame as `frame + n - 1`; with both
/// bounded it cannot overflow (it did, and panicked in debug builds, for
/// `1 hold W 18446744073709551615`).
pub const MAX_FRAME: u64 = 1 << 32;

#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    Key(KeyCode),
    Hold(KeyCode, u64),
    Scene(String),
    Culling(CullingMode),
    View(DebugView),
    Layout(LayoutChoice),
    Select(Option<usize>),
    Scope(Scope),
    Wireframes(Wireframes),
    WireColour(WireColour),
    Tab(Tab),
    Set(String, String),
    Hover(f32, f32),
    Click(f32, f32),
    /// Hover / click on the shadow-atlas panel's image.
    AtlasHover(f32, f32),
    AtlasClick(f32, f32),
    Leave,
    Resize(u32, u32),
    Minimize,
    Restore,
    Screenshot(PathBuf),
    Memory,
    Overlaps,
    /// The culling check against brute force at the current camera (its window opens).
    Check,
    /// The advisor on the current scene and camera; the script waits for its answer.
    Advise,
    /// A small calibration, written to the cache and used; the script waits for it.
    Calibrate,
    /// Background compiles on (`live`) or off (`wait`).
    Compiles(bool),
    CompileDelay(u64),
    WaitCompiles,
    FrameLog(PathBuf),
    /// The pipelines panel's rows as JSON.
    Pipelines(PathBuf),
    /// Set one of configuration B's knobs (the split view).
    CompareSet(String, String),
    /// Configuration B's knobs from a settings file.
    CompareFile(PathBuf),
    /// Replay a camera path file.
    Replay(PathBuf),
    Quit,
}

impl Action {
    /// Runs after the frame is drawn.
    pub fn is_post(&self) -> bool {
        matches!(
            self,
            Action::Screenshot(_)
                | Action::Memory
                | Action::Overlaps
                | Action::Check
                | Action::Advise
                | Action::Calibrate
                | Action::Pipelines(_)
                | Action::Quit
        )
    }
}

#[derive(Clone, Debug, Default)]
pub struct Script {
    /// Sorted by frame; equal frames keep file order.
    pub actions: Vec<(u64, Action)>,
    next: usize,
}

pub fn key_code(name: &str) -> Result<KeyCode, String> {
    let k = match name.to_ascii_lowercase().as_str() {
        "w" => KeyCode::KeyW,
        "a" => KeyCode::KeyA,
        "s" => KeyCode::KeyS,
        "d" => KeyCode::KeyD,
        "e" => KeyCode::KeyE,
        "q" => KeyCode::KeyQ,
        "z" => KeyCode::KeyZ,
        "x" => KeyCode::KeyX,
        "up" => KeyCode::ArrowUp,
        "down" => KeyCode::ArrowDown,
        "left" => KeyCode::ArrowLeft,
        "right" => KeyCode::ArrowRight,
        "shift" => KeyCode::ShiftLeft,
        "space" => KeyCode::Space,
        "f1" => KeyCode::F1,
        "f9" => KeyCode::F9,
        "f10" => KeyCode::F10,
        "f11" => KeyCode::F11,
        "f12" => KeyCode::F12,
        _ => {
            return Err(format!(
                "unknown key '{name}' (W A S D E Q Z X Up Down Left Right Shift Space F1 F9 F10 F11 F12)"
            ))
        }
    };
    Ok(k)
}

fn unit(v: &str) -> Result<f32, String> {
    let x: f32 = v.parse().map_err(|_| format!("'{v}' is not a number"))?;
    if !(0.0..=1.0).contains(&x) {
        return Err(format!("{x} is outside [0, 1]"));
    }
    Ok(x)
}

fn count<T: std::str::FromStr>(v: &str, what: &str) -> Result<T, String> {
    v.parse().map_err(|_| format!("{what} '{v}' is not a whole number"))
}

/// One script line's action: one arm per action of the language in the module doc, in that
/// order, each parsing its own arguments.
fn parse_action(words: &[&str], base: &Path) -> Result<Action, String> {
    // table: one arm per action of the script language, in the module doc's order
    let (name, args) = words.split_first().ok_or("missing action")?;
    let want = |n: usize| -> Result<(), String> {
        if args.len() != n {
            Err(format!("'{name}' takes {n} argument(s), got {}", args.len()))
        } else {
            Ok(())
        }
    };
    let a = match *name {
        "key" => {
            want(1)?;
            Action::Key(key_code(args[0])?)
        }
        "hold" => {
            want(2)?;
            let n: u64 = count(args[1], "frame count")?;
            if n == 0 {
                return Err("hold needs at least 1 frame".into());
            }
            if n > MAX_FRAME {
                return Err(format!("hold of {n} frames is longer than {MAX_FRAME}"));
            }
            Action::Hold(key_code(args[0])?, n)
        }
        "scene" => {
            want(1)?;
            let file = crate::scene::import::is_gltf_path(args[0]);
            if !file && !crate::scene::builtin::NAMES.iter().any(|(n, _)| *n == args[0]) {
                return Err(format!("unknown scene '{}' (see `lampshade scenes`, or a .gltf/.glb file)", args[0]));
            }
            Action::Scene(args[0].to_string())
        }
        "culling" => {
            want(1)?;
            Action::Culling(CullingMode::parse(args[0])?)
        }
        "view" => {
            want(1)?;
            Action::View(DebugView::parse(args[0])?)
        }
        "layout" => {
            want(1)?;
            Action::Layout(LayoutChoice::parse(args[0])?)
        }
        "select" => {
            want(1)?;
            Action::Select(if args[0] == "none" { None } else { Some(count(args[0], "light index")?) })
        }
        "scope" => {
            want(1)?;
            Action::Scope(Scope::parse(args[0])?)
        }
        "wireframes" => {
            want(1)?;
            Action::Wireframes(Wireframes::parse(args[0])?)
        }
        "wire-colour" | "wire-color" => {
            want(1)?;
            Action::WireColour(WireColour::parse(args[0])?)
        }
        "tab" => {
            want(1)?;
            Action::Tab(Tab::parse(args[0])?)
        }
        "set" => {
            want(2)?;
            Action::Set(args[0].to_string(), args[1].to_string())
        }
        "compare-set" => {
            want(2)?;
            Action::CompareSet(args[0].to_string(), args[1].to_string())
        }
        "compare-file" | "replay" => {
            want(1)?;
            let p = Path::new(args[0]);
            let p = if p.is_absolute() { p.to_path_buf() } else { base.join(p) };
            if *name == "replay" {
                Action::Replay(p)
            } else {
                Action::CompareFile(p)
            }
        }
        "hover" | "click" => {
            want(2)?;
            let (u, v) = (unit(args[0])?, unit(args[1])?);
            if *name == "hover" {
                Action::Hover(u, v)
            } else {
                Action::Click(u, v)
            }
        }
        "atlas-hover" | "atlas-click" => {
            want(2)?;
            let (u, v) = (unit(args[0])?, unit(args[1])?);
            if *name == "atlas-hover" {
                Action::AtlasHover(u, v)
            } else {
                Action::AtlasClick(u, v)
            }
        }
        "leave" => {
            want(0)?;
            Action::Leave
        }
        "resize" => {
            want(2)?;
            let (w, h): (u32, u32) = (count(args[0], "width")?, count(args[1], "height")?);
            if w > 16384 || h > 16384 {
                return Err(format!("window size {w}x{h} is too large"));
            }
            Action::Resize(w, h)
        }
        "minimize" | "minimise" => {
            want(0)?;
            Action::Minimize
        }
        "restore" => {
            want(0)?;
            Action::Restore
        }
        "screenshot" => {
            want(1)?;
            let p = Path::new(args[0]);
            Action::Screenshot(if p.is_absolute() { p.to_path_buf() } else { base.join(p) })
        }
        "memory" => {
            want(0)?;
            Action::Memory
        }
        "overlaps" => {
            want(0)?;
            Action::Overlaps
        }
        "check" => {
            want(0)?;
            Action::Check
        }
        "advise" => {
            want(0)?;
            Action::Advise
        }
        "compiles" => {
            want(1)?;
            match args[0] {
                "wait" => Action::Compiles(false),
                "live" => Action::Compiles(true),
                other => return Err(format!("compiles '{other}': wait or live")),
            }
        }
        "compile-delay" => {
            want(1)?;
            let ms: u64 = count(args[0], "delay")?;
            if ms > 600_000 {
                return Err(format!("compile delay {ms} ms is longer than ten minutes"));
            }
            Action::CompileDelay(ms)
        }
        "wait-compiles" => {
            want(0)?;
            Action::WaitCompiles
        }
        "frame-log" | "pipelines" => {
            want(1)?;
            let p = Path::new(args[0]);
            let p = if p.is_absolute() { p.to_path_buf() } else { base.join(p) };
            if *name == "frame-log" {
                Action::FrameLog(p)
            } else {
                Action::Pipelines(p)
            }
        }
        "calibrate" => {
            want(0)?;
            Action::Calibrate
        }
        "quit" => {
            want(0)?;
            Action::Quit
        }
        other => return Err(format!("unknown action '{other}'")),
    };
    Ok(a)
}

impl Script {
    /// Parses a script; relative screenshot paths are taken from `base` (the working directory).
    pub fn parse(text: &str, base: &Path) -> Result<Self> {
        let mut actions = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let words: Vec<&str> = line.split_whitespace().collect();
            let frame: u64 = match words[0].parse() {
                Ok(f) => f,
                Err(_) => bail!("line {}: '{}' is not a frame number", i + 1, words[0]),
            };
            if frame > MAX_FRAME {
                bail!("line {}: frame {frame} is past the last frame a script may use ({MAX_FRAME})", i + 1);
            }
            let action = parse_action(&words[1..], base).map_err(|e| anyhow::anyhow!("line {}: {e}", i + 1))?;
            actions.push((frame, action));
        }
        if actions.is_empty() {
            bail!("the script has no actions");
        }
        actions.sort_by_key(|(f, _)| *f);
        Ok(Self { actions, next: 0 })
    }

    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading script {}", path.display()))?;
        let base = std::env::current_dir().context("no working directory")?;
        Self::parse(&text, &base).with_context(|| format!("in script {}", path.display()))
    }

    /// The actions of `frame` (all earlier ones must have been taken).
    pub fn take(&mut self, frame: u64) -> Vec<Action> {
        let mut out = Vec::new();
        while let Some((f, a)) = self.actions.get(self.next) {
            if *f > frame {
                break;
            }
            out.push(a.clone());
            self.next += 1;
        }
        out
    }

    pub fn finished(&self) -> bool {
        self.next >= self.actions.len()
    }

    pub fn last_frame(&self) -> u64 {
        self.actions.last().map_or(0, |(f, _)| *f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_action_and_sorts_by_frame() {
        let s = Script::parse(
            "# a comment\n\n20 quit\n5 key W\n5 hold shift 10   # trailing comment\n6 culling stencil-invert\n\
             7 view stencil\n8 select 3\n8 select none\n9 set exposure 2\n10 hover 0.5 0.25\n\
             11 screenshot out/a.png\n12 layout packed\n13 wireframes all\n14 tab lights\n15 resize 800 600\n\
             16 check\n",
            Path::new("/base"),
        )
        .unwrap();
        assert_eq!(s.actions.first().unwrap(), &(5, Action::Key(KeyCode::KeyW)));
        assert_eq!(s.actions.last().unwrap(), &(20, Action::Quit));
        assert!(s.actions.contains(&(11, Action::Screenshot(PathBuf::from("/base/out/a.png")))));
        assert!(s.actions.contains(&(6, Action::Culling(CullingMode::StencilInvert))));
        assert!(s.actions.contains(&(16, Action::Check)) && Action::Check.is_post());
    }

    #[test]
    fn bad_lines_name_their_line() {
        for (text, needle) in [
            ("x quit", "line 1"),
            ("1 jump", "unknown action"),
            ("1\n2 key Tab", "line 1"),
            ("1 quit\n2 key Tab", "unknown key"),
            ("1 culling sometimes", "unknown culling mode"),
            ("1 hover 2 0", "outside [0, 1]"),
            ("1 hold W 0", "at least 1"),
            ("1 hold W 18446744073709551615", "longer than 4294967296"),
            ("4294967297 quit", "past the last frame"),
            ("1 select -1", "not a whole number"),
            ("1 quit now", "takes 0"),
            ("# nothing", "no actions"),
        ] {
            let e = format!("{:#}", Script::parse(text, Path::new("/")).unwrap_err());
            assert!(e.contains(needle), "{text:?}: {e}");
        }
    }

    #[test]
    fn take_returns_each_action_once() {
        let mut s = Script::parse("1 key W\n1 key E\n3 quit", Path::new("/")).unwrap();
        assert!(s.take(0).is_empty());
        assert_eq!(s.take(1).len(), 2);
        assert!(s.take(2).is_empty());
        assert_eq!(s.take(3), vec![Action::Quit]);
        assert!(s.finished());
    }
}
