//! `lampshade`: the commands. Their arguments are declared in `lampshade::cli`.

use anyhow::{bail, Context, Result};
use clap::Parser;
use lampshade::cli::{image_size, AdaptersArgs, BenchArgs, CheckArgs, Cli, Command, RenderArgs};
use lampshade::renderer::{Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::settings_file::SceneKeys;
use lampshade::{Gpu, Scene};

fn bench(args: BenchArgs) -> Result<()> {
    use lampshade::bench;
    if args.camera_path.is_some() {
        return bench_path(args);
    }
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
    // The scene is opened once here, so that a bad name or file fails before the sweep starts,
    // its warnings are shown once, and a scene with its own lights keeps them.
    let requested = lampshade::cli::requested_lights(args.lights, args.light_grid);
    let is_file = lampshade::scene::import::is_gltf_path(&args.scene);
    if is_file {
        o.lights = lampshade::scene::import::DEFAULT_ADDED_LIGHTS;
    }
    if let Some(n) = requested {
        o.lights = n;
    }
    let (scene, warnings) =
        open_scene(&args.scene, BuiltinOptions { lights: requested, time: 0.0 }, &Default::default())?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scene);
    }
    o.fixed_lights = if is_file {
        // Lights were added only if the file has none: then there are exactly `o.lights` point
        // lights and the fill sun (a file's own sun would have kept them out).
        !(scene.lights.len() == o.lights && scene.sun == Some(lampshade::scene::Sun::fill_sun()))
    } else {
        !builtin::TAKES_LIGHT_COUNT.contains(&args.scene.as_str())
    };
    if o.fixed_lights {
        eprintln!(
            "note: {} brings its own {} light(s): the bench does not vary the light count",
            args.scene,
            scene.lights.len()
        );
    }
    for g in &args.only {
        let apart = [bench::LEDGER_GROUP, bench::GBUFFER_GROUP, bench::RESTIR_GROUP];
        if !bench::GROUPS.contains(&g.as_str()) && !apart.contains(&g.as_str()) {
            bail!("--only {g}: groups are {}, {}", bench::GROUPS.join(", "), apart.join(", "));
        }
    }
    if args.only.iter().any(|g| g == bench::RESTIR_GROUP) {
        if args.only.len() > 1 {
            bail!("--only {}: the equal-time replays run alone", bench::RESTIR_GROUP);
        }
        return bench_restir(&args);
    }
    o.groups = args.only.clone();
    if let Some(&bad) = args.counts.iter().find(|&&n| n == 0 || n > lampshade::scene::builtin::MAX_LIGHTS) {
        bail!("--counts {bad}: light counts run from 1 to {}", lampshade::scene::builtin::MAX_LIGHTS);
    }
    o.counts = args.counts.clone();
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let gpu = Gpu::open(&args.adapter.choice())?;
    o.costs = lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?;
    eprintln!("calibration: {}", o.costs.describe());
    let bar = indicatif::ProgressBar::new((bench::configs(&o).len() * 2 + o.frames.max(1)) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .map_err(|e| anyhow::anyhow!("{e}"))?,
    );
    let run = bench::run(&gpu, &o, |done, total, label| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(label.to_string());
    })?;
    bar.finish_with_message("done");
    gpu.errors.check()?;
    for k in &run.skipped {
        eprintln!("skipped {} `{}` on {}: {}", k.group, k.label, k.scene, k.reason);
    }
    let rows = &run.rows;
    bench::write_csv(rows, &args.out.join("bench.csv"))?;
    let md = bench::markdown(&run, &gpu.info.name, &o);
    std::fs::write(args.out.join("bench.md"), &md)?;
    bench::plot(rows, &args.out.join("bench.png"))?;
    let paths = rows.iter().any(|r| r.group == "path");
    if paths {
        bench::plot_paths(rows, &args.out.join("paths.png"))?;
    }
    let scaling = rows.iter().any(|r| r.group == "lights" || r.group == "radius");
    if scaling {
        bench::plot_scaling(rows, &args.out.join("scaling.png"))?;
    }
    let stochastic = rows.iter().any(|r| r.group == bench::STOCHASTIC_GROUP);
    if stochastic {
        std::fs::write(args.out.join("stochastic.md"), bench::stochastic_markdown(rows))?;
        bench::plot_stochastic(rows, &args.out.join("stochastic.png"))?;
    }
    println!("{md}");
    for group in ["lights", "radius"] {
        for (x, mode, ms) in bench::winners(rows, group) {
            println!("{group} {x}: fastest {mode} ({ms:.1} ms)");
        }
    }
    println!(
        "wrote {}/bench.csv, bench.md, bench.png{}{}{}",
        args.out.display(),
        if scaling { ", scaling.png" } else { "" },
        if paths { ", paths.png" } else { "" },
        if stochastic { ", stochastic.md, stochastic.png" } else { "" }
    );
    Ok(())
}

