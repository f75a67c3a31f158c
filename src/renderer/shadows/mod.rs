//! Shadows (seed 002: "shadow maps work very well with deferred shading"): which
//! lights cast this frame, where each one's tiles lie in the one shadow atlas, and how a
//! view-space point maps into a tile (`ShadowTile`). The technique is this folder:
//! - `mod.rs`: the options ([`ShadowMode`], [`ShadowFilter`], [`ShadowCube`]) and the plan;
//! - [`pass`] with `casters.wgsl`: the shadow pass, drawing the casters into the tiles;
//! - `lookup.wgsl`: the lookups; every place that shades a light reads the tiles through one
//!   WGSL function, `ls_shadow`, and the sun through `ls_sun_shadow`;
//! - [`atlas_view`] with `atlas_view.wgsl`: the viewer's image of the atlas.
//!
//! - **The atlas:** one Depth32Float texture whose side is the largest power of two within the
//!   byte budget (`Settings::shadow_budget_mb`) and the device's limit. Tiles are power-of-two
//!   squares, packed largest first along the atlas's Morton (Z) order, which leaves no gap.
//! - **Resolution:** the sun's cascades take a quarter of the side each; a spot's tile (and each
//!   of a point light's six faces) follows the light's screen footprint,
//!   `next_pow2(sqrt(screen_share x pixels))` between [`MIN_TILE`] and a quarter of the side.
//!   Lights are served sun first, then by footprint; when the atlas is full a light's tiles
//!   are halved down to [`MIN_TILE`], and past that it falls back to unshadowed (counted).
//!   Lights off screen (no footprint) are not given a tile (counted too).
//! - **Depth:** linear in distance (the fragment shader writes -z / far), so the biases are in
//!   world units: each is a number of texels, times a texel's world size at the receiver.
//! - **Border:** each tile's projection leaves [`BORDER`] texels on every side beyond the
//!   frustum the light needs, so filter taps near a tile's (or a cube face's) edge read depths
//!   rendered for them, never a neighbour's: no seams between a point light's faces.
//! - **Point lights** (and spots wider than [`CUBE_SPOT_ANGLE`]): seed 002's "virtual shadow
//!   depth cube" — six 90° faces (plus the border) unrolled into 2D tiles of the atlas; the
//!   face is picked from the major axis of the light-to-surface vector (view-space axes).
//! - **Cube array** (`--shadow-cube array`): the same six faces as layers of one
//!   Depth32Float cube-array texture instead of atlas tiles, sampled by direction with the
//!   hardware's (seamless) cube filtering, so no border. See [`ShadowCube`] and
//!   [`cube_array_fit`] for the size rule.
//! - **Cube indirection** (`--shadow-cube indirect`): the unrolled tiles, but the face and its
//!   coordinates come from one texture fetch of a shared indirection cube (seed 002's "G16R16
//!   cubemap efficiently maps XYZ->ST") instead of the major-axis pick; see
//!   [`indirection_error`] for what that costs in accuracy.
//! - **The sun:** 1-4 cascades over the view frustum up to the farthest scene point; split
//!   distances lambda x logarithmic + (1 - lambda) x uniform; each cascade an orthographic tile
//!   around the bounding sphere of its slice, deep enough to hold every object.

pub mod atlas_view;
pub mod cost;
pub mod cube;
pub mod pass;
pub mod scratch;

use super::records::{ShadowParams, ShadowTile, NO_SHADOW};
pub use crate::renderer::kit::features::ShadowCode;
pub use crate::renderer::options::shadows::{ShadowCube, ShadowFilter, ShadowFormat, ShadowMode, ShadowOptions};
use crate::scene::{Light, Scene};
pub use cost::{ShadowCost, COSTLY_PASSES, COSTLY_TRIANGLES};
pub use cube::{
    indirection_decode, indirection_error, indirection_side, indirection_texels, MAX_INDIRECTION, MIN_TILE,
};
use glam::{DMat3, DMat4, DVec3};
use serde::{Deserialize, Serialize};

impl ShadowFilter {
    /// Texels from the lookup point whose depths the kernel reads: the hardware's 2x2 reaches 1,
    /// 3x3 of them 1 texel apart 2, the Poisson disc of radius 2 texels 3.
    pub fn reach(self) -> u32 {
        self as u32 + 1
    }
}

impl ShadowFormat {
    pub fn texture(self) -> wgpu::TextureFormat {
        match self {
            ShadowFormat::Depth32 => wgpu::TextureFormat::Depth32Float,
            ShadowFormat::Depth24 => wgpu::TextureFormat::Depth24Plus,
            ShadowFormat::Depth16 => wgpu::TextureFormat::Depth16Unorm,
        }
    }

    /// Bytes a texel, for the budget.
    pub fn bytes(self) -> u64 {
        match self {
            ShadowFormat::Depth16 => 2,
            ShadowFormat::Depth32 | ShadowFormat::Depth24 => 4,
        }
    }

    /// The largest step between stored depths in [0, 1]: 2^-24 for a 32-bit float near 1 and
    /// for 24-bit unorm (1 / (2^24 - 1), which Depth24Plus's float fallback does not exceed),
    /// 1 / 65535 for 16-bit unorm.
    pub fn step(self) -> f32 {
        match self {
            ShadowFormat::Depth32 | ShadowFormat::Depth24 => 2f32.powi(-24),
            ShadowFormat::Depth16 => 1.0 / 65535.0,
        }
    }
}

/// `ShadowTile::info[0]` of a tile: perspective in the atlas, orthographic in the atlas (the
/// sun's cascades), or one face of a cube in the cube array (`rect[0]` its layer).
pub const TILE_PERSPECTIVE: f32 = 0.0;
pub const TILE_ORTHOGRAPHIC: f32 = 1.0;
pub const TILE_CUBE_FACE: f32 = 2.0;

/// Texels on each side of a tile beyond the frustum its light needs: the widest kernel reaches
/// 2 texels (`poisson16`) plus the hardware's 2x2 footprint, 1 more.
pub const BORDER: u32 = 4;
/// Spots wider than this (half-angle, degrees) are shadowed as a cube (six faces).
pub const CUBE_SPOT_ANGLE: f32 = 60.0;

/// Whether `mode` lets light `l`'s kind cast (its own flag aside): spots from `spots`, points
/// from `all`.
pub fn kind_casts(l: &Light, mode: ShadowMode) -> bool {
    match l {
        Light::Spot(_) => matches!(mode, ShadowMode::Spots | ShadowMode::All),
        Light::Point(_) => mode == ShadowMode::All,
    }
}

