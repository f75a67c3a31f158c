//! The `presets` group: each seed's whole pipeline as its preset sets it.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::presets::Preset;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    // Each seed's whole pipeline as its preset sets it, shadows and post chain included (held
    // against the reference with the preset's shadows: the FLIP column includes the seeds'
    // post effects); the counters as every row has them.
    let presets: &[Preset] = if q { &[Preset::Seed000, Preset::Seed004] } else { &Preset::SEEDS };
    presets.iter().map(|&p| s.row("presets", p.name(), p.settings(base), o.lights)).collect()
}
