//! The `accumulation` group: the light accumulation target's formats, the default
//! (Rgba16Float) among them, so the group's rows hold every format against one reference.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{AccumFormat, Settings};

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let accumulations: &[AccumFormat] = if q {
        &[AccumFormat::Rgba16Float, AccumFormat::Rgba8Log]
    } else {
        &[
            AccumFormat::Rgba16Float,
            AccumFormat::Rgba32Float,
            AccumFormat::Rg11b10Ufloat,
            AccumFormat::Rgba8Log,
            AccumFormat::Rgba8Unorm,
        ]
    };
    let mut v = Vec::new();
    for &accumulation in accumulations {
        v.push(s.row("accumulation", accumulation.name(), Settings { accumulation, ..base.clone() }, o.lights));
    }
    v
}
