//! Engine-style caps (`lampshade::renderer::caps`): a cap that is not reached changes nothing,
//! bit for bit; a cap that is reached drops exactly the lights it states, and the light the
//! frame lost is what brute force gives for those lights where the cap dropped them.

use crate::common::*;
use glam::{DMat4, DVec3, Vec3};
use lampshade::headless::render_image;
use lampshade::oracle::rounding_bound;
use lampshade::renderer::caps::{CapOrder, CapStats};
use lampshade::renderer::explain::brute::BruteForce;
use lampshade::renderer::post::PostImage;
use lampshade::renderer::{CullingMode, RenderPath, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::{Camera, Light, Material, Mesh, Object, PointLight, Scene};

const W: u32 = 128;
const H: u32 = 72;

/// A wall 12 units before the camera and `n` point lights just before it on a 6 x 4 grid (more
/// rows past 24), every light in view, radii 1.5-3 so that several share each 32-pixel tile,
/// intensities and colours varied so that "nearest" and "brightest" pick different lights.
fn wall_scene(n: usize) -> Scene {
    let camera = Camera::looking_at(DVec3::new(0.0, 0.0, 12.0), DVec3::ZERO);
    let mut s = Scene { meshes: vec![Mesh::cube()], ..Scene::new("caps-wall", camera) };
    s.sun = None;
    s.materials.push(Material { specular_level: 0.3, specular_exponent: 32.0, ..Material::diffuse(Vec3::splat(0.6)) });
    s.objects.push(Object {
        mesh: 0,
        material: 0,
        transform: DMat4::from_scale_rotation_translation(
            DVec3::new(24.0, 14.0, 0.2),
            Default::default(),
            DVec3::new(0.0, 0.0, -0.1),
        ),
        layer: 0,
    });
    let lights = (0..n)
        .map(|i| {
            let (col, row) = ((i % 6) as f64, (i / 6) as f64);
            let k = i as f32;
            Light::Point(PointLight {
                position: DVec3::new(
                    -6.0 + 2.4 * col,
                    -3.0 + 2.0 * (row % 4.0) + 0.3 * (row / 4.0).floor(),
                    0.5 + 0.1 * (i % 5) as f64,
                ),
                color: Vec3::new(0.5 + 0.5 * (k * 0.37).fract(), 0.5 + 0.5 * (k * 0.61).fract(), 0.6),
                intensity: 0.5 + (k * 0.73).fract() * 2.0,
                radius: 1.5 + 1.5 * (k * 0.29).fract(),
                cookie: None,
                mask: lampshade::scene::ALL_LAYERS,
                cast_shadows: false,
            })
        })
        .collect();
    s.set_lights(lights);
    s
}

fn base(culling: CullingMode) -> Settings {
    Settings { culling, count_fragments: false, timestamps: false, ..unshadowed() }
}

/// Renders `scene` with `s` into `r`; the frame's stats.
fn draw(r: &mut Renderer, scene: &Scene, s: &Settings) -> lampshade::FrameStats {
    render_image(gpu(), r, scene, s, W, H).expect("render").1
}

/// The accumulated light of `r`'s last frame: (diffuse, specular) RGBA per pixel.
fn light(r: &Renderer) -> (Vec<f32>, Vec<f32>) {
    r.last_frame().read_accumulation(gpu()).expect("accumulation")
}

/// Brute force over `scene` drawn with `s` (every light of the scene at every pixel).
fn brute(r: &mut Renderer, scene: &Scene, s: &Settings) -> BruteForce {
    draw(r, scene, s);
    r.last_frame().brute_force(gpu()).expect("brute force")
}

/// Holds a frame's light (its accumulation minus the lightless frame's) against `expected`
/// (diffuse, specular RGB per pixel), channel by channel, within the accumulation's rounding for
/// the `k` lights brute force counts there. Returns the worst ratio to the bound.
fn hold(
    lit: &(Vec<f32>, Vec<f32>),
    dark: &(Vec<f32>, Vec<f32>),
    expected: &[([f32; 3], [f32; 3])],
    k: &[u32],
    what: &str,
) {
    let format = Settings::default().accumulation;
    for (p, (d, sp)) in expected.iter().enumerate() {
        for c in 0..3 {
            for (acc, rest, want) in
                [(lit.0[4 * p + c], dark.0[4 * p + c], d[c]), (lit.1[4 * p + c], dark.1[4 * p + c], sp[c])]
            {
                let bound = rounding_bound(format, acc.max(rest + want), k[p]);
                let got = acc - rest;
                assert!(
                    (got - want).abs() <= bound,
                    "{what}: pixel ({}, {}) channel {c}: the frame added {got}, the lights it kept add {want} (bound {bound})",
                    p as u32 % W,
                    p as u32 / W
                );
            }
        }
    }
}

fn caps_of(stats: &lampshade::FrameStats) -> CapStats {
    stats.caps.clone().expect("a frame with a cap set reports it")
}

#[test]
fn a_cap_that_is_not_reached_changes_no_pixel() {
    let scene = wall_scene(24);
    let n = scene.lights.len().to_string();
    type Case<'a> = (CullingMode, RenderPath, &'a [(&'a str, &'a str)]);
    let cases: &[Case] = &[
        (CullingMode::Clustered, RenderPath::Deferred, &[("max-lights", &n), ("cap-order", "brightest")]),
        (CullingMode::Volume, RenderPath::Deferred, &[("max-lights", &n), ("cap-order", "nearest")]),
        (CullingMode::Tiled, RenderPath::Deferred, &[("light-distance", "1000")]),
        (CullingMode::Clustered, RenderPath::Deferred, &[("lights-per-cluster", "1000")]),
        (CullingMode::Clustered, RenderPath::Deferred, &[("lights-per-cluster", "1000"), ("cap-order", "nearest")]),
        (CullingMode::Clustered, RenderPath::Forward, &[("lights-per-object", "1000")]),
    ];
    let gpu = gpu();
    for &(culling, path, knobs) in cases {
        let plain = Settings { path, ..base(culling) };
        let mut capped = plain.clone();
        for (k, v) in knobs {
            capped.set(k, v).unwrap();
        }
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &plain).unwrap();
        let (a, _) = render_image(gpu, &mut r, &scene, &plain, W, H).unwrap();
        let hdr_a = r.last_frame().read_post_image(gpu, PostImage::Hdr).unwrap();
        let (b, stats) = render_image(gpu, &mut r, &scene, &capped, W, H).unwrap();
        let hdr_b = r.last_frame().read_post_image(gpu, PostImage::Hdr).unwrap();
        let what = format!("{}/{} {knobs:?}", path.name(), culling.name());
        let caps = caps_of(&stats);
        assert!(!caps.reached(), "{what}: {caps:?}");
        assert_eq!(a.as_raw(), b.as_raw(), "{what}: the picture moved");
        assert_eq!(hdr_a, hdr_b, "{what}: the HDR colour moved");
    }
}

