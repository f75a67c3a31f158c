//! The `resolution` group: the frame's size.

use super::sweep::Sweep;
use crate::bench::options::Config;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let mut v = Vec::new();
    let sizes: &[(u32, u32)] =
        if q { &[(160, 90), (640, 360)] } else { &[(160, 90), (320, 180), (640, 360), (1280, 720)] };
    for &size in sizes {
        let label = format!("{}x{}", size.0, size.1);
        v.push(Config { size, ..s.row("resolution", label, base.clone(), o.lights) });
    }
    v
}
