//! What is drawn: camera, meshes, materials and lights. Plain data, no GPU objects.

pub mod builtin;
pub mod camera_path;
pub mod cookie;
pub mod import;
pub mod lightmap;
pub mod occluders;
mod open;
pub mod room;

pub use open::{open, unused_light_count};

use glam::{DMat3, DMat4, DVec3, Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// A perspective camera. Position is f64 so scenes far from the origin keep their precision:
/// the renderer works in camera-relative (view) space and never sends world positions to the GPU.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    /// Radians around +Y; 0 looks down -Z.
    pub yaw: f64,
    /// Radians above the horizon.
    pub pitch: f64,
    /// Vertical field of view in radians.
    pub fov_y: f64,
    pub near: f64,
    pub far: f64,
}

impl Camera {
    pub fn looking_at(position: DVec3, target: DVec3) -> Self {
        let d = (target - position).normalize_or(DVec3::NEG_Z);
        Self {
            position,
            yaw: d.x.atan2(-d.z),
            pitch: d.y.clamp(-1.0, 1.0).asin(),
            fov_y: 60f64.to_radians(),
            near: 0.1,
            far: 400.0,
        }
    }

    pub fn forward(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        DVec3::new(sy * cp, sp, -cy * cp)
    }

    pub fn right(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        DVec3::new(cy, 0.0, sy)
    }

    /// World-to-view rotation (rows: right, up, back).
    pub fn rotation(&self) -> DMat3 {
        let f = self.forward();
        let r = self.right();
        let u = r.cross(f);
        DMat3::from_cols(r, u, -f).transpose()
    }

    /// A world point in view space, computed in f64.
    pub fn to_view(&self, p: DVec3) -> DVec3 {
        self.rotation() * (p - self.position)
    }

    /// Right-handed projection to depth [0, 1]; `reversed` maps near to 1 and far to 0.
    pub fn projection(&self, aspect: f64, reversed: bool) -> DMat4 {
        let ys = 1.0 / (self.fov_y * 0.5).tan();
        let xs = ys / aspect;
        let (n, f) = if reversed { (self.far, self.near) } else { (self.near, self.far) };
        DMat4::from_cols(
            glam::DVec4::new(xs, 0.0, 0.0, 0.0),
            glam::DVec4::new(0.0, ys, 0.0, 0.0),
            glam::DVec4::new(0.0, 0.0, f / (n - f), -1.0),
            glam::DVec4::new(0.0, 0.0, n * f / (n - f), 0.0),
        )
    }

    /// Checks the values a user or a file can set.
    pub fn validate(&self) -> Result<(), String> {
        let finite = self.position.is_finite() && self.yaw.is_finite() && self.pitch.is_finite();
        if !finite {
            return Err("camera position and angles must be finite".into());
        }
        if !(self.fov_y > 1e-3 && self.fov_y < std::f64::consts::PI - 1e-3) {
            return Err(format!("field of view {:.3} rad is outside (0, pi)", self.fov_y));
        }
        if !(self.near > 0.0 && self.far > self.near && self.far.is_finite()) {
            return Err(format!("need 0 < near < far, got near {} far {}", self.near, self.far));
        }
        Ok(())
    }
}

#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    /// xyz: tangent along +u, w: handedness (+1/-1) of the bitangent. Zero when the mesh has no
    /// normal map (the shader then ignores it).
    pub tangent: [f32; 4],
    /// The second texture coordinate set (glTF TEXCOORD_1), for maps that name it.
    pub uv1: [f32; 2],
}

impl Vertex {
    pub fn new(position: [f32; 3], normal: [f32; 3], uv: [f32; 2]) -> Self {
        Self { position, normal, uv, tangent: [0.0; 4], uv1: [0.0; 2] }
    }
}

/// An RGBA8 image a material samples. Colour textures (base colour, emissive) are sRGB-encoded;
/// data textures (normal, metallic-roughness) are linear.
#[derive(Clone, Debug)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub srgb: bool,
    /// `width * height * 4` bytes, rows top to bottom.
    pub rgba: Vec<u8>,
}

/// Texels per square of [`Texture::missing`]'s checker.
pub const MISSING_CELL: u32 = 16;

impl Texture {
    /// The visible stand-in for a colour texture that could not be loaded: a magenta and black
    /// checker, as engines show a missing texture. 8 x 8 squares of [`MISSING_CELL`] texels:
    /// magnified with bilinear filtering, only a one-texel band at each square's edge blends,
    /// so the squares stay sharp instead of washing into a pink gradient.
    pub fn missing(name: &str, srgb: bool) -> Self {
        let n = 8 * MISSING_CELL;
        let mut rgba = Vec::with_capacity((n * n * 4) as usize);
        for y in 0..n {
            for x in 0..n {
                let on = (x / MISSING_CELL + y / MISSING_CELL).is_multiple_of(2);
                rgba.extend_from_slice(if on { &[255, 0, 255, 255] } else { &[0, 0, 0, 255] });
            }
        }
        Self { name: format!("{name} (missing)"), width: n, height: n, srgb, rgba }
    }
}

