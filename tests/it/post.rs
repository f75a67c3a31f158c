//! The HDR post chain: bloom, auto-exposure, tone curves, grading.

use crate::common;

use crate::common::{gpu, scene};
use lampshade::headless::render_image;
use lampshade::renderer::post::{self, PostImage, Tonemap};
use lampshade::renderer::settings::Focus;
use lampshade::renderer::{Renderer, Settings, OUTPUT_FORMAT};
use lampshade::Scene;

fn renderer(settings: &Settings) -> Renderer {
    Renderer::new(gpu(), OUTPUT_FORMAT, settings).expect("renderer")
}

/// Renders one frame and returns the output, the HDR scene colour the chain started from, and
/// the bloomed colour when bloom ran.
fn frame(
    r: &mut Renderer,
    scene: &Scene,
    s: &Settings,
    w: u32,
    h: u32,
) -> (image::RgbaImage, Vec<f32>, Option<Vec<f32>>) {
    let (img, _) = render_image(gpu(), r, scene, s, w, h).expect("render");
    let hdr = r.last_frame().read_post_image(gpu(), PostImage::Hdr).expect("hdr readback").expect("the chain ran");
    let bloomed =
        if s.bloom { r.last_frame().read_post_image(gpu(), PostImage::Bloomed).expect("readback") } else { None };
    (img, hdr, bloomed)
}

fn quiet() -> Settings {
    Settings { count_fragments: false, timestamps: false, ..Settings::default() }
}

fn max_step(a: &image::RgbaImage, b: &image::RgbaImage) -> (u8, usize) {
    let mut worst = 0u8;
    let mut over = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
        worst = worst.max(d);
        over += (d > 1) as usize;
    }
    (worst, over)
}

fn srgb8(v: f64) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let e = if v <= 0.0031308 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    (e * 255.0).round() as u8
}

