//! The records the shaders read, with named fields, and the frame's storage buffers that hold
//! them. Each record is declared once, through [`gpu_record!`], which also lists its fields so
//! that `tests/it/shader_contract.rs` can hold every record against its WGSL twin (member names,
//! offsets and size, parsed from the final shader source with naga).

mod buffers;

pub use buffers::{FrameBuffers, FrameLists, COMPOSE_SLOT, SHADOW_TABLE_WIDTH};

use super::options::culling::cutoff_radius;
use super::options::Options;
use super::shadows::cube::indirection_texels;
use crate::renderer::kit::texture;
use crate::scene::{AlphaMode, Camera, Light, Scene};
use glam::{DMat4, Vec4};

/// `GpuLight.kind` of a point light.
pub const LIGHT_KIND_POINT: u32 = 0;
/// `GpuLight.kind` of a spot light.
pub const LIGHT_KIND_SPOT: u32 = 1;
/// Material flags (`GpuObject.info.x`): the object samples a normal map.
pub const MAT_NORMAL_MAP: u32 = 1;
/// The object samples a metallic-roughness map.
pub const MAT_METAL_ROUGH: u32 = 2;
/// The first of four flags, one per map (base colour, normal, emissive, metallic-roughness):
/// the map reads other coordinates than TEXCOORD_0 as they are (`ObjectRecord::uv_transform`).
/// Unflagged maps sample the interpolated TEXCOORD_0 directly, as before transforms existed
/// (some rasterisers, lavapipe among them, pick a mip level slightly differently for a computed
/// coordinate than for an interpolated one).
pub const MAT_UV_TRANSFORMED: u32 = 4;
/// A `metal` object with a metallic-roughness map picks its model per pixel: `metal` where
/// the map's metallic (times the factor) is at least `import::METAL_THRESHOLD`, `blinn-phong`
/// below (bands of paint in a metal keep their diffuse term). Not set when a model is forced.
pub const MAT_METAL_BY_PIXEL: u32 = 64;
/// The object's material has a lightmap (`scene::Lightmap`; its scale in
/// `ObjectRecord::lightmap`).
pub const MAT_LIGHTMAP: u32 = 128;
/// The object samples a base-colour map; without it the map is the white default and is not
/// sampled (a sample costs lavapipe's G-buffer pass about a quarter of its time on a one-surface
/// scene, and white reads back as exactly 1.0).
pub const MAT_BASE_MAP: u32 = 256;
/// The object samples an emissive map (without it, as `MAT_BASE_MAP`: not sampled).
pub const MAT_EMISSIVE_MAP: u32 = 512;
/// Where the lightmap crossfade starts, as a share of `Settings::lightmap_distance` (fully
/// baked at the distance itself).
pub const LIGHTMAP_FADE_START: f32 = 0.8;

pub use super::kit::bindings::{LIGHT_PLANE_BYTES, UNIFORM_LIGHTS};
/// The planes a light record is split into.
pub const LIGHT_PLANE_COUNT: usize = 4;
/// The first shadow tile as stored in plane 3 (24 bits): `NO_SHADOW` is stored as this.
const PLANE_NO_SHADOW: u32 = 0xff_ffff;

/// Whether `lights` can be read from the light planes: at most [`UNIFORM_LIGHTS`], none with a
/// cookie (the planes leave the cookie's fields out). Shadow tiles and kinds are checked when
/// packed ([`light_planes`]).
pub fn planes_hold(lights: &[Light]) -> bool {
    lights.len() <= UNIFORM_LIGHTS && lights.iter().all(|l| l.cookie().is_none())
}

/// The light records split into the four planes `light_at` (common.wgsl) reads, plane after
/// plane, `lights.len()` vec4s each (as u32 bits):
/// 0: position, radius; 1: colour, clamp; 2: direction, cos_outer;
/// 3: cos_inner, falloff, mask, kind | shadow count << 4 | first shadow tile << 8.
/// Left out: `tan_outer` and the cookie's fields (no pass that reads a light at a pixel's index
/// uses them without a cookie). `None` when a light's kind, shadow count or first tile does not
/// fit its bits.
pub fn light_planes(lights: &[LightRecord]) -> Option<Vec<[u32; 4]>> {
    let n = lights.len();
    let mut out = vec![[0u32; 4]; LIGHT_PLANE_COUNT * n];
    let bits = |v: [f32; 3], w: f32| [v[0].to_bits(), v[1].to_bits(), v[2].to_bits(), w.to_bits()];
    for (i, l) in lights.iter().enumerate() {
        let first = if l.shadow[0] == NO_SHADOW { PLANE_NO_SHADOW } else { l.shadow[0] };
        if l.kind > 15
            || l.shadow[1] > 15
            || first > PLANE_NO_SHADOW
            || (first == PLANE_NO_SHADOW) != (l.shadow[0] == NO_SHADOW)
        {
            return None;
        }
        out[i] = bits(l.position, l.radius);
        out[n + i] = bits(l.color, l.clamp);
        out[2 * n + i] = bits(l.direction, l.cos_outer);
        out[3 * n + i] = [l.cos_inner.to_bits(), l.falloff.to_bits(), l.mask, l.kind | l.shadow[1] << 4 | first << 8];
    }
    Some(out)
}

