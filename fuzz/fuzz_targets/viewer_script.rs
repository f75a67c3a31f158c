//! Fuzzes viewer scripts (`lampshade view --script FILE`): `Script::parse` on arbitrary text
//! (bytes that are not UTF-8 replaced, as `String::from_utf8_lossy` does). An error is fine; a
//! panic, a hang or an unbounded allocation is a bug.
//!
//! A script that parses is then checked for what the viewer does with it without a window:
//! the actions are sorted by frame and `take` hands each out once; a `hold` must end on a frame
//! the viewer can compute (`frame + n - 1` in `App::apply`, without overflow); `select` and
//! `set` go through `UiState` as `App::apply` sends them (on the built-in `spot` scene).
//!
//! Needs the `viewer` feature: `cargo fuzz run --features viewer viewer_script`.
#![no_main]

use lampshade::app::script::{Action, Script};
use lampshade::app::state::UiState;
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::Scene;
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;

fn scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| builtin::build("spot", BuiltinOptions::default()).expect("the spot scene builds"))
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let Ok(mut script) = Script::parse(&text, Path::new("/fuzz/base")) else {
        return;
    };
    assert!(!script.actions.is_empty(), "a parsed script has actions");
    assert!(script.actions.windows(2).all(|w| w[0].0 <= w[1].0), "actions are sorted by frame");
    let scene = scene();
    let mut state = UiState { scene: "spot".into(), ..UiState::default() };
    for (frame, action) in &script.actions {
        match action {
            // App::apply: `self.keys.holds.insert(k, frame + n - 1)`.
            Action::Hold(_, n) => {
                assert!(*n >= 1 && frame.checked_add(*n).is_some(), "hold of {n} frames from frame {frame}")
            }
            Action::Select(Some(k)) if *k < scene.lights.len() => state.selected_light = Some(*k),
            Action::Select(None) => state.selected_light = None,
            Action::Set(name, value) => {
                let _ = state.set(name, value, scene);
            }
            Action::Screenshot(p) => assert!(p.is_absolute(), "screenshot path {} is not absolute", p.display()),
            _ => {}
        }
    }
    let (n, last) = (script.actions.len(), script.last_frame());
    assert_eq!(script.take(last).len(), n, "take hands out every action up to the last frame");
    assert!(script.finished());
});
