//! The G-buffer layout as data: which attribute goes to which channel of which target in which
//! format. Seed 000's four fp16 targets and a packed 8-byte layout are table entries; the WGSL
//! that writes and reads them (`gbuffer_store` / `gbuffer_load`) is generated from the table,
//! so the encoding lives in exactly one place.

use crate::scene::Brdf;
use serde::{Deserialize, Serialize};
use std::fmt::Write;

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

/// The layouts Lampshade knows, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum LayoutChoice {
    /// Albedo sRGB8 + spec; octahedral normal fp16 + exponent; emissive fp16; depth copy R32F.
    #[default]
    Compact,
    /// Seed 000's own: RT0 diffuse RGB + specular level, RT1 the light accumulation, RT2
    /// world-space normal (+ exponent), RT3 world-space view vector, all Rgba16Float.
    Seed000,
    /// Eight bytes: albedo sRGB8 + spec, octahedral normal 8+8 + exponent; no emissive; depth copy.
    Packed,
    /// The accuracy reference: four Rgba32Float targets, xyz normal, stored view-space position.
    Reference,
    /// Derived from the scene: only the channels its materials use (see `fit`).
    Fit,
    /// `compact` with the normal alone in an octahedral Rg8Unorm target (8+8 bits); the
    /// exponent moves to the emissive target's free fp16 channel, so only the normal differs.
    Oct8,
    /// The same with octahedral Rg16Unorm (16+16 bits; needs TEXTURE_FORMAT_16BIT_NORM).
    Oct16,
    /// The same with x y z in Rgba8Unorm (8 bits each).
    Xyz8,
    /// The same with x y z in Rgba16Float.
    Xyz16f,
    /// The same with seed 001's Lambert azimuthal equal-area projection in Rg8Unorm (8+8 bits).
    Lambert8,
    /// The same with the Lambert azimuthal equal-area projection in Rg16Unorm (16+16 bits;
    /// needs TEXTURE_FORMAT_16BIT_NORM).
    Lambert16,
    /// Seed 002's example: three Rgba16Float targets (24 B/px), view-space position +
    /// single-channel emissive, diffuse + specular, xyz normal + the free channel (the
    /// exponent; with several models, the material ID and the exponent packed).
    Seed002,
}

impl LayoutChoice {
    pub const ALL: [LayoutChoice; 12] = [
        LayoutChoice::Compact,
        LayoutChoice::Seed000,
        LayoutChoice::Seed002,
        LayoutChoice::Packed,
        LayoutChoice::Reference,
        LayoutChoice::Fit,
        LayoutChoice::Oct8,
        LayoutChoice::Oct16,
        LayoutChoice::Xyz8,
        LayoutChoice::Xyz16f,
        LayoutChoice::Lambert8,
        LayoutChoice::Lambert16,
    ];

    /// The layouts that differ from `compact` in the normal's encoding only.
    pub const NORMAL_ENCODINGS: [LayoutChoice; 6] = [
        LayoutChoice::Oct8,
        LayoutChoice::Oct16,
        LayoutChoice::Xyz8,
        LayoutChoice::Xyz16f,
        LayoutChoice::Lambert8,
        LayoutChoice::Lambert16,
    ];