/// `GpuLight.cookie` of a light without a cookie.
pub const NO_COOKIE: u32 = u32::MAX;
/// The largest finite fp16 value: what the fp16 targets saturate at.
pub const FP16_MAX: f32 = 65504.0;
/// The largest finite Rg11b10Ufloat value.
pub const RG11B10_MAX: f32 = 64512.0;

/// A record's WGSL twin: its struct name and its fields' names and byte offsets, in order.
pub struct RecordLayout {
    pub wgsl: &'static str,
    pub size: usize,
    pub fields: Vec<(&'static str, usize)>,
}

/// Declares a `#[repr(C)]` record and its [`RecordLayout`] from one field list.
macro_rules! gpu_record {
    ($(#[$m:meta])* pub struct $name:ident as $wgsl:literal {
        $($(#[$fm:meta])* pub $field:ident : $ty:ty,)*
    }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fm])* pub $field: $ty,)* }

        impl $name {
            pub fn layout() -> RecordLayout {
                RecordLayout {
                    wgsl: $wgsl,
                    size: std::mem::size_of::<$name>(),
                    fields: vec![$((stringify!($field), std::mem::offset_of!($name, $field)),)*],
                }
            }
        }
    };
}

gpu_record! {
    /// The camera and what every pass reads once per frame (`camera` in the shaders).
    pub struct CameraRecord as "Camera" {
        pub proj: [[f32; 4]; 4],
        pub inv_proj: [[f32; 4]; 4],
        /// World to view rotation (no translation): world-space G-buffer layouts (`seed000`)
        /// store normals and view vectors turned back by its transpose.
        pub view_rotation: [[f32; 4]; 4],
        /// width, height, 1/width, 1/height.
        pub screen: [f32; 4],
        pub ambient: [f32; 4],
        /// View-space direction towards the sun; w = 1 when the scene has a sun.
        pub sun_dir: [f32; 4],
        pub sun_color: [f32; 4],
        pub background: [f32; 4],
        pub exposure: f32,
        /// Depth value of the far plane: 1, or 0 with reversed Z.
        pub far_depth: f32,
        /// The most ambient + sun may add to a channel (`overlap::clamps`: the most lights'
        /// rectangles meeting at any tile decide it; filled after planning).
        pub light_clamp: f32,
        pub pad0: f32,
        /// The forward pass's screen tiles: tile size in pixels (0: no tile lists), tiles
        /// across, tiles down, and where the tiles' (first, count) pairs start in the light
        /// lists (filled by `plan::plan_draws`).
        pub forward_tiles: [u32; 4],
        /// Seed 004's lightmap crossfade (`baked_weight` in the shaders): realtime up to x,
        /// fully baked from y (view distance); z = 1 when lightmaps apply this frame.
        pub lightmap_fade: [f32; 4],
        /// The stochastic estimators (`options::stochastic`): the noise seed, RIS's candidates
        /// M and samples K (0: exact shading), 0.
        pub noise: [u32; 4],
        /// Stochastic culling's attenuation threshold (0: off), the planted bias on lights of
        /// odd index (1: none), 0, 0.
        pub stochastic: [f32; 4],
    }
}

