//! The core's other promises: live switching of settings on one renderer, every G-buffer
//! layout and depth convention drawing the same scene, the pixel probe, thumbnails, bad input.

use crate::common::*;
use lampshade::compare::{flip, max_channel_difference};
use lampshade::headless::{render_image, Offscreen};
use lampshade::renderer::{CullingMode, DebugView, LayoutChoice, Renderer, Settings, OUTPUT_FORMAT};

const W: u32 = 192;
const H: u32 = 108;

#[test]
fn one_renderer_switches_modes_layouts_and_depth_live() {
    let gpu = gpu();
    let mut scene = scene("demo");
    scene.lights_mut().truncate(300);
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
        let p = r.last_frame().probe(gpu, W / 2, H - 2).unwrap();
        assert!(p.valid);
        assert!((p.albedo - glam::Vec3::splat(0.5)).abs().max_element() < 0.01, "{layout:?}: albedo {}", p.albedo);
        let up_view = (scene.camera.rotation() * glam::DVec3::Y).as_vec3();
        assert!(p.normal.dot(up_view) > 0.99, "{layout:?}: normal {} vs {}", p.normal, up_view);
        // The point lies on the floor: world y = 0.
        let world = scene.camera.position + scene.camera.rotation().transpose() * p.position.as_dvec3();
        assert!(world.y.abs() < 0.02, "{layout:?}: reconstructed floor point at y = {}", world.y);
        // Top right: sky.
        assert!(!r.last_frame().probe(gpu, W - 1, 0).unwrap().valid, "top right is sky");
        assert!(r.last_frame().probe(gpu, W, 0).is_err(), "a pixel outside the frame must be an error");
    }
    // A pixel the light shades lists it; the lit value is what the light buffers hold.
    let s = Settings::default();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
    let lit = (0..H).flat_map(|y| (0..W).map(move |x| (x, y))).step_by(97).find_map(|(x, y)| {
        let p = r.last_frame().probe(gpu, x, y).ok()?;
        (!p.lights.is_empty()).then_some(p)
    });
    let p = lit.expect("some pixel is touched by the light");
    assert_eq!(p.lights, vec![0]);
    assert!(p.diffuse_light.max_element() > scene.ambient.max_element());
}