    /// The layout for `scene` (every object shaded with `force` when given): `Fit` derives one
    /// from it; the fixed tables take it as they are, plus the material ID channel when the
    /// scene uses more than one reflectance model (in the channel the table leaves spare:
    /// [`LayoutChoice::material_slot`]). A layout without a spare channel cannot show several
    /// models: that is an error naming them, not a silent fallback.
    ///
    /// Then the object layer (seed 004's light culling masks), the same way: a shader constant
    /// unless some light's mask tells the scene's layers apart; then in the first channel the
    /// layout (after the material ID) leaves unused, at no byte more; `fit` adds an R8Unorm
    /// target (1 B/px) when it has none; another layout without one is an error that says so.
    pub fn layout_for(self, scene: &crate::scene::Scene, force: Option<Brdf>) -> Result<GBufferLayout, String> {
        let mut layout = self.layout_for_models(scene, force)?;
        let Some(layer) = scene.uniform_layer() else {
            let spare = layout.targets.iter().enumerate().find_map(|(i, t)| {
                t.channels
                    .iter()
                    .enumerate()
                    .position(|(c, s)| s.is_none() && !(t.format.is_srgb() && c < 3))
                    .map(|c| (i, c))
            });
            match spare {
                Some((t, c)) => layout.targets[t].channels[c] = Some(Slot { attr: Attr::Layer, comp: 0 }),
                None if self == LayoutChoice::Fit => layout.targets.push(TargetDesc {
                    name: "layer",
                    format: wgpu::TextureFormat::R8Unorm,
                    channels: vec![Some(Slot { attr: Attr::Layer, comp: 0 })],
                }),
                None => {
                    let used = scene.used_layers();
                    let layers: Vec<String> = (0..32).filter(|k| used & (1 << k) != 0).map(|k| k.to_string()).collect();
                    let lights: Vec<String> = scene
                        .lights
                        .iter()
                        .enumerate()
                        .filter(|(_, l)| l.mask() & used != 0 && l.mask() & used != used)
                        .map(|(i, _)| i.to_string())
                        .take(8)
                        .collect();
                    return Err(format!(
                        "layout {} has no spare channel for the object layer that light culling masks need \
                         (objects on layers {}; lights {} light some of those layers but not all){}; \
                         use compact, fit or reference, or masks that take every layer in use or none",
                        layout.name,
                        layers.join(", "),
                        lights.join(", "),
                        if layout.uniform_brdf.is_none() { " — the material ID took its spare channel" } else { "" }
                    ));
                }
            }
            layout.uniform_layer = None;
            return Ok(layout);
        };
        layout.uniform_layer = Some(layer);
        Ok(layout)
    }

    /// [`Self::layout_for`] without the layer: the table and the material ID channel.
    fn layout_for_models(self, scene: &crate::scene::Scene, force: Option<Brdf>) -> Result<GBufferLayout, String> {
        let brdfs = scene.brdfs(force);
        if self == LayoutChoice::Fit {
            return Ok(fit_for(scene, &brdfs));
        }
        let mut layout = self.layout();
        if let [one] = brdfs[..] {
            layout.uniform_brdf = Some(one);
            return Ok(layout);
        }
        let Some((t, c)) = self.material_slot() else {
            let names: Vec<String> = brdfs.iter().map(|b| b.name()).collect();
            return Err(format!(
                "layout {} has no spare channel for the material ID, and the scene uses {} reflectance models ({}); \
                 use compact, fit, packed, seed000, reference, xyz8 or xyz16f, or force one model (--brdf)",
                layout.name,
                brdfs.len(),
                names.join(", ")
            ));
        };
        // Seed 002's free channel holds the exponent too (packed with the ID).
        let attr = if self == LayoutChoice::Seed002 { Attr::MaterialExp } else { Attr::Material };
        layout.targets[t].channels[c] = Some(Slot { attr, comp: 0 });
        layout.uniform_brdf = None;
        Ok(layout)
    }

    /// Where the fixed table keeps the material ID when a scene needs one: (target, channel)
    /// of a channel its formats already have and leave unused, so the ID costs no bytes.
    /// `oct8`, `oct16`, `lambert8` and `lambert16` have none.
    pub fn material_slot(self) -> Option<(usize, usize)> {
        match self {
            // normal+exp .w (fp16; 8-bit unorm in packed; the normal target in xyz8/xyz16f).
            LayoutChoice::Compact | LayoutChoice::Packed | LayoutChoice::Xyz8 | LayoutChoice::Xyz16f => Some((1, 3)),
            // The position (seed 000: view vector) target's .w.
            LayoutChoice::Seed000 | LayoutChoice::Reference => Some((2, 3)),
            // Seed 002's free channel (normal target .w), packed with the exponent.
            LayoutChoice::Seed002 => Some((2, 3)),
            // `fit` places it itself (`fit_material_slot`).
            LayoutChoice::Fit => None,
            LayoutChoice::Oct8 | LayoutChoice::Oct16 | LayoutChoice::Lambert8 | LayoutChoice::Lambert16 => None,
        }
    }

