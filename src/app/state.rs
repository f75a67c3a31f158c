//! The viewer's UI state: plain serde data, apart from every GPU object. Panels and scripts change
//! it; the next frame builds its `Scene` and `Settings` from it.

use crate::renderer::knobs::{self, parse_switch as parse_bool};
use crate::renderer::Settings;
use crate::scene::{Camera, Light, Material, Scene, Sun};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Largest light count the viewer accepts (the core's own limit).
pub const MAX_LIGHTS: usize = crate::scene::builtin::MAX_LIGHTS;
/// Resolution scale bounds: share of the viewport's pixels the scene is rendered at.
pub const MIN_SCALE: f32 = 0.1;
pub const MAX_SCALE: f32 = 2.0;
/// The default resolution scale: keeps the 1024-light demo responsive on a software rasteriser.
pub const DEFAULT_SCALE: f32 = 0.5;

/// Which lights the stencil and complexity views (and the wireframes) show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Scope {
    #[default]
    All,
    Selected,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Wireframes {
    #[default]
    Off,
    All,
    Selected,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum WireColour {
    /// The light's own colour.
    #[default]
    Light,
    /// ideal / shaded per light: red wastes work, green shades only what it lights.
    Efficiency,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Tab {
    #[default]
    Scene,
    Lights,
    Materials,
    Camera,
    Help,
}

impl Tab {
    pub const ALL: [Tab; 5] = [Tab::Scene, Tab::Lights, Tab::Materials, Tab::Camera, Tab::Help];
}

// One name per value (clap's, which is serde's), as for the renderer's knobs.
crate::renderer::options::knob_names!(Scope => "scope", Wireframes => "wireframes", WireColour => "wire colour", Tab => "tab");

/// What the user changed on one light; position and direction keep following the animation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightEdit {
    pub color: Vec3,
    pub intensity: f32,
    pub radius: f32,
    /// Spot half-angles (inner, outer) in radians; `None` for point lights.
    pub angles: Option<(f32, f32)>,
    /// The light's own shadow flag (`Light::cast_shadows`).
    #[serde(default = "cast_default")]
    pub cast_shadows: bool,
    /// Culling mask (seed 004): bit k = lights layer k.
    #[serde(default = "all_layers")]
    pub mask: u32,
}

fn cast_default() -> bool {
    true
}

fn all_layers() -> u32 {
    crate::scene::ALL_LAYERS
}

impl LightEdit {
    pub fn of(light: &Light) -> Self {
        match light {
            Light::Point(p) => Self {
                color: p.color,
                intensity: p.intensity,
                radius: p.radius,
                angles: None,
                cast_shadows: p.cast_shadows,
                mask: p.mask,
            },
            Light::Spot(s) => Self {
                color: s.color,
                intensity: s.intensity,
                radius: s.radius,
                angles: Some((s.inner_angle, s.outer_angle)),
                cast_shadows: s.cast_shadows,
                mask: s.mask,
            },
        }
    }

    pub fn apply(&self, light: &mut Light) {
        let (color, intensity, radius, cast_shadows, mask) = match light {
            Light::Point(p) => (&mut p.color, &mut p.intensity, &mut p.radius, &mut p.cast_shadows, &mut p.mask),
            Light::Spot(s) => {
                if let Some((inner, outer)) = self.angles {
                    s.inner_angle = inner;
                    s.outer_angle = outer;
                }
                (&mut s.color, &mut s.intensity, &mut s.radius, &mut s.cast_shadows, &mut s.mask)
            }
        };
        (*color, *intensity, *radius, *cast_shadows, *mask) =
            (self.color, self.intensity, self.radius, self.cast_shadows, self.mask);
    }
}

/// Everything the panels control. Serialisable, so a screenshot can record it.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct UiState {
    pub scene: String,
    /// Point lights in `demo` (`None`: the scene's default).
    pub lights: Option<usize>,
    /// Animation time in seconds.
    pub time: f64,
    pub animate: bool,
    /// A new noise seed each frame (the stochastic estimators' noise moves, as a renderer that
    /// reuses nothing across frames shows it).
    #[serde(default)]
    pub animate_noise: bool,
    /// Animation speed factor.
    pub time_speed: f64,
    pub settings: Settings,
    pub resolution_scale: f32,
    pub selected_light: Option<usize>,
    /// The culling check's row whose difference image is shown.
    #[serde(skip)]
    pub check_row: usize,
    /// Stencil / complexity views for all lights or the selected one.
    pub scope: Scope,
    pub wireframes: Wireframes,
    pub wire_colour: WireColour,
    /// `None` until the user moves: the scene's own camera.
    pub camera: Option<Camera>,
    /// Camera speed in units per second (Shift: x4).
    pub move_speed: f64,
    pub light_edits: BTreeMap<usize, LightEdit>,
    /// The light list in the ledger's order: costliest first, with bars.
    pub lights_by_cost: bool,
    /// Cookies the user picked per light (seed 004): a built-in name or a PNG path; `None`
    /// takes the light's cookie away.
    #[serde(default)]
    pub light_cookies: BTreeMap<usize, Option<String>>,
    /// Multipliers on every light's radius and intensity.
    pub radius_scale: f32,
    pub intensity_scale: f32,
    pub material_edits: BTreeMap<usize, Material>,
    pub ambient: Option<Vec3>,
    /// `Some(None)`: the user switched the sun off.
    pub sun: Option<Option<Sun>>,
    pub tab: Tab,
    /// Material the materials tab edits.
    pub material_index: usize,
    /// The path typed into the "open" field.
    #[serde(skip)]
    pub open_path: String,
    /// Which panels the user wants; a window too small for them hides some anyway (`ui::draw`).
    pub panels: Panels,
    /// The shadow-atlas panel's zoom and pan.
    pub atlas_view: AtlasView,
    /// The split view: configuration B beside the panels' A (`app::split`).
    pub split: super::split::Split,
}

/// The part of the shadow atlas its panel shows: `zoom` (1 = the whole atlas) around `centre`
/// (atlas fractions, 0..1 across and down).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct AtlasView {
    pub zoom: f32,
    pub centre: [f32; 2],
}