/// `bench --only restir`: the equal-time comparison on a moving camera (`bench::run_restir`),
/// every layout of `bench::restir_layouts` (with --lights N, the sphere wall with N lights
/// alone; with --quick, the quick rows), at 1280x720 unless --size says otherwise.
fn bench_restir(args: &BenchArgs) -> Result<()> {
    use lampshade::bench;
    let size = args.size.unwrap_or((1280, 720));
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    if let Some(file) = &args.restir_json {
        let text = std::fs::read_to_string(file).with_context(|| format!("reading {}", file.display()))?;
        let rows = bench::read_restir_json(&text).with_context(|| format!("parsing {}", file.display()))?;
        let size = rows.first().map_or(size, |r| (size.0, (r.pixels / size.0.max(1) as u64) as u32));
        let md = bench::restir_markdown(&rows, size, "the adapter of that run");
        std::fs::write(args.out.join("restir.md"), &md)?;
        bench::plot_restir(&rows, &args.out.join("restir.png"))?;
        println!("{md}\nwrote {}/restir.md, restir.png from {}", args.out.display(), file.display());
        return Ok(());
    }
    let gpu = Gpu::open(&args.adapter.choice())?;
    let costs = lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?;
    let configs = bench::restir_configs(&Settings::default(), args.quick);
    let layouts = match lampshade::cli::requested_lights(args.lights, args.light_grid) {
        Some(n) => vec![bench::restir_wall(n, 1.0)],
        None => bench::restir_layouts(),
    };
    let bar = indicatif::ProgressBar::new((configs.len() * layouts.len()) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .map_err(|e| anyhow::anyhow!("{e}"))?,
    );
    let mut rows = Vec::new();
    for l in &layouts {
        rows.extend(bench::run_restir(&gpu, l, &configs, size, &costs, &mut |label| {
            bar.inc(1);
            bar.set_message(label.to_string());
        })?);
        std::fs::write(args.out.join("restir.json"), serde_json::to_string_pretty(&rows)?)?;
    }
    bar.finish_and_clear();
    let md = bench::restir_markdown(&rows, size, &gpu.info.name);
    std::fs::write(args.out.join("restir.md"), &md)?;
    bench::plot_restir(&rows, &args.out.join("restir.png"))?;
    println!("{md}\nwrote {}/restir.md, restir.json, restir.png", args.out.display());
    Ok(())
}

/// `bench --camera-path`: the culling modes replayed along a camera path (`bench::run_path`).
fn bench_path(args: BenchArgs) -> Result<()> {
    use lampshade::bench::{path_markdown, run_path, PathConfig, PathOptions};
    use lampshade::renderer::CullingMode;
    use lampshade::scene::camera_path::CameraPath;
    let file = args.camera_path.clone().context("--camera-path")?;
    let path = CameraPath::load(&file)?;
    if let Some(s) = args.path_step {
        if !(s.is_finite() && s > 0.0 && s <= 10.0) {
            bail!("--path-step {s} must lie in (0, 10] seconds");
        }
    }
    let step = path.step(args.path_step);
    if !args.only.is_empty() {
        bail!("--only chooses the sweep's groups; with --camera-path, --modes chooses the culling modes");
    }
    let lights = lampshade::cli::requested_lights(args.lights, args.light_grid);
    let (scene, warnings) = open_scene(&args.scene, BuiltinOptions { lights, time: 0.0 }, &Default::default())?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scene);
    }
    if let Some(named) = path.scene.as_deref().filter(|n| *n != args.scene) {
        eprintln!("note: {} was recorded in {named}, replayed in {}", file.display(), args.scene);
    }
    let modes = match args.modes.as_slice() {
        [] => vec![CullingMode::Tiled, CullingMode::Clustered, CullingMode::Zbin],
        m => m.to_vec(),
    };
    let configs: Vec<PathConfig> = modes
        .iter()
        .map(|&culling| PathConfig {
            label: culling.name(),
            settings: Settings { culling, ..Settings::default() },
            exact: true,
        })
        .collect();
    let size = args.size.unwrap_or((480, 270));
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let gpu = Gpu::open(&args.adapter.choice())?;
    let costs = lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?;
    let bar = indicatif::ProgressBar::new(path.frames(step) as u64);
    let o = PathOptions { step, size, costs };
    let rows = run_path(&gpu, &scene, &path, &configs, &o, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    gpu.errors.check()?;
    let md = path_markdown(&rows, &args.scene, &file.display().to_string(), step, size, &gpu.info.name);
    std::fs::write(args.out.join("path.md"), &md)?;
    std::fs::write(args.out.join("path.json"), serde_json::to_string_pretty(&rows)?)?;
    println!("{md}\nwrote {}/path.md, path.json", args.out.display());
    Ok(())
}

