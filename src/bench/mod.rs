//! Speed against error: `lampshade bench` renders one scene under many configurations, times
//! each pass (median of N frames, GPU timestamps), counts fragments, and measures the error of
//! each image against a reference rendered without deferred approximations (every light
//! full-screen, an Rgba32Float G-buffer with stored position, Rgba32Float accumulation, blended
//! surfaces composited in depth order per pixel by 16 layers of depth peeling).
//! Output: `bench.csv`, `bench.md` and `bench.png` (time against error, Pareto front marked).
//!
//! - [`options`]: the bench's options and a configuration;
//! - [`groups`]: each group's configurations, a table per group;
//! - [`configs`]: the sweep, every group's table in order, and its calibration rows;
//! - [`run`]: rendering them, with the reference each is measured against;
//! - [`report`]: the CSV and markdown tables, the limits and the Pareto front;
//! - [`plot`]: the charts.

pub mod advise;
pub mod calibrate;
mod configs;
mod gbuffer_split;
mod groups;
mod ledger;
mod options;
mod pair;
mod path;
mod plot;
mod report;
mod restir;
mod run;
mod stochastic;

pub use configs::*;
pub use gbuffer_split::{split_markdown, SplitRow, GBUFFER_GROUP};
pub use groups::*;
pub use ledger::*;
pub use options::*;
pub use pair::*;
pub use path::*;
pub use plot::*;
pub use report::*;
pub use restir::{
    plot_restir, read_restir_json, restir_configs, restir_layouts, restir_markdown, run_restir, wall as restir_wall,
    RestirRow, RESTIR_GROUP,
};
pub use run::*;
pub use stochastic::{lighting_ms, lights_per_pixel, plot_stochastic, stochastic_markdown, FLIP_TARGET};

use crate::compare::flip;
use crate::gpu::Gpu;
use crate::headless::render_image;
use crate::renderer::{
    AccumFormat, CullingMode, FrameStats, LayoutChoice, RenderPath, Renderer, Settings, ShadowFilter, ShadowMode,
    OUTPUT_FORMAT,
};
use crate::scene::builtin::BuiltinOptions;
use anyhow::{Context, Result};
use serde::Serialize;
use std::collections::HashMap;
use std::path::Path;

/// A configuration the bench did not run, and why: the scene cannot take it (a G-buffer layout
/// with no channel for the material ID a multi-material scene needs, say) or the adapter cannot
/// give it. It is listed in the report and on the console; the sweep goes on without it.
#[derive(Clone, Debug, Serialize)]
pub struct Skipped {
    pub group: String,
    pub label: String,
    pub scene: String,
    pub reason: String,
}

