//! How much of the screen a light covers: its volume's vertices projected, its sphere's
//! silhouette as an ellipse, and a footprint clipped to the screen and measured.

use super::super::volumes;
use crate::renderer::records::LightRecord;
use glam::{DVec2, DVec3, Mat4, Vec2, Vec3};

/// The NDC box of `light`'s bounding mesh's vertices under projection `p`, as the hull path
/// projects them.
pub(super) fn projected_vertex_box(light: &LightRecord, mesh: &volumes::VolumeMesh, p: &Mat4) -> (DVec2, DVec2) {
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for v in &mesh.vertices {
        let q = *p * volumes::place_light(*v, light).extend(1.0);
        let n = Vec2::new(q.x, q.y) / q.w;
        lo = lo.min(n);
        hi = hi.max(n);
    }
    (lo.as_dvec2(), hi.as_dvec2())
}

/// Area (NDC) on screen of an ellipse given by its bounding box (`lo`, `hi`: an ellipse's box is
/// centred on it) and its `area`, exact, when the screen cuts it along one side or two opposite
/// sides; `None` when it crosses a horizontal and a vertical side (near a corner, where the two
/// cut-off parts may overlap; [`silhouette_area`] clips a polygon instead).
///
/// An affine map takes the ellipse to the unit circle and keeps ratios of areas. It takes the
/// line x = 1 to a line at distance h = (1 - centre.x) / half-width from the circle's centre
/// (the half-width of an ellipse's box is its support along x, which the map takes to the unit
/// circle's support 1), and the circle's part beyond a line at distance h is the share
/// (acos h - h sqrt(1 - h^2)) / pi of it. Parts beyond opposite sides never overlap. The
/// 32-corner polygon this replaces cost 270 ns a light (1,246 partly visible lights of `demo`'s
/// 16,384: 0.33 ms a frame).
pub(super) fn ellipse_on_screen((lo, hi): (DVec2, DVec2), area: f64) -> Option<f32> {
    let (centre, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    if !(half.x > 0.0 && half.y > 0.0 && area.is_finite()) {
        return None;
    }
    // The share of the ellipse beyond the line at distance `h` (in half-widths) from its centre.
    let beyond = |h: f64| {
        let h = h.clamp(-1.0, 1.0);
        (h.acos() - h * (1.0 - h * h).sqrt()) / std::f64::consts::PI
    };
    let cut = |d: f64| if d < 1.0 { beyond(d) } else { 0.0 };
    let (right, left) = (cut((1.0 - centre.x) / half.x), cut((1.0 + centre.x) / half.x));
    let (top, bottom) = (cut((1.0 - centre.y) / half.y), cut((1.0 + centre.y) / half.y));
    if (right > 0.0 || left > 0.0) && (top > 0.0 || bottom > 0.0) {
        return None;
    }
    Some((area * (1.0 - right - left - top - bottom).max(0.0)) as f32)
}

/// Area (NDC) on screen of the ellipse a sphere (view-space centre `c`, radius `r`, wholly in
/// front of the eye) projects to: the circle where the eye's tangent cone touches the sphere
/// (centre c (1 - r^2/|c|^2), radius r sqrt(1 - r^2/|c|^2), across the view ray to c), as a
/// polygon of [`SILHOUETTE_CORNERS`] corners widened to the circle's area, projected (a convex
/// polygon in order) and clipped to the screen.
pub(super) fn silhouette_area(c: DVec3, r: f64, xs: f64, ys: f64) -> f32 {
    let l2 = c.length_squared();
    let k = 1.0 - r * r / l2;
    let (centre, radius) = (c * k, r * k.sqrt());
    let (u, v) = (c / l2.sqrt()).any_orthonormal_pair();
    // An inscribed polygon of n corners has sin(2 pi / n) n / (2 pi) of the circle's area.
    let step = std::f64::consts::TAU / SILHOUETTE_CORNERS as f64;
    let widen = (step / step.sin()).sqrt();
    let mut poly = [Vec2::ZERO; SILHOUETTE_CORNERS];
    for (p, (cos, sin)) in poly.iter_mut().zip(unit_circle()) {
        let q = centre + (u * cos + v * sin) * (radius * widen);
        *p = Vec2::new((xs * q.x / -q.z) as f32, (ys * q.y / -q.z) as f32);
    }
    clipped_area_of(&poly)
}

/// The corners of [`silhouette_area`]'s polygon on the unit circle, (cos, sin), computed once.
fn unit_circle() -> &'static [(f64, f64); SILHOUETTE_CORNERS] {
    static CORNERS: std::sync::OnceLock<[(f64, f64); SILHOUETTE_CORNERS]> = std::sync::OnceLock::new();
    CORNERS.get_or_init(|| {
        let step = std::f64::consts::TAU / SILHOUETTE_CORNERS as f64;
        std::array::from_fn(|i| {
            let a = step * i as f64;
            (a.cos(), a.sin())
        })
    })
}

/// Corners of the polygon [`silhouette_area`] stands for an ellipse with.
const SILHOUETTE_CORNERS: usize = 32;