/// Reads a settings file for `compare`.
fn settings_file(path: &std::path::Path) -> Result<(Settings, SceneKeys)> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading settings {}", path.display()))?;
    lampshade::settings_file::parse(&text).with_context(|| format!("parsing settings {}", path.display()))
}

/// `lampshade compare`: two settings files on one scene (`bench::compare_pair`).
fn compare(args: lampshade::cli::CompareArgs) -> Result<()> {
    if args.frames == 0 || args.frames > 1000 {
        bail!("--frames {} must be between 1 and 1000", args.frames);
    }
    let (sa, ka) = settings_file(&args.a)?;
    let (sb, kb) = settings_file(&args.b)?;
    // One scene for both: the scene keys the files give must agree.
    let keys = lampshade::settings_file::merge_scene_keys(&ka, &kb)
        .map_err(|e| anyhow::anyhow!("{} and {}: {e}", args.a.display(), args.b.display()))?;
    let (w, h) = match (args.size, keys.size) {
        (Some(s), _) => s,
        (None, Some([w, h])) => image_size(&format!("{w}x{h}")).map_err(anyhow::Error::msg)?,
        (None, None) => (640, 360),
    };
    let time = keys.time.unwrap_or(0.0);
    let lights = args.lights.or(keys.lights);
    let (mut scene, warnings) = open_scene(&args.scene, BuiltinOptions { lights, time }, &Default::default())?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scene);
    }
    keys.apply_to(&mut scene).with_context(|| format!("settings files: scene '{}'", args.scene))?;
    if let Some(camera) = keys.camera {
        camera.validate().map_err(|e| anyhow::anyhow!("settings file camera: {e}"))?;
        scene.camera = camera;
    }
    let gpu = Gpu::open(&args.adapter.choice())?;
    let costs = lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?;
    let o = lampshade::bench::PairOptions { size: (w, h), frames: args.frames, costs };
    let label = |p: &std::path::Path| p.file_name().map_or(p.display().to_string(), |n| n.to_string_lossy().into());
    let report =
        lampshade::bench::compare_pair(&gpu, &scene, &args.scene, (&sa, &sb), (&label(&args.a), &label(&args.b)), &o)?;
    gpu.errors.check()?;
    let md = lampshade::bench::write_pair(&args.out, &report)?;
    println!("{md}\nwrote {}/a.png, b.png, flip.png, difference.png, compare.md, compare.json", args.out.display());
    Ok(())
}

