//! Culling may only skip work, never light: every mode renders the same picture as
//! `fullscreen` on every built-in case, and the stencil modes shade no more than `volume`.

use crate::common::*;
use lampshade::compare::{flip, max_channel_difference};
use lampshade::renderer::{CullingMode, Method, Settings};

pub const W: u32 = 192;
pub const H: u32 = 108;
/// Culling changes which fragments run, not their arithmetic: the images must agree to one
/// 8-bit step per channel and a FLIP mean well under what an eye could see.
const MAX_CHANNEL_STEP: u8 = 1;
const FLIP_MEAN: f32 = 0.001;

pub const CASES: &[&str] = &["demo", "spot", "inside", "near", "far", "occluded", "floating"];
const STENCIL: [CullingMode; 3] =
    [CullingMode::StencilTwoPass, CullingMode::StencilInvert, CullingMode::StencilReplace];

fn settings(culling: CullingMode) -> Settings {
    Settings { culling, count_fragments: true, count_ideal: true, ..Settings::default() }
}

/// A case's frame at the test size, `demo` with 200 of its lights (fewer keep the full-screen
/// reference quick at test size). Shared with `tiled::tiled_and_clustered_give_the_fullscreen_picture_and_shade_at_least_the_ideal`,
/// which renders the same frames.
pub fn case_frame(name: &str, s: &Settings) -> std::sync::Arc<Frame> {
    let key = if name == "demo" { "demo, 200 lights".to_string() } else { name.to_string() };
    let make = || {
        let mut scene = scene(name);
        if name == "demo" {
            scene.lights_mut().truncate(200);
        }
        scene
    };
    frame_of(&key, make, s, W, H)
}

#[test]
fn every_mode_matches_fullscreen_on_every_case() {
    for name in CASES {
        let reference = case_frame(name, &settings(CullingMode::Fullscreen));
        assert_finite(&reference, name);
        assert!(lit_share(&reference.image) > 0.2, "{name}: the reference frame is mostly black");
        let full = reference.stats.shaded_fragments.unwrap();
        let mut volume_shaded = 0;
        for mode in CullingMode::ALL.into_iter().skip(1) {
            let f = case_frame(name, &settings(mode));
            assert_finite(&f, name);
            let step = max_channel_difference(&reference.image, &f.image);
            let (fl, _) = flip(&reference.image, &f.image).unwrap();
            assert!(
                step <= MAX_CHANNEL_STEP && fl.mean <= FLIP_MEAN,
                "{name}/{}: differs from fullscreen by {step} steps, FLIP mean {}",
                mode.name(),
                fl.mean
            );
            let shaded = f.stats.shaded_fragments.unwrap();
            assert_eq!(
                f.stats.ideal_fragments, reference.stats.ideal_fragments,
                "{name}: the ideal depends on the mode"
            );
            // Light by light too: volume modes count the ideal over the light's bounding volume,
            // `fullscreen` over the whole screen (`surfaces/measure.rs`).
            for (l, r) in f.stats.per_light.iter().zip(&reference.stats.per_light) {
                assert_eq!(l.ideal, r.ideal, "{name}/{}: light {}'s ideal depends on the mode", mode.name(), l.index);
            }
            // Every culling mode shades at least the ideal: its volumes circumscribe the lights.
            for l in &f.stats.per_light {
                if let Some(c) = l.coverage {
                    assert!(c >= l.shaded.unwrap(), "{name}/{}: coverage {c} below shaded", mode.name());
                }
                assert!(
                    l.shaded.unwrap() >= l.ideal.unwrap(),
                    "{name}/{}: light {} shaded {} < ideal {}",
                    mode.name(),
                    l.index,
                    l.shaded.unwrap(),
                    l.ideal.unwrap()
                );
            }
            match mode {
                CullingMode::Volume => {
                    volume_shaded = shaded;
                    assert!(shaded < full, "{name}: volume shades {shaded}, fullscreen {full}");
                }
                m if STENCIL.contains(&m) => {
                    assert!(shaded <= volume_shaded, "{name}/{}: shades {shaded} > volume {volume_shaded}", m.name());
                }
                _ => {}
            }
        }
    }
}

