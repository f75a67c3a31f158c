//! The options layer: every knob's value types, below the techniques. A technique reads its
//! own options type (`CullingOptions`, `ShadowOptions`, `PostOptions`, …, each in the file of
//! its name here) and the frame-wide [`FrameOptions`]; `Settings` (`settings.rs`, above every
//! technique) is the one flat struct a knob is named in, and builds each options type in one
//! place (`Settings::options`).
//!
//! Imports nothing of the renderer but `kit/`.

mod fields;

pub mod calibration;
pub mod caps;
pub mod culling;
pub mod post;
pub mod shadows;
pub mod stochastic;
pub mod surfaces;

use serde::{Deserialize, Serialize};

pub use super::kit::gbuffer::LayoutChoice;
use caps::CapOrder;
use culling::{ClusterBuilder, CullingMode, ForwardLights, NearLights};
use post::{Aa, Focus, Tonemap};
use shadows::{ShadowCube, ShadowFilter, ShadowFormat, ShadowMode};

pub(crate) use fields::{by_technique, settings_fields};

/// The one name of a knob's value, used by the CLI, settings files, scripts, the viewer and the
/// bench: clap's `ValueEnum` name, which is the kebab-case name serde writes (the
/// `every_knob_value_has_one_name` test holds the two together).
pub fn name_of<T: clap::ValueEnum>(v: &T) -> String {
    v.to_possible_value().map_or_else(String::new, |p| p.get_name().to_string())
}

/// The value of a knob (`what`, for the message) named `s` (or one of its old aliases).
pub fn parse_name<T: clap::ValueEnum>(what: &str, s: &str) -> Result<T, String> {
    T::from_str(s, false).map_err(|_| {
        let names: Vec<String> = T::value_variants().iter().map(name_of).collect();
        format!("unknown {what} '{s}' (one of {})", names.join(", "))
    })
}

/// The value's one-line description (its doc comment), for tooltips.
pub fn help_of<T: clap::ValueEnum>(v: &T) -> String {
    v.to_possible_value().and_then(|p| p.get_help().map(|h| h.to_string())).unwrap_or_default()
}

/// `name()` and `parse()` for a knob enum, in terms of [`name_of`] and [`parse_name`].
macro_rules! knob_names {
    ($($t:ty => $what:literal),* $(,)?) => {$(
        impl $t {
            /// The value's one name (see [`name_of`]).
            pub fn name(self) -> String {
                $crate::renderer::options::name_of(&self)
            }

            #[doc = concat!("Parses a ", $what, " by its name (see [`parse_name`]).")]
            pub fn parse(s: &str) -> Result<Self, String> {
                $crate::renderer::options::parse_name($what, s)
            }
        }
    )*};
}

/// Which reflectance model shades the objects: each material's own, or one for all (an
/// experiment: the same scene as a metal, toon or unlit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum BrdfOverride {
    /// Each material's own model.
    #[default]
    Scene,
    /// Lambert diffuse + normalised Blinn-Phong specular.
    BlinnPhong,
    /// Lambert diffuse only.
    Lambert,
    /// No diffuse; the Blinn-Phong lobe tinted by the base colour.
    Metal,
    /// Banded diffuse and highlight.
    Toon,
    /// The base colour as it is, no lighting.
    Unlit,
    /// Seed 000's standard Phong: Lambert diffuse + level x (R.V)^n.
    Phong,
}

impl BrdfOverride {
    /// The forced model, or `None` for each material's own.
    pub fn brdf(self) -> Option<crate::scene::Brdf> {
        use crate::scene::Brdf;
        match self {
            BrdfOverride::Scene => None,
            BrdfOverride::BlinnPhong => Some(Brdf::BlinnPhong),
            BrdfOverride::Lambert => Some(Brdf::Lambert),
            BrdfOverride::Metal => Some(Brdf::Metal),
            BrdfOverride::Toon => Some(Brdf::Toon),
            BrdfOverride::Unlit => Some(Brdf::Unlit),
            BrdfOverride::Phong => Some(Brdf::Phong),
        }
    }
}

