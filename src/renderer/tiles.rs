//! The CPU's part of the `tiled` and `clustered` culling modes: the clustered mode's light
//! lists (Olsson, Billeter, Assarsson 2012, assigned on the CPU as Bevy does), and `auto`'s
//! frame-level choice between its per-light plan and `clustered`.
//!
//! The GPU's part (the tiled mode's compute pass, the shading pass both share, the debug view)
//! is `passes::tiled`.

use super::plan::{LightPlan, Method, PlanView};
use super::records::LightRecord;
use super::settings::CullingMode;
use glam::{Vec2, Vec3};

/// Size in pixels of the `tiled` mode's tiles (Andersson 2011: 16x16, one compute workgroup).
pub const TILE: u32 = 16;
/// Size in pixels of the `clustered` mode's screen tiles.
pub const CLUSTER_TILE: u32 = 32;
/// Exponential depth slices between the near and far planes (`clustered`).
pub const SLICES: u32 = 32;
/// A list count meaning "every light" (the GPU's list buffer ran out of room for this tile):
/// the tile is shaded with all lights, the right picture at a higher cost.
pub const ALL_LIGHTS: u32 = u32::MAX;

/// The list length the `tile-lights` view shows at the top of its colour map (longer lists
/// saturate): generated into WGSL as `LS_TILE_HEAT_MAX`, and the viewer's legend reads it.
pub const HEAT_MAX: f32 = 64.0;

/// The heatmap colour map of the complexity and `tile-lights` views, as `heat()` in
/// `shaders/compose.wgsl` computes it (linear RGB), for the viewer's legend and the tests.
pub fn heat(t: f32) -> [f32; 3] {
    let x = t.clamp(0.0, 1.0);
    let c = |v: f32| v.clamp(0.0, 1.0);
    [c(1.5 * x), c(1.5 * x - 0.5), c(0.5 - (x - 0.5).abs() + (3.0 * x - 2.0).max(0.0))]
}

/// The clustered grid of one frame: tiles across and down, slices, and the slice mapping
/// (a view depth d lies in slice `floor(ln d x scale + bias)`, clamped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterGrid {
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub slices: u32,
    pub scale: f32,
    pub bias: f32,
    pub near: f32,
    pub far: f32,
}

impl ClusterGrid {
    pub fn new(size: (u32, u32), near: f32, far: f32) -> Self {
        let far = far.max(near * 1.0001);
        let scale = SLICES as f32 / (far / near).ln();
        Self {
            tiles_x: size.0.div_ceil(CLUSTER_TILE),
            tiles_y: size.1.div_ceil(CLUSTER_TILE),
            slices: SLICES,
            scale,
            bias: -near.ln() * scale,
            near,
            far,
        }
    }

    pub fn cells(&self) -> usize {
        (self.tiles_x * self.tiles_y * self.slices) as usize
    }

    /// The slice of view depth `d` (what the shader computes, clamped to the grid).
    pub fn slice(&self, d: f32) -> u32 {
        let k = (d.max(1e-30).ln() * self.scale + self.bias).floor();
        (k.max(0.0) as u32).min(self.slices - 1)
    }

