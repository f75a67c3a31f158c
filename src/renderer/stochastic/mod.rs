//! Stochastic many-light shading: two estimators whose expectation is the exact frame.
//!
//! - **Reservoir-resampled lighting** (RIS: Talbot et al. 2005, "Importance Resampling for
//!   Global Illumination"; the streaming form of Bitterli et al. 2020, "Spatiotemporal
//!   reservoir resampling", without its reuse), on the list modes (tiled, clustered, z-binned):
//!   each pixel keeps K samples, each drawn from M candidates taken uniformly from the pixel's
//!   own list, and shades only those, with their shadows (`ris.wgsl`). The proposal's
//!   probability is 1 / (the list's length), which the list's header holds (a tile or cluster
//!   list's count, a z-bin's range of sorted lights), so a pixel's cost is M x K unshadowed
//!   evaluations and K shaded lights whatever its list's length.
//! - **Stochastic light culling** (Tokuyoshi and Harada 2016, "Stochastic Light Culling"), on
//!   every culling mode: each light's range is drawn for the frame ([`randomise_ranges`]) so
//!   that the light reaches distance d with probability p(d) = min(1, a(d) / t), and the shader
//!   compensates where it reaches (`shade_light_view`: max(a(d), t) = a(d) / p(d)). The
//!   culling modes only see smaller lights: stencil volumes, lists and bins cull them as any.
//!
//! What each is unbiased for, and the tests that hold them to it, are in docs/stochastic.md.

pub mod reuse;
pub mod ris;

use crate::renderer::options::StochasticOptions;
use crate::renderer::records::LightRecord;

/// A uniform number in (0, 1) for light `i` under `seed`: SplitMix64 (Steele et al. 2014) of
/// the two, its top 53 bits, offset by half a step so that neither end is drawn.
pub fn light_uniform(seed: u32, i: usize) -> f64 {
    let mut z = (u64::from(seed) << 32 ^ i as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// The distance, as a fraction of the falloff radius, at which the shader's attenuation
/// a(x) = (1 - x^2)^2 (`distance_attenuation`) falls to `level` (0 < level <= 1).
pub fn attenuation_distance(level: f64) -> f64 {
    (1.0 - level.clamp(0.0, 1.0).sqrt()).max(0.0).sqrt()
}

/// Stochastic light culling's ranges for the frame: light i reaches where its attenuation
/// a(d) exceeds u_i x t, u_i uniform in (0, 1) ([`light_uniform`] of the noise seed and i), t
/// the threshold; so at distance d it reaches with probability min(1, a(d) / t). A range is
/// only ever cut: a light's own cut-off (`light_cutoff`) still holds. With a planted bias b,
/// the lights of odd index reach with probability min(1, b a(d) / t) instead (u_i / b), so
/// their randomised light is b times what it should be.
/// Returns how many lights' ranges were cut.
pub fn randomise_ranges(lights: &mut [LightRecord], o: &StochasticOptions) -> usize {
    if !o.stochastic_culling {
        return 0;
    }
    let t = f64::from(o.stochastic_threshold.clamp(f32::MIN_POSITIVE, 1.0));
    let bias = f64::from(o.planted_bias).max(f64::MIN_POSITIVE);
    let mut cut = 0;
    for (i, l) in lights.iter_mut().enumerate() {
        let mut u = light_uniform(o.noise_seed, i);
        if i % 2 == 1 {
            u /= bias;
        }
        let reach = if u * t >= 1.0 { 0.0 } else { (f64::from(l.falloff) * attenuation_distance(u * t)) as f32 };
        if reach < l.radius {
            l.radius = reach;
            cut += 1;
        }
    }
    cut
}

/// A frame's stochastic estimators, for its stats (`FrameStats::stochastic`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StochasticStats {
    pub noise_seed: u32,
    /// RIS's samples a pixel and candidates a sample (0 and 0: the lists shaded exactly).
    pub ris_samples: u32,
    pub ris_candidates: u32,
    /// RIS's reuse: the spatial neighbours (0: none), temporal reuse; and the denoiser; `reuse`
    /// when any of them runs (RIS then runs as passes over kept reservoirs).
    #[serde(default)]
    pub ris_spatial: u32,
    #[serde(default)]
    pub ris_temporal: bool,
    #[serde(default)]
    pub denoise: bool,
    #[serde(default)]
    pub reuse: bool,
    /// Stochastic culling's threshold (`None`: off), how many lights' ranges it cut this frame,
    /// and the mean over all lights of the range kept, as a fraction of the falloff radius.
    pub culling_threshold: Option<f32>,
    pub ranges_cut: usize,
    pub mean_range: f64,
}

impl StochasticStats {
    /// The stats of a frame drawn with `o` whose light records are `lights`; `None` when no
    /// estimator is on.
    pub fn of(o: &StochasticOptions, lights: &[LightRecord]) -> Option<Self> {
        if !o.any() {
            return None;
        }
        let cut = lights.iter().filter(|l| l.radius < l.falloff).count();
        let kept: f64 = lights.iter().map(|l| f64::from(l.radius) / f64::from(l.falloff).max(1e-30)).sum();
        Some(Self {
            noise_seed: o.noise_seed,
            ris_samples: if o.ris() { o.ris_samples } else { 0 },
            ris_candidates: if o.ris() { o.ris_candidates } else { 0 },
            ris_spatial: if o.reuse() { o.ris_spatial } else { 0 },
            ris_temporal: o.reuse() && o.ris_temporal,
            denoise: o.reuse() && o.ris_denoise,
            reuse: o.reuse(),
            culling_threshold: o.stochastic_culling.then_some(o.stochastic_threshold),
            ranges_cut: if o.stochastic_culling { cut } else { 0 },
            mean_range: if lights.is_empty() { 1.0 } else { kept / lights.len() as f64 },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_range_is_where_the_attenuation_falls_to_the_level() {
        for level in [1e-6, 0.01, 0.25, 0.5, 0.99] {
            let x = attenuation_distance(level);
            let a = (1.0 - x * x).powi(2);
            assert!((a - level).abs() < 1e-12, "{level}: {a}");
        }
        assert_eq!(attenuation_distance(1.0), 0.0);
    }

    #[test]
    fn the_uniforms_stay_inside_the_open_interval_and_vary_with_the_seed() {
        let a: Vec<f64> = (0..1000).map(|i| light_uniform(7, i)).collect();
        assert!(a.iter().all(|&u| u > 0.0 && u < 1.0));
        let mean = a.iter().sum::<f64>() / a.len() as f64;
        assert!((mean - 0.5).abs() < 0.05, "{mean}");
        assert_ne!(light_uniform(7, 3), light_uniform(8, 3));
    }
}
