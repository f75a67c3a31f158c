//! The CPU's part of the `tiled` and `clustered` culling modes: the clustered mode's light
//! lists (Olsson, Billeter, Assarsson 2012, assigned on the CPU as Bevy does), and `auto`'s
//! frame-level choice between its per-light plan and `clustered`.
//!
//! The GPU's part (the tiled mode's compute pass, the shading pass both share, the debug view)
//! is `culling::tiled::pass`.

pub mod pass;
pub mod scratch;

use crate::renderer::culling::methods::Covers;
use crate::renderer::culling::plan::{FramePlan, LightPlan, Method, PlanView};
use crate::renderer::options::calibration::{CostConstants, ListCost};
use crate::renderer::options::caps::CapOrder;
use crate::renderer::options::culling::CullingMode;
use crate::renderer::records::LightRecord;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Size in pixels of the `tiled` mode's tiles (Andersson 2011: 16x16, one compute workgroup).
pub const TILE: u32 = 16;
/// Size in pixels of the `clustered` mode's screen tiles.
pub const CLUSTER_TILE: u32 = 32;
/// Exponential depth slices between the nearest and the farthest depth the frame's lights
/// reach (`clustered`).
pub const SLICES: u32 = 64;
/// The most cells a clustered grid the knobs ask for may have (`frame::Shape` refuses finer
/// ones): 4M cells, whose (first, count) headers take 32 MiB. The default grid at 7680x4320
/// has 2.1M.
pub const MAX_GRID_CELLS: u64 = 1 << 22;
/// From this many lights the CPU's cluster lists (`cluster_lists`, the CPU builder) are split
/// over two threads; below it a thread costs more than it saves.
pub const PARALLEL_MIN_LIGHTS: usize = 1024;
/// A list count meaning "every light" (the GPU's list buffer ran out of room for this tile):
/// the tile is shaded with all lights, the right picture at a higher cost.
pub const ALL_LIGHTS: u32 = u32::MAX;

/// Lights the tiled compute pass keeps a bit for at once (2048 words of workgroup memory): a
/// frame with more lights builds each tile's list in batches of this many, counted in a first
/// sweep and tested again and written in a second (`tiled.wgsl`, `cs_tile_lists`).
pub const GPU_LIST_MAX_LIGHTS: u32 = 65536;
/// List entries one draw of the tiled or clustered shading pass walks per pixel: lists longer
/// than this are walked in draws of this many entries each, added together (one instance per
/// chunk, `SHADE_CHUNK` x the chunk onwards). lavapipe (gallivm) stops every loop of a shader
/// invocation once they have run 65,535 iterations between them (`LP_MAX_TGSI_LOOP_ITERATIONS`,
/// shared by all its loops), silently: a list of 70,000 lights lost the last 4,465. A chunk's
/// two loops (every light, then the casters) run at most 2 x 32,000 iterations.
pub const SHADE_CHUNK: u32 = 32_000;

/// The draws (instances) of the shading pass for `lights` lights: lists hold at most every
/// light, so `lights` / [`SHADE_CHUNK`] rounded up (at least one).
pub fn shade_chunks(lights: usize) -> u32 {
    (lights as u64).div_ceil(SHADE_CHUNK as u64).max(1) as u32
}

/// The list length the `tile-lights` view shows at the top of its colour map (longer lists
/// saturate): generated into WGSL as `LS_TILE_HEAT_MAX`, and the viewer's legend reads it.
pub const HEAT_MAX: f32 = 64.0;

/// The heatmap colour map of the complexity and `tile-lights` views, as `heat()` in
/// `surfaces/compose.wgsl` computes it (linear RGB), for the viewer's legend and the tests.
pub fn heat(t: f32) -> [f32; 3] {
    let x = t.clamp(0.0, 1.0);
    let c = |v: f32| v.clamp(0.0, 1.0);
    [c(1.5 * x), c(1.5 * x - 0.5), c(0.5 - (x - 0.5).abs() + (3.0 * x - 2.0).max(0.0))]
}

