//! The seed presets (`--preset`): each renders the demo, the project's room and every hard case
//! finite and lit, with the formats and bytes per pixel its seed names; seed 004's near-plane
//! rule draws exactly the lights that cross the near plane full-screen and changes no pixel;
//! seed 002's front-to-back order changes no pixel and writes fewer G-buffer samples.

use crate::common::*;
use lampshade::compare::max_channel_difference;
use lampshade::headless::render_image;
use lampshade::renderer::presets::Preset;
use lampshade::renderer::settings::BlendedMode;
use lampshade::renderer::{DrawOrder, Method, NearLights, RenderPath, Renderer, Settings, OUTPUT_FORMAT};

const W: u32 = 96;
const H: u32 = 54;

pub fn room() -> lampshade::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/room/room.gltf");
    let opts = lampshade::scene::import::ImportOptions::default();
    lampshade::scene::import::load(&path, &opts, &mut |_| {}).expect("assets/room/room.gltf loads").scene
}

/// The preset's settings, with the ideal count (a full-screen pass per light) off.
fn preset(p: Preset) -> Settings {
    Settings { count_ideal: false, ..p.apply(&Settings::default()).expect("the preset applies") }
}

#[test]
fn every_preset_renders_demo_the_room_and_every_hard_case_finite_and_lit() {
    let mut scenes: Vec<(String, lampshade::Scene)> = vec![("demo".into(), scene("demo")), ("room".into(), room())];
    scenes.extend(HARD_CASES.iter().map(|n| (n.to_string(), scene(n))));
    let gpu = gpu();
    for p in Preset::SEEDS {
        let s = preset(p);
        // One renderer per preset, as a viewer switching scenes keeps one.
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        for (name, scene) in &scenes {
            let (w, h) = if name == "overflow" { hard_case_size(name) } else { (W, H) };
            let (image, stats) = render_image(gpu, &mut r, scene, &s, w, h).unwrap();
            let (diffuse, specular) = r.last_frame().read_accumulation(gpu).unwrap();
            let f = Frame { image, stats, diffuse, specular };
            let what = format!("{} on {name}", p.name());
            assert_finite(&f, &what);
            assert!(lit_share(&f.image) > 0.05, "{what}: the picture is black");
            let st = &f.stats;
            // The formats and bytes the seed names.
            match p {
                Preset::Seed000 => {
                    // "four fp16 textures": RT0, RT2 and RT3 (24 B) and RT1, the one light
                    // accumulation (8 B): 32 B/px, and depth.
                    assert_eq!((st.gbuffer_layout.as_str(), st.gbuffer_bytes_per_pixel), ("seed000", 24), "{what}");
                    assert_eq!((st.accumulation_format.as_str(), st.accumulation_bytes_per_pixel), ("Rgba16Float", 8));
                    assert!(st.ambient_in_gbuffer, "{what}: RT1 starts with ambient and sun");
                }
                Preset::Seed001 => {
                    // Two 8-bit channels of Lambert normal beside compact's albedo, emissive and
                    // the depth copy position is reconstructed from.
                    assert_eq!((st.gbuffer_layout.as_str(), st.gbuffer_bytes_per_pixel), ("lambert8", 18), "{what}");
                }
                Preset::Seed002 => {
                    assert_eq!((st.gbuffer_layout.as_str(), st.gbuffer_bytes_per_pixel), ("seed002", 24), "{what}");
                    assert_eq!(st.accumulation_format, "Rgba16Float", "{what}");
                }
                Preset::Seed003 | Preset::Seed004 => {
                    assert_eq!(st.path, RenderPath::LightPrepass, "{what}");
                    let pp = st.prepass.as_ref().expect("pre-pass figures");
                    // Seed 003: 24-bit normal + 8-bit exponent; the light buffer ARGB32, 8-bit
                    // linear (seed 003) or log-encoded (seed 004).
                    let light = if p == Preset::Seed003 { "Bgra8Unorm" } else { "Rgba8Unorm" };
                    assert_eq!(pp.normal_exp_bytes_per_pixel, 4, "{what}");
                    // Both read the depth buffer: seed 004's "depth is not explicitly rendered",
                    // seed 003's "24-bit z-buffer" as an input texture.
                    assert_eq!(pp.depth_copy_bytes_per_pixel, 0, "{what}: {}", st.depth_read);
                    assert_eq!(
                        (pp.light_buffer_format.as_str(), pp.light_buffer_bytes_per_pixel),
                        (light, 4),
                        "{what}"
                    );
                }
                Preset::Default => unreachable!(),
            }
        }
    }
}

