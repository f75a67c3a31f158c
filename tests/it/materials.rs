//! Seed 002's material IDs: each reflectance model against its f64 twin, the ID
//! channel allocated only for scenes of several models, culling modes against full-screen on
//! the `materials` scene, unlit surfaces that ignore lights, and a metal's coloured highlight.

use crate::common::*;
use glam::{DVec3, Vec3};
use lampshade::compare::max_channel_difference;
use lampshade::headless::render_image;
use lampshade::renderer::kit::gbuffer::Attr;
use lampshade::renderer::{
    AccumFormat, BrdfOverride, CullingMode, LayoutChoice, PixelProbe, Renderer, Settings, OUTPUT_FORMAT,
};
use lampshade::scene::{Brdf, Light, Material, Object, PointLight, Scene};

const W: u32 = 320;
const H: u32 = 180;

/// Relative and absolute error allowed between the GPU (f32 arithmetic, f32 accumulation) and
/// f64, as `tests/it/hard_cases.rs` states them: the probe decodes the very values the shaders
/// read, so the G-buffer's quantisation does not enter; f32 rounding does.
const REL: f64 = 1e-4;
const ABS: f64 = 1e-4;

/// Pixel of world point `p` in a `W`x`H` frame of `scene`.
fn pixel_of(scene: &Scene, p: DVec3) -> (u32, u32) {
    let v = scene.camera.to_view(p);
    let c = scene.camera.projection(W as f64 / H as f64, false) * v.extend(1.0);
    let (x, y) = (c.x / c.w, c.y / c.w);
    (((x * 0.5 + 0.5) * W as f64) as u32, ((0.5 - y * 0.5) * H as f64) as u32)
}

/// Pixels on each sphere of the `materials` scene (in `Brdf::ALL` order): the points whose
/// normals lean from the one facing the eye by a grid of offsets along the camera's right and
/// up, inside its disc (upper half: the pane covers the lower front of two spheres).
fn sphere_pixels(scene: &Scene) -> Vec<(Brdf, Vec<(u32, u32)>)> {
    let spheres: Vec<&Object> = scene.objects.iter().filter(|o| scene.meshes[o.mesh].name == "sphere").collect();
    spheres
        .iter()
        .map(|o| {
            let c = o.transform.transform_point3(DVec3::ZERO);
            let r = o.transform.transform_vector3(DVec3::X).length();
            let d = (scene.camera.position - c).normalize();
            let right = scene.camera.right();
            let up = d.cross(right).normalize();
            let mut px = Vec::new();
            for i in -3..=3 {
                for j in -3..=2 {
                    let n = (d + right * (i as f64 * 0.2) + up * (j as f64 * 0.1 + 0.35)).normalize();
                    px.push(pixel_of(scene, c + n * r));
                }
            }
            (scene.materials[o.material].brdf, px)
        })
        .collect()
}

/// A linear value as the sRGB8 output stores it.
fn srgb8(c: f32) -> i32 {
    let s = if c <= 0.0031308 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0).round() as i32
}

fn probe_at(r: &Renderer, x: u32, y: u32) -> PixelProbe {
    r.last_frame().probe(gpu(), x, y).unwrap()
}

