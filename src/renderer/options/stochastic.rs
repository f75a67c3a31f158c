//! The options of `stochastic/`.

/// Declared with the other options types from the fields of `fields.rs`.
pub use super::StochasticOptions;

impl StochasticOptions {
    /// Whether the list modes shade by reservoir resampling instead of exactly.
    pub fn ris(&self) -> bool {
        self.ris_samples > 0
    }

    /// Whether RIS runs as passes over kept reservoirs (`stochastic::reuse`): to reuse samples
    /// across pixels or frames (ReSTIR), or to denoise its light.
    pub fn reuse(&self) -> bool {
        self.ris() && (self.ris_spatial > 0 || self.ris_temporal || self.ris_denoise)
    }

    /// Why these options cannot be drawn, apart from the path and mode (`Settings::validate`):
    /// reuse and the denoiser need RIS's samples, at most `reuse::MAX_SAMPLES` of them.
    pub fn validate(&self) -> Result<(), String> {
        let reuse = self.ris_spatial > 0 || self.ris_temporal || self.ris_denoise;
        if reuse && self.ris_samples == 0 {
            return Err(
                "ris-spatial, ris-temporal and ris-denoise work on RIS's samples: set ris-samples 1 to 4, or turn them off"
                    .into(),
            );
        }
        let most = crate::renderer::stochastic::reuse::MAX_SAMPLES;
        if reuse && self.ris_samples > most {
            return Err(format!(
                "reuse keeps every RIS sample of every pixel twice, 32 bytes each: at most {most} samples (ris-samples {})",
                self.ris_samples
            ));
        }
        Ok(())
    }

    /// Whether the frame is drawn by a stochastic estimator at all (its pixels are random
    /// variables whose expectation is the exact frame).
    pub fn any(&self) -> bool {
        self.ris() || self.stochastic_culling
    }

    /// The camera record's `noise`: the seed, RIS's candidates and samples (0: exact), 0.
    pub fn noise_words(&self) -> [u32; 4] {
        let samples = if self.ris() { self.ris_samples } else { 0 };
        [self.noise_seed, self.ris_candidates.max(1), samples, 0]
    }

    /// The camera record's `stochastic`: stochastic culling's threshold (0: off), the planted
    /// bias, 0, 0.
    pub fn culling_words(&self) -> [f32; 4] {
        let threshold = if self.stochastic_culling { self.stochastic_threshold } else { 0.0 };
        [threshold, self.planted_bias, 0.0, 0.0]
    }
}

impl super::Options {
    /// Whether RIS runs as passes over kept reservoirs (`stochastic::reuse`): for its reuse or
    /// denoiser, or for the views that average its frames.
    pub fn ris_passes(&self) -> bool {
        self.stochastic.reuse() || (self.stochastic.ris() && self.frame.debug_view.converges())
    }
}
