//! Two configurations side by side (`bench::compare_pair`, `lampshade compare`): a
//! configuration against itself differs nowhere; two exact list modes on `demo` agree within a
//! step; and each side's error is the figure `bench` reports for the same settings.

use crate::common::{gpu, with_lights};
use lampshade::bench::{self, compare_pair, PairOptions};
use lampshade::renderer::{AccumFormat, CullingMode, Settings};

const SIZE: (u32, u32) = (160, 90);

fn options() -> PairOptions {
    PairOptions { size: SIZE, frames: 1, costs: Default::default() }
}

#[test]
fn a_configuration_against_itself_differs_nowhere() {
    let scene = with_lights("demo", 64);
    let s = Settings::default();
    let r = compare_pair(gpu(), &scene, "demo", (&s, &s), ("A", "A"), &options()).unwrap();
    assert_eq!(r.max_steps, 0, "largest step");
    assert_eq!(r.differing_pixels, 0.0);
    assert_eq!((r.flip_mean, r.flip_max), (0.0, 0.0), "FLIP of a picture against itself");
    assert!(r.difference.pixels().all(|p| p.0 == [0, 0, 0, 255]), "the difference image is not black");
    assert_eq!(r.a.error, r.b.error);
    // Not an empty comparison: the picture is lit, and each side timed its passes.
    assert!(crate::common::lit_share(&r.a.image) > 0.25, "the demo is mostly dark");
    assert!(r.a.gpu_ms.iter().any(|(p, ms)| p == "lighting" && *ms > 0.0), "{:?}", r.a.gpu_ms);
}

/// Both exact list modes shade every light that reaches a pixel, in another order (tiled: by
/// screen tile, clustered: by depth slice): the sums differ at most in their rounding, one step.
/// The ledger's delta names lights whose cost changed (the two modes list them differently).
#[test]
fn tiled_against_clustered_on_demo_is_within_one_step() {
    let scene = with_lights("demo", 256);
    let a = Settings { culling: CullingMode::Tiled, ..Settings::default() };
    let b = Settings { culling: CullingMode::Clustered, ..Settings::default() };
    let r = compare_pair(gpu(), &scene, "demo", (&a, &b), ("tiled", "clustered"), &options()).unwrap();
    assert!(r.max_steps <= 1, "tiled and clustered differ by {} steps", r.max_steps);
    assert!(!r.ledger_delta.is_empty(), "no light's cost changed between tiled and clustered");
    let md = bench::pair_markdown(&r);
    assert!(md.contains("| lighting |") && md.contains("largest step"), "{md}");
}

/// The fp16 and f32 accumulation rows of `bench --only accumulation`, drawn again as a pair:
/// each side's error (FLIP, the largest light error, PSNR) is the bench's, to the bit. The two
/// differ, so the comparison is not of one number with itself.
#[test]
fn fp16_against_f32_accumulation_reports_the_bench_error() {
    let mut o = bench::BenchOptions::new("demo", false);
    o.size = SIZE;
    o.lights = 64;
    o.frames = 1;
    o.groups = vec!["accumulation".into()];
    let run = bench::run(gpu(), &o, |_, _, _| {}).unwrap();
    let configs = bench::configs(&o);
    let pick = |f: AccumFormat| {
        let name = f.name();
        let row = run.rows.iter().find(|r| r.group == "accumulation" && r.accumulation == name);
        let cfg = configs.iter().find(|c| c.group == "accumulation" && c.settings.accumulation == f);
        (row.unwrap_or_else(|| panic!("no bench row for {name}")).clone(), cfg.expect("its configuration").clone())
    };
    let (row16, cfg16) = pick(AccumFormat::Rgba16Float);
    let (row32, cfg32) = pick(AccumFormat::Rgba32Float);
    let scene = with_lights("demo", 64);
    let r =
        compare_pair(gpu(), &scene, "demo", (&cfg16.settings, &cfg32.settings), ("fp16", "f32"), &options()).unwrap();
    for (side, row) in [(&r.a, &row16), (&r.b, &row32)] {
        let e = side.error;
        assert_eq!(
            e.flip_mean.to_bits(),
            row.flip_mean.to_bits(),
            "{}: FLIP {} vs the bench's {}",
            side.label,
            e.flip_mean,
            row.flip_mean
        );
        assert_eq!(
            e.max_abs_light_error.to_bits(),
            row.max_abs_light_error.to_bits(),
            "{}: light error {} vs the bench's {}",
            side.label,
            e.max_abs_light_error,
            row.max_abs_light_error
        );
        assert_eq!(e.psnr_db.to_bits(), row.psnr_db.to_bits(), "{}: PSNR {} vs {}", side.label, e.psnr_db, row.psnr_db);
    }
    assert_ne!(r.a.error.max_abs_light_error, r.b.error.max_abs_light_error, "fp16 and f32 measured the same error");
    assert!(r.a.error.max_abs_light_error.is_finite() && r.b.error.psnr_db.is_finite());
}
