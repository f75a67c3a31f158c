//! Every adapter users have: the capability table comes from the adapter's own report, a
//! masked table (the GL profile) makes each affected choice take its other way or be refused
//! with the capability named, no choice panics, a wgpu error is the frame's error, and wgpu's
//! real GL backend (Mesa's llvmpipe through EGL) renders every culling mode and path to its
//! own full-screen picture.

use crate::common::*;
use lampshade::compare::{flip, max_channel_difference};
use lampshade::gpu::{AdapterChoice, Backend};
use lampshade::headless::render_image;
use lampshade::renderer::kit::adapter::{Occlusion, Profile, FORMATS};
use lampshade::renderer::{support, CullingMode, RenderPath, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::{Gpu, Scene};
use std::sync::OnceLock;

const W: u32 = 160;
const H: u32 = 90;

/// The test adapter masked to wgpu's GL backend's table.
fn gl_profile() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| {
        Gpu::open(&AdapterChoice { restrict: Some(Profile::Gl), ..Default::default() }).expect("the masked adapter")
    })
}

/// wgpu's GL backend (Mesa's EGL and llvmpipe: `.ci/run` installs them).
fn gl() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| {
        Gpu::open(&AdapterChoice { backend: Some(Backend::Gl), ..Default::default() })
            .expect("wgpu's GL backend (apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri)")
    })
}

fn demo(lights: usize) -> Scene {
    let mut s = scene("demo");
    s.lights_mut().truncate(lights);
    s
}

fn draw(gpu: &Gpu, scene: &Scene, settings: &Settings) -> anyhow::Result<(image::RgbaImage, lampshade::FrameStats)> {
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, settings)?;
    render_image(gpu, &mut r, scene, settings, W, H)
}

#[test]
fn the_capability_table_is_read_from_the_adapters_report() {
    for gpu in [gpu(), gl()] {
        let caps = &gpu.caps;
        assert_eq!(caps.adapter.name, gpu.info.name);
        assert_eq!(caps.features, gpu.features);
        assert_eq!(caps.downlevel, gpu.adapter.get_downlevel_capabilities().flags);
        assert_eq!(caps.limits.max_color_attachments, gpu.device.limits().max_color_attachments);
        for &f in FORMATS {
            let report = gpu.adapter.get_texture_format_features(f);
            let said = report.allowed_usages.contains(wgpu::TextureUsages::RENDER_ATTACHMENT);
            // Rendering needs what the format needs enabled on the device too.
            let needs = f.required_features()
                | if f == wgpu::TextureFormat::Rg11b10Ufloat {
                    wgpu::Features::RG11B10UFLOAT_RENDERABLE
                } else {
                    wgpu::Features::empty()
                };
            assert_eq!(caps.renderable(f), said && gpu.features.contains(needs), "{:?} on {}", f, caps.adapter);
        }
        let rows = caps.rows();
        let row = |name: &str| rows.iter().find(|r| r.name == name).map(|r| r.has);
        assert_eq!(row("timestamp queries"), Some(gpu.has(wgpu::Features::TIMESTAMP_QUERY)));
        assert_eq!(
            row("cube-array textures"),
            Some(caps.downlevel.contains(wgpu::DownlevelFlags::CUBE_ARRAY_TEXTURES))
        );
    }
    // What the two backends of the same driver report differently.
    let (vk, gl) = (&gpu().caps, &gl().caps);
    assert_eq!((vk.adapter.backend.as_str(), gl.adapter.backend.as_str()), ("vulkan", "gl"));
    assert!(vk.renderable(wgpu::TextureFormat::R32Float) && !gl.renderable(wgpu::TextureFormat::R32Float));
    assert_eq!((vk.occlusion, gl.occlusion), (Occlusion::Exact, Occlusion::Binary));
    // On Mesa's llvmpipe under both: gallivm's loop limit holds under either; the debug-group
    // crash is lavapipe's (Vulkan) alone. The cube guess is GL's on any driver.
    if vk.adapter.name.starts_with("llvmpipe") {
        assert!(vk.quirks.loop_limit.is_some() && gl.quirks.loop_limit.is_some());
        assert!(vk.quirks.no_encoder_debug_groups && !gl.quirks.no_encoder_debug_groups);
    }
    assert!(!vk.quirks.cube_guess_by_layers && gl.quirks.cube_guess_by_layers);
}

