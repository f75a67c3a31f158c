//! The cost model's constants, as `auto`'s frame rule and the ledger read them: the built-in
//! defaults (measured on idle lavapipe on this project's 2-core machine) or a calibration
//! measured on the adapter that runs (`lampshade calibrate`, `bench::calibrate`; the cache in
//! `crate::calibration`).
//!
//! The renderer holds one ([`Calibration::builtin`] unless it is given another,
//! `Renderer::set_calibration`); the culling plan reads its [`CostConstants`] from `PlanView`.

use serde::{Deserialize, Serialize};

/// The version of the calibration file's format: a file of another version is stale.
pub const CALIBRATION_VERSION: u32 = 1;

/// The costs of one list mode (`clustered`, `tiled`, `zbin`): its full-screen passes with
/// empty lists (per megapixel), a listed light-pixel pair, and how many pairs its lists hold
/// per pixel of the lights' volumes' screen footprint.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListCost {
    pub fixed_ms_per_mpx: f64,
    pub pair_ns: f64,
    pub pairs_per_footprint: f64,
}

/// What `auto`'s frame rule weighs (`culling::tiled::frame_costs`): the per-light plan (a draw,
/// a fragment of a drawn light's footprint) against each list mode it may choose. A list mode
/// without costs is not weighed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostConstants {
    /// One light draw of the per-light plan (ms).
    pub draw_ms: f64,
    /// One fragment of a drawn light's screen footprint (ns).
    pub fragment_ns: f64,
    pub clustered: ListCost,
    pub tiled: Option<ListCost>,
    pub zbin: Option<ListCost>,
    /// The fewest lights the constants were measured at: the frame rule weighs the list modes
    /// from there up, and keeps the per-light plan below, where its lines would be extrapolated
    /// (a file without it: the built-in [`BUILTIN_MIN_LIGHTS`]).
    #[serde(default = "builtin_min_lights")]
    pub min_lights: usize,
}

/// The built-in constants' fewest lights: they were measured at 1,024 lights and more, and with
/// fewer than this many the per-light plan's draws cost little.
pub const BUILTIN_MIN_LIGHTS: usize = 256;

fn builtin_min_lights() -> usize {
    BUILTIN_MIN_LIGHTS
}

/// From the full bench (idle lavapipe, 2 cores): a light draw about 30 µs, a shaded
/// fragment 17 ns, a full-screen pass at 1280x720 about 15 ms (the clustered shading pass with
/// empty lists is one).
pub const BUILTIN_DRAW_MS: f64 = 0.030;
pub const BUILTIN_FRAGMENT_NS: f64 = 17.0;
/// From `lampshade bench demo --only culling --frames 10` (1280x720, 1,028 lights; one run on
/// a loaded machine where fullscreen took 6.5x its idle time, so scaled by 1/6.5): clustered's
/// lighting 564.6 ms = ambient + its full-screen pass (about 2 x 15 x 6.5 ms) + 4.59 M
/// light-pixel pairs, so about 80 ns a pair there and 12 ns idle. In that run `tiled` (1,160 ms)
/// lost to two-pass (767 ms): its compute pass costs more than the CPU's cluster assignment, so
/// the built-in rule weighs `clustered` alone. Since the slices were fitted to the lights'
/// depths (64 of them) the lists hold 0.31 pairs per pixel of coverage; the idle bench after
/// that change (clustered lighting 47.3 ms) agrees with these constants' estimate
/// (14.7 + 8.37 M x 0.31 x 12 ns = 45.8 ms).
pub const BUILTIN_CLUSTERED_FIXED_MS_PER_MPX: f64 = 16.0;
pub const BUILTIN_PAIR_NS: f64 = 12.0;
pub const BUILTIN_PAIR_PER_FOOTPRINT: f64 = 0.31;

impl CostConstants {
    /// The built-in constants: `clustered` against the per-light plan, `tiled` and `zbin` not
    /// weighed.
    pub const BUILTIN: CostConstants = CostConstants {
        draw_ms: BUILTIN_DRAW_MS,
        fragment_ns: BUILTIN_FRAGMENT_NS,
        clustered: ListCost {
            fixed_ms_per_mpx: BUILTIN_CLUSTERED_FIXED_MS_PER_MPX,
            pair_ns: BUILTIN_PAIR_NS,
            pairs_per_footprint: BUILTIN_PAIR_PER_FOOTPRINT,
        },
        tiled: None,
        zbin: None,
        min_lights: BUILTIN_MIN_LIGHTS,
    };

    /// Every value finite and at zero or above.
    pub fn validate(&self) -> Result<(), String> {
        let mut values = vec![("draw_ms", self.draw_ms), ("fragment_ns", self.fragment_ns)];
        for (name, l) in [("clustered", Some(self.clustered)), ("tiled", self.tiled), ("zbin", self.zbin)] {
            if let Some(l) = l {
                values.push((name, l.fixed_ms_per_mpx));
                values.push((name, l.pair_ns));
                values.push((name, l.pairs_per_footprint));
            }
        }
        match values.iter().find(|(_, v)| !v.is_finite() || *v < 0.0) {
            Some((name, v)) => Err(format!("{name}: {v} is not a finite cost at zero or above")),
            None => Ok(()),
        }
    }
}

impl Default for CostConstants {
    fn default() -> Self {
        Self::BUILTIN
    }
}

/// The constants and where they were measured: the adapter's key (empty for the built-in
/// defaults), when, and how.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    pub version: u32,
    /// The adapter it was measured on (`crate::calibration::key`); empty for the defaults.
    pub key: String,
    /// The UTC date it was measured (`YYYY-MM-DD`); empty for the defaults.
    pub measured: String,
    /// The command and frames it was measured with.
    pub how: String,
    pub costs: CostConstants,
}

impl Calibration {
    /// The built-in defaults.
    pub fn builtin() -> Self {
        Self {
            version: CALIBRATION_VERSION,
            key: String::new(),
            measured: String::new(),
            how: String::new(),
            costs: CostConstants::BUILTIN,
        }
    }

    pub fn is_builtin(&self) -> bool {
        self.key.is_empty()
    }

    /// What the stats say of it: "built-in defaults" or "<key>, measured <date>".
    pub fn describe(&self) -> String {
        if self.is_builtin() {
            "built-in defaults".into()
        } else {
            format!("{}, measured {}", self.key, self.measured)
        }
    }
}

impl Default for Calibration {
    fn default() -> Self {
        Self::builtin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_constants_auto_was_fitted_with() {
        // The values the frame rule decided with before calibrations existed: a calibration
        // never given leaves every choice as it was.
        let b = Calibration::default();
        assert!(b.is_builtin());
        assert_eq!(b.describe(), "built-in defaults");
        let c = b.costs;
        assert_eq!(c.draw_ms, 0.030);
        assert_eq!(c.fragment_ns, 17.0);
        assert_eq!(c.clustered, ListCost { fixed_ms_per_mpx: 16.0, pair_ns: 12.0, pairs_per_footprint: 0.31 });
        assert_eq!((c.tiled, c.zbin), (None, None));
        assert_eq!(c.validate(), Ok(()));
        // A file written before the fewest-lights field reads with the built-in count.
        let mut v = serde_json::to_value(c).unwrap();
        v.as_object_mut().unwrap().remove("min_lights");
        let old: CostConstants = serde_json::from_value(v).unwrap();
        assert_eq!(old.min_lights, BUILTIN_MIN_LIGHTS);
        assert!(CostConstants { draw_ms: f64::NAN, ..c }.validate().is_err());
    }
}
