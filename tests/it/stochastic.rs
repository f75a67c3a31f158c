//! The stochastic estimators (`renderer::stochastic`) held to their expectation: N frames with
//! different noise seeds against brute force in linear f32 (`oracle::expectation`: per pixel
//! and per region, Bonferroni at 1e-3 for the whole test), a planted bias the same test must
//! catch, and the same seed giving the same bytes.

use crate::common::{gpu, hard_case_size, scene, HARD_CASES};
use lampshade::headless::render_image;
use lampshade::oracle::expectation::{expectation, Expectation, ExpectationTest};
use lampshade::renderer::{AccumFormat, CullingMode, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::Scene;
use lampshade::LayoutChoice;

/// Full precision (the reference layout, an Rgba32Float accumulation, whose per-light clamp is
/// off), shadows as the default casts them (the sun's and the spots').
fn base(culling: CullingMode) -> Settings {
    Settings {
        culling,
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        count_ideal: false,
        ..Settings::default()
    }
}

fn ris(culling: CullingMode, samples: u32, candidates: u32) -> Settings {
    Settings { ris_samples: samples, ris_candidates: candidates, ..base(culling) }
}

fn culled(culling: CullingMode, threshold: f32) -> Settings {
    Settings { stochastic_culling: true, stochastic_threshold: threshold, ..base(culling) }
}

fn planted(s: Settings) -> Settings {
    Settings { planted_bias: 0.97, ..s }
}

fn test_of(scene: &Scene, settings: &Settings, size: (u32, u32), frames: u32) -> Expectation {
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, settings).expect("renderer");
    let t = ExpectationTest { frames, ..Default::default() };
    expectation(gpu, &mut r, scene, settings, size, &t).expect("expectation test")
}

fn show(what: &str, e: &Expectation) -> String {
    let region = e.regions.iter().cloned().fold(0.0, f64::max);
    format!(
        "{what}: {} px ({} steady); worst |t| {:.2} at {:?} (mean {:.4e}, brute force {:.4e}, sd {:.3e}), above {:.2}, \
         limit {:.2}; beyond 3: {} (independent pixels: {:.1}); regions' worst {region:.2}, limit {:.2}; bias {:+.4}",
        e.pixels,
        e.steady,
        e.worst_pixel,
        e.worst_at,
        e.worst_mean,
        e.worst_reference,
        e.worst_deviation,
        e.worst_above,
        e.pixel_limit,
        e.beyond_three,
        e.beyond_three_expected,
        e.region_limit,
        e.relative_bias,
    )
}