fn render(args: RenderArgs) -> Result<()> {
    let (mut settings, keys) = match &args.settings {
        Some(path) => {
            let text = std::fs::read_to_string(path).with_context(|| format!("reading settings {}", path.display()))?;
            lampshade::settings_file::parse(&text).with_context(|| format!("parsing settings {}", path.display()))?
        }
        None => (Settings::default(), Default::default()),
    };
    let scene_name = args.scene.clone().or(keys.scene.clone()).unwrap_or_else(|| "demo".into());
    let time = args.time.or(keys.time).unwrap_or(0.0);
    let lights = lampshade::cli::requested_lights(args.lights, args.light_grid).or(keys.lights);
    let (w, h) = match (args.size, keys.size) {
        (Some(s), _) => s,
        (None, Some([w, h])) => image_size(&format!("{w}x{h}")).map_err(anyhow::Error::msg)?,
        (None, None) => (1280, 720),
    };
    if !time.is_finite() {
        bail!("time {time} must be finite");
    }
    args.knobs.apply(&mut settings).map_err(anyhow::Error::msg)?;
    if args.light.is_some() {
        settings.selected_light = args.light;
    }
    // Ideal counting costs a full-screen pass per light: only when asked for (`--ideal`, or a
    // settings file's `count_ideal`), never implied by `--stats` (whose JSON says whether it ran).
    settings.count_ideal |= args.ideal;
    settings.validate().map_err(anyhow::Error::msg)?;
    let scene = render_scene(&args, &keys, &scene_name, BuiltinOptions { lights, time })?;
    settings.count_fragments = ledger_on(args.ledger, &settings, scene.lights.len());
    if let Some(k) = settings.selected_light {
        if k >= scene.lights.len() {
            bail!("--light {k}: scene '{scene_name}' has {} lights", scene.lights.len());
        }
    }
    let gpu = Gpu::open(&args.adapter.choice())?;
    let mut renderer = Renderer::new(&gpu, OUTPUT_FORMAT, &settings)?;
    renderer.set_calibration(lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?);
    let bar = costly_shadows(&scene, &settings, &mut renderer)?;
    let (image, stats) = lampshade::headless::render_image(&gpu, &mut renderer, &scene, &settings, w, h)?;
    if let Some(bar) = bar {
        bar.finish();
    }
    // An error outside the frame's own (the read-back): the image is not to be trusted.
    gpu.errors.check()?;
    image.save(&args.out).with_context(|| format!("writing {}", args.out.display()))?;
    println!(
        "{}: {} lights, {}{}, shaded {} fragments, ideal {}, gpu {} ms, calibration: {} -> {}",
        scene_name,
        stats.lights,
        settings.culling.name(),
        stats
            .tiles
            .as_ref()
            .filter(|_| settings.culling == lampshade::CullingMode::Auto)
            .map_or(String::new(), |t| format!(" ({})", t.method.name())),
        stats.shaded_fragments.map_or("-".into(), |v| v.to_string()),
        stats.ideal_fragments.map_or("not counted (--ideal)".into(), |v| v.to_string()),
        stats.gpu_ms.total.map_or("-".into(), |v| format!("{v:.2}")),
        stats.calibration,
        args.out.display()
    );
    let probe = match args.probe {
        Some((x, y)) => {
            let e = renderer.last_frame().explain(&gpu, x, y).with_context(|| format!("--probe {x},{y}"))?;
            print!("{}", lampshade::renderer::explain::table(&e));
            Some(e)
        }
        None => None,
    };
    if let Some(path) = &args.stats {
        let json = serde_json::json!({
            "probe": probe,
            "adapter": stats.adapter,
            "scene": scene_name,
            "time": time,
            "settings": settings,
            "stats": stats,
            "size": stats.size,
            "culling": stats.culling,
            "lights": stats.lights,
            "gpu_ms": stats.gpu_ms,
            "cpu_ms": stats.cpu_ms,
            "shaded_fragments": stats.shaded_fragments,
            "ideal_fragments": stats.ideal_fragments,
            "ideal_counted": settings.count_ideal,
            "ledger": settings.count_fragments,
            "wasted_fragments": stats.wasted_fragments,
            "light_cost_ms": stats.light_cost_ms,
            "cost_model": stats.cost_model,
            "calibration": stats.calibration,
            "coverage_fragments": stats.coverage_fragments,
            "efficiency": stats.efficiency,
            "gbuffer_bytes_per_pixel": stats.gbuffer_bytes_per_pixel,
            "gbuffer_fragments": stats.gbuffer_fragments,
            "volume_meshes": stats.volume_meshes,
            "forward": stats.forward,
            "post": stats.post,
            "per_light": stats.per_light,
        });
        std::fs::write(path, serde_json::to_string_pretty(&json)?)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// `render`'s scene: the built-in scene or file, at the viewpoint asked for, with its baked
/// light maps and the settings file's scene keys and camera.
fn render_scene(args: &RenderArgs, keys: &SceneKeys, scene_name: &str, builtin: BuiltinOptions) -> Result<Scene> {
    let import = lampshade::scene::import::ImportOptions::default();
    let (mut scene, warnings) = open_scene(scene_name, builtin, &import)?;
    for w in &warnings {
        eprintln!("warning: {scene_name}: {w}");
    }
    if let Some(k) = args.viewpoint {
        let Some((_, camera)) = scene.viewpoints.get(k) else {
            bail!("--viewpoint {k}: '{scene_name}' offers {} viewpoint(s)", scene.viewpoints.len());
        };
        scene.camera = *camera;
    }
    if let Some(dir) = &args.baked {
        let baked = lampshade::scene::lightmap::load(dir, &scene)?;
        lampshade::scene::lightmap::apply(&mut scene, &baked);
    }
    keys.apply_to(&mut scene).with_context(|| format!("settings file: scene '{scene_name}'"))?;
    if let Some(camera) = keys.camera {
        camera.validate().map_err(|e| anyhow::anyhow!("settings file camera: {e}"))?;
        scene.camera = camera;
    }
    Ok(scene)
}

/// Before a frame whose shadows ask for costly work (`ShadowCost::costly`, whether a preset,
/// a settings file or a flag turned them on): says what they ask for on stderr, and returns the
/// progress bar the renderer moves as the GPU finishes the shadow-map passes.
fn costly_shadows(
    scene: &Scene,
    settings: &Settings,
    renderer: &mut Renderer,
) -> Result<Option<indicatif::ProgressBar>> {
    let cost = lampshade::renderer::shadows::ShadowCost::of(scene, &settings.shadow_options());
    if !cost.costly() {
        return Ok(None);
    }
    eprintln!("{}", cost.warning());
    let bar = indicatif::ProgressBar::new(cost.passes);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .map_err(|e| anyhow::anyhow!("{e}"))?,
    );
    let sink = bar.clone();
    renderer.set_progress(Some(std::sync::Arc::new(move |what: &str, done: u64, total: u64| {
        sink.set_length(total);
        sink.set_position(done);
        sink.set_message(what.to_string());
    })));
    Ok(Some(bar))
}

/// Whether `render` counts the ledger's fragments: as `asked`, or by default up to
/// `LEDGER_DEFAULT_MAX` lights (saying so when the settings asked for it above that).
fn ledger_on(asked: Option<bool>, settings: &Settings, lights: usize) -> bool {
    match asked {
        Some(on) => on,
        None if lights > lampshade::renderer::explain::cost::LEDGER_DEFAULT_MAX => {
            if settings.count_fragments {
                eprintln!(
                    "note: {} lights: the light ledger is off above {} unless asked (--ledger on)",
                    lights,
                    lampshade::renderer::explain::cost::LEDGER_DEFAULT_MAX
                );
            }
            false
        }
        None => settings.count_fragments,
    }
}

/// `lampshade check`: every culling mode against brute force at the scene's cameras and at
/// cameras generated around it (`lampshade::oracle`).
fn check(args: CheckArgs) -> Result<()> {
    use lampshade::oracle::{self, Scope};
    use lampshade::renderer::{CullingMode, RenderPath};
    let mut settings = Settings::default();
    args.knobs.apply(&mut settings).map_err(anyhow::Error::msg)?;
    settings.validate().map_err(anyhow::Error::msg)?;
    let given = |name: &str| args.knobs.0.iter().any(|(k, _)| *k == name);
    let mut scope = Scope::default();
    if given("culling") {
        scope.modes = vec![settings.culling];
    }
    if given("path") {
        scope.paths = vec![settings.path];
    }
    let import = lampshade::scene::import::ImportOptions::default();
    let (scene, warnings) = open_scene(&args.scene, BuiltinOptions { lights: args.lights, time: 0.0 }, &import)?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scene);
    }
    let mut cameras: Vec<(String, lampshade::scene::Camera)> = Vec::new();
    match args.viewpoint {
        Some(k) => {
            let Some((name, camera)) = scene.viewpoints.get(k) else {
                bail!("--viewpoint {k}: '{}' offers {} viewpoint(s)", args.scene, scene.viewpoints.len());
            };
            cameras.push((format!("viewpoint {k} ({name})"), *camera));
        }
        None => {
            cameras.push(("the scene's camera".into(), scene.camera));
            for (k, (name, camera)) in scene.viewpoints.iter().enumerate() {
                cameras.push((format!("viewpoint {k} ({name})"), *camera));
            }
            for (k, camera) in oracle::cameras_around(&scene, args.cameras, 1).into_iter().enumerate() {
                cameras.push((format!("generated camera {k}"), camera));
            }
        }
    }
    let (w, h) = args.size;
    let gpu = Gpu::open(&args.adapter.choice())?;
    let mut renderer = oracle::renderer(&gpu)?;
    renderer.set_calibration(lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?);
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let bar = indicatif::ProgressBar::new(cameras.len() as u64);
    let mut rows = Vec::new();
    let (mut failed, mut refused) = (0usize, 0usize);
    for (c, (name, camera)) in cameras.iter().enumerate() {
        camera.validate().map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        let mut s = scene.clone();
        s.camera = *camera;
        let results = oracle::check_scene(&gpu, &mut renderer, &s, &settings, (w, h), &scope, args.out.is_some())?;
        for (m, difference) in results {
            if m.refused.is_some() {
                refused += 1;
            }
            let mut image = None;
            if let (Some(dir), Some(d), true) = (&args.out, &difference, m.failed()) {
                let path = dir.join(format!("camera{c}-{}-{}.png", m.path, m.mode));
                oracle::difference_image(d, w, h).save(&path).with_context(|| format!("writing {}", path.display()))?;
                image = Some(path.display().to_string());
            }
            if m.failed() {
                failed += 1;
                bar.suspend(|| {
                    eprintln!(
                        "{name}: {}/{}: {} pixels miss light, {} have extra light; worst {:?}",
                        m.path, m.mode, m.missed, m.extra, m.worst
                    )
                });
            }
            rows.push(
                serde_json::json!({ "camera": name, "camera_values": camera, "result": m, "difference_image": image }),
            );
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    gpu.errors.check()?;
    let modes: Vec<String> = scope.modes.iter().map(|m: &CullingMode| m.name()).collect();
    let paths: Vec<String> = scope.paths.iter().map(|p: &RenderPath| p.name()).collect();
    println!(
        "{}: {} lights, {} cameras, {} frames ({} on each of {}; the forward paths' lists against themselves \
         unculled) at {w}x{h}: {} miss or add light, {} refused",
        args.scene,
        scene.lights.len(),
        cameras.len(),
        rows.len(),
        modes.join(", "),
        paths.join(", "),
        failed,
        refused
    );
    for r in rows.iter().filter(|r| r["result"]["refused"].is_string()) {
        println!("  refused: {}: {}", r["camera"], r["result"]["refused"]);
    }
    if let Some(dir) = &args.out {
        let path = dir.join("check.json");
        let json = serde_json::json!({ "scene": args.scene, "size": [w, h], "settings": settings, "frames": rows });
        std::fs::write(&path, serde_json::to_string_pretty(&json)?)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if failed > 0 {
        bail!("{failed} frame(s) miss or add light against brute force");
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

/// `lampshade advise`: the advisor (`bench::advise`) on a scene.
fn advise(args: lampshade::cli::AdviseArgs) -> Result<()> {
    use lampshade::bench::advise;
    let mut settings = Settings { shadows: lampshade::renderer::ShadowMode::None, ..Settings::default() };
    args.knobs.apply(&mut settings).map_err(anyhow::Error::msg)?;
    settings.validate().map_err(anyhow::Error::msg)?;
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    let takes = builtin::TAKES_LIGHT_COUNT.contains(&args.scene.as_str());
    let import = lampshade::scene::import::ImportOptions::default();
    let most = args.lights.iter().copied().max();
    let (mut scene, warnings) = open_scene(&args.scene, BuiltinOptions { lights: most, time: 0.0 }, &import)?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scene);
    }
    // The viewpoint's camera, for every count (a built-in scene is built again per count).
    let mut label = args.scene.clone();
    let camera = match args.viewpoint {
        None => None,
        Some(k) => {
            let Some((name, camera)) = scene.viewpoints.get(k) else {
                bail!("--viewpoint {k}: '{}' offers {} viewpoint(s)", args.scene, scene.viewpoints.len());
            };
            label = format!("{} (viewpoint {k}: {name})", args.scene);
            scene.camera = *camera;
            Some(*camera)
        }
    };
    let counts: Vec<usize> = if !args.lights.is_empty() {
        args.lights.clone()
    } else if takes {
        vec![64, 256, 1024, 4096]
    } else {
        vec![scene.lights.len()]
    };
    if counts.contains(&0) {
        bail!("--lights: a light count must be at least 1");
    }
    if !takes && counts.iter().any(|&n| n > scene.lights.len()) {
        bail!("--lights: '{}' has {} lights; it can be advised at that many or fewer", args.scene, scene.lights.len());
    }
    let gpu = Gpu::open(&args.adapter.choice())?;
    let name = args.scene.clone();
    let scene_at: Box<dyn FnMut(usize) -> Result<lampshade::Scene>> = Box::new(move |n| {
        let mut s = if takes {
            builtin::build(&name, BuiltinOptions { lights: Some(n), time: 0.0 }).map_err(anyhow::Error::msg)?
        } else {
            advise::strided(&scene, n)
        };
        if let Some(camera) = camera {
            s.camera = camera;
        }
        Ok(s)
    });
    let candidates = advise::candidates(&settings);
    let mut frames = advise::GpuFrames::new(&gpu, candidates.clone(), scene_at, args.size, args.frames);
    frames.calibration = lampshade::calibration::resolve(&gpu.info, args.calibration.calibration.as_deref())?;
    eprintln!("calibration: {}", frames.calibration.describe());
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("[{bar:30}] {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let a = advise::advise(&mut frames, &label, args.size, &candidates, &counts, &mut |done, total, what| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    })?;
    bar.finish_and_clear();
    let md = advise::markdown(&a);
    print!("{md}");
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        std::fs::write(dir.join("advise.md"), &md).with_context(|| format!("writing {}", dir.display()))?;
        std::fs::write(dir.join("advise.json"), serde_json::to_string_pretty(&a)?)
            .with_context(|| format!("writing {}", dir.display()))?;
        lampshade::bench::plot_advice(&a, &dir.join("advise.png"))?;
        eprintln!("wrote {}/advise.md, advise.json, advise.png", dir.display());
    }
    Ok(())
}

/// `lampshade calibrate`: the cost model's constants measured on this adapter
/// (`bench::calibrate`), kept in the cache folder (`lampshade::calibration`) or `--out`.
fn calibrate(args: lampshade::cli::CalibrateArgs) -> Result<()> {
    use lampshade::bench::calibrate::{self, CalibrateOptions};
    let o =
        CalibrateOptions { scene: "demo".into(), size: args.size, counts: args.lights.clone(), frames: args.frames };
    if o.frames == 0 || o.frames > 1000 {
        bail!("--frames {} must be between 1 and 1000", o.frames);
    }
    if o.counts.iter().any(|&n| n == 0 || n > lampshade::renderer::settings::MAX_LIGHTS_EVERY_MODE) {
        bail!("--lights: each count must be between 1 and {}", lampshade::renderer::settings::MAX_LIGHTS_EVERY_MODE);
    }
    // Where it goes, checked before a minute of frames.
    let dir = match &args.out {
        Some(_) => None,
        None => Some(lampshade::calibration::cache_dir().context(
            "no cache folder: neither XDG_CACHE_HOME nor HOME is set to an absolute path (or give --out FILE)",
        )?),
    };
    let gpu = Gpu::open(&args.adapter.choice())?;
    let key = lampshade::calibration::key(&gpu.info);
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("[{bar:30}] {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let start = std::time::Instant::now();
    let run = calibrate::calibrate(&gpu, &key, &o, &mut |done, total, what| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    })?;
    bar.finish_and_clear();
    gpu.errors.check()?;
    print!("{}", calibrate::markdown(&run));
    let path = match (&args.out, dir) {
        (Some(file), _) => {
            std::fs::write(file, serde_json::to_string_pretty(&run.calibration)?)
                .with_context(|| format!("writing {}", file.display()))?;
            file.clone()
        }
        (None, Some(dir)) => lampshade::calibration::write(&dir, &run.calibration)?,
        (None, None) => bail!("no place to write the calibration"),
    };
    println!("measured in {:.1} s -> {}", start.elapsed().as_secs_f64(), path.display());
    Ok(())
}

/// `lampshade bake`: seed 004's lightmaps for a scene, to a folder `render --baked` reads.
fn bake(args: lampshade::cli::BakeArgs) -> Result<()> {
    let (mut scene, warnings) = open_scene(&args.scene, BuiltinOptions::default(), &Default::default())?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scene);
    }
    // A built-in scene that comes baked is baked again from its unbaked self.
    if args.scene == "courtyard" {
        scene = builtin::courtyard_unbaked();
    }
    let options = lampshade::scene::lightmap::BakeOptions {
        texels: args.texels,
        rays: args.rays,
        occlusion_distance: args.occlusion_distance,
    };
    let bar = indicatif::ProgressBar::new(scene.objects.len() as u64);
    let start = std::time::Instant::now();
    let baked = lampshade::scene::lightmap::bake(&scene, &options, |done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    lampshade::scene::lightmap::save(&baked, scene.objects.len(), &args.out)?;
    println!(
        "{}: baked {} of {} objects in {:.1} s -> {}",
        args.scene,
        baked.objects.len(),
        scene.objects.len(),
        start.elapsed().as_secs_f64(),
        args.out.display()
    );
    for (k, why) in &baked.skipped {
        println!("  object {k} left out: {why}");
    }
    Ok(())
}

/// `lampshade adapters`: each adapter found, its capability table and what it supports.
fn adapters(args: AdaptersArgs) -> Result<()> {
    let choice = args.adapter.choice();
    let found = lampshade::gpu::adapters(&choice);
    if found.is_empty() {
        bail!(
            "no graphics adapter found. On a headless Linux machine install Mesa's software Vulkan driver \
             (`apt-get install mesa-vulkan-drivers libvulkan1`) or its GL driver (`libegl-mesa0 libgl1-mesa-dri`)"
        );
    }
    let mut json = Vec::new();
    // `--adapter`: that one only (an index in the whole list, or a part of its name).
    let wanted = |i: usize, a: &wgpu::Adapter| match choice.adapter.as_deref() {
        None => true,
        Some(w) => {
            w.parse::<usize>().map_or_else(|_| a.get_info().name.to_lowercase().contains(&w.to_lowercase()), |k| k == i)
        }
    };
    for (i, adapter) in found.iter().enumerate().filter(|(i, a)| wanted(*i, a)) {
        let caps = lampshade::gpu::caps_of(adapter, choice.restrict);
        let missing = lampshade::gpu::REQUIRED_DOWNLEVEL - caps.downlevel;
        // An adapter that cannot run the shader module gives no choice.
        let choices = if missing.is_empty() { lampshade::renderer::support::choices(&caps) } else { Vec::new() };
        if args.json {
            json.push(serde_json::json!({ "index": i, "table": caps.report(Vec::new()), "choices": choices }));
            continue;
        }
        let a = &caps.adapter;
        println!("{i}: {} ({}, {}; driver {} {})", a.name, a.backend, a.device_type, a.driver, a.driver_info);
        if let Some(p) = caps.profile {
            println!("   masked to the {p:?} profile");
        }
        if !missing.is_empty() {
            println!("   cannot run Lampshade: lacks {missing:?}");
        }
        for r in caps.rows() {
            if r.has {
                println!("   yes  {}", r.name);
            } else {
                println!("   no   {}: {}", r.name, r.without);
            }
        }
        let mut knob = "";
        for c in &choices {
            if c.knob != knob {
                knob = c.knob;
                let ok: Vec<&str> =
                    choices.iter().filter(|d| d.knob == knob && d.outcome.is_ok()).map(|d| d.value.as_str()).collect();
                println!("   --{knob}: {}", if ok.is_empty() { "none".to_string() } else { ok.join(", ") });
            }
            match &c.outcome {
                Err(why) => println!("      not {}: {why}", c.value),
                Ok(f) if !f.is_empty() => println!("      {}: {}", c.value, f.join("; ")),
                Ok(_) => {}
            }
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
    }
    Ok(())
}

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    if matches!(
        cli.command,
        Some(
            Command::Render(_)
                | Command::Bench(_)
                | Command::Adapters(_)
                | Command::Check(_)
                | Command::Compare(_)
                | Command::Advise(_)
                | Command::Calibrate(_)
        )
    ) {
        lampshade::gpu::quiet_headless_device_select();
    }
    let result = match cli.command {
        Some(Command::Render(args)) => render(args),
        Some(Command::Bench(args)) => bench(args),
        Some(Command::Check(args)) => check(args),
        Some(Command::Compare(args)) => compare(args),
        Some(Command::Advise(args)) => advise(args),
        Some(Command::Calibrate(args)) => calibrate(args),
        Some(Command::Adapters(args)) => adapters(args),
        Some(Command::Bake(args)) => bake(args),
        Some(Command::MakeAssets { out }) => lampshade::scene::room::write(&out),
        Some(Command::Presets) => {
            print!("{}", lampshade::renderer::presets::Preset::markdown());
            Ok(())
        }
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
