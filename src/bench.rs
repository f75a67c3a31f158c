//! Speed against error: `lampshade bench` renders one scene under many configurations, times
//! each pass (median of N frames, GPU timestamps), counts fragments, and measures the error of
//! each image against a reference rendered without deferred approximations (every light
//! full-screen, an Rgba32Float G-buffer with stored position, Rgba32Float accumulation).
//! Output: `bench.csv`, `bench.md` and `bench.png` (time against error, Pareto front marked).

use crate::compare::flip;
use crate::gpu::Gpu;
use crate::headless::render_image;
use crate::renderer::post::{Aa, Tonemap};
use crate::renderer::{
    AccumFormat, CullingMode, DepthFormat, ForwardLights, FrameStats, LayoutChoice, RenderPath, Renderer, Settings,
    ShadowCube, ShadowFilter, ShadowMode, OUTPUT_FORMAT,
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

/// A configuration the bench did not run, and why: the scene cannot take it (a G-buffer layout
/// with no channel for the material ID a multi-material scene needs, say) or the adapter cannot
/// give it. It is listed in the report and on the console; the sweep goes on without it.
#[derive(Clone, Debug, Serialize)]
pub struct Skipped {
    pub group: String,
    pub label: String,
    pub scene: String,
    pub reason: String,
}

/// What a sweep gives: a row per configuration that ran, and the configurations it skipped.
#[derive(Clone, Debug, Default)]
pub struct BenchRun {
    pub rows: Vec<Row>,
    pub skipped: Vec<Skipped>,
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
    /// Every light's radius times this (the `radius` group; 1 elsewhere).
    pub radius_scale: f64,
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
    /// The scene's light radii were scaled by this (the `radius` group; 1 elsewhere).
    pub radius_scale: f64,
    pub width: u32,
    pub height: u32,
    pub gbuffer_ms: f64,
    pub lighting_ms: f64,
    pub compose_ms: f64,
    /// The forward pass of blended surfaces (0 without any).
    pub forward_ms: f64,
    /// The post chain's passes (0 where a pass did not run).
    pub bloom_ms: f64,
    pub exposure_ms: f64,
    pub tonemap_ms: f64,
    pub grading_ms: f64,
    pub fog_ms: f64,
    pub dof_ms: f64,
    pub vignette_ms: f64,
    pub aa_ms: f64,
    pub total_ms: f64,
    /// Light draws of a timed (uncounted) frame, and the batches they draw.
    pub draw_calls: u64,
    pub light_batches: u64,
    pub coverage_fragments: u64,
    pub shaded_fragments: u64,
    pub ideal_fragments: u64,
    pub efficiency: f64,
    pub gbuffer_bytes_per_pixel: u32,
    pub flip_mean: f32,
    pub max_abs_light_error: f32,
    pub psnr_db: f64,
    pub pareto: bool,
    /// The culling mode of the reference this row's error is measured against: `fullscreen`,
    /// or `volume` where a full-screen reference would take minutes (see [`reference_culling`]).
    pub reference: String,
    /// `total_ms` over the same run's `limit` row for this scene, light count, size and radius
    /// (NaN where the group has none; 1 on the `limit` row itself).
    pub limit_ratio: f64,
    /// The rendering path's figures (the `path` group; defaults elsewhere).
    pub path: PathFigures,
    /// The shadow maps' figures (every row, NaN/0 without shadows).
    pub shadow: ShadowFigures,
}

/// What the `shadows` group compares: the shadow pass's cost and memory. Its time
/// is part of `total_ms` (the G-buffer to the compose, plus the shadow pass before them).
#[derive(Clone, Debug, Serialize)]
pub struct ShadowFigures {
    /// Median GPU ms of the shadow pass (the atlas's render pass and the cube array's layers;
    /// NaN when nothing cast).
    pub gpu_ms: f64,
    /// Bytes of the atlas and the cube array as allocated.
    pub bytes: u64,
    /// Lights (the sun counted) with shadows, and those that fell back for the budget.
    pub casting: u32,
    pub fallback_budget: u32,
    /// Lights that should cast but are off screen (unshadowed, counted).
    pub fallback_off_screen: u32,
    /// `--shadow-cube`, and the cube array's face side (0 with `unrolled`).
    pub cube: String,
    pub cube_side: u32,
}

impl Default for ShadowFigures {
    fn default() -> Self {
        Self {
            gpu_ms: f64::NAN,
            bytes: 0,
            casting: 0,
            fallback_budget: 0,
            fallback_off_screen: 0,
            cube: "-".into(),
            cube_side: 0,
        }
    }
}

impl ShadowFigures {
    fn of(stats: &FrameStats, times: &[FrameStats]) -> Self {
        let Some(sh) = &stats.shadow else { return Self::default() };
        Self {
            gpu_ms: median(times.iter().filter_map(|t| t.shadow.as_ref().and_then(|s| s.gpu_ms)).collect()),
            bytes: sh.bytes(),
            casting: sh.casting,
            fallback_budget: sh.fallback_budget,
            fallback_off_screen: sh.fallback_off_screen,
            cube: sh.cube.name(),
            cube_side: sh.cube_side,
        }
    }
}

/// What the `path` group compares between rendering paths.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PathFigures {
    /// `RenderPath::name`.
    pub path: String,
    /// Render passes up to the compose or tonemap (included): deferred's G-buffer, lights,
    /// compose; forward's depth pass, shading (or ambient + sun and the pairs), tonemap.
    pub passes: u32,
    /// Bytes per pixel of every intermediate target, samples included (G-buffer, depth-stencil,
    /// light accumulation or HDR colour, MSAA targets and their resolve).
    pub target_bytes_per_pixel: u32,
    /// Entries of the forward paths' object light lists: the (object, light) pairs the
    /// multi-pass path draws (filled in for every path of the same scene and light count).
    pub object_light_pairs: u64,
    /// Lit pixels: the deferred path's shaded light fragments for the same scene and light
    /// count (filled in for every path).
    pub lit_fragments: u64,
    /// Every draw of the frame up to the compose or tonemap: deferred's object draws into the
    /// G-buffer, its light draws, the compose; the forward paths' draws of every pass and the
    /// tonemap.
    pub draw_calls: u64,
    /// Opaque and masked objects drawn (from the forward rows; filled in for every path).
    pub objects: u64,
    /// Why the path could not render (empty when it did); the row has no figures then.
    pub error: String,
}

/// The cut-off thresholds the `cutoff` group sweeps (fractions of each light's peak).
pub const CUTOFFS: [(f32, &str); 4] = [(0.0, "0"), (1.0 / 256.0, "1/256"), (1.0 / 64.0, "1/64"), (1.0 / 16.0, "1/16")];

