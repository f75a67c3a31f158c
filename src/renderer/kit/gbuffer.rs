//! The G-buffer layout as data: which attribute goes to which channel of which target in which
//! format. Seed 000's four fp16 targets and a packed 8-byte layout are table entries; the WGSL
//! that writes and reads them (`gbuffer_store` / `gbuffer_load`) is generated from the table,
//! so the encoding lives in exactly one place.

mod layouts;
mod targets;
mod wgsl;

pub use layouts::{fit, fit_for, prepass_layout, LayoutChoice, FIT_SPECULAR_ERROR_BOUND, OCT8_MAX_ERROR_DEG};
pub use targets::GBufferTargets;

use crate::scene::Brdf;
use serde::{Deserialize, Serialize};

/// Specular exponents are stored as `log2(exponent) / SPEC_EXP_LOG_RANGE`: exponents 1 ..= 2^11.
/// The shaders get it as the generated constant `LS_SPEC_EXP_LOG_RANGE`.
pub const SPEC_EXP_LOG_RANGE: f32 = 11.0;

/// The specular channel stores the reflectance f0 = level x 8 / (exponent + 8), in [0, 1] for
/// every material (the level reaches 257 for a polished metal); this is the level back.
/// Mirrors `surface_of` in `kit/common.wgsl`.
pub fn level_from_reflectance(f0: f32, exponent: f32) -> f32 {
    f0 * (exponent + 8.0) / 8.0
}

/// A surface attribute the lighting model needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Attr {
    /// Linear diffuse albedo, 3 components in [0, 1].
    Albedo,
    /// Specular level, 1 component in [0, 1].
    SpecLevel,
    /// Specular exponent, stored as log2(exp) / [`SPEC_EXP_LOG_RANGE`] in [0, 1] (exponents 1..2048).
    SpecExp,
    /// View-space normal: 2 components (octahedral) or 3 (xyz), in [-1, 1].
    Normal,
    /// Linear emitted radiance, 3 components, >= 0.
    Emissive,
    /// Hardware depth, 1 component; position is reconstructed from it (seed 001).
    Depth,
    /// Stored view-space position, 3 components (seed 000 stores a view vector).
    Position,
    /// The material ID (seed 002): which reflectance model ([`Brdf`]) shades the pixel, stored
    /// as ID / 255 in 1 component. Present only when the scene uses more than one model.
    Material,
    /// The object's culling layer (seed 004's light culling masks), 0..=31, stored as
    /// layer / 255 in 1 component. Present only when some light's mask tells the scene's
    /// layers apart (`Scene::uniform_layer`).
    Layer,
    /// Seed 002's single-channel emissive: the emission E stored as one multiple e of the
    /// albedo A, e = E.A / A.A (the least-squares fit), and decoded as e A. Exact when the
    /// emission is proportional to the albedo; otherwise off by E - e A, the part of E
    /// orthogonal to A ([`emission_residual`]). A black albedo loses the emission.
    EmissiveScale,
    /// Seed 002's free channel when the scene uses several reflectance models: the material ID
    /// in the integer part and the specular exponent's code (log2(exp) / [`SPEC_EXP_LOG_RANGE`])
    /// times 255/256 in the fraction, in one fp16 channel. IDs stay below 8, where fp16 steps
    /// are at most 2^-8. The conversion to fp16 may round to nearest or toward zero (Vulkan
    /// leaves it to the implementation; lavapipe truncates): either way the largest fraction,
    /// 255/256, never reaches the next ID, and the code is off by less than one step,
    /// 2^-8 x 256/255, i.e. the exponent by a factor below 2^(11 x 2^-8 x 256/255) = 1.0304.
    MaterialExp,
}

/// The largest relative error [`Attr::MaterialExp`] leaves in the specular exponent (3.0%).
pub const MATERIAL_EXP_RELATIVE_ERROR: f64 = 0.0304;