    /// The fixed layout (`Fit` without a scene falls back to `Compact`), for scenes shaded with
    /// the default model alone (no material ID channel).
    pub fn layout(self) -> GBufferLayout {
        use wgpu::TextureFormat as F;
        use Attr::*;
        let s = |attr, comp| Some(Slot { attr, comp });
        match self {
            LayoutChoice::Compact | LayoutChoice::Fit => GBufferLayout {
                name: "compact",
                normal: NormalEncoding::Octahedral,
                world: false,
                uniform_brdf: Some(Brdf::BlinnPhong),
                uniform_layer: Some(0),
                one_accumulation: false,
                targets: vec![
                    TargetDesc {
                        name: "albedo+spec",
                        format: F::Rgba8UnormSrgb,
                        channels: vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), s(SpecLevel, 0)],
                    },
                    TargetDesc {
                        name: "normal+exp",
                        format: F::Rgba16Float,
                        channels: vec![s(Normal, 0), s(Normal, 1), s(SpecExp, 0), None],
                    },
                    TargetDesc {
                        name: "emissive",
                        format: F::Rgba16Float,
                        channels: vec![s(Emissive, 0), s(Emissive, 1), s(Emissive, 2), None],
                    },
                    TargetDesc { name: "depth", format: F::R32Float, channels: vec![s(Depth, 0)] },
                ],
            },
            // Seed 000's four fp16 targets with a stored position, and the same table in f32.
            LayoutChoice::Oct8 => normal_apart("oct8", F::Rg8Unorm, NormalEncoding::Octahedral),
            LayoutChoice::Oct16 => normal_apart("oct16", F::Rg16Unorm, NormalEncoding::Octahedral),
            LayoutChoice::Xyz8 => normal_apart("xyz8", F::Rgba8Unorm, NormalEncoding::Xyz),
            LayoutChoice::Xyz16f => normal_apart("xyz16f", F::Rgba16Float, NormalEncoding::Xyz),
            LayoutChoice::Lambert8 => normal_apart("lambert8", F::Rg8Unorm, NormalEncoding::Lambert),
            LayoutChoice::Lambert16 => normal_apart("lambert16", F::Rg16Unorm, NormalEncoding::Lambert),
            LayoutChoice::Seed000 => seed000(),
            LayoutChoice::Seed002 => seed002(),
            LayoutChoice::Reference => four_stored("reference", F::Rgba32Float),
            LayoutChoice::Packed => GBufferLayout {
                name: "packed",
                normal: NormalEncoding::Octahedral,
                world: false,
                uniform_brdf: Some(Brdf::BlinnPhong),
                uniform_layer: Some(0),
                one_accumulation: false,
                targets: vec![
                    TargetDesc {
                        name: "albedo+spec",
                        format: F::Rgba8UnormSrgb,
                        channels: vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), s(SpecLevel, 0)],
                    },
                    TargetDesc {
                        name: "normal+exp",
                        format: F::Rgba8Unorm,
                        channels: vec![s(Normal, 0), s(Normal, 1), s(SpecExp, 0), None],
                    },
                    TargetDesc { name: "depth", format: F::R32Float, channels: vec![s(Depth, 0)] },
                ],
            },
        }
    }
}

/// `compact` with the normal in a target of its own, of `format`, and the specular exponent in
/// the emissive target's fourth (fp16) channel: everything but the normal's encoding is stored
/// as `compact` stores it, so a sweep over these isolates the normal's error.
fn normal_apart(name: &'static str, format: wgpu::TextureFormat, normal: NormalEncoding) -> GBufferLayout {
    use wgpu::TextureFormat as F;
    use Attr::*;
    let s = |attr, comp| Some(Slot { attr, comp });
    let mut channels: Vec<Option<Slot>> = (0..normal.components() as u8).map(|c| s(Normal, c)).collect();
    channels.resize(channel_count(format), None);
    GBufferLayout {
        name,
        normal,
        world: false,
        uniform_brdf: Some(Brdf::BlinnPhong),
        uniform_layer: Some(0),
        one_accumulation: false,
        targets: vec![
            TargetDesc {
                name: "albedo+spec",
                format: F::Rgba8UnormSrgb,
                channels: vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), s(SpecLevel, 0)],
            },
            TargetDesc { name: "normal", format, channels },
            TargetDesc {
                name: "emissive+exp",
                format: F::Rgba16Float,
                channels: vec![s(Emissive, 0), s(Emissive, 1), s(Emissive, 2), s(SpecExp, 0)],
            },
            TargetDesc { name: "depth", format: F::R32Float, channels: vec![s(Depth, 0)] },
        ],
    }
}