/// The rendering pipeline: the three the seeds describe, side by side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum RenderPath {
    /// Deferred shading (seeds 000-002): a G-buffer, lights as volumes over it, compose.
    #[default]
    Deferred,
    /// Deferred lighting (seeds 003-004): normals + exponent, lights into a light buffer, the
    /// geometry drawn again with its maps.
    LightPrepass,
    /// Forward single-pass (seed 002): each object with its light list in one shader.
    Forward,
    /// Forward multi-pass (seed 002): one additive draw per (object, light) pair.
    ForwardMultipass,
}

impl RenderPath {
    /// Whether the path draws a G-buffer that the passes after it read (and the probe, the
    /// explanation and brute force read back): the deferred paths, not the forward ones.
    pub fn keeps_gbuffer(self) -> bool {
        match self {
            RenderPath::Deferred | RenderPath::LightPrepass => true,
            RenderPath::Forward | RenderPath::ForwardMultipass => false,
        }
    }

    pub const ALL: [RenderPath; 4] =
        [RenderPath::Deferred, RenderPath::LightPrepass, RenderPath::Forward, RenderPath::ForwardMultipass];

    /// Whether the path can multisample: deferred shading cannot (seed 002: "Deferred shading
    /// is incompatible with MSAA" … "G-Buffer cannot be resolved").
    pub fn can_multisample(self) -> bool {
        self != RenderPath::Deferred
    }
}

/// The order of the opaque draws (the G-buffer pass, the light pre-pass's passes 1 and 3, the
/// forward paths' depth pre-pass and opaque passes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DrawOrder {
    /// By pipeline and material: the fewest state changes.
    #[default]
    Material,
    /// Nearest first, by each object's bounding sphere (seed 002: "an initial
    /// front-to-back-sorted z-only pass"): later, farther surfaces fail the depth test, so
    /// fewer fragments are shaded; the stats' `gbuffer_fragments` counts them.
    FrontToBack,
}

/// Where the passes after the G-buffer read each pixel's depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DepthRead {
    /// From an R32Float copy the G-buffer pass writes beside its other targets (4 bytes a
    /// pixel written and read again): the stencil methods keep the depth-stencil buffer
    /// attached for writing while they read it, which a buffer bound for reading cannot be.
    #[default]
    Copy,
    /// From the depth buffer itself, through a depth-aspect view (seed 004: "if the platform
    /// supports reading Z as a texture, depth is not explicitly rendered"), where the frame
    /// allows (`key::depth_read_refusal`); the copy otherwise, and the stats say why.
    Buffer,
}

/// How the lighting shaders pick a pixel's reflectance model (seed 002's material IDs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialBranch {
    /// Every model's terms computed, one selected: no divergent branch (lavapipe runs both
    /// sides of a branch whenever one lane takes each).
    #[default]
    Select,
    /// A branch on the material ID, each model computing only its own terms (seed 002:
    /// "reasonably coherent dynamic branching"). The same values.
    Branch,
}

/// How blended (alpha `BLEND`) surfaces are composited over the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum BlendedMode {
    /// Alpha blending (`src x alpha + dst x (1 - alpha)`), sorted back to front by each
    /// object's bounding sphere.
    #[default]
    Alpha,
    /// Additive (`src x alpha + dst`; seed 003: "additive blending modes be used to eliminate
    /// the need to sort polygons"): drawn unsorted, in scene order; the sum does not depend on
    /// it beyond the fp16 target's rounding.
    Additive,
    /// Depth peeling (seed 002: "can use depth peeling"; Everitt 2001, "Interactive
    /// Order-Independent Transparency"): `peel_layers` passes each keep the nearest blended
    /// fragment behind the last layer and add it under the layers before it, so every pixel's
    /// fragments are composited in depth order without sorting objects, interpenetrating ones
    /// included. Fragments behind the last layer are dropped (the stats count them).
    Peeled,
}

/// The most layers depth peeling peels (`Settings::peel_layers`).
pub const MAX_PEEL_LAYERS: u32 = 16;

/// Samples per pixel of the paths that can multisample (`RenderPath::can_multisample`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
pub enum Msaa {
    /// One sample per pixel.
    #[default]
    #[value(name = "1")]
    #[serde(rename = "1")]
    X1,
    /// Four samples per pixel.
    #[value(name = "4")]
    #[serde(rename = "4")]
    X4,
}

impl Msaa {
    pub fn samples(self) -> u32 {
        match self {
            Msaa::X1 => 1,
            Msaa::X4 => 4,
        }
    }
}

