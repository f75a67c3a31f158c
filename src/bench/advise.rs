//! `lampshade advise`: which path and culling mode is fastest for this scene, and up to how
//! many lights each stays fastest, predicted from a short calibration and then measured.
//!
//! **The model.** A frame of candidate c with n lights costs
//!
//! ```text
//! T_c(n) = fixed_c + draws_c(n) · t_draw,c + pairs_c(n) · t_pair,c
//! ```
//!
//! the light ledger's model (`renderer::explain::cost`) over the whole frame: `fixed` holds the
//! G-buffer (or the forward depth pre-pass), compose, and a list mode's full-screen pass;
//! `draws` are the frame's light draws and `pairs` the light-pixel pairs it evaluated. The
//! coefficients are fitted (`CostModel::fit`, least squares) on calibration frames at light
//! counts below every count asked about. Draws and pairs both grow with the lights, so frames
//! that only vary the count cannot tell a draw's cost from its pairs'; half of the calibration
//! frames therefore halve every light's radius (a quarter of the pairs for the same draws).
//! The draws and pairs at the scene's own radii are fitted as lines in n (a scene's lights
//! drawn from one distribution add pairs in proportion). So each T_c is a line in n, the
//! predicted best at n is the lowest line, and a crossover (where one candidate stops being
//! fastest) is where two lines meet.
//!
//! **Then it measures**: every candidate at every count asked, once every prediction is fixed.
//! At each count the candidates are timed in interleaved rounds (one frame of each in turn,
//! round after round), so that a change in the machine's load falls on all of them alike; each
//! time is the median of the rounds' GPU times with its standard error. It prints prediction
//! against measurement, and answers with the fastest measured of the three predicted fastest,
//! judged by its regret against the measured best of all. A measured crossover lies between two
//! measured counts where the best changes; it is placed where the two candidates' measured
//! times, joined by straight lines, cross.

use crate::gpu::Gpu;
use crate::headless::render_image;
use crate::renderer::explain::cost::{CostModel, Sample};
use crate::renderer::{CullingMode, RenderPath, Renderer, Settings, OUTPUT_FORMAT};
use crate::Scene;
use anyhow::Result;
use serde::Serialize;

/// One path and culling mode the advisor weighs.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub name: String,
    pub settings: Settings,
}

/// The candidates: deferred shading with seed 000's and seed 001's volume methods, tiled,
/// clustered and z-binned lists, and forward single-pass with its tile lists (seed 002's
/// comparison).
pub fn candidates(base: &Settings) -> Vec<Candidate> {
    let mut v: Vec<Candidate> = [
        CullingMode::Volume,
        CullingMode::StencilTwoPass,
        CullingMode::Tiled,
        CullingMode::Clustered,
        CullingMode::Zbin,
    ]
    .into_iter()
    .map(|culling| Candidate {
        name: format!("deferred {}", culling.name()),
        settings: Settings { path: RenderPath::Deferred, culling, ..base.clone() },
    })
    .collect();
    v.push(Candidate { name: "forward".into(), settings: Settings { path: RenderPath::Forward, ..base.clone() } });
    v
}

/// One frame: its light count and radius scale, light draws, evaluated pairs and GPU ms.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Point {
    pub lights: usize,
    pub radius_scale: f64,
    pub draws: f64,
    pub pairs: f64,
    pub ms: f64,
    /// The standard error of the timed frames' ms (their spread / √n; 0 for one frame).
    pub se_ms: f64,
    /// `auto`'s frame-rule terms of the frame's lights as drawn (`tiles::light_terms`): their
    /// draws, their drawn footprint in pixels, and their footprint as a list mode lists it
    /// (what `lampshade calibrate` fits the rule's constants on).
    pub light_draws: f64,
    pub footprint: f64,
    pub listed: f64,
}

/// What renders the advisor's frames: the GPU ([`GpuFrames`]), or a synthetic source in tests.
pub trait Frames {
    /// Candidate `c`'s frame with `lights` lights, every radius times `radius_scale`.
    fn frame(&mut self, c: usize, lights: usize, radius_scale: f64) -> Result<Point>;

    /// Candidates `cs`' frames with `lights` lights and radii times `radius_scale`, timed in
    /// interleaved rounds (one frame of each in turn, round after round): per candidate, its
    /// frame with the median of its rounds and that median's standard error. The default takes
    /// each candidate's [`frame`](Self::frame) in turn, for a source without drift.
    fn interleaved(&mut self, cs: &[usize], lights: usize, radius_scale: f64) -> Vec<Result<Point>> {
        cs.iter().map(|&c| self.frame(c, lights, radius_scale)).collect()
    }
}

