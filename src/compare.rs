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
    // The largest error from the map itself: the pool's maximum starts at the smallest
    // positive float, so two equal images would report that instead of 0.
    let max = err.to_vec().into_iter().fold(0f32, f32::max);
    let result = FlipResult { mean: pool.mean(), max, p99: pool.get_percentile(0.99, false) };
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

/// What [`difference_image`] multiplies each channel's difference by: a one-step difference
/// shows as 16, and 16 steps or more saturate.
pub const DIFFERENCE_GAIN: u8 = 16;

/// `|a - b|` per channel times [`DIFFERENCE_GAIN`] (saturating), opaque: black where the
/// images agree. Compared over the smaller of the two sizes.
pub fn difference_image(a: &RgbaImage, b: &RgbaImage) -> RgbaImage {
    let (w, h) = (a.width().min(b.width()), a.height().min(b.height()));
    RgbaImage::from_fn(w, h, |x, y| {
        let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
        let d = |c: usize| p[c].abs_diff(q[c]).saturating_mul(DIFFERENCE_GAIN);
        image::Rgba([d(0), d(1), d(2), 255])
    })
}

/// How far a rendering may be from a stored reference made on another machine. Lavapipe
/// compiles every shader for the CPU it runs on, so the same frame differs between CPUs in the
/// last bits of float arithmetic; the pictures do not differ otherwise (rasterisation is fixed
/// point). Measured (`tests/it/images.rs`, `cross_cpu_variation`, on every stored reference):
///
/// | code lavapipe generated for | largest step | pixels > 2 steps | FLIP mean (room, 160x90) |
/// |---|---|---|---|
/// | this AVX-512 Xeon vs another AVX-512 Xeon (Mesa 22.3.6, reported) | 2 | 0% (27% differ by 1-2) | 0.0160 |
/// | SSE4.1 only (`GALLIUM_OVERRIDE_CPU_CAPS=sse4.1`) | 2 (room 320x180), 1 at the stored sizes | 0% | 0.00002 |
/// | AVX without AVX2/FMA (`=avx`) | 0 | 0% | 0 |
/// | SSE2 only (`=sse2`, no SSE4.1 rounding) | 7 (room) | 0.44% (room) | 0.0055 |
///
/// So: every pixel within `steps` of the reference, except at most `outlier_share` of them
/// within `outlier_steps` (SSE2's worst case with room to spare: 0.44% of pixels, 7 steps); and
/// a FLIP mean no larger than that of the reference against itself with `steps` of noise on
/// *every* pixel (`noise_flip`), a bound derived from the image rather than a number: the
/// reported machine's 0.0160 on the room lies under the room's 0.027 (1-2 steps on 27% of the
/// pixels is less than 2 steps on all of them). FLIP mean on its own is no measure of this
/// noise: on a 160x90 image it reached 0.016 for differences no one can see.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub steps: u8,
    pub outlier_steps: u8,
    pub outlier_share: f64,
}

/// The tolerance of every stored-reference test (see `Tolerance`).
pub const CROSS_CPU: Tolerance = Tolerance { steps: 2, outlier_steps: 8, outlier_share: 0.01 };

/// `img` with `steps` of deterministic pseudo-random noise (+steps or -steps per channel,
/// clamped) on every pixel: what the step tolerance allows everywhere at once.
pub fn with_noise(img: &RgbaImage, steps: u8) -> RgbaImage {
    let mut out = img.clone();
    let mut x: u32 = 0x9e37_79b9;
    for p in out.pixels_mut() {
        for c in 0..3 {
            // xorshift32: fixed sequence, so the bound is the same on every run.
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            p[c] = if x & 1 == 0 { p[c].saturating_add(steps) } else { p[c].saturating_sub(steps) };
        }
    }
    out
}

/// FLIP mean of `reference` against itself with `steps` of noise on every pixel.
pub fn noise_flip(reference: &RgbaImage, steps: u8) -> Result<f32> {
    Ok(flip(reference, &with_noise(reference, steps))?.0.mean)
}

/// Outcome of comparing a rendering against its stored reference.
pub struct Snapshot {
    pub name: String,
    pub flip: Option<FlipResult>,
    /// Largest per-channel difference, and the share of pixels beyond `Tolerance::steps`.
    pub max_steps: u8,
    pub outliers: f64,
    pub created: bool,
}

/// Compares `actual` with `dir/<name>.png` under `tolerance`. When the environment variable
/// `LAMPSHADE_UPDATE_REFERENCES=1` is set the reference is (re)written instead. On a failure,
/// `<name>-actual.png` and `<name>-difference.png` (FLIP's error map) are written to `out_dir`.
pub fn check_snapshot(
    dir: &Path,
    out_dir: &Path,
    name: &str,
    actual: &RgbaImage,
    tolerance: Tolerance,
) -> Result<Snapshot> {
    let reference_path = dir.join(format!("{name}.png"));
    let update = std::env::var("LAMPSHADE_UPDATE_REFERENCES").is_ok_and(|v| v == "1");
    if update {
        actual.save(&reference_path).with_context(|| format!("writing {}", reference_path.display()))?;
        return Ok(Snapshot { name: name.into(), flip: None, max_steps: 0, outliers: 0.0, created: true });
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
    let steps: Vec<u8> = reference
        .pixels()
        .zip(actual.pixels())
        .map(|(p, q)| (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0))
        .collect();
    let max_steps = steps.iter().copied().max().unwrap_or(0);
    let outliers = steps.iter().filter(|d| **d > tolerance.steps).count() as f64 / steps.len().max(1) as f64;
    let flip_bound = noise_flip(&reference, tolerance.steps)?;
    let mut problems = Vec::new();
    if max_steps > tolerance.outlier_steps {
        problems.push(format!("a pixel differs by {max_steps} steps (at most {})", tolerance.outlier_steps));
    }
    if outliers > tolerance.outlier_share {
        problems.push(format!(
            "{:.2}% of the pixels differ by more than {} steps (at most {:.2}%)",
            outliers * 100.0,
            tolerance.steps,
            tolerance.outlier_share * 100.0
        ));
    }
    if result.mean > flip_bound {
        problems.push(format!(
            "FLIP mean {:.4} exceeds {flip_bound:.4} (the reference against itself with {} steps of noise)",
            result.mean, tolerance.steps
        ));
    }
    if !problems.is_empty() {
        std::fs::create_dir_all(out_dir)?;
        let a: PathBuf = out_dir.join(format!("{name}-actual.png"));
        let d: PathBuf = out_dir.join(format!("{name}-difference.png"));
        actual.save(&a)?;
        diff.save(&d)?;
        bail!("{name}: {}; wrote {} and {}", problems.join("; "), a.display(), d.display());
    }
    Ok(Snapshot { name: name.into(), flip: Some(result), max_steps, outliers, created: false })
}
