//! `lampshade bench --only restir`: the equal-time comparison of stochastic many-light shading
//! with exact culling, on a moving camera. Per layout (the stochastic group's densest, and one
//! at a few lights a pixel), each configuration replays the first [`FLIP_FRAME`] + 1 frames
//! of its scene's camera path (`assets/paths/`), the camera moving every frame and the noise
//! seed changing with it (temporal reuse and the denoiser keep their history along the path):
//!
//! - **time**: the mean lighting span over the path (list builds, candidates, reuse and
//!   denoising included), each of RIS's passes apart;
//! - **error**: FLIP of frame [`FLIP_FRAME`] against the exact frame there (an exact mode,
//!   which the oracle holds to brute force), and the signed difference of its lights' light
//!   from the exact one's, summed over the linear accumulation (the bias; for an unbiased row
//!   it is that frame's noise, for the denoiser and the engines' caps mostly their bias), and
//!   of its sRGB output;
//! - **flicker**: the mean FLIP between adjacent frames, beside the fastest exact mode's (the
//!   motion's own).
//!
//! The rows: the exact modes, RIS on the clustered lists with K in {1, 2, 4}, reuse off,
//! spatial, temporal or both, and the denoiser off or on, and the engines' caps. Clustered,
//! not z-binned: a z-bin's range of sorted lights holds far more lights than reach a pixel
//! (its tile mask leaves them out only as zero-weight candidates), so at 40 lights a pixel
//! one sample of 8 uniform candidates from it found no light at most pixels (measured: a
//! frame nearly black), where a cluster's list held few enough to find one at most. Each configuration is
//! replayed alone (its reservoirs are hundreds of MB at 1280x720), in the order listed.

use super::*;
use crate::scene::camera_path::CameraPath;

/// The group's name for `--only` (apart from [`GROUPS`]: its rows are replays, not stills).
pub const RESTIR_GROUP: &str = "restir";

/// The path frame the error is measured at.
pub const FLIP_FRAME: usize = 30;

/// The spatial neighbours of the rows with spatial reuse.
pub const SPATIAL_NEIGHBOURS: u32 = 4;

/// RIS's samples a pixel the rows sweep (reuse keeps at most four).
pub const RESTIR_SAMPLES: [u32; 3] = [1, 2, 4];

/// A layout of the comparison: a stochastic-group layout and its scene's camera path.
pub struct RestirLayout {
    pub label: String,
    pub scene: &'static str,
    pub lights: usize,
    pub radius_scale: f64,
}

/// The dense sphere wall and the radius sweep's densest point (about 40 lights a pixel each),
/// and the sphere wall at 1,024 lights (a few).
pub fn restir_layouts() -> Vec<RestirLayout> {
    vec![wall(16384, 1.0), wall(1024, 4.0), wall(1024, 1.0)]
}

/// The sphere wall with `lights` lights, their radii times `radius_scale`.
pub fn wall(lights: usize, radius_scale: f64) -> RestirLayout {
    let label = match radius_scale {
        1.0 => format!("wall {lights}"),
        r => format!("wall {lights} r x{r}"),
    };
    RestirLayout { label, scene: "sphere-wall", lights, radius_scale }
}

/// What kind of row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
pub enum RestirFamily {
    Exact,
    Stochastic,
    Engine,
}

/// One configuration to replay.
#[derive(Clone, Debug)]
pub struct RestirConfig {
    pub label: String,
    pub family: RestirFamily,
    pub settings: Settings,
}

