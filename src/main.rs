use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use lampshade::renderer::{
    AccumFormat, CullingMode, DebugView, DepthFormat, LayoutChoice, Renderer, Settings, OUTPUT_FORMAT,
};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::Gpu;
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "lampshade", version, about = "A workbench for deferred shading with light-volume culling")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render one frame headless to a PNG.
    Render(RenderArgs),
    /// Open the viewer (the default command).
    #[cfg(feature = "viewer")]
    View(lampshade::app::ViewArgs),
    /// Sweep the knobs that trade speed for error; write CSV, markdown and a plot.
    Bench(BenchArgs),
    /// List the built-in scenes.
    Scenes,
    /// Regenerate the project's own glTF scene (assets/room) from code.
    MakeAssets {
        /// Output directory.
        #[arg(long, default_value = "assets/room")]
        out: PathBuf,
    },
}

#[derive(clap::Args)]
struct RenderArgs {
    /// Built-in scene name (see `lampshade scenes`) or a glTF file (.gltf, .glb); default
    /// `demo`, or the settings file's.
    scene: Option<String>,
    /// glTF without lights: point lights per side of the grid added over the scene (0: none).
    #[arg(long, default_value_t = 8)]
    light_grid: u32,
    /// Start from the file's viewpoint K (its cameras in order, then a framing view).
    #[arg(long)]
    viewpoint: Option<usize>,
    /// Output PNG.
    #[arg(long)]
    out: PathBuf,
    /// Image size, WxH (default 1280x720, or the settings file's).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    #[arg(long, value_enum)]
    culling: Option<CullingMode>,
    /// Number of point lights (demo).
    #[arg(long)]
    lights: Option<usize>,
    /// Animation time in seconds (default 0, or the settings file's).
    #[arg(long)]
    time: Option<f64>,
    #[arg(long, value_enum)]
    layout: Option<LayoutChoice>,
    #[arg(long, value_enum)]
    debug_view: Option<DebugView>,
    /// Light accumulation format.
    #[arg(long, value_enum)]
    accumulation: Option<AccumFormat>,
    /// Depth-stencil format.
    #[arg(long, value_enum)]
    depth_format: Option<DepthFormat>,
    /// Cut lights off where they fall below this fraction of their peak (0 ..< 1, 0 = exact).
    #[arg(long)]
    light_cutoff: Option<f32>,
    /// Subdivisions of the point lights' bounding icosphere (0 ..= 4).
    #[arg(long)]
    sphere_subdivisions: Option<u32>,
    /// Sides of the spot lights' bounding pyramid (3 ..= 64).
    #[arg(long)]
    cone_sides: Option<u32>,
    /// Restrict the stencil view to light K.
    #[arg(long)]
    light: Option<usize>,
    /// Count the ideal fragments too (a full-screen counting pass per light).
    #[arg(long)]
    ideal: bool,
    /// Write the frame's statistics as JSON.
    #[arg(long)]
    stats: Option<PathBuf>,
    /// Start from a settings file (as the viewer's F12 screenshots write: renderer settings plus
    /// scene, lights, time, camera and size); flags override it.
    #[arg(long)]
    settings: Option<PathBuf>,
}

#[derive(clap::Args)]
struct BenchArgs {
    #[arg(default_value = "demo")]
    scene: String,
    /// Output directory for bench.csv, bench.md and bench.png.
    #[arg(long)]
    out: PathBuf,
    /// A short sweep (small size, fewer lights and frames), about a minute.
    #[arg(long)]
    quick: bool,
    /// Frames timed per configuration.
    #[arg(long)]
    frames: Option<usize>,
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    #[arg(long)]
    lights: Option<usize>,
    /// Only these groups (comma-separated): culling, layout, accumulation, depth, cutoff,
    /// tessellation, resolution, lights.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
}

fn bench(args: BenchArgs) -> Result<()> {
    use lampshade::bench;
    let mut o = bench::BenchOptions::new(&args.scene, args.quick);
    if let Some(f) = args.frames {
        if f == 0 || f > 1000 {
            bail!("--frames {f} must be between 1 and 1000");
        }
        o.frames = f;
    }
    if let Some(s) = args.size {
        o.size = s;
    }
    if let Some(n) = args.lights {
        o.lights = n;
    }
    for g in &args.only {
        if !bench::GROUPS.contains(&g.as_str()) {
            bail!("--only {g}: groups are {}", bench::GROUPS.join(", "));
        }
    }
    o.groups = args.only.clone();
    builtin::build(&o.scene, BuiltinOptions::default()).map_err(anyhow::Error::msg)?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let gpu = Gpu::headless()?;
    let bar = indicatif::ProgressBar::new((bench::configs(&o).len() * 2 + o.frames.max(1)) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .map_err(|e| anyhow::anyhow!("{e}"))?,
    );
    let rows = bench::run(&gpu, &o, |done, total, label| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(label.to_string());
    })?;
    bar.finish_with_message("done");
    bench::write_csv(&rows, &args.out.join("bench.csv"))?;
    let md = bench::markdown(&rows, &gpu.info.name, &o);
    std::fs::write(args.out.join("bench.md"), &md)?;
    bench::plot(&rows, &args.out.join("bench.png"))?;
    println!("{md}");
    println!("wrote {}/bench.csv, bench.md, bench.png", args.out.display());
    Ok(())
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("size '{s}' is not WxH"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("width '{w}' is not a number"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("height '{h}' is not a number"))?;
    if w == 0 || h == 0 || w > 8192 || h > 8192 {
        return Err(format!("size {w}x{h} must be between 1x1 and 8192x8192"));
    }
    Ok((w, h))
}

