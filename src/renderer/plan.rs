//! What the CPU decides before any pass is recorded: per light, the culling method that draws
//! it (and the facts that decide it: its volume, the planes it crosses, its screen share); per
//! object, whether it goes into the G-buffer or is shaded forward, in which order, and which
//! lights reach it.

use super::records::{CameraRecord, FrameRecords, LightRecord};
use super::settings::{CullingMode, ForwardLights};
use super::stats::ForwardStats;
use super::volumes::{self, VolumeKind, Volumes};
use crate::scene::{AlphaMode, Scene};
use glam::{DVec3, Mat4, Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Above this share of the screen, `auto` draws a light full-screen (see [`plan_light`]).
pub const AUTO_FULLSCREEN_SHARE: f32 = 0.5;
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
    /// `auto` only: the volume lies outside the view frustum and is not drawn.
    Skipped,
}

impl Method {
    /// The name in stats, the viewer and the bench: the culling mode's name, or `skipped`.
    pub fn name(self) -> String {
        match CullingMode::ALL.into_iter().find(|m| m.method() == Some(self)) {
            Some(m) => m.name().to_string(),
            None => "skipped".into(),
        }
    }
}

impl CullingMode {
    /// The one method a fixed mode draws every light with; `None` for `auto`.
    pub fn method(self) -> Option<Method> {
        match self {
            CullingMode::Fullscreen => Some(Method::Fullscreen),
            CullingMode::Volume => Some(Method::Volume),
            CullingMode::StencilTwoPass => Some(Method::StencilTwoPass),
            CullingMode::StencilInvert => Some(Method::StencilInvert),
            CullingMode::StencilReplace => Some(Method::StencilReplace),
            CullingMode::Auto => None,
        }
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
    /// Share of the screen covered by the volume's projected bounding rectangle.
    pub screen_share: f32,
    /// That rectangle in normalised device coordinates (min, max), not clipped to the screen;
    /// the whole screen when the volume crosses the near plane, `None` when it is off screen.
    /// It bounds every visible point the light can reach (the volume circumscribes the light).
    pub screen_rect: Option<(Vec2, Vec2)>,
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
}

/// Which mesh bounds the light, where it sits against the near and far planes, and how much of
/// the screen it covers; then which method draws it.
///
/// `auto`'s rule, per light: outside the frustum, skip it; covering more than
/// [`AUTO_FULLSCREEN_SHARE`] of the screen, draw it full-screen (rasterising its faces buys
/// nothing); a screen rectangle of at least [`AUTO_STENCIL_MIN_PIXELS`], seed 000's two-pass
/// stencil (the marking draw saves thousands of shaded fragments); else the plain volume (one
/// draw, back faces, GreaterEqual), since for small volumes the extra marking draw costs more
/// than the fragments it saves. Thresholds from `lampshade bench --only culling` on lavapipe at
/// 320x180, 640x360 and 1280x720 (README, "Measurements").
pub fn plan_light(light: &LightRecord, volumes: &Volumes, view: &PlanView) -> LightPlan {
    let volume = VolumeKind::of(light);
    let pos = Vec3::from(light.position);
    let dir = Vec3::from(light.direction);
    let (near, far) = (view.near, view.far);
    let mut crosses_near = false;
    let mut crosses_far = false;
    // Clip-space side planes: a convex volume with every vertex outside one of them is outside
    // the frustum.
    let mut outside = [true; 4];
    let (mut all_before_near, mut all_beyond_far) = (true, true);
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for v in &volumes.mesh(volume).vertices {
        let p = volumes::place(*v, pos, light.radius, dir, light.tan_outer);
        let dist = -p.z;
        crosses_near |= dist <= near * 1.01;
        crosses_far |= dist >= far * 0.99;
        all_before_near &= dist < near;
        all_beyond_far &= dist > far;
        let c = view.proj * p.extend(1.0);
        for (k, d) in [c.w - c.x, c.w + c.x, c.w - c.y, c.w + c.y].into_iter().enumerate() {
            outside[k] &= d < 0.0;
        }
        if c.w > 0.0 {
            let n = Vec2::new(c.x, c.y) / c.w;
            lo = lo.min(n);
            hi = hi.max(n);
        }
    }
    let off_screen = outside.iter().any(|&o| o)
        || all_before_near
        || all_beyond_far
        || !(crosses_near || lo.x < 1.0 && lo.y < 1.0 && hi.x > -1.0 && hi.y > -1.0);
    let crosses_near = crosses_near && !off_screen;
    let screen_share = if off_screen {
        0.0
    } else if crosses_near {
        1.0
    } else {
        let a = (hi.min(Vec2::ONE) - lo.max(-Vec2::ONE)).max(Vec2::ZERO);
        a.x * a.y / 4.0
    };
    let pixels = screen_share * (view.size.0 * view.size.1) as f32;
    let method = if crosses_far && !view.depth_clamp && !(view.mode == CullingMode::Auto && off_screen) {
        // Without depth clamp the far side would be clipped away: no volume method is correct,
        // so the light is drawn full-screen.
        Method::Fullscreen
    } else if let Some(fixed) = view.mode.method() {
        fixed
    } else if off_screen {
        Method::Skipped
    } else if screen_share > AUTO_FULLSCREEN_SHARE {
        Method::Fullscreen
    } else if pixels >= AUTO_STENCIL_MIN_PIXELS {
        Method::StencilTwoPass
    } else {
        Method::Volume
    };
    let screen_rect = if off_screen {
        None
    } else if crosses_near {
        Some((-Vec2::ONE, Vec2::ONE))
    } else {
        Some((lo, hi))
    };
    LightPlan { method, volume, crosses_near, crosses_far, screen_share, screen_rect }
}

/// One object draw: (object, pipeline index within its pass, material).
pub type Draw = (usize, usize, usize);

/// Objects of one frame by how they are drawn.
#[derive(Default)]
pub struct DrawLists {
    /// Into the G-buffer: pipeline index from `passes::gbuffer::pipeline_index`.
    pub gbuffer: Vec<Draw>,
    /// Forward, blended, sorted back to front; pipeline index 1 for two-sided.
    pub forward: Vec<Draw>,
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
        let lights: Vec<LightPlan> = records.lights.iter().map(|l| plan_light(l, volumes, view)).collect();
        let (draws, light_lists, forward) =
            plan_draws(scene, &mut records.objects, &mut records.camera, bounds, &lights, view);
        Self { lights, draws, light_lists, forward }
    }

