//! What llvmpipe (lavapipe's rasteriser) may bin into one scene, and the light passes split to
//! stay under it: a culling policy of the light and measurement passes.

use super::methods::{self, Covers};
use super::plan::LightPlan;
use crate::renderer::stats::LIGHTS_PER_QUERY_SET;

/// What llvmpipe (lavapipe's rasteriser) may bin into one scene, in bytes, before our estimate
/// says a new render pass must start: half its `LP_SCENE_MAX_SIZE` of 36 MiB, for margin.
///
/// Why: llvmpipe bins every command into 64x64-pixel tiles and flushes ("rasterises") the
/// scene when its storage is full. An occlusion query's begin and end commands are binned
/// into *every* tile (2 x 240 commands at 1280x720, about 8.5 KiB per light), so thousands of
/// counted lights fill a scene by themselves. If the scene fills exactly while a query's begin
/// command is being binned, llvmpipe has already listed the query as active: the flushed
/// scene's tiles that did not get the begin command "end" the query at their tile end
/// (`lp_rast_tile_end`) with a start of 0, adding every sample the tile passed in the whole
/// scene. That was the `sphere-wall` report (light 3132, off screen, ideal 0, counted 3,315,608
/// fragments at 1280x720 with 4,096 lights; never at 640x360, 60 tiles, or 1,024 lights, where
/// the scene never fills); with this repository's `sphere-wall` it was light 2555, off screen,
/// counting 1,020,508 in `stencil-two-pass` (its volume: 0). The workaround keeps every scene
/// small: the lights are split into render passes whose estimated binned size stays under this
/// budget ([`light_pass_ranges`]). Observed: after the split no light is miscounted (every
/// off-screen light counts 0, two-pass never exceeds its volume, `tests/it/scale.rs`), so a render
/// pass boundary starts a new llvmpipe scene here.
pub const LLVMPIPE_SCENE_BUDGET: u64 = 18 << 20;

/// Bytes llvmpipe bins per command (its command blocks hold 29 in about 512 bytes).
const LP_COMMAND: u64 = 512 / 29 + 1;

/// Bytes of one binned triangle's record (planes and interpolation inputs; under 512).
const LP_TRIANGLE: u64 = 512;

/// llvmpipe's tile size in pixels.
const LP_TILE: u32 = 64;

/// Estimated bytes llvmpipe bins for one light's counted draws: its query's begin and end in
/// every tile, and for each of `draws` draws of `triangles` triangles every triangle in every
/// tile its screen rectangle touches (a triangle is binned only where its bounds fall; a
/// full-screen light's rectangle is the screen), with its record.
pub fn binned_bytes(plan: &LightPlan, size: (u32, u32), draws: u64, triangles: u64) -> u64 {
    let (w, h) = (size.0.max(1), size.1.max(1));
    let tiles = (w.div_ceil(LP_TILE) * h.div_ceil(LP_TILE)) as u64;
    let rect_tiles = match (plan.method, plan.screen_rect) {
        _ if methods::row(plan.method).covers == Covers::Screen => tiles,
        (_, None) => 0,
        (_, Some((lo, hi))) => {
            let t = |x: f32, n: u32| (((x + 1.0) * 0.5 * n as f32).clamp(0.0, n as f32 - 1.0) as u32) / LP_TILE;
            let (x0, x1, y0, y1) = (t(lo.x, w), t(hi.x, w), t(-hi.y, h), t(-lo.y, h));
            (((x1.saturating_sub(x0) + 2) * (y1.saturating_sub(y0) + 2)) as u64).min(tiles)
        }
    };
    2 * tiles * LP_COMMAND + draws * triangles * (rect_tiles * LP_COMMAND + LP_TRIANGLE)
}

/// Splits lights `0..n` into ranges, one per render pass, such that no range crosses a query
/// set (of [`LIGHTS_PER_QUERY_SET`]) and each range's summed `cost` (bytes llvmpipe bins,
/// [`binned_bytes`]) stays under [`LLVMPIPE_SCENE_BUDGET`] (a light costing more is alone).
pub fn pass_ranges(n: usize, cost: impl Fn(usize) -> u64) -> Vec<std::ops::Range<usize>> {
    let mut ranges = Vec::new();
    let (mut start, mut bytes) = (0, 0u64);
    for i in 0..n {
        let c = cost(i);
        if i > start && (i % LIGHTS_PER_QUERY_SET == 0 || bytes + c > LLVMPIPE_SCENE_BUDGET) {
            ranges.push(start..i);
            (start, bytes) = (i, 0);
        }
        bytes += c;
    }
    ranges.push(start..n);
    ranges
}

/// The light accumulation's ranges: by query set only when no fragment is counted (a scene
/// that fills without queries is harmless), else kept under the budget (see
/// [`LLVMPIPE_SCENE_BUDGET`]). `triangles` is the sphere's and the cone's triangle count.
pub fn light_pass_ranges(
    plans: &[LightPlan],
    size: (u32, u32),
    counts: bool,
    triangles: (u64, u64),
) -> Vec<std::ops::Range<usize>> {
    pass_ranges(plans.len(), |i| {
        let p = &plans[i];
        if !counts {
            return 0;
        }
        let t = match p.volume {
            super::volumes::VolumeKind::Sphere => triangles.0,
            super::volumes::VolumeKind::Cone => triangles.1,
        };
        let row = methods::row(p.method);
        match row.covers {
            Covers::Screen => binned_bytes(p, size, row.draws_per_light as u64, 1),
            Covers::Volume => binned_bytes(p, size, row.draws_per_light as u64, t),
            Covers::Nothing => binned_bytes(p, size, 0, 0),
        }
    })
}
