//! The core's other promises: live switching of settings on one renderer, every G-buffer
//! layout and depth convention drawing the same scene, the pixel probe, thumbnails, bad input.

mod common;
use common::*;
use lampshade::compare::{flip, max_channel_difference};
use lampshade::headless::{render_image, Offscreen};
use lampshade::renderer::{CullingMode, DebugView, LayoutChoice, Renderer, Settings, OUTPUT_FORMAT};

const W: u32 = 192;
const H: u32 = 108;

#[test]
fn one_renderer_switches_modes_layouts_and_depth_live() {
    let gpu = gpu();
    let mut scene = scene("demo");
    scene.lights.truncate(300);
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &Settings::default()).unwrap();
    for layout in LayoutChoice::ALL {
        for reversed_z in [false, true] {
            for culling in [CullingMode::StencilTwoPass, CullingMode::Volume] {
                let s = Settings { layout, reversed_z, culling, ..Settings::default() };
                let (live, _) = render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
                let fresh = render(&scene, &s, W, H);
                assert_eq!(
                    max_channel_difference(&live, &fresh.image),
                    0,
                    "{layout:?} reversed {reversed_z} {culling:?}: a reused renderer differs from a fresh one"
                );
            }
        }
    }
}

#[test]
fn every_layout_and_depth_convention_draws_the_same_scene() {
    // The layouts quantise differently (8-bit octahedral normals, fp16 stored positions), so
    // they agree within a FLIP bound, not bit for bit.
    for name in ["demo", "spot"] {
        let reference = render(&scene(name), &Settings::default(), W, H);
        for layout in LayoutChoice::ALL {
            for reversed_z in [false, true] {
                let f = render(&scene(name), &Settings { layout, reversed_z, ..Settings::default() }, W, H);
                assert_finite(&f, name);
                let (r, _) = flip(&reference.image, &f.image).unwrap();
                assert!(r.mean < 0.02, "{name} {layout:?} reversed {reversed_z}: FLIP mean {}", r.mean);
            }
        }
    }
}