/// The sweep. Every configuration differs from the default (`volume` culling, `compact`
/// layout, Rgba16Float accumulation, Depth32FloatStencil8, exact radii, an 80-triangle sphere
/// and a 12-sided cone) in one knob; `--quick` keeps a subset of each group.
pub fn configs(o: &BenchOptions) -> Vec<Config> {
    // Timed frames do not count: counting splits every batch's shading draw into a draw per
    // light (its occlusion query). The counts come from a separate counted render. Unshadowed:
    // shadows are the `shadows` group's knob, so every other row differs from its (unshadowed)
    // reference in its own knob only, and the tables from before shadows were on by default
    // are reproduced by the same commands.
    let base = Settings {
        count_fragments: false,
        count_ideal: false,
        timestamps: true,
        shadows: ShadowMode::None,
        ..Settings::default()
    };
    let c = |group, label: String, settings: Settings, lights| Config {
        group,
        label,
        settings,
        lights,
        size: o.size,
        scene: None,
        radius_scale: 1.0,
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
    // Where each culling mode wins, over the light count: every mode at every count, but
    // `fullscreen` (every light over every pixel) only where a frame takes seconds, not minutes.
    // A file's added lights each reach past the model's centre (a dome around it), so their
    // cost grows much faster with the count than the demo's small lights.
    let counts: &[usize] = match (crate::scene::import::is_gltf_path(&o.scene), o.quick) {
        (_, _) if o.fixed_lights => &[],
        (true, true) => &[16, 64],
        (true, false) => &[16, 64, 256],
        (false, true) => &[16, 1024],
        (false, false) => &LIGHT_COUNTS,
    };
    for &n in counts {
        for mode in CullingMode::ALL {
            if mode == CullingMode::Fullscreen && n > FULLSCREEN_MAX_LIGHTS {
                continue;
            }
            v.push(c("lights", format!("{} x{n}", mode.name()), Settings { culling: mode, ..base.clone() }, n));
        }
    }
    // Over the light radius: every mode with each light's radius scaled (the bench's light
    // count; a file's own lights are scaled too).
    let scales: &[f64] = if q { &[0.5, 2.0] } else { &RADIUS_SCALES };
    for &radius_scale in scales {
        for mode in CullingMode::ALL {
            let label = format!("{} r x{radius_scale}", mode.name());
            let settings = Settings { culling: mode, ..base.clone() };
            v.push(Config { radius_scale, ..c("radius", label, settings, o.lights) });
        }
    }
    // Seed 000's ambient + sun written by the G-buffer pass (the default) against a full-screen
    // pass of their own.
    for ambient_in_gbuffer in [true, false] {
        let label = if ambient_in_gbuffer { "ambient in g-buffer pass" } else { "ambient own pass" };
        v.push(c("ambient", label.into(), Settings { ambient_in_gbuffer, ..base.clone() }, o.lights));
    }
    // The forward pass's light lists (the same picture each; its time is `forward_ms`; only
    // scenes with blended surfaces, e.g. `glass`, have a forward pass).
    for forward_lights in ForwardLights::ALL {
        let label = format!("forward {}", forward_lights.name());
        v.push(c("forward", label, Settings { forward_lights, ..base.clone() }, o.lights));
    }
    // The rendering paths side by side (seed 002): every path over the light count,
    // and on the room. A path that cannot render on this build is a row saying why.
    let counts: &[usize] = if o.fixed_lights {
        &[]
    } else if q {
        &[64, 256]
    } else {
        &PATH_LIGHT_COUNTS
    };
    for &n in counts {
        for path in RenderPath::ALL {
            v.push(c("path", format!("{} x{n}", path.name()), Settings { path, ..base.clone() }, n));
        }
    }
    for path in RenderPath::ALL {
        let label = format!("{} room", path.name());
        v.push(Config { scene: Some(ROOM), ..c("path", label, Settings { path, ..base.clone() }, o.lights) });
    }
    // The post chain, one effect at a time, then all of them; the light error is of
    // the accumulation, before post, so it is the `volume` row's in every one of these.
    let post: Vec<(&str, Settings)> = {
        let mut p = vec![
            ("post off", base.clone()),
            ("bloom", Settings { bloom: true, ..base.clone() }),
            ("auto-exposure", Settings { auto_exposure: true, ..base.clone() }),
        ];
        let curves: &[Tonemap] = if q { &[Tonemap::Agx] } else { &Tonemap::ALL };
        p.extend(curves.iter().map(|&t| {
            let label: &'static str = match t {
                Tonemap::Aces => "tonemap aces (chain)",
                Tonemap::Reinhard => "tonemap reinhard",
                Tonemap::Agx => "tonemap agx",
                Tonemap::PbrNeutral => "tonemap pbr-neutral",
                Tonemap::None => "tonemap none",
            };
            // ACES alone is compose's own curve; the identity LUT takes it through the chain.
            let lut = (t == Tonemap::Aces).then(|| "identity".to_string());
            (label, Settings { tonemap: t, lut, ..base.clone() })
        }));
        p.push(("lut identity", Settings { lut: Some("identity".into()), tonemap: Tonemap::Agx, ..base.clone() }));
        // After tone mapping (AgX, so the chain runs for the curve alone in `tonemap agx`).
        let ldr = Settings { tonemap: Tonemap::Agx, ..base.clone() };
        p.push(("fog", Settings { fog: true, ..ldr.clone() }));
        p.push(("dof", Settings { dof: true, ..ldr.clone() }));
        p.push(("vignette", Settings { vignette: 0.5, ..ldr.clone() }));
        p.push(("aa edge", Settings { aa: Aa::Edge, ..ldr.clone() }));
        p.push(("aa fxaa", Settings { aa: Aa::Fxaa, ..ldr.clone() }));
        p.push((
            "all on",
            Settings {
                bloom: true,
                auto_exposure: true,
                lut: Some("identity".into()),
                fog: true,
                dof: true,
                vignette: 0.5,
                aa: Aa::Edge,
                ..ldr.clone()
            },
        ));
        p
    };
    for (label, settings) in post {
        v.push(c("post", label.into(), settings, o.lights));
    }
    // Shadows of the sun and the spots, against the finest shadows (`shadow_reference`):
    // atlas size, kernel, cascades. (Point lights' cube array is not built; the unrolled cube is
    // the only layout.)
    let shadowed = Settings { shadows: ShadowMode::Spots, ..base.clone() };
    let mut sh = vec![("none".to_string(), Settings { shadows: ShadowMode::None, ..base.clone() })];
    for mb in if q { vec![4.0, 64.0] } else { vec![1.0, 4.0, 16.0, 64.0] } {
        sh.push((format!("atlas {mb} MiB"), Settings { shadow_budget_mb: mb, ..shadowed.clone() }));
    }
    for f in [ShadowFilter::Pcf2x2, ShadowFilter::Poisson16] {
        sh.push((f.name(), Settings { shadow_filter: f, ..shadowed.clone() }));
    }
    for n in if q { vec![1, 4] } else { vec![1, 2, 4] } {
        sh.push((format!("{n} cascades"), Settings { shadow_cascades: n, ..shadowed.clone() }));
    }
    for (label, settings) in sh {
        v.push(c("shadows", label, settings, o.lights));
    }
    // Point lights' six faces (every light casting; `CUBE_LIGHTS` point lights, plus the
    // scene's spots): unrolled into the atlas (seed 002's virtual cube) or a cube array, at the
    // default budget, against the finest shadows of `all` (`shadow_reference`).
    for cube in [ShadowCube::Unrolled, ShadowCube::Array] {
        let settings = Settings { shadows: ShadowMode::All, shadow_cube: cube, ..base.clone() };
        v.push(c("shadows", format!("cube {}", cube.name()), settings, CUBE_LIGHTS));
    }
    v.retain(|c| o.groups.is_empty() || o.groups.iter().any(|g| g == c.group));
    v
}

/// Point lights of the `shadows` group's cube rows (each casts six faces).
pub const CUBE_LIGHTS: usize = 16;

