//! The culling oracle: each culling mode's light, pixel by pixel, against brute force (every
//! light evaluated at every pixel in f32, `Last::brute_force`), on cases drawn by a seeded
//! generator ([`case::generate`]) or read from a file. Culling may only skip work: a pixel
//! where brute force adds more light than the mode did, by more than the accumulation's
//! rounding, is a missed pair; more light than brute force is extra light.
//!
//! The forward paths keep no G-buffer: each is held against itself unculled instead
//! ([`check_forward`]). What is compared, per path with a G-buffer (deferred, light pre-pass):
//! - the mode's accumulated light minus the same frame without lights (ambient, and what the
//!   G-buffer pass writes first), against brute force's sum;
//! - per channel: diffuse and specular (the pre-pass's light buffer: diffuse and the
//!   specular's luminance; seed 000's one target: the lit colour).
//!
//! The bound ([`rounding_bound`]) is the accumulation format's rounding: each of the k lights
//! adding at the pixel is blended into the target, and each blend rounds.
//!
//! [`shrink`] reduces a failing case to the fewest lights and boxes that still fail.

pub mod case;
pub mod expectation;
pub mod shrink;

use crate::gpu::Gpu;
use crate::headless::render_image;
use crate::renderer::{AccumFormat, CullingMode, RenderPath, Renderer, Settings, OUTPUT_FORMAT};
use anyhow::Result;
use case::Case;
use serde::{Deserialize, Serialize};

/// The forward paths, held against themselves unculled (`ForwardLights::All`: every light in
/// every object's list, multi-pass's pairs full screen): they keep no G-buffer for brute force,
/// and their culling is their object lists, not the culling mode.
pub const FORWARD_PATHS: [RenderPath; 2] = [RenderPath::Forward, RenderPath::ForwardMultipass];

/// How far one accumulated channel may lie from the exact sum `value` of the k lights adding
/// at a pixel in `format`, from rounding alone. Each light's blend rounds twice (its value
/// converted to the target's format, then the sum; the tiled pass's one write of its f32 sum
/// likewise), and the lightless frame's value is rounded once on its own and once where the
/// lights' frame wrote it: 2k + 2 roundings of half a step each.
/// - Rgba16Float: half an ulp is at most 2^-11 of the value, and under fp16's normal range
///   half the subnormal step, 2^-25;
/// - Rgba32Float: 2^-24 of the value, with k more for brute force's own f32 sum, added in
///   another order;
/// - Rg11b10Ufloat: 5 mantissa bits in blue (6 in red and green), 2^-6 of the value, and half
///   its subnormal step, 2^-21;
/// - Rgba8Log and Rgba8Unorm: their own stated bounds for k + 2 writes
///   ([`crate::renderer::settings::log_accum_error_bound`], `unorm_accum_error_bound`).
pub fn rounding_bound(format: AccumFormat, value: f32, k: u32) -> f32 {
    let n = 2.0 * k as f32 + 2.0;
    let v = value.abs();
    match format {
        AccumFormat::Rgba16Float => n * (2f32.powi(-11) * v).max(2f32.powi(-25)),
        AccumFormat::Rgba32Float => (n + k as f32) * (2f32.powi(-24) * v).max(f32::MIN_POSITIVE),
        AccumFormat::Rg11b10Ufloat => n * (2f32.powi(-6) * v).max(2f32.powi(-21)),
        AccumFormat::Rgba8Log => crate::renderer::settings::log_accum_error_bound(v, k + 2),
        AccumFormat::Rgba8Unorm => crate::renderer::settings::unorm_accum_error_bound(k + 2),
    }
}

/// How far the light pass and brute force may differ at a pixel, per light adding there, from
/// flushing denormals alone: Vulkan lets any shader instruction flush a denormal input or
/// result to zero. A light's contribution is its colour x intensity (the one factor above 1,
/// applied last) times factors in [0, 1] (attenuation, N.L, the specular lobe and level, the
/// shadow, the cookie, a metal's albedo); once an intermediate product falls below
/// `f32::MIN_POSITIVE` and is flushed, what it would have given is below `MIN_POSITIVE` x the
/// light's largest colour x intensity channel. The two shaders order the products differently,
/// so either may flush where the other does not. The light pre-pass's mono specular adds up to
/// three more flushed terms (the luminance-weighted channels, weights below 1). So
/// `MIN_POSITIVE x (brightest + 3)`, `brightest` the largest channel of any light's colour x
/// intensity in the scene; it matters only near 1e-37, where a case of stream 4 (17100) lost a
/// 1.8e-37 contribution under a light of intensity 17.6.
pub fn flush_bound(lights: &[crate::scene::Light]) -> f32 {
    use crate::scene::Light;
    let brightest = lights
        .iter()
        .map(|l| match l {
            Light::Point(p) => (p.color * p.intensity).max_element(),
            Light::Spot(s) => (s.color * s.intensity).max_element(),
        })
        .fold(0.0f32, f32::max);
    f32::MIN_POSITIVE * (brightest + 3.0)
}

