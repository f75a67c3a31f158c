//! The light pre-pass (`--path light-prepass`, seeds 003/004): it renders every scene
//! finite and lit, every culling mode gives the full-screen picture within the path, its light
//! buffer holds what either encoding promises, its difference from deferred shading stays
//! inside the bound `reference::prepass_enclosure` derives, and it refuses what it cannot draw.

use crate::common::*;
use lampshade::compare::max_channel_difference;
use lampshade::headless::render_image;
use lampshade::renderer::post::PostImage;
use lampshade::renderer::settings::{log_accum_error_bound, unorm_accum_error_bound, LOG_ACCUM_MAX};
use lampshade::renderer::{
    AccumFormat, BrdfOverride, CullingMode, DebugView, LayoutChoice, Msaa, RenderPath, Renderer, Settings,
    OUTPUT_FORMAT,
};

const W: u32 = 160;
const H: u32 = 90;

fn prepass(base: Settings) -> Settings {
    Settings { path: RenderPath::LightPrepass, ..base }
}

fn room() -> lampshade::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/room/room.gltf");
    let opts = lampshade::scene::import::ImportOptions::default();
    lampshade::scene::import::load(&path, &opts, &mut |_| {}).expect("assets/room/room.gltf loads").scene
}

#[test]
fn renders_demo_room_and_every_hard_case_finite_and_lit() {
    let mut scenes: Vec<(String, lampshade::Scene)> = vec![("demo".into(), scene("demo")), ("room".into(), room())];
    scenes.extend(HARD_CASES.iter().map(|n| (n.to_string(), scene(n))));
    for (name, scene) in &scenes {
        let f = render(scene, &prepass(Settings { count_ideal: false, ..Settings::default() }), W, H);
        assert_finite(&f, name);
        assert!(lit_share(&f.image) > 0.05, "{name}: the light pre-pass's picture is black");
        // The light buffer holds light where lights reach (not only ambient from pass 3).
        let lit = f.diffuse.chunks_exact(4).filter(|c| c[0] + c[1] + c[2] > 0.0).count();
        assert!(lit > 0, "{name}: the light buffer is empty");
        let p = f.stats.prepass.as_ref().expect("pre-pass figures");
        assert_eq!(f.stats.path, RenderPath::LightPrepass);
        assert_eq!((p.normal_exp_bytes_per_pixel, p.depth_copy_bytes_per_pixel), (4, 4), "{name}");
        assert_eq!((p.light_buffer_bytes_per_pixel, p.hdr_bytes_per_pixel), (8, 8), "{name}");
        assert!(p.final_draw_calls > 0 && p.final_draw_calls == p.base_draw_calls, "{name}: {p:?}");
        // Both geometry passes counted: pass 3 shades at most what pass 1 left visible.
        let (base, fin) = (p.base_fragments.unwrap(), p.final_fragments.unwrap());
        assert!(fin > 0 && fin <= base, "{name}: pass 1 {base} fragments, pass 3 {fin}");
    }
}