/// A candidate's fitted model: its cost model and its draws and pairs as lines in n.
#[derive(Clone, Debug, Serialize)]
pub struct Fit {
    pub model: CostModel,
    /// (at zero lights, per light).
    pub draws: (f64, f64),
    pub pairs: (f64, f64),
}

impl Fit {
    /// Fits candidate frames `points` (at least two light counts at the scene's radii).
    pub fn of(points: &[Point], source: &str) -> Option<Self> {
        let samples: Vec<Sample> =
            points.iter().map(|p| Sample { draws: p.draws, ideal: p.pairs, wasted: 0.0, ms: p.ms }).collect();
        // Frames whose times show no cost per light (noise over a pass that does not grow at
        // these counts) fit no positive coefficients: the frame is then its mean, flat.
        let model = CostModel::fit(&samples, source).unwrap_or_else(|| CostModel {
            fixed_ms: samples.iter().map(|s| s.ms).sum::<f64>() / samples.len().max(1) as f64,
            draw_ms: 0.0,
            pair_ns: 0.0,
            reject_ns: None,
            source: format!("{source} (flat: no cost per light measurable)"),
        });
        let own: Vec<&Point> = points.iter().filter(|p| p.radius_scale == 1.0).collect();
        let line = |f: &dyn Fn(&Point) -> f64| line(&own.iter().map(|p| (p.lights as f64, f(p))).collect::<Vec<_>>());
        Some(Self { model, draws: line(&|p| p.draws), pairs: line(&|p| p.pairs) })
    }

    /// The predicted frame time at `n` lights: (at zero lights, per light) of the line T(n).
    pub fn time_line(&self) -> (f64, f64) {
        let m = &self.model;
        let at0 = m.fixed_ms + self.draws.0 * m.draw_ms + self.pairs.0 * m.pair_ns * 1e-6;
        let per = self.draws.1 * m.draw_ms + self.pairs.1 * m.pair_ns * 1e-6;
        (at0, per)
    }

    pub fn predict(&self, n: f64) -> f64 {
        let (a, b) = self.time_line();
        a + b * n
    }
}

/// Least-squares line y = a + b x through `xy` (the mean, flat, with one distinct x), the
/// slope held at zero or above and the intercept at zero or above (no frame has fewer than no
/// draws or pairs).
fn line(xy: &[(f64, f64)]) -> (f64, f64) {
    let n = xy.len().max(1) as f64;
    let (mx, my) = (xy.iter().map(|p| p.0).sum::<f64>() / n, xy.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return (my.max(0.0), 0.0);
    }
    let b = (sxy / sxx).max(0.0);
    let a = my - b * mx;
    if a < 0.0 {
        // Through the origin.
        let b0 = xy.iter().map(|p| p.0 * p.1).sum::<f64>() / xy.iter().map(|p| p.0 * p.0).sum::<f64>().max(1e-300);
        return (0.0, b0.max(0.0));
    }
    (a, b)
}

/// The calibration frames for counts `asked`, (lights, radius scale): a quarter and a half of
/// the fewest asked, and an eighth of the most asked when that lies further up (so the lines
/// are fitted over a span of counts, not extrapolated from the smallest alone), at the scene's
/// radii; the last two again at half the radii. None is a count asked about, and each costs at
/// most an eighth of the largest frame measured.
pub fn calibration_counts(asked: &[usize]) -> Vec<(usize, f64)> {
    let least = asked.iter().copied().min().unwrap_or(1).max(1);
    let most = asked.iter().copied().max().unwrap_or(1).max(1);
    let mut v: Vec<usize> = vec![(least / 4).max(1), (least / 2).max(1)];
    if most / 8 > least / 2 && !asked.contains(&(most / 8)) {
        v.push(most / 8);
    }
    v.dedup();
    if v.len() < 2 && least > 1 {
        v = vec![1, least - 1];
    }
    let halves: Vec<(usize, f64)> = v.iter().rev().take(2).rev().map(|&n| (n, 0.5)).collect();
    v.into_iter().map(|n| (n, 1.0)).chain(halves).collect()
}

