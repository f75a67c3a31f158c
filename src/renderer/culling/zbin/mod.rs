//! The `zbin` culling mode (Drobot 2017, "Improved Culling for Tiled and Clustered
//! Rendering", SIGGRAPH Advances in Real-Time Rendering; Call of Duty: Infinite Warfare, and
//! Blender EEVEE-Next after it). Per-cluster lists cost O(tiles x slices x lights) memory and
//! a CPU assignment per cell; z-binning splits the cluster into its two axes:
//! - **depth**: the lights are sorted by the first depth bin their sphere reaches, and each of
//!   [`BINS`] bins holds the range `[first, end)` of sorted positions whose lights reach its
//!   depths (O(bins) words);
//! - **screen**: each tile holds a bitmask, one bit a sorted light (O(tiles x lights / 32)
//!   words), built on the GPU (`zbin.wgsl`): a pass takes each tile's depth bounds from the
//!   G-buffer (`cs_zbin_bounds`), then one invocation a light sets its bit in each tile of its
//!   screen rectangle whose frustum piece between those bounds its sphere meets
//!   (`cs_zbin_mask`, the clustered lists' axis-by-axis test). Drobot's masks are the
//!   rectangles alone; the bounds halve the pairs walked on `demo`.
//!
//! A pixel walks the set bits of its tile's mask between its bin's `first` and `end`. Nothing
//! is dropped that reaches the pixel: a light reaching a point at view depth d reaches d's bin
//! (its range is widened by a bin on each side against the shader's own rounding of the bin)
//! and that point's tile (its rectangle bounds every visible point it reaches, widened by a
//! pixel); the shading loop's own reach test then skips what the two tests let through.
//!
//! This file is the CPU's part, all of it O(lights + bins): the depth and screen spans of each
//! light from its plan, a counting sort by first bin, and the bins' ranges in two sweeps over a
//! "next unassigned bin" forest (each bin is assigned once, whatever the lights' depth extents).
//! The GPU's part lives in `culling::tiled::pass`, beside the other list modes (the same
//! bindings and shading skeleton), and `zbin.wgsl`.

use crate::renderer::culling::plan::{LightPlan, PlanView};
use crate::renderer::culling::tiled::{fitted_depths, ClusterGrid};
use crate::renderer::records::LightRecord;

/// Depth bins, exponential between the nearest and the farthest depth the frame's lights
/// reach (as the clustered slices, [`ClusterGrid::slice`]). EEVEE-Next uses 4,096 linear bins;
/// exponential bins keep the same relative width at every depth (0.7% of the depth with the
/// lights spanning a 1,000:1 depth range).
pub const BINS: u32 = 1024;

/// Tile sizes tried for the masks, smallest first: the smallest whose masks fit
/// [`MASK_MAX_WORDS`] is taken (16x16 as the tiled mode; larger tiles only past a few hundred
/// thousand lights at 1080p).
pub const TILE_SIZES: [u32; 5] = [16, 32, 64, 128, 256];

/// Most u32 words of the masks: 96 MiB, leaving room in the 128 MiB binding (WebGPU's
/// guaranteed storage-binding size) for the per-light counters before them.
pub const MASK_MAX_WORDS: u64 = (96 << 20) / 4;

/// Sorted lights one draw of the shading pass walks under a loop limit (lavapipe's: gallivm
/// ends a shader invocation's loops once they have run 65,535 iterations between them). A
/// chunk's walk takes at most `ZBIN_CHUNK / 32` word iterations and `ZBIN_CHUNK` bit
/// iterations, twice (every light, then the casting ones): 2 x (960 + 30,720) = 63,360.
/// Adapters without a loop limit walk every light in one draw.
pub const ZBIN_CHUNK: u32 = 30_720;

/// No sorted light reaches the bin: `first = end = 0`.
const EMPTY: u32 = u32::MAX;

/// What the GPU needs for one z-binned frame.
#[derive(Clone, Debug)]
pub struct ZBinJob {
    /// The masks' tiles and the depth bins (`slices`).
    pub grid: ClusterGrid,
    /// The upload: `[first, end)` per bin, then the sorted lights' indices (`visible`), then each
    /// sorted light's tile rectangle (`x0 | x1 << 16`, `y0 | y1 << 16`).
    pub data: Vec<u32>,
    /// Lights sorted (those reaching a visible point of some bin).
    pub visible: u32,
    /// Mask words per tile: `visible / 32`, rounded up, at least 1.
    pub words: u32,
    /// Sorted lights per shading draw ([`ZBIN_CHUNK`] under a loop limit, all otherwise).
    pub chunk: u32,
    /// The (light, tile) pairs the rectangles hold: the most mask bits the GPU can set.
    pub entries: u64,
}

impl ZBinJob {
    pub fn order_base(&self) -> u32 {
        2 * self.grid.slices
    }

