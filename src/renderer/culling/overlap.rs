//! The fp16 clamp by what can overlap a pixel. Every light's contribution to a channel, and the
//! ambient + sun term, is clamped so that no pixel's sum in the accumulation target can reach
//! the format's largest finite value, however many lights the scene has: a light may add at
//! most `max / (3 (c + 1))`, where `c` is the largest number of lights whose conservative screen
//! rectangles ([`LightPlan::screen_rect`]) cover any [`OVERLAP_TILE`]-pixel tile the light's
//! own rectangle covers; ambient + sun may add `max / (3 (c + 1))` with `c` the largest count
//! over all tiles. An isolated light among 50,000 keeps its full value (one light: max / 6).
//!
//! **Why no pixel reaches `max`** (fp16: 65504; Rg11b10Ufloat: 64512, its smallest channel
//! maximum). Take a visible pixel in tile T, and let n be the number of lights whose rectangles
//! cover T. A light adds a non-zero value only inside its true shape, which its volume
//! circumscribes and its rectangle bounds on screen (widened by a pixel here, see `pixel_rect`),
//! so only those n lights add anything at the pixel. Each of them covers T, so its own `c` is at
//! least n and it adds at most max / (3 (n + 1)); ambient + sun's `c` is the largest over all
//! tiles, at least n, so it too writes at most max / (3 (n + 1)). With exact arithmetic the
//! n + 1 terms sum to at most max / 3. The targets round: each term is rounded to the format
//! (relative error u: 2^-11 for fp16, 2^-6 for the 5-bit mantissa of Rg11b10's blue), added to
//! the stored sum s in at least f32 (relative 2^-24) and the result rounded to nearest. Round to
//! nearest never lands farther above the exact sum y = s + x than s itself lies below it (s is
//! representable), so the stored result is at most s + 2x, plus the f32 step's 2^-23 (s + x).
//! Over n + 1 terms the stored sum is at most 2 (1 + u)(1 + 2^-24) max / 3 + (n + 1) 2^-23 max
//! <= 0.678 max + 0.120 max (n <= 1,000,000, the most lights Lampshade takes) < max. So no pixel's
//! accumulated diffuse or specular light reaches the format's maximum (fp16's infinity lies
//! beyond it), whatever the light count. The f64 reference (`crate::reference::shade`) applies
//! the same per-light values, read back with `Last::light_clamps`.

use super::plan::LightPlan;
pub use crate::renderer::records::{format_max, light_clamp};

/// Tile size in pixels of the overlap count.
pub const OVERLAP_TILE: u32 = 16;
thread_local! {
    /// `clamps`' range-maximum table, kept for the next frame on this thread.
    static TABLE: std::cell::Cell<Vec<u32>> = const { std::cell::Cell::new(Vec::new()) };
}

/// `clamps`' tile rectangle of a light that covers no tile (no rectangle has x0 > x1).
const NO_TILES: [u32; 4] = [1, 0, 0, 0];

/// Each light's clamp and the ambient + sun term's, for `plans` on a `size` screen.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Clamps {
    pub ambient: f32,
    pub lights: Vec<f32>,
    /// The largest number of rectangles covering one tile.
    pub most_overlapping: usize,
}

/// A rectangle in NDC to the tiles its pixels lie in (inclusive), widened by a pixel against
/// rounding, as the forward pass's tile lists do; `None` when it misses the screen.
fn tile_rect(rect: (glam::Vec2, glam::Vec2), (w, h): (u32, u32)) -> Option<[u32; 4]> {
    let (lo, hi) = rect;
    let (wf, hf) = (w as f32, h as f32);
    // In pixels, y down: the tiles of floor(a) - 1 ..= floor(a) + 1, without the floors (as
    // `tiles::Span` does): for an integer n, floor(a) >= n exactly when a >= n, and `as u32`
    // truncates, saturating negative and NaN values to 0.
    let (ax0, ax1) = ((lo.x + 1.0) * 0.5 * wf, (hi.x + 1.0) * 0.5 * wf);
    let (ay0, ay1) = ((1.0 - hi.y) * 0.5 * hf, (1.0 - lo.y) * 0.5 * hf);
    // NaN compares false: a rectangle with NaN corners covers every tile.
    if ax1 < -1.0 || ay1 < -1.0 || ax0 >= wf + 1.0 || ay0 >= hf + 1.0 {
        return None;
    }
    let far = |a: f32| if a.is_nan() { u32::MAX } else { (a as u32).saturating_add(1) };
    let tile = |v: u32, max: u32| v.min(max - 1) / OVERLAP_TILE;
    Some([tile((ax0 - 1.0) as u32, w), tile((ay0 - 1.0) as u32, h), tile(far(ax1), w), tile(far(ay1), h)])
}

