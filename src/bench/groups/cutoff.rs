//! The `cutoff` group: each light's cut-off threshold.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::Settings;

/// The cut-off thresholds the `cutoff` group sweeps (fractions of each light's peak).
pub const CUTOFFS: [(f32, &str); 4] = [(0.0, "0"), (1.0 / 256.0, "1/256"), (1.0 / 64.0, "1/64"), (1.0 / 16.0, "1/16")];

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let mut v = Vec::new();
    for (t, name) in CUTOFFS {
        if t == 0.0 && q {
            continue;
        }
        v.push(s.row("cutoff", format!("cutoff {name}"), Settings { light_cutoff: t, ..base.clone() }, o.lights));
    }
    v
}