/// How a material's alpha is used (glTF's `alphaMode`).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub enum AlphaMode {
    /// Alpha ignored: drawn into the G-buffer.
    #[default]
    Opaque,
    /// Punch-through: fragments with alpha below the cutoff are discarded in the G-buffer pass.
    Mask { cutoff: f32 },
    /// Blended: deferred shading cannot shade it (one surface per pixel), so it is drawn after
    /// lighting in a forward pass, sorted back to front, lit by the same lights.
    Blend,
}

/// How a mesh's indices are drawn: triangle lists, or glTF's points and lines (line strips and
/// loops become lists), which are drawn one pixel wide into the G-buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Topology {
    #[default]
    Triangles,
    Lines,
    Points,
}

#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    /// Lines and points usually have no normals: theirs are zero, and a zero normal is shaded
    /// as facing the viewer (`safe_normalize`'s fallback in the shaders).
    pub topology: Topology,
}

/// The cube's lightmap layout (its TEXCOORD_1): face k in cell (k % 3, k / 3) of a 3 x 2 grid,
/// inset by [`CUBE_LIGHTMAP_INSET`] of a cell on each side so that bilinear filtering at a
/// face's edge reads only that face's texels (down to 8 x 8 texels a cell).
pub fn cube_lightmap_uv(face: usize, uv: Vec2) -> Vec2 {
    let cell = Vec2::new((face % 3) as f32, (face / 3) as f32);
    let inset = uv * (1.0 - 2.0 * CUBE_LIGHTMAP_INSET) + Vec2::splat(CUBE_LIGHTMAP_INSET);
    (cell + inset) / Vec2::new(3.0, 2.0)
}

/// The inset of a cube face in its lightmap cell, as a share of the cell.
pub const CUBE_LIGHTMAP_INSET: f32 = 1.0 / 16.0;

impl Mesh {
    /// An axis-aligned unit cube centred on the origin, with per-face normals; TEXCOORD_1 lays
    /// the faces out for a lightmap ([`cube_lightmap_uv`]).
    pub fn cube() -> Self {
        let mut m = Mesh { name: "cube".into(), ..Default::default() };
        let faces: [(Vec3, Vec3, Vec3); 6] = [
            (Vec3::X, Vec3::Y, Vec3::Z),
            (Vec3::NEG_X, Vec3::Y, Vec3::NEG_Z),
            (Vec3::Y, Vec3::Z, Vec3::X),
            (Vec3::NEG_Y, Vec3::Z, Vec3::NEG_X),
            (Vec3::Z, Vec3::Y, Vec3::NEG_X),
            (Vec3::NEG_Z, Vec3::Y, Vec3::X),
        ];
        for (k, (n, up, right)) in faces.into_iter().enumerate() {
            let base = m.vertices.len() as u32;
            for (u, v) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                let p = n * 0.5 + right * (u - 0.5) + up * (v - 0.5);
                let mut vertex = Vertex::new(p.into(), n.into(), Vec2::new(u, v).into());
                vertex.uv1 = cube_lightmap_uv(k, Vec2::new(u, v)).into();
                m.vertices.push(vertex);
            }
            // Counter-clockwise seen from outside: right x up = normal.
            let ccw = right.cross(up).dot(n) > 0.0;
            if ccw {
                m.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            } else {
                m.indices.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
            }
        }
        m
    }
}

/// The reflectance model a material is shaded with (seed 002's material ID: the G-buffer keeps
/// it per pixel when a scene uses more than one, see `renderer::gbuffer`). The discriminants
/// are the stored IDs and the WGSL constants `LS_BRDF_*`.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Brdf {
    /// Lambert diffuse + normalised Blinn-Phong specular in white (the model before IDs).
    #[default]
    BlinnPhong = 0,
    /// Lambert diffuse only: no specular term, from lights, sun or ambient.
    Lambert = 1,
    /// A conductor: no diffuse term; the Blinn-Phong lobe tinted by the base colour (the
    /// albedo channel holds the specular colour F0, the specular channel a scalar on it).
    Metal = 2,
    /// Banded: diffuse N.L in three steps (1/3, 2/3, 1), the highlight one flat band where the
    /// Blinn-Phong lobe exceeds half its peak. The distance and spot falloffs stay smooth.
    Toon = 3,
    /// glTF `KHR_materials_unlit`: the base colour as it is (times exposure); lights, sun and
    /// ambient add nothing.
    Unlit = 4,
    /// Seed 000's "standard Phong function": Lambert diffuse + level x (R.V)^n in white, R the
    /// light's direction mirrored about the normal (Phong 1975), with no N.L on the highlight
    /// and nothing where N.L <= 0. The level is the material's as it is (no normalisation).
    Phong = 5,
}

