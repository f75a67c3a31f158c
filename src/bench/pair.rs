//! `lampshade compare`: two configurations of one scene, side by side. Both are drawn at the
//! same size from the same scene and camera, timed in interleaved rounds (one frame of each a
//! round, so background load falls on both alike), and each is held against the bench's
//! reference ([`reference`], [`frame_error`]): its error is the figure `bench` reports for the
//! same settings. Between them: the largest 8-bit step, the share of pixels that differ, FLIP
//! of B against A and its map, an amplified difference image, and the lights whose ledger cost
//! changed most.

use super::run::{frame_error, reference, FrameError, Reference};
use super::*;
use crate::compare::{difference_image, FlipResult, DIFFERENCE_GAIN};

/// How a pair is drawn.
#[derive(Clone, Debug)]
pub struct PairOptions {
    pub size: (u32, u32),
    /// Timed rounds (one frame of each side a round); the medians are reported.
    pub frames: usize,
    /// The cost model's constants `auto` and the ledger weigh with.
    pub costs: crate::renderer::options::calibration::Calibration,
}

/// One side of a comparison.
#[derive(Clone, Debug, Serialize)]
pub struct SideReport {
    pub label: String,
    pub settings: Settings,
    /// Median GPU milliseconds of each pass that ran over the timed frames (`GpuMs`' names).
    pub gpu_ms: Vec<(String, f64)>,
    /// The frame's error against the reference (as `bench` reports it).
    pub error: FrameError,
    /// What `auto` drew the lights with (empty for the other modes).
    pub auto_chose: String,
    /// Each light's cost by the ledger's model (index, ms), from the counted frame.
    #[serde(skip)]
    pub light_ms: Vec<(usize, f64)>,
    #[serde(skip)]
    pub image: image::RgbaImage,
}

/// A light whose ledger cost differs between the sides.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct LightDelta {
    pub light: usize,
    pub a_ms: f64,
    pub b_ms: f64,
}

/// The two sides and what lies between them.
#[derive(Clone, Debug, Serialize)]
pub struct PairReport {
    pub scene: String,
    pub lights: usize,
    pub size: (u32, u32),
    pub adapter: String,
    /// The reference both sides' errors are measured against: its culling mode.
    pub reference: String,
    pub a: SideReport,
    pub b: SideReport,
    /// The largest per-channel difference of B from A (0..255).
    pub max_steps: u8,
    /// The share of pixels where B differs from A at all.
    pub differing_pixels: f64,
    /// FLIP of B against A.
    pub flip_mean: f32,
    pub flip_p99: f32,
    pub flip_max: f32,
    /// Up to ten lights whose cost changed most, largest change first.
    pub ledger_delta: Vec<LightDelta>,
    #[serde(skip)]
    pub flip_map: image::RgbaImage,
    #[serde(skip)]
    pub difference: image::RgbaImage,
}

/// Median of each pass that ran in `times` (those present in every frame), by `GpuMs`' names.
pub fn median_passes(times: &[FrameStats]) -> Vec<(String, f64)> {
    let maps: Vec<serde_json::Map<String, serde_json::Value>> = times
        .iter()
        .filter_map(|s| match serde_json::to_value(&s.gpu_ms) {
            Ok(serde_json::Value::Object(m)) => Some(m),
            _ => None,
        })
        .collect();
    let Some(first) = maps.first() else { return Vec::new() };
    // The frame's order; the post effects (by their own names) before the total.
    const ORDER: [&str; 10] = [
        "shadows",
        "gbuffer",
        "lighting",
        "lists",
        "compose",
        "forward",
        "prepass_final",
        "bloom",
        "exposure",
        "tonemap",
    ];
    let rank = |k: &str| ORDER.iter().position(|o| *o == k).unwrap_or(if k == "total" { 12 } else { 11 });
    let mut keys: Vec<&String> = first.keys().collect();
    keys.sort_by_key(|k| rank(k));
    let mut out = Vec::new();
    for key in keys {
        let v: Vec<f64> = maps.iter().filter_map(|m| m.get(key)?.as_f64()).collect();
        if !v.is_empty() && v.len() == maps.len() {
            out.push((key.clone(), median(v)));
        }
    }
    out
}