    /// The near and far view depth of slice `k`.
    pub fn slice_depths(&self, k: u32) -> (f32, f32) {
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
}

impl ClusterLists {
    /// Light indices of cell `cell`.
    pub fn list(&self, cell: usize) -> &[u32] {
        let (first, count) = (self.data[2 * cell] as usize, self.data[2 * cell + 1] as usize);
        &self.data[first..first + count]
    }
}

/// The view-space box of a cluster: tile (`tx`, `ty`) widened by a pixel, between view depths
/// `d0` and `d1`; `proj` is the projection (symmetric or not).
fn cluster_box(view: &PlanView, tile: u32, (tx, ty): (u32, u32), (d0, d1): (f32, f32)) -> (Vec3, Vec3) {
    let (w, h) = (view.size.0 as f32, view.size.1 as f32);
    let ndc_x = |px: f32| px / w * 2.0 - 1.0;
    let ndc_y = |py: f32| 1.0 - py / h * 2.0;
    let (x0, x1) = (ndc_x((tx * tile) as f32 - 1.0), ndc_x(((tx + 1) * tile) as f32 + 1.0));
    let (y0, y1) = (ndc_y(((ty + 1) * tile) as f32 + 1.0), ndc_y((ty * tile) as f32 - 1.0));
    let p = view.proj;
    // Clip x = P00 x + P20 z with w = -z = d: x = d (ndc + P20) / P00 (likewise y).
    let vx = |ndc: f32, d: f32| d * (ndc + p.z_axis.x) / p.x_axis.x;
    let vy = |ndc: f32, d: f32| d * (ndc + p.z_axis.y) / p.y_axis.y;
    let xs = [vx(x0, d0), vx(x0, d1), vx(x1, d0), vx(x1, d1)];
    let ys = [vy(y0, d0), vy(y0, d1), vy(y1, d0), vy(y1, d1)];
    let min =
        Vec3::new(xs.into_iter().fold(f32::INFINITY, f32::min), ys.into_iter().fold(f32::INFINITY, f32::min), -d1);
    let max = Vec3::new(
        xs.into_iter().fold(f32::NEG_INFINITY, f32::max),
        ys.into_iter().fold(f32::NEG_INFINITY, f32::max),
        -d0,
    );
    (min, max)
}

/// Builds the clustered lists (conservative: a light enters every cluster its bounding sphere
/// meets). Per light: its screen rectangle ([`LightPlan::screen_rect`], which bounds every
/// visible point it reaches) widened by a pixel gives the tiles, its depth range widened by a
/// slice on each side the slices; then each candidate cluster's view-space box (the tile's
/// frustum piece between the slice's depths, widened by a pixel and by 0.1% in depth) is tested
/// against the light's sphere. A spot is bounded by its sphere.
pub fn cluster_lists(lights: &[LightRecord], plans: &[LightPlan], view: &PlanView) -> ClusterLists {
    let grid = ClusterGrid::new(view.size, view.near, view.far);
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); grid.cells()];
    let (w, h) = (view.size.0 as f32, view.size.1 as f32);
    for (i, (l, p)) in lights.iter().zip(plans).enumerate() {
        let Some((lo, hi)) = p.screen_rect else { continue };
        let c = Vec3::from(l.position);
        let r = l.radius;
        if r.is_nan() || r <= 0.0 || !c.is_finite() {
            continue;
        }
        let (d0, d1) = ((-c.z - r).max(grid.near), (-c.z + r).min(grid.far));
        if d0 > d1 {
            continue;
        }
        let px = |x: f32| ((x + 1.0) * 0.5 * w).floor();
        let py = |y: f32| ((1.0 - y) * 0.5 * h).floor();
        let (x0, x1) = (px(lo.x) - 1.0, px(hi.x) + 1.0);
        let (y0, y1) = (py(hi.y) - 1.0, py(lo.y) + 1.0);
        if x1 < 0.0 || y1 < 0.0 || x0 >= w || y0 >= h {
            continue;
        }
        let tile = |v: f32, max: u32| (v.max(0.0) as u32).min(max - 1) / CLUSTER_TILE;
        let (tx0, tx1, ty0, ty1) =
            (tile(x0, view.size.0), tile(x1, view.size.0), tile(y0, view.size.1), tile(y1, view.size.1));
        let k0 = grid.slice(d0).saturating_sub(1);
        let k1 = (grid.slice(d1) + 1).min(grid.slices - 1);
        for k in k0..=k1 {
            let (s0, s1) = grid.slice_depths(k);
            let depths = (s0 * 0.999, s1 * 1.001);
            for ty in ty0..=ty1 {
                for tx in tx0..=tx1 {
                    let (bmin, bmax) = cluster_box(view, CLUSTER_TILE, (tx, ty), depths);
                    let nearest = c.clamp(bmin, bmax);
                    if nearest.distance_squared(c) <= r * r * 1.0001 {
                        cells[grid.cell(tx, ty, k)].push(i as u32);
                    }
                }
            }
        }
    }
    let header = 2 * cells.len();
    let entries: usize = cells.iter().map(Vec::len).sum();
    let mut data = Vec::with_capacity(header + entries);
    let mut first = header as u32;
    let mut longest = 0;
    for c in &cells {
        data.extend([first, c.len() as u32]);
        first += c.len() as u32;
        longest = longest.max(c.len() as u32);
    }
    for c in &cells {
        data.extend_from_slice(c);
    }
    ClusterLists { data, grid: Some(grid), entries: entries as u64, longest }
}

