//! Memory over a long run of the library alone: one `Renderer` rendering 1,000 frames of the
//! animated `demo` while the culling mode, the debug view and the G-buffer layout change, with
//! a thumbnail (`compose_view`) and a pixel probe every frame, as the viewer does. Resident
//! memory after the warm-up (200 frames: every mode, view and layout of the schedule seen, so
//! every pipeline exists) may grow by less than 5% over the remaining 800 frames. The viewer's
//! own soak run is `the_viewer_runs_thousands_of_frames_in_constant_memory` in `tests/it/viewer.rs`.
//!
//! What it caught: Mesa 22.3's lavapipe recompiles a shader whose branches read a uniform
//! buffer every time that buffer is written, and keeps the old compilation (0.4-1 MB a draw:
//! +1,140 MiB over 800 frames here, 213%); and every layout switch compiled all pipelines again
//! (+26 MiB over 800 frames, 12%). Memory, not speed: nothing here is timed. It runs in a process
//! of its own so that no other test shares the process whose memory it reads.

use crate::common::*;
use lampshade::headless::Offscreen;
use lampshade::memory::resident_bytes;
use lampshade::renderer::{CullingMode, DebugView, LayoutChoice, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};

const W: u32 = 160;
const H: u32 = 90;
const FRAMES: usize = 1000;
/// One full cycle of the schedule's layouts (3 x 50 frames) and more.
const WARMUP: usize = 200;
/// Allowed growth of resident memory after the warm-up.
const MAX_GROWTH: f64 = 0.05;
/// Point lights in `demo` (the memory behaviour does not depend on the count; fewer keep the
/// test short in CI's debug build).
const LIGHTS: usize = 64;

/// The state of frame `i`: every culling mode, a spread of views and three layouts, something
/// changing every few frames.
fn settings_for(i: usize) -> Settings {
    let modes = CullingMode::ALL;
    let views = [DebugView::Lit, DebugView::Normal, DebugView::Stencil, DebugView::Complexity, DebugView::Albedo];
    let layouts = [LayoutChoice::Compact, LayoutChoice::Seed000, LayoutChoice::Packed];
    Settings {
        culling: modes[(i / 7) % modes.len()],
        debug_view: views[(i / 11) % views.len()],
        layout: layouts[(i / 50) % layouts.len()],
        ..Settings::default()
    }
}

/// Set in the process [`a_renderer_renders_a_thousand_frames_in_constant_memory`] starts.
const CHILD: &str = "LAMPSHADE_SOAK_CHILD";

/// Runs the soak in a process of its own (this test binary again, running only
/// [`soak_in_this_process`]), so that no other test's allocations share the memory it reads.
#[test]
fn a_renderer_renders_a_thousand_frames_in_constant_memory() {
    in_own_process();
}

fn in_own_process() {
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args(["--exact", "soak::soak_in_this_process", "--ignored", "--nocapture", "--test-threads", "1"])
        .env(CHILD, "1")
        .output()
        .expect("starting the soak's own process");
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    eprintln!("{stderr}");
    assert!(out.status.success(), "the soak's process failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("1 passed"), "the soak did not run in its process:\n{stdout}");
}

/// The soak's body. Ignored in a plain run: it judges this process's memory, so it runs only in
/// the process of its own that the test above starts.
#[test]
#[ignore = "run by a_renderer_renders_a_thousand_frames_in_constant_memory in a process of its own"]
fn soak_in_this_process() {
    if std::env::var_os(CHILD).is_none() {
        // Asked for by name (`--ignored`): it still gets a process of its own.
        return in_own_process();
    }
    if resident_bytes().is_none() {
        eprintln!("SKIPPED: no /proc/self/status on this system, resident memory cannot be read");
        return;
    }
    let gpu = gpu();
    let mut renderer = Renderer::new(gpu, OUTPUT_FORMAT, &Settings::default()).expect("renderer");
    let out = Offscreen::new(gpu, W, H);
    let thumb = Offscreen::new(gpu, 64, 36);
    let mut after_warmup = 0;
    let mut samples = Vec::new();
    let mut lit = 0;
    for i in 0..FRAMES {
        // The animated scene, rebuilt at each frame's time as the viewer does with Space on.
        let options = BuiltinOptions { lights: Some(LIGHTS), time: i as f64 / 30.0 };
        let scene = builtin::build("demo", options).expect("demo");
        let settings = settings_for(i);
        renderer.render(&scene, &settings, &out.view, W, H).unwrap_or_else(|e| panic!("frame {i}: {e:#}"));
        renderer
            .last_frame()
            .compose_view(DebugView::Normal, &thumb.view, 64, 36)
            .unwrap_or_else(|e| panic!("frame {i}: {e:#}"));
        renderer
            .last_frame()
            .probe(gpu, (i as u32 * 7) % W, (i as u32 * 3) % H)
            .unwrap_or_else(|e| panic!("frame {i}: {e:#}"));
        if i + 1 == WARMUP {
            after_warmup = resident_bytes().unwrap_or(0);
        }
        if i % 100 == 99 {
            samples.push((i + 1, resident_bytes().unwrap_or(0) >> 20));
        }
        // Lit frames are read back now and then and must show the scene: the run is not judged
        // on frames that were never drawn.
        if i % 50 == 0 && settings.debug_view == DebugView::Lit {
            let img = out.read(gpu).expect("readback");
            assert!(lit_share(&img) > 0.2, "frame {i} is (nearly) black");
            lit += 1;
        }
    }
    assert!(lit >= 3, "only {lit} lit frames were checked");
    let end = resident_bytes().unwrap_or(0);
    let growth = end as f64 / after_warmup as f64 - 1.0;
    eprintln!(
        "resident MiB after the warm-up {}, at the end {}, growth {:.1}%; every 100 frames: {samples:?}; \
         live GPU objects: {:?}",
        after_warmup >> 20,
        end >> 20,
        growth * 100.0,
        gpu.device.get_internal_counters().hal
    );
    assert!(
        growth < MAX_GROWTH,
        "resident memory grew by {:.1}% over {} frames after the warm-up ({} MiB to {} MiB; every 100 frames {samples:?})",
        growth * 100.0,
        FRAMES - WARMUP,
        after_warmup >> 20,
        end >> 20
    );
}