/// Seed 000's own layout, four Rgba16Float targets (32 B/px): RT0 diffuse colour + specular
/// level, RT1 the light accumulation (ONE target, `one_accumulation`: the lit colour, which
/// the G-buffer pass starts with ambient and sun and every light adds to), RT2 the world-space
/// normal, RT3 the world-space, not normalised, view vector. The seed's alphas hold "nothing";
/// RT2's carries the specular exponent (the renderer's materials have one each; in a channel
/// the format has anyway, so it costs no byte). There is no emissive target: the G-buffer pass
/// writes a surface's emission into RT1 (`GBufferLayout::wgsl`), as RT1 holds all light.
fn seed000() -> GBufferLayout {
    use Attr::*;
    let s = |attr, comp| Some(Slot { attr, comp });
    let target = |name, channels| TargetDesc { name, format: wgpu::TextureFormat::Rgba16Float, channels };
    GBufferLayout {
        name: "seed000",
        normal: NormalEncoding::Xyz,
        world: true,
        uniform_brdf: Some(Brdf::BlinnPhong),
        uniform_layer: Some(0),
        one_accumulation: true,
        targets: vec![
            target("diffuse+spec", vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), s(SpecLevel, 0)]),
            target("world normal+exp", vec![s(Normal, 0), s(Normal, 1), s(Normal, 2), s(SpecExp, 0)]),
            target("view vector", vec![s(Position, 0), s(Position, 1), s(Position, 2), None]),
        ],
    }
}

/// Seed 002's example layout ("Three 16-bit Float MRTs"), 24 B/px and no depth target:
/// RT0 view-space position + emissive (one channel, [`Attr::EmissiveScale`]), RT1 diffuse +
/// specular (level; the seed's "gloss"), RT2 xyz normal + the free channel. The seed leaves
/// the exponent out; the free channel carries it, and when the scene uses several reflectance
/// models the material ID with it ([`Attr::MaterialExp`], the talk's "use that last free
/// channel in G-buffer to store material ID").
fn seed002() -> GBufferLayout {
    use Attr::*;
    let s = |attr, comp| Some(Slot { attr, comp });
    let target = |name, channels| TargetDesc { name, format: wgpu::TextureFormat::Rgba16Float, channels };
    GBufferLayout {
        name: "seed002",
        normal: NormalEncoding::Xyz,
        world: false,
        uniform_brdf: Some(Brdf::BlinnPhong),
        uniform_layer: Some(0),
        one_accumulation: false,
        targets: vec![
            target("position+emissive", vec![s(Position, 0), s(Position, 1), s(Position, 2), s(EmissiveScale, 0)]),
            target("diffuse+spec", vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), s(SpecLevel, 0)]),
            target("normal+free", vec![s(Normal, 0), s(Normal, 1), s(Normal, 2), s(SpecExp, 0)]),
        ],
    }
}

/// Four targets of one format: albedo + specular level, xyz normal + exponent, stored
/// view-space position, emissive.
fn four_stored(name: &'static str, format: wgpu::TextureFormat) -> GBufferLayout {
    use Attr::*;
    let s = |attr, comp| Some(Slot { attr, comp });
    let target = |name, channels| TargetDesc { name, format, channels };
    GBufferLayout {
        name,
        normal: NormalEncoding::Xyz,
        world: false,
        uniform_brdf: Some(Brdf::BlinnPhong),
        uniform_layer: Some(0),
        one_accumulation: false,
        targets: vec![
            target("albedo+spec", vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), s(SpecLevel, 0)]),
            target("normal+exp", vec![s(Normal, 0), s(Normal, 1), s(Normal, 2), s(SpecExp, 0)]),
            target("position", vec![s(Position, 0), s(Position, 1), s(Position, 2), None]),
            target("emissive", vec![s(Emissive, 0), s(Emissive, 1), s(Emissive, 2), None]),
        ],
    }
}

/// Largest octahedral 8+8-bit angular error, as published for octahedral quantisation (0.946 degrees).
pub const OCT8_MAX_ERROR_DEG: f64 = 0.946;
/// Relative error the quantised normal may cause in a specular highlight.
pub const FIT_SPECULAR_ERROR_BOUND: f64 = 0.01;

/// Model only what the scene needs: albedo always; the specular level and exponent only when
/// some material is specular; emissive only when something emits; octahedral normals in 8+8
/// bits when the sharpest highlight tolerates it (cos(0.946 deg)^e >= 1 - 1%, i.e. exponents up
/// to ~72), else 16+16 float; depth always (position from depth). Specular means a material
/// with a specular level whose reflectance model uses it (`lambert` and `unlit` do not). The
/// material ID channel is added by [`LayoutChoice::layout_for`] when `brdfs` holds more than
/// one model ([`fit_material_slot`]).
pub fn fit(scene: &crate::scene::Scene) -> GBufferLayout {
    fit_for(scene, &scene.brdfs(None))
}