/// The projected corners (NDC) of a convex volume clipped at the near plane: its vertices at or
/// beyond the plane, and where its edges cross it. `placed` are the mesh's view-space vertices.
pub(super) fn clipped_footprint(placed: &[Vec3], indices: &[u32], proj: Mat4, near: f32) -> Vec<Vec2> {
    let project = |p: Vec3| {
        let c = proj * p.extend(1.0);
        Vec2::new(c.x, c.y) / c.w
    };
    let mut out: Vec<Vec2> = placed.iter().filter(|p| -p.z >= near).map(|&p| project(p)).collect();
    // An edge crosses only where one end lies before the plane: with none there, the walk over
    // the edges (three a triangle) would find nothing.
    if !placed.iter().any(|p| -p.z - near < 0.0) {
        return out;
    }
    for tri in indices.chunks_exact(3) {
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let (Some(&a), Some(&b)) = (placed.get(tri[i] as usize), placed.get(tri[j] as usize)) else {
                continue;
            };
            let (da, db) = (-a.z - near, -b.z - near);
            // One end strictly on each side: the edge crosses the plane (each edge is met twice,
            // from both of its triangles; a repeated point does not change the hull).
            if (da < 0.0) != (db < 0.0) && da != db {
                let t = da / (da - db);
                let mut p = a + (b - a) * t;
                p.z = -near;
                out.push(project(p));
            }
        }
    }
    out
}

/// Area (NDC units, the screen is 4) of the convex hull of `points` inside the screen square.
pub(super) fn screen_area(points: &[Vec2]) -> f32 {
    clipped_area(convex_hull(points))
}

/// Area (NDC) of a convex polygon (corners in order, either way round) inside the screen.
fn clipped_area(poly: Vec<Vec2>) -> f32 {
    clipped_area_of(&poly)
}

/// [`clipped_area`], on the stack for polygons of up to [`CLIP_CORNERS`] - 4 corners (each
/// clipping plane adds at most one corner to a convex polygon).
fn clipped_area_of(poly: &[Vec2]) -> f32 {
    let n = poly.len();
    if n + 4 > CLIP_CORNERS {
        let (mut a, mut b) = (poly.to_vec(), vec![Vec2::ZERO; n + 4]);
        a.resize(n + 4, Vec2::ZERO);
        return clip_to_screen(&mut a, &mut b, n);
    }
    let (mut a, mut b) = ([Vec2::ZERO; CLIP_CORNERS], [Vec2::ZERO; CLIP_CORNERS]);
    a[..n].copy_from_slice(poly);
    clip_to_screen(&mut a, &mut b, n)
}

/// Corners [`clipped_area_of`] clips on the stack.
const CLIP_CORNERS: usize = SILHOUETTE_CORNERS + 4;

/// Sutherland-Hodgman against x <= 1, x >= -1, y <= 1, y >= -1 of the polygon `a[..n]`
/// (`a` and `b` hold n + 4 corners), then its area.
pub(super) fn clip_to_screen(a: &mut [Vec2], b: &mut [Vec2], mut n: usize) -> f32 {
    let (mut src, mut dst) = (a, b);
    for (axis, sign) in [(0usize, 1.0f32), (0, -1.0), (1, 1.0), (1, -1.0)] {
        if n == 0 {
            break;
        }
        // The coordinate clipped, without indexing by a run-time axis.
        let along = |p: Vec2| if axis == 0 { p.x } else { p.y };
        let inside = |p: Vec2| sign * along(p) <= 1.0;
        // Wholly inside this plane (most partly visible lights cross one screen edge): clipping
        // would copy the corners unchanged, so it is skipped.
        if src[..n].iter().all(|&p| inside(p)) {
            continue;
        }
        let mut m = 0;
        // The next corner without a division (`% n`) per edge: the same edges in the same order.
        let next = |k: usize| if k + 1 == n { 0 } else { k + 1 };
        for k in 0..n {
            let (p, q) = (src[k], src[next(k)]);
            if inside(p) {
                dst[m] = p;
                m += 1;
            }
            if inside(p) != inside(q) {
                let t = (sign - along(p)) / (along(q) - along(p));
                dst[m] = p + (q - p) * t;
                m += 1;
            }
        }
        std::mem::swap(&mut src, &mut dst);
        n = m;
    }
    let twice: f32 = (0..n).map(|k| src[k].perp_dot(src[if k + 1 == n { 0 } else { k + 1 }])).sum();
    (twice * 0.5).abs()
}

/// Andrew's monotone chain: the hull's corners in counter-clockwise order (non-finite points
/// are dropped).
fn convex_hull(points: &[Vec2]) -> Vec<Vec2> {
    let mut p: Vec<Vec2> = points.iter().copied().filter(|p| p.is_finite()).collect();
    // Unstable: equal points are equal in both coordinates, so the order (and the hull) is the
    // same as a stable sort's, without its scratch allocation (measured: no change in the hull
    // path's 2.2 µs a light at 16,384 lights; its cost is spread over the mesh's edges).
    p.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<Vec2> = Vec::with_capacity(2 * p.len());
    let chain = |hull: &mut Vec<Vec2>, points: &mut dyn Iterator<Item = Vec2>| {
        let start = hull.len();
        for q in points {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    };
    chain(&mut hull, &mut p.iter().copied());
    chain(&mut hull, &mut p.iter().rev().copied());
    hull
}
