//! Rendering the configurations: each one's frames, times, counts and error against its reference.

use super::*;

/// The median of `v` and its standard error, the sample spread over √n (NaN for no values;
/// 0 for one).
pub(crate) fn median_se(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (median(v.to_vec()), (var / n).sqrt())
}

pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

pub(crate) struct Reference {
    image: image::RgbaImage,
    light: Vec<f32>,
    peak: f32,
}

/// The finest shadows of a mode, the `shadows` group's reference: a 64 MiB atlas (4096
/// texels), 16 Poisson taps, 4 cascades.
pub fn shadow_reference(mode: ShadowMode) -> Settings {
    Settings {
        shadows: mode,
        shadow_budget_mb: 64.0,
        shadow_filter: ShadowFilter::Poisson16,
        shadow_cascades: 4,
        ..Settings::default()
    }
}

pub(crate) fn reference(gpu: &Gpu, scene: &crate::Scene, size: (u32, u32), shadows: ShadowMode) -> Result<Reference> {
    let settings = Settings {
        culling: reference_culling(scene.lights.len(), size),
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        // Blended surfaces in depth order at every pixel (up to 16 deep), not by object.
        blended: crate::renderer::BlendedMode::Peeled,
        peel_layers: crate::renderer::settings::MAX_PEEL_LAYERS,
        count_fragments: false,
        timestamps: false,
        ..shadow_reference(shadows)
    };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings)?;
    let (image, _) = render_image(gpu, &mut r, scene, &settings, size.0, size.1)?;
    let (d, s) = r.last_frame().read_accumulation(gpu)?;
    let light: Vec<f32> = d.into_iter().chain(s).collect();
    let peak = light.iter().copied().filter(|v| v.is_finite()).fold(0.0, f32::max);
    Ok(Reference { image, light, peak })
}

/// Runs the sweep; `progress(done, total, label)` is called before each configuration.
/// A configuration that cannot be built or rendered for this scene on this adapter is skipped
/// with its reason (a `path` row is kept instead, saying why); only a failure to open the scene,
/// or one after a configuration's first frame rendered, ends the run. The steps:
/// 1. prepare every configuration ([`prepare`]);
/// 2. `frames` timed rounds, interleaved;
/// 3. count, and compare with the reference, each configuration ([`measure`]).
pub fn run(gpu: &Gpu, o: &BenchOptions, mut progress: impl FnMut(usize, usize, &str)) -> Result<BenchRun> {
    // The error column compares every configuration with the f32 reference: an adapter that
    // cannot render it (wgpu's GL backend) is told before anything is timed.
    let probe =
        Settings { layout: LayoutChoice::Reference, accumulation: AccumFormat::Rgba32Float, ..Settings::default() };
    crate::renderer::support(&gpu.caps, &probe)
        .map_err(|e| anyhow::anyhow!("the bench's error reference cannot be rendered here: {e:#}"))?;
    let list = configs(o);
    let frames = o.frames.max(1);
    // Steps: prepare each configuration, `frames` timed rounds, then count and compare each.
    let steps = list.len() * 2 + frames;
    let mut files = SceneFiles::default();
    let (mut prepared, failed, skipped) =
        prepare(gpu, o, &list, &mut files, &mut |k, label| progress(k, steps, label))?;
    // Timed rounds, interleaved: each round renders every configuration once, so background
    // load on a shared machine falls on all of them alike and the ratios stay comparable.
    for round in 0..frames {
        progress(list.len() + round, steps, &format!("timed round {}/{frames}", round + 1));
        for (cfg, scene, renderer, times) in prepared.iter_mut() {
            // Timed without counting (occlusion queries, the tiled pass's per-light atomics):
            // the counts come from the counted render below.
            let timed = Settings { count_fragments: false, ..cfg.settings.clone() };
            times.push(render_image(gpu, renderer, scene, &timed, cfg.size.0, cfg.size.1)?.1);
        }
    }
    // The ledger group fits the per-light cost model per mode; the counted frames below
    // charge their lights by it.
    let ledger = match o.groups.is_empty() || o.groups.iter().any(|g| g == super::LEDGER_GROUP) {
        true => super::ledger(gpu, o, &mut files, &mut |label| progress(list.len() + frames, steps, label))?,
        false => Vec::new(),
    };
    let gbuffer_split = match o.groups.is_empty() || o.groups.iter().any(|g| g == super::GBUFFER_GROUP) {
        true => super::gbuffer_split::gbuffer_split(gpu, o, &mut files, &mut |label| {
            progress(list.len() + frames, steps, label)
        })?,
        false => Vec::new(),
    };
    let models = super::fitted_models(&ledger);
    let mut refs: HashMap<RefKey, Reference> = HashMap::new();
    let mut rows = Vec::new();
    for (k, (cfg, scene, mut renderer, times)) in prepared.into_iter().enumerate() {
        progress(list.len() + frames + k, steps, &format!("error of {}", cfg.label));
        renderer.cost_models = models.clone();
        rows.push(measure(gpu, o, cfg, &scene, &mut renderer, &times, &mut refs)?);
    }
    for (cfg, lights, error) in failed {
        rows.push(failed_row(cfg, &o.scene, lights, error));
    }
    fill_path_siblings(&mut rows);
    progress(steps, steps, "done");
    mark_pareto(&mut rows);
    add_limits(&mut rows);
    add_regret(&mut rows);
    add_units(&mut rows);
    Ok(BenchRun { rows, skipped, ledger, gbuffer_split })
}