#[test]
fn each_brdf_matches_its_f64_twin_at_sampled_pixels() {
    let scene = scene("materials");
    let mut worst = 0f64;
    // Lights as volumes with ambient + sun from the G-buffer pass, and the tiled pass with
    // ambient + sun from their own full-screen pass: every path that evaluates the models.
    for (culling, ambient_in_gbuffer) in [(CullingMode::Volume, true), (CullingMode::Tiled, false)] {
        // Full precision everywhere, the exact radius (as `gpu_lighting_matches_f64_at_sampled_pixels`);
        // the reference layout keeps the ID in its position target's fourth channel.
        let settings = Settings {
            culling,
            ambient_in_gbuffer,
            layout: LayoutChoice::Reference,
            accumulation: AccumFormat::Rgba32Float,
            light_cutoff: 0.0,
            ..unshadowed()
        };
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
        let (_, stats) = render_image(gpu(), &mut r, &scene, &settings, W, H).unwrap();
        assert_eq!(stats.ambient_in_gbuffer, ambient_in_gbuffer);
        assert!(r.layout().has(Attr::Material), "six models and no material ID channel");
        let clamp = lampshade::reference::Clamps::of(&r);
        for (brdf, pixels) in sphere_pixels(&scene) {
            let (mut checked, mut near_step) = (0, 0);
            for (x, y) in pixels {
                let p = probe_at(&r, x, y);
                assert!(p.valid, "{brdf:?}: ({x},{y}) is background");
                assert_eq!(p.brdf, brdf, "({x},{y}): the ID channel holds {:?}", p.material_id);
                let (d, s, margin) = lampshade::reference::shade_with_margin(&scene, &p, &clamp);
                // A toon step within f32 rounding (1e-5 here, far above it) may fall either way.
                if margin < 1e-5 {
                    near_step += 1;
                    continue;
                }
                checked += 1;
                for (gpu_v, cpu_v, what) in [(p.diffuse_light, d, "diffuse"), (p.specular_light, s, "specular")] {
                    for c in 0..3 {
                        let (g, e) = (gpu_v[c] as f64, cpu_v[c]);
                        let err = (g - e).abs();
                        worst = worst.max(err / e.abs().max(1e-3));
                        assert!(
                            err <= REL * e.abs() + ABS,
                            "{} {brdf:?} ({x},{y}) {what}[{c}]: GPU {g} vs f64 {e}",
                            culling.name()
                        );
                    }
                }
                // Each model leaves its mark: no specular for lambert and unlit, no diffuse for
                // a metal, exactly 1 diffuse for unlit.
                match brdf {
                    Brdf::Lambert | Brdf::Unlit => assert_eq!(p.specular_light, Vec3::ZERO, "{brdf:?}"),
                    Brdf::Metal => assert_eq!(p.diffuse_light, Vec3::ZERO, "{brdf:?}"),
                    _ => {}
                }
            }
            assert!(checked >= 30, "{brdf:?}: only {checked} pixels compared ({near_step} at a toon step)");
        }
    }
    println!("worst relative error against f64: {worst:.2e}");
}

#[test]
fn the_id_survives_every_layout_with_a_spare_channel() {
    // The ID in fp16 (compact, xyz16f, seed000), 8-bit unorm (packed, xyz8, fit's normal
    // target) and f32 (reference): every sphere's pixels decode to their material's model, in
    // the G-buffer and in the `material-id` view.
    let scene = scene("materials");
    for layout in LayoutChoice::ALL {
        let settings = Settings { layout, ..Settings::default() };
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
        let result = render_image(gpu(), &mut r, &scene, &settings, W, H);
        if layout.material_slot().is_none() && layout != LayoutChoice::Fit {
            let Err(e) = result else { panic!("{}: several models on a layout without room", layout.name()) };
            let e = format!("{e:#}");
            assert!(e.contains("no spare channel") && e.contains("metal"), "{}: {e}", layout.name());
            continue;
        }
        result.unwrap();
        for (brdf, pixels) in sphere_pixels(&scene) {
            for (x, y) in pixels.into_iter().step_by(7) {
                assert_eq!(probe_at(&r, x, y).brdf, brdf, "{} ({x},{y})", layout.name());
            }
        }
    }
}

#[test]
fn the_material_id_view_paints_each_model_in_its_colour() {
    let scene = scene("materials");
    let settings = Settings { debug_view: lampshade::renderer::DebugView::MaterialId, ..Settings::default() };
    let f = render(&scene, &settings, W, H);
    for (brdf, pixels) in sphere_pixels(&scene) {
        let want = brdf.debug_color().map(srgb8);
        for (x, y) in pixels.into_iter().step_by(5) {
            let got = f.image.get_pixel(x, y);
            for c in 0..3 {
                assert!((got[c] as i32 - want[c]).abs() <= 1, "{brdf:?} ({x},{y}): {got:?} vs {want:?}");
            }
        }
    }
}

