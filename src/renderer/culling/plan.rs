//! What the CPU decides before any pass is recorded: per light, the culling method that draws
//! it (and the facts that decide it: its volume, the planes it crosses, its screen share); per
//! object, whether it goes into the G-buffer or is shaded forward, in which order, and which
//! lights reach it.

mod draws;
mod footprint;
mod forward_paths;

pub use draws::{long_forward_list_warnings, FORWARD_TILE, MAX_FORWARD_LIST_ENTRIES};
pub use forward_paths::{forward_path_lists, scissor_rect, ForwardPair, ForwardPathLists};

use draws::plan_draws;
use footprint::{clipped_footprint, ellipse_on_screen, projected_vertex_box, screen_area, silhouette_area};

use super::batches::LightBatches;
use super::stats::ForwardStats;
use super::volumes::{self, VolumeKind, Volumes};
use crate::renderer::options::culling::{CullingMode, ForwardLights};
pub use crate::renderer::options::culling::{FORWARD_LIST_MAX, FORWARD_LOOP_LIGHTS};
use crate::renderer::records::{FrameRecords, LightRecord};
use crate::scene::Scene;
use glam::{DVec2, DVec3, Mat4, Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Volumes whose projected bounding rectangle covers at least this many pixels are stencil
/// culled by `auto` (the marking draw pays off); smaller ones are drawn as plain volumes.
pub const AUTO_STENCIL_MIN_PIXELS: f32 = 4096.0;

/// How one light is drawn this frame: a fixed [`CullingMode`]'s method, or what `auto` chose.
/// The names are the culling modes' names (the old short names still load).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    #[default]
    Fullscreen,
    Volume,
    #[serde(alias = "two-pass")]
    StencilTwoPass,
    #[serde(alias = "invert")]
    StencilInvert,
    #[serde(alias = "replace")]
    StencilReplace,
    /// Shaded from its tiles' light lists in the tiled pass (`culling::tiled::pass`).
    Tiled,
    /// Shaded from its clusters' light lists in the tiled pass.
    Clustered,
    /// Shaded from its tile's bitmask within its depth bin's range in the tiled pass
    /// (`culling::zbin`).
    Zbin,
    /// `auto` only: the volume lies outside the view frustum and is not drawn.
    Skipped,
}

impl Method {
    /// Whether the tiled pass shades this light from a list or mask (`tiled`, `clustered`,
    /// `zbin`), not a draw of its own.
    pub fn listed(self) -> bool {
        matches!(self, Method::Tiled | Method::Clustered | Method::Zbin)
    }

    /// The name in stats, the viewer and the bench: the culling mode's name, or `skipped`.
    pub fn name(self) -> String {
        match super::methods::row(self).mode {
            Some(m) => m.name().to_string(),
            None => "skipped".into(),
        }
    }
}

impl CullingMode {
    /// The one method a fixed mode draws every light with; `None` for `auto`.
    pub fn method(self) -> Option<Method> {
        super::methods::METHODS.iter().find(|r| r.mode == Some(self)).map(|r| r.method)
    }
}

/// What the CPU decided for one light this frame.
#[derive(Clone, Copy, Debug)]
pub struct LightPlan {
    pub method: Method,
    pub volume: VolumeKind,
    /// The volume reaches in front of the near plane (or holds the camera).
    pub crosses_near: bool,
    /// The volume reaches beyond the far plane.
    pub crosses_far: bool,
    /// Share of the screen covered by the volume's footprint: the mesh clipped at the near plane
    /// and projected (its convex hull, clipped to the screen). 1 when the volume holds the eye.
    pub screen_share: f32,
    /// That rectangle in normalised device coordinates (min, max), not clipped to the screen;
    /// the whole screen when the volume crosses the near plane, `None` when it is off screen.
    /// It bounds every visible point the light can reach (the volume circumscribes the light).
    pub screen_rect: Option<(Vec2, Vec2)>,
    /// The view depths the light's sphere spans, (nearest, farthest): (centre depth - radius,
    /// centre depth + radius), from the record; (inf, -inf) when the radius is not positive or
    /// the centre not finite. The clustered grid and spans read it here rather than from the
    /// records (one walk over 112-byte records fewer at 16,384 lights).
    pub depths: (f32, f32),
}

/// [`LightPlan::depths`] of a record.
pub fn light_depths(light: &LightRecord) -> (f32, f32) {
    let (c, r) = (Vec3::from(light.position), light.radius);
    if r.is_nan() || r <= 0.0 || !c.is_finite() {
        return (f32::INFINITY, f32::NEG_INFINITY);
    }
    (-c.z - r, -c.z + r)
}

/// The view a frame's lights are planned against.
pub struct PlanView {
    pub proj: Mat4,
    pub near: f32,
    pub far: f32,
    pub size: (u32, u32),
    pub mode: CullingMode,
    /// Light volumes are drawn with depth clamp (so they may cross the far plane).
    pub depth_clamp: bool,
    /// Which lights the forward pass walks per blended fragment.
    pub forward_lights: ForwardLights,
    /// Draw lights in batches (`Settings::light_batching`; see `batches.rs`).
    pub light_batching: bool,
    /// Who builds the clustered lists.
    pub cluster_build: crate::renderer::settings::ClusterBuilder,
    /// The clustered grid and per-cluster cap asked for.
    pub grid: super::tiled::GridChoice,
    /// Lights kept per object on the forward paths, and by which order (0: all).
    pub object_cap: (u32, crate::renderer::caps::CapOrder),
    /// The adapter's shader loop limit (`Quirks::loop_limit`): a GPU list build that would run
    /// past it is done on the CPU instead.
    pub loop_limit: Option<u64>,
    /// Seed 004's rule (`NearLights::Fullscreen`): a light whose volume crosses the near plane
    /// is drawn full-screen instead of by its volume method (without depth clamp, always).
    pub near_fullscreen: bool,
    /// Opaque draws nearest first (`DrawOrder::FrontToBack`) instead of by material.
    pub front_to_back: bool,
    /// Blended draws back to front (alpha blending); unsorted, in scene order, when they are
    /// added (`BlendedMode::Additive`).
    pub sort_blended: bool,
    /// The light pre-pass (seed 004): opaque objects whose reflectance model its one
    /// Blinn-Phong light buffer cannot carry (toon) are shaded forward after pass 3; `Some`
    /// holds the model forced on every object (`--brdf`), if any.
    pub prepass_models: Option<Option<crate::scene::Brdf>>,
    /// The cost model's constants `auto`'s frame rule weighs (`tiles::frame_costs`): the
    /// renderer's calibration.
    pub costs: crate::renderer::options::calibration::CostConstants,
}