/// Whether light `l` is shadowed by a cube (six faces) rather than one perspective tile: point
/// lights and spots wider than [`CUBE_SPOT_ANGLE`].
pub fn casts_cube(l: &Light) -> bool {
    match l {
        // In radians: a spot authored at exactly 60° (whose f32 radians turn back into
        // 60.000004°) is a single tile, as "wider than" says.
        Light::Spot(s) => s.outer_angle > CUBE_SPOT_ANGLE.to_radians(),
        Light::Point(_) => true,
    }
}

/// The sun, when it casts under a mode other than `none` (it shines: intensity above 0).
pub fn sun_casts(scene: &Scene) -> Option<crate::scene::Sun> {
    scene.sun.filter(|s| s.intensity > 0.0)
}

impl ShadowCode {
    pub fn of(scene: Option<&Scene>, st: &ShadowOptions) -> ShadowCode {
        let mode = st.shadows;
        // The kernel only matters to a lookup: with none compiled in, the default, so that
        // changing `--shadow-filter` then compiles nothing new.
        let none = ShadowCode {
            sun: false,
            tiles: false,
            cubes: None,
            filter: ShadowFilter::default(),
            format: ShadowFormat::default(),
            casters_apart: false,
        };
        if mode == ShadowMode::None {
            return none;
        }
        let mut code = ShadowCode { filter: st.shadow_filter, format: st.shadow_format, ..none };
        let Some(scene) = scene else {
            code.sun = true;
            code.tiles = matches!(mode, ShadowMode::Spots | ShadowMode::All);
            code.cubes = code.tiles.then_some(st.shadow_cube);
            return code;
        };
        code.sun = sun_casts(scene).is_some();
        let mut casters = 0;
        for l in scene.lights.iter().filter(|l| kind_casts(l, mode) && l.cast_shadows()) {
            if casts_cube(l) {
                code.cubes = Some(st.shadow_cube);
            } else {
                code.tiles = true;
            }
            casters += 1;
        }
        code.casters_apart = casters > 0 && 2 * casters <= scene.lights.len();
        if !(code.sun || code.tiles || code.cubes.is_some()) {
            return none;
        }
        code
    }
}

/// Why a light that should cast has no shadow this frame.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct ShadowStats {
    pub mode: ShadowMode,
    pub filter: ShadowFilter,
    #[serde(default)]
    pub format: ShadowFormat,
    pub atlas_side: u32,
    pub atlas_bytes: u64,
    pub tiles: u32,
    /// Share of the atlas's texels the tiles take.
    pub atlas_used: f64,
    /// Lights (the sun counted) with shadows this frame.
    pub casting: u32,
    pub sun_cascades: u32,
    /// The sun's cascades' drawing time (ms) in a ledger frame, timed apart from the lights'
    /// (`LightStats::shadow_ms`); `None` otherwise.
    #[serde(default)]
    pub sun_ms: Option<f64>,
    /// Fallbacks to unshadowed: the light's volume is off screen, or the atlas was full.
    pub fallback_off_screen: u32,
    pub fallback_budget: u32,
    /// Lights whose own `cast_shadows` flag is off (not a fallback: asked for).
    pub flag_off: u32,
    /// Caster draws (objects x tiles after culling each object against each tile).
    pub caster_draws: u64,
    /// Where the cubes live (`--shadow-cube`); with `array`, the cube array's face side,
    /// layers (6 a casting cube) and bytes as allocated (0 when no cube casts).
    pub cube: ShadowCube,
    pub cube_side: u32,
    pub cube_layers: u32,
    pub cube_bytes: u64,
    /// With `indirect`, the indirection cube's side and bytes (0 when no cube casts).
    #[serde(default)]
    pub indirection_side: u32,
    #[serde(default)]
    pub indirection_bytes: u64,
    pub gpu_ms: Option<f64>,
}

impl ShadowStats {
    /// Bytes of shadow maps this frame: the atlas, the cube array and the indirection cube as
    /// allocated.
    pub fn bytes(&self) -> u64 {
        self.atlas_bytes + self.cube_bytes + self.indirection_bytes
    }
}

/// One tile to draw: its record index, its texel rectangle in the atlas, the objects cast into it.
#[derive(Clone, Debug)]
pub struct TileDraw {
    pub tile: u32,
    pub x: u32,
    pub y: u32,
    pub size: u32,
    pub objects: Vec<u32>,
    /// `Some(layer)`: a face of the cube array (`x`, `y` 0, `size` the array's side), not a tile
    /// of the atlas.
    pub layer: Option<u32>,
}

/// The frame's shadow plan.
#[derive(Clone, Debug, Default)]
pub struct ShadowPlan {
    pub side: u32,
    pub tiles: Vec<ShadowTile>,
    pub params: ShadowParams,
    pub draws: Vec<TileDraw>,
    /// Per light: (first tile, tile count), `NO_SHADOW` when unshadowed.
    pub lights: Vec<(u32, u32)>,
    pub stats: ShadowStats,
    /// The cube array's face side and layers (`--shadow-cube array`; 0 when no cube casts).
    pub cube_side: u32,
    pub cube_layers: u32,
    /// The indirection cube's side (`--shadow-cube indirect`; 0 when no cube casts).
    pub indirection_side: u32,
    /// The casting lights' indices in light order: what the `shadow` view walks (uploaded after
    /// the tiles, `ShadowParams::counts`).
    pub casters: Vec<u32>,
}

impl Default for ShadowParams {
    fn default() -> Self {
        Self { sun: [NO_SHADOW, 0, 0, 0], splits: [0.0; 4], bias: [0.0; 4], counts: [0; 4] }
    }
}

/// Side of the atlas for a budget of `mb` MiB (`bytes` a texel), capped at `limit`.
pub fn atlas_side(mb: f32, bytes: u64, limit: u32) -> u32 {
    let texels = (mb as f64 * 1024.0 * 1024.0 / bytes.max(1) as f64).max(1.0);
    let mut side = 1u32;
    while (side as f64 * 2.0).powi(2) <= texels && side * 2 <= limit {
        side *= 2;
    }
    side.max(MIN_TILE.min(limit))
}

/// The cube array's size rule (`--shadow-cube array`): every cube in the array has one face
/// side. `wants` holds each cube light's wanted face side (its footprint rule, as for atlas
/// tiles), in priority order; `bytes` is what the budget leaves after the atlas (the budget
/// less the atlas as allocated). The side starts at the largest want (at most `max_side`) and
/// is halved while 6 faces x `texel` bytes x side² x (cube lights) exceeds `bytes`, down to
/// [`MIN_TILE`]; at `MIN_TILE` the first cubes in priority order that fit are kept, the rest
/// fall back to unshadowed (budget). At most `max_layers` / 6 cubes (the device's array-layer
/// limit; the rest are budget fallbacks too). Returns (face side, cubes kept).
pub fn cube_array_fit(wants: &[u32], bytes: u64, texel: u64, max_side: u32, max_layers: u32) -> (u32, usize) {
    let Some(&most) = wants.iter().max() else { return (0, 0) };
    let n = wants.len().min((max_layers / 6) as usize);
    let cube = |side: u32| 6 * texel * side as u64 * side as u64;
    let mut side = most.min(max_side.max(1));
    while side > MIN_TILE && n as u64 * cube(side) > bytes {
        side /= 2;
    }
    let kept = n.min((bytes / cube(side)) as usize);
    (if kept == 0 { 0 } else { side }, kept)
}

