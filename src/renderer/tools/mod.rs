//! The diagnostic tools over the last frame: each takes what the frame kept, never the renderer's internals.

mod brute;
mod explain;
mod probe;
mod readback;
