//! What the user chooses per frame: culling mode, G-buffer layout, debug view, counters.
//! Plain serde data, apart from GPU objects, so the viewer can persist it and
//! `lampshade render --settings FILE` can reproduce a screenshot.

use serde::{Deserialize, Serialize};

use super::options::{by_technique, settings_fields};

pub use super::options::caps::CapOrder;
pub use super::options::culling::{
    cutoff_radius, ClusterBuilder, CullingMode, ForwardLights, NearLights, CONE_SIDES_RANGE, DEFAULT_CONE_SIDES,
    DEFAULT_SPHERE_SUBDIVISIONS, MAX_LIGHTS_EVERY_MODE, MAX_SPHERE_SUBDIVISIONS,
};
pub use super::options::post::{Aa, Focus, Tonemap};
pub use super::options::shadows::{ShadowCube, ShadowFilter, ShadowFormat, ShadowMode};
pub use super::options::*;

/// Declares `Settings` and its `Default` from the fields of [`settings_fields`].
macro_rules! settings_struct {
    ($($(#[$m:meta])* [$technique:ident] $f:ident: $t:ty = $d:expr,)*) => {
        /// Every knob's value, by the knob's name: the one flat struct the CLI, settings files,
        /// scripts and the viewer name options by.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(default)]
        pub struct Settings {
            $($(#[$m])* pub $f: $t,)*
        }

        impl Default for Settings {
            fn default() -> Self {
                Self { $($f: $d,)* }
            }
        }
    };
}

settings_fields!(settings_struct);

impl Settings {
    /// Checks every knob against its row of the table ([`super::knobs::KNOBS`]): one place for
    /// the ranges that the CLI, settings files, scripts and the viewer's sliders share.
    pub fn validate(&self) -> Result<(), String> {
        super::knobs::KNOBS.iter().try_for_each(|k| k.check(self))?;
        if self.msaa != Msaa::X1 && !self.path.can_multisample() {
            return Err(format!(
                "the {} path cannot multisample (seed 002: \"Deferred shading is incompatible with MSAA\" … \
                 \"G-Buffer cannot be resolved\"); use --msaa 1 with --aa edge (seed 002's \"Intelligent Blur\") \
                 or fxaa, or the light-prepass or forward paths",
                self.path.name()
            ));
        }
        if self.msaa != Msaa::X1 && self.blended == BlendedMode::Peeled {
            return Err("depth peeling peels single-sampled depth; use --msaa 1 or another --blended mode".into());
        }
        if self.ris_samples > 0 && !(self.culling.can_list() && self.path.keeps_gbuffer()) {
            return Err(format!(
                "RIS (ris-samples {}) draws its samples from the light lists of a G-buffer path: use culling tiled, clustered, zbin or auto on the deferred or light pre-pass path, or ris-samples 0 (culling {}, path {})",
                self.ris_samples,
                self.culling.name(),
                self.path.name()
            ));
        }
        self.stochastic_options().validate()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_files_without_the_new_knobs_still_load() {
        // A settings file as the viewer wrote it before depth format, cut-off and tessellation.
        let old = r#"{"culling":"stencil-two-pass","layout":"compact","debug_view":"lit","selected_light":null,
            "reversed_z":true,"exposure":1.5,"count_fragments":true,"count_ideal":false,"timestamps":true,
            "accumulation":"rgba16-float","depth_clamp":true}"#;
        let s: Settings = serde_json::from_str(old).unwrap();
        assert_eq!(s.culling, CullingMode::StencilTwoPass);
        assert!(s.reversed_z);
        assert_eq!(s.depth_format, DepthFormat::Depth32FloatStencil8);
        assert_eq!((s.light_cutoff, s.sphere_subdivisions, s.cone_sides), (0.0, 1, 12));
        assert_eq!((s.path, s.msaa), (RenderPath::Deferred, Msaa::X1));
        s.validate().unwrap();
        // And the new ones round-trip.
        let new = Settings {
            accumulation: AccumFormat::Rgba8Log,
            depth_format: DepthFormat::Depth24PlusStencil8,
            light_cutoff: 1.0 / 64.0,
            sphere_subdivisions: 3,
            cone_sides: 24,
            ..Settings::default()
        };
        let text = serde_json::to_string(&new).unwrap();
        assert!(text.contains("\"rgba8-log\"") && text.contains("\"depth24-plus-stencil8\""), "{text}");
        assert_eq!(serde_json::from_str::<Settings>(&text).unwrap(), new);
    }

    /// The serde name (settings files) and the clap name (CLI, scripts, viewer, bench) of every
    /// knob value are the same string, and `parse` takes it back.
    fn one_name<T: clap::ValueEnum + Serialize + PartialEq + std::fmt::Debug>() {
        for v in T::value_variants() {
            let serde_name = serde_json::to_value(v).unwrap();
            assert_eq!(serde_name.as_str(), Some(name_of(v).as_str()), "{v:?}");
            assert_eq!(parse_name::<T>("knob", &name_of(v)).as_ref(), Ok(v));
        }
    }

    #[test]
    fn every_knob_value_has_one_name() {
        one_name::<CullingMode>();
        one_name::<DebugView>();
        one_name::<AccumFormat>();
        one_name::<DepthFormat>();
        one_name::<LayoutChoice>();
        one_name::<ForwardLights>();
        one_name::<BrdfOverride>();
        one_name::<crate::scene::Brdf>();
        one_name::<Tonemap>();
        one_name::<Aa>();
        one_name::<RenderPath>();
        one_name::<Msaa>();
        one_name::<ClusterBuilder>();
        for l in LayoutChoice::ALL.into_iter().filter(|l| *l != LayoutChoice::Fit) {
            assert_eq!(l.layout().name, l.name(), "the layout table's name");
        }
        for m in CullingMode::ALL {
            if let Some(method) = m.method() {
                assert_eq!(serde_json::to_value(method).unwrap().as_str(), Some(m.name().as_str()));
                assert_eq!(method.name(), m.name());
            }
        }
        // The old short names still load.
        assert_eq!(DepthFormat::parse("d24s8"), Ok(DepthFormat::Depth24PlusStencil8));
        assert_eq!(serde_json::from_str::<DepthFormat>("\"d32s8\"").unwrap(), DepthFormat::Depth32FloatStencil8);
        assert!(CullingMode::parse("stencil").unwrap_err().contains("one of fullscreen, volume, stencil-two-pass"));
    }

    #[test]
    fn bad_knob_values_are_clear_errors() {
        let bad = |s: Settings| s.validate().unwrap_err();
        for t in [1.0, -0.1, f32::NAN, f32::INFINITY] {
            assert!(bad(Settings { light_cutoff: t, ..Settings::default() }).contains("cut-off"), "{t}");
        }
        assert!(bad(Settings { sphere_subdivisions: 5, ..Settings::default() }).contains("sphere subdivisions 5"));
        assert!(bad(Settings { cone_sides: 2, ..Settings::default() }).contains("cone sides 2"));
        assert!(bad(Settings { cone_sides: 65, ..Settings::default() }).contains("between 3 and 64"));
        assert!(serde_json::from_str::<Settings>(r#"{"depth_format":"depth16"}"#).is_err());
        assert!(serde_json::from_str::<Settings>(r#"{"accumulation":"rgba8"}"#).is_err());
        let e = bad(Settings { msaa: Msaa::X4, ..Settings::default() });
        assert!(e.contains("deferred path cannot multisample"), "{e}");
        Settings { msaa: Msaa::X4, path: RenderPath::Forward, ..Settings::default() }.validate().unwrap();
    }

    /// The focus is `auto` or a distance in every way a user writes it: the knob (CLI, scripts),
    /// settings files (a number, as files wrote it when the knob was one, or `"auto"`), and
    /// both round-trip; a bad one is an error that says what the knob takes.
    #[test]
    fn the_focus_is_auto_or_a_distance_and_old_numeric_files_still_load() {
        let d = Settings::default();
        assert_eq!(d.focus_distance, Focus::Auto);
        assert_eq!(d.get("focus-distance").unwrap(), "auto");
        let mut s = d.clone();
        s.set("focus-distance", "12.5").unwrap();
        assert_eq!(s.focus_distance, Focus::Distance(12.5));
        s.set("focus-distance", "auto").unwrap();
        assert_eq!(s.focus_distance, Focus::Auto);
        for bad in ["0", "-3", "nonsense", "inf", "1e8"] {
            let e = s.set("focus-distance", bad).unwrap_err();
            assert!(e.contains("focus") || e.contains("auto or"), "{bad}: {e}");
            assert_eq!(s.focus_distance, Focus::Auto, "{bad} changed the setting");
        }
        let old: Settings = serde_json::from_str(r#"{"dof":true,"focus_distance":8}"#).unwrap();
        assert_eq!(old.focus_distance, Focus::Distance(8.0));
        let named: Settings = serde_json::from_str(r#"{"focus_distance":"auto"}"#).unwrap();
        assert_eq!(named.focus_distance, Focus::Auto);
        assert!(serde_json::from_str::<Settings>(r#"{"focus_distance":"near"}"#).is_err());
        let bad = Settings { focus_distance: Focus::Distance(-1.0), ..Settings::default() };
        assert!(bad.validate().unwrap_err().contains("focus distance -1"));
        for f in [Focus::Auto, Focus::Distance(3.25)] {
            let s = Settings { focus_distance: f, ..Settings::default() };
            let text = serde_json::to_string(&s).unwrap();
            assert_eq!(serde_json::from_str::<Settings>(&text).unwrap(), s, "{text}");
        }
    }

    #[test]
    fn the_cutoff_radius_is_where_the_attenuation_reaches_the_threshold() {
        let attenuation = |d: f32, r: f32| (1.0 - (d / r).powi(2)).clamp(0.0, 1.0).powi(2);
        assert_eq!(cutoff_radius(10.0, 0.0), 10.0);
        for t in [1.0 / 256.0, 1.0 / 64.0, 1.0 / 16.0, 0.5] {
            let r = cutoff_radius(10.0, t);
            assert!(r < 10.0);
            assert!((attenuation(r, 10.0) - t).abs() < 1e-5, "{t}: attenuation {} at {r}", attenuation(r, 10.0));
        }
        assert!((cutoff_radius(1.0, 1.0 / 16.0) - 0.75f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn the_log_encoding_decodes_what_it_stores() {
        // Light L is stored as the 8-bit code nearest 255 * 2^-L; decoding is within the stated
        // bound for one write, and saturation decodes to the finite top of the range.
        for k in 0..=800 {
            let light = k as f32 / 100.0;
            let code = (255.0 * (-light).exp2()).round() / 255.0;
            let back = log_accum_decode(code);
            if light < LOG_ACCUM_MAX - 1.0 {
                let err = (back - light).abs();
                assert!(err <= log_accum_error_bound(light, 1), "{light}: decoded {back}");
            }
            assert!(back.is_finite() && back <= LOG_ACCUM_MAX);
        }
        assert_eq!(log_accum_decode(0.0), LOG_ACCUM_MAX);
        assert_eq!(log_accum_decode(1.0), 0.0);
    }
}

/// Builds each technique's options type from `Settings`, a field for a field, from the lists of
/// [`by_technique`].
macro_rules! options_from_settings {
    ($($technique:ident { $($(#[$m:meta])* $f:ident: $t:ty,)* })*) => {
        $(options_from_settings!(@one $technique { $($f)* });)*
    };
    (@one frame $fields:tt) => { options_from_settings!(@from FrameOptions $fields); };
    (@one culling $fields:tt) => { options_from_settings!(@from culling::CullingOptions $fields); };
    (@one caps $fields:tt) => { options_from_settings!(@from caps::CapsOptions $fields); };
    (@one shadows $fields:tt) => { options_from_settings!(@from shadows::ShadowOptions $fields); };
    (@one post $fields:tt) => { options_from_settings!(@from post::PostOptions $fields); };
    (@one surfaces $fields:tt) => { options_from_settings!(@from surfaces::SurfaceOptions $fields); };
    (@one stochastic $fields:tt) => { options_from_settings!(@from StochasticOptions $fields); };
    (@from $($ty:ident)::+ { $($f:ident)* }) => {
        impl From<&Settings> for super::options::$($ty)::+ {
            fn from(s: &Settings) -> Self {
                Self { $($f: s.$f.clone(),)* }
            }
        }
    };
}

settings_fields!(by_technique @sort options_from_settings {} {} {} {} {} {} {});

/// Each technique's options, built from the flat `Settings` in this one place: a technique
/// reads its own (and the frame's), never `Settings`.
impl Settings {
    pub fn frame_options(&self) -> super::options::FrameOptions {
        self.into()
    }

    pub fn culling_options(&self) -> super::options::culling::CullingOptions {
        self.into()
    }

    pub fn caps_options(&self) -> super::options::caps::CapsOptions {
        self.into()
    }

    pub fn shadow_options(&self) -> super::options::shadows::ShadowOptions {
        self.into()
    }

    pub fn post_options(&self) -> super::options::post::PostOptions {
        self.into()
    }

    pub fn surfaces_options(&self) -> super::options::surfaces::SurfaceOptions {
        self.into()
    }

    /// These settings with every stochastic estimator off (RIS, its reuse and denoiser,
    /// stochastic culling, the planted bias): the exact frame they are held to.
    pub fn made_exact(&self) -> Settings {
        Settings {
            ris_samples: 0,
            ris_spatial: 0,
            ris_temporal: false,
            ris_denoise: false,
            stochastic_culling: false,
            planted_bias: 1.0,
            ..self.clone()
        }
    }

    pub fn stochastic_options(&self) -> super::options::StochasticOptions {
        self.into()
    }

    /// Every technique's options.
    pub fn options(&self) -> super::options::Options {
        super::options::Options {
            frame: self.frame_options(),
            culling: self.culling_options(),
            caps: self.caps_options(),
            shadows: self.shadow_options(),
            post: self.post_options(),
            surfaces: self.surfaces_options(),
            stochastic: self.stochastic_options(),
        }
    }
}
