//! The options of `surfaces/`.

/// Declared with the other options types from the fields of `fields.rs`.
pub use super::SurfaceOptions;