/// What the compose pass shows. The values are shared with WGSL as generated constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum DebugView {
    #[default]
    Lit = 0,
    Albedo = 1,
    Normal = 2,
    Depth = 3,
    Specular = 4,
    Emissive = 5,
    DiffuseLight = 6,
    SpecularLight = 7,
    /// Seed 000's diagram: blue passed Z in the marking pass, red passed Z in the shading pass,
    /// green passed the stencil test (lit).
    Stencil = 8,
    /// Lights touching each pixel.
    Complexity = 9,
    /// Lights in each pixel's tile list (`tiled`) or cluster list (`clustered`; `tiled` for
    /// the other modes): a heatmap, the legend in the viewer.
    TileLights = 10,
    /// The reflectance model of each pixel (the material ID, or the scene's one model), one
    /// colour per model (`Brdf::debug_color`), the legend in the viewer.
    MaterialId = 11,
    /// The post chain's bloom buffer (the upsampled chain before it is added), exposed and
    /// tonemapped; runs bloom even when it is off.
    Bloom = 12,
    /// The auto-exposure histogram (bins of log2 luminance, 1/3 stop each) over the dimmed
    /// picture; yellow: the adapted luminance, white: the frame's mean.
    Histogram = 13,
    /// The anti-aliasing's edge mask (the edge blur's G-buffer discontinuities, or FXAA's luma
    /// contrast test; `edge` when anti-aliasing is off): white where it may change a pixel.
    Edges = 14,
    /// Depth of field's circle of confusion at the frame's focus (the same `Focus` the blur
    /// uses, auto included): dark green where in focus (under half a pixel, copied unchanged),
    /// grey growing to white at `post::MAX_COC` px.
    Coc = 15,
    /// The shadow factor, the least of the sun's and of every casting light's that
    /// reaches the pixel: white lit, black shadowed; dark blue where no surface is drawn.
    Shadow = 16,
    /// The sun's cascades, one colour each (red, green, blue, yellow), darkened by its shadow;
    /// grey beyond the last cascade.
    Cascades = 17,
    /// The light ledger's waste at each pixel: the lights the frame evaluated there whose true
    /// shape does not hold the pixel's point (evaluated minus ideal), drawn with each light's
    /// own culling (its stencil marks, its tile or cluster list): a heatmap on the tile-lights
    /// scale; with a selected light, that light's alone. Deferred path.
    Waste = 18,
    /// RIS's estimate averaged over the frames drawn since the camera, the lights or a setting
    /// other than the noise seed last changed (`stochastic::reuse`): the lit picture it
    /// converges to. Exact frames show the lit picture.
    Converge = 19,
    /// How much RIS's light at each pixel varies from frame to frame over the same frames: its
    /// standard deviation over its mean, a heatmap from 0 to 2 (the legend in the viewer).
    /// Exact frames show none.
    Variance = 20,
}

impl DebugView {
    pub const ALL: [DebugView; 21] = [
        DebugView::Lit,
        DebugView::Albedo,
        DebugView::Normal,
        DebugView::Depth,
        DebugView::Specular,
        DebugView::Emissive,
        DebugView::DiffuseLight,
        DebugView::SpecularLight,
        DebugView::Stencil,
        DebugView::Complexity,
        DebugView::TileLights,
        DebugView::MaterialId,
        DebugView::Bloom,
        DebugView::Histogram,
        DebugView::Edges,
        DebugView::Coc,
        DebugView::Shadow,
        DebugView::Cascades,
        DebugView::Waste,
        DebugView::Converge,
        DebugView::Variance,
    ];

    /// Whether the view averages RIS's frames (`Converge`, `Variance`).
    pub fn converges(self) -> bool {
        matches!(self, DebugView::Converge | DebugView::Variance)
    }

    /// The name of the view's generated WGSL constant (`LS_VIEW_…`): its name in capitals.
    pub fn wgsl_name(self) -> String {
        self.name().to_uppercase().replace('-', "_")
    }
}

