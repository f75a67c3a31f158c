//! The sweep: every group's table (`groups/`) in the order the report lists them, then the
//! calibration rows at each scene and size the sweep renders.

use super::groups::{Sweep, ENGINES_GROUP, STOCHASTIC_GROUP, TABLES};
use super::options::{BenchOptions, Config};
use crate::renderer::{CullingMode, Settings};

/// The sweep. Every configuration differs from the default (`volume` culling, `compact`
/// layout, Rgba16Float accumulation, Depth32FloatStencil8, exact radii, an 80-triangle sphere
/// and a 12-sided cone) in one knob; `--quick` keeps a subset of each group. Each group's
/// table is in its own file of `groups/`, and `groups::TABLES` runs them in order. The
/// `stochastic` group, a sweep over eleven layouts of its own, runs only when named.
pub fn configs(o: &BenchOptions) -> Vec<Config> {
    let sweep = Sweep::new(o);
    let mut v: Vec<Config> = TABLES.iter().flat_map(|rows| rows(&sweep)).collect();
    let named = |c: &Config| o.groups.iter().any(|g| g == c.group);
    v.retain(|c| named(c) || (o.groups.is_empty() && c.group != STOCHASTIC_GROUP));
    let calibration = calibration_rows(&sweep, &v);
    v.extend(calibration);
    v
}

/// The calibration pass at every scene and size the sweep `v` renders, timed in the same
/// interleaved rounds: the unit of ρ_fs and of the fixed passes' cost.
fn calibration_rows(sweep: &Sweep, v: &[Config]) -> Vec<Config> {
    let mut at: Vec<(Option<&'static str>, (u32, u32))> = Vec::new();
    for k in v.iter().map(|c| (c.scene, c.size)) {
        if !at.contains(&k) {
            at.push(k);
        }
    }
    at.into_iter()
        .map(|(scene, size)| {
            let settings = Settings { culling: CullingMode::Fullscreen, ..sweep.base.clone() };
            let label =
                format!("calibration {}{}x{}", scene.map_or(String::new(), |s| format!("{s} ")), size.0, size.1);
            Config { scene, size, calibration: true, ..sweep.row(CALIBRATION, label, settings, 1) }
        })
        .collect()
}

/// The group of the calibration rows: one point light reaching every pixel, shaded
/// `fullscreen` over the scene's G-buffer (the scene's own lights left out), at each scene and
/// size of the sweep. Its lighting time is one full-screen light pass: the unit of ρ_fs.
pub const CALIBRATION: &str = "calibration";

/// The calibration pass's scene: `scene` with its lights replaced by one white point light at
/// the camera whose radius reaches past every surface (so no pixel is outside it).
pub fn calibration_scene(scene: &mut crate::Scene) {
    let reach = scene.bounds().map_or(1e3, |(lo, hi)| {
        let c = scene.camera.position;
        // The farthest corner of the bounds from the camera.
        (hi - c).abs().max((c - lo).abs()).length() * 2.0 + 1.0
    });
    scene.set_lights(vec![crate::scene::Light::Point(crate::scene::PointLight {
        position: scene.camera.position,
        color: glam::Vec3::ONE,
        intensity: 1.0,
        radius: reach as f32,
        cookie: None,
        mask: u32::MAX,
        cast_shadows: false,
    })]);
}

/// The configuration groups, for `--only`.
pub const GROUPS: &[&str] = &[
    "culling",
    ENGINES_GROUP,
    "presets",
    "near",
    "materials",
    "layout",
    "accumulation",
    "depth",
    "cutoff",
    "tessellation",
    "resolution",
    "lights",
    "radius",
    "ambient",
    "forward",
    "post",
    "shadows",
    "path",
    STOCHASTIC_GROUP,
];

/// Scales every light's radius (and so its reach and volume) by `k`.
pub fn scale_light_radii(scene: &mut crate::Scene, k: f64) {
    for l in scene.lights_mut() {
        match l {
            crate::scene::Light::Point(p) => p.radius *= k as f32,
            crate::scene::Light::Spot(s) => s.radius *= k as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn culling_rows(lights: usize, size: (u32, u32)) -> Vec<String> {
        let o = BenchOptions {
            scene: "demo".into(),
            quick: false,
            frames: 1,
            size,
            lights,
            time: 0.0,
            groups: vec!["culling".into()],
            counts: Vec::new(),
            fixed_lights: false,
            costs: Default::default(),
        };
        configs(&o).into_iter().filter(|c| c.group == "culling").map(|c| c.label).collect()
    }

    #[test]
    fn the_culling_group_drops_fullscreen_only_past_the_references_budget() {
        let every: Vec<String> = CullingMode::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(culling_rows(1024, (1280, 720)), every);
        // 1024 x 1920 x 1080 = 2.1e9 pairs: within the budget, so the GPU run's 1,024 rows
        // include it; 16,384 lights at the same size do not.
        assert_eq!(culling_rows(1024, (1920, 1080)), every);
        let without: Vec<String> = every.iter().filter(|m| *m != "fullscreen").cloned().collect();
        assert_eq!(culling_rows(16_384, (1920, 1080)), without);
        assert_eq!(culling_rows(100_000, (1920, 1080)), without);
    }
}