#[test]
fn a_grid_changes_the_lists_and_not_the_picture() {
    // Bevy's grid (4,096 cells, 24 slices, the first to 5 units) and three.js's flat tiles
    // against the default: the lists are conservative in any grid, so only the cost moves.
    let scene = wall_scene(24);
    let gpu = gpu();
    let plain = base(CullingMode::Clustered);
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &plain).unwrap();
    draw(&mut r, &scene, &plain);
    let reference = light(&r);
    let default_lists = r.last_frame().tile_lists(gpu).unwrap().expect("lists").data;
    for knobs in [
        &[("cluster-budget", "4096"), ("cluster-slices", "24"), ("first-slice-depth", "5")][..],
        &[("cluster-tile", "32"), ("cluster-slices", "1")][..],
        &[("cluster-tile", "8"), ("cluster-slices", "3"), ("first-slice-depth", "11.9")][..],
        // Every light wholly before the first slice's end (they reach 8-15 units deep).
        &[("cluster-slices", "24"), ("first-slice-depth", "20")][..],
    ] {
        let mut s = plain.clone();
        for (k, v) in knobs {
            s.set(k, v).unwrap();
        }
        draw(&mut r, &scene, &s);
        let lists = r.last_frame().tile_lists(gpu).unwrap().expect("lists");
        assert_ne!(lists.data, default_lists, "{knobs:?}: the grid was not used");
        let got = light(&r);
        let off = got.0.iter().zip(&reference.0).chain(got.1.iter().zip(&reference.1)).filter(|(a, b)| a != b).count();
        assert_eq!(off, 0, "{knobs:?}: {off} channels moved");
    }
}