impl Brdf {
    pub const ALL: [Brdf; 6] = [Brdf::BlinnPhong, Brdf::Lambert, Brdf::Metal, Brdf::Toon, Brdf::Unlit, Brdf::Phong];

    /// The value's one name (`blinn-phong`, `lambert`, `metal`, `toon`, `unlit`, `phong`).
    pub fn name(self) -> String {
        clap::ValueEnum::to_possible_value(&self).map_or_else(String::new, |p| p.get_name().to_string())
    }

    /// The ID stored in the G-buffer's material channel.
    pub fn id(self) -> u32 {
        self as u32
    }

    /// Whether the light pre-pass's one buffer (every light's Blinn-Phong terms at unit
    /// reflectance, summed) can shade the model in its final pass: not toon (it bands each
    /// light's terms apart) nor Phong (another lobe); those are shaded forward after pass 3.
    pub fn prepass_lit(self) -> bool {
        !matches!(self, Brdf::Toon | Brdf::Phong)
    }

    /// Whether the model uses the specular level and exponent.
    pub fn specular(self) -> bool {
        matches!(self, Brdf::BlinnPhong | Brdf::Metal | Brdf::Toon | Brdf::Phong)
    }

    /// The colour the `material-id` debug view paints the model in (linear RGB; the viewer's
    /// legend shows the same).
    pub fn debug_color(self) -> [f32; 3] {
        match self {
            Brdf::BlinnPhong => [0.55, 0.55, 0.55],
            Brdf::Lambert => [0.1, 0.35, 0.9],
            Brdf::Metal => [0.95, 0.65, 0.1],
            Brdf::Toon => [0.85, 0.15, 0.6],
            Brdf::Unlit => [0.15, 0.8, 0.25],
            Brdf::Phong => [0.9, 0.9, 0.75],
        }
    }
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Material {
    /// Linear diffuse albedo.
    pub diffuse: Vec3,
    /// Blinn-Phong specular level in [0, 1].
    pub specular_level: f32,
    /// Blinn-Phong exponent in [1, 2048].
    pub specular_exponent: f32,
    /// Linear emitted radiance.
    pub emissive: Vec3,
    /// Opacity (glTF base colour alpha factor), multiplied by the base colour texture's alpha.
    #[serde(default = "one")]
    pub alpha: f32,
    #[serde(default)]
    pub alpha_mode: AlphaMode,
    /// Both faces drawn (back faces with the normal flipped); else back faces are culled.
    #[serde(default)]
    pub double_sided: bool,
    #[serde(default)]
    pub textures: MaterialTextures,
    /// Strength of the normal map (glTF `normalTexture.scale`).
    #[serde(default = "one")]
    pub normal_scale: f32,
    /// glTF metallic and roughness factors, used per pixel when `textures.metallic_roughness`
    /// is set: the shader then derives diffuse, specular level and exponent from them with
    /// [`Material::from_metallic_roughness`]'s mapping. Without that texture the mapping is
    /// applied once on the CPU and these are informational.
    #[serde(default)]
    pub metallic: f32,
    #[serde(default = "one")]
    pub roughness: f32,
    /// Each map's texture coordinate set and transform.
    #[serde(default)]
    pub uvs: MaterialUvs,
    /// The reflectance model (seed 002's material ID).
    #[serde(default)]
    pub brdf: Brdf,
    /// Seed 002's post-processing distortion: where the surface is visible, the picture behind
    /// it is shifted by this times the view-space normal's x and y, in fractions of the screen
    /// height (`--distortion`; 0: none). glTF: the material's `extras` `{"distortion": k}`.
    #[serde(default)]
    pub distortion: f32,
    /// Seed 004's lightmap, read with the second texture coordinate set (TEXCOORD_1): see
    /// [`Lightmap`]. glTF: the material's `extras` `{"lightmap": {"texture": i, "scale": s}}`.
    #[serde(default)]
    pub lightmap: Option<Lightmap>,
}

/// A baked lightmap (seed 004: "Lightmaps are also applied in the final pass"): a linear RGBA8
/// texture, read at the surface's TEXCOORD_1. RGB is the baked diffuse irradiance (ambient
/// through its occlusion, plus the sun through its visibility) divided by `scale`; A is the
/// ambient occlusion, the share of the sky the point sees (what the renderer adds near the
/// camera: "only baked indirect lighting"). `lampshade bake` writes them
/// (`scene::lightmap`).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Lightmap {
    /// Index into `Scene::textures`.
    pub texture: usize,
    /// The irradiance RGB = 1 stands for.
    pub scale: f32,
}