    pub fn rect_base(&self) -> u32 {
        self.order_base() + self.visible
    }

    /// The sorted lights' indices.
    pub fn order(&self) -> &[u32] {
        let b = self.order_base() as usize;
        &self.data[b..b + self.visible as usize]
    }

    /// Bin `k`'s `[first, end)` in sorted positions.
    pub fn bin(&self, k: u32) -> (u32, u32) {
        (self.data[2 * k as usize], self.data[2 * k as usize + 1])
    }

    /// Sorted light `j`'s tiles: (x0, x1), (y0, y1), inclusive.
    pub fn rect(&self, j: u32) -> ((u32, u32), (u32, u32)) {
        let b = (self.rect_base() + 2 * j) as usize;
        let (x, y) = (self.data[b], self.data[b + 1]);
        ((x & 0xffff, x >> 16), (y & 0xffff, y >> 16))
    }

    /// The shading pass's draws: one per `chunk` sorted lights, at least one.
    pub fn draws(&self) -> u32 {
        self.visible.div_ceil(self.chunk.max(1)).max(1)
    }

    /// The rectangles' masks (for the tests): per tile, `words` words. The GPU's masks are
    /// these less the tiles whose depth bounds the light's sphere misses.
    pub fn rect_masks(&self) -> Vec<u32> {
        let tiles = (self.grid.tiles_x * self.grid.tiles_y) as usize;
        let words = self.words as usize;
        let mut m = vec![0u32; tiles * words];
        for j in 0..self.visible {
            let ((x0, x1), (y0, y1)) = self.rect(j);
            for ty in y0..=y1 {
                for tx in x0..=x1 {
                    m[(ty * self.grid.tiles_x + tx) as usize * words + (j / 32) as usize] |= 1 << (j % 32);
                }
            }
        }
        m
    }

    /// Light indices a pixel of tile `tile` at bin `k` walks, given the masks (`masks`, as
    /// [`Self::rect_masks`] lays them out or the GPU left them).
    pub fn walk(&self, masks: &[u32], tile: u32, k: u32) -> Vec<u32> {
        let (first, end) = self.bin(k);
        let base = tile as usize * self.words as usize;
        (first..end)
            .filter(|&j| masks.get(base + (j / 32) as usize).is_some_and(|w| w >> (j % 32) & 1 == 1))
            .map(|j| self.order()[j as usize])
            .collect()
    }
}

/// A light in view: its index, its bins `[k0, k1)` and its pixel rectangle (x0, x1, y0, y1).
type Spanned = (u32, u32, u32, (u32, u32, u32, u32));

/// Light `p`'s pixel rectangle (x0, x1, y0, y1, inclusive, y down), widened by a pixel and
/// clamped to the screen, as the clustered spans take it (`tiles::Span`); `None` off screen.
pub fn pixel_rect(p: &LightPlan, size: (u32, u32)) -> Option<(u32, u32, u32, u32)> {
    let (lo, hi) = p.screen_rect?;
    let (w, h) = (size.0 as f32, size.1 as f32);
    let (ax0, ax1) = ((lo.x + 1.0) * 0.5 * w, (hi.x + 1.0) * 0.5 * w);
    let (ay0, ay1) = ((1.0 - hi.y) * 0.5 * h, (1.0 - lo.y) * 0.5 * h);
    // (NaN fails every comparison: such a rectangle is dropped below by the same tests.)
    if !(ax1 >= -1.0 && ay1 >= -1.0 && ax0 < w + 1.0 && ay0 < h + 1.0) {
        return None;
    }
    // `as u32` saturates (negative and NaN give 0): the floor of the non-negative values.
    let clamp = |v: u32, max: u32| v.min(max - 1);
    Some((
        clamp((ax0 - 1.0) as u32, size.0),
        clamp((ax1 as u32).saturating_add(1), size.0),
        clamp((ay0 - 1.0) as u32, size.1),
        clamp((ay1 as u32).saturating_add(1), size.1),
    ))
}

