//! Seed 004's cookies and light culling masks  on the `cookies` scene: masks
//! exclude exactly the objects they name, every culling mode gives the full-screen picture, the
//! cookie's projection matches its f64 twin within a derived bound, lights without either are
//! untouched, a layout without room for the layer is a clear error, and so are bad cookie files.

use crate::common::*;
use glam::{DVec3, Vec3};
use lampshade::compare::max_channel_difference;
use lampshade::headless::render_image;
use lampshade::renderer::kit::gbuffer::Attr;
use lampshade::renderer::{AccumFormat, CullingMode, LayoutChoice, PixelProbe, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::cookie::CookieImage;
use lampshade::scene::{Light, Scene, ALL_LAYERS};

const W: u32 = 240;
const H: u32 = 135;

/// Full precision: the reference layout (the layer in its emissive target's fourth channel),
/// f32 accumulation, exact radii.
fn exact() -> Settings {
    Settings {
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        light_cutoff: 0.0,
        count_ideal: false,
        ..unshadowed()
    }
}

/// Renders and keeps the renderer for probing.
fn rendered(scene: &Scene, settings: &Settings) -> Renderer {
    let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, settings).unwrap();
    render_image(gpu(), &mut r, scene, settings, W, H).unwrap();
    r
}

/// Every `step`-th pixel's probe that shows a surface.
fn probes(r: &Renderer, step: u32) -> Vec<PixelProbe> {
    let mut out = Vec::new();
    for y in (step / 2..H).step_by(step as usize) {
        for x in (step / 2..W).step_by(step as usize) {
            let p = r.last_frame().probe(gpu(), x, y).unwrap();
            if p.valid {
                out.push(p);
            }
        }
    }
    out
}

fn without_light(scene: &Scene, k: usize) -> Scene {
    let mut s = scene.clone();
    s.lights_mut().remove(k);
    s
}

fn close(a: Vec3, b: Vec3) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() <= 1e-6 * a[c].abs().max(b[c].abs()) + 1e-7)
}

#[test]
fn a_mask_excludes_exactly_the_objects_it_names() {
    // The scene's masks: light 1 (warm) lights layers 0 and 1, not the sphere on layer 2;
    // light 2 (cool) lights layers 0 and 2, not the box on layer 1. Cookies off, so the masks
    // alone decide.
    let mut masked = scene("cookies");
    masked.lights_mut().iter_mut().for_each(|l| l.set_cookie(None));
    assert_eq!((masked.lights[1].mask(), masked.lights[2].mask()), (0b011, 0b101));
    let mut unmasked = masked.clone();
    unmasked.lights_mut().iter_mut().for_each(|l| l.set_mask(ALL_LAYERS));
    let s = exact();
    let m = rendered(&masked, &s);
    assert!(m.layout().has(Attr::Layer), "masks that split the layers and no layer channel");
    let u = rendered(&unmasked, &s);
    assert!(!u.layout().has(Attr::Layer), "a layer channel without masks");
    let no_warm = rendered(&without_light(&unmasked, 1), &s);
    let no_cool = rendered(&without_light(&unmasked, 2), &s);
    let mut seen = [0usize; 3];
    let mut differs = [0usize; 3];
    for p in probes(&m, 4) {
        let (x, y) = (p.x, p.y);
        let pu = u.last_frame().probe(gpu(), x, y).unwrap();
        // What the pixel must receive: every light but the one whose mask leaves its layer out.
        let expected = match p.layer {
            0 => pu.clone(),
            1 => no_cool.last_frame().probe(gpu(), x, y).unwrap(),
            2 => no_warm.last_frame().probe(gpu(), x, y).unwrap(),
            l => panic!("({x},{y}) is on layer {l}: the scene has layers 0, 1, 2"),
        };
        assert_eq!(pu.layer, 0, "the unmasked frame stores no layer");
        for (a, b, what) in [
            (p.diffuse_light, expected.diffuse_light, "diffuse"),
            (p.specular_light, expected.specular_light, "specular"),
        ] {
            assert!(close(a, b), "layer {} ({x},{y}) {what}: masked {a} against {b}", p.layer);
        }
        seen[p.layer as usize] += 1;
        if !close(pu.diffuse_light, p.diffuse_light) {
            differs[p.layer as usize] += 1;
        }
    }
    eprintln!("pixels per layer {seen:?}; of them changed by the masks {differs:?}");
    // Each layer was sampled, and the masks did take light away from the excluded objects only.
    assert!(seen.iter().all(|&n| n > 20), "{seen:?}");
    assert_eq!(differs[0], 0);
    assert!(differs[1] > seen[1] / 4 && differs[2] > seen[2] / 4, "{differs:?} of {seen:?}");

    // The forward pass reads the layer from the object record: the sphere drawn blended with
    // alpha 1 is forward-shaded and must look as the deferred sphere does (one 8-bit step: both
    // end in the fp16 HDR target, as the pane is blended in both).
    let mut blended = masked.clone();
    let sphere = blended.objects.iter().position(|o| o.layer == 2).unwrap();
    let mut mat = blended.materials[blended.objects[sphere].material];
    mat.alpha_mode = lampshade::scene::AlphaMode::Blend;
    mat.alpha = 1.0;
    blended.materials.push(mat);
    blended.objects[sphere].material = blended.materials.len() - 1;
    let a = render(&masked, &s, W, H);
    let b = render(&blended, &s, W, H);
    let unmasked_blended = {
        let mut u = blended.clone();
        u.lights_mut().iter_mut().for_each(|l| l.set_mask(ALL_LAYERS));
        render(&u, &s, W, H)
    };
    let step = max_channel_difference(&a.image, &b.image);
    assert!(step <= 1, "forward-shaded sphere {step} steps from the deferred one");
    assert!(
        max_channel_difference(&b.image, &unmasked_blended.image) > 8,
        "the warm light's mask changed nothing on the forward-shaded sphere"
    );
}

