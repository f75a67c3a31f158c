//! The options of `shadows/`.

use serde::{Deserialize, Serialize};

/// Which lights cast shadows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowMode {
    /// No shadows.
    None,
    /// The sun only.
    Sun,
    /// The sun and spot lights (the default: the lights a scene has few of
    /// and that throw the shadows a viewer looks for; point lights cost six faces each).
    #[default]
    Spots,
    /// The sun, spots and point lights.
    All,
}

/// The shadow lookup's filter. Its value + 1 is its reach: how many texels from the lookup
/// point it reads depths (the normal offset adds it, see `shadow_tile_factor` in common.wgsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum ShadowFilter {
    /// One hardware comparison sample: 2x2 texels, bilinearly weighted.
    Pcf2x2 = 0,
    /// 3x3 hardware samples one texel apart (a 4x4-texel footprint).
    #[default]
    Pcf3x3 = 1,
    /// 16 hardware samples on a Poisson disc of radius 2 texels.
    Poisson16 = 2,
}

/// The depth format of the shadow atlas and the cube array (seed 002: "Use D16 or D24X8 format
/// for shadow maps"). The maps store linear depth -z / far in [0, 1]; a format's step (its
/// quantisation near 1, [`ShadowFormat::step`]) is added to the depth bias: the stored depth
/// rounds by up to half a step, and the reference the hardware compares with may be converted
/// to the format's precision, by up to half a step more.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowFormat {
    /// Depth32Float, 4 bytes a texel.
    #[default]
    Depth32,
    /// wgpu's Depth24Plus (D24X8 where the adapter has it, else a 32-bit float), 4 bytes a
    /// texel as budgeted.
    Depth24,
    /// Depth16Unorm, 2 bytes a texel: twice the texels for a budget (the side doubles when the
    /// budget allows a power of two more).
    Depth16,
}

/// Where point lights' (and wide spots') six faces live.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowCube {
    /// Seed 002's "virtual shadow depth cube": six tiles of the 2D atlas, each with a
    /// [`BORDER`], the face picked in the shader.
    #[default]
    Unrolled,
    /// One Depth32Float cube-array texture, six layers a light, all cubes one size, sampled by
    /// direction (`texture_depth_cube_array`; seamless hardware filtering, no border). Needs
    /// the adapter's `DownlevelFlags::CUBE_ARRAY_TEXTURES`.
    Array,
    /// The unrolled tiles, the face and its coordinates read from seed 002's "G16R16 cubemap
    /// [that] efficiently maps XYZ->ST" instead of picked in the shader: one shared cube
    /// texture whose texels hold their own face and face coordinates (`indirection_texels`),
    /// sampled nearest by the light-to-point direction. Within [`indirection_error`] texels
    /// of the face-pick's lookup point; the depth bias widens by that much.
    Indirect,
}

/// Declared with the other options types from the fields of `fields.rs`.
pub use super::ShadowOptions;