/// The light counts of the `path` group (plus the room, with its own lights).
pub const PATH_LIGHT_COUNTS: [usize; 3] = [64, 256, 1024];
/// The project's glTF room, the `path` group's second scene.
pub const ROOM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf");

/// The configuration groups, for `--only`.
pub const GROUPS: &[&str] = &[
    "culling",
    "layout",
    "accumulation",
    "depth",
    "cutoff",
    "tessellation",
    "resolution",
    "lights",
    "radius",
    "ambient",
    "forward",
    "post",
    "shadows",
    "path",
];

/// The light counts the full sweep's `lights` group runs every mode at (plus the scene's spots).
pub const LIGHT_COUNTS: [usize; 5] = [64, 256, 1024, 4096, 16384];
/// `fullscreen` runs in the `lights` group only up to this many lights: at 1280x720 each light is
/// 0.9 M fragments (~17 ns each on lavapipe), so 256 lights are ~4 s a frame and 16,384 would be
/// over four minutes.
pub const FULLSCREEN_MAX_LIGHTS: usize = 256;
/// The radius factors of the `radius` group.
pub const RADIUS_SCALES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];
/// A reference frame is rendered with every light full-screen while lights x pixels stays under
/// this (about 40 s on lavapipe); above it the reference draws plain volumes, which every
/// culling test holds equal to full-screen within one 8-bit step (`tests/it/culling.rs`), so the
/// error figures stay those of the layout and accumulation, not of a culling approximation.
pub const REFERENCE_FULLSCREEN_BUDGET: f64 = 2.5e9;

/// The culling mode of the reference frame for `lights` lights at `size`.
pub fn reference_culling(lights: usize, size: (u32, u32)) -> CullingMode {
    if lights as f64 * size.0 as f64 * size.1 as f64 <= REFERENCE_FULLSCREEN_BUDGET {
        CullingMode::Fullscreen
    } else {
        CullingMode::Volume
    }
}

/// Scales every light's radius (and so its reach and volume) by `k`.
pub fn scale_light_radii(scene: &mut crate::Scene, k: f64) {
    for l in &mut scene.lights {
        match l {
            crate::scene::Light::Point(p) => p.radius *= k as f32,
            crate::scene::Light::Spot(s) => s.radius *= k as f32,
        }
    }
}

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

fn reference(gpu: &Gpu, scene: &crate::Scene, size: (u32, u32), shadows: ShadowMode) -> Result<Reference> {
    let settings = Settings {
        culling: reference_culling(scene.lights.len(), size),
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        count_fragments: false,
        timestamps: false,
        ..shadow_reference(shadows)
    };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings)?;
    let (image, _) = render_image(gpu, &mut r, scene, &settings, size.0, size.1)?;
    let (d, s) = r.read_accumulation(gpu)?;
    let light: Vec<f32> = d.into_iter().chain(s).collect();
    let peak = light.iter().copied().filter(|v| v.is_finite()).fold(0.0, f32::max);
    Ok(Reference { image, light, peak })
}

/// Runs the sweep; `progress(done, total, label)` is called before each configuration.
/// Runs the sweep. A configuration that cannot be built or rendered for this scene on this
/// adapter is skipped with its reason (a `path` row is kept instead, saying why); only a failure
/// to open the scene, or one after a configuration's first frame rendered, ends the run.
pub fn run(gpu: &Gpu, o: &BenchOptions, mut progress: impl FnMut(usize, usize, &str)) -> Result<BenchRun> {
    let list = configs(o);
    let frames = o.frames.max(1);
    // Steps: prepare each configuration, `frames` timed rounds, then count and compare each.
    let steps = list.len() * 2 + frames;
    // Prepare every configuration (scene, renderer, a warm-up frame for shader JIT). A file is
    // read once per light count.
    let mut prepared = Vec::new();
    let mut failed: Vec<(&Config, usize, String)> = Vec::new();
    let mut skipped: Vec<Skipped> = Vec::new();
    let mut scenes: HashMap<(&str, usize, u64), crate::Scene> = HashMap::new();
    for (k, cfg) in list.iter().enumerate() {
        progress(k, steps, &format!("prepare {}", cfg.label));
        let name = cfg.scene.unwrap_or(&o.scene);
        let lights = (!o.fixed_lights || cfg.scene.is_some()).then_some(cfg.lights);
        let scene = match scenes.entry((name, cfg.lights, cfg.radius_scale.to_bits())) {
            std::collections::hash_map::Entry::Occupied(e) => e.get().clone(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let options = crate::scene::import::ImportOptions::default();
                let (mut scene, _) =
                    crate::scene::open(name, BuiltinOptions { lights, time: o.time }, &options, &mut |_| {})?;
                scale_light_radii(&mut scene, cfg.radius_scale);
                e.insert(scene).clone()
            }
        };
        let skip = |e: anyhow::Error| Skipped {
            group: cfg.group.into(),
            label: cfg.label.clone(),
            scene: name.to_string(),
            reason: format!("{e:#}"),
        };
        let mut renderer = match Renderer::new(gpu, OUTPUT_FORMAT, &cfg.settings) {
            Ok(r) => r,
            Err(e) => {
                skipped.push(skip(e));
                continue;
            }
        };
        if let Err(e) = render_image(gpu, &mut renderer, &scene, &cfg.settings, cfg.size.0, cfg.size.1) {
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
    // By scene, light count, size and radius factor (bits).
    type RefKey<'a> = (&'a str, usize, (u32, u32), u64, ShadowMode);
    let mut refs: HashMap<RefKey, Reference> = HashMap::new();
    let mut rows = Vec::new();
    for (k, (cfg, scene, mut renderer, times)) in prepared.into_iter().enumerate() {
        progress(list.len() + frames + k, steps, &format!("error of {}", cfg.label));
        let (w, h) = cfg.size;
        // The `shadows` group (its `none` row too) is held against the finest shadows (of every
        // light for the cube rows).
        let shadows = match cfg.group {
            "shadows" if cfg.settings.shadows == ShadowMode::All => ShadowMode::All,
            "shadows" => ShadowMode::Spots,
            _ => ShadowMode::None,
        };
        let key = (cfg.scene.unwrap_or(&o.scene), cfg.lights, cfg.size, cfg.radius_scale.to_bits(), shadows);
        let reference = match refs.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(reference(gpu, &scene, cfg.size, shadows)?),
        };
        let pick = |f: fn(&FrameStats) -> Option<f64>| median(times.iter().filter_map(f).collect());
        let counted = Settings { count_fragments: true, count_ideal: true, timestamps: false, ..cfg.settings.clone() };
        let (image, stats) = render_image(gpu, &mut renderer, &scene, &counted, w, h)?;
        let (d, s) = renderer.read_accumulation(gpu)?;
        let figures = path_figures(gpu, &cfg.settings, &renderer, &stats)?;
        // The forward paths have no light accumulation: their error is FLIP's alone.
        let accumulated = stats.forward_path.is_none();
        // FLIP compares output images; a frame through the post chain is not the reference's
        // picture by design, so its row has none (NaN). The light error and PSNR are of the
        // accumulation, before post, in every row.
        let chain = crate::renderer::post::chain_active(&cfg.settings);
        let flip_mean = if chain { f32::NAN } else { flip(&reference.image, &image)?.0.mean };
        let mut max_err = 0f32;
        let mut sq = 0f64;
        for (a, b) in d.iter().chain(s.iter()).zip(&reference.light) {
            let e = if a.is_finite() { (a - b).abs() } else { f32::INFINITY };
            max_err = max_err.max(e);
            sq += (e as f64).powi(2);
        }
        let mse = sq / reference.light.len().max(1) as f64;
        let mut psnr = if mse > 0.0 { 10.0 * ((reference.peak as f64).powi(2) / mse).log10() } else { f64::INFINITY };
        if cfg.settings.path != crate::renderer::RenderPath::Deferred {
            // The light error compares deferred's accumulation (ambient + sun, specular times
            // reflectance) with the reference's; the other paths hold no such buffer (the light
            // pre-pass's is unit-reflectance light without ambient): their error is FLIP's, on
            // the final picture.
            (max_err, psnr) = (f32::NAN, f64::NAN);
        }
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
            radius_scale: cfg.radius_scale,
            width: w,
            height: h,
            gbuffer_ms: pick(|s| s.gpu_ms.gbuffer),
            lighting_ms: pick(|s| s.gpu_ms.lighting),
            compose_ms: pick(|s| s.gpu_ms.compose),
            forward_ms: pick(|s| s.gpu_ms.forward.or(s.gpu_ms.total.map(|_| 0.0))),
            bloom_ms: pick(|s| s.gpu_ms.bloom.or(s.gpu_ms.total.map(|_| 0.0))),
            exposure_ms: pick(|s| s.gpu_ms.exposure.or(s.gpu_ms.total.map(|_| 0.0))),
            tonemap_ms: pick(|s| s.gpu_ms.tonemap.or(s.gpu_ms.total.map(|_| 0.0))),
            grading_ms: pick(|s| s.gpu_ms.grading.or(s.gpu_ms.total.map(|_| 0.0))),
            fog_ms: pick(|s| s.gpu_ms.fog.or(s.gpu_ms.total.map(|_| 0.0))),
            dof_ms: pick(|s| s.gpu_ms.dof.or(s.gpu_ms.total.map(|_| 0.0))),
            vignette_ms: pick(|s| s.gpu_ms.vignette.or(s.gpu_ms.total.map(|_| 0.0))),
            aa_ms: pick(|s| s.gpu_ms.aa.or(s.gpu_ms.total.map(|_| 0.0))),
            total_ms: pick(|s| s.gpu_ms.total),
            draw_calls: times.last().map_or(0, |s| s.draw_calls),
            light_batches: times.last().map_or(0, |s| s.light_batches),
            coverage_fragments: stats.coverage_fragments.unwrap_or(0),
            shaded_fragments: stats.shaded_fragments.unwrap_or_else(|| forward_shaded(&stats)),
            ideal_fragments: stats.ideal_fragments.unwrap_or(0),
            efficiency: stats.efficiency.unwrap_or(f64::NAN),
            gbuffer_bytes_per_pixel: stats.gbuffer_bytes_per_pixel,
            flip_mean,
            max_abs_light_error: if accumulated { max_err } else { f32::NAN },
            psnr_db: if accumulated { psnr } else { f64::NAN },
            pareto: false,
            reference: reference_culling(scene.lights.len(), cfg.size).name(),
            limit_ratio: f64::NAN,
            path: figures,
            shadow: ShadowFigures::of(&stats, &times),
        });
    }
    for (cfg, lights, error) in failed {
        rows.push(failed_row(cfg, &o.scene, lights, error));
    }
    fill_path_siblings(&mut rows);
    progress(steps, steps, "done");
    mark_pareto(&mut rows);
    add_limits(&mut rows);
    Ok(BenchRun { rows, skipped })
}

