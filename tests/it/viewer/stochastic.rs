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