/// A configuration ready to time: its scene, its renderer (warm), its timed frames' stats.
type Ready<'c> = (&'c Config, crate::Scene, Renderer, Vec<FrameStats>);

/// The references, by scene, light count, size, radius factor (bits) and shadows.
type RefKey<'a> = (&'a str, usize, (u32, u32), u64, ShadowMode);

/// Prepares every configuration: its scene (a file is read once per light count), a renderer
/// and a warm-up frame (shader JIT). Returns those ready, the `path` rows that failed (with the
/// scene's light count and why) and the configurations skipped.
#[allow(clippy::type_complexity)]
fn prepare<'c>(
    gpu: &Gpu,
    o: &'c BenchOptions,
    list: &'c [Config],
    files: &mut SceneFiles,
    progress: &mut dyn FnMut(usize, &str),
) -> Result<(Vec<Ready<'c>>, Vec<(&'c Config, usize, String)>, Vec<Skipped>)> {
    // Prepare every configuration (scene, renderer, a warm-up frame for shader JIT). A file is
    // read once per light count.
    let mut prepared: Vec<Ready<'c>> = Vec::new();
    let mut failed: Vec<(&Config, usize, String)> = Vec::new();
    let mut skipped: Vec<Skipped> = Vec::new();
    let mut scenes: HashMap<(&str, usize, u64), crate::Scene> = HashMap::new();
    for (k, cfg) in list.iter().enumerate() {
        progress(k, &format!("prepare {}", cfg.label));
        let name = cfg.scene.unwrap_or(&o.scene);
        let lights = (!o.fixed_lights || cfg.scene.is_some()).then_some(cfg.lights);
        let mut scene = match scenes.entry((name, cfg.lights, cfg.radius_scale.to_bits())) {
            std::collections::hash_map::Entry::Occupied(e) => e.get().clone(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let mut scene = files.open(name, BuiltinOptions { lights, time: o.time })?;
                scale_light_radii(&mut scene, cfg.radius_scale);
                e.insert(scene).clone()
            }
        };
        if cfg.calibration {
            calibration_scene(&mut scene);
        }
        let skip = |e: anyhow::Error| Skipped {
            group: cfg.group.into(),
            label: cfg.label.clone(),
            scene: name.to_string(),
            reason: format!("{e:#}"),
        };
        let mut renderer = match Renderer::new(gpu, OUTPUT_FORMAT, &cfg.settings) {
            Ok(mut r) => {
                r.set_calibration(o.costs.clone());
                r
            }
            Err(e) => {
                skipped.push(skip(e));
                continue;
            }
        };
        // The warm-up frame, then the counted frame `measure` draws: a pipeline compiles on its
        // first draw, so the counting pipelines compile here, and a configuration whose counting
        // this adapter cannot build is skipped like one it cannot draw.
        let counted = Settings { count_fragments: true, count_ideal: true, timestamps: false, ..cfg.settings.clone() };
        let (w, h) = cfg.size;
        let warm = render_image(gpu, &mut renderer, &scene, &cfg.settings, w, h)
            .and_then(|_| render_image(gpu, &mut renderer, &scene, &counted, w, h));
        if let Err(e) = warm {
            if cfg.group == "path" {
                // A path this build cannot render is a row saying why: the path comparison
                // shows every path.
                failed.push((cfg, scene.lights.len(), format!("{e:#}")));
            } else {
                skipped.push(skip(e));
            }
            continue;
        }
        prepared.push((cfg, scene, renderer, Vec::<FrameStats>::new()));
    }
    Ok((prepared, failed, skipped))
}