#[test]
fn the_camera_caps_keep_the_lights_their_order_names_and_the_frame_loses_exactly_the_rest() {
    let scene = wall_scene(24);
    let gpu = gpu();
    let plain = base(CullingMode::Clustered);
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &plain).unwrap();
    let mut dark_scene = scene.clone();
    dark_scene.set_lights(Vec::new());
    draw(&mut r, &dark_scene, &plain);
    let dark = light(&r);
    let all = brute(&mut r, &scene, &plain);
    let eye = scene.camera.position;
    let reach = |l: &Light| (l.position() - eye).length() - l.radius() as f64;
    let score = |l: &Light| {
        let (d, rr) = ((l.position() - eye).length(), l.radius() as f64);
        lampshade::renderer::caps::peak(l) * if d <= rr { 1.0 } else { (rr / d).powi(2) }
    };
    let distance = {
        let mut d: Vec<f64> = scene.lights.iter().map(reach).collect();
        d.sort_by(f64::total_cmp);
        d[d.len() / 2]
    };
    let cases: Vec<(String, Settings)> = [CapOrder::Scene, CapOrder::Nearest, CapOrder::Brightest]
        .into_iter()
        .map(|order| {
            (format!("max-lights 10, {order:?}"), Settings { max_lights: 10, cap_order: order, ..plain.clone() })
        })
        .chain([(format!("light-distance {distance}"), Settings { light_distance: distance as f32, ..plain.clone() })])
        .collect();
    for (what, s) in cases {
        let stats = draw(&mut r, &scene, &s);
        let lit = light(&r);
        let caps = caps_of(&stats);
        let kept = caps.kept.clone().expect("the cap dropped lights");
        let dropped: Vec<usize> = (0..scene.lights.len()).filter(|i| !kept.contains(&(*i as u32))).collect();
        assert_eq!(stats.lights, kept.len(), "{what}: the frame drew the lights it kept");
        assert_eq!((caps.dropped_by_count + caps.dropped_by_distance) as usize, dropped.len(), "{what}");
        // The rule, checked from the lights (every light is in view).
        let l = |i: usize| &scene.lights[i];
        let k = |i: &u32| *i as usize;
        match (s.max_lights, s.cap_order) {
            (10, CapOrder::Scene) => assert_eq!(kept, (0..10).collect::<Vec<u32>>(), "{what}"),
            (10, CapOrder::Nearest) => {
                let far_kept = kept.iter().map(|i| reach(l(k(i)))).fold(f64::MIN, f64::max);
                assert!(dropped.iter().all(|&i| reach(l(i)) >= far_kept), "{what}: a nearer light was dropped");
            }
            (10, CapOrder::Brightest) => {
                let dim_kept = kept.iter().map(|i| score(l(k(i)))).fold(f64::MAX, f64::min);
                assert!(dropped.iter().all(|&i| score(l(i)) <= dim_kept), "{what}: a brighter light was dropped");
            }
            _ => {
                assert!(kept.iter().all(|i| reach(l(k(i))) <= distance), "{what}");
                assert!(dropped.iter().all(|&i| reach(l(i)) > distance), "{what}");
            }
        }
        // Against brute force: the frame's light plus brute force over the dropped lights alone
        // is brute force over every light.
        let mut dropped_scene = scene.clone();
        dropped_scene.set_lights(dropped.iter().map(|&i| scene.lights[i]).collect());
        let lost = brute(&mut r, &dropped_scene, &plain);
        let expected: Vec<([f32; 3], [f32; 3])> = (0..all.diffuse.len())
            .map(|p| {
                let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                (sub(all.diffuse[p], lost.diffuse[p]), sub(all.specular[p], lost.specular[p]))
            })
            .collect();
        hold(&lit, &dark, &expected, &all.adding, &what);
        let pairs: u64 = lost.adding.iter().map(|&n| n as u64).sum();
        assert!(pairs > 0, "{what}: the dropped lights reached no pixel: the case tests nothing");
    }
}