/// Under the GL profile the default frame takes the R32Uint depth copy (exact: the same pixels
/// as the unmasked adapter's frame), counts nothing it cannot count, and the choices the
/// profile cannot give are refused naming the adapter and the capability, at `Renderer::new`
/// and at a frame asking for them later, as `support` predicts.
#[test]
fn the_gl_profile_takes_each_fallback_or_refuses_with_the_named_capability() {
    let scene = demo(200);
    let s = Settings { count_fragments: true, ..unshadowed() };
    let (masked, stats) = draw(gl_profile(), &scene, &s).expect("the default frame under the GL profile");
    let (full, full_stats) = draw(gpu(), &scene, &s).expect("the default frame");
    assert!(lit_share(&masked) > 0.2, "the masked frame is mostly black");
    assert_eq!(max_channel_difference(&masked, &full), 0, "the R32Uint depth copy is not exact");
    assert!(stats.adapter.fallbacks.iter().any(|f| f.contains("R32Uint")), "{:?}", stats.adapter.fallbacks);
    assert!(full_stats.adapter.fallbacks.is_empty(), "{:?}", full_stats.adapter.fallbacks);
    assert_eq!(stats.adapter.profile, Some(Profile::Gl));
    assert!(stats.shaded_fragments.is_none() && full_stats.shaded_fragments.is_some());
    assert_eq!(stats.adapter.capabilities.get("exact occlusion queries"), Some(&false));

    let caps = &gl_profile().caps;
    let mut ok = Renderer::new(gl_profile(), OUTPUT_FORMAT, &s).expect("renderer");
    for (knob, value, lacks) in [
        ("layout", "reference", "Rgba32Float render targets"),
        ("accumulation", "rgba32-float", "Rgba32Float"),
        ("accumulation", "rg11b10-ufloat", "Rg11b10Ufloat"),
    ] {
        let mut asked = s.clone();
        asked.set(knob, value).expect("a valid setting");
        let why = support(caps, &asked).expect_err("refused by the table").to_string();
        assert!(why.contains(lacks) && why.contains(&caps.adapter.name) && why.contains("Gl profile"), "{why}");
        let at_new = Renderer::new(gl_profile(), OUTPUT_FORMAT, &asked).err().expect("refused at new").to_string();
        assert_eq!(at_new, why);
        let out = lampshade::headless::Offscreen::new(gl_profile(), W, H);
        let at_frame = ok.render(&scene, &asked, &out.view, W, H).expect_err("refused at a frame").to_string();
        assert_eq!(at_frame, why);
        // The unmasked adapter gives it.
        assert!(support(&gpu().caps, &asked).is_ok(), "{knob} {value}");
    }
    // The renderer refused without breaking: the next frame draws.
    let out = lampshade::headless::Offscreen::new(gl_profile(), W, H);
    ok.render(&scene, &s, &out.view, W, H).expect("a frame after the refusals");
    assert_eq!(max_channel_difference(&out.read(gl_profile()).expect("readback"), &full), 0);
    // The pixel probe reads the R32Uint depth copy as the depth the R32Float one holds.
    let mut unmasked = Renderer::new(gpu(), OUTPUT_FORMAT, &s).expect("renderer");
    let out_full = lampshade::headless::Offscreen::new(gpu(), W, H);
    unmasked.render(&scene, &s, &out_full.view, W, H).expect("frame");
    for (x, y) in [(W / 2, H / 2), (W / 4, H - 4), (3, 3)] {
        let (a, b) = (
            ok.last_frame().probe(gl_profile(), x, y).expect("probe"),
            unmasked.last_frame().probe(gpu(), x, y).expect("probe"),
        );
        assert_eq!((a.valid, a.position), (b.valid, b.position), "pixel {x},{y}");
    }

    // Every value of every choice knob is answered without a panic; those refused are exactly
    // the ones the table rules out.
    let choices = lampshade::renderer::support::choices(caps);
    let refused: Vec<String> =
        choices.iter().filter(|c| c.outcome.is_err()).map(|c| format!("{} {}", c.knob, c.value)).collect();
    assert_eq!(refused, ["layout reference", "accumulation rgba32-float", "accumulation rg11b10-ufloat"]);
    assert!(lampshade::renderer::support::choices(&gpu().caps).iter().all(|c| c.outcome.is_ok()));
}

/// The post chain in Rgba16Float where Rgba32Float is not renderable: within one 8-bit step of
/// the f32 chain (`post::post_format` derives the bound for the ACES curve; auto-exposure is off:
/// its histogram bins are not part of that bound, nor are the effects after tone mapping).
#[test]
fn the_gl_profiles_half_float_post_chain_is_within_one_step() {
    let scene = demo(200);
    let s = Settings { bloom: true, ..unshadowed() };
    let (masked, stats) = draw(gl_profile(), &scene, &s).expect("the post chain under the GL profile");
    let (full, _) = draw(gpu(), &scene, &s).expect("the post chain");
    assert!(stats.adapter.fallbacks.iter().any(|f| f.contains("post chain runs in Rgba16Float")));
    let step = max_channel_difference(&masked, &full);
    assert!(step <= 1, "the half-float chain is {step} steps from the f32 chain");
}