/// Which mesh bounds the light, where it sits against the near and far planes, and how much of
/// the screen it covers; then which method draws it.
///
/// `auto`'s rule, per light:
/// - outside the frustum: skip it;
/// - a sphere that holds the whole view frustum (its eight corners): full-screen, which shades
///   exactly the fragments a volume would (every visible point is inside) without rasterising
///   faces;
/// - a volume crossing the near plane: the plain volume (back faces, GreaterEqual); without
///   depth clamp full-screen, in every volume mode (see `choose`). Its front
///   faces are clipped where the two-pass marking draw would mark, so marking saves it nothing:
///   on `street` the volume shades exactly the fragments two-pass does, light by light
///   (`tests/it/hard_cases.rs`), and skipping the marking draw took auto from 4-6% behind the
///   best fixed mode to level with it at 1280x720;
/// - a screen rectangle of at least [`AUTO_STENCIL_MIN_PIXELS`]: seed 000's two-pass stencil
///   (the marking draw saves thousands of shaded fragments);
/// - else the plain volume (one draw, back faces, GreaterEqual), since for small volumes the
///   extra marking draw costs more than the fragments it saves.
///
/// The rectangle and `screen_share` come from the volume's real footprint: the mesh clipped at
/// the near plane (its vertices beyond it and its edges' crossings), projected. A volume that
/// crosses the near plane is no longer counted as the whole screen, and it is never sent
/// full-screen for covering much of the screen: its shading draw (back faces, GreaterEqual; the
/// two-pass mark simply finds no front face where they are clipped) still shades only the points
/// in front of its far side, while a full-screen draw shades every pixel. The old rule (more
/// than half the screen, near-crossing counted as all of it: full-screen) shaded 4.5x the
/// fragments of two-pass on the `street` hard case and lost to it in time (docs/measurements.md). Thresholds from `lampshade bench --only culling` on lavapipe at 320x180,
/// 640x360 and 1280x720.
pub fn plan_light(light: &LightRecord, volumes: &Volumes, view: &PlanView) -> LightPlan {
    plan_hull(light, volumes.mesh(VolumeKind::of(light)), view)
}

