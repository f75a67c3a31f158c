//! The peers' culling modes: `tiled` (Andersson 2011: per-16x16-tile light lists between each
//! tile's depth bounds, built by a compute pass) and `clustered` (Olsson et al. 2012: lists per
//! view-space cluster, built on the CPU) and `zbin` (Drobot 2017: lights sorted into depth
//! bins, a bitmask of lights per tile built by a compute pass), each shading every pixel in one
//! full-screen pass.
//! Culling may only skip work, never light: the picture is `fullscreen`'s, every light-pixel
//! pair inside a light's true shape is evaluated, and the counts are the pairs walked.

use crate::common::*;
use lampshade::compare::{flip, max_channel_difference};
use lampshade::headless::render_image;
use lampshade::renderer::inspect::inside_light;
use lampshade::renderer::settings::ClusterBuilder;
use lampshade::renderer::{AccumFormat, CullingMode, DebugView, Method, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::Scene;

const MODES: [CullingMode; 3] = [CullingMode::Tiled, CullingMode::Clustered, CullingMode::Zbin];
// `culling`'s cases and size: the two tests share those frames.
use crate::culling::{CASES, H, W};
/// The hard cases (tests/common's list, so a new one is tested here too) not among `CASES`.
fn hard() -> impl Iterator<Item = &'static str> {
    HARD_CASES.iter().copied().filter(|n| !CASES.contains(n))
}

fn settings(culling: CullingMode) -> Settings {
    Settings { culling, count_fragments: true, count_ideal: true, ..Settings::default() }
}

fn case(name: &str) -> (Scene, u32, u32) {
    let mut s = scene(name);
    if name == "demo" {
        // Fewer lights keep the full-screen reference (and the ideal) quick at test size.
        s.lights_mut().truncate(200);
    }
    if name == "railings" {
        // Half among the bars, half before the far wall (they alternate).
        s.lights_mut().truncate(256);
    }
    let (w, h) = if CASES.contains(&name) { (W, H) } else { hard_case_size(name) };
    (s, w, h)
}

/// Renders and keeps the renderer, for its readbacks.
fn render_with(
    scene: &Scene,
    s: &Settings,
    w: u32,
    h: u32,
) -> (Renderer, image::RgbaImage, lampshade::renderer::FrameStats) {
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s).expect("renderer");
    let (image, stats) = render_image(gpu, &mut r, scene, s, w, h).expect("render");
    (r, image, stats)
}

#[test]
fn tiled_and_clustered_give_the_fullscreen_picture_and_shade_at_least_the_ideal() {
    // `railings`: a depth discontinuity in nearly every tile.
    for name in CASES.iter().copied().chain(hard()).chain(["railings"]) {
        let (scene, w, h) = case(name);
        // 10,000 lights: no per-light ideal pass, the picture only.
        let ideal = name != "overflow";
        let s = |m| Settings { count_ideal: ideal, ..settings(m) };
        // The cases' frames are `culling`'s (the same scenes, settings and size): rendered once.
        let frame = |s: &Settings| {
            if CASES.contains(&name) {
                crate::culling::case_frame(name, s)
            } else {
                std::sync::Arc::new(render(&scene, s, w, h))
            }
        };
        let reference = frame(&s(CullingMode::Fullscreen));
        for mode in MODES {
            let f = frame(&s(mode));
            assert_finite(&f, name);
            // A frame that does not count shades through its own entry point (`fs_tiled`, no
            // counting atomic): the same picture, byte for byte.
            let quiet = render(&scene, &Settings { count_fragments: false, count_ideal: false, ..s(mode) }, w, h);
            let moved = max_channel_difference(&quiet.image, &f.image);
            assert_eq!(moved, 0, "{name}/{}: the uncounted frame is {moved} steps off the counted", mode.name());
            let step = max_channel_difference(&reference.image, &f.image);
            let (fl, _) = flip(&reference.image, &f.image).unwrap();
            // The FLIP bound of tests/it/culling.rs on its cases; the hard cases are held to one
            // step, as tests/it/hard_cases.rs holds every mode (see the next test for why many
            // overlapping lights differ by a step in places).
            let flip_bound = if CASES.contains(&name) { 0.001 } else { 0.01 };
            assert!(
                step <= 1 && fl.mean <= flip_bound,
                "{name}/{}: {step} steps from fullscreen, FLIP mean {}",
                mode.name(),
                fl.mean
            );
            let method = mode.method().unwrap();
            let t = f.stats.tiles.as_ref().expect("tile stats");
            assert_eq!(t.method, method);
            assert!(f.stats.per_light.iter().all(|l| l.method == method), "{name}/{}", mode.name());
            if !ideal {
                continue;
            }
            assert_eq!(f.stats.ideal_fragments, reference.stats.ideal_fragments, "{name}: the ideal moved");
            for l in &f.stats.per_light {
                let (shaded, ideal) = (l.shaded.unwrap(), l.ideal.unwrap());
                assert!(shaded >= ideal, "{name}/{}: light {} shaded {shaded} < ideal {ideal}", mode.name(), l.index);
            }
            // The lists cull: fewer pairs than every light at every pixel.
            if scene.lights.len() > 4 {
                let full = reference.stats.shaded_fragments.unwrap();
                let shaded = f.stats.shaded_fragments.unwrap();
                assert!(shaded < full, "{name}/{}: {shaded} pairs, fullscreen {full}", mode.name());
            }
        }
    }
}