/// The bench's scenes: each glTF file is read once, and every light count's scene is a copy of
/// it with its lights added, so they all share its images (on the CPU, and on the device, where
/// renderers share uploads by image).
#[derive(Default)]
pub struct SceneFiles {
    /// Each file as read, and whether it takes a light count (it has no lights of its own).
    files: HashMap<String, (crate::Scene, bool)>,
}

impl SceneFiles {
    /// Scene `name` (built-in, or a glTF file with `lights` point lights added when it has
    /// none: the importer's default count when `None`).
    pub fn open(&mut self, name: &str, builtin: BuiltinOptions) -> Result<crate::Scene> {
        use crate::scene::import::{self, lighting, ImportOptions};
        if !import::is_gltf_path(name) {
            return Ok(crate::scene::open(name, builtin, &ImportOptions::default(), &mut |_| {})?.0);
        }
        let (file, takes_lights) = match self.files.entry(name.to_string()) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let options = ImportOptions { lights: 0, ..ImportOptions::default() };
                let imported = import::load(std::path::Path::new(name), &options, &mut |_| {})?;
                e.insert((imported.scene, imported.stats.default_lights))
            }
        };
        let mut scene = file.clone();
        if *takes_lights {
            lighting::add_surface_lights(&mut scene, builtin.lights.unwrap_or(ImportOptions::default().lights));
        }
        Ok(scene)
    }
}

/// The frame's ten costliest lights (index, ms), costliest first, by its stats' cost model.
fn costliest(stats: &FrameStats) -> Vec<(usize, f64)> {
    let mut v: Vec<(usize, f64)> = stats.per_light.iter().filter_map(|l| Some((l.index, l.cost_ms?))).collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    v.truncate(10);
    v
}