/// [`plan_light`] with the light's bounding mesh given.
fn plan_hull(light: &LightRecord, mesh: &volumes::VolumeMesh, view: &PlanView) -> LightPlan {
    let volume = VolumeKind::of(light);
    let pos = Vec3::from(light.position);
    let (near, far) = (view.near, view.far);
    let placed: Vec<Vec3> = mesh.vertices.iter().map(|v| volumes::place_light(*v, light)).collect();
    let mut crosses_near = false;
    let mut crosses_far = false;
    // Clip-space side planes: a convex volume with every vertex outside one of them is outside
    // the frustum.
    let mut outside = [true; 4];
    let (mut all_before_near, mut all_beyond_far) = (true, true);
    for p in &placed {
        let dist = -p.z;
        // The vertex shader places the vertex with its own f32 rounding: at most a few steps of
        // the terms summed (`volumes::place`: the light's position and three offsets), here and
        // there, 16 steps of their magnitudes. A vertex within that of the near plane may be
        // clipped by it.
        let slack = 16.0 * f32::EPSILON * (pos.length() + (*p - pos).length());
        crosses_near |= dist <= near * 1.01 + slack;
        crosses_far |= dist >= far * 0.99 || may_clip_far(&view.proj, dist, slack);
        // Before the near plane or beyond the far plane only where the f32 clip test surely
        // clips what lies there: with a tiny near plane it keeps geometry far behind the far
        // plane, and the light still reaches that.
        let clipped = !may_keep_depth(&view.proj, dist, slack);
        all_before_near &= dist < near && clipped;
        all_beyond_far &= dist > far && clipped;
        let c = view.proj * p.extend(1.0);
        for (k, d) in [c.w - c.x, c.w + c.x, c.w - c.y, c.w + c.y].into_iter().enumerate() {
            outside[k] &= d < 0.0;
        }
    }
    // The footprint: the volume clipped at the near plane, projected. It is convex (a convex
    // volume in front of the eye projects to a convex region), so the hull of the projected
    // corners of the clipped volume is exactly the area its back faces rasterise.
    let footprint = clipped_footprint(&placed, &mesh.indices, view.proj, near);
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for n in &footprint {
        lo = lo.min(*n);
        hi = hi.max(*n);
    }
    let off_screen = outside.iter().any(|&o| o)
        || all_before_near
        || all_beyond_far
        || !(crosses_near || lo.x < 1.0 && lo.y < 1.0 && hi.x > -1.0 && hi.y > -1.0);
    let crosses_near = crosses_near && !off_screen;
    let (screen_share, rect_share) = if off_screen {
        (0.0, 0.0)
    } else {
        let a = (hi.min(Vec2::ONE) - lo.max(-Vec2::ONE)).max(Vec2::ZERO);
        (screen_area(&footprint) / 4.0, a.x * a.y / 4.0)
    };
    let pixels = rect_share * (view.size.0 * view.size.1) as f32;
    // The sphere holds the whole view frustum (all eight corners): every visible point is inside
    // it, so a full-screen triangle shades exactly the fragments a volume would, without
    // rasterising faces. The mesh circumscribes the sphere, so this is conservative.
    let holds_frustum = volume == VolumeKind::Sphere && {
        let (xs, ys) = (view.proj.x_axis.x, view.proj.y_axis.y);
        [near, far].into_iter().all(|d| {
            [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
                .into_iter()
                .all(|(sx, sy)| Vec3::new(sx * d / xs, sy * d / ys, -d).distance(pos) < light.radius)
        })
    };
    let method = choose(view, Facts { crosses_near, crosses_far, off_screen, holds_frustum, pixels });
    let screen_rect = if off_screen {
        None
    } else if crosses_near {
        Some((-Vec2::ONE, Vec2::ONE))
    } else {
        Some((lo, hi))
    };
    LightPlan { method, volume, crosses_near, crosses_far, screen_share, screen_rect, depths: light_depths(light) }
}

/// Whether the clipper's far test may clip a vertex at view depth `dist` placed with rounding
/// `slack` (see [`plan_hull`]). The test is z <= w on the f32 clip coordinates, z = a z_view + b
/// and w = -z_view. On standard depth w - z = n (f - d) / (f - n) exactly; with a near plane tiny
/// against the distance that is smaller than the rounding of z and w (a few steps of |a d| + |b|
/// and of d, here and on the GPU: 8 steps; the placement's `slack` through a and w), and the
/// vertex may be clipped far short of the far plane: a near plane of 2.3e-6 against a far of 32
/// clipped faces 25 away. Reversed depth puts the far plane at z = 0, where z's rounding is a
/// few steps of n: within the 1% margin the callers also test.
fn may_clip_far(proj: &Mat4, dist: f32, slack: f32) -> bool {
    let (a, b) = (proj.z_axis.z, proj.w_axis.z);
    let z = b - a * dist;
    dist - z <= 8.0 * f32::EPSILON * ((a * dist).abs() + b.abs() + dist) + slack * (a.abs() + 1.0)
}

/// Whether the clipper's f32 depth tests, 0 <= z and z <= w, may keep a point of the scene at
/// view depth `dist`, with the rounding [`may_clip_far`] allows (8 steps of |a d| + |b| in z,
/// of d in w, and the vertex's placement `slack` through both). The exact z - w is
/// n (d - f) / (f - n) beyond the far plane on standard depth: with n / f under about 16 f32
/// steps that is below the rounding at every depth, and the clipper may keep surfaces at any
/// distance behind the far plane (a near plane of 6e-9 against a far of 0.018 kept a floor 0.42
/// away, lit by a spot whose volume lay wholly beyond the far plane). The bound is linear in d,
/// as z - w is, so a convex volume whose every vertex fails it holds no point the clip keeps.
/// Computed in f64 from the projection's f32 terms, so the test adds no rounding of its own.
fn may_keep_depth(proj: &Mat4, dist: f32, slack: f32) -> bool {
    let (a, b, d) = (proj.z_axis.z as f64, proj.w_axis.z as f64, dist as f64);
    let z = b - a * d;
    let eps = f32::EPSILON as f64;
    let z_rounding = 8.0 * eps * ((a * d).abs() + b.abs()) + slack as f64 * a.abs();
    let w_rounding = 8.0 * eps * d + slack as f64;
    z >= -z_rounding && z - d <= z_rounding + w_rounding
}

/// What decides a light's method (see [`plan_light`]).
struct Facts {
    crosses_near: bool,
    crosses_far: bool,
    off_screen: bool,
    holds_frustum: bool,
    /// Pixels of the footprint's bounding rectangle on screen.
    pixels: f32,
}

fn choose(view: &PlanView, f: Facts) -> Method {
    let method = choose_method(view, &f);
    let volume =
        matches!(method, Method::Volume | Method::StencilTwoPass | Method::StencilInvert | Method::StencilReplace);
    // Without depth clamp a near-crossing volume's faces are clipped at the near plane, and a
    // vertex the clipper makes there carries the rounding of its edge's endpoints (a few f32
    // steps of their clip-space coordinates) against a w of only `near`: the back face's
    // rasterised depth has no bound in terms of the volume's margin, so no volume method's depth
    // test is safe for that light. Drawn full-screen, as seed 004 draws every such light.
    if (view.near_fullscreen || !view.depth_clamp) && f.crosses_near && volume {
        Method::Fullscreen
    } else {
        method
    }
}

fn choose_method(view: &PlanView, f: &Facts) -> Method {
    if f.crosses_far && !view.depth_clamp && !(view.mode == CullingMode::Auto && f.off_screen) {
        // Without depth clamp the far side would be clipped away: no volume method is correct,
        // so the light is drawn full-screen.
        Method::Fullscreen
    } else if let Some(fixed) = view.mode.method() {
        fixed
    } else if f.off_screen {
        Method::Skipped
    } else if f.holds_frustum {
        Method::Fullscreen
    } else if f.crosses_near {
        Method::Volume
    } else if f.pixels >= AUTO_STENCIL_MIN_PIXELS {
        Method::StencilTwoPass
    } else {
        Method::Volume
    }
}

/// The sphere mesh's radii per unit of light radius: it lies inside the sphere through its
/// vertices (`outer`) and holds the sphere touching its nearest face (`inner`, 1.002: the mesh
/// circumscribes the light with `VOLUME_MARGIN`); `mean` is the radius of the sphere with the
/// same mean projected area (Cauchy: a convex body's projected area averaged over directions is
/// a quarter of its surface area).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereRadii {
    pub outer: f32,
    pub inner: f32,
    pub mean: f32,
}

impl SphereRadii {
    pub fn of(mesh: &volumes::VolumeMesh) -> Self {
        let v = |i: u32| mesh.vertices.get(i as usize).map_or(Vec3::ZERO, |v| v.truncate());
        let outer = mesh.vertices.iter().map(|v| v.truncate().length()).fold(0.0, f32::max);
        let (mut inner, mut surface) = (f32::INFINITY, 0.0f64);
        for t in mesh.indices.chunks_exact(3) {
            let (a, b, c) = (v(t[0]), v(t[1]), v(t[2]));
            let n = (b - a).cross(c - a);
            surface += 0.5 * n.length() as f64;
            inner = inner.min(n.normalize_or_zero().dot(a).abs());
        }
        let mean = (surface / (4.0 * std::f64::consts::PI)).sqrt() as f32;
        Self { outer, inner: inner.min(outer), mean }
    }
}

/// The analytic path of [`plan_sphere_ahead`] is taken only when the projections of the
/// spheres inside and outside the mesh differ by at most this share of the screen: the mesh's
/// footprint lies between them, so this bounds the error of its `screen_share` (the sphere of
/// the same mean projected area lies between them too). Measured, the error is far smaller:
/// at most 0.0014 of the screen against the hull over the 16,384 lights of `demo` at 1280x720,
/// and within the hull test's 0.002 of a per-pixel ray count at 0 to 2 subdivisions
/// (`plan::tests`). Closer volumes go to the hull (87 of `demo`'s 16,384).
pub const ANALYTIC_SHARE_SLACK: f64 = 0.05;