/// What a sweep gives: a row per configuration that ran, and the configurations it skipped.
#[derive(Clone, Debug, Default)]
pub struct BenchRun {
    pub rows: Vec<Row>,
    pub skipped: Vec<Skipped>,
    /// The `ledger` group: the per-light cost model checked per mode.
    pub ledger: Vec<LedgerRow>,
    /// The `gbuffer` group: the G-buffer span split into what a frame pays before it draws.
    pub gbuffer_split: Vec<SplitRow>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub group: String,
    pub label: String,
    pub scene: String,
    pub culling: String,
    pub layout: String,
    pub accumulation: String,
    pub reversed_z: bool,
    /// The depth-stencil format the frame used (the adapter's fallback shows here).
    pub depth_format: String,
    pub light_cutoff: f32,
    pub sphere_subdivisions: u32,
    pub cone_sides: u32,
    /// Bounding meshes the frame drew, e.g. "sphere+cone".
    pub volumes: String,
    pub lights: usize,
    /// The scene's light radii were scaled by this (the `radius` group; 1 elsewhere).
    pub radius_scale: f64,
    pub width: u32,
    pub height: u32,
    pub gbuffer_ms: f64,
    pub lighting_ms: f64,
    pub compose_ms: f64,
    /// The forward pass of blended surfaces (0 without any).
    pub forward_ms: f64,
    /// The post chain's passes (0 where a pass did not run).
    pub bloom_ms: f64,
    pub exposure_ms: f64,
    pub tonemap_ms: f64,
    /// Each effect after tone mapping, in `post::effects::EFFECTS`' order (0 where it did not
    /// run; the CSV's `NAME_ms` columns).
    pub effects_ms: Vec<f64>,
    pub total_ms: f64,
    /// The standard error of `total_ms`'s timed frames (their spread / √n).
    pub total_se_ms: f64,
    /// `auto`'s rows of the `culling` and `lights` groups: its regret against the best mode
    /// at the same point ([`report::add_regret`]); blank elsewhere.
    pub regret: Regret,
    /// `auto`'s rows: the list mode it shaded the frame with, or `per-light` (its per-light
    /// plan); empty elsewhere.
    pub auto_chose: String,
    /// Light draws of a timed (uncounted) frame, and the batches they draw.
    pub draw_calls: u64,
    pub light_batches: u64,
    pub coverage_fragments: u64,
    pub shaded_fragments: u64,
    pub ideal_fragments: u64,
    pub efficiency: f64,
    pub gbuffer_bytes_per_pixel: u32,
    pub flip_mean: f32,
    pub max_abs_light_error: f32,
    pub psnr_db: f64,
    pub pareto: bool,
    /// The culling mode of the reference this row's error is measured against: `fullscreen`,
    /// or `volume` where a full-screen reference would take minutes (see [`reference_culling`]).
    pub reference: String,
    /// `total_ms` over the same run's `limit` row for this scene, light count, size and radius
    /// (NaN where the group has none; 1 on the `limit` row itself).
    pub limit_ratio: f64,
    /// Median GPU ms of building the light lists or masks on the GPU (tiled, GPU-built
    /// clustered, zbin; NaN where the frame built none on the GPU). Part of `lighting_ms`.
    pub lists_ms: f64,
    /// Units that survive a change of hardware (see [`add_units`]).
    pub units: Units,
    /// The rendering path's figures (the `path` group; defaults elsewhere).
    pub path: PathFigures,
    /// The shadow maps' figures (every row, NaN/0 without shadows).
    pub shadow: ShadowFigures,
    /// What the engine-style caps dropped and what that cost in light (the `engines` group;
    /// empty elsewhere).
    pub caps: CapFigures,
    /// The ledger: the frame's ten costliest lights (index, ms) by the cost model its counted
    /// frame used (`cost_source`), costliest first; empty where the frame has no per-light
    /// costs (the forward paths).
    #[serde(skip)]
    pub costliest: Vec<(usize, f64)>,
    #[serde(skip)]
    pub cost_source: String,
}

/// `auto`'s regret at one point (scene, light count, size): the measured total time of the
/// configuration it chose over the best candidate's, the fastest other culling mode at that
/// point. Where it chose a list mode, the configuration chosen is that mode's own row (the same
/// frame; `auto`'s own row is timed beside it); where it kept its per-light plan, `auto`'s
/// row. Met where the chosen is the best or the two differ by less than two combined standard
/// errors (√(se_chosen² + se_best²)), so that noise alone does not count against the choice.
#[derive(Clone, Debug, Serialize)]
pub struct Regret {
    /// The configuration chosen: a list mode's name, or `auto` (its per-light plan).
    pub chosen: String,
    pub chosen_ms: f64,
    pub chosen_se_ms: f64,
    pub best: String,
    pub best_ms: f64,
    pub best_se_ms: f64,
    pub ratio: f64,
    pub met: Option<bool>,
}

impl Default for Regret {
    fn default() -> Self {
        Self {
            chosen: String::new(),
            chosen_ms: f64::NAN,
            chosen_se_ms: f64::NAN,
            best: String::new(),
            best_ms: f64::NAN,
            best_se_ms: f64::NAN,
            ratio: f64::NAN,
            met: None,
        }
    }
}

/// A row's figures in units that survive a change of hardware (NaN where the row lacks what a
/// unit divides by). Pairs are light–pixel pairs: `shaded_fragments` are the pairs a mode
/// evaluated (its stencil-passed fragments, or its list entries walked per pixel), and
/// `ideal_fragments` the pairs inside the lights' true shapes.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Units {
    /// Lighting ns per evaluated pair.
    pub ns_per_pair: f64,
    /// Lighting ns per ideal pair.
    pub ns_per_ideal: f64,
    /// ρ_fs: lighting time over the same run's calibration pass at the same scene and size
    /// (one light over every pixel of the G-buffer, [`CALIBRATION`]).
    pub rho_fs: f64,
    /// The G-buffer pass and the compose in calibration passes.
    pub gbuffer_fs: f64,
    pub compose_fs: f64,
    /// List building or marking over lighting (`lists_ms / lighting_ms`; NaN where the frame
    /// built no lists on the GPU: the drawn modes mark in the same draws they shade with).
    pub culling_share: f64,
}