/// Where the lower envelope of the lines `lines` (candidate, (a, b)) changes candidate between
/// `lo` and `hi` lights: (n, the candidate fastest below n, the one fastest above).
pub fn crossovers(lines: &[(usize, (f64, f64))], lo: f64, hi: f64) -> Vec<(f64, usize, usize)> {
    let best =
        |n: f64| lines.iter().min_by(|x, y| (x.1 .0 + x.1 .1 * n).total_cmp(&(y.1 .0 + y.1 .1 * n))).map(|x| x.0);
    let mut out = Vec::new();
    let Some(mut current) = best(lo) else { return out };
    let mut n = lo;
    // Walk the envelope: from the current line, the nearest crossing ahead with a line that
    // is lower past it.
    while n < hi {
        let (a, b) = lines.iter().find(|x| x.0 == current).map(|x| x.1).unwrap_or_default();
        let next = lines
            .iter()
            .filter(|x| x.0 != current && x.1 .1 < b)
            .map(|x| ((x.1 .0 - a) / (b - x.1 .1), x.0))
            .filter(|(m, _)| *m > n && *m < hi)
            .min_by(|p, q| p.0.total_cmp(&q.0));
        let Some((m, c)) = next else { break };
        out.push((m, current, c));
        current = c;
        n = m;
    }
    out
}

/// Where measured times cross: between consecutive counts where the measured best changes,
/// where the two candidates' times, joined by straight lines in n, meet.
pub fn measured_crossovers(counts: &[usize], ms: &[Vec<f64>]) -> Vec<(f64, usize, usize)> {
    let best =
        |k: usize| (0..ms.len()).filter(|&c| ms[c][k].is_finite()).min_by(|&a, &b| ms[a][k].total_cmp(&ms[b][k]));
    let mut out = Vec::new();
    for k in 1..counts.len() {
        let (Some(a), Some(b)) = (best(k - 1), best(k)) else { continue };
        if a == b {
            continue;
        }
        let (n0, n1) = (counts[k - 1] as f64, counts[k] as f64);
        let d0 = ms[a][k - 1] - ms[b][k - 1];
        let d1 = ms[a][k] - ms[b][k];
        let t = if (d0 - d1).abs() > 0.0 { d0 / (d0 - d1) } else { 0.5 };
        out.push((n0 + t.clamp(0.0, 1.0) * (n1 - n0), a, b));
    }
    out
}

/// The advisor's answer.
#[derive(Clone, Debug, Serialize)]
pub struct Advice {
    pub scene: String,
    pub size: (u32, u32),
    pub candidates: Vec<String>,
    /// The calibration frames: (lights, radius scale).
    pub calibration: Vec<(usize, f64)>,
    pub counts: Vec<usize>,
    /// Per candidate: its calibration frames, and its fit (`None` when they could not be
    /// fitted or drawn).
    pub points: Vec<Vec<Point>>,
    pub fits: Vec<Option<Fit>>,
    /// Per candidate, per count: predicted and measured ms (NaN where not drawn).
    pub predicted: Vec<Vec<f64>>,
    pub measured: Vec<Vec<f64>>,
    /// Per candidate, per count: the measured ms's standard error.
    pub measured_se: Vec<Vec<f64>>,
    /// Why a candidate's frames were not drawn, if so.
    pub refused: Vec<Option<String>>,
    pub predicted_crossovers: Vec<(f64, usize, usize)>,
    pub measured_crossovers: Vec<(f64, usize, usize)>,
}

/// The predicted candidates the advisor measures before it answers.
pub const MEASURED_TOP: usize = 3;

impl Advice {
    /// The answer at count index `k`: of the [`MEASURED_TOP`] candidates predicted fastest, the
    /// one measured fastest (`None` when none of them was drawn).
    pub fn answer(&self, k: usize) -> Option<usize> {
        let mut order: Vec<usize> = (0..self.predicted.len()).filter(|&c| self.predicted[c][k].is_finite()).collect();
        order.sort_by(|&a, &b| self.predicted[a][k].total_cmp(&self.predicted[b][k]));
        order
            .into_iter()
            .take(MEASURED_TOP)
            .filter(|&c| self.measured[c][k].is_finite())
            .min_by(|&a, &b| self.measured[a][k].total_cmp(&self.measured[b][k]))
    }

    /// The answer's regret at count index `k`: its measured ms over the measured best's, and
    /// whether it is met (the answer is the best, or the two differ by less than two combined
    /// standard errors).
    pub fn regret(&self, k: usize) -> Option<(f64, bool)> {
        let (a, (_, b)) = (self.answer(k)?, self.best(k));
        let b = b?;
        let (ta, tb) = (self.measured[a][k], self.measured[b][k]);
        let noise = 2.0 * (self.measured_se[a][k].powi(2) + self.measured_se[b][k].powi(2)).sqrt();
        Some((ta / tb, a == b || ta - tb < noise))
    }