/// Seed 002's packed channels against the f32 reference layout, pixel by pixel on the five
/// reflectance models. The probe (the CPU's decoding of the stored texels): the material ID
/// survives exactly, the exponent within its derived 3%, and the one-channel emission is off
/// by exactly the part of the material's emission orthogonal to its albedo
/// (`emission_residual`), plus fp16 rounding (albedo and scale, 2^-11 each). Half the materials
/// emit in their own hue (exact), half not. The shaders' decoding (`gbuffer_load`), through the
/// debug views: the material ID view equal, the exponent (specular view's green, 8 bits) within
/// a step of rounding and one of the 3%, the emissive view equal where the emission has the
/// albedo's hue and different where it is far from it.
#[test]
fn seed002s_packed_channels_decode_as_derived() {
    use lampshade::renderer::kit::gbuffer::{emission_residual, MATERIAL_EXP_RELATIVE_ERROR};
    let gpu = gpu();
    let mut scene = scene("materials");
    for (i, m) in scene.materials.iter_mut().enumerate() {
        m.emissive = if i % 2 == 0 { m.diffuse * 0.5 } else { glam::Vec3::new(0.2, 0.5, 0.9) };
    }
    let probes = |layout| {
        let s = Settings { layout, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
        let mut v = Vec::new();
        for y in (3..H).step_by(9) {
            for x in (3..W).step_by(9) {
                v.push(r.last_frame().probe(gpu, x, y).unwrap());
            }
        }
        v
    };
    let (reference, seed) = (probes(LayoutChoice::Reference), probes(LayoutChoice::Seed002));
    let (mut n, mut ids, mut orthogonal) = (0, std::collections::BTreeSet::new(), 0);
    for (a, b) in reference.iter().zip(&seed) {
        assert_eq!(a.valid, b.valid, "({}, {})", a.x, a.y);
        if !a.valid {
            continue;
        }
        n += 1;
        let at = format!("({}, {})", a.x, a.y);
        assert_eq!(a.material_id, b.material_id, "{at}: the material ID");
        ids.extend(b.material_id);
        let ratio = (b.specular_exponent / a.specular_exponent).max(a.specular_exponent / b.specular_exponent);
        assert!(
            ratio as f64 - 1.0 <= MATERIAL_EXP_RELATIVE_ERROR,
            "{at}: exponent {} vs {}",
            b.specular_exponent,
            a.specular_exponent
        );
        let residual = emission_residual(a.emissive, a.albedo);
        orthogonal += (residual > 0.05) as usize;
        let rounding = 3.0 * 2f32.powi(-11) * a.emissive.max_element() + 1e-6;
        let off = (b.emissive - a.emissive).abs().max_element();
        assert!(
            (off - residual).abs() <= rounding,
            "{at}: emission {} vs {}: off by {off}, the derived residual is {residual}",
            b.emissive,
            a.emissive
        );
    }
    assert!(n > 100, "only {n} surface pixels probed");
    assert!(ids.len() >= 4, "the probes met only the models {ids:?}");
    assert!(orthogonal > 10, "only {orthogonal} probes emit off their albedo's hue");
    let view = |layout, debug_view| render(&scene, &Settings { layout, debug_view, ..Settings::default() }, W, H).image;
    for (debug_view, steps) in [(DebugView::MaterialId, 0), (DebugView::Specular, 2)] {
        let (a, b) = (view(LayoutChoice::Reference, debug_view), view(LayoutChoice::Seed002, debug_view));
        let d = max_channel_difference(&a, &b);
        assert!(d <= steps, "{debug_view:?}: seed002's view differs from the reference's by {d} steps");
    }
    let (a, b) = (view(LayoutChoice::Reference, DebugView::Emissive), view(LayoutChoice::Seed002, DebugView::Emissive));
    let (mut same_hue, mut apart) = (0, 0);
    for p in reference.iter().filter(|p| p.valid && p.emissive.max_element() > 0.0) {
        let step = |img: &image::RgbaImage| img.get_pixel(p.x, p.y).0;
        let d = step(&a).iter().zip(step(&b)).map(|(u, v)| u.abs_diff(v)).max().unwrap_or(0);
        if emission_residual(p.emissive, p.albedo) < 1e-3 {
            same_hue += 1;
            assert!(d <= 1, "({}, {}): emission in the albedo's hue, yet the views differ by {d} steps", p.x, p.y);
        } else if emission_residual(p.emissive, p.albedo) > 0.2 {
            apart += 1;
            assert!(d > 4, "({}, {}): emission far from the albedo's hue, yet the views agree", p.x, p.y);
        }
    }
    assert!(same_hue > 10 && apart > 10, "{same_hue} probes emit in the albedo's hue, {apart} far from it");
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
    r.last_frame().compose_view(DebugView::Albedo, &out.view, W, H).unwrap();
    let via_thumbnail = out.read(gpu).unwrap();
    let direct = render(&scene, &Settings { debug_view: DebugView::Albedo, ..s.clone() }, W, H);
    assert_eq!(max_channel_difference(&via_thumbnail, &direct.image), 0);
    // A quarter-size thumbnail is not blank.
    let small = Offscreen::new(gpu, W / 4, H / 4);
    r.last_frame().compose_view(DebugView::Normal, &small.view, W / 4, H / 4).unwrap();
    assert!(lit_share(&small.read(gpu).unwrap()) > 0.3);
    assert!(r.last_frame().compose_view(DebugView::Normal, &small.view, 0, 4).is_err());
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
    if let lampshade::scene::Light::Spot(l) = &mut bad.lights_mut()[0] {
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
    use lampshade::renderer::kit::gbuffer::{fit, Attr};
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
        let p = r.last_frame().probe(gpu, x, y).unwrap();
        let shown = img.get_pixel(x, y).0;
        let grey_background = shown[0] == shown[1] && shown[1] == shown[2];
        assert_eq!(p.lights.is_empty(), grey_background, "({x},{y}): lights {:?}, pixel {shown:?}", p.lights);
        seen.insert(p.lights.len());
    }
    assert!(seen.len() >= 2, "the samples should see pixels with different light counts: {seen:?}");
}

/// For each pixel, the lights whose exact shape (uncut radius) holds its point, from a renderer
/// whose last frame drew `scene` with no cut-off.
fn lights_at_pixels(gpu: &lampshade::Gpu, r: &Renderer) -> Vec<Vec<usize>> {
    use lampshade::renderer::inspect::inside_light;
    let points = r.last_frame().view_positions(gpu).unwrap();
    let lights = r.last_frame().light_records();
    points
        .iter()
        .map(|p| match p {
            Some(p) => (0..lights.len()).filter(|&i| inside_light(&lights[i], *p)).collect(),
            None => Vec::new(),
        })
        .collect()
}

fn demo_with(lights: usize) -> lampshade::Scene {
    let mut s = scene("demo");
    s.lights_mut().truncate(lights);
    s
}

#[test]
fn the_light_cutoff_trades_fragments_for_an_error_below_threshold_times_peak() {
    use lampshade::renderer::AccumFormat;
    let gpu = gpu();
    for (name, scene) in
        [("classify", scene("classify")), ("coincident", scene("coincident")), ("demo", demo_with(120))]
    {
        // f32 accumulation, so the comparison sees the cut-off and not fp16 rounding.
        let base = Settings { accumulation: AccumFormat::Rgba32Float, count_ideal: true, ..Settings::default() };
        let mut r0 = Renderer::new(gpu, OUTPUT_FORMAT, &base).unwrap();
        let (_, exact_stats) = render_image(gpu, &mut r0, &scene, &base, W, H).unwrap();
        let (d0, s0) = r0.last_frame().read_accumulation(gpu).unwrap();
        let touching = lights_at_pixels(gpu, &r0);
        let colours: Vec<glam::Vec3> =
            r0.last_frame().light_records().iter().map(|l| glam::Vec3::from(l.color)).collect();
        let mut last_shaded = exact_stats.shaded_fragments.unwrap();
        for t in [1.0 / 256.0, 1.0 / 64.0, 1.0 / 16.0] {
            let s = Settings { light_cutoff: t, ..base.clone() };
            let f = render(&scene, &s, W, H);
            let shaded = f.stats.shaded_fragments.unwrap();
            assert!(shaded < last_shaded, "{name} cut-off {t}: shaded {shaded}, before {last_shaded}");
            last_shaded = shaded;
            // A light cut off at `t` of its peak loses at most t x its colour at any point.
            let mut worst = 0f32;
            let mut changed = 0;
            for (px, lights) in touching.iter().enumerate() {
                let allowed: glam::Vec3 = lights.iter().map(|&i| colours[i] * t).sum();
                for c in 0..3 {
                    for (cut, exact) in [(&f.diffuse, &d0), (&f.specular, &s0)] {
                        let err = (cut[px * 4 + c] - exact[px * 4 + c]).abs();
                        changed += (err > 0.0) as usize;
                        worst = worst.max(err / allowed[c].max(1e-6));
                        assert!(
                            err <= allowed[c] * 1.001 + 1e-5,
                            "{name} cut-off {t}, pixel {px}: error {err} above {}",
                            allowed[c]
                        );
                    }
                }
            }
            // Not vacuous: the biggest cut-off removes light somewhere in every case.
            assert!(changed > 0 || t < 1.0 / 16.0, "{name} cut-off {t}: nothing changed");
            println!(
                "{name} cut-off {t}: shaded {shaded}, {changed} values changed, worst error {worst:.3} of the bound"
            );
        }
    }
}

#[test]
fn log_accumulation_stays_within_its_derived_bound() {
    use lampshade::renderer::settings::{log_accum_error_bound, LOG_ACCUM_MAX};
    use lampshade::renderer::AccumFormat;
    let gpu = gpu();
    for (name, scene) in [("classify", scene("classify")), ("spot", scene("spot")), ("demo", demo_with(120))] {
        let exact = Settings { accumulation: AccumFormat::Rgba32Float, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &exact).unwrap();
        render_image(gpu, &mut r, &scene, &exact, W, H).unwrap();
        let (d, s) = r.last_frame().read_accumulation(gpu).unwrap();
        let touching = lights_at_pixels(gpu, &r);
        let log = render(&scene, &Settings { accumulation: AccumFormat::Rgba8Log, ..Settings::default() }, W, H);
        assert_finite(&log, name);
        let (mut checked, mut saturated, mut brightest, mut worst) = (0, 0, 0f32, 0f32);
        for (px, lights) in touching.iter().enumerate() {
            // The ambient + sun write and one blend per light touching the point.
            let blends = 1 + lights.len() as u32;
            for c in 0..3 {
                for (got, want) in [(&log.diffuse, &d), (&log.specular, &s)] {
                    let (got, want) = (got[px * 4 + c], want[px * 4 + c]);
                    let bound = log_accum_error_bound(want, blends);
                    if want + bound > LOG_ACCUM_MAX - 0.5 {
                        // Near the top of the range one code spans most of a unit: saturation.
                        saturated += 1;
                        continue;
                    }
                    checked += 1;
                    brightest = brightest.max(want);
                    worst = worst.max((got - want).abs() / bound);
                    assert!(
                        (got - want).abs() <= bound + 1e-5,
                        "{name} pixel {px}: decoded {got}, exact {want}, bound {bound} ({blends} writes)"
                    );
                }
            }
        }
        assert!(checked > 6 * (W * H) as usize * 9 / 10, "{name}: only {checked} values checked");
        assert!(brightest > 0.5, "{name}: the check never saw bright light ({brightest})");
        println!("{name}: worst error {worst:.3} of the bound, {saturated} saturated values, brightest {brightest}");
    }
}

#[test]
fn the_frame_reports_the_volume_meshes_it_drew() {
    // Volume kinds only for the light types present: no cone without narrow spots.
    let points_only = render(&scene("classify"), &Settings::default(), W, H);
    assert_eq!(points_only.stats.volume_meshes, vec!["sphere"]);
    let spot = render(&scene("spot"), &Settings::default(), W, H);
    assert!(spot.stats.volume_meshes.contains(&"cone".to_string()), "{:?}", spot.stats.volume_meshes);
    let full = render(&scene("spot"), &Settings { culling: CullingMode::Fullscreen, ..Settings::default() }, W, H);
    assert!(full.stats.volume_meshes.is_empty(), "full-screen lights draw no mesh");
    let fine =
        render(&scene("spot"), &Settings { sphere_subdivisions: 3, cone_sides: 24, ..Settings::default() }, W, H);
    assert_eq!((fine.stats.sphere_triangles, fine.stats.cone_triangles), (1280, 24 + 22));
}

#[test]
fn one_renderer_switches_the_bench_knobs_live() {
    // Depth format, accumulation, cut-off and tessellation rebuild what they must on a reused
    // renderer: its frames equal a fresh renderer's, in either order of switching.
    use lampshade::renderer::{AccumFormat, DepthFormat};
    let gpu = gpu();
    let scene = demo_with(150);
    let base = Settings::default();
    let knobs = [
        Settings { depth_format: DepthFormat::Depth24PlusStencil8, ..base.clone() },
        Settings { accumulation: AccumFormat::Rgba8Log, ..base.clone() },
        Settings { light_cutoff: 1.0 / 16.0, ..base.clone() },
        Settings { sphere_subdivisions: 0, cone_sides: 5, ..base.clone() },
        Settings { sphere_subdivisions: 3, culling: CullingMode::StencilTwoPass, ..base.clone() },
        base.clone(),
    ];
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &base).unwrap();
    for s in knobs.iter().chain(knobs.iter().rev()) {
        let (live, stats) = render_image(gpu, &mut r, &scene, s, W, H).unwrap();
        let fresh = render(&scene, s, W, H);
        assert_eq!(max_channel_difference(&live, &fresh.image), 0, "{s:?}: a reused renderer differs");
        assert_eq!(stats.shaded_fragments, fresh.stats.shaded_fragments, "{s:?}");
        assert_eq!(stats.depth_stencil_format, fresh.stats.depth_stencil_format);
    }
}