impl Default for Units {
    fn default() -> Self {
        Self {
            ns_per_pair: f64::NAN,
            ns_per_ideal: f64::NAN,
            rho_fs: f64::NAN,
            gbuffer_fs: f64::NAN,
            compose_fs: f64::NAN,
            culling_share: f64::NAN,
        }
    }
}

/// What the `shadows` group compares: the shadow pass's cost and memory. Its time
/// is part of `total_ms` (the G-buffer to the compose, plus the shadow pass before them).
#[derive(Clone, Debug, Serialize)]
pub struct ShadowFigures {
    /// Median GPU ms of the shadow pass (the atlas's render pass and the cube array's layers;
    /// NaN when nothing cast).
    pub gpu_ms: f64,
    /// Bytes of the atlas, the cube array and the indirection cube as allocated.
    pub bytes: u64,
    /// Lights (the sun counted) with shadows, and those that fell back for the budget.
    pub casting: u32,
    pub fallback_budget: u32,
    /// Lights that should cast but are off screen (unshadowed, counted).
    pub fallback_off_screen: u32,
    /// `--shadow-cube`, and the cube array's face side or the indirection cube's (0 with
    /// `unrolled`).
    pub cube: String,
    pub cube_side: u32,
}

impl Default for ShadowFigures {
    fn default() -> Self {
        Self {
            gpu_ms: f64::NAN,
            bytes: 0,
            casting: 0,
            fallback_budget: 0,
            fallback_off_screen: 0,
            cube: "-".into(),
            cube_side: 0,
        }
    }
}

impl ShadowFigures {
    fn of(stats: &FrameStats, times: &[FrameStats]) -> Self {
        let Some(sh) = &stats.shadow else { return Self::default() };
        Self {
            gpu_ms: median(times.iter().filter_map(|t| t.shadow.as_ref().and_then(|s| s.gpu_ms)).collect()),
            bytes: sh.bytes(),
            casting: sh.casting,
            fallback_budget: sh.fallback_budget,
            fallback_off_screen: sh.fallback_off_screen,
            cube: sh.cube.name(),
            cube_side: sh.cube_side.max(sh.indirection_side),
        }
    }
}

/// An `engines` row's caps: what they dropped, and what the frame lost against brute force.
#[derive(Clone, Debug, Serialize)]
pub struct CapFigures {
    /// Where the engine's figures come from (`caps::ENGINES`).
    pub source: String,
    /// Lights the camera caps dropped, and list entries the per-cluster and per-object caps
    /// left out.
    pub dropped_lights: u64,
    pub dropped_entries: u64,
    /// Pixels lacking light beyond the accumulation's rounding against brute force over every
    /// light (NaN on the forward paths, which keep no G-buffer for it).
    pub missed_pixels: f64,
    /// Light-pixel pairs the lights the camera caps dropped add, by brute force over them.
    pub dropped_pairs: f64,
    /// Light-pixel pairs the per-cluster cap's dropped entries reach (`oracle::CapLoss`).
    pub entry_pairs: f64,
}

impl Default for CapFigures {
    fn default() -> Self {
        Self {
            source: String::new(),
            dropped_lights: 0,
            dropped_entries: 0,
            missed_pixels: f64::NAN,
            dropped_pairs: f64::NAN,
            entry_pairs: f64::NAN,
        }
    }
}