#[test]
fn every_culling_mode_gives_the_full_screen_picture_with_masks_and_cookies() {
    let scene = scene("cookies");
    let mut failures = Vec::new();
    // The default layout (the layer in compact's emissive .w) and packed (its normal target's .w).
    for layout in [LayoutChoice::Compact, LayoutChoice::Packed] {
        let s = |culling| Settings { culling, layout, count_ideal: false, ..Settings::default() };
        let reference = render(&scene, &s(CullingMode::Fullscreen), W, H);
        assert_finite(&reference, "cookies");
        assert!(lit_share(&reference.image) > 0.5, "the cookies scene is mostly black");
        for mode in CullingMode::ALL.into_iter().skip(1) {
            let f = render(&scene, &s(mode), W, H);
            assert_finite(&f, mode.name().as_str());
            let step = max_channel_difference(&reference.image, &f.image);
            if step > 1 {
                failures.push(format!("{layout:?} {}: {step} steps from fullscreen", mode.name()));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The largest error of the GPU's cookie coordinates (in uv units) at the point `v` from the
/// light (view space, f64), derived from f32 rounding:
///
/// * the point: the GPU reconstructs it from the f32 depth with the f32 inverse projection
///   (16 entries rounded, a 4x4 product and a divide) and subtracts the light's f32 position:
///   at most `EP = 16 u` of (|p| + |light|), u = 2^-24 (each operation ≤ 1 u, rounding of the
///   inputs ≤ 1 u each, doubled for margin);
/// * a spot: uv = 0.5 + (v.right, -v.up) x k, k = 0.5 / (z tan); with |v.right| ≤ |v| the
///   coordinates move by at most (δ / z + |v| δ / z²) x 0.5 / tan for a point error δ, plus
///   the basis' own rounding (direction, up, the cross product: 4 u, turning v by ≤ 4 u |v|)
///   and 6 u for the products and sums that make uv;
/// * a cube: uv = 0.5 (sc / ma + 1) with |sc| ≤ ma and ma ≥ |v| / √3, so a direction error δ
///   (the point's, plus 3 u |v| for the f32 rotation into world space) moves uv by at most
///   δ / ma; plus 4 u for the division and the sum.
fn uv_error(scene: &Scene, light: &Light, v: DVec3, p: DVec3) -> f64 {
    const U: f64 = 1.0 / 16_777_216.0;
    let lv = scene.camera.to_view(light.position());
    let ep = 16.0 * U * (p.length() + lv.length());
    match light {
        Light::Spot(s) => {
            let rot = scene.camera.rotation();
            let dir = (rot * s.direction.as_dvec3()).normalize();
            let z = v.dot(dir);
            let t = (s.outer_angle as f64).tan();
            let d = ep + 4.0 * U * v.length();
            (d / z + v.length() * d / (z * z)) * 0.5 / t + 6.0 * U
        }
        Light::Point(_) => {
            let ma = v.abs().max_element();
            (ep + 3.0 * U * v.length()) / ma + 4.0 * U
        }
    }
}

#[test]
fn the_cookie_projection_matches_its_f64_twin() {
    let scene = scene("cookies");
    let mut plain = scene.clone();
    plain.lights_mut().iter_mut().for_each(|l| l.set_cookie(None));
    let r = rendered(&scene, &exact());
    let clamp = lampshade::reference::Clamps::of(&r);
    let rot = scene.camera.rotation();
    let (mut checked, mut dark, mut bright, mut face_edges) = (0, 0, 0, 0);
    let mut worst = 0f64;
    'pixels: for p in probes(&r, 4) {
        let pos = p.position.as_dvec3();
        // The cookie's own error at this pixel, per light: how far the sample can move (uv
        // error x texels per uv x the largest step between neighbouring texels) plus the f32
        // bilinear blend (three mixes, 3 u, and the 8-bit texel's conversion, 1 u).
        let mut extra = DVec3::ZERO;
        for (i, light) in scene.lights.iter().enumerate() {
            let Some(c) = light.cookie() else { continue };
            let image: &CookieImage = &scene.cookies[c as usize];
            let v = pos - scene.camera.to_view(light.position());
            if matches!(light, Light::Point(_)) {
                // Within rounding of a cube edge the GPU may pick the other face.
                let a = (rot.transpose() * v).abs();
                let mut s = [a.x, a.y, a.z];
                s.sort_by(f64::total_cmp);
                if s[2] - s[1] < 1e-4 * s[2] {
                    face_edges += 1;
                    continue 'pixels;
                }
            }
            let e = uv_error(&scene, light, v, pos) * image.size as f64 * image.max_step() + 4.0 / 16_777_216.0;
            // Times the light's whole uncookied contribution at the pixel.
            let mut only = plain.clone();
            only.lights = std::sync::Arc::new(vec![plain.lights[i]]);
            let (d, s) = lampshade::reference::shade(&only, &p, &lampshade::reference::Clamps::none(1));
            let (d0, s0) = lampshade::reference::shade(
                &Scene { lights: std::sync::Arc::new(vec![]), ..only.clone() },
                &p,
                &lampshade::reference::Clamps::none(0),
            );
            extra += (d - d0 + s - s0) * e;
            let f = lampshade::reference::cookie(&scene, light, v, rot);
            if d.x - d0.x > 0.05 {
                if f.x < 0.1 {
                    dark += 1;
                }
                if f.x > 0.9 {
                    bright += 1;
                }
            }
        }
        let (d, s) = lampshade::reference::shade(&scene, &p, &clamp);
        for (g, e, what) in [(p.diffuse_light, d, "diffuse"), (p.specular_light, s, "specular")] {
            for c in 0..3 {
                // tests/it/hard_cases.rs' f32-against-f64 bound for the lighting, plus the cookie's.
                let bound = 1e-4 * e[c].abs() + 1e-4 + extra[c];
                let err = (g[c] as f64 - e[c]).abs();
                worst = worst.max(err / bound);
                assert!(err <= bound, "({},{}) {what}[{c}]: GPU {} vs f64 {} (bound {bound})", p.x, p.y, g[c], e[c]);
            }
        }
        checked += 1;
    }
    eprintln!(
        "{checked} pixels within the bound (worst {worst:.3} of it); {face_edges} skipped at cube edges; \
         {dark} lit pixels under a dark cookie texel, {bright} under a bright one"
    );
    assert!(checked > 800, "{checked}");
    // The cookies did shape the light: lit pixels both behind the bars and in the panes.
    assert!(dark > 20 && bright > 20, "{dark} dark, {bright} bright");
}

#[test]
fn lights_without_cookie_or_mask_are_untouched_by_the_others() {
    // Light 2 alone (mask reset, no cookie), against the whole scene where lights 0 and 1 keep
    // their cookies and masks (the layer channel allocated, the cookie texels bound) but shine
    // with zero intensity: each adds exactly +0.0, so the plain light's frame must be the same
    // bits in the accumulation buffers (f32: the clamps do not enter).
    let mut base = scene("cookies");
    base.lights_mut()[2].set_mask(ALL_LAYERS);
    base.lights_mut()[2].set_cookie(None);
    let mut alone = base.clone();
    alone.lights = std::sync::Arc::new(vec![base.lights[2]]);
    let mut with_dark = base.clone();
    for l in &mut with_dark.lights_mut()[..2] {
        match l {
            Light::Point(p) => p.intensity = 0.0,
            Light::Spot(s) => s.intensity = 0.0,
        }
    }
    let s = exact();
    for culling in [CullingMode::Fullscreen, CullingMode::Volume, CullingMode::Tiled] {
        let s = Settings { culling, ..s.clone() };
        let r = rendered(&with_dark, &s);
        assert!(r.layout().has(Attr::Layer), "light 1's mask splits the layers");
        let a = render(&alone, &s, W, H);
        let b = render(&with_dark, &s, W, H);
        let same = a
            .diffuse
            .iter()
            .zip(&b.diffuse)
            .chain(a.specular.iter().zip(&b.specular))
            .all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same, "{}: the plain light's frame changed", culling.name());
        assert_eq!(a.image, b.image);
    }
    // And the default scenes keep their layouts: no layer channel, the same bytes per pixel.
    for name in ["demo", "spot", "materials"] {
        let sc = scene(name);
        assert_eq!(sc.uniform_layer(), Some(0), "{name}");
        for c in LayoutChoice::ALL {
            if let Ok(l) = c.layout_for(&sc, None) {
                assert!(!l.has(Attr::Layer), "{name} {c:?}");
            }
        }
    }
}

#[test]
fn a_layout_without_a_spare_channel_for_the_layer_is_a_clear_error() {
    let scene = scene("cookies");
    assert_eq!(scene.uniform_layer(), None);
    // oct8 and oct16 (and lambert8, lambert16, seed002) keep no channel free; packed's one free channel goes to the material ID
    // when the scene has several models.
    let mut several = scene.clone();
    several.materials[0].brdf = lampshade::scene::Brdf::Lambert;
    for (c, sc) in [(LayoutChoice::Oct8, &scene), (LayoutChoice::Oct16, &scene), (LayoutChoice::Packed, &several)] {
        let e = c.layout_for(sc, None).unwrap_err();
        assert!(
            e.contains("no spare channel for the object layer")
                && e.contains("layers 0, 1, 2")
                && e.contains("lights 1, 2"),
            "{c:?}: {e}"
        );
        // And through the renderer: an error, not a panic, not a picture without masks.
        let settings = Settings { layout: c, count_ideal: false, ..Settings::default() };
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
        let e = render_image(gpu(), &mut r, sc, &settings, 64, 36).expect_err("rendered without the layer");
        assert!(format!("{e:#}").contains("no spare channel for the object layer"), "{e:#}");
    }
    // Every other layout finds a channel at no byte more, but fit, which adds one byte.
    for c in LayoutChoice::ALL {
        if matches!(
            c,
            LayoutChoice::Oct8
                | LayoutChoice::Oct16
                | LayoutChoice::Lambert8
                | LayoutChoice::Lambert16
                | LayoutChoice::Seed002
        ) {
            assert!(c.layout_for(&scene, None).unwrap_err().contains("no spare channel"), "{c:?}");
            continue;
        }
        let l = c.layout_for(&scene, None).unwrap();
        l.validate().unwrap();
        assert!(l.has(Attr::Layer), "{c:?}");
        let mut plain = scene.clone();
        plain.lights_mut().iter_mut().for_each(|l| l.set_mask(ALL_LAYERS));
        let without = c.layout_for(&plain, None).unwrap();
        let extra = l.bytes_per_pixel() - without.bytes_per_pixel();
        assert_eq!(extra, 0, "{c:?}: the layer costs {extra} B/px");
    }
    // fit without a spare channel (no specular, no emissive: Rg8 normals) adds an R8 target.
    let mut matte = scene.clone();
    for m in &mut matte.materials {
        m.specular_level = 0.0;
    }
    let l = LayoutChoice::Fit.layout_for(&matte, None).unwrap();
    l.validate().unwrap();
    let mut plain = matte.clone();
    plain.lights_mut().iter_mut().for_each(|l| l.set_mask(ALL_LAYERS));
    assert_eq!(l.bytes_per_pixel(), LayoutChoice::Fit.layout_for(&plain, None).unwrap().bytes_per_pixel());
}

#[test]
fn bad_cookie_files_are_clear_errors() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/cookie-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let write_png = |name: &str, w: u32, h: u32| {
        let path = dir.join(name);
        image::RgbaImage::from_pixel(w, h, image::Rgba([200, 100, 50, 255])).save(&path).unwrap();
        path
    };
    let square = write_png("square.png", 16, 16);
    let strip = write_png("strip.png", 96, 16);
    let wide = write_png("wide.png", 32, 16);
    let junk = dir.join("junk.png");
    std::fs::write(&junk, b"not a png at all").unwrap();
    let cut = dir.join("cut.png");
    let bytes = std::fs::read(&square).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let missing = dir.join("missing.png");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let mut scene = scene("cookies");
    // Good files load: a square on the spot (light 0), a strip of six on a point light.
    scene.set_light_cookie(0, Some(&s(&square))).unwrap();
    scene.set_light_cookie(1, Some(&s(&strip))).unwrap();
    scene.validate().unwrap();
    let c = &scene.cookies[scene.lights[1].cookie().unwrap() as usize];
    assert!(c.is_cube() && c.size == 16);
    for (light, spec, says) in [
        (0, s(&missing), "missing.png"),
        (0, s(&junk), "not a readable PNG"),
        (0, s(&cut), "not a readable PNG"),
        (0, s(&wide), "must be square for a spot"),
        (1, s(&square), "strip of six square faces"),
        (0, "lamp".to_string(), "neither a built-in cookie (window, flashlight) nor a .png file"),
        (7, "window".to_string(), "no light 7"),
    ] {
        let before = scene.lights.clone();
        let e = scene.set_light_cookie(light, Some(&spec)).unwrap_err();
        assert!(e.contains(says), "{spec}: {e}");
        assert_eq!(scene.lights, before, "{spec}: a failed cookie changed the lights");
    }
    // A 2D cookie on a point light (by index) is refused by validation.
    let mut wrong = scene.clone();
    let spot_cookie = wrong.lights[0].cookie();
    wrong.lights_mut()[1].set_cookie(spot_cookie);
    assert!(wrong.validate().unwrap_err().contains("a point light takes a cube"));
}

#[test]
fn gltf_extras_carry_cookies_masks_and_layers() {
    use lampshade::scene::{import, room};
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/cookie-tests/room");
    let _ = std::fs::remove_dir_all(&dir);
    room::write(&dir).unwrap();
    let path = dir.join("room.gltf");
    let original: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    image::RgbaImage::from_pixel(8, 8, image::Rgba([255, 128, 0, 255])).save(dir.join("cookie.png")).unwrap();
    // Node 0 is a mesh node, nodes 11.. are the point lights and 21 the spot (room.rs).
    let with = |edits: &[(usize, serde_json::Value)]| {
        let mut doc = original.clone();
        for (node, extras) in edits {
            doc["nodes"][*node]["extras"] = extras.clone();
        }
        let p = dir.join("edited.gltf");
        std::fs::write(&p, doc.to_string()).unwrap();
        import::load(&p, &Default::default(), &mut |_| {})
    };
    let imported = with(&[
        (0, serde_json::json!({"layer": 3, "other": "kept apart"})),
        (11, serde_json::json!({"cookie": "flashlight", "mask": 8})),
        (21, serde_json::json!({"cookie": "cookie.png"})),
    ])
    .unwrap();
    let s = imported.scene;
    s.validate().unwrap();
    assert!(s.objects.iter().any(|o| o.layer == 3));
    let point = s.lights.iter().find(|l| l.mask() == 8).expect("the masked light");
    assert_eq!(s.cookies[point.cookie().unwrap() as usize].name, "flashlight");
    let spot = s.lights.iter().find(|l| matches!(l, Light::Spot(_))).unwrap();
    let c = &s.cookies[spot.cookie().unwrap() as usize];
    assert!(c.name.ends_with("cookie.png") && c.size == 8 && !c.is_cube());
    // Bad values are errors naming the node.
    for (node, extras, says) in [
        (0, serde_json::json!({"layer": 32}), "node 0 extras: \"layer\" must be a layer 0..=31"),
        (11, serde_json::json!({"mask": -1}), "\"mask\" must be a 32-bit layer mask"),
        (21, serde_json::json!({"cookie": "missing.png"}), "missing.png"),
        (21, serde_json::json!({"cookie": 3}), "\"cookie\" must be"),
    ] {
        let e = format!("{:#}", with(&[(node, extras)]).err().expect("loaded a bad extras value"));
        assert!(e.contains(says), "{e}");
    }
}

/// Seed 004's "limited support" for light culling masks on the light pre-pass: its buffer has no
/// channel for a layer, so it is shaded as one layer (the one most objects are on), and objects
/// on layers some light's mask tells apart from it are shaded forward after pass 3, as toon.
/// On `cookies` the red box (layer 1) and the blue sphere (layer 2) are apart from the floor's
/// and wall's layer 0: their pixels are deferred shading's (full-precision G-buffer and
/// accumulation) within one 8-bit step, and pass 3 draws every opaque object but those two.
#[test]
fn the_light_prepass_shades_objects_its_masks_tell_apart_forward() {
    let scene = scene("cookies");
    let (layer, shared) = scene.shared_layers();
    assert_eq!((layer, shared & 0b111), (0, 0b001), "layer 0 shared, 1 and 2 apart");
    let (deferred, prepass) = full_precision_and_prepass();
    let (a, b) = (render(&scene, &deferred, W, H), render(&scene, &prepass, W, H));
    let pixel_of = |p: DVec3| {
        let v = scene.camera.to_view(p);
        let c = scene.camera.projection(W as f64 / H as f64, false) * v.extend(1.0);
        let (x, y) = (c.x / c.w, c.y / c.w);
        (((x * 0.5 + 0.5) * W as f64) as i64, ((0.5 - y * 0.5) * H as f64) as i64)
    };
    // The red box's face towards the camera and the blue sphere's upper half (the pane covers
    // its lower front).
    let mut checked = 0;
    for (what, centre) in [("red box", DVec3::new(-2.3, 1.2, 1.0)), ("blue sphere", DVec3::new(2.3, 1.7, 0.6))] {
        let (cx, cy) = pixel_of(centre);
        for dy in -2..=2 {
            for dx in -2..=2 {
                let (x, y) = ((cx + dx) as u32, (cy + dy) as u32);
                let (p, q) = (a.image.get_pixel(x, y), b.image.get_pixel(x, y));
                let step = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
                assert!(step <= 1, "{what} ({x},{y}): deferred {p:?}, light pre-pass {q:?}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 50);
    let opaque_apart = scene
        .objects
        .iter()
        .filter(|o| shared & (1 << o.layer) == 0)
        .filter(|o| scene.materials[o.material].alpha_mode == lampshade::scene::AlphaMode::Opaque)
        .count() as u64;
    assert_eq!(opaque_apart, 2);
    let p = b.stats.prepass.as_ref().expect("pre-pass figures");
    assert_eq!(p.final_draw_calls + opaque_apart, p.base_draw_calls, "{p:?}");
    // An alpha-masked object there is shaded forward too, discarding as pass 1 did: the same
    // picture while its alpha is above the cutoff, and the same draws.
    let mut masked = scene.clone();
    let red = masked.objects.iter().find(|o| o.layer == 1).expect("the red box").material;
    masked.materials[red].alpha_mode = lampshade::scene::AlphaMode::Mask { cutoff: 0.5 };
    let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &prepass).unwrap();
    let (image, stats) = render_image(gpu(), &mut r, &masked, &prepass, W, H).expect("a masked object apart");
    let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &prepass).unwrap();
    let (opaque, _) = render_image(gpu(), &mut r, &scene, &prepass, W, H).expect("opaque");
    assert_eq!(max_channel_difference(&image, &opaque), 0, "masked above its cutoff is the opaque picture");
    let p = stats.prepass.as_ref().expect("pre-pass figures");
    assert_eq!(p.final_draw_calls + opaque_apart, p.base_draw_calls, "{p:?}");
}