fn luminance(c: &[f32]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// With every effect off the frame never enters the chain (bit for bit today's); through the
/// chain with the built-in identity LUT and ACES, it is within one 8-bit step of today's: the
/// chain starts from the fp16 HDR scene colour (half an fp16 step, 2^-12 relative, before the
/// curve) and the grading's sRGB encode/decode round trip and trilinear lookup are exact up to
/// f32 rounding. Both on `demo` and on `glass` (blended surfaces: compose in HDR, forward,
/// then compose's own tonemap against the chain's).
#[test]
fn every_effect_off_is_todays_frame_and_the_identity_lut_is_within_one_step() {
    for name in ["demo", "glass"] {
        let sc = scene(name);
        let off = quiet();
        assert!(!post::chain_active(off.debug_view, &off.post_options()));
        let (today, stats) = render_image(gpu(), &mut renderer(&off), &sc, &off, 160, 90).unwrap();
        assert!(stats.post.is_none(), "{name}: no chain with every effect off");
        let id = Settings { lut: Some("identity".into()), ..off.clone() };
        let (graded, stats) = render_image(gpu(), &mut renderer(&id), &sc, &id, 160, 90).unwrap();
        assert!(stats.post.is_some_and(|p| p.ran("grading")), "{name}: the chain ran");
        let (worst, over) = max_step(&today, &graded);
        eprintln!("{name}: identity LUT through the chain, worst {worst} step(s), {over} pixels over 1");
        assert!(worst <= 1, "{name}: identity LUT moved a pixel by {worst} steps");
        assert!(common::lit_share(&graded) > 0.3, "{name}: blank frame");
    }
}

/// Each curve, run by the chain on the GPU, gives its CPU twin (`Tonemap::apply`, f64) of the
/// HDR colour the chain read, within one 8-bit step; and every curve maps 0 to 0 and is
/// monotonic (the twins, `post::tests`).
#[test]
fn every_tonemap_on_the_gpu_matches_its_cpu_twin() {
    let sc = scene("demo");
    for t in Tonemap::ALL {
        // ACES is also drawn through the chain here (with the identity LUT).
        let lut = (t == Tonemap::Aces).then(|| "identity".to_string());
        let s = Settings { tonemap: t, exposure: 1.7, lut, ..quiet() };
        let mut r = renderer(&s);
        let (img, hdr, _) = frame(&mut r, &sc, &s, 160, 90);
        let mut worst = 0u8;
        for (i, p) in img.pixels().enumerate() {
            let c = &hdr[i * 4..i * 4 + 3];
            let want = t.apply([c[0] as f64 * 1.7, c[1] as f64 * 1.7, c[2] as f64 * 1.7]);
            for k in 0..3 {
                worst = worst.max(p[k].abs_diff(srgb8(want[k])));
            }
        }
        assert!(worst <= 1, "{t:?}: the GPU curve is {worst} steps from its CPU twin");
        eprintln!("{t:?}: worst {worst} steps from the twin");
    }
}

/// Bloom spreads only from pixels above its threshold: with the threshold above every pixel
/// the bloomed colour is the HDR colour bit for bit. And it conserves the bright pass's light:
/// summed over the full-size pixels, what bloom adds is `intensity` × the light above the
/// threshold (computed here in f64 from the HDR colour the chain read), within the bound
/// derived in `post::bloom_energy_bound` (the chain's f32 rounding, 3.0e-6 relative), plus the
/// bright pass's own rounding (at most 8 f32 roundings of each bright pixel's colour, also
/// covering pixels within rounding of the threshold) and the subtraction bloomed − HDR here
/// (half an f32 step of each bloomed value). 256x128 is divisible by 32, so nothing is lost at
/// the edges; at 250x130 (odd levels) light can only be lost.
#[test]
fn bloom_spreads_only_from_pixels_above_its_threshold_and_conserves_their_light() {
    let sc = scene("demo");
    let above_all = Settings { bloom: true, bloom_threshold: 1e6, ..quiet() };
    let (_, hdr, bloomed) = frame(&mut renderer(&above_all), &sc, &above_all, 256, 128);
    assert_eq!(hdr, bloomed.expect("bloomed"), "nothing is above the threshold, yet bloom added light");
    let brightest = hdr.chunks_exact(4).map(luminance).fold(0.0f32, f32::max);
    assert!(brightest > 0.1, "{brightest}");

    for (w, h, exact) in [(256u32, 128u32, true), (250, 130, false)] {
        for threshold in [0.3 * brightest, 0.8 * brightest] {
            let intensity = 0.75f32;
            let s = Settings { bloom: true, bloom_threshold: threshold, bloom_intensity: intensity, ..quiet() };
            let (_, hdr, bloomed) = frame(&mut renderer(&s), &sc, &s, w, h);
            let bloomed = bloomed.expect("bloomed");
            for ch in 0..3 {
                let (mut bright, mut near, mut added, mut magnitude) = (0f64, 0f64, 0f64, 0f64);
                let mut bright_pixels = 0;
                for (c, b) in hdr.chunks_exact(4).zip(bloomed.chunks_exact(4)) {
                    let l = luminance(c) as f64;
                    let t = threshold as f64;
                    if l > t {
                        bright += c[ch] as f64 * (l - t) / l;
                        bright_pixels += 1;
                    }
                    if l > t * (1.0 - 1e-5) {
                        near += c[ch].abs() as f64;
                    }
                    added += b[ch] as f64 - c[ch] as f64;
                    magnitude += b[ch].abs() as f64;
                }
                assert!(bright_pixels > 0 && bright > 0.0, "threshold {threshold}: no pixel above it");
                let i = intensity as f64;
                let bound = i * (post::bloom_energy_bound() * bright + 8.0 * 2f64.powi(-24) * near)
                    + 2f64.powi(-24) * magnitude;
                let excess = added - i * bright;
                eprintln!("bloom {w}x{h} threshold {threshold:.3} ch {ch}: added {added:.4}, I x bright {:.4}, excess {excess:.3e}, bound {bound:.3e}", i * bright);
                assert!(excess <= bound, "{w}x{h} threshold {threshold} channel {ch}: added {added}, {excess} over intensity x bright {}, bound {bound}", i * bright);
                if exact {
                    assert!(excess.abs() <= bound, "{w}x{h} threshold {threshold} channel {ch}: added {added}, intensity x bright {}, bound {bound}", i * bright);
                } else {
                    assert!(added > 0.5 * i * bright, "{w}x{h}: the odd sizes lost more than half the bloom");
                }
            }
        }
    }
}

/// The mean log2 luminance of the histogram's bins as `cs_adapt` takes it (bin centres, black
/// left out), from the HDR colour on the CPU.
fn histogram_mean(hdr: &[f32]) -> f64 {
    let (lo, hi) = (post::HIST_LOG_MIN, post::HIST_LOG_MAX);
    let bins = post::HIST_BINS;
    let w = ((hi - lo) / (bins - 1) as f32) as f64;
    let (mut n, mut sum) = (0f64, 0f64);
    for c in hdr.chunks_exact(4) {
        let l = luminance(c);
        if l.is_nan() || l < lo.exp2() {
            continue;
        }
        let t = (l.log2() - lo) / (hi - lo);
        let b = 1 + ((t * (bins - 1) as f32).floor().clamp(0.0, (bins - 2) as f32)) as u32;
        n += 1.0;
        sum += lo as f64 + (b as f64 - 0.5) * w;
    }
    sum / n
}

/// Auto-exposure: the first frame starts at its own histogram mean; after every light is made
/// 8 times brighter the adapted log2 luminance approaches the new mean by exactly
/// `adapt_rate(speed)` of the remaining way per frame (a fixed 1/60 s), never overshooting or
/// turning back, and is within 0.01 stops of it by frame N = ceil(ln(0.01 / gap) / ln(1 − rate)):
/// the exposed mean luminance is then the target within 0.01 stops (the mean itself is taken
/// at bin centres, 1/3 stop bins).
#[test]
fn auto_exposure_converges_to_the_target_without_oscillating() {
    let mut sc = scene("demo");
    let speed = 20.0;
    let s = Settings { auto_exposure: true, adaptation_speed: speed, target_luminance: 0.18, ..quiet() };
    let mut r = renderer(&s);
    let (_, hdr, _) = frame(&mut r, &sc, &s, 160, 90);
    let (adapted, measured) = r.last_frame().exposure_state(gpu()).unwrap().expect("state");
    let cpu = histogram_mean(&hdr);
    assert!((measured as f64 - cpu).abs() < 1e-3, "histogram mean {measured} on the GPU, {cpu} on the CPU");
    assert_eq!(adapted, measured, "the first frame starts at its own luminance");

    for l in sc.lights_mut() {
        match l {
            lampshade::scene::Light::Point(p) => p.intensity *= 8.0,
            lampshade::scene::Light::Spot(p) => p.intensity *= 8.0,
        }
    }
    if let Some(sun) = &mut sc.sun {
        sun.intensity *= 8.0;
    }
    sc.ambient *= 8.0;
    let rate = post::adapt_rate(speed) as f64;
    let (_, hdr, _) = frame(&mut r, &sc, &s, 160, 90);
    let (mut a, m) = r.last_frame().exposure_state(gpu()).unwrap().expect("state");
    let target = histogram_mean(&hdr);
    assert!((m as f64 - target).abs() < 1e-3, "{m} against {target}");
    let gap0 = target - adapted as f64;
    assert!(gap0 > 1.0, "the brighter lights raised the mean by only {gap0} stops");
    let frames = ((0.01 / gap0).ln() / (1.0 - rate).ln()).ceil() as usize;
    assert!(frames < 40, "{frames}");
    let mut previous = adapted as f64;
    for n in 1..=frames {
        if n > 1 {
            frame(&mut r, &sc, &s, 160, 90);
            a = r.last_frame().exposure_state(gpu()).unwrap().expect("state").0;
        }
        let a = a as f64;
        let expected = target - gap0 * (1.0 - rate).powi(n as i32);
        assert!((a - expected).abs() < 1e-3, "frame {n}: adapted {a}, the time step gives {expected}");
        assert!(
            a >= previous && a <= target + 1e-4,
            "frame {n}: {a} after {previous} (target {target}): not monotonic"
        );
        previous = a;
    }
    assert!((target - previous).abs() <= 0.01, "after {frames} frames {previous} is not within 0.01 of {target}");
    eprintln!("auto-exposure: gap {gap0:.3} stops, rate {rate:.4}, within 0.01 stop after {frames} frames ({previous:.4} of {target:.4})");
}

/// A malformed `.cube` file is an error naming the file and the line, from the knob (CLI,
/// scripts) and from the renderer when the file turns bad after it was set; never a panic.
#[test]
fn a_malformed_cube_file_is_an_error_not_a_panic() {
    // Under target/, emptied first: every file here is written by this test.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/post-tests/cube");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("good.cube");
    let mut text = String::from("LUT_3D_SIZE 2\n");
    for b in 0..2 {
        for g in 0..2 {
            for r in 0..2 {
                text += &format!("{r} {g} {b}\n");
            }
        }
    }
    std::fs::write(&good, &text).unwrap();
    let mut s = quiet();
    s.set("lut", good.to_str().unwrap()).expect("a good file");
    let sc = scene("spot");
    let mut r = renderer(&s);
    render_image(gpu(), &mut r, &sc, &s, 64, 36).expect("render with the good LUT");
    for (bad, why) in [
        ("LUT_3D_SIZE 2\n0 0 0\n", "needs 8 entries"),
        ("LUT_3D_SIZE 2\n0 0\n", "line 2"),
        ("LUT_3D_SIZE x\n", "whole number"),
        ("\u{0}\u{1}garbage", "before LUT_3D_SIZE"),
        ("LUT_3D_SIZE 2\nDOMAIN_MAX 0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n", "must exceed"),
    ] {
        let path = dir.join("bad.cube");
        std::fs::write(&path, bad).unwrap();
        let e = s.clone().set("lut", path.to_str().unwrap()).unwrap_err();
        assert!(e.contains(why) && e.contains("bad.cube"), "{e}");
        // Set while good, broken before the renderer reads it.
        let named = Settings { lut: Some(path.to_str().unwrap().into()), ..s.clone() };
        let e = render_image(gpu(), &mut r, &sc, &named, 64, 36).unwrap_err().to_string();
        assert!(e.contains(why), "{e}");
    }
    assert!(s.clone().set("lut", dir.join("missing.cube").to_str().unwrap()).unwrap_err().contains("cannot read"));
    let _ = std::fs::remove_dir_all(&dir);
}

fn linear(v: u8) -> f64 {
    let e = v as f64 / 255.0;
    if e <= 0.04045 {
        e / 12.92
    } else {
        ((e + 0.055) / 1.055).powf(2.4)
    }
}

/// Two frames through the chain (tone curve `none`, so the chain runs without changing the
/// picture's values) from one renderer: without and with `extra`, and the view-space points.
fn before_after(
    name: &str,
    extra: impl Fn(&mut Settings),
    w: u32,
    h: u32,
) -> (Scene, image::RgbaImage, image::RgbaImage, Vec<Option<glam::Vec3>>, Settings) {
    let sc = scene(name);
    let base = Settings { tonemap: Tonemap::None, exposure: 0.5, ..quiet() };
    let mut with = base.clone();
    extra(&mut with);
    let mut r = renderer(&base);
    let (a, _) = render_image(gpu(), &mut r, &sc, &base, w, h).unwrap();
    let (b, stats) = render_image(gpu(), &mut r, &sc, &with, w, h).unwrap();
    assert!(stats.post.is_some());
    let points = r.last_frame().view_positions(gpu()).unwrap();
    (sc, a, b, points, with)
}

/// Fog is `post::fog_amount` of each pixel's view-space point (f64 twin) mixed towards the
/// background colour, within one 8-bit step (the frame without fog is read back in 8 bits,
/// half a step, and the fogged one rounds once more); background pixels are unchanged; and the
/// amount grows monotonically with distance along every ray (the twin, sampled here along the
/// rays of the frame's pixels).
#[test]
fn fog_follows_its_formula_and_grows_with_depth() {
    let (sc, plain, fogged, points, s) = before_after(
        "demo",
        |s| {
            s.fog = true;
            s.fog_density = 0.03;
            s.fog_height_falloff = 0.2;
        },
        160,
        90,
    );
    let up = (sc.camera.rotation() * glam::DVec3::Y).to_array();
    // The fog colour is the background as the chain turned the sky (here: exposure, no curve).
    let fog = sc.background.to_array().map(|c| (c as f64 * s.exposure as f64).clamp(0.0, 1.0));
    let (mut worst, mut fogged_pixels) = (0u8, 0);
    for ((p, q), point) in plain.pixels().zip(fogged.pixels()).zip(&points) {
        match point {
            None => assert_eq!(p, q, "a background pixel changed"),
            Some(v) => {
                let v = v.as_dvec3().to_array();
                let f = post::fog_amount(v, up, s.fog_density as f64, s.fog_height_falloff as f64);
                fogged_pixels += (f > 0.1) as usize;
                for c in 0..3 {
                    let want = srgb8(linear(p[c]) * (1.0 - f) + fog[c] * f);
                    worst = worst.max(want.abs_diff(q[c]));
                }
                // Along this pixel's ray the amount never falls.
                let mut last = 0.0;
                for k in 1..=64 {
                    let t = k as f64 / 16.0;
                    let a = post::fog_amount(v.map(|x| x * t), up, s.fog_density as f64, s.fog_height_falloff as f64);
                    assert!(a >= last, "fog falls along a ray at {t} x {v:?}");
                    last = a;
                }
            }
        }
    }
    assert!(fogged_pixels > 1000, "only {fogged_pixels} pixels got over 10% fog");
    assert!(worst <= 1, "fog is {worst} steps from its formula");
    eprintln!("fog: {fogged_pixels} pixels over 10% fog, worst {worst} step(s) from the twin");
}

/// Depth of field copies every pixel whose circle of confusion (from its view depth, computed
/// here on the CPU) is under half a pixel, bit for bit, and blurs the rest.
#[test]
fn depth_of_field_leaves_in_focus_pixels_unchanged() {
    let (_, sharp, blurred, points, s) = before_after(
        "demo",
        |s| {
            s.dof = true;
            s.aperture = 12.0;
            s.focus_distance = Focus::Distance(20.0);
        },
        160,
        90,
    );
    let (mut in_focus, mut changed_out_of_focus) = (0, 0);
    for ((p, q), point) in sharp.pixels().zip(blurred.pixels()).zip(&points) {
        let coc = point.map_or(0.0, |v| {
            let z = -v.z as f64;
            (s.aperture as f64 * (z - 20.0).abs() / z).min(post::MAX_COC as f64)
        });
        // Away from the boundary, by more than f32 rounding of the same formula.
        if coc < 0.49 {
            assert_eq!(p, q, "a pixel in focus (CoC {coc}) changed");
            in_focus += point.is_some() as usize;
        } else if coc > 2.0 && p != q {
            changed_out_of_focus += 1;
        }
    }
    eprintln!("dof: {in_focus} surface pixels in focus unchanged, {changed_out_of_focus} out of focus blurred");
    assert!(in_focus > 100, "only {in_focus} surface pixels in focus");
    assert!(changed_out_of_focus > 1000, "only {changed_out_of_focus} out-of-focus pixels blurred");
}

/// `sc` scaled by `k` about the origin: its objects, its camera (position, near and far planes)
/// and its lights (positions and radii); the picture is the same up to the lights' falloff.
fn scaled(mut sc: Scene, k: f64) -> Scene {
    let scale = glam::DMat4::from_scale(glam::DVec3::splat(k));
    for o in &mut sc.objects {
        o.transform = scale * o.transform;
    }
    sc.camera.position *= k;
    sc.camera.near *= k;
    sc.camera.far *= k;
    for l in sc.lights_mut() {
        match l {
            lampshade::scene::Light::Point(p) => {
                p.position *= k;
                p.radius *= k as f32;
            }
            lampshade::scene::Light::Spot(s) => {
                s.position *= k;
                s.radius *= k as f32;
            }
        }
    }
    sc
}

/// Auto focus (the default) focuses where the camera looks, at any scene scale: on `demo`
/// scaled by 0.1 and by 10, with depth of field on (aperture 8), every pixel of the 9x9 window
/// round the screen's centre whose circle of confusion at the centre pixel's view depth
/// (computed here on the CPU from the read-back view positions) is under half a pixel equals
/// the frame without depth of field bit for bit (such a pixel is copied, so the bound is 0;
/// 0.49 leaves f32 rounding of the same formula), and there are a dozen or more of them (the
/// centre sits on the floor, whose depth changes fast from row to row); while at the old fixed
/// focus of 10 units no pixel of the window is in focus, the centre pixel's CoC is over 2 px
/// and most of the window is blurred.
#[test]
fn auto_focus_keeps_the_screen_centre_sharp_at_any_scene_scale() {
    let (w, h) = (160u32, 90u32);
    let coc = |z: f64, focus: f64| (8.0 * (z - focus).abs() / z).min(post::MAX_COC as f64);
    for k in [0.1, 10.0] {
        let sc = scaled(scene("demo"), k);
        let base = Settings { tonemap: Tonemap::None, exposure: 0.5, ..quiet() };
        let auto = Settings { dof: true, aperture: 8.0, ..base.clone() };
        assert_eq!(auto.focus_distance, Focus::Auto, "auto is the default");
        let fixed = Settings { focus_distance: Focus::Distance(10.0), ..auto.clone() };
        let mut r = renderer(&base);
        let (sharp, _) = render_image(gpu(), &mut r, &sc, &base, w, h).unwrap();
        let (blurred, _) = render_image(gpu(), &mut r, &sc, &fixed, w, h).unwrap();
        let (focused, stats) = render_image(gpu(), &mut r, &sc, &auto, w, h).unwrap();
        assert!(stats.post.is_some_and(|p| p.ran("dof")), "x{k}: depth of field ran");
        let points = r.last_frame().view_positions(gpu()).unwrap();
        let centre = points[((h / 2) * w + w / 2) as usize].expect("a surface at the screen's centre");
        let z0 = -centre.z as f64;
        assert!(coc(z0, 10.0) > 2.0, "x{k}: focus 10 leaves the centre (depth {z0}) sharp; the test proves nothing");
        let (mut in_focus, mut in_focus_fixed, mut blurred_by_fixed) = (0, 0, 0);
        for y in h / 2 - 4..=h / 2 + 4 {
            for x in w / 2 - 4..=w / 2 + 4 {
                let Some(v) = points[(y * w + x) as usize] else { continue };
                if coc(-v.z as f64, z0) < 0.49 {
                    assert_eq!(sharp.get_pixel(x, y), focused.get_pixel(x, y), "x{k}: ({x}, {y}) in focus changed");
                    in_focus += 1;
                }
                in_focus_fixed += (coc(-v.z as f64, 10.0) < 0.49) as usize;
                blurred_by_fixed += (sharp.get_pixel(x, y) != blurred.get_pixel(x, y)) as usize;
            }
        }
        eprintln!(
            "x{k}: centre depth {z0:.3}, {in_focus}/81 in focus unchanged, focus 10 changed {blurred_by_fixed}/81"
        );
        assert!(in_focus >= 12, "x{k}: only {in_focus} of the 81 centre pixels in focus");
        assert_eq!(in_focus_fixed, 0, "x{k}: focus 10 has centre pixels in focus");
        assert!(blurred_by_fixed >= 40, "x{k}: focus 10 changed only {blurred_by_fixed} of the 81 centre pixels");
    }
}

/// Edge AA (seed 002) and FXAA change only pixels on their edge mask (the `edges` view, which
/// marks the mask with full green) and leave every other pixel bit for bit; both change some.
#[test]
fn edge_aa_and_fxaa_change_only_pixels_on_their_edge_mask() {
    for aa in [post::Aa::Edge, post::Aa::Fxaa] {
        let (sc, plain, smoothed, _, s) = before_after("demo", |s| s.aa = aa, 160, 90);
        let view = Settings { debug_view: lampshade::renderer::DebugView::Edges, ..s.clone() };
        let (mask, _) = render_image(gpu(), &mut renderer(&view), &sc, &view, 160, 90).unwrap();
        let (mut changed, mut on_mask) = (0, 0);
        for ((p, q), m) in plain.pixels().zip(smoothed.pixels()).zip(mask.pixels()) {
            let edge = m[1] == 255;
            on_mask += edge as usize;
            if p != q {
                changed += 1;
                assert!(edge, "{aa:?} changed a pixel off its mask");
            }
        }
        assert!(changed > 100, "{aa:?} changed only {changed} pixels");
        assert!(on_mask < 160 * 90 / 2, "{aa:?}: the mask covers {on_mask} pixels");
        eprintln!("{aa:?}: {changed} pixels changed, {on_mask} on the mask of {}", 160 * 90);
    }
}

/// Fog runs after tone mapping and grading, so it must fade geometry towards the sky as those
/// passes turned it, not towards the raw background colour: under thick fog, with ACES,
/// auto-exposure and the identity LUT, every geometry pixel is within one step of the sky's own
/// pixels (the fog amount is 1 - exp(-30 d) > 1 - 1e-6 at the nearest demo point, d > 0.5).
#[test]
fn thick_fog_turns_geometry_into_the_sky_beside_it() {
    let sc = scene("demo");
    let s = Settings {
        fog: true,
        fog_density: 30.0,
        fog_height_falloff: 0.0,
        auto_exposure: true,
        lut: Some("identity".into()),
        ..quiet()
    };
    let mut r = renderer(&s);
    let (img, stats) = render_image(gpu(), &mut r, &sc, &s, 160, 90).unwrap();
    assert!(stats.post.is_some());
    let points = r.last_frame().view_positions(gpu()).unwrap();
    let sky: Vec<[u8; 3]> =
        img.pixels().zip(&points).filter(|(_, p)| p.is_none()).map(|(q, _)| [q[0], q[1], q[2]]).collect();
    assert!(sky.len() > 100, "too little sky ({} pixels)", sky.len());
    let (mut worst, mut geometry) = (0u8, 0);
    for (q, p) in img.pixels().zip(&points) {
        if p.is_some() {
            geometry += 1;
            for c in 0..3 {
                worst = worst.max(q[c].abs_diff(sky[0][c]));
            }
        }
    }
    // The sky itself is one colour (bloom is off).
    assert!(sky.iter().all(|k| k == &sky[0]), "the sky is not one colour");
    assert!(geometry > 1000, "too little geometry ({geometry} pixels)");
    assert!(worst <= 1, "thick fog is {worst} steps from the sky's colour {:?}", sky[0]);
}

/// Seed 002's distortion moves only pixels under a distorting surface: on `glass` (its panes
/// and boxes distort), every pixel that changes has an offset in the distortion buffer, many
/// do change, and each changed pixel is a copy of the undistorted frame's pixel at the offset
/// the buffer gives (or its own, where that source lies in front of the glass). A scene without
/// distorting materials (`demo`) is unchanged bit for bit.
#[test]
fn distortion_moves_only_pixels_under_a_distorting_surface() {
    let (w, h) = (192u32, 108u32);
    let mut sc = scene("glass");
    sc.lights_mut().truncate(64);
    let base = Settings { tonemap: Tonemap::None, exposure: 0.5, ..quiet() };
    let with = Settings { distortion: true, ..base.clone() };
    let mut r = renderer(&base);
    let (plain, _) = render_image(gpu(), &mut r, &sc, &base, w, h).unwrap();
    let (bent, _) = render_image(gpu(), &mut r, &sc, &with, w, h).unwrap();
    let buffer = r.last_frame().read_post_image(gpu(), PostImage::Distortion).unwrap().expect("the chain ran");
    let points = r.last_frame().view_positions(gpu()).unwrap();
    let (mut changed, mut under, mut in_front) = (0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let d = &buffer[4 * (y * w + x) as usize..][..4];
            let covered = d[3] > 0.0;
            under += covered as usize;
            let (p, q) = (plain.get_pixel(x, y), bent.get_pixel(x, y));
            // The source the offset names (view y up, screen y down), as the effect rounds it.
            let sx = (x as f32 + (d[0] * h as f32).round()).clamp(0.0, (w - 1) as f32) as u32;
            let sy = (y as f32 + (-d[1] * h as f32).round()).clamp(0.0, (h - 1) as f32) as u32;
            // A source surface nearer than the nearest distorting surface here is in front of
            // the glass: the pixel keeps its own colour.
            if covered && points[(sy * w + sx) as usize].is_some_and(|v| -v.z * d[3] < 1.0) {
                in_front += 1;
                assert_eq!(p, q, "({x}, {y}) took ({sx}, {sy}), which lies in front of the glass");
                continue;
            }
            if p == q {
                continue;
            }
            changed += 1;
            assert!(covered, "({x}, {y}) changed without a distorting surface over it");
            assert_eq!(q, plain.get_pixel(sx, sy), "({x}, {y}) is not the pixel its offset names, ({sx}, {sy})");
        }
    }
    eprintln!(
        "glass: {changed} pixels moved, {under} under a distorting surface of {}, {in_front} kept (source in front)",
        w * h
    );
    assert!(changed > 500, "only {changed} pixels moved");
    assert!(in_front > 0, "no pixel's source lay in front of the glass: the rule went untested");
    let demo = scene("demo");
    let (a, _) = render_image(gpu(), &mut r, &demo, &base, w, h).unwrap();
    let (b, _) = render_image(gpu(), &mut r, &demo, &with, w, h).unwrap();
    assert_eq!(max_step(&a, &b), (0, 0), "demo has no distorting surface, yet the picture changed");
}

