//! Speed against error: `lampshade bench` renders one scene under many configurations, times
//! each pass (median of N frames, GPU timestamps), counts fragments, and measures the error of
//! each image against a reference rendered without deferred approximations (every light
//! full-screen, an Rgba32Float G-buffer with stored position, Rgba32Float accumulation).
//! Output: `bench.csv`, `bench.md` and `bench.png` (time against error, Pareto front marked).

use crate::compare::flip;
use crate::gpu::Gpu;
use crate::headless::render_image;
use crate::renderer::{
    AccumFormat, CullingMode, DepthFormat, ForwardLights, FrameStats, LayoutChoice, Renderer, Settings, OUTPUT_FORMAT,
};
use crate::scene::builtin::BuiltinOptions;
use anyhow::{Context, Result};
use serde::Serialize;
use std::collections::HashMap;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scene: String,
    pub quick: bool,
    /// Frames timed per configuration (the median is reported).
    pub frames: usize,
    pub size: (u32, u32),
    pub lights: usize,
    pub time: f64,
    /// Run only the configurations of these groups (all when empty).
    pub groups: Vec<String>,
    /// The scene brings a fixed set of lights (a glTF file with lights, a built-in scene that
    /// takes no count): `lights` is not varied and the `lights` group is left out.
    pub fixed_lights: bool,
}

impl BenchOptions {
    pub fn new(scene: &str, quick: bool) -> Self {
        if quick {
            Self {
                scene: scene.into(),
                quick,
                frames: 3,
                size: (320, 180),
                lights: 256,
                time: 0.0,
                groups: Vec::new(),
                fixed_lights: false,
            }
        } else {
            Self {
                scene: scene.into(),
                quick,
                frames: 10,
                size: (1280, 720),
                lights: 1024,
                time: 0.0,
                groups: Vec::new(),
                fixed_lights: false,
            }
        }
    }
}

/// One configuration: what it varies, and the settings, light count, size and scene it runs with.
#[derive(Clone, Debug)]
pub struct Config {
    pub group: &'static str,
    pub label: String,
    pub settings: Settings,
    pub lights: usize,
    pub size: (u32, u32),
    /// Another built-in scene than the bench's (the depth group's `far-origin` rows).
    pub scene: Option<&'static str>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub group: String,
    pub label: String,
    pub scene: String,
    pub culling: String,
    pub layout: String,
    pub accumulation: String,
    pub reversed_z: bool,
    /// The depth-stencil format the frame used (the adapter's fallback shows here).
    pub depth_format: String,
    pub light_cutoff: f32,
    pub sphere_subdivisions: u32,
    pub cone_sides: u32,
    /// Bounding meshes the frame drew, e.g. "sphere+cone".
    pub volumes: String,
    pub lights: usize,
    pub width: u32,
    pub height: u32,
    pub gbuffer_ms: f64,
    pub lighting_ms: f64,
    pub compose_ms: f64,
    /// The forward pass of blended surfaces (0 without any).
    pub forward_ms: f64,
    pub total_ms: f64,
    pub coverage_fragments: u64,
    pub shaded_fragments: u64,
    pub ideal_fragments: u64,
    pub efficiency: f64,
    pub gbuffer_bytes_per_pixel: u32,
    pub flip_mean: f32,
    pub max_abs_light_error: f32,
    pub psnr_db: f64,
    pub pareto: bool,
}

/// The cut-off thresholds the `cutoff` group sweeps (fractions of each light's peak).
pub const CUTOFFS: [(f32, &str); 4] = [(0.0, "0"), (1.0 / 256.0, "1/256"), (1.0 / 64.0, "1/64"), (1.0 / 16.0, "1/16")];

