//! The `path` group: the rendering paths side by side.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{RenderPath, Settings};

/// The light counts of the `path` group (plus the room, with its own lights).
pub const PATH_LIGHT_COUNTS: [usize; 3] = [64, 256, 1024];
/// The project's glTF room, the `path` group's second scene.
pub const ROOM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf");

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    let mut v = Vec::new();
    // The rendering paths side by side (seed 002): every path over the light count,
    // and on the room. A path that cannot render on this build is a row saying why.
    let counts: &[usize] = if o.fixed_lights {
        &[]
    } else if q {
        &[64, 256]
    } else {
        &PATH_LIGHT_COUNTS
    };
    for &n in counts {
        for path in RenderPath::ALL {
            v.push(s.row("path", format!("{} x{n}", path.name()), Settings { path, ..base.clone() }, n));
        }
    }
    for path in RenderPath::ALL {
        let label = format!("{} room", path.name());
        v.push(Config { scene: Some(ROOM), ..s.row("path", label, Settings { path, ..base.clone() }, o.lights) });
    }
    // The light pre-pass with `--msaa 4`: pass 3 and the forward pass over four samples, primed
    // by a depth-only draw of pass 1's list.
    let msaa = Settings { path: RenderPath::LightPrepass, msaa: crate::renderer::Msaa::X4, ..base.clone() };
    v.push(s.row("path", format!("light-prepass msaa x4 x{}", o.lights), msaa, o.lights));
    v
}