/// The report's list of skipped configurations (empty when none was).
pub fn skipped_markdown(skipped: &[Skipped]) -> String {
    if skipped.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\n### Skipped ({})\n\nConfigurations this scene or adapter cannot take; the rest of the sweep ran without them.\n\n\
         | group | configuration | scene | reason |\n|---|---|---|---|\n",
        skipped.len()
    );
    for k in skipped {
        s += &format!(
            "| {} | {} | {} | {} |\n",
            k.group,
            k.label,
            k.scene,
            k.reason.replace('|', "/").replace('\n', " ")
        );
    }
    s
}

/// The `path` figures of a rendered frame: passes, target bytes per pixel, list entries.
fn path_figures(gpu: &Gpu, settings: &Settings, renderer: &Renderer, stats: &FrameStats) -> Result<PathFigures> {
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
        let accum = bytes(settings.accumulation.format(gpu.features)?);
        // G-buffer, lights, compose; the HDR colour when blended surfaces or post need it.
        let hdr = stats.forward.is_some() || stats.post.is_some();
        f.passes = 3;
        // Its light draws, the ambient + sun draw when it is not the G-buffer pass's, the
        // compose (the G-buffer's object draws are added from the forward rows).
        f.draw_calls = stats.draw_calls + !stats.ambient_in_gbuffer as u64 + 1;
        f.target_bytes_per_pixel = stats.gbuffer_bytes_per_pixel
            + bytes(renderer.depth_format())
            + 2 * accum
            + if hdr { bytes(crate::renderer::passes::HDR_FORMAT) } else { 0 };
    }
    Ok(f)
}

/// Bytes per pixel of the renderer's depth-stencil target.
fn renderer_depth_bytes(renderer: &Renderer) -> u32 {
    let format = renderer.depth_format();
    format.block_copy_size(None).unwrap_or_else(|| {
        format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)).unwrap_or(4)
            + format.block_copy_size(Some(wgpu::TextureAspect::StencilOnly)).unwrap_or(0)
    })
}

/// Samples the forward paths' shading passes passed (single-pass's shading, multi-pass's
/// ambient + sun and pairs; not the depth pass) when counted.
fn forward_shaded(stats: &FrameStats) -> u64 {
    stats.forward_path.as_ref().map_or(0, |fp| {
        fp.passes
            .iter()
            .filter(|p| p.name != "depth" && !p.name.starts_with("g-buffer"))
            .filter_map(|p| p.fragments)
            .sum()
    })
}

/// The row of a path configuration that failed to render: its error, no figures.
fn failed_row(cfg: &Config, scene: &str, lights: usize, error: String) -> Row {
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
        grading_ms: f64::NAN,
        fog_ms: f64::NAN,
        dof_ms: f64::NAN,
        vignette_ms: f64::NAN,
        aa_ms: f64::NAN,
        total_ms: f64::NAN,
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
    }
}