/// Light accumulation precision (seed 002: "16-bit floating point enables HDR; can use 8-bit
/// for higher performance, beware of saturation").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum AccumFormat {
    #[default]
    Rgba16Float,
    Rgba32Float,
    Rg11b10Ufloat,
    /// Seed 004 (Unity's deferred lighting): Rgba8Unorm holding `exp2(-light)`, blended
    /// multiplicatively (src x dst), so the product of the lights' factors encodes the sum of
    /// their light; compose decodes `-log2`. Range: 0 ..= [`LOG_ACCUM_MAX`] (= log2 255, about 8):
    /// more light saturates at the top of the range. Precision: one 8-bit step of the stored
    /// value is `log2(q / (q - 1))` of light at code q, i.e. 0.0057 near 0, 0.011 at 1, 0.09 at 4
    /// and 1.0 at the top; every blend rounds once more (see [`log_accum_error_bound`]).
    Rgba8Log,
    /// Seed 003's light buffer ("24-bit diffuse color (rgb) and 8-bit specular value", blended
    /// `GL_ONE, GL_ONE`) and seed 002's "8-bit for higher performance, beware of saturation":
    /// 8-bit linear channels, added. Stored as Bgra8Unorm, the byte order of the seeds'
    /// ARGB32. Range 0 ..= 1: more light saturates at 1. Precision: every write rounds to the
    /// nearest of 255 steps, so a sum of `blends` writes below 1 is off by at most
    /// `blends x 0.5 / 255` ([`unorm_accum_error_bound`]).
    Rgba8Unorm,
}

/// How far an [`AccumFormat::Rgba8Unorm`] channel may be from the exact sum when `blends`
/// writes produced it and the sum stays below 1: the blender adds each write's value to a
/// stored code and rounds the result to the nearest code, half a step (0.5/255); the stored
/// codes themselves add exactly. So at most `blends x 0.5 / 255`, whatever the order.
pub fn unorm_accum_error_bound(blends: u32) -> f32 {
    blends as f32 * 0.5 / 255.0
}

/// Largest light an [`AccumFormat::Rgba8Log`] channel holds: the smallest non-zero code, 1/255,
/// decodes to log2(255). A code of 0 (saturated) decodes to the same value, never infinity.
pub const LOG_ACCUM_MAX: f32 = 7.994_353_4;

/// Decodes a stored [`AccumFormat::Rgba8Log`] value (in 0..=1) to light, as compose does.
pub fn log_accum_decode(stored: f32) -> f32 {
    -(stored.max(1.0 / 255.0)).log2()
}

/// How far an [`AccumFormat::Rgba8Log`] channel may be from the exact sum `light` when `blends`
/// writes (the ambient pass and each light touching the pixel) produced it and the sum is below
/// [`LOG_ACCUM_MAX`]: each write rounds the source factor and the product to the nearest 8-bit
/// code (half a step, 0.5/255, each), an error `e` in a stored value `v >= 2^-light` moves the
/// decoded light by at most `e / (v ln 2)`. So at most `blends x (1/255) x 2^light / ln 2`.
pub fn log_accum_error_bound(light: f32, blends: u32) -> f32 {
    blends as f32 * (1.0 / 255.0) * light.exp2() / std::f32::consts::LN_2
}

impl AccumFormat {
    pub const ALL: [AccumFormat; 5] = [
        AccumFormat::Rgba16Float,
        AccumFormat::Rgba32Float,
        AccumFormat::Rg11b10Ufloat,
        AccumFormat::Rgba8Log,
        AccumFormat::Rgba8Unorm,
    ];

    /// The texture format, or why the adapter cannot blend into it.
    pub fn format(self, caps: &super::kit::adapter::AdapterCaps) -> anyhow::Result<wgpu::TextureFormat> {
        let format = match self {
            AccumFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
            AccumFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
            AccumFormat::Rg11b10Ufloat => wgpu::TextureFormat::Rg11b10Ufloat,
            AccumFormat::Rgba8Log => wgpu::TextureFormat::Rgba8Unorm,
            // Bgra8Unorm tells the linear 8-bit buffer from the log one (`kit::log_accum`).
            AccumFormat::Rgba8Unorm => wgpu::TextureFormat::Bgra8Unorm,
        };
        // The lights add into it: it must take blending.
        if !caps.blendable(format) {
            return Err(caps.refuse(
                &format!("--accumulation {}", name_of(&self)),
                &format!("blending into {format:?} render targets"),
                "use --accumulation rgba16-float",
            ));
        }
        Ok(format)
    }
}

