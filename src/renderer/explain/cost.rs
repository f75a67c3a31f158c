//! The cost half of the light ledger: what each light costs the light pass, in milliseconds.
//!
//! **The model.** The light pass is a fixed part plus each light's cost,
//!
//! ```text
//! T = T_fixed + Σ_i cost_i,    cost_i = d_i · t_draw + p_i · t_pair
//! ```
//!
//! - `d_i`: the light's own draws in the light pass (the method's `draws_per_light`: one
//!   volume or full-screen draw, two with a stencil mark; none in `tiled` and `clustered`,
//!   where the light has no draw of its own, or when `auto` skipped it off screen);
//! - `p_i`: the light-pixel pairs the pass evaluated for it (its `shaded` count: the samples
//!   its draws shaded, or in `tiled`/`clustered` the pixels whose list held it), wasted or not;
//! - `T_fixed`: what the pass costs with no light at all. In `tiled` and `clustered` that is
//!   the full-screen pass that walks the lists and the building of the lists; in every mode
//!   the ambient and sun. It is stated apart: no light is charged for it.
//!
//! A draw costs its setup whatever it covers (state, the volume mesh's vertices, the raster of
//! fragments the depth or stencil test rejects, which grows with the volume as its pairs do
//! for volumes of one shape and so folds into `t_pair`); each evaluated pair costs one run of
//! the shading loop's body.
//!
//! **Rejected pairs.** A wasted pair (evaluated, outside the light's true shape) returns at the
//! shading's range or cone test, before the BRDF: it costs less than a shaded one, so a light
//! whose draws mostly miss (a spot's cone volume around the few pixels its cone lights) costs
//! less than its pairs at one rate say. Where the ledger has measured it, the model splits the
//! pairs,
//!
//! ```text
//! cost_i = d_i · t_draw + e_i · t_pair + w_i · t_reject,    e_i = ideal, w_i = p_i - e_i
//! ```
//!
//! with `t_reject` not fitted per mode but measured apart, where nearly every pair is one: the
//! `fullscreen` mode's pair cost. There every light is evaluated at every pixel, so its
//! frames are over 99% rejected pairs of the same fragment shader, timed with a large signal;
//! the drawn modes (`volume`, the stencil modes) run that shader too, so the constant carries
//! over to them. Its bias is the ideal share of `fullscreen`'s pairs times the excess of a
//! shaded pair over a rejected one. A fit with the wasted pairs as a free term of every mode
//! was tried first: on lavapipe the timed frames could not determine it (its coefficient swung
//! with the noise, from 0 to 1,100 ns, and the sum check got worse), which is why the constant
//! is measured where it dominates instead. The list modes keep one pair cost: their rejected
//! pair is a loop iteration, not a fragment, and no mode of theirs isolates it.
//!
//! **The coefficients** come from timing, never from the frame they are charged to:
//! [`CostModel::fit`] solves least squares over frames that each shade a different subset of
//! the lights (`lampshade bench --only ledger` times them), and the bench then checks the model
//! on frames it was not fitted on: the whole set (the sum) and the set less each of the ten
//! costliest lights (the removals). Without a fit, [`CostModel::of`] gives the constants `auto`
//! decides with: the renderer's calibration (`lampshade calibrate`, measured on the adapter that
//! runs), or the built-in ones ([`CostModel::builtin`]), measured on idle lavapipe on this
//! project's 2-core machine, which on another adapter give the order of the lights, not their
//! milliseconds.

use crate::renderer::culling::methods;
use crate::renderer::culling::stats::LightStats;
use crate::renderer::options::calibration::Calibration;
use crate::renderer::plan::Method;
use serde::{Deserialize, Serialize};

/// Above this many lights `render` leaves the ledger off unless asked (`--ledger on`): its
/// counters split the light pass's batched draws into a draw per light.
pub const LEDGER_DEFAULT_MAX: usize = 4096;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CostModel {
    /// The light pass with no light (ms).
    pub fixed_ms: f64,
    /// One light draw (ms).
    pub draw_ms: f64,
    /// One evaluated light-pixel pair (ns); with `reject_ns`, one inside the light's shape.
    pub pair_ns: f64,
    /// One rejected pair (ns), where measured apart (`fullscreen`'s pair cost): a wasted pair
    /// then costs this instead of `pair_ns`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reject_ns: Option<f64>,
    /// Where the coefficients come from: "lavapipe constants" or the fit's frames.
    pub source: String,
}

/// One timed frame of a fit: its draws and evaluated pairs summed over the lights it shaded
/// (the pairs split at the lights' ideal counts, for the report), and its light pass's time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Sample {
    pub draws: f64,
    /// Evaluated pairs inside the lights' true shapes, and the wasted rest.
    pub ideal: f64,
    pub wasted: f64,
    pub ms: f64,
}