#[test]
fn every_point_inside_a_light_lies_in_a_cell_whose_list_holds_it() {
    // On the CPU, from the G-buffer's points: for every pixel and every light whose true shape
    // (radius and cone) holds the pixel's point, the list of the pixel's tile or cluster (read
    // back from the GPU) holds the light. And the per-light counts are exactly the pairs the
    // lists give: light i's count is the number of valid pixels whose list holds i.
    let gpu = gpu();
    for name in ["demo", "spot", "inside", "near", "street", "spot-extremes", "grazing", "railings"] {
        let mut scene = scene(name);
        if name == "railings" {
            scene.lights_mut().truncate(256);
        }
        let (w, h) = (160, 90);
        for mode in MODES {
            let s = Settings { count_ideal: false, ..settings(mode) };
            let (r, _, stats) = render_with(&scene, &s, w, h);
            let lists = r.last_frame().tile_lists(gpu).unwrap().expect("the frame's lists");
            let points = r.last_frame().view_positions(gpu).unwrap();
            let lights = r.last_frame().light_records();
            // Pairs per light: at least (`pairs`) and at most (`pairs_hi`) what the lists give
            // (a point within a twentieth of a slice or bin of a boundary may fall on either
            // side in f32 on the GPU and from the f64 point here: both cells are tried, and
            // every light reaching the point must be in both).
            let mut pairs = vec![0u64; lights.len()];
            let mut pairs_hi = vec![0u64; lights.len()];
            let mut inside = 0;
            for (k, p) in points.iter().enumerate() {
                let Some(p) = p else { continue };
                let (x, y) = (k as u32 % w, k as u32 / w);
                let candidates: Vec<Vec<u32>> =
                    lists.cells_near(x, y, -p.z, 0.05).into_iter().map(|c| lists.list(c)).collect();
                let list = candidates.concat();
                for i in 0..lights.len() as u32 {
                    let held = candidates.iter().filter(|l| l.contains(&i)).count();
                    pairs[i as usize] += (held == candidates.len()) as u64;
                    pairs_hi[i as usize] += (held > 0) as u64;
                }
                for (i, l) in lights.iter().enumerate() {
                    if inside_light(l, *p) {
                        inside += 1;
                        assert!(
                            candidates.iter().all(|l| l.contains(&(i as u32))),
                            "{name}/{}: light {i} reaches pixel ({x}, {y}) but its list {list:?} lacks it",
                            mode.name()
                        );
                    }
                }
            }
            assert!(inside > 100, "{name}: only {inside} light-point pairs inside a light");
            let t = stats.tiles.as_ref().unwrap();
            if mode == CullingMode::Zbin {
                // The masks' bits: the GPU's lie inside the lights' rectangles (the CPU's
                // reference; the depth bounds take tiles out), the test above holds that none
                // a light reaches is missing, and a tile's entries are its bits.
                let job = r.last_frame().zbin_job().expect("a z-binned frame's job");
                let rect = job.rect_masks();
                assert_eq!(lists.masks.len(), rect.len());
                let outside = lists.masks.iter().zip(&rect).any(|(g, c)| g & !c != 0);
                assert!(!outside, "{name}: a bit outside its light's rectangle");
                let bits: u64 = lists.masks.iter().map(|w| w.count_ones() as u64).sum();
                assert!(t.entries == bits && bits <= job.entries, "{name}: {} entries, {bits} bits", t.entries);
            } else {
                assert_eq!(t.entries, (0..t.cells as usize).map(|c| lists.list(c).len() as u64).sum::<u64>());
            }
            assert_eq!(t.overflowed, 0);
            for ((l, &expected), &most) in stats.per_light.iter().zip(&pairs).zip(&pairs_hi) {
                let shaded = l.shaded.unwrap();
                assert!(
                    (expected..=most).contains(&shaded),
                    "{name}/{}: light {} counted {shaded} pairs, its lists give {expected}..={most}",
                    mode.name(),
                    l.index
                );
            }
        }
    }
}