/// Seed 000 writes ambient + sun into the accumulation from the G-buffer pass (its RT1): the
/// same light as the full-screen ambient pass, which reads it back from the G-buffer. With f32
/// targets (`reference` layout, Rgba32Float accumulation) the two differ only by the f32 rounding
/// of storing and re-reading the normal, position and exponent: a few ulps, so 2e-6 relative
/// (plus 1e-7) bounds them. With `compact`'s fp16 normals the G-buffer pass works from the
/// normal before rounding, so the pictures may differ by a step where the sun grazes.
#[test]
fn ambient_and_sun_written_by_the_gbuffer_pass_equal_their_own_pass() {
    use lampshade::renderer::AccumFormat;
    for (name, scene) in [("demo", demo_with(40)), ("classify", scene("classify")), ("spot", scene("spot"))] {
        assert!(scene.sun.is_some() || scene.ambient.max_element() > 0.0, "{name}: nothing to compare");
        // Unshadowed: the G-buffer pass looks the sun's shadow up at the interpolated position,
        // its own pass at the one rebuilt from depth, so where a comparison tap sits on an edge
        // the two differ by more than rounding (demo: 5.5e-6 relative with shadows on).
        let exact = Settings {
            layout: LayoutChoice::Reference,
            accumulation: AccumFormat::Rgba32Float,
            count_fragments: false,
            ..unshadowed()
        };
        let folded = render(&scene, &exact, W, H);
        let own = render(&scene, &Settings { ambient_in_gbuffer: false, ..exact.clone() }, W, H);
        assert!(folded.stats.ambient_in_gbuffer && !own.stats.ambient_in_gbuffer, "{name}: the knob was not applied");
        let mut worst = 0f32;
        let mut lit = 0;
        for (a, b) in folded.diffuse.iter().chain(&folded.specular).zip(own.diffuse.iter().chain(&own.specular)) {
            let err = (a - b).abs();
            lit += (*b > 0.0) as usize;
            worst = worst.max(err / b.abs().max(1e-3));
            assert!(err <= 2e-6 * b.abs() + 1e-7, "{name}: G-buffer pass {a}, own pass {b}");
        }
        assert!(lit > (W * H) as usize, "{name}: too little light to compare ({lit} values)");
        println!("{name}: worst relative difference {worst:.2e}");
        // The 8-bit picture with the default shadows on: within a step either way.
        let compact = Settings { count_fragments: false, ..Settings::default() };
        let a = render(&scene, &compact, W, H);
        let b = render(&scene, &Settings { ambient_in_gbuffer: false, ..compact.clone() }, W, H);
        let step = max_channel_difference(&a.image, &b.image);
        assert!(step <= 1, "{name}: compact differs by {step} steps");
    }
}