/// The sweep. Every configuration differs from the default (`volume` culling, `compact`
/// layout, Rgba16Float accumulation, Depth32FloatStencil8, exact radii, an 80-triangle sphere
/// and a 12-sided cone) in one knob; `--quick` keeps a subset of each group.
pub fn configs(o: &BenchOptions) -> Vec<Config> {
    let base = Settings { count_fragments: true, count_ideal: false, timestamps: true, ..Settings::default() };
    let c = |group, label: String, settings: Settings, lights| Config {
        group,
        label,
        settings,
        lights,
        size: o.size,
        scene: None,
    };
    let q = o.quick;
    let mut v = Vec::new();
    for mode in CullingMode::ALL {
        v.push(c("culling", mode.name(), Settings { culling: mode, ..base.clone() }, o.lights));
    }
    // Seed 000's fp16 targets, the packed and fitted layouts, and the normal encodings with
    // everything else as `compact` stores it (compact itself is the `volume` row).
    let layouts: &[LayoutChoice] = if q {
        &[LayoutChoice::Seed000, LayoutChoice::Oct8, LayoutChoice::Xyz8]
    } else {
        &[
            LayoutChoice::Seed000,
            LayoutChoice::Packed,
            LayoutChoice::Fit,
            LayoutChoice::Oct8,
            LayoutChoice::Oct16,
            LayoutChoice::Xyz8,
            LayoutChoice::Xyz16f,
        ]
    };
    for &layout in layouts {
        v.push(c("layout", format!("{layout:?}").to_lowercase(), Settings { layout, ..base.clone() }, o.lights));
    }
    let accumulations: &[AccumFormat] = if q {
        &[AccumFormat::Rgba8Log]
    } else {
        &[AccumFormat::Rgba32Float, AccumFormat::Rg11b10Ufloat, AccumFormat::Rgba8Log]
    };
    for &accumulation in accumulations {
        v.push(c("accumulation", accumulation.name(), Settings { accumulation, ..base.clone() }, o.lights));
    }
    // Depth format x depth convention, on the bench's scene and on the far-origin hard case.
    let scenes: &[Option<&'static str>] = if q { &[None] } else { &[None, Some("far-origin")] };
    for &scene in scenes {
        for depth_format in DepthFormat::ALL {
            for reversed_z in [false, true] {
                if q && depth_format == DepthFormat::default() && !reversed_z {
                    continue; // the `volume` row
                }
                let label = format!(
                    "{}{}{}",
                    scene.map_or(String::new(), |s| format!("{s} ")),
                    depth_format.name(),
                    if reversed_z { " reversed-z" } else { "" }
                );
                let settings = Settings { depth_format, reversed_z, ..base.clone() };
                v.push(Config { scene, ..c("depth", label, settings, o.lights) });
            }
        }
    }
    for (t, name) in CUTOFFS {
        if t == 0.0 && q {
            continue;
        }
        v.push(c("cutoff", format!("cutoff {name}"), Settings { light_cutoff: t, ..base.clone() }, o.lights));
    }
    let subdivisions: &[u32] = if q { &[0, 2] } else { &[0, 1, 2, 3] };
    for &sphere_subdivisions in subdivisions {
        let faces = 20 * 4u32.pow(sphere_subdivisions);
        let label = format!("sphere {faces} tris");
        v.push(c("tessellation", label, Settings { sphere_subdivisions, ..base.clone() }, o.lights));
    }
    let sides: &[u32] = if q { &[] } else { &[6, 24] };
    for &cone_sides in sides {
        v.push(c(
            "tessellation",
            format!("cone {cone_sides} sides"),
            Settings { cone_sides, ..base.clone() },
            o.lights,
        ));
    }
    let sizes: &[(u32, u32)] =
        if q { &[(160, 90), (640, 360)] } else { &[(160, 90), (320, 180), (640, 360), (1280, 720)] };
    for &size in sizes {
        let label = format!("{}x{}", size.0, size.1);
        v.push(Config { size, ..c("resolution", label, base.clone(), o.lights) });
    }
    // A file's added lights each reach past the model's centre (a dome around it), so their
    // cost grows much faster with the count than the demo's small lights.
    let counts: &[usize] = match (crate::scene::import::is_gltf_path(&o.scene), o.quick) {
        (_, _) if o.fixed_lights => &[],
        (true, true) => &[16, 64],
        (true, false) => &[16, 64, 256],
        (false, true) => &[16, 1024],
        (false, false) => &[1, 64, 256, 4096],
    };
    for &n in counts {
        for mode in [CullingMode::Volume, CullingMode::StencilTwoPass] {
            v.push(c("lights", format!("{} x{n}", mode.name()), Settings { culling: mode, ..base.clone() }, n));
        }
    }
    // The forward pass's light lists (the same picture each; its time is `forward_ms`; only
    // scenes with blended surfaces, e.g. `glass`, have a forward pass).
    for forward_lights in ForwardLights::ALL {
        let label = format!("forward {}", forward_lights.name());
        v.push(c("forward", label, Settings { forward_lights, ..base.clone() }, o.lights));
    }
    v.retain(|c| o.groups.is_empty() || o.groups.iter().any(|g| g == c.group));
    v
}

/// The configuration groups, for `--only`.
pub const GROUPS: &[&str] =
    &["culling", "layout", "accumulation", "depth", "cutoff", "tessellation", "resolution", "lights", "forward"];

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

struct Reference {
    image: image::RgbaImage,
    light: Vec<f32>,
    peak: f32,
}

fn reference(gpu: &Gpu, scene: &crate::Scene, size: (u32, u32)) -> Result<Reference> {
    let settings = Settings {
        culling: CullingMode::Fullscreen,
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        count_fragments: false,
        timestamps: false,
        ..Settings::default()
    };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings)?;
    let (image, _) = render_image(gpu, &mut r, scene, &settings, size.0, size.1)?;
    let (d, s) = r.read_accumulation(gpu)?;
    let light: Vec<f32> = d.into_iter().chain(s).collect();
    let peak = light.iter().copied().filter(|v| v.is_finite()).fold(0.0, f32::max);
    Ok(Reference { image, light, peak })
}