/// The largest [`Material::distortion`]: a shift of a quarter of the screen height.
pub const MAX_DISTORTION: f32 = 0.25;

fn one() -> f32 {
    1.0
}

/// Indices into [`Scene::textures`].
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct MaterialTextures {
    /// sRGB; multiplies `diffuse` (rgb) and `alpha` (a).
    pub base_color: Option<usize>,
    /// Linear, tangent space (glTF convention: +y up in the texture).
    pub normal: Option<usize>,
    /// sRGB; multiplies `emissive`.
    pub emissive: Option<usize>,
    /// Linear; roughness in green, metallic in blue (glTF).
    pub metallic_roughness: Option<usize>,
}

/// Which texture coordinates a map reads and how they are transformed before sampling
/// (glTF's `texCoord` and `KHR_texture_transform`): uv' = offset + R(rotation) (scale * uv),
/// the extension's translation x rotation x scale.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct UvTransform {
    /// 0: `Vertex::uv`, 1: `Vertex::uv1`.
    pub set: u32,
    pub offset: Vec2,
    /// Radians, counter-clockwise in the texture as glTF defines it.
    pub rotation: f32,
    pub scale: Vec2,
}

impl Default for UvTransform {
    fn default() -> Self {
        Self { set: 0, offset: Vec2::ZERO, rotation: 0.0, scale: Vec2::ONE }
    }
}

impl UvTransform {
    /// The two rows of the 2x3 matrix, each with a fourth value: the set (first row), 0.
    /// The extension's matrix is T R S with R = [[cos, sin], [-sin, cos]] (row-major), the
    /// direction Khronos' TextureTransformTest sample checks.
    pub fn rows(&self) -> [[f32; 4]; 2] {
        let (s, c) = self.rotation.sin_cos();
        let (sx, sy) = (self.scale.x, self.scale.y);
        [[c * sx, s * sy, self.offset.x, self.set as f32], [-s * sx, c * sy, self.offset.y, 0.0]]
    }

    /// The transformed coordinates of `uv` (what the shader computes).
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let [r0, r1] = self.rows();
        Vec2::new(r0[0] * uv.x + r0[1] * uv.y + r0[2], r1[0] * uv.x + r1[1] * uv.y + r1[2])
    }

    pub fn is_identity(&self) -> bool {
        *self == Self { set: self.set, ..Self::default() }
    }
}

/// Per map of a material, its [`UvTransform`] (the same slots as [`MaterialTextures`]).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct MaterialUvs {
    pub base_color: UvTransform,
    pub normal: UvTransform,
    pub emissive: UvTransform,
    pub metallic_roughness: UvTransform,
}

impl Default for Material {
    fn default() -> Self {
        Self::diffuse(Vec3::splat(0.8))
    }
}

/// The largest specular level a material of this exponent can have: reflectance f0 = 1 under
/// the Blinn-Phong normalisation, (exponent + 8) / 8.
pub fn max_specular_level(exponent: f32) -> f32 {
    (exponent.max(1.0) + 8.0) / 8.0
}

/// Dielectric reflectance at normal incidence (glTF's default, ior 1.5).
pub const DIELECTRIC_F0: f32 = 0.04;

/// Luminance of linear RGB: the Rec. 709 (sRGB) weights. The shaders get it as the generated
/// `LS_LUMINANCE`.
pub const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// [`LUMINANCE`] as an f32 vector.
pub fn luminance_weights() -> Vec3 {
    let [r, g, b] = LUMINANCE.map(|w| w as f32);
    Vec3::new(r, g, b)
}

impl Material {
    pub fn diffuse(c: Vec3) -> Self {
        Self {
            diffuse: c,
            specular_level: 0.3,
            specular_exponent: 32.0,
            emissive: Vec3::ZERO,
            alpha: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            textures: MaterialTextures::default(),
            normal_scale: 1.0,
            metallic: 0.0,
            roughness: 1.0,
            uvs: MaterialUvs::default(),
            brdf: Brdf::BlinnPhong,
            distortion: 0.0,
            lightmap: None,
        }
    }