#[test]
fn the_cluster_cap_keeps_what_it_states_per_cell_and_the_frame_loses_exactly_the_rest() {
    // One slice of 32-pixel tiles (three.js's tiles): a pixel's cell is its tile, so brute force
    // light by light says what each pixel's kept lights add.
    let scene = wall_scene(24);
    let gpu = gpu();
    let plain = Settings { cluster_tile: 32, cluster_slices: 1, ..base(CullingMode::Clustered) };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &plain).unwrap();
    let mut one = scene.clone();
    one.set_lights(Vec::new());
    draw(&mut r, &one, &plain);
    let dark = light(&r);
    let each: Vec<BruteForce> = (0..scene.lights.len())
        .map(|i| {
            one.set_lights(vec![scene.lights[i]]);
            brute(&mut r, &one, &plain)
        })
        .collect();
    let all = brute(&mut r, &scene, &plain);
    let full = r.last_frame().tile_lists(gpu).unwrap().expect("lists");
    for order in [CapOrder::Scene, CapOrder::Nearest, CapOrder::Brightest] {
        let what = format!("lights-per-cluster 3, {order:?}");
        let s = Settings { lights_per_cluster: 3, cap_order: order, ..plain.clone() };
        let stats = draw(&mut r, &scene, &s);
        let lit = light(&r);
        let lists = r.last_frame().tile_lists(gpu).unwrap().expect("lists");
        // The dropped entries' reached pairs, entry by entry: a pixel's tile's uncapped entries
        // that its capped list lacks, whose light's shape holds the pixel's point.
        let records = r.last_frame().light_records().to_vec();
        let reached_dropped: u64 = r
            .last_frame()
            .view_positions(gpu)
            .unwrap()
            .iter()
            .enumerate()
            .filter_map(|(p, q)| q.map(|q| (p as u32, q)))
            .map(|(p, q)| {
                let cell = lists.cell(p % W, p / W, -q.z);
                let kept = lists.list(cell);
                full.list(cell)
                    .iter()
                    .filter(|l| !kept.contains(l))
                    .filter(|&&l| lampshade::renderer::inspect::inside_light(&records[l as usize], q))
                    .count() as u64
            })
            .sum();
        let cells = (lists.params.tiles_x * lists.params.tiles_y) as usize;
        let mut dropped = 0u64;
        for c in 0..cells {
            let (a, b) = (full.list(c), lists.list(c));
            assert_eq!(b.len(), a.len().min(3), "{what}: cell {c}");
            assert!(
                b.windows(2).all(|w| w[0] < w[1]) && b.iter().all(|l| a.contains(l)),
                "{what}: cell {c}: {b:?} of {a:?}"
            );
            if order == CapOrder::Scene {
                assert_eq!(b, a[..b.len()], "{what}: cell {c}");
            }
            dropped += (a.len() - b.len()) as u64;
        }
        assert!(dropped > 0, "{what}: the cap was not reached: the case tests nothing");
        assert_eq!(caps_of(&stats).cluster_entries_dropped, dropped, "{what}");
        // Per pixel: the kept lights of its tile, light by light.
        let mut lost_pairs = 0u64;
        let expected: Vec<([f32; 3], [f32; 3])> = (0..(W * H) as usize)
            .map(|p| {
                let cell = lists.cell(p as u32 % W, p as u32 / W, 1.0);
                let kept = lists.list(cell);
                let (mut d, mut sp) = ([0f32; 3], [0f32; 3]);
                for (i, b) in each.iter().enumerate() {
                    if kept.contains(&(i as u32)) {
                        for c in 0..3 {
                            d[c] += b.diffuse[p][c];
                            sp[c] += b.specular[p][c];
                        }
                    } else {
                        lost_pairs += b.adding[p] as u64;
                    }
                }
                (d, sp)
            })
            .collect();
        hold(&lit, &dark, &expected, &all.adding, &what);
        assert!(lost_pairs > 0, "{what}: no dropped pair reached a pixel");
        // The pairs the bench reports: the dropped entries' pairs whose light reaches the
        // pixel's point, at least the pairs that add light (N.L and the falloff's zero at the
        // rim make some reached pairs add nothing).
        let loss = lampshade::oracle::cap_loss(gpu, &mut r, &scene, &s, (W, H)).unwrap();
        let entry = loss.entry_pairs.expect("entry pairs");
        assert_eq!(
            entry, reached_dropped,
            "{what}: the bench's entry pairs against the dropped entries, pixel by pixel"
        );
        assert!(entry >= lost_pairs, "{what}: {entry} reached pairs dropped, {lost_pairs} adding");
    }
    // The count's other half: over the uncapped lists, every pair whose light's shape holds
    // the pixel's point is listed, as many as the GPU's ideal count (`fs_ideal`) finds.
    let counted = Settings { count_ideal: true, ..plain.clone() };
    let stats = draw(&mut r, &scene, &counted);
    let listed = lampshade::oracle::listed_reached_pairs(gpu, &r).unwrap().expect("lists");
    assert_eq!(Some(listed), stats.ideal_fragments, "reached pairs over the uncapped lists against the ideal count");
}