/// The rows of one layout on `base`; `quick`: the clustered and z-binned exact modes, and RIS
/// with one sample, reuse off or both, the denoiser off or on (the GPU check's rows at 10^5
/// and 10^6 lights).
pub fn restir_configs(base: &Settings, quick: bool) -> Vec<RestirConfig> {
    if quick {
        return restir_configs(base, false)
            .into_iter()
            .filter(|c| match c.family {
                RestirFamily::Exact => matches!(c.settings.culling, CullingMode::Clustered | CullingMode::Zbin),
                RestirFamily::Stochastic => {
                    c.settings.ris_samples == 1 && (c.settings.ris_spatial > 0) == c.settings.ris_temporal
                }
                RestirFamily::Engine => false,
            })
            .collect();
    }
    let mut v = Vec::new();
    for culling in super::groups::STOCHASTIC_EXACT_MODES {
        v.push(RestirConfig {
            label: culling.name(),
            family: RestirFamily::Exact,
            settings: Settings { culling, ..base.clone() },
        });
    }
    for k in RESTIR_SAMPLES {
        for (reuse, spatial, temporal) in [
            ("", 0, false),
            (" spatial", SPATIAL_NEIGHBOURS, false),
            (" temporal", 0, true),
            (" both", SPATIAL_NEIGHBOURS, true),
        ] {
            for denoise in [false, true] {
                let settings = Settings {
                    culling: CullingMode::Clustered,
                    ris_samples: k,
                    ris_candidates: super::groups::RIS_CANDIDATES,
                    ris_spatial: spatial,
                    ris_temporal: temporal,
                    ris_denoise: denoise,
                    ..base.clone()
                };
                let label = format!("clustered RIS K{k}{reuse}{}", if denoise { " denoised" } else { "" });
                v.push(RestirConfig { label, family: RestirFamily::Stochastic, settings });
            }
        }
    }
    for e in crate::renderer::caps::ENGINES {
        if let Ok(settings) = crate::renderer::presets::engine_settings(e, base) {
            v.push(RestirConfig { label: e.name.into(), family: RestirFamily::Engine, settings });
        }
    }
    v
}

/// One configuration's replay on one layout (`restir.json`; a field a run before it did not
/// write reads as NaN).
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RestirRow {
    pub layout: String,
    pub label: String,
    pub family: RestirFamily,
    /// The exact frame's lights a pixel at frame [`FLIP_FRAME`] (its G-buffer points inside a
    /// light's shape, over the pixels).
    pub lights_per_pixel: f64,
    /// The frame's pixels.
    pub pixels: u64,
    /// Mean over the path's frames, in ms: the lighting span, and RIS's candidates, spatial
    /// and denoise passes (NaN where they did not run).
    pub lighting_ms: f64,
    pub candidates_ms: f64,
    pub spatial_ms: f64,
    pub denoise_ms: f64,
    /// FLIP of frame [`FLIP_FRAME`] against the exact frame there (mean).
    pub flip: f64,
    /// Its lights' light less the exact frame's over the exact frame's, summed over the pixels
    /// and channels of the linear accumulation less the lightless frame's: signed. One frame's:
    /// for an unbiased row its noise, for the denoiser, temporal reuse on a moving camera and
    /// the engines' caps mostly their bias.
    pub bias: f64,
    /// The same of the sRGB output (after the tonemap, whose curve and clipping make a noisy
    /// frame darker on average however unbiased its light).
    pub display_bias: f64,
    /// Mean FLIP between adjacent frames, and the fastest exact mode's.
    pub flicker: f64,
    pub exact_flicker: f64,
    /// This row's lighting time over the fastest exact mode's.
    pub time_ratio: f64,
}

/// The scene of a layout, with its path's first camera.
fn layout_scene(l: &RestirLayout) -> Result<(crate::Scene, CameraPath)> {
    let opts = crate::scene::import::ImportOptions::default();
    let (mut scene, _) =
        crate::scene::open(l.scene, BuiltinOptions { lights: Some(l.lights), time: 0.0 }, &opts, &mut |_| {})?;
    scale_light_radii(&mut scene, l.radius_scale);
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/paths").join(format!("{}.json", l.scene));
    let path = CameraPath::load(&file).with_context(|| format!("the camera path of {}", l.scene))?;
    Ok((scene, path))
}

