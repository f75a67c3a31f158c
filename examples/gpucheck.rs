//! The correctness half of `scripts/gpu-check.sh`, for an adapter the suite never runs on (a
//! real GPU): renders every stored reference configuration (`screenshots/reference/`, the
//! cases of `tests/it/images.rs` and the room of `tests/it/gltf.rs`) and compares each with
//! lavapipe's reference under the cross-CPU tolerance (`lampshade::compare::CROSS_CPU`); then
//! renders every culling mode on the culling tests' scenes and compares each with
//! `fullscreen` on the same adapter, which the suite holds to one 8-bit step on lavapipe.
//!
//! `cargo run --release --example gpucheck -- [--adapter NAME] [--backend B] [--out DIR] [--root REPO]`
//!
//! Prints one line per comparison and a last line `gpucheck: N of M within bounds`; exits 1
//! when a comparison is outside its bound, 2 when the adapter or a file cannot be opened.

use anyhow::{Context, Result};
use clap::Parser;
use lampshade::compare::{check_snapshot, flip, max_channel_difference, noise_flip, CROSS_CPU};
use lampshade::gpu::{AdapterChoice, Gpu};
use lampshade::headless::render_image;
use lampshade::renderer::{CullingMode, DebugView, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::Scene;
use std::path::{Path, PathBuf};

#[derive(Parser)]
struct Args {
    /// The adapter: a part of its name or its index in `lampshade adapters` (default: the
    /// high-performance adapter).
    #[arg(long)]
    adapter: Option<String>,
    /// Only this backend (vulkan, gl, metal, dx12).
    #[arg(long, value_enum)]
    backend: Option<lampshade::gpu::Backend>,
    /// Where the rendered images go (and, for a failed reference, its difference image).
    #[arg(long, default_value = "target/gpucheck")]
    out: PathBuf,
    /// The repository root, where `screenshots/reference/` and `assets/room/` are.
    #[arg(long, default_value = ".")]
    root: PathBuf,
}

/// What one comparison gave, and whether it is inside its bound.
struct Line {
    text: String,
    ok: bool,
}

struct Frame {
    image: image::RgbaImage,
    non_finite: usize,
}

fn render(gpu: &Gpu, scene: &Scene, settings: &Settings, w: u32, h: u32) -> Result<Frame> {
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, settings)?;
    let (image, _) = render_image(gpu, &mut r, scene, settings, w, h)?;
    let (d, s) = r.last_frame().read_accumulation(gpu)?;
    let non_finite = d.iter().chain(s.iter()).filter(|v| !v.is_finite()).count();
    Ok(Frame { image, non_finite })
}

fn builtin_scene(name: &str) -> Result<Scene> {
    builtin::build(name, BuiltinOptions::default()).map_err(|e| anyhow::anyhow!("built-in scene {name}: {e}"))
}