/// The largest value a channel of `format` holds: past it the target saturates, which is not
/// the culling's doing (such pixels are counted apart).
pub fn range_max(format: AccumFormat) -> f32 {
    match format {
        AccumFormat::Rgba16Float => 65504.0,
        AccumFormat::Rgba32Float => f32::MAX,
        AccumFormat::Rg11b10Ufloat => 64512.0,
        AccumFormat::Rgba8Log => crate::renderer::settings::LOG_ACCUM_MAX,
        AccumFormat::Rgba8Unorm => 1.0,
    }
}

/// The worst pixel of a mode, and the lights the explanation there says the mode missed.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Worst {
    pub x: u32,
    pub y: u32,
    /// Brute force's value minus the mode's (positive: light missing), in the channel where it
    /// is largest against its bound.
    pub difference: f32,
    pub bound: f32,
    /// Brute force's value there.
    pub reference: f32,
    /// The lights the pixel's explanation names as missed (admitted by no culling stage, adding
    /// light).
    pub missed_lights: Vec<usize>,
}

/// One culling mode on one path of one case.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ModeResult {
    pub path: String,
    pub mode: String,
    /// Pixels where brute force adds more light than the mode by more than the bound.
    pub missed: usize,
    /// Pixels where the mode adds more light than brute force by more than the bound.
    pub extra: usize,
    /// Pixels past the accumulation format's range (not compared).
    pub saturated: usize,
    pub worst: Option<Worst>,
    /// Why the frame was not drawn (a mode or layout the adapter refuses), instead of a result.
    pub refused: Option<String>,
    /// The refusal is the path's, before any culling: the case's settings do not suit it (the
    /// light pre-pass keeps its specular in alpha, which Rg11b10Ufloat lacks). Not a limit of
    /// the mode.
    #[serde(default)]
    pub path_refused: bool,
}

impl ModeResult {
    /// A frame of `path` and `mode` with nothing counted yet.
    pub fn new(path: String, mode: String) -> Self {
        Self { path, mode, missed: 0, extra: 0, saturated: 0, worst: None, refused: None, path_refused: false }
    }

    /// A frame that was not drawn, and why.
    pub fn refused(path: String, mode: String, why: &anyhow::Error) -> Self {
        Self { refused: Some(format!("{why:#}")), ..Self::new(path, mode) }
    }

    pub fn failed(&self) -> bool {
        self.missed > 0 || self.extra > 0
    }
}

/// A case's results, every path and mode.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CaseResult {
    pub seed: u64,
    pub index: u64,
    pub lights: usize,
    pub modes: Vec<ModeResult>,
}

impl CaseResult {
    pub fn failures(&self) -> impl Iterator<Item = &ModeResult> {
        self.modes.iter().filter(|m| m.failed())
    }
}

/// What to check: the paths and modes (all by default).
#[derive(Clone, Debug)]
pub struct Scope {
    pub paths: Vec<RenderPath>,
    pub modes: Vec<CullingMode>,
}

impl Default for Scope {
    fn default() -> Self {
        Self { paths: RenderPath::ALL.to_vec(), modes: CullingMode::ALL.to_vec() }
    }
}

impl Scope {
    /// The frames a case draws for the comparison: each culling mode on each G-buffer path, one
    /// on each forward path.
    pub fn frames(&self) -> usize {
        self.paths.iter().map(|p| if FORWARD_PATHS.contains(p) { 1 } else { self.modes.len() }).sum()
    }
}

/// The light a frame accumulated, per pixel and channel: (diffuse RGB, specular RGB).
struct Light {
    diffuse: Vec<f32>,
    specular: Vec<f32>,
}

fn accumulated(gpu: &Gpu, r: &Renderer) -> Result<Light> {
    let (diffuse, specular) = r.last_frame().read_accumulation(gpu)?;
    Ok(Light { diffuse, specular })
}