/// A layout without an emissive target (`seed000`, `packed`) carries emission in the light
/// accumulation the G-buffer pass starts, so with `ambient_in_gbuffer` off it still writes
/// ambient + sun there: the same picture either way (emission was lost with the knob off: 79
/// pixels of `demo` at 320x180, up to 146 steps), and the stats say where ambient went.
#[test]
fn a_layout_without_an_emissive_target_keeps_its_emission_with_ambient_in_its_own_pass() {
    let demo = scene("demo");
    for layout in [LayoutChoice::Seed000, LayoutChoice::Packed] {
        let on = Settings { layout, count_fragments: false, ..Settings::default() };
        let off = Settings { ambient_in_gbuffer: false, ..on.clone() };
        let (a, b) =
            (frame_of("demo", || demo.clone(), &on, 320, 180), frame_of("demo", || demo.clone(), &off, 320, 180));
        assert!(b.stats.ambient_in_gbuffer, "{}: ambient left the G-buffer pass", layout.name());
        assert_eq!(max_channel_difference(&a.image, &b.image), 0, "{}: emission lost with ambient off", layout.name());
    }
    // A layout with an emissive target keeps its own ambient pass when asked.
    let compact = Settings { ambient_in_gbuffer: false, count_fragments: false, ..Settings::default() };
    assert!(!frame_of("demo", || demo.clone(), &compact, 320, 180).stats.ambient_in_gbuffer);
}

/// `seed000` is seed 000's own layout: RT2 holds the world-space normal and RT3 the world-space,
/// not normalised, view vector (surface to eye), whatever way the camera looks. Checked against
/// `compact`, which stores a view-space normal and reconstructs the position from depth: at the
/// same pixels, seed000's stored vectors are compact's turned into world space (to fp16
/// precision: 2^-11 relative, and the normals' encoding bounds), and on `demo`'s floor (the plane
/// y = 0) the stored normal is the world's up and the view vector's y the eye's height. RT0's
/// alpha holds the specular level as it is.
#[test]
fn seed000_stores_world_space_normals_and_view_vectors() {
    let gpu = gpu();
    let scene = demo_with(8);
    let probe_at = |layout: LayoutChoice| {
        let settings = Settings { layout, count_fragments: false, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings).unwrap();
        render_image(gpu, &mut r, &scene, &settings, W, H).unwrap();
        r
    };
    let seed = probe_at(LayoutChoice::Seed000);
    let compact = probe_at(LayoutChoice::Compact);
    assert_eq!(seed.layout().targets.len(), 3, "RT0, RT2, RT3 (RT1 is the accumulation)");
    let eye_y = scene.camera.position.y as f32;
    let to_world = scene.camera.rotation().transpose().as_mat3();
    let (mut checked, mut floor) = (0, 0);
    for k in 0..40u32 {
        let (x, y) = ((k * 37 + 5) % W, H / 2 + (k * 23 + 3) % (H / 2));
        let (p, c) = (seed.last_frame().probe(gpu, x, y).unwrap(), compact.last_frame().probe(gpu, x, y).unwrap());
        if !p.valid || !c.valid {
            continue;
        }
        let raw = |name: &str| {
            let v = p.raw.iter().find(|(n, _, _)| n == name).map(|(_, _, v)| *v).unwrap();
            glam::Vec3::new(v[0], v[1], v[2])
        };
        let (n, v) = (raw("world normal+exp"), raw("view vector"));
        // RT0's alpha holds the specular level itself (seed 000), compact's 8-bit channel the
        // reflectance f0 = level x 8 / (n + 8): the same level within compact's half step.
        let level = p.raw.iter().find(|(n, _, _)| n == "diffuse+spec").map(|(_, _, v)| v[3]).unwrap();
        let half_step = 0.5 / 255.0 * (c.specular_exponent + 8.0) / 8.0 + 1e-3 * level;
        assert!(
            (level - c.specular_level).abs() <= half_step,
            "({x},{y}): RT0.a {level} vs compact's level {}",
            c.specular_level
        );
        let (n_expected, v_expected) = (to_world * c.normal, to_world * -c.position);
        assert!((n - n_expected).length() < 3e-3, "({x},{y}): stored normal {n} vs {n_expected}");
        assert!(
            (v - v_expected).length() < 2e-3 * v_expected.length(),
            "({x},{y}): stored view vector {v} vs {v_expected}"
        );
        // Decoded back into view space for the lighting.
        assert!(
            (p.position - c.position).length() < 2e-3 * c.position.length(),
            "({x},{y}): {} vs {}",
            p.position,
            c.position
        );
        if (n - glam::Vec3::Y).length() < 3e-3 && (v.y - eye_y).abs() < 0.02 {
            floor += 1;
        }
        checked += 1;
    }
    assert!(checked >= 20 && floor >= 3, "checked {checked} pixels, {floor} on the floor");
}