/// Counts configuration `cfg`'s frame and compares it with its reference (rendered once per
/// [`RefKey`] into `refs`): its row, with the median of its timed frames `times`.
fn measure<'c>(
    gpu: &Gpu,
    o: &'c BenchOptions,
    cfg: &'c Config,
    scene: &crate::Scene,
    renderer: &mut Renderer,
    times: &[FrameStats],
    refs: &mut HashMap<RefKey<'c>, Reference>,
) -> Result<Row> {
    let (w, h) = cfg.size;
    // The `shadows` group (its `none` row too) is held against the finest shadows (of every
    // light for the cube rows).
    let shadows = match cfg.group {
        "shadows" if cfg.settings.shadows == ShadowMode::All => ShadowMode::All,
        "shadows" => ShadowMode::Spots,
        "presets" => cfg.settings.shadows,
        _ => ShadowMode::None,
    };
    let key = (cfg.scene.unwrap_or(&o.scene), cfg.lights, cfg.size, cfg.radius_scale.to_bits(), shadows);
    let reference = match refs.entry(key) {
        std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
        std::collections::hash_map::Entry::Vacant(e) => e.insert(reference(gpu, scene, cfg.size, shadows)?),
    };
    let pick = |f: &dyn Fn(&FrameStats) -> Option<f64>| median(times.iter().filter_map(f).collect());
    let counted = Settings { count_fragments: true, count_ideal: true, timestamps: false, ..cfg.settings.clone() };
    let (image, stats) = render_image(gpu, renderer, scene, &counted, w, h)?;
    let figures = path_figures(gpu, &cfg.settings, renderer, &stats)?;
    let error = frame_error(gpu, reference, &cfg.settings, renderer, &stats, &image)?;
    let caps = if cfg.group == super::groups::ENGINES_GROUP {
        cap_figures(gpu, cfg, scene, renderer, &stats)?
    } else {
        CapFigures::default()
    };
    Ok(Row {
        group: cfg.group.into(),
        label: cfg.label.clone(),
        scene: cfg.scene.unwrap_or(&o.scene).to_string(),
        culling: cfg.settings.culling.name(),
        layout: stats.gbuffer_layout.clone(),
        accumulation: cfg.settings.accumulation.name(),
        reversed_z: cfg.settings.reversed_z,
        depth_format: stats.depth_stencil_format.clone(),
        light_cutoff: cfg.settings.light_cutoff,
        sphere_subdivisions: cfg.settings.sphere_subdivisions,
        cone_sides: cfg.settings.cone_sides,
        volumes: if stats.volume_meshes.is_empty() { "-".into() } else { stats.volume_meshes.join("+") },
        lights: scene.lights.len(),
        radius_scale: cfg.radius_scale,
        width: w,
        height: h,
        gbuffer_ms: pick(&|s| s.gpu_ms.gbuffer),
        lighting_ms: pick(&|s| s.gpu_ms.lighting),
        compose_ms: pick(&|s| s.gpu_ms.compose),
        forward_ms: pick(&|s| s.gpu_ms.forward.or(s.gpu_ms.total.map(|_| 0.0))),
        bloom_ms: pick(&|s| s.gpu_ms.bloom.or(s.gpu_ms.total.map(|_| 0.0))),
        exposure_ms: pick(&|s| s.gpu_ms.exposure.or(s.gpu_ms.total.map(|_| 0.0))),
        tonemap_ms: pick(&|s| s.gpu_ms.tonemap.or(s.gpu_ms.total.map(|_| 0.0))),
        effects_ms: crate::renderer::post::effects::EFFECTS
            .iter()
            .map(|e| pick(&|s| s.gpu_ms.effect(e.name).or(s.gpu_ms.total.map(|_| 0.0))))
            .collect(),
        total_ms: pick(&|s| s.gpu_ms.total),
        total_se_ms: median_se(&times.iter().filter_map(|s| s.gpu_ms.total).collect::<Vec<_>>()).1,
        regret: Default::default(),
        auto_chose: match cfg.settings.culling {
            crate::renderer::CullingMode::Auto => stats.tiles.as_ref().map_or("per-light".into(), |t| t.method.name()),
            _ => String::new(),
        },
        lists_ms: pick(&|s| s.gpu_ms.lists),
        units: Units::default(),
        draw_calls: times.last().map_or(0, |s| s.draw_calls),
        light_batches: times.last().map_or(0, |s| s.light_batches),
        coverage_fragments: stats.coverage_fragments.unwrap_or(0),
        shaded_fragments: stats.shaded_fragments.unwrap_or_else(|| forward_shaded(&stats)),
        ideal_fragments: stats.ideal_fragments.unwrap_or(0),
        efficiency: stats.efficiency.unwrap_or(f64::NAN),
        gbuffer_bytes_per_pixel: stats.gbuffer_bytes_per_pixel,
        flip_mean: error.flip_mean,
        max_abs_light_error: error.max_abs_light_error,
        psnr_db: error.psnr_db,
        pareto: false,
        reference: reference_culling(scene.lights.len(), cfg.size).name(),
        limit_ratio: f64::NAN,
        path: figures,
        shadow: ShadowFigures::of(&stats, times),
        caps,
        costliest: costliest(&stats),
        cost_source: stats.cost_model.as_ref().map_or(String::new(), |m| m.source.clone()),
    })
}

