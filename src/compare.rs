//! Image comparison with NVIDIA's FLIP metric (nv-flip), and the failure artefacts image tests
//! write: `<name>-actual.png` and `<name>-difference.png`.

use anyhow::{bail, Context, Result};
use image::RgbaImage;
use std::path::{Path, PathBuf};

/// FLIP statistics of `test` against `reference`.
#[derive(Clone, Copy, Debug)]
pub struct FlipResult {
    pub mean: f32,
    pub max: f32,
    /// 99th percentile of the per-pixel error.
    pub p99: f32,
}

fn rgb(img: &RgbaImage) -> nv_flip::FlipImageRgb8 {
    let data: Vec<u8> = img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
    nv_flip::FlipImageRgb8::with_data(img.width(), img.height(), &data)
}

/// Runs FLIP; returns the statistics and the colour-mapped error image.
pub fn flip(reference: &RgbaImage, test: &RgbaImage) -> Result<(FlipResult, RgbaImage)> {
    if reference.dimensions() != test.dimensions() {
        bail!("image sizes differ: reference {:?}, test {:?}", reference.dimensions(), test.dimensions());
    }
    let err = nv_flip::flip(rgb(reference), rgb(test), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let mut pool = nv_flip::FlipPool::from_image(&err);
    let result = FlipResult { mean: pool.mean(), max: pool.max_value(), p99: pool.get_percentile(0.99, false) };
    let map = err.apply_color_lut(&nv_flip::magma_lut());
    let rgba: Vec<u8> = map.to_vec().chunks(3).flat_map(|c| [c[0], c[1], c[2], 255]).collect();
    let diff =
        RgbaImage::from_raw(reference.width(), reference.height(), rgba).context("FLIP map has the wrong size")?;
    Ok((result, diff))
}

/// The largest per-channel difference between two images (0..255).
pub fn max_channel_difference(a: &RgbaImage, b: &RgbaImage) -> u8 {
    a.pixels().zip(b.pixels()).flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c]))).max().unwrap_or(0)
}

/// Outcome of comparing a rendering against its stored reference.
pub struct Snapshot {
    pub name: String,
    pub flip: Option<FlipResult>,
    pub created: bool,
}

/// Compares `actual` with `dir/<name>.png` under `threshold` (FLIP mean). When the environment
/// variable `LAMPSHADE_UPDATE_REFERENCES=1` is set the reference is (re)written instead. On a
/// failure, `<name>-actual.png` and `<name>-difference.png` are written to `out_dir`.
pub fn check_snapshot(dir: &Path, out_dir: &Path, name: &str, actual: &RgbaImage, threshold: f32) -> Result<Snapshot> {
    let reference_path = dir.join(format!("{name}.png"));
    let update = std::env::var("LAMPSHADE_UPDATE_REFERENCES").is_ok_and(|v| v == "1");
    if update {
        actual.save(&reference_path).with_context(|| format!("writing {}", reference_path.display()))?;
        return Ok(Snapshot { name: name.into(), flip: None, created: true });
    }
    let reference = image::open(&reference_path)
        .with_context(|| {
            format!(
                "reference {} is missing; run with LAMPSHADE_UPDATE_REFERENCES=1 to create it",
                reference_path.display()
            )
        })?
        .to_rgba8();
    let (result, diff) = flip(&reference, actual)?;
    if result.mean > threshold {
        std::fs::create_dir_all(out_dir)?;
        let a: PathBuf = out_dir.join(format!("{name}-actual.png"));
        let d: PathBuf = out_dir.join(format!("{name}-difference.png"));
        actual.save(&a)?;
        diff.save(&d)?;
        bail!(
            "{name}: FLIP mean {:.4} exceeds {threshold} (max {:.3}); wrote {} and {}",
            result.mean,
            result.max,
            a.display(),
            d.display()
        );
    }
    Ok(Snapshot { name: name.into(), flip: Some(result), created: false })
}