/// What the `path` group compares between rendering paths.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PathFigures {
    /// `RenderPath::name`.
    pub path: String,
    /// Render passes up to the compose or tonemap (included): deferred's G-buffer, lights,
    /// compose; forward's depth pass, shading (or ambient + sun and the pairs), tonemap.
    pub passes: u32,
    /// Bytes per pixel of every intermediate target, samples included (G-buffer, depth-stencil,
    /// light accumulation or HDR colour, MSAA targets and their resolve).
    pub target_bytes_per_pixel: u32,
    /// Entries of the forward paths' object light lists: the (object, light) pairs the
    /// multi-pass path draws (filled in for every path of the same scene and light count).
    pub object_light_pairs: u64,
    /// Lit pixels: the deferred path's shaded light fragments for the same scene and light
    /// count (filled in for every path).
    pub lit_fragments: u64,
    /// Every draw of the frame up to the compose or tonemap: deferred's object draws into the
    /// G-buffer, its light draws, the compose; the forward paths' draws of every pass and the
    /// tonemap.
    pub draw_calls: u64,
    /// Opaque and masked objects drawn (from the forward rows; filled in for every path).
    pub objects: u64,
    /// Why the path could not render (empty when it did); the row has no figures then.
    pub error: String,
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    #[test]
    fn both_sweeps_cover_every_group_with_valid_settings() {
        for quick in [true, false] {
            let o = BenchOptions::new("demo", quick);
            let list = configs(&o);
            assert!(list.len() >= 8, "{} configurations", list.len());
            for g in GROUPS.iter().filter(|g| **g != STOCHASTIC_GROUP) {
                assert!(list.iter().any(|c| c.group == *g), "quick {quick}: no {g} configuration");
            }
            // The stochastic group's own sweep runs only when named.
            assert!(!list.iter().any(|c| c.group == STOCHASTIC_GROUP), "quick {quick}: stochastic unasked");
            let named = configs(&BenchOptions { groups: vec![STOCHASTIC_GROUP.into()], ..o.clone() });
            assert!(named.iter().any(|c| c.group == STOCHASTIC_GROUP), "quick {quick}: no stochastic configuration");
            for c in list.iter().chain(&named) {
                c.settings.validate().unwrap();
            }
            for l in [&list, &named] {
                let labels: std::collections::HashSet<_> = l.iter().map(|c| (c.group, c.label.clone())).collect();
                assert_eq!(labels.len(), l.len(), "duplicate labels");
            }
        }
        let full = configs(&BenchOptions::new("demo", false));
        let cutoffs: Vec<f32> = full.iter().filter(|c| c.group == "cutoff").map(|c| c.settings.light_cutoff).collect();
        assert_eq!(cutoffs, vec![0.0, 1.0 / 256.0, 1.0 / 64.0, 1.0 / 16.0]);
        let depth = full.iter().filter(|c| c.group == "depth" && c.scene == Some("far-origin")).count();
        assert_eq!(depth, 4, "far-origin under both depth formats and both conventions");
        let mut only = BenchOptions::new("demo", true);
        only.groups = vec!["tessellation".into()];
        let tessellation = configs(&only);
        assert!(tessellation.iter().all(|c| c.group == "tessellation" || c.group == CALIBRATION));
        // One calibration pass at every scene and size the sweep renders, and no other.
        for list in [full, tessellation] {
            let at = |c: &Config| (c.scene, c.size);
            let cal: Vec<_> = list.iter().filter(|c| c.calibration).map(at).collect();
            let mut rendered: Vec<_> = list.iter().filter(|c| !c.calibration).map(at).collect();
            rendered.dedup();
            rendered.sort();
            rendered.dedup();
            let mut sorted = cal.clone();
            sorted.sort();
            assert_eq!(sorted, rendered);
            assert!(list
                .iter()
                .filter(|c| c.calibration)
                .all(|c| c.group == CALIBRATION && c.settings.culling == CullingMode::Fullscreen && c.lights == 1));
        }
    }

    /// A row of scene `s`, 10 lights at 8x8, every figure zero.
    pub(crate) fn blank_row() -> Row {
        Row {
            group: "g".into(),
            label: String::new(),
            scene: "s".into(),
            culling: String::new(),
            layout: String::new(),
            accumulation: String::new(),
            reversed_z: false,
            depth_format: String::new(),
            light_cutoff: 0.0,
            sphere_subdivisions: 1,
            cone_sides: 12,
            volumes: String::new(),
            lights: 10,
            radius_scale: 1.0,
            width: 8,
            height: 8,
            gbuffer_ms: 0.0,
            lighting_ms: 0.0,
            compose_ms: 0.0,
            forward_ms: 0.0,
            bloom_ms: 0.0,
            exposure_ms: 0.0,
            tonemap_ms: 0.0,
            effects_ms: Vec::new(),
            total_ms: 0.0,
            total_se_ms: f64::NAN,
            regret: Default::default(),
            auto_chose: String::new(),
            draw_calls: 0,
            light_batches: 0,
            coverage_fragments: 0,
            shaded_fragments: 0,
            ideal_fragments: 0,
            efficiency: 0.0,
            gbuffer_bytes_per_pixel: 0,
            flip_mean: 0.0,
            max_abs_light_error: 0.0,
            psnr_db: 0.0,
            pareto: false,
            reference: "fullscreen".into(),
            limit_ratio: f64::NAN,
            lists_ms: f64::NAN,
            units: Units::default(),
            path: Default::default(),
            caps: Default::default(),
            shadow: Default::default(),
            costliest: Vec::new(),
            cost_source: String::new(),
        }
    }

    /// `auto`'s regret: against the fastest plain mode at its own point only, met within two
    /// combined standard errors, not against variants or the limit.
    #[test]
    fn autos_regret_is_against_the_fastest_plain_mode_at_its_point_within_two_standard_errors() {
        // The rows' light counts are the scene's four spots over the count the label asks.
        let row = |culling: &str, lights: usize, ms: f64, se: f64| Row {
            group: "lights".into(),
            label: format!("{culling} x{lights}"),
            culling: culling.into(),
            lights: lights + 4,
            total_ms: ms,
            total_se_ms: se,
            ..blank_row()
        };
        let mut rows = vec![
            // 64 lights: auto (its per-light plan) 10 ± 1 against tiled 5 ± 0.1: regret 2, not
            // met.
            Row { auto_chose: "per-light".into(), ..row("auto", 64, 10.0, 1.0) },
            row("clustered", 64, 9.0, 0.5),
            row("tiled", 64, 5.0, 0.1),
            // A variant and the limit, faster still, are not candidates.
            Row { label: "clustered gpu-lists x64".into(), ..row("clustered", 64, 1.0, 0.1) },
            Row { label: "limit".into(), ..row("limit", 64, 0.5, 0.0) },
            // 256 lights: auto chose clustered, 10 ± 1 against zbin's 9 ± 0.5: 1 < 2 x
            // sqrt(1.25), met. Its own row, timed beside, is not what it chose.
            Row { auto_chose: "clustered".into(), ..row("auto", 256, 30.0, 1.0) },
            row("clustered", 256, 10.0, 1.0),
            row("zbin", 256, 9.0, 0.5),
            // The 64 lights' tiled at another size is another point.
            Row { width: 7, ..row("tiled", 256, 1.0, 0.1) },
        ];
        add_regret(&mut rows);
        let r = &rows[0].regret;
        assert_eq!((r.best.as_str(), r.ratio, r.met), ("tiled", 2.0, Some(false)), "{r:?}");
        let r = &rows[5].regret;
        assert_eq!((r.chosen.as_str(), r.best.as_str(), r.met), ("clustered", "zbin", Some(true)), "{r:?}");
        assert!((r.ratio - 10.0 / 9.0).abs() < 1e-12);
        assert!(rows.iter().filter(|r| r.culling != "auto").all(|r| r.regret.ratio.is_nan()));
        let md = regret_markdown(&rows);
        assert!(md.contains("Met at 1 of 2 points"), "{md}");
    }

    #[test]
    fn the_pareto_front_is_per_scene_light_count_and_size() {
        let row = |label: &str, scene: &str, ms: f64, flip: f32| Row {
            label: label.into(),
            scene: scene.into(),
            total_ms: ms,
            flip_mean: flip,
            ..blank_row()
        };
        let mut rows = vec![
            row("fast", "a", 1.0, 0.02),
            row("exact", "a", 5.0, 0.001),
            row("dominated", "a", 6.0, 0.01),
            // Another scene is not compared with scene a.
            row("other", "b", 9.0, 0.5),
        ];
        mark_pareto(&mut rows);
        let front: Vec<&str> = rows.iter().filter(|r| r.pareto).map(|r| r.label.as_str()).collect();
        assert_eq!(front, vec!["fast", "exact", "other"]);
    }

    #[test]
    fn the_limit_row_prices_the_ideal_pairs_at_the_cheapest_pair_any_mode_measured() {
        let row = |label: &str, culling: &str, lights: usize, g: f64, l: f64, c: f64, shaded: u64| Row {
            group: "culling".into(),
            label: label.into(),
            scene: "s".into(),
            culling: culling.into(),
            lights,
            gbuffer_ms: g,
            lighting_ms: l,
            compose_ms: c,
            total_ms: g + l + c,
            shaded_fragments: shaded,
            ideal_fragments: 1000,
            ..blank_row()
        };
        let mut rows = vec![
            // 100 ms for 100,000 pairs: 0.001 ms a pair.
            row("fullscreen", "fullscreen", 10, 10.0, 100.0, 4.0, 100_000),
            row("volume", "volume", 10, 12.0, 9.0, 6.0, 3000),
            // The cheapest pair of the run: 0.8 ms for 1,000 pairs.
            row("clustered", "clustered", 10, 11.0, 0.8, 5.0, 1000),
            // Another light count is priced by the same cheapest pair.
            row("volume", "volume", 40, 11.0, 30.0, 5.0, 9000),
        ];
        // Another scene's cheaper pair is not this scene's price.
        rows.push(Row { scene: "t".into(), ..row("clustered", "clustered", 10, 1.0, 0.001, 1.0, 1000) });
        add_limits(&mut rows);
        let labels: Vec<(&str, usize)> = rows.iter().map(|r| (r.label.as_str(), r.lights)).collect();
        assert_eq!(
            labels,
            vec![
                ("fullscreen", 10),
                ("volume", 10),
                ("clustered", 10),
                ("limit", 10),
                ("volume", 40),
                ("limit", 40),
                ("clustered", 10),
                ("limit", 10)
            ]
        );
        // Medians of G-buffer (11) and compose (5), plus 1,000 ideal pairs at 0.0008 ms.
        let limit = &rows[3];
        assert!((limit.total_ms - (11.0 + 5.0 + 0.8)).abs() < 1e-9, "{}", limit.total_ms);
        assert!((rows[2].limit_ratio - 1.0).abs() < 1e-9, "{}", rows[2].limit_ratio);
        assert!((rows[1].limit_ratio - 27.0 / 16.8).abs() < 1e-9, "{}", rows[1].limit_ratio);
        assert!((rows[5].total_ms - (11.0 + 5.0 + 0.8)).abs() < 1e-9);
        // Without any counted row there is no limit.
        let mut alone = vec![row("volume", "volume", 10, 12.0, 9.0, 6.0, 0)];
        add_limits(&mut alone);
        assert_eq!(alone.len(), 1);
        assert!(alone[0].limit_ratio.is_nan());
        // A shadow pass is a fixed pass like the G-buffer: its median joins the limit.
        let mut shadowed = vec![
            row("fullscreen", "fullscreen", 10, 10.0, 100.0, 4.0, 100_000),
            row("volume", "volume", 10, 12.0, 9.0, 6.0, 3000),
            row("stencil", "stencil-two-pass", 10, 11.0, 5.0, 5.0, 1100),
        ];
        for (r, s) in shadowed.iter_mut().zip([3.0, 2.0, 4.0]) {
            r.shadow.gpu_ms = s;
        }
        add_limits(&mut shadowed);
        assert!((shadowed[3].total_ms - (11.0 + 3.0 + 5.0 + 1.0)).abs() < 1e-9, "{}", shadowed[3].total_ms);
    }

    #[test]
    fn the_units_divide_by_the_pairs_and_the_calibration_of_the_same_scene_and_size() {
        let mut rows = vec![
            Row { group: CALIBRATION.into(), lighting_ms: 2.0, shaded_fragments: 64, ..blank_row() },
            Row {
                group: "culling".into(),
                gbuffer_ms: 8.0,
                lighting_ms: 10.0,
                compose_ms: 1.0,
                lists_ms: 2.5,
                shaded_fragments: 1000,
                ideal_fragments: 500,
                ..blank_row()
            },
            // No calibration at this size: no ρ_fs; no lists: no culling share.
            Row { group: "culling".into(), width: 16, lighting_ms: 10.0, shaded_fragments: 1000, ..blank_row() },
        ];
        add_units(&mut rows);
        let u = rows[1].units;
        assert!((u.ns_per_pair - 10_000.0).abs() < 1e-9 && (u.ns_per_ideal - 20_000.0).abs() < 1e-9, "{u:?}");
        assert!((u.rho_fs - 5.0).abs() < 1e-12 && (u.gbuffer_fs - 4.0).abs() < 1e-12, "{u:?}");
        assert!((u.compose_fs - 0.5).abs() < 1e-12 && (u.culling_share - 0.25).abs() < 1e-12, "{u:?}");
        assert!((rows[0].units.rho_fs - 1.0).abs() < 1e-12);
        let other = rows[2].units;
        assert!(other.rho_fs.is_nan() && other.culling_share.is_nan() && other.ns_per_ideal.is_nan(), "{other:?}");
    }
}