/// The light-space transform of cube face `face` (+x, -x, +y, -y, +z, -z of view space, the
/// array's layer order) for a light at `origin`: q = R (p - origin) with q.x = sc, q.y = -tc,
/// -q.z = |rc| of the cube-map face selection table (Vulkan spec, "Cube Map Face
/// Selection"; the same in D3D and Metal), so that ndc (q.xy / -q.z) lands where the hardware
/// looks up the direction p - origin: u = (sc / |rc| + 1) / 2, v = (tc / |rc| + 1) / 2, v = 0 the
/// top row, which the viewport maps ndc.y = +1 to. Not all six are rotations (some mirror):
/// casters draw both faces, so the handedness does not matter.
pub fn cube_face_space(origin: DVec3, face: usize) -> DMat4 {
    // Rows of R: q.x, q.y, q.z in terms of (rx, ry, rz).
    let rows: [[f64; 3]; 3] = match face {
        0 => [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
        1 => [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
        2 => [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, -1.0, 0.0]],
        3 => [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        4 => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
        _ => [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };
    let r = DMat3::from_cols(rows[0].into(), rows[1].into(), rows[2].into()).transpose();
    DMat4::from_mat3(r) * DMat4::from_translation(-origin)
}

/// A cube-array face: the light at `origin`, face `face`, exactly 90° (no border: the hardware
/// filters across faces), `size` texels, layer `layer`.
fn cube_face_tile(origin: DVec3, face: usize, far: f64, size: u32, layer: u32) -> ShadowTile {
    let near = (far * 1e-3).min(0.05);
    ShadowTile {
        to_light: cube_face_space(origin, face).as_mat4().to_cols_array_2d(),
        proj: [1.0, 1.0, (1.0 / far) as f32, 0.0],
        rect: [layer as f32, 0.0, 0.0, 0.0],
        info: [TILE_CUBE_FACE, (2.0 / size as f64) as f32, size as f32, near as f32],
    }
}

/// (x, y) of Morton index `i`.
fn morton(i: u64) -> (u32, u32) {
    let (mut x, mut y) = (0u32, 0u32);
    for b in 0..32 {
        x |= (((i >> (2 * b)) & 1) as u32) << b;
        y |= (((i >> (2 * b + 1)) & 1) as u32) << b;
    }
    (x, y)
}

/// Packs power-of-two squares of `sizes` (each at most `side`, their area at most `side`²)
/// into a `side` square: largest first along the Morton order in units of the smallest, each
/// square starts at a multiple of its own area (every earlier one is a multiple of it), so it
/// is an aligned block. Returns each square's corner, in `sizes`' order.
pub fn pack(sizes: &[u32], side: u32) -> Option<Vec<(u32, u32)>> {
    let unit = *sizes.iter().min()?;
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by(|&a, &b| sizes[b].cmp(&sizes[a]).then(a.cmp(&b)));
    let mut out = vec![(0, 0); sizes.len()];
    let mut at = 0u64;
    let cap = (side as u64 / unit as u64).pow(2);
    for i in order {
        let s = sizes[i];
        if !s.is_power_of_two() || s > side {
            return None;
        }
        let area = (s as u64 / unit as u64).pow(2);
        if at + area > cap {
            return None;
        }
        let (x, y) = morton(at);
        out[i] = (x * unit, y * unit);
        at += area;
    }
    Some(out)
}

/// A rigid transform from view space into a light space whose z axis is `z` (the light looks
/// down -z) and whose origin is `origin`.
fn light_space(origin: DVec3, z: DVec3) -> DMat4 {
    let z = z.normalize();
    let up = if z.y.abs() < 0.99 { DVec3::Y } else { DVec3::X };
    let x = up.cross(z).normalize();
    let y = z.cross(x);
    let rows = DMat3::from_cols(x, y, z).transpose();
    DMat4::from_mat3(rows) * DMat4::from_translation(-origin)
}

/// The six cube faces' directions (view-space axes), in the order `ls_shadow` picks them:
/// +x, -x, +y, -y, +z, -z.
pub const FACES: [DVec3; 6] = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];

/// A perspective tile: the light at `origin` looking along `dir`, half-angle `half` (radians)
/// reaching `far`, `size` texels.
fn perspective_tile(origin: DVec3, dir: DVec3, half: f64, far: f64, size: u32) -> ShadowTile {
    let r = size as f64;
    // ndc = q.xy * s / w: the frustum's edge (tan half) lands BORDER texels inside the tile.
    let s = (r - 2.0 * BORDER as f64) / (r * half.tan());
    let near = (far * 1e-3).min(0.05);
    ShadowTile {
        to_light: light_space(origin, -dir).as_mat4().to_cols_array_2d(),
        proj: [s as f32, s as f32, (1.0 / far) as f32, 0.0],
        rect: [0.0; 4],
        info: [0.0, (2.0 / (r * s)) as f32, size as f32, near as f32],
    }
}

/// Bounding spheres (view space) of the objects that cast: triangle meshes, not blended.
fn casters(scene: &Scene, bounds: &[(DVec3, f64)], view: DMat4) -> Vec<(u32, DVec3, f64)> {
    let mut out = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        let Some(mesh) = scene.meshes.get(o.mesh) else { continue };
        if mesh.topology != crate::scene::Topology::Triangles {
            continue;
        }
        if scene.materials.get(o.material).is_some_and(|m| m.is_blended()) {
            continue;
        }
        let Some(&(c, r)) = bounds.get(o.mesh) else { continue };
        let m = view * o.transform;
        let scale = m.x_axis.truncate().length().max(m.y_axis.truncate().length()).max(m.z_axis.truncate().length());
        out.push((i as u32, m.transform_point3(c), r * scale));
    }
    out
}

/// Whether a sphere (view space) may touch `tile`'s frustum.
fn sphere_meets(tile: &ShadowTile, c: DVec3, r: f64) -> bool {
    let m = glam::Mat4::from_cols_array_2d(&tile.to_light).as_dmat4();
    let q = m.transform_point3(c);
    let s = tile.proj[0] as f64;
    if tile.info[0] == TILE_ORTHOGRAPHIC {
        // Orthographic: |q.xy| <= 1/s; the depth range holds every caster by construction.
        return q.x.abs() - r <= 1.0 / s && q.y.abs() - r <= 1.0 / s;
    }
    let far = 1.0 / tile.proj[2] as f64;
    let w = -q.z;
    if w + r < 0.0 || w - r > far {
        return false;
    }
    // Side planes |q.x| <= t w, t = 1/s: signed distance (|q.x| - t w) / sqrt(1 + t^2).
    let t = 1.0 / s;
    let k = (1.0 + t * t).sqrt();
    (q.x.abs() - t * w) / k <= r && (q.y.abs() - t * w) / k <= r
}

/// What the planner reads besides the scene.
pub struct ShadowInputs<'a> {
    pub options: &'a ShadowOptions,
    /// Each mesh's bounding sphere (model space).
    pub bounds: &'a [(DVec3, f64)],
    /// Each light's screen share and whether its volume is on screen (`plan::LightPlan`).
    pub footprints: Vec<(f32, bool)>,
    pub size: (u32, u32),
    /// The camera's projection (standard or reversed, only the x and y scales are read).
    pub proj: DMat4,
    pub max_texture: u32,
    /// The device's `max_texture_array_layers` (the cube array holds 6 a light).
    pub max_layers: u32,
}

