//! The viewer's split view (`app::split`) and camera paths (`app::replay`): B right of the
//! divider, the difference of A against itself black, a replayed path the same frames on every
//! run, a recording that replays, the RenderDoc key's message, and a soak with both on.

use super::*;
use lampshade::scene::camera_path::{CameraPath, DEFAULT_STEP};

/// The split view in a 1280x720 window at scale 1 (the viewport 1:1 in the window): with no
/// knob of B's set, B is A (its image byte for byte, the difference view's largest step 0);
/// B with the tiled list mode is within a step of A's `volume`; B with 4 times the exposure is
/// drawn right of the divider: in the window, pixels left of it are A's and right of it B's.
#[test]
fn the_split_view_draws_b_right_of_the_divider_and_a_against_itself_differs_nowhere() {
    need_display!();
    let dir = out_dir("split");
    let script = dir.join("split.script");
    std::fs::write(
        &script,
        "1 set shadows none\n1 set scale 1\n1 set panel-gbuffer off\n1 set compare on\n1 set compare-view difference\n\
         4 screenshot same.png\n\
         5 compare-set culling tiled\n8 screenshot tiled.png\n\
         9 compare-set culling volume\n9 compare-set exposure 4\n9 set compare-view split\n9 set divider 0.3\n\
         12 screenshot split.png\n12 quit\n",
    )
    .unwrap();
    view("demo", &script, &["--lights", "256"], &dir);
    let same = json(&dir, "same-viewport.json");
    assert_eq!(same["compare"]["max_steps"], 0, "{}", same["compare"]);
    assert!(load(&dir, "same-viewport.png") == load(&dir, "same-viewport-b.png"), "B with no knobs is not A");
    let tiled = json(&dir, "tiled-viewport.json");
    assert_eq!(tiled["compare"]["b"]["culling"], "tiled");
    assert!(tiled["compare"]["max_steps"].as_u64().is_some_and(|s| s <= 1), "{}", tiled["compare"]);

    let doc = json(&dir, "split-viewport.json");
    let (a, b, window) =
        (load(&dir, "split-viewport.png"), load(&dir, "split-viewport-b.png"), load(&dir, "split.png"));
    let mean =
        |i: &RgbaImage| i.pixels().map(|p| p[0] as f64 + p[1] as f64 + p[2] as f64).sum::<f64>() / i.len() as f64;
    assert!(mean(&b) > 1.5 * mean(&a), "B (exposure 4) is not brighter than A: {} against {}", mean(&b), mean(&a));
    let r: Vec<f64> = doc["compare"]["viewport"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!((r[2].round() as u32, r[3].round() as u32), a.dimensions(), "the viewport is not 1:1 in the window");
    // Sample rows in the viewport's lowest tenth (the compare window floats over its top).
    let (mut a_side, mut b_side, mut n) = (0, 0, 0);
    for k in 0..40u32 {
        let y = (a.height() as f64 * (0.88 + 0.1 * (k % 4) as f64 / 4.0)) as u32;
        for (u, side) in [(0.05 + 0.2 * (k / 4) as f64 / 10.0, 0), (0.4 + 0.55 * (k / 4) as f64 / 10.0, 1)] {
            let x = (a.width() as f64 * u) as u32;
            let w = window.get_pixel((r[0] + x as f64).round() as u32, (r[1] + y as f64).round() as u32);
            let near = |img: &RgbaImage| (0..3).all(|c| w[c].abs_diff(img.get_pixel(x, y)[c]) <= 2);
            let differs = (0..3).any(|c| a.get_pixel(x, y)[c].abs_diff(b.get_pixel(x, y)[c]) > 8);
            if !differs {
                continue;
            }
            n += 1;
            match side {
                0 => a_side += near(&a) as u32,
                _ => b_side += near(&b) as u32,
            }
        }
    }
    assert!(n >= 40, "only {n} samples where A and B differ");
    assert!(
        a_side as f64 >= 0.45 * n as f64 && b_side as f64 >= 0.45 * n as f64,
        "left of the divider A's pixels at {a_side}, right B's at {b_side}, of {n}"
    );
}

/// A camera path replayed in two runs draws the same viewport, byte for byte, at the same
/// replay frame; the frame's camera is the path's at frame n (1/60 s a frame), not the wall
/// clock's. Then a recording (F9, a held key, F9) saves a path that F10 replays.
#[test]
fn a_replayed_path_is_the_same_frames_on_every_run_and_a_recording_replays() {
    need_display!();
    let path_file = root().join("assets/paths/demo.json");
    let path = CameraPath::load(&path_file).unwrap();
    let mut shots = Vec::new();
    for run in 0..2 {
        let dir = out_dir(&format!("replay-{run}"));
        let script = dir.join("replay.script");
        std::fs::write(
            &script,
            format!(
                "1 set shadows none\n1 replay {}\n{} screenshot a.png\n41 screenshot b.png\n41 quit\n",
                path_file.display(),
                5 + 2 * run
            ),
        )
        .unwrap();
        view("demo", &script, &["--lights", "64", "--size", "640x400"], &dir);
        // The replay began on frame 1: frame F draws path frame F - 1.
        let cam = json(&dir, "b-viewport.json")["camera"].clone();
        same_camera(&cam, &path.frame(40, DEFAULT_STEP), &format!("run {run}: frame 41 against the path's frame 40"));
        shots.push((load(&dir, "b-viewport.png"), load(&dir, "a-viewport.png")));
    }
    assert!(shots[0].0 == shots[1].0, "the same replay frame differs between two runs");
    assert!(shots[0].1 != shots[1].1, "replay frames 4 and 6 are the same picture: the camera did not move");

    let dir = out_dir("record");
    let script = dir.join("record.script");
    std::fs::write(
        &script,
        "1 set shadows none\n2 key F9\n3 hold E 15\n20 key F9\n21 key F10\n30 screenshot r.png\n30 key F11\n31 quit\n",
    )
    .unwrap();
    let out = view(
        "demo",
        &script,
        &["--lights", "64", "--size", "640x400", "--screenshot-dir", dir.to_str().unwrap()],
        &dir,
    );
    let (stdout, stderr) = text(&out);
    assert!(stdout.contains("recorded") && stdout.contains("path-1.json"), "{stdout}");
    let recorded = CameraPath::load(&dir.join("path-1.json")).unwrap();
    assert!((recorded.duration() - 18.0 / 30.0).abs() < 1e-6, "recorded {} s over 18 frames", recorded.duration());
    assert!(recorded.keys.len() >= 3, "{} keys", recorded.keys.len());
    let cam = json(&dir, "r-viewport.json")["camera"].clone();
    // F10 on frame 21 starts the replay with the next frame: frame 30 draws the path's frame 8.
    same_camera(
        &cam,
        &recorded.frame(8, recorded.step(None)),
        "F10's replay at frame 30 against the recording's frame 8",
    );
    // No RenderDoc in this process: the key says so (and captures nothing).
    assert!(stderr.contains("RenderDoc is not attached"), "{stderr}");
}

/// `got` (a screenshot's camera) is `want` to within 1e-12 relative in every value: the viewer
/// binary and this test evaluate the path in builds of their own, whose last bits of a
/// position may differ.
fn same_camera(got: &serde_json::Value, want: &lampshade::scene::Camera, what: &str) {
    let want = serde_json::to_value(want).unwrap();
    let nums = |v: &serde_json::Value| -> Vec<f64> {
        ["position", "yaw", "pitch", "fov_y", "near", "far"]
            .iter()
            .flat_map(|k| match &v[*k] {
                serde_json::Value::Array(a) => a.iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>(),
                x => vec![x.as_f64().unwrap_or(f64::NAN)],
            })
            .collect()
    };
    let (g, w) = (nums(got), nums(&want));
    assert_eq!(g.len(), 8, "{what}: {got}");
    for (a, b) in g.iter().zip(&w) {
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{what}: {got} against {want}");
    }
}