/// [`fit`] for a scene whose objects use the models `brdfs` (one: forced or its only one).
pub fn fit_for(scene: &crate::scene::Scene, brdfs: &[Brdf]) -> GBufferLayout {
    use wgpu::TextureFormat as F;
    use Attr::*;
    let s = |attr, comp| Some(Slot { attr, comp });
    // With one forced model every material is shaded with it.
    let forced = if let [one] = brdfs { Some(*one) } else { None };
    let uses_specular = |m: &&crate::scene::Material| m.specular_level > 0.0 && forced.unwrap_or(m.brdf).specular();
    let specular = scene.materials.iter().any(|m| uses_specular(&m));
    let max_exp = scene.materials.iter().filter(uses_specular).map(|m| m.specular_exponent as f64).fold(1.0, f64::max);
    let eight_bit = !specular || OCT8_MAX_ERROR_DEG.to_radians().cos().powf(max_exp) >= 1.0 - FIT_SPECULAR_ERROR_BOUND;
    let mut targets = vec![TargetDesc {
        name: "albedo+spec",
        format: F::Rgba8UnormSrgb,
        channels: vec![s(Albedo, 0), s(Albedo, 1), s(Albedo, 2), if specular { s(SpecLevel, 0) } else { None }],
    }];
    let normal_format = match (eight_bit, specular) {
        (true, true) => F::Rgba8Unorm,
        (true, false) => F::Rg8Unorm,
        (false, true) => F::Rgba16Float,
        (false, false) => F::Rg16Float,
    };
    let mut channels = vec![s(Normal, 0), s(Normal, 1)];
    if specular {
        channels.extend([s(SpecExp, 0), None]);
    }
    targets.push(TargetDesc { name: "normal+exp", format: normal_format, channels });
    if scene.any_emissive() {
        targets.push(TargetDesc {
            name: "emissive",
            format: F::Rgba16Float,
            channels: vec![s(Emissive, 0), s(Emissive, 1), s(Emissive, 2), None],
        });
    }
    targets.push(TargetDesc { name: "depth", format: F::R32Float, channels: vec![s(Depth, 0)] });
    let mut layout = GBufferLayout {
        name: "fit",
        normal: NormalEncoding::Octahedral,
        world: false,
        targets,
        uniform_brdf: forced,
        uniform_layer: Some(0),
        one_accumulation: false,
    };
    if forced.is_none() {
        // Several models: the ID goes to a channel the formats already have (always one).
        if let Some((t, c)) = fit_material_slot(&layout) {
            layout.targets[t].channels[c] = Some(Slot { attr: Material, comp: 0 });
        }
    }
    layout
}