impl Default for AtlasView {
    fn default() -> Self {
        Self { zoom: 1.0, centre: [0.5, 0.5] }
    }
}

/// The panels around the viewport, each shown or hidden from the top bar.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Panels {
    pub left: bool,
    pub right: bool,
    pub gbuffer: bool,
    /// The shadow-atlas window (floats over the viewport; off until asked for).
    pub shadows: bool,
    /// The "why each light" window (opens on a click in the viewport).
    pub explain: bool,
    /// The culling check's window (opens when a check runs).
    pub check: bool,
    /// The advisor's window (opens when it starts).
    #[serde(default)]
    pub advice: bool,
    /// The pipelines window: each configuration's pipelines with their compile times.
    #[serde(default)]
    pub pipelines: bool,
}

impl Default for Panels {
    fn default() -> Self {
        Self {
            left: true,
            right: true,
            gbuffer: true,
            shadows: false,
            explain: false,
            check: false,
            advice: false,
            pipelines: false,
        }
    }
}

impl Default for UiState {
    fn default() -> Self {
        Self {
            scene: "demo".into(),
            lights: None,
            time: 0.0,
            animate: true,
            animate_noise: false,
            time_speed: 1.0,
            settings: Settings { count_ideal: false, ..Settings::default() },
            resolution_scale: DEFAULT_SCALE,
            selected_light: None,
            check_row: 0,
            scope: Scope::All,
            wireframes: Wireframes::Off,
            wire_colour: WireColour::Light,
            camera: None,
            move_speed: 8.0,
            light_edits: BTreeMap::new(),
            lights_by_cost: false,
            light_cookies: BTreeMap::new(),
            radius_scale: 1.0,
            intensity_scale: 1.0,
            panels: Panels::default(),
            material_edits: BTreeMap::new(),
            ambient: None,
            sun: None,
            tab: Tab::Scene,
            material_index: 0,
            open_path: String::new(),
            atlas_view: AtlasView::default(),
            split: Default::default(),
        }
    }
}

fn parse_f64(v: &str) -> Result<f64, String> {
    let x: f64 = v.parse().map_err(|_| format!("'{v}' is not a number"))?;
    if !x.is_finite() {
        return Err(format!("'{v}' is not a finite number"));
    }
    Ok(x)
}

fn in_range(name: &str, x: f64, lo: f64, hi: f64) -> Result<f64, String> {
    if x < lo || x > hi {
        return Err(format!("{name} {x} is outside [{lo}, {hi}]"));
    }
    Ok(x)
}