#[test]
fn the_lists_sum_closer_to_the_exact_light_than_per_light_blending() {
    // `street` (64 overlapping lights): every per-light mode blends each light into the fp16
    // target, rounding once per light, in light order (volume equals fullscreen bit for bit);
    // the tiled pass sums a pixel's lights in f32 and rounds once. So its picture differs from
    // fullscreen's by up to one 8-bit step on some pixels, and the reason is fullscreen's error:
    // against an Rgba32Float full-screen frame, tiled and clustered are closer than fullscreen.
    let scene = scene("street");
    let s = |culling| Settings { culling, count_ideal: false, ..settings(culling) };
    let exact =
        render(&scene, &Settings { accumulation: AccumFormat::Rgba32Float, ..s(CullingMode::Fullscreen) }, 160, 90);
    let error = |f: &Frame| {
        let (mut worst, mut sum) = (0f32, 0f64);
        for (a, b) in exact.diffuse.iter().zip(&f.diffuse).chain(exact.specular.iter().zip(&f.specular)) {
            let e = (a - b).abs() / a.abs().max(1e-3);
            worst = worst.max(e);
            sum += e as f64;
        }
        (worst, sum / (2 * exact.diffuse.len()) as f64)
    };
    let full = error(&render(&scene, &s(CullingMode::Fullscreen), 160, 90));
    for mode in MODES {
        let e = error(&render(&scene, &s(mode), 160, 90));
        println!(
            "{}: worst {:.2e}, mean {:.2e}; fullscreen worst {:.2e}, mean {:.2e}",
            mode.name(),
            e.0,
            e.1,
            full.0,
            full.1
        );
        assert!(e.0 <= full.0 && e.1 <= full.1, "{}: {e:?} from the f32 sum, fullscreen {full:?}", mode.name());
    }
}

#[test]
fn with_log_accumulation_the_one_write_stays_within_two_writes_of_the_exact_light() {
    // Seed 004's Rgba8 log accumulation rounds once per write: a per-light mode writes once per
    // light touching a pixel (its bound grows with them, tests/core.rs), the tiled pass once per
    // pixel after the ambient + sun write, whatever the list. So its error is held to the bound
    // of two writes against the Rgba32Float full-screen frame, far tighter than fullscreen's own
    // (which is why tests/it/culling.rs does not hold tiled and clustered to fullscreen-log).
    use lampshade::renderer::settings::{log_accum_error_bound, LOG_ACCUM_MAX};
    for name in ["demo", "spot"] {
        let (scene, w, h) = case(name);
        let exact = render(
            &scene,
            &Settings { accumulation: AccumFormat::Rgba32Float, ..settings(CullingMode::Fullscreen) },
            w,
            h,
        );
        for mode in MODES {
            let log = render(
                &scene,
                &Settings { accumulation: AccumFormat::Rgba8Log, count_ideal: false, ..settings(mode) },
                w,
                h,
            );
            let (mut checked, mut brightest) = (0, 0f32);
            for (got, want) in log.diffuse.iter().zip(&exact.diffuse).chain(log.specular.iter().zip(&exact.specular)) {
                let bound = log_accum_error_bound(*want, 2);
                if want + bound > LOG_ACCUM_MAX - 0.5 {
                    continue;
                }
                checked += 1;
                brightest = brightest.max(*want);
                assert!(
                    (got - want).abs() <= bound + 1e-5,
                    "{name}/{}: decoded {got}, exact {want}, bound {bound}",
                    mode.name()
                );
            }
            assert!(checked > exact.diffuse.len(), "{name}: only {checked} values checked");
            assert!(brightest > 0.5, "{name}: the check never saw bright light ({brightest})");
        }
    }
}