/// Renders `case` on every path and mode of `scope` and holds each against brute force.
/// `renderer` is reused between cases (its passes stay built).
pub fn check(gpu: &Gpu, renderer: &mut Renderer, case: &Case, scope: &Scope) -> Result<CaseResult> {
    let scene = case.scene().map_err(anyhow::Error::msg)?;
    scene.validate().map_err(anyhow::Error::msg)?;
    let modes = check_scene(gpu, renderer, &scene, &case.settings.settings(), (case.width, case.height), scope, false)?
        .into_iter()
        .map(|(m, _)| m)
        .collect();
    Ok(CaseResult { seed: case.seed, index: case.index, lights: case.lights.len(), modes })
}

/// Per pixel, brute force's value minus the mode's over the bound, in the channel where that
/// is largest (positive: light missing; beyond 1 a missed pair, below -1 extra light; 0 on
/// saturated and background pixels), row by row.
pub type Difference = Vec<f32>;

/// `scene` drawn with `base` (its culling mode replaced by each of `scope`'s, its path by each
/// path's) at `size`, each frame held against brute force; with `differences`, each frame's
/// [`Difference`] too.
pub fn check_scene(
    gpu: &Gpu,
    renderer: &mut Renderer,
    scene: &crate::scene::Scene,
    base: &Settings,
    (w, h): (u32, u32),
    scope: &Scope,
    differences: bool,
) -> Result<Vec<(ModeResult, Option<Difference>)>> {
    let mut dark_scene = scene.clone();
    dark_scene.lights_mut().clear();
    let format = base.accumulation;
    let mut modes = Vec::new();
    let refused =
        |path: RenderPath, mode: CullingMode, e: &anyhow::Error| ModeResult::refused(path.name(), mode.name(), e);
    for &path in &scope.paths {
        if FORWARD_PATHS.contains(&path) {
            modes.push(check_forward(gpu, renderer, scene, base, (w, h), path, differences)?);
            continue;
        }
        // Counting and timing change no pixel (tested); debug views replace the light.
        let base = Settings {
            path,
            count_fragments: false,
            count_ideal: false,
            timestamps: false,
            debug_view: Settings::default().debug_view,
            ..base.clone()
        };
        // The lightless frame, then brute force over the first mode's G-buffer: every mode
        // draws the same G-buffer (the culling comes after it) from the same depth, except
        // that a mode which writes the stencil reads the depth copy where `--depth-read buffer`
        // lets the others read the depth buffer (`key::depth_read_refusal`), whose 24-bit depth
        // the copy does not round. So each depth source has its own lightless frame and brute
        // force, made the first time a mode reads it.
        if let Err(e) = render_image(gpu, renderer, &dark_scene, &base, w, h) {
            let path_refused = |m| ModeResult { path_refused: true, ..refused(path, m, &e) };
            modes.extend(scope.modes.iter().map(|&m| (path_refused(m), None)));
            continue;
        }
        let base_source = renderer.last_frame().reads_depth_buffer();
        // (reads the depth buffer, lightless frame's light, brute force)
        let mut sources: Vec<(bool, Light, Option<crate::renderer::explain::brute::BruteForce>)> =
            vec![(base_source, accumulated(gpu, renderer)?, None)];
        for &mode in &scope.modes {
            let settings = Settings { culling: mode, ..base.clone() };
            if let Err(e) = render_image(gpu, renderer, scene, &settings, w, h) {
                modes.push((refused(path, mode, &e), None));
                continue;
            }
            let source = renderer.last_frame().reads_depth_buffer();
            let at = match sources.iter().position(|s| s.0 == source) {
                Some(i) => i,
                None => {
                    // The lightless frame of this mode's depth source, then this mode again.
                    render_image(gpu, renderer, &dark_scene, &settings, w, h)?;
                    sources.push((source, accumulated(gpu, renderer)?, None));
                    render_image(gpu, renderer, scene, &settings, w, h)?;
                    sources.len() - 1
                }
            };
            if sources[at].2.is_none() {
                sources[at].2 = Some(renderer.last_frame().brute_force(gpu)?);
            }
            let (_, dark, reference) = &sources[at];
            let Some(bf) = reference else { continue };
            let lit = accumulated(gpu, renderer)?;
            let one_target = renderer.last_frame().one_target() && path == RenderPath::Deferred;
            let mut difference = differences.then(|| vec![0.0; bf.adding.len()]);
            let flush = flush_bound(&scene.lights);
            let mut result =
                compare_into(&lit, dark, bf, (format, flush), (path, one_target), difference.as_deref_mut());
            result.path = path.name();
            result.mode = mode.name();
            if let Some(worst) = result.worst.as_mut().filter(|_| result.missed > 0) {
                if let Ok(e) = renderer.last_frame().explain(gpu, worst.x, worst.y) {
                    worst.missed_lights = e.lights.iter().filter(|l| l.missed).map(|l| l.index).collect();
                }
            }
            modes.push((result, difference));
        }
    }
    Ok(modes)
}