/// Cost constants of `auto`'s frame rule, idle lavapipe on this project's 2-core machine.
/// From the full bench (idle): a light draw about 30 µs ([`DRAW_MS`]), a shaded
/// fragment 17 ns ([`FRAGMENT_NS`]), a full-screen pass at 1280x720 about 15 ms
/// ([`CLUSTERED_FIXED_MS_PER_MPX`]: the clustered shading pass with empty lists is one).
/// From `lampshade bench demo --only culling --frames 10` (1280x720, 1,028 lights; one run on
/// a loaded machine where fullscreen took 6.5x its idle time, so scaled by 1/6.5): clustered's
/// lighting 564.6 ms = ambient + its full-screen pass (about 2 x 15 x 6.5 ms) + 4.59 M
/// light-pixel pairs, so about 80 ns a pair there and 12 ns idle ([`PAIR_NS`]); its lists held
/// 0.55 pairs per pixel of the lights' volumes' coverage (4.59 M against 8.37 M,
/// [`PAIR_PER_FOOTPRINT`]). In that run `tiled` (1,160 ms) lost to two-pass (767 ms): its
/// compute pass costs more than the CPU's cluster assignment, so the rule weighs `clustered`.
pub const DRAW_MS: f64 = 0.030;
pub const FRAGMENT_NS: f64 = 17.0;
pub const CLUSTERED_FIXED_MS_PER_MPX: f64 = 16.0;
pub const PAIR_NS: f64 = 12.0;
pub const PAIR_PER_FOOTPRINT: f64 = 0.55;
/// Below this many lights `auto` keeps its per-light plan: the constants above were measured
/// at 1,024 lights and more, and with few lights the per-light plan's draws cost little.
pub const FRAME_RULE_MIN_LIGHTS: usize = 256;

/// Draw calls a per-light method issues.
fn draws(m: Method) -> f64 {
    match m {
        Method::Fullscreen | Method::Volume => 1.0,
        Method::StencilTwoPass | Method::StencilInvert | Method::StencilReplace => 2.0,
        Method::Tiled | Method::Clustered | Method::Skipped => 0.0,
    }
}

/// Estimated GPU ms of `auto`'s per-light plan and of `clustered` for the frame (per-light,
/// clustered): draws x [`DRAW_MS`] + each drawn light's footprint x [`FRAGMENT_NS`], against
/// a full-screen pass + the footprints x [`PAIR_PER_FOOTPRINT`] x [`PAIR_NS`].
pub fn frame_costs(plans: &[LightPlan], size: (u32, u32)) -> (f64, f64) {
    let pixels = (size.0 as f64) * (size.1 as f64);
    let mut per_light = 0.0;
    let mut clustered = CLUSTERED_FIXED_MS_PER_MPX * pixels / 1e6;
    for p in plans {
        let footprint = match p.method {
            Method::Fullscreen => pixels,
            Method::Skipped => 0.0,
            _ => p.screen_share as f64 * pixels,
        };
        per_light += draws(p.method) * DRAW_MS + footprint * FRAGMENT_NS * 1e-6;
        if p.method != Method::Skipped {
            clustered += (p.screen_share as f64 * pixels).min(pixels) * PAIR_PER_FOOTPRINT * PAIR_NS * 1e-6;
        }
    }
    (per_light, clustered)
}

