//! The `ledger` group: the per-light cost model (`renderer::explain::cost`) fitted and checked
//! against reality, per culling mode, on the bench's scene.
//!
//! For each mode:
//! 1. **fit** on frames that each shade a subset of the lights (every fourth and every other
//!    light by evaluated pairs; the half and the quarter with the fewest pairs, and with the
//!    most; the half with the least and with the most wasted share), each counted for its own
//!    draws and pairs, then timed (not the empty set: a frame without lights skips passes,
//!    the lists, so it is not on the model's line). `fullscreen` runs first: its pair cost is
//!    a rejected pair's (nearly all its pairs are), and the drawn modes price their wasted
//!    pairs at it (`CostModel::fit_with_reject`). Their one-rate fit is kept beside it, and
//!    each removal shows both predictions;
//! 2. **the sum**: the model's fixed part plus every light's cost against the whole set's
//!    measured light pass, a frame the fit never saw (goal: within ±10%, or within the pass's
//!    own round-to-round spread where that is larger, on adapters whose timing noise is
//!    comparable to a light's cost; the report says which bound held);
//! 3. **the removals**: the ten costliest lights, each taken out in turn; the measured saving
//!    (the median over rounds of whole-set time minus the set without it, interleaved round by
//!    round) against the light's cost in the model (goal: within ±20%). A removal is resolved
//!    when its measured saving exceeds three standard errors; an unresolved one is reported
//!    with its noise, not counted as a pass or a failure, and the report counts both per mode;
//! 4. **the ledger's own cost**: the light pass with the per-light counters on against off, in
//!    the same rounds.

use super::*;
use crate::renderer::explain::cost::{self, CostModel, Sample};
use crate::renderer::LightStats;

/// The modes the ledger group checks: every mode whose lights all go one way (`auto` mixes
/// methods per light; its lights' costs come from the modes it mixes).
pub fn ledger_modes() -> impl Iterator<Item = CullingMode> {
    CullingMode::ALL.into_iter().filter(|m| *m != CullingMode::Auto)
}

/// The group's name for `--only` (apart from [`GROUPS`]: its rows are not configurations).
pub const LEDGER_GROUP: &str = "ledger";

/// Lights taken out one at a time.
pub const REMOVALS: usize = 10;

/// One light of a mode's ten costliest.
#[derive(Clone, Debug, Serialize)]
pub struct CostlyLight {
    pub index: usize,
    pub kind: String,
    pub draws: u64,
    pub pairs: u64,
    pub ideal: Option<u64>,
    pub wasted: Option<u64>,
    /// Its cost in the fitted model (ms).
    pub predicted_ms: f64,
    /// Its cost in the one-rate fit (every evaluated pair at one cost), where the model
    /// prices rejected pairs apart (ms).
    pub one_rate_ms: Option<f64>,
    /// The measured saving without it (ms), and that saving's standard error.
    pub measured_ms: f64,
    pub noise_ms: f64,
}

impl CostlyLight {
    /// Whether the measurement resolves the light: its saving exceeds three standard errors.
    pub fn resolved(&self) -> bool {
        self.measured_ms > 3.0 * self.noise_ms
    }

    pub fn within(&self) -> bool {
        self.within_of(self.predicted_ms)
    }