/// Each light's cost by the ledger's model (index, ms), from a frame's stats.
pub fn light_costs(stats: &FrameStats) -> Vec<(usize, f64)> {
    stats.per_light.iter().filter_map(|l| Some((l.index, l.cost_ms?))).collect()
}

/// The ten lights whose cost differs most between `a` and `b` (a light missing on a side
/// costs 0 there), largest change first; ties by index.
pub fn ledger_delta(a: &[(usize, f64)], b: &[(usize, f64)]) -> Vec<LightDelta> {
    let mut by: std::collections::BTreeMap<usize, (f64, f64)> = Default::default();
    for &(i, ms) in a {
        by.entry(i).or_default().0 = ms;
    }
    for &(i, ms) in b {
        by.entry(i).or_default().1 = ms;
    }
    let mut v: Vec<LightDelta> = by.into_iter().map(|(light, (a_ms, b_ms))| LightDelta { light, a_ms, b_ms }).collect();
    v.retain(|d| d.a_ms != d.b_ms);
    v.sort_by(|x, y| (y.b_ms - y.a_ms).abs().total_cmp(&(x.b_ms - x.a_ms).abs()).then(x.light.cmp(&y.light)));
    v.truncate(10);
    v
}

/// Draws `a` and `b` on `scene` (see the module's notes). `labels` name the sides.
pub fn compare_pair(
    gpu: &Gpu,
    scene: &crate::Scene,
    scene_name: &str,
    (a, b): (&Settings, &Settings),
    labels: (&str, &str),
    o: &PairOptions,
) -> Result<PairReport> {
    let (w, h) = o.size;
    let mut renderers = Vec::new();
    for s in [a, b] {
        s.validate().map_err(anyhow::Error::msg)?;
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s)?;
        r.set_calibration(o.costs.clone());
        // The warm-up: pipelines compile on their first draw, the counted frame's too.
        render_image(gpu, &mut r, scene, s, w, h)?;
        renderers.push(r);
    }
    let mut times: [Vec<FrameStats>; 2] = [Vec::new(), Vec::new()];
    for _ in 0..o.frames.max(1) {
        for (k, s) in [a, b].into_iter().enumerate() {
            let timed = Settings { count_fragments: false, timestamps: true, ..s.clone() };
            times[k].push(render_image(gpu, &mut renderers[k], scene, &timed, w, h)?.1);
        }
    }
    let mut refs: Vec<(ShadowMode, Reference)> = Vec::new();
    let mut sides = Vec::new();
    for (k, (s, label)) in [(a, labels.0), (b, labels.1)].into_iter().enumerate() {
        if !refs.iter().any(|(m, _)| *m == s.shadows) {
            refs.push((s.shadows, reference(gpu, scene, o.size, s.shadows)?));
        }
        let reference = &refs.iter().find(|(m, _)| *m == s.shadows).context("the reference")?.1;
        // The error frame as the bench draws it: counted, without timestamps.
        let counted = Settings { count_fragments: true, count_ideal: true, timestamps: false, ..s.clone() };
        let (image, stats) = render_image(gpu, &mut renderers[k], scene, &counted, w, h)?;
        let error = frame_error(gpu, reference, s, &renderers[k], &stats, &image)?;
        sides.push(SideReport {
            label: label.to_string(),
            settings: s.clone(),
            gpu_ms: median_passes(&times[k]),
            error,
            auto_chose: match s.culling {
                crate::renderer::CullingMode::Auto => {
                    stats.tiles.as_ref().map_or("per-light".into(), |t| t.method.name())
                }
                _ => String::new(),
            },
            light_ms: light_costs(&stats),
            image,
        });
    }
    let (sb, sa) = (sides.pop().context("side B")?, sides.pop().context("side A")?);
    let (f, flip_map): (FlipResult, _) = flip(&sa.image, &sb.image)?;
    let max_steps = crate::compare::max_channel_difference(&sa.image, &sb.image);
    let differing = sa.image.pixels().zip(sb.image.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
    Ok(PairReport {
        scene: scene_name.to_string(),
        lights: scene.lights.len(),
        size: o.size,
        adapter: gpu.info.name.clone(),
        reference: reference_culling(scene.lights.len(), o.size).name(),
        max_steps,
        differing_pixels: differing as f64 / (w as f64 * h as f64).max(1.0),
        flip_mean: f.mean,
        flip_p99: f.p99,
        flip_max: f.max,
        ledger_delta: ledger_delta(&sa.light_ms, &sb.light_ms),
        difference: difference_image(&sa.image, &sb.image),
        flip_map,
        a: sa,
        b: sb,
    })
}

