//! The `shadows` group: shadows of the sun and the spots, and point lights' cubes.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{Settings, ShadowCube, ShadowFilter, ShadowFormat, ShadowMode};

/// Point lights of the `shadows` group's cube rows (each casts six faces).
pub const CUBE_LIGHTS: usize = 16;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    // Shadows of the sun and the spots, against the finest shadows (`shadow_reference`):
    // atlas size, kernel, cascades. (Point lights' cube array is not built; the unrolled cube is
    // the only layout.)
    let shadowed = Settings { shadows: ShadowMode::Spots, ..base.clone() };
    let mut sh = vec![("none".to_string(), Settings { shadows: ShadowMode::None, ..base.clone() })];
    for mb in if q { vec![4.0, 64.0] } else { vec![1.0, 4.0, 16.0, 64.0] } {
        sh.push((format!("atlas {mb} MiB"), Settings { shadow_budget_mb: mb, ..shadowed.clone() }));
    }
    for f in [ShadowFilter::Pcf2x2, ShadowFilter::Poisson16] {
        sh.push((f.name(), Settings { shadow_filter: f, ..shadowed.clone() }));
    }
    for n in if q { vec![1, 4] } else { vec![1, 2, 4] } {
        sh.push((format!("{n} cascades"), Settings { shadow_cascades: n, ..shadowed.clone() }));
    }
    // Seed 002's D16 / D24X8 maps (at the same budget: D16 halves the bytes, the side only
    // doubles when the budget holds the next power of two).
    for f in if q { vec![ShadowFormat::Depth16] } else { vec![ShadowFormat::Depth24, ShadowFormat::Depth16] } {
        sh.push((f.name(), Settings { shadow_format: f, ..shadowed.clone() }));
    }
    let mut v: Vec<Config> =
        sh.into_iter().map(|(label, settings)| s.row("shadows", label, settings, o.lights)).collect();
    // Point lights' six faces (every light casting; `CUBE_LIGHTS` point lights, plus the
    // scene's spots): unrolled into the atlas (seed 002's virtual cube), the same tiles read
    // through seed 002's indirection cube (not in `--quick`), or a cube array, at the default
    // budget, against the finest shadows of `all` (`shadow_reference`).
    let cubes: &[ShadowCube] = if q {
        &[ShadowCube::Unrolled, ShadowCube::Array]
    } else {
        &[ShadowCube::Unrolled, ShadowCube::Indirect, ShadowCube::Array]
    };
    for &cube in cubes {
        let settings = Settings { shadows: ShadowMode::All, shadow_cube: cube, ..base.clone() };
        v.push(s.row("shadows", format!("cube {}", cube.name()), settings, CUBE_LIGHTS));
    }
    v
}