/// A frame's error against its reference ([`reference`]): what the bench's rows and
/// `lampshade compare` report.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FrameError {
    /// FLIP mean of the output against the reference's; NaN for a frame through the post chain
    /// (not the reference's picture by design).
    pub flip_mean: f32,
    /// The largest absolute difference of the light accumulation (diffuse, then specular)
    /// from the reference's; NaN where the path holds no such buffer.
    pub max_abs_light_error: f32,
    /// PSNR of the light accumulation against the reference's, its peak the reference's
    /// brightest value; NaN as the light error.
    pub psnr_db: f64,
}

/// The error of the frame `renderer` last drew (`image`, `stats`, with `settings`) against
/// `reference`: the accumulation is read back from the renderer.
pub(crate) fn frame_error(
    gpu: &Gpu,
    reference: &Reference,
    settings: &Settings,
    renderer: &Renderer,
    stats: &FrameStats,
    image: &image::RgbaImage,
) -> Result<FrameError> {
    let (d, s) = renderer.last_frame().read_accumulation(gpu)?;
    // The forward paths have no light accumulation: their error is FLIP's alone.
    let accumulated = stats.forward_path.is_none();
    // FLIP compares output images; a frame through the post chain is not the reference's
    // picture by design, so its row has none (NaN). The light error and PSNR are of the
    // accumulation, before post, in every row.
    let chain = crate::renderer::post::chain_active(settings.debug_view, &settings.post_options());
    let flip_mean = if chain { f32::NAN } else { flip(&reference.image, image)?.0.mean };
    let mut max_err = 0f32;
    let mut sq = 0f64;
    for (a, b) in d.iter().chain(s.iter()).zip(&reference.light) {
        let e = if a.is_finite() { (a - b).abs() } else { f32::INFINITY };
        max_err = max_err.max(e);
        sq += (e as f64).powi(2);
    }
    let mse = sq / reference.light.len().max(1) as f64;
    let mut psnr = if mse > 0.0 { 10.0 * ((reference.peak as f64).powi(2) / mse).log10() } else { f64::INFINITY };
    if settings.path != crate::renderer::RenderPath::Deferred || renderer.layout().one_accumulation {
        // The light error compares deferred's accumulation (ambient + sun, specular times
        // reflectance) with the reference's; the other paths hold no such buffer (the light
        // pre-pass's is unit-reflectance light without ambient, seed 000's one RT1 the lit
        // colour with the albedo in): their error is FLIP's, on the final picture.
        (max_err, psnr) = (f32::NAN, f64::NAN);
    }
    Ok(FrameError {
        flip_mean,
        max_abs_light_error: if accumulated { max_err } else { f32::NAN },
        psnr_db: if accumulated { psnr } else { f64::NAN },
    })
}

/// An `engines` row's [`CapFigures`]: from its counted frame's stats, and on the G-buffer
/// paths from [`crate::oracle::cap_loss`] (which draws the frame again, uncapped and capped).
fn cap_figures(
    gpu: &Gpu,
    cfg: &Config,
    scene: &crate::Scene,
    renderer: &mut Renderer,
    stats: &FrameStats,
) -> Result<CapFigures> {
    let source = crate::renderer::caps::ENGINES
        .iter()
        .find(|e| e.name == cfg.label)
        .map_or_else(|| "no caps".to_string(), |e| e.source.to_string());
    let c = stats.caps.clone().unwrap_or_default();
    let mut f = CapFigures {
        source,
        dropped_lights: (c.dropped_by_count + c.dropped_by_distance) as u64,
        dropped_entries: c.cluster_entries_dropped + c.object_entries_dropped,
        ..CapFigures::default()
    };
    if !crate::oracle::FORWARD_PATHS.contains(&cfg.settings.path) {
        let loss = crate::oracle::cap_loss(gpu, renderer, scene, &cfg.settings, cfg.size)?;
        f.missed_pixels = loss.missed_pixels as f64;
        f.dropped_pairs = loss.dropped_pairs.map_or(f64::NAN, |n| n as f64);
        f.entry_pairs = loss.entry_pairs.map_or(f64::NAN, |n| n as f64);
    }
    Ok(f)
}