/// Every culling mode against `fullscreen` within the path, under `base`: within one 8-bit step
/// (the deferred tests' tolerance, `tests/it/culling.rs`); with seed 004's log encoding tiled and
/// clustered write once per pixel instead of once per light and are exempt, as there.
fn modes_match_fullscreen(base: &Settings, cases: &[&str], what: &str) {
    let mut failures = Vec::new();
    for name in cases {
        let mut scene = scene(name);
        scene.lights_mut().truncate(200);
        let s = |culling| prepass(Settings { culling, ..base.clone() });
        let reference = render(&scene, &s(CullingMode::Fullscreen), W, H);
        assert_finite(&reference, name);
        for mode in CullingMode::ALL.into_iter().skip(1) {
            let f = render(&scene, &s(mode), W, H);
            assert_finite(&f, name);
            let step = max_channel_difference(&reference.image, &f.image);
            let one_write = matches!(mode, CullingMode::Tiled | CullingMode::Clustered | CullingMode::Zbin)
                || f.stats.per_light.iter().any(|l| l.method.listed());
            let log = base.accumulation == AccumFormat::Rgba8Log;
            if step > 1 && !(log && one_write) {
                failures.push(format!("{what} {name}/{}: {step} steps from fullscreen", mode.name()));
            }
            for l in &f.stats.per_light {
                if let (Some(s), Some(i)) = (l.shaded, l.ideal) {
                    if s < i {
                        failures.push(format!(
                            "{what} {name}/{}: light {} shaded {s} < ideal {i}",
                            mode.name(),
                            l.index
                        ));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_culling_mode_matches_fullscreen_within_the_path() {
    let mut cases = vec!["demo", "spot", "classify"];
    cases.extend(HARD_CASES.iter().filter(|c| **c != "overflow"));
    modes_match_fullscreen(&Settings::default(), &cases, "rgba16-float");
}

#[test]
fn every_culling_mode_matches_fullscreen_with_the_log_light_buffer() {
    let s = Settings { accumulation: AccumFormat::Rgba8Log, ..Settings::default() };
    modes_match_fullscreen(&s, &["demo", "spot", "inside", "near", "far"], "rgba8-log");
}

/// The encodings of the light buffer: seed 003's (8-bit linear, additive), seed 004's (log
/// Rgba8, multiplicative) and fp16 (additive), each channel, the mono specular in A included,
/// against the exact (Rgba32Float) buffer for the blends that wrote it (the start value and
/// one per light whose shape holds the pixel's point): the log buffer decoded within
/// `log_accum_error_bound`, the 8-bit linear one within `unorm_accum_error_bound` below its
/// saturation at 1, and the fp16 buffer within two fp16 roundings per light.
#[test]
fn every_light_buffer_encoding_holds_the_light() {
    let gpu = gpu();
    for name in ["classify", "spot", "coincident"] {
        let scene = scene(name);
        let exact_s = prepass(Settings { accumulation: AccumFormat::Rgba32Float, ..Settings::default() });
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &exact_s).unwrap();
        render_image(gpu, &mut r, &scene, &exact_s, W, H).unwrap();
        let exact = r.last_frame().read_light_buffer(gpu).unwrap();
        let lights = r.last_frame().light_records().to_vec();
        let touching: Vec<u32> = r
            .last_frame()
            .view_positions(gpu)
            .unwrap()
            .iter()
            .map(|p| {
                p.map_or(0, |p| {
                    lights.iter().filter(|l| lampshade::renderer::inspect::inside_light(l, p)).count() as u32
                })
            })
            .collect();
        assert!(exact.iter().skip(3).step_by(4).any(|a| *a > 0.0), "{name}: no mono specular anywhere");
        let encodings = [(AccumFormat::Rgba8Log, 4), (AccumFormat::Rgba8Unorm, 4), (AccumFormat::Rgba16Float, 8)];
        for (accumulation, bytes) in encodings {
            let s = prepass(Settings { accumulation, ..Settings::default() });
            let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
            let (_, stats) = render_image(gpu, &mut r, &scene, &s, W, H).unwrap();
            assert_eq!(stats.prepass.as_ref().unwrap().light_buffer_bytes_per_pixel, bytes);
            let got = r.last_frame().read_light_buffer(gpu).unwrap();
            let (mut checked, mut worst) = (0, 0f32);
            for (px, blends) in touching.iter().enumerate() {
                for c in 0..4 {
                    let (g, want) = (got[px * 4 + c], exact[px * 4 + c]);
                    assert!(g.is_finite(), "{name}: non-finite light");
                    let bound = if accumulation == AccumFormat::Rgba8Log {
                        let b = log_accum_error_bound(want, 1 + blends);
                        if want + b > LOG_ACCUM_MAX - 0.5 {
                            continue; // saturated: the top code spans most of a unit
                        }
                        b
                    } else if accumulation == AccumFormat::Rgba8Unorm {
                        let b = unorm_accum_error_bound(1 + blends);
                        if want + b >= 1.0 {
                            continue; // saturated at 1, as seed 002 warns
                        }
                        b
                    } else {
                        // Each light's value is rounded to fp16 as it is written and the sum
                        // again as it is blended: two roundings per light, each at most one ulp
                        // (2^-10 relative; Vulkan leaves fp16's rounding mode to the device,
                        // and lavapipe's truncation measured below on the HDR target).
                        want * 2.0 * *blends as f32 * 2f32.powi(-10) + 1e-6
                    };
                    checked += 1;
                    worst = worst.max((g - want).abs() / bound.max(1e-9));
                    assert!(
                        (g - want).abs() <= bound,
                        "{name} {accumulation:?} pixel {px} channel {c}: {g} vs exact {want} (bound {bound})"
                    );
                }
            }
            assert!(checked > 1000, "{name}: only {checked} values checked");
            println!("{name} {accumulation:?}: worst error / bound {worst:.3}");
        }
    }
}

/// The pre-pass against deferred shading on the hard cases, at sampled pixels, in linear light
/// before exposure: deferred with the `reference` layout and f32 accumulation (its G-buffer
/// stores the surface exactly), the pre-pass with an f32 light buffer, so what separates them is
/// the pre-pass's own approximation: the 8-bit normal, the 8-bit exponent and the mono
/// specular. `reference::prepass_enclosure` derives (from the deferred frame's exact surface)
/// the range the pre-pass's value must fall in; on top, the f32 arithmetic allowance of
/// `tests/it/hard_cases.rs` (1e-4 relative + 1e-4) and the HDR target's fp16 rounding (2^-10).
#[test]
fn difference_from_deferred_stays_within_the_derived_bound() {
    let gpu = gpu();
    let normal_error = LayoutChoice::Xyz8.layout().normal_error_bound();
    assert!((normal_error.to_degrees() - 0.3892).abs() < 1e-3, "xyz8's bound {}", normal_error.to_degrees());
    // log2(n) / 11 in 8 bits: half a step is 11 / 510 of log2(n).
    let exp_ratio = 2f64.powf(11.0 / 510.0);
    let (mut worst_diff, mut worst_width, mut worst_share) = (0f64, 0f64, 0f64);
    let mut worst_at = String::new();
    let mut failures = Vec::new();
    // The hard cases, and `demo` for the sun, which the light buffer carries as a light.
    for name in HARD_CASES.iter().chain(&["demo"]) {
        let scene = scene(name);
        let (w, h) = if *name == "overflow" { (96, 54) } else { (W, H) };
        let base = Settings { culling: CullingMode::Volume, light_cutoff: 0.0, ..unshadowed() };
        let deferred_s =
            Settings { layout: LayoutChoice::Reference, accumulation: AccumFormat::Rgba32Float, ..base.clone() };
        let mut deferred = Renderer::new(gpu, OUTPUT_FORMAT, &deferred_s).unwrap();
        render_image(gpu, &mut deferred, &scene, &deferred_s, w, h).unwrap();
        let clamp = lampshade::reference::Clamps::of(&deferred);
        let pre_s = prepass(Settings { accumulation: AccumFormat::Rgba32Float, ..base });
        let mut pre = Renderer::new(gpu, OUTPUT_FORMAT, &pre_s).unwrap();
        render_image(gpu, &mut pre, &scene, &pre_s, w, h).unwrap();
        let hdr = pre.last_frame().read_post_image(gpu, PostImage::Hdr).unwrap().expect("the pre-pass's HDR colour");
        let mut checked = 0;
        for k in 0..96u32 {
            let (x, y) = ((k * 37 + 5) % w, (k * 23 + 3) % h);
            let p = deferred.last_frame().probe(gpu, x, y).unwrap();
            if !p.valid {
                continue;
            }
            checked += 1;
            let (lo, hi) = lampshade::reference::prepass_enclosure(&scene, &p, &clamp, normal_error, exp_ratio);
            let i = ((y * w + x) * 4) as usize;
            for c in 0..3 {
                let (got, def) = (hdr[i + c] as f64, p.lit[c] as f64);
                // The HDR target's fp16 rounding: one ulp (2^-10 relative), not half: lavapipe
                // truncates (`overflow` (34,52): 42941.5 stored as 42912, not 42944).
                let allow = 1e-4 * got.abs().max(def.abs()) + 1e-4 + got.abs() * 2f64.powi(-10);
                if def < 65504.0 {
                    // (`overflow`'s deferred values above fp16's range are clamped by both
                    // paths' composes, not by the probe's `lit`.)
                    worst_diff = worst_diff.max((got - def).abs() / def.abs().max(1.0));
                }
                worst_width = worst_width.max(hi[c] - lo[c]);
                let outside = (lo[c] - got).max(got - hi[c]).max(0.0);
                if outside / allow > worst_share {
                    worst_share = outside / allow;
                    worst_at = format!("{name} ({x},{y})[{c}]: {got} in [{}, {}], deferred {def}", lo[c], hi[c]);
                }
                if outside > allow {
                    failures.push(format!(
                        "{name} ({x},{y})[{c}]: pre-pass {got:.6} outside [{:.6}, {:.6}] (deferred {def:.6})",
                        lo[c], hi[c]
                    ));
                }
            }
        }
        assert!(checked >= 10, "{name}: only {checked} sampled pixels hit geometry");
    }
    println!(
        "largest |pre-pass - deferred| / max(deferred, 1) {worst_diff:.4}, widest enclosure {worst_width:.4}, \
         worst excess / allowance {worst_share:.3} at {worst_at}"
    );
    assert!(failures.is_empty(), "{} pixels outside:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn refuses_what_it_cannot_draw_with_a_clear_error() {
    let gpu = gpu();
    let try_render = |scene: &lampshade::Scene, s: &Settings| -> anyhow::Result<()> {
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s)?;
        render_image(gpu, &mut r, scene, s, 64, 36).map(|_| ())
    };
    let demo = scene("demo");
    // Deferred cannot multisample (`Settings::validate`); the pre-pass can.
    let msaa = try_render(&demo, &Settings { msaa: Msaa::X4, ..Settings::default() }).unwrap_err();
    assert!(msaa.to_string().contains("cannot multisample"), "{msaa}");
    try_render(&demo, &prepass(Settings { msaa: Msaa::X4, ..Settings::default() })).unwrap();
    let rg11 =
        try_render(&demo, &prepass(Settings { accumulation: AccumFormat::Rg11b10Ufloat, ..Settings::default() }))
            .unwrap_err();
    assert!(rg11.to_string().contains("rg11b10"), "{rg11}");
    let albedo =
        try_render(&demo, &prepass(Settings { debug_view: DebugView::Albedo, ..Settings::default() })).unwrap_err();
    assert!(albedo.to_string().contains("albedo"), "{albedo}");
    // Toon: the `materials` scene's toon object, opaque or alpha-masked, is shaded forward
    // (seed 004; `materials::the_light_prepass_shades_toon_and_phong_forward_as_deferred_does`),
    // and forcing blinn-phong draws it in the buffer.
    let mut materials = scene("materials");
    try_render(&materials, &prepass(Settings::default())).unwrap();
    for m in materials.materials.iter_mut().filter(|m| m.brdf == lampshade::scene::Brdf::Toon) {
        m.alpha_mode = lampshade::scene::AlphaMode::Mask { cutoff: 0.5 };
    }
    try_render(&materials, &prepass(Settings::default())).unwrap();
    try_render(&materials, &prepass(Settings { brdf: BrdfOverride::BlinnPhong, ..Settings::default() })).unwrap();
    // The views the thin buffer does hold.
    for view in [DebugView::Normal, DebugView::DiffuseLight, DebugView::SpecularLight, DebugView::Depth] {
        try_render(&demo, &prepass(Settings { debug_view: view, ..Settings::default() })).unwrap();
    }
}

/// Pixels whose depth says a geometric edge passes through their 3x3 neighbourhood: a
/// neighbour with no surface where this pixel has one (or the reverse), or a kink in 1/z, which
/// is affine in screen space across a plane (so its second difference is zero up to depth
/// rounding, here 1e-4 relative) and is not across a silhouette, a crease or a curved surface.
fn edge_mask(points: &[Option<glam::Vec3>], w: u32, h: u32) -> Vec<bool> {
    let at = |x: i64, y: i64| -> Option<Option<f64>> {
        (x >= 0 && y >= 0 && x < w as i64 && y < h as i64)
            .then(|| points[(y * w as i64 + x) as usize].map(|p| -1.0 / p.z as f64))
    };
    let mut kink = vec![false; (w * h) as usize];
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let c = at(x, y).flatten();
            let mut edge = false;
            for (dx, dy) in [(1, 0), (0, 1), (1, 1), (1, -1)] {
                let (a, b) = (at(x - dx, y - dy), at(x + dx, y + dy));
                for n in [a, b].into_iter().flatten() {
                    edge |= n.is_some() != c.is_some();
                }
                if let (Some(Some(a)), Some(c), Some(Some(b))) = (a, c, b) {
                    edge |= (a - 2.0 * c + b).abs() > 1e-4 * c.abs();
                }
            }
            kink[(y * w as i64 + x) as usize] = edge;
        }
    }
    // Dilated by one pixel: a kink at a neighbour's centre can put an edge inside this pixel.
    let mut mask = kink.clone();
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let near = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx >= 0 && ny >= 0 && nx < w as i64 && ny < h as i64 && kink[(ny * w as i64 + nx) as usize]
                })
            });
            mask[(y * w as i64 + x) as usize] |= near;
        }
    }
    mask
}

