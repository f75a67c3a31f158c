//! What one renderer's forward paths keep between a frame and its read-back: the occlusion queries, the drawn order they count, the multisampled targets.

use std::sync::{Arc, Mutex};

pub(crate) struct Msaa {
    pub(crate) size: (u32, u32),
    pub(crate) color: wgpu::TextureView,
    pub(crate) depth: wgpu::TextureView,
}

/// A renderer's forward-path buffers: the occlusion queries of the path's passes with their
/// resolve and read-back buffers (made on the first forward frame), and the multisampled
/// targets of the last size.
#[derive(Default)]
pub struct ForwardScratch {
    pub(crate) queries: std::sync::OnceLock<Queries>,
    /// The per-draw queries of counted frames ([`MAX_DRAW_QUERIES`]), made on the first.
    pub(crate) draws: std::sync::OnceLock<Queries>,
    /// What the last counted frame's draw queries counted, in query order.
    pub(crate) counted: Mutex<Vec<Counted>>,
    pub(crate) msaa: Mutex<Option<Arc<Msaa>>>,
}

/// What one draw query of a counted frame covers: a single-pass object (each light of its
/// list evaluated at every sample it shades) or a multi-pass (object, light) pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Counted {
    Object(usize),
    Pair(usize),
}

pub(crate) struct Queries {
    pub(crate) set: wgpu::QuerySet,
    pub(crate) resolve: wgpu::Buffer,
    pub(crate) readback: wgpu::Buffer,
}

impl Queries {
    pub(crate) fn new(device: &wgpu::Device, label: &str, count: u32) -> Self {
        let buffer = |what: &str, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("{label} {what}")),
                size: count as u64 * 8,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as B;
        Queries {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Occlusion,
                count,
            }),
            resolve: buffer("resolve", B::QUERY_RESOLVE | B::COPY_SRC),
            readback: buffer("readback", B::COPY_DST | B::MAP_READ),
        }
    }
}