/// `x.floor()` without the library call: baseline x86-64 has no rounding instruction, so
/// `f32::floor` calls `floorf` (3% of the CPU planning at 16,384 lights, four to six calls a
/// light). Exact for |x| < 2^23, where every float's integer part fits an `i32`; larger values
/// (already integers) and NaN go to `floor`. Only the sign of a zero can differ (`-0.0` gives
/// `0.0`), which no caller tells apart.
#[inline]
pub fn floor(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        let t = x as i32 as f32;
        if t > x {
            t - 1.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// The clustered grid of one frame: tiles across and down, slices, and the slice mapping
/// (a view depth d lies in slice `floor(ln d x scale + bias)`, clamped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterGrid {
    pub tile: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub slices: u32,
    pub scale: f32,
    pub bias: f32,
    pub near: f32,
    pub far: f32,
    /// 0, or the view depth the first slice ends at: slice 0 then runs from the eye to it and
    /// the others exponentially from it to `far` ([`ClusterGrid::first_slice`]).
    pub first: f32,
}

impl ClusterGrid {
    pub fn new(size: (u32, u32), near: f32, far: f32) -> Self {
        Self::with_cells(size, near, far, CLUSTER_TILE, SLICES)
    }

    /// A grid of `tile`-pixel tiles and `slices` exponential slices from `near` to `far`.
    pub fn with_cells(size: (u32, u32), near: f32, far: f32, tile: u32, slices: u32) -> Self {
        let far = far.max(near * 1.0001);
        let scale = slices as f32 / (far / near).ln();
        Self {
            tile,
            tiles_x: size.0.div_ceil(tile),
            tiles_y: size.1.div_ceil(tile),
            slices,
            scale,
            bias: -near.ln() * scale,
            near,
            far,
            first: 0.0,
        }
    }

    /// Bevy's slices (`ClusterZConfig`, after the Doom 2016 slicing, Sousa and Geffroy's
    /// SIGGRAPH 2016 talk): slice 0 from the eye to view depth `first`, slices 1 .. `slices`
    /// exponential from `first` to `far`. The shader's mapping is the same formula, floor(ln d x
    /// scale + bias) clamped: with scale = (slices - 1) / ln(far / first) and bias = 1 - ln(first)
    /// x scale, depth `first` maps to 1 and every depth before it clamps to slice 0.
    pub fn first_slice(size: (u32, u32), first: f32, far: f32, tile: u32, slices: u32) -> Self {
        let far = far.max(first * 1.0001);
        let scale = if slices > 1 { (slices - 1) as f32 / (far / first).ln() } else { 0.0 };
        let bias = if slices > 1 { 1.0 - first.ln() * scale } else { 0.0 };
        Self { scale, bias, first, ..Self::with_cells(size, first, far, tile, slices) }
    }

    pub fn cells(&self) -> usize {
        (self.tiles_x * self.tiles_y * self.slices) as usize
    }

    /// The slice of view depth `d` (what the shader computes, clamped to the grid).
    pub fn slice(&self, d: f32) -> u32 {
        let k = floor(d.max(1e-30).ln() * self.scale + self.bias);
        (k.max(0.0) as u32).min(self.slices - 1)
    }

    /// The near and far view depth of slice `k`.
    pub fn slice_depths(&self, k: u32) -> (f32, f32) {
        if self.first > 0.0 {
            // Slice 0 holds every depth before `first`; with one slice, every depth.
            if self.slices <= 1 {
                return (0.0, f32::INFINITY);
            }
            if k == 0 {
                return (0.0, self.first);
            }
        }
        let d = |k: u32| ((k as f32 - self.bias) / self.scale).exp();
        (d(k), d(k + 1))
    }

    /// The cell of tile (`tx`, `ty`) and slice `k`, as the shader indexes it.
    pub fn cell(&self, tx: u32, ty: u32, k: u32) -> usize {
        ((k * self.tiles_y + ty) * self.tiles_x + tx) as usize
    }
}

/// The clustered mode's lists as uploaded: a (first, count) pair per cell, then the entries
/// (light indices, in light order); `first` indexes this same array.
#[derive(Clone, Debug, Default)]
pub struct ClusterLists {
    pub data: Vec<u32>,
    pub grid: Option<ClusterGrid>,
    pub entries: u64,
    pub longest: u32,
    /// Entries the per-cluster cap left out (`Settings::lights_per_cluster`).
    pub capped: u64,
}

impl ClusterLists {
    /// The lists as uploaded into one binding of at most `max` words: as they are if they fit;
    /// otherwise the longest lists give way first: their cells walk every light instead
    /// (`ALL_LIGHTS`, counted as overflowed; the same picture at a higher cost, which is least
    /// where a list already holds many lights), and the rest are laid out again in cell order.
    pub fn fitted(&self, max: usize) -> std::borrow::Cow<'_, [u32]> {
        let data = &self.data;
        if data.len() <= max {
            return std::borrow::Cow::Borrowed(data);
        }
        let cells = self.grid.map_or(0, |g| g.cells());
        let header = 2 * cells;
        let len = |c: usize| if data[2 * c + 1] == ALL_LIGHTS { usize::MAX } else { data[2 * c + 1] as usize };
        let mut order: Vec<usize> = (0..cells).collect();
        order.sort_by_key(|&c| len(c));
        let mut keep = vec![false; cells];
        let mut used = 0;
        for c in order {
            let n = len(c);
            if n == usize::MAX || header + used + n > max {
                break;
            }
            used += n;
            keep[c] = true;
        }
        let mut out = vec![0u32; header];
        out.reserve(used);
        for (c, &kept) in keep.iter().enumerate() {
            if kept {
                let first = data[2 * c] as usize;
                out[2 * c] = out.len() as u32;
                out[2 * c + 1] = data[2 * c + 1];
                out.extend_from_slice(&data[first..first + len(c)]);
            } else {
                out[2 * c + 1] = ALL_LIGHTS;
            }
        }
        std::borrow::Cow::Owned(out)
    }

    /// Light indices of cell `cell`.
    pub fn list(&self, cell: usize) -> &[u32] {
        let (first, count) = (self.data[2 * cell] as usize, self.data[2 * cell + 1] as usize);
        &self.data[first..first + count]
    }
}

/// The view-space extent of the grid's cells, separable: a cluster's box is the tile's frustum
/// piece between its slice's depths, and its x range depends only on the tile's column and the
/// slice (likewise y on the row), its z range only on the slice.
struct CellBounds {
    grid: ClusterGrid,
    size: (u32, u32),
    /// Per column: view x over view depth at the column's left and right edges (widened by a
    /// pixel), so the column spans `d x a0 .. d x a1` at depth d.
    columns: Vec<(f32, f32)>,
    rows: Vec<(f32, f32)>,
    /// Per slice: its near and far depth, widened by 0.1%.
    slices: Vec<(f32, f32)>,
}

impl CellBounds {
    fn new(grid: &ClusterGrid, view: &PlanView) -> Self {
        let (w, h) = (view.size.0 as f32, view.size.1 as f32);
        let p = view.proj;
        // Clip x = P00 x + P20 z with w = -z = d: x = d (ndc + P20) / P00 (likewise y).
        let tile = grid.tile;
        let columns = (0..grid.tiles_x)
            .map(|tx| {
                let ndc = |px: f32| px / w * 2.0 - 1.0;
                let a = |n: f32| (n + p.z_axis.x) / p.x_axis.x;
                (a(ndc((tx * tile) as f32 - 1.0)), a(ndc(((tx + 1) * tile) as f32 + 1.0)))
            })
            .collect();
        let rows = (0..grid.tiles_y)
            .map(|ty| {
                let ndc = |py: f32| 1.0 - py / h * 2.0;
                let a = |n: f32| (n + p.z_axis.y) / p.y_axis.y;
                (a(ndc(((ty + 1) * tile) as f32 + 1.0)), a(ndc((ty * tile) as f32 - 1.0)))
            })
            .collect();
        let slices = (0..grid.slices)
            .map(|k| {
                let (s0, s1) = grid.slice_depths(k);
                (s0 * 0.999, s1 * 1.001)
            })
            .collect();
        Self { grid: *grid, size: view.size, columns, rows, slices }
    }
}

/// Squared distance from `c` to the interval covered by `d x a` for `d` in `d0..d1` and `a` in
/// `a0..a1` (a frustum piece's extent along one axis).
fn gap2(c: f32, (a0, a1): (f32, f32), (d0, d1): (f32, f32)) -> f32 {
    let lo = (d0 * a0).min(d1 * a0);
    let hi = (d0 * a1).max(d1 * a1);
    let g = (lo - c).max(c - hi).max(0.0);
    g * g
}