/// The fast path of [`plan_light`] for the common case at thousands of lights: a sphere volume
/// wholly between the near and far planes (no clipping), or wholly outside the view. A sphere
/// in front of the eye projects to an ellipse, so no hull is built:
/// - the rectangle ([`LightPlan::screen_rect`]) is the tight projected bounding box of the
///   sphere through the mesh's vertices, which holds the mesh and so its footprint
///   (conservative, as the hull's box was) and what `auto` decides on (the hull's box, the
///   box of the mesh's projected vertices, which lie on that sphere, is at most a few percent
///   smaller);
/// - `screen_share` is the area of the ellipse of the sphere with the mesh's mean projected
///   area (`SphereRadii::mean`);
/// - partly on screen, the share is that ellipse clipped to the screen ([`silhouette_area`]);
/// - `None` (the hull is built) when the volume crosses the near or far plane, or is so close
///   that the inner and outer spheres' projections differ by more than
///   [`ANALYTIC_SHARE_SLACK`] of the screen.
///
/// The projected sphere (centre c in view space, depth z = -c.z > r): a view ray x = m z is
/// tangent where (c.x - m z)^2 = r^2 (1 + m^2), so m = (c.x z +- r sqrt(c.x^2 + z^2 - r^2)) /
/// (z^2 - r^2) (likewise in y); the ellipse's area at unit distance is
/// pi r^2 sqrt(|c|^2 - r^2) / (z^2 - r^2)^(3/2) (Quilez, "sphere projection"), scaled by the
/// projection's x and y factors into NDC.
pub fn plan_sphere_ahead(
    light: &LightRecord,
    radii: SphereRadii,
    mesh: &volumes::VolumeMesh,
    view: &PlanView,
) -> Option<LightPlan> {
    let volume = VolumeKind::of(light);
    let p = &view.proj;
    // A symmetric perspective projection (what `Camera::projection` builds).
    if volume != VolumeKind::Sphere || p.z_axis.x != 0.0 || p.z_axis.y != 0.0 || p.w_axis.w != 0.0 {
        return None;
    }
    let c = Vec3::from(light.position).as_dvec3();
    let (xs, ys) = (p.x_axis.x as f64, p.y_axis.y as f64);
    let z = -c.z;
    let outer = (light.radius * radii.outer) as f64;
    let (near, far) = (view.near as f64, view.far as f64);
    let deepest = (z + outer) as f32;
    let slack = 16.0 * f32::EPSILON * (c.length() as f32 + outer as f32);
    if z + outer >= far * 0.99 || may_clip_far(p, deepest, slack) {
        // Beyond or across the far plane, or where its f32 clip test may clip: the hull path
        // decides (rare).
        return None;
    }
    let off = |method| LightPlan {
        method,
        volume,
        crosses_near: false,
        crosses_far: false,
        screen_share: 0.0,
        screen_rect: None,
        depths: light_depths(light),
    };
    let facts = |off_screen, pixels| Facts {
        crosses_near: false,
        crosses_far: false,
        off_screen,
        holds_frustum: false,
        pixels,
    };
    // Wholly behind the near plane where the f32 clip surely clips (its deepest point: the
    // closer to the plane, the likelier kept), or wholly outside a side plane of the frustum
    // (the centre farther than the radius through the vertices: every vertex is outside, as the
    // hull path tests them).
    let outside = |a: f64, s: f64| (s * a.abs() - z) / (s * s + 1.0).sqrt() > outer;
    let before_near = z + outer < near && !may_keep_depth(p, deepest, slack);
    if before_near || outside(c.x, xs) || outside(c.y, ys) {
        return Some(off(choose(view, facts(true, 0.0))));
    }
    // Every vertex beyond the near plane, with the hull path's 1% margin.
    if z - outer <= near * 1.01 {
        return None;
    }
    let (z2, l2) = (z * z, c.length_squared());
    let bounds = |r: f64| {
        let d = z2 - r * r;
        let extent = |a: f64| {
            let t = r * (a * a + d).max(0.0).sqrt();
            ((a * z - t) / d, (a * z + t) / d)
        };
        let ((x0, x1), (y0, y1)) = (extent(c.x), extent(c.y));
        (DVec2::new(x0 * xs, y0 * ys), DVec2::new(x1 * xs, y1 * ys))
    };
    let area = |r: f64| {
        let d = z2 - r * r;
        std::f64::consts::PI * r * r * (l2 - r * r).max(0.0).sqrt() / (d * d.sqrt()) * xs * ys
    };
    let (lo, hi) = bounds(outer);
    if !(lo.x < 1.0 && lo.y < 1.0 && hi.x > -1.0 && hi.y > -1.0) {
        return Some(off(choose(view, facts(true, 0.0))));
    }
    let partly = lo.x < -1.0 || lo.y < -1.0 || hi.x > 1.0 || hi.y > 1.0;
    let inner = (light.radius * radii.inner) as f64;
    // The outer ellipse lies in its box: a box of at most the slack needs no areas.
    let m = hi - lo;
    if m.x * m.y / 4.0 > ANALYTIC_SHARE_SLACK && (area(outer) - area(inner)) / 4.0 > ANALYTIC_SHARE_SLACK {
        return None;
    }
    // The hull path decides on the box of the projected vertices, which lies between the inner
    // sphere's box (the mesh holds that sphere) and the outer's (its vertices lie on it). Where
    // the two boxes disagree (on being on screen, or on `auto`'s threshold) the vertices are
    // projected as the hull path projects them, so both paths decide alike.
    let vertex_box = || projected_vertex_box(light, mesh, p);
    let on_screen = |(lo, hi): (DVec2, DVec2)| lo.x < 1.0 && lo.y < 1.0 && hi.x > -1.0 && hi.y > -1.0;
    // The inner box lies in the outer one: wholly on screen if the outer one is.
    let inner_box = bounds(inner);
    let mut exact = None;
    if partly && !on_screen(inner_box) {
        let b = *exact.get_or_insert_with(vertex_box);
        if !on_screen(b) {
            return Some(off(choose(view, facts(true, 0.0))));
        }
    }
    let screen = (view.size.0 * view.size.1) as f32;
    let pixels_of = |(lo, hi): (DVec2, DVec2)| {
        let m = (hi.min(DVec2::ONE) - lo.max(-DVec2::ONE)).max(DVec2::ZERO);
        (m.x * m.y / 4.0) as f32 * screen
    };
    let (p_outer, p_inner) = (pixels_of((lo, hi)), pixels_of(inner_box));
    // Only `auto` decides on the pixels (a fixed mode's method is its own): the vertices are
    // projected only for it.
    let pixels = if view.mode != CullingMode::Auto
        || (p_outer >= AUTO_STENCIL_MIN_PIXELS) == (p_inner >= AUTO_STENCIL_MIN_PIXELS)
    {
        p_outer
    } else {
        pixels_of(*exact.get_or_insert_with(vertex_box))
    };
    let method = choose(view, facts(false, pixels));
    let mean = (light.radius * radii.mean) as f64;
    let screen_share = if partly {
        ellipse_on_screen(bounds(mean), area(mean)).unwrap_or_else(|| silhouette_area(c, mean, xs, ys)) / 4.0
    } else {
        (area(mean) / 4.0) as f32
    };
    let screen_rect = Some((lo.as_vec2(), hi.as_vec2()));
    let depths = light_depths(light);
    Some(LightPlan { method, volume, crosses_near: false, crosses_far: false, screen_share, screen_rect, depths })
}