/// Plans the frame's shadows. The steps:
/// 1. the requests: the sun's cascades, then each casting light on screen, largest footprint
///    first ([`requests`]);
/// 2. the budget: in that order, each request's tiles halved until they fit what is left
///    ([`grant`]);
/// 3. the atlas: the granted tiles packed in Morton order and re-fitted to the sizes they were
///    granted, each with the casters its frustum meets ([`place`]);
/// 4. with `--shadow-cube array`, the cube lights' faces in the cube array ([`place_cubes`]).
pub fn plan(scene: &Scene, inp: &ShadowInputs<'_>) -> ShadowPlan {
    let st = inp.options;
    let side = atlas_side(st.shadow_budget_mb, st.shadow_format.bytes(), inp.max_texture.max(1));
    let mut out = ShadowPlan {
        side,
        lights: vec![(NO_SHADOW, 0); scene.lights.len()],
        stats: ShadowStats {
            mode: st.shadows,
            filter: st.shadow_filter,
            format: st.shadow_format,
            atlas_side: side,
            atlas_bytes: side as u64 * side as u64 * st.shadow_format.bytes(),
            cube: st.shadow_cube,
            ..Default::default()
        },
        ..Default::default()
    };
    out.params.bias = [st.shadow_bias, st.shadow_slope_bias, st.shadow_normal_offset, 1.0 / side as f32];
    out.params.sun = [NO_SHADOW, 0, st.shadow_filter as u32, scene.objects.len() as u32];
    if st.shadows == ShadowMode::None {
        // No atlas is kept (a 1-texel stand-in is bound).
        out.side = 1;
        return with_casters(out);
    }
    let cam = &scene.camera;
    let view = DMat4::from_mat3(cam.rotation()) * DMat4::from_translation(-cam.position);
    let casters = casters(scene, inp.bounds, view);
    let (requests, cubes) = requests(scene, inp, &casters, side, &mut out);
    let (granted, used) = grant(requests, side, &mut out.stats);
    let sizes: Vec<u32> = granted.iter().flat_map(|r| std::iter::repeat_n(r.size, r.tiles.len())).collect();
    // With the cube array, the atlas shrinks to the smallest power of two holding its tiles
    // (Morton packing puts the first k² units in a k x k square), and the cube array gets the
    // budget's rest; the tiles keep the sizes they were granted against the full side.
    let array = st.shadow_cube == ShadowCube::Array;
    let side = if array {
        let largest = sizes.iter().copied().max().unwrap_or(1);
        let mut s = largest.max(1);
        while (s as u64).pow(2) < used {
            s *= 2;
        }
        s.min(side)
    } else {
        side
    };
    if array {
        out.side = side;
        out.stats.atlas_side = side;
        out.stats.atlas_bytes = side as u64 * side as u64 * 4;
        out.params.bias[3] = 1.0 / side as f32;
    }
    let corners = pack(&sizes, side);
    if corners.is_none() && cubes.is_empty() {
        // Nothing to pack (no caster this frame): no atlas is kept.
        out.side = 1;
        return with_casters(out);
    }
    place(&mut out, granted, (&sizes, &corners.unwrap_or_default()), side, &casters);
    if sizes.is_empty() {
        // Cubes only (the array): a 1-texel atlas stands in.
        out.side = 1;
        out.stats.atlas_side = 1;
        out.stats.atlas_bytes = 4;
    }
    out.stats.tiles = out.tiles.len() as u32;
    out.stats.atlas_used = used as f64 / (side as u64 * side as u64) as f64;
    if !cubes.is_empty() {
        place_cubes(&mut out, scene, inp, &cubes, &casters);
    }
    if st.shadow_cube == ShadowCube::Indirect && out.lights.iter().any(|l| l.1 == 6) {
        let n = indirection_side(side);
        out.indirection_side = n;
        out.stats.indirection_side = n;
        out.stats.indirection_bytes = 6 * 4 * n as u64 * n as u64;
    }
    with_casters(out)
}

/// One shadow request: the sun (`light` `None`) or a light, its tiles' records and the size it
/// wants for each.
struct Request {
    light: Option<usize>,
    tiles: Vec<ShadowTile>,
    size: u32,
}