impl Sample {
    pub fn pairs(&self) -> f64 {
        self.ideal + self.wasted
    }
}

impl CostModel {
    /// The built-in constants of `auto`'s frame rule (`CostConstants::BUILTIN`): a drawn
    /// light's fragment against a listed pair in the list modes; the fixed part is the list
    /// modes' full-screen pass at `pixels`.
    pub fn builtin(listed: bool, pixels: f64) -> Self {
        Self::of(&Calibration::builtin(), listed.then_some(Method::Clustered), pixels)
    }

    /// The constants `auto`'s frame rule weighs with in `calibration`, for a frame shaded by
    /// the list mode `listed` (its own costs where the calibration has them, else
    /// `clustered`'s) or drawn light by light (`None`).
    pub fn of(calibration: &Calibration, listed: Option<Method>, pixels: f64) -> Self {
        let c = &calibration.costs;
        let list = match listed {
            None => None,
            Some(Method::Tiled) => Some(c.tiled.unwrap_or(c.clustered)),
            Some(Method::Zbin) => Some(c.zbin.unwrap_or(c.clustered)),
            Some(_) => Some(c.clustered),
        };
        let source = if calibration.is_builtin() {
            "lavapipe constants (auto's)".to_string()
        } else {
            format!("calibration ({})", calibration.describe())
        };
        Self {
            fixed_ms: list.map_or(0.0, |l| l.fixed_ms_per_mpx * pixels / 1e6),
            draw_ms: c.draw_ms,
            pair_ns: list.map_or(c.fragment_ns, |l| l.pair_ns),
            reject_ns: None,
            source,
        }
    }

    /// The cost of `draws` draws and `pairs` evaluated pairs at the one pair rate (ms).
    pub fn cost_ms(&self, draws: u64, pairs: u64) -> f64 {
        draws as f64 * self.draw_ms + pairs as f64 * self.pair_ns * 1e-6
    }

    /// Light `l`'s cost, when its pairs were counted: its ideal and wasted pairs apart where
    /// the model prices rejected pairs and the frame counted the ideal ones.
    pub fn light_ms(&self, l: &LightStats) -> Option<f64> {
        let shaded = l.shaded?;
        let draws = light_draws(l.method);
        Some(match (self.reject_ns, l.ideal) {
            (Some(reject), Some(ideal)) => {
                let e = ideal.min(shaded);
                draws as f64 * self.draw_ms + (e as f64 * self.pair_ns + (shaded - e) as f64 * reject) * 1e-6
            }
            _ => self.cost_ms(draws, shaded),
        })
    }

    /// [`fit`](Self::fit) with rejected pairs priced at `reject_ns`, measured apart: their
    /// cost is taken off each frame's time, and the rest fitted on the ideal pairs.
    pub fn fit_with_reject(samples: &[Sample], reject_ns: f64, source: impl Into<String>) -> Option<Self> {
        let rest: Vec<Sample> =
            samples.iter().map(|s| Sample { wasted: 0.0, ms: s.ms - s.wasted * reject_ns * 1e-6, ..*s }).collect();
        Some(Self { reject_ns: Some(reject_ns), ..Self::fit(&rest, source)? })
    }

    /// Least squares over `samples`: `T = fixed + draws · draw_ms + pairs · pair_ns`, the
    /// draws' term only where the samples' draws vary (none in the list modes). Whether to
    /// keep it is chosen by leave-one-out cross-validation: with it and without it, the model
    /// is refitted without each sample in turn and scored by how far it then predicts that
    /// sample; the lesser error wins, so a term the frames cannot tell from the others drops
    /// out instead of fitting the noise. A fit with a negative coefficient is refused (no light
    /// may cost less than nothing, and no pass less than nothing with none): the fixed part is
    /// then held at zero. `None` when no fit has every coefficient at zero or above.
    pub fn fit(samples: &[Sample], source: impl Into<String>) -> Option<Self> {
        let source = source.into();
        let varies = |c: usize| samples.iter().any(|s| value(s, c) != value(&samples[0], c));
        let mut sets = vec![vec![0, 2]];
        if varies(1) {
            sets.push(vec![0, 1, 2]);
        }
        let solve = |samples: &[Sample], cols: &[usize]| -> Option<[f64; 3]> {
            let x = least_squares(samples, cols)?;
            let mut c = [0.0; 3];
            for (k, &col) in cols.iter().enumerate() {
                c[col] = x[k];
            }
            Some(c)
        };
        let mut best: Option<(f64, [f64; 3])> = None;
        for cols in &mut sets {
            let Some(mut c) = solve(samples, cols) else { continue };
            if c[0] < 0.0 {
                // Noise pushed the fixed part below zero: held at zero, the rest fitted again.
                cols.remove(0);
                let Some(c0) = solve(samples, cols) else { continue };
                c = c0;
            }
            if c.iter().any(|v| *v < 0.0 || !v.is_finite()) {
                continue;
            }
            let mut error = 0.0;
            for j in 0..samples.len() {
                let rest: Vec<Sample> = samples.iter().enumerate().filter(|(k, _)| *k != j).map(|(_, s)| *s).collect();
                error += match solve(&rest, cols) {
                    Some(cj) => (predict(&cj, &samples[j]) - samples[j].ms).powi(2),
                    None => f64::INFINITY,
                };
            }
            if best.is_none_or(|(e, _)| error < e) {
                best = Some((error, c));
            }
        }
        let (_, c) = best?;
        Some(Self { fixed_ms: c[0], draw_ms: c[1], pair_ns: c[2], reject_ns: None, source })
    }