/// Builds the clustered lists (conservative: a light enters every cluster its bounding sphere
/// meets). Per light: its screen rectangle ([`LightPlan::screen_rect`], which bounds every
/// visible point it reaches) widened by a pixel gives the tiles, its depth range widened by a
/// slice on each side the slices; then each candidate cluster's view-space box (the tile's
/// frustum piece between the slice's depths, widened by a pixel and by 0.1% in depth) is tested
/// against the light's sphere, axis by axis ([`CellBounds`]: the squared distance to the box is
/// the sum of the three axes' squared gaps, so a slice or row already out of reach ends early).
/// A spot is bounded by its sphere. The lists are filled by a counting sort over (cell, light)
/// pairs found in light order, so every list is in light order.
pub fn cluster_lists(lights: &[LightRecord], plans: &[LightPlan], view: &PlanView) -> ClusterLists {
    cluster_lists_on(lights, plans, view, lights.len() >= PARALLEL_MIN_LIGHTS)
}

/// [`cluster_lists`], on two threads if `parallel` (the same lists either way).
fn cluster_lists_on(lights: &[LightRecord], plans: &[LightPlan], view: &PlanView, parallel: bool) -> ClusterLists {
    let grid = fitted_grid(lights, plans, view);
    let bounds = CellBounds::new(&grid, view);
    // Two passes over the lights, the same tests in the same order: the first counts each
    // cell's lights, the second writes them at their cell's cursor (so in light order). Two
    // threads share each pass: the count by halves of the lights, the fill by two runs of
    // slices holding about half the entries each (cells are numbered slice by slice, so a
    // run of slices is a run of cells and of entries).
    let cells = grid.cells();
    let count = |range: std::ops::Range<usize>| {
        let mut counts = vec![0u32; cells];
        let mut gx = Vec::new();
        for (l, p) in lights[range.clone()].iter().zip(&plans[range]) {
            light_cells(l, p, &bounds, 0..grid.slices, &mut gx, |cell| counts[cell] += 1);
        }
        counts
    };
    let half = lights.len() / 2;
    let (mut counts, rest) = both(parallel, || count(0..half), || count(half..lights.len()));
    for (c, r) in counts.iter_mut().zip(&rest) {
        *c += r;
    }
    let per_slice = (grid.tiles_x * grid.tiles_y) as usize;
    let total: u64 = counts.iter().map(|&n| n as u64).sum();
    let mut split = grid.slices;
    let mut so_far = 0u64;
    for k in 0..grid.slices {
        if 2 * so_far >= total {
            split = k;
            break;
        }
        so_far += counts[k as usize * per_slice..(k as usize + 1) * per_slice].iter().map(|&n| n as u64).sum::<u64>();
    }
    let split_cell = if split < grid.slices { grid.cell(0, 0, split) } else { cells };
    let halves = [0..split, split..grid.slices];
    let header = 2 * cells;
    let entries: usize = counts.iter().map(|&n| n as usize).sum();
    let mut data = vec![0u32; header + entries];
    let mut first = header as u32;
    let mut longest = 0;
    for (cell, n) in counts.iter_mut().enumerate() {
        data[2 * cell] = first;
        data[2 * cell + 1] = *n;
        longest = longest.max(*n);
        // From here on the count is the cell's cursor.
        *n = first;
        first += data[2 * cell + 1];
    }
    {
        let near_end = if split_cell < cells { counts[split_cell] as usize } else { data.len() };
        let (near_data, far_data) = data.split_at_mut(near_end);
        let far_data = (far_data, near_end);
        let near_data = (&mut near_data[header..], header);
        let (near, far) = counts.split_at_mut(split_cell);
        let fill =
            |slices: std::ops::Range<u32>, cursors: &mut [u32], offset: usize, (out, base): (&mut [u32], usize)| {
                let mut gx = Vec::new();
                for (i, (l, p)) in lights.iter().zip(plans).enumerate() {
                    light_cells(l, p, &bounds, slices.clone(), &mut gx, |cell| {
                        let at = &mut cursors[cell - offset];
                        out[*at as usize - base] = i as u32;
                        *at += 1;
                    });
                }
            };
        both(
            parallel,
            || fill(halves[0].clone(), near, 0, near_data),
            || fill(halves[1].clone(), far, split_cell, far_data),
        );
    }
    let mut lists = ClusterLists { data, grid: Some(grid), entries: entries as u64, longest, capped: 0 };
    cap_cells(&mut lists, lights, &bounds, view.grid.cap, view.grid.order);
    lists
}

/// Runs `a` and `b`, on two threads if `parallel` and the machine has more than one core. The
/// helper thread's CPU time is added to the caller's (`cputime`), so the frame's CPU figures
/// count both threads.
pub fn both<A: Send, B: Send>(parallel: bool, a: impl FnOnce() -> A + Send, b: impl FnOnce() -> B + Send) -> (A, B) {
    if !parallel || cores() < 2 {
        return (a(), b());
    }
    let (a, (b, spent)) = std::thread::scope(|s| {
        let b = s.spawn(|| crate::renderer::cputime::measured(b));
        let a = a();
        // A panic in `b` is a bug in this module: carry it over.
        (a, b.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
    });
    crate::renderer::cputime::add_helper(spent);
    (a, b)
}

/// The machine's cores, asked once (`available_parallelism` reads the cgroup files on every
/// call: about 2% of the CPU planning at 16,384 lights when it was asked twice a frame).
fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// The cells light `l` may reach: tiles `x.0 ..= x.1` across, `y.0 ..= y.1` down, slices
/// `k.0 .. k.1` (its screen rectangle widened by a pixel, its depth range widened by a slice
/// on each side); `None` when it reaches no cell. What [`light_cells`] tests, and what the GPU's
/// assignment (`cs_cluster_count` in `tiled.wgsl`) is given per light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    pub x: (u32, u32),
    pub y: (u32, u32),
    pub k: (u32, u32),
}