fn render(args: RenderArgs) -> Result<()> {
    let (mut settings, keys) = match &args.settings {
        Some(path) => {
            let text = std::fs::read_to_string(path).with_context(|| format!("reading settings {}", path.display()))?;
            lampshade::settings_file::parse(&text).with_context(|| format!("parsing settings {}", path.display()))?
        }
        None => (Settings::default(), Default::default()),
    };
    let scene_name = args.scene.clone().or(keys.scene).unwrap_or_else(|| "demo".into());
    let time = args.time.or(keys.time).unwrap_or(0.0);
    let lights = args.lights.or(keys.lights);
    let (w, h) = match (args.size, keys.size) {
        (Some(s), _) => s,
        (None, Some([w, h])) => parse_size(&format!("{w}x{h}")).map_err(anyhow::Error::msg)?,
        (None, None) => (1280, 720),
    };
    if !time.is_finite() {
        bail!("time {time} must be finite");
    }
    if let Some(c) = args.culling {
        settings.culling = c;
    }
    if let Some(l) = args.layout {
        settings.layout = l;
    }
    if let Some(v) = args.debug_view {
        settings.debug_view = v;
    }
    if let Some(a) = args.accumulation {
        settings.accumulation = a;
    }
    if let Some(d) = args.depth_format {
        settings.depth_format = d;
    }
    if let Some(t) = args.light_cutoff {
        settings.light_cutoff = t;
    }
    if let Some(n) = args.sphere_subdivisions {
        settings.sphere_subdivisions = n;
    }
    if let Some(n) = args.cone_sides {
        settings.cone_sides = n;
    }
    if args.light.is_some() {
        settings.selected_light = args.light;
    }
    settings.count_ideal = args.ideal || args.stats.is_some();
    settings.validate().map_err(anyhow::Error::msg)?;
    let import = lampshade::scene::import::ImportOptions { light_grid: args.light_grid, ..Default::default() };
    let (mut scene, warnings) = open_scene(&scene_name, BuiltinOptions { lights, time }, &import)?;
    for w in &warnings {
        eprintln!("warning: {scene_name}: {w}");
    }
    if let Some(k) = args.viewpoint {
        let Some((_, camera)) = scene.viewpoints.get(k) else {
            bail!("--viewpoint {k}: '{scene_name}' offers {} viewpoint(s)", scene.viewpoints.len());
        };
        scene.camera = *camera;
    }
    if let Some(camera) = keys.camera {
        camera.validate().map_err(|e| anyhow::anyhow!("settings file camera: {e}"))?;
        scene.camera = camera;
    }
    if let Some(k) = settings.selected_light {
        if k >= scene.lights.len() {
            bail!("--light {k}: scene '{scene_name}' has {} lights", scene.lights.len());
        }
    }
    let gpu = Gpu::headless()?;
    let mut renderer = Renderer::new(&gpu, OUTPUT_FORMAT, &settings)?;
    let (image, stats) = lampshade::headless::render_image(&gpu, &mut renderer, &scene, &settings, w, h)?;
    image.save(&args.out).with_context(|| format!("writing {}", args.out.display()))?;
    println!(
        "{}: {} lights, {}, shaded {} fragments, ideal {}, gpu {} ms -> {}",
        scene_name,
        stats.lights,
        settings.culling.name(),
        stats.shaded_fragments.map_or("-".into(), |v| v.to_string()),
        stats.ideal_fragments.map_or("-".into(), |v| v.to_string()),
        stats.gpu_ms.total.map_or("-".into(), |v| format!("{v:.2}")),
        args.out.display()
    );
    if let Some(path) = &args.stats {
        let json = serde_json::json!({
            "adapter": { "name": gpu.info.name, "backend": format!("{:?}", gpu.info.backend) },
            "scene": scene_name,
            "time": time,
            "settings": settings,
            "stats": stats,
            "size": stats.size,
            "culling": stats.culling,
            "lights": stats.lights,
            "gpu_ms": stats.gpu_ms,
            "shaded_fragments": stats.shaded_fragments,
            "ideal_fragments": stats.ideal_fragments,
            "coverage_fragments": stats.coverage_fragments,
            "efficiency": stats.efficiency,
            "gbuffer_bytes_per_pixel": stats.gbuffer_bytes_per_pixel,
            "volume_meshes": stats.volume_meshes,
            "per_light": stats.per_light,
        });
        std::fs::write(path, serde_json::to_string_pretty(&json)?)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// Opens a built-in scene or a glTF file, showing the load's progress on a terminal.
fn open_scene(
    name: &str,
    builtin: BuiltinOptions,
    import: &lampshade::scene::import::ImportOptions,
) -> Result<(lampshade::Scene, Vec<String>)> {
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg:>10} [{bar:30}] {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let result = lampshade::scene::open(name, builtin, import, &mut |p| {
        bar.set_message(p.stage.to_string());
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
    });
    bar.finish_and_clear();
    result
}

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render(args),
        Some(Command::Bench(args)) => bench(args),
        Some(Command::MakeAssets { out }) => lampshade::scene::room::write(&out),
        Some(Command::Scenes) => {
            for (name, what) in builtin::NAMES {
                println!("{name:10} {what}");
            }
            Ok(())
        }
        #[cfg(feature = "viewer")]
        Some(Command::View(args)) => lampshade::app::run(args),
        #[cfg(feature = "viewer")]
        None => lampshade::app::run(Default::default()),
        #[cfg(not(feature = "viewer"))]
        None => Err(anyhow::anyhow!("built without the viewer; use `lampshade render`")),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