/// Runs the sweep; `progress(done, total, label)` is called before each configuration.
pub fn run(gpu: &Gpu, o: &BenchOptions, mut progress: impl FnMut(usize, usize, &str)) -> Result<Vec<Row>> {
    let list = configs(o);
    let frames = o.frames.max(1);
    // Steps: prepare each configuration, `frames` timed rounds, then count and compare each.
    let steps = list.len() * 2 + frames;
    // Prepare every configuration (scene, renderer, a warm-up frame for shader JIT). A file is
    // read once per light count.
    let mut prepared = Vec::new();
    let mut scenes: HashMap<(&str, usize), crate::Scene> = HashMap::new();
    for (k, cfg) in list.iter().enumerate() {
        progress(k, steps, &format!("prepare {}", cfg.label));
        let name = cfg.scene.unwrap_or(&o.scene);
        let lights = (!o.fixed_lights || cfg.scene.is_some()).then_some(cfg.lights);
        let scene = match scenes.entry((name, cfg.lights)) {
            std::collections::hash_map::Entry::Occupied(e) => e.get().clone(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let options = crate::scene::import::ImportOptions::default();
                let (scene, _) =
                    crate::scene::open(name, BuiltinOptions { lights, time: o.time }, &options, &mut |_| {})?;
                e.insert(scene).clone()
            }
        };
        let mut renderer = match Renderer::new(gpu, OUTPUT_FORMAT, &cfg.settings) {
            Ok(r) => r,
            Err(e) => {
                log::warn!("skipping {}: {e:#}", cfg.label);
                continue;
            }
        };
        render_image(gpu, &mut renderer, &scene, &cfg.settings, cfg.size.0, cfg.size.1)?;
        prepared.push((cfg, scene, renderer, Vec::<FrameStats>::new()));
    }
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
    let mut refs: HashMap<(&str, usize, (u32, u32)), Reference> = HashMap::new();
    let mut rows = Vec::new();
    for (k, (cfg, scene, mut renderer, times)) in prepared.into_iter().enumerate() {
        progress(list.len() + frames + k, steps, &format!("error of {}", cfg.label));
        let (w, h) = cfg.size;
        let reference = match refs.entry((cfg.scene.unwrap_or(&o.scene), cfg.lights, cfg.size)) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(reference(gpu, &scene, cfg.size)?),
        };
        let pick = |f: fn(&FrameStats) -> Option<f64>| median(times.iter().filter_map(f).collect());
        let counted = Settings { count_ideal: true, timestamps: false, ..cfg.settings.clone() };
        let (image, stats) = render_image(gpu, &mut renderer, &scene, &counted, w, h)?;
        let (d, s) = renderer.read_accumulation(gpu)?;
        let (fl, _) = flip(&reference.image, &image)?;
        let mut max_err = 0f32;
        let mut sq = 0f64;
        for (a, b) in d.iter().chain(s.iter()).zip(&reference.light) {
            let e = if a.is_finite() { (a - b).abs() } else { f32::INFINITY };
            max_err = max_err.max(e);
            sq += (e as f64).powi(2);
        }
        let mse = sq / reference.light.len().max(1) as f64;
        let psnr = if mse > 0.0 { 10.0 * ((reference.peak as f64).powi(2) / mse).log10() } else { f64::INFINITY };
        rows.push(Row {
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
            width: w,
            height: h,
            gbuffer_ms: pick(|s| s.gpu_ms.gbuffer),
            lighting_ms: pick(|s| s.gpu_ms.lighting),
            compose_ms: pick(|s| s.gpu_ms.compose),
            forward_ms: pick(|s| s.gpu_ms.forward.or(s.gpu_ms.total.map(|_| 0.0))),
            total_ms: pick(|s| s.gpu_ms.total),
            coverage_fragments: stats.coverage_fragments.unwrap_or(0),
            shaded_fragments: stats.shaded_fragments.unwrap_or(0),
            ideal_fragments: stats.ideal_fragments.unwrap_or(0),
            efficiency: stats.efficiency.unwrap_or(f64::NAN),
            gbuffer_bytes_per_pixel: stats.gbuffer_bytes_per_pixel,
            flip_mean: fl.mean,
            max_abs_light_error: max_err,
            psnr_db: psnr,
            pareto: false,
        });
    }
    progress(steps, steps, "done");
    mark_pareto(&mut rows);
    Ok(rows)
}

