//! What one renderer's tiled pass keeps between a frame and its read-back: the lists' buffers and the frame's grid.

use super::super::plan::Method;
use crate::renderer::records::TileParams;
use std::sync::Mutex;

pub(crate) struct Buffers {
    pub(crate) params: wgpu::Buffer,
    pub(crate) lists: wgpu::Buffer,
    pub(crate) counts: wgpu::Buffer,
    pub(crate) group: wgpu::BindGroup,
    /// Readback of the headers and of the counters.
    pub(crate) lists_read: wgpu::Buffer,
    pub(crate) counts_read: wgpu::Buffer,
    /// Made for this frame (by the pass's `prepare`): nothing uploaded into them yet.
    pub(crate) fresh: bool,
}

/// What the last frame left to read back.
#[derive(Clone, Copy)]
pub(crate) struct Pending {
    pub(crate) method: Method,
    pub(crate) cells: u64,
    pub(crate) lights: usize,
    pub(crate) counted: bool,
    pub(crate) tile_size: u32,
    pub(crate) slices: u32,
    pub(crate) params: TileParams,
    /// u32 words of the list buffer in use.
    pub(crate) words: u64,
    /// Z-binned: u32 words of the masks (after the per-light counters in the counts buffer).
    pub(crate) mask_words: u64,
}

/// A renderer's tile lists: the buffers (grown as frames need) and what the last frame left to
/// read back.
#[derive(Default)]
pub struct TiledScratch {
    pub(crate) state: Mutex<(Option<Buffers>, Option<Pending>)>,
}