    /// Whether the measured saving is within ±20% of `predicted` (ms).
    pub fn within_of(&self, predicted: f64) -> bool {
        (self.measured_ms - predicted).abs() <= 0.2 * predicted
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct LedgerRow {
    pub mode: String,
    #[serde(skip)]
    pub culling: CullingMode,
    pub lights: usize,
    pub size: (u32, u32),
    pub model: Option<CostModel>,
    /// The one-rate fit beside a model that prices rejected pairs apart.
    pub one_rate: Option<CostModel>,
    /// The fit's frames: (draws, pairs, measured ms).
    pub samples: Vec<Sample>,
    /// The whole set: the model's fixed part + the lights' costs, against the measured pass.
    pub predicted_ms: f64,
    pub measured_ms: f64,
    /// The whole set by the one-rate fit, where the model prices rejected pairs apart.
    pub one_rate_predicted_ms: Option<f64>,
    /// The whole set's light pass, its round-to-round spread (the rounds' standard deviation).
    pub measured_spread_ms: f64,
    pub costliest: Vec<CostlyLight>,
    /// The light pass with the ledger's counters on and off (medians, ms).
    pub counted_ms: f64,
    pub uncounted_ms: f64,
    /// Why the mode has no row (it could not be built or rendered here).
    pub error: Option<String>,
}

impl LedgerRow {
    /// The sum's relative error.
    pub fn sum_error(&self) -> f64 {
        (self.predicted_ms - self.measured_ms) / self.measured_ms
    }

    /// The sum check's bound (ms) and which it is: ±10% of the measured pass, or the pass's
    /// round-to-round spread where that is larger.
    pub fn sum_bound(&self) -> (f64, &'static str) {
        let tenth = 0.1 * self.measured_ms;
        if self.measured_spread_ms > tenth {
            (self.measured_spread_ms, "spread")
        } else {
            (tenth, "±10%")
        }
    }

    /// Whether the sum check holds.
    pub fn sum_holds(&self) -> bool {
        (self.predicted_ms - self.measured_ms).abs() <= self.sum_bound().0
    }
}

/// Runs the group: a row per mode of [`ledger_modes`] (the reference's budget keeps
/// `fullscreen` out where its frame would take minutes).
pub fn ledger(
    gpu: &Gpu,
    o: &BenchOptions,
    files: &mut super::run::SceneFiles,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<LedgerRow>> {
    let lights = (!o.fixed_lights).then_some(o.lights);
    let scene = files.open(&o.scene, BuiltinOptions { lights, time: o.time })?;
    let pairs = scene.lights.len() as f64 * o.size.0 as f64 * o.size.1 as f64;
    // Each light's ideal pairs (its true shape over the G-buffer: the same in every mode),
    // counted once.
    progress("ledger: ideal counts");
    let ideal: Vec<u64> = {
        let s = Settings { count_ideal: true, shadows: ShadowMode::None, ..Settings::default() };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s)?;
        let stats = render_image(gpu, &mut r, &scene, &s, o.size.0, o.size.1)?.1;
        stats.per_light.iter().map(|l| l.ideal).collect::<Option<Vec<u64>>>().ok_or_else(|| {
            anyhow::anyhow!("this adapter's occlusion queries do not count samples: the ledger has no pairs")
        })?
    };
    let mut rows = Vec::new();
    // A rejected pair's cost: `fullscreen`'s pair cost, once its row has run.
    let mut reject_ns: Option<f64> = None;
    for mode in ledger_modes() {
        if mode == CullingMode::Fullscreen && pairs > REFERENCE_FULLSCREEN_BUDGET {
            continue;
        }
        progress(&format!("ledger {}", mode.name()));
        let settings = Settings {
            culling: mode,
            count_fragments: false,
            count_ideal: false,
            timestamps: true,
            shadows: ShadowMode::None,
            ..Settings::default()
        };
        let drawn = mode != CullingMode::Fullscreen && !mode.method().is_some_and(|m| m.listed());
        let reject = reject_ns.filter(|_| drawn);
        let row = mode_row(gpu, o, &scene, &ideal, &settings, reject).unwrap_or_else(|e| LedgerRow {
            mode: mode.name(),
            culling: mode,
            lights: scene.lights.len(),
            size: o.size,
            model: None,
            one_rate: None,
            samples: Vec::new(),
            predicted_ms: f64::NAN,
            measured_ms: f64::NAN,
            one_rate_predicted_ms: None,
            measured_spread_ms: f64::NAN,
            costliest: Vec::new(),
            counted_ms: f64::NAN,
            uncounted_ms: f64::NAN,
            error: Some(format!("{e:#}")),
        });
        if mode == CullingMode::Fullscreen {
            reject_ns = row.model.as_ref().map(|m| m.pair_ns);
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The scene with only the lights `keep` (indices into its lights).
fn subset(scene: &crate::Scene, keep: &[usize]) -> crate::Scene {
    let mut s = scene.clone();
    s.set_lights(keep.iter().map(|&i| scene.lights[i]).collect());
    s
}

/// A frame's features from its counted render, whose light k is the scene's light `keep[k]`
/// (`ideal`: each of the scene's lights' ideal pairs).
fn features(per_light: &[LightStats], keep: &[usize], ideal: &[u64]) -> Sample {
    let mut f = Sample::default();
    for (l, &i) in per_light.iter().zip(keep) {
        let shaded = l.shaded.unwrap_or(0);
        let e = ideal[i].min(shaded);
        f.draws += cost::light_draws(l.method) as f64;
        f.ideal += e as f64;
        f.wasted += (shaded - e) as f64;
    }
    f
}

fn mode_row(
    gpu: &Gpu,
    o: &BenchOptions,
    scene: &crate::Scene,
    ideal: &[u64],
    settings: &Settings,
    reject_ns: Option<f64>,
) -> Result<LedgerRow> {
    let (w, h) = o.size;
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, settings)?;
    r.set_calibration(o.costs.clone());
    let counted = Settings { count_fragments: true, ..settings.clone() };
    let lighting = |stats: &FrameStats| stats.gpu_ms.lighting.unwrap_or(f64::NAN);
    // Warm (shader compiles), then the whole set counted.
    render_image(gpu, &mut r, scene, settings, w, h)?;
    let mut full = render_image(gpu, &mut r, scene, &counted, w, h)?.1;
    let n = scene.lights.len();
    for (l, &i) in full.per_light.iter_mut().zip(ideal) {
        l.ideal = Some(i);
        l.wasted = l.shaded.map(|s| s.saturating_sub(i));
    }
    let everyone: Vec<usize> = (0..n).collect();
    // The fit's subsets, by the lights' evaluated pairs.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| full.per_light[i].shaded.unwrap_or(0));
    // And by the share of their pairs wasted.
    let share = |i: usize| {
        let l = &full.per_light[i];
        l.wasted.unwrap_or(0) as f64 / l.shaded.unwrap_or(0).max(1) as f64
    };
    let mut by_waste = order.clone();
    by_waste.sort_by(|&a, &b| share(a).total_cmp(&share(b)));
    // The fixed part is where the line meets no light.
    let subsets: Vec<Vec<usize>> = vec![
        order.iter().step_by(4).copied().collect(),
        order[..n / 2].to_vec(),
        order[n / 2..].to_vec(),
        order[..n / 4].to_vec(),
        order[n - n / 4..].to_vec(),
        order.iter().step_by(2).copied().collect(),
        by_waste[..n / 2].to_vec(),
        by_waste[n / 2..].to_vec(),
    ];
    let scenes: Vec<crate::Scene> = subsets.iter().map(|k| subset(scene, k)).collect();
    let mut fit_features = Vec::new();
    for (s, keep) in scenes.iter().zip(&subsets) {
        render_image(gpu, &mut r, s, settings, w, h)?;
        fit_features.push(features(&render_image(gpu, &mut r, s, &counted, w, h)?.1.per_light, keep, ideal));
    }
    // The ten costliest by the calibration's model for now; the fitted one reorders them below.
    let builtin = CostModel::of(&o.costs, settings.culling.method().filter(|m| m.listed()), (w * h) as f64);
    let mut by_cost: Vec<usize> = (0..n).collect();
    let cost_of = |m: &CostModel, i: usize| m.light_ms(&full.per_light[i]).unwrap_or(0.0);
    by_cost.sort_by(|&a, &b| cost_of(&builtin, b).total_cmp(&cost_of(&builtin, a)));
    let removed: Vec<usize> = by_cost.iter().copied().take(REMOVALS.min(n)).collect();
    let without: Vec<crate::Scene> =
        removed.iter().map(|&k| subset(scene, &(0..n).filter(|&i| i != k).collect::<Vec<_>>())).collect();
    for s in &without {
        render_image(gpu, &mut r, s, settings, w, h)?;
    }
    // Timed rounds, interleaved: the subsets, the whole set, the set less each light, and the
    // whole set counted; at least five for a median with a spread, except in the quick sweep.
    let rounds = if o.quick { o.frames.max(1) } else { o.frames.max(5) };
    let mut fit_times = vec![Vec::new(); scenes.len()];
    let (mut whole, mut with_counts) = (Vec::new(), Vec::new());
    let mut less = vec![Vec::new(); without.len()];
    for _ in 0..rounds {
        for (s, t) in scenes.iter().zip(&mut fit_times) {
            t.push(lighting(&render_image(gpu, &mut r, s, settings, w, h)?.1));
        }
        whole.push(lighting(&render_image(gpu, &mut r, scene, settings, w, h)?.1));
        for (s, t) in without.iter().zip(&mut less) {
            t.push(lighting(&render_image(gpu, &mut r, s, settings, w, h)?.1));
        }
        with_counts.push(lighting(&render_image(gpu, &mut r, scene, &counted, w, h)?.1));
    }
    let samples: Vec<Sample> =
        fit_features.iter().zip(&fit_times).map(|(f, t)| Sample { ms: median(t.clone()), ..*f }).collect();
    let source = format!("fitted on {} frames of {rounds} rounds", samples.len());
    let one_rate = CostModel::fit(&samples, source.clone());
    let (model, one_rate) = match reject_ns {
        Some(reject) => (
            CostModel::fit_with_reject(&samples, reject, format!("{source}, rejected pairs at fullscreen's pair cost")),
            one_rate,
        ),
        None => (one_rate, None),
    };
    let (measured_ms, spread) = (median(whole.clone()), super::run::median_se(&whole).1 * (whole.len() as f64).sqrt());
    let whole_features = features(&full.per_light, &everyone, ideal);
    let predicted_ms = model.as_ref().map_or(f64::NAN, |m| m.predict(&whole_features));
    let mut costliest: Vec<CostlyLight> = removed
        .iter()
        .zip(&less)
        .map(|(&k, t)| {
            let cost = [model.as_ref(), one_rate.as_ref()].map(|m| m.map(|m| cost_of(m, k)));
            removal(k, &full.per_light[k], &whole, t, cost)
        })
        .collect();
    costliest.sort_by(|a, b| b.predicted_ms.total_cmp(&a.predicted_ms));
    Ok(LedgerRow {
        mode: settings.culling.name(),
        culling: settings.culling,
        lights: n,
        size: o.size,
        one_rate_predicted_ms: one_rate.as_ref().map(|m| m.predict(&whole_features)),
        model,
        one_rate,
        samples,
        predicted_ms,
        measured_ms,
        measured_spread_ms: spread,
        costliest,
        counted_ms: median(with_counts),
        uncounted_ms: measured_ms,
        error: None,
    })
}

/// Light `k`'s removal (`l` its counted stats): the whole set's rounds `whole` against those
/// without it, `less`, and its cost by the model and by the one-rate fit.
fn removal(k: usize, l: &LightStats, whole: &[f64], less: &[f64], cost: [Option<f64>; 2]) -> CostlyLight {
    let diffs: Vec<f64> = whole.iter().zip(less).map(|(a, b)| a - b).collect();
    let measured = median(diffs.clone());
    let mad = median(diffs.iter().map(|v| (v - measured).abs()).collect());
    CostlyLight {
        index: k,
        kind: l.kind.to_string(),
        draws: cost::light_draws(l.method),
        pairs: l.shaded.unwrap_or(0),
        ideal: l.ideal,
        wasted: l.wasted,
        predicted_ms: cost[0].unwrap_or(f64::NAN),
        one_rate_ms: cost[1],
        measured_ms: measured,
        // The median's standard error, from the deviations' spread (1.4826 MAD is σ for normal
        // noise; the median's is 1.2533 σ/√n).
        noise_ms: 1.2533 * 1.4826 * mad / (diffs.len() as f64).sqrt(),
    }
}

/// The fitted models by mode, for the other configurations' per-light costs.
pub fn fitted_models(rows: &[LedgerRow]) -> Vec<(CullingMode, CostModel)> {
    rows.iter().filter_map(|r| Some((r.culling, r.model.clone()?))).collect()
}

/// Every configuration's ten costliest lights, by the cost model of its counted frame (the
/// `ledger` group's fit for its mode where that ran, or the built-in constants).
pub fn costliest_markdown(rows: &[Row]) -> String {
    let rows: Vec<&Row> = rows.iter().filter(|r| !r.costliest.is_empty() && r.group != CALIBRATION).collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n### The ten costliest lights of each configuration\n\nLight index: its cost in the light pass (ms), by the cost model named \
         (`renderer::explain::cost`: its draws and its evaluated pairs).\n\n\
         | group | configuration | lights | model | costliest (light: ms) |\n|---|---|---|---|---|\n",
    );
    for r in rows {
        let list: Vec<String> = r.costliest.iter().map(|(i, ms)| format!("{i}: {ms:.3}")).collect();
        s += &format!("| {} | {} | {} | {} | {} |\n", r.group, r.label, r.lights, r.cost_source, list.join(", "));
    }
    s
}

/// The group's markdown: a table of the modes, then each mode's ten costliest lights.
pub fn ledger_markdown(rows: &[LedgerRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n## The light ledger: each light's cost, checked\n\n\
         Model (`renderer::explain::cost`): light pass = fixed + Σ lights (draws x draw ms + evaluated pairs x ns a pair; in the drawn modes a \
         rejected pair at `fullscreen`'s pair cost, the rej ns column), fitted by least squares on frames of light subsets (every fourth and every other light; the halves and quarters \
         with the fewest and most pairs; the halves with the least and most wasted share), \
         then held against frames it was not fitted on. Sum: fixed + the lights' costs against the whole set's light pass \
         (goal ±10%, or the pass's round-to-round spread where that is larger: the bound column says which). Removals: each \
         of the ten costliest lights taken out; measured saving = median over interleaved rounds \
         of (whole - without it), ± its standard error (goal ±20%; resolved when the saving exceeds three standard errors). \
         Ledger: the light pass with the per-light counters on, against off.\n\n\
         | mode | lights | size | fixed ms | draw ms | ns/pair | rej ns | predicted ms | measured ms | sum error | sum bound | sum holds | resolved removals within ±20% | resolved | unresolved | ledger on ms | off ms |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        if let Some(e) = &r.error {
            s += &format!(
                "| {} | {} | {}x{} | error: {e} | | | | | | | | | | | | | |\n",
                r.mode, r.lights, r.size.0, r.size.1
            );
            continue;
        }
        let [fixed, draw, pair, reject] =
            r.model.as_ref().map_or(["-".to_string(), "-".into(), "-".into(), "-".into()], |m| {
                [
                    format!("{:.3}", m.fixed_ms),
                    format!("{:.4}", m.draw_ms),
                    format!("{:.2}", m.pair_ns),
                    m.reject_ns.map_or("-".into(), |v| format!("{v:.2}")),
                ]
            });
        let resolved: Vec<&CostlyLight> = r.costliest.iter().filter(|c| c.resolved()).collect();
        let (bound, which) = r.sum_bound();
        s += &format!(
            "| {} | {} | {}x{} | {fixed} | {draw} | {pair} | {reject} | {:.2} | {:.2} | {:+.1}% | {which} ({bound:.2} ms) | {} | {}/{} | {} | {} | {:.2} | {:.2} |\n",
            r.mode,
            r.lights,
            r.size.0,
            r.size.1,
            r.predicted_ms,
            r.measured_ms,
            100.0 * r.sum_error(),
            if r.sum_holds() { "yes" } else { "no" },
            resolved.iter().filter(|c| c.within()).count(),
            resolved.len(),
            resolved.len(),
            r.costliest.len() - resolved.len(),
            r.counted_ms,
            r.uncounted_ms,
        );
    }
    for r in rows.iter().filter(|r| r.error.is_none()) {
        let frames: Vec<String> = r
            .samples
            .iter()
            .map(|f| format!("{} draws, {} pairs ({} wasted): {:.2} ms", f.draws, f.pairs(), f.wasted, f.ms))
            .collect();
        s += &format!("\n**{}**: the fit's frames: {}.\n", r.mode, frames.join("; "));
        if let (Some(m), Some(one)) = (&r.model, &r.one_rate) {
            s += &format!(
                "\n**{}**: one rate for every pair: fixed {:.3} ms, draw {:.4} ms, {:.2} ns a pair (against {:.2} shaded and {:.2} rejected); the whole set {:.2} ms ({:+.1}%).\n",
                r.mode,
                one.fixed_ms,
                one.draw_ms,
                one.pair_ns,
                m.pair_ns,
                m.reject_ns.unwrap_or(f64::NAN),
                r.one_rate_predicted_ms.unwrap_or(f64::NAN),
                100.0 * (r.one_rate_predicted_ms.unwrap_or(f64::NAN) - r.measured_ms) / r.measured_ms
            );
        }
        s += &format!(
            "\n**{}**: the ten costliest lights\n\n| light | kind | draws | pairs | ideal | wasted | cost ms (model) | one rate ms | saving ms (measured) | ± | check | one rate's check |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
            r.mode
        );
        for c in &r.costliest {
            let opt = |v: Option<u64>| v.map_or("-".into(), |v| v.to_string());
            let check = match (c.resolved(), c.within()) {
                (false, _) => "unresolved",
                (true, true) => "within",
                (true, false) => "outside",
            };
            let one_check = match (c.one_rate_ms, c.resolved()) {
                (None, _) => "-",
                (Some(_), false) => "unresolved",
                (Some(one), true) if c.within_of(one) => "within",
                (Some(_), true) => "outside",
            };
            s += &format!(
                "| {} | {} | {} | {} | {} | {} | {:.4} | {} | {:.4} | {:.4} | {check} | {one_check} |\n",
                c.index,
                c.kind,
                c.draws,
                c.pairs,
                opt(c.ideal),
                opt(c.wasted),
                c.predicted_ms,
                c.one_rate_ms.map_or("-".into(), |v| format!("{v:.4}")),
                c.measured_ms,
                c.noise_ms
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A removal resolves once its saving passes three standard errors; the sum's bound is ±10%
    /// unless the pass's own spread is larger.
    #[test]
    fn a_removal_resolves_past_three_standard_errors_and_the_sum_takes_the_larger_bound() {
        let light = |measured_ms: f64, noise_ms: f64| CostlyLight {
            index: 0,
            kind: "point".into(),
            draws: 1,
            pairs: 100,
            ideal: None,
            wasted: None,
            predicted_ms: 0.5,
            one_rate_ms: None,
            measured_ms,
            noise_ms,
        };
        assert!(light(0.31, 0.1).resolved() && !light(0.3, 0.1).resolved() && !light(-1.0, 0.1).resolved());
        let row = |predicted_ms: f64, measured_spread_ms: f64| LedgerRow {
            mode: "volume".into(),
            culling: CullingMode::Volume,
            lights: 60,
            size: (640, 360),
            model: None,
            one_rate: None,
            samples: Vec::new(),
            predicted_ms,
            measured_ms: 10.0,
            one_rate_predicted_ms: None,
            measured_spread_ms,
            costliest: Vec::new(),
            counted_ms: f64::NAN,
            uncounted_ms: f64::NAN,
            error: None,
        };
        assert_eq!(row(11.0, 0.5).sum_bound(), (1.0, "±10%"));
        assert!(row(11.0, 0.5).sum_holds() && !row(11.5, 0.5).sum_holds());
        assert_eq!(row(11.5, 2.0).sum_bound(), (2.0, "spread"));
        assert!(row(11.5, 2.0).sum_holds() && !row(12.5, 2.0).sum_holds());
    }
}