/// Marks the rows no other row of the same scene, light count and size beats in both time and
/// error.
pub fn mark_pareto(rows: &mut [Row]) {
    let key = |r: &Row| (r.scene.clone(), r.lights, r.width, r.height);
    let snapshot: Vec<(_, f64, f32)> = rows.iter().map(|r| (key(r), r.total_ms, r.flip_mean)).collect();
    for (i, r) in rows.iter_mut().enumerate() {
        let (k, t, e) = &snapshot[i];
        r.pareto = !snapshot
            .iter()
            .enumerate()
            .any(|(j, (k2, t2, e2))| j != i && k2 == k && t2 <= t && e2 <= e && (t2 < t || e2 < e));
    }
}

pub fn write_csv(rows: &[Row], path: &Path) -> Result<()> {
    let mut out = String::from(
        "group,label,scene,culling,layout,accumulation,reversed_z,depth_format,light_cutoff,sphere_subdivisions,cone_sides,volumes,\
         lights,width,height,gbuffer_ms,lighting_ms,compose_ms,forward_ms,total_ms,\
         coverage_fragments,shaded_fragments,ideal_fragments,efficiency,gbuffer_bytes_per_pixel,flip_mean,max_abs_light_error,psnr_db,pareto\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{},{},{},{:.4},{},{:.6},{:.6},{:.2},{}\n",
            r.group,
            r.label,
            r.scene,
            r.culling,
            r.layout,
            r.accumulation,
            r.reversed_z,
            r.depth_format,
            r.light_cutoff,
            r.sphere_subdivisions,
            r.cone_sides,
            r.volumes,
            r.lights,
            r.width,
            r.height,
            r.gbuffer_ms,
            r.lighting_ms,
            r.compose_ms,
            r.forward_ms,
            r.total_ms,
            r.coverage_fragments,
            r.shaded_fragments,
            r.ideal_fragments,
            r.efficiency,
            r.gbuffer_bytes_per_pixel,
            r.flip_mean,
            r.max_abs_light_error,
            r.psnr_db,
            r.pareto
        );
    }
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