#[test]
fn hidden_and_floating_lights_shade_nothing_in_stencil_modes() {
    for name in ["occluded", "floating"] {
        let scene = scene(name);
        for mode in STENCIL {
            let f = render(&scene, &settings(mode), W, H);
            let l = &f.stats.per_light[0];
            assert_eq!(l.ideal, Some(0), "{name}: the test light must touch no visible point");
            assert_eq!(l.shaded, Some(0), "{name}/{}: light 0 shaded {:?} fragments", mode.name(), l.shaded);
            // The second light is visible and lit: the counts are live, not stuck at zero.
            assert!(f.stats.per_light[1].shaded.unwrap() > 0);
        }
        // Plain volumes (back faces, GreaterEqual) already skip the floating light, but shade
        // the wall in front of the hidden one: that is the work the stencil saves.
        let v = render(&scene, &settings(CullingMode::Volume), W, H);
        let volume_shaded = v.stats.per_light[0].shaded.unwrap();
        if name == "occluded" {
            assert!(volume_shaded > 0, "volume mode should shade the wall in front of the hidden light");
        } else {
            assert_eq!(volume_shaded, 0);
        }
    }
}

#[test]
fn camera_cases_use_the_paths_they_test() {
    let inside = render(&scene("inside"), &settings(CullingMode::StencilReplace), W, H);
    assert!(inside.stats.per_light[0].crosses_near, "the camera should be inside the light");
    let far = render(&scene("far"), &settings(CullingMode::Volume), W, H);
    assert!(far.stats.per_light[0].crosses_far, "the light should cross the far plane");
    let expected = if far.stats.depth_clamp { Method::Volume } else { Method::Fullscreen };
    assert_eq!(far.stats.per_light[0].method, expected);
}

#[test]
fn without_depth_clamp_far_crossing_lights_fall_back_to_fullscreen() {
    let scene = scene("far");
    let reference = render(&scene, &settings(CullingMode::Fullscreen), W, H);
    for mode in CullingMode::ALL {
        let s = Settings { depth_clamp: false, ..settings(mode) };
        let f = render(&scene, &s, W, H);
        assert!(!f.stats.depth_clamp);
        // Tiled and clustered draw no volume: their lists need no depth clamp.
        let expected = match mode {
            CullingMode::Tiled | CullingMode::Clustered | CullingMode::Zbin => mode.method().unwrap(),
            _ => Method::Fullscreen,
        };
        assert_eq!(f.stats.per_light[0].method, expected, "{}", mode.name());
        assert!(max_channel_difference(&reference.image, &f.image) <= MAX_CHANNEL_STEP);
    }
}

#[test]
fn without_depth_clamp_near_crossing_lights_fall_back_to_fullscreen() {
    // The near plane clips such a volume's faces, and the clipper's new vertices carry their
    // edge's rounding against a w of only `near`: no volume method's depth test is safe, so the
    // plan draws the light full-screen. With depth clamp (where the adapter has it) the near
    // plane does not clip and the mode's own method stays.
    for name in ["inside", "near"] {
        let scene = scene(name);
        let reference = render(&scene, &settings(CullingMode::Fullscreen), W, H);
        for mode in CullingMode::ALL {
            let clamped = render(&scene, &settings(mode), W, H);
            let f = render(&scene, &Settings { depth_clamp: false, ..settings(mode) }, W, H);
            assert!(!f.stats.depth_clamp);
            let l = &f.stats.per_light[0];
            assert!(l.crosses_near, "{name}: the light should cross the near plane");
            let (expected, with_clamp) = match mode {
                CullingMode::Tiled | CullingMode::Clustered | CullingMode::Zbin => {
                    (mode.method().unwrap(), mode.method().unwrap())
                }
                CullingMode::Fullscreen => (Method::Fullscreen, Method::Fullscreen),
                CullingMode::Auto => (Method::Fullscreen, Method::Volume),
                _ => (Method::Fullscreen, mode.method().unwrap()),
            };
            assert_eq!(l.method, expected, "{name}/{}", mode.name());
            if clamped.stats.depth_clamp {
                assert_eq!(clamped.stats.per_light[0].method, with_clamp, "{name}/{} with depth clamp", mode.name());
            }
            assert!(max_channel_difference(&reference.image, &f.image) <= MAX_CHANNEL_STEP, "{name}/{}", mode.name());
        }
    }
}