    /// The `metal` model's terms from glTF's metallic-roughness (mirrored in WGSL by
    /// `metal_from_pbr`): the specular colour F0 = mix(dielectric_f0, base, metallic) (glTF's
    /// own F0) goes to the albedo channel, the specular level is the normalised peak of
    /// reflectance 1 ((exponent + 8) / 8), the exponent as [`Material::blinn_phong_from_pbr`].
    /// The diffuse part a partly metallic pixel would have, base x (1 - metallic), is left out:
    /// the metal model has no diffuse term (the importer picks it for metallic >= 0.5 only).
    ///
    /// Returns (specular colour, specular level, specular exponent).
    pub fn metal_from_pbr(base: Vec3, metallic: f32, roughness: f32, dielectric_f0: f32) -> (Vec3, f32, f32) {
        let m = metallic.clamp(0.0, 1.0);
        let (_, _, exponent) = Self::blinn_phong_from_pbr(base, m, roughness, dielectric_f0);
        let f0 = Vec3::splat(dielectric_f0.clamp(0.0, 1.0)).lerp(base.clamp(Vec3::ZERO, Vec3::ONE), m);
        (f0, (exponent + 8.0) / 8.0, exponent)
    }

    /// Blinn-Phong terms from glTF's metallic-roughness model (mirrored in WGSL by
    /// `blinn_phong_from_pbr`; keep the two in step):
    /// - diffuse = base x (1 - metallic): metals have no diffuse term;
    /// - f0 = mix(dielectric_f0, luminance(base), metallic): the specular colour of a metal is
    ///   reduced to a scalar level, since our specular term is white (a stated limitation);
    /// - alpha = roughness^2, exponent = 2/alpha^2 - 2 (the Blinn-Phong lobe with the same
    ///   width as a Beckmann/GGX lobe of that roughness), clamped to [1, 2048];
    /// - level = f0 x (exponent + 8) / 8: the Blinn-Phong normalisation, so a smooth surface's
    ///   narrow highlight keeps its energy instead of vanishing. Not clamped: a polished metal's
    ///   level reaches (2048 + 8) / 8 = 257; the G-buffer stores f0 (see
    ///   `renderer::gbuffer::level_from_reflectance`).
    ///
    /// Returns (diffuse, specular level, specular exponent).
    pub fn blinn_phong_from_pbr(base: Vec3, metallic: f32, roughness: f32, dielectric_f0: f32) -> (Vec3, f32, f32) {
        let m = metallic.clamp(0.0, 1.0);
        let r = roughness.clamp(0.0, 1.0);
        let lum = base.dot(luminance_weights());
        let f0 = dielectric_f0 + (lum - dielectric_f0) * m;
        let a = (r * r).max(1e-3);
        let exponent = (2.0 / (a * a) - 2.0).clamp(1.0, 2048.0);
        let level = f0.clamp(0.0, 1.0) * (exponent + 8.0) / 8.0;
        (base * (1.0 - m), level, exponent)
    }

    /// The models the material's pixels use: its own, and `blinn-phong` too for a metal with a
    /// metallic-roughness map, whose less metallic pixels are shaded so
    /// (`renderer::records::MAT_METAL_BY_PIXEL`).
    pub fn brdfs(&self) -> Vec<Brdf> {
        if self.brdf == Brdf::Metal && self.textures.metallic_roughness.is_some() {
            vec![Brdf::BlinnPhong, Brdf::Metal]
        } else {
            vec![self.brdf]
        }
    }

    pub fn is_blended(&self) -> bool {
        self.alpha_mode == AlphaMode::Blend
    }
}

/// One mesh placed in the world with one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub mesh: usize,
    pub material: usize,
    pub transform: DMat4,
    /// Culling layer (seed 004), 0..=31: lit only by lights whose `mask` has bit `layer`.
    pub layer: u8,
}

/// Every layer: the mask of a light that lights everything (the default).
pub const ALL_LAYERS: u32 = u32::MAX;