/// On lavapipe every pipeline is compiled to machine code when it is created (2 to 9 MiB of heap
/// each for the shading passes), and the renderer keeps the passes of recent configurations, so
/// a configuration builds only the passes its frames draw: a deferred frame with no blended
/// surface, no tile lists and no post chain builds none of the forward, tiled or post-chain
/// pipelines; the first frame that draws one builds it, and only once.
#[test]
fn passes_are_built_by_the_first_frame_that_draws_them() {
    // Its own device: wgpu counts live pipelines per device, and other tests share `gpu()`.
    let gpu = lampshade::Gpu::headless().expect("these tests need a GPU adapter");
    let live = || {
        let h = gpu.device.get_internal_counters().hal;
        (h.render_pipelines.read(), h.compute_pipelines.read())
    };
    let mut scene = scene("demo");
    scene.lights_mut().truncate(64);
    assert!(!scene.any_blended(), "the plain frame must have no blended surface to shade forward");
    let out = Offscreen::new(&gpu, W, H);
    let plain = Settings { culling: CullingMode::Volume, ..Settings::default() };
    let tiled = Settings { culling: CullingMode::Tiled, ..plain.clone() };
    let bloom = Settings { bloom: true, ..plain.clone() };
    let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &plain).unwrap();
    let mut draw = |s: &Settings| r.render(&scene, s, &out.view, W, H).unwrap();
    draw(&plain);
    let first = live();
    draw(&plain);
    assert_eq!(live(), first, "a second plain frame built pipelines");
    draw(&tiled);
    let after_tiled = live();
    assert!(after_tiled.1 > first.1, "the tiled frame built no compute pipeline: it was built before it was drawn");
    draw(&bloom);
    let after_bloom = live();
    assert!(after_bloom.0 > after_tiled.0, "the bloom frame built no render pipeline: the chain was built before");
    for s in [&tiled, &bloom, &plain] {
        draw(s);
    }
    assert_eq!(live(), after_bloom, "passes already built were built again");
}

#[test]
fn a_change_of_shader_features_alone_keeps_the_targets_and_the_exposure() {
    // Frames 0-3 show `classify`; frames 4-7 a dimmer `classify`, to which one renderer also
    // adds a narrow spot that casts but sits far below the floor, off screen and out of reach:
    // that scene needs the spots' shadow lookup (another pipeline set) while its picture is the
    // dim one's. Auto-exposure adapts slowly to the dimming, so a frame after the switch equals
    // the frame of the renderer that never switched only if the targets (which hold the
    // adaptation) were kept across the change of pipeline set.
    let gpu = gpu();
    let bright = scene("classify");
    let mut dim = bright.clone();
    dim.ambient *= 0.3;
    for l in dim.lights_mut().iter_mut() {
        match l {
            lampshade::scene::Light::Point(p) => p.intensity *= 0.3,
            lampshade::scene::Light::Spot(p) => p.intensity *= 0.3,
        }
    }
    if let Some(sun) = dim.sun.as_mut() {
        sun.intensity *= 0.3;
    }
    let mut dim_with_spot = dim.clone();
    dim_with_spot.lights_mut().push(lampshade::scene::Light::Spot(lampshade::scene::SpotLight {
        position: glam::DVec3::new(0.0, -10_000.0, 0.0),
        direction: glam::Vec3::NEG_Y,
        color: glam::Vec3::ONE,
        intensity: 1.0,
        radius: 1.0,
        inner_angle: 0.3,
        outer_angle: 0.4,
        cast_shadows: true,
        cookie: None,
        mask: u32::MAX,
    }));
    let s = Settings {
        auto_exposure: true,
        adaptation_speed: 1.0,
        count_fragments: false,
        timestamps: false,
        ..Settings::default()
    };
    let frames = |scenes: &[&lampshade::Scene]| {
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).expect("renderer");
        let mut last = None;
        for sc in scenes {
            last = Some(render_image(gpu, &mut r, sc, &s, W, H).expect("render"));
        }
        last.expect("frames")
    };
    let (switched, switched_stats) = frames(&[&bright, &bright, &bright, &bright, &dim_with_spot, &dim_with_spot]);
    let (never, never_stats) = frames(&[&bright, &bright, &bright, &bright, &dim, &dim]);
    assert!(switched_stats.shader_lookups.iter().any(|l| l == "spot tiles"), "{:?}", switched_stats.shader_lookups);
    assert!(!never_stats.shader_lookups.iter().any(|l| l == "spot tiles"), "{:?}", never_stats.shader_lookups);
    assert_eq!(max_channel_difference(&switched, &never), 0, "the switch reset the exposure or changed the picture");
    // The exposure is still adapting: a renderer that starts at the dim scene differs, so the
    // comparison above can fail.
    let (restarted, _) = frames(&[&dim_with_spot, &dim_with_spot]);
    assert!(max_channel_difference(&restarted, &never) > 0, "the exposure did not need the frames before");
}

