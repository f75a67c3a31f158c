//! The `engines` group: the shortcuts engines ship, each against the same frame uncapped.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{CullingMode, Settings};

/// The group of the engines' presets.
pub const ENGINES_GROUP: &str = "engines";

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, base) = (s.o, &s.base);
    // The shortcuts engines ship (`renderer::caps::ENGINES`), each against the same frame
    // uncapped: clustered deferred, and the forward path for the engines that shade forward.
    let mut v = vec![
        s.row(
            ENGINES_GROUP,
            "clustered uncapped".into(),
            Settings { culling: CullingMode::Clustered, ..base.clone() },
            o.lights,
        ),
        s.row(
            ENGINES_GROUP,
            "forward uncapped".into(),
            Settings { path: crate::renderer::RenderPath::Forward, ..base.clone() },
            o.lights,
        ),
    ];
    for e in crate::renderer::caps::ENGINES {
        if let Ok(settings) = crate::renderer::presets::engine_settings(e, base) {
            v.push(s.row(ENGINES_GROUP, e.name.into(), settings, o.lights));
        }
    }
    v
}