gpu_record! {
    /// A light in view space, as the shaders see it. `color` is colour x intensity.
    pub struct LightRecord as "GpuLight" {
        pub position: [f32; 3],
        pub radius: f32,
        pub color: [f32; 3],
        pub kind: u32,
        pub direction: [f32; 3],
        pub cos_outer: f32,
        pub cos_inner: f32,
        pub tan_outer: f32,
        /// The radius the attenuation falls to zero at. `radius` is where the light is cut off
        /// and what its volume bounds: the same, or less under `Settings::light_cutoff`.
        pub falloff: f32,
        /// The most this light may add to a channel (`overlap::clamps`, filled after planning).
        pub clamp: f32,
        /// A spot cookie's "up" in view space (`scene::cookie::spot_up`); its right is
        /// direction x up.
        pub cookie_up: [f32; 3],
        /// Where the cookie's first face starts in `cookie_texels` (a `u32` per texel), or
        /// [`NO_COOKIE`]. A point light's six faces follow each other.
        pub cookie: u32,
        /// Culling mask (seed 004): bit k set = the light lights objects on layer k.
        pub mask: u32,
        /// The cookie's face side in texels.
        pub cookie_size: u32,
        /// The tangent of the half-angle of a spot's bounding cone (`volume_tan`): its outer
        /// angle widened by the rounding of the shader's cone test. 0 for point lights.
        pub volume_tan: f32,
        /// How far the bounding volume is grown all round: the stored position's error where
        /// the layout stores it (`stored_position_pads`); 0 otherwise.
        pub volume_pad: f32,
        /// X, the light's first shadow tile in `shadow_tiles` (a spot's one, a point
        /// light's six faces in a row), or `NO_SHADOW` (unshadowed; filled by `shadows::plan`);
        /// y, its tile count (1 or 6); z, w unused.
        pub shadow: [u32; 4],
    }
}

/// `LightRecord::shadow.x` of a light that casts no shadow this frame.
pub const NO_SHADOW: u32 = u32::MAX;
/// `LightRecord::shadow` of a light that casts no shadow this frame.
pub const UNSHADOWED: [u32; 4] = [NO_SHADOW, 0, 0, 0];

gpu_record! {
    /// One shadow-map tile of the atlas: how a view-space point maps into it.
    /// `to_light` turns view space into the tile's light space (the light looks down -z);
    /// then ndc.xy = q.xy x `proj.xy` / w with w = -q.z (perspective) or 1 (orthographic),
    /// and the stored depth is -q.z x `proj.z` + `proj.w` (linear in distance, 0 ..= 1).
    pub struct ShadowTile as "ShadowTile" {
        pub to_light: [[f32; 4]; 4],
        pub proj: [f32; 4],
        /// The tile in the atlas: u, v of its corner and its size, in atlas uv.
        pub rect: [f32; 4],
        /// Orthographic (1) or perspective (0); the world size of a texel at w = 1; the tile's
        /// resolution in texels; 0.
        pub info: [f32; 4],
    }
}

gpu_record! {
    /// The frame's shadow parameters (`shadow_params` in the shaders; `shadows::plan`).
    pub struct ShadowParams as "ShadowParams" {
        /// The sun's first cascade tile (`NO_SHADOW`: the sun casts none), its cascades, the
        /// filter (`ShadowFilter`), the number of objects (the shadow pass's instance index is
        /// tile x objects + object).
        pub sun: [u32; 4],
        /// View depth (-z) where each cascade ends.
        pub splits: [f32; 4],
        /// Constant bias, slope bias, normal offset (texels), 1 / atlas side.
        pub bias: [f32; 4],
        /// The frame's light count; the casting lights' count and the table row their indices
        /// start at (after the tiles, [`SHADOW_TABLE_WIDTH`] x 4 a row: the `shadow` debug view
        /// walks them); 0.
        pub counts: [u32; 4],
    }
}

gpu_record! {
    /// One drawn object: transforms and material factors.
    pub struct ObjectRecord as "GpuObject" {
        pub model_view: [[f32; 4]; 4],
        pub normal_view: [[f32; 4]; 4],
        /// Albedo, specular level.
        pub albedo_spec: [f32; 4],
        /// Emissive, specular exponent.
        pub emissive_exp: [f32; 4],
        /// Alpha factor, alpha cut-off (mask), normal scale, culling layer (0..=31, seed 004).
        pub material: [f32; 4],
        /// Metallic, roughness, dielectric f0 (used per pixel with a metallic-roughness map),
        /// distortion strength (`Material::distortion`).
        pub pbr: [f32; 4],
        /// Flags (`MAT_*`), first entry in the light lists, count (forward-shaded objects),
        /// reflectance model (`Brdf::id`).
        pub info: [u32; 4],
        /// Per map (base colour, normal, emissive, metallic-roughness) the two rows of its
        /// `UvTransform`; the first row's w is the texture coordinate set.
        pub uv_transform: [[f32; 4]; 8],
        /// The lightmap's scale (`scene::Lightmap::scale`; with `MAT_LIGHTMAP`), 0, 0, 0.
        pub lightmap: [f32; 4],
    }
}

gpu_record! {
    /// The compose pass's parameters, one 256-byte slot per view (`compose` in the shaders).
    pub struct ComposeParams as "ComposeParams" {
        /// A `DebugView`.
        pub view: u32,
        pub pad0: u32,
        /// Target pixel to G-buffer pixel.
        pub scale: [f32; 2],
    }
}

