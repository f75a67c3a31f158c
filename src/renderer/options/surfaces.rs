//! The options of `surfaces/`.

use super::{BlendedMode, BrdfOverride, DrawOrder, MaterialBranch};

/// The surfaces' options: how they are drawn, sorted, blended, lightmapped and shaded. Each
/// field is `Settings`' of the same name, which documents it.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceOptions {
    pub depth_prepass: bool,
    pub draw_order: DrawOrder,
    pub blended: BlendedMode,
    pub lightmaps: bool,
    pub lightmap_distance: f32,
    pub peel_layers: u32,
    pub material_branch: MaterialBranch,
    pub anisotropy: u32,
    pub ambient_in_gbuffer: bool,
    pub brdf: BrdfOverride,
}