    /// The bounding meshes this frame draws ("sphere", "cone"): volume kinds are drawn only for
    /// the light types present (a scene without narrow spots draws no cone).
    pub fn volume_meshes_drawn(&self) -> Vec<String> {
        let drawn = |kind| {
            self.lights.iter().any(|p| p.volume == kind && !matches!(p.method, Method::Fullscreen | Method::Skipped))
        };
        [VolumeKind::Sphere, VolumeKind::Cone].into_iter().filter(|&k| drawn(k)).map(|k| k.name().to_string()).collect()
    }
}

/// Size in pixels of the forward pass's screen tiles.
pub const FORWARD_TILE: u32 = 16;

/// Sorts the objects into the G-buffer pass (opaque, masked) and the forward pass (blended,
/// back to front by the view depth of their bounding sphere's centre), and builds the forward
/// pass's light lists (see [`ForwardLights`]):
/// - per blended object, the lights whose sphere reaches its bounding sphere (`tiled` also
///   drops lights off screen; `all` lists every light);
/// - with `tiled`, per [`FORWARD_TILE`]-pixel screen tile, the lights of those lists whose
///   screen rectangle ([`LightPlan::screen_rect`], widened by a pixel against rounding) covers
///   the tile; `camera.forward_tiles` tells the shader where they are.
///
/// A light is left out of a list only where it cannot reach: every list is in light order, so
/// a fragment sums the same non-zero terms in the same order whichever list it walks.
fn plan_draws(
    scene: &Scene,
    objects: &mut [super::records::ObjectRecord],
    camera: &mut CameraRecord,
    bounds: &[(DVec3, f64)],
    plans: &[LightPlan],
    view: &PlanView,
) -> (DrawLists, Vec<u32>, Option<ForwardStats>) {
    let mode = view.forward_lights;
    let mut lists = Vec::new();
    let mut draws = DrawLists::default();
    let mut forward: Vec<(f64, usize, usize, usize)> = Vec::new();
    let mut stats = ForwardStats { lights: mode, ..Default::default() };
    // Lights in at least one blended object's list: the only ones a tile needs.
    let mut reaches_glass = vec![false; scene.lights.len()];
    for (i, o) in scene.objects.iter().enumerate() {
        let m = &scene.materials[o.material];
        let topology = scene.meshes.get(o.mesh).map_or(Default::default(), |mesh| mesh.topology);
        if topology != crate::scene::Topology::Triangles {
            // Lines and points go into the G-buffer whatever their alpha mode (the importer
            // warns about blended ones).
            let masked = matches!(m.alpha_mode, AlphaMode::Mask { .. });
            let p = super::passes::gbuffer::topology_pipeline_index(topology, masked, m.double_sided);
            draws.gbuffer.push((i, p, o.material));
            continue;
        }
        match m.alpha_mode {
            AlphaMode::Blend => {
                let (c, r) = bounds.get(o.mesh).copied().unwrap_or((DVec3::ZERO, 0.0));
                let centre = o.transform.transform_point3(c);
                let scale = (0..3).map(|k| o.transform.col(k).truncate().length()).fold(0.0, f64::max);
                let radius = r * scale;
                let first = lists.len() as u32;
                for (k, l) in scene.lights.iter().enumerate() {
                    let keep = match mode {
                        ForwardLights::All => true,
                        ForwardLights::Object => (l.position() - centre).length() < radius + l.radius() as f64,
                        ForwardLights::Tiled => {
                            plans.get(k).is_some_and(|p| p.screen_rect.is_some())
                                && (l.position() - centre).length() < radius + l.radius() as f64
                        }
                    };
                    if keep {
                        lists.push(k as u32);
                        reaches_glass[k] = true;
                    }
                }
                let count = lists.len() as u32 - first;
                objects[i].info[1] = first;
                objects[i].info[2] = count;
                stats.objects += 1;
                stats.object_list_entries += count as u64;
                stats.longest_object_list = stats.longest_object_list.max(count);
                let depth = scene.camera.to_view(centre).z;
                forward.push((depth, i, m.double_sided as usize, o.material));
            }
            mode => {
                let masked = matches!(mode, AlphaMode::Mask { .. });
                draws.gbuffer.push((i, super::passes::gbuffer::pipeline_index(masked, m.double_sided), o.material));
            }
        }
    }
    camera.forward_tiles = [0; 4];
    if mode == ForwardLights::Tiled && !forward.is_empty() {
        let (w, h) = view.size;
        let (tx, ty) = (w.div_ceil(FORWARD_TILE), h.div_ceil(FORWARD_TILE));
        let mut tiles: Vec<Vec<u32>> = vec![Vec::new(); (tx * ty) as usize];
        for (k, p) in plans.iter().enumerate() {
            let Some((lo, hi)) = p.screen_rect.filter(|_| reaches_glass[k]) else { continue };
            // NDC to pixels (y down), widened by a pixel; a fragment's centre lies inside.
            let px = |x: f32| ((x + 1.0) * 0.5 * w as f32).floor();
            let py = |y: f32| ((1.0 - y) * 0.5 * h as f32).floor();
            let tile = |v: f32, max: u32| (v.max(0.0) as u32).min(max - 1) / FORWARD_TILE;
            let (x0, x1) = (px(lo.x) - 1.0, px(hi.x) + 1.0);
            let (y0, y1) = (py(hi.y) - 1.0, py(lo.y) + 1.0);
            if x1 < 0.0 || y1 < 0.0 || x0 >= w as f32 || y0 >= h as f32 {
                continue;
            }
            for y in tile(y0, h)..=tile(y1, h) {
                for x in tile(x0, w)..=tile(x1, w) {
                    tiles[(y * tx + x) as usize].push(k as u32);
                }
            }
        }
        let header = lists.len() as u32;
        let mut first = header + 2 * tiles.len() as u32;
        for t in &tiles {
            lists.extend([first, t.len() as u32]);
            first += t.len() as u32;
            stats.tile_list_entries += t.len() as u64;
            stats.longest_tile_list = stats.longest_tile_list.max(t.len() as u32);
        }
        for t in &tiles {
            lists.extend_from_slice(t);
        }
        stats.tiles = tiles.len() as u64;
        camera.forward_tiles = [FORWARD_TILE, tx, ty, header];
    }
    // View space looks down -z: the farthest has the most negative z and is drawn first.
    forward.sort_by(|a, b| a.0.total_cmp(&b.0));
    draws.forward = forward.into_iter().map(|(_, i, p, m)| (i, p, m)).collect();
    // Fewer pipeline and material switches in the G-buffer pass.
    draws.gbuffer.sort_by_key(|&(_, p, m)| (p, m));
    let stats = (!draws.forward.is_empty()).then_some(stats);
    (draws, lists, stats)
}
