//! `lampshade calibrate`: the cost model's constants measured on the adapter that runs, so that
//! `auto`, the ledger and `advise` weigh with that adapter's costs instead of lavapipe's.
//!
//! **The frames.** `demo` at a few light counts, and the two largest again with every radius
//! halved (a quarter of the pairs for the same draws, so a draw's cost and a fragment's come
//! apart), under the per-light mode `volume` (a draw a light) and the list modes `clustered`,
//! `tiled` and `zbin`; at each point the four modes are timed in interleaved rounds, as `advise`
//! measures (`advise::GpuFrames::interleaved`: two warm-up frames each, then rounds of one frame
//! of each mode in turn, the median of each mode's rounds; then one counted frame each for the
//! pairs), so that a drift in the machine's load falls on every mode alike instead of on the
//! mode measured last. The whole frame is timed: the G-buffer and compose are common
//! to every mode and fall into each fit's fixed part.
//!
//! **The fits** (least squares, `CostModel::fit`):
//! - per light: `T = F + draws · draw_ms + footprint · fragment_ns` over the `volume` frames,
//!   with `draws` and `footprint` counted as `auto`'s rule counts them (`tiles::light_terms`).
//!   `stencil-two-pass` is not fitted with them: its marking draw costs less than a shading
//!   draw and its footprint's fragments are mostly rejected by the stencil test, so one draw
//!   and one fragment cost do not hold both (on lavapipe the joint fit put a draw at zero);
//! - per list mode m: `T = F_m + pairs · pair_ns`; its full-screen passes are what it costs
//!   beyond the per-light frame's fixed part, `(F_m - F) / megapixels`; its pairs per pixel of
//!   footprint the least-squares ratio of its pairs to the lights' footprint.
//!
//! A constant the frames cannot fit keeps its built-in value (`clustered`, the per-light
//! costs) or is left out (`tiled`, `zbin`: `auto` then does not weigh it), and the run says so.

use super::advise::{Candidate, Frames, GpuFrames, Point};
use crate::gpu::Gpu;
use crate::renderer::explain::cost::{CostModel, Sample};
use crate::renderer::options::calibration::{Calibration, CostConstants, ListCost, CALIBRATION_VERSION};
use crate::renderer::{CullingMode, RenderPath, Settings};
use crate::scene::builtin::{self, BuiltinOptions};
use anyhow::Result;
use serde::Serialize;

/// What `calibrate` renders.
#[derive(Clone, Debug)]
pub struct CalibrateOptions {
    /// A built-in scene that takes a light count.
    pub scene: String,
    pub size: (u32, u32),
    /// The light counts (the two largest are also drawn at half the radii).
    pub counts: Vec<usize>,
    /// Timed frames per point (their median is taken).
    pub frames: usize,
}

impl Default for CalibrateOptions {
    fn default() -> Self {
        Self { scene: "demo".into(), size: (640, 360), counts: vec![64, 256, 1024, 2048], frames: 5 }
    }
}

/// The modes measured: the per-light one first.
const MODES: [CullingMode; 4] = [CullingMode::Volume, CullingMode::Clustered, CullingMode::Tiled, CullingMode::Zbin];

/// A calibration and the frames and fits it came from.
#[derive(Clone, Debug, Serialize)]
pub struct CalibrationRun {
    pub calibration: Calibration,
    /// Per mode: its name and frames.
    pub points: Vec<(String, Vec<Point>)>,
    /// The fitted models: the per-light fit, then each list mode's (`None`: not fitted).
    pub fits: Vec<(String, Option<CostModel>)>,
    /// What could not be fitted and kept its built-in value or was left out.
    pub notes: Vec<String>,
}

/// The frames' (lights, radius scale).
fn points_of(counts: &[usize]) -> Vec<(usize, f64)> {
    let mut counts = counts.to_vec();
    counts.sort_unstable();
    counts.dedup();
    let halves: Vec<(usize, f64)> = counts.iter().rev().take(2).rev().map(|&n| (n, 0.5)).collect();
    counts.into_iter().map(|n| (n, 1.0)).chain(halves).collect()
}