fn srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

#[test]
fn the_tile_lights_view_shows_each_pixels_list_length() {
    // The view's colour at every pixel is the colour map at the length of the pixel's list
    // (read back), for tiled and clustered frames and for a volume frame (which builds tiled
    // lists for the view alone); background pixels are dark grey.
    let gpu = gpu();
    let scene = scene("demo");
    let (w, h) = (160, 90);
    for mode in [CullingMode::Tiled, CullingMode::Clustered, CullingMode::Zbin, CullingMode::Volume] {
        let s = Settings { debug_view: DebugView::TileLights, count_ideal: false, ..settings(mode) };
        let (r, image, stats) = render_with(&scene, &s, w, h);
        let lists = r.last_frame().tile_lists(gpu).unwrap().expect("lists for the view");
        let expected_mode = match mode {
            CullingMode::Clustered => 1,
            CullingMode::Zbin => 2,
            _ => 0,
        };
        assert_eq!(lists.params.mode, expected_mode, "{}", mode.name());
        let points = r.last_frame().view_positions(gpu).unwrap();
        let mut lengths = std::collections::BTreeSet::new();
        for (k, p) in points.iter().enumerate() {
            let (x, y) = (k as u32 % w, k as u32 / w);
            // A point within a twentieth of a slice or bin of a boundary may fall on either side
            // (f32 on the GPU, f64 here): either cell's length passes.
            let colour = |n: usize| {
                if n == 0 {
                    [0.02; 3]
                } else {
                    lampshade::renderer::tiles::heat(n as f32 / lampshade::renderer::tiles::HEAT_MAX)
                }
            };
            let expected: Vec<[f32; 3]> = match p {
                Some(p) => {
                    let cells = lists.cells_near(x, y, -p.z, 0.05);
                    lengths.insert(lists.list(cells[0]).len());
                    cells.into_iter().map(|c| colour(lists.list(c).len())).collect()
                }
                None => vec![[0.02; 3]],
            };
            let got = image.get_pixel(x, y);
            let matches = |e: &[f32; 3]| (0..3).all(|c| (got[c] as f32 - srgb(e[c]) * 255.0).abs() <= 2.0);
            assert!(
                expected.iter().any(matches),
                "{}: pixel ({x}, {y}) is {:?}, the map gives {:?}",
                mode.name(),
                got,
                expected.iter().map(|e| e.map(|v| srgb(v) * 255.0)).collect::<Vec<_>>()
            );
        }
        assert!(lengths.len() > 5, "{}: too few distinct list lengths {lengths:?}", mode.name());
        let t = stats.tiles.as_ref().unwrap();
        if mode == CullingMode::Zbin {
            // A tile's longest walk is its whole mask.
            let words = lists.params.words as usize;
            let longest = lists.masks.chunks(words).map(|m| m.iter().map(|w| w.count_ones()).sum::<u32>()).max();
            assert_eq!(Some(t.longest), longest);
        } else {
            assert_eq!(t.longest as usize, (0..t.cells as usize).map(|c| lists.list(c).len()).max().unwrap());
        }
        if mode == CullingMode::Volume {
            // The view builds lists; the frame still draws volumes.
            assert!(stats.per_light.iter().all(|l| l.method == Method::Volume));
        }
    }
}