fn all_layers() -> u32 {
    ALL_LAYERS
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct PointLight {
    pub position: DVec3,
    pub color: Vec3,
    pub intensity: f32,
    /// Distance at which the light's contribution reaches exactly zero.
    pub radius: f32,
    /// Cookie (seed 004): index into `Scene::cookies` of a cube cookie.
    #[serde(default)]
    pub cookie: Option<u32>,
    /// Culling mask (seed 004): bit k set = lights objects on layer k.
    #[serde(default = "all_layers")]
    pub mask: u32,
    /// Whether the light may cast a shadow (`Settings::shadows` decides which kinds do; this
    /// flag only turns one light off). Settings and scene files, glTF `extras.cast_shadows`.
    #[serde(default = "cast_shadows_default")]
    pub cast_shadows: bool,
}

fn cast_shadows_default() -> bool {
    true
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct SpotLight {
    pub position: DVec3,
    pub direction: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub radius: f32,
    /// Half-angle (radians) inside which the light is at full strength.
    pub inner_angle: f32,
    /// Half-angle (radians) at which it reaches zero.
    pub outer_angle: f32,
    /// Whether the light may cast a shadow (see [`PointLight::cast_shadows`]).
    #[serde(default = "cast_shadows_default")]
    pub cast_shadows: bool,
    /// Cookie (seed 004): index into `Scene::cookies` of a 2D cookie.
    #[serde(default)]
    pub cookie: Option<u32>,
    /// Culling mask (seed 004): bit k set = lights objects on layer k.
    #[serde(default = "all_layers")]
    pub mask: u32,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
}

impl Light {
    pub fn position(&self) -> DVec3 {
        match self {
            Light::Point(p) => p.position,
            Light::Spot(s) => s.position,
        }
    }
    pub fn radius(&self) -> f32 {
        match self {
            Light::Point(p) => p.radius,
            Light::Spot(s) => s.radius,
        }
    }
    pub fn color(&self) -> Vec3 {
        match self {
            Light::Point(p) => p.color,
            Light::Spot(s) => s.color,
        }
    }
    /// The light's own shadow flag.
    pub fn cast_shadows(&self) -> bool {
        match self {
            Light::Point(p) => p.cast_shadows,
            Light::Spot(s) => s.cast_shadows,
        }
    }
    pub fn set_cast_shadows(&mut self, on: bool) {
        match self {
            Light::Point(p) => p.cast_shadows = on,
            Light::Spot(s) => s.cast_shadows = on,
        }
    }
    /// The cookie's index in `Scene::cookies`.
    pub fn cookie(&self) -> Option<u32> {
        match self {
            Light::Point(p) => p.cookie,
            Light::Spot(s) => s.cookie,
        }
    }
    /// The culling mask: bit k set = lights layer k.
    pub fn mask(&self) -> u32 {
        match self {
            Light::Point(p) => p.mask,
            Light::Spot(s) => s.mask,
        }
    }
    pub fn set_mask(&mut self, mask: u32) {
        match self {
            Light::Point(p) => p.mask = mask,
            Light::Spot(s) => s.mask = mask,
        }
    }
    pub fn set_cookie(&mut self, cookie: Option<u32>) {
        match self {
            Light::Point(p) => p.cookie = cookie,
            Light::Spot(s) => s.cookie = cookie,
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        let (pos, color, intensity, radius) = match self {
            Light::Point(p) => (p.position, p.color, p.intensity, p.radius),
            Light::Spot(s) => {
                if !s.direction.is_finite() || s.direction.length_squared() < 1e-12 {
                    return Err("spot direction must be a finite non-zero vector".into());
                }
                let max = std::f32::consts::FRAC_PI_2;
                if !(s.outer_angle >= 0.0 && s.outer_angle <= max && s.inner_angle >= 0.0) {
                    return Err(format!("spot outer angle {} must lie in [0, pi/2]", s.outer_angle));
                }
                if s.inner_angle > s.outer_angle {
                    return Err("spot inner angle exceeds the outer angle".into());
                }
                (s.position, s.color, s.intensity, s.radius)
            }
        };
        if !pos.is_finite() || !color.is_finite() || !intensity.is_finite() || !radius.is_finite() {
            return Err("light values must be finite".into());
        }
        if radius <= 0.0 || intensity < 0.0 || color.min_element() < 0.0 {
            return Err(format!("light needs radius > 0 and non-negative colour/intensity (radius {radius})"));
        }
        Ok(())
    }
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Sun {
    /// Direction the light travels (from the sun towards the ground).
    pub direction: Vec3,
    pub color: Vec3,
    pub intensity: f32,
}

impl Sun {
    /// The demo's sun, and the one the viewer's "sun on" (panel or `set sun on`) brings back.
    pub const DEFAULT: Sun =
        Sun { direction: Vec3::new(-0.4, -1.0, -0.3), color: Vec3::new(1.0, 0.9, 0.75), intensity: 0.12 };
    /// The brighter sun a glTF file with no lights of its own gets (with the light grid).
    pub const FILL: Sun =
        Sun { direction: Vec3::new(-0.4, -1.0, -0.3), color: Vec3::new(1.0, 0.95, 0.85), intensity: 0.6 };

    /// `DEFAULT` with its direction normalised.
    pub fn default_sun() -> Sun {
        Sun { direction: Self::DEFAULT.direction.normalize(), ..Self::DEFAULT }
    }

    /// `FILL` with its direction normalised.
    pub fn fill_sun() -> Sun {
        Sun { direction: Self::FILL.direction.normalize(), ..Self::FILL }
    }
}

/// Everything a frame draws.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub camera: Camera,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub objects: Vec<Object>,
    /// Shared and copied on write ([`Scene::lights_mut`]): a renderer keeps the last frame's
    /// list, so the same list again (`Arc::ptr_eq`) tells it no light changed without reading
    /// one, and a change through `lights_mut` always makes a new list.
    pub lights: std::sync::Arc<Vec<Light>>,
    pub sun: Option<Sun>,
    pub ambient: Vec3,
    pub background: Vec3,
    /// Images the materials sample (shared, so cloning a scene does not copy pixels).
    pub textures: Vec<std::sync::Arc<Texture>>,
    /// Named cameras a file offers (a glTF scene's cameras); `camera` starts at the first.
    pub viewpoints: Vec<(String, Camera)>,
    /// The lights' cookies (seed 004), shared so cloning a scene does not copy texels.
    pub cookies: Vec<std::sync::Arc<cookie::CookieImage>>,
}

impl Scene {
    /// An empty scene: no geometry, no lights, the default ambient and background.
    pub fn new(name: &str, camera: Camera) -> Self {
        Self {
            name: name.into(),
            camera,
            meshes: Vec::new(),
            materials: Vec::new(),
            objects: Vec::new(),
            lights: Default::default(),
            sun: None,
            ambient: Vec3::splat(0.03),
            background: Vec3::new(0.01, 0.012, 0.02),
            textures: Vec::new(),
            viewpoints: Vec::new(),
            cookies: Vec::new(),
        }
    }

    /// The lights to change: the list itself when nothing else holds it, else a copy of it
    /// that replaces the shared one (so a renderer holding the last frame's sees a new list).
    pub fn lights_mut(&mut self) -> &mut Vec<Light> {
        std::sync::Arc::make_mut(&mut self.lights)
    }

    /// Replaces the lights.
    pub fn set_lights(&mut self, lights: Vec<Light>) {
        self.lights = std::sync::Arc::new(lights);
    }

    /// Rejects values that would make the frame meaningless, naming the first bad one.
    pub fn validate(&self) -> Result<(), String> {
        self.validate_except_lights()?;
        self.validate_lights()
    }

    /// [`Scene::validate`]'s checks of the lights (and the cookies they name).
    pub fn validate_lights(&self) -> Result<(), String> {
        for (i, l) in self.lights.iter().enumerate() {
            l.validate().map_err(|e| format!("light {i}: {e}"))?;
            if let Some(c) = l.cookie() {
                let Some(image) = self.cookies.get(c as usize) else {
                    return Err(format!("light {i} refers to missing cookie {c}"));
                };
                let point = matches!(l, Light::Point(_));
                if image.is_cube() != point {
                    return Err(format!(
                        "light {i}: cookie {} is {}, a {} light takes {}",
                        image.name,
                        if image.is_cube() { "a cube" } else { "2D" },
                        if point { "point" } else { "spot" },
                        if point { "a cube" } else { "a 2D image" }
                    ));
                }
            }
        }
        Ok(())
    }

    /// [`Scene::validate`] but for the lights: a renderer that checked this very light list
    /// (and cookies) before does not read every light again.
    pub fn validate_except_lights(&self) -> Result<(), String> {
        self.camera.validate()?;
        for (i, o) in self.objects.iter().enumerate() {
            if o.mesh >= self.meshes.len() || o.material >= self.materials.len() {
                return Err(format!("object {i} refers to a missing mesh or material"));
            }
            if !o.transform.is_finite() {
                return Err(format!("object {i} has a non-finite transform"));
            }
        }
        for (i, o) in self.objects.iter().enumerate() {
            if o.layer > 31 {
                return Err(format!("object {i} is on layer {}; layers are 0..=31", o.layer));
            }
        }
        for (i, m) in self.materials.iter().enumerate() {
            let finite = m.diffuse.is_finite()
                && m.emissive.is_finite()
                && m.specular_level.is_finite()
                && m.specular_exponent.is_finite()
                && m.alpha.is_finite()
                && m.normal_scale.is_finite()
                && m.metallic.is_finite()
                && m.roughness.is_finite()
                && [m.uvs.base_color, m.uvs.normal, m.uvs.emissive, m.uvs.metallic_roughness]
                    .iter()
                    .all(|t| t.rows().iter().flatten().all(|v| v.is_finite()) && t.set <= 1);
            if !finite {
                return Err(format!("material {i} has non-finite values"));
            }
            let t = m.textures;
            if let Some(l) = m.lightmap {
                if !(l.scale.is_finite() && l.scale > 0.0) {
                    return Err(format!("material {i}'s lightmap scale {} is not a positive number", l.scale));
                }
            }
            let lightmap = m.lightmap.map(|l| l.texture);
            for k in [t.base_color, t.normal, t.emissive, t.metallic_roughness, lightmap].into_iter().flatten() {
                if k >= self.textures.len() {
                    return Err(format!("material {i} refers to missing texture {k}"));
                }
            }
            if let AlphaMode::Mask { cutoff } = m.alpha_mode {
                if !cutoff.is_finite() {
                    return Err(format!("material {i} has a non-finite alpha cutoff"));
                }
            }
        }
        for (i, t) in self.textures.iter().enumerate() {
            if t.width == 0 || t.height == 0 || t.rgba.len() != (t.width as usize) * (t.height as usize) * 4 {
                return Err(format!(
                    "texture {i} ({}) has {} bytes for {}x{}",
                    t.name,
                    t.rgba.len(),
                    t.width,
                    t.height
                ));
            }
        }
        Ok(())
    }

    /// Whether anything is drawn by the forward transparency pass.
    pub fn any_blended(&self) -> bool {
        self.objects.iter().any(|o| self.materials.get(o.material).is_some_and(|m| m.is_blended()))
    }

    /// World-space bounds of every object (min, max), or `None` for an empty scene.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for o in &self.objects {
            let Some(mesh) = self.meshes.get(o.mesh) else { continue };
            for v in &mesh.vertices {
                let p = o.transform.transform_point3(glam::Vec3::from(v.position).as_dvec3());
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }

    /// The reflectance models the drawn objects use (`force`: every object with that one), in
    /// ID order. An empty scene uses the default.
    pub fn brdfs(&self, force: Option<Brdf>) -> Vec<Brdf> {
        if let Some(b) = force {
            return vec![b];
        }
        let mut used: Vec<Brdf> =
            self.objects.iter().filter_map(|o| self.materials.get(o.material)).flat_map(|m| m.brdfs()).collect();
        used.sort();
        used.dedup();
        if used.is_empty() {
            used.push(Brdf::default());
        }
        used
    }

    /// Sets light `light`'s cookie from a built-in name or a PNG path (`None`: no cookie);
    /// a cube for a point light, 2D for a spot. Errors name the light and the file.
    pub fn set_light_cookie(&mut self, light: usize, spec: Option<&str>) -> Result<(), String> {
        let Some(l) = self.lights.get(light) else {
            return Err(format!("no light {light} (the scene has {})", self.lights.len()));
        };
        let Some(spec) = spec else {
            self.lights_mut()[light].set_cookie(None);
            return Ok(());
        };
        let cube = matches!(l, Light::Point(_));
        let found = self.cookies.iter().position(|c| c.name == spec && c.is_cube() == cube);
        let index = match found {
            Some(k) => k,
            None => {
                let image = cookie::CookieImage::resolve(spec, cube).map_err(|e| format!("light {light}: {e}"))?;
                self.cookies.push(std::sync::Arc::new(image));
                self.cookies.len() - 1
            }
        };
        self.lights_mut()[light].set_cookie(Some(index as u32));
        Ok(())
    }

    /// The object layers in use (bit k: some object is on layer k).
    pub fn used_layers(&self) -> u32 {
        self.objects.iter().fold(0, |m, o| m | (1u32 << (o.layer & 31)))
    }

    /// Whether the lighting depends on each pixel's layer: some light's mask holds some of
    /// the layers in use but not all (a light that lights every used layer, or none, gives the
    /// same at every pixel). `None` then; else the one layer every pixel may be shaded as.
    pub fn uniform_layer(&self) -> Option<u32> {
        let used = self.used_layers();
        let split = self.lights.iter().any(|l| {
            let m = l.mask() & used;
            m != 0 && m != used
        });
        if split {
            None
        } else {
            Some(self.objects.first().map_or(0, |o| (o.layer & 31) as u32))
        }
    }

    /// The light pre-pass's one layer and the layers that share it (seed 004's "limited support"
    /// for light culling masks: its buffer has no channel for a layer). The layer is the used
    /// one most objects are on (the lowest of a tie); a used layer shares it when every light
    /// lights both or neither. Objects on shared layers go through the light buffer, shaded as
    /// that layer; the others are shaded forward after pass 3. Returns (layer, shared layers
    /// as a mask); every used layer shares it when [`Self::uniform_layer`] is `Some`.
    pub fn shared_layers(&self) -> (u32, u32) {
        let mut count = [0usize; 32];
        for o in &self.objects {
            count[(o.layer & 31) as usize] += 1;
        }
        let layer = (0..32).max_by_key(|&k| (count[k], std::cmp::Reverse(k))).unwrap_or(0) as u32;
        let same = |k: u32| self.lights.iter().all(|l| (l.mask() >> k) & 1 == (l.mask() >> layer) & 1);
        let shared = (0..32).filter(|&k| same(k)).fold(0u32, |m, k| m | (1 << k));
        (layer, shared)
    }

    pub fn any_emissive(&self) -> bool {
        self.materials.iter().any(|m| m.emissive.max_element() > 0.0)
    }
}