/// The `path` figures of a rendered frame: passes, target bytes per pixel, list entries.
pub(crate) fn path_figures(
    gpu: &Gpu,
    settings: &Settings,
    renderer: &Renderer,
    stats: &FrameStats,
) -> Result<PathFigures> {
    let mut f = PathFigures { path: settings.path.name(), ..Default::default() };
    if let Some(fp) = &stats.forward_path {
        // Its passes, and the tonemap.
        f.passes = fp.passes.len() as u32 + 1;
        f.draw_calls = fp.draw_calls() + 1;
        f.objects = fp.objects as u64;
        f.target_bytes_per_pixel = fp.bytes_per_pixel();
        f.object_light_pairs = fp.list_entries;
    } else if let Some(pp) = &stats.prepass {
        // Seeds 003/004: pass 1, the lights, pass 3, then the tonemap; its draw calls are
        // pass 1's and pass 3's object draws, the light draws, the full-screen draw that
        // clears the light buffer (the ambient pass's, which adds ambient + sun in pass 3 on
        // this path) and the tonemap.
        f.passes = 4;
        f.draw_calls =
            pp.base_draw_calls + stats.draw_calls + !stats.ambient_in_gbuffer as u64 + pp.final_draw_calls + 1;
        f.target_bytes_per_pixel = pp.normal_exp_bytes_per_pixel
            + pp.depth_copy_bytes_per_pixel
            + pp.light_buffer_bytes_per_pixel
            + pp.hdr_bytes_per_pixel
            + pp.msaa_bytes_per_pixel
            + renderer_depth_bytes(renderer);
    } else {
        let bytes = |format: wgpu::TextureFormat| {
            format.block_copy_size(None).unwrap_or_else(|| {
                format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)).unwrap_or(4)
                    + format.block_copy_size(Some(wgpu::TextureAspect::StencilOnly)).unwrap_or(0)
            })
        };
        let accum = bytes(settings.accumulation.format(&gpu.caps)?);
        // G-buffer, lights, compose; the HDR colour when blended surfaces or post need it.
        let hdr = stats.forward.is_some() || stats.post.is_some();
        f.passes = 3;
        // Its light draws, the ambient + sun draw when it is not the G-buffer pass's, the
        // compose (the G-buffer's object draws are added from the forward rows).
        f.draw_calls = stats.draw_calls + !stats.ambient_in_gbuffer as u64 + 1;
        f.target_bytes_per_pixel = stats.gbuffer_bytes_per_pixel
            + bytes(renderer.depth_format())
            + 2 * accum
            + if hdr { bytes(crate::renderer::kit::HDR_FORMAT) } else { 0 };
    }
    Ok(f)
}

/// Bytes per pixel of the renderer's depth-stencil target.
pub(crate) fn renderer_depth_bytes(renderer: &Renderer) -> u32 {
    let format = renderer.depth_format();
    format.block_copy_size(None).unwrap_or_else(|| {
        format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)).unwrap_or(4)
            + format.block_copy_size(Some(wgpu::TextureAspect::StencilOnly)).unwrap_or(0)
    })
}