/// The frame-level rule, after the per-light plans: `tiled` and `clustered` shade every light
/// from their lists; `auto` with at least [`FRAME_RULE_MIN_LIGHTS`] lights keeps its per-light
/// plan unless [`frame_costs`] estimates `clustered` cheaper, and then shades the whole frame
/// clustered. Returns the method of the tiled pass, if the frame uses it.
pub fn frame_rule(plans: &mut [LightPlan], view: &PlanView) -> Option<Method> {
    let method = match view.mode {
        CullingMode::Tiled => Method::Tiled,
        CullingMode::Clustered => Method::Clustered,
        CullingMode::Auto if plans.len() >= FRAME_RULE_MIN_LIGHTS => {
            let (per_light, clustered) = frame_costs(plans, view.size);
            if clustered >= per_light {
                return None;
            }
            Method::Clustered
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
    use crate::renderer::settings::ForwardLights;
    use crate::scene::Camera;

    fn view(size: (u32, u32)) -> PlanView {
        let cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        PlanView {
            proj: cam.projection(size.0 as f64 / size.1 as f64, false).as_mat4(),
            near: cam.near as f32,
            far: cam.far as f32,
            size,
            mode: CullingMode::Clustered,
            depth_clamp: true,
            forward_lights: ForwardLights::Tiled,
            light_batching: true,
        }
    }

    #[test]
    fn auto_keeps_its_per_light_plan_for_few_lights_and_shades_many_clustered() {
        let small = LightPlan {
            method: Method::Volume,
            volume: crate::renderer::VolumeKind::Sphere,
            crosses_near: false,
            crosses_far: false,
            screen_share: 0.001,
            screen_rect: Some((Vec2::ZERO, Vec2::splat(0.05))),
        };
        let mut v = view((1280, 720));
        v.mode = CullingMode::Auto;
        let mut few = vec![small; 8];
        assert_eq!(frame_rule(&mut few, &v), None);
        assert!(few.iter().all(|p| p.method == Method::Volume));
        // 300 tiny lights: the full-screen pass costs more than their draws.
        let mut some = vec![small; 300];
        let (per_light, clustered) = frame_costs(&some, v.size);
        assert!(clustered > per_light, "{clustered} ms clustered, {per_light} ms per light");
        assert_eq!(frame_rule(&mut some, &v), None);
        let mut many = vec![small; 4096];
        let (per_light, clustered) = frame_costs(&many, v.size);
        assert!(clustered < per_light, "{clustered} ms clustered, {per_light} ms per light");
        assert_eq!(frame_rule(&mut many, &v), Some(Method::Clustered));
        assert!(many.iter().all(|p| p.method == Method::Clustered));
        // Fixed modes are left alone; tiled and clustered take every light.
        v.mode = CullingMode::Volume;
        assert_eq!(frame_rule(&mut few, &v), None);
        v.mode = CullingMode::Clustered;
        assert_eq!(frame_rule(&mut few, &v), Some(Method::Clustered));
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
        for _ in 0..200 {
            let d = 0.5 + rnd() * 60.0;
            let ndc = Vec2::new(rnd() * 2.4 - 1.2, rnd() * 2.4 - 1.2);
            let p = inv.project_point3(Vec3::new(ndc.x, ndc.y, 0.5));
            let pos = p.normalize() * d;
            let radius = 0.3 + rnd() * 6.0;
            let l = LightRecord {
                position: pos.into(),
                radius,
                color: [1.0; 3],
                kind: crate::renderer::records::LIGHT_KIND_POINT,
                direction: [0.0, 0.0, -1.0],
                cos_outer: -1.0,
                cos_inner: -1.0,
                tan_outer: 0.0,
                falloff: radius,
                clamp: f32::MAX,
            };
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
        };
        let plans = vec![plan; lights.len()];
        let lists = cluster_lists(&lights, &plans, &v);
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
