//! Light batches: which lights share one instanced draw.
//!
//! Every draw costs about 25-35 µs on lavapipe whatever it rasterises, so drawing 1,028 lights
//! one draw (or a mark and a shade draw) each spent about half of `demo`'s frame on draw
//! overhead. A batch is a run of entries of the frame's draw list (`draw_lights` in the
//! shaders): the light pass draws it as one instanced draw, and the vertex shader reads its
//! light from `draw_lights[instance_index]` (WGSL's `instance_index` counts from the draw's first
//! instance, the batch's first entry), so a batch's lights need not be consecutive.
//!
//! - **Full-screen and plain volumes** (no stencil): additive blending commutes, so all of a
//!   method's lights go into one batch per volume kind (full-screen: one batch). Only the fp16
//!   summation order changes.
//! - **Stencil methods** (two-pass, invert, replace): lights whose conservative pixel
//!   rectangles do not overlap share a batch: one instanced mark draw, then one instanced shade
//!   draw (split into runs of casting and other lights when only casters run the shadow
//!   lookups: `culling::light_pass::casting_runs`). Why the picture and every light's shaded fragments stay those of the unbatched frame:
//!   1. A light's draws rasterise only inside its rectangle (see [`Footprint`]), so at any pixel
//!      at most one light of a batch does anything: the pixel sees that light's mark, then its
//!      shade, as unbatched.
//!   2. Across batches a pixel may see lights in another order than unbatched, so each light's
//!      (mark, shade) must find the stencil as unbatched. It does, because each method leaves
//!      the stencil in a state the next light ignores (checked against the `StencilMethod`
//!      literals in `culling/light_pass.rs`):
//!      - *two-pass* (seed 000): the mark increments on front faces' depth fail; the shade draws
//!        the back faces, which cover every pixel the front faces cover (a closed convex mesh;
//!        where the near plane clips front faces the back faces cover more), with Zero on
//!        stencil fail, depth fail and pass: every pixel the light touched is zero again;
//!      - *invert* (seed 001): the mark inverts on either face's depth fail; the shade (back
//!        faces, depth test off, stencil NotEqual 0) has pass op Zero and fail op Keep on a
//!        zero value: every pixel the light touched is zero again;
//!      - *replace* (seed 002): the mark writes the batch's reference X, the shade tests
//!        Equal X and writes nothing. X is new since the last clear (one value per batch,
//!        1..=255, the stencil cleared every 255 batches as it was every 255 lights), so values
//!        left by earlier batches never equal it: a light's test sees only its own marks (no
//!        other light of its batch reaches its pixels).
//!
//!   Lights crossing the near plane are drawn unmarked, as plain volumes, and leave the stencil
//!   as they found it (`methods::CROSSING_NEAR`; batched apart by their `Key`).
//!
//!   So every light shades exactly the samples it shades unbatched.
//! - **Light order kept**: batches are formed in light order, and a light joins its key's last
//!   batch only if that batch comes after every batch holding an earlier light whose footprint
//!   shares a [`CELL`] with it (for plain volumes and full-screen lights, whose draws blend in
//!   instance order, it may also be that batch itself); else it opens a new batch. So every
//!   pixel receives its lights in light order, as unbatched: the same blends in the same order,
//!   bit-identical sums (`tests/it/batching.rs` compares the bits). Largest-first first-fit needed
//!   2.25x fewer batches but reordered the blends: a step off on 2.7% of the room's pixels.
//! - Batches never span two blocks of [`LIGHTS_PER_QUERY_SET`] lights: the light pass records
//!   one render pass per block (one occlusion query set each), as before.
//!
//! Cells are coarser than pixels, so two lights can be kept apart that would not have met (more
//! batches, never wrong).

use super::plan::{LightPlan, Method, PlanView};
use super::volumes::{self, VolumeKind, Volumes};
use crate::renderer::records::LightRecord;
use crate::renderer::stats::LIGHTS_PER_QUERY_SET;
use glam::Vec2;

/// Side in pixels of the occupancy grid's cells.
pub const CELL: u32 = 8;