/// The comparison as markdown: time per pass and error per side, then B against A.
pub fn pair_markdown(r: &PairReport) -> String {
    let mut md = format!(
        "# {} against {}\n\n{}, {} lights, {}x{}, on {}. Error against the reference ({} culling, f32 \
         accumulation, full G-buffer), as `lampshade bench` reports it.\n\n",
        r.b.label, r.a.label, r.scene, r.lights, r.size.0, r.size.1, r.adapter, r.reference
    );
    let mut passes: Vec<&str> = r.a.gpu_ms.iter().map(|p| p.0.as_str()).collect();
    for (p, _) in &r.b.gpu_ms {
        if !passes.contains(&p.as_str()) {
            passes.push(p);
        }
    }
    let ms = |s: &SideReport, p: &str| s.gpu_ms.iter().find(|q| q.0 == p).map_or("-".into(), |q| format!("{:.3}", q.1));
    md += "| GPU ms (median) | A | B |\n|---|---|---|\n";
    for p in passes {
        md += &format!("| {p} | {} | {} |\n", ms(&r.a, p), ms(&r.b, p));
    }
    let num = |v: f64, digits: usize| if v.is_nan() { "-".to_string() } else { format!("{v:.digits$}") };
    md += "\n| error against the reference | A | B |\n|---|---|---|\n";
    md += &format!("| FLIP mean | {} | {} |\n", num(r.a.error.flip_mean as f64, 5), num(r.b.error.flip_mean as f64, 5));
    md += &format!(
        "| largest light error | {} | {} |\n",
        num(r.a.error.max_abs_light_error as f64, 5),
        num(r.b.error.max_abs_light_error as f64, 5)
    );
    md += &format!("| light PSNR (dB) | {} | {} |\n", num(r.a.error.psnr_db, 2), num(r.b.error.psnr_db, 2));
    if !r.a.auto_chose.is_empty() || !r.b.auto_chose.is_empty() {
        md += &format!("| auto chose | {} | {} |\n", r.a.auto_chose, r.b.auto_chose);
    }
    md += &format!(
        "\n**B against A:** largest step {}, {:.3}% of pixels differ, FLIP mean {:.5} (99th percentile {:.5}, \
         largest {:.5}). `difference.png` is |B − A| per channel times {DIFFERENCE_GAIN}; `flip.png` FLIP's map.\n",
        r.max_steps,
        r.differing_pixels * 100.0,
        r.flip_mean,
        r.flip_p99,
        r.flip_max
    );
    if !r.ledger_delta.is_empty() {
        md += "\n| light | A ms | B ms | change |\n|---|---|---|---|\n";
        for d in &r.ledger_delta {
            md += &format!("| {} | {:.4} | {:.4} | {:+.4} |\n", d.light, d.a_ms, d.b_ms, d.b_ms - d.a_ms);
        }
    }
    md
}

/// Writes `a.png`, `b.png`, `flip.png`, `difference.png`, `compare.md` and `compare.json` to
/// `dir`; returns the markdown.
pub fn write_pair(dir: &Path, r: &PairReport) -> Result<String> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (name, img) in
        [("a.png", &r.a.image), ("b.png", &r.b.image), ("flip.png", &r.flip_map), ("difference.png", &r.difference)]
    {
        let p = dir.join(name);
        img.save(&p).with_context(|| format!("writing {}", p.display()))?;
    }
    let md = pair_markdown(r);
    std::fs::write(dir.join("compare.md"), &md).with_context(|| format!("writing {}", dir.display()))?;
    std::fs::write(dir.join("compare.json"), serde_json::to_string_pretty(r)?)
        .with_context(|| format!("writing {}", dir.display()))?;
    Ok(md)
}