gpu_record! {
    /// The tiled and clustered passes' parameters (`tile_params` in the shaders).
    pub struct TileParams as "TileParams" {
        /// 0: tiled (lists built on the GPU between each tile's depth bounds), 1: clustered,
        /// 2: z-binned (`culling::zbin`; `slices` are its depth bins, `capacity` the lights
        /// sorted).
        pub mode: u32,
        /// Tile size in pixels, tiles across and down, depth slices (1 when tiled).
        pub tile_size: u32,
        pub tiles_x: u32,
        pub tiles_y: u32,
        pub slices: u32,
        pub light_count: u32,
        /// Entries the list region (after the headers) holds.
        pub capacity: u32,
        /// Clustered: a view depth d lies in slice floor(ln(d) x slice_scale + slice_bias).
        pub slice_scale: f32,
        pub slice_bias: f32,
        /// Clustered: the view depths the slices span.
        pub near: f32,
        pub far: f32,
        /// The `tile-lights` view of a clustered frame: 0 shows each pixel's own cluster (at
        /// its surface's depth); d > 0 shows, at every pixel, background included, the cluster
        /// of its tile at view depth d (`Settings::tile_view_depth`).
        pub view_depth: f32,
        /// The light the waste view is restricted to (`Settings::selected_light`), or
        /// `u32::MAX` for every light.
        pub selected: u32,
        /// Z-binned: mask words per tile, where the masks start in `tile_counts`, where the
        /// sorted lights' indices and their rectangles start in `tile_lists`, and the sorted
        /// lights one shading draw walks.
        pub words: u32,
        pub mask_base: u32,
        pub order_base: u32,
        pub rect_base: u32,
        pub chunk: u32,
    }
}

/// Effects after tone mapping the chain holds at most (`post::effects::EFFECTS`):
/// `PostParams::effect` has a slot each.
pub const MAX_EFFECTS: usize = 12;

gpu_record! {
    /// The post chain's parameters (`post_params` in the shaders; `post::params`).
    pub struct PostParams as "PostParams" {
        /// A `Tonemap`.
        pub tonemap: u32,
        pub auto_exposure: u32,
        /// Edge of the grading LUT (0: no grading).
        pub lut_size: u32,
        pub pad0: u32,
        /// The exposure knob (with auto-exposure, a factor on top of the adapted exposure).
        pub exposure: f32,
        /// Bloom: luminance above which pixels bloom, and the factor on the bloom added back.
        pub threshold: f32,
        pub intensity: f32,
        /// Auto-exposure: the target luminance and the fraction of the way moved per frame.
        pub target_luminance: f32,
        pub adapt_rate: f32,
        /// The histogram's log2 luminance range.
        pub log_min: f32,
        pub log_max: f32,
        /// Depth of field's auto focus where the screen's centre pixel is background: the
        /// framed scene's view distance (`post::focus_fallback`).
        pub focus_fallback: f32,
        /// The LUT's input domain (xyz).
        pub lut_min: [f32; 4],
        pub lut_max: [f32; 4],
        /// Fog: density and height falloff.
        pub fog_density: f32,
        pub fog_falloff: f32,
        /// Depth of field: the fixed focus distance (0: auto, the view depth at the screen's
        /// centre) and the CoC in pixels at infinity.
        pub focus_distance: f32,
        pub aperture: f32,
        /// Vignette strength (0: off), and the anti-aliasing (an `Aa`).
        pub vignette: f32,
        pub aa: u32,
        pub pad2: u32,
        pub pad3: u32,
        /// Each effect's own parameters, by its row in `post::effects::EFFECTS`
        /// (`LS_EFFECT_<NAME>`).
        pub effect: [[f32; 4]; MAX_EFFECTS],
    }
}

/// Every record that has a WGSL twin.
pub fn layouts() -> Vec<RecordLayout> {
    vec![
        CameraRecord::layout(),
        LightRecord::layout(),
        ObjectRecord::layout(),
        ComposeParams::layout(),
        TileParams::layout(),
        PostParams::layout(),
        ShadowTile::layout(),
        ShadowParams::layout(),
    ]
}

pub(crate) fn mat(m: DMat4) -> [[f32; 4]; 4] {
    m.as_mat4().to_cols_array_2d()
}

impl LightRecord {
    /// The light in `camera`'s view space, cut off at `cutoff` of its peak
    /// (`Settings::light_cutoff`).
    pub fn in_view(camera: &Camera, light: &Light, cutoff: f32) -> Self {
        Self::in_view_rotated(camera, camera.rotation(), light, cutoff)
    }