/// Where `fit` keeps the material ID: a channel its targets' formats already have and leave
/// unused: the normal target's fourth (8-bit unorm or fp16) when the scene is specular (the
/// exponent fills the third), else the albedo target's alpha (8-bit, linear in an sRGB
/// format), which the specular level would hold. Either way the ID costs no bytes.
fn fit_material_slot(layout: &GBufferLayout) -> Option<(usize, usize)> {
    layout
        .targets
        .iter()
        .take(2)
        .enumerate()
        .rev()
        .find_map(|(i, t)| (t.channels.len() == 4 && t.channels[3].is_none()).then_some((i, 3)))
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
    pub fn for_caps(mut self, caps: &super::caps::Caps) -> Self {
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
    pub fn check_caps(&self, caps: &super::caps::Caps) -> anyhow::Result<()> {
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

    /// `.x`, `.y`, ... for vector attributes, nothing for scalars.
    fn accessor(&self, s: &Slot) -> &'static str {
        if self.components(s.attr) == 1 && !matches!(s.attr, Attr::Normal) {
            ""
        } else {
            [".x", ".y", ".z", ".w"][s.comp as usize]
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

    /// WGSL: bindings of the targets for reading (group `group`), the `GBufferOut` struct,
    /// `gbuffer_store(Surface) -> GBufferOut` and `gbuffer_load(vec2<i32>) -> Surface`. With
    /// `ambient`, `GBufferOut` also has the two light accumulation targets after the layout's
    /// (`light_diffuse`, `light_specular`), which `gbuffer_store` fills with ambient + sun
    /// (`ambient_sun`, seed 000's RT1 starting value).
    pub fn wgsl(&self, group: u32, ambient: bool) -> String {
        let mut w = String::new();
        let _ = writeln!(w, "// Generated from G-buffer layout '{}'.", self.name);
        let _ = writeln!(w, "const GBUFFER_NORMAL_OCTAHEDRAL: bool = {};", self.normal == NormalEncoding::Octahedral);
        let _ = writeln!(w, "const GBUFFER_NORMAL_LAMBERT: bool = {};", self.normal == NormalEncoding::Lambert);
        let _ = writeln!(w, "const GBUFFER_HAS_DEPTH: bool = {};", self.has(Attr::Depth));
        let _ = writeln!(w, "const GBUFFER_WORLD: bool = {};", self.world);
        let _ = writeln!(w, "const GBUFFER_ONE_ACCUM: bool = {};", self.one_accumulation);
        let _ = writeln!(w, "const GBUFFER_POSITION_ROUNDING: f32 = {:?};", self.position_rounding() as f32);
        let _ = writeln!(w, "const GBUFFER_SPEC_LEVEL_RAW: bool = {};", self.spec_level_raw());
        // The material ID: per pixel from its channel, or the scene's one model.
        let _ = writeln!(w, "const GBUFFER_HAS_MATERIAL: bool = {};", self.uniform_brdf.is_none());
        let _ = writeln!(w, "const GBUFFER_BRDF: u32 = {}u;", self.uniform_brdf.unwrap_or_default().id());
        // The culling layer (seed 004): per pixel from its channel, or the scene's one layer.
        let _ = writeln!(w, "const GBUFFER_HAS_LAYER: bool = {};", self.uniform_layer.is_none());
        let _ = writeln!(w, "const GBUFFER_LAYER: u32 = {}u;", self.uniform_layer.unwrap_or(0));
        for (i, t) in self.targets.iter().enumerate() {
            let _ = writeln!(w, "@group({group}) @binding({i}) var gbuf{i}: texture_2d<{}>;", scalar(t.format));
        }
        let _ = writeln!(w, "struct GBufferOut {{");
        // The depth buffer read as a target is not an output: locations count rendered targets.
        let mut location = 0;
        for (i, t) in self.targets.iter().enumerate().filter(|(_, t)| !is_depth_buffer(t)) {
            let _ = writeln!(w, "    @location({location}) t{i}: vec4<{}>,", scalar(t.format));
            location += 1;
        }
        // A stored position is the point the lighting shades: the depth the volumes test against
        // is that point's, projected after the target's rounding, not the rasteriser's plane,
        // which can lie far from it along the ray on a grazing surface (`position_depth`).
        let position_depth = self.position_depth();
        if position_depth.is_some() {
            let _ = writeln!(w, "    @builtin(frag_depth) depth: f32,");
        }
        if ambient {
            let n = location;
            let _ = writeln!(w, "    @location({n}) light_diffuse: vec4<f32>,");
            if !self.one_accumulation {
                let _ = writeln!(w, "    @location({}) light_specular: vec4<f32>,", n + 1);
            }
        }
        let _ = writeln!(w, "}};");
        // Packed attribute vectors.
        let _ = writeln!(w, "fn gbuffer_store(s: Surface) -> GBufferOut {{");
        let _ = writeln!(w, "    var o: GBufferOut;");
        let _ = writeln!(w, "    let a = attributes_of(s);");
        let comps = ["x", "y", "z", "w"];
        for (i, t) in self.targets.iter().enumerate().filter(|(_, t)| !is_depth_buffer(t)) {
            let _ = writeln!(w, "    o.t{i} = vec4<{}>();", scalar(t.format));
            for (c, slot) in t.channels.iter().enumerate() {
                if let Some(s) = slot {
                    let src = match s.attr {
                        // The least-squares multiple of the albedo (fp16's largest finite value at most).
                        Attr::EmissiveScale => "min(select(0.0, max(dot(a.emissive, a.albedo), 0.0) / \
                                                max(dot(a.albedo, a.albedo), 1e-30), dot(a.albedo, a.albedo) > 0.0), 65504.0)"
                            .to_string(),
                        Attr::MaterialExp => "a.material * 255.0 + a.spec_exp * (255.0 / 256.0)".to_string(),
                        _ => format!("a.{}{}", attr_field(s.attr), self.accessor(s)),
                    };
                    let val = if is_bits(t.format) {
                        format!("bitcast<u32>({src})")
                    } else if s.attr.signed() && !is_float(t.format) {
                        format!("{src} * 0.5 + 0.5")
                    } else {
                        src
                    };
                    let _ = writeln!(w, "    o.t{i}.{} = {val};", comps[c]);
                }
            }
        }
        if let Some(half) = position_depth {
            let p = if half {
                "vec3<f32>(unpack2x16float(pack2x16float(a.position.xy)), unpack2x16float(pack2x16float(vec2<f32>(a.position.z, 0.0))).x)"
            } else {
                "a.position"
            };
            // As `gbuffer_load` reads it back: seed 000's world-space view vector turned to view space.
            let p =
                if self.world { format!("-(camera.view_rotation * vec4<f32>({p}, 0.0)).xyz") } else { p.to_string() };
            let _ = writeln!(w, "    let stored_clip = camera.proj * vec4<f32>({p}, 1.0);");
            let _ = writeln!(w, "    o.depth = clamp(stored_clip.z / stored_clip.w, 0.0, 1.0);");
        }
        if ambient {
            let _ = writeln!(w, "    let stored = as_stored(s);");
            let _ = writeln!(w, "    let light = ambient_sun(stored);");
            // A layout without an emissive target (seed 000's) writes the surface's emission
            // into the accumulation here: it is light, and compose adds the specular target
            // (seed 000: the one accumulation) as it is.
            let emitted = if self.has(Attr::Emissive) { "" } else { " + max(s.emissive, vec3<f32>(0.0))" };
            let diffuse = "min(light.diffuse, ambient_limit(stored))";
            let specular = format!("min(light.specular{emitted}, ambient_limit(stored))");
            if self.one_accumulation {
                let _ = writeln!(w, "    o.light_diffuse = encode_light({diffuse} * stored.albedo + {specular});");
            } else {
                let _ = writeln!(w, "    o.light_diffuse = encode_light({diffuse});");
                let _ = writeln!(w, "    o.light_specular = encode_light({specular});");
            }
        }
        let _ = writeln!(w, "    return o;\n}}");
        let _ = writeln!(w, "fn gbuffer_load(p: vec2<i32>) -> Surface {{");
        let _ = writeln!(w, "    var a = default_attributes();");
        if self.targets.iter().flat_map(|t| &t.channels).flatten().any(|s| s.attr == Attr::EmissiveScale) {
            let _ = writeln!(w, "    var emissive_scale = 0.0;");
        }
        for (i, t) in self.targets.iter().enumerate() {
            let _ = writeln!(w, "    let t{i} = textureLoad(gbuf{i}, p, 0);");
            for (c, slot) in t.channels.iter().enumerate() {
                if let Some(s) = slot {
                    let src = format!("t{i}.{}", comps[c]);
                    let val = if is_bits(t.format) {
                        format!("bitcast<f32>({src})")
                    } else if s.attr.signed() && !is_float(t.format) {
                        format!("{src} * 2.0 - 1.0")
                    } else {
                        src
                    };
                    match s.attr {
                        Attr::EmissiveScale => {
                            let _ = writeln!(w, "    emissive_scale = {val};");
                        }
                        Attr::MaterialExp => {
                            let _ = writeln!(w, "    a.material = floor({val}) / 255.0;");
                            let _ = writeln!(w, "    a.spec_exp = fract({val}) * (256.0 / 255.0);");
                        }
                        _ => {
                            let _ = writeln!(w, "    a.{}{} = {val};", attr_field(s.attr), self.accessor(s));
                        }
                    }
                }
            }
        }
        if self.targets.iter().flat_map(|t| &t.channels).flatten().any(|s| s.attr == Attr::EmissiveScale) {
            let _ = writeln!(w, "    a.emissive = emissive_scale * a.albedo;");
        }
        let _ = writeln!(w, "    return surface_of(a, p);\n}}");
        w
    }
}

/// A target holding a float's bits in an unsigned integer (the R32Uint depth copy).
pub(crate) fn is_bits(format: wgpu::TextureFormat) -> bool {
    format == wgpu::TextureFormat::R32Uint
}

/// The WGSL scalar type a target is written and read as.
fn scalar(format: wgpu::TextureFormat) -> &'static str {
    if is_bits(format) {
        "u32"
    } else {
        "f32"
    }
}

fn attr_field(a: Attr) -> &'static str {
    match a {
        Attr::Albedo => "albedo",
        Attr::SpecLevel => "spec_level",
        Attr::SpecExp => "spec_exp",
        Attr::Normal => "normal",
        Attr::Emissive => "emissive",
        Attr::Depth => "depth",
        Attr::Position => "position",
        Attr::Material => "material",
        Attr::Layer => "layer",
        Attr::EmissiveScale => "emissive_scale",
        Attr::MaterialExp => "material_exp",
    }
}

/// The G-buffer's textures for one size.
pub struct GBufferTargets {
    pub layout: GBufferLayout,
    pub textures: Vec<wgpu::Texture>,
    pub views: Vec<wgpu::TextureView>,
}

impl GBufferTargets {
    /// The targets at `width`x`height`; a target that is the depth buffer
    /// ([`is_depth_buffer`]) is `depth`, the frame's depth-stencil texture, seen through its
    /// depth aspect.
    pub fn new(device: &wgpu::Device, layout: &GBufferLayout, width: u32, height: u32, depth: &wgpu::Texture) -> Self {
        let textures: Vec<wgpu::Texture> = layout
            .targets
            .iter()
            .map(|t| {
                use wgpu::TextureUsages as U;
                if is_depth_buffer(t) {
                    return depth.clone();
                }
                let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
                super::texture(device, t.name, t.format, (width, height), usage)
            })
            .collect();
        let views = textures
            .iter()
            .zip(&layout.targets)
            .map(|(tex, t)| {
                let aspect = if is_depth_buffer(t) { wgpu::TextureAspect::DepthOnly } else { wgpu::TextureAspect::All };
                tex.create_view(&wgpu::TextureViewDescriptor { aspect, ..Default::default() })
            })
            .collect();
        Self { layout: layout.clone(), textures, views }
    }

    /// The aspect target `i` is read back through (the depth buffer's depth, else the whole).
    pub fn aspect(&self, i: usize) -> wgpu::TextureAspect {
        match self.layout.targets.get(i) {
            Some(t) if is_depth_buffer(t) => wgpu::TextureAspect::DepthOnly,
            _ => wgpu::TextureAspect::All,
        }
    }

    /// Bind group layout entries for reading every target with `textureLoad`.
    pub fn bind_group_layout(device: &wgpu::Device, layout: &GBufferLayout) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = (layout.targets.iter().enumerate())
            .map(|(i, t)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                // Compute: the tiled pass reads each tile's depth bounds.
                visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: if is_bits(t.format) {
                        wgpu::TextureSampleType::Uint
                    } else {
                        wgpu::TextureSampleType::Float { filterable: false }
                    },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            })
            .collect();
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer read"),
            entries: &entries,
        })
    }

    pub fn bind_group(&self, device: &wgpu::Device, bgl: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = self
            .views
            .iter()
            .enumerate()
            .map(|(i, v)| wgpu::BindGroupEntry { binding: i as u32, resource: wgpu::BindingResource::TextureView(v) })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer read"),
            layout: bgl,
            entries: &entries,
        })
    }
}

