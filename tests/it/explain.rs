//! Why each light lit a pixel (`Last::explain`, `render --probe X,Y`): the explanation
//! adds up to the pixel in every culling mode on the hard cases, drops no light, and names the
//! stage that rejected a light hidden behind a wall.

use crate::common::*;
use lampshade::headless::render_image;
use lampshade::renderer::explain::{Culling, Explanation};
use lampshade::renderer::{CullingMode, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::Scene;

fn settings(culling: CullingMode) -> Settings {
    Settings { culling, count_fragments: false, ..Settings::default() }
}

/// Renders `scene` with `st` and returns the renderer (for `explain`) and the accumulation
/// (diffuse, specular; RGBA a pixel).
fn rendered(scene: &Scene, st: &Settings, w: u32, h: u32) -> (Renderer, (Vec<f32>, Vec<f32>)) {
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, st).expect("renderer");
    render_image(gpu, &mut r, scene, st, w, h).expect("render");
    let acc = r.last_frame().read_accumulation(gpu).expect("accumulation");
    (r, acc)
}

/// The lights the frame evaluated at the pixel and that add light there.
fn adding(e: &Explanation) -> usize {
    e.lights.iter().filter(|l| l.culling.admitted() && l.contributes()).count()
}

/// What the explanation's admitted lights add, taken from pixel `i`'s accumulated light,
/// leaves what the frame without lights accumulated there (`dark`: its diffuse and specular
/// targets), within (k + 2) half-ulps of fp16 for the k lights that add (see the test below).
fn assert_adds_up(e: &Explanation, i: usize, dark: (&[f32], &[f32]), what: &str) {
    let k = adding(e);
    for c in 0..3 {
        for (acc, rest, dark) in [
            (e.accumulated_diffuse[c], e.rest_diffuse[c], dark.0[4 * i + c]),
            (e.accumulated_specular[c], e.rest_specular[c], dark.1[4 * i + c]),
        ] {
            let bound = (k as f32 + 2.0) * 2f32.powi(-11) * acc.abs();
            assert!(
                (rest - dark).abs() <= bound,
                "{what}: channel {c}: accumulated {acc}, the lights leave {rest}, the frame without lights has \
                 {dark} (bound {bound})\n{}",
                lampshade::renderer::explain::table(e)
            );
        }
    }
}

/// For every hard case, every culling mode (shadows on, as by default), at the pixels where
/// the lights add the most and at two fixed ones: no light that adds to the pixel was left out
/// by the culling (`missed` 0), and what the admitted lights add, taken from the accumulated
/// light, leaves exactly what the same frame without lights accumulates (ambient and sun,
/// written by the G-buffer pass: the same pass, the same values). The bound is the targets'
/// fp16 rounding: each of the k lights that add is blended into an Rgba16Float target, and
/// each blend rounds the running sum (at most the final value: every term is >= 0) by at most
/// half an ulp, 2^-11 of it; the rest is written once and the tiled pass adds its f32 sum once,
/// so (k + 2) x 2^-11 of the value.
#[test]
fn the_explanation_adds_up_to_the_pixel_in_every_mode_on_the_hard_cases() {
    let gpu = gpu();
    let mut checked = 0;
    let mut with_light = 0;
    for &name in HARD_CASES {
        let s = scene(name);
        let (w, h) = hard_case_size(name);
        let mut dark = s.clone();
        dark.lights_mut().clear();
        let (_, (d0, s0)) = rendered(&dark, &settings(CullingMode::Fullscreen), w, h);
        // The pixels where the lights add the most (in the full-screen frame), and two fixed.
        let (_, (d1, _)) = rendered(&s, &settings(CullingMode::Fullscreen), w, h);
        let mut order: Vec<usize> = (0..(w * h) as usize).collect();
        let added = |i: usize| (0..3).map(|c| d1[4 * i + c] - d0[4 * i + c]).fold(0.0f32, f32::max);
        order.sort_by(|&a, &b| added(b).total_cmp(&added(a)));
        let mut pixels: Vec<(u32, u32)> = order.iter().take(2).map(|&i| (i as u32 % w, i as u32 / w)).collect();
        pixels.extend([(w / 3, h / 2), (2 * w / 3, h / 3)]);
        for mode in CullingMode::ALL {
            let (r, _) = rendered(&s, &settings(mode), w, h);
            for &(x, y) in &pixels {
                let e = r.last_frame().explain(gpu, x, y).expect("explain");
                let what = format!("{name}, {}, pixel {x},{y}", mode.name());
                assert_eq!(
                    e.missed,
                    0,
                    "{what}: the culling left out light:\n{}",
                    lampshade::renderer::explain::table(&e)
                );
                if !e.valid {
                    continue;
                }
                with_light += (adding(&e) > 0) as usize;
                assert_adds_up(&e, (y * w + x) as usize, (&d0, &s0), &what);
                checked += 1;
            }
        }
    }
    eprintln!("{checked} pixels explained, {with_light} of them lit by some light");
    assert!(with_light > 100, "only {with_light} explained pixels had any light");
}