/// The mean of the finite values of `v` (NaN when none is).
fn finite_mean(v: &[f64]) -> f64 {
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.is_empty() {
        f64::NAN
    } else {
        f.iter().sum::<f64>() / f.len() as f64
    }
}

/// The sum of an accumulation's channels (diffuse and specular).
fn light_sum(a: &(Vec<f32>, Vec<f32>)) -> f64 {
    a.0.iter().chain(&a.1).map(|&v| f64::from(v)).sum()
}

/// The summed difference of `image`'s channels from `exact`'s over `exact`'s sum.
fn relative_difference(image: &image::RgbaImage, exact: &image::RgbaImage) -> f64 {
    let sum = |i: &image::RgbaImage| i.pixels().map(|p| p.0[..3].iter().map(|&c| c as f64).sum::<f64>()).sum::<f64>();
    let e = sum(exact);
    if e > 0.0 {
        sum(image) / e - 1.0
    } else {
        0.0
    }
}

impl Default for RestirRow {
    fn default() -> Self {
        RestirRow {
            layout: String::new(),
            label: String::new(),
            family: RestirFamily::Exact,
            lights_per_pixel: f64::NAN,
            pixels: 0,
            lighting_ms: f64::NAN,
            candidates_ms: f64::NAN,
            spatial_ms: f64::NAN,
            denoise_ms: f64::NAN,
            flip: f64::NAN,
            bias: f64::NAN,
            display_bias: f64::NAN,
            flicker: f64::NAN,
            exact_flicker: f64::NAN,
            time_ratio: f64::NAN,
        }
    }
}

/// Rows read back from `restir.json`: serde_json writes NaN as null, read back here as NaN.
pub fn read_restir_json(text: &str) -> Result<Vec<RestirRow>> {
    let mut value: serde_json::Value = serde_json::from_str(text)?;
    if let Some(rows) = value.as_array_mut() {
        for row in rows.iter_mut().filter_map(|r| r.as_object_mut()) {
            row.retain(|_, v| !v.is_null());
        }
    }
    Ok(serde_json::from_value(value)?)
}