/// One object draw: (object, pipeline index within its pass, material).
pub type Draw = (usize, usize, usize);

/// Objects of one frame by how they are drawn.
#[derive(Default)]
pub struct DrawLists {
    /// Into the G-buffer: pipeline index from `surfaces::gbuffer::pipeline_index`.
    pub gbuffer: Vec<Draw>,
    /// Forward, blended, sorted back to front; pipeline index 1 for two-sided.
    pub forward: Vec<Draw>,
    /// The light pre-pass's opaque objects it cannot light (toon; seed 004: "objects with
    /// shaders that can't handle Deferred Lighting are rendered after this process is done,
    /// using RenderTech-ForwardRendering path"): in `gbuffer` (pass 1's depth) but not in
    /// `lit`, shaded forward with their light lists after pass 3. Pipeline index: 1 for
    /// two-sided, + 2 for alpha-masked.
    pub forward_opaque: Vec<Draw>,
    /// Pass 3's draws when `forward_opaque` is not empty: `gbuffer` without them.
    pub lit: Vec<Draw>,
    /// The objects whose material distorts (seed 002's distortion, `post::distortion`), opaque
    /// or blended, in scene order; pipeline index 1 for two-sided.
    pub distorting: Vec<Draw>,
}

impl DrawLists {
    /// The light pre-pass's pass 3 draws: every G-buffer draw but those shaded forward.
    pub fn prepass_final(&self) -> &[Draw] {
        if self.forward_opaque.is_empty() {
            &self.gbuffer
        } else {
            &self.lit
        }
    }
}

/// Everything decided on the CPU for one frame.
#[derive(Default)]
pub struct FramePlan {
    pub lights: Vec<LightPlan>,
    pub draws: DrawLists,
    /// The forward pass's light lists: the blended objects' lists (each object's `info` holds
    /// its offset and count), then, with tiles, each tile's (offset, count) and the tiles' lists
    /// (the camera record's `forward_tiles` says where).
    pub light_lists: Vec<u32>,
    /// The sizes of those lists (`None` without blended objects).
    pub forward: Option<ForwardStats>,
    /// Which lights share an instanced draw, and the draw list they index.
    pub batches: LightBatches,
    /// `Method::Tiled`, `Method::Clustered` or `Method::Zbin` when the tiled pass shades this frame's lights
    /// (`tiles::frame_rule`), with the clustered lists built on the CPU or the GPU's job.
    pub tiled: Option<Method>,
    pub clusters: Option<super::tiled::ClusterBuild>,
    /// The z-binned frame's sorted lights, bins and rectangles (`Method::Zbin`).
    pub zbins: Option<super::zbin::ZBinJob>,
}

impl FramePlan {
    /// Plans the lights and the object draws of `scene`; fills the objects' light-list fields
    /// in `records`. `bounds` is each mesh's bounding sphere (model space).
    pub fn new(
        scene: &Scene,
        records: &mut FrameRecords,
        bounds: &[(DVec3, f64)],
        volumes: &Volumes,
        view: &PlanView,
    ) -> Self {
        Self::reusing(scene, records, bounds, volumes, view, Vec::new())
    }

    /// [`FramePlan::new`] with the light plans written into `lights` (emptied first; its
    /// allocation is kept, as [`FrameRecords::reusing`] keeps the records').
    pub fn reusing(
        scene: &Scene,
        records: &mut FrameRecords,
        bounds: &[(DVec3, f64)],
        volumes: &Volumes,
        view: &PlanView,
        mut lights: Vec<LightPlan>,
    ) -> Self {
        let radii = SphereRadii::of(&volumes.sphere);
        // On one thread: split over two, the plans cost more CPU time in all (0.2-0.4 ms more
        // at 16,384 lights: the helper's spawn, and the half it plans read from the other
        // core's cache), which is what the CPU budget counts (`cputime`).
        lights.clear();
        lights.extend(records.lights.iter().map(|l| {
            plan_sphere_ahead(l, radii, &volumes.sphere, view).unwrap_or_else(|| plan_light(l, volumes, view))
        }));
        // The frame-level rule first: lights it hands to the tiled pass are left out of the
        // batches.
        let tiled = super::tiled::frame_rule(&mut lights, view);
        let clusters = (tiled == Some(Method::Clustered)).then(|| {
            use super::tiled::{cluster_job, cluster_lists, ClusterBuild};
            match view.cluster_build {
                crate::renderer::settings::ClusterBuilder::Cpu => {
                    ClusterBuild::Cpu(cluster_lists(&records.lights, &lights, view))
                }
                // The GPU lays out the default grid, without a cap.
                crate::renderer::settings::ClusterBuilder::Gpu if !view.grid.is_default() => {
                    ClusterBuild::Cpu(cluster_lists(&records.lights, &lights, view))
                }
                crate::renderer::settings::ClusterBuilder::Gpu => {
                    // A light the GPU could not assign within the adapter's loop limit (gallivm's):
                    // the CPU builds this frame's lists (the stats' `lists_on_gpu` says so).
                    let job = cluster_job(&records.lights, &lights, view);
                    if view.loop_limit.is_none_or(|l| job.longest <= super::tiled::gpu_loop_budget(l)) {
                        ClusterBuild::Gpu(job)
                    } else {
                        ClusterBuild::Cpu(cluster_lists(&records.lights, &lights, view))
                    }
                }
            }
        });
        let zbins = (tiled == Some(Method::Zbin)).then(|| super::zbin::zbin_job(&records.lights, &lights, view));
        let (draws, light_lists, forward) =
            plan_draws(scene, &mut records.objects, &mut records.camera, bounds, &lights, view);
        let batches = LightBatches::new(&lights, &records.lights, volumes, view);
        Self { lights, draws, light_lists, forward, batches, tiled, clusters, zbins }
    }