/// The frame's requests in priority order (the sun's cascades, then the casting lights on
/// screen, largest footprint first; ties by index, so the order is the same in every culling
/// mode), and with `--shadow-cube array` the cube lights (points, wide spots) with the face
/// size each wants. Counts the lights left out in `out.stats`; sets the sun's cascade splits.
fn requests(
    scene: &Scene,
    inp: &ShadowInputs<'_>,
    casters: &[(u32, DVec3, f64)],
    side: u32,
    out: &mut ShadowPlan,
) -> (Vec<Request>, Vec<(usize, u32)>) {
    let (st, cam) = (inp.options, &scene.camera);
    let rot = cam.rotation();
    let mut requests: Vec<Request> = Vec::new();
    let quarter = (side / 4).max(MIN_TILE.min(side));
    if let Some(sun) = sun_casts(scene) {
        let to_sun = (rot * (-sun.direction.as_dvec3())).normalize_or(DVec3::Y);
        let tiles = sun_cascades(scene, st, casters, to_sun, inp.proj, quarter);
        if !tiles.1.is_empty() {
            out.params.splits = tiles.0;
            requests.push(Request { light: None, size: quarter, tiles: tiles.1 });
        }
    }
    let pixels = inp.size.0 as f64 * inp.size.1 as f64;
    let mut lit: Vec<(usize, f32)> = Vec::new();
    for (i, l) in scene.lights.iter().enumerate() {
        if !kind_casts(l, st.shadows) {
            continue;
        }
        if !l.cast_shadows() {
            out.stats.flag_off += 1;
            continue;
        }
        let (share, on) = inp.footprints.get(i).copied().unwrap_or((0.0, false));
        if !on || share <= 0.0 {
            out.stats.fallback_off_screen += 1;
            continue;
        }
        lit.push((i, share));
    }
    lit.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let array = st.shadow_cube == ShadowCube::Array;
    let mut cubes: Vec<(usize, u32)> = Vec::new();
    for (i, share) in lit {
        let want = ((share as f64 * pixels).sqrt().ceil() as u32).next_power_of_two().clamp(MIN_TILE, quarter);
        let origin = rot * (scene.lights[i].position() - cam.position);
        let far = scene.lights[i].radius() as f64;
        let tiles = match &scene.lights[i] {
            Light::Spot(s) if !casts_cube(&scene.lights[i]) => {
                let dir = (rot * s.direction.as_dvec3()).normalize();
                let half = (s.outer_angle as f64).max(0.5f64.to_radians()) * 1.02;
                vec![perspective_tile(origin, dir, half, far, want)]
            }
            _ if array => {
                cubes.push((i, want));
                continue;
            }
            // The faces in the cube-map orientation (`cube_face_space`), which the indirection
            // cube's coordinates follow; the face pick finds the same texels in them.
            _ => (0..6)
                .map(|f| ShadowTile {
                    to_light: cube_face_space(origin, f).as_mat4().to_cols_array_2d(),
                    ..perspective_tile(origin, FACES[f], std::f64::consts::FRAC_PI_4, far, want)
                })
                .collect(),
        };
        requests.push(Request { light: Some(i), tiles, size: want });
    }
    (requests, cubes)
}

/// Fits the budget: in priority order, halves a request's tiles until they fit what is left of
/// the `side`² atlas; a light that does not fit at `MIN_TILE` falls back (counted). Returns the
/// granted requests and the texels they use.
fn grant(requests: Vec<Request>, side: u32, stats: &mut ShadowStats) -> (Vec<Request>, u64) {
    let total = side as u64 * side as u64;
    let mut used = 0u64;
    let mut granted: Vec<Request> = Vec::new();
    for mut r in requests {
        let n = r.tiles.len() as u64;
        while r.size > MIN_TILE && used + n * (r.size as u64).pow(2) > total {
            r.size /= 2;
        }
        if used + n * (r.size as u64).pow(2) > total || r.size > side {
            if r.light.is_some() {
                stats.fallback_budget += 1;
            }
            continue;
        }
        used += n * (r.size as u64).pow(2);
        granted.push(r);
    }
    (granted, used)
}

/// Places the granted tiles at their packed corners in the `side`² atlas: each tile's
/// projection re-fitted to its granted size (the border is in texels), its caster draws, and
/// each light's (first tile, count) or the sun's cascades.
fn place(
    out: &mut ShadowPlan,
    granted: Vec<Request>,
    (sizes, corners): (&[u32], &[(u32, u32)]),
    side: u32,
    casters: &[(u32, DVec3, f64)],
) {
    let mut k = 0usize;
    for r in granted {
        let first = out.tiles.len() as u32;
        for mut t in r.tiles {
            let (x, y) = corners[k];
            let size = sizes[k];
            k += 1;
            let s_old = t.proj[0] as f64;
            let r_old = t.info[2] as f64;
            let tan_half = (r_old - 2.0 * BORDER as f64) / (r_old * s_old);
            let rs = size as f64;
            let s = (rs - 2.0 * BORDER as f64) / (rs * tan_half);
            t.proj[0] = s as f32;
            t.proj[1] = s as f32;
            t.info[1] = (2.0 / (rs * s)) as f32;
            t.info[2] = size as f32;
            t.rect =
                [x as f32 / side as f32, y as f32 / side as f32, size as f32 / side as f32, size as f32 / side as f32];
            out.add_tile(t, (x, y, size), None, casters);
        }
        let count = out.tiles.len() as u32 - first;
        out.stats.casting += 1;
        match r.light {
            Some(i) => out.lights[i] = (first, count),
            None => {
                out.params.sun[0] = first;
                out.params.sun[1] = count;
                out.stats.sun_cascades = count;
            }
        }
    }
}

/// The cube array: one face side for every cube (`cube_array_fit`) within what the atlas left
/// of the budget, six layers a light; the cubes that do not fit fall back (counted).
fn place_cubes(
    out: &mut ShadowPlan,
    scene: &Scene,
    inp: &ShadowInputs<'_>,
    cubes: &[(usize, u32)],
    casters: &[(u32, DVec3, f64)],
) {
    let (cam, rot) = (&scene.camera, scene.camera.rotation());
    let budget = (inp.options.shadow_budget_mb.max(0.0) as f64 * 1024.0 * 1024.0) as u64;
    let left = budget.saturating_sub(out.stats.atlas_bytes);
    let wants: Vec<u32> = cubes.iter().map(|c| c.1).collect();
    let texel = inp.options.shadow_format.bytes();
    let (cube_side, kept) = cube_array_fit(&wants, left, texel, inp.max_texture.max(1), inp.max_layers);
    out.stats.fallback_budget += (cubes.len() - kept) as u32;
    for (c, &(i, _)) in cubes.iter().take(kept).enumerate() {
        let origin = rot * (scene.lights[i].position() - cam.position);
        let far = scene.lights[i].radius() as f64;
        let first = out.tiles.len() as u32;
        for face in 0..6 {
            let layer = (6 * c + face) as u32;
            let t = cube_face_tile(origin, face, far, cube_side, layer);
            out.add_tile(t, (0, 0, cube_side), Some(layer), casters);
        }
        out.lights[i] = (first, 6);
        out.stats.casting += 1;
    }
    if kept > 0 {
        out.cube_side = cube_side;
        out.cube_layers = 6 * kept as u32;
        out.stats.cube_side = cube_side;
        out.stats.cube_layers = out.cube_layers;
        out.stats.cube_bytes = texel * out.cube_layers as u64 * cube_side as u64 * cube_side as u64;
    }
    out.stats.tiles = out.tiles.len() as u32;
}

impl ShadowPlan {
    /// Adds tile `t` at (x, y, size) in the atlas (or cube-array `layer`) with a draw of the
    /// casters whose bounding spheres its frustum meets.
    fn add_tile(
        &mut self,
        t: ShadowTile,
        (x, y, size): (u32, u32, u32),
        layer: Option<u32>,
        casters: &[(u32, DVec3, f64)],
    ) {
        let index = self.tiles.len() as u32;
        let objects: Vec<u32> =
            casters.iter().filter(|(_, c, rad)| sphere_meets(&t, *c, *rad)).map(|(o, _, _)| *o).collect();
        self.stats.caster_draws += objects.len() as u64;
        self.draws.push(TileDraw { tile: index, x, y, size, objects, layer });
        self.tiles.push(t);
    }
}

