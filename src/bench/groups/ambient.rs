//! The `ambient` group: where the ambient light and the sun are written.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::Settings;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, base) = (s.o, &s.base);
    let mut v = Vec::new();
    // Seed 000's ambient + sun written by the G-buffer pass (the default) against a full-screen
    // pass of their own.
    for ambient_in_gbuffer in [true, false] {
        let label = if ambient_in_gbuffer { "ambient in g-buffer pass" } else { "ambient own pass" };
        v.push(s.row("ambient", label.into(), Settings { ambient_in_gbuffer, ..base.clone() }, o.lights));
    }
    v
}