pub fn markdown(rows: &[Row], gpu_name: &str, o: &BenchOptions) -> String {
    let mut s = format!(
        "Scene `{}`, time {}, adapter {gpu_name}; GPU ms are medians of {} frames; error against the reference \
         (full-screen lights, Rgba32Float G-buffer and accumulation). Ratio: lighting time over `fullscreen`'s in the \
         same run and size. * = on the Pareto front (time, FLIP) for its scene, light count and size. \
         Volumes: the bounding meshes the frame drew (only the kinds its lights need).\n\n",
        o.scene, o.time, o.frames
    );
    s += "| group | configuration | lights | size | G-buffer B/px | volumes | gbuffer ms | lighting ms | forward ms | total ms | lighting ratio | coverage | shaded | ideal | efficiency | FLIP mean | max abs light error | PSNR dB |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    let full: HashMap<(usize, u32, u32), f64> = rows
        .iter()
        .filter(|r| r.label == "fullscreen")
        .map(|r| ((r.lights, r.width, r.height), r.lighting_ms))
        .collect();
    for r in rows {
        let ratio = full
            .get(&(r.lights, r.width, r.height))
            .filter(|_| r.scene == o.scene)
            .map_or("-".into(), |f| format!("{:.3}", r.lighting_ms / f));
        s += &format!(
            "| {} | {}{} | {} | {}x{} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {} | {} | {} | {} | {:.3} | {:.5} | {:.4} | {:.1} |\n",
            r.group,
            r.label,
            if r.pareto { " *" } else { "" },
            r.lights,
            r.width,
            r.height,
            r.gbuffer_bytes_per_pixel,
            r.volumes,
            r.gbuffer_ms,
            r.lighting_ms,
            r.forward_ms,
            r.total_ms,
            ratio,
            r.coverage_fragments,
            r.shaded_fragments,
            r.ideal_fragments,
            r.efficiency,
            r.flip_mean,
            r.max_abs_light_error,
            r.psnr_db
        );
    }
    s
}

