//! Settings files: what `lampshade render --settings FILE` reads and the viewer's F12 writes
//! beside its screenshot. A JSON object holding the renderer's [`Settings`] fields (flattened)
//! plus the scene keys `scene`, `lights`, `time`, `camera` and `size`, and the viewer's own
//! `viewer` state (which `render` does not use). The renderer's fields may also sit in a nested
//! `"renderer": {...}` object. Any other key is an error that names it: a misspelt knob is
//! never ignored silently.
//!
//! The text comes from the user, so [`parse`] never panics: any input gives the settings or an
//! error that says what is wrong (fuzzed by `fuzz/fuzz_targets/settings_file.rs`).

use crate::renderer::presets::Preset;
use crate::renderer::Settings;
use crate::scene::Camera;
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

/// Largest image side a settings file may ask for (as `lampshade render --size`).
pub const MAX_SIZE: u32 = 8192;

/// What a settings file may carry beside the renderer's [`Settings`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneKeys {
    /// Built-in scene name or glTF file.
    pub scene: Option<String>,
    /// Light count (the demo scene).
    pub lights: Option<usize>,
    /// Animation time in seconds.
    pub time: Option<f64>,
    pub camera: Option<Camera>,
    /// Image size, `[width, height]`.
    pub size: Option<[u32; 2]>,
    /// Seed 004's cookies by light index: a built-in name (`window`, `flashlight`), a PNG path
    /// (relative to the working directory), or null for none: `{"0": "window"}`.
    #[serde(default)]
    pub light_cookies: Option<std::collections::BTreeMap<usize, Option<String>>>,
    /// Seed 004's culling masks by light index (bit k = lights layer k): `{"1": 3}`.
    #[serde(default)]
    pub light_masks: Option<std::collections::BTreeMap<usize, u32>>,
    /// Culling layers (0..=31) by object index: `{"4": 1}`.
    #[serde(default)]
    pub object_layers: Option<std::collections::BTreeMap<usize, u8>>,
    /// Each light's own shadow flag by light index (`--shadows` decides which kinds
    /// cast; false keeps a light from casting): `{"0": false}`.
    #[serde(default)]
    pub light_shadows: Option<std::collections::BTreeMap<usize, bool>>,
}

impl SceneKeys {
    /// Applies the per-light cookies, masks and shadow flags and the per-object layers to
    /// `scene`. Errors name the key, the index and the problem (a missing or bad cookie file
    /// among them).
    pub fn apply_to(&self, scene: &mut crate::scene::Scene) -> Result<()> {
        for (&i, cookie) in self.light_cookies.iter().flatten() {
            scene.set_light_cookie(i, cookie.as_deref()).map_err(anyhow::Error::msg).context("light_cookies")?;
        }
        for (&i, &mask) in self.light_masks.iter().flatten() {
            let n = scene.lights.len();
            let Some(l) = scene.lights_mut().get_mut(i) else {
                bail!("light_masks: no light {i} (the scene has {n})");
            };
            l.set_mask(mask);
        }
        for (&i, &on) in self.light_shadows.iter().flatten() {
            let n = scene.lights.len();
            let Some(l) = scene.lights_mut().get_mut(i) else {
                bail!("light_shadows: no light {i} (the scene has {n})");
            };
            l.set_cast_shadows(on);
        }
        for (&i, &layer) in self.object_layers.iter().flatten() {
            let n = scene.objects.len();
            let Some(o) = scene.objects.get_mut(i) else {
                bail!("object_layers: no object {i} (the scene has {n})");
            };
            if layer > 31 {
                bail!("object_layers: object {i} on layer {layer}; layers are 0..=31");
            }
            o.layer = layer;
        }
        Ok(())
    }
}