/// The same sum in the light's shadows: `shadows` with every light casting (the sun, a spot, a
/// point light's cube), at the pixels the shadows darken the most (against the same frame
/// without shadows), in the modes that shade from a draw, a list and the stencil. Each such
/// pixel's explanation names a light whose shadow factor is below 1 there, and the sum holds.
#[test]
fn the_explanation_adds_up_in_the_lights_shadows() {
    use lampshade::renderer::ShadowMode;
    let gpu = gpu();
    let s = scene("shadows");
    let (w, h) = (160, 90);
    let shadowed = |culling| Settings { shadows: ShadowMode::All, ..settings(culling) };
    let mut dark = s.clone();
    dark.lights_mut().clear();
    let (_, (d0, s0)) = rendered(&dark, &shadowed(CullingMode::Fullscreen), w, h);
    let (_, (lit, _)) =
        rendered(&s, &Settings { shadows: ShadowMode::None, ..settings(CullingMode::Fullscreen) }, w, h);
    let (_, (shade, _)) = rendered(&s, &shadowed(CullingMode::Fullscreen), w, h);
    let mut order: Vec<usize> = (0..(w * h) as usize).collect();
    let darkened = |i: usize| (0..3).map(|c| lit[4 * i + c] - shade[4 * i + c]).fold(0.0f32, f32::max);
    order.sort_by(|&a, &b| darkened(b).total_cmp(&darkened(a)));
    let pixels: Vec<(u32, u32)> = order.iter().take(6).map(|&i| (i as u32 % w, i as u32 / w)).collect();
    for mode in [CullingMode::Volume, CullingMode::StencilReplace, CullingMode::Tiled, CullingMode::Clustered] {
        let (r, _) = rendered(&s, &shadowed(mode), w, h);
        for &(x, y) in &pixels {
            let e = r.last_frame().explain(gpu, x, y).expect("explain");
            let what = format!("shadows, {}, pixel {x},{y}", mode.name());
            let table = lampshade::renderer::explain::table(&e);
            assert_eq!(e.missed, 0, "{what}: the culling left out light:\n{table}");
            assert!(e.lights.iter().any(|l| l.shadow < 1.0), "{what}: no light is shadowed here:\n{table}");
            assert_adds_up(&e, (y * w + x) as usize, (&d0, &s0), &what);
        }
    }
}

