//! What the bench is asked for ([`BenchOptions`]) and one configuration it sweeps ([`Config`]).

use crate::renderer::Settings;

#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scene: String,
    pub quick: bool,
    /// Frames timed per configuration (the median is reported).
    pub frames: usize,
    pub size: (u32, u32),
    pub lights: usize,
    pub time: f64,
    /// Run only the configurations of these groups (all when empty).
    pub groups: Vec<String>,
    /// The `lights` group's light counts (its defaults when empty).
    pub counts: Vec<usize>,
    /// The scene brings a fixed set of lights (a glTF file with lights, a built-in scene that
    /// takes no count): `lights` is not varied and the `lights` group is left out.
    pub fixed_lights: bool,
    /// The cost model's constants `auto` and the ledger's estimates weigh with (the built-in
    /// defaults unless the CLI read a calibration).
    pub costs: crate::renderer::options::calibration::Calibration,
}

impl BenchOptions {
    pub fn new(scene: &str, quick: bool) -> Self {
        if quick {
            Self {
                scene: scene.into(),
                quick,
                frames: 3,
                size: (320, 180),
                lights: 256,
                time: 0.0,
                groups: Vec::new(),
                counts: Vec::new(),
                fixed_lights: false,
                costs: Default::default(),
            }
        } else {
            Self {
                scene: scene.into(),
                quick,
                frames: 10,
                size: (1280, 720),
                lights: 1024,
                time: 0.0,
                groups: Vec::new(),
                counts: Vec::new(),
                fixed_lights: false,
                costs: Default::default(),
            }
        }
    }
}

/// One configuration: what it varies, and the settings, light count, size and scene it runs with.
#[derive(Clone, Debug)]
pub struct Config {
    pub group: &'static str,
    pub label: String,
    pub settings: Settings,
    pub lights: usize,
    pub size: (u32, u32),
    /// Another built-in scene than the bench's (the depth group's `far-origin` rows).
    pub scene: Option<&'static str>,
    /// Every light's radius times this (the `radius` group; 1 elsewhere).
    pub radius_scale: f64,
    /// The calibration pass ([`CALIBRATION`](super::CALIBRATION)): the scene's lights are
    /// replaced by one point light that reaches every pixel, shaded `fullscreen`.
    pub calibration: bool,
}