/// Parses `#rrggbb` or `r,g,b` (linear, 0..=1000).
pub fn parse_colour(v: &str) -> Result<Vec3, String> {
    if let Some(hex) = v.strip_prefix('#') {
        if hex.len() != 6 {
            return Err(format!("colour '{v}' is not #rrggbb"));
        }
        let c = u32::from_str_radix(hex, 16).map_err(|_| format!("colour '{v}' is not #rrggbb"))?;
        let f = |s: u32| ((c >> s) & 255) as f32 / 255.0;
        return Ok(Vec3::new(f(16), f(8), f(0)));
    }
    let parts: Vec<&str> = v.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("colour '{v}' is not r,g,b or #rrggbb"));
    }
    let mut c = [0.0f32; 3];
    for (i, p) in parts.iter().enumerate() {
        c[i] = in_range("colour component", parse_f64(p.trim())?, 0.0, 1000.0)? as f32;
    }
    Ok(Vec3::from(c))
}

impl UiState {
    /// The renderer's settings for this frame: the stencil scope folded into `selected_light`.
    pub fn frame_settings(&self) -> Settings {
        Settings {
            selected_light: match self.scope {
                Scope::All => None,
                Scope::Selected => self.selected_light,
            },
            // The panels read the per-light table (the light list, the probe, the shadow atlas)
            // whether or not the frame counts.
            per_light_stats: true,
            ..self.settings.clone()
        }
    }

    /// The edit record of light `i` of `scene`, created from the light's current values.
    pub fn light_edit(&mut self, scene: &Scene, i: usize) -> Option<&mut LightEdit> {
        let light = scene.lights.get(i)?;
        Some(self.light_edits.entry(i).or_insert_with(|| LightEdit::of(light)))
    }