impl Span {
    fn of(l: &LightRecord, p: &LightPlan, grid: &ClusterGrid, size: (u32, u32)) -> Option<Span> {
        let (lo, hi) = p.screen_rect?;
        // The sphere's depths from the plan (`plan::light_depths` of this record), not the
        // record: one walk over the records fewer.
        debug_assert_eq!(p.depths, super::plan::light_depths(l));
        // The depths the grid's slices hold: from its near depth, or from the eye when slice 0
        // runs from it (`ClusterGrid::first_slice`).
        let nearest = if grid.first > 0.0 { 0.0 } else { grid.near };
        let (d0, d1) = (p.depths.0.max(nearest), p.depths.1.min(grid.far));
        if d0.is_nan() || d1.is_nan() || d0 > d1 {
            return None;
        }
        // The rectangle in pixels (y down), widened by a pixel: floor(a) - 1 and floor(a) + 1
        // tiled. No floor is needed: for an integer n, floor(a) >= n exactly when a >= n, and
        // `as u32` truncates (and saturates: negative and NaN give 0), which is the floor for the
        // non-negative values the tiles clamp to. The same tiles as the floors gave, with fewer
        // branches (this function was the largest part of the spans' time).
        let (w, h) = (size.0 as f32, size.1 as f32);
        let (ax0, ax1) = ((lo.x + 1.0) * 0.5 * w, (hi.x + 1.0) * 0.5 * w);
        let (ay0, ay1) = ((1.0 - hi.y) * 0.5 * h, (1.0 - lo.y) * 0.5 * h);
        if ax1 < -1.0 || ay1 < -1.0 || ax0 >= w + 1.0 || ay0 >= h + 1.0 {
            return None;
        }
        // The default grid's tile is `CLUSTER_TILE` (`ClusterGrid::new`): a shift, not the
        // integer division by a run-time field; other grids (`GridChoice`) divide.
        // (a - 1 is exact for a >= 1; the far side adds its pixel in integers, as a + 1 may round.)
        let t = grid.tile;
        let tile =
            |v: u32, max: u32| if t == CLUSTER_TILE { v.min(max - 1) / CLUSTER_TILE } else { v.min(max - 1) / t };
        let (x0, y0) = ((ax0 - 1.0) as u32, (ay0 - 1.0) as u32);
        let (x1, y1) = ((ax1 as u32).saturating_add(1), (ay1 as u32).saturating_add(1));
        Some(Span {
            x: (tile(x0, size.0), tile(x1, size.0)),
            y: (tile(y0, size.1), tile(y1, size.1)),
            k: (grid.slice(d0).saturating_sub(1), (grid.slice(d1) + 2).min(grid.slices)),
        })
    }

    /// Cells in the span: a bound on the cells the light enters.
    pub fn cells(&self) -> u64 {
        (self.x.1 - self.x.0 + 1) as u64 * (self.y.1 - self.y.0 + 1) as u64 * self.k.1.saturating_sub(self.k.0) as u64
    }

    /// The most loop iterations the GPU's assignment (`cluster_assign` in `tiled.wgsl`)
    /// can run for this span: per slice, one of the slice loop, two column scans, and the rows
    /// with their columns.
    pub fn gpu_loop_iterations(&self) -> u64 {
        let (xs, ys) = ((self.x.1 - self.x.0 + 1) as u64, (self.y.1 - self.y.0 + 1) as u64);
        self.k.1.saturating_sub(self.k.0) as u64 * (1 + 2 * xs + ys + ys * xs)
    }

    /// As the GPU reads it: (x0 | x1 << 16, y0 | y1 << 16, k0 | k1 << 16, 0); no cell is
    /// (0, 0, 0, 0) (an empty slice range).
    pub fn packed(span: Option<Span>) -> [u32; 4] {
        span.map_or([0; 4], |s| [s.x.0 | s.x.1 << 16, s.y.0 | s.y.1 << 16, s.k.0 | s.k.1 << 16, 0])
    }
}

/// Calls `f` with every cell of `grid` in `slices` whose box meets light `l`'s sphere (see
/// [`cluster_lists`]); `gx` is scratch space.
fn light_cells(
    l: &LightRecord,
    p: &LightPlan,
    bounds: &CellBounds,
    slices: std::ops::Range<u32>,
    gx: &mut Vec<f32>,
    mut f: impl FnMut(usize),
) {
    let grid = &bounds.grid;
    let Some(span) = Span::of(l, p, grid, bounds.size) else { return };
    let c = Vec3::from(l.position);
    let r = l.radius;
    let ((tx0, tx1), (ty0, ty1)) = (span.x, span.y);
    let k0 = span.k.0.max(slices.start);
    let k1 = span.k.1.min(slices.end);
    let r2 = r * r * 1.0001;
    for k in k0..k1 {
        let depths = bounds.slices[k as usize];
        let dz = (depths.0 + c.z).max(-c.z - depths.1).max(0.0);
        let dz2 = dz * dz;
        if dz2 > r2 {
            continue;
        }
        // The columns within reach at this slice (the gap grows away from the light's column,
        // so they are a run): only those are tested row by row.
        gx.clear();
        gx.extend((tx0..=tx1).map(|tx| gap2(c.x, bounds.columns[tx as usize], depths)));
        let Some(a) = gx.iter().position(|g| dz2 + g <= r2) else { continue };
        let b = gx.iter().rposition(|g| dz2 + g <= r2).unwrap_or(a);
        for ty in ty0..=ty1 {
            let dyz2 = dz2 + gap2(c.y, bounds.rows[ty as usize], depths);
            if dyz2 > r2 {
                continue;
            }
            let row = grid.cell(tx0, ty, k);
            for (j, g) in gx.iter().enumerate().take(b + 1).skip(a) {
                if dyz2 + g <= r2 {
                    f(row + j);
                }
            }
        }
    }
}

/// The clustered grid the frame's lights span: its slices cover the depths they reach, not
/// near to far (no light reaches a point nearer or farther, so the end slices' lists, which
/// such points fall into, hold every light that reaches them).
pub fn fitted_grid(lights: &[LightRecord], plans: &[LightPlan], view: &PlanView) -> ClusterGrid {
    debug_assert_eq!(lights.len(), plans.len());
    let (near, far) = fitted_depths(plans, view);
    let g = &view.grid;
    let tile = g.tile(view.size);
    let slices = if g.slices > 0 { g.slices } else { SLICES };
    if g.first_slice_depth > 0.0 {
        ClusterGrid::first_slice(view.size, g.first_slice_depth, far.max(near), tile, slices)
    } else {
        ClusterGrid::with_cells(view.size, near, far.max(near), tile, slices)
    }
}

/// The view depths the frame's lights reach on screen, within the view's near and far planes
/// (the view's planes when none does).
pub fn fitted_depths(plans: &[LightPlan], view: &PlanView) -> (f32, f32) {
    let (mut zmin, mut zmax) = (f32::INFINITY, 0.0f32);
    for p in plans {
        // `depths` is empty (inf, -inf) for a radius that is not positive.
        if p.screen_rect.is_some() && p.depths.0 < p.depths.1 {
            zmin = zmin.min(p.depths.0);
            zmax = zmax.max(p.depths.1);
        }
    }
    let (near, far) = if zmin < zmax { (zmin.max(view.near), zmax.min(view.far)) } else { (view.near, view.far) };
    (near, far.max(near))
}