/// Lights drawn by one instanced draw (or one mark and one shade draw).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Batch {
    pub method: Method,
    pub volume: VolumeKind,
    /// The batch's lights cross the near plane (shaded unmarked with another pipeline:
    /// `methods::CROSSING_NEAR`).
    pub crosses_near: bool,
    /// The batch's entries in [`LightBatches::list`]: `first..first + count`.
    pub first: u32,
    pub count: u32,
}

impl Batch {
    /// The instance range that draws the batch.
    pub fn instances(&self) -> std::ops::Range<u32> {
        self.first..self.first + self.count
    }
}

/// The frame's batches and the draw list they index.
#[derive(Clone, Debug, Default)]
pub struct LightBatches {
    /// In drawing order, block by block.
    pub batches: Vec<Batch>,
    /// Per block of [`LIGHTS_PER_QUERY_SET`] lights, the range of `batches` it draws.
    pub blocks: Vec<std::ops::Range<usize>>,
    /// The draw list (`draw_lights` in the shaders): first the identity (entry `i` is light `i`,
    /// for draws of one light: unbatched frames, the debug and measurement passes), then each
    /// batch's lights.
    pub list: Vec<u32>,
}

/// Where a light's draws can rasterise: nothing, or inside a pixel rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Footprint {
    Empty,
    /// x0, y0, x1, y1 in pixels, inclusive, inside the screen (y down).
    Rect([u32; 4]),
}

/// The pixels (inclusive, clipped to the screen) a rectangle in NDC can touch, widened by a
/// pixel against rounding (as `plan_draws`' tile lists do); `None` when it misses the screen.
/// A rectangle that is not finite is the whole screen.
pub fn pixel_rect(lo: Vec2, hi: Vec2, (w, h): (u32, u32)) -> Option<[u32; 4]> {
    if w == 0 || h == 0 {
        return None;
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Some([0, 0, w - 1, h - 1]);
    }
    let px = |x: f32| super::tiled::floor((x + 1.0) * 0.5 * w as f32);
    let py = |y: f32| super::tiled::floor((1.0 - y) * 0.5 * h as f32);
    let (x0, x1) = (px(lo.x) - 1.0, px(hi.x) + 1.0);
    let (y0, y1) = (py(hi.y) - 1.0, py(lo.y) + 1.0);
    if x1 < 0.0 || y1 < 0.0 || x0 >= w as f32 || y0 >= h as f32 || x0 > x1 || y0 > y1 {
        return None;
    }
    let clamp = |v: f32, max: u32| (v.max(0.0) as u32).min(max - 1);
    Some([clamp(x0, w), clamp(y0, h), clamp(x1, w), clamp(y1, h)])
}

/// Where light `light`'s volume draws can rasterise this frame.
///
/// - On screen, not crossing the near plane: every vertex lies beyond the near plane, so the
///   mesh projects inside the hull of its projected vertices, which `screen_rect` bounds.
/// - Crossing the near plane: `screen_rect` is the whole screen.
/// - Off screen (`screen_rect` is `None`): without depth clamp nothing is rasterised (outside a
///   side plane, or wholly in front of the near or beyond the far plane: clipped). With depth
///   clamp the near and far planes do not clip, so the volume is checked again here: nothing if
///   all its vertices lie outside one side plane or behind the eye (w <= 0, clipped by the side
///   planes), the rectangle of its projected vertices if all lie in front of the eye (beyond the
///   far plane, drawn at clamped depth), else the whole screen.
pub fn footprint(plan: &LightPlan, light: &LightRecord, volumes: &Volumes, view: &PlanView) -> Footprint {
    let whole = Footprint::Rect([0, 0, view.size.0.max(1) - 1, view.size.1.max(1) - 1]);
    if let Some((lo, hi)) = plan.screen_rect {
        if plan.crosses_near {
            return whole;
        }
        return pixel_rect(lo, hi, view.size).map_or(Footprint::Empty, Footprint::Rect);
    }
    if !view.depth_clamp {
        return Footprint::Empty;
    }
    let mut outside = [true; 4];
    let (mut all_behind, mut all_ahead) = (true, true);
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for v in &volumes.mesh(plan.volume).vertices {
        let c = view.proj * volumes::place_light(*v, light).extend(1.0);
        for (k, d) in [c.w - c.x, c.w + c.x, c.w - c.y, c.w + c.y].into_iter().enumerate() {
            outside[k] &= d < 0.0;
        }
        all_behind &= c.w <= 0.0;
        all_ahead &= c.w > 0.0;
        if c.w > 0.0 {
            let n = Vec2::new(c.x, c.y) / c.w;
            lo = lo.min(n);
            hi = hi.max(n);
        }
    }
    if outside.iter().any(|&o| o) || all_behind {
        Footprint::Empty
    } else if all_ahead {
        pixel_rect(lo, hi, view.size).map_or(Footprint::Empty, Footprint::Rect)
    } else {
        whole
    }
}