/// A forward path's frame with its culled object lists against the same frame unculled: the
/// HDR colour, pixel by pixel. Both walk their lists in light order and a light left out adds
/// exactly zero where it cannot reach, so the culled frame's f32 sums (single-pass) and fp16
/// blends (multi-pass: adding 0 is exact) are the unculled frame's; the bound allows one fp16
/// rounding on each side (2 x 2^-11 of the value, 2^-24 under fp16's normal range).
fn check_forward(
    gpu: &Gpu,
    renderer: &mut Renderer,
    scene: &crate::scene::Scene,
    base: &Settings,
    (w, h): (u32, u32),
    path: RenderPath,
    differences: bool,
) -> Result<(ModeResult, Option<Difference>)> {
    use crate::renderer::{post::PostImage, ForwardLights};
    let base = Settings { path, count_fragments: false, count_ideal: false, timestamps: false, ..base.clone() };
    let lists = if base.forward_lights == ForwardLights::All { ForwardLights::Tiled } else { base.forward_lights };
    let mut result = ModeResult::new(path.name(), format!("{} lists", crate::renderer::settings::name_of(&lists)));
    let mut hdr = |forward_lights| -> Result<Vec<f32>> {
        render_image(gpu, renderer, scene, &Settings { forward_lights, ..base.clone() }, w, h)?;
        renderer
            .last_frame()
            .read_post_image(gpu, PostImage::Hdr)?
            .ok_or_else(|| anyhow::anyhow!("the forward frame kept no HDR colour"))
    };
    let (reference, culled) = match hdr(ForwardLights::All).and_then(|r| Ok((r, hdr(lists)?))) {
        Ok(v) => v,
        Err(e) => return Ok((ModeResult::refused(result.path, result.mode, &e), None)),
    };
    let mut difference = differences.then(|| vec![0.0; (w * h) as usize]);
    let mut worst_ratio = 1.0f32;
    for p in 0..(w * h) as usize {
        let (mut missed, mut extra, mut pixel_worst) = (false, false, 0f32);
        for c in 0..3 {
            let (r, m) = (reference[4 * p + c], culled[4 * p + c]);
            if r >= 65504.0 || m >= 65504.0 {
                result.saturated += 1;
                continue;
            }
            let bound = 2.0 * (2f32.powi(-11) * r.abs().max(m.abs())).max(2f32.powi(-25));
            let d = r - m;
            let ratio = d.abs() / bound;
            if ratio > pixel_worst.abs() {
                pixel_worst = d / bound;
            }
            missed |= d > bound;
            extra |= -d > bound;
            if ratio > worst_ratio {
                worst_ratio = ratio;
                result.worst = Some(Worst {
                    x: p as u32 % w,
                    y: p as u32 / w,
                    difference: d,
                    bound,
                    reference: r,
                    missed_lights: Vec::new(),
                });
            }
        }
        if let Some(d) = difference.as_mut() {
            d[p] = pixel_worst;
        }
        result.missed += missed as usize;
        result.extra += extra as usize;
    }
    Ok((result, difference))
}

/// Holds one frame's light against brute force (see the module's doc).
#[cfg(test)]
fn compare(
    lit: &Light,
    dark: &Light,
    bf: &crate::renderer::explain::brute::BruteForce,
    format: AccumFormat,
    path: (RenderPath, bool),
) -> ModeResult {
    compare_into(lit, dark, bf, (format, 0.0), path, None)
}