/// Whether the frame's shading lists are built on the GPU: `tiled`'s always, `clustered`'s
/// when the GPU builds them, `zbin`'s masks when some light is visible.
pub fn lists_on_gpu(plan: &FramePlan) -> bool {
    match plan.tiled {
        Some(Method::Tiled) => true,
        Some(_) if matches!(plan.clusters, Some(ClusterBuild::Gpu(_))) => true,
        Some(Method::Zbin) => plan.zbins.as_ref().is_some_and(|z| z.visible > 0),
        _ => false,
    }
}

/// The clustered grid and the per-cluster cap a frame asks for (`Settings::cluster_tile`,
/// `cluster_budget`, `cluster_slices`, `first_slice_depth`, `lights_per_cluster`,
/// `cap_order`); the default is [`CLUSTER_TILE`]-pixel tiles, [`SLICES`] slices, no cap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridChoice {
    pub tile: u32,
    pub budget: u32,
    pub slices: u32,
    pub first_slice_depth: f32,
    pub cap: u32,
    pub order: CapOrder,
}

impl GridChoice {
    pub fn of(s: &crate::renderer::options::culling::CullingOptions, order: CapOrder) -> Self {
        Self {
            tile: s.cluster_tile,
            budget: s.cluster_budget,
            slices: s.cluster_slices,
            first_slice_depth: s.first_slice_depth,
            cap: s.lights_per_cluster,
            order,
        }
    }

    /// The tile side at `size`.
    pub fn tile(&self, size: (u32, u32)) -> u32 {
        if self.tile > 0 {
            self.tile
        } else if self.budget > 0 {
            let slices = if self.slices > 0 { self.slices } else { SLICES };
            crate::renderer::caps::budget_tile(self.budget, slices, size)
        } else {
            CLUSTER_TILE
        }
    }

    /// The default grid without a cap: what the GPU list build lays out.
    pub fn is_default(&self) -> bool {
        *self == Self { order: self.order, ..Self::default() }
    }
}

/// Keeps at most `cap` lights in each cell of `lists` ([`crate::renderer::caps`]), chosen by
/// `order` against the cell's centre (the middle of its tile's frustum piece at the middle of
/// its slice), in light order; counts the entries left out in `ClusterLists::capped`.
fn cap_cells(
    lists: &mut ClusterLists,
    lights: &[LightRecord],
    bounds: &CellBounds,
    cap: u32,
    order: crate::renderer::caps::CapOrder,
) {
    let Some(grid) = lists.grid else { return };
    if cap == 0 || lists.longest <= cap {
        return;
    }
    let cells = grid.cells();
    let per_slice = (grid.tiles_x * grid.tiles_y) as usize;
    let header = 2 * cells;
    let mut data = vec![0u32; header];
    data.reserve(lists.data.len() - header);
    let (mut longest, mut capped) = (0u32, 0u64);
    let luminance = crate::scene::luminance_weights();
    let at = |i: u32| {
        let l = &lights[i as usize];
        (Vec3::from(l.position), l.radius, Vec3::from(l.color).dot(luminance) as f64)
    };
    for c in 0..cells {
        let list = lists.list(c);
        let first = data.len() as u32;
        if list.len() > cap as usize {
            let (k, rest) = (c / per_slice, c % per_slice);
            let (ty, tx) = (rest / grid.tiles_x as usize, rest % grid.tiles_x as usize);
            let (d0, d1) = bounds.slices[k];
            let d = if d1.is_finite() { 0.5 * (d0 + d1) } else { d0.max(grid.far) };
            let (cx, cy) = (bounds.columns[tx], bounds.rows[ty]);
            let centre = Vec3::new(d * 0.5 * (cx.0 + cx.1), d * 0.5 * (cy.0 + cy.1), -d);
            let kept = crate::renderer::caps::keep_nearest_or_brightest(list, cap as usize, order, centre, at);
            capped += (list.len() - kept.len()) as u64;
            data.extend_from_slice(&kept);
        } else {
            data.extend_from_slice(list);
        }
        let n = data.len() as u32 - first;
        data[2 * c] = first;
        data[2 * c + 1] = n;
        longest = longest.max(n);
    }
    lists.entries = (data.len() - header) as u64;
    lists.data = data;
    lists.longest = longest;
    lists.capped = capped;
}

/// What the GPU needs to build the clustered lists itself ([`ClusterBuild::Gpu`]): the grid,
/// each light's [`Span`] packed, and the entries the spans can hold at most (the list
/// buffer's room: the GPU's lists never overflow it).
#[derive(Clone, Debug, Default)]
pub struct ClusterJob {
    pub grid: Option<ClusterGrid>,
    pub spans: Vec<[u32; 4]>,
    pub bound: u64,
    /// The most loop iterations one light's assignment can take on the GPU
    /// ([`Span::gpu_loop_iterations`]).
    pub longest: u64,
}

/// The loop iterations a GPU list build may ask of one invocation under a loop limit: lavapipe
/// ends a shader invocation's loops once they have run 65,535 iterations between them
/// (gallivm's shared loop limiter, `kit::adapter::GALLIVM_LOOP_LIMIT`, silently), so a light whose
/// span takes more would be left out of the cells past it (`inside` at 2560x1440 shaded
/// nothing). Frames with such a light build their lists on the CPU (`plan::FramePlan::new`);
/// adapters without a loop limit always build them on the GPU when asked.
pub const GPU_LOOP_BUDGET: u64 = 65_000;

/// [`GPU_LOOP_BUDGET`] under loop limit `limit`: the same room (535 iterations) left for the
/// invocation's other loops.
pub fn gpu_loop_budget(limit: u64) -> u64 {
    limit.saturating_sub(crate::renderer::kit::adapter::GALLIVM_LOOP_LIMIT - GPU_LOOP_BUDGET)
}

/// The spans of every light (on one thread, as `plan::FramePlan::reusing` plans the lights).
pub fn cluster_job(lights: &[LightRecord], plans: &[LightPlan], view: &PlanView) -> ClusterJob {
    let grid = fitted_grid(lights, plans, view);
    let (mut bound, mut longest) = (0u64, 0u64);
    let spans: Vec<[u32; 4]> = lights
        .iter()
        .zip(plans)
        .map(|(l, p)| {
            let s = Span::of(l, p, &grid, view.size);
            if let Some(s) = s {
                bound += s.cells();
                longest = longest.max(s.gpu_loop_iterations());
            }
            Span::packed(s)
        })
        .collect();
    ClusterJob { grid: Some(grid), spans, bound, longest }
}