/// Name of [`prepass_layout`].
pub const PREPASS_LAYOUT: &str = "prepass";

/// The light pre-pass's first pass (seeds 003/004): ONE Rgba8Unorm target, the view-space
/// normal's x y z remapped to [0, 1] in RGB (8 bits each; seed 004's ARGB32, seed 003's 24-bit
/// normal) and the specular exponent as log2(exponent) / 11 in A (seed 003's "scaled 8-bit
/// specular exponent"). Rounding: each normal component is off by at most half a step,
/// q = 1/255 in [-1, 1] units, so the direction by at most asin(sqrt(3) q) = 0.389 degrees
/// ([`GBufferLayout::normal_error_bound`]); the exponent's log2 by at most 11 / 510, i.e. the
/// exponent by a factor 2^(11/510) = 1.0151.
///
/// Plus the depth copy every layout here keeps (R32Float; `GBufferLayout::for_caps`): the stencil culling methods write the
/// stencil while the lights read depth, and wgpu cannot sample a depth-stencil texture that is
/// the pass's writable attachment (seed 004's own fallback: "if Z buffer can't be accessed as
/// a texture, then depth is rendered" apart). One reflectance model in the buffer: the light
/// pass shades Blinn-Phong with unit reflectance (`surface_of` under `LS_PREPASS`).
pub fn prepass_layout() -> GBufferLayout {
    use wgpu::TextureFormat as F;
    use Attr::*;
    let s = |attr, comp| Some(Slot { attr, comp });
    GBufferLayout {
        name: PREPASS_LAYOUT,
        normal: NormalEncoding::Xyz,
        world: false,
        uniform_brdf: Some(Brdf::BlinnPhong),
        uniform_layer: Some(0),
        one_accumulation: false,
        targets: vec![
            TargetDesc {
                name: "normal+exp",
                format: F::Rgba8Unorm,
                channels: vec![s(Normal, 0), s(Normal, 1), s(Normal, 2), s(SpecExp, 0)],
            },
            TargetDesc { name: "depth", format: F::R32Float, channels: vec![s(Depth, 0)] },
        ],
    }
}

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
