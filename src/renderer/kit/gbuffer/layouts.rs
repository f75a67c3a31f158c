//! The layouts Lampshade knows: the fixed tables by name ([`LayoutChoice`]), the layout fitted
//! to a scene ([`fit`]) and the light pre-pass's thin buffer ([`prepass_layout`]).

use super::{channel_count, Attr, GBufferLayout, NormalEncoding, Slot, TargetDesc, PREPASS_LAYOUT};
use crate::scene::Brdf;
use serde::{Deserialize, Serialize};

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