/// Against lavapipe's stored references, under the bound the image tests use.
fn references(gpu: &Gpu, root: &Path, out: &Path) -> Result<Vec<Line>> {
    let room = lampshade::scene::import::load(&root.join("assets/room/room.gltf"), &Default::default(), &mut |_| {})?;
    let cases: Vec<(&str, Scene, DebugView, u32, u32)> = vec![
        ("demo", builtin_scene("demo")?, DebugView::Lit, 256, 144),
        ("spot", builtin_scene("spot")?, DebugView::Lit, 256, 144),
        ("classify-stencil", builtin_scene("classify")?, DebugView::Stencil, 256, 144),
        ("demo-normals", builtin_scene("demo")?, DebugView::Normal, 256, 144),
        ("room", room.scene, DebugView::Lit, 160, 90),
    ];
    let refs = root.join("screenshots/reference");
    let mut lines = Vec::new();
    for (name, scene, view, w, h) in cases {
        let settings = Settings { debug_view: view, ..Settings::default() };
        let f = render(gpu, &scene, &settings, w, h)?;
        f.image.save(out.join(format!("{name}.png")))?;
        let reference =
            image::open(refs.join(format!("{name}.png"))).with_context(|| format!("reference {name}.png"))?.to_rgba8();
        let steps = max_channel_difference(&reference, &f.image);
        let over = reference
            .pixels()
            .zip(f.image.pixels())
            .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > CROSS_CPU.steps))
            .count();
        let (fl, _) = flip(&reference, &f.image)?;
        let bound = noise_flip(&reference, CROSS_CPU.steps)?;
        let verdict = check_snapshot(&refs, out, name, &f.image, CROSS_CPU);
        let ok = verdict.is_ok() && f.non_finite == 0;
        lines.push(Line {
            text: format!(
                "reference {name:>16} {w}x{h}: largest step {steps}, {:.2}% of pixels over {} steps, FLIP mean \
                 {:.5} (bound {bound:.5}), {} non-finite: {}",
                100.0 * over as f64 / (w * h) as f64,
                CROSS_CPU.steps,
                fl.mean,
                f.non_finite,
                match &verdict {
                    Ok(_) => "within the cross-CPU tolerance".to_string(),
                    Err(e) => format!("OUTSIDE ({e:#})"),
                }
            ),
            ok,
        });
    }
    Ok(lines)
}

/// Every culling mode against `fullscreen` on this adapter: the culling tests' bound, one step.
fn modes(gpu: &Gpu, out: &Path) -> Result<Vec<Line>> {
    let (w, h) = (256, 144);
    let mut lines = Vec::new();
    for name in ["demo", "spot", "inside", "near", "far", "occluded", "street", "tiny-radius", "spot-extremes"] {
        let scene = builtin_scene(name)?;
        let full = render(gpu, &scene, &Settings { culling: CullingMode::Fullscreen, ..Settings::default() }, w, h)?;
        full.image.save(out.join(format!("modes-{name}-fullscreen.png")))?;
        for mode in CullingMode::ALL.into_iter().filter(|m| *m != CullingMode::Fullscreen) {
            let f = render(gpu, &scene, &Settings { culling: mode, ..Settings::default() }, w, h)?;
            let steps = max_channel_difference(&full.image, &f.image);
            let over = full
                .image
                .pixels()
                .zip(f.image.pixels())
                .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 1))
                .count();
            let ok = steps <= 1 && f.non_finite == 0;
            if !ok {
                f.image.save(out.join(format!("modes-{name}-{}.png", mode.name())))?;
            }
            lines.push(Line {
                text: format!(
                    "modes {name:>14} {:>16}: largest step against fullscreen {steps}, {over} pixels over 1 step, {} \
                     non-finite{}",
                    mode.name(),
                    f.non_finite,
                    if ok { "" } else { ": OUTSIDE (one step)" }
                ),
                ok,
            });
        }
    }
    Ok(lines)
}

fn run(args: &Args) -> Result<bool> {
    let root = args.root.as_path();
    std::fs::create_dir_all(&args.out)?;
    let choice = AdapterChoice { adapter: args.adapter.clone(), backend: args.backend, restrict: None };
    let gpu = Gpu::open(&choice)?;
    let info = gpu.adapter.get_info();
    println!(
        "gpucheck: adapter {} ({:?}, {:?}; driver {} {})",
        info.name, info.backend, info.device_type, info.driver, info.driver_info
    );
    let mut lines = references(&gpu, root, &args.out)?;
    lines.extend(modes(&gpu, &args.out)?);
    for l in &lines {
        println!("{}", l.text);
    }
    let ok = lines.iter().filter(|l| l.ok).count();
    println!("gpucheck: {ok} of {} within bounds", lines.len());
    Ok(ok == lines.len())
}

fn main() {
    let args = Args::parse();
    match run(&args) {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("gpucheck: {e:#}");
            std::process::exit(2);
        }
    }
}