/// glTF: `"extras": {"distortion": k}` on a material sets its distortion strength; a value out
/// of [0, MAX_DISTORTION] or not a number is a warning naming the material, and no distortion.
#[test]
fn gltf_extras_set_a_materials_distortion() {
    use lampshade::scene::import::{self, ImportOptions};
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/gltf-tests/distortion-extras");
    let _ = std::fs::remove_dir_all(&dir);
    lampshade::scene::room::write(&dir).expect("write the room");
    let path = dir.join("room.gltf");
    let original: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).expect("room.gltf")).expect("json");
    let load = |extras: [serde_json::Value; 3]| {
        let mut v = original.clone();
        let materials = v["materials"].as_array_mut().expect("the room's materials");
        assert!(materials.len() >= 3, "the room has {} materials", materials.len());
        for (m, e) in materials.iter_mut().zip(extras) {
            m["extras"] = e;
        }
        std::fs::write(&path, serde_json::to_vec(&v).expect("json")).expect("write");
        import::load(&path, &ImportOptions::default(), &mut |_| {}).expect("the room loads")
    };
    let strengths = |i: &import::Imported| i.scene.materials.iter().map(|m| m.distortion).collect::<Vec<_>>();
    let plain = load([serde_json::json!({}), serde_json::json!({}), serde_json::json!({})]);
    assert!(strengths(&plain).iter().all(|&k| k == 0.0), "without extras nothing distorts");
    let set = load([
        serde_json::json!({"distortion": 0.05}),
        serde_json::json!({"distortion": 3.0}),
        serde_json::json!({"distortion": "lots"}),
    ]);
    let k = strengths(&set);
    assert_eq!(k.iter().filter(|&&k| k > 0.0).count(), 1, "exactly one material distorts: {k:?}");
    assert!(k.contains(&0.05), "{k:?}");
    let warned = set.warnings.iter().filter(|w| w.contains("distortion")).count();
    assert_eq!(warned, 2, "two bad strengths, two warnings: {:?}", set.warnings);
}