/// `occluded`: the light behind the wall reaches nothing visible. At the wall's pixels its
/// screen bounds cover, each mode's own stage stops it or lets it through for nothing: the
/// volume method's depth test passes (its back faces lie behind the wall: evaluated, wasted),
/// the stencil methods' test fails (the wall is in front of the volume), and the tiled and
/// clustered lists leave it out (the cells' depth bounds end at the wall).
#[test]
fn a_light_behind_a_wall_is_wasted_by_the_volume_method_and_rejected_by_the_others() {
    let gpu = gpu();
    let s = scene("occluded");
    let (w, h) = (160, 90);
    // The pixels whose ray meets the light's volume (in the volume frame: the light is not
    // `volume missed` there), on a grid of every 6th pixel.
    let (r, _) = rendered(&s, &settings(CullingMode::Volume), w, h);
    let mut pixels = Vec::new();
    for y in (0..h).step_by(6) {
        for x in (0..w).step_by(6) {
            let e = r.last_frame().explain(gpu, x, y).expect("explain");
            if e.lights.iter().any(|l| l.index == 0 && l.culling != Culling::VolumeMissed) {
                pixels.push((x, y));
            }
        }
    }
    assert!(pixels.len() >= 10, "the hidden light's volume meets only {} probed pixels", pixels.len());
    for (mode, expect, wasted) in [
        (CullingMode::Volume, Culling::VolumeDepthPassed, true),
        (CullingMode::StencilTwoPass, Culling::InFrontOfVolume, false),
        (CullingMode::StencilInvert, Culling::InFrontOfVolume, false),
        (CullingMode::StencilReplace, Culling::InFrontOfVolume, false),
        (CullingMode::Tiled, Culling::NotInList, false),
        (CullingMode::Clustered, Culling::NotInList, false),
    ] {
        let (r, _) = rendered(&s, &settings(mode), w, h);
        for &(x, y) in &pixels {
            let e = r.last_frame().explain(gpu, x, y).expect("explain");
            let what = format!("{}, pixel {x},{y}", mode.name());
            let Some(l) = e.lights.iter().find(|l| l.index == 0) else {
                panic!("{what}: the hidden light is not listed")
            };
            assert!(!l.contributes(), "{what}: the hidden light adds light");
            assert_eq!((l.culling, l.wasted), (expect, wasted), "{what}\n{}", lampshade::renderer::explain::table(&e));
        }
    }
    eprintln!("the hidden light checked at {} pixels in six modes", pixels.len());
}

/// The explanation asks for the deferred path's G-buffer: the forward paths and the light
/// pre-pass get an error naming the path, not a panic or a wrong answer.
#[test]
fn explaining_a_frame_without_a_deferred_gbuffer_is_a_clear_error() {
    let gpu = gpu();
    let s = scene("occluded");
    for path in [lampshade::renderer::RenderPath::Forward, lampshade::renderer::RenderPath::ForwardMultipass] {
        let st = Settings { path, ..settings(CullingMode::Volume) };
        let (r, _) = rendered(&s, &st, 64, 36);
        let err = r.last_frame().explain(gpu, 10, 10).expect_err("explained a non-deferred frame");
        assert!(err.to_string().contains(&path.name()), "{err}");
    }
    let (r, _) = rendered(&s, &settings(CullingMode::Volume), 64, 36);
    assert!(r.last_frame().explain(gpu, 64, 10).is_err(), "a pixel outside the frame");
}

