//! The viewer's "Stochastic shading" section driven by scripts: RIS's reuse and denoiser knobs,
//! and the views that average RIS's frames (`converge`, `variance`).

use super::*;

/// The mean absolute channel difference between two images of one size.
fn mean_step(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let total: u64 =
        a.pixels().zip(b.pixels()).map(|(p, q)| (0..3).map(|c| p[c].abs_diff(q[c]) as u64).sum::<u64>()).sum();
    total as f64 / (3 * a.width() * a.height()) as f64
}

/// RIS with its reuse and denoiser set by script and saved with the screenshot's settings; then
/// RIS alone in the `converge` view, which averages its frames (the viewer draws a new seed
/// each frame in it): after 36 frames the viewport lies nearer the exact picture than after
/// one, by more than half (the noise of a mean of 36 falls to a sixth; measured 0.32 steps
/// after one, 0.07 after 36). The `variance` view then draws the frame-to-frame deviation as a
/// heatmap where the lights' pools lie, and none once RIS is off.
#[test]
fn the_stochastic_views_average_riss_frames_and_the_reuse_knobs_apply() {
    need_display!();
    let dir = out_dir("stochastic");
    let script = dir.join("stochastic.script");
    std::fs::write(
        &script,
        "1 set shadows none\n1 culling clustered\n1 set ris-samples 1\n1 set ris-spatial 4\n1 set ris-temporal on\n\
         1 set ris-denoise on\n4 screenshot knobs.png\n\
         5 set ris-spatial 0\n5 set ris-temporal off\n5 set ris-denoise off\n5 view converge\n6 screenshot one.png\n\
         41 screenshot converged.png\n\
         42 view variance\n60 screenshot variance.png\n\
         61 set ris-samples 0\n63 screenshot exact-variance.png\n64 view lit\n66 screenshot exact.png\n67 quit\n",
    )
    .unwrap();
    view("demo", &script, &["--no-state", "--lights", "64", "--size", "640x400"], &dir);
    let knobs = json(&dir, "knobs-viewport.json");
    assert_eq!(knobs["ris_spatial"], 4, "{knobs}");
    assert_eq!(knobs["ris_temporal"], true, "{knobs}");
    assert_eq!(knobs["ris_denoise"], true, "{knobs}");
    assert!(lit_share(&load(&dir, "knobs-viewport.png")) > 0.2, "RIS with reuse and the denoiser drew black");
    let exact = load(&dir, "exact-viewport.png");
    let (one, converged) = (load(&dir, "one-viewport.png"), load(&dir, "converged-viewport.png"));
    let (e1, e36) = (mean_step(&one, &exact), mean_step(&converged, &exact));
    assert!(e36 < 0.5 * e1, "the converge view did not converge: {e1:.2} steps off after one frame, {e36:.2} after 36");
    // The heatmap's colours against the grey it draws where nothing varies.
    let heat = |img: &RgbaImage| {
        img.pixels().filter(|p| p.0[..3].iter().max().unwrap_or(&0) - p.0[..3].iter().min().unwrap_or(&0) > 20).count()
            as f64
    };
    let pixels = (exact.width() * exact.height()) as f64;
    let (variance, none) =
        (heat(&load(&dir, "variance-viewport.png")), heat(&load(&dir, "exact-variance-viewport.png")));
    // Measured: 4.3% of the viewport (the 64 lights' pools of light on the floor).
    assert!(variance > 0.02 * pixels, "the variance view shows little: {variance} of {pixels} pixels");
    assert_eq!(none, 0.0, "the variance view shows deviation in an exact frame");
}

/// The stochastic soak's schedule for `frames` frames, resident memory every `memory_every`:
/// the demo's 256 lights on the clustered lists with RIS (2 samples, 4 neighbours' spatial
/// reuse, temporal reuse, the denoiser) while its camera path replays (looping every 721
/// frames); the view through lit, converge and variance every 40 frames, the samples between 1
/// and 2 every 120 (the reservoirs made anew), the denoiser off and on every 200 (its regions
/// made anew) and temporal reuse off and on every 280.
pub(super) fn stochastic_soak_plan(frames: u64, memory_every: u64) -> String {
    let path = root().join("assets/paths/demo.json");
    let mut plan = format!(
        "1 set scale 0.25\n1 set lights 256\n1 set shadows none\n1 culling clustered\n1 set ris-samples 2\n\
         1 set ris-spatial 4\n1 set ris-temporal on\n1 set ris-denoise on\n1 replay {}\n",
        path.display()
    );
    let views = ["lit", "converge", "variance"];
    for (k, f) in (40..frames).step_by(40).enumerate() {
        plan += &format!("{f} view {}\n", views[k % views.len()]);
        if k % 3 == 0 {
            plan += &format!("{f} set ris-samples {}\n", 1 + (k / 3) % 2);
        }
        if k % 5 == 0 {
            plan += &format!("{f} set ris-denoise {}\n", if (k / 5) % 2 == 0 { "off" } else { "on" });
        }
        if k % 7 == 0 {
            plan += &format!("{f} set ris-temporal {}\n", if (k / 7) % 2 == 0 { "off" } else { "on" });
        }
    }
    for f in (memory_every..=frames).step_by(memory_every as usize) {
        plan += &format!("{f} memory\n");
    }
    plan
}

/// RIS with its reuse and denoiser left on while the demo's camera path replays, as a user
/// watches a flythrough with the stochastic path (`stochastic_soak_plan`), in the soaks'
/// smallest window at a quarter scale. Resident memory every 50 frames, judged by
/// `memory::judge_soak_compiling` after a warm-up of 300 (docs/testing.md "Soaks").
///
/// The lengths are the fewest that prove a bound of 4 KiB a frame, measured on a recording of
/// this schedule with memory every 10 frames (`viewer::soak_lengths` with
/// `LAMPSHADE_SOAK=stochastic`): 191-195 MiB from frame 50 to 3,000, wandering by 2 MiB as the
/// reservoirs and the denoiser's regions are made anew; no clean window failed, and a leak of 4
/// KiB a frame added to it was caught by every window of 2,050 judged frames (14 of 14), while
/// 1,750 missed it in 6 of 20 and 750 in 19 of 40.
#[test]
fn riss_reuse_and_denoiser_on_a_replaying_path_run_in_constant_memory() {
    need_display!();
    const FRAMES: u64 = 2350;
    const WARMUP: u64 = 300;
    let dir = out_dir("stochastic-soak");
    let script = dir.join("soak.script");
    let mut plan = stochastic_soak_plan(FRAMES, 50);
    plan += &format!("{0} view lit\n{1} screenshot last.png\n{1} quit\n", FRAMES + 1, FRAMES + 2);
    std::fs::write(&script, plan).unwrap();
    let out = view("demo", &script, &["--size", ATLAS_SOAK_WINDOW, "--no-state"], &dir);
    let stdout = text(&out).0;
    if !judge_memory_lines(&stdout, FRAMES / 50, WARMUP, " with RIS's reuse and denoiser on a replaying path") {
        return;
    }
    let doc = json(&dir, "last-viewport.json");
    assert!(doc["ris_samples"].as_u64().is_some_and(|k| k > 0), "RIS was off at the end: {doc}");
    assert!(lit_share(&load(&dir, "last-viewport.png")) > 0.05, "the last viewport is black");
}