/// What lights must share to be drawn together: the pipelines and the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Key {
    method: u8,
    volume: u8,
    crosses_near: bool,
}

/// Whether the light pass draws a light of method `m`: not when it is skipped, nor when the
/// tiled pass shades it.
fn drawn(m: Method) -> bool {
    super::methods::row(m).draws.is_some()
}

impl LightBatches {
    /// The batches of a frame's planned lights; with `view.light_batching` off, one batch per
    /// drawn light in light order (the draws the renderer made before batching).
    pub fn new(plans: &[LightPlan], lights: &[LightRecord], volumes: &Volumes, view: &PlanView) -> Self {
        let n = plans.len();
        let mut out = LightBatches { list: (0..n as u32).collect(), ..Default::default() };
        for start in (0..n).step_by(LIGHTS_PER_QUERY_SET) {
            let end = (start + LIGHTS_PER_QUERY_SET).min(n);
            let first_batch = out.batches.len();
            if view.light_batching {
                out.batch_block(start..end, plans, lights, volumes, view);
            } else {
                for (i, p) in plans.iter().enumerate().take(end).skip(start) {
                    if drawn(p.method) {
                        out.batches.push(Batch {
                            method: p.method,
                            volume: p.volume,
                            crosses_near: p.crosses_near,
                            first: i as u32,
                            count: 1,
                        });
                    }
                }
            }
            out.blocks.push(first_batch..out.batches.len());
        }
        out
    }