    /// The predicted and the measured best candidate at count index `k`.
    pub fn best(&self, k: usize) -> (Option<usize>, Option<usize>) {
        let pick = |t: &Vec<Vec<f64>>| {
            (0..t.len()).filter(|&c| t[c][k].is_finite()).min_by(|&a, &b| t[a][k].total_cmp(&t[b][k]))
        };
        (pick(&self.predicted), pick(&self.measured))
    }
}

/// Runs the advisor over `frames`: calibrates every candidate, predicts, then measures at
/// `counts`. `progress(done, total, what)` is called before each frame.
pub fn advise(
    frames: &mut dyn Frames,
    scene: &str,
    size: (u32, u32),
    candidates: &[Candidate],
    counts: &[usize],
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<Advice> {
    let mut counts = counts.to_vec();
    counts.sort_unstable();
    counts.dedup();
    let calibration = calibration_counts(&counts);
    let total = candidates.len() * calibration.len() + counts.len();
    let mut done = 0;
    let (mut fits, mut refused, mut all_points) = (Vec::new(), Vec::new(), Vec::new());
    let mut predicted = vec![vec![f64::NAN; counts.len()]; candidates.len()];
    let mut measured = vec![vec![f64::NAN; counts.len()]; candidates.len()];
    let mut measured_se = vec![vec![f64::NAN; counts.len()]; candidates.len()];
    // Candidate by candidate: its calibration, its fit and its prediction.
    for (c, cand) in candidates.iter().enumerate() {
        let mut points = Vec::new();
        let mut why = None;
        for &(n, k) in &calibration {
            progress(done, total, &format!("calibrating {} at {n} lights, radii x{k}", cand.name));
            done += 1;
            match frames.frame(c, n, k) {
                Ok(p) => points.push(p),
                Err(e) => why = Some(format!("{e:#}")),
            }
        }
        let fit = if why.is_none() { Fit::of(&points, "calibration frames") } else { None };
        for (k, &n) in counts.iter().enumerate() {
            predicted[c][k] = fit.as_ref().map_or(f64::NAN, |f| f.predict(n as f64));
        }
        fits.push(fit);
        refused.push(why);
        all_points.push(points);
    }
    // Then every count, the candidates that drew interleaved round by round.
    for (k, &n) in counts.iter().enumerate() {
        progress(done, total, &format!("measuring every candidate at {n} lights, interleaved"));
        done += 1;
        let live: Vec<usize> = (0..candidates.len()).filter(|&c| refused[c].is_none()).collect();
        for (&c, r) in live.iter().zip(frames.interleaved(&live, n, 1.0)) {
            match r {
                Ok(p) => (measured[c][k], measured_se[c][k]) = (p.ms, p.se_ms),
                Err(e) => refused[c] = Some(format!("{e:#}")),
            }
        }
    }
    progress(total, total, "done");
    let lines: Vec<(usize, (f64, f64))> =
        fits.iter().enumerate().filter_map(|(c, f)| Some((c, f.as_ref()?.time_line()))).collect();
    let (lo, hi) = (counts.first().copied().unwrap_or(1) as f64, counts.last().copied().unwrap_or(1) as f64);
    Ok(Advice {
        scene: scene.into(),
        size,
        candidates: candidates.iter().map(|c| c.name.clone()).collect(),
        calibration,
        predicted_crossovers: crossovers(&lines, lo, hi),
        measured_crossovers: measured_crossovers(&counts, &measured),
        counts,
        points: all_points,
        fits,
        predicted,
        measured,
        measured_se,
        refused,
    })
}

/// The GPU's frames: the scene at each light count (`scene_at`), each candidate on its own
/// renderer, timed as the bench times (a warm-up frame, then the median of `timed` frames'
/// GPU ms) and counted once for its draws and pairs.
pub struct GpuFrames<'a> {
    pub gpu: &'a Gpu,
    pub candidates: Vec<Candidate>,
    pub scene_at: Box<dyn FnMut(usize) -> Result<Scene> + 'a>,
    pub size: (u32, u32),
    pub timed: usize,
    /// The calibration each candidate's renderer weighs with (the defaults unless set).
    pub calibration: crate::renderer::options::calibration::Calibration,
    renderers: Vec<Option<Renderer>>,
    scenes: Vec<((usize, u64), Scene)>,
}

impl<'a> GpuFrames<'a> {
    pub fn new(
        gpu: &'a Gpu,
        candidates: Vec<Candidate>,
        scene_at: Box<dyn FnMut(usize) -> Result<Scene> + 'a>,
        size: (u32, u32),
        timed: usize,
    ) -> Self {
        let renderers = candidates.iter().map(|_| None).collect();
        Self {
            gpu,
            candidates,
            scene_at,
            size,
            timed: timed.max(1),
            calibration: Default::default(),
            renderers,
            scenes: Vec::new(),
        }
    }
}