#[test]
fn the_near_plane_rule_draws_the_crossing_lights_full_screen_and_changes_no_pixel() {
    // `near`: a light volume crosses the near plane; `inside`: the camera stands in one.
    for name in ["near", "inside", "street"] {
        let scene = scene(name);
        let volume = Settings { count_ideal: false, ..Settings::default() };
        let rule = Settings { near_lights: NearLights::Fullscreen, ..volume.clone() };
        let (a, b) = (render(&scene, &volume, W, H), render(&scene, &rule, W, H));
        let crossing: Vec<usize> = b.stats.per_light.iter().filter(|l| l.crosses_near).map(|l| l.index).collect();
        assert!(!crossing.is_empty(), "{name}: no light crosses the near plane");
        for (la, lb) in a.stats.per_light.iter().zip(&b.stats.per_light) {
            let want = if lb.crosses_near { Method::Fullscreen } else { la.method };
            assert_eq!(lb.method, want, "{name} light {}: crosses near {}", lb.index, lb.crosses_near);
        }
        // Culling only skips work: drawing a light full-screen instead of by its volume
        // shades a superset of its pixels, and the extra ones add zero.
        let d = max_channel_difference(&a.image, &b.image);
        assert!(d <= 1, "{name}: the near-plane rule changed a pixel by {d} steps");
    }
}

#[test]
fn front_to_back_order_draws_the_same_picture_with_fewer_gbuffer_fragments() {
    // Seed 002's "front-to-back-sorted" opaque draws: the same depth-tested picture; farther
    // surfaces fail the depth test behind nearer ones already drawn, so the G-buffer pass
    // writes fewer samples (overdraw) than in material order on scenes that overlap in depth.
    // Where two surfaces meet at exactly the same depth (a box standing on the floor) the
    // first drawn keeps the pixel, so those pixels may differ: each differing pixel must be
    // such a tie, the same depth in both frames.
    let gpu = gpu();
    let (w, h) = (W * 2, H * 2);
    for name in ["demo", "street"] {
        let scene = scene(name);
        let material = Settings { count_ideal: false, ..Settings::default() };
        let sorted = Settings { draw_order: DrawOrder::FrontToBack, ..material.clone() };
        let mut ra = Renderer::new(gpu, OUTPUT_FORMAT, &material).unwrap();
        let mut rb = Renderer::new(gpu, OUTPUT_FORMAT, &sorted).unwrap();
        let (a, sa) = render_image(gpu, &mut ra, &scene, &material, w, h).unwrap();
        let (b, sb) = render_image(gpu, &mut rb, &scene, &sorted, w, h).unwrap();
        let mut ties = 0;
        for (x, y, p) in a.enumerate_pixels() {
            if p.0.iter().zip(b.get_pixel(x, y).0).all(|(u, v)| u.abs_diff(v) <= 1) {
                continue;
            }
            let (pa, pb) = (ra.last_frame().probe(gpu, x, y).unwrap(), rb.last_frame().probe(gpu, x, y).unwrap());
            assert!(
                pa.valid && pb.valid && pa.position.z == pb.position.z,
                "{name} pixel ({x}, {y}): the draw order changed it, and not at a depth tie ({} vs {})",
                pa.position.z,
                pb.position.z
            );
            ties += 1;
        }
        assert!(ties * 1000 < w * h, "{name}: {ties} pixels changed");
        let (fa, fb) = (sa.gbuffer_fragments.unwrap(), sb.gbuffer_fragments.unwrap());
        assert!(fb < fa, "{name}: front-to-back wrote {fb} G-buffer samples, material order {fa}");
        println!("{name}: G-buffer samples {fa} in material order, {fb} front to back; {ties} depth ties differ");
    }
    // The light pre-pass's pass 1 counts the same way.
    let scene = scene("street");
    let p = Settings { path: RenderPath::LightPrepass, count_ideal: false, ..Settings::default() };
    let f = render(&scene, &p, W, H);
    assert_eq!(f.stats.gbuffer_fragments, f.stats.prepass.as_ref().and_then(|p| p.base_fragments));
}