    /// [`Self::in_view`] with the camera's rotation computed once by the caller
    /// (`Camera::rotation` takes four sines and cosines: per light it was most of the records'
    /// CPU time at 16,384 lights).
    pub fn in_view_rotated(camera: &Camera, rot: glam::DMat3, light: &Light, cutoff: f32) -> Self {
        let to_view = |p: glam::DVec3| rot * (p - camera.position);
        match light {
            Light::Point(p) => Self {
                position: to_view(p.position).as_vec3().into(),
                radius: cutoff_radius(p.radius, cutoff),
                falloff: p.radius,
                color: (p.color * p.intensity).into(),
                kind: LIGHT_KIND_POINT,
                direction: [0.0, 0.0, -1.0],
                cos_outer: -1.0,
                cos_inner: -1.0,
                tan_outer: 0.0,
                clamp: f32::MAX,
                shadow: UNSHADOWED,
                cookie_up: [0.0, 1.0, 0.0],
                cookie: NO_COOKIE,
                mask: p.mask,
                cookie_size: 0,
                volume_tan: 0.0,
                volume_pad: 0.0,
            },
            Light::Spot(s) => Self {
                position: to_view(s.position).as_vec3().into(),
                radius: cutoff_radius(s.radius, cutoff),
                falloff: s.radius,
                color: (s.color * s.intensity).into(),
                kind: LIGHT_KIND_SPOT,
                direction: (rot * s.direction.as_dvec3()).normalize().as_vec3().into(),
                cos_outer: s.outer_angle.cos(),
                cos_inner: s.inner_angle.cos(),
                tan_outer: s.outer_angle.tan(),
                volume_tan: volume_tan(f64::from(s.outer_angle.cos())),
                clamp: f32::MAX,
                shadow: UNSHADOWED,
                cookie_up: (rot * crate::scene::cookie::spot_up(s.direction.as_dvec3())).as_vec3().into(),
                cookie: NO_COOKIE,
                mask: s.mask,
                cookie_size: 0,
                volume_pad: 0.0,
            },
        }
    }
}

/// Rounding of the shaders' spot test `dot(light_to_surface, direction) >= cos_outer`
/// (`spot_attenuation`, `inside_light`), in units of `f32::EPSILON`: the unit vector to the
/// surface is a difference over its length (WGSL allows 2.5 ULP for the division and 2 for the
/// inverse square root beneath the length: with the sum of squares about 4 ε per component), the
/// direction is an f64 unit vector rounded to f32 (1 ε) and the dot product rounds three
/// products and two sums (1.5 ε): 6.5 ε, which 16 more than doubles. (The cone is widened from
/// the f32 `cos_outer` the shaders compare with.)
pub const SPOT_TEST_ROUNDING: f64 = 16.0;

/// The tangent of a spot's bounding-cone half-angle for outer cosine `cos_outer`: the angle
/// whose cosine is `cos_outer` less [`SPOT_TEST_ROUNDING`], every direction the shaders' f32
/// test may find inside. At small angles the widening is what matters: a spot of outer angle 0
/// lights every point whose computed cosine rounds to 1, up to 2^-12 rad off its axis and more
/// with the rounding above, while a cone of tangent 0 covers no pixel. From about 2 degrees to
/// 89.9 the mesh's own 0.2% margin (`volumes::VOLUME_MARGIN`) already exceeds it.
pub fn volume_tan(cos_outer: f64) -> f32 {
    // tan(acos c), with no transcendental: it runs per spot per frame.
    let c = (cos_outer - SPOT_TEST_ROUNDING * f32::EPSILON as f64).max(-1.0);
    ((1.0 - c * c).max(0.0).sqrt() / c) as f32
}