/// Gives every `path` row of a scene and light count the forward rows' pair count and the
/// deferred row's lit fragments, so each path can be plotted against both.
fn fill_path_siblings(rows: &mut [Row]) {
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

/// The groups whose rows are culling modes, and so get a `limit` row.
pub const LIMIT_GROUPS: [&str; 3] = ["culling", "lights", "radius"];

/// What a frame could cost if lighting did only the ideal work: G-buffer ms + compose ms + ideal
/// fragments x `fullscreen`'s lighting ms per shaded fragment, all from the same run. The
/// shadow pass, when lights cast, is a fixed pass like the G-buffer: `gbuffer_ms` holds both.
/// `fullscreen` shades every pixel for every light, so its ms per fragment is the price of one
/// light-fragment evaluation with no per-draw or culling overhead worth counting (1,028 lights x
/// 0.9 M fragments); the ideal is the fragments inside the lights' true shapes. G-buffer and
/// compose do the same work in every mode, so their medians over the key's rows are used.
pub fn limit_ms(gbuffer_ms: f64, compose_ms: f64, ideal: u64, ms_per_fragment: f64) -> f64 {
    gbuffer_ms + compose_ms + ideal as f64 * ms_per_fragment
}

/// Adds a `limit` row after the last row of each (group, scene, light count, size, radius) among
/// [`LIMIT_GROUPS`], and sets every such row's `limit_ratio`. The ms per fragment comes from the
/// `fullscreen` row of the same scene and size (same light count and radius if the run has one,
/// else the one with the most shaded fragments); without any `fullscreen` row there is no limit.
pub fn add_limits(rows: &mut Vec<Row>) {
    type Key = (String, String, usize, u32, u32, u64);
    let key = |r: &Row| (r.group.clone(), r.scene.clone(), r.lights, r.width, r.height, r.radius_scale.to_bits());
    let full: Vec<Row> = rows
        .iter()
        .filter(|r| r.culling == "fullscreen" && r.label != "limit" && r.shaded_fragments > 0)
        .cloned()
        .collect();
    let per_fragment = |k: &Key| -> Option<f64> {
        let same = |r: &&Row| r.scene == k.1 && r.width == k.3 && r.height == k.4;
        let exact = full.iter().find(|r| same(r) && r.lights == k.2 && r.radius_scale.to_bits() == k.5);
        let best = exact.or_else(|| full.iter().filter(same).max_by_key(|r| r.shaded_fragments))?;
        Some(best.lighting_ms / best.shaded_fragments as f64)
    };
    let mut keys: Vec<Key> = Vec::new();
    for r in rows.iter().filter(|r| LIMIT_GROUPS.contains(&r.group.as_str())) {
        if !keys.contains(&key(r)) {
            keys.push(key(r));
        }
    }
    for k in keys {
        let Some(ms_per_fragment) = per_fragment(&k) else { continue };
        let mine: Vec<&Row> = rows.iter().filter(|r| key(r) == k).collect();
        let Some(first) = mine.first() else { continue };
        let gbuffer = median(mine.iter().map(|r| r.gbuffer_ms).filter(|v| v.is_finite()).collect());
        // NaN where nothing cast: no shadow pass ran.
        let shadows = median(mine.iter().map(|r| r.shadow.gpu_ms).filter(|v| v.is_finite()).collect());
        let compose = median(mine.iter().map(|r| r.compose_ms).filter(|v| v.is_finite()).collect());
        // Every mode counts the same ideal (tested); the largest guards against a row that did
        // not count it.
        let ideal = mine.iter().map(|r| r.ideal_fragments).max().unwrap_or(0);
        let lighting = ideal as f64 * ms_per_fragment;
        let limit =
            limit_ms(gbuffer + if shadows.is_finite() { shadows } else { 0.0 }, compose, ideal, ms_per_fragment);
        let row = Row {
            label: "limit".into(),
            culling: "limit".into(),
            volumes: "-".into(),
            gbuffer_ms: gbuffer,
            lighting_ms: lighting,
            compose_ms: compose,
            forward_ms: 0.0,
            total_ms: limit,
            coverage_fragments: 0,
            shaded_fragments: ideal,
            ideal_fragments: ideal,
            efficiency: 1.0,
            flip_mean: f32::NAN,
            max_abs_light_error: f32::NAN,
            psnr_db: f64::NAN,
            pareto: false,
            limit_ratio: 1.0,
            draw_calls: 0,
            light_batches: 0,
            ..(*first).clone()
        };
        for r in rows.iter_mut().filter(|r| key(r) == k) {
            r.limit_ratio = r.total_ms / limit;
        }
        let at = rows.iter().rposition(|r| key(r) == k).map_or(rows.len(), |i| i + 1);
        rows.insert(at, row);
    }
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
         lights,radius_scale,width,height,gbuffer_ms,lighting_ms,compose_ms,forward_ms,bloom_ms,exposure_ms,tonemap_ms,grading_ms,fog_ms,dof_ms,vignette_ms,aa_ms,total_ms,draw_calls,light_batches,\
         coverage_fragments,shaded_fragments,ideal_fragments,efficiency,gbuffer_bytes_per_pixel,flip_mean,max_abs_light_error,psnr_db,pareto,\
         reference,limit_ratio,path,passes,target_bytes_per_pixel,object_light_pairs,lit_fragments,error,\
         shadow_ms,shadow_bytes,shadow_casting,shadow_fallback_budget,shadow_fallback_off_screen,shadow_cube,shadow_cube_side\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{},{},{},{},{},{:.4},{},{:.6},{:.6},{:.2},{},{},{:.3},{},{},{},{},{},\"{}\",{:.3},{},{},{},{},{},{}\n",
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
            r.radius_scale,
            r.width,
            r.height,
            r.gbuffer_ms,
            r.lighting_ms,
            r.compose_ms,
            r.forward_ms,
            r.bloom_ms,
            r.exposure_ms,
            r.tonemap_ms,
            r.grading_ms,
            r.fog_ms,
            r.dof_ms,
            r.vignette_ms,
            r.aa_ms,
            r.total_ms,
            r.draw_calls,
            r.light_batches,
            r.coverage_fragments,
            r.shaded_fragments,
            r.ideal_fragments,
            r.efficiency,
            r.gbuffer_bytes_per_pixel,
            r.flip_mean,
            r.max_abs_light_error,
            r.psnr_db,
            r.pareto,
            r.reference,
            r.limit_ratio,
            r.path.path,
            r.path.passes,
            r.path.target_bytes_per_pixel,
            r.path.object_light_pairs,
            r.path.lit_fragments,
            r.path.error.replace('"', "'").replace(',', ";"),
            r.shadow.gpu_ms,
            r.shadow.bytes,
            r.shadow.casting,
            r.shadow.fallback_budget,
            r.shadow.fallback_off_screen,
            r.shadow.cube,
            r.shadow.cube_side
        );
    }
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