/// Time (x) against FLIP error (y): one panel per group, one labelled point per configuration,
/// the default configuration (`culling` / `volume`) in grey in every panel for comparison, and
/// the Pareto front of the panel's scene, light count and size joined by a black line (points
/// on it ringed).
pub fn plot(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let pts: Vec<&Row> = rows.iter().filter(|r| r.total_ms.is_finite() && r.total_ms > 0.0).collect();
    let mut groups: Vec<&str> = Vec::new();
    for r in &pts {
        if !groups.contains(&r.group.as_str()) {
            groups.push(&r.group);
        }
    }
    let cols = groups.len().clamp(1, 4);
    let rows_n = groups.len().div_ceil(cols).max(1);
    let root = BitMapBackend::new(path, (480 * cols as u32, 400 * rows_n as u32 + 50)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(50);
    title.titled("Speed against error, one panel per knob (lower left is better)", ("sans-serif", 26))?;
    let panels = body.split_evenly((rows_n, cols));
    let palette = [
        RED,
        BLUE,
        RGBColor(0, 150, 0),
        MAGENTA,
        RGBColor(0, 150, 170),
        RGBColor(230, 120, 0),
        RGBColor(120, 70, 20),
        RGBColor(90, 90, 90),
    ];
    let default = pts.iter().find(|r| r.group == "culling" && r.label == "volume").copied();
    let key = |r: &Row| (r.scene.clone(), r.lights, r.width, r.height);
    for (gi, (g, area)) in groups.iter().zip(panels.iter()).enumerate() {
        let color = palette[gi % palette.len()];
        let mut mine: Vec<&Row> = pts.iter().filter(|r| r.group == *g).copied().collect();
        if let Some(d) = default.filter(|_| *g != "culling") {
            mine.push(d);
        }
        let t_lo = mine.iter().map(|r| r.total_ms).fold(f64::INFINITY, f64::min) / 1.5;
        let t_hi = mine.iter().map(|r| r.total_ms).fold(0.0, f64::max) * 2.5;
        let e_hi = mine.iter().map(|r| r.flip_mean as f64).fold(1e-4, f64::max) * 1.25;
        // Ticks of our own: at least three per axis, labels distinct (plotters' log axis labels
        // only powers of ten, so a narrow range had one tick or none).
        let x_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
        let y_ticks = crate::plot_layout::linear_ticks(0.0, e_hi);
        let (x_dec, y_dec) = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&y_ticks));
        let mut chart = ChartBuilder::on(area)
            .caption(*g, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(64)
            .build_cartesian_2d((t_lo..t_hi).log_scale(), 0.0..e_hi)?;
        chart
            .configure_mesh()
            .x_desc("GPU ms per frame (median)")
            .y_desc("FLIP mean")
            .label_style(("sans-serif", 13))
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            // The log axis still labels its powers of ten: blank, the ticks are drawn below.
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .draw()?;
        let font: TextStyle = ("sans-serif", 13).into_font().into();
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let base = area.get_base_pixel();
        let grid = RGBColor(225, 225, 225);
        for &t in &x_ticks {
            chart.draw_series(LineSeries::new([(t, 0.0), (t, e_hi)], grid))?;
            let text = format!("{t:.x_dec$}");
            let (w, _) = area.estimate_text_size(&text, &font)?;
            let (px, _) = chart.backend_coord(&(t, 0.0));
            area.draw(&Text::new(text, (px - w as i32 / 2 - base.0, yr.end + 4 - base.1), font.clone()))?;
        }
        for &e in &y_ticks {
            chart.draw_series(LineSeries::new([(t_lo, e), (t_hi, e)], grid))?;
            let text = format!("{e:.y_dec$}");
            let (w, h) = area.estimate_text_size(&text, &font)?;
            let (_, py) = chart.backend_coord(&(t_lo, e));
            area.draw(&Text::new(text, (xr.start - 6 - w as i32 - base.0, py - h as i32 / 2 - base.1), font.clone()))?;
        }
        // The Pareto front of each scene/lights/size among this panel's points.
        let mut keys: Vec<_> = mine.iter().map(|r| key(r)).collect();
        keys.dedup();
        for k in keys {
            let mut front: Vec<(f64, f64)> =
                mine.iter().filter(|r| r.pareto && key(r) == k).map(|r| (r.total_ms, r.flip_mean as f64)).collect();
            front.sort_by(|a, b| a.0.total_cmp(&b.0));
            if front.len() > 1 {
                chart.draw_series(LineSeries::new(front, BLACK.stroke_width(1)))?;
            }
        }
        // Markers first, then each label where it covers no marker and no other label and
        // stays inside the plotting area (`plot_layout::place_labels`).
        mine.sort_by(|a, b| a.total_ms.total_cmp(&b.total_ms).then(b.flip_mean.total_cmp(&a.flip_mean)));
        let mut points = Vec::new();
        let mut sizes = Vec::new();
        let mut labels = Vec::new();
        for r in &mine {
            let is_default = default.is_some_and(|d| std::ptr::eq(d, *r)) && *g != "culling";
            let c = if is_default { RGBColor(160, 160, 160) } else { color };
            let p = (r.total_ms, r.flip_mean as f64);
            let label = if is_default {
                "default".to_string()
            } else if r.lights == default.map_or(0, |d| d.lights) {
                r.label.clone()
            } else {
                format!("{} ({} lights)", r.label, r.lights)
            };
            chart.draw_series(std::iter::once(Circle::new(p, 5, c.filled())))?;
            if r.pareto {
                chart.draw_series(std::iter::once(Circle::new(p, 8, BLACK.stroke_width(1))))?;
            }
            let (w, h) = area.estimate_text_size(&label, &font)?;
            points.push(chart.backend_coord(&p));
            sizes.push((w as i32, h as i32));
            labels.push((p, label, c));
        }
        let spots = crate::plot_layout::place_labels(&points, &sizes, 8, (xr.start, yr.start, xr.end, yr.end));
        let mut left_out = 0;
        for (((p, label, c), spot), (px, py)) in labels.into_iter().zip(spots).zip(points) {
            let Some((l, t, _, _)) = spot else {
                left_out += 1;
                continue;
            };
            chart.draw_series(std::iter::once(
                EmptyElement::at(p) + Text::new(label, (l - px, t - py), font.color(&c)),
            ))?;
        }
        if left_out > 0 {
            let (x0, y1) = (xr.start + 4, yr.end - 16);
            area.draw(&Text::new(
                format!("{left_out} label(s) left out: no free spot (see bench.md)"),
                (x0 - base.0, y1 - base.1),
                font.color(&BLACK),
            ))?;
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_sweeps_cover_every_group_with_valid_settings() {
        for quick in [true, false] {
            let o = BenchOptions::new("demo", quick);
            let list = configs(&o);
            assert!(list.len() >= 8, "{} configurations", list.len());
            for g in GROUPS {
                assert!(list.iter().any(|c| c.group == *g), "quick {quick}: no {g} configuration");
            }
            for c in &list {
                c.settings.validate().unwrap();
            }
            let labels: std::collections::HashSet<_> = list.iter().map(|c| (c.group, c.label.clone())).collect();
            assert_eq!(labels.len(), list.len(), "duplicate labels");
        }
        let full = configs(&BenchOptions::new("demo", false));
        let cutoffs: Vec<f32> = full.iter().filter(|c| c.group == "cutoff").map(|c| c.settings.light_cutoff).collect();
        assert_eq!(cutoffs, vec![0.0, 1.0 / 256.0, 1.0 / 64.0, 1.0 / 16.0]);
        let depth = full.iter().filter(|c| c.group == "depth" && c.scene == Some("far-origin")).count();
        assert_eq!(depth, 4, "far-origin under both depth formats and both conventions");
        let mut only = BenchOptions::new("demo", true);
        only.groups = vec!["tessellation".into()];
        assert!(configs(&only).iter().all(|c| c.group == "tessellation"));
    }

    #[test]
    fn the_pareto_front_is_per_scene_light_count_and_size() {
        let row = |label: &str, scene: &str, ms: f64, flip: f32| Row {
            group: "g".into(),
            label: label.into(),
            scene: scene.into(),
            culling: String::new(),
            layout: String::new(),
            accumulation: String::new(),
            reversed_z: false,
            depth_format: String::new(),
            light_cutoff: 0.0,
            sphere_subdivisions: 1,
            cone_sides: 12,
            volumes: String::new(),
            lights: 10,
            width: 8,
            height: 8,
            gbuffer_ms: 0.0,
            lighting_ms: 0.0,
            compose_ms: 0.0,
            forward_ms: 0.0,
            total_ms: ms,
            coverage_fragments: 0,
            shaded_fragments: 0,
            ideal_fragments: 0,
            efficiency: 0.0,
            gbuffer_bytes_per_pixel: 0,
            flip_mean: flip,
            max_abs_light_error: 0.0,
            psnr_db: 0.0,
            pareto: false,
        };
        let mut rows = vec![
            row("fast", "a", 1.0, 0.02),
            row("exact", "a", 5.0, 0.001),
            row("dominated", "a", 6.0, 0.01),
            // Another scene is not compared with scene a.
            row("other", "b", 9.0, 0.5),
        ];
        mark_pareto(&mut rows);
        let front: Vec<&str> = rows.iter().filter(|r| r.pareto).map(|r| r.label.as_str()).collect();
        assert_eq!(front, vec!["fast", "exact", "other"]);
    }
}
