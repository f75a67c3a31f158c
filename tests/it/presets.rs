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

fn room() -> lampshade::Scene {
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
            let (diffuse, specular) = r.read_accumulation(gpu).unwrap();
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
            let (pa, pb) = (ra.probe(gpu, x, y).unwrap(), rb.probe(gpu, x, y).unwrap());
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
        (image, r.read_post_image(gpu, lampshade::renderer::post::PostImage::Hdr).unwrap())
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