pub fn markdown(run: &BenchRun, gpu_name: &str, o: &BenchOptions) -> String {
    let rows = &run.rows[..];
    let mut s = format!(
        "Scene `{}`, time {}, adapter {gpu_name}; GPU ms are medians of {} frames; error against the reference \
         (full-screen lights, Rgba32Float G-buffer and accumulation), measured before post: the light error and PSNR \
         on the light accumulation, FLIP on the output only for frames without the post chain (`-` in the `post` rows). Ratio: lighting time over `fullscreen`'s in the \
         same run and size. * = on the Pareto front (time, FLIP) for its scene, light count and size. \
         Volumes: the bounding meshes the frame drew (only the kinds its lights need). \
         `limit` (groups culling, lights, radius): G-buffer ms + compose ms + ideal fragments x `fullscreen`'s \
         lighting ms per shaded fragment, from this run; `x limit` is each row's total over it.\n\n",
        o.scene, o.time, o.frames
    );
    let volume_refs: Vec<String> = rows
        .iter()
        .filter(|r| r.reference != "fullscreen" && r.label != "limit")
        .map(|r| format!("{} lights at {}x{}", r.lights, r.width, r.height))
        .fold(Vec::new(), |mut v, k| {
            if !v.contains(&k) {
                v.push(k);
            }
            v
        });
    if !volume_refs.is_empty() {
        s += &format!(
            "References drawn with plain volumes (a full-screen one would take minutes; volumes are tested equal to \
             full-screen within one 8-bit step): {}.\n\n",
            volume_refs.join(", ")
        );
    }
    s += "| group | configuration | lights | size | G-buffer B/px | volumes | gbuffer ms | shadows ms | lighting ms | forward ms | post ms (bloom/exposure/tonemap/grading/fog/dof/vignette/aa) | total ms | x limit | lighting ratio | draw calls (batches) | coverage | shaded | ideal | efficiency | FLIP mean | max abs light error | PSNR dB |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    let full: HashMap<(usize, u32, u32), f64> = rows
        .iter()
        .filter(|r| r.label == "fullscreen")
        .map(|r| ((r.lights, r.width, r.height), r.lighting_ms))
        .collect();
    for r in rows {
        let ratio = full
            .get(&(r.lights, r.width, r.height))
            .filter(|_| r.scene == o.scene)
            .filter(|_| r.label != "limit")
            .map_or("-".into(), |f| format!("{:.3}", r.lighting_ms / f));
        let x_limit = if r.limit_ratio.is_finite() { format!("{:.2}", r.limit_ratio) } else { "-".into() };
        let error = |v: f64, d: usize| if v.is_finite() { format!("{v:.d$}") } else { "-".into() };
        s += &format!(
            "| {} | {}{} | {} | {}x{} | {} | {} | {:.2} | {} | {:.2} | {:.2} | {} | {:.2} | {} | {} | {} ({}) | {} | {} | {} | {:.3} | {} | {} | {} |\n",
            r.group,
            r.label,
            if r.pareto { " *" } else { "" },
            r.lights,
            r.width,
            r.height,
            r.gbuffer_bytes_per_pixel,
            r.volumes,
            r.gbuffer_ms,
            if r.shadow.gpu_ms.is_finite() { format!("{:.2}", r.shadow.gpu_ms) } else { "-".into() },
            r.lighting_ms,
            r.forward_ms,
            if r.bloom_ms + r.exposure_ms + r.tonemap_ms + r.grading_ms > 0.0 {
                format!(
                    "{:.2}/{:.2}/{:.2}/{:.2}/{:.2}/{:.2}/{:.2}/{:.2}",
                    r.bloom_ms,
                    r.exposure_ms,
                    r.tonemap_ms,
                    r.grading_ms,
                    r.fog_ms,
                    r.dof_ms,
                    r.vignette_ms,
                    r.aa_ms
                )
            } else {
                "-".into()
            },
            r.total_ms,
            x_limit,
            ratio,
            r.draw_calls,
            r.light_batches,
            r.coverage_fragments,
            r.shaded_fragments,
            r.ideal_fragments,
            r.efficiency,
            error(r.flip_mean as f64, 5),
            error(r.max_abs_light_error as f64, 4),
            error(r.psnr_db, 1)
        );
    }
    s += &paths_markdown(rows);
    s += &shadows_markdown(rows);
    s += &skipped_markdown(&run.skipped);
    s
}

/// The `shadows` group's table: the shadow pass's GPU ms (outside `total ms`), the
/// bytes of the atlas and the cube array, who casts, and the error against the finest shadows.
pub fn shadows_markdown(rows: &[Row]) -> String {
    let shadows: Vec<&Row> = rows.iter().filter(|r| r.group == "shadows").collect();
    if shadows.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n### Shadows\n\n\
         Shadow ms: the shadow pass (atlas and cube array; `-` where nothing cast), part of `total ms`. \
         Bytes: the atlas and the cube array as allocated. Casting: lights with shadows (the sun counted); budget, \
         off screen: lights that fell back to unshadowed for the budget or for being off screen. FLIP mean against the finest shadows (64 MiB, poisson16, \
         4 cascades) of the same casters (`cube` rows: every light, cubes unrolled).\n\n\
         | configuration | lights | shadow ms | total ms | bytes | casting | budget | off screen | cube side | FLIP mean |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in shadows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {:.5} |\n",
            r.label,
            r.lights,
            if r.shadow.gpu_ms.is_finite() { format!("{:.2}", r.shadow.gpu_ms) } else { "-".into() },
            r.total_ms,
            r.shadow.bytes,
            r.shadow.casting,
            r.shadow.fallback_budget,
            r.shadow.fallback_off_screen,
            if r.shadow.cube == "array" { r.shadow.cube_side.to_string() } else { "-".into() },
            r.flip_mean
        );
    }
    s
}

/// The `path` group's table: per scene and light count, each path's intermediate
/// bytes per pixel, passes, draw calls, GPU ms and error; a path that failed says why.
pub fn paths_markdown(rows: &[Row]) -> String {
    let paths: Vec<&Row> = rows.iter().filter(|r| r.group == "path").collect();
    if paths.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n### Rendering paths\n\n\
         Bytes/pixel: every intermediate target, samples included. Passes: up to the compose or tonemap. \
         Draw calls: every draw up to the compose or tonemap (deferred: one per object into the G-buffer, its light draws, \
         the compose; light pre-pass: pass 1's and pass 3's object draws, its light draws and the tonemap; forward: every \
         pass's draws and the tonemap). \
         Pairs: entries of the forward object light lists, the (object, light) draws of multi-pass. \
         Lit: the deferred light pass's shaded fragments for that scene and count. \
         Shaded: fragments the path's shading passes shaded (deferred: light fragments). Error: FLIP mean against the reference.\n\n\
         | scene | lights | path | bytes/pixel | passes | draw calls | pairs | lit | shaded | GPU ms | FLIP mean |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in paths {
        let scene = std::path::Path::new(&r.scene).file_stem().map_or(r.scene.clone(), |f| f.to_string_lossy().into());
        if !r.path.error.is_empty() {
            s += &format!("| {scene} | {} | {} | error: {} | | | | | | | |\n", r.lights, r.path.path, r.path.error);
            continue;
        }
        s += &format!(
            "| {scene} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.5} |\n",
            r.lights,
            r.path.path,
            r.path.target_bytes_per_pixel,
            r.path.passes,
            r.path.draw_calls,
            r.path.object_light_pairs,
            r.path.lit_fragments,
            r.shaded_fragments,
            r.total_ms,
            r.flip_mean
        );
    }
    s
}