/// Renderers on one device share the pass set of a configuration: a second renderer of it,
/// created while the first is alive, builds no pipeline. Each keeps its own scratch (the tile
/// lists, the query read-backs): the two drawing in turn at other sizes leave each other's
/// lists and counts alone, and each draws what a renderer alone on the device draws, bit for
/// bit.
#[test]
fn renderers_share_pass_sets_and_keep_their_own_scratch() {
    // Its own device: wgpu counts live pipelines per device, and other tests share `gpu()`.
    let gpu = lampshade::Gpu::headless().expect("these tests need a GPU adapter");
    let pipelines = || {
        let h = gpu.device.get_internal_counters().hal;
        h.render_pipelines.read() + h.compute_pipelines.read()
    };
    let spot = scene("spot");
    let s = |culling| Settings { culling, ..Settings::default() };
    let frame = |r: &mut Renderer, s: &Settings, (w, h): (u32, u32)| {
        let (image, stats) = render_image(&gpu, r, &spot, s, w, h).expect("render");
        let (d, sp) = r.last_frame().read_accumulation(&gpu).expect("accumulation");
        (image, stats, d, sp)
    };
    let lists = |r: &Renderer| r.last_frame().tile_lists(&gpu).expect("tile lists").map(|l| l.data);
    let shaded = |st: &lampshade::renderer::FrameStats| st.per_light.iter().map(|l| l.shaded).collect::<Vec<_>>();
    for mode in [CullingMode::StencilReplace, CullingMode::Tiled, CullingMode::Clustered] {
        let mut first = Renderer::new(&gpu, OUTPUT_FORMAT, &s(mode)).expect("renderer");
        let alone = frame(&mut first, &s(mode), (W, H));
        let first_lists = lists(&first);
        assert_eq!(first_lists.is_some(), mode != CullingMode::StencilReplace, "{mode:?}: lists");
        let built = pipelines();
        let mut second = Renderer::new(&gpu, OUTPUT_FORMAT, &s(mode)).expect("renderer");
        // The second draws a larger frame (other lists, other counts) with the shared set.
        let larger = frame(&mut second, &s(mode), (2 * W, 2 * H));
        assert_eq!(pipelines(), built, "{mode:?}: the second renderer built pipelines: it did not share the set");
        assert_eq!(lists(&first), first_lists, "{mode:?}: the second renderer's frame changed the first's lists");
        if first_lists.is_some() {
            assert_ne!(lists(&second), first_lists, "{mode:?}: a frame twice the size has the same lists");
        }
        assert_ne!(shaded(&larger.1), shaded(&alone.1), "{mode:?}: a frame twice the size shaded as many fragments");
        for (who, r) in [("first", &mut first), ("second", &mut second)] {
            let again = frame(r, &s(mode), (W, H));
            assert_eq!(max_channel_difference(&alone.0, &again.0), 0, "{mode:?}, {who}: another picture");
            assert!(alone.2 == again.2 && alone.3 == again.3, "{mode:?}, {who}: the accumulation differs");
            assert_eq!(shaded(&alone.1), shaded(&again.1), "{mode:?}, {who}: other per-light counts");
        }
        assert_eq!(pipelines(), built, "{mode:?}: drawing in turn built pipelines");
    }
}

#[test]
fn every_timed_pass_reports_its_own_span_on_every_path() {
    // Each pass names its timing span where it is declared; a span begun in one pass and
    // ended under another name, or never ended, reads as null here.
    let timed = |name: &str, knobs: &[(&str, &str)]| {
        let mut s = Settings::default();
        for (k, v) in knobs {
            s.set(k, v).expect("a knob");
        }
        assert!(s.timestamps, "the default settings time the frame");
        render(&scene(name), &s, 96, 54).stats
    };
    let post = [
        ("bloom", "on"),
        ("auto-exposure", "on"),
        ("lut", "identity"),
        ("fog", "on"),
        ("dof", "on"),
        ("vignette", "0.3"),
        ("distortion", "on"),
        ("aa", "fxaa"),
    ];
    let d = timed("demo", &post).gpu_ms;
    let mut parts = vec![
        ("gbuffer", d.gbuffer),
        ("lighting", d.lighting),
        ("compose", d.compose),
        ("shadows", d.shadows),
        ("bloom", d.bloom),
        ("exposure", d.exposure),
        ("tonemap", d.tonemap),
    ];
    // Every effect of the table, each under its own name.
    parts.extend(lampshade::renderer::post::effects::EFFECTS.iter().map(|e| (e.name, d.effect(e.name))));
    for &(name, ms) in &parts {
        assert!(ms.is_some_and(|ms| ms >= 0.0), "deferred with every effect: {name} is {ms:?}");
    }
    let total = d.total.expect("a total");
    let sum: f64 = parts.iter().filter_map(|(_, ms)| *ms).sum();
    assert!(total >= 0.99 * sum, "the parts ({sum} ms) exceed the total ({total} ms): {d:?}");
    let glass = timed("glass", &[("shadows", "none")]).gpu_ms;
    assert!(glass.forward.is_some() && glass.compose.is_some(), "blended surfaces: {glass:?}");
    let tiled = timed("demo", &[("culling", "tiled")]).gpu_ms;
    assert!(tiled.lists.is_some() && tiled.lighting.is_some(), "tiled lists on the GPU: {tiled:?}");
    let prepass = timed("demo", &[("path", "light-prepass")]).gpu_ms;
    assert!(prepass.prepass_final.is_some() && prepass.compose.is_some(), "light pre-pass: {prepass:?}");
    for path in ["forward", "forward-multipass"] {
        let s = timed("demo", &[("path", path)]);
        let fp = s.forward_path.expect("the forward path's figures");
        assert!(!fp.passes.is_empty());
        for p in &fp.passes {
            assert!(p.gpu_ms.is_some(), "{path}: the {} pass has no time", p.name);
        }
        assert!(s.gpu_ms.total.is_some(), "{path}: no total");
    }
}