/// Grows each light's bounding volume (`volume_pad`) by how far a layout that stores the
/// position (`GBufferLayout::position_rounding`, `rounding`: seed 000's and 002's fp16, the
/// reference's f32) may shade a point off the pixel's ray. The stored point s is the surface
/// point t on the pixel's ray (unit direction r) plus an error d, |d| <= sqrt(3) rounding |t|
/// (`stored_position_error`). The depth the volumes are tested against is s's, so a volume
/// that admits the pixel for s must hold q, the point of the ray at s's depth:
/// q - s = (d_z / r_z) r - d, so |q - s| <= |d| (1 + 1 / |r_z|), and 1 / |r_z| is at most the
/// frustum corner's sqrt(1 + tan^2(fov_x / 2) + tan^2(fov_y / 2)) (`proj`). A lit s lies within
/// the light's radius, so |t| <= (|light| + radius)(1 + sqrt(3) rounding); 1.01 covers that and
/// the f32 arithmetic here. At a 0.5-degree field of view seed 000's fp16 view vector is off by
/// about a ninth of the view's height, and a light of radius 3e-4 lit pixels its volume did not
/// cover.
pub fn stored_position_pads(lights: &mut [LightRecord], rounding: f64, proj: &DMat4) {
    if rounding == 0.0 {
        return;
    }
    let (tx, ty) = (1.0 / proj.x_axis.x, 1.0 / proj.y_axis.y);
    let off_ray = 1.0 + (1.0 + tx * tx + ty * ty).sqrt();
    let k = 3f64.sqrt() * rounding * off_ray * 1.01;
    for l in lights {
        let reach = glam::Vec3::from(l.position).length() as f64 + l.radius as f64;
        l.volume_pad = (k * reach) as f32;
    }
}

impl CameraRecord {
    pub fn new(scene: &Scene, o: &Options, size: (u32, u32), accum: wgpu::TextureFormat) -> Self {
        let (width, height) = size;
        let cam = &scene.camera;
        let proj = cam.projection(width as f64 / height as f64, o.frame.reversed_z);
        let rot = cam.rotation();
        let sun = scene.sun.map(|s| {
            let d = (rot * (-s.direction.as_dvec3())).normalize().as_vec3();
            (d.extend(1.0), (s.color * s.intensity).extend(0.0))
        });
        let (sun_dir, sun_color) = sun.unwrap_or((Vec4::ZERO, Vec4::ZERO));
        Self {
            proj: mat(proj),
            inv_proj: mat(proj.inverse()),
            view_rotation: mat(DMat4::from_mat3(rot)),
            screen: [width as f32, height as f32, 1.0 / width as f32, 1.0 / height as f32],
            ambient: scene.ambient.extend(0.0).into(),
            sun_dir: sun_dir.into(),
            sun_color: sun_color.into(),
            background: scene.background.extend(1.0).into(),
            exposure: o.post.exposure,
            far_depth: if o.frame.reversed_z { 0.0 } else { 1.0 },
            light_clamp: light_clamp(accum, scene.lights.len()),
            pad0: 0.0,
            forward_tiles: [0; 4],
            lightmap_fade: {
                let on = o.surfaces.lightmaps && crate::scene::lightmap::any(scene);
                let d = o.surfaces.lightmap_distance;
                [d * LIGHTMAP_FADE_START, d, if on { 1.0 } else { 0.0 }, 0.0]
            },
            noise: o.stochastic.noise_words(),
            stochastic: o.stochastic.culling_words(),
        }
    }
}

impl ObjectRecord {
    /// Object `o` of `scene` seen from `view` (world to view). The light-list fields are left
    /// at zero for `plan::plan_draws` to fill.
    /// `force`: the reflectance model every object is shaded with (`Settings::brdf`), else the
    /// material's (`info.w`).
    pub fn new(scene: &Scene, o: &crate::scene::Object, view: DMat4, force: Option<crate::scene::Brdf>) -> Self {
        let mv = view * o.transform;
        let nm = DMat4::from_mat3(glam::DMat3::from_mat4(mv).inverse().transpose());
        let m = &scene.materials[o.material];
        let mut flags = 0;
        if m.textures.normal.is_some() {
            flags |= MAT_NORMAL_MAP;
        }
        if m.textures.metallic_roughness.is_some() {
            flags |= MAT_METAL_ROUGH;
        }
        if m.textures.base_color.is_some() {
            flags |= MAT_BASE_MAP;
        }
        if m.textures.emissive.is_some() {
            flags |= MAT_EMISSIVE_MAP;
        }
        let u = &m.uvs;
        for (k, t) in [u.base_color, u.normal, u.emissive, u.metallic_roughness].iter().enumerate() {
            if !t.is_identity() || t.set != 0 {
                flags |= MAT_UV_TRANSFORMED << k;
            }
        }
        if force.is_none() && m.brdf == crate::scene::Brdf::Metal && m.textures.metallic_roughness.is_some() {
            flags |= MAT_METAL_BY_PIXEL;
        }
        if m.lightmap.is_some() {
            flags |= MAT_LIGHTMAP;
        }
        let cutoff = match m.alpha_mode {
            AlphaMode::Mask { cutoff } => cutoff,
            _ => 0.0,
        };
        Self {
            model_view: mat(mv),
            normal_view: mat(nm),
            albedo_spec: m.diffuse.extend(m.specular_level).into(),
            emissive_exp: m.emissive.extend(m.specular_exponent).into(),
            material: [m.alpha, cutoff, m.normal_scale, f32::from(o.layer & 31)],
            // With a metallic-roughness map the importer keeps f0 in specular_level.
            pbr: [m.metallic, m.roughness, m.specular_level, m.distortion.clamp(0.0, crate::scene::MAX_DISTORTION)],
            info: [flags, 0, 0, force.unwrap_or(m.brdf).id()],
            uv_transform: {
                let u = &m.uvs;
                let [a, b, c, d] = [u.base_color, u.normal, u.emissive, u.metallic_roughness].map(|t| t.rows());
                [a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]]
            },
            lightmap: [m.lightmap.map_or(0.0, |l| l.scale), 0.0, 0.0, 0.0],
        }
    }
}