/// The frame's z-binned job. `loop_limit`: the adapter's (`Quirks::loop_limit`), which sets
/// the shading pass's chunk.
pub fn zbin_job(lights: &[LightRecord], plans: &[LightPlan], view: &PlanView) -> ZBinJob {
    debug_assert_eq!(lights.len(), plans.len());
    // The depths the lights reach (the clustered grid's knobs are not z-binning's).
    let (near, far) = fitted_depths(plans, view);
    let depth_grid = ClusterGrid::with_cells(view.size, near, far, TILE_SIZES[0], BINS);
    // Each light's bins [k0, k1) and pixel rectangle; lights reaching no visible point of the
    // grid's depths are left out.
    let mut spans: Vec<Spanned> = Vec::with_capacity(lights.len());
    for (i, p) in plans.iter().enumerate() {
        let Some(rect) = pixel_rect(p, view.size) else { continue };
        let (d0, d1) = (p.depths.0.max(depth_grid.near), p.depths.1.min(depth_grid.far));
        if d0.is_nan() || d1.is_nan() || d0 > d1 {
            continue;
        }
        let k0 = depth_grid.slice(d0).saturating_sub(1);
        let k1 = (depth_grid.slice(d1) + 2).min(BINS);
        spans.push((i as u32, k0, k1, rect));
    }
    let visible = spans.len() as u32;
    let words = visible.div_ceil(32).max(1);
    let tile = TILE_SIZES
        .into_iter()
        .find(|&t| view.size.0.div_ceil(t) as u64 * view.size.1.div_ceil(t) as u64 * words as u64 <= MASK_MAX_WORDS)
        .unwrap_or(TILE_SIZES[TILE_SIZES.len() - 1]);
    let grid = ClusterGrid::with_cells(view.size, near, far, tile, BINS);
    // Counting sort by first bin (stable: light order within a bin).
    let mut starts = vec![0u32; BINS as usize + 1];
    for s in &spans {
        starts[s.1 as usize + 1] += 1;
    }
    for k in 0..BINS as usize {
        starts[k + 1] += starts[k];
    }
    let mut sorted = vec![0u32; spans.len()];
    for (n, s) in spans.iter().enumerate() {
        let slot = &mut starts[s.1 as usize];
        sorted[*slot as usize] = n as u32;
        *slot += 1;
    }
    let bins_k = |j: u32| {
        let s = &spans[sorted[j as usize] as usize];
        (s.1, s.2)
    };
    let first = cover(BINS, 0..visible, bins_k);
    let last = cover(BINS, (0..visible).rev(), bins_k);
    let mut data = Vec::with_capacity(2 * BINS as usize + 3 * visible as usize);
    for (f, l) in first.iter().zip(&last) {
        match (*f, *l) {
            (EMPTY, _) | (_, EMPTY) => data.extend([0, 0]),
            (f, l) => data.extend([f, l + 1]),
        }
    }
    data.extend(sorted.iter().map(|&n| spans[n as usize].0));
    let mut entries = 0u64;
    for &n in &sorted {
        let (x0, x1, y0, y1) = spans[n as usize].3;
        let (tx0, tx1, ty0, ty1) = (x0 / tile, x1 / tile, y0 / tile, y1 / tile);
        entries += (tx1 - tx0 + 1) as u64 * (ty1 - ty0 + 1) as u64;
        data.extend([tx0 | tx1 << 16, ty0 | ty1 << 16]);
    }
    let chunk = if view.loop_limit.is_some() { ZBIN_CHUNK } else { visible.max(1) };
    ZBinJob { grid, data, visible, words, chunk, entries }
}

/// For each of `bins` bins, the first position in `positions` order whose bins (`bins_of`)
/// hold it, or [`EMPTY`]. Each bin is assigned once: `next` points past assigned bins (a
/// forest, halved on each walk), so the sweep costs O(positions + bins), not the sum of the
/// positions' bin counts (a light spanning every bin would cost `bins` each).
fn cover(bins: u32, positions: impl Iterator<Item = u32>, bins_of: impl Fn(u32) -> (u32, u32)) -> Vec<u32> {
    let mut out = vec![EMPTY; bins as usize];
    // next[k]: the first unassigned bin at or after k, through the forest (bins: none).
    let mut next: Vec<u32> = (0..=bins).collect();
    fn find(next: &mut [u32], mut k: u32) -> u32 {
        while next[k as usize] != k {
            let up = next[next[k as usize] as usize];
            next[k as usize] = up;
            k = up;
        }
        k
    }
    for j in positions {
        let (k0, k1) = bins_of(j);
        let mut k = find(&mut next, k0);
        while k < k1 {
            out[k as usize] = j;
            next[k as usize] = k + 1;
            k = find(&mut next, k + 1);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_bin_covers_exactly_the_positions_between_the_first_and_last_reaching_it() {
        // Bin ranges of 7 positions over 12 bins, one spanning every bin.
        let spans = [(0, 2), (1, 5), (3, 4), (0, 12), (7, 9), (8, 8), (10, 12)];
        let f = |j: u32| spans[j as usize];
        let first = cover(12, 0..7, f);
        let last = cover(12, (0..7).rev(), f);
        for k in 0..12u32 {
            let holders: Vec<u32> = (0..7).filter(|&j| spans[j as usize].0 <= k && k < spans[j as usize].1).collect();
            assert_eq!(first[k as usize], holders.first().copied().unwrap_or(EMPTY), "bin {k}");
            assert_eq!(last[k as usize], holders.last().copied().unwrap_or(EMPTY), "bin {k}");
        }
        // No position holds a bin past the last's end: empty ranges stay empty.
        let none = cover(4, 0..1, |_| (1, 1));
        assert!(none.iter().all(|&v| v == EMPTY));
    }
}