impl GpuFrames<'_> {
    /// The scene at `lights` lights with its radii scaled, made once.
    fn scene(&mut self, lights: usize, radius_scale: f64) -> Result<usize> {
        let key = (lights, radius_scale.to_bits());
        if let Some(i) = self.scenes.iter().position(|(k, _)| *k == key) {
            return Ok(i);
        }
        let mut s = (self.scene_at)(lights)?;
        if radius_scale != 1.0 {
            super::configs::scale_light_radii(&mut s, radius_scale);
        }
        self.scenes.push((key, s));
        Ok(self.scenes.len() - 1)
    }

    /// Candidate `c`'s timed settings, and its renderer made once.
    fn timed_settings(&mut self, c: usize) -> Result<Settings> {
        let base = &self.candidates[c].settings;
        let timed = Settings { count_fragments: false, count_ideal: false, timestamps: true, ..base.clone() };
        if self.renderers[c].is_none() {
            let mut r = Renderer::new(self.gpu, OUTPUT_FORMAT, &timed)?;
            r.set_calibration(self.calibration.clone());
            self.renderers[c] = Some(r);
        }
        Ok(timed)
    }

    /// One frame of candidate `c` on scene `s`: its GPU ms and its draw calls.
    fn time(&mut self, c: usize, s: usize, settings: &Settings) -> Result<(f64, f64)> {
        let (w, h) = self.size;
        let r = self.renderers[c].as_mut().ok_or_else(|| anyhow::anyhow!("no renderer for candidate {c}"))?;
        let (_, stats) = render_image(self.gpu, r, &self.scenes[s].1, settings, w, h)?;
        Ok((stats.gpu_ms.total.unwrap_or(f64::NAN), stats.draw_calls as f64))
    }
}

impl GpuFrames<'_> {
    /// Candidate `c`'s frame on scene `s` counted for its draws and pairs, with the timed
    /// frames `times` (their median and its standard error).
    fn counted(&mut self, c: usize, s: usize, timed: &Settings, times: &[f64], draws: f64) -> Result<Point> {
        let counted = Settings { count_fragments: true, count_ideal: false, timestamps: false, ..timed.clone() };
        let (w, h) = self.size;
        let ((lights, radius_scale), scene) = (self.scenes[s].0, &self.scenes[s].1);
        let r = self.renderers[c].as_mut().ok_or_else(|| anyhow::anyhow!("no renderer for candidate {c}"))?;
        let (_, stats) = render_image(self.gpu, r, scene, &counted, w, h)?;
        // The pairs: each light's evaluated samples summed (the forward path's lights share
        // each object's fragments), else the frame's shaded fragments.
        let per_light: Option<u64> = stats.per_light.iter().map(|l| l.shaded).sum();
        let pairs = per_light.filter(|_| !stats.per_light.is_empty()).or(stats.shaded_fragments).unwrap_or(0);
        let pixels = w as f64 * h as f64;
        let (mut light_draws, mut footprint, mut listed) = (0.0, 0.0, 0.0);
        for l in &stats.per_light {
            let (d, f, s) = crate::renderer::tiles::light_terms(l.method, l.screen_share, pixels);
            light_draws += d;
            footprint += f;
            listed += s;
        }
        let (ms, se_ms) = super::run::median_se(times);
        let radius_scale = f64::from_bits(radius_scale);
        Ok(Point { lights, radius_scale, draws, pairs: pairs as f64, ms, se_ms, light_draws, footprint, listed })
    }
}

impl Frames for GpuFrames<'_> {
    /// Two warm-up frames (the first of a new scene or size builds what it needs, lavapipe
    /// compiles shaders on first use), the timed frames, then one counted: one candidate's
    /// rounds.
    fn frame(&mut self, c: usize, lights: usize, radius_scale: f64) -> Result<Point> {
        self.interleaved(&[c], lights, radius_scale).pop().unwrap_or_else(|| Err(anyhow::anyhow!("no frame")))
    }

    /// Each candidate warmed by two frames, then `timed` rounds of one frame of each in turn,
    /// then each counted.
    fn interleaved(&mut self, cs: &[usize], lights: usize, radius_scale: f64) -> Vec<Result<Point>> {
        let s = match self.scene(lights, radius_scale) {
            Ok(s) => s,
            Err(e) => return cs.iter().map(|_| Err(anyhow::anyhow!("{e:#}"))).collect(),
        };
        let mut settings: Vec<Result<Settings>> = Vec::new();
        for &c in cs {
            let warmed = self.timed_settings(c).and_then(|t| {
                for _ in 0..2 {
                    self.time(c, s, &t)?;
                }
                Ok(t)
            });
            settings.push(warmed);
        }
        let mut times = vec![Vec::new(); cs.len()];
        let mut draws = vec![0.0; cs.len()];
        for _ in 0..self.timed {
            for (i, &c) in cs.iter().enumerate() {
                let Ok(t) = &settings[i] else { continue };
                match self.time(c, s, &t.clone()) {
                    Ok((ms, d)) => {
                        times[i].push(ms);
                        draws[i] = d;
                    }
                    Err(e) => settings[i] = Err(e),
                }
            }
        }
        cs.iter().enumerate().zip(settings).map(|((i, &c), t)| self.counted(c, s, &t?, &times[i], draws[i])).collect()
    }
}