#[test]
fn anisotropic_filtering_changes_only_textured_pixels_and_switches_live() {
    // Seed 002's "use aniso filtering during G-buffer pass": the material sampler only, so a
    // scene without textures draws the same pixels; the room's textured floor, seen at a
    // grazing angle, changes. One renderer switches it both ways (the material bind groups
    // are made again with the new sampler).
    let gpu = gpu();
    let plain = Settings { count_ideal: false, ..Settings::default() };
    let aniso = Settings { anisotropy: 16, ..plain.clone() };
    let demo = scene("demo");
    assert!(demo.textures.is_empty(), "demo has no textures");
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &plain).unwrap();
    let (a, _) = render_image(gpu, &mut r, &demo, &plain, W, H).unwrap();
    let (b, _) = render_image(gpu, &mut r, &demo, &aniso, W, H).unwrap();
    assert_eq!(max_channel_difference(&a, &b), 0, "anisotropy changed an untextured scene");
    let room = room();
    let (a, _) = render_image(gpu, &mut r, &room, &plain, W * 2, H * 2).unwrap();
    let (b, _) = render_image(gpu, &mut r, &room, &aniso, W * 2, H * 2).unwrap();
    let (c, _) = render_image(gpu, &mut r, &room, &plain, W * 2, H * 2).unwrap();
    let changed = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert!(changed > 0, "anisotropy 16 changed no pixel of the room");
    assert_eq!(max_channel_difference(&a, &c), 0, "back at 1 the room is not the first frame");
    println!("room: anisotropy 16 changed {changed} of {} pixels", a.pixels().count());
}

#[test]
fn additive_blended_surfaces_need_no_order_and_only_add_light() {
    // Seed 003: "additive blending modes be used to eliminate the need to sort polygons".
    // `glass`: rows of glass over the demo. With `--blended additive` the blended objects are
    // drawn in scene order; reversing that order changes each pixel's HDR value by at most the
    // fp16 target's rounding, one ulp (2^-10 relative; lavapipe truncates) per blend, and the
    // glass only adds: no channel below the frame without it.
    let gpu = gpu();
    let s = Settings { blended: BlendedMode::Additive, count_ideal: false, ..Settings::default() };
    let glass = scene("glass");
    let blended: Vec<usize> =
        (0..glass.objects.len()).filter(|&i| glass.materials[glass.objects[i].material].is_blended()).collect();
    assert!(blended.len() >= 4, "glass has {} blended objects", blended.len());
    let mut reversed = glass.clone();
    for (k, &i) in blended.iter().enumerate() {
        reversed.objects[i] = glass.objects[blended[blended.len() - 1 - k]].clone();
    }
    let mut without = glass.clone();
    without.objects.retain(|o| !glass.materials[o.material].is_blended());
    let frame = |scene: &lampshade::Scene| {
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        let (image, _) = render_image(gpu, &mut r, scene, &s, W, H).unwrap();
        (image, r.last_frame().read_post_image(gpu, lampshade::renderer::post::PostImage::Hdr).unwrap())
    };
    let ((image, a), (_, b), (base, _)) = (frame(&glass), frame(&reversed), frame(&without));
    let (a, b) = (a.expect("the HDR colour"), b.expect("the HDR colour"));
    let blends = blended.len() as f32;
    let mut differ = 0;
    for i in (0..a.len()).filter(|i| i % 4 != 3) {
        let ulps = 2.0 * blends * 2f32.powi(-10) * a[i].abs().max(b[i].abs());
        assert!((a[i] - b[i]).abs() <= ulps, "value {i}: {} in scene order, {} reversed", a[i], b[i]);
        differ += usize::from(a[i] != b[i]);
    }
    // The tonemapped output (the frame without glass has no HDR image of its own): at least
    // the glass-free frame's, within one 8-bit step (the two frames tonemap in different
    // passes), and brighter where the glass is.
    let mut brighter = 0;
    for (p, q) in image.pixels().zip(base.pixels()) {
        for c in 0..3 {
            assert!(p[c] as i32 >= q[c] as i32 - 1, "a pixel darkened by additive glass: {p:?} vs {q:?}");
        }
        brighter += usize::from((0..3).any(|c| p[c] > q[c] + 1));
    }
    assert!(brighter > (W * H / 20) as usize, "the glass added light to only {brighter} pixels");
    println!(
        "additive glass: {brighter} pixels brighter than without it, {differ} HDR values differ between the two orders"
    );
}