    /// Batches one block's drawn lights in light order, so that every pixel still receives its
    /// lights in the order the unbatched frame draws them (bit-identical sums): each light joins
    /// the last batch of its key (method, mesh, near-crossing) if that batch comes after every
    /// batch that holds an earlier light whose footprint shares a [`CELL`] with it (for plain
    /// volumes and full-screen lights, which need no stencil, it may also be that batch itself:
    /// instances blend in instance order), else it opens a new batch at the end.
    fn batch_block(
        &mut self,
        block: std::ops::Range<usize>,
        plans: &[LightPlan],
        lights: &[LightRecord],
        volumes: &Volumes,
        view: &PlanView,
    ) {
        // A block the light pass draws nothing of (every light tiled, clustered or skipped)
        // needs no occupancy grid.
        if !plans[block.clone()].iter().any(|p| drawn(p.method)) {
            return;
        }
        let (w, h) = view.size;
        let (gw, gh) = (w.div_ceil(CELL).max(1) as usize, h.div_ceil(CELL).max(1) as usize);
        // Per cell, the last batch (index into `sets`) holding a light there, plus one (0: none);
        // `whole`: the same for lights covering the whole grid, kept apart so that full-screen
        // lights do not walk every cell.
        let mut grid = vec![0usize; gw * gh];
        let mut whole = 0usize;
        let mut sets: Vec<(Key, Vec<u32>)> = Vec::new();
        let mut last_of: Vec<(Key, usize)> = Vec::new();
        for i in block {
            let p = &plans[i];
            if !drawn(p.method) {
                continue;
            }
            let key = Key {
                method: super::methods::order(p.method),
                // Full-screen draws use no mesh: one batch whatever the light's kind.
                volume: if p.method == Method::Fullscreen { 0 } else { p.volume as u8 },
                // The stencil methods shade near-crossing lights with another pipeline, unmarked.
                crosses_near: p.crosses_near && super::methods::row(p.method).marks(),
            };
            let foot = if p.method == Method::Fullscreen {
                Footprint::Rect([0, 0, w.max(1) - 1, h.max(1) - 1])
            } else {
                footprint(p, &lights[i], volumes, view)
            };
            let cells = match foot {
                Footprint::Empty => None,
                Footprint::Rect([x0, y0, x1, y1]) => Some([
                    (x0 / CELL) as usize,
                    (y0 / CELL) as usize,
                    ((x1 / CELL) as usize).min(gw - 1),
                    ((y1 / CELL) as usize).min(gh - 1),
                ]),
            };
            let covers_all = cells == Some([0, 0, gw - 1, gh - 1]);
            // The last batch (plus one) that must be drawn before this light.
            let mut after = whole;
            if let Some([cx0, cy0, cx1, cy1]) = cells.filter(|_| !covers_all) {
                for y in cy0..=cy1 {
                    after = after.max(grid[y * gw + cx0..=y * gw + cx1].iter().copied().max().unwrap_or(0));
                }
            } else if covers_all {
                after = after.max(grid.iter().copied().max().unwrap_or(0));
            }
            let last = last_of.iter().find(|(k, _)| *k == key).map(|&(_, b)| b);
            // `last + 1 > after`: drawn after every earlier light here; `==` allowed without stencil.
            let joins = match last {
                Some(b) if cells.is_none() => Some(b),
                Some(b) if b + 1 > after => Some(b),
                Some(b) if b + 1 == after && !super::methods::row(p.method).marks() => Some(b),
                _ => None,
            };
            let b = match joins {
                Some(b) => b,
                None => {
                    sets.push((key, Vec::new()));
                    let b = sets.len() - 1;
                    match last_of.iter_mut().find(|(k, _)| *k == key) {
                        Some(entry) => entry.1 = b,
                        None => last_of.push((key, b)),
                    }
                    b
                }
            };
            sets[b].1.push(i as u32);
            if covers_all {
                whole = whole.max(b + 1);
            } else if let Some([cx0, cy0, cx1, cy1]) = cells {
                for y in cy0..=cy1 {
                    for cell in &mut grid[y * gw + cx0..=y * gw + cx1] {
                        *cell = (*cell).max(b + 1);
                    }
                }
            }
        }
        for (_, members) in sets {
            let p = plans[members[0] as usize];
            let first = self.list.len() as u32;
            self.list.extend_from_slice(&members);
            self.batches.push(Batch {
                method: p.method,
                volume: p.volume,
                crosses_near: p.crosses_near,
                first,
                count: members.len() as u32,
            });
        }
    }

    /// The lights of `batch`, from the draw list.
    pub fn lights_of(&self, batch: &Batch) -> &[u32] {
        &self.list[batch.first as usize..(batch.first + batch.count) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_rects_widen_by_a_pixel_and_clip_to_the_screen() {
        let size = (100, 50);
        // The whole screen and more.
        assert_eq!(pixel_rect(Vec2::splat(-2.0), Vec2::splat(2.0), size), Some([0, 0, 99, 49]));
        // Just right of and above the centre: pixel column 50 (x = 0 is the edge between 49
        // and 50), row 24 (y = 0 is the edge between rows 24 and 25), widened by one.
        assert_eq!(pixel_rect(Vec2::new(0.0, 0.0), Vec2::new(0.01, 0.01), size), Some([49, 23, 51, 26]));
        assert_eq!(pixel_rect(Vec2::new(1.5, 0.0), Vec2::new(2.0, 0.5), size), None);
        assert_eq!(pixel_rect(Vec2::NAN, Vec2::ONE, size), Some([0, 0, 99, 49]));
    }
}