/// `--msaa 4` multisamples pass 3 only: passes 1 and 2 (the normal buffer and the light buffer)
/// are the single-sample ones, and a pixel whose samples all see one surface is shaded once,
/// with the same inputs, as without MSAA. So MSAA may change only pixels an edge crosses: every
/// pixel that moved by more than one 8-bit step must lie in the depth edge mask (from the depth
/// at the frame's resolution and at twice it, for geometry thinner than a pixel). The room is
/// tested without its glass (blended surfaces write no depth) and without its alpha-masked
/// fence: a pixel whose centre lies just outside the fence quad but whose samples lie inside
/// is shaded at texture coordinates extrapolated past the quad's edge, which wrap to the
/// texture's far side, so MSAA grows a faint border of the far side's texels there, outside any
/// depth edge (non-centroid MSAA; centroid interpolation mis-selects mips: tried, 411 pixels
/// off the edges).

#[test]
fn msaa_changes_only_pixels_on_geometric_edges() {
    let gpu = gpu();
    let mut room = room();
    let skip: Vec<bool> = room
        .materials
        .iter()
        .map(|m| m.is_blended() || matches!(m.alpha_mode, lampshade::scene::AlphaMode::Mask { .. }))
        .collect();
    room.objects.retain(|o| !skip.get(o.material).copied().unwrap_or(false));
    let scenes =
        [("room", room), ("demo", scene("demo")), ("occluded", scene("occluded")), ("street", scene("street"))];
    for (name, scene) in &scenes {
        let one = prepass(Settings { count_ideal: false, ..Settings::default() });
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &one).unwrap();
        let (a, _) = render_image(gpu, &mut r, scene, &one, W, H).unwrap();
        let mut mask = edge_mask(&r.last_frame().view_positions(gpu).unwrap(), W, H);
        // Geometry thinner than a pixel can miss every pixel centre and still cover samples: the
        // depth at twice the resolution sees it too (a pixel is an edge where any of its four).
        let mut fine = Renderer::new(gpu, OUTPUT_FORMAT, &one).unwrap();
        render_image(gpu, &mut fine, scene, &one, 2 * W, 2 * H).unwrap();
        let fine_mask = edge_mask(&fine.last_frame().view_positions(gpu).unwrap(), 2 * W, 2 * H);
        for (i, m) in mask.iter_mut().enumerate() {
            let (x, y) = (i as u32 % W, i as u32 / W);
            *m |= (0..4).any(|k| fine_mask[((2 * y + k / 2) * 2 * W + 2 * x + k % 2) as usize]);
        }
        let four = Settings { msaa: Msaa::X4, ..one.clone() };
        let mut r4 = Renderer::new(gpu, OUTPUT_FORMAT, &four).unwrap();
        let (b, stats) = render_image(gpu, &mut r4, scene, &four, W, H).unwrap();
        assert_eq!(stats.prepass.as_ref().map(|p| p.samples), Some(4));
        let (mut changed, mut outside) = (0, Vec::new());
        for (i, (pa, pb)) in a.pixels().zip(b.pixels()).enumerate() {
            let step = (0..3).map(|c| pa[c].abs_diff(pb[c])).max().unwrap_or(0);
            if step > 1 {
                changed += 1;
                if !mask[i] {
                    outside.push(format!("({}, {}): {step} steps", i as u32 % W, i as u32 / W));
                }
            }
        }
        let share = mask.iter().filter(|m| **m).count() as f64 / mask.len() as f64;
        println!("{name}: {changed} pixels changed by MSAA, edge mask {:.1} % of the frame", share * 100.0);
        assert!(changed > 0, "{name}: MSAA changed nothing");
        assert!(share < 0.6, "{name}: the edge mask covers {:.0} % of the frame", share * 100.0);
        assert!(
            outside.is_empty(),
            "{name}: {} changed pixels off the edges: {:?}",
            outside.len(),
            &outside[..outside.len().min(12)]
        );
    }
}