/// Three unlit glass panes through one vertical axis, at 0° and ±40°: every pair interpenetrates,
/// and all three share a bounding sphere, so no order of the objects is right at every pixel.
/// Over an opaque floor (its top at y = 0, which the panes pass through) and wall lit by
/// ambient alone. Returns the scene and each pane's
/// (object transform, colour, alpha).
fn crossed_panes() -> (lampshade::Scene, Vec<(glam::DMat4, glam::Vec3, f32)>) {
    use glam::{DMat4, DVec3, Vec3};
    use lampshade::scene::{AlphaMode, Brdf, Camera, Material, Mesh, Object, Scene};
    let camera =
        Camera { near: 0.1, far: 40.0, ..Camera::looking_at(DVec3::new(0.6, 1.9, 5.5), DVec3::new(0.0, 1.2, 0.0)) };
    let mut s = Scene::new("crossed panes", camera);
    s.ambient = Vec3::splat(0.5);
    s.meshes.push(Mesh::cube());
    let boxed = |s: &mut Scene, min: DVec3, max: DVec3, diffuse: Vec3| {
        s.materials.push(Material::diffuse(diffuse));
        let t = DMat4::from_translation((min + max) * 0.5) * DMat4::from_scale(max - min);
        s.objects.push(Object { mesh: 0, material: s.materials.len() - 1, transform: t, layer: 0 });
    };
    boxed(&mut s, DVec3::new(-6.0, -1.0, -6.0), DVec3::new(6.0, 0.0, 6.0), Vec3::new(0.5, 0.5, 0.45));
    boxed(&mut s, DVec3::new(-6.0, 0.0, -3.0), DVec3::new(6.0, 5.0, -2.5), Vec3::new(0.3, 0.35, 0.6));
    let panes = [
        (0.0f64, Vec3::new(1.0, 0.25, 0.1), 0.5f32),
        (40.0, Vec3::new(0.1, 0.9, 0.2), 0.4),
        (-40.0, Vec3::new(0.2, 0.3, 1.0), 0.6),
    ];
    let mut out = Vec::new();
    for (angle, colour, alpha) in panes {
        s.materials.push(Material {
            diffuse: colour,
            alpha,
            alpha_mode: AlphaMode::Blend,
            brdf: Brdf::Unlit,
            ..Material::diffuse(colour)
        });
        // Its lower edge below the floor: the opaque depth hides that strip.
        let t = DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0))
            * DMat4::from_rotation_y(angle.to_radians())
            * DMat4::from_scale(DVec3::new(3.0, 2.5, 0.002));
        s.objects.push(Object { mesh: 0, material: s.materials.len() - 1, transform: t, layer: 0 });
        out.push((t, colour, alpha));
    }
    (s, out)
}

