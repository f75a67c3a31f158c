//! What one renderer's shadow passes keep between a frame and its read-back: the per-light timers, and the atlas view's range buffers.

/// Whose tiles a timed shadow render pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    /// The sun's cascades.
    Sun,
    Light(usize),
}

pub(crate) struct Timers {
    pub(crate) set: wgpu::QuerySet,
    pub(crate) resolve: wgpu::Buffer,
    pub(crate) readback: wgpu::Buffer,
    pub(crate) capacity: u32,
}

/// A renderer's per-light shadow timing (the ledger's frames): the timestamp queries, grown as
/// frames need, and the last frame's owner of each pair.
#[derive(Default)]
pub struct ShadowTimes {
    pub(crate) timers: std::sync::Mutex<Option<std::sync::Arc<Timers>>>,
    pub(crate) owners: std::sync::Mutex<Vec<(Owner, u32)>>,
}

/// A renderer's range buffers (made on first use): `atlas_range` (least and greatest depth
/// bits, the image's side, a pad) and its copy for the CPU.
#[derive(Default)]
pub struct AtlasScratch {
    pub(crate) buffers: std::sync::OnceLock<(wgpu::Buffer, wgpu::Buffer)>,
}