/// The records of one frame, before upload.
pub struct FrameRecords {
    pub camera: CameraRecord,
    pub lights: Vec<LightRecord>,
    pub objects: Vec<ObjectRecord>,
    /// The projection the frame is drawn with (f64, for the probe and the plans).
    pub proj: DMat4,
    /// World to view.
    pub view: DMat4,
}

impl FrameRecords {
    pub fn new(scene: &Scene, o: &Options, size: (u32, u32), accum: wgpu::TextureFormat) -> Self {
        Self::reusing(scene, o, size, accum, Vec::new())
    }

    /// [`FrameRecords::new`] with the light records written into `lights` (emptied first; its
    /// allocation is kept). The renderer hands back the records of the frame before last: a
    /// fresh 1.8 MB at 16,384 lights was faulted in page by page on every other frame once the
    /// allocator had returned the last one to the system (416 page faults, about 0.35 ms).
    pub fn reusing(
        scene: &Scene,
        o: &Options,
        size: (u32, u32),
        accum: wgpu::TextureFormat,
        mut lights: Vec<LightRecord>,
    ) -> Self {
        let cam = &scene.camera;
        let view = DMat4::from_mat3(cam.rotation()) * DMat4::from_translation(-cam.position);
        lights.clear();
        let rot = cam.rotation();
        let starts = cookie_starts(scene);
        lights.extend(scene.lights.iter().map(|l| {
            let mut r = LightRecord::in_view_rotated(cam, rot, l, o.culling.light_cutoff);
            if let Some((start, image)) =
                l.cookie().and_then(|c| Some((*starts.get(c as usize)?, scene.cookies.get(c as usize)?)))
            {
                r.cookie = start;
                r.cookie_size = image.size;
            }
            r
        }));
        Self {
            camera: CameraRecord::new(scene, o, size, accum),
            lights,
            objects: scene
                .objects
                .iter()
                .map(|ob| ObjectRecord::new(scene, ob, view, o.surfaces.brdf.brdf()))
                .collect(),
            proj: cam.projection(size.0 as f64 / size.1 as f64, o.frame.reversed_z),
            view,
        }
    }
}

/// Where each of `scene.cookies` starts in the cookie texel buffer (`cookie_texels`, one
/// `u32` per texel, the cookies one after the other).
pub fn cookie_starts(scene: &Scene) -> Vec<u32> {
    let mut at = 0u64;
    scene
        .cookies
        .iter()
        .map(|c| {
            let start = at;
            at += c.faces.len() as u64 * c.size as u64 * c.size as u64;
            start.min(u32::MAX as u64 - 1) as u32
        })
        .collect()
}

/// Texels per row of the cookie texture (`cookie_texels`): texel i is at (i % row, i / row).
pub const COOKIE_ROW: u32 = 4096;