    /// What the model predicts for a frame, fixed part included.
    pub fn predict(&self, s: &Sample) -> f64 {
        match self.reject_ns {
            Some(reject) => {
                predict(&[self.fixed_ms, self.draw_ms, self.pair_ns], &Sample { wasted: 0.0, ..*s })
                    + s.wasted * reject * 1e-6
            }
            None => predict(&[self.fixed_ms, self.draw_ms, self.pair_ns], s),
        }
    }
}

/// Column `c` of a sample: 0 ones, 1 draws, 2 pairs in millions (so that the normal equations
/// are well scaled: ms per million pairs is ns per pair).
fn value(s: &Sample, c: usize) -> f64 {
    match c {
        0 => 1.0,
        1 => s.draws,
        _ => s.pairs() * 1e-6,
    }
}

fn predict(c: &[f64; 3], s: &Sample) -> f64 {
    (0..3).map(|k| c[k] * value(s, k)).sum()
}

/// The light pass's draws of a light shaded with `method`.
pub fn light_draws(method: Method) -> u64 {
    methods::row(method).draws_per_light as u64
}

/// Solves the normal equations of the columns `cols` ([`value`]) by Gauss-Jordan elimination
/// with partial pivoting.
fn least_squares(samples: &[Sample], cols: &[usize]) -> Option<Vec<f64>> {
    let n = cols.len();
    if samples.len() < n {
        return None;
    }
    let mut a = vec![vec![0.0f64; n + 1]; n];
    for s in samples {
        for (r, &cr) in cols.iter().enumerate() {
            for (k, &ck) in cols.iter().enumerate() {
                a[r][k] += value(s, cr) * value(s, ck);
            }
            a[r][n] += value(s, cr) * s.ms;
        }
    }
    let scale = a.iter().flat_map(|row| row[..n].iter()).map(|v| v.abs()).fold(0.0, f64::max);
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        a.swap(col, pivot);
        if a[col][col].abs() <= 1e-12 * scale.max(1e-300) {
            return None;
        }
        for r in 0..n {
            if r != col {
                let f = a[r][col] / a[col][col];
                let pivot_row = a[col].clone();
                for (v, p) in a[r][col..=n].iter_mut().zip(&pivot_row[col..=n]) {
                    *v -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|r| a[r][n] / a[r][r]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(m: &CostModel, draws: f64, pairs: f64) -> Sample {
        let s = Sample { draws, ideal: pairs / 4.0, wasted: pairs * 0.75, ms: 0.0 };
        Sample { ms: m.predict(&s), ..s }
    }

    fn model(fixed_ms: f64, draw_ms: f64, pair_ns: f64) -> CostModel {
        CostModel { fixed_ms, draw_ms, pair_ns, reject_ns: None, source: String::new() }
    }

    #[test]
    fn the_fit_recovers_the_coefficients_of_exact_frames() {
        let truth = model(3.0, 0.02, 11.0);
        let s: Vec<Sample> = [(0.0, 0.0), (64.0, 1e5), (64.0, 9e5), (32.0, 2e5), (128.0, 1e6)]
            .iter()
            .map(|&(d, p)| frame(&truth, d, p))
            .collect();
        let fit = CostModel::fit(&s, "test").expect("separable");
        for (got, want) in [(fit.fixed_ms, 3.0), (fit.draw_ms, 0.02), (fit.pair_ns, 11.0)] {
            assert!((got - want).abs() < 1e-6, "{fit:?}");
        }
        // The list modes: no draws, two terms.
        let listed: Vec<Sample> = [0.0, 1e5, 8e5].iter().map(|&p| frame(&truth, 0.0, p)).collect();
        let fit = CostModel::fit(&listed, "test").expect("separable");
        assert_eq!(fit.draw_ms, 0.0);
        assert!((fit.pair_ns - 11.0).abs() < 1e-6 && (fit.fixed_ms - 3.0).abs() < 1e-9, "{fit:?}");
    }

    #[test]
    fn the_fit_drops_a_term_it_cannot_tell_from_noise_and_refuses_what_it_cannot_separate() {
        // Draws that cost nothing, timed with noise that would make them negative.
        let s = [
            Sample { draws: 0.0, ideal: 0.0, ms: 2.0, ..Default::default() },
            Sample { draws: 100.0, ideal: 1e6, ms: 11.9, ..Default::default() },
            Sample { draws: 50.0, ideal: 1e6, ms: 12.1, ..Default::default() },
            Sample { draws: 50.0, ideal: 5e5, ms: 7.05, ..Default::default() },
        ];
        let fit = CostModel::fit(&s, "test").expect("fits");
        assert!(fit.draw_ms == 0.0 && fit.pair_ns > 9.0 && fit.pair_ns < 11.0, "{fit:?}");
        // A fixed part of about nothing that the noise puts below zero (-0.15 ms) is held at
        // zero, and the line goes through the origin (least squares: Σxy / Σx²).
        let s2 = [(1e5, 0.9), (2e5, 2.0), (4e5, 4.1)].map(|(ideal, ms)| Sample { ideal, ms, ..Default::default() });
        let fit = CostModel::fit(&s2, "test").expect("fits");
        assert_eq!(fit.fixed_ms, 0.0);
        assert!((fit.pair_ns - 2.13 / 0.21).abs() < 1e-9, "{fit:?}");
        // Every frame the same pairs: the pairs cannot be told from the fixed part.
        let same = [
            Sample { ideal: 1e5, ms: 2.0, ..Default::default() },
            Sample { ideal: 1e5, ms: 2.1, ..Default::default() },
        ];
        assert_eq!(CostModel::fit(&same, "test"), None);
        assert_eq!(CostModel::fit(&s[..1], "test"), None);
    }

    #[test]
    fn a_lights_cost_is_its_draws_and_its_pairs() {
        let m = model(1.0, 0.5, 10.0);
        let l = LightStats { method: Method::StencilTwoPass, shaded: Some(3_000_000), ..Default::default() };
        assert!((m.light_ms(&l).unwrap() - (2.0 * 0.5 + 30.0)).abs() < 1e-9);
        let listed = LightStats { method: Method::Clustered, ..l.clone() };
        assert!((m.light_ms(&listed).unwrap() - 30.0).abs() < 1e-9);
        assert_eq!(m.light_ms(&LightStats { shaded: None, ..l }), None);
    }

    #[test]
    fn rejected_pairs_priced_apart_are_taken_off_before_the_fit() {
        // Frames whose wasted pairs cost 4 ns and shaded ones 40: one rate for both cannot
        // fit them, the split recovers both.
        let truth = CostModel { reject_ns: Some(4.0), ..model(1.0, 0.01, 40.0) };
        let s: Vec<Sample> = [(16.0, 1e4, 9e5), (32.0, 5e4, 2e5), (8.0, 4e4, 4e5), (64.0, 2e4, 1e6), (40.0, 8e4, 5e5)]
            .iter()
            .map(|&(draws, ideal, wasted)| {
                let f = Sample { draws, ideal, wasted, ms: 0.0 };
                Sample { ms: truth.predict(&f), ..f }
            })
            .collect();
        let fit = CostModel::fit_with_reject(&s, 4.0, "test").expect("separable");
        for (got, want) in [(fit.fixed_ms, 1.0), (fit.draw_ms, 0.01), (fit.pair_ns, 40.0)] {
            assert!((got - want).abs() < 1e-6, "{fit:?}");
        }
        // A light's cost splits its pairs at its ideal count, and falls back to the one rate
        // where the ideal was not counted.
        let l = LightStats { method: Method::Volume, shaded: Some(10_000), ideal: Some(2_000), ..Default::default() };
        let want = 0.01 + (2_000.0 * 40.0 + 8_000.0 * 4.0) * 1e-6;
        assert!((fit.light_ms(&l).unwrap() - want).abs() < 1e-12);
        let uncounted = LightStats { ideal: None, ..l };
        assert!((fit.light_ms(&uncounted).unwrap() - (0.01 + 10_000.0 * 40.0 * 1e-6)).abs() < 1e-12);
    }
}