/// `--msaa 4` primes pass 3's samples with a depth-only draw of pass 1's list (pass 1's depth
/// has one sample a pixel), so pass 3 tests less-equal without writing, as it does single-
/// sampled (seed 003: "the z-buffer is already in a primed state, reducing the number of
/// fragment shader executions to only the surfaces that have not been occluded"): each
/// sample's nearest surface is shaded once, whatever the draw order. Pass 1, which tests
/// against its own writes, shades more in material order than front to back on `demo`; pass
/// 3's samples are the same count in both orders, at most 4 a pixel, and the pictures agree.
#[test]
fn multisampled_pass_3_is_primed_and_shades_each_sample_once_in_any_draw_order() {
    use lampshade::renderer::DrawOrder;
    let demo = scene("demo");
    let base = prepass(Settings { msaa: Msaa::X4, count_ideal: false, ..Settings::default() });
    let material = render(&demo, &Settings { draw_order: DrawOrder::Material, ..base.clone() }, W, H);
    let nearest = render(&demo, &Settings { draw_order: DrawOrder::FrontToBack, ..base.clone() }, W, H);
    let (m, n) = (material.stats.prepass.clone().unwrap(), nearest.stats.prepass.clone().unwrap());
    let (m1, n1) = (m.base_fragments.unwrap(), n.base_fragments.unwrap());
    assert!(m1 > n1, "pass 1 shades {m1} fragments in material order and {n1} front to back: no overdraw to remove");
    let (m3, n3) = (m.final_fragments.unwrap(), n.final_fragments.unwrap());
    assert_eq!(m3, n3, "pass 3's samples depend on the draw order: the depth is not primed");
    assert!(m3 <= 4 * (W * H) as u64, "pass 3 shaded {m3} samples of {}", 4 * W * H);
    assert_eq!((m.prime_draw_calls, m.samples), (m.base_draw_calls, 4));
    let steps = max_channel_difference(&material.image, &nearest.image);
    assert!(steps <= 1, "the draw order changed the picture by {steps} steps");
    // Single-sampled, pass 3 tests pass 1's depth: no prime.
    let one = render(&demo, &Settings { msaa: Msaa::X1, ..base }, W, H);
    assert_eq!(one.stats.prepass.unwrap().prime_draw_calls, 0);
}

