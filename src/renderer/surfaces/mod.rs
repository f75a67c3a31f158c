//! The passes every path shares:
//! - [`gbuffer`]: the geometry into the G-buffer (and the depth the light volumes test);
//! - [`compose`]: the lit picture or a debug view from the G-buffer and light buffers, and the
//!   tonemap from the HDR colour;
//! - [`blended`]: blended surfaces shaded forward over the HDR picture, back to front (deferred
//!   shading cannot do transparency);
//! - [`debug`]: seed 000's stencil diagram and the light-complexity heatmap;
//! - [`measure`]: measurement only, outside the frame's timestamps: the ideal fragment count
//!   and the rasterised coverage.

pub mod blended;
pub mod compose;
pub mod debug;
pub mod gbuffer;
pub mod measure;
pub mod peel;