    /// The bounding meshes this frame draws ("sphere", "cone"): volume kinds are drawn only for
    /// the light types present (a scene without narrow spots draws no cone).
    pub fn volume_meshes_drawn(&self) -> Vec<String> {
        let drawn = |kind| {
            self.lights
                .iter()
                .any(|p| p.volume == kind && super::methods::row(p.method).covers == super::methods::Covers::Volume)
        };
        [VolumeKind::Sphere, VolumeKind::Cone].into_iter().filter(|&k| drawn(k)).map(|k| k.name().to_string()).collect()
    }
}

/// xorshift64 from `seed`: the culling tests' fixed pseudo-random sequence.
#[cfg(test)]
pub(crate) fn xorshift64(mut seed: u64) -> impl FnMut() -> u64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    }
}

#[cfg(test)]
impl PlanView {
    /// The view the tests plan against: `cam`'s projection over `size` in `mode`, the rest as a
    /// default frame has it.
    pub(crate) fn for_test(cam: &crate::scene::Camera, size: (u32, u32), mode: CullingMode) -> PlanView {
        PlanView {
            proj: cam.projection(size.0 as f64 / size.1 as f64, false).as_mat4(),
            near: cam.near as f32,
            far: cam.far as f32,
            size,
            mode,
            depth_clamp: true,
            forward_lights: ForwardLights::Tiled,
            light_batching: true,
            cluster_build: crate::renderer::options::culling::ClusterBuilder::Cpu,
            grid: Default::default(),
            object_cap: (0, Default::default()),
            loop_limit: None,
            near_fullscreen: false,
            front_to_back: false,
            sort_blended: true,
            prepass_models: None,
            costs: Default::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::footprint::clip_to_screen;
    use super::*;
    use crate::renderer::volumes::VolumeMesh;
    use crate::scene::Camera;

    /// Pixels whose centre's view ray meets the mesh beyond the near plane (what its back faces
    /// rasterise), counted ray by ray on the CPU.
    fn pixels_hit(placed: &[Vec3], indices: &[u32], proj: Mat4, near: f32, (w, h): (u32, u32)) -> u32 {
        let centre = placed.iter().copied().sum::<Vec3>() / placed.len() as f32;
        let planes: Vec<(Vec3, f32)> = indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| placed[i as usize]);
                let n = (b - a).cross(c - a);
                let n = if n.dot(a - centre) < 0.0 { -n } else { n };
                (n, n.dot(a))
            })
            .collect();
        let mut hit = 0;
        for y in 0..h {
            for x in 0..w {
                let ndc = Vec2::new(2.0 * (x as f32 + 0.5) / w as f32 - 1.0, 1.0 - 2.0 * (y as f32 + 0.5) / h as f32);
                // The point at view depth t is d * t.
                let d = Vec3::new(ndc.x / proj.x_axis.x, ndc.y / proj.y_axis.y, -1.0);
                let (mut t0, mut t1) = (near, f32::INFINITY);
                for &(n, k) in &planes {
                    let nd = n.dot(d);
                    if nd > 0.0 {
                        t1 = t1.min(k / nd);
                    } else if nd < 0.0 {
                        t0 = t0.max(k / nd);
                    } else if k < 0.0 {
                        t1 = f32::NEG_INFINITY;
                    }
                }
                hit += (t0 <= t1) as u32;
            }
        }
        hit
    }

    #[test]
    fn the_footprint_is_the_share_of_pixels_whose_rays_meet_the_clipped_volume() {
        let size = (320u32, 180u32);
        let cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        let proj = cam.projection(size.0 as f64 / size.1 as f64, false).as_mat4();
        let near = cam.near as f32;
        let sphere = VolumeMesh::sphere(1);
        let cone = VolumeMesh::cone(12);
        let down = Vec3::new(0.3, -1.0, -0.2).normalize();
        // (mesh, position, radius, direction, tan of the cone's angle, what)
        let cases = [
            (&sphere, Vec3::new(0.0, 0.0, -10.0), 3.0, down, 0.0, "ahead"),
            (&sphere, Vec3::new(0.5, -0.3, 1.0), 3.0, down, 0.0, "holds the eye"),
            (&sphere, Vec3::new(3.5, 0.0, 0.0), 3.0, down, 0.0, "beside, crossing near"),
            (&sphere, Vec3::new(-2.0, 0.3, 0.3), 1.9, down, 0.0, "left, crossing near"),
            (&sphere, Vec3::new(1.0, -2.0, -1.5), 2.6, down, 0.0, "below, crossing near"),
            (&sphere, Vec3::new(20.0, 0.0, -5.0), 3.0, down, 0.0, "off to the side"),
            (&cone, Vec3::new(-1.0, 2.0, -1.0), 6.0, down, 0.6, "a cone crossing near"),
            (&cone, Vec3::new(0.0, 1.0, -12.0), 8.0, down, 0.5, "a cone ahead"),
        ];
        let total = (size.0 * size.1) as f32;
        for (mesh, pos, radius, dir, tan, what) in cases {
            let placed: Vec<Vec3> =
                mesh.vertices.iter().map(|v| volumes::place(*v, pos, radius, dir, tan, 0.0)).collect();
            let share = screen_area(&clipped_footprint(&placed, &mesh.indices, proj, near)) / 4.0;
            let counted = pixels_hit(&placed, &mesh.indices, proj, near, size) as f32 / total;
            println!("{what}: footprint {share:.5}, rays {counted:.5}");
            // Only pixels on the footprint's outline can differ (pixel centres against area).
            assert!((share - counted).abs() <= 0.002, "{what}: footprint {share}, rays {counted}");
        }
    }

    #[test]
    fn a_tiny_near_plane_brings_the_f32_far_clip_in_front_of_the_far_plane() {
        // The oracle's case: standard depth, near 2.3e-6, far 32; a light whose volume reaches
        // 26 deep, well inside the 1% margin, may still be clipped by the f32 far test.
        let mut cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        cam.far = 31.7;
        let mesh = VolumeMesh::sphere(1);
        let light = point(Vec3::new(0.0, 0.0, -17.7), 7.86);
        for (near, crosses) in [(2.25e-6, true), (0.1, false)] {
            cam.near = near;
            let view = PlanView::for_test(&cam, (64, 36), CullingMode::StencilTwoPass);
            let hull = plan_hull(&light, &mesh, &view);
            assert_eq!(hull.crosses_far, crosses, "near {near}");
            if crosses {
                let fast = plan_sphere_ahead(&light, SphereRadii::of(&mesh), &mesh, &view);
                assert!(fast.is_none(), "the analytic plan must leave it to the hull");
            }
            let unclamped = PlanView { depth_clamp: false, ..view };
            let expected = if crosses { Method::Fullscreen } else { Method::StencilTwoPass };
            assert_eq!(plan_hull(&light, &mesh, &unclamped).method, expected, "near {near}");
        }
    }

    #[test]
    fn a_tiny_near_plane_lets_the_f32_far_clip_keep_what_lies_beyond_the_far_plane() {
        // The oracle's case: standard depth, near 6e-9, far 0.018; a light wholly beyond the far
        // plane still lit a floor the clipper kept 0.42 away. Planned off screen, it was left
        // out of the forward paths' lists.
        let mut cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        cam.far = 0.018;
        let mesh = VolumeMesh::sphere(1);
        let light = point(Vec3::new(0.0, 0.0, -0.1), 0.05);
        for (near, reversed, kept) in [(6e-9, false, true), (1e-3, false, false), (6e-9, true, false)] {
            cam.near = near;
            let mut view = PlanView::for_test(&cam, (64, 36), CullingMode::Auto);
            view.proj = cam.projection(64.0 / 36.0, reversed).as_mat4();
            let plan = plan_hull(&light, &mesh, &view);
            assert_eq!(plan.screen_rect.is_some(), kept, "near {near}, reversed {reversed}");
            assert_eq!(plan.method == Method::Skipped, !kept, "near {near}, reversed {reversed}");
        }
    }

    #[test]
    fn a_volume_within_the_f32_near_clips_rounding_stays_on_screen() {
        // Wholly in front of the near plane but within z's rounding there (a step of 10 is
        // 9.5e-7), the volume may light what the clip keeps; a centimetre in front, not.
        let mut cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        let mesh = VolumeMesh::sphere(1);
        cam.near = 10.0;
        cam.far = 1000.0;
        for reversed in [false, true] {
            let mut view = PlanView::for_test(&cam, (64, 36), CullingMode::Auto);
            view.proj = cam.projection(64.0 / 36.0, reversed).as_mat4();
            for (depth, radius, kept) in [(10.0 - 3e-6, 1e-6, true), (10.0 - 1e-2, 1e-3, false)] {
                let light = point(Vec3::new(0.0, 0.0, -depth), radius);
                let plan = plan_hull(&light, &mesh, &view);
                assert_eq!(plan.screen_rect.is_some(), kept, "depth {depth}, reversed {reversed}");
                // The analytic plan, where it decides, agrees (it leaves the first to the hull).
                if let Some(fast) = plan_sphere_ahead(&light, SphereRadii::of(&mesh), &mesh, &view) {
                    assert_eq!(fast.screen_rect.is_some(), kept, "depth {depth}, reversed {reversed}");
                }
            }
        }
    }

    fn point(pos: Vec3, radius: f32) -> LightRecord {
        let mut l = LightRecord::in_view(
            &Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z),
            &crate::scene::Light::Point(crate::scene::PointLight {
                position: glam::DVec3::ZERO,
                color: Vec3::ONE,
                intensity: 1.0,
                radius,
                cast_shadows: true,
                cookie: None,
                mask: crate::scene::ALL_LAYERS,
            }),
            0.0,
        );
        l.position = pos.into();
        l
    }

    #[test]
    fn the_analytic_share_is_the_share_of_pixels_whose_rays_meet_the_volume() {
        // Spheres wholly in front of the eye and on screen: the analytic path's share against a
        // per-pixel ray count of the mesh, as the hull is held above (same bound).
        let size = (320u32, 180u32);
        let cam = Camera::looking_at(glam::DVec3::ZERO, glam::DVec3::NEG_Z);
        let view = PlanView::for_test(&cam, size, CullingMode::Auto);
        let total = (size.0 * size.1) as f32;
        let mut taken = 0;
        for subdivisions in 0..=2 {
            let mesh = VolumeMesh::sphere(subdivisions);
            let radii = SphereRadii::of(&mesh);
            for (pos, radius) in [
                (Vec3::new(0.0, 0.0, -30.0), 3.0),
                (Vec3::new(4.0, -2.0, -25.0), 2.5),
                (Vec3::new(-6.0, 3.0, -40.0), 5.0),
                (Vec3::new(1.0, 1.0, -12.0), 1.0),
                (Vec3::new(0.0, 0.0, -10.0), 3.0),
                // Partly on screen: the silhouette clipped to the screen.
                (Vec3::new(25.0, 0.0, -25.0), 3.0),
                (Vec3::new(0.0, -14.0, -25.0), 2.0),
                (Vec3::new(-24.0, 13.5, -25.0), 3.0),
                (Vec3::new(9.0, 5.0, -10.0), 1.5),
            ] {
                let light = point(pos, radius);
                let Some(fast) = plan_sphere_ahead(&light, radii, &mesh, &view) else { continue };
                taken += 1;
                let placed: Vec<Vec3> =
                    mesh.vertices.iter().map(|v| volumes::place(*v, pos, radius, Vec3::NEG_Z, 0.0, 0.0)).collect();
                let counted = pixels_hit(&placed, &mesh.indices, view.proj, view.near, size) as f32 / total;
                let hull = plan_hull(&light, &mesh, &view);
                println!(
                    "{subdivisions} {pos} r {radius}: analytic {:.5}, hull {:.5}, rays {counted:.5}",
                    fast.screen_share, hull.screen_share
                );
                assert!((fast.screen_share - counted).abs() <= 0.002, "{pos}: {} vs rays {counted}", fast.screen_share);
                assert_eq!(fast.method, hull.method, "{pos}");
                // The analytic rectangle holds the hull's.
                let ((a0, a1), (h0, h1)) = (fast.screen_rect.unwrap(), hull.screen_rect.unwrap());
                assert!(a0.cmple(h0 + 1e-5).all() && a1.cmpge(h1 - 1e-5).all(), "{pos}: {a0} {a1} vs {h0} {h1}");
            }
        }
        assert!(taken >= 20, "the analytic path took only {taken} cases");
    }

    #[test]
    fn the_analytic_plan_agrees_with_the_hull_on_demo_with_sixteen_thousand_lights() {
        let scene = crate::scene::builtin::demo(16_384, 0.0);
        let size = (1280u32, 720u32);
        let view = PlanView::for_test(&scene.camera, size, CullingMode::Auto);
        let mesh = VolumeMesh::sphere(1);
        let radii = SphereRadii::of(&mesh);
        let rot = scene.camera.rotation();
        let (mut taken, mut worst, mut flipped, mut skipped) = (0, 0f32, 0, 0);
        for l in scene.lights.iter() {
            let light = LightRecord::in_view_rotated(&scene.camera, rot, l, 0.0);
            if VolumeKind::of(&light) != VolumeKind::Sphere {
                continue;
            }
            let Some(fast) = plan_sphere_ahead(&light, radii, &mesh, &view) else { continue };
            taken += 1;
            let hull = plan_hull(&light, &mesh, &view);
            worst = worst.max((fast.screen_share - hull.screen_share).abs());
            skipped += (fast.method == Method::Skipped) as usize;
            flipped += (fast.method != hull.method) as usize;
            if let (Some((a0, a1)), Some((h0, h1))) = (fast.screen_rect, hull.screen_rect) {
                assert!(a0.cmple(h0 + 1e-5).all() && a1.cmpge(h1 - 1e-5).all());
            }
            if hull.screen_rect.is_some() {
                assert!(fast.screen_rect.is_some(), "a light the hull sees on screen is planned off screen");
            }
        }
        println!("{taken} lights planned analytically ({skipped} off screen), worst share difference {worst:.5}, {flipped} methods differ");
        assert!(taken > 16_000, "the analytic path took only {taken} of 16,384 lights");
        assert!(worst <= 0.002, "share differs from the hull's by {worst}");
        assert_eq!(flipped, 0, "{flipped} of {taken} methods differ from the hull's");
    }

    /// The closed form against a fine polygon clipped to the screen: random rotated ellipses
    /// cut by one side or two opposite sides agree to 1e-4 of their area (the 4,096-corner
    /// polygon, widened to the ellipse's area, is within 1e-6 of it; the clip runs in f32), and
    /// ellipses cut near a corner are left to the polygon.
    #[test]
    fn the_closed_form_share_of_a_partly_visible_ellipse_is_its_clipped_area() {
        let mut next = xorshift64(0x2545_f491_4f6c_dd1d);
        let mut rnd = || (next() >> 11) as f64 / (1u64 << 53) as f64;
        const N: usize = 4096;
        let widen = {
            let step = std::f64::consts::TAU / N as f64;
            (step / step.sin()).sqrt()
        };
        let (mut checked, mut corners) = (0, 0);
        for _ in 0..2000 {
            let (a, b) = (0.02 + rnd(), 0.02 + rnd());
            let t = std::f64::consts::PI * rnd();
            let c = DVec2::new(3.0 * rnd() - 1.5, 3.0 * rnd() - 1.5);
            let (ct, st) = (t.cos(), t.sin());
            let half =
                DVec2::new((a * a * ct * ct + b * b * st * st).sqrt(), (a * a * st * st + b * b * ct * ct).sqrt());
            let area = std::f64::consts::PI * a * b;
            let mut poly: Vec<Vec2> = (0..N)
                .map(|k| {
                    let s = std::f64::consts::TAU * k as f64 / N as f64;
                    let (x, y) = (a * widen * s.cos(), b * widen * s.sin());
                    Vec2::new((c.x + x * ct - y * st) as f32, (c.y + x * st + y * ct) as f32)
                })
                .collect();
            poly.resize(N + 4, Vec2::ZERO);
            let mut scratch = vec![Vec2::ZERO; N + 4];
            let clipped = clip_to_screen(&mut poly, &mut scratch, N) as f64;
            match ellipse_on_screen((c - half, c + half), area) {
                Some(closed) => {
                    checked += 1;
                    assert!(
                        (closed as f64 - clipped).abs() <= 1e-4 * area + 1e-6,
                        "ellipse at {c} axes {a} {b} angle {t}: closed form {closed}, clipped polygon {clipped}"
                    );
                }
                None => {
                    // Only where a vertical and a horizontal side both cut it.
                    let cuts = |c: f64, h: f64| c + h > 1.0 || c - h < -1.0;
                    assert!(cuts(c.x, half.x) && cuts(c.y, half.y), "refused an ellipse at {c} half {half}");
                    corners += 1;
                }
            }
        }
        assert!(checked > 500 && corners > 100, "{checked} checked, {corners} near corners");
    }

    #[test]
    fn lists_past_the_paired_loops_reach_are_warned_of() {
        let max = FORWARD_LIST_MAX;
        assert!(long_forward_list_warnings(Some(max), None).is_empty());
        assert_eq!(long_forward_list_warnings(Some(max + 1), None).len(), 1);
        let blended = |object: u32, tile: u32, tiles: u64| ForwardStats {
            longest_object_list: object,
            longest_tile_list: tile,
            tiles,
            ..Default::default()
        };
        // A fragment walks the shorter of its object's and its tile's list.
        assert!(long_forward_list_warnings(None, Some(&blended(max + 1, max, 4))).is_empty());
        assert_eq!(long_forward_list_warnings(None, Some(&blended(max + 1, max + 1, 4))).len(), 1);
        // Without tiles, the object lists alone.
        assert_eq!(long_forward_list_warnings(None, Some(&blended(max + 1, 0, 0))).len(), 1);
        assert_eq!(long_forward_list_warnings(Some(max + 1), Some(&blended(max + 1, 0, 0))).len(), 2);
    }

    #[test]
    fn the_hull_and_the_screen_clip_measure_areas() {
        // A square twice the screen's size covers it all; a triangle inside keeps its area.
        let big = [Vec2::new(-2.0, -2.0), Vec2::new(2.0, -2.0), Vec2::new(2.0, 2.0), Vec2::new(-2.0, 2.0)];
        assert!((screen_area(&big) - 4.0).abs() < 1e-6);
        let tri = [Vec2::new(0.0, 0.0), Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.5), Vec2::new(0.1, 0.1)];
        assert!((screen_area(&tri) - 0.125).abs() < 1e-6);
        // Half outside on the right.
        let half = [Vec2::new(0.5, -0.5), Vec2::new(1.5, -0.5), Vec2::new(1.5, 0.5), Vec2::new(0.5, 0.5)];
        assert!((screen_area(&half) - 0.5).abs() < 1e-6);
        assert_eq!(screen_area(&[Vec2::ZERO, Vec2::ONE]), 0.0);
        assert_eq!(screen_area(&[Vec2::NAN, Vec2::ZERO]), 0.0);
    }
}