/// RIS with 16 samples of 64 candidates, enough for the per-pixel test, on every hard case
/// (the list modes in turn), shadows as the default casts them, at half each case's size
/// (what makes a case hard is its geometry and lights, not its pixel count), 32 frames each.
#[test]
fn reservoir_resampling_is_unbiased_on_the_hard_cases() {
    let modes = [CullingMode::Tiled, CullingMode::Clustered, CullingMode::Zbin];
    let mut failures = Vec::new();
    for (i, name) in HARD_CASES.iter().enumerate() {
        let s = ris(modes[i % 3], 16, 64);
        let (w, h) = hard_case_size(name);
        let e = test_of(&scene(name), &s, (w / 2, h / 2), 32);
        if !e.passed() {
            failures.push(show(&format!("{name} {:?}", s.culling), &e));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// RIS with few samples (1 and 2 of 8 candidates) is heavy-tailed at a pixel: its regions and
/// the upper side of its pixels (`Expectation::passed_skewed`), 64 frames.
#[test]
fn reservoir_resampling_with_few_samples_is_unbiased_in_its_regions() {
    for (name, s) in [
        ("demo", ris(CullingMode::Tiled, 2, 8)),
        ("demo", ris(CullingMode::Zbin, 1, 8)),
        ("sphere-wall", ris(CullingMode::Clustered, 1, 8)),
    ] {
        let e = test_of(&scene(name), &s, (96, 54), 64);
        assert!(e.passed_skewed(), "{}", show(name, &e));
    }
}

/// Stochastic light culling, unbiased on every culling mode (stencil volumes included): culling
/// only skips work, so each mode's frame of a noise seed is the same random frame, which the
/// exact oracle holds to brute force over that frame's drawn ranges (every mode, seeds 1 to 3,
/// no pixel missing or adding light beyond the rounding); and the mean of that frame over the
/// seeds is held to brute force over the exact frame on `stencil-invert` at the default
/// threshold (64 frames) and `zbin` at threshold 1 (every contribution randomised, so a pixel's
/// tail of rarely reaching lights is longer: 256 frames).
#[test]
fn stochastic_culling_is_unbiased_on_every_mode() {
    let gpu = gpu();
    let demo = scene("demo");
    let mut failures = Vec::new();
    let mut renderer = lampshade::oracle::renderer(gpu).expect("renderer");
    let scope = lampshade::oracle::Scope {
        paths: vec![lampshade::renderer::RenderPath::Deferred],
        modes: CullingMode::ALL.to_vec(),
    };
    for seed in 1..=3 {
        let s = Settings { noise_seed: seed, ..culled(CullingMode::Volume, 0.25) };
        let results =
            lampshade::oracle::check_scene(gpu, &mut renderer, &demo, &s, (96, 54), &scope, false).expect("the oracle");
        assert_eq!(results.len(), CullingMode::ALL.len());
        for (m, _) in results.iter().filter(|(m, _)| m.failed() || m.refused.is_some()) {
            failures.push(format!("seed {seed}, {}: {} missed, {} extra, {:?}", m.mode, m.missed, m.extra, m.refused));
        }
    }
    for (s, frames) in [(culled(CullingMode::StencilInvert, 0.25), 64), (culled(CullingMode::Zbin, 1.0), 256)] {
        let e = test_of(&demo, &s, (96, 54), frames);
        if !e.passed() {
            failures.push(show(&format!("{:?} at {}", s.culling, s.stochastic_threshold), &e));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The share of each pixel's light that the lights of odd index carry (brute force over them
/// alone against brute force over all), at the lit pixels of `scene` drawn with `settings`.
fn odd_shares(scene: &Scene, settings: &Settings, (w, h): (u32, u32)) -> Vec<f32> {
    let gpu = gpu();
    let exact = settings.made_exact();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &exact).expect("renderer");
    let mut sums = Vec::new();
    let mut odd = scene.clone();
    let lights: Vec<_> = scene.lights.iter().cloned().enumerate().filter(|(i, _)| i % 2 == 1).map(|(_, l)| l).collect();
    *odd.lights_mut() = lights;
    for s in [scene, &odd] {
        render_image(gpu, &mut r, s, &exact, w, h).expect("render");
        let b = r.last_frame().brute_force(gpu).expect("brute force");
        sums.push(b.diffuse.iter().zip(&b.specular).map(|(d, s)| d.iter().chain(s).sum::<f32>()).collect::<Vec<f32>>());
    }
    sums[0].iter().zip(&sums[1]).filter(|(all, _)| **all > 0.0).map(|(all, odd)| odd / all).collect()
}

/// x0.97 on the lights of odd index, which carry at least 20% of the light at most of the
/// pixels, fails each estimator's test at the frames the test draws; the same run without it
/// passes. RIS: 2 samples of 8 on `demo`, 64 frames, and 2 of 8 on the clustered lists with 4
/// neighbours' reuse, 128 frames (its neighbours share samples, so its regions' means vary
/// more: 1 sample from the z-bins' longer ranges left the bias at |t| 2.05 of the regions' 4.5
/// at 64 frames, and 3.72 of 4.33 at 192x108 and 128); stochastic culling: threshold 1 on
/// `sphere-wall` (4,096 lights), 256 frames (its pixels share each frame's ranges, so a frame's
/// region means vary together: it takes more frames to see 1.5% in them).
#[test]
fn a_planted_bias_fails_the_unbiasedness_tests() {
    for (name, s, frames, size) in [
        ("demo", ris(CullingMode::Tiled, 2, 8), 64, (96, 54)),
        ("demo", reused(CullingMode::Clustered, 2, 4, false), 128, (96, 54)),
        ("sphere-wall", culled(CullingMode::Tiled, 1.0), 256, (96, 54)),
    ] {
        let sc = scene(name);
        let shares = odd_shares(&sc, &s, size);
        let carrying = shares.iter().filter(|&&x| x >= 0.2).count();
        assert!(carrying * 2 > shares.len(), "{name}: odd lights carry 20% at {carrying} of {} pixels", shares.len());
        let clean = test_of(&sc, &s, size, frames);
        assert!(clean.passed_skewed(), "{}", show(name, &clean));
        let biased = test_of(&sc, &planted(s.clone()), size, frames);
        assert!(!biased.passed_skewed(), "the planted bias went unseen: {}", show(name, &biased));
    }
}

/// The same noise seed gives the same frame, byte for byte; another seed another frame.
#[test]
fn the_same_seed_gives_the_same_bytes() {
    let gpu = gpu();
    let demo = scene("demo");
    for s in
        [ris(CullingMode::Zbin, 2, 8), culled(CullingMode::StencilInvert, 0.5), reused(CullingMode::Tiled, 2, 4, true)]
    {
        let mut frames = Vec::new();
        for seed in [7, 7, 8] {
            let s = Settings { noise_seed: seed, ..s.clone() };
            let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).expect("renderer");
            let (image, _) = render_image(gpu, &mut r, &demo, &s, 96, 54).expect("render");
            let (d, sp) = r.last_frame().read_accumulation(gpu).expect("accumulation");
            frames.push((image.into_raw(), d, sp));
        }
        assert!(frames[0] == frames[1], "{:?}: seed 7 twice differs", s.culling);
        assert!(frames[0].1 != frames[2].1, "{:?}: seeds 7 and 8 draw the same light", s.culling);
    }
}

fn reused(culling: CullingMode, samples: u32, spatial: u32, temporal: bool) -> Settings {
    Settings { ris_spatial: spatial, ris_temporal: temporal, ..ris(culling, samples, 8) }
}

/// ReSTIR's spatial reuse with its 1/Z weights is unbiased: RIS of 8 candidates with 4 and 8
/// neighbours, held to brute force in its regions and the upper side of its pixels (one sample
/// of 8 is heavy-tailed at a pixel, and reuse does not make it less so where few neighbours
/// are alike), 64 frames, each frame's reuse independent of the last (temporal reuse off). On
/// `demo` it also lowers the noise: the same configuration without reuse is noisier per lit
/// pixel. (On `sphere-wall` at this size it does not: 16 pixels span several spheres, whose
/// normals leave few neighbours alike, and those taken rarely share the pixel's lights.)
#[test]
fn spatial_reuse_is_unbiased_in_its_regions() {
    for (name, s) in
        [("demo", reused(CullingMode::Zbin, 1, 4, false)), ("sphere-wall", reused(CullingMode::Clustered, 2, 8, false))]
    {
        let e = test_of(&scene(name), &s, (96, 54), 64);
        assert!(e.passed_skewed(), "{}", show(name, &e));
        if name != "demo" {
            continue;
        }
        let plain = test_of(&scene(name), &Settings { ris_spatial: 0, ..s.clone() }, (96, 54), 64);
        assert!(
            e.relative_noise < plain.relative_noise,
            "{name}: spatial reuse did not lower the noise: {:.4} against {:.4} without",
            e.relative_noise,
            plain.relative_noise
        );
    }
}

/// The mean absolute difference between two accumulations' channels.
fn mean_difference(a: &(Vec<f32>, Vec<f32>), b: &(Vec<f32>, Vec<f32>)) -> f64 {
    let d = |x: &[f32], y: &[f32]| x.iter().zip(y).map(|(p, q)| f64::from((p - q).abs())).sum::<f64>();
    (d(&a.0, &b.0) + d(&a.1, &b.1)) / (a.0.len() + a.1.len()).max(1) as f64
}

/// The accumulation (diffuse, specular) of `s` drawn on `scene` at `size` by `r`.
fn accumulation(scene: &Scene, s: &Settings, r: &mut Renderer, (w, h): (u32, u32)) -> (Vec<f32>, Vec<f32>) {
    render_image(gpu(), r, scene, s, w, h).expect("render");
    r.last_frame().read_accumulation(gpu()).expect("accumulation")
}

/// The accumulation of `s` made exact, by a renderer of its own.
fn exact_accumulation(scene: &Scene, s: &Settings, size: (u32, u32)) -> (Vec<f32>, Vec<f32>) {
    let exact = s.made_exact();
    accumulation(scene, &exact, &mut Renderer::new(gpu(), OUTPUT_FORMAT, &exact).expect("renderer"), size)
}

/// The mean absolute difference from `reference` of `s` drawn by `r` with the noise seeds
/// `seeds`, one frame each, in order.
fn errors_by_seed(
    scene: &Scene,
    s: &Settings,
    r: &mut Renderer,
    reference: &(Vec<f32>, Vec<f32>),
    seeds: std::ops::RangeInclusive<u32>,
    size: (u32, u32),
) -> Vec<f64> {
    seeds
        .map(|seed| {
            mean_difference(&accumulation(scene, &Settings { noise_seed: seed, ..s.clone() }, r, size), reference)
        })
        .collect()
}

/// Temporal reuse on a still camera: each frame's samples are combined with the history of the
/// frames before at the same surface, so the error against the exact frame falls frame after
/// frame, towards what one sample drawn in proportion to the target leaves (RIS's floor: the
/// target has no shadow, so it does not fall to 0). The mean absolute difference of the
/// accumulation from the exact one (the same configuration with RIS off) after 8 frames is
/// below the first frame's and below that of frame 8 drawn alone (the same seed without
/// temporal reuse: a history never read, or rejected everywhere, draws exactly that frame),
/// with and without spatial reuse.
#[test]
fn temporal_reuse_converges_on_a_still_camera() {
    let demo = scene("demo");
    for s in [reused(CullingMode::Tiled, 1, 0, true), reused(CullingMode::Clustered, 1, 4, true)] {
        let reference = exact_accumulation(&demo, &s, (96, 54));
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &s).expect("renderer");
        let errors = errors_by_seed(&demo, &s, &mut r, &reference, 1..=8, (96, 54));
        let alone = Settings { noise_seed: 8, ris_temporal: false, ..s.clone() };
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &alone).expect("renderer");
        let alone = mean_difference(&accumulation(&demo, &alone, &mut r, (96, 54)), &reference);
        assert!(
            errors[7] < errors[0] && errors[7] < alone,
            "{:?} spatial {}: mean error by frame {errors:?}, frame 8 alone {alone}",
            s.culling,
            s.ris_spatial
        );
        eprintln!("{:?} spatial {}: mean error by frame {errors:?}, frame 8 alone {alone}", s.culling, s.ris_spatial);
    }
}

/// The denoiser (temporal accumulation and an a-trous filter guided by the variance) lowers
/// the error it is there to lower: on a still camera, the mean absolute difference of the
/// accumulation from the exact one is lower with it than without it at the same seeds and
/// reservoirs, on the first frame (the filter alone, guided by the 3x3 variance) and on the
/// eighth (with seven frames of history), with spatial and temporal reuse on. It is biased by
/// design, so no test holds it to its expectation; the bench reports its error and bias.
#[test]
fn the_denoiser_lowers_the_error() {
    let demo = scene("demo");
    let s = Settings { ris_denoise: true, ..reused(CullingMode::Tiled, 1, 4, true) };
    let raw = Settings { ris_denoise: false, ..s.clone() };
    let reference = exact_accumulation(&demo, &s, (192, 108));
    let errors = |s: &Settings| {
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, s).expect("renderer");
        errors_by_seed(&demo, s, &mut r, &reference, 1..=8, (192, 108))
    };
    let (denoised, raw) = (errors(&s), errors(&raw));
    eprintln!("mean error by frame, denoised {denoised:?}, raw {raw:?}");
    for frame in [0, 7] {
        assert!(
            denoised[frame] < raw[frame],
            "frame {}: the denoiser did not lower the error: {denoised:?} against {raw:?}",
            frame + 1
        );
    }
}

/// The `converge` view averages RIS's frames while the camera, the lights and the settings but
/// the seed hold still: its accumulation after 16 frames lies nearer the exact one than the
/// first frame's (mean absolute difference below half: the noise of a mean of 16 falls to a
/// quarter); a setting changed starts it anew (the next frame is as far as a first).
#[test]
fn the_converge_view_averages_riss_frames() {
    let demo = scene("demo");
    let s = Settings { debug_view: lampshade::renderer::DebugView::Converge, ..ris(CullingMode::Clustered, 1, 8) };
    let reference = exact_accumulation(&demo, &s, (96, 54));
    let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &s).expect("renderer");
    let errors = errors_by_seed(&demo, &s, &mut r, &reference, 1..=16, (96, 54));
    assert!(errors[15] < 0.5 * errors[0], "mean error by frame {errors:?}");
    let changed = Settings { noise_seed: 17, ris_candidates: 9, ..s.clone() };
    let anew = mean_difference(&accumulation(&demo, &changed, &mut r, (96, 54)), &reference);
    assert!(anew > 0.5 * errors[0], "a changed setting did not start the average anew: {anew} after {errors:?}");
}