/// The light pre-pass (seed 003): the explanation adds up to its light buffer as it adds up to
/// the deferred accumulation. Each light's terms are shaded with unit reflectance there (the
/// buffer's RGB the diffuse light, its A the specular light's luminance), and what the admitted
/// lights add, taken from the pixel's buffer, leaves the lightless frame's buffer within the
/// same (k + 2) fp16 roundings (half an ulp, or half the subnormal step for values under fp16's
/// normal range, which the buffer's small specular luminances reach), on every hard case in
/// every mode, with no light missed.
#[test]
fn the_explanation_adds_up_on_the_light_prepass() {
    use lampshade::renderer::RenderPath;
    let gpu = gpu();
    let mut with_light = 0;
    for &name in HARD_CASES {
        let s = scene(name);
        let (w, h) = hard_case_size(name);
        let st = |mode| Settings { path: RenderPath::LightPrepass, ..settings(mode) };
        let buffer = |scene: &Scene, mode| {
            let (r, _) = rendered(scene, &st(mode), w, h);
            let b = r.last_frame().read_light_buffer(gpu).expect("light buffer");
            (r, b)
        };
        let mut dark = s.clone();
        dark.lights_mut().clear();
        let (_, b0) = buffer(&dark, CullingMode::Fullscreen);
        let (_, b1) = buffer(&s, CullingMode::Fullscreen);
        let mut order: Vec<usize> = (0..(w * h) as usize).collect();
        let added = |i: usize| (0..4).map(|c| b1[4 * i + c] - b0[4 * i + c]).fold(0.0f32, f32::max);
        order.sort_by(|&a, &b| added(b).total_cmp(&added(a)));
        let mut pixels: Vec<(u32, u32)> = order.iter().take(2).map(|&i| (i as u32 % w, i as u32 / w)).collect();
        pixels.extend([(w / 3, h / 2), (2 * w / 3, h / 3)]);
        for mode in CullingMode::ALL {
            let (r, _) = buffer(&s, mode);
            for &(x, y) in &pixels {
                let e = r.last_frame().explain(gpu, x, y).expect("explain");
                let what = format!("{name}, {}, light pre-pass, pixel {x},{y}", mode.name());
                let table = lampshade::renderer::explain::table(&e);
                assert!(e.prepass, "{what}");
                assert_eq!(e.missed, 0, "{what}: the culling left out light:\n{table}");
                if !e.valid {
                    continue;
                }
                let k = adding(&e);
                with_light += (k > 0) as usize;
                let i = (y * w + x) as usize;
                let channels = [
                    (e.accumulated_diffuse.x, e.rest_diffuse.x, b0[4 * i]),
                    (e.accumulated_diffuse.y, e.rest_diffuse.y, b0[4 * i + 1]),
                    (e.accumulated_diffuse.z, e.rest_diffuse.z, b0[4 * i + 2]),
                    (e.accumulated_specular.x, e.rest_specular.x, b0[4 * i + 3]),
                ];
                for (c, (acc, rest, dark)) in channels.into_iter().enumerate() {
                    // Each rounding is half an ulp of the value, or below fp16's normal range
                    // half its subnormal step (2^-24): a specular luminance of 1e-8 is stored 0.
                    let bound = (k as f32 + 2.0) * (2f32.powi(-11) * acc.abs()).max(2f32.powi(-25));
                    assert!(
                        (rest - dark).abs() <= bound,
                        "{what}: channel {c}: buffer {acc}, the lights leave {rest}, the lightless frame has {dark} \
                         (bound {bound})\n{table}"
                    );
                }
            }
        }
    }
    assert!(with_light > 100, "only {with_light} explained pixels had any light");
}

