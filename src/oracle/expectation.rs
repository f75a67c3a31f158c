//! The stochastic estimators held to their expectation: N frames of a stochastic configuration,
//! each with its own noise seed, against brute force over the exact frame (every light at every
//! pixel, in f32), compared in linear f32 before any quantisation.
//!
//! What is compared at a pixel is the oracle's: the accumulated light less the lightless
//! frame's, summed over the compared channels ([`super::pixel_channels`]), against brute
//! force's sum. Each frame's residual d = (that sum) - (brute force's) is a random variable
//! whose mean is 0 for an unbiased estimator. Two family-wise checks, each at level alpha / 2:
//! - **Per pixel**: t = (|mean d| - e) / (s / sqrt N), s the pixel's sample standard deviation
//!   over the N frames and e the accumulation's rounding bound there (`rounding_bound`, as the
//!   oracle's exact rule; a pixel no frame varies at must lie within it). Bonferroni over the
//!   frame's pixels: every |t| below Student's t quantile at 1 - alpha / (4 x pixels). This is
//!   valid whatever ties the pixels together (stochastic culling draws one range per light for
//!   the whole frame, so its pixels are not independent).
//! - **Per region**: the same t for each region's mean residual per frame (a 4 x 4 grid of the
//!   image, and the whole image), Bonferroni over the 17. A region's mean averages hundreds of
//!   pixels, so it sees a small bias spread over many pixels that no single pixel's noise lets
//!   through: the planted bias (x0.97 on the lights of odd index) is caught here.
//!
//! The t quantile is the normal's (from `libm::erfc`) corrected for N - 1 degrees of freedom by
//! the Cornish-Fisher expansion (Abramowitz and Stegun 26.7.5); the normal approximation of the
//! mean's distribution is what both checks rest on, so N is at least [`MIN_FRAMES`].
//! The count of pixels beyond |t| = 3 is reported beside what independent pixels would give.

use super::{accumulated, flush_bound, pixel_channels, rounding_bound, Light};
use crate::gpu::Gpu;
use crate::headless::render_image;
use crate::renderer::{CullingMode, RenderPath, Renderer, Settings};
use anyhow::{bail, Result};
use serde::{Deserialize, Serialize};

/// The fewest frames a test of the expectation draws.
pub const MIN_FRAMES: u32 = 32;

/// The regions' grid across and down.
pub const REGION_GRID: u32 = 4;

/// How a stochastic configuration's expectation is tested.
#[derive(Clone, Copy, Debug)]
pub struct ExpectationTest {
    /// Frames drawn, noise seeds `first_seed ..` (at least [`MIN_FRAMES`]).
    pub frames: u32,
    pub first_seed: u32,
    /// The family-wise false-alarm rate of the whole test.
    pub alpha: f64,
}

impl Default for ExpectationTest {
    fn default() -> Self {
        Self { frames: 64, first_seed: 1, alpha: 1e-3 }
    }
}

/// What the test found.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Expectation {
    pub frames: u32,
    /// Pixels with a G-buffer point that brute force or some frame lights, and of them those
    /// no frame varied at (not judged on their own, see `t_sides`).
    pub pixels: usize,
    pub steady: usize,
    /// The largest per-pixel |t|, where it is, and the Bonferroni limit; `worst_above` is the
    /// largest t of a pixel whose mean lies above brute force.
    pub worst_pixel: f64,
    pub worst_above: f64,
    pub worst_at: (u32, u32),
    /// There: the frames' mean, brute force's value and the residual's sample deviation.
    pub worst_mean: f64,
    pub worst_reference: f64,
    pub worst_deviation: f64,
    pub pixel_limit: f64,
    /// Pixels beyond |t| = 3, and how many independent pixels would give on average.
    pub beyond_three: usize,
    pub beyond_three_expected: f64,
    /// Each region's |t| (the 4 x 4 grid row by row, then the whole image) and their limit.
    pub regions: Vec<f64>,
    pub region_limit: f64,
    /// The whole image's mean residual over its mean brute-force value (signed).
    pub relative_bias: f64,
    /// The mean per-frame standard deviation of a pixel's residual over its brute-force value
    /// (the estimator's noise, for the record).
    pub relative_noise: f64,
}