/// Samples the forward paths' shading passes passed (single-pass's shading, multi-pass's
/// ambient + sun and pairs; not the depth pass) when counted.
pub(crate) fn forward_shaded(stats: &FrameStats) -> u64 {
    stats.forward_path.as_ref().map_or(0, |fp| {
        fp.passes
            .iter()
            .filter(|p| p.name != "depth" && !p.name.starts_with("g-buffer"))
            .filter_map(|p| p.fragments)
            .sum()
    })
}

/// The row of a path configuration that failed to render: its error, no figures.
pub(crate) fn failed_row(cfg: &Config, scene: &str, lights: usize, error: String) -> Row {
    Row {
        group: cfg.group.into(),
        label: cfg.label.clone(),
        scene: cfg.scene.unwrap_or(scene).to_string(),
        culling: cfg.settings.culling.name(),
        layout: "-".into(),
        accumulation: cfg.settings.accumulation.name(),
        reversed_z: cfg.settings.reversed_z,
        depth_format: "-".into(),
        light_cutoff: cfg.settings.light_cutoff,
        sphere_subdivisions: cfg.settings.sphere_subdivisions,
        cone_sides: cfg.settings.cone_sides,
        volumes: "-".into(),
        lights,
        radius_scale: cfg.radius_scale,
        width: cfg.size.0,
        height: cfg.size.1,
        gbuffer_ms: f64::NAN,
        lighting_ms: f64::NAN,
        compose_ms: f64::NAN,
        forward_ms: f64::NAN,
        bloom_ms: f64::NAN,
        exposure_ms: f64::NAN,
        tonemap_ms: f64::NAN,
        effects_ms: vec![f64::NAN; crate::renderer::post::effects::EFFECTS.len()],
        total_ms: f64::NAN,
        total_se_ms: f64::NAN,
        regret: Default::default(),
        auto_chose: String::new(),
        lists_ms: f64::NAN,
        units: Units::default(),
        draw_calls: 0,
        light_batches: 0,
        coverage_fragments: 0,
        shaded_fragments: 0,
        ideal_fragments: 0,
        efficiency: f64::NAN,
        gbuffer_bytes_per_pixel: 0,
        flip_mean: f32::NAN,
        max_abs_light_error: f32::NAN,
        psnr_db: f64::NAN,
        pareto: false,
        reference: reference_culling(lights, cfg.size).name(),
        limit_ratio: f64::NAN,
        path: PathFigures { path: cfg.settings.path.name(), error, ..Default::default() },
        shadow: ShadowFigures::default(),
        caps: Default::default(),
        costliest: Vec::new(),
        cost_source: String::new(),
    }
}

/// Gives every `path` row of a scene and light count the forward rows' pair count and the
/// deferred row's lit fragments, so each path can be plotted against both.
pub(crate) fn fill_path_siblings(rows: &mut [Row]) {
    let key = |r: &Row| (r.scene.clone(), r.lights, r.width, r.height);
    let pairs: HashMap<_, u64> = rows
        .iter()
        .filter(|r| r.group == "path" && r.path.object_light_pairs > 0)
        .map(|r| (key(r), r.path.object_light_pairs))
        .collect();
    let lit: HashMap<_, u64> = rows
        .iter()
        .filter(|r| r.group == "path" && r.path.path == RenderPath::Deferred.name())
        .map(|r| (key(r), r.shaded_fragments))
        .collect();
    let objects: HashMap<_, u64> =
        rows.iter().filter(|r| r.group == "path" && r.path.objects > 0).map(|r| (key(r), r.path.objects)).collect();
    for r in rows.iter_mut().filter(|r| r.group == "path") {
        r.path.objects = objects.get(&key(r)).copied().unwrap_or(0);
        if r.path.path == RenderPath::Deferred.name() && r.path.error.is_empty() {
            // Its G-buffer's object draws on top of the light draws and the compose.
            r.path.draw_calls += r.path.objects;
        }
        r.path.object_light_pairs = pairs.get(&key(r)).copied().unwrap_or(0);
        r.path.lit_fragments = lit.get(&key(r)).copied().unwrap_or(0);
    }
}