/// A validation error is an error, never a panic: one the frame makes is the frame's error (and
/// the next frame draws), one made outside any frame is kept for the caller and not blamed on
/// the next frame.
#[test]
fn a_wgpu_validation_error_becomes_an_error_where_it_was_made() {
    let gpu = Gpu::headless().expect("a device of its own");
    let scene = demo(16);
    let s = unshadowed();
    let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &s).expect("renderer");
    let out = lampshade::headless::Offscreen::new(&gpu, W, H);
    r.render(&scene, &s, &out.view, W, H).expect("a first frame");
    // Outside a frame: MAP_READ with STORAGE is invalid without MAPPABLE_PRIMARY_BUFFERS.
    let _bad = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("invalid on purpose"),
        size: 256,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    r.render(&scene, &s, &out.view, W, H).expect("a frame is not blamed for an error made outside it");
    let e = gpu.errors.check().expect_err("the error outside the frame is kept").to_string();
    assert!(e.starts_with("wgpu error: validation error") && e.contains("invalid on purpose"), "{e}");
    assert!(gpu.errors.check().is_ok(), "an error is reported once");
    // Inside a frame: a target of another format than the pipelines were built for.
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
    let wrong =
        lampshade::renderer::kit::texture(&gpu.device, "wrong", wgpu::TextureFormat::Rgba16Float, (W, H), usage);
    let view = wrong.create_view(&Default::default());
    let e = r.render(&scene, &s, &view, W, H).expect_err("the frame reports its error").to_string();
    assert!(e.starts_with("wgpu error: validation error"), "{e}");
    assert!(gpu.errors.check().is_ok(), "the frame's error is its own, not left for the caller");
    r.render(&scene, &s, &out.view, W, H).expect("the next frame draws");
}

/// A pipeline compiles on its first draw (`kit::OnFirstUse`). A compile that fails is the error
/// of the call that drew with it first (`renderer::scoped`, as every drawing call of the
/// renderer runs), not a panic and not left in the device's error sink, and each later draw with
/// it fails the same way.
#[test]
fn a_pipeline_that_fails_to_compile_on_first_draw_is_that_calls_error() {
    let gpu = Gpu::headless().expect("a device of its own");
    let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("one entry point"),
        source: wgpu::ShaderSource::Wgsl("@compute @workgroup_size(1) fn present() {}".into()),
    });
    let pipe = lampshade::renderer::kit::compute_pipe(&gpu.device, "names a missing entry", None, &module, "absent");
    let draw = || -> anyhow::Result<()> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipe);
            pass.dispatch_workgroups(1, 1, 1);
        }
        gpu.queue.submit([encoder.finish()]);
        Ok(())
    };
    assert!(gpu.errors.check().is_ok(), "nothing compiled before the first draw");
    let e = lampshade::renderer::scoped(&gpu.device, draw).expect_err("the first draw's error").to_string();
    assert!(e.starts_with("wgpu error:") && e.contains("absent"), "{e}");
    assert!(gpu.errors.check().is_ok(), "the compile's error is the call's, not left for the caller");
    lampshade::renderer::scoped(&gpu.device, draw).expect_err("the invalid pipeline stays invalid");
    assert!(gpu.errors.check().is_ok());
}

/// wgpu's GL backend renders the default frame, and under every path every culling mode (tiled
/// under the deferred path only, below) to that path's own full-screen picture, within
/// culling's one step as on Vulkan (tests/it/culling.rs, tests/it/paths.rs).
#[test]
fn the_gl_backend_renders_every_mode_to_its_full_screen_picture() {
    let scene = demo(64);
    let (default, stats) = draw(gl(), &scene, &Settings::default()).expect("GL, the default frame");
    assert!(lit_share(&default) > 0.2, "GL's default frame is mostly black");
    assert_eq!(stats.adapter.adapter.backend, "gl");
    let paths = [RenderPath::Deferred, RenderPath::LightPrepass, RenderPath::Forward, RenderPath::ForwardMultipass];
    for path in paths {
        let base = Settings { path, ..unshadowed() };
        let full = Settings { culling: CullingMode::Fullscreen, ..base.clone() };
        let (reference, _) = draw(gl(), &scene, &full).unwrap_or_else(|e| panic!("GL {}: {e:#}", path.name()));
        assert!(lit_share(&reference) > 0.2, "GL {}: the reference frame is mostly black", path.name());
        // Tiled shading's pipelines take Mesa's GL 32 s each to compile with a cold shader cache
        // (as on CI): the deferred path's covers their translation to GLSL.
        let modes = CullingMode::ALL.into_iter().skip(1);
        for culling in modes.filter(|&m| m != CullingMode::Tiled || path == RenderPath::Deferred) {
            let what = format!("GL {} {}", path.name(), culling.name());
            let (img, _) =
                draw(gl(), &scene, &Settings { culling, ..base.clone() }).unwrap_or_else(|e| panic!("{what}: {e:#}"));
            let step = max_channel_difference(&reference, &img);
            let (fl, _) = flip(&reference, &img).expect("flip");
            assert!(step <= 1 && fl.mean <= 0.001, "{what}: {step} steps from fullscreen, FLIP mean {}", fl.mean);
        }
    }
}

/// Depth peeling on wgpu's GL backend (whose GLSL cannot load from a depth texture, so the
/// layers read depth as unfilterable float textures): the crossed panes match the CPU
/// per-pixel depth sort within the fp16 rounding, as on Vulkan.
#[test]
fn the_gl_backend_peels_blended_surfaces_in_depth_order() {
    crate::presets::check_peeling(gl(), "GL deferred", &Settings::default());
}