/// Who builds the clustered lists: the CPU ([`cluster_lists`]) or the GPU from each light's
/// [`Span`] ([`cluster_job`]); the same lists (the tests hold them together).
#[derive(Clone, Debug)]
pub enum ClusterBuild {
    Cpu(ClusterLists),
    Gpu(ClusterJob),
}

impl ClusterBuild {
    pub fn grid(&self) -> Option<ClusterGrid> {
        match self {
            ClusterBuild::Cpu(c) => c.grid,
            ClusterBuild::Gpu(j) => j.grid,
        }
    }
}

/// One light's terms in the frame rule's costs, as [`frame_costs`] counts them: its draws and
/// the fragments of its footprint when drawn by `method`, and its footprint as a list mode
/// lists it (none when skipped).
pub fn light_terms(method: Method, screen_share: f32, pixels: f64) -> (f64, f64, f64) {
    let row = crate::renderer::culling::methods::row(method);
    let footprint = match row.covers {
        Covers::Screen => pixels,
        Covers::Nothing => 0.0,
        Covers::Volume => screen_share as f64 * pixels,
    };
    let listed = if method == Method::Skipped { 0.0 } else { (screen_share as f64 * pixels).min(pixels) };
    (row.draws_per_light as f64, footprint, listed)
}

/// The estimated GPU ms of `auto`'s per-light plan and of each list mode the constants weigh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCosts {
    pub per_light: f64,
    pub clustered: f64,
    pub tiled: Option<f64>,
    pub zbin: Option<f64>,
}

impl FrameCosts {
    /// The cheapest list mode weighed and its cost (`clustered` on a tie).
    pub fn cheapest_list(&self) -> (Method, f64) {
        let mut best = (Method::Clustered, self.clustered);
        for (m, c) in [(Method::Tiled, self.tiled), (Method::Zbin, self.zbin)] {
            if let Some(c) = c.filter(|c| *c < best.1) {
                best = (m, c);
            }
        }
        best
    }
}

/// Estimated GPU ms of `auto`'s per-light plan and of the list modes for the frame: draws x
/// `draw_ms` + each drawn light's footprint x `fragment_ns`, against each list mode's
/// full-screen passes + the footprints x its pairs per footprint x its `pair_ns`.
pub fn frame_costs(plans: &[LightPlan], size: (u32, u32), costs: &CostConstants) -> FrameCosts {
    let pixels = (size.0 as f64) * (size.1 as f64);
    let (mut draws, mut drawn, mut listed) = (0.0, 0.0, 0.0);
    for p in plans {
        let (d, f, l) = light_terms(p.method, p.screen_share, pixels);
        draws += d;
        drawn += f;
        listed += l;
    }
    let list = |c: &ListCost| c.fixed_ms_per_mpx * pixels / 1e6 + listed * c.pairs_per_footprint * c.pair_ns * 1e-6;
    FrameCosts {
        per_light: draws * costs.draw_ms + drawn * costs.fragment_ns * 1e-6,
        clustered: list(&costs.clustered),
        tiled: costs.tiled.as_ref().map(list),
        zbin: costs.zbin.as_ref().map(list),
    }
}

/// The frame-level rule, after the per-light plans: `tiled`, `clustered` and `zbin` shade every
/// light from their lists; `auto` with at least the constants' `min_lights` lights (the fewest
/// they were measured at) keeps its per-light plan unless [`frame_costs`] estimates a list mode
/// cheaper (`clustered`, or `tiled` and `zbin` where the view's constants weigh them), and then
/// shades the whole frame with the cheapest. Returns the method of the tiled pass, if the frame
/// uses it.
pub fn frame_rule(plans: &mut [LightPlan], view: &PlanView) -> Option<Method> {
    let method = match view.mode {
        CullingMode::Tiled => Method::Tiled,
        CullingMode::Clustered => Method::Clustered,
        CullingMode::Zbin => Method::Zbin,
        // Past what every mode takes, `zbin`: O(lights) on the CPU and in memory.
        CullingMode::Auto if plans.len() > crate::renderer::settings::MAX_LIGHTS_EVERY_MODE => Method::Zbin,
        CullingMode::Auto if plans.len() >= view.costs.min_lights => {
            let mut costs = frame_costs(plans, view.size, &view.costs);
            // Past GPU_LIST_MAX_LIGHTS lights `tiled` tests every light against every tile
            // twice (its batches' count and write sweeps): a cost per tile and light that the
            // model's fixed and per-pair terms do not hold, so it is not weighed there.
            if plans.len() > GPU_LIST_MAX_LIGHTS as usize {
                costs.tiled = None;
            }
            let (list, cost) = costs.cheapest_list();
            if cost >= costs.per_light {
                return None;
            }
            list
        }
        _ => return None,
    };
    for p in plans.iter_mut() {
        p.method = method;
    }
    Some(method)
}