/// The depth-stencil buffer's format. Position is reconstructed from the G-buffer's depth copy
/// (`GBufferLayout::for_caps`) either way; this decides the precision of every depth *test* (visibility in the
/// G-buffer pass, the light volumes' tests against the scene).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DepthFormat {
    /// Depth32FloatStencil8 (needs the adapter's DEPTH32FLOAT_STENCIL8; without it the renderer
    /// falls back to Depth24PlusStencil8 and says so in the frame's stats).
    #[default]
    #[value(alias = "d32s8")]
    #[serde(alias = "d32s8")]
    Depth32FloatStencil8,
    /// Depth24PlusStencil8: 24-bit (or better, the implementation's choice) depth.
    #[value(alias = "d24s8")]
    #[serde(alias = "d24s8")]
    Depth24PlusStencil8,
}

impl DepthFormat {
    pub const ALL: [DepthFormat; 2] = [DepthFormat::Depth32FloatStencil8, DepthFormat::Depth24PlusStencil8];

    /// The texture format on an adapter with `features`.
    pub fn format(self, features: wgpu::Features) -> wgpu::TextureFormat {
        match self {
            DepthFormat::Depth32FloatStencil8 if features.contains(wgpu::Features::DEPTH32FLOAT_STENCIL8) => {
                wgpu::TextureFormat::Depth32FloatStencil8
            }
            _ => wgpu::TextureFormat::Depth24PlusStencil8,
        }
    }
}

pub(crate) use knob_names;

knob_names!(
    CullingMode => "culling mode",
    DebugView => "view",
    AccumFormat => "accumulation format",
    DepthFormat => "depth format",
    LayoutChoice => "layout",
    ForwardLights => "forward light list",
    BrdfOverride => "reflectance model",
    Tonemap => "tonemap",
    Aa => "anti-aliasing",
    RenderPath => "rendering path",
    ClusterBuilder => "cluster list builder",
    Msaa => "MSAA sample count",
    NearLights => "near-plane rule",
    DrawOrder => "draw order",
    DepthRead => "depth read",
    BlendedMode => "blending of blended surfaces",
    MaterialBranch => "material selection",
    ShadowMode => "shadow casters",
    ShadowFilter => "shadow filter",
    ShadowCube => "shadow cube layout",
    ShadowFormat => "shadow map format",
    CapOrder => "cap order",
);

/// Declares each technique's options type from the lists of [`by_technique`]. Each field is
/// `Settings`' of the same name.
macro_rules! options_types {
    (frame $frame:tt culling $culling:tt caps $caps:tt shadows $shadows:tt post $post:tt surfaces $surfaces:tt stochastic $stochastic:tt) => {
        options_types!(@one $frame
            /// What every pass of a frame may read: the path, the view, the formats and what is
            /// measured.
            FrameOptions);
        options_types!(@one $culling
            /// The light culling's options: the mode, the bounding volumes, the lists' grids and caps.
            CullingOptions);
        options_types!(@one $caps
            /// The engine light caps' options: how many lights, how far, kept in which order.
            CapsOptions);
        options_types!(@one $shadows
            /// The shadows' options: who casts, the atlas's budget and format, the biases,
            /// filter, cascades and cube layout.
            ShadowOptions);
        options_types!(@one $post
            /// The post chain's options: exposure and tone curve, bloom, grading, fog, depth of
            /// field, vignette, anti-aliasing, distortion.
            PostOptions);
        options_types!(@one $surfaces
            /// The surfaces' options: how they are drawn, sorted, blended, lightmapped and shaded.
            SurfaceOptions);
        options_types!(@one $stochastic
            /// The stochastic estimators' options: reservoir-resampled lighting on the list modes,
            /// stochastic light culling on every mode, and the seed of their random numbers.
            StochasticOptions);
    };
    (@one { $($(#[$m:meta])* $f:ident: $t:ty,)* } $(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $name {
            $($(#[$m])* pub $f: $t,)*
        }
    };
}

settings_fields!(by_technique @sort options_types {} {} {} {} {} {} {});

/// Every technique's options for one frame, built from `Settings` (`Settings::options`). The
/// frame's passes get it through `FrameInputs`; each reads `frame` and its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub frame: FrameOptions,
    pub culling: CullingOptions,
    pub caps: CapsOptions,
    pub shadows: ShadowOptions,
    pub post: PostOptions,
    pub surfaces: SurfaceOptions,
    pub stochastic: StochasticOptions,
}