/// `--tile-view-depth D` on a clustered frame (the viewer's cluster slice): every pixel,
/// background included, shows the length of its tile's list at view depth D, the colour map
/// at that length; slices near and far differ; 0 is the per-pixel view above.
#[test]
fn the_cluster_slice_view_shows_each_tiles_list_at_the_chosen_depth() {
    let gpu = gpu();
    let scene = scene("demo");
    let (w, h) = (160, 90);
    let mut seen = Vec::new();
    for depth in [6.0f32, 25.0] {
        let s = Settings {
            debug_view: DebugView::TileLights,
            count_ideal: false,
            tile_view_depth: depth,
            ..settings(CullingMode::Clustered)
        };
        let (r, image, _) = render_with(&scene, &s, w, h);
        let lists = r.last_frame().tile_lists(gpu).unwrap().expect("lists for the view");
        assert_eq!(lists.params.mode, 1);
        let mut total = 0usize;
        for y in 0..h {
            for x in 0..w {
                let n = lists.list(lists.cell(x, y, depth)).len();
                total += n;
                let expected = if n == 0 {
                    [0.02; 3]
                } else {
                    lampshade::renderer::tiles::heat(n as f32 / lampshade::renderer::tiles::HEAT_MAX)
                };
                let got = image.get_pixel(x, y);
                for c in 0..3 {
                    let want = srgb(expected[c]) * 255.0;
                    assert!(
                        (got[c] as f32 - want).abs() <= 2.0,
                        "slice at {depth}: pixel ({x}, {y}) channel {c} is {}, the map gives {want:.1} ({n} lights)",
                        got[c]
                    );
                }
            }
        }
        assert!(total > 0, "the slice at {depth} holds no light");
        seen.push(total);
    }
    assert_ne!(seen[0], seen[1], "the slices at two depths show the same lists");
}

#[test]
fn the_gpu_builds_the_cpus_clustered_lists_and_the_same_picture() {
    // `--cluster-build gpu` runs the CPU's tests (tiles::light_cells) in a compute pass and
    // sorts each list into light order: the lists read back are the CPU's, entry for entry,
    // and the frames are the same bit for bit (the same lights summed in the same order).
    // Scenes: lights in front of, across and behind the near plane, spots, a street of
    // lights among the camera, and 1,028 lights (the two-thread CPU path).
    let gpu = gpu();
    for name in ["demo", "spot", "inside", "near", "street", "spot-extremes", "grazing", "tiny-radius"] {
        let scene = scene(name);
        let (w, h) = (200, 120);
        let built = |b: ClusterBuilder| {
            let s = Settings { cluster_build: b, count_ideal: false, ..settings(CullingMode::Clustered) };
            let (r, image, stats) = render_with(&scene, &s, w, h);
            (r.last_frame().tile_lists(gpu).unwrap().expect("the frame's lists"), image, stats)
        };
        let (cpu, cpu_image, cpu_stats) = built(ClusterBuilder::Cpu);
        let (on_gpu, gpu_image, gpu_stats) = built(ClusterBuilder::Gpu);
        assert!(gpu_stats.lists_on_gpu && !cpu_stats.lists_on_gpu, "{name}");
        let p = &cpu.params;
        assert_eq!(
            (p.tiles_x, p.tiles_y, p.slices, p.slice_scale, p.slice_bias),
            (
                on_gpu.params.tiles_x,
                on_gpu.params.tiles_y,
                on_gpu.params.slices,
                on_gpu.params.slice_scale,
                on_gpu.params.slice_bias
            ),
            "{name}: the grid"
        );
        let cells = (p.tiles_x * p.tiles_y * p.slices) as usize;
        let mut entries = 0;
        for c in 0..cells {
            let (a, b) = (cpu.list(c), on_gpu.list(c));
            assert_eq!(a, b, "{name}: cluster {c}'s list");
            entries += a.len();
        }
        assert!(entries > 0, "{name}: no entries");
        assert_eq!(cpu_stats.tiles.as_ref().unwrap().entries, gpu_stats.tiles.as_ref().unwrap().entries, "{name}");
        assert_eq!(cpu_stats.shaded_fragments, gpu_stats.shaded_fragments, "{name}");
        assert!(cpu_image == gpu_image, "{name}: the pictures differ");
    }
}

