//! Brute force: every light of the last frame evaluated at every pixel of its G-buffer, in f32,
//! on the GPU, whatever the culling decided (`cs_brute_force`): the reference the culling
//! oracle holds each mode against. A light the culling skipped at a pixel where this adds light
//! is a missed pair.
//!
//! Each pixel sums the lights in one invocation. Under a loop limit (`Quirks::loop_limit`:
//! gallivm ends an invocation's loops after 65,535 iterations between them) the lights are
//! shaded in chunks, one compute pass each, every chunk adding onto the last: a light costs at
//! most [`ITERATIONS_PER_LIGHT`] iterations, so a chunk holds
//! `gpu_loop_budget(limit) / ITERATIONS_PER_LIGHT` lights. Without a limit one pass shades all.

use super::super::kit::Shared;

/// Loop iterations one light takes in `cs_brute_force`: one of the light loop, and the shadow
/// filter's taps: at most 16 (the Poisson kernel's one loop; PCF 3x3 takes 3 + 9 = 12).
pub const ITERATIONS_PER_LIGHT: u64 = 17;

/// vec4s `cs_brute_force` writes a pixel.
pub(crate) const WORDS: usize = 3;

pub struct BrutePass {
    pub(crate) pipeline: crate::renderer::kit::ComputePipe,
    pub(crate) bgl: wgpu::BindGroupLayout,
}

impl BrutePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let (pipeline, bgl) = super::compute_pipeline(device, shared, "brute force", "cs_brute_force");
        Self { pipeline, bgl }
    }
}

/// Every light at every pixel of the last frame, summed in f32: per pixel, row by row.
#[derive(Clone, Debug, Default)]
pub struct BruteForce {
    pub width: u32,
    pub height: u32,
    /// RGB diffuse light (before albedo), as the diffuse target accumulates it.
    pub diffuse: Vec<[f32; 3]>,
    /// RGB specular light, as the specular target accumulates it.
    pub specular: Vec<[f32; 3]>,
    /// The lit colour (diffuse x albedo + specular): what seed 000's one target accumulates.
    pub lit: Vec<[f32; 3]>,
    /// How many lights add light at the pixel.
    pub adding: Vec<u32>,
}

/// The lights a chunk of `cs_brute_force` shades under loop limit `limit` (all of them without
/// one).
pub fn chunk_lights(limit: Option<u64>, lights: usize) -> usize {
    match limit {
        Some(l) => (crate::renderer::culling::tiled::gpu_loop_budget(l) / ITERATIONS_PER_LIGHT).max(1) as usize,
        None => lights.max(1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_stays_inside_the_loop_limit() {
        let limit = crate::renderer::kit::adapter::GALLIVM_LOOP_LIMIT;
        let chunk = chunk_lights(Some(limit), 100_000) as u64;
        assert!(chunk * ITERATIONS_PER_LIGHT <= crate::renderer::culling::tiled::gpu_loop_budget(limit));
        assert!((chunk + 1) * ITERATIONS_PER_LIGHT > crate::renderer::culling::tiled::gpu_loop_budget(limit));
        assert_eq!(chunk_lights(None, 100_000), 100_000);
    }
}