/// Counts the rectangles over every tile (a 2D difference array: O(lights + tiles)), then gives
/// each light the largest count over its tiles (a 2D range-maximum table: O(1) a light).
pub fn clamps(plans: &[LightPlan], size: (u32, u32), format: wgpu::TextureFormat) -> Clamps {
    let (w, h) = (size.0.max(1), size.1.max(1));
    let (tx, ty) = (w.div_ceil(OVERLAP_TILE) as usize, h.div_ceil(OVERLAP_TILE) as usize);
    // One walk over the plans: each light's tiles (`NO_TILES`: none), counted into the
    // difference array as they are found.
    let mut diff = vec![0i64; (tx + 1) * (ty + 1)];
    let rects: Vec<[u32; 4]> = plans
        .iter()
        .map(|p| match p.screen_rect.and_then(|r| tile_rect(r, (w, h))) {
            Some(r) => {
                let [x0, y0, x1, y1] = r.map(|v| v as usize);
                diff[y0 * (tx + 1) + x0] += 1;
                diff[y0 * (tx + 1) + x1 + 1] -= 1;
                diff[(y1 + 1) * (tx + 1) + x0] -= 1;
                diff[(y1 + 1) * (tx + 1) + x1 + 1] += 1;
                r
            }
            None => NO_TILES,
        })
        .collect();
    // Prefix sums: the count per tile.
    let mut count = vec![0u32; tx * ty];
    let mut above = vec![0i64; tx + 1];
    for y in 0..ty {
        let mut run = 0i64;
        for x in 0..tx {
            run += diff[y * (tx + 1) + x];
            above[x] += run;
            count[y * tx + x] = above[x].max(0) as u32;
        }
    }
    let most = count.iter().copied().max().unwrap_or(0) as usize;
    // A 2D sparse table: level (ky, kx) holds at (y, x) the largest count over the 2^ky rows
    // from y and the 2^kx columns from x (cut at the grid's edge), so any rectangle's maximum
    // is that of four overlapping power-of-two blocks: O(1) a light (a light spans about ten
    // tile rows at 16,384 lights on `demo`, which the row-by-row table walked one by one).
    let log2 = |n: usize| (usize::BITS - 1 - n.leading_zeros()) as usize;
    let (lx, ly) = (log2(tx) + 1, log2(ty) + 1);
    let plane = tx * ty;
    // The table (600 KB at 1280x720) is kept from frame to frame: allocated afresh, its pages
    // were faulted in every frame (173,000 page faults over `cpuplan loop`'s 250 frames, about
    // 0.5 ms a frame of CPU). Every entry is written below, so its old contents do not matter.
    let mut table = TABLE.with(|t| t.take());
    table.resize(lx * ly * plane, 0);
    let level = |ky: usize, kx: usize| (ky * lx + kx) * plane;
    // Only the levels some light asks for are built, with what they are built from: level
    // (ky, kx) from (ky - 1, kx), down to (0, kx), which comes from (0, kx - 1). At 16,384
    // lights on `demo` most lights span a few tiles, so most of the 42 levels at 1280x720 go
    // unread. `wanted[kx]` is the largest ky asked for at width level kx (+1; 0: none).
    let mut wanted = vec![0usize; lx];
    for &[x0, y0, x1, y1] in rects.iter().filter(|&&r| r != NO_TILES) {
        let (kx, ky) = (log2((x1 - x0 + 1) as usize), log2((y1 - y0 + 1) as usize));
        wanted[kx] = wanted[kx].max(ky + 1);
    }
    let widest = wanted.iter().rposition(|&k| k > 0).unwrap_or(0);
    table[..plane].copy_from_slice(&count);
    for kx in 1..=widest {
        let half = 1 << (kx - 1);
        let (done, rest) = table.split_at_mut(level(0, kx));
        let (src, dst) = (&done[level(0, kx - 1)..], &mut rest[..plane]);
        for y in 0..ty {
            let (s, d) = (&src[y * tx..(y + 1) * tx], &mut dst[y * tx..(y + 1) * tx]);
            for x in 0..tx {
                d[x] = if x + half < tx { s[x].max(s[x + half]) } else { s[x] };
            }
        }
    }
    for ky in 1..ly {
        let half = 1 << (ky - 1);
        for kx in (0..lx).filter(|&kx| wanted[kx] > ky) {
            let (done, rest) = table.split_at_mut(level(ky, kx));
            let (src, dst) = (&done[level(ky - 1, kx)..level(ky - 1, kx) + plane], &mut rest[..plane]);
            for y in 0..ty {
                let d = &mut dst[y * tx..(y + 1) * tx];
                let a = &src[y * tx..(y + 1) * tx];
                if y + half < ty {
                    let b = &src[(y + half) * tx..(y + half + 1) * tx];
                    for ((d, a), b) in d.iter_mut().zip(a).zip(b) {
                        *d = (*a).max(*b);
                    }
                } else {
                    d.copy_from_slice(a);
                }
            }
        }
    }
    // Each count's clamp once (the same division as per light, looked up).
    let clamp_of: Vec<f32> = (0..=most).map(|c| light_clamp(format, c)).collect();
    let lights = rects
        .iter()
        .map(|&r| {
            let c = (r != NO_TILES).then_some(r).map_or(0, |[x0, y0, x1, y1]| {
                let (x0, y0, x1, y1) = (x0 as usize, y0 as usize, x1 as usize, y1 as usize);
                let (kx, ky) = (log2(x1 - x0 + 1), log2(y1 - y0 + 1));
                let t = &table[level(ky, kx)..level(ky, kx) + plane];
                let (xb, yb) = (x1 + 1 - (1 << kx), y1 + 1 - (1 << ky));
                t[y0 * tx + x0].max(t[y0 * tx + xb]).max(t[yb * tx + x0]).max(t[yb * tx + xb])
            });
            clamp_of.get(c as usize).copied().unwrap_or_else(|| light_clamp(format, c as usize))
        })
        .collect();
    TABLE.with(|t| t.replace(table));
    Clamps { ambient: light_clamp(format, most), lights, most_overlapping: most }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::plan::Method;
    use crate::renderer::volumes::VolumeKind;
    use glam::Vec2;

    fn plan(rect: Option<(Vec2, Vec2)>) -> LightPlan {
        LightPlan {
            method: Method::Volume,
            volume: VolumeKind::Sphere,
            crosses_near: false,
            crosses_far: false,
            screen_share: 0.0,
            screen_rect: rect,
            depths: (f32::INFINITY, f32::NEG_INFINITY),
        }
    }

    #[test]
    fn each_light_is_clamped_by_the_most_lights_meeting_at_its_tiles() {
        let fmt = wgpu::TextureFormat::Rgba16Float;
        let size = (320, 180);
        // Three stacked in the top-left corner, one alone on the right, one off screen, one
        // covering everything.
        let corner = Some((Vec2::new(-1.0, 0.8), Vec2::new(-0.9, 1.0)));
        let alone = Some((Vec2::new(0.5, -0.2), Vec2::new(0.6, -0.1)));
        let plans = [plan(corner), plan(corner), plan(corner), plan(alone), plan(None)];
        let c = clamps(&plans, size, fmt);
        assert_eq!(c.most_overlapping, 3);
        assert_eq!(c.lights[0], light_clamp(fmt, 3));
        assert_eq!(c.lights[3], light_clamp(fmt, 1));
        assert_eq!(c.lights[4], light_clamp(fmt, 0));
        assert_eq!(c.ambient, light_clamp(fmt, 3));
        let mut all = plans.to_vec();
        all.push(plan(Some((Vec2::splat(-1.0), Vec2::splat(1.0)))));
        let c = clamps(&all, size, fmt);
        assert_eq!(c.most_overlapping, 4);
        assert_eq!(c.lights[3], light_clamp(fmt, 2));
        assert_eq!(c.lights[5], light_clamp(fmt, 4));
        // Against a brute-force count over random rectangles.
        let mut rng = 1u64;
        let mut next = || {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (rng >> 40) as f32 / (1u64 << 24) as f32 * 2.6 - 1.3
        };
        let random: Vec<LightPlan> = (0..300)
            .map(|_| {
                let (a, b, s) = (next(), next(), next().abs() * 0.3);
                plan(Some((Vec2::new(a, b), Vec2::new(a + s, b + s * 0.5))))
            })
            .collect();
        // And rectangles of every size up to the whole screen (every level of the table).
        let mut random = random;
        random.extend((0..300).map(|_| {
            let (a, b, sx, sy) = (next(), next(), next().abs() * 2.0, next().abs() * 2.0);
            plan(Some((Vec2::new(a, b), Vec2::new(a + sx, b + sy))))
        }));
        let c = clamps(&random, size, fmt);
        let tiles: Vec<Option<[u32; 4]>> = random.iter().map(|p| tile_rect(p.screen_rect.unwrap(), size)).collect();
        let count = |x: u32, y: u32| {
            tiles
                .iter()
                .flatten()
                .filter(|[x0, y0, x1, y1]| (*x0..=*x1).contains(&x) && (*y0..=*y1).contains(&y))
                .count()
        };
        for (i, t) in tiles.iter().enumerate() {
            let want = t.map_or(0, |[x0, y0, x1, y1]| {
                (y0..=y1).flat_map(|y| (x0..=x1).map(move |x| (x, y))).map(|(x, y)| count(x, y)).max().unwrap()
            });
            assert_eq!(c.lights[i], light_clamp(fmt, want), "light {i}");
        }
    }

    /// `tile_rect` without floors gives the tiles of the floored pixel rectangle widened by a
    /// pixel (what it computed before), NaN corners covering every tile.
    #[test]
    fn the_tiles_of_a_rectangle_are_those_of_its_floored_pixels() {
        let size = (320u32, 180u32);
        let old = |(lo, hi): (Vec2, Vec2)| -> Option<[u32; 4]> {
            let (w, h) = size;
            let px = |x: f32| ((x + 1.0) * 0.5 * w as f32).floor();
            let py = |y: f32| ((1.0 - y) * 0.5 * h as f32).floor();
            let (x0, x1) = (px(lo.x) - 1.0, px(hi.x) + 1.0);
            let (y0, y1) = (py(hi.y) - 1.0, py(lo.y) + 1.0);
            if x1 < 0.0 || y1 < 0.0 || x0 >= w as f32 || y0 >= h as f32 {
                return None;
            }
            let tile = |v: f32, max: u32| {
                let v = if v.is_nan() { 0.0 } else { v };
                (v.max(0.0) as u32).min(max - 1) / OVERLAP_TILE
            };
            let (x1, y1) = (if x1.is_nan() { f32::INFINITY } else { x1 }, if y1.is_nan() { f32::INFINITY } else { y1 });
            Some([tile(x0, w), tile(y0, h), tile(x1, w), tile(y1, h)])
        };
        let mut rng = 7u64;
        let mut next = || {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (rng >> 40) as f32 / (1u64 << 24) as f32 * 5.0 - 2.5
        };
        let mut v: Vec<f32> = (0..3000).map(|_| next()).collect();
        v.extend((0..=40).map(|k| -1.0 + k as f32 / 20.0));
        v.extend([1.0 + 2.0 / 320.0, -1.0 - 2.0 / 320.0, 1e30, -1e30, f32::INFINITY, f32::NAN]);
        for q in v.windows(4) {
            let r = (Vec2::new(q[0], q[1]), Vec2::new(q[2], q[3]));
            assert_eq!(tile_rect(r, size), old(r), "{r:?}");
        }
    }

    /// Rounds to nearest (ties to even) with `bits` mantissa bits, as the targets store.
    fn round_to(v: f32, bits: i32) -> f32 {
        if v <= 0.0 {
            return v;
        }
        let ulp = 2f64.powi(v.log2().floor() as i32 - bits);
        ((v as f64 / ulp).round_ties_even() * ulp) as f32
    }

    #[test]
    fn the_bound_holds_for_every_overlap() {
        // n + 1 terms at the clamp of n overlapping lights, each rounded to the target, summed
        // in f32 and rounded to nearest at every step, stay below the maximum: fp16 (10 bits),
        // Rg11b10's red and green (6) and blue (5).
        for (fmt, bits) in [
            (wgpu::TextureFormat::Rgba16Float, 10),
            (wgpu::TextureFormat::Rg11b10Ufloat, 6),
            (wgpu::TextureFormat::Rg11b10Ufloat, 5),
        ] {
            let max = format_max(fmt).unwrap();
            for n in [0usize, 1, 7, 100, 1000, 20_000] {
                let x = round_to(light_clamp(fmt, n), bits);
                let mut s = x;
                for _ in 0..n {
                    s = round_to(s + x, bits);
                }
                assert!(s < max, "{fmt:?} ({bits} bits), {n} lights: {s}");
            }
        }
        assert_eq!(light_clamp(wgpu::TextureFormat::Rgba32Float, 5), f32::MAX);
    }
}
