//! The pass contract (`inputs::pass::Pass`): every pass of the frame declares the pipelines its
//! recording draws with, the frame builds them before it records, and a configuration's whole
//! set can be built ahead of its first frame (`Renderer::build_pipelines`), on any thread.
//! Each test runs on a device of its own, so no other test's frames have built its pipelines.

use crate::common::*;
use lampshade::headless::render_image;
use lampshade::renderer::{CullingMode, DebugView, Msaa, RenderPath, Renderer, Settings, ShadowMode, OUTPUT_FORMAT};
use lampshade::{Gpu, Scene};

/// Configurations that between them draw with every pass: each path, each culling mode, the
/// debug views with passes of their own, blended surfaces, the post chain, shadows, MSAA and the
/// ledger's counting.
fn configurations() -> Vec<(&'static str, Scene, Settings)> {
    let base = Settings { count_ideal: false, ..Settings::default() };
    let mut v = Vec::new();
    for culling in [
        CullingMode::StencilTwoPass,
        CullingMode::StencilInvert,
        CullingMode::StencilReplace,
        CullingMode::Volume,
        CullingMode::Fullscreen,
        CullingMode::Tiled,
        CullingMode::Clustered,
        CullingMode::Zbin,
        CullingMode::Auto,
    ] {
        v.push(("demo", scene("demo"), Settings { culling, ..base.clone() }));
    }
    for path in [RenderPath::LightPrepass, RenderPath::Forward, RenderPath::ForwardMultipass] {
        v.push(("demo", scene("demo"), Settings { path, ..base.clone() }));
        v.push(("glass", scene("glass"), Settings { path, msaa: Msaa::X4, ..base.clone() }));
    }
    for debug_view in [DebugView::Stencil, DebugView::Complexity, DebugView::TileLights, DebugView::Waste] {
        v.push(("demo", scene("demo"), Settings { debug_view, ..base.clone() }));
    }
    v.push(("glass", scene("glass"), Settings { bloom: true, vignette: 0.5, fog: true, ..base.clone() }));
    v.push(("street", scene("street"), Settings { shadows: ShadowMode::All, ..base.clone() }));
    v.push(("demo", scene("demo"), Settings { count_fragments: true, count_ideal: true, ..base.clone() }));
    v
}

#[test]
fn a_configurations_declared_pipelines_built_ahead_leave_its_first_frame_nothing_to_compile() {
    let gpu = Gpu::headless().expect("a second device on the adapter");
    // Each configuration is drawn once: its pass set need not outlive its renderer.
    gpu.passes.keep_bytes_at_most(1);
    for (name, scene, settings) in configurations() {
        let what = format!(
            "{name}, {} path, {}, {} view",
            settings.path.name(),
            settings.culling.name(),
            settings.debug_view.name()
        );
        let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &settings).expect("renderer");
        let (declared, _built) = r.build_pipelines(&scene, &settings, (96, 54)).expect("build the declared pipelines");
        assert!(declared > 0, "{what}: nothing declared");
        let (_, stats) = render_image(&gpu, &mut r, &scene, &settings, 96, 54).expect("render");
        let p = stats.pipelines;
        assert_eq!(p.declared, declared, "{what}: the frame declared another set than was built ahead");
        assert_eq!((p.built, p.while_recording), (0, 0), "{what}: the first frame compiled pipelines");
    }
}

#[test]
fn the_declared_set_builds_on_another_thread_and_is_what_the_frame_draws() {
    let gpu = Gpu::headless().expect("a second device on the adapter");
    let (scene, settings) =
        (scene("demo"), Settings { culling: CullingMode::Tiled, count_ideal: false, ..Settings::default() });
    let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &settings).expect("renderer");
    // Declared and built on a worker; the frame on this thread then compiles nothing.
    let (declared, built) = std::thread::scope(|s| {
        s.spawn(|| r.build_pipelines(&scene, &settings, (96, 54)).expect("build")).join().expect("the worker")
    });
    assert_eq!(built, declared, "a fresh device had none of them built");
    let (_, stats) = render_image(&gpu, &mut r, &scene, &settings, 96, 54).expect("render");
    assert_eq!((stats.pipelines.built, stats.pipelines.while_recording), (0, 0));
}

/// The viewer's pipeline cache (`pipeline_cache`): a damaged file is no error (wgpu starts an
/// empty cache from it), a frame draws with its pipelines made through the cache, and what is
/// saved is what the next run reads. On lavapipe the cache's data is wgpu's and Vulkan's
/// headers alone (docs/measurements.md), so this holds the file's round trip, not its use.
#[test]
fn a_damaged_pipeline_cache_file_starts_empty_and_a_saved_one_reads_back() {
    let gpu = Gpu::headless().expect("a second device on the adapter");
    if !gpu.has(wgpu::Features::PIPELINE_CACHE) {
        eprintln!("SKIPPED: {} has no pipeline cache", gpu.info.name);
        return;
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("pipeline-cache");
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join("pipelines.bin");
    let damaged = b"not a pipeline cache".to_vec();
    std::fs::write(&path, &damaged).expect("writing the damaged file");
    let read = lampshade::pipeline_cache::load_from(&gpu, &path).expect("a damaged file is no error");
    assert_eq!(read, Some(damaged.len()));
    assert!(gpu.passes.pipeline_cache().is_some(), "no cache held for the device");
    let (scene, settings) = (scene("demo"), Settings { count_ideal: false, ..Settings::default() });
    let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &settings).expect("renderer");
    let (img, _) = render_image(&gpu, &mut r, &scene, &settings, 96, 54).expect("a frame through the cache");
    assert!(img.pixels().any(|p| p[0] > 0), "the frame drawn through the cache is black");
    let written = lampshade::pipeline_cache::save_to(&gpu, &path).expect("saving").expect("a cache to save");
    let file = std::fs::read(&path).expect("reading the saved file");
    assert_eq!(file.len(), written);
    assert_ne!(file, damaged, "the damaged file was kept");
    assert_eq!(lampshade::pipeline_cache::load_from(&gpu, &path).expect("reading it back"), Some(written));
}
