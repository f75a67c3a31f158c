//! `lampshade bench SCENE --camera-path FILE`: each configuration replayed along a recorded
//! camera path, frame `n` at path time `n · step` (never the wall clock, so every configuration
//! and every machine draws the same cameras). Per configuration: the GPU frame time's median,
//! 95th and 99th percentiles, the worst frame and where on the path it fell, and the flicker:
//! the mean FLIP between adjacent frames. A moving camera changes the picture by itself, so the
//! flicker of an exact mode is the motion's alone; each row stands beside the same figure for
//! the fastest exact mode, and what a configuration adds to it is its own temporal noise.
//!
//! The configurations are drawn in interleaved rounds, one frame of each per path frame, so
//! background load falls on all of them alike.

use super::*;
use crate::scene::camera_path::{CameraPath, MIN_BENCH_FRAMES};

/// One configuration to replay along the path.
#[derive(Clone, Debug)]
pub struct PathConfig {
    pub label: String,
    pub settings: Settings,
    /// Whether the configuration draws exactly the reference's light (it only skips work): the
    /// culling modes. Only exact configurations set the motion's flicker.
    pub exact: bool,
}

/// One configuration's replay.
#[derive(Clone, Debug, Serialize)]
pub struct PathRow {
    pub label: String,
    pub exact: bool,
    pub frames: usize,
    /// GPU frame time (ms): median, 95th and 99th percentiles (nearest rank) and mean.
    pub p50_ms: f64,
    pub p95_ms: f64,
    pub p99_ms: f64,
    pub mean_ms: f64,
    /// The slowest frame: its time, number, path time and camera position.
    pub worst_ms: f64,
    pub worst_frame: usize,
    pub worst_t: f64,
    pub worst_position: [f64; 3],
    /// Mean FLIP between adjacent frames.
    pub flicker: f64,
    /// The flicker of the fastest exact configuration (by median), and its label.
    pub exact_flicker: f64,
    pub exact_label: String,
    /// What `auto` drew the lights with, by frames (empty for the other modes).
    pub auto_chose: Vec<(String, usize)>,
}

/// The `q` quantile of `v` by nearest rank (NaN when empty).
pub fn quantile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let rank = ((q * s.len() as f64).ceil() as usize).clamp(1, s.len());
    s[rank - 1]
}

/// How a path is replayed.
#[derive(Clone, Debug)]
pub struct PathOptions {
    /// Seconds of path time a frame.
    pub step: f64,
    pub size: (u32, u32),
    /// The cost model's constants `auto` weighs with.
    pub costs: crate::renderer::options::calibration::Calibration,
}