/// The panes a ray through pixel position (x, y) of a w x h frame enters, nearest first, as
/// (distance, pane index): a slab test on each pane's box in its own space; hits below the
/// floor's top (y = 0) are hidden.
fn panes_on_ray(
    camera: &lampshade::scene::Camera,
    panes: &[(glam::DMat4, glam::Vec3, f32)],
    w: u32,
    h: u32,
    x: f64,
    y: f64,
) -> Vec<(f64, usize)> {
    use glam::DVec3;
    let tan = (camera.fov_y * 0.5).tan();
    let aspect = w as f64 / h as f64;
    let view = DVec3::new((x / w as f64 * 2.0 - 1.0) * tan * aspect, (1.0 - y / h as f64 * 2.0) * tan, -1.0);
    let dir = camera.rotation().transpose() * view;
    let mut hits = Vec::new();
    for (i, (t, _, _)) in panes.iter().enumerate() {
        let inv = t.inverse();
        let (o, d) = (inv.transform_point3(camera.position), inv.transform_vector3(dir));
        let (mut near, mut far) = (f64::MIN, f64::MAX);
        for a in 0..3 {
            let (t0, t1) = ((-0.5 - o[a]) / d[a], (0.5 - o[a]) / d[a]);
            near = near.max(t0.min(t1));
            far = far.min(t0.max(t1));
        }
        let floor = if dir.y < 0.0 { -camera.position.y / dir.y } else { f64::MAX };
        if near <= far && near > 0.0 && near < floor {
            hits.push((near, i));
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    hits
}

#[test]
fn depth_peeling_matches_a_per_pixel_depth_sorted_reference_where_the_object_sort_does_not() {
    // Seed 002: "can use depth peeling". On three interpenetrating unlit panes the reference
    // composites, at each pixel, the panes a ray through its centre enters, sorted by distance
    // on the CPU, over the frame without them (the panes' alpha set to 0, which leaves the
    // scene colour exactly as it was). Pixels whose five points (centre, +-0.45 px) do not see
    // the same panes in the same order (pane edges, the lines where panes cross) are left
    // out. Peeled with 3 layers, every other pixel matches within the fp16 rounding: the
    // layers' composite and the scene colour are stored in fp16 (at most 2^-10 relative,
    // lavapipe truncates) once per layer and once over the scene, so (layers + 1) x 2^-10 of
    // the largest value involved (1 here). The object sort misses the reference at the
    // crossings; 2 layers drop the farthest pane where three overlap, and say so.
    let configs = [
        ("deferred", Settings { ..Settings::default() }),
        (
            "reversed Z, d24s8",
            Settings {
                reversed_z: true,
                depth_format: lampshade::renderer::DepthFormat::Depth24PlusStencil8,
                ..Settings::default()
            },
        ),
        ("forward", Settings { path: RenderPath::Forward, ..Settings::default() }),
        ("light pre-pass", Settings { path: RenderPath::LightPrepass, ..Settings::default() }),
    ];
    for (name, base) in configs {
        check_peeling(gpu(), name, &base);
    }
}

/// Depth peeling on `crossed_panes` under `base` against the CPU per-pixel depth sort (see
/// the test above); the counts are checked where the adapter's occlusion queries count.
pub fn check_peeling(gpu: &lampshade::gpu::Gpu, name: &str, base: &Settings) {
    let (scene, panes) = crossed_panes();
    let (w, h) = (160u32, 120u32);
    let mut clear = scene.clone();
    for m in clear.materials.iter_mut().filter(|m| m.is_blended()) {
        m.alpha = 0.0;
    }
    let frame = |scene: &lampshade::Scene, s: &Settings| {
        let s = Settings { count_ideal: false, ..s.clone() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        let (_, stats) = render_image(gpu, &mut r, scene, &s, w, h).unwrap();
        let hdr = r
            .last_frame()
            .read_post_image(gpu, lampshade::renderer::post::PostImage::Hdr)
            .unwrap()
            .expect("the HDR colour");
        (hdr, stats)
    };
    let counted = gpu.caps.occlusion == lampshade::renderer::kit::adapter::Occlusion::Exact;
    let bound = 4.0 * 2f32.powi(-10);
    let (background, _) = frame(&clear, &Settings { blended: BlendedMode::Peeled, ..base.clone() });
    // Every pixel's reference, or None where the five points disagree.
    let mut reference = vec![None; (w * h) as usize];
    let mut crossings = 0;
    for y in 0..h {
        for x in 0..w {
            let at =
                |dx: f64, dy: f64| panes_on_ray(&scene.camera, &panes, w, h, x as f64 + 0.5 + dx, y as f64 + 0.5 + dy);
            let centre = at(0.0, 0.0);
            let order: Vec<usize> = centre.iter().map(|p| p.1).collect();
            let same = [(0.45, 0.0), (-0.45, 0.0), (0.0, 0.45), (0.0, -0.45)]
                .iter()
                .all(|&(dx, dy)| at(dx, dy).iter().map(|p| p.1).collect::<Vec<_>>() == order);
            if !same {
                crossings += usize::from(centre.len() > 1);
                continue;
            }
            let i = (y * w + x) as usize * 4;
            let mut v = glam::Vec3::from_slice(&background[i..i + 3]);
            for &(_, k) in centre.iter().rev() {
                let (_, c, a) = panes[k];
                v = c * a + v * (1.0 - a);
            }
            reference[(y * w + x) as usize] = Some((v, centre.len()));
        }
    }
    let misses = |hdr: &[f32]| {
        let mut n = 0;
        for (p, r) in reference.iter().enumerate() {
            let Some((v, _)) = r else { continue };
            let got = glam::Vec3::from_slice(&hdr[p * 4..p * 4 + 3]);
            n += usize::from((got - *v).abs().max_element() > bound);
        }
        n
    };
    let three = reference.iter().flatten().filter(|r| r.1 == 3).count();
    assert!(three > 500 && crossings > 20, "{name}: {three} pixels see three panes, {crossings} crossing pixels");
    let (peeled, stats) = frame(&scene, &Settings { blended: BlendedMode::Peeled, peel_layers: 3, ..base.clone() });
    let f = stats.forward.as_ref().expect("forward stats");
    // Counted where the adapter's occlusion queries count samples (not wgpu's GL backend).
    let zero = counted.then_some(0);
    assert_eq!((f.peel_layers, f.unpeeled), (Some(3), zero), "{name}: three layers hold every pane");
    assert_eq!(misses(&peeled), 0, "{name}: peeled pixels off the depth-sorted reference");
    let (sorted, sorted_stats) = frame(&scene, &Settings { blended: BlendedMode::Alpha, ..base.clone() });
    assert_eq!(
        f.fragments,
        sorted_stats.forward.as_ref().and_then(|f| f.fragments),
        "{name}: the peeled fragments are the sorted pass's"
    );
    let sort_misses = misses(&sorted);
    assert!(sort_misses > 200, "{name}: the object sort is off the reference at only {sort_misses} pixels");
    let (two, stats) = frame(&scene, &Settings { blended: BlendedMode::Peeled, peel_layers: 2, ..base.clone() });
    let unpeeled = stats.forward.as_ref().and_then(|f| f.unpeeled).unwrap_or(three as u64);
    assert_eq!(
        stats.forward.as_ref().and_then(|f| f.unpeeled).is_some(),
        counted,
        "{name}: counted where the queries count"
    );
    let two_misses = misses(&two);
    assert!(
        two_misses >= three * 9 / 10 && unpeeled as usize >= three,
        "{name}: 2 layers: {two_misses} misses, {unpeeled} samples unpeeled, {three} pixels of three panes"
    );
    println!("{name}: peeled exact at {} pixels ({three} of three panes, {crossings} crossing pixels left out); the object sort off at {sort_misses}; 2 layers off at {two_misses} ({unpeeled} unpeeled)", reference.iter().flatten().count());
}

#[test]
fn lightmaps_crossfade_from_realtime_near_to_baked_far_monotone_in_distance() {
    // Seed 004: "Close to the camera, realtime lighting is used, and only baked indirect
    // lighting is added. This crossfades into fully baked lighting further away." On
    // `courtyard` (every object lightmapped), three frames differ only in the crossfade: N all
    // near (--lightmap-distance 1e5), F all baked (1e-3), M at 18 (realtime to 14.4, baked
    // from 18). The lighting is linear in the weight, so at each pixel whose near and baked values
    // differ, w = (M - N) / (F - N) (luminance of the HDR scene colour; the lights and the
    // albedo cancel) must be the shader's clamp((d - 14.4) / 3.6) at the pixel's view distance d,
    // within the fp16 rounding of the three frames: each value is stored at most 4 times
    // (light buffer or accumulation, scene colour), 2^-10 relative each (lavapipe truncates),
    // so |dw| <= 4 x 2^-10 x (|M| + |N| + |F|) / |F - N|. And w is non-decreasing in d.
    let gpu = gpu();
    let scene = scene("courtyard");
    assert!(lampshade::scene::lightmap::any(&scene), "courtyard has no lightmaps");
    let (w, h) = (240u32, 135u32);
    let paths = [RenderPath::Deferred, RenderPath::LightPrepass, RenderPath::Forward];
    // Each pixel's view-space point, from the deferred frame's G-buffer (the forward paths have
    // none; the geometry is the same).
    let points = {
        let s = Settings { count_ideal: false, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        render_image(gpu, &mut r, &scene, &s, w, h).unwrap();
        r.last_frame().view_positions(gpu).unwrap()
    };
    for path in paths {
        // Bloom, above every value: the frame keeps its HDR colour, the colour itself unchanged.
        let base = Settings { path, count_ideal: false, bloom: true, bloom_threshold: 1e4, ..Settings::default() };
        let frame = |scene: &lampshade::Scene, distance: f32| {
            let s = Settings { lightmap_distance: distance, ..base.clone() };
            let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
            render_image(gpu, &mut r, scene, &s, w, h).unwrap();
            r.last_frame().read_post_image(gpu, lampshade::renderer::post::PostImage::Hdr).unwrap().expect("HDR colour")
        };
        let lum = |c: &[f32]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let (near, far, mid) = (frame(&scene, 1e5), frame(&scene, 1e-3), frame(&scene, 18.0));
        // The ends are pure: fully baked takes nothing from the realtime sun (a brighter sun,
        // not baked again, changes no value), near takes nothing from the baked irradiance (maps
        // whose RGB stands for twice the light change no value).
        let mut sunny = scene.clone();
        if let Some(sun) = sunny.sun.as_mut() {
            sun.intensity *= 2.0;
        }
        let differ = |a: &[f32], b: &[f32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
        let n = differ(&frame(&sunny, 1e-3), &far);
        assert_eq!(n, 0, "{}: {n} values of the fully baked frame change with the realtime sun", path.name());
        let mut brighter = scene.clone();
        for m in brighter.materials.iter_mut() {
            if let Some(l) = m.lightmap.as_mut() {
                l.scale *= 2.0;
            }
        }
        let n = differ(&frame(&brighter, 1e5), &near);
        assert_eq!(n, 0, "{}: {n} values of the near frame change with the baked irradiance", path.name());
        let mut samples: Vec<(f32, f32)> = Vec::new();
        let mut worst = 0f32;
        for (i, p) in points.iter().enumerate() {
            let Some(p) = p else { continue };
            let (n, f, m) = (lum(&near[i * 4..]), lum(&far[i * 4..]), lum(&mid[i * 4..]));
            if (f - n).abs() < 0.02 {
                continue;
            }
            let weight = (m - n) / (f - n);
            let d = p.length();
            let expected = ((d - 14.4) / 3.6).clamp(0.0, 1.0);
            let bound = 4.0 * 2f32.powi(-10) * (m.abs() + n.abs() + f.abs()) / (f - n).abs() + 1e-4;
            assert!(
                (weight - expected).abs() <= bound,
                "{}: pixel {i} at distance {d:.2}: weight {weight:.4}, the crossfade gives {expected:.4} (bound {bound:.4})",
                path.name()
            );
            worst = worst.max((weight - expected).abs() / bound);
            samples.push((d, weight));
        }
        let between = samples.iter().filter(|s| s.1 > 0.1 && s.1 < 0.9).count();
        let (nearer, farther) =
            (samples.iter().filter(|s| s.0 < 14.0).count(), samples.iter().filter(|s| s.0 > 18.5).count());
        assert!(
            between > 20 && nearer > 200 && farther > 200,
            "{}: {nearer} near, {between} between, {farther} far pixels",
            path.name()
        );
        // Monotone: the weights, ordered by distance, never fall by more than their bounds.
        samples.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut highest = f32::MIN;
        for &(d, wt) in &samples {
            assert!(wt >= highest - 0.02, "{}: the weight falls to {wt:.3} at {d:.2} after {highest:.3}", path.name());
            highest = highest.max(wt);
        }
        println!(
            "{}: {} pixels compared ({nearer} near, {between} crossfading, {farther} baked); worst error {worst:.2} of its bound",
            path.name(),
            samples.len()
        );
    }
}

#[test]
fn the_light_prepass_gives_surfaces_without_a_lightmap_their_whole_sun() {
    // The pre-pass's thin buffer cannot tell lightmapped pixels, so its sun is faded by the
    // crossfade weight everywhere and pass 3 adds the faded share back to surfaces without a
    // lightmap, from their own normal. `courtyard` with the floor's lightmap taken away, fully
    // baked (--lightmap-distance 1e-3: all of the floor's sun comes from pass 3) against
    // --lightmaps off (all of it from the buffer), in the HDR scene colour: the two differ by
    // the buffer's normal, 8 bits a component over [-1, 1] (each off by at most 1/255, so
    // N.L by at most sqrt(3)/255), times the sun's intensity and the floor's albedo, plus the
    // fp16 rounding in each frame: once per draw added into the buffer (the sun, each point
    // light) and once into the scene colour, 2^-10 of the value each (lavapipe truncates), so
    // 2 x (lights + 2) x 2^-10 of the larger value. Without the sun added back the floor would
    // lose all of it.
    let gpu = gpu();
    // Without its point lights: the buffer's specular takes its colour from the diffuse sum, so
    // with lights of other colours the sun's highlight would be tinted there and not in pass 3
    // (the pre-pass's own approximation, tested in `prepass`).
    let mut scene = scene("courtyard");
    scene.lights_mut().clear();
    let floor = scene.objects[0].material;
    scene.materials[floor].lightmap = None;
    let albedo = scene.materials[floor].diffuse.max_element();
    let sun = scene.sun.expect("courtyard's sun");
    let sun = (sun.color * sun.intensity).max_element();
    // Bloom above every value: the frame keeps its HDR colour, unchanged.
    let base = Settings {
        path: RenderPath::LightPrepass,
        count_ideal: false,
        bloom: true,
        bloom_threshold: 1e4,
        ..Settings::default()
    };
    let (w, h) = (240u32, 135u32);
    let roundings = 2.0 * (scene.lights.len() as f32 + 2.0);
    let frame = |s: &Settings| {
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s).unwrap();
        render_image(gpu, &mut r, &scene, s, w, h).unwrap();
        r.last_frame().read_post_image(gpu, lampshade::renderer::post::PostImage::Hdr).unwrap().expect("HDR colour")
    };
    let baked = frame(&Settings { lightmap_distance: 1e-3, ..base.clone() });
    let off = frame(&Settings { lightmaps: false, ..base.clone() });
    // The bottom tenth of the frame, its middle half: floor only, below every box.
    let mut worst = 0f32;
    for y in h * 9 / 10..h {
        for x in w / 4..w * 3 / 4 {
            let i = ((y * w + x) * 4) as usize;
            for c in 0..3 {
                let (a, b) = (baked[i + c], off[i + c]);
                let bound = sun * albedo * 3f32.sqrt() / 255.0 + roundings * 2f32.powi(-10) * a.abs().max(b.abs());
                assert!(
                    (a - b).abs() <= bound,
                    "({x},{y}) channel {c}: {a} from pass 3, {b} from the buffer (bound {bound})"
                );
                worst = worst.max((a - b).abs() / bound);
            }
        }
    }
    println!("floor without a lightmap: worst difference {worst:.2} of its bound");
}

#[test]
fn a_24_bit_depth_buffer_read_as_a_texture_gives_the_points_its_copy_gives_within_a_step() {
    // Seed 003's lights read "the 24-bit z-buffer" itself (`--preset seed003`). The positions
    // the probe and the tests reconstruct come from the same buffer (read back through a draw:
    // WebGPU copies no Depth24Plus texel) and must agree with the f32 copy's within the
    // buffer's rounding: depth d = f/(f - n) (1 - n/z) is stored as a 24-bit step, off by at
    // most one step 2^-24 (rounded or truncated), and read back as an f32 off by at most half
    // an ulp below 1, 2^-25: 1.5 x 2^-24 in d, so the view depth moves by at most
    // 1.5 x 2^-24 (f - n) z^2 / (f n), plus the f32 reconstruction's own 2^-22 |z|.
    let gpu = gpu();
    let scene = scene("demo");
    let seed003 = preset(Preset::Seed003);
    assert_eq!(seed003.depth_format, lampshade::renderer::DepthFormat::Depth24PlusStencil8);
    let copy = Settings { depth_read: lampshade::renderer::DepthRead::Copy, ..seed003.clone() };
    let positions = |s: &Settings| {
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s).unwrap();
        let (_, stats) = render_image(gpu, &mut r, &scene, s, W, H).unwrap();
        (r.last_frame().view_positions(gpu).expect("the positions read back"), stats)
    };
    let ((buffer, sb), (copied, sc)) = (positions(&seed003), positions(&copy));
    assert!(sb.depth_read.starts_with("depth buffer"), "{}", sb.depth_read);
    assert!(!sc.depth_read.starts_with("depth buffer"), "{}", sc.depth_read);
    let (n, f) = (scene.camera.near, scene.camera.far);
    let (mut compared, mut worst, mut differ) = (0, 0f64, 0);
    for (a, b) in buffer.iter().zip(&copied) {
        assert_eq!(a.is_some(), b.is_some(), "a pixel is background in one frame only");
        let (Some(a), Some(b)) = (a, b) else { continue };
        let z = -(b.z as f64);
        let bound = 1.5 * 2f64.powi(-24) * (f - n) * z * z / (f * n) + 2f64.powi(-22) * z;
        let d = (a.z as f64 - b.z as f64).abs();
        assert!(d <= bound, "view depth {z}: {} from the buffer, {} from the copy (bound {bound})", a.z, b.z);
        worst = worst.max(d / bound);
        differ += usize::from(d > 0.0);
        compared += 1;
    }
    assert!(compared > (W * H / 2) as usize && differ > 0, "{compared} pixels compared, {differ} differ");
    println!("24-bit depth read: {compared} pixels, {differ} differ from the copy, worst {worst:.2} of the bound");
}