#[test]
fn culling_modes_agree_with_fullscreen_on_the_multi_brdf_scene() {
    let scene = scene("materials");
    let s = |culling| Settings { culling, count_ideal: false, ..Settings::default() };
    let reference = render(&scene, &s(CullingMode::Fullscreen), W, H);
    assert_finite(&reference, "materials");
    assert!(lit_share(&reference.image) > 0.5, "the materials scene is mostly black");
    let mut failures = Vec::new();
    for mode in CullingMode::ALL.into_iter().skip(1) {
        let f = render(&scene, &s(mode), W, H);
        assert_finite(&f, mode.name().as_str());
        let step = max_channel_difference(&reference.image, &f.image);
        if step > 1 {
            failures.push(format!("{}: {step} steps from fullscreen", mode.name()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn unlit_ignores_lights() {
    // The unlit sphere shows its base colour whatever the lights, sun and ambient do; the
    // lambert sphere beside it does change (the lights do reach there).
    let lit = scene("materials");
    let mut dark = lit.clone();
    dark.lights_mut().clear();
    dark.sun = None;
    dark.ambient = Vec3::splat(0.3);
    let mut bright = lit.clone();
    for l in bright.lights_mut() {
        if let Light::Point(p) = l {
            p.intensity *= 4.0;
        }
    }
    let settings = Settings::default();
    let frames: Vec<_> = [&lit, &dark, &bright].iter().map(|s| render(s, &settings, W, H)).collect();
    let spheres = sphere_pixels(&lit);
    let unlit = &spheres.iter().find(|(b, _)| *b == Brdf::Unlit).unwrap().1;
    let lambert = &spheres.iter().find(|(b, _)| *b == Brdf::Lambert).unwrap().1;
    for &(x, y) in unlit {
        for f in &frames[1..] {
            assert_eq!(f.image.get_pixel(x, y), frames[0].image.get_pixel(x, y), "unlit ({x},{y}) changed");
        }
    }
    let changed = lambert.iter().filter(|&&(x, y)| frames[1].image.get_pixel(x, y) != frames[0].image.get_pixel(x, y));
    assert!(changed.count() > lambert.len() / 2, "the lights do not reach the lambert sphere: no test");
    // And it is its base colour: diffuse light 1, nothing specular.
    let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
    render_image(gpu(), &mut r, &lit, &settings, W, H).unwrap();
    for &(x, y) in unlit {
        let p = probe_at(&r, x, y);
        assert_eq!((p.diffuse_light, p.specular_light), (Vec3::ONE, Vec3::ZERO), "({x},{y})");
    }
}

/// One sphere of material `m` under one white point light, no sun, no ambient.
fn one_sphere(m: Material) -> Scene {
    let mut s = scene("materials");
    let sphere = s.objects.iter().find(|o| s.meshes[o.mesh].name == "sphere").unwrap().clone();
    s.materials = vec![m];
    s.objects = vec![Object { material: 0, ..sphere }];
    s.sun = None;
    s.ambient = Vec3::ZERO;
    let c = sphere.transform.transform_point3(DVec3::ZERO);
    s.lights = std::sync::Arc::new(vec![Light::Point(PointLight {
        position: c + DVec3::new(1.0, 2.5, 3.0),
        color: Vec3::ONE,
        intensity: 2.0,
        radius: 12.0,
        cast_shadows: true,
        cookie: None,
        mask: lampshade::scene::ALL_LAYERS,
    })]);
    s
}

#[test]
fn the_metal_highlight_carries_its_base_colour() {
    // Gold under a white light: the metal's highlight has the base colour's hue; shaded as
    // blinn-phong (`--brdf blinn-phong`), the same surface's highlight is white. The scene has
    // one model, so this is also the path without an ID channel (the model a constant).
    let gold = Vec3::new(1.0, 0.71, 0.29);
    let (f0, level, exponent) = Material::metal_from_pbr(gold, 1.0, 0.3, 0.04);
    assert_eq!(f0, gold);
    let scene = one_sphere(Material {
        diffuse: f0,
        specular_level: level,
        specular_exponent: exponent,
        brdf: Brdf::Metal,
        ..Material::default()
    });
    let brightest = |force: BrdfOverride| {
        // f32 albedo and accumulation: the hue is compared to f32 rounding.
        let settings = Settings {
            brdf: force,
            layout: LayoutChoice::Reference,
            accumulation: AccumFormat::Rgba32Float,
            ..Settings::default()
        };
        let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &settings).unwrap();
        render_image(gpu(), &mut r, &scene, &settings, W, H).unwrap();
        assert!(!r.layout().has(Attr::Material), "one model, yet an ID channel");
        let (_, pixels) = &sphere_pixels(&scene)[0];
        let (x0, y0) = pixels[0];
        let (x1, y1) = pixels[pixels.len() - 1];
        let mut best = probe_at(&r, x0, y0);
        for y in y1.min(y0)..=y1.max(y0) {
            for x in (x0.min(x1)..=x0.max(x1)).step_by(2) {
                let p = probe_at(&r, x, y);
                if p.specular_light.length() > best.specular_light.length() {
                    best = p;
                }
            }
        }
        best
    };
    let metal = brightest(BrdfOverride::Scene);
    assert_eq!(metal.brdf, Brdf::Metal);
    assert_eq!(metal.diffuse_light, Vec3::ZERO);
    let s = metal.specular_light;
    assert!(s.x > 1.0, "no highlight found: {s}");
    // The highlight's colour is the stored albedo's (sRGB8-rounded gold), to f32 rounding.
    let hue = s / s.x;
    let want = metal.albedo / metal.albedo.x;
    assert!((hue - want).abs().max_element() < 1e-4, "highlight {hue} vs base colour {want}");
    assert!(hue.z < 0.5, "the highlight is not gold: {hue}");
    let plain = brightest(BrdfOverride::BlinnPhong);
    assert_eq!(plain.brdf, Brdf::BlinnPhong);
    let s = plain.specular_light;
    assert!(s.x > 1.0 && (s - Vec3::splat(s.x)).abs().max_element() < 1e-4 * s.x, "blinn-phong highlight {s}");
}

#[test]
fn the_forward_pass_shades_each_model_as_the_deferred_path_does() {
    // The spheres drawn blended with alpha 1 (so forward-shaded, the picture's own colour)
    // against the same spheres opaque (deferred): the same models in both. Full-precision
    // G-buffer and accumulation, so both paths see the same surface; both end in the fp16 HDR
    // target (the pane is blended in both), so one 8-bit step of rounding is allowed.
    let opaque = scene("materials");
    let mut blended = opaque.clone();
    let spheres: Vec<usize> =
        (0..blended.objects.len()).filter(|&i| blended.meshes[blended.objects[i].mesh].name == "sphere").collect();
    for &i in &spheres {
        let mut m = blended.materials[blended.objects[i].material];
        m.alpha_mode = lampshade::scene::AlphaMode::Blend;
        m.alpha = 1.0;
        blended.materials.push(m);
        blended.objects[i].material = blended.materials.len() - 1;
    }
    let settings = Settings {
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        count_ideal: false,
        ..unshadowed()
    };
    let a = render(&opaque, &settings, W, H);
    let b = render(&blended, &settings, W, H);
    let mut checked = 0;
    for (brdf, pixels) in sphere_pixels(&opaque) {
        for (x, y) in pixels {
            let (p, q) = (a.image.get_pixel(x, y), b.image.get_pixel(x, y));
            let step = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
            assert!(step <= 1, "{brdf:?} ({x},{y}): deferred {p:?}, forward {q:?}");
            checked += 1;
        }
    }
    assert_eq!(checked, spheres.len() * 42);
    // The forward pass did draw them: they are not in the G-buffer (its material-id view shows
    // what is behind them, never the unlit sphere's colour).
    let ids = render(&blended, &Settings { debug_view: lampshade::renderer::DebugView::MaterialId, ..settings }, W, H);
    let unlit = Brdf::Unlit.debug_color().map(srgb8);
    for (brdf, pixels) in sphere_pixels(&opaque) {
        for (x, y) in pixels {
            let p = ids.image.get_pixel(x, y);
            assert!((0..3).any(|c| (p[c] as i32 - unlit[c]).abs() > 1), "{brdf:?} ({x},{y}) is in the G-buffer");
        }
    }
}

/// Seed 004: "objects with shaders that can't handle Deferred Lighting are rendered after this
/// process is done, using RenderTech-ForwardRendering path". The light pre-pass's one
/// Blinn-Phong buffer cannot carry toon's per-light bands nor Phong's lobe, so its opaque toon
/// and Phong spheres are shaded forward after pass 3, with their light lists, as the forward
/// pass shades blended surfaces: their pixels are deferred shading's (full-precision G-buffer
/// and accumulation) within one 8-bit step, and the other spheres still go through the light
/// buffer.
#[test]
fn the_light_prepass_shades_toon_and_phong_forward_as_deferred_does() {
    // Opaque, then alpha-masked above the cutoff (kept: shaded as the opaque ones), then below
    // it (dropped in pass 1 and in the forward draw: the pre-pass shows what is behind, as
    // deferred does).
    use lampshade::scene::AlphaMode;
    let (deferred, prepass) = full_precision_and_prepass();
    let cases =
        [(AlphaMode::Opaque, 1.0), (AlphaMode::Mask { cutoff: 0.5 }, 0.8), (AlphaMode::Mask { cutoff: 0.5 }, 0.3)];
    let mut kept_images = Vec::new();
    for (mode, alpha) in cases {
        let mut scene = scene("materials");
        for m in scene.materials.iter_mut().filter(|m| !m.brdf.prepass_lit()) {
            m.alpha_mode = mode;
            m.alpha = alpha;
        }
        let (a, b) = (render(&scene, &deferred, W, H), render(&scene, &prepass, W, H));
        let mut checked = 0;
        for (brdf, pixels) in sphere_pixels(&scene) {
            if brdf.prepass_lit() {
                continue;
            }
            for (x, y) in pixels {
                let (p, q) = (a.image.get_pixel(x, y), b.image.get_pixel(x, y));
                let step = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
                assert!(step <= 1, "{mode:?} {alpha} {brdf:?} ({x},{y}): deferred {p:?}, light pre-pass {q:?}");
                checked += 1;
            }
        }
        assert_eq!(checked, 2 * 42, "the toon and the Phong sphere");
        kept_images.push(b.image.clone());
    }
    // The dropped spheres are gone: their pixels differ from the kept ones.
    let (kept, dropped) = (&kept_images[1], &kept_images[2]);
    let scene = scene("materials");
    let gone = sphere_pixels(&scene)
        .into_iter()
        .filter(|(b, _)| !b.prepass_lit())
        .flat_map(|(_, p)| p)
        .filter(|&(x, y)| kept.get_pixel(x, y) != dropped.get_pixel(x, y))
        .count();
    assert!(gone > 60, "only {gone} of the spheres' pixels changed when they were dropped");
    let b = render(&scene, &prepass, W, H);
    // Pass 1 drew every opaque object's depth, pass 3 all but the toon and Phong ones.
    let forward = |m: &Material| !m.brdf.prepass_lit() && m.alpha_mode == lampshade::scene::AlphaMode::Opaque;
    let apart = scene.objects.iter().filter(|o| forward(&scene.materials[o.material])).count() as u64;
    assert!(apart >= 2);
    let p = b.stats.prepass.as_ref().unwrap();
    assert_eq!(p.final_draw_calls + apart, p.base_draw_calls, "{p:?}");
}

/// Seed 002's "reasonably coherent dynamic branching" on the material ID (`--material-branch
/// branch`) against computing every model and selecting one: each model computes its own
/// terms with the same arithmetic, so the pictures are the same and the accumulation agrees
/// to f32 rounding (the two shaders may contract differently), on the deferred and forward
/// paths of the six-model scene.
#[test]
fn branching_on_the_material_gives_the_selected_models_values() {
    use lampshade::renderer::settings::MaterialBranch;
    use lampshade::renderer::RenderPath;
    let scene = scene("materials");
    for path in [RenderPath::Deferred, RenderPath::Forward] {
        let select = Settings { path, count_ideal: false, ..unshadowed() };
        let branch = Settings { material_branch: MaterialBranch::Branch, ..select.clone() };
        let (a, b) = (render(&scene, &select, W, H), render(&scene, &branch, W, H));
        assert!(lit_share(&a.image) > 0.2);
        let d = max_channel_difference(&a.image, &b.image);
        assert_eq!(d, 0, "{path:?}: branching changed a pixel by {d} steps");
        for (x, y) in a.diffuse.iter().chain(&a.specular).zip(b.diffuse.iter().chain(&b.specular)) {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(1.0), "{path:?}: {x} selected, {y} branched");
        }
    }
}