/// The ledger of `tiled` and `clustered`, where a light has no draw of its own: each light's
/// pairs (the shading pass's per-light counters) equal, light by light and exactly, the pairs
/// counted on the CPU from the lists read back (every pixel with a G-buffer point adds one to
/// each light of its tile's or cluster's list), so a light outside every list has none; they
/// add up to the frame's total; and every light's pairs hold its ideal pairs (culling only
/// skips work), the rest being its wasted pairs. `demo` with 64 point lights and its spots, on
/// a frame where some lights reach no cell.
#[test]
fn the_ledgers_pairs_are_the_lists_pixels_light_by_light() {
    let gpu = gpu();
    let scene = with_lights("demo", 64);
    let (w, h) = (160, 90);
    for mode in [CullingMode::Tiled, CullingMode::Clustered] {
        let st = Settings { culling: mode, count_fragments: true, count_ideal: true, ..settings(mode) };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &st).expect("renderer");
        let stats = render_image(gpu, &mut r, &scene, &st, w, h).expect("render").1;
        let lists = r.last_frame().tile_lists(gpu).expect("lists").expect("the frame built lists");
        let points = r.last_frame().view_positions(gpu).expect("positions");
        let mut expected = vec![0u64; scene.lights.len()];
        for (k, p) in points.iter().enumerate() {
            let Some(p) = p else { continue };
            let (x, y) = (k as u32 % w, k as u32 / w);
            for i in lists.list(lists.cell(x, y, -p.z)) {
                expected[i as usize] += 1;
            }
        }
        let what = mode.name();
        let counted: Vec<u64> = stats.per_light.iter().map(|l| l.shaded.expect("counted")).collect();
        assert_eq!(counted, expected, "{what}: per-light pairs against the lists' pixels");
        assert_eq!(stats.shaded_fragments, Some(expected.iter().sum()), "{what}");
        let unlisted = expected.iter().filter(|&&n| n == 0).count();
        assert!(unlisted > 0 && unlisted < scene.lights.len(), "{what}: {unlisted} lights in no list");
        for l in &stats.per_light {
            let (shaded, ideal) = (l.shaded.unwrap(), l.ideal.expect("ideal counted"));
            assert!(shaded >= ideal, "{what}: light {} evaluated {shaded} pairs of its {ideal} ideal", l.index);
            assert_eq!(l.wasted, Some(shaded - ideal), "{what}: light {}", l.index);
            assert!(l.cost_ms.is_some_and(|c| c >= 0.0), "{what}: light {} has no cost", l.index);
        }
        let wasted: u64 = stats.per_light.iter().filter_map(|l| l.wasted).sum();
        assert_eq!(stats.wasted_fragments, Some(wasted), "{what}");
        assert!(wasted > 0, "{what}: lists that waste nothing on demo");
    }
}

/// The ledger off: the same picture, bit for bit, in the modes whose counters are atomics in
/// the shading pass (a second entry point), and no per-light figure at all; nor, unless asked
/// for, the per-light table.
#[test]
fn the_ledger_off_changes_no_pixel_and_counts_nothing() {
    let gpu = gpu();
    let scene = with_lights("demo", 64);
    for mode in [CullingMode::Tiled, CullingMode::Clustered] {
        let on = Settings { count_fragments: true, ..settings(mode) };
        let off = Settings { per_light_stats: true, ..settings(mode) };
        let (_, a) = rendered(&scene, &on, 160, 90);
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &off).expect("renderer");
        let stats = render_image(gpu, &mut r, &scene, &off, 160, 90).expect("render").1;
        let b = r.last_frame().read_accumulation(gpu).expect("accumulation");
        assert!(a == b, "{}: the counted frame's light differs from the uncounted one's", mode.name());
        assert_eq!(stats.shaded_fragments, None, "{}", mode.name());
        assert_eq!(stats.per_light.len(), scene.lights.len());
        assert!(stats.per_light.iter().all(|l| l.shaded.is_none() && l.cost_ms.is_none() && l.wasted.is_none()));
        assert_eq!((stats.light_cost_ms, stats.wasted_fragments), (None, None), "{}", mode.name());
        // Not asked for, the per-light table is not built, and the stats say so.
        let quiet = render_image(gpu, &mut r, &scene, &settings(mode), 160, 90).expect("render").1;
        assert!(quiet.per_light.is_empty() && !quiet.per_light_stats, "{}", mode.name());
        assert!(stats.per_light_stats, "{}", mode.name());
    }
}

