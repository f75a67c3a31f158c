//! The `tessellation` group: the light volumes' sphere and cone meshes.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::Settings;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let mut v = Vec::new();
    let subdivisions: &[u32] = if q { &[0, 2] } else { &[0, 1, 2, 3] };
    for &sphere_subdivisions in subdivisions {
        let faces = 20 * 4u32.pow(sphere_subdivisions);
        let label = format!("sphere {faces} tris");
        v.push(s.row("tessellation", label, Settings { sphere_subdivisions, ..base.clone() }, o.lights));
    }
    let sides: &[u32] = if q { &[] } else { &[6, 24] };
    for &cone_sides in sides {
        v.push(s.row(
            "tessellation",
            format!("cone {cone_sides} sides"),
            Settings { cone_sides, ..base.clone() },
            o.lights,
        ));
    }
    v
}