/// Replays `configs` along `path` (`o`: the step and size). `progress(done, total)` is called
/// each path frame.
pub fn run_path(
    gpu: &Gpu,
    scene: &crate::Scene,
    path: &CameraPath,
    configs: &[PathConfig],
    o: &PathOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<PathRow>> {
    let (step, size, costs) = (o.step, o.size, &o.costs);
    let frames = path.frames(step);
    if frames < MIN_BENCH_FRAMES {
        anyhow::bail!(
            "the path gives {frames} frames at a step of {step:.4} s ({:.2} s long); the bench needs at least \
             {MIN_BENCH_FRAMES} (a longer path or a smaller --path-step)",
            path.duration()
        );
    }
    if configs.is_empty() {
        anyhow::bail!("no configuration to replay");
    }
    let (w, h) = size;
    let mut scene = scene.clone();
    scene.camera = path.frame(0, step);
    struct Run {
        renderer: Renderer,
        times: Vec<f64>,
        flicker: Vec<f64>,
        last: Option<image::RgbaImage>,
        auto: std::collections::BTreeMap<String, usize>,
    }
    let mut runs = Vec::new();
    for c in configs {
        c.settings.validate().map_err(|e| anyhow::anyhow!("{}: {e}", c.label))?;
        let mut renderer = Renderer::new(gpu, OUTPUT_FORMAT, &c.settings).with_context(|| c.label.clone())?;
        renderer.set_calibration(costs.clone());
        // The warm-up frame (pipelines compile on their first draw).
        render_image(gpu, &mut renderer, &scene, &c.settings, w, h).with_context(|| c.label.clone())?;
        runs.push(Run { renderer, times: Vec::new(), flicker: Vec::new(), last: None, auto: Default::default() });
    }
    for n in 0..frames {
        progress(n, frames);
        scene.camera = path.frame(n, step);
        for (c, run) in configs.iter().zip(runs.iter_mut()) {
            let timed = Settings { count_fragments: false, timestamps: true, ..c.settings.clone() };
            let (image, stats) = render_image(gpu, &mut run.renderer, &scene, &timed, w, h)?;
            let ms = stats.gpu_ms.total.context("the adapter gave no GPU time (timestamps)")?;
            run.times.push(ms);
            if c.settings.culling == crate::renderer::CullingMode::Auto {
                let m = stats.tiles.as_ref().map_or("per-light".into(), |t| t.method.name());
                *run.auto.entry(m).or_default() += 1;
            }
            if let Some(prev) = &run.last {
                run.flicker.push(flip(prev, &image)?.0.mean as f64);
            }
            run.last = Some(image);
        }
    }
    progress(frames, frames);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let mut rows: Vec<PathRow> = configs
        .iter()
        .zip(&runs)
        .map(|(c, run)| {
            let (worst_frame, worst_ms) =
                run.times.iter().copied().enumerate().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or((0, f64::NAN));
            let at = path.frame(worst_frame, step);
            PathRow {
                label: c.label.clone(),
                exact: c.exact,
                frames,
                p50_ms: quantile(&run.times, 0.5),
                p95_ms: quantile(&run.times, 0.95),
                p99_ms: quantile(&run.times, 0.99),
                mean_ms: mean(&run.times),
                worst_ms,
                worst_frame,
                worst_t: worst_frame as f64 * step,
                worst_position: at.position.to_array(),
                flicker: mean(&run.flicker),
                exact_flicker: f64::NAN,
                exact_label: String::new(),
                auto_chose: run.auto.iter().map(|(k, v)| (k.clone(), *v)).collect(),
            }
        })
        .collect();
    let fastest = rows.iter().filter(|r| r.exact).min_by(|a, b| a.p50_ms.total_cmp(&b.p50_ms)).cloned();
    if let Some(f) = fastest {
        for r in &mut rows {
            r.exact_flicker = f.flicker;
            r.exact_label = f.label.clone();
        }
    }
    Ok(rows)
}

/// The replay as markdown.
pub fn path_markdown(rows: &[PathRow], scene: &str, path: &str, step: f64, size: (u32, u32), adapter: &str) -> String {
    let frames = rows.first().map_or(0, |r| r.frames);
    let mut md = format!(
        "# {scene} along {path}\n\n{frames} frames, {step:.5} s of path time a frame, {}x{}, on {adapter}. GPU frame \
         time (timestamps), percentiles by nearest rank; flicker: mean FLIP between adjacent frames, beside the \
         fastest exact mode's (the camera's motion alone).\n\n\
         | configuration | p50 ms | p95 ms | p99 ms | worst ms | worst frame (t s, position) | flicker | exact mode's flicker |\n\
         |---|---|---|---|---|---|---|---|\n",
        size.0, size.1
    );
    for r in rows {
        let p = r.worst_position;
        md += &format!(
            "| {}{} | {:.2} | {:.2} | {:.2} | {:.2} | {} ({:.2} s, {:.2} {:.2} {:.2}) | {:.5} | {:.5} ({}) |\n",
            r.label,
            if r.auto_chose.is_empty() {
                String::new()
            } else {
                format!(" ({})", r.auto_chose.iter().map(|(m, n)| format!("{m} ×{n}")).collect::<Vec<_>>().join(", "))
            },
            r.p50_ms,
            r.p95_ms,
            r.p99_ms,
            r.worst_ms,
            r.worst_frame,
            r.worst_t,
            p[0],
            p[1],
            p[2],
            r.flicker,
            r.exact_flicker,
            r.exact_label
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::quantile;

    #[test]
    fn quantiles_take_the_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(|x| x as f64).collect();
        assert_eq!(quantile(&v, 0.5), 50.0);
        assert_eq!(quantile(&v, 0.95), 95.0);
        assert_eq!(quantile(&v, 0.99), 99.0);
        assert_eq!(quantile(&[3.0], 0.99), 3.0);
        assert!(quantile(&[], 0.5).is_nan());
    }
}