/// The scene keys of two settings files drawn as one scene (`lampshade compare`): each key
/// either file gives, and an error naming any key both give with different values.
pub fn merge_scene_keys(a: &SceneKeys, b: &SceneKeys) -> Result<SceneKeys> {
    let (va, vb) = (serde_json::to_value(a)?, serde_json::to_value(b)?);
    let (Some(ma), Some(mb)) = (va.as_object(), vb.as_object()) else { bail!("scene keys are not an object") };
    let mut merged = ma.clone();
    for (k, v) in mb {
        match ma.get(k) {
            Some(x) if !x.is_null() && !v.is_null() && x != v => {
                bail!("both set \"{k}\", to different values ({x} and {v}); a comparison draws one scene")
            }
            Some(x) if !x.is_null() => {}
            _ => {
                merged.insert(k.clone(), v.clone());
            }
        }
    }
    Ok(serde_json::from_value(serde_json::Value::Object(merged))?)
}

/// The key under which the viewer's F12 stores its own state.
pub const VIEWER_KEY: &str = "viewer";
/// The key of an optional nested object of renderer settings.
pub const RENDERER_KEY: &str = "renderer";
/// The key naming a preset (`renderer::presets`) the file's renderer settings apply on top of.
pub const PRESET_KEY: &str = "preset";

/// The field names of a struct, read from its serialised default (every field is written).
fn field_names<T: Serialize>(value: &T) -> Vec<String> {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::Object(m)) => m.keys().cloned().collect(),
        _ => Vec::new(),
    }
}

/// The renderer settings' keys.
pub fn settings_keys() -> Vec<String> {
    field_names(&Settings::default())
}

/// The scene keys.
pub fn scene_keys() -> Vec<String> {
    field_names(&SceneKeys::default())
}