/// Pixel rectangle to NDC (for tests): the centre of pixel (x, y).
pub fn pixel_ndc(x: u32, y: u32, size: (u32, u32)) -> Vec2 {
    Vec2::new(2.0 * (x as f32 + 0.5) / size.0 as f32 - 1.0, 1.0 - 2.0 * (y as f32 + 0.5) / size.1 as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A white point light's record at view-space `position`.
    fn point_light(position: [f32; 3], radius: f32) -> LightRecord {
        LightRecord {
            position,
            radius,
            color: [1.0; 3],
            kind: crate::renderer::records::LIGHT_KIND_POINT,
            direction: [0.0, 0.0, -1.0],
            cos_outer: -1.0,
            cos_inner: -1.0,
            tan_outer: 0.0,
            falloff: radius,
            clamp: f32::MAX,
            shadow: crate::renderer::records::UNSHADOWED,
            ..bytemuck::Zeroable::zeroed()
        }
    }
    use crate::scene::Camera;

    #[test]
    fn lists_past_one_binding_give_way_longest_first_to_walking_every_light() {
        // 4 cells (2 x 2 tiles, 1 slice) holding 3, 0, 4 and 2 lights.
        let grid = ClusterGrid {
            tile: 32,
            tiles_x: 2,
            tiles_y: 2,
            slices: 1,
            scale: 1.0,
            bias: 0.0,
            near: 0.1,
            far: 10.0,
            first: 0.0,
        };
        let lists: [&[u32]; 4] = [&[0, 2, 5], &[], &[1, 2, 3, 4], &[6, 7]];
        let mut data = vec![0u32; 8];
        for (c, l) in lists.iter().enumerate() {
            data[2 * c] = data.len() as u32;
            data[2 * c + 1] = l.len() as u32;
            data.extend_from_slice(l);
        }
        let c = ClusterLists { data: data.clone(), grid: Some(grid), entries: 9, longest: 4, capped: 0 };
        assert_eq!(&*c.fitted(data.len()), &data[..], "lists that fit are uploaded as they are");
        // Room for the header and 5 entries: the shortest lists fit (cells 1, 3 and 0: 0, 2
        // and 3 entries); the longest (cell 2's 4) walks every light.
        let f = c.fitted(8 + 5);
        assert_eq!(f.len(), 8 + 5);
        assert_eq!(&f[..8], &[8, 3, 11, 0, 0, ALL_LIGHTS, 11, 2]);
        assert_eq!(&f[8..11], lists[0]);
        assert_eq!(&f[11..13], lists[3]);
        // Room for 1 entry: only the empty list stays.
        let f = c.fitted(8 + 1);
        assert_eq!(&f[..], &[0, ALL_LIGHTS, 8, 0, 0, ALL_LIGHTS, 0, ALL_LIGHTS]);
    }

    fn view(size: (u32, u32)) -> PlanView {
        let cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        PlanView::for_test(&cam, size, CullingMode::Clustered)
    }

    /// A tiny light drawn as a sphere volume, 10 units ahead.
    fn small_volume_light() -> LightPlan {
        LightPlan {
            method: Method::Volume,
            volume: crate::renderer::VolumeKind::Sphere,
            crosses_near: false,
            crosses_far: false,
            screen_share: 0.001,
            screen_rect: Some((Vec2::ZERO, Vec2::splat(0.05))),
            depths: (9.0, 11.0),
        }
    }

    #[test]
    fn auto_keeps_its_per_light_plan_for_few_lights_and_shades_many_clustered() {
        let small = small_volume_light();
        let mut v = view((1280, 720));
        v.mode = CullingMode::Auto;
        let mut few = vec![small; 8];
        assert_eq!(frame_rule(&mut few, &v), None);
        assert!(few.iter().all(|p| p.method == Method::Volume));
        // 300 tiny lights: the full-screen pass costs more than their draws.
        let mut some = vec![small; 300];
        let c = frame_costs(&some, v.size, &v.costs);
        assert!(c.clustered > c.per_light, "{c:?}");
        assert_eq!(frame_rule(&mut some, &v), None);
        let mut many = vec![small; 4096];
        let c = frame_costs(&many, v.size, &v.costs);
        assert!(c.clustered < c.per_light, "{c:?}");
        assert_eq!(frame_rule(&mut many, &v), Some(Method::Clustered));
        assert!(many.iter().all(|p| p.method == Method::Clustered));
        // Fixed modes are left alone; tiled and clustered take every light.
        v.mode = CullingMode::Volume;
        assert_eq!(frame_rule(&mut few, &v), None);
        v.mode = CullingMode::Clustered;
        assert_eq!(frame_rule(&mut few, &v), Some(Method::Clustered));
    }

    #[test]
    fn a_calibration_that_makes_tiled_or_zbin_cheapest_makes_auto_choose_it() {
        let small = small_volume_light();
        let mut v = view((1280, 720));
        v.mode = CullingMode::Auto;
        assert_eq!(frame_rule(&mut vec![small; 4096], &v), Some(Method::Clustered));
        let cheap = ListCost { fixed_ms_per_mpx: 1.0, pair_ns: 1.0, pairs_per_footprint: 0.1 };
        v.costs.tiled = Some(cheap);
        assert_eq!(frame_rule(&mut vec![small; 4096], &v), Some(Method::Tiled));
        v.costs.zbin = Some(ListCost { fixed_ms_per_mpx: 0.5, ..cheap });
        assert_eq!(frame_rule(&mut vec![small; 4096], &v), Some(Method::Zbin));
        // Below the rule's count, the per-light plan whatever the constants.
        assert_eq!(frame_rule(&mut vec![small; 8], &v), None);
        // Draws costing nothing keep the per-light plan.
        v.costs.draw_ms = 0.0;
        v.costs.fragment_ns = 0.0;
        assert_eq!(frame_rule(&mut vec![small; 4096], &v), None);
    }

    /// The spans' tiles without floors are the tiles of the floored pixel rectangle (widened by
    /// a pixel), as they were computed before: random rectangles, on and off screen, at pixel
    /// boundaries, huge and NaN.
    #[test]
    fn the_spans_tiles_are_the_floored_rectangles_tiles() {
        let size = (1280u32, 720u32);
        let grid = ClusterGrid::new(size, 0.1, 100.0);
        let old = |lo: Vec2, hi: Vec2| -> Option<((u32, u32), (u32, u32))> {
            let (w, h) = (size.0 as f32, size.1 as f32);
            let px = |x: f32| ((x + 1.0) * 0.5 * w).floor();
            let py = |y: f32| ((1.0 - y) * 0.5 * h).floor();
            let (x0, x1) = (px(lo.x) - 1.0, px(hi.x) + 1.0);
            let (y0, y1) = (py(hi.y) - 1.0, py(lo.y) + 1.0);
            if x1 < 0.0 || y1 < 0.0 || x0 >= w || y0 >= h {
                return None;
            }
            let tile = |v: f32, max: u32| (v.max(0.0) as u32).min(max - 1) / CLUSTER_TILE;
            Some(((tile(x0, size.0), tile(x1, size.0)), (tile(y0, size.1), tile(y1, size.1))))
        };
        let mut next = crate::renderer::culling::plan::xorshift64(0x9e37_79b9_7f4a_7c15);
        let mut rnd = || (next() >> 40) as f32 / (1u64 << 24) as f32;
        let mut corners: Vec<f32> = (0..4000).map(|_| 5.0 * rnd() - 2.5).collect();
        // Exactly on pixel edges and the screen's edges, beyond it, huge, NaN.
        corners.extend((0..=64).map(|k| -1.0 + k as f32 / 32.0));
        corners.extend([1.0 + 2.0 / 1280.0, -1.0 - 2.0 / 1280.0, 1e30, -1e30, f32::INFINITY, f32::NAN]);
        let plan = |lo: Vec2, hi: Vec2| LightPlan {
            method: Method::Clustered,
            volume: crate::renderer::VolumeKind::Sphere,
            crosses_near: false,
            crosses_far: false,
            screen_share: 0.1,
            screen_rect: Some((lo, hi)),
            depths: (1.0, 2.0),
        };
        let light = LightRecord { position: [0.0, 0.0, -1.5], radius: 0.5, ..bytemuck::Zeroable::zeroed() };
        let mut on = 0;
        for (i, pair) in corners.windows(4).enumerate() {
            let (lo, hi) = (Vec2::new(pair[0], pair[1 + i % 2]), Vec2::new(pair[2], pair[3 - i % 2]));
            for (lo, hi) in [(lo, hi), (lo.min(hi), lo.max(hi))] {
                let new = Span::of(&light, &plan(lo, hi), &grid, size).map(|s| (s.x, s.y));
                assert_eq!(new, old(lo, hi), "rectangle {lo} {hi}");
                on += new.is_some() as u32;
            }
        }
        assert!(on > 1000, "{on} on screen");
    }

    #[test]
    fn the_slices_span_the_depths_the_lights_reach() {
        let v = view((320, 180));
        let light = |depth: f32, radius: f32| point_light([0.0, 0.0, -depth], radius);
        let plan = |l: &LightRecord, on_screen: bool| LightPlan {
            method: Method::Clustered,
            volume: crate::renderer::VolumeKind::Sphere,
            crosses_near: false,
            crosses_far: false,
            screen_share: 0.1,
            screen_rect: on_screen.then_some((-Vec2::splat(0.1), Vec2::splat(0.1))),
            depths: crate::renderer::plan::light_depths(l),
        };
        // An off-screen light (no rectangle) does not widen the range.
        let lights = [light(20.0, 2.0), light(40.0, 2.0), light(500.0, 2.0)];
        let plans = [plan(&lights[0], true), plan(&lights[1], true), plan(&lights[2], false)];
        let lists = cluster_lists(&lights, &plans, &v);
        let g = lists.grid.unwrap();
        assert_eq!((g.near, g.far), (18.0, 42.0));
        let (first, _) = g.slice_depths(0);
        let (_, last) = g.slice_depths(g.slices - 1);
        assert!((first - 18.0).abs() < 1e-3 && (last - 42.0).abs() < 1e-3, "{first}..{last}");
        // A light across the near plane starts the range at the near plane.
        let lists = cluster_lists(&[light(1.0, 3.0)], &[plan(&light(1.0, 3.0), true)], &v);
        assert_eq!(lists.grid.unwrap().near, v.near);
    }

    #[test]
    fn the_fast_floor_is_floor() {
        let mut seed = 3u32;
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.5,
            -1.5,
            -0.999_999_94,
            0.999_999_94,
            1_279.999_9,
            -1280.0001,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            1e9,
            -1e9,
            1e30,
            f32::MAX,
            f32::MIN,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for _ in 0..200_000 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            values.push(f32::from_bits(seed));
        }
        for v in values {
            let (fast, exact) = (floor(v), v.floor());
            assert!(fast == exact || fast.is_nan() && exact.is_nan(), "floor({v:e}): {fast:e}, want {exact:e}");
        }
    }

    #[test]
    fn the_slices_cover_near_to_far_in_order() {
        let g = ClusterGrid::new((320, 180), 0.1, 1000.0);
        assert_eq!(g.slice(0.1001), 0);
        assert_eq!(g.slice(999.0), SLICES - 1);
        for k in 0..SLICES {
            let (a, b) = g.slice_depths(k);
            assert!(a < b);
            assert_eq!(g.slice((a * b).sqrt()), k, "slice {k}: {a}..{b}");
        }
    }

    #[test]
    fn a_cluster_holds_every_light_reaching_a_point_in_it() {
        // Random points in view and lights around them: every light whose sphere holds a
        // point is in the list of the point's cluster.
        let size = (320, 180);
        let v = view(size);
        let inv = v.proj.inverse();
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32
        };
        let mut lights = Vec::new();
        // Enough lights for the two-thread path.
        for _ in 0..PARALLEL_MIN_LIGHTS + 300 {
            let d = 0.5 + rnd() * 60.0;
            let ndc = Vec2::new(rnd() * 2.4 - 1.2, rnd() * 2.4 - 1.2);
            let p = inv.project_point3(Vec3::new(ndc.x, ndc.y, 0.5));
            let pos = p.normalize() * d;
            let radius = 0.3 + rnd() * 6.0;
            let l = point_light(pos.into(), radius);
            lights.push(l);
        }
        // The whole screen as every light's rectangle: the clusters' own tests do the culling.
        let plan = LightPlan {
            method: Method::Clustered,
            volume: crate::renderer::VolumeKind::Sphere,
            crosses_near: false,
            crosses_far: false,
            screen_share: 1.0,
            screen_rect: Some((-Vec2::ONE, Vec2::ONE)),
            depths: (0.0, 0.0),
        };
        let plans: Vec<LightPlan> =
            lights.iter().map(|l| LightPlan { depths: crate::renderer::plan::light_depths(l), ..plan }).collect();
        let lists = cluster_lists(&lights, &plans, &v);
        // One thread or two, the same lists.
        let serial = cluster_lists_on(&lights, &plans, &v, false);
        assert_eq!(lists.data, serial.data);
        assert!(lists.entries > 0 && lists.entries == serial.entries);
        let grid = lists.grid.unwrap();
        let mut checked = 0;
        for _ in 0..4000 {
            let (x, y) = ((rnd() * size.0 as f32) as u32, (rnd() * size.1 as f32) as u32);
            let ndc = pixel_ndc(x, y, size);
            let dir = inv.project_point3(Vec3::new(ndc.x, ndc.y, 0.5)).normalize();
            let d = 0.2 + rnd() * 70.0;
            let point = dir * (d / -dir.z);
            let cell = grid.cell(x / CLUSTER_TILE, y / CLUSTER_TILE, grid.slice(d));
            for (i, l) in lights.iter().enumerate() {
                if Vec3::from(l.position).distance(point) < l.radius {
                    checked += 1;
                    assert!(
                        lists.list(cell).contains(&(i as u32)),
                        "light {i} reaches ({x}, {y}) at {d} but is not listed"
                    );
                }
            }
        }
        assert!(checked > 200, "too few points inside lights ({checked})");
    }
}

/// The tiled pass's lists (`tiled`, `clustered`, or the `tile-lights` view's): cells (tiles, or
/// tiles x slices), their entries summed and the longest (read back when counting).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct TileStats {
    pub method: Method,
    /// Tile size in pixels and depth slices (1 when tiled).
    pub tile_size: u32,
    pub slices: u32,
    pub cells: u64,
    pub entries: u64,
    pub longest: u32,
    /// Tiles the GPU list buffer had no room for (shaded with every light).
    pub overflowed: u64,
}