/// `scene` with `n` of its lights, evenly strided (all of them when it has no more).
pub fn strided(scene: &Scene, n: usize) -> Scene {
    let len = scene.lights.len();
    let mut s = scene.clone();
    if n < len {
        s.set_lights((0..n).map(|k| scene.lights[k * len / n]).collect());
    }
    s
}

/// The advice as Markdown: the model per candidate, prediction against measurement per count,
/// the best of each, and the crossovers.
pub fn markdown(a: &Advice) -> String {
    let fmt = |v: f64| if v.is_finite() { format!("{v:.2}") } else { "-".into() };
    let name = |c: usize| a.candidates.get(c).cloned().unwrap_or_default();
    let mut s = format!(
        "## Advice for `{}` at {}x{}\n\nCalibrated on frames at (lights, radius scale) {:?} (below every count asked), then measured. \
         T(n) = fixed + draws(n) x t_draw + pairs(n) x t_pair, each candidate's coefficients fitted on its \
         calibration frames (GPU ms, medians).\n\n\
         | candidate | fixed ms | t_draw ms | t_pair ns | draws per light | pairs per light | refused |\n|---|---|---|---|---|---|---|\n",
        a.scene, a.size.0, a.size.1, a.calibration
    );
    for (c, f) in a.fits.iter().enumerate() {
        match f {
            Some(f) => {
                s += &format!(
                    "| {} | {:.2} | {:.4} | {:.2} | {:.2} | {:.0} | {} |\n",
                    name(c),
                    f.model.fixed_ms,
                    f.model.draw_ms,
                    f.model.pair_ns,
                    f.draws.1,
                    f.pairs.1,
                    a.refused[c].as_deref().unwrap_or("")
                )
            }
            None => {
                s += &format!("| {} | - | - | - | - | - | {} |\n", name(c), a.refused[c].as_deref().unwrap_or("no fit"))
            }
        }
    }
    s += "\n| lights | candidate | predicted ms | measured ms | predicted / measured |\n|---|---|---|---|---|\n";
    for (k, &n) in a.counts.iter().enumerate() {
        for c in 0..a.candidates.len() {
            let (p, m) = (a.predicted[c][k], a.measured[c][k]);
            s += &format!("| {n} | {} | {} | {} | {} |\n", name(c), fmt(p), fmt(m), fmt(p / m));
        }
    }
    let met = (0..a.counts.len()).filter(|&k| a.regret(k).is_some_and(|r| r.1)).count();
    s += &format!(
        "\nThe answer at each count: of the {MEASURED_TOP} candidates predicted fastest, the one measured fastest. \
         Its regret is its measured ms over the measured best's, met where it is the best or the two differ by \
         less than two combined standard errors: met at {met} of {} counts.\n\n\
         | lights | predicted best | answer | measured best | agree | the predicted best's measured ms / the best's | regret | met |\n\
         |---|---|---|---|---|---|---|---|\n",
        a.counts.len()
    );
    for (k, &n) in a.counts.iter().enumerate() {
        let (p, m) = a.best(k);
        let n_of = |c: Option<usize>| c.map_or("-".to_string(), name);
        let ratio = match (p, m) {
            (Some(p), Some(m)) => a.measured[p][k] / a.measured[m][k],
            _ => f64::NAN,
        };
        let (regret, met) =
            a.regret(k).map_or(("-".to_string(), "-"), |(r, m)| (format!("{r:.3}"), if m { "yes" } else { "no" }));
        s += &format!(
            "| {n} | {} | {} | {} | {} | {} | {regret} | {met} |\n",
            n_of(p),
            n_of(a.answer(k)),
            n_of(m),
            if p == m { "yes" } else { "no" },
            fmt(ratio)
        );
    }
    let cross = |v: &[(f64, usize, usize)]| {
        if v.is_empty() {
            "none in the range asked".to_string()
        } else {
            v.iter()
                .map(|(n, x, y)| format!("{} stops being fastest at {n:.0} lights ({} from there)", name(*x), name(*y)))
                .collect::<Vec<_>>()
                .join("; ")
        }
    };
    s += &format!(
        "\nPredicted crossovers: {}.\n\nMeasured crossovers: {}.\n",
        cross(&a.predicted_crossovers),
        cross(&a.measured_crossovers)
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Frames from known costs: per candidate a fixed part, a draw cost and a pair cost, draws
    /// proportional to the lights and pairs to the lights times the radius squared, the time
    /// disturbed by a fixed pattern of up to ±`noise` (no randomness in the suite).
    struct Synthetic {
        costs: Vec<(f64, f64, f64, f64, f64)>,
        noise: f64,
        k: u64,
    }

    impl Synthetic {
        fn truth(&self, c: usize, lights: f64) -> f64 {
            let (fixed, draw_ms, pair_ns, draws_per, pairs_per) = self.costs[c];
            fixed + draws_per * lights * draw_ms + pairs_per * lights * pair_ns * 1e-6
        }
    }

    impl Frames for Synthetic {
        fn frame(&mut self, c: usize, lights: usize, radius_scale: f64) -> Result<Point> {
            let (fixed, draw_ms, pair_ns, draws_per, pairs_per) = self.costs[c];
            let (draws, pairs) = (draws_per * lights as f64, pairs_per * lights as f64 * radius_scale * radius_scale);
            self.k += 1;
            let noise = 1.0 + self.noise * [1.0, -1.0, 0.5, -0.5, 0.0][(self.k % 5) as usize];
            Ok(Point {
                lights,
                radius_scale,
                draws,
                pairs,
                ms: (fixed + draws * draw_ms + pairs * pair_ns * 1e-6) * noise,
                ..Point::default()
            })
        }
    }

    /// A volume-like candidate (a draw per light at 0.3 ms, 40,000 pairs per light at 17 ns)
    /// and a list-like one (no draws, a full-screen fixed part, cheaper pairs).
    const COSTS: [(f64, f64, f64, f64, f64); 2] = [(30.0, 0.3, 17.0, 1.0, 40_000.0), (45.0, 0.0, 12.0, 0.0, 25_000.0)];
    const COUNTS: [usize; 4] = [64, 256, 1024, 4096];

    fn run(noise: f64) -> (Advice, Synthetic) {
        let mut f = Synthetic { costs: COSTS.to_vec(), noise, k: 0 };
        let cands: Vec<Candidate> = ["volume-like", "list-like"]
            .iter()
            .map(|n| Candidate { name: n.to_string(), settings: Settings::default() })
            .collect();
        let a = advise(&mut f, "synthetic", (1280, 720), &cands, &COUNTS, &mut |_, _, _| {}).unwrap();
        (a, f)
    }

    #[test]
    fn the_model_recovers_known_draw_and_pair_costs_within_5_percent() {
        // Frames disturbed by ±1%: every coefficient within 5%.
        let (a, _) = run(0.01);
        for (c, &cost) in COSTS.iter().enumerate() {
            let m = &a.fits[c].as_ref().unwrap().model;
            assert!(near_all(m, cost), "candidate {c}: {m:?} against {cost:?}");
        }
        // The exact lines cross where 30 + 0.98 n = 45 + 0.3 n: n = 22, below the range asked,
        // so the list-like candidate is fastest throughout, predicted and measured.
        for k in 0..a.counts.len() {
            assert_eq!(a.best(k), (Some(1), Some(1)));
        }
        // Without the halved radii the draw cost cannot be told from the pairs', even from
        // undisturbed frames.
        let mut f = Synthetic { costs: COSTS.to_vec(), noise: 0.0, k: 0 };
        let only_counts: Vec<Point> = [16, 32, 512].iter().map(|&n| f.frame(0, n, 1.0).unwrap()).collect();
        let m = Fit::of(&only_counts, "counts only").map(|f| f.model);
        assert!(m.as_ref().is_none_or(|m| !near_all(m, COSTS[0])), "{m:?}");
    }

    #[test]
    fn predictions_at_the_counts_asked_stay_within_5_percent_of_the_truth_under_2_percent_noise() {
        let (a, f) = run(0.02);
        for c in 0..COSTS.len() {
            for (k, &n) in a.counts.iter().enumerate() {
                let (p, t) = (a.predicted[c][k], f.truth(c, n as f64));
                assert!((p - t).abs() <= 0.05 * t, "candidate {c} at {n}: predicted {p}, truly {t}");
            }
        }
    }

    fn near_all(m: &CostModel, (fixed, draw_ms, pair_ns, _, _): (f64, f64, f64, f64, f64)) -> bool {
        let near = |got: f64, want: f64| (got - want).abs() <= 0.05 * want.max(1e-9);
        near(m.fixed_ms, fixed) && near(m.draw_ms, draw_ms) && near(m.pair_ns, pair_ns)
    }

    /// The answer is the fastest measured of the three predicted fastest, and its regret is met
    /// within two combined standard errors of the measured best.
    #[test]
    fn the_answer_is_the_fastest_measured_of_the_top_three_predicted_and_its_regret_is_judged_by_noise() {
        let names = ["a", "b", "c", "d"];
        // One count. Predicted: a < b < c < d. Measured: d fastest (10), then b (11), c, a.
        let advice = |se: f64| Advice {
            scene: "s".into(),
            size: (1, 1),
            candidates: names.iter().map(|n| n.to_string()).collect(),
            calibration: Vec::new(),
            counts: vec![64],
            points: vec![Vec::new(); 4],
            fits: vec![None; 4],
            predicted: vec![vec![1.0], vec![2.0], vec![3.0], vec![4.0]],
            measured: vec![vec![14.0], vec![11.0], vec![12.0], vec![10.0]],
            measured_se: vec![vec![se]; 4],
            refused: vec![None; 4],
            predicted_crossovers: Vec::new(),
            measured_crossovers: Vec::new(),
        };
        // d is not among the top three predicted: the answer is b, 1.1 x the best.
        let a = advice(0.1);
        assert_eq!((a.answer(0), a.best(0)), (Some(1), (Some(0), Some(3))));
        let (regret, met) = a.regret(0).expect("a regret");
        assert!((regret - 1.1).abs() < 1e-12 && !met, "{regret} {met}");
        // With 0.4 ms standard errors, 1 ms < 2 x sqrt(0.32) = 1.13 ms: met.
        assert_eq!(advice(0.4).regret(0).map(|r| r.1), Some(true));
        assert!(markdown(&a).contains("met at 0 of 1 counts"), "{}", markdown(&a));
    }

    /// A machine whose load grows through the run: two candidates of the same true cost are
    /// measured, count by count, next to each other, so the drift falls on both alike. Measured
    /// candidate by candidate after each one's calibration, the second would read 15% slower.
    #[test]
    fn candidates_are_measured_side_by_side_so_a_drifting_load_falls_on_all_alike() {
        struct Drift {
            inner: Synthetic,
            frames: f64,
        }
        impl Frames for Drift {
            fn frame(&mut self, c: usize, lights: usize, radius_scale: f64) -> Result<Point> {
                let p = self.inner.frame(c, lights, radius_scale)?;
                self.frames += 1.0;
                Ok(Point { ms: p.ms * (1.0 + 0.02 * self.frames), ..p })
            }
        }
        let mut f = Drift { inner: Synthetic { costs: vec![COSTS[0]; 2], noise: 0.0, k: 0 }, frames: 0.0 };
        let cands: Vec<Candidate> =
            ["a", "b"].iter().map(|n| Candidate { name: n.to_string(), settings: Settings::default() }).collect();
        let a = advise(&mut f, "drift", (1280, 720), &cands, &COUNTS, &mut |_, _, _| {}).unwrap();
        for k in 0..COUNTS.len() {
            let ratio = a.measured[1][k] / a.measured[0][k];
            assert!((1.0..1.05).contains(&ratio), "at {}: b / a = {ratio}", COUNTS[k]);
        }
    }

    #[test]
    fn crossovers_follow_the_lower_envelope() {
        // y = 10 + n, y = 40 + 0.5 n, y = 100 + 0.1 n: 1 -> 2 at n = 60, 2 -> 3 at n = 150.
        let lines = [(0, (10.0, 1.0)), (1, (40.0, 0.5)), (2, (100.0, 0.1))];
        let x = crossovers(&lines, 1.0, 1000.0);
        assert_eq!(x.len(), 2);
        assert!((x[0].0 - 60.0).abs() < 1e-9 && (x[0].1, x[0].2) == (0, 1));
        assert!((x[1].0 - 150.0).abs() < 1e-9 && (x[1].1, x[1].2) == (1, 2));
        let m = measured_crossovers(&[10, 100], &[vec![20.0, 110.0], vec![45.0, 90.0]]);
        // d0 = -25, d1 = 20: t = 25/45 of the way from 10 to 100.
        assert_eq!(m.len(), 1);
        assert!((m[0].0 - 60.0).abs() < 1e-9);
    }
}