/// Parses a settings file's text into the renderer settings and the scene keys, and checks
/// them: `Settings::validate`, a finite time, a size within 1x1 ..= [`MAX_SIZE`]² and a valid
/// camera. Errors say which part is wrong.
pub fn parse(text: &str) -> Result<(Settings, SceneKeys)> {
    // serde reads a struct from an array too (its fields in order): `[]` would be the defaults.
    if !text.trim_start().starts_with('{') {
        bail!("a settings file is one JSON object ({{\"culling\": ..., \"scene\": ...}})");
    }
    // The keys first, values skipped (without recursion, so a deeply nested `viewer` value
    // cannot overflow the stack).
    let top: std::collections::BTreeMap<String, serde::de::IgnoredAny> =
        serde_json::from_str(text).context("not a JSON object")?;
    let (renderer, scene) = (settings_keys(), scene_keys());
    for k in top.keys() {
        if !renderer.contains(k) && !scene.contains(k) && k != VIEWER_KEY && k != RENDERER_KEY && k != PRESET_KEY {
            bail!(
                "unknown key \"{k}\": a settings file holds renderer settings ({}), scene keys ({}), \"{PRESET_KEY}\", \"{RENDERER_KEY}\" and \"{VIEWER_KEY}\"",
                renderer.join(", "),
                scene.join(", ")
            );
        }
    }
    let mut settings = serde_json::from_str::<Settings>(text).context("renderer settings")?;
    // `{"preset": "seed000", "culling": "tiled"}`: the preset's settings, the file's renderer
    // keys on top (as `--preset` and later flags).
    if top.contains_key(PRESET_KEY) {
        #[derive(Deserialize)]
        struct Named {
            preset: String,
        }
        let named: Named = serde_json::from_str(text).context("\"preset\" must be a preset's name")?;
        let preset = Preset::parse(&named.preset).map_err(anyhow::Error::msg)?;
        let base = preset.apply(&Settings::default()).map_err(anyhow::Error::msg)?;
        let mut merged = serde_json::to_value(&base).context("renderer settings")?;
        let given: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(text).context("not a JSON object")?;
        if let Some(m) = merged.as_object_mut() {
            m.extend(given.into_iter().filter(|(k, _)| renderer.contains(k)));
        }
        settings = Settings::deserialize(merged).context("renderer settings")?;
    }
    let keys = serde_json::from_str::<SceneKeys>(text).context("scene keys")?;
    // `{"renderer": {"exposure": 3}}` reads as `{"exposure": 3}`.
    if top.contains_key(RENDERER_KEY) {
        #[derive(Deserialize)]
        struct Outer {
            renderer: serde_json::Value,
        }
        let outer: Outer = serde_json::from_str(text).context("\"renderer\"")?;
        let serde_json::Value::Object(nested) = outer.renderer else {
            bail!("\"renderer\" must be an object of renderer settings ({{\"exposure\": 2, ...}})");
        };
        for k in nested.keys() {
            if !renderer.contains(k) {
                bail!("unknown key \"renderer.{k}\": renderer settings are {}", renderer.join(", "));
            }
            if top.contains_key(k) {
                bail!("\"{k}\" is given both at the top level and in \"renderer\"");
            }
        }
        let mut merged = serde_json::to_value(&settings).context("renderer settings")?;
        if let Some(m) = merged.as_object_mut() {
            m.extend(nested);
        }
        settings = Settings::deserialize(merged).context("renderer settings")?;
    }
    settings.validate().map_err(anyhow::Error::msg).context("renderer settings")?;
    if let Some(t) = keys.time {
        if !t.is_finite() {
            bail!("time {t} must be finite");
        }
    }
    if let Some([w, h]) = keys.size {
        if w == 0 || h == 0 || w > MAX_SIZE || h > MAX_SIZE {
            bail!("size {w}x{h} must be between 1x1 and {MAX_SIZE}x{MAX_SIZE}");
        }
    }
    if let Some(camera) = &keys.camera {
        camera.validate().map_err(|e| anyhow::anyhow!("camera: {e}"))?;
    }
    Ok((settings, keys))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_preset_key_applies_first_and_the_files_keys_on_top() {
        let (s, _) = parse(r#"{"preset": "seed004", "aa": "fxaa", "scene": "demo"}"#).unwrap();
        let seed004 = Preset::Seed004.apply(&Settings::default()).unwrap();
        assert_eq!(s, Settings { aa: crate::renderer::settings::Aa::Fxaa, ..seed004 });
        assert_eq!(s.get("preset").unwrap(), "custom");
        let (s, _) = parse(r#"{"preset": "seed000", "renderer": {"exposure": 2}}"#).unwrap();
        assert_eq!((s.get("preset").unwrap().as_str(), s.exposure), ("seed000", 2.0));
        let e = format!("{:#}", parse(r#"{"preset": "seed9"}"#).unwrap_err());
        assert!(e.contains("unknown preset 'seed9'") && e.contains("seed004"), "{e}");
        assert!(parse(r#"{"preset": 3}"#).is_err());
    }

    #[test]
    fn a_viewer_file_round_trips() {
        let keys = SceneKeys {
            scene: Some("demo".into()),
            lights: Some(64),
            time: Some(1.5),
            // Values JSON holds exactly: serde_json (without its `float_roundtrip` feature) may
            // read some f64s back one ulp off, e.g. the pitch of `Camera::looking_at`.
            camera: Some(Camera {
                position: glam::DVec3::new(0.0, 2.0, 8.0),
                yaw: 0.5,
                pitch: -0.25,
                fov_y: 1.0,
                near: 0.1,
                far: 400.0,
            }),
            size: Some([640, 360]),
            ..Default::default()
        };
        let settings = Settings { exposure: 1.5, ..Settings::default() };
        let mut doc = serde_json::to_value(&settings).unwrap();
        let extra = serde_json::to_value(&keys).unwrap();
        doc.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        doc["viewer"] = serde_json::json!({ "anything": [1, 2, 3] });
        let (s, k) = parse(&doc.to_string()).unwrap();
        assert_eq!((s, k), (settings, keys));
        assert_eq!(parse("{}").unwrap(), (Settings::default(), SceneKeys::default()));
    }

    #[test]
    fn a_nested_renderer_object_is_read_like_top_level_keys() {
        let (s, _) = parse(r#"{"renderer": {"exposure": 3, "culling": "volume"}, "scene": "spot"}"#).unwrap();
        assert_eq!(s.exposure, 3.0);
        assert_eq!(s.culling, crate::renderer::CullingMode::Volume);
        // Validated like the rest.
        assert!(parse(r#"{"renderer": {"exposure": -1}}"#).is_err());
    }

    #[test]
    fn every_settings_and_scene_field_is_a_known_key() {
        // The key lists come from the serialised structs: a new field is known at once.
        let s = settings_keys();
        for k in ["culling", "exposure", "light_cutoff", "cone_sides", "selected_light"] {
            assert!(s.contains(&k.to_string()), "{k} missing from {s:?}");
        }
        assert_eq!(
            scene_keys(),
            [
                "camera",
                "light_cookies",
                "light_masks",
                "light_shadows",
                "lights",
                "object_layers",
                "scene",
                "size",
                "time"
            ]
        );
        // Seed 004's keys.
        let (_, k) = parse(
            r#"{"light_cookies": {"0": "window", "1": null}, "light_masks": {"2": 5}, "object_layers": {"3": 1}}"#,
        )
        .unwrap();
        assert_eq!(k.light_masks.unwrap()[&2], 5);
        assert_eq!(k.light_cookies.unwrap()[&1], None);
    }

    #[test]
    fn cookies_masks_and_layers_apply_to_the_scene() {
        let mut scene = crate::scene::builtin::build("spot", Default::default()).unwrap();
        let (_, k) =
            parse(r#"{"light_cookies": {"0": "window"}, "light_masks": {"0": 2}, "object_layers": {"1": 1}}"#).unwrap();
        k.apply_to(&mut scene).unwrap();
        assert_eq!(scene.lights[0].mask(), 2);
        assert_eq!(scene.cookies[scene.lights[0].cookie().unwrap() as usize].name, "window");
        assert_eq!(scene.objects[1].layer, 1);
        // A light's shadow flag, off and back on.
        assert!(scene.lights[0].cast_shadows());
        let (_, k) = parse(r#"{"light_shadows": {"0": false}}"#).unwrap();
        k.apply_to(&mut scene).unwrap();
        assert!(!scene.lights[0].cast_shadows());
        let (_, k) = parse(r#"{"light_shadows": {"0": true}}"#).unwrap();
        k.apply_to(&mut scene).unwrap();
        assert!(scene.lights[0].cast_shadows());
        for (text, needle) in [
            (r#"{"light_cookies": {"0": "nowhere/c.png"}}"#, "nowhere/c.png"),
            (r#"{"light_cookies": {"9": "window"}}"#, "no light 9"),
            (r#"{"light_masks": {"9": 1}}"#, "no light 9"),
            (r#"{"light_shadows": {"9": false}}"#, "no light 9"),
            (r#"{"object_layers": {"1": 40}}"#, "layers are 0..=31"),
            (r#"{"object_layers": {"99": 1}}"#, "no object 99"),
        ] {
            let (_, k) = parse(text).unwrap();
            let e = format!("{:#}", k.apply_to(&mut scene.clone()).unwrap_err());
            assert!(e.contains(needle), "{text}: {e}");
        }
    }

    #[test]
    fn bad_files_are_clear_errors() {
        for (text, needle) in [
            ("", "one JSON object"),
            ("[]", "one JSON object"),
            ("  [1.0]", "one JSON object"),
            (r#"{"culling": "sideways"}"#, "sideways"),
            (r#"{"exposure": 0}"#, "exposure 0"),
            (r#"{"cone_sides": 99}"#, "cone sides 99"),
            (r#"{"size": [0, 10]}"#, "size 0x10"),
            (r#"{"size": [10]}"#, "scene keys"),
            (r#"{"lights": -1}"#, "scene keys"),
            (r#"{"time": 1e400}"#, "out of range"),
            (r#"{"exposur": 2}"#, "unknown key \"exposur\""),
            (r#"{"renderer": {"exposur": 2}}"#, "unknown key \"renderer.exposur\""),
            (r#"{"renderer": 3}"#, "must be an object"),
            (r#"{"renderer": {"exposure": 2}, "exposure": 3}"#, "both at the top level"),
            (
                r#"{"camera": {"position": [0,0,0], "yaw": 0, "pitch": 0, "fov_y": 4, "near": 0.1, "far": 10}}"#,
                "field of view",
            ),
        ] {
            let e = format!("{:#}", parse(text).unwrap_err());
            assert!(e.contains(needle), "{text:?}: {e}");
        }
    }
}