/// The pixel probe (the viewer's pixel panel) on a pre-pass frame: the light buffer decoded
/// (mono specular as grey) and pass 3's colour as `lit`; no read past the 1x1 stand-in target.
#[test]
fn the_probe_reads_the_pre_pass_buffers() {
    let gpu = gpu();
    let s = prepass(Settings::default());
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).unwrap();
    render_image(gpu, &mut r, &scene("demo"), &s, W, H).unwrap();
    let buffer = r.last_frame().read_light_buffer(gpu).unwrap();
    let hdr = r.last_frame().read_post_image(gpu, PostImage::Hdr).unwrap().unwrap();
    let mut lit = 0;
    for (x, y) in [(80, 60), (40, 70), (120, 80), (10, 85)] {
        let p = r.last_frame().probe(gpu, x, y).unwrap();
        let i = ((y * W + x) * 4) as usize;
        assert_eq!(p.diffuse_light.to_array(), [buffer[i], buffer[i + 1], buffer[i + 2]]);
        assert_eq!(p.specular_light.to_array(), [buffer[i + 3]; 3]);
        if p.valid {
            assert_eq!(p.lit.to_array(), [hdr[i], hdr[i + 1], hdr[i + 2]]);
            lit += usize::from(p.lit.max_element() > 0.0);
        }
    }
    assert!(lit > 0, "no probed pixel lit");
}