#[test]
fn the_probe_decodes_what_the_scene_put_there() {
    let gpu = gpu();
    let scene = scene("classify");
    for layout in LayoutChoice::ALL {
        let s = Settings { layout, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
        // Bottom centre: the floor (albedo 0.5, normal +Y in world), in front of the light.
        let p = r.probe(gpu, W / 2, H - 2).unwrap();
        assert!(p.valid);
        assert!((p.albedo - glam::Vec3::splat(0.5)).abs().max_element() < 0.01, "{layout:?}: albedo {}", p.albedo);
        let up_view = (scene.camera.rotation() * glam::DVec3::Y).as_vec3();
        assert!(p.normal.dot(up_view) > 0.99, "{layout:?}: normal {} vs {}", p.normal, up_view);
        // The point lies on the floor: world y = 0.
        let world = scene.camera.position + scene.camera.rotation().transpose() * p.position.as_dvec3();
        assert!(world.y.abs() < 0.02, "{layout:?}: reconstructed floor point at y = {}", world.y);
        // Top right: sky.
        assert!(!r.probe(gpu, W - 1, 0).unwrap().valid, "top right is sky");
        assert!(r.probe(gpu, W, 0).is_err(), "a pixel outside the frame must be an error");
    }
    // A pixel the light shades lists it; the lit value is what the light buffers hold.
    let s = Settings::default();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
    let lit = (0..H).flat_map(|y| (0..W).map(move |x| (x, y))).step_by(97).find_map(|(x, y)| {
        let p = r.probe(gpu, x, y).ok()?;
        (!p.lights.is_empty()).then_some(p)
    });
    let p = lit.expect("some pixel is touched by the light");
    assert_eq!(p.lights, vec![0]);
    assert!(p.diffuse_light.max_element() > scene.ambient.max_element());
}

#[test]
fn thumbnails_recompose_the_last_frame() {
    let gpu = gpu();
    let scene = scene("spot");
    let s = Settings::default();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
    // Full-size albedo through compose_view equals a frame rendered with that debug view.
    let out = Offscreen::new(gpu, W, H);
    r.compose_view(DebugView::Albedo, &out.view, W, H).unwrap();
    let via_thumbnail = out.read(gpu).unwrap();
    let direct = render(&scene, &Settings { debug_view: DebugView::Albedo, ..s.clone() }, W, H);
    assert_eq!(max_channel_difference(&via_thumbnail, &direct.image), 0);
    // A quarter-size thumbnail is not blank.
    let small = Offscreen::new(gpu, W / 4, H / 4);
    r.compose_view(DebugView::Normal, &small.view, W / 4, H / 4).unwrap();
    assert!(lit_share(&small.read(gpu).unwrap()) > 0.3);
    assert!(r.compose_view(DebugView::Normal, &small.view, 0, 4).is_err());
}

#[test]
fn bad_values_are_errors_not_panics() {
    let gpu = gpu();
    let s = Settings::default();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    let out = Offscreen::new(gpu, 8, 8);
    let mut bad = scene("spot");
    bad.camera.near = -1.0;
    assert!(r.render(&bad, &s, &out.view, 8, 8).is_err());
    let mut bad = scene("spot");
    if let lampshade::scene::Light::Spot(l) = &mut bad.lights[0] {
        l.radius = f32::NAN;
    }
    assert!(r.render(&bad, &s, &out.view, 8, 8).unwrap_err().to_string().contains("light 0"));
    assert!(r.render(&scene("spot"), &Settings { exposure: -1.0, ..s.clone() }, &out.view, 8, 8).is_err());
    assert!(r.render(&scene("spot"), &s, &out.view, 0, 8).is_err());
    assert!(lampshade::scene::builtin::build("nope", Default::default()).unwrap_err().contains("demo"));
    // And the renderer still works afterwards.
    assert!(r.render(&scene("spot"), &s, &out.view, 8, 8).is_ok());
}

#[test]
fn the_fitted_layout_models_only_what_the_scene_needs() {
    use lampshade::renderer::gbuffer::{fit, Attr};
    // classify: no emissive material, exponents of 32: 8+8-bit normals, no emissive target.
    let small = fit(&scene("classify"));
    small.validate().unwrap();
    assert!(!small.has(Attr::Emissive));
    assert_eq!(small.bytes_per_pixel(), 4 + 4 + 4);
    // demo: emissive boxes and exponents up to 128: emissive kept, 16-bit normals.
    let demo = fit(&scene("demo"));
    assert!(demo.has(Attr::Emissive));
    assert_eq!(demo.targets[1].format, wgpu::TextureFormat::Rgba16Float);
    // An all-diffuse scene keeps no specular channel at all.
    let mut dull = scene("classify");
    dull.materials.iter_mut().for_each(|m| m.specular_level = 0.0);
    let dull = fit(&dull);
    assert!(!dull.has(Attr::SpecLevel) && !dull.has(Attr::SpecExp));
    assert_eq!(dull.bytes_per_pixel(), 4 + 2 + 4);
    // And the fitted frame matches the default one.
    let a = render(&scene("classify"), &Settings::default(), W, H);
    let b = render(&scene("classify"), &Settings { layout: LayoutChoice::Fit, ..Settings::default() }, W, H);
    assert_eq!(b.stats.gbuffer_bytes_per_pixel, 12);
    let (r, _) = flip(&a.image, &b.image).unwrap();
    assert!(r.mean < 0.01, "FLIP mean {}", r.mean);
}

#[test]
fn light_complexity_counts_the_lights_touching_each_pixel() {
    // The heatmap is drawn with light volumes; it must agree with the probe's CPU list of
    // lights whose true shape holds the pixel's point.
    let gpu = gpu();
    let scene = scene("coincident");
    let s = Settings { debug_view: DebugView::Complexity, ..Settings::default() };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    let (img, _) = render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for k in 0..64u32 {
        let (x, y) = ((k * 29 + 7) % W, (k * 13 + 5) % H);
        let p = r.probe(gpu, x, y).unwrap();
        let shown = img.get_pixel(x, y).0;
        let grey_background = shown[0] == shown[1] && shown[1] == shown[2];
        assert_eq!(p.lights.is_empty(), grey_background, "({x},{y}): lights {:?}, pixel {shown:?}", p.lights);
        seen.insert(p.lights.len());
    }
    assert!(seen.len() >= 2, "the samples should see pixels with different light counts: {seen:?}");
}