/// Seed 002's claim, plotted from the `path` group: GPU ms of each path against the (object,
/// light) pairs (left; forward multi-pass draws one per pair) and against the lit fragments
/// (right; deferred shades those), log-log, one series per path, the room ringed.
pub fn plot_paths(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let pts: Vec<&Row> = rows
        .iter()
        .filter(|r| r.group == "path" && r.path.error.is_empty() && r.total_ms.is_finite() && r.total_ms > 0.0)
        .collect();
    if pts.is_empty() {
        anyhow::bail!("no path row rendered");
    }
    let root = BitMapBackend::new(path, (1400, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, 2));
    let (t0, t1) = pts.iter().fold((f64::INFINITY, 0f64), |(a, b), r| (a.min(r.total_ms), b.max(r.total_ms)));
    let (t_lo, t_hi) = (t0 / 1.3, t1 * 1.3);
    let t_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
    let t_dec = crate::plot_layout::tick_decimals(&t_ticks);
    type Axis = fn(&Row) -> f64;
    let panels_spec: [(&str, &str, Axis); 2] = [
        ("GPU ms against (object, light) pairs", "(object, light) pairs", |r| r.path.object_light_pairs as f64),
        ("GPU ms against lit fragments (deferred)", "lit fragments", |r| r.path.lit_fragments as f64),
    ];
    for ((caption, x_desc, x), area) in panels_spec.into_iter().zip(panels.iter()) {
        let xs: Vec<f64> = pts.iter().map(|r| x(r)).filter(|v| *v > 0.0).collect();
        if xs.is_empty() {
            continue;
        }
        let (x_lo, x_hi) = xs.iter().fold((f64::INFINITY, 0f64), |(a, b), v| (a.min(*v), b.max(*v)));
        let (x_lo, x_hi) = (x_lo / 1.3, x_hi * 1.3);
        let x_ticks = crate::plot_layout::log_ticks(x_lo, x_hi);
        let x_dec = crate::plot_layout::tick_decimals(&x_ticks);
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 20))
            .margin(14)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (t_lo..t_hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("GPU ms per frame (median; room ringed)")
            .label_style(("sans-serif", 13))
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .draw()?;
        draw_ticks(&mut chart, area, (&x_ticks, x_dec), (&t_ticks, t_dec), (x_lo, x_hi), (t_lo, t_hi))?;
        for (i, p) in RenderPath::ALL.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let mut mine: Vec<(f64, f64, bool)> = pts
                .iter()
                .filter(|r| r.path.path == p.name() && x(r) > 0.0)
                .map(|r| (x(r), r.total_ms, r.scene == ROOM))
                .collect();
            if mine.is_empty() {
                continue;
            }
            mine.sort_by(|a, b| a.0.total_cmp(&b.0));
            let line: Vec<(f64, f64)> = mine.iter().filter(|m| !m.2).map(|m| (m.0, m.1)).collect();
            chart
                .draw_series(LineSeries::new(line, colour.stroke_width(2)))?
                .label(p.name())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            chart.draw_series(mine.iter().map(|&(x, y, room)| {
                if room {
                    Circle::new((x, y), 7, colour.stroke_width(2))
                } else {
                    Circle::new((x, y), 4, colour.filled())
                }
            }))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// Time (x) against FLIP error (y): one panel per group, one labelled point per configuration,
/// the default configuration (`culling` / `volume`) in grey in every panel for comparison, and
/// the Pareto front of the panel's scene, light count and size joined by a black line (points
/// on it ringed).
pub fn plot(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let pts: Vec<&Row> = rows
        .iter()
        .filter(|r| r.total_ms.is_finite() && r.total_ms > 0.0 && r.flip_mean.is_finite() && r.label != "limit")
        .collect();
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
    let palette = PALETTE;
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
        draw_ticks(&mut chart, area, (&x_ticks, x_dec), (&y_ticks, y_dec), (t_lo, t_hi), (0.0, e_hi))?;
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

/// Grid lines and labels at our own ticks (`plot_layout`): plotters' log axes label only
/// powers of ten, so both plots blank its labels and draw these. `x` and `y` are the ticks with
/// their decimals; the ranges are the plotted ones.
/// The plots' series colours, one per configuration or culling mode in order (both plots).
const PALETTE: [plotters::style::RGBColor; 8] = {
    use plotters::style::{RGBColor, BLUE, MAGENTA, RED};
    [
        RED,
        BLUE,
        RGBColor(0, 150, 0),
        MAGENTA,
        RGBColor(0, 150, 170),
        RGBColor(230, 120, 0),
        RGBColor(120, 70, 20),
        RGBColor(90, 90, 90),
    ]
};

fn draw_ticks<DB, X, Y>(
    chart: &mut plotters::chart::ChartContext<'_, DB, plotters::coord::cartesian::Cartesian2d<X, Y>>,
    area: &plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    (x_ticks, x_dec): (&[f64], usize),
    (y_ticks, y_dec): (&[f64], usize),
    (x_lo, x_hi): (f64, f64),
    (y_lo, y_hi): (f64, f64),
) -> Result<()>
where
    DB: plotters::prelude::DrawingBackend,
    DB::ErrorType: 'static,
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    use plotters::prelude::*;
    let font: TextStyle = ("sans-serif", 13).into_font().into();
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let base = area.get_base_pixel();
    let grid = RGBColor(225, 225, 225);
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("drawing the plot: {e}");
    for &v in x_ticks {
        chart.draw_series(LineSeries::new([(v, y_lo), (v, y_hi)], grid)).map_err(|e| err(&e))?;
        let text = format!("{v:.x_dec$}");
        let (w, _) = area.estimate_text_size(&text, &font).map_err(|e| err(&e))?;
        let (px, _) = chart.backend_coord(&(v, y_lo));
        area.draw(&Text::new(text, (px - w as i32 / 2 - base.0, yr.end + 4 - base.1), font.clone()))
            .map_err(|e| err(&e))?;
    }
    for &v in y_ticks {
        chart.draw_series(LineSeries::new([(x_lo, v), (x_hi, v)], grid)).map_err(|e| err(&e))?;
        let text = format!("{v:.y_dec$}");
        let (w, h) = area.estimate_text_size(&text, &font).map_err(|e| err(&e))?;
        let (_, py) = chart.backend_coord(&(x_lo, v));
        area.draw(&Text::new(text, (xr.start - 6 - w as i32 - base.0, py - h as i32 / 2 - base.1), font.clone()))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// For each x (light count in `lights`, radius factor in `radius`), the culling mode with the
/// lowest total time: where each mode wins.
pub fn winners(rows: &[Row], group: &str) -> Vec<(f64, String, f64)> {
    let x = |r: &Row| if group == "radius" { r.radius_scale } else { r.lights as f64 };
    let mut xs: Vec<f64> = rows.iter().filter(|r| r.group == group).map(x).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    xs.into_iter()
        .filter_map(|v| {
            rows.iter()
                .filter(|r| r.group == group && x(r) == v && r.label != "limit" && r.total_ms.is_finite())
                .min_by(|a, b| a.total_ms.total_cmp(&b.total_ms))
                .map(|r| (v, r.culling.clone(), r.total_ms))
        })
        .collect()
}

/// Where each culling mode wins: total GPU ms (log) against the light count (log) and against
/// the light radius factor, one line per mode, the `limit` dashed in black, the fastest mode at
/// each point ringed. Rows of the `lights` and `radius` groups.
pub fn plot_scaling(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let root = BitMapBackend::new(path, (1200, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(50);
    title.titled("Where each culling mode wins (total GPU ms per frame, lower is better)", ("sans-serif", 24))?;
    let panels = body.split_evenly((1, 2));
    let palette = PALETTE;
    for (group, area) in ["lights", "radius"].into_iter().zip(panels.iter()) {
        let x = |r: &Row| if group == "radius" { r.radius_scale } else { r.lights as f64 };
        let mine: Vec<&Row> =
            rows.iter().filter(|r| r.group == group && r.total_ms.is_finite() && r.total_ms > 0.0).collect();
        if mine.is_empty() {
            area.titled(&format!("{group}: not run"), ("sans-serif", 18))?;
            continue;
        }
        let (x_lo, x_hi) = mine.iter().map(|r| x(r)).fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (t_lo, t_hi) =
            mine.iter().map(|r| r.total_ms).fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (x_lo, x_hi) = (x_lo / 1.3, x_hi * 1.3);
        let (t_lo, t_hi) = (t_lo / 1.3, t_hi * 1.3);
        let x_ticks = crate::plot_layout::log_ticks(x_lo, x_hi);
        let t_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
        let (x_dec, t_dec) = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&t_ticks));
        let caption = if group == "radius" {
            format!("over light radius ({} lights, radius x factor)", mine[0].lights)
        } else {
            "over light count (radius as the scene gives it)".to_string()
        };
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 18))
            .margin(14)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (t_lo..t_hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(if group == "radius" { "light radius factor" } else { "lights" })
            .y_desc("GPU ms per frame (median)")
            .label_style(("sans-serif", 13))
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .draw()?;
        draw_ticks(&mut chart, area, (&x_ticks, x_dec), (&t_ticks, t_dec), (x_lo, x_hi), (t_lo, t_hi))?;
        let mut modes: Vec<String> = Vec::new();
        for r in &mine {
            if !modes.contains(&r.culling) {
                modes.push(r.culling.clone());
            }
        }
        let wins = winners(rows, group);
        for (i, mode) in modes.iter().enumerate() {
            let mut line: Vec<(f64, f64)> =
                mine.iter().filter(|r| &r.culling == mode).map(|r| (x(r), r.total_ms)).collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            let is_limit = mode == "limit";
            let color = if is_limit { BLACK } else { palette[i % palette.len()] };
            let style = color.stroke_width(if is_limit { 1 } else { 2 });
            if is_limit {
                // Dashed: every other segment of a finely split line (log x).
                let mut dashes = Vec::new();
                for w in line.windows(2) {
                    let ((x0, y0), (x1, y1)) = (w[0], w[1]);
                    for k in (0..20).step_by(2) {
                        let at = |f: f64| (x0 * (x1 / x0).powf(f), y0 * (y1 / y0).powf(f));
                        dashes.push([at(k as f64 / 20.0), at((k + 1) as f64 / 20.0)]);
                    }
                }
                for d in dashes {
                    chart.draw_series(LineSeries::new(d, style))?;
                }
            } else {
                chart.draw_series(LineSeries::new(line.clone(), style))?;
            }
            chart
                .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))?
                .label(mode.as_str())
                .legend(move |(lx, ly)| Rectangle::new([(lx, ly - 4), (lx + 14, ly + 4)], color.filled()));
        }
        for (v, _, t) in &wins {
            chart.draw_series(std::iter::once(Circle::new((*v, *t), 9, BLACK.stroke_width(2))))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()?;
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
            radius_scale: 1.0,
            width: 8,
            height: 8,
            gbuffer_ms: 0.0,
            lighting_ms: 0.0,
            compose_ms: 0.0,
            forward_ms: 0.0,
            bloom_ms: 0.0,
            exposure_ms: 0.0,
            tonemap_ms: 0.0,
            grading_ms: 0.0,
            fog_ms: 0.0,
            dof_ms: 0.0,
            vignette_ms: 0.0,
            aa_ms: 0.0,
            total_ms: ms,
            draw_calls: 0,
            light_batches: 0,
            coverage_fragments: 0,
            shaded_fragments: 0,
            ideal_fragments: 0,
            efficiency: 0.0,
            gbuffer_bytes_per_pixel: 0,
            flip_mean: flip,
            max_abs_light_error: 0.0,
            psnr_db: 0.0,
            pareto: false,
            reference: "fullscreen".into(),
            limit_ratio: f64::NAN,
            path: Default::default(),
            shadow: Default::default(),
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

    #[test]
    fn the_limit_row_is_gbuffer_plus_compose_plus_the_ideal_at_fullscreen_cost() {
        let row = |label: &str, culling: &str, lights: usize, g: f64, l: f64, c: f64, shaded: u64| Row {
            group: "culling".into(),
            label: label.into(),
            scene: "s".into(),
            culling: culling.into(),
            layout: String::new(),
            accumulation: String::new(),
            reversed_z: false,
            depth_format: String::new(),
            light_cutoff: 0.0,
            sphere_subdivisions: 1,
            cone_sides: 12,
            volumes: String::new(),
            lights,
            radius_scale: 1.0,
            width: 8,
            height: 8,
            gbuffer_ms: g,
            lighting_ms: l,
            compose_ms: c,
            forward_ms: 0.0,
            bloom_ms: 0.0,
            exposure_ms: 0.0,
            tonemap_ms: 0.0,
            grading_ms: 0.0,
            fog_ms: 0.0,
            dof_ms: 0.0,
            vignette_ms: 0.0,
            aa_ms: 0.0,
            total_ms: g + l + c,
            draw_calls: 0,
            light_batches: 0,
            coverage_fragments: 0,
            shaded_fragments: shaded,
            ideal_fragments: 1000,
            efficiency: 0.0,
            gbuffer_bytes_per_pixel: 0,
            flip_mean: 0.0,
            max_abs_light_error: 0.0,
            psnr_db: 0.0,
            pareto: false,
            reference: "fullscreen".into(),
            limit_ratio: f64::NAN,
            path: Default::default(),
            shadow: Default::default(),
        };
        let mut rows = vec![
            // 100 ms for 100,000 fragments: 0.001 ms a fragment.
            row("fullscreen", "fullscreen", 10, 10.0, 100.0, 4.0, 100_000),
            row("volume", "volume", 10, 12.0, 9.0, 6.0, 3000),
            row("stencil", "stencil-two-pass", 10, 11.0, 5.0, 5.0, 1100),
            // Another light count without a fullscreen row borrows its ms per fragment.
            row("volume", "volume", 40, 11.0, 30.0, 5.0, 9000),
        ];
        add_limits(&mut rows);
        let labels: Vec<(&str, usize)> = rows.iter().map(|r| (r.label.as_str(), r.lights)).collect();
        assert_eq!(
            labels,
            vec![("fullscreen", 10), ("volume", 10), ("stencil", 10), ("limit", 10), ("volume", 40), ("limit", 40)]
        );
        // Medians of G-buffer (11) and compose (5), plus 1,000 ideal fragments at 0.001 ms.
        let limit = &rows[3];
        assert!((limit.total_ms - (11.0 + 5.0 + 1.0)).abs() < 1e-9, "{}", limit.total_ms);
        assert!((rows[2].limit_ratio - 21.0 / 17.0).abs() < 1e-9, "{}", rows[2].limit_ratio);
        assert!((rows[5].total_ms - (11.0 + 5.0 + 1.0)).abs() < 1e-9);
        // Without any fullscreen row there is no limit.
        let mut alone = vec![row("volume", "volume", 10, 12.0, 9.0, 6.0, 3000)];
        add_limits(&mut alone);
        assert_eq!(alone.len(), 1);
        assert!(alone[0].limit_ratio.is_nan());
        // A shadow pass is a fixed pass like the G-buffer: its median joins the limit.
        let mut shadowed = vec![
            row("fullscreen", "fullscreen", 10, 10.0, 100.0, 4.0, 100_000),
            row("volume", "volume", 10, 12.0, 9.0, 6.0, 3000),
            row("stencil", "stencil-two-pass", 10, 11.0, 5.0, 5.0, 1100),
        ];
        for (r, s) in shadowed.iter_mut().zip([3.0, 2.0, 4.0]) {
            r.shadow.gpu_ms = s;
        }
        add_limits(&mut shadowed);
        assert!((shadowed[3].total_ms - (11.0 + 3.0 + 5.0 + 1.0)).abs() < 1e-9, "{}", shadowed[3].total_ms);
    }
}