/// The light planes (`records::light_planes`: the light records again, in four uniform arrays)
/// are what every per-pixel light loop reads when a scene has at most 4,096 lights and no
/// cookies; with more, the loops read the storage buffer. `demo` with 4,096 lights (planes),
/// then with a 4,097th light behind the camera that reaches nothing (storage): the same result,
/// bit for bit — the light sums on the deferred paths, the HDR colour on the forward ones —
/// in the per-pixel loops (tiled, clustered with the CPU's and the GPU's lists, the forward
/// paths), the light pass (volume and stencil, deferred and the light pre-pass), the ideal
/// count's pass, and with the spots' shadows, every light's (cubes: the tile count 6 comes from
/// the planes) and none. Fails if a plane holds a field in the wrong place (with the planes'
/// falloff scaled by 1.001, or their first shadow tile off by one).
#[test]
fn the_light_planes_give_the_storage_buffers_picture() {
    use lampshade::renderer::post::PostImage;
    use lampshade::renderer::{RenderPath, ShadowMode};
    use lampshade::scene::builtin::{self, BuiltinOptions};
    use lampshade::scene::{Light, PointLight};
    let planes = builtin::build("demo", BuiltinOptions { lights: Some(4092), time: 0.0 }).expect("demo");
    assert_eq!(planes.lights.len(), 4096, "demo's spots and 4,092 point lights");
    let mut storage = planes.clone();
    storage.lights_mut().push(Light::Point(PointLight {
        position: planes.camera.position - planes.camera.forward() * 5.0,
        color: glam::Vec3::ONE,
        intensity: 1.0,
        radius: 0.01,
        cast_shadows: false,
        cookie: None,
        mask: lampshade::scene::ALL_LAYERS,
    }));
    let (w, h) = (160, 90);
    let base = [Settings::default(), Settings { shadows: ShadowMode::All, ..Settings::default() }, unshadowed()];
    let configs = base.iter().flat_map(|s| {
        [CullingMode::Clustered, CullingMode::Tiled, CullingMode::Volume, CullingMode::StencilReplace]
            .map(|culling| Settings { culling, ..s.clone() })
            .into_iter()
            .chain([
                Settings { culling: CullingMode::Clustered, cluster_build: ClusterBuilder::Gpu, ..s.clone() },
                Settings { culling: CullingMode::Volume, count_ideal: true, ..s.clone() },
            ])
            .chain(
                [RenderPath::Forward, RenderPath::ForwardMultipass, RenderPath::LightPrepass]
                    .map(|path| Settings { path, ..s.clone() }),
            )
    });
    let gpu = gpu();
    // The light sums (deferred, light pre-pass) or the HDR colour (forward paths), and the image.
    let run = |scene: &Scene, s: &Settings| {
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s).expect("renderer");
        let (image, stats) = render_image(gpu, &mut r, scene, s, w, h).expect("render");
        let values = match s.path {
            RenderPath::Forward | RenderPath::ForwardMultipass => r
                .last_frame()
                .read_post_image(gpu, PostImage::Hdr)
                .expect("readback")
                .expect("the forward paths' HDR colour"),
            _ => {
                let (d, sp) = r.last_frame().read_accumulation(gpu).expect("accumulation readback");
                d.into_iter().chain(sp).collect()
            }
        };
        (image, stats, values)
    };
    for s in configs {
        let (ia, sa, a) = run(&planes, &s);
        let (ib, sb, b) = run(&storage, &s);
        let what = format!("{} {} shadows {}", s.culling.name(), s.path.name(), s.shadows.name());
        // The planes are llvmpipe's workaround (`Quirks::uniform_gathers`): other adapters read
        // storage at any count, and the two frames then compare storage with storage.
        let gathers = gpu.caps.quirks.uniform_gathers;
        assert_eq!(sa.shader_lookups.iter().any(|l| l == "light planes"), gathers, "{what}: 4,096 lights");
        assert!(!sb.shader_lookups.iter().any(|l| l == "light planes"), "{what}: 4,097 read storage");
        assert!(lit_share(&ia) > 0.2, "{what}: the frame is lit");
        assert!(a.iter().any(|v| *v > 0.0), "{what}: nothing read back");
        assert!(a == b, "{what}: the light sums or HDR colour differ");
        assert_eq!(max_channel_difference(&ia, &ib), 0, "{what}");
        assert_eq!(sa.ideal_fragments, sb.ideal_fragments, "{what}: the ideal count");
    }
}