    /// Sets one named value the way the panels do, rejecting nonsense with a message. Scripts
    /// use this (`set NAME VALUE`); `scene` is the frame's current scene (for the selected light).
    pub fn set(&mut self, name: &str, value: &str, scene: &Scene) -> Result<String, String> {
        if knobs::find(name).is_some() {
            self.settings.set(name, value)?;
            return Ok(format!("{name} = {value}"));
        }
        match name {
            "lights" => {
                if self.scene != "demo" {
                    return Err(format!("scene '{}' has a fixed set of lights", self.scene));
                }
                let n: usize = value.parse().map_err(|_| format!("light count '{value}' is not a whole number"))?;
                if n > MAX_LIGHTS {
                    return Err(format!("light count {n} is more than {MAX_LIGHTS}"));
                }
                self.lights = Some(n);
                if self.selected_light.is_some_and(|k| k >= n + 4) {
                    self.selected_light = None;
                }
            }
            "scale" => {
                self.resolution_scale =
                    in_range("resolution scale", parse_f64(value)?, MIN_SCALE as f64, MAX_SCALE as f64)? as f32
            }
            "time" => self.time = in_range("time", parse_f64(value)?, -1e6, 1e6)?,
            "speed" => self.time_speed = in_range("time speed", parse_f64(value)?, -100.0, 100.0)?,
            "move-speed" => self.move_speed = in_range("move speed", parse_f64(value)?, 0.01, 1000.0)?,
            "animate" => self.animate = parse_bool(value)?,
            "animate-noise" => self.animate_noise = parse_bool(value)?,
            "costliest-first" => self.lights_by_cost = parse_bool(value)?,
            "panel-left" => self.panels.left = parse_bool(value)?,
            "panel-right" => self.panels.right = parse_bool(value)?,
            "panel-gbuffer" => self.panels.gbuffer = parse_bool(value)?,
            "panel-shadows" => self.panels.shadows = parse_bool(value)?,
            "panel-pipelines" => self.panels.pipelines = parse_bool(value)?,
            "compare" => self.split.on = parse_bool(value)?,
            "compare-view" => self.split.view = super::split::SplitView::parse(value)?,
            "divider" => self.split.divider = in_range("divider", parse_f64(value)?, 0.0, 1.0)? as f32,
            "radius-scale" => self.radius_scale = in_range("radius scale", parse_f64(value)?, 0.01, 100.0)? as f32,
            "intensity-scale" => {
                self.intensity_scale = in_range("intensity scale", parse_f64(value)?, 0.0, 100.0)? as f32
            }
            "ambient" => self.ambient = Some(parse_colour(value)?),
            "sun" => {
                // The same sun as the panel's checkbox.
                self.sun = Some(parse_bool(value)?.then(Sun::default_sun));
            }
            "radius" | "intensity" | "colour" | "color" | "inner" | "outer" | "cast" => {
                let Some(k) = self.selected_light else {
                    return Err(format!("'{name}' edits the selected light: select one first"));
                };
                let edit = self.light_edit(scene, k).ok_or_else(|| format!("light {k} does not exist"))?;
                let mut e = *edit;
                match name {
                    "radius" => e.radius = in_range("radius", parse_f64(value)?, 0.01, 10_000.0)? as f32,
                    "intensity" => e.intensity = in_range("intensity", parse_f64(value)?, 0.0, 10_000.0)? as f32,
                    "colour" | "color" => e.color = parse_colour(value)?,
                    // The selected light's shadow flag.
                    "cast" => e.cast_shadows = parse_bool(value)?,
                    _ => {
                        let Some((inner, outer)) = e.angles else {
                            return Err(format!("light {k} is a point light: it has no cone angles"));
                        };
                        let a = (in_range("angle", parse_f64(value)?, 0.0, 90.0)? as f32).to_radians();
                        e.angles = Some(if name == "inner" {
                            if a > outer {
                                return Err(format!("inner angle {value}° exceeds the outer angle"));
                            }
                            (a, outer)
                        } else {
                            (inner.min(a), a)
                        });
                    }
                }
                let mut l = scene.lights[k];
                e.apply(&mut l);
                l.validate().map_err(|err| format!("light {k}: {err}"))?;
                *edit = e;
            }
            // Seed 004: the selected light's culling mask (decimal or 0x hex) and cookie.
            "mask" | "cookie" => {
                let Some(k) = self.selected_light.filter(|k| *k < scene.lights.len()) else {
                    return Err(format!("'{name}' edits the selected light: select one first"));
                };
                if name == "cookie" {
                    let spec = (value != "none").then(|| value.to_string());
                    if let Some(spec) = &spec {
                        let cube = matches!(scene.lights[k], Light::Point(_));
                        crate::scene::cookie::CookieImage::resolve(spec, cube)
                            .map_err(|e| format!("light {k}: {e}"))?;
                    }
                    self.light_cookies.insert(k, spec);
                } else {
                    let mask = match value.strip_prefix("0x") {
                        Some(hex) => u32::from_str_radix(hex, 16),
                        None => value.parse(),
                    }
                    .map_err(|_| format!("mask '{value}' is not a 32-bit number (decimal or 0x hex)"))?;
                    let edit = self.light_edit(scene, k).ok_or_else(|| format!("light {k} does not exist"))?;
                    edit.mask = mask;
                }
            }
            _ => return Err(format!("unknown setting '{name}'")),
        }
        Ok(format!("{name} = {value}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::loading::SceneCache;
    use crate::scene::builtin::{self, BuiltinOptions};

    #[test]
    fn nonsense_is_rejected_and_leaves_the_state_alone() {
        let mut s = UiState::default();
        let scene = builtin::build("demo", BuiltinOptions { lights: Some(4), time: 0.0 }).unwrap();
        for (k, v) in [
            ("exposure", "-1"),
            ("exposure", "NaN"),
            ("scale", "0"),
            ("lights", "-3"),
            ("lights", "1e9"),
            ("radius", "5"),
            ("ambient", "red"),
            ("bogus", "1"),
        ] {
            assert!(s.set(k, v, &scene).is_err(), "{k} {v} was accepted");
        }
        assert_eq!(s.settings.exposure, 1.0);
        s.selected_light = Some(0);
        assert!(s.set("radius", "-2", &scene).is_err());
        assert!(s.set("outer", "10", &scene).is_err(), "a point light has no cone");
        s.set("radius", "7.5", &scene).unwrap();
        assert_eq!(s.light_edits[&0].radius, 7.5);
        s.selected_light = Some(4); // the first spot
        s.set("outer", "10", &scene).unwrap();
        assert!(s.set("inner", "20", &scene).is_err());
    }

    #[test]
    fn edits_survive_animation() {
        let mut s = UiState { lights: Some(8), ..UiState::default() };
        let mut cache = SceneCache::default();
        let a = cache.frame_scene(&s).unwrap();
        s.selected_light = Some(2);
        s.set("colour", "#ff0000", &a).unwrap();
        s.time = 3.0;
        let b = cache.frame_scene(&s).unwrap();
        assert_eq!(b.lights[2].color(), Vec3::X);
        assert_ne!(a.lights[2].position(), b.lights[2].position());
    }
}