#[test]
fn stencil_replace_survives_more_than_255_lights() {
    // The stencil is cleared every 255 lights; light 256 reuses reference value 1.
    let mut scene = scene("demo");
    scene.lights_mut().truncate(600);
    let a = render(&scene, &settings(CullingMode::Volume), W, H);
    let b = render(&scene, &settings(CullingMode::StencilReplace), W, H);
    assert!(max_channel_difference(&a.image, &b.image) <= MAX_CHANNEL_STEP);
}

#[test]
fn stencil_modes_shade_exactly_the_points_inside_the_bounding_mesh() {
    // Counted on the CPU from the G-buffer's reconstructed positions: a stencil mode's shaded
    // count is the number of pixels whose point lies inside the light's bounding mesh (not
    // inside the light itself: that is the ideal, which is smaller).
    let gpu = gpu();
    for name in ["spot", "classify", "inside", "near", "occluded"] {
        let scene = scene(name);
        for mode in STENCIL {
            let s = settings(mode);
            let mut r = lampshade::Renderer::new(gpu, lampshade::renderer::OUTPUT_FORMAT, &s).unwrap();
            let (_, stats) = lampshade::headless::render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
            let points = r.last_frame().view_positions(gpu).unwrap();
            for (i, l) in stats.per_light.iter().enumerate() {
                let planes = r.last_frame().volume_planes(i).unwrap();
                let inside =
                    points.iter().flatten().filter(|p| planes.iter().all(|(a, n)| n.dot(**p - *a) <= 0.0)).count()
                        as u64;
                let shaded = l.shaded.unwrap();
                // Pixels whose point lies on a face within float rounding may go either way.
                let slack = 2 + inside / 200;
                assert!(
                    shaded.abs_diff(inside) <= slack,
                    "{name}/{}: light {i} shaded {shaded}, points inside its mesh {inside}",
                    mode.name()
                );
                assert!(inside >= l.ideal.unwrap());
            }
        }
    }
}

#[test]
fn the_stencil_modes_agree_light_by_light_on_the_full_demo() {
    // The three stencil methods test the same geometric condition (the scene point lies between
    // the volume's front and back faces), so per light they shade the same samples, up to
    // pixels whose point lies exactly on a face (Less against LessEqual).
    let scene = scene("demo");
    let runs: Vec<_> = STENCIL.iter().map(|&m| render(&scene, &settings(m), 320, 180)).collect();
    for (k, run) in runs.iter().enumerate().skip(1) {
        for (a, b) in runs[0].stats.per_light.iter().zip(&run.stats.per_light) {
            let (x, y) = (a.shaded.unwrap(), b.shaded.unwrap());
            assert!(
                x.abs_diff(y) <= 2 + x / 100,
                "light {}: {} shades {x}, {} shades {y}",
                a.index,
                STENCIL[0].name(),
                STENCIL[k].name()
            );
        }
    }
}

