//! What one renderer's passes keep between a frame and its read-back: the tile lists' buffers,
//! the forward paths' occlusion queries and multisampled targets, the atlas view's range. A pass
//! set holds only what is built for a configuration (pipelines, layouts), so every renderer on a
//! device shares the sets of its configurations (`PassPool`) while each writes its own scratch.

use crate::renderer::culling::tiled::scratch::TiledScratch;
use crate::renderer::paths::forward_scratch::ForwardScratch;
use crate::renderer::shadows::scratch::{AtlasScratch, ShadowTimes};

#[derive(Default)]
pub struct Scratch {
    pub tiled: TiledScratch,
    /// The ledger's per-light shadow timing.
    pub shadows: ShadowTimes,
    pub forward: ForwardScratch,
    pub atlas_view: AtlasScratch,
    /// RIS's reservoirs, kept from frame to frame for temporal reuse.
    pub reuse: crate::renderer::stochastic::reuse::ReuseScratch,
}