/// The cookie texel buffer's contents for `scene` (at least one word).
pub fn cookie_words(scene: &Scene) -> Vec<u32> {
    let mut words: Vec<u32> = scene.cookies.iter().flat_map(|c| c.words().collect::<Vec<_>>()).collect();
    if words.is_empty() {
        words.push(0);
    }
    words
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::Settings;

    fn light(k: u32) -> LightRecord {
        let f = |x: u32| x as f32 + 0.25 * k as f32;
        LightRecord {
            position: [f(1), f(2), f(3)],
            radius: f(4),
            color: [f(5), f(6), f(7)],
            kind: k % 2,
            direction: [f(8), f(9), f(10)],
            cos_outer: f(11),
            cos_inner: f(12),
            tan_outer: f(13),
            falloff: f(14),
            clamp: f(15),
            cookie_up: [0.0; 3],
            cookie: NO_COOKIE,
            mask: 0xdead_0000 | k,
            cookie_size: 0,
            volume_tan: 0.0,
            volume_pad: 0.0,
            shadow: if k == 1 { UNSHADOWED } else { [7 * k, 6, 0, 0] },
        }
    }

    /// What `light_at` (common.wgsl) reads back from the planes, field by field.
    fn unpack(planes: &[[u32; 4]], n: usize, i: usize) -> LightRecord {
        let [a, b, c, e] = [planes[i], planes[n + i], planes[2 * n + i], planes[3 * n + i]];
        let v = |w: [u32; 4]| [f32::from_bits(w[0]), f32::from_bits(w[1]), f32::from_bits(w[2])];
        let first = e[3] >> 8;
        LightRecord {
            position: v(a),
            radius: f32::from_bits(a[3]),
            color: v(b),
            clamp: f32::from_bits(b[3]),
            direction: v(c),
            cos_outer: f32::from_bits(c[3]),
            cos_inner: f32::from_bits(e[0]),
            falloff: f32::from_bits(e[1]),
            mask: e[2],
            kind: e[3] & 15,
            shadow: [if first == 0xff_ffff { NO_SHADOW } else { first }, (e[3] >> 4) & 15, 0, 0],
            cookie: NO_COOKIE,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    #[test]
    fn the_light_planes_hold_every_field_the_loops_read() {
        let lights: Vec<LightRecord> = (0..5).map(light).collect();
        let planes = light_planes(&lights).expect("these lights fit the planes");
        assert_eq!(planes.len(), LIGHT_PLANE_COUNT * lights.len());
        for (i, l) in lights.iter().enumerate() {
            let back = unpack(&planes, lights.len(), i);
            // Left out: tan_outer (the volumes' shapes read it from `lights`) and the cookie's
            // fields (planes are not used with cookies).
            let want = LightRecord { tan_outer: 0.0, ..*l };
            assert_eq!(bytemuck::bytes_of(&back), bytemuck::bytes_of(&want), "light {i}");
        }
    }

    #[test]
    fn records_written_into_a_used_allocation_are_the_fresh_ones() {
        let scene = match crate::scene::builtin::build(
            "demo",
            crate::scene::builtin::BuiltinOptions { lights: Some(300), time: 1.5 },
        ) {
            Ok(s) => s,
            Err(e) => panic!("{e:#}"),
        };
        let settings = Settings::default();
        let fmt = wgpu::TextureFormat::Rgba16Float;
        let fresh = FrameRecords::new(&scene, &settings.options(), (640, 360), fmt);
        // A spare holding more, different records (the frame before last's, of a larger scene).
        let spare: Vec<LightRecord> = (0..1000).map(light).collect();
        let reused = FrameRecords::reusing(&scene, &settings.options(), (640, 360), fmt, spare);
        assert_eq!(reused.lights.len(), scene.lights.len());
        assert!(bytemuck::cast_slice::<_, u8>(&reused.lights) == bytemuck::cast_slice::<_, u8>(&fresh.lights));
        assert!(reused.lights.capacity() >= 1000, "the spare's allocation was not kept");
    }

    #[test]
    fn lights_whose_fields_overflow_the_planes_bits_are_refused() {
        let mut l = light(2);
        l.shadow = [0xff_ffff, 1, 0, 0];
        assert!(light_planes(&[l]).is_none(), "a first tile that reads back as no shadow");
        l.shadow = [3, 16, 0, 0];
        assert!(light_planes(&[l]).is_none(), "a tile count over 15");
        l.shadow = [3, 6, 0, 0];
        l.kind = 16;
        assert!(light_planes(&[l]).is_none(), "a kind over 15");
        l.kind = 1;
        assert!(light_planes(&[l]).is_some());
    }
}

/// The largest finite value of an accumulation format whose sums must stay finite, `None` for
/// formats that cannot overflow in practice (Rgba32Float; Rgba8Log saturates at a finite value).
pub fn format_max(format: wgpu::TextureFormat) -> Option<f32> {
    match format {
        wgpu::TextureFormat::Rgba16Float => Some(FP16_MAX),
        wgpu::TextureFormat::Rg11b10Ufloat => Some(RG11B10_MAX),
        _ => None,
    }
}

/// The most one term may add to a channel when at most `overlap` lights meet at a tile it
/// covers (see the module's proof); `f32::MAX` for formats without overflow.
pub fn light_clamp(format: wgpu::TextureFormat, overlap: usize) -> f32 {
    match format_max(format) {
        Some(max) => max / (3.0 * (overlap as f32 + 1.0)),
        None => f32::MAX,
    }
}