/// Measures the constants on `gpu` under `key` (`crate::calibration::key`). `progress(done,
/// total, what)` is called before each point.
pub fn calibrate(
    gpu: &Gpu,
    key: &str,
    o: &CalibrateOptions,
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<CalibrationRun> {
    if !builtin::TAKES_LIGHT_COUNT.contains(&o.scene.as_str()) {
        anyhow::bail!("calibrate: '{}' is not a built-in scene that takes a light count", o.scene);
    }
    if o.counts.is_empty() || o.counts.contains(&0) || o.frames == 0 {
        anyhow::bail!("calibrate: light counts and frames must be at least 1");
    }
    let base =
        Settings { shadows: crate::renderer::ShadowMode::None, path: RenderPath::Deferred, ..Settings::default() };
    let candidates: Vec<Candidate> = MODES
        .iter()
        .map(|&culling| Candidate { name: culling.name(), settings: Settings { culling, ..base.clone() } })
        .collect();
    let name = o.scene.clone();
    let scene_at = Box::new(move |n| {
        builtin::build(&name, BuiltinOptions { lights: Some(n), time: 0.0 }).map_err(anyhow::Error::msg)
    });
    let mut frames = GpuFrames::new(gpu, candidates.clone(), scene_at, o.size, o.frames);
    let points = points_of(&o.counts);
    let total = points.len();
    let mut measured: Vec<(String, Vec<Point>)> = candidates.iter().map(|c| (c.name.clone(), Vec::new())).collect();
    let all: Vec<usize> = (0..candidates.len()).collect();
    for (k, &(n, r)) in points.iter().enumerate() {
        progress(k, total, &format!("every mode at {n} lights, radii x{r}, interleaved"));
        for ((_, v), p) in measured.iter_mut().zip(frames.interleaved(&all, n, r)) {
            v.push(p?);
        }
    }
    progress(total, total, "fitting");
    let how = format!(
        "lampshade calibrate: {} at {}x{}, {:?} lights (the two largest also at half the radii), the modes interleaved, median of {} rounds",
        o.scene, o.size.0, o.size.1, o.counts, o.frames
    );
    Ok(fit(key, &how, o.size, measured))
}

/// The constants from the frames of [`MODES`], in that order.
pub fn fit(key: &str, how: &str, size: (u32, u32), measured: Vec<(String, Vec<Point>)>) -> CalibrationRun {
    let mpx = size.0 as f64 * size.1 as f64 / 1e6;
    let mut costs = CostConstants::BUILTIN;
    let mut notes = Vec::new();
    let mut fits = Vec::new();
    let drawn: Vec<Sample> = measured
        .iter()
        .take(1)
        .flat_map(|(_, v)| v.iter())
        .map(|p| Sample { draws: p.light_draws, ideal: p.footprint, wasted: 0.0, ms: p.ms })
        .collect();
    let per_light = CostModel::fit(&drawn, "calibrate: volume frames");
    let fixed_drawn = match &per_light {
        Some(m) => {
            costs.draw_ms = m.draw_ms;
            costs.fragment_ns = m.pair_ns;
            m.fixed_ms
        }
        None => {
            notes.push("the per-light frames fitted no draw and fragment costs: built-in values kept".into());
            f64::NAN
        }
    };
    fits.push(("per light".to_string(), per_light));
    for (name, v) in measured.iter().skip(1) {
        let samples: Vec<Sample> =
            v.iter().map(|p| Sample { draws: 0.0, ideal: p.pairs, wasted: 0.0, ms: p.ms }).collect();
        let model = CostModel::fit(&samples, format!("calibrate: {name} frames"));
        let (sxy, sxx) = v.iter().fold((0.0, 0.0), |(a, b), p| (a + p.pairs * p.listed, b + p.listed * p.listed));
        let list = model.as_ref().filter(|_| fixed_drawn.is_finite() && sxx > 0.0).map(|m| ListCost {
            fixed_ms_per_mpx: (m.fixed_ms - fixed_drawn).max(0.0) / mpx,
            pair_ns: m.pair_ns,
            pairs_per_footprint: sxy / sxx,
        });
        match (name.as_str(), list) {
            ("clustered", Some(l)) => costs.clustered = l,
            ("tiled", l) => costs.tiled = l,
            ("zbin", l) => costs.zbin = l,
            _ => {}
        }
        if list.is_none() {
            notes.push(format!(
                "{name}: not fitted ({})",
                if name == "clustered" { "built-in values kept" } else { "auto does not weigh it" }
            ));
        }
        fits.push((name.clone(), model));
    }
    // The rule weighs the list modes only where the constants were measured, not below.
    if let Some(n) = measured.iter().flat_map(|(_, v)| v.iter().map(|p| p.lights)).min() {
        costs.min_lights = n;
    }
    let calibration = Calibration {
        version: CALIBRATION_VERSION,
        key: key.to_string(),
        measured: crate::calibration::today(),
        how: how.to_string(),
        costs,
    };
    CalibrationRun { calibration, points: measured, fits, notes }
}

/// The run as Markdown: the constants against the built-in ones, and each fit.
pub fn markdown(r: &CalibrationRun) -> String {
    let (c, b) = (&r.calibration.costs, CostConstants::BUILTIN);
    let list = |l: Option<ListCost>| {
        l.map_or("not weighed".to_string(), |l| {
            format!(
                "{:.2} ms/Mpx + {:.2} ns a pair x {:.3} pairs a footprint pixel",
                l.fixed_ms_per_mpx, l.pair_ns, l.pairs_per_footprint
            )
        })
    };
    let mut s = format!(
        "## Calibration\n\n{}\n\nkey: {}\n\n| constant | measured | built-in |\n|---|---|---|\n",
        r.calibration.how, r.calibration.key
    );
    s += &format!("| draw (ms) | {:.4} | {:.4} |\n", c.draw_ms, b.draw_ms);
    s += &format!("| drawn fragment (ns) | {:.2} | {:.2} |\n", c.fragment_ns, b.fragment_ns);
    s += &format!("| clustered | {} | {} |\n", list(Some(c.clustered)), list(Some(b.clustered)));
    s += &format!("| tiled | {} | {} |\n", list(c.tiled), list(b.tiled));
    s += &format!("| zbin | {} | {} |\n", list(c.zbin), list(b.zbin));
    s += &format!("| the rule weighs list modes from (lights) | {} | {} |\n\n", c.min_lights, b.min_lights);
    s += "| fit | fixed ms | draw ms | pair ns |\n|---|---|---|---|\n";
    for (name, m) in &r.fits {
        match m {
            Some(m) => s += &format!("| {name} | {:.2} | {:.4} | {:.2} |\n", m.fixed_ms, m.draw_ms, m.pair_ns),
            None => s += &format!("| {name} | - | - | - |\n"),
        }
    }
    s += "\n| mode | lights | radii | light draws | footprint (M px) | listed (M px) | pairs (M) | ms |\n|---|---|---|---|---|---|---|---|\n";
    for (name, v) in &r.points {
        for p in v {
            s += &format!(
                "| {name} | {} | x{} | {:.0} | {:.3} | {:.3} | {:.3} | {:.2} |\n",
                p.lights,
                p.radius_scale,
                p.light_draws,
                p.footprint * 1e-6,
                p.listed * 1e-6,
                p.pairs * 1e-6,
                p.ms
            );
        }
    }
    for n in &r.notes {
        s += &format!("\nnote: {n}");
    }
    s + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact frames from known constants at 640x360: the per-light frames `40 ms + 0.02 ms a
    /// draw + 30 ns a footprint pixel`, each list mode `fixed + its pairs (a share of the
    /// footprint) x its pair cost`.
    #[test]
    fn the_fit_recovers_the_constants_of_exact_frames() {
        let size = (640, 360);
        let mpx = 640.0 * 360.0 / 1e6;
        let frame = |n: usize, r: f64| {
            let footprint = n as f64 * 1000.0 * r * r;
            Point {
                lights: n,
                radius_scale: r,
                light_draws: n as f64,
                footprint,
                listed: footprint,
                ..Point::default()
            }
        };
        let at = points_of(&[256, 1024, 2048]);
        let per_light: Vec<Point> = at
            .iter()
            .map(|&(n, r)| frame(n, r))
            .map(|p| Point { ms: 40.0 + p.light_draws * 0.02 + p.footprint * 30e-6, ..p })
            .collect();
        // (name, fixed ms, pair ns, pairs per footprint pixel).
        let lists = [("clustered", 52.0, 20.0, 0.6), ("tiled", 140.0, 9.0, 1.1), ("zbin", 70.0, 27.0, 0.65)];
        let mut measured = vec![("volume".to_string(), per_light)];
        for (name, fixed, pair_ns, ppf) in lists {
            let v = at
                .iter()
                .map(|&(n, r)| {
                    let p = frame(n, r);
                    let pairs = p.listed * ppf;
                    Point { light_draws: 0.0, footprint: 0.0, pairs, ms: fixed + pairs * pair_ns * 1e-6, ..p }
                })
                .collect();
            measured.push((name.to_string(), v));
        }
        let run = fit("key", "test", size, measured);
        let c = run.calibration.costs;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs().max(1.0);
        assert!(close(c.draw_ms, 0.02) && close(c.fragment_ns, 30.0), "{c:?}");
        for (name, fixed, pair_ns, ppf) in lists {
            let l = match name {
                "clustered" => c.clustered,
                "tiled" => c.tiled.expect("tiled fitted"),
                _ => c.zbin.expect("zbin fitted"),
            };
            assert!(close(l.fixed_ms_per_mpx, (fixed - 40.0) / mpx), "{name}: {l:?}");
            assert!(close(l.pair_ns, pair_ns) && close(l.pairs_per_footprint, ppf), "{name}: {l:?}");
        }
        assert!(run.notes.is_empty(), "{:?}", run.notes);
        assert_eq!(run.calibration.key, "key");
        assert_eq!(c.min_lights, 256, "the fewest lights measured");
        assert!(markdown(&run).contains("| tiled |"));
    }
}