/// [`compare`], writing each pixel's [`Difference`] into `difference` when given.
fn compare_into(
    lit: &Light,
    dark: &Light,
    bf: &crate::renderer::explain::brute::BruteForce,
    (format, flush): (AccumFormat, f32),
    (path, one_target): (RenderPath, bool),
    mut difference: Option<&mut [f32]>,
) -> ModeResult {
    let mut r = ModeResult::new(String::new(), String::new());
    let mut worst_ratio = 1.0f32;
    let max = range_max(format);
    for p in 0..bf.adding.len() {
        let k = bf.adding[p];
        let (channels, n) = pixel_channels(p, lit, dark, bf, (path, one_target));
        let (mut missed, mut extra, mut saturated) = (false, false, false);
        let mut pixel_worst = 0f32;
        for &(acc, rest, reference) in &channels[..n] {
            if rest + reference >= max || acc >= max {
                saturated = true;
                continue;
            }
            let bound = rounding_bound(format, acc.max(rest + reference), k) + k as f32 * flush;
            let difference = reference - (acc - rest);
            let ratio = difference.abs() / bound;
            if ratio > pixel_worst.abs() {
                pixel_worst = difference / bound;
            }
            if difference > bound {
                missed = true;
            } else if -difference > bound {
                extra = true;
            }
            if ratio > worst_ratio {
                worst_ratio = ratio;
                r.worst = Some(Worst {
                    x: p as u32 % bf.width,
                    y: p as u32 / bf.width,
                    difference,
                    bound,
                    reference,
                    missed_lights: Vec::new(),
                });
            }
        }
        if let Some(d) = difference.as_deref_mut() {
            d[p] = pixel_worst;
        }
        r.missed += missed as usize;
        r.extra += extra as usize;
        r.saturated += saturated as usize;
    }
    r
}

/// The channels compared at pixel `p`, each (accumulated, lightless, brute force), and how many
/// there are: diffuse and specular RGB; the light pre-pass's diffuse RGB and the specular's
/// luminance; seed 000's one target's lit colour.
fn pixel_channels(
    p: usize,
    lit: &Light,
    dark: &Light,
    bf: &crate::renderer::explain::brute::BruteForce,
    (path, one_target): (RenderPath, bool),
) -> ([(f32, f32, f32); 6], usize) {
    let mut channels: [(f32, f32, f32); 6] = [(0.0, 0.0, 0.0); 6];
    // Channel c of the accumulated diffuse and specular targets, and of the lightless frame's.
    let diffuse = |c: usize| (lit.diffuse[4 * p + c], dark.diffuse[4 * p + c]);
    let specular = |c: usize| (lit.specular[4 * p + c], dark.specular[4 * p + c]);
    let n = if path == RenderPath::LightPrepass {
        for (c, slot) in channels.iter_mut().take(3).enumerate() {
            *slot = (diffuse(c).0, diffuse(c).1, bf.diffuse[p][c]);
        }
        let s = glam::Vec3::from_array(bf.specular[p]).dot(crate::scene::luminance_weights());
        channels[3] = (specular(0).0, specular(0).1, s);
        4
    } else if one_target {
        for (c, slot) in channels.iter_mut().take(3).enumerate() {
            *slot = (diffuse(c).0, diffuse(c).1, bf.lit[p][c]);
        }
        3
    } else {
        for c in 0..3 {
            let (d, s) = (diffuse(c), specular(c));
            channels[c] = (d.0, d.1, bf.diffuse[p][c]);
            channels[3 + c] = (s.0, s.1, bf.specular[p][c]);
        }
        6
    };
    (channels, n)
}

/// What a frame under engine-style caps (`renderer::caps`) lost against brute force over every
/// light of the scene: the pixels that lack light beyond the accumulation's rounding (the
/// oracle's missed pixels), and, when the caps dropped whole lights from the frame (the camera
/// caps), the light-pixel pairs those lights add (brute force over them alone counts them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CapLoss {
    pub missed_pixels: usize,
    pub extra_pixels: usize,
    /// Light–pixel pairs the lights the camera caps dropped add, by brute force over them.
    pub dropped_pairs: Option<u64>,
    /// Light–pixel pairs the per-cluster cap's dropped entries reach: listed for the pixel's cell
    /// without the cap and not with it, the light's shape holding the pixel's point
    /// ([`listed_reached_pairs`] of the frame without the cluster cap, less the frame's).
    pub entry_pairs: Option<u64>,
}