impl ShadowPlan {
    /// Light `i`'s share of the frame's shadow maps: its tiles (atlas tiles or cube-array
    /// faces), their texels, and the caster draws into them; zeros when it casts none. With
    /// the sun's cascades (`params.sun`) the lights' shares add up to the plan's tiles, texels
    /// and `stats.caster_draws`.
    pub fn light_share(&self, i: usize) -> (u32, u64, u64) {
        match self.lights.get(i) {
            Some(&(first, count)) if first != NO_SHADOW => self.tiles_share(first, count),
            _ => (0, 0, 0),
        }
    }

    /// Tiles `first .. first + count`: (count, texels, caster draws).
    fn tiles_share(&self, first: u32, count: u32) -> (u32, u64, u64) {
        let draws = self.draws.get(first as usize..(first + count) as usize).unwrap_or_default();
        let texels = draws.iter().map(|d| d.size as u64 * d.size as u64).sum();
        (draws.len() as u32, texels, draws.iter().map(|d| d.objects.len() as u64).sum())
    }
}

/// `plan`'s caster list and the counts the `shadow` view reads: (lights, casters, the table row
/// the casters start at: after the parameters' row and the tiles', 0).
fn with_casters(mut out: ShadowPlan) -> ShadowPlan {
    out.casters = (0..out.lights.len() as u32).filter(|&i| out.lights[i as usize].0 != NO_SHADOW).collect();
    out.params.counts = [out.lights.len() as u32, out.casters.len() as u32, 1 + out.tiles.len() as u32, 0];
    out
}