impl Expectation {
    /// Every pixel and every region within its limit: the test for an estimator whose
    /// per-pixel mean over the frames is near normal (enough samples a frame, see
    /// docs/stochastic.md).
    pub fn passed(&self) -> bool {
        self.worst_pixel <= self.pixel_limit && self.regions_passed()
    }

    /// The regions within their limit, and no pixel's mean above brute force beyond it: the
    /// test for a heavy-tailed estimator (few samples a frame). Its pixels' means lie below
    /// their expectation with little spread in most runs and far above it in a few (a rare
    /// strong light drawn), so a pixel's t is skewed towards the low side; its upper side
    /// stays within the normal's (the t statistic of a right-skewed variable is left-skewed),
    /// and a bias that takes light away shows in the regions' means, which average hundreds of
    /// pixels.
    pub fn passed_skewed(&self) -> bool {
        self.worst_above <= self.pixel_limit && self.regions_passed()
    }

    pub fn regions_passed(&self) -> bool {
        self.regions.iter().all(|&t| t <= self.region_limit)
    }
}

/// The standard normal's upper quantile: z with P(Z > z) = `p` (0 < p < 1/2), by bisection on
/// `erfc`.
pub fn normal_upper_quantile(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 0.5 * libm::erfc(mid / std::f64::consts::SQRT_2) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Student's t upper quantile for `dof` degrees of freedom: the normal's, corrected by the
/// Cornish-Fisher expansion to the third order in 1 / dof (Abramowitz and Stegun 26.7.5).
pub fn t_upper_quantile(p: f64, dof: f64) -> f64 {
    let z = normal_upper_quantile(p);
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    let g1 = (z3 + z) / 4.0;
    let g2 = (5.0 * z5 + 16.0 * z3 + 3.0 * z) / 96.0;
    let g3 = (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / 384.0;
    z + g1 / dof + g2 / dof.powi(2) + g3 / dof.powi(3)
}

/// The |t| of a residual whose N samples sum to `sum` with squares `squares`, less `bound`
/// (infinite where no sample varies and the mean lies beyond the bound).
fn t_of(sum: f64, squares: f64, n: f64, bound: f64) -> f64 {
    let mean = sum / n;
    let var = ((squares - n * mean * mean) / (n - 1.0)).max(0.0);
    let deviation = (mean.abs() - bound).max(0.0);
    let se = (var / n).sqrt();
    match (deviation > 0.0, se > 0.0) {
        (false, _) => 0.0,
        (true, true) => deviation / se,
        (true, false) => f64::INFINITY,
    }
}

/// [`t_of`] by side, for a pixel: (the mean above zero, the mean below), 0 for a pixel whose
/// frames did not vary (`varied` false). Such a pixel is not judged: both estimators add
/// light by rare events (a light drawn or not, a range that reaches or not), and N frames
/// that all saw the same outcome can lie on either side of the expectation with no spread to
/// show for it (a light reaching with probability 0.99 is in 64 frames out of 64 one time in
/// two, adding max(a, t) > a each time). The regions judge what such pixels add up to.
fn t_sides(sum: f64, squares: f64, n: f64, bound: f64, varied: bool) -> (f64, f64) {
    if !varied {
        return (0.0, 0.0);
    }
    let t = t_of(sum, squares, n, bound);
    if sum > 0.0 {
        (t, 0.0)
    } else {
        (0.0, t)
    }
}

/// Per pixel: brute force's sum over the compared channels, and the oracle's rounding bound
/// summed over them (as the exact rule bounds each channel).
fn reference_and_bounds(
    dark: &Light,
    bf: &crate::renderer::explain::brute::BruteForce,
    path: (RenderPath, bool),
    (format, flush): (crate::renderer::AccumFormat, f32),
) -> (Vec<f64>, Vec<f64>) {
    let pixels = bf.adding.len();
    let zero = Light { diffuse: vec![0.0; 4 * pixels], specular: vec![0.0; 4 * pixels] };
    (0..pixels)
        .map(|p| {
            let (c, n) = pixel_channels(p, &zero, dark, bf, path);
            let k = bf.adding[p];
            let value: f64 = c[..n].iter().map(|&(_, _, r)| f64::from(r)).sum();
            let e: f64 = c[..n]
                .iter()
                .map(|&(_, rest, r)| f64::from(rounding_bound(format, rest + r, k) + k as f32 * flush))
                .sum();
            (value, e)
        })
        .unzip()
}

/// `settings` (a stochastic configuration on a G-buffer path) drawn `test.frames` times with
/// noise seeds from `test.first_seed`, held to brute force over the same configuration made
/// exact (RIS off, stochastic culling off, no planted bias).
pub fn expectation(
    gpu: &Gpu,
    renderer: &mut Renderer,
    scene: &crate::scene::Scene,
    settings: &Settings,
    (w, h): (u32, u32),
    test: &ExpectationTest,
) -> Result<Expectation> {
    if test.frames < MIN_FRAMES {
        bail!("an expectation test draws at least {MIN_FRAMES} frames, not {}", test.frames);
    }
    if !settings.path.keeps_gbuffer() {
        bail!("the expectation is held to brute force over a G-buffer: the {} path keeps none", settings.path.name());
    }
    let stochastic = Settings { count_fragments: false, count_ideal: false, timestamps: false, ..settings.clone() };
    let exact = stochastic.made_exact();
    let mut dark_scene = scene.clone();
    dark_scene.lights_mut().clear();
    render_image(gpu, renderer, &dark_scene, &exact, w, h)?;
    let dark = accumulated(gpu, renderer)?;
    render_image(gpu, renderer, scene, &exact, w, h)?;
    let bf = renderer.last_frame().brute_force(gpu)?;
    let one_target = renderer.last_frame().one_target() && settings.path == RenderPath::Deferred;
    let path = (settings.path, one_target);
    let pixels = (w * h) as usize;
    let flush = flush_bound(&scene.lights);
    // Per pixel: brute force's sum over the compared channels and the rounding bound there.
    let (reference, bound) = reference_and_bounds(&dark, &bf, path, (settings.accumulation, flush));
    let regions = (REGION_GRID * REGION_GRID + 1) as usize;
    let region_of = |p: usize| {
        let (x, y) = (p as u32 % w, p as u32 / w);
        ((y * REGION_GRID / h) * REGION_GRID + x * REGION_GRID / w) as usize
    };
    let mut region_size = vec![0usize; regions];
    for p in 0..pixels {
        region_size[region_of(p)] += 1;
    }
    region_size[regions - 1] = pixels;
    let (mut sum, mut squares) = (vec![0f64; pixels], vec![0f64; pixels]);
    let (mut region_sum, mut region_squares) = (vec![0f64; regions], vec![0f64; regions]);
    let mut lit_anywhere = vec![false; pixels];
    // Each pixel's smallest and largest residual: whether its frames varied at all (by more
    // than the rounding; the sums of squares cancel to noise where they did not).
    let (mut low, mut high) = (vec![f64::INFINITY; pixels], vec![f64::NEG_INFINITY; pixels]);
    for f in 0..test.frames {
        let s = Settings { noise_seed: test.first_seed.wrapping_add(f), ..stochastic.clone() };
        render_image(gpu, renderer, scene, &s, w, h)?;
        let lit = accumulated(gpu, renderer)?;
        let mut frame_region = vec![0f64; regions];
        for p in 0..pixels {
            let (c, n) = pixel_channels(p, &lit, &dark, &bf, path);
            let value: f64 = c[..n].iter().map(|&(acc, rest, _)| f64::from(acc) - f64::from(rest)).sum();
            let d = value - reference[p];
            lit_anywhere[p] |= value != 0.0;
            low[p] = low[p].min(d);
            high[p] = high[p].max(d);
            sum[p] += d;
            squares[p] += d * d;
            frame_region[region_of(p)] += d;
            frame_region[regions - 1] += d;
        }
        for r in 0..regions {
            let m = frame_region[r] / region_size[r].max(1) as f64;
            region_sum[r] += m;
            region_squares[r] += m * m;
        }
    }
    let n = f64::from(test.frames);
    let tested: Vec<usize> = (0..pixels).filter(|&p| reference[p] > 0.0 || lit_anywhere[p]).collect();
    let dof = n - 1.0;
    let pixel_limit = t_upper_quantile(test.alpha / 4.0 / tested.len().max(1) as f64, dof);
    let region_limit = t_upper_quantile(test.alpha / 4.0 / regions as f64, dof);
    let (mut worst_pixel, mut worst, mut beyond_three, mut noise) = (0f64, 0, 0usize, 0f64);
    let (mut worst_above, mut steady) = (0f64, 0usize);
    for &p in &tested {
        let varied = high[p] - low[p] > bound[p];
        steady += !varied as usize;
        let (above, below) = t_sides(sum[p], squares[p], n, bound[p], varied);
        let t = above.max(below);
        worst_above = worst_above.max(above);
        beyond_three += (t > 3.0) as usize;
        if t > worst_pixel {
            worst_pixel = t;
            worst = p;
        }
        if reference[p] > 0.0 {
            let mean = sum[p] / n;
            noise += (((squares[p] - n * mean * mean) / dof).max(0.0)).sqrt() / reference[p];
        }
    }
    let region_bound = |r: usize| match r {
        _ if r == regions - 1 => bound.iter().sum::<f64>() / pixels as f64,
        _ => (0..pixels).filter(|&p| region_of(p) == r).map(|p| bound[p]).sum::<f64>() / region_size[r].max(1) as f64,
    };
    let region_t = (0..regions).map(|r| t_of(region_sum[r], region_squares[r], n, region_bound(r))).collect();
    let mean_reference = reference.iter().sum::<f64>() / pixels as f64;
    let lit_pixels = tested.iter().filter(|&&p| reference[p] > 0.0).count().max(1);
    Ok(Expectation {
        frames: test.frames,
        pixels: tested.len(),
        steady,
        worst_pixel,
        worst_above,
        worst_at: (worst as u32 % w, worst as u32 / w),
        worst_mean: reference[worst] + sum[worst] / n,
        worst_reference: reference[worst],
        worst_deviation: ((squares[worst] - sum[worst] * sum[worst] / n) / dof).max(0.0).sqrt(),
        pixel_limit,
        beyond_three,
        beyond_three_expected: tested.len() as f64 * 2.0 * 0.5 * libm::erfc(3.0 / std::f64::consts::SQRT_2),
        regions: region_t,
        region_limit,
        relative_bias: region_sum[regions - 1] / n / mean_reference.max(f64::MIN_POSITIVE),
        relative_noise: noise / lit_pixels as f64,
    })
}

/// A stochastic configuration the oracle holds to its expectation on a case: its label, the
/// changes it makes to the case's settings, and which test applies ([`Expectation::passed`],
/// or [`Expectation::passed_skewed`] where few samples make each pixel heavy-tailed).
pub struct StochasticMode {
    pub label: &'static str,
    pub apply: fn(Settings) -> Settings,
    pub skewed: bool,
}

/// The stochastic modes of the oracle's expectation rule: RIS on each list mode with enough
/// samples for the per-pixel test (16 samples of 64 candidates), RIS with one sample of eight
/// candidates (its regions and upper side), stochastic culling on a stencil mode and a list
/// mode, at the default threshold and at 1 (every contribution randomised).
pub const STOCHASTIC_MODES: &[StochasticMode] = &[
    StochasticMode {
        label: "tiled, RIS 16 x 64",
        apply: |s| Settings { culling: CullingMode::Tiled, ris_samples: 16, ris_candidates: 64, ..s },
        skewed: false,
    },
    StochasticMode {
        label: "clustered, RIS 16 x 64",
        apply: |s| Settings { culling: CullingMode::Clustered, ris_samples: 16, ris_candidates: 64, ..s },
        skewed: false,
    },
    StochasticMode {
        label: "zbin, RIS 16 x 64",
        apply: |s| Settings { culling: CullingMode::Zbin, ris_samples: 16, ris_candidates: 64, ..s },
        skewed: false,
    },
    StochasticMode {
        label: "zbin, RIS 1 x 8",
        apply: |s| Settings { culling: CullingMode::Zbin, ris_samples: 1, ris_candidates: 8, ..s },
        skewed: true,
    },
    StochasticMode {
        label: "stencil-invert, stochastic culling 0.25",
        apply: |s| Settings {
            culling: CullingMode::StencilInvert,
            stochastic_culling: true,
            stochastic_threshold: 0.25,
            ..s
        },
        skewed: false,
    },
    StochasticMode {
        label: "auto, stochastic culling 1",
        apply: |s| Settings { culling: CullingMode::Auto, stochastic_culling: true, stochastic_threshold: 1.0, ..s },
        skewed: false,
    },
];

/// One stochastic mode's result on a case.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ModeExpectation {
    pub label: String,
    pub path: String,
    pub expectation: Expectation,
    pub skewed: bool,
}

impl ModeExpectation {
    pub fn passed(&self) -> bool {
        match self.skewed {
            true => self.expectation.passed_skewed(),
            false => self.expectation.passed(),
        }
    }
}

/// The oracle's expectation rule on `case`: each of [`STOCHASTIC_MODES`] on the deferred path
/// (and the light pre-pass where the case's settings suit it), `test.frames` frames each.
pub fn check_case(
    gpu: &Gpu,
    renderer: &mut Renderer,
    case: &super::case::Case,
    test: &ExpectationTest,
) -> Result<Vec<ModeExpectation>> {
    let scene = case.scene().map_err(anyhow::Error::msg)?;
    let base = case.settings.settings();
    let mut out = Vec::new();
    for path in [RenderPath::Deferred, RenderPath::LightPrepass] {
        // The light pre-pass keeps its specular in alpha, which Rg11b10Ufloat lacks: the path
        // refuses such a case before any culling (the exact oracle's `path_refused`).
        if path == RenderPath::LightPrepass && base.accumulation == crate::renderer::AccumFormat::Rg11b10Ufloat {
            continue;
        }
        for m in STOCHASTIC_MODES {
            let settings = (m.apply)(Settings { path, ..base.clone() });
            let e = expectation(gpu, renderer, &scene, &settings, (case.width, case.height), test)?;
            out.push(ModeExpectation { label: m.label.into(), path: path.name(), expectation: e, skewed: m.skewed });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quantiles_match_the_tables() {
        // Normal: 1.959964 at 0.025, 3.090232 at 0.001, 5.326724 at 5e-8.
        assert!((normal_upper_quantile(0.025) - 1.959964).abs() < 1e-5);
        assert!((normal_upper_quantile(0.001) - 3.090232).abs() < 1e-5);
        assert!((normal_upper_quantile(5e-8) - 5.326724).abs() < 1e-5);
        // Student's t: 2.039513 at 0.025 with 31 dof, 3.375 at 0.001 with 31 (tables: 3.3749).
        assert!((t_upper_quantile(0.025, 31.0) - 2.039513).abs() < 2e-3);
        assert!((t_upper_quantile(0.001, 31.0) - 3.3749).abs() < 1e-2);
        assert!((t_upper_quantile(0.001, 63.0) - 3.2289).abs() < 5e-3);
    }

    #[test]
    fn a_residual_within_its_bound_is_no_deviation() {
        assert_eq!(t_of(0.5, 0.25, 2.0, 0.3), 0.0);
        assert_eq!(t_of(1.0, 0.5, 2.0, 0.1), f64::INFINITY);
        // A pixel whose frames never varied is not judged on its own.
        assert_eq!(t_sides(-1.0, 0.5, 2.0, 0.1, false), (0.0, 0.0));
        assert_eq!(t_sides(3.0, 5.0, 3.0, 0.0, true).1, 0.0);
        let t = t_of(3.0, 5.0, 3.0, 0.0);
        assert!((t - 1.0 / (1.0f64 / 3.0).sqrt()).abs() < 1e-9, "{t}");
    }
}