/// Light–pixel pairs of the last frame whose light is listed for the pixel's tile or cluster
/// and whose shape holds the pixel's point (`inspect::inside_light`); None for a frame without
/// lists. The cell is the CPU's (`TileLists::cell`), which can differ from the GPU's by one slice
/// where a point lies on a boundary within the logarithm's rounding.
pub fn listed_reached_pairs(gpu: &Gpu, renderer: &Renderer) -> Result<Option<u64>> {
    let (Some(lists), Some((w, _))) = (renderer.last_frame().tile_lists(gpu)?, renderer.size()) else {
        return Ok(None);
    };
    let positions = renderer.last_frame().view_positions(gpu)?;
    let lights = renderer.last_frame().light_records();
    let mut cells: std::collections::HashMap<usize, Vec<u32>> = std::collections::HashMap::new();
    let mut pairs = 0u64;
    for (k, p) in positions.iter().enumerate() {
        let Some(p) = p else { continue };
        let c = lists.cell(k as u32 % w, k as u32 / w, -p.z);
        let list = cells.entry(c).or_insert_with(|| lists.list(c));
        let inside = |&i: &u32| lights.get(i as usize).is_some_and(|l| crate::renderer::inspect::inside_light(l, *p));
        pairs += list.iter().filter(|i| inside(i)).count() as u64;
    }
    Ok(Some(pairs))
}

/// [`CapLoss`] of `scene` drawn with `settings` (a G-buffer path) at `size`, on `renderer`.
pub fn cap_loss(
    gpu: &Gpu,
    renderer: &mut Renderer,
    scene: &crate::scene::Scene,
    settings: &Settings,
    (w, h): (u32, u32),
) -> Result<CapLoss> {
    if FORWARD_PATHS.contains(&settings.path) {
        anyhow::bail!("the forward paths keep no G-buffer for brute force");
    }
    let base = Settings { count_fragments: false, count_ideal: false, timestamps: false, ..settings.clone() };
    let uncapped =
        Settings { max_lights: 0, light_distance: 0.0, lights_per_cluster: 0, lights_per_object: 0, ..base.clone() };
    let mut dark_scene = scene.clone();
    dark_scene.lights_mut().clear();
    render_image(gpu, renderer, &dark_scene, &uncapped, w, h)?;
    let dark = accumulated(gpu, renderer)?;
    render_image(gpu, renderer, scene, &uncapped, w, h)?;
    let all = renderer.last_frame().brute_force(gpu)?;
    // The per-cluster cap's pairs: the frame without that cap alone (the same kept lights and
    // grid), then the capped frame, each counted over its lists.
    let listed_without_cap = match settings.lights_per_cluster {
        0 => None,
        _ => {
            render_image(gpu, renderer, scene, &Settings { lights_per_cluster: 0, ..base.clone() }, w, h)?;
            Some(listed_reached_pairs(gpu, renderer)?)
        }
    };
    let (_, stats) = render_image(gpu, renderer, scene, &base, w, h)?;
    let entry_pairs = match listed_without_cap {
        // No cap: nothing dropped. A cap on a frame without lists: nothing to count.
        None => Some(0),
        Some(None) => None,
        Some(Some(uncapped)) => listed_reached_pairs(gpu, renderer)?.map(|kept| uncapped.saturating_sub(kept)),
    };
    let lit = accumulated(gpu, renderer)?;
    let one_target = renderer.last_frame().one_target() && settings.path == RenderPath::Deferred;
    let flush = flush_bound(&scene.lights);
    let r = compare_into(&lit, &dark, &all, (settings.accumulation, flush), (settings.path, one_target), None);
    let caps = stats.caps.unwrap_or_default();
    let dropped_pairs = match caps.kept {
        Some(kept) => {
            let mut dropped = scene.clone();
            let mut is_kept = vec![false; scene.lights.len()];
            for &i in &kept {
                is_kept[i as usize] = true;
            }
            let lights = scene.lights.iter().zip(&is_kept).filter(|(_, &k)| !k).map(|(l, _)| *l).collect();
            dropped.set_lights(lights);
            render_image(gpu, renderer, &dropped, &uncapped, w, h)?;
            Some(renderer.last_frame().brute_force(gpu)?.adding.iter().map(|&n| n as u64).sum())
        }
        None => Some(0),
    };
    Ok(CapLoss { missed_pixels: r.missed, extra_pixels: r.extra, dropped_pairs, entry_pairs })
}