/// The sun's cascades: split distances (view depth where each ends) and one orthographic tile
/// per cascade (its size set later), or none when nothing casts.
fn sun_cascades(
    scene: &Scene,
    st: &ShadowOptions,
    casters: &[(u32, DVec3, f64)],
    to_sun: DVec3,
    proj: DMat4,
    size: u32,
) -> ([f32; 4], Vec<ShadowTile>) {
    if casters.is_empty() {
        return ([0.0; 4], Vec::new());
    }
    let cam = &scene.camera;
    let near = cam.near.max(1e-6);
    // The cascades end at the farthest scene point (or the far plane).
    let deepest = casters.iter().map(|(_, c, r)| -c.z + r).fold(0.0, f64::max);
    let far = cam.far.min(deepest).max(near * 2.0);
    let n = st.shadow_cascades.clamp(1, 4) as usize;
    let lambda = st.shadow_split_lambda.clamp(0.0, 1.0) as f64;
    let split = |i: usize| {
        let f = i as f64 / n as f64;
        lambda * near * (far / near).powf(f) + (1.0 - lambda) * (near + (far - near) * f)
    };
    let tan_x = 1.0 / proj.x_axis.x.abs().max(1e-12);
    let tan_y = 1.0 / proj.y_axis.y.abs().max(1e-12);
    let mut splits = [0.0f32; 4];
    let mut tiles = Vec::new();
    for (i, end) in splits.iter_mut().enumerate().take(n) {
        let (d0, d1) = (split(i), split(i + 1));
        *end = d1 as f32;
        let corners: Vec<DVec3> = [d0, d1]
            .iter()
            .flat_map(|&d| {
                [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
                    .map(|(sx, sy)| DVec3::new(sx * d * tan_x, sy * d * tan_y, -d))
            })
            .collect();
        let centre = corners.iter().copied().sum::<DVec3>() / 8.0;
        let radius = corners.iter().map(|c| (*c - centre).length()).fold(0.0, f64::max).max(1e-6);
        // Depth: every caster between the tile's origin plane and its far end.
        let top = casters.iter().map(|(_, c, r)| (*c - centre).dot(to_sun) + r).fold(radius, f64::max);
        let bottom = casters.iter().map(|(_, c, r)| (*c - centre).dot(to_sun) - r).fold(-radius, f64::min);
        let range = (top - bottom).max(1e-6);
        let r = size as f64;
        let s = (r - 2.0 * BORDER as f64) / (r * radius);
        tiles.push(ShadowTile {
            to_light: light_space(centre + to_sun * top, to_sun).as_mat4().to_cols_array_2d(),
            proj: [s as f32, s as f32, (1.0 / range) as f32, 0.0],
            rect: [0.0; 4],
            info: [1.0, (2.0 / (r * s)) as f32, size as f32, 0.0],
        });
    }
    (splits, tiles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shadow_the_plan_grants_has_its_lookup_compiled_in() {
        // The plan, not a table: for built-in scenes with their lights' flags, angles and the
        // sun varied, under every mode and cube layout, every light the plan gives tiles (all
        // on screen, a large budget) is of a kind `ShadowCode::of` compiles a lookup for, and
        // every kind compiled in is granted to some light (no lookup compiled for nothing).
        use crate::scene::builtin::{build, BuiltinOptions};
        let mut scenes: Vec<Scene> = ["shadows", "spot", "spot-extremes", "cookies", "demo"]
            .iter()
            .map(|n| build(n, BuiltinOptions { lights: Some(40), time: 0.0 }).expect("built-in scene"))
            .collect();
        let mut varied = scenes[0].clone();
        for (i, l) in varied.lights_mut().iter_mut().enumerate() {
            if let Light::Spot(s) = l {
                // Exactly at the rule's angle: a single tile.
                s.outer_angle = CUBE_SPOT_ANGLE.to_radians();
            }
            l.set_cast_shadows(i % 2 == 0);
        }
        if let Some(sun) = varied.sun.as_mut() {
            sun.intensity = 0.0;
        }
        scenes.push(varied);
        let mut wide = scenes[1].clone();
        for l in wide.lights_mut().iter_mut() {
            if let Light::Spot(s) = l {
                s.outer_angle = CUBE_SPOT_ANGLE.to_radians() * 1.001;
            }
        }
        scenes.push(wide);
        for scene in &scenes {
            let bounds = crate::renderer::scene_gpu::mesh_bounds(scene);
            for mode in [ShadowMode::Sun, ShadowMode::Spots, ShadowMode::All] {
                for cube in [ShadowCube::Unrolled, ShadowCube::Array, ShadowCube::Indirect] {
                    let st = super::super::Settings {
                        shadows: mode,
                        shadow_cube: cube,
                        shadow_budget_mb: 256.0,
                        ..Default::default()
                    };
                    let code = ShadowCode::of(Some(scene), &st.shadow_options());
                    let plan = test_plan(scene, &bounds, &st);
                    let what = format!("{} {mode:?} {cube:?}: {code:?}", scene.name);
                    let mut granted = (plan.params.sun[0] != NO_SHADOW, false, None);
                    for &(first, count) in plan.lights.iter().filter(|l| l.0 != NO_SHADOW) {
                        let kind = plan.tiles[first as usize].info[0];
                        match count {
                            1 => granted.1 = true,
                            6 if kind == TILE_CUBE_FACE => granted.2 = Some(ShadowCube::Array),
                            // The unrolled tiles, read through the indirection or not.
                            6 if cube == ShadowCube::Indirect => granted.2 = Some(ShadowCube::Indirect),
                            6 => granted.2 = Some(ShadowCube::Unrolled),
                            n => panic!("{what}: a light with {n} tiles"),
                        }
                    }
                    assert_eq!(granted, (code.sun, code.tiles, code.cubes), "{what}");
                    // The indirection cube is made exactly when it is read.
                    assert_eq!(plan.indirection_side > 0, code.cubes == Some(ShadowCube::Indirect), "{what}");
                }
            }
        }
        // The angle rule at its boundary: exactly 60° is a tile, a hair wider a cube.
        let spot = |deg: f32| {
            let mut l = scenes[1].lights.iter().find(|l| matches!(l, Light::Spot(_))).copied().expect("a spot");
            if let Light::Spot(s) = &mut l {
                s.outer_angle = deg.to_radians();
            }
            l
        };
        assert!(!casts_cube(&spot(CUBE_SPOT_ANGLE)) && casts_cube(&spot(CUBE_SPOT_ANGLE + 0.01)));
    }

    #[test]
    fn the_shaders_compile_in_the_shadow_lookups_some_light_can_need() {
        use crate::scene::builtin::{build, BuiltinOptions};
        use ShadowMode as M;
        let scene = |name: &str| build(name, BuiltinOptions::default()).expect("built-in scene");
        let code = |scene: Option<&Scene>, shadows, cube| {
            let st = super::super::Settings { shadows, shadow_cube: cube, ..Default::default() };
            let c = ShadowCode::of(scene, &st.shadow_options());
            (c.sun, c.tiles, c.cubes)
        };
        let (un, ar) = (ShadowCube::Unrolled, ShadowCube::Array);
        let shadows = scene("shadows"); // the sun, a narrow spot, a point light
        assert_eq!(code(Some(&shadows), M::None, un), (false, false, None));
        assert_eq!(code(Some(&shadows), M::Sun, un), (true, false, None));
        assert_eq!(code(Some(&shadows), M::Spots, un), (true, true, None));
        assert_eq!(code(Some(&shadows), M::All, un), (true, true, Some(un)));
        assert_eq!(code(Some(&shadows), M::All, ar), (true, true, Some(ar)));
        let ind = ShadowCube::Indirect;
        assert_eq!(code(Some(&shadows), M::All, ind), (true, true, Some(ind)));
        assert_eq!(code(Some(&shadows), M::Spots, ind), (true, true, None));
        // A light's own flag off takes its lookup out; no sun, no cascades.
        let mut flagged = shadows.clone();
        for l in flagged.lights_mut().iter_mut().filter(|l| matches!(l, Light::Point(_))) {
            l.set_cast_shadows(false);
        }
        flagged.sun = None;
        assert_eq!(code(Some(&flagged), M::All, un), (false, true, None));
        // Point lights only: no single tiles. A spot wider than CUBE_SPOT_ANGLE is a cube.
        let wall = scene("sphere-wall");
        let c = code(Some(&wall), M::All, un);
        assert!(!c.1 && c.2 == Some(un), "{c:?}");
        let c = code(Some(&wall), M::Spots, un);
        assert!(!c.1 && c.2.is_none(), "{c:?}");
        let mut wide = scene("spot");
        assert!(code(Some(&wide), M::Spots, un).1);
        for l in wide.lights_mut().iter_mut() {
            if let Light::Spot(s) = l {
                s.outer_angle = (CUBE_SPOT_ANGLE + 1.0).to_radians();
            }
        }
        let c = code(Some(&wide), M::Spots, un);
        assert!(!c.1 && c.2 == Some(un), "{c:?}");
        // Before a scene: what the settings allow.
        assert_eq!(code(None, M::Spots, ar), (true, true, Some(ar)));
        assert_eq!(code(None, M::None, ar), (false, false, None));
    }

    #[test]
    fn packing_fills_the_atlas_without_overlap() {
        let sizes = [256, 64, 64, 128, 32, 256, 512, 64, 64, 32, 32, 32];
        let side = 1024;
        let corners = pack(&sizes, side).expect("fits");
        let mut seen = vec![false; (side * side / 32 / 32) as usize];
        for (&(x, y), &s) in corners.iter().zip(&sizes) {
            assert_eq!((x % s, y % s), (0, 0), "aligned");
            assert!(x + s <= side && y + s <= side);
            for yy in (y..y + s).step_by(32) {
                for xx in (x..x + s).step_by(32) {
                    let i = (yy / 32 * side / 32 + xx / 32) as usize;
                    assert!(!seen[i], "overlap at {xx},{yy}");
                    seen[i] = true;
                }
            }
        }
        // Too much area is refused.
        assert!(pack(&[1024, 32], 1024).is_none());
    }

    #[test]
    fn the_cube_array_fits_the_budget_with_one_side() {
        let cube = |side: u64| 6 * 4 * side * side;
        // Room for all at the largest want.
        assert_eq!(cube_array_fit(&[256, 64, 128], 3 * cube(256), 4, 8192, 256), (256, 3));
        // One byte short: halved once.
        assert_eq!(cube_array_fit(&[256, 64, 128], 3 * cube(256) - 1, 4, 8192, 256), (128, 3));
        // At MIN_TILE only the first in priority order that fit.
        assert_eq!(cube_array_fit(&[64; 10], 4 * cube(32) + 5, 4, 8192, 256), (32, 4));
        // Nothing fits: no array.
        assert_eq!(cube_array_fit(&[64], cube(32) - 1, 4, 8192, 256), (0, 0));
        // The layer limit: 256 / 6 = 42 cubes.
        assert_eq!(cube_array_fit(&[32; 50], u64::MAX / 2, 4, 8192, 256), (32, 42));
        // The device's side limit.
        assert_eq!(cube_array_fit(&[1024], u64::MAX / 2, 4, 512, 256), (512, 1));
        assert_eq!(cube_array_fit(&[], 1 << 30, 4, 8192, 256), (0, 0));
        // Two bytes a texel (Depth16): the budget of three 256-cubes at 4 bytes holds them at
        // 256 with room for three more.
        assert_eq!(cube_array_fit(&[256; 6], 3 * cube(256), 2, 8192, 256), (256, 6));
    }

    /// The plan of `scene` under `st` at 640x360, every light on screen with a 1% footprint,
    /// on a device with 8192-texel textures and 2048 layers.
    fn test_plan(scene: &Scene, bounds: &[(DVec3, f64)], st: &super::super::Settings) -> ShadowPlan {
        plan(
            scene,
            &ShadowInputs {
                options: &st.shadow_options(),
                bounds,
                footprints: vec![(0.01, true); scene.lights.len()],
                size: (640, 360),
                proj: scene.camera.projection(16.0 / 9.0, false),
                max_texture: 8192,
                max_layers: 2048,
            },
        )
    }

    /// Each face looks down its own axis (the axis maps to the face's centre at distance 1),
    /// and every direction lands inside the face of its major axis (|ndc| <= 1, w = |major|).
    #[test]
    fn cube_faces_cover_their_axes() {
        for (f, axis) in FACES.iter().enumerate() {
            let m = cube_face_space(DVec3::new(1.0, 2.0, 3.0), f);
            let q = m.transform_point3(DVec3::new(1.0, 2.0, 3.0) + *axis);
            assert!((q - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-12, "face {f}: {q}");
        }
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..1000 {
            let d = DVec3::new(rnd(), rnd(), rnd());
            let a = d.abs();
            let f = if a.x >= a.y && a.x >= a.z {
                (d.x < 0.0) as usize
            } else if a.y >= a.z {
                2 + (d.y < 0.0) as usize
            } else {
                4 + (d.z < 0.0) as usize
            };
            let q = cube_face_space(DVec3::ZERO, f).transform_point3(d);
            let w = -q.z;
            assert!((w - a.max_element()).abs() < 1e-12);
            assert!(q.x.abs() <= w + 1e-12 && q.y.abs() <= w + 1e-12);
        }
    }

    /// The indirection cube's texel holding a direction (the cube-map face selection table of
    /// the Vulkan spec, written out here, not taken from `cube_face_space`) decodes to that
    /// direction's face and to face coordinates within half a texel and the 16-bit rounding:
    /// `indirection_error` without the hardware's sub-texel term. The coordinates are also
    /// where `cube_face_space` puts the direction, so the face tiles and the indirection agree.
    #[test]
    fn the_indirection_cube_maps_each_direction_to_its_face_and_coordinates() {
        let mut seed = 11u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for n in [32u32, 1024] {
            let texels = indirection_texels(n);
            assert_eq!(texels.len(), 6 * 4 * (n * n) as usize);
            let bound = indirection_error(1.0, n) - (1.0 / 16.0) / n as f64;
            for k in 0..20_000 {
                // Every fourth direction on a face edge or corner.
                let mut d = DVec3::new(rnd(), rnd(), rnd());
                if k % 4 == 0 {
                    d.y = d.x.abs() * d.y.signum();
                }
                let (rx, ry, rz) = (d.x, d.y, d.z);
                let a = d.abs();
                let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
                    if rx > 0.0 {
                        (0, -rz, -ry, a.x)
                    } else {
                        (1, rz, -ry, a.x)
                    }
                } else if a.y >= a.z {
                    if ry > 0.0 {
                        (2, rx, rz, a.y)
                    } else {
                        (3, rx, -rz, a.y)
                    }
                } else if rz > 0.0 {
                    (4, rx, -ry, a.z)
                } else {
                    (5, -rx, -ry, a.z)
                };
                let (u, v) = ((sc / ma + 1.0) / 2.0, (tc / ma + 1.0) / 2.0);
                let q = cube_face_space(DVec3::ZERO, face).transform_point3(d);
                assert!((q.x / -q.z - (2.0 * u - 1.0)).abs() < 1e-9 && (-q.y / -q.z - (2.0 * v - 1.0)).abs() < 1e-9);
                let (i, j) = (((u * n as f64) as u32).min(n - 1), ((v * n as f64) as u32).min(n - 1));
                let at = 4 * ((face as u32 * n + j) * n + i) as usize;
                let (f, du, dv) = indirection_decode([texels[at], texels[at + 1], texels[at + 2], texels[at + 3]]);
                assert_eq!(f, face as u32, "n {n}: {d}");
                assert!((du - u).abs() <= bound && (dv - v).abs() <= bound, "n {n}: {d}: ({du}, {dv}) for ({u}, {v})");
            }
        }
        assert_eq!(indirection_side(2048), 512);
        assert_eq!(indirection_side(8192), MAX_INDIRECTION);
        assert_eq!(indirection_side(64), MIN_TILE);
    }

    /// The lights' shares of the shadow maps and the sun's cascades add up to the plan's
    /// tiles, texels and caster draws; a light that casts holds tiles, one that does not none.
    #[test]
    fn each_lights_shadow_share_adds_up_to_the_plan() {
        use crate::scene::builtin::{build, BuiltinOptions};
        for (name, cube) in
            [("shadows", ShadowCube::Unrolled), ("shadows", ShadowCube::Array), ("demo", ShadowCube::Unrolled)]
        {
            let scene = build(name, BuiltinOptions::default()).expect("built-in scene");
            let bounds = crate::renderer::scene_gpu::mesh_bounds(&scene);
            let st = super::super::Settings { shadows: ShadowMode::All, shadow_cube: cube, ..Default::default() };
            let plan = test_plan(&scene, &bounds, &st);
            let sun = if plan.params.sun[0] == NO_SHADOW {
                (0, 0, 0)
            } else {
                plan.tiles_share(plan.params.sun[0], plan.params.sun[1])
            };
            let mut sum = sun;
            for i in 0..scene.lights.len() {
                let (t, x, d) = plan.light_share(i);
                assert_eq!(t > 0, plan.lights[i].0 != NO_SHADOW, "{name}: light {i}");
                assert!(t == 0 || x >= t as u64 * (MIN_TILE as u64).pow(2), "{name}: light {i}: {x} texels");
                sum = (sum.0 + t, sum.1 + x, sum.2 + d);
            }
            let texels: u64 = plan.draws.iter().map(|d| d.size as u64 * d.size as u64).sum();
            assert_eq!(sum, (plan.tiles.len() as u32, texels, plan.stats.caster_draws), "{name} {cube:?}");
            assert!(sum.0 > sun.0, "{name}: no light cast");
        }
    }

    #[test]
    fn the_atlas_side_follows_the_budget() {
        assert_eq!(atlas_side(16.0, 4, 8192), 2048);
        assert_eq!(atlas_side(64.0, 4, 8192), 4096);
        assert_eq!(atlas_side(64.0, 4, 2048), 2048);
        assert_eq!(atlas_side(1.0, 4, 8192), 512);
        // Two bytes a texel: twice the texels, the next power of two when it fits.
        assert_eq!(atlas_side(32.0, 2, 8192), 4096);
        assert_eq!(atlas_side(16.0, 2, 8192), 2048);
    }
}
