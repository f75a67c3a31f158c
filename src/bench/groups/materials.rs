//! The `materials` group: how the shading picks each pixel's material model.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::settings::MaterialBranch;
use crate::renderer::Settings;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, base) = (s.o, &s.base);
    // Seed 002's material IDs: every model computed and one selected, or a branch on the ID
    // (the same values; on a scene of one model both compile to that model alone).
    [MaterialBranch::Select, MaterialBranch::Branch]
        .into_iter()
        .map(|material_branch| {
            let label = format!("material {}", material_branch.name());
            s.row("materials", label, Settings { material_branch, ..base.clone() }, o.lights)
        })
        .collect()
}