/// Checks a case and, when a mode fails, shrinks it ([`shrink::shrink`]) to the fewest lights
/// and boxes that still fail that mode.
pub fn check_and_shrink(
    gpu: &Gpu,
    renderer: &mut Renderer,
    case: &Case,
    scope: &Scope,
) -> Result<(CaseResult, Option<Case>)> {
    let result = check(gpu, renderer, case, scope)?;
    let Some(first) = result.failures().next() else { return Ok((result, None)) };
    let (path_name, mode_name) = (first.path.clone(), first.mode.clone());
    let path = RenderPath::ALL.into_iter().find(|p| p.name() == path_name).unwrap_or(RenderPath::Deferred);
    let modes = CullingMode::ALL.into_iter().filter(|m| m.name() == mode_name).collect::<Vec<_>>();
    let narrow =
        Scope { paths: vec![path], modes: if modes.is_empty() { vec![CullingMode::Fullscreen] } else { modes } };
    let shrunk = shrink::shrink(case, |c| {
        check(gpu, renderer, c, &narrow)
            .map(|r| r.failures().any(|m| m.path == path_name && m.mode == mode_name))
            .unwrap_or(false)
    });
    Ok((result, Some(shrunk)))
}

/// A [`Difference`] as an image: within the bound, grey up to a quarter; missed light in red
/// and extra light in blue, from half to full brightness as the ratio to the bound goes from 1
/// to 256 (log scale); background and saturated pixels black.
pub fn difference_image(difference: &[f32], width: u32, height: u32) -> image::RgbaImage {
    image::RgbaImage::from_fn(width, height, |x, y| {
        let d = difference.get((y * width + x) as usize).copied().unwrap_or(0.0);
        let a = d.abs();
        if a <= 1.0 {
            let g = (a * 64.0) as u8;
            return image::Rgba([g, g, g, 255]);
        }
        let v = (128.0 + 127.0 * (a.log2() / 8.0).min(1.0)) as u8;
        if d > 0.0 {
            image::Rgba([v, 0, 0, 255])
        } else {
            image::Rgba([0, 0, v, 255])
        }
    })
}

/// Cameras around `scene` for `lampshade check`: its bounds' centre seen from inside them, at
/// their edge and from outside, pitched from straight down to above the horizon, with near
/// planes from a thousandth of the bounds' radius up and fields of view from 30 to 110
/// degrees: case `k` of stream `seed` ([`case::Rng`]), so a report's camera can be drawn again.
pub fn cameras_around(scene: &crate::scene::Scene, n: usize, seed: u64) -> Vec<crate::scene::Camera> {
    use glam::DVec3;
    let (lo, hi) = scene.bounds().unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)));
    let (centre, radius) = ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3));
    (0..n as u64)
        .map(|k| {
            let mut r = case::Rng::new(seed, k);
            let distance = radius * [0.3, 1.0, 2.0][k as usize % 3] * r.range(0.8, 1.2);
            let pitch = if k % 4 == 0 { -std::f64::consts::FRAC_PI_2 } else { r.range(-1.4, 0.5) };
            let yaw = r.range(-std::f64::consts::PI, std::f64::consts::PI);
            // The camera looks along (yaw, pitch) at the centre from `distance` back.
            let look = DVec3::new(yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos());
            let near = radius * r.log(1e-3, 0.05);
            crate::scene::Camera {
                position: centre - look * distance,
                yaw,
                pitch,
                fov_y: r.range(30.0, 110.0).to_radians(),
                near,
                far: (distance + 2.0 * radius) * 4.0 + near,
            }
        })
        .collect()
}

/// A renderer for the oracle's frames.
pub fn renderer(gpu: &Gpu) -> Result<Renderer> {
    Renderer::new(gpu, OUTPUT_FORMAT, &Settings { count_fragments: false, timestamps: false, ..Settings::default() })
}

/// The pass pool budget of a [`Runner`]'s device: a settings block of 50 cases draws each path
/// with 30 or so shader-feature and material variants (shadows, cookies, masks, light planes,
/// one reflectance model or several), each a pass set of its own; 32 sets of 23 pipelines at
/// lavapipe's estimate (`Quirks::pipeline_bytes`).
pub const RUNNER_POOL_BYTES: u64 = 32 * (23 * (3 << 20) + crate::renderer::kit::pool::SET_BYTES);

/// Runs case after case on one device with bounded memory. A pass set's pipelines compile when
/// a frame first declares them (`kit::Declared`), about 23 a case, and hold a few MiB each on
/// lavapipe.
/// Measured on stream 4, cases 8900-9049 (three settings blocks, 64x36): keeping 8 sets, 172
/// sets were built, 117 s, 0.75 GB peak; keeping 32, 85 built, 86 s, 2.3 GB. The runner keeps
/// [`RUNNER_POOL_BYTES`] in the pool and starts a new renderer, dropping the old one's sets, when the
/// settings change.
pub struct Runner {
    renderer: Option<(case::CaseSettings, Renderer)>,
}