/// Seed 000's one RT1: every light adds its lit colour, albedo x diffuse + specular, to one
/// target, and compose shows it as it is. With f32 accumulation and no ambient or sun (which
/// the G-buffer pass computes from the unrounded surface), RT1 at sampled pixels equals the f64
/// evaluation of the probe's decoded surface, albedo x diffuse + specular, within the f32
/// allowance of `hard_cases::gpu_lighting_matches_f64_at_sampled_pixels`.
#[test]
fn seed000_accumulates_the_lit_colour_in_its_one_rt1() {
    use lampshade::renderer::AccumFormat;
    let gpu = gpu();
    let settings = Settings {
        layout: LayoutChoice::Seed000,
        accumulation: AccumFormat::Rgba32Float,
        culling: CullingMode::Volume,
        count_ideal: false,
        ..unshadowed()
    };
    let (mut worst, mut checked) = (0f64, 0);
    for name in ["classify", "spot", "on-surface", "coincident", "spot-extremes"] {
        let mut scene = scene(name);
        (scene.sun, scene.ambient) = (None, glam::Vec3::ZERO);
        assert!(!scene.any_emissive(), "{name} has emissive surfaces");
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings).unwrap();
        let (_, stats) = render_image(gpu, &mut r, &scene, &settings, W, H).unwrap();
        assert_eq!(stats.accumulation_bytes_per_pixel, 16, "one Rgba32Float target");
        let clamp = lampshade::reference::Clamps::of(&r);
        for k in 0..48u32 {
            let (x, y) = ((k * 37 + 5) % W, (k * 23 + 3) % H);
            let p = r.last_frame().probe(gpu, x, y).unwrap();
            if !p.valid {
                continue;
            }
            checked += 1;
            assert_eq!(p.specular_light, glam::Vec3::ZERO, "{name}: RT1 holds all light");
            let (d, s) = lampshade::reference::shade(&scene, &p, &clamp);
            let want = d * p.albedo.as_dvec3() + s;
            for c in 0..3 {
                let (g, e) = (p.diffuse_light[c] as f64, want[c]);
                let err = (g - e).abs();
                worst = worst.max(err / e.abs().max(1e-3));
                assert!(err <= 1e-4 * e.abs() + 1e-4, "{name} ({x},{y})[{c}]: RT1 {g} vs f64 {e}");
                assert_eq!(p.lit[c], p.diffuse_light[c], "{name}: the probe's lit colour is RT1");
            }
        }
    }
    assert!(checked >= 50, "only {checked} sampled pixels hit geometry");
    println!("worst relative error of RT1 against f64: {worst:.2e}");
}

/// Seed 004's "depth is not explicitly rendered": with `--depth-read buffer` the G-buffer pass
/// writes no R32F copy and every reader takes the depth buffer's depth aspect instead. The
/// 32-bit float buffer holds what the copy held, so the frame is the copy's bit for bit: the
/// picture, the linear light, the fragment counts, the reconstructed positions and the probe;
/// and 4 bytes a pixel are gone. Where the frame cannot (a stencil method or `auto` writing the
/// stencil while the lights read, 24-bit depth, a stencil view), it keeps the copy and says why.
#[test]
fn reading_the_depth_buffer_instead_of_its_copy_changes_nothing_but_the_bytes() {
    use lampshade::renderer::{DepthRead, RenderPath};
    let gpu = gpu();
    let demo = scene("demo");
    let base = Settings { count_ideal: true, ..Settings::default() };
    let allowed = [
        (RenderPath::Deferred, LayoutChoice::Compact, CullingMode::Volume),
        (RenderPath::Deferred, LayoutChoice::Compact, CullingMode::Fullscreen),
        (RenderPath::Deferred, LayoutChoice::Compact, CullingMode::Tiled),
        (RenderPath::Deferred, LayoutChoice::Compact, CullingMode::Clustered),
        (RenderPath::Deferred, LayoutChoice::Lambert8, CullingMode::Volume),
        (RenderPath::Deferred, LayoutChoice::Fit, CullingMode::Clustered),
        (RenderPath::LightPrepass, LayoutChoice::Compact, CullingMode::Volume),
        (RenderPath::LightPrepass, LayoutChoice::Compact, CullingMode::Tiled),
    ];
    for (path, layout, culling) in allowed {
        let what = format!("{path:?} {layout:?} {culling:?}");
        let copy_settings = Settings { path, layout, culling, ..base.clone() };
        let buffer_settings = Settings { depth_read: DepthRead::Buffer, ..copy_settings.clone() };
        let mut rc = Renderer::new(gpu, OUTPUT_FORMAT, &copy_settings).unwrap();
        let (copy, cs) = render_image(gpu, &mut rc, &demo, &copy_settings, W, H).unwrap();
        let mut rb = Renderer::new(gpu, OUTPUT_FORMAT, &buffer_settings).unwrap();
        let (buffer, bs) = render_image(gpu, &mut rb, &demo, &buffer_settings, W, H).unwrap();
        assert!(cs.depth_read.starts_with("R32Float copy (--depth-read copy"), "{what}: {}", cs.depth_read);
        assert_eq!(bs.depth_read, "depth buffer (its depth aspect; no copy)", "{what}");
        let differ = copy.pixels().zip(buffer.pixels()).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{what}: {differ} pixels differ");
        let (accum_c, accum_b) =
            (rc.last_frame().read_accumulation(gpu).unwrap(), rb.last_frame().read_accumulation(gpu).unwrap());
        let same_bits = |a: &[f32], b: &[f32]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same_bits(&accum_c.0, &accum_b.0) && same_bits(&accum_c.1, &accum_b.1), "{what}: the light differs");
        assert_eq!(
            (cs.shaded_fragments, cs.ideal_fragments),
            (bs.shaded_fragments, bs.ideal_fragments),
            "{what}: the counts differ"
        );
        if path == RenderPath::Deferred {
            assert_eq!(cs.gbuffer_bytes_per_pixel - bs.gbuffer_bytes_per_pixel, 4, "{what}");
            let (pc, pb) = (rc.last_frame().view_positions(gpu).unwrap(), rb.last_frame().view_positions(gpu).unwrap());
            assert!(pc.iter().flatten().count() > (W * H / 2) as usize, "{what}: too few surface pixels");
            assert!(pc == pb, "{what}: the reconstructed positions differ");
        } else {
            let depth_copy = |s: &lampshade::FrameStats| s.prepass.as_ref().unwrap().depth_copy_bytes_per_pixel;
            assert_eq!((depth_copy(&cs), depth_copy(&bs)), (4, 0), "{what}");
        }
        for (x, y) in [(W / 2, H / 2), (W / 4, H * 3 / 4), (W - 3, H - 2)] {
            let (a, b) = (rc.last_frame().probe(gpu, x, y).unwrap(), rb.last_frame().probe(gpu, x, y).unwrap());
            assert_eq!((a.valid, a.position, a.normal), (b.valid, b.position, b.normal), "{what}: probe at ({x}, {y})");
        }
    }
    // Where the frame must keep the copy: the reason, and the copy's bytes.
    let refused = [
        (Settings { culling: CullingMode::StencilReplace, ..base.clone() }, "writes the stencil"),
        (Settings { culling: CullingMode::Auto, ..base.clone() }, "auto picks stencil methods"),
        (Settings { debug_view: DebugView::Stencil, ..base.clone() }, "stencil view"),
    ];
    for (s, why) in refused {
        let s = Settings { depth_read: DepthRead::Buffer, ..s };
        let f = render(&demo, &s, W, H);
        assert!(f.stats.depth_read.contains(why), "{:?}: {}", s.culling, f.stats.depth_read);
        assert_eq!(f.stats.gbuffer_bytes_per_pixel, 24, "{}", f.stats.depth_read);
    }
}

