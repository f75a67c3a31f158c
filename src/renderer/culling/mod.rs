//! Light culling: which pixels each light is drawn over, and how. Every method gives the
//! full-screen picture (culling only skips work, never light); they differ in what they cost.
//! - [`plan`]: each light's method this frame (the mode, or `auto`'s choice per light), the
//!   object draw lists and the forward lists;
//! - [`volumes`]: the bounding meshes (icosphere, pyramid) the volume and stencil methods draw;
//! - [`batches`]: lights that share one instanced draw;
//! - [`overlap`]: the fp16 clamp by what can overlap a pixel;
//! - [`light_pass`] with `lights.wgsl`: ambient + sun, then each light with its method's
//!   stencil states (seed 000's two-pass stencil, seed 001's single-pass INVERT, seed 002's
//!   REPLACE);
//! - [`tiled`]: tiled and clustered light lists (Olsson et al. 2012), built on the CPU or the
//!   GPU, and the one full-screen pass that shades them (`tiled.wgsl`);
//! - [`zbin`]: Drobot's z-bins (lights sorted by depth, a bin's range of them, a tile's
//!   bitmask), shaded by the same pass (`zbin.wgsl`).

pub mod batches;
pub mod binning;
pub mod light_pass;
pub mod methods;
pub mod overlap;
pub mod plan;
pub mod stats;
pub mod tiled;
pub mod volumes;
pub mod zbin;