/// `overflow` (10,000 overlapping lights) at 640x360: the CPU's clustered lists hold about
/// 43 M entries, past the 128 MiB one storage binding may hold (wgpu refused the bind group
/// and the renderer panicked). The cells past the limit walk every light instead. The light
/// sums are the GPU-built lists' (which overflow by their own rule) within one fp16 step
/// (2^-10 of the value): on this scene the two builders differ by that much even where
/// nothing overflows (72 of 57,600 pixels at 320x180, before this fix too).
#[test]
fn clustered_lists_past_one_binding_overflow_into_walking_every_light() {
    let scene = scene("overflow");
    let (w, h) = (640, 360);
    // Counted (the overflowed cells are in the counted frame's stats) with the CPU's lists.
    let built = |b: ClusterBuilder| {
        let s = Settings {
            cluster_build: b,
            count_fragments: b == ClusterBuilder::Cpu,
            count_ideal: false,
            ..settings(CullingMode::Clustered)
        };
        render(&scene, &s, w, h)
    };
    let cpu = built(ClusterBuilder::Cpu);
    let on_gpu = built(ClusterBuilder::Gpu);
    assert_finite(&cpu, "overflow, CPU-built lists");
    let t = cpu.stats.tiles.as_ref().expect("tile stats");
    assert!(t.overflowed > 0, "the lists fit after all: {} cells overflowed", t.overflowed);
    let a = cpu.diffuse.iter().chain(&cpu.specular);
    let b = on_gpu.diffuse.iter().chain(&on_gpu.specular);
    let off = a.zip(b).filter(|(x, y)| (*x - *y).abs() > x.abs().max(y.abs()) / 1024.0).count();
    assert_eq!(off, 0, "{off} light sums differ by more than an fp16 step");
    assert!(lit_share(&cpu.image) > 0.5, "the frame is lit");
}

/// lavapipe ends a shader invocation's loops after 65,535 iterations between them, silently.
/// The GPU's list build walks a light's span of clusters in one invocation: `inside` (the
/// camera within a light) at 2560x1440 has a span of 80 x 45 tiles x 64 slices, and with the
/// GPU's lists the frame shaded nothing. Such frames build their lists on the CPU
/// (`tiles::GPU_LOOP_BUDGET`): the same picture as the CPU's lists, and the light there.
#[test]
fn a_light_too_wide_for_the_gpus_list_build_gets_the_cpus_lists() {
    let scene = scene("inside");
    let (w, h) = (2560, 1440);
    let built = |b: ClusterBuilder| {
        let s = Settings { cluster_build: b, count_ideal: false, ..settings(CullingMode::Clustered) };
        render(&scene, &s, w, h)
    };
    let (cpu, asked_gpu) = (built(ClusterBuilder::Cpu), built(ClusterBuilder::Gpu));
    assert!(asked_gpu.stats.shaded_fragments.unwrap_or(0) > 1_000_000, "{:?} pairs", asked_gpu.stats.shaded_fragments);
    assert!(lit_share(&asked_gpu.image) > 0.5, "the frame is lit");
    assert_eq!(max_channel_difference(&cpu.image, &asked_gpu.image), 0);
    // Under a loop limit (llvmpipe's) the CPU builds them; an adapter without one builds them
    // on the GPU whole.
    let limited = gpu().caps.quirks.loop_limit.is_some();
    assert_eq!(asked_gpu.stats.lists_on_gpu, !limited, "who built the lists under loop limit {limited}");
    // At the tests' usual size the GPU still builds them.
    let small = render(
        &scene,
        &Settings { cluster_build: ClusterBuilder::Gpu, count_ideal: false, ..settings(CullingMode::Clustered) },
        W,
        H,
    );
    assert!(small.stats.lists_on_gpu);
}