#[test]
fn the_object_cap_keeps_what_it_states_per_object_on_the_forward_path() {
    // Two boxes 8 apart, six lights before each that reach only their own box: each box's list
    // is its six lights, and keeping k of them per object is keeping those k in the scene.
    let camera = Camera::looking_at(DVec3::new(0.0, 0.0, 12.0), DVec3::ZERO);
    let mut scene = Scene { meshes: vec![Mesh::cube()], ..Scene::new("caps-objects", camera) };
    scene.sun = None;
    scene.materials.push(Material::diffuse(Vec3::splat(0.7)));
    let mut lights = Vec::new();
    for (o, x) in [-4.0f64, 4.0].into_iter().enumerate() {
        scene.objects.push(Object {
            mesh: 0,
            material: 0,
            transform: DMat4::from_scale_rotation_translation(
                DVec3::splat(2.0),
                Default::default(),
                DVec3::new(x, 0.0, 0.0),
            ),
            layer: 0,
        });
        for j in 0..6 {
            let a = j as f64 * 1.0;
            lights.push(Light::Point(PointLight {
                position: DVec3::new(x + 0.6 * a.cos(), 0.6 * a.sin(), 1.3 + 0.15 * j as f64),
                color: Vec3::ONE,
                intensity: 0.4 + 0.3 * ((j * 5 + o * 3) % 6) as f32,
                radius: 2.4,
                cookie: None,
                mask: lampshade::scene::ALL_LAYERS,
                cast_shadows: false,
            }));
        }
    }
    scene.set_lights(lights);
    let gpu = gpu();
    let plain = Settings { path: RenderPath::Forward, ..base(CullingMode::Clustered) };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &plain).unwrap();
    let hdr = |r: &Renderer| {
        r.last_frame().read_post_image(gpu, PostImage::Hdr).unwrap().expect("the forward frame's HDR colour")
    };
    for order in [CapOrder::Scene, CapOrder::Nearest, CapOrder::Brightest] {
        let what = format!("lights-per-object 2, {order:?}");
        let stats = draw(&mut r, &scene, &Settings { lights_per_object: 2, cap_order: order, ..plain.clone() });
        let capped = hdr(&r);
        assert_eq!(caps_of(&stats).object_entries_dropped, 8, "{what}: 4 of 6 lights dropped on each box");
        // The two lights each box keeps, from the lights: at the box's centre, the first, the
        // nearest or the brightest.
        let mut kept = Vec::new();
        for (o, x) in [-4.0f64, 4.0].into_iter().enumerate() {
            let centre = DVec3::new(x, 0.0, 0.0);
            let mut own: Vec<usize> = (6 * o..6 * o + 6).collect();
            let l = |i: usize| &scene.lights[i];
            let d = |i: usize| (l(i).position() - centre).length();
            let e = |i: usize| {
                lampshade::renderer::caps::irradiance_at(
                    lampshade::renderer::caps::peak(l(i)),
                    d(i),
                    l(i).radius() as f64,
                )
            };
            match order {
                CapOrder::Scene => {}
                CapOrder::Nearest => own.sort_by(|&a, &b| d(a).total_cmp(&d(b))),
                CapOrder::Brightest => own.sort_by(|&a, &b| e(b).total_cmp(&e(a))),
            }
            kept.extend_from_slice(&own[..2]);
        }
        kept.sort_unstable();
        let mut only = scene.clone();
        only.set_lights(kept.iter().map(|&i| scene.lights[i]).collect());
        draw(&mut r, &only, &plain);
        let expected = hdr(&r);
        let off = capped.iter().zip(&expected).filter(|(a, b)| a != b).count();
        assert_eq!(off, 0, "{what}: {off} channels differ from the scene with only lights {kept:?}");
        // And the cap did change the picture.
        draw(&mut r, &scene, &plain);
        assert_ne!(hdr(&r), capped, "{what}: the dropped lights lit nothing");
    }
}