/// Replays `configs` on `layout` at `size`; `progress(label)` is called as each starts.
pub fn run_restir(
    gpu: &Gpu,
    layout: &RestirLayout,
    configs: &[RestirConfig],
    size: (u32, u32),
    costs: &crate::renderer::options::calibration::Calibration,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<RestirRow>> {
    let (mut scene, path) = layout_scene(layout)?;
    let (w, h) = size;
    let step = path.step(None);
    // The exact frame at FLIP_FRAME, with its lights a pixel.
    scene.camera = path.frame(FLIP_FRAME, step);
    // Lights a pixel counted up to 16,384 lights (the count is one occlusion query a light).
    let count_ideal = layout.lights <= 16384;
    let exact_settings = Settings { culling: CullingMode::Clustered, count_ideal, ..Settings::default() };
    let mut exact = Renderer::new(gpu, OUTPUT_FORMAT, &exact_settings)?;
    exact.set_calibration(costs.clone());
    let (reference, stats) = render_image(gpu, &mut exact, &scene, &exact_settings, w, h)?;
    let reference_light = light_sum(&exact.last_frame().read_accumulation(gpu)?);
    let mut dark = scene.clone();
    dark.lights_mut().clear();
    render_image(gpu, &mut exact, &dark, &exact_settings, w, h)?;
    let dark_light = light_sum(&exact.last_frame().read_accumulation(gpu)?);
    drop(exact);
    let lights_light = (reference_light - dark_light).max(f64::MIN_POSITIVE);
    let lights_per_pixel = stats.ideal_fragments.map_or(f64::NAN, |n| n as f64 / (w as f64 * h as f64));
    let mut rows = Vec::new();
    for c in configs {
        progress(&format!("{}: {}", layout.label, c.label));
        c.settings.validate().map_err(|e| anyhow::anyhow!("{}: {e}", c.label))?;
        let mut renderer = Renderer::new(gpu, OUTPUT_FORMAT, &c.settings).with_context(|| c.label.clone())?;
        renderer.set_calibration(costs.clone());
        // The warm-up frame (pipelines compile on their first draw), off the path.
        scene.camera = path.frame(0, step);
        let warm = Settings { noise_seed: u32::MAX - 1, ..c.settings.clone() };
        render_image(gpu, &mut renderer, &scene, &warm, w, h).with_context(|| c.label.clone())?;
        let (mut ms, mut passes, mut flicker) = (Vec::new(), [Vec::new(), Vec::new(), Vec::new()], Vec::new());
        let mut last: Option<image::RgbaImage> = None;
        for n in 0..=FLIP_FRAME {
            scene.camera = path.frame(n, step);
            let s =
                Settings { noise_seed: n as u32 + 1, timestamps: true, count_fragments: false, ..c.settings.clone() };
            let (image, stats) = render_image(gpu, &mut renderer, &scene, &s, w, h)?;
            // A forward path has no lighting span: its passes' (depth pre-pass included).
            let forward = stats.forward_path.as_ref().map(|fp| fp.passes.iter().filter_map(|p| p.gpu_ms).sum());
            ms.push(stats.gpu_ms.lighting.or(forward).unwrap_or(f64::NAN));
            let g = &stats.gpu_ms;
            for (v, t) in passes.iter_mut().zip([g.ris_candidates, g.ris_spatial, g.ris_denoise]) {
                v.push(t.unwrap_or(f64::NAN));
            }
            if let Some(prev) = &last {
                flicker.push(flip(prev, &image)?.0.mean as f64);
            }
            last = Some(image);
        }
        let last = last.context("no frame drawn")?;
        let light = light_sum(&renderer.last_frame().read_accumulation(gpu)?);
        rows.push(RestirRow {
            layout: layout.label.clone(),
            label: c.label.clone(),
            family: c.family,
            lights_per_pixel,
            pixels: w as u64 * h as u64,
            lighting_ms: finite_mean(&ms),
            candidates_ms: finite_mean(&passes[0]),
            spatial_ms: finite_mean(&passes[1]),
            denoise_ms: finite_mean(&passes[2]),
            flip: flip(&reference, &last)?.0.mean as f64,
            bias: (light - reference_light) / lights_light,
            display_bias: relative_difference(&last, &reference),
            flicker: finite_mean(&flicker),
            exact_flicker: f64::NAN,
            time_ratio: f64::NAN,
        });
        gpu.errors.check()?;
    }
    let fastest = rows
        .iter()
        .filter(|r| r.family == RestirFamily::Exact)
        .min_by(|a, b| a.lighting_ms.total_cmp(&b.lighting_ms))
        .map(|r| (r.lighting_ms, r.flicker));
    if let Some((ms, flicker)) = fastest {
        for r in &mut rows {
            r.time_ratio = r.lighting_ms / ms;
            r.exact_flicker = flicker;
        }
    }
    Ok(rows)
}

/// Whether `r` meets the headline: FLIP at most `flip` in at most `ratio` of the fastest exact
/// mode's lighting time.
pub fn meets(r: &RestirRow, flip: f64, ratio: f64) -> bool {
    r.flip <= flip && r.time_ratio <= ratio
}

/// The comparison as markdown: per layout, every row with its time, each pass, its error,
/// bias and flicker; and whether any stochastic row met FLIP 0.02 in half the fastest exact
/// mode's time, and whether an engine's cap beats a stochastic row on both.
pub fn restir_markdown(rows: &[RestirRow], size: (u32, u32), adapter: &str) -> String {
    let mut md = format!(
        "# Stochastic against exact, equal time on a moving camera\n\n{}x{} on {adapter}; each row replays frames \
         0-{FLIP_FRAME} of its scene's camera path. ms: mean lighting span over the frames (lists, candidates, \
         reuse and denoising included; RIS's passes apart); ns/px: that time a pixel (Helio publishes 1.05 ns/px); \
         FLIP and bias at frame {FLIP_FRAME} against the exact frame (bias: the lights' linear light, summed; \
         display bias: the sRGB output's); flicker: mean FLIP between adjacent frames (the fastest exact mode's is \
         the motion's own).\n",
        size.0, size.1
    );
    let mut layouts: Vec<&str> = rows.iter().map(|r| r.layout.as_str()).collect();
    layouts.dedup();
    let ms = |v: f64| if v.is_finite() { format!("{v:.2}") } else { "-".into() };
    for l in layouts {
        let of: Vec<&RestirRow> = rows.iter().filter(|r| r.layout == l).collect();
        let lpp = of.first().map_or(f64::NAN, |r| r.lights_per_pixel);
        md += &format!(
            "\n## {l} ({lpp:.1} lights a pixel)\n\n| configuration | ms | ns/px | × fastest exact | candidates ms | \
             spatial ms | denoise ms | FLIP | bias | display bias | flicker | exact flicker |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n"
        );
        for r in &of {
            md += &format!(
                "| {} | {} | {:.2} | {:.2} | {} | {} | {} | {:.4} | {:+.4} | {:+.4} | {:.4} | {:.4} |\n",
                r.label,
                ms(r.lighting_ms),
                r.lighting_ms * 1e6 / r.pixels.max(1) as f64,
                r.time_ratio,
                ms(r.candidates_ms),
                ms(r.spatial_ms),
                ms(r.denoise_ms),
                r.flip,
                r.bias,
                r.display_bias,
                r.flicker,
                r.exact_flicker
            );
        }
        let met: Vec<&&RestirRow> =
            of.iter().filter(|r| r.family == RestirFamily::Stochastic && meets(r, 0.02, 0.5)).collect();
        md += &match met.first() {
            Some(r) => format!("\nFLIP ≤ 0.02 in ≤ ½ the fastest exact mode's time: met by {}.\n", r.label),
            None => {
                let best = of
                    .iter()
                    .filter(|r| r.family == RestirFamily::Stochastic && r.time_ratio <= 0.5)
                    .min_by(|a, b| a.flip.total_cmp(&b.flip));
                match best {
                    Some(b) => format!(
                        "\nFLIP ≤ 0.02 in ≤ ½ the fastest exact mode's time: not met; the lowest FLIP within half the \
                         time is {} ({:.4} at {:.2}×).\n",
                        b.label, b.flip, b.time_ratio
                    ),
                    None => "\nFLIP ≤ 0.02 in ≤ ½ the fastest exact mode's time: not met; no stochastic row took \
                             under half the time.\n"
                        .into(),
                }
            }
        };
        let beaten: Vec<String> = of
            .iter()
            .filter(|e| e.family == RestirFamily::Engine)
            .filter(|e| {
                of.iter()
                    .any(|s| s.family == RestirFamily::Stochastic && e.lighting_ms < s.lighting_ms && e.flip < s.flip)
            })
            .map(|e| e.label.clone())
            .collect();
        if !beaten.is_empty() {
            md += &format!("Engine caps faster and closer than some stochastic row: {}.\n", beaten.join(", "));
        }
    }
    md
}

/// Speed against error per layout (`restir.png`): each row's lighting time over the fastest
/// exact mode's (log) against its FLIP at frame [`FLIP_FRAME`], the headline's corner (½ the
/// time, FLIP 0.02) drawn.
pub fn plot_restir(rows: &[RestirRow], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let mut layouts: Vec<&str> = rows.iter().map(|r| r.layout.as_str()).collect();
    layouts.dedup();
    let cols = layouts.len().clamp(1, 3);
    let root = BitMapBackend::new(path, (460 * cols as u32, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(80);
    title.titled(
        "Stochastic against exact on a moving camera: time over the fastest exact mode's against FLIP",
        ("sans-serif", 22),
    )?;
    let kind = |r: &RestirRow| match r.family {
        RestirFamily::Exact => 0,
        RestirFamily::Stochastic if r.label.ends_with("denoised") => 2,
        RestirFamily::Stochastic => 1,
        RestirFamily::Engine => 3,
    };
    let legend = [
        (0, "exact modes", super::PALETTE[1]),
        (1, "RIS, reuse off / spatial / temporal / both", super::PALETTE[0]),
        (2, "the same, denoised", super::PALETTE[2]),
        (3, "engine caps", super::PALETTE[5]),
    ];
    for (i, (_, name, c)) in legend.iter().enumerate() {
        let (x, y) = (20 + 340 * (i as i32 % 2), 40 + 20 * (i as i32 / 2));
        title.draw(&Circle::new((x, y + 8), 6, c.filled()))?;
        title.draw(&Text::new(*name, (x + 12, y), ("sans-serif", 15).into_font()))?;
    }
    let areas = body.split_evenly((1, cols));
    for (l, area) in layouts.iter().zip(areas.iter()) {
        let pts: Vec<(f64, f64, usize)> = rows
            .iter()
            .filter(|r| r.layout == *l && r.time_ratio.is_finite() && r.time_ratio > 0.0 && r.flip.is_finite())
            .map(|r| (r.time_ratio, r.flip, kind(r)))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let lo = pts.iter().map(|p| p.0).fold(0.5, f64::min) / 1.3;
        let hi = pts.iter().map(|p| p.0).fold(1.0, f64::max) * 1.3;
        let e_hi = pts.iter().map(|p| p.1).fold(0.03, f64::max) * 1.1;
        let lpp = rows.iter().find(|r| r.layout == *l).map_or(f64::NAN, |r| r.lights_per_pixel);
        let mut chart = ChartBuilder::on(area)
            .caption(format!("{l} ({lpp:.1} lights/px)"), ("sans-serif", 17))
            .margin(10)
            .x_label_area_size(32)
            .y_label_area_size(52)
            .build_cartesian_2d((lo..hi).log_scale(), 0.0..e_hi)?;
        super::plot::blank_mesh(&mut chart, ("lighting time / fastest exact", "FLIP mean"), 12)?;
        let x_ticks = crate::plot_layout::log_ticks(lo, hi);
        let y_ticks = crate::plot_layout::linear_ticks(0.0, e_hi);
        let decimals = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&y_ticks));
        super::plot::draw_ticks(
            &mut chart,
            area,
            (&x_ticks, decimals.0),
            (&y_ticks, decimals.1),
            (lo, hi),
            (0.0, e_hi),
        )?;
        chart.draw_series(LineSeries::new([(lo, 0.02), (0.5, 0.02), (0.5, 0.0)], BLACK.mix(0.4)))?;
        for (k, _, c) in legend {
            chart.draw_series(pts.iter().filter(|p| p.2 == k).map(|p| Circle::new((p.0, p.1), 4, c.filled())))?;
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_restir_configuration_is_valid_and_named_once() {
        let configs = restir_configs(&Settings::default(), false);
        let mut labels: Vec<&str> = configs.iter().map(|c| c.label.as_str()).collect();
        for c in &configs {
            c.settings.validate().unwrap_or_else(|e| panic!("{}: {e}", c.label));
        }
        assert_eq!(configs.iter().filter(|c| c.family == RestirFamily::Stochastic).count(), 24);
        labels.sort_unstable();
        labels.dedup();
        assert_eq!(labels.len(), configs.len(), "a label repeats");
        let quick = restir_configs(&Settings::default(), true);
        let names: Vec<&str> = quick.iter().map(|c| c.label.as_str()).collect();
        assert_eq!(
            names,
            [
                "clustered",
                "zbin",
                "clustered RIS K1",
                "clustered RIS K1 denoised",
                "clustered RIS K1 both",
                "clustered RIS K1 both denoised"
            ]
        );
    }
}
