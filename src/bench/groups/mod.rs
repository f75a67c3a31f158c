//! The bench's groups: each group's table of configurations in a file of its own, with the
//! values it sweeps over, built on [`sweep::Sweep`]'s base settings (each row differs from
//! them in the one knob its group varies).

mod accumulation;
mod ambient;
mod culling;
mod cutoff;
mod depth;
mod engines;
mod forward;
mod layout;
mod lights;
mod materials;
mod near;
mod path;
mod post;
mod presets;
mod radius;
mod resolution;
mod shadows;
mod stochastic;
mod sweep;
mod tessellation;

pub use cutoff::CUTOFFS;
pub use engines::ENGINES_GROUP;
pub use lights::{FULLSCREEN_MAX_LIGHTS, LIGHT_COUNTS};
pub use path::{PATH_LIGHT_COUNTS, ROOM};
pub use radius::RADIUS_SCALES;
pub use shadows::CUBE_LIGHTS;
pub use stochastic::{
    EXACT_MODES as STOCHASTIC_EXACT_MODES, LAYOUTS as STOCHASTIC_LAYOUTS, RIS_CANDIDATES, STOCHASTIC_GROUP,
};
pub(super) use sweep::Sweep;
pub use sweep::{reference_culling, REFERENCE_FULLSCREEN_BUDGET};

use super::options::Config;

/// Every group's table, in the order the sweep runs them.
pub(super) const TABLES: &[fn(&Sweep) -> Vec<Config>] = &[
    culling::rows,
    layout::rows,
    accumulation::rows,
    depth::rows,
    cutoff::rows,
    tessellation::rows,
    resolution::rows,
    lights::rows,
    radius::rows,
    ambient::rows,
    forward::rows,
    path::rows,
    post::rows,
    shadows::rows,
    near::rows,
    materials::rows,
    presets::rows,
    engines::rows,
    stochastic::rows,
];