/// Every mode against `fullscreen` under `base` on `cases`: within one 8-bit step, and never
/// shading fewer fragments than a light's true shape holds.
fn modes_match_fullscreen(base: &Settings, cases: &[&str], what: &str) {
    for name in cases {
        let mut scene = scene(name);
        scene.lights_mut().truncate(200);
        let s = |culling| Settings { culling, ..base.clone() };
        let reference = render(&scene, &s(CullingMode::Fullscreen), W, H);
        assert_finite(&reference, name);
        for mode in CullingMode::ALL.into_iter().skip(1) {
            let f = render(&scene, &s(mode), W, H);
            assert_finite(&f, name);
            let step = max_channel_difference(&reference.image, &f.image);
            // Tiled and clustered write the log accumulation once per pixel, not once per
            // light: they differ from fullscreen-log by fullscreen's own rounding (up to 4 steps
            // on demo), and tests/it/tiled.rs holds them to two writes' bound of the exact light.
            let one_write = matches!(mode, CullingMode::Tiled | CullingMode::Clustered | CullingMode::Zbin)
                || f.stats.per_light.iter().any(|l| l.method.listed());
            let log = base.accumulation == lampshade::renderer::AccumFormat::Rgba8Log;
            assert!(
                step <= MAX_CHANNEL_STEP || (log && one_write),
                "{what} {name}/{}: {step} steps from fullscreen",
                mode.name()
            );
            for l in &f.stats.per_light {
                assert!(
                    l.shaded.unwrap() >= l.ideal.unwrap(),
                    "{what} {name}/{}: light {} shaded {} < ideal {}",
                    mode.name(),
                    l.index,
                    l.shaded.unwrap(),
                    l.ideal.unwrap()
                );
            }
        }
    }
}

#[test]
fn every_mode_matches_fullscreen_with_log_accumulation() {
    // Seed 004's multiplicative blend: a light outside its shape multiplies by exactly 1, so
    // skipping it (culling) changes nothing.
    let s = Settings { accumulation: lampshade::renderer::AccumFormat::Rgba8Log, ..settings(CullingMode::Volume) };
    modes_match_fullscreen(&s, &["demo", "spot", "inside", "near", "far"], "rgba8-log");
}

#[test]
fn every_mode_matches_fullscreen_with_a_light_cutoff() {
    // The cut-off shrinks the volume and the shader's radius alike.
    for t in [1.0 / 64.0, 1.0 / 16.0] {
        let s = Settings { light_cutoff: t, ..settings(CullingMode::Volume) };
        modes_match_fullscreen(&s, &["demo", "spot", "inside", "near"], &format!("cut-off {t}"));
    }
}

#[test]
fn tessellation_changes_the_work_not_the_picture() {
    // Coarse and fine volumes all circumscribe their lights: the picture stays the fullscreen
    // one, and finer meshes shade fewer fragments (closer to the ideal).
    for (sphere_subdivisions, cone_sides) in [(0, 3), (0, 6), (2, 24), (3, 12)] {
        let s = Settings { sphere_subdivisions, cone_sides, ..settings(CullingMode::Volume) };
        modes_match_fullscreen(
            &s,
            &["demo", "spot", "inside"],
            &format!("sphere {sphere_subdivisions} cone {cone_sides}"),
        );
    }
    let shaded = |name: &str, sphere_subdivisions, cone_sides| {
        let mut scene = scene(name);
        scene.lights_mut().truncate(200);
        let s = Settings { sphere_subdivisions, cone_sides, ..settings(CullingMode::Volume) };
        render(&scene, &s, W, H).stats.shaded_fragments.unwrap()
    };
    let spheres: Vec<u64> = (0..=3).map(|k| shaded("demo", k, 12)).collect();
    assert!(spheres.windows(2).all(|p| p[1] < p[0]), "demo shaded by subdivision 0..3: {spheres:?}");
    let cones: Vec<u64> = [3, 6, 24].into_iter().map(|n| shaded("spot", 1, n)).collect();
    assert!(cones.windows(2).all(|p| p[1] < p[0]), "spot shaded by 3, 6, 24 sides: {cones:?}");
}