/// The ledger off compiles no counter: a renderer on a device of its own (so no other test's
/// frame has built a pass it shares) draws every culling mode and path, with shadows on, and
/// has made none of the ledger's GPU objects (the tiled pass's counting pipeline, the waste
/// view, the forward paths' per-draw queries, the per-light shadow timers); one counted frame
/// in each of `tiled` and forward single-pass, with a view of the waste, then makes them.
#[test]
fn the_ledger_off_compiles_no_counter() {
    use lampshade::renderer::{DebugView, RenderPath};
    let own = lampshade::gpu::Gpu::headless().expect("a second device");
    let scene = with_lights("demo", 16);
    let off = settings(CullingMode::Tiled);
    let mut r = Renderer::new(&own, OUTPUT_FORMAT, &off).expect("renderer");
    for mode in CullingMode::ALL {
        render_image(&own, &mut r, &scene, &settings(mode), 96, 54).expect("render");
    }
    for path in [RenderPath::LightPrepass, RenderPath::Forward, RenderPath::ForwardMultipass] {
        render_image(&own, &mut r, &scene, &Settings { path, ..off.clone() }, 96, 54).expect("render");
    }
    assert_eq!(r.last_frame().ledger_objects(), Vec::<&str>::new(), "frames without the ledger made its objects");
    let on = Settings { count_fragments: true, count_ideal: true, ..off.clone() };
    render_image(&own, &mut r, &scene, &on, 96, 54).expect("render");
    let forward = Settings { path: RenderPath::Forward, ..on.clone() };
    render_image(&own, &mut r, &scene, &forward, 96, 54).expect("render");
    render_image(
        &own,
        &mut r,
        &scene,
        &Settings { debug_view: DebugView::Waste, culling: CullingMode::Volume, ..off },
        96,
        54,
    )
    .expect("render");
    let made = r.last_frame().ledger_objects();
    assert!(made.len() == 4, "counted frames made {made:?}");
}

/// The waste view (`--debug-view waste`) against the ledger: in every culling mode, over the
/// whole frame, the view's per-pixel counts add up exactly to the lights' wasted pairs (each
/// light's evaluated samples minus its ideal ones, from the counted frame's queries and list
/// counters), and with a light selected to that light's; on `demo` with 64 lights and on the hard cases where volumes hold the camera or
/// cross the near and far planes (`inside`, `near`, `far`, `spot-extremes`).
#[test]
fn the_waste_view_adds_up_to_the_ledgers_wasted_pairs_in_every_mode() {
    use lampshade::renderer::DebugView;
    let gpu = gpu();
    let demo = with_lights("demo", 64);
    let scenes = [
        ("demo", demo),
        ("inside", scene("inside")),
        ("near", scene("near")),
        ("far", scene("far")),
        ("spot-extremes", scene("spot-extremes")),
    ];
    let (w, h) = (160, 90);
    for (name, s) in &scenes {
        for mode in CullingMode::ALL {
            let what = format!("{name}, {}", mode.name());
            let counted = Settings { count_fragments: true, count_ideal: true, ..settings(mode) };
            let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &counted).expect("renderer");
            let stats = render_image(gpu, &mut r, s, &counted, w, h).expect("render").1;
            let wasted = stats.wasted_fragments.unwrap_or_else(|| panic!("{what}: no waste counted"));
            let view = Settings { debug_view: DebugView::Waste, ..settings(mode) };
            render_image(gpu, &mut r, s, &view, w, h).expect("render the view");
            let counts = r.last_frame().read_debug_view(gpu).expect("debug target");
            let shown: f64 = counts.iter().map(|&c| c as f64).sum();
            assert_eq!(shown, wasted as f64, "{what}: the view's counts against the ledger's wasted pairs");
            if *name == "demo" && mode != CullingMode::Auto {
                assert!(wasted > 0, "{what}: a mode that wastes nothing on demo");
            }
            // One light's: the view of the light that wastes the most against its own count.
            let worst = stats.per_light.iter().max_by_key(|l| l.wasted).expect("lights");
            let one = Settings { selected_light: Some(worst.index), ..view.clone() };
            render_image(gpu, &mut r, s, &one, w, h).expect("render the view");
            let shown: f64 = r.last_frame().read_debug_view(gpu).expect("debug target").iter().map(|&c| c as f64).sum();
            assert_eq!(shown, worst.wasted.unwrap() as f64, "{what}: light {}'s waste", worst.index);
        }
    }
}