impl Runner {
    /// Limits `gpu`'s pass pool to [`RUNNER_POOL_BYTES`]: give the runner a device of its own.
    pub fn new(gpu: &Gpu) -> Self {
        gpu.passes.keep_bytes_at_most(RUNNER_POOL_BYTES);
        Self { renderer: None }
    }

    /// The renderer for `case`'s settings.
    fn renderer(&mut self, gpu: &Gpu, case: &Case) -> Result<&mut Renderer> {
        if self.renderer.as_ref().is_none_or(|(s, _)| *s != case.settings) {
            self.renderer = None;
            self.renderer = Some((case.settings.clone(), renderer(gpu)?));
        }
        match self.renderer.as_mut() {
            Some((_, r)) => Ok(r),
            None => anyhow::bail!("no renderer"),
        }
    }

    /// [`check`] with this runner's renderer.
    pub fn check(&mut self, gpu: &Gpu, case: &Case, scope: &Scope) -> Result<CaseResult> {
        let r = self.renderer(gpu, case)?;
        check(gpu, r, case, scope)
    }

    /// [`check_and_shrink`] with this runner's renderer.
    pub fn check_and_shrink(&mut self, gpu: &Gpu, case: &Case, scope: &Scope) -> Result<(CaseResult, Option<Case>)> {
        let r = self.renderer(gpu, case)?;
        check_and_shrink(gpu, r, case, scope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::explain::brute::BruteForce;

    /// Two pixels, one light adding 0.5 to the first one's diffuse red.
    fn brute() -> BruteForce {
        BruteForce {
            width: 2,
            height: 1,
            diffuse: vec![[0.5, 0.0, 0.0], [0.0; 3]],
            specular: vec![[0.0; 3]; 2],
            lit: vec![[0.5, 0.0, 0.0], [0.0; 3]],
            adding: vec![1, 0],
        }
    }

    fn light(red: f32) -> Light {
        Light { diffuse: vec![0.1 + red, 0.1, 0.1, 1.0, 0.1, 0.1, 0.1, 1.0], specular: vec![0.0; 8] }
    }

    #[test]
    fn a_light_left_out_is_missed_and_one_added_is_extra() {
        let dark = light(0.0);
        let f = AccumFormat::Rgba16Float;
        let deferred = (RenderPath::Deferred, false);
        assert_eq!(compare(&light(0.5), &dark, &brute(), f, deferred).missed, 0);
        // Off by the rounding bound's worth: still the same light.
        let ulp = rounding_bound(f, 0.6, 1) * 0.99;
        let close = compare(&light(0.5 - ulp), &dark, &brute(), f, deferred);
        assert_eq!((close.missed, close.extra), (0, 0));
        let missed = compare(&light(0.0), &dark, &brute(), f, deferred);
        assert_eq!((missed.missed, missed.extra), (1, 0));
        let worst = missed.worst.expect("a worst pixel");
        assert_eq!((worst.x, worst.y, worst.reference), (0, 0, 0.5));
        let extra = compare(&light(0.7), &dark, &brute(), f, deferred);
        assert_eq!((extra.missed, extra.extra), (0, 1));
        // A value past the format's range is not compared.
        let saturated = compare(&light(70000.0), &dark, &brute(), f, deferred);
        assert_eq!((saturated.missed, saturated.extra, saturated.saturated), (0, 0, 1));
    }

    /// The bound grows with the lights adding (each blend rounds) and with the value (a relative
    /// step), and never falls to zero (fp16's subnormal step).
    #[test]
    fn the_rounding_bound_follows_the_format() {
        let f = AccumFormat::Rgba16Float;
        assert_eq!(rounding_bound(f, 1.0, 0), 2.0 * 2f32.powi(-11));
        assert_eq!(rounding_bound(f, 1.0, 3), 8.0 * 2f32.powi(-11));
        assert_eq!(rounding_bound(f, 0.0, 0), 2.0 * 2f32.powi(-25));
        assert!(rounding_bound(AccumFormat::Rgba32Float, 1.0, 3) < rounding_bound(f, 1.0, 3) / 1000.0);
    }
}