/// How far [`Attr::EmissiveScale`] leaves a material's emission from its own (linear units,
/// per channel at most): the part of `emissive` orthogonal to `albedo`; all of it for a black
/// albedo.
pub fn emission_residual(emissive: glam::Vec3, albedo: glam::Vec3) -> f32 {
    let a2 = albedo.dot(albedo);
    let e = if a2 > 0.0 { emissive.dot(albedo) / a2 } else { 0.0 };
    (emissive - e.max(0.0) * albedo).abs().max_element()
}

impl Attr {
    /// Whether the attribute's natural range is [-1, 1] (needs remapping in unorm channels).
    pub(crate) fn signed(self) -> bool {
        matches!(self, Attr::Normal | Attr::Position)
    }

    /// Whether a channel holding `self` gives attribute `attr` (a packed channel gives two).
    pub fn gives(self, attr: Attr) -> bool {
        self == attr
            || (self == Attr::MaterialExp && matches!(attr, Attr::Material | Attr::SpecExp))
            || (self == Attr::EmissiveScale && attr == Attr::Emissive)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum NormalEncoding {
    /// Octahedral map to two channels (Cigolle et al. 2014).
    Octahedral,
    /// Three channels, x y z.
    Xyz,
    /// Lambert azimuthal equal-area projection to two channels (seed 001; "Compact Normal
    /// Storage for small G-Buffers", Pranckevičius 2009, method #4): the view-space unit
    /// normal n goes to e = n.xy / sqrt(2 + 2 n.z), a point of the unit disc; the one
    /// direction it cannot tell apart, n = -z (facing straight away from the eye), is the disc's
    /// rim.
    Lambert,
}

impl NormalEncoding {
    fn components(self) -> usize {
        match self {
            NormalEncoding::Octahedral | NormalEncoding::Lambert => 2,
            NormalEncoding::Xyz => 3,
        }
    }
}

/// One channel of a target: component `comp` of attribute `attr`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Slot {
    pub attr: Attr,
    pub comp: u8,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TargetDesc {
    pub name: &'static str,
    pub format: wgpu::TextureFormat,
    /// One entry per channel of the format.
    pub channels: Vec<Option<Slot>>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct GBufferLayout {
    pub name: &'static str,
    pub normal: NormalEncoding,
    /// Normals and positions are stored in world space (seed 000: the world-space normal and
    /// the world-space, not normalised, view vector from the surface to the eye), turned into
    /// view space on reading; otherwise in view space.
    pub world: bool,
    pub targets: Vec<TargetDesc>,
    /// The one reflectance model of a scene that uses one: a constant in the shaders and no
    /// channel. `None`: the model is read per pixel from the [`Attr::Material`] channel.
    pub uniform_brdf: Option<Brdf>,
    /// The one culling layer every pixel is shaded as when no light's mask tells the scene's
    /// layers apart: a constant in the shaders and no channel. `None`: read per pixel from the
    /// [`Attr::Layer`] channel.
    pub uniform_layer: Option<u32>,
    /// Seed 000's RT1: the light passes accumulate the lit colour (albedo x diffuse + specular,
    /// emission and ambient + sun from the G-buffer pass) into ONE target, which compose reads
    /// as it is; otherwise diffuse light (before the albedo) and specular light go to two
    /// targets and compose multiplies the albedo in.
    pub one_accumulation: bool,
}

fn channel_count(format: wgpu::TextureFormat) -> usize {
    format.components() as usize
}

pub(crate) fn is_float(format: wgpu::TextureFormat) -> bool {
    matches!(
        format,
        wgpu::TextureFormat::R16Float
            | wgpu::TextureFormat::Rg16Float
            | wgpu::TextureFormat::Rgba16Float
            | wgpu::TextureFormat::R32Float
            | wgpu::TextureFormat::Rg32Float
            | wgpu::TextureFormat::Rgba32Float
            | wgpu::TextureFormat::Rg11b10Ufloat
            | wgpu::TextureFormat::Depth32Float
    )
}

/// Whether target `t` is the depth buffer itself, read through its depth aspect (format
/// `Depth32Float`, [`GBufferLayout::reading_depth_buffer`]): bound for reading like the other
/// targets, but not rendered by the G-buffer pass.
pub fn is_depth_buffer(t: &TargetDesc) -> bool {
    t.format == wgpu::TextureFormat::Depth32Float
}

/// Largest rounding error of one stored normal component in [-1, 1]: half a step of a
/// normalised format (whose step is 2 / (2^bits - 1) after the [-1, 1] -> [0, 1] remap), half an
/// ulp below 1 of a float format.
pub fn component_rounding(format: wgpu::TextureFormat) -> f64 {
    use wgpu::TextureFormat as F;
    match format {
        F::R8Unorm | F::Rg8Unorm | F::Rgba8Unorm | F::Rgba8UnormSrgb => 1.0 / 255.0,
        F::R16Unorm | F::Rg16Unorm | F::Rgba16Unorm => 1.0 / 65535.0,
        // 10 stored mantissa bits: values in [0.5, 1) are 2^-11 apart.
        F::R16Float | F::Rg16Float | F::Rgba16Float => 2f64.powi(-12),
        F::R32Float | F::Rg32Float | F::Rgba32Float => 2f64.powi(-25),
        _ => 1.0,
    }
}

impl GBufferLayout {
    /// The largest angle (radians) between a unit normal and what this layout's encoding gives
    /// back, from the quantisation alone (`q`: [`component_rounding`] of the normal's format):
    ///
    /// * xyz: the stored vector is off by at most `sqrt(3) q`, so after renormalising the
    ///   direction is off by at most `asin(sqrt(3) q)`;
    /// * octahedral: a point v = (x, y, 1 - |x| - |y|) of the octahedron has |v| >= 1/sqrt(3);
    ///   an error of at most `q` in x and y moves v by at most sqrt(q^2 + q^2 + (2q)^2) = sqrt(6) q
    ///   and the normalised direction by at most |dv| / |v| <= sqrt(6) sqrt(3) q = 3 sqrt(2) q
    ///   (the lower hemisphere's fold only permutes and reflects the coordinates). For 8+8 bits
    ///   that is 0.955 degrees (0.946 measured, `OCT8_MAX_ERROR_DEG`);
    /// * Lambert azimuthal equal-area: the bound depends on the direction, see
    ///   [`Self::normal_error_bound_at`]; this is its value over the hemisphere facing the eye
    ///   (view-space n.z >= 0), 0.906 degrees for 8+8 bits.
    pub fn normal_error_bound(&self) -> f64 {
        self.normal_error_bound_at(std::f64::consts::FRAC_PI_2)
    }

    /// [`Self::normal_error_bound`] for a normal `theta` radians from the stored frame's +z (the
    /// view direction towards the eye in view space). The same for every direction but with the
    /// Lambert azimuthal equal-area encoding, whose decoding stretches with the angle: with
    /// g = 2e on the disc of radius 2, a normal at angle θ sits at radius r = 2 sin(θ/2); the
    /// map stretches radial steps by dθ/dr = 1 / cos(θ/2) and shrinks the others (by cos(θ/2)).
    /// Rounding moves g by at most 2 sqrt(2) q, within which θ reaches at most
    /// θ' = 2 asin(min(1, r/2 + sqrt(2) q)), so the angle is off by at most
    /// 2 sqrt(2) q / cos(θ'/2); π where θ' reaches the rim (n = -z cannot be bounded).
    pub fn normal_error_bound_at(&self, theta: f64) -> f64 {
        let Some(t) = self.targets.iter().find(|t| t.channels.iter().flatten().any(|s| s.attr == Attr::Normal)) else {
            return std::f64::consts::PI;
        };
        let q = component_rounding(t.format);
        match self.normal {
            NormalEncoding::Xyz => (3f64.sqrt() * q).min(1.0).asin(),
            NormalEncoding::Octahedral => 3.0 * 2f64.sqrt() * q,
            NormalEncoding::Lambert => {
                let reach = ((theta.clamp(0.0, std::f64::consts::PI) / 2.0).sin() + 2f64.sqrt() * q).min(1.0);
                let half = reach.asin();
                let stretch = half.cos();
                if stretch <= 0.0 {
                    return std::f64::consts::PI;
                }
                (2.0 * 2f64.sqrt() * q / stretch).min(std::f64::consts::PI)
            }
        }
    }

    /// The layout as `caps`' adapter can render it: a depth copy in R32Float becomes R32Uint
    /// holding depth's bits (written with `bitcast<u32>`, read back with `bitcast<f32>`: exact)
    /// where R32Float is not renderable (wgpu's GL backend).
    pub fn for_caps(mut self, caps: &super::adapter::AdapterCaps) -> Self {
        use wgpu::TextureFormat as F;
        for t in &mut self.targets {
            let depth_only = t.channels.iter().all(|c| matches!(c, Some(Slot { attr: Attr::Depth, .. })));
            if t.format == F::R32Float && depth_only && !caps.renderable(F::R32Float) && caps.renderable(F::R32Uint) {
                t.format = F::R32Uint;
            }
        }
        self
    }

    /// The layout reading depth from the depth buffer (a `Depth32Float` view of its depth
    /// aspect) instead of the R32Float copy the G-buffer pass writes: the copy's target stays in
    /// the table, bound at the same slot and read by the same code, but is no longer rendered.
    /// Exact: the copy holds the fragment's depth as the 32-bit float buffer stores it. Only for
    /// a frame `key::depth_read_refusal` allows.
    pub fn reading_depth_buffer(mut self) -> Self {
        for t in &mut self.targets {
            let depth_only = t.channels.iter().all(|c| matches!(c, Some(Slot { attr: Attr::Depth, .. })));
            if depth_only && t.format == wgpu::TextureFormat::R32Float {
                t.format = wgpu::TextureFormat::Depth32Float;
            }
        }
        self
    }

    /// Whether depth is read from the depth buffer ([`Self::reading_depth_buffer`]).
    pub fn reads_depth_buffer(&self) -> bool {
        self.targets.iter().any(is_depth_buffer)
    }

    /// The targets the G-buffer pass renders, in attachment order: all but the depth buffer.
    pub fn rendered(&self) -> impl Iterator<Item = &TargetDesc> {
        self.targets.iter().filter(|t| !is_depth_buffer(t))
    }

    /// Checks that the adapter can render every target's format.
    pub fn check_caps(&self, caps: &super::adapter::AdapterCaps) -> anyhow::Result<()> {
        for t in self.rendered() {
            if !caps.renderable(t.format) {
                return Err(caps.refuse(
                    &format!("layout {} (its {} target)", self.name, t.name),
                    &format!("{:?} render targets", t.format),
                    "choose another --layout (`lampshade adapters` lists those it renders)",
                ));
            }
        }
        Ok(())
    }

    /// Bytes per pixel of the colour targets (the depth-stencil buffer is reported apart).
    pub fn bytes_per_pixel(&self) -> u32 {
        self.rendered().map(|t| t.format.block_copy_size(None).unwrap_or(0)).sum()
    }

    /// Whether some channel gives `attr` (alone or packed with another).
    pub fn has(&self, attr: Attr) -> bool {
        self.targets.iter().flat_map(|t| t.channels.iter()).flatten().any(|s| s.attr.gives(attr))
    }

    /// Whether the specular level is stored as it is: where its channel is a float (seed 000's
    /// "RT0 … Alpha – specular level", seed 002's, the reference's), which holds the level's
    /// whole range ((exponent + 8) / 8 at reflectance 1). A normalised 8-bit channel stores the
    /// reflectance f0 = level x 8 / (exponent + 8) in [0, 1] instead ([`level_from_reflectance`]).
    pub fn spec_level_raw(&self) -> bool {
        self.targets
            .iter()
            .any(|t| is_float(t.format) && t.channels.iter().flatten().any(|s| s.attr == Attr::SpecLevel))
    }

    /// The largest relative rounding of a stored position component (seed 000's and 002's
    /// fp16 positions: half an ulp, 2^-11; f32: 2^-24); 0 for layouts that reconstruct the
    /// position from depth. The shadow lookups widen their depth bias by it (seed 002: "may
    /// want to increase shadow bias based on pos.z if using fp16 for G-buffer positions").
    pub fn position_rounding(&self) -> f64 {
        if self.has(Attr::Depth) {
            return 0.0;
        }
        self.targets
            .iter()
            .filter(|t| t.channels.iter().flatten().any(|s| s.attr == Attr::Position))
            .map(|t| match t.format {
                wgpu::TextureFormat::Rgba16Float | wgpu::TextureFormat::Rg16Float | wgpu::TextureFormat::R16Float => {
                    2f64.powi(-11)
                }
                _ => 2f64.powi(-24),
            })
            .fold(0.0, f64::max)
    }

    fn components(&self, attr: Attr) -> usize {
        match attr {
            Attr::Albedo | Attr::Emissive | Attr::Position => 3,
            Attr::Normal => self.normal.components(),
            Attr::SpecLevel
            | Attr::SpecExp
            | Attr::Depth
            | Attr::Material
            | Attr::Layer
            | Attr::EmissiveScale
            | Attr::MaterialExp => 1,
        }
    }

    /// Checks that the table is complete and consistent.
    pub fn validate(&self) -> Result<(), String> {
        for t in &self.targets {
            if t.channels.len() != channel_count(t.format) {
                return Err(format!("target {} lists {} channels for {:?}", t.name, t.channels.len(), t.format));
            }
            for s in t.channels.iter().flatten() {
                let bits = s.attr == Attr::Depth && t.format == wgpu::TextureFormat::R32Uint;
                if matches!(s.attr, Attr::Depth | Attr::Position) && !is_float(t.format) && !bits {
                    return Err(format!("{:?} needs a float channel, {} is {:?}", s.attr, t.name, t.format));
                }
            }
        }
        // The light pre-pass's thin buffer holds no albedo: its final pass reads the material.
        let needed: &[Attr] = if self.name == PREPASS_LAYOUT { &[Attr::Normal] } else { &[Attr::Albedo, Attr::Normal] };
        for &attr in needed {
            for c in 0..self.components(attr) {
                if !self
                    .targets
                    .iter()
                    .flat_map(|t| t.channels.iter())
                    .flatten()
                    .any(|s| s.attr.gives(attr) && (s.comp == c as u8 || self.components(s.attr) == 1))
                {
                    return Err(format!("layout {} misses {:?}[{c}]", self.name, attr));
                }
            }
        }
        if !self.has(Attr::Depth) && !self.has(Attr::Position) {
            return Err(format!("layout {} stores neither depth nor position", self.name));
        }
        if self.uniform_brdf.is_none() != self.has(Attr::Material) {
            return Err(format!(
                "layout {}: a material ID channel goes with a scene of several reflectance models, and only then",
                self.name
            ));
        }
        if self.uniform_layer.is_none() != self.has(Attr::Layer) {
            return Err(format!(
                "layout {}: a layer channel goes with a scene whose light masks tell its layers apart, and only then",
                self.name
            ));
        }
        Ok(())
    }

    /// For a layout that stores the position (view space, or seed 000's world-space view
    /// vector) and no depth: whether the position's
    /// target is half precision (`Some(true)`: fp16, `Some(false)`: f32). The G-buffer pass then
    /// writes the stored position's projected depth (`frag_depth`), so the volume methods' depth
    /// tests and the lighting see one point. The rasteriser's depth and the perspective-correct
    /// position differ by the vertices' snapping times the surface's depth slope, unbounded on a
    /// grazing surface: with the rasteriser's depth, the culling oracle found lights missed on
    /// the `reference`, `seed000` and `seed002` layouts. Writing depth turns off early depth
    /// testing in these layouts' G-buffer pass.
    pub fn position_depth(&self) -> Option<bool> {
        if self.has(Attr::Depth) {
            return None;
        }
        let t = self.targets.iter().find(|t| t.channels.iter().flatten().any(|s| s.attr == Attr::Position))?;
        Some(t.format == wgpu::TextureFormat::Rgba16Float)
    }
}

/// A target holding a float's bits in an unsigned integer (the R32Uint depth copy).
pub(crate) fn is_bits(format: wgpu::TextureFormat) -> bool {
    format == wgpu::TextureFormat::R32Uint
}

/// Name of [`prepass_layout`].
pub const PREPASS_LAYOUT: &str = "prepass";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_layout_is_valid_and_reports_its_size() {
        let sizes: Vec<u32> = LayoutChoice::ALL
            .iter()
            .map(|c| {
                let l = c.layout();
                l.validate().unwrap();
                l.bytes_per_pixel()
            })
            .collect();
        // seed000: RT0, RT2, RT3 (RT1 is the accumulation, not counted here); seed002: its
        // three fp16 targets, as the seed says.
        assert_eq!(sizes, vec![24, 24, 24, 12, 64, 24, 18, 20, 20, 24, 18, 20]);
    }

    #[test]
    fn seed002s_free_channel_keeps_the_material_id_and_the_exponent_apart() {
        // Every ID a scene can have and every exponent code, through fp16 as the target stores
        // them, and unpacked as `gbuffer_load` does.
        for b in Brdf::ALL {
            let id = b.id() as f32;
            for k in 0..=4096 {
                let code = k as f32 / 4096.0;
                let v = id + code * (255.0 / 256.0);
                // Rounded to nearest, and toward zero (the other conversion Vulkan allows).
                let nearest = half::f16::from_f32(v);
                let toward_zero =
                    if nearest.to_f32() > v { half::f16::from_bits(nearest.to_bits() - 1) } else { nearest };
                for stored in [nearest.to_f32(), toward_zero.to_f32()] {
                    assert_eq!(stored.floor(), id, "{b:?} code {code}: the ID changed");
                    let back = stored.fract() * (256.0 / 255.0);
                    let ratio = 2f64.powf(((back - code).abs() * SPEC_EXP_LOG_RANGE) as f64);
                    assert!(ratio - 1.0 <= MATERIAL_EXP_RELATIVE_ERROR, "{b:?} code {code}: exponent off by {ratio}");
                }
            }
        }
    }

    #[test]
    fn seed002s_one_channel_emission_is_exact_along_the_albedo_only() {
        use glam::Vec3;
        let a = Vec3::new(0.8, 0.4, 0.1);
        assert!(emission_residual(a * 3.0, a) < 1e-6);
        // Orthogonal to the albedo: all of it is lost.
        let e = Vec3::new(0.4, -0.8, 0.0) * 2.0;
        assert!((emission_residual(e, a) - e.abs().max_element()).abs() < 1e-6);
        // Black albedo: nothing survives.
        assert_eq!(emission_residual(Vec3::ONE, Vec3::ZERO), 1.0);
    }

    #[test]
    fn only_stored_positions_widen_the_shadow_bias() {
        assert_eq!(LayoutChoice::Compact.layout().position_rounding(), 0.0);
        assert_eq!(LayoutChoice::Seed002.layout().position_rounding(), 2f64.powi(-11));
        assert_eq!(LayoutChoice::Seed000.layout().position_rounding(), 2f64.powi(-11));
        assert_eq!(LayoutChoice::Reference.layout().position_rounding(), 2f64.powi(-24));
    }

    #[test]
    fn the_normal_layouts_differ_from_compact_in_the_normal_only() {
        let compact = LayoutChoice::Compact.layout();
        let names: Vec<&str> = LayoutChoice::ALL.iter().map(|c| c.layout().name).collect();
        for c in LayoutChoice::NORMAL_ENCODINGS {
            let l = c.layout();
            assert_eq!(names.iter().filter(|n| **n == l.name).count(), 1, "{} is not a unique name", l.name);
            // Every attribute but the normal sits in a channel of the same format as in compact.
            for attr in [Attr::Albedo, Attr::SpecLevel, Attr::SpecExp, Attr::Emissive, Attr::Depth] {
                let format_of = |l: &GBufferLayout| {
                    l.targets.iter().find(|t| t.channels.iter().flatten().any(|s| s.attr == attr)).map(|t| t.format)
                };
                assert_eq!(format_of(&l), format_of(&compact), "{}: {attr:?} is stored differently", l.name);
            }
        }
    }

    #[test]
    fn normal_error_bounds_follow_the_quantisation() {
        let deg = |c: LayoutChoice| c.layout().normal_error_bound().to_degrees();
        // Octahedral 8+8: 3 sqrt(2) / 255 rad, just above the 0.946 degrees measured.
        assert!((deg(LayoutChoice::Oct8) - 0.9533).abs() < 1e-3, "{}", deg(LayoutChoice::Oct8));
        assert!(deg(LayoutChoice::Oct8) >= OCT8_MAX_ERROR_DEG);
        assert_eq!(deg(LayoutChoice::Packed), deg(LayoutChoice::Oct8));
        // xyz 8-bit: asin(sqrt(3) / 255).
        assert!((deg(LayoutChoice::Xyz8) - 0.3892).abs() < 1e-3, "{}", deg(LayoutChoice::Xyz8));
        // 16-bit unorm is 257 times finer than 8-bit; fp16 (11 significant bits below 1) 16 times.
        assert!(deg(LayoutChoice::Oct16) < deg(LayoutChoice::Oct8) / 250.0);
        assert!(deg(LayoutChoice::Xyz16f) < deg(LayoutChoice::Xyz8) / 15.0);
        assert!(deg(LayoutChoice::Compact) < deg(LayoutChoice::Oct8) / 15.0);
        assert!(deg(LayoutChoice::Reference) < 1e-5);
        // Lambert 8+8 over the hemisphere facing the eye: 2 sqrt(2) q / cos(theta'/2), theta'
        // just past 90 degrees: 0.906 degrees, a little under octahedral's 0.953; it grows
        // towards the back (2.68 degrees at 150), and near the rim (n = -z) it is pi.
        assert!((deg(LayoutChoice::Lambert8) - 0.906).abs() < 2e-3, "{}", deg(LayoutChoice::Lambert8));
        let at = |c: LayoutChoice, t: f64| c.layout().normal_error_bound_at(t.to_radians()).to_degrees();
        assert!(at(LayoutChoice::Lambert8, 0.0) < at(LayoutChoice::Lambert8, 90.0));
        assert!((at(LayoutChoice::Lambert8, 150.0) - 2.680).abs() < 2e-3, "{}", at(LayoutChoice::Lambert8, 150.0));
        assert_eq!(at(LayoutChoice::Lambert8, 180.0), 180.0);
        assert!(deg(LayoutChoice::Lambert16) < deg(LayoutChoice::Lambert8) / 250.0);
        // The other encodings' bounds do not depend on the direction.
        assert_eq!(at(LayoutChoice::Oct8, 180.0), deg(LayoutChoice::Oct8));
    }

    #[test]
    fn the_material_id_channel_is_there_only_for_scenes_of_several_models() {
        use crate::scene::builtin::{build, BuiltinOptions};
        let one = build("demo", BuiltinOptions::default()).unwrap();
        let several = build("materials", BuiltinOptions::default()).unwrap();
        assert_eq!(one.brdfs(None), vec![Brdf::BlinnPhong]);
        assert_eq!(several.brdfs(None), Brdf::ALL.to_vec());
        // Every model alone (as the only material of the scene, or forced) is a constant.
        let mut metal = one.clone();
        metal.materials.iter_mut().for_each(|m| m.brdf = Brdf::Metal);
        for c in LayoutChoice::ALL {
            let plain = if c == LayoutChoice::Fit { fit(&one) } else { c.layout() };
            for (scene, force, model) in
                [(&one, None, Brdf::BlinnPhong), (&metal, None, Brdf::Metal), (&several, Some(Brdf::Toon), Brdf::Toon)]
            {
                let l = c.layout_for(scene, force).unwrap();
                l.validate().unwrap();
                assert!(!l.has(Attr::Material), "{}: an ID channel for one model", l.name);
                assert_eq!(l.uniform_brdf, Some(model), "{}", l.name);
                if c != LayoutChoice::Fit {
                    assert_eq!(l.bytes_per_pixel(), plain.bytes_per_pixel(), "{}", l.name);
                }
            }
            let l = c.layout_for(&several, None);
            match c {
                LayoutChoice::Oct8 | LayoutChoice::Oct16 | LayoutChoice::Lambert8 | LayoutChoice::Lambert16 => {
                    let e = l.unwrap_err();
                    assert!(
                        e.contains("no spare channel") && e.contains("blinn-phong, lambert, metal, toon, unlit"),
                        "{e}"
                    );
                }
                _ => {
                    let l = l.unwrap();
                    l.validate().unwrap();
                    assert!(l.has(Attr::Material), "{}: every model and no ID channel", l.name);
                    assert_eq!(l.uniform_brdf, None);
                    // In a channel the formats already had: no byte more.
                    let without =
                        if c == LayoutChoice::Fit { fit_for(&several, &[Brdf::BlinnPhong]) } else { c.layout() };
                    assert_eq!(l.bytes_per_pixel(), without.bytes_per_pixel(), "{}", l.name);
                    // The WGSL reads the ID from its channel.
                    let wgsl = l.wgsl(1, true);
                    assert!(wgsl.contains("const GBUFFER_HAS_MATERIAL: bool = true;") && wgsl.contains("a.material ="));
                }
            }
        }
        // fit: the ID takes the normal target's spare fourth channel of a specular scene, the
        // albedo target's alpha of one without specular (lambert and unlit only).
        let l = LayoutChoice::Fit.layout_for(&several, None).unwrap();
        assert_eq!(l.targets[1].channels[3], Some(Slot { attr: Attr::Material, comp: 0 }));
        let mut matte = several.clone();
        for (k, m) in matte.materials.iter_mut().enumerate() {
            m.brdf = if k % 2 == 0 { Brdf::Lambert } else { Brdf::Unlit };
        }
        let l = LayoutChoice::Fit.layout_for(&matte, None).unwrap();
        l.validate().unwrap();
        assert!(!l.has(Attr::SpecLevel), "lambert and unlit need no specular channels");
        assert_eq!(l.targets[0].channels[3], Some(Slot { attr: Attr::Material, comp: 0 }));
    }

    #[test]
    fn a_layout_without_normals_is_rejected() {
        let mut l = LayoutChoice::Compact.layout();
        l.targets.remove(1);
        assert!(l.validate().unwrap_err().contains("Normal"));
    }

    #[test]
    fn depth_in_an_8_bit_channel_is_rejected() {
        let mut l = LayoutChoice::Compact.layout();
        l.targets[3].format = wgpu::TextureFormat::R8Unorm;
        assert!(l.validate().is_err());
    }
}
