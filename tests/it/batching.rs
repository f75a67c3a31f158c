//! Batched light draws change the draw calls, not the picture: every culling mode
//! gives the unbatched frame bit for bit (every pixel's lights blend in light order), every light shades
//! exactly the samples it shades unbatched, and the batches are what `renderer::batches` says
//! (no two lights of a batch meet, every drawn light in exactly one batch).

use crate::common::*;
use glam::Vec2;
use lampshade::compare::max_channel_difference;
use lampshade::headless::render_image;
use lampshade::renderer::batches::{footprint, Footprint};
use lampshade::renderer::plan::{FramePlan, PlanView};
use lampshade::renderer::records::FrameRecords;
use lampshade::renderer::volumes::{self, Volumes};
use lampshade::renderer::{CullingMode, FrameStats, Method, Renderer, Settings, ShadowMode, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::Scene;

const W: u32 = 192;
const H: u32 = 108;
const CASES: &[&str] = &["demo", "spot", "inside", "near", "far", "occluded", "floating"];
struct Run {
    image: image::RgbaImage,
    stats: FrameStats,
    light: Vec<f32>,
}

fn run(r: &mut Renderer, scene: &Scene, s: &Settings, (w, h): (u32, u32)) -> Run {
    let gpu = gpu();
    let (image, stats) = render_image(gpu, r, scene, s, w, h).expect("render");
    let (d, sp) = r.last_frame().read_accumulation(gpu).expect("accumulation");
    Run { image, stats, light: d.into_iter().chain(sp).collect() }
}

#[test]
fn batched_frames_equal_unbatched_light_by_light() {
    let gpu = gpu();
    let mut failures = Vec::new();
    for name in CASES {
        let scene = scene(name);
        for mode in CullingMode::ALL {
            let s = |light_batching, count_fragments| Settings {
                culling: mode,
                light_batching,
                count_fragments,
                ..Settings::default()
            };
            let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s(true, true)).unwrap();
            let unbatched = run(&mut r, &scene, &s(false, true), (W, H));
            let counted = run(&mut r, &scene, &s(true, true), (W, H));
            let batched = run(&mut r, &scene, &s(true, false), (W, H));
            let what = format!("{name}/{}", mode.name());
            assert_finite_run(&batched, &what);
            for (other, how) in [(&counted, "counted"), (&batched, "uncounted")] {
                // Batches keep every pixel's lights in light order (`batches.rs`): the same
                // blends in the same order, so the same bits.
                let step = max_channel_difference(&unbatched.image, &other.image);
                if step > 0 {
                    failures.push(format!("{what}: batched ({how}) is {step} steps from unbatched"));
                }
                let differ = unbatched.light.iter().zip(&other.light).position(|(x, y)| x.to_bits() != y.to_bits());
                if let Some(at) = differ {
                    failures.push(format!(
                        "{what}: batched ({how}) accumulation differs at value {at}: {} against {}",
                        other.light[at], unbatched.light[at]
                    ));
                }
            }
            // Counted light by light: exactly the unbatched counts.
            for (u, b) in unbatched.stats.per_light.iter().zip(&counted.stats.per_light) {
                if u.shaded != b.shaded {
                    failures.push(format!(
                        "{what}: light {} shaded {:?} unbatched, {:?} batched",
                        u.index, u.shaded, b.shaded
                    ));
                }
            }
            assert_eq!(batched.stats.shaded_fragments, None, "{what}: the uncounted frame counted");
            // Fewer batches than lights wherever two lights share one; never more draws.
            let (u, b) = (&unbatched.stats, &batched.stats);
            assert!(b.light_batches <= u.light_batches && b.draw_calls <= u.draw_calls, "{what}: {u:?} {b:?}");
            let drawn =
                u.per_light.iter().filter(|l| !(l.method == Method::Skipped || l.method.listed())).count() as u64;
            assert_eq!(u.light_batches, drawn, "{what}: unbatched, one batch per drawn light");
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn assert_finite_run(r: &Run, what: &str) {
    let bad = r.light.iter().filter(|v| !v.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite accumulation values");
}

#[test]
fn draw_calls_fall_on_the_full_demo() {
    // demo at 1280x720 as the bench draws it (uncounted, unshadowed: with shadows a batch's
    // casting and other lights draw with pipelines of their own, `ShadowCode::casters_apart`):
    // per method, the draws the batches need, and far fewer than a draw (or two) per light.
    let gpu = gpu();
    let scene = scene("demo");
    let (w, h) = (1280, 720);
    for mode in CullingMode::ALL {
        let s = |light_batching| Settings {
            culling: mode,
            light_batching,
            count_fragments: false,
            // The methods below are read from the per-light table.
            per_light_stats: true,
            timestamps: false,
            shadows: ShadowMode::None,
            ..Settings::default()
        };
        // Full-screen lights are batched whatever the size: a smaller frame keeps it quick.
        let (w, h) = if mode == CullingMode::Fullscreen { (w / 4, h / 4) } else { (w, h) };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s(true)).unwrap();
        let (_, u) = render_image(gpu, &mut r, &scene, &s(false), w, h).unwrap();
        let (_, b) = render_image(gpu, &mut r, &scene, &s(true), w, h).unwrap();
        let methods = |st: &FrameStats| {
            let mut m: Vec<Method> = st.per_light.iter().map(|l| l.method).filter(|m| *m != Method::Skipped).collect();
            m.sort_by_key(|m| m.name());
            m.dedup();
            m
        };
        println!(
            "{}: unbatched {} draws for {} batches, batched {} draws for {} batches",
            mode.name(),
            u.draw_calls,
            u.light_batches,
            b.draw_calls,
            b.light_batches
        );
        // REPLACE clears the stencil before every 256th batch (of one light, unbatched).
        let clears =
            |batches: u64| if mode == CullingMode::StencilReplace { batches.saturating_sub(1) / 255 } else { 0 };
        // Unbatched: two draws per stencil-culled light, one otherwise.
        let per_light: u64 = u
            .per_light
            .iter()
            .map(|l| match l.method {
                Method::Skipped | Method::Tiled | Method::Clustered | Method::Zbin => 0,
                Method::Fullscreen | Method::Volume => 1,
                _ => 2,
            })
            .sum();
        assert_eq!(u.draw_calls, per_light + clears(u.light_batches), "{}", mode.name());
        let tiled = |st: &FrameStats| st.per_light.iter().all(|l| l.method.listed());
        if tiled(&b) {
            // The tiled pass shades the frame (`tiled`, `clustered`, `zbin`, or `auto`'s frame rule): the
            // light pass draws nothing, batched or not.
            assert_eq!((b.draw_calls, b.light_batches, u.draw_calls), (0, 0, 0), "{}", mode.name());
            continue;
        }
        match mode {
            // One instanced draw for all lights; volumes: one per mesh (sphere, cone).
            CullingMode::Fullscreen => assert_eq!((b.draw_calls, b.light_batches), (1, 1)),
            CullingMode::Volume => assert_eq!((b.draw_calls, b.light_batches), (2, 2)),
            CullingMode::StencilReplace => {
                // A mark and a shade per batch, and a stencil clear every 255 batches.
                assert_eq!(b.draw_calls, 2 * b.light_batches + clears(b.light_batches));
            }
            CullingMode::StencilTwoPass | CullingMode::StencilInvert => {
                assert_eq!(b.draw_calls, 2 * b.light_batches);
            }
            CullingMode::Auto => assert!(methods(&b).len() > 1, "auto draws demo with one method"),
            CullingMode::Tiled | CullingMode::Clustered | CullingMode::Zbin => {
                unreachable!("{}: drawn by the light pass", mode.name())
            }
        }
        assert!(
            b.draw_calls * 4 < u.draw_calls,
            "{}: {} draws batched, {} unbatched",
            mode.name(),
            b.draw_calls,
            u.draw_calls
        );
    }
}

#[test]
fn stencil_replace_batches_survive_more_than_255_batches_and_several_query_blocks() {
    // demo with 16,384 lights at 160x90: 4 blocks of 4,096 occlusion queries, and more than
    // 255 batches, so the stencil is cleared between batches as it was between lights.
    let gpu = gpu();
    let scene = builtin::build("demo", BuiltinOptions { lights: Some(16384), time: 0.0 }).unwrap();
    let size = (160, 90);
    for mode in [CullingMode::StencilReplace, CullingMode::StencilTwoPass] {
        let s = |light_batching| Settings { culling: mode, light_batching, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s(true)).unwrap();
        let u = run(&mut r, &scene, &s(false), size);
        let b = run(&mut r, &scene, &s(true), size);
        println!("{}: {} lights in {} batches", mode.name(), b.stats.lights, b.stats.light_batches);
        assert!(b.stats.light_batches > 255, "{}: only {} batches", mode.name(), b.stats.light_batches);
        assert!(b.stats.light_batches < u.stats.light_batches);
        assert_eq!(max_channel_difference(&u.image, &b.image), 0, "{}", mode.name());
        assert!(u.light.iter().zip(&b.light).all(|(x, y)| x.to_bits() == y.to_bits()), "{}", mode.name());
        for (x, y) in u.stats.per_light.iter().zip(&b.stats.per_light) {
            assert_eq!(x.shaded, y.shaded, "{}: light {}", mode.name(), x.index);
        }
    }
}

/// The plan of `scene` at `size` in `mode`, as `Renderer::render` makes it.
fn plan(scene: &Scene, volumes: &Volumes, mode: CullingMode, size: (u32, u32)) -> (FramePlan, FrameRecords, PlanView) {
    let settings = Settings { culling: mode, ..Settings::default() };
    let mut records = FrameRecords::new(scene, &settings.options(), size, wgpu::TextureFormat::Rgba16Float);
    let view = PlanView {
        proj: records.proj.as_mat4(),
        near: scene.camera.near as f32,
        far: scene.camera.far as f32,
        size,
        mode,
        depth_clamp: gpu().has(wgpu::Features::DEPTH_CLIP_CONTROL),
        forward_lights: settings.forward_lights,
        light_batching: true,
        cluster_build: settings.cluster_build,
        grid: Default::default(),
        object_cap: (0, Default::default()),
        loop_limit: None,
        near_fullscreen: false,
        front_to_back: false,
        sort_blended: true,
        prepass_models: None,
        costs: Default::default(),
    };
    let plan = FramePlan::new(scene, &mut records, &[], volumes, &view);
    (plan, records, view)
}

#[test]
fn no_two_lights_of_a_batch_meet_and_every_drawn_light_is_in_one_batch() {
    let volumes = Volumes::new(&gpu().device, (1, 12));
    let size = (1280, 720);
    let mut cases: Vec<(String, Scene)> =
        ["demo", "street", "inside", "near", "far"].iter().map(|n| (n.to_string(), scene(n))).collect();
    cases.push((
        "demo x16384".into(),
        builtin::build("demo", BuiltinOptions { lights: Some(16384), time: 0.0 }).unwrap(),
    ));
    for (name, scene) in &cases {
        for mode in CullingMode::ALL {
            let (plan, records, view) = plan(scene, &volumes, mode, size);
            let b = &plan.batches;
            let n = plan.lights.len();
            let what = format!("{name}/{}", mode.name());
            // The list starts with the identity (per-light draws read it).
            assert!(b.list.iter().take(n).copied().eq(0..n as u32), "{what}");
            let mut seen = vec![0u32; n];
            for (block, range) in b.blocks.iter().enumerate() {
                for batch in &b.batches[range.clone()] {
                    let lights = b.lights_of(batch);
                    assert!(!lights.is_empty(), "{what}: an empty batch");
                    let feet: Vec<Footprint> = lights
                        .iter()
                        .map(|&i| {
                            let (i, p) = (i as usize, &plan.lights[i as usize]);
                            seen[i] += 1;
                            assert_eq!(i / 4096, block, "{what}: light {i} batched outside its query block");
                            assert_eq!(p.method, batch.method, "{what}: light {i}");
                            if p.method != Method::Fullscreen {
                                assert_eq!(p.volume, batch.volume, "{what}: light {i}");
                            }
                            if p.method == Method::StencilReplace {
                                assert_eq!(p.crosses_near, batch.crosses_near, "{what}: light {i}");
                            }
                            footprint(p, &records.lights[i], &volumes, &view)
                        })
                        .collect();
                    if !matches!(batch.method, Method::Fullscreen | Method::Volume) {
                        for (k, f) in feet.iter().enumerate() {
                            for (g, other) in feet.iter().enumerate().skip(k + 1) {
                                if let (Footprint::Rect(p), Footprint::Rect(q)) = (f, other) {
                                    let apart = p[2] < q[0] || q[2] < p[0] || p[3] < q[1] || q[3] < p[1];
                                    assert!(
                                        apart,
                                        "{what}: lights {} {p:?} and {} {q:?} share a batch",
                                        lights[k], lights[g]
                                    );
                                }
                            }
                        }
                    }
                }
            }
            for (i, p) in plan.lights.iter().enumerate() {
                let expected = u32::from(!(p.method == Method::Skipped || p.method.listed()));
                assert_eq!(seen[i], expected, "{what}: light {i} ({:?}) in {} batches", p.method, seen[i]);
            }
            // Light order at every pixel: two lights whose footprints meet are drawn in light
            // order (an earlier batch, or the same instanced draw without stencil).
            if n <= 2000 {
                let mut batch_of = vec![usize::MAX; n];
                for (k, batch) in b.batches.iter().enumerate() {
                    for &l in b.lights_of(batch) {
                        batch_of[l as usize] = k;
                    }
                }
                let feet: Vec<Footprint> =
                    (0..n).map(|i| footprint(&plan.lights[i], &records.lights[i], &volumes, &view)).collect();
                for i in (0..n).filter(|&i| batch_of[i] != usize::MAX) {
                    for j in (i + 1..n).filter(|&j| batch_of[j] != usize::MAX) {
                        let full = |k: usize| plan.lights[k].method == Method::Fullscreen;
                        let meet = full(i)
                            || full(j)
                            || matches!((feet[i], feet[j]), (Footprint::Rect(p), Footprint::Rect(q))
                                if !(p[2] < q[0] || q[2] < p[0] || p[3] < q[1] || q[3] < p[1]));
                        let same_ok = batch_of[i] == batch_of[j]
                            && matches!(plan.lights[i].method, Method::Fullscreen | Method::Volume);
                        assert!(
                            !meet || batch_of[i] < batch_of[j] || same_ok,
                            "{what}: lights {i} and {j} meet but are drawn in batches {} and {}",
                            batch_of[i],
                            batch_of[j]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_lights_footprint_holds_every_pixel_its_volume_can_rasterise() {
    // Batching rests on this: the projected mesh vertices of every light in front of the near
    // plane lie inside its footprint (the hull they span is what its faces rasterise).
    let volumes = Volumes::new(&gpu().device, (1, 12));
    let size = (1280, 720);
    let mut checked = 0;
    for name in ["demo", "spot", "street", "far", "tiny-radius", "spot-extremes"] {
        let scene = scene(name);
        let (plan, records, view) = plan(&scene, &volumes, CullingMode::StencilTwoPass, size);
        for (i, p) in plan.lights.iter().enumerate() {
            let l = &records.lights[i];
            let f = footprint(p, l, &volumes, &view);
            for v in &volumes.mesh(p.volume).vertices {
                let c = view.proj * volumes::place_light(*v, l).extend(1.0);
                if c.w <= view.near {
                    continue;
                }
                let n = Vec2::new(c.x, c.y) / c.w;
                let (x, y) = ((n.x + 1.0) * 0.5 * size.0 as f32, (1.0 - n.y) * 0.5 * size.1 as f32);
                if x < 0.0 || y < 0.0 || x >= size.0 as f32 || y >= size.1 as f32 {
                    continue;
                }
                let Footprint::Rect([x0, y0, x1, y1]) = f else {
                    panic!("{name}: light {i} has no footprint but a vertex on screen at ({x}, {y})")
                };
                assert!(
                    x >= x0 as f32 && x <= x1 as f32 + 1.0 && y >= y0 as f32 && y <= y1 as f32 + 1.0,
                    "{name}: light {i}'s vertex at ({x}, {y}) lies outside its footprint {:?}",
                    [x0, y0, x1, y1]
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 10_000, "only {checked} vertices checked");
}

#[test]
fn the_complexity_view_is_the_same_batched() {
    // The heatmap adds 1 per light whose true shape holds the pixel's point: small integers,
    // exact in fp16 in any order, so batched and unbatched views are identical.
    let gpu = gpu();
    for name in ["demo", "spot", "inside", "far"] {
        let scene = scene(name);
        for mode in [CullingMode::Fullscreen, CullingMode::Volume, CullingMode::StencilTwoPass, CullingMode::Auto] {
            let s = |light_batching| Settings {
                culling: mode,
                light_batching,
                debug_view: lampshade::renderer::DebugView::Complexity,
                ..Settings::default()
            };
            let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s(true)).unwrap();
            let (u, _) = render_image(gpu, &mut r, &scene, &s(false), W, H).unwrap();
            let (b, _) = render_image(gpu, &mut r, &scene, &s(true), W, H).unwrap();
            let shades: std::collections::HashSet<[u8; 4]> = u.pixels().map(|p| p.0).collect();
            let least = if name == "demo" { 3 } else { 2 };
            assert!(shades.len() >= least, "{name}: the heatmap shows {} colours", shades.len());
            assert_eq!(max_channel_difference(&u, &b), 0, "{name}/{}", mode.name());
        }
    }
}

#[test]
fn log_accumulation_stays_unbatched() {
    // Rgba8Log rounds each blend to 8 bits: its sum depends on the blend order, which batching
    // changes, so its frames keep a draw per light (and `culling.rs`'s log test its one step).
    let gpu = gpu();
    let mut scene = scene("demo");
    scene.lights_mut().truncate(200);
    let s = Settings {
        culling: CullingMode::StencilTwoPass,
        accumulation: lampshade::renderer::AccumFormat::Rgba8Log,
        ..Settings::default()
    };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    let (_, st) = render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
    assert_eq!(st.light_batches, 200);
    let fp16 = Settings { accumulation: lampshade::renderer::AccumFormat::Rgba16Float, ..s };
    let (_, st) = render_image(gpu, &mut r, &scene, &fp16, W, H).unwrap();
    assert!(st.light_batches < 100, "{} batches", st.light_batches);
}