/// A frame whose inputs are the frame before's (the same light list, camera, objects, materials,
/// settings and size) takes that frame's CPU part and upload as they were, and draws the same
/// picture; any change (a light moved through `lights_mut`, the camera, a setting, the size)
/// computes and uploads again, and gives a fresh renderer's picture of the changed frame, in
/// every list mode (whose lists the reused frame does not write again) and a drawn one.
#[test]
fn a_frame_with_the_last_ones_inputs_reuses_its_cpu_part_and_any_change_does_not() {
    let gpu = gpu();
    let mut scene = with_lights("demo", 300);
    for culling in [CullingMode::Zbin, CullingMode::Clustered, CullingMode::Tiled, CullingMode::StencilReplace] {
        let s = Settings { culling, ..unshadowed() };
        let name = culling.name();
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
        let frame = |r: &mut Renderer, scene: &lampshade::Scene, s: &Settings, (w, h): (u32, u32)| {
            render_image(gpu, r, scene, s, w, h).unwrap()
        };
        let (first, a) = frame(&mut r, &scene, &s, (W, H));
        let (again, b) = frame(&mut r, &scene, &s, (W, H));
        assert!(!a.cpu_reused && b.cpu_reused, "{name}: {} then {}", a.cpu_reused, b.cpu_reused);
        assert_eq!(b.cpu_ms.records, 0.0, "{name}");
        assert_eq!(max_channel_difference(&first, &again), 0, "{name}: the reused frame differs");
        assert_eq!(
            (a.shaded_fragments, a.tiles.as_ref().map(|t| t.entries)),
            (b.shaded_fragments, b.tiles.map(|t| t.entries))
        );
        // A light moved: copied on write, so the renderer sees another list.
        let mut moved = scene.clone();
        if let lampshade::scene::Light::Point(p) = &mut moved.lights_mut()[0] {
            p.position.x += 3.0;
        }
        let mut camera = scene.clone();
        camera.camera.yaw += 0.05;
        let exposure = Settings { exposure: 1.5, ..s.clone() };
        for (what, changed, settings, size) in [
            ("a light", &moved, &s, (W, H)),
            ("the camera", &camera, &s, (W, H)),
            ("the exposure", &scene, &exposure, (W, H)),
            ("the size", &scene, &s, (W + 8, H)),
        ] {
            let (image, st) = frame(&mut r, changed, settings, size);
            assert!(!st.cpu_reused, "{name}: {what} changed, the CPU part reused");
            let fresh = render(changed, settings, size.0, size.1);
            assert_eq!(max_channel_difference(&image, &fresh.image), 0, "{name}: {what} changed: not a fresh frame");
            // And back to the first frame's inputs: computed again, its picture again.
            let (back, st) = frame(&mut r, &scene, &s, (W, H));
            assert!(!st.cpu_reused && max_channel_difference(&back, &first) == 0, "{name}: back from {what}");
        }
        // Changed in place, the light list is copied while the renderer holds it.
        let held = scene.lights.clone();
        scene.lights_mut()[1] = scene.lights[2];
        assert!(!std::sync::Arc::ptr_eq(&held, &scene.lights));
        let (image, st) = frame(&mut r, &scene, &s, (W, H));
        assert!(!st.cpu_reused, "{name}: a light edited in place, the CPU part reused");
        assert_eq!(max_channel_difference(&image, &render(&scene, &s, W, H).image), 0, "{name}: in place");
    }
}
