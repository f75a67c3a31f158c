//! The HDR post chain (after transparency, in the seeds' order: seed 002's glow, exposure,
//! edge smoothing and fog, seed 003's grading, depth of field and vignetting): bloom →
//! auto-exposure → tone mapping → colour grading → anti-aliasing → fog → depth of field →
//! vignette. The technique
//! is this folder: [`bloom`], [`exposure`], [`tonemap`], then the effects after tone mapping as
//! one table ([`effects::EFFECTS`]); their WGSL is `post.wgsl`. This file holds what they
//! share and the chain itself ([`encode_chain`]): the tone curves' and fog's CPU twins
//! (formula for formula as the WGSL), the `.cube` parser, the histogram's constants and the
//! chain's size-dependent targets.
//!
//! The chain runs only when an effect asks for it ([`chain_active`]): with every effect off and
//! the ACES curve, the frame is composed and tonemapped by compose exactly as before (bit for
//! bit). Error against the f64 reference is measured on the light accumulation, before any of
//! this: the chain does not change what the accuracy figures measure.

pub mod bloom;
pub mod distortion;
pub mod effects;
pub mod exposure;
pub mod tonemap;

pub mod targets;
use super::kit::Declared;
use super::kit::Lazy;
use super::options::post::PostOptions;
pub use super::options::post::{Aa, Tonemap};
use super::records::PostParams;
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use effects::EFFECTS;
use serde::{Deserialize, Serialize};
pub use targets::{PostTargets, BLOOM_LEVELS, HIST_BINS, MAX_LUT_SIZE, STATE_WORDS};

pub const HIST_LOG_MIN: f32 = -12.0;
pub const HIST_LOG_MAX: f32 = 9.0;
/// Width of a histogram bin in stops.
pub fn hist_bin_stops() -> f32 {
    (HIST_LOG_MAX - HIST_LOG_MIN) / (HIST_BINS - 1) as f32
}
/// The time step of one frame: auto-exposure is stepped by frames, not by the wall clock, so
/// scripted runs and tests are deterministic.
pub const FRAME_DT: f32 = 1.0 / 60.0;
/// Format of the chain's intermediate images where the adapter renders it (f32: the bloom
/// energy test sums them).
pub const POST_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The chain's format on an adapter: [`POST_FORMAT`], else Rgba16Float (wgpu's GL backend renders
/// no 32-bit float target).
///
/// What half floats cost, with the ACES curve: a stored f16 value is off by at most 2^-11 of
/// itself. A pixel's HDR value reaches the tone curve through at most 10 stored images (the
/// bright pass, four downsamples, four upsamples, the combine: `BLOOM_LEVELS` = 5), each a sum of
/// positive terms, so it is off by at most 10 x 2^-11 = 0.0049 of itself. ACES (Narkowicz's fit)
/// followed by the sRGB encoding changes the output by at most 0.286 per unit of ln(x) (its
/// largest slope against ln x, at x = 0.17, computed over 1e-6..1e4), so the output moves by at
/// most 0.286 x 0.0049 = 0.0014, 0.36 of an 8-bit step: below one step, so the 8-bit outputs of
/// the two chains differ by at most one step. The effects after tone mapping are not part of
/// this bound (FXAA's and the edge filter's thresholds may decide differently on the two).
pub fn post_format(caps: &crate::renderer::kit::adapter::AdapterCaps) -> wgpu::TextureFormat {
    if caps.renderable(POST_FORMAT) {
        POST_FORMAT
    } else {
        wgpu::TextureFormat::Rgba16Float
    }
}

impl Tonemap {
    pub const ALL: [Tonemap; 5] = [Tonemap::Aces, Tonemap::Reinhard, Tonemap::Agx, Tonemap::PbrNeutral, Tonemap::None];

    pub fn wgsl_name(self) -> String {
        self.name().to_uppercase().replace('-', "_")
    }

    /// The curve on the CPU, formula for formula as `tonemap` in `post.wgsl` (f64).
    pub fn apply(self, c: [f64; 3]) -> [f64; 3] {
        let clamp01 = |v: [f64; 3]| v.map(|x| x.clamp(0.0, 1.0));
        match self {
            Tonemap::Aces => {
                let (a, b, cc, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
                clamp01(c.map(|x| (x * (a * x + b)) / (x * (cc * x + d) + e)))
            }
            Tonemap::Reinhard => c.map(|x| x.max(0.0) / (1.0 + x.max(0.0))),
            Tonemap::Agx => {
                // Inset matrix (rows as WGSL's column-major mat3x3 multiplies them).
                const INSET: [[f64; 3]; 3] = [
                    [0.842479062253094, 0.0423282422610123, 0.0423756549057051],
                    [0.0784335999999992, 0.878468636469772, 0.0784336],
                    [0.0792237451477643, 0.0791661274605434, 0.879142973793104],
                ];
                const OUTSET: [[f64; 3]; 3] = [
                    [1.19687900512017, -0.0528968517574562, -0.0529716355144438],
                    [-0.0980208811401368, 1.15190312990417, -0.0980434501171241],
                    [-0.0990297440797205, -0.0989611768448433, 1.15107367264116],
                ];
                let (min_ev, max_ev) = (-12.47393, 4.026069);
                // Columns of the matrix: v = M x = sum_j x_j * column_j.
                let mul = |m: &[[f64; 3]; 3], x: [f64; 3]| {
                    let mut out = [0.0; 3];
                    for (j, col) in m.iter().enumerate() {
                        for i in 0..3 {
                            out[i] += col[i] * x[j];
                        }
                    }
                    out
                };
                let v = mul(&INSET, c.map(|x| x.max(0.0)));
                let v = v.map(|x| {
                    let t = (x.max(1e-10).log2().clamp(min_ev, max_ev) - min_ev) / (max_ev - min_ev);
                    let (x2, x4) = (t * t, t * t * t * t);
                    15.5 * x4 * x2 - 40.14 * x4 * t + 31.96 * x4 - 6.868 * x2 * t + 0.4298 * x2 + 0.1191 * t - 0.00232
                });
                clamp01(mul(&OUTSET, v).map(|x| x.max(0.0).powf(2.2)))
            }
            Tonemap::PbrNeutral => {
                let start = 0.8 - 0.04;
                let desaturation = 0.15;
                let x = c[0].min(c[1]).min(c[2]).max(0.0);
                let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
                let col = c.map(|v| v.max(0.0) - offset);
                let peak = col[0].max(col[1]).max(col[2]);
                if peak < start {
                    return clamp01(col);
                }
                let d = 1.0 - start;
                let new_peak = 1.0 - d * d / (peak + d - start);
                let col = col.map(|v| v * new_peak / peak);
                let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
                clamp01(col.map(|v| v * (1.0 - g) + new_peak * g))
            }
            Tonemap::None => clamp01(c),
        }
    }
}

/// Largest circle of confusion, in pixels (diameter).
pub const MAX_COC: f32 = 16.0;

/// Fog's share of a pixel at view-space point `p` (camera at the origin) with the camera's up
/// direction `up` (view space): 1 - exp(-optical depth), the optical depth of density
/// `density × exp(-falloff × h)` (h: height above the camera) along the ray, which is
/// `density × distance × (1 - exp(-falloff Δh)) / (falloff Δh)` (→ density × distance as
/// falloff Δh → 0). It grows monotonically with distance along every ray. `fs_fog` computes
/// the same in f32.
pub fn fog_amount(p: [f64; 3], up: [f64; 3], density: f64, falloff: f64) -> f64 {
    let distance = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let dh = p[0] * up[0] + p[1] * up[1] + p[2] * up[2];
    let x = falloff * dh;
    let shape = if x.abs() < 1e-4 { 1.0 - 0.5 * x } else { -(-x).exp_m1() / x };
    1.0 - (-density * distance * shape).exp()
}

/// Whether the frame goes through the post chain: any effect on, or a curve other than the
/// ACES that compose applies itself.
pub fn chain_active(view: super::DebugView, s: &PostOptions) -> bool {
    match view {
        super::DebugView::Lit => {
            s.bloom || s.auto_exposure || s.tonemap != Tonemap::Aces || EFFECTS.iter().any(|e| (e.on)(s))
        }
        v => post_view(v),
    }
}

/// The debug views the post chain draws (bloom buffer, histogram).
pub fn post_view(v: super::DebugView) -> bool {
    use super::DebugView as V;
    matches!(v, V::Bloom | V::Histogram | V::Edges | V::Coc)
}

/// A 3D colour LUT (Adobe's `.cube` format): `size`³ RGB entries, red fastest, mapping the
/// display-encoded (sRGB) colour in `domain_min ..= domain_max` to a graded one.
#[derive(Clone, Debug, PartialEq)]
pub struct Lut {
    pub size: u32,
    pub domain_min: [f32; 3],
    pub domain_max: [f32; 3],
    pub table: Vec<[f32; 3]>,
}

impl Lut {
    /// The identity: every colour maps to itself (trilinear interpolation of it is exact).
    pub fn identity(size: u32) -> Self {
        let n = size as usize;
        let k = |i: usize| i as f32 / (n - 1) as f32;
        let mut table = Vec::with_capacity(n * n * n);
        for b in 0..n {
            for g in 0..n {
                for r in 0..n {
                    table.push([k(r), k(g), k(b)]);
                }
            }
        }
        Self { size, domain_min: [0.0; 3], domain_max: [1.0; 3], table }
    }

    /// `identity` (built in, 33³) or a `.cube` file.
    pub fn load(name: &str) -> Result<Self, String> {
        if name == "identity" {
            return Ok(Self::identity(33));
        }
        let text = std::fs::read_to_string(name).map_err(|e| format!("cannot read LUT '{name}': {e}"))?;
        Self::parse(&text).map_err(|e| format!("LUT '{name}': {e}"))
    }

    /// Parses a `.cube` file's text (a UTF-8 byte-order mark allowed): `TITLE`, `LUT_3D_SIZE N`
    /// (2 ..= 65), optional `DOMAIN_MIN`/`DOMAIN_MAX` or `LUT_3D_INPUT_RANGE lo hi`, comments
    /// (`#`), then N³ lines of three finite numbers. Any other keyword is an error naming it.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut size: Option<u32> = None;
        let mut domain_min = [0.0f32; 3];
        let mut domain_max = [1.0f32; 3];
        let mut table = Vec::new();
        let three = |words: &[&str], line: usize| -> Result<[f32; 3], String> {
            if words.len() != 3 {
                return Err(format!("line {line}: expected three numbers, found {}", words.len()));
            }
            let mut v = [0.0f32; 3];
            for (o, w) in v.iter_mut().zip(words) {
                *o = w.parse().map_err(|_| format!("line {line}: '{w}' is not a number"))?;
                if !o.is_finite() {
                    return Err(format!("line {line}: '{w}' is not finite"));
                }
            }
            Ok(v)
        };
        // A UTF-8 byte-order mark (some editors write one) is not part of the first keyword.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let l = raw.split('#').next().unwrap_or("").trim();
            if l.is_empty() {
                continue;
            }
            let words: Vec<&str> = l.split_whitespace().collect();
            match words[0] {
                "TITLE" => {}
                "LUT_3D_SIZE" => {
                    let n: u32 = words
                        .get(1)
                        .and_then(|w| w.parse().ok())
                        .ok_or_else(|| format!("line {line}: LUT_3D_SIZE needs a whole number"))?;
                    if !(2..=MAX_LUT_SIZE).contains(&n) {
                        return Err(format!("line {line}: LUT_3D_SIZE {n} is not in 2 ..= {MAX_LUT_SIZE}"));
                    }
                    if size.is_some() {
                        return Err(format!("line {line}: LUT_3D_SIZE given twice"));
                    }
                    size = Some(n);
                }
                "LUT_1D_SIZE" => return Err(format!("line {line}: 1D LUTs are not supported (LUT_3D_SIZE only)")),
                "DOMAIN_MIN" => domain_min = three(&words[1..], line)?,
                "DOMAIN_MAX" => domain_max = three(&words[1..], line)?,
                // DaVinci Resolve's form of the domain: one range for all three channels.
                "LUT_3D_INPUT_RANGE" => {
                    let range: Vec<f32> = words[1..].iter().filter_map(|w| w.parse().ok()).collect();
                    let [lo, hi] = range[..] else {
                        return Err(format!("line {line}: LUT_3D_INPUT_RANGE needs two numbers"));
                    };
                    if !(lo.is_finite() && hi.is_finite()) || words.len() != 3 {
                        return Err(format!("line {line}: LUT_3D_INPUT_RANGE needs two finite numbers"));
                    }
                    (domain_min, domain_max) = ([lo; 3], [hi; 3]);
                }
                w if w.starts_with(|c: char| c.is_ascii_alphabetic()) => {
                    return Err(format!("line {line}: unknown keyword '{w}'"));
                }
                _ => {
                    if size.is_none() {
                        return Err(format!("line {line}: table data before LUT_3D_SIZE"));
                    }
                    table.push(three(&words, line)?);
                }
            }
        }
        let Some(size) = size else { return Err("no LUT_3D_SIZE".into()) };
        let want = (size as usize).pow(3);
        if table.len() != want {
            return Err(format!("LUT_3D_SIZE {size} needs {want} entries, the file has {}", table.len()));
        }
        if (0..3).any(|c| domain_max[c] <= domain_min[c]) {
            return Err(format!("DOMAIN_MAX {domain_max:?} must exceed DOMAIN_MIN {domain_min:?}"));
        }
        Ok(Self { size, domain_min, domain_max, table })
    }
}

/// The largest relative amount by which the bloom chain's total (its light summed over the
/// full-resolution pixels) can exceed the bright pass's: the downsample (a 2×2 box, outside
/// pixels zero) and the 2× bilinear upsample (edge-clamped: every source texel lands on exactly
/// four output pixels' worth of weight, 0.75 + 0.75 + 0.25 + 0.25 per axis, edges included)
/// conserve it in exact arithmetic, and the level weights (1/2, 1/4, 1/8, 1/16, 1/16) sum to 1.
/// Odd sizes only lose light (an upsample to 2n - 1 pixels drops a row). What is left is f32
/// rounding, counted along a value's path through `post.wgsl`, each operation within
/// 2^-24 relative (all terms are non-negative, so relative bounds compound): a 2×2 box is 3
/// additions (× 0.25 is exact), 5 levels down = 15; `bloom_up` is two nested `mix`es of 3
/// roundings each (a × (1 − t) + b × t with t = 0.25 or 0.75, 1 − t exact) = 6, and an up level
/// adds its halves (× 0.5 exact) = 7, 4 levels up = 28; the combine's final `bloom_up` and the
/// multiply by the intensity = 7. The bright pass's own rounding is the caller's (the test adds
/// it). 50 operations: `(1 + 2^-24)^50 - 1`, about 3.0e-6; at sizes divisible by 32 the total
/// is equal within it.
pub fn bloom_energy_bound() -> f64 {
    (1.0 + 2f64.powi(-24)).powi(50) - 1.0
}

/// An image of the chain that `Last::read_post_image` reads back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PostImage {
    /// The HDR scene colour the chain starts from (after the forward pass).
    Hdr,
    /// The HDR colour with bloom added.
    Bloomed,
    /// The distortion buffer (offsets in .rg, the nearest distorter's 1 / view depth in .a).
    Distortion,
}

/// The chain's passes, from the frame's pass set.
pub struct ChainPasses<'a> {
    pub bloom: &'a Lazy<bloom::BloomPass>,
    pub exposure: &'a Lazy<exposure::ExposurePass>,
    pub tonemap: &'a Lazy<tonemap::TonemapPass>,
    pub effects: &'a Lazy<effects::EffectsPass>,
    pub distortion: &'a Lazy<distortion::DistortionPass>,
}

/// The chain as one step of the frame, into the frame's output.
pub struct Chain<'a>(pub ChainPasses<'a>);

impl Pass for Chain<'_> {
    /// As [`encode_chain`] takes the chain: bloom, exposure, then the view's pipeline, or the
    /// tonemap and each effect that is on (the last into the output), the distortion buffer's
    /// draws before its effect.
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        let p = &self.0;
        let (s, view) = (&f.options.post, f.options.frame.debug_view);
        p.bloom.declare(f, out);
        p.exposure.declare(f, out);
        use super::DebugView as V;
        match view {
            V::Bloom | V::Histogram => out.add(p.tonemap.view_pipeline(f)),
            V::Edges | V::Coc => {
                out.add(p.tonemap.pipeline(false));
                out.add_all(p.effects.view_pipeline(view));
            }
            _ => {
                let on: Vec<usize> = (0..EFFECTS.len()).filter(|&i| (EFFECTS[i].on)(s)).collect();
                out.add(p.tonemap.pipeline(on.is_empty()));
                for (k, &i) in on.iter().enumerate() {
                    if EFFECTS[i].buffer_first {
                        p.distortion.declare(f, out);
                    }
                    out.add_all(p.effects.pipeline(i, k + 1 == on.len()));
                }
            }
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        if let Some(pt) = f.targets.post.as_ref() {
            let stamps = f.timestamps(None, Some(crate::renderer::surfaces::compose::SPAN));
            encode_chain(encoder, f, &self.0, pt, f.output, stamps);
        }
        Ok(PassReport::default())
    }
}

/// Records the chain after the HDR compose and the forward pass, in the seeds' order: bloom,
/// auto-exposure, tone mapping, grading, distortion (its buffer drawn first), anti-aliasing,
/// fog, depth of field, vignette. Each pass skips itself when its effect is off; the
/// last that runs writes `target`, and `end` (the compose span's end stamp) closes the frame.
pub fn encode_chain(
    encoder: &mut wgpu::CommandEncoder,
    f: &crate::renderer::inputs::FrameInputs<'_>,
    p: &ChainPasses<'_>,
    pt: &PostTargets,
    target: &wgpu::TextureView,
    end: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let (s, view) = (&f.options.post, f.options.frame.debug_view);
    p.bloom.encode(encoder, f, pt);
    let hdr = if s.bloom { &pt.from_bloomed } else { &pt.from_hdr };
    p.exposure.encode(encoder, f, pt, hdr);
    use super::DebugView as V;
    match view {
        // The bloom view reads the chain's finest level (the combine's group), the histogram
        // view the picture.
        V::Bloom => p.tonemap.encode_view(encoder, f, &pt.combine, target),
        V::Histogram => p.tonemap.encode_view(encoder, f, hdr, target),
        V::Edges | V::Coc => {
            p.tonemap.encode(encoder, f, hdr, &pt.toned_view, false);
            p.effects.encode_view(encoder, f, view, &pt.from_toned, target);
        }
        _ => {
            // After tone mapping: the effects that are on, alternating between two images;
            // the last writes the output.
            let on: Vec<usize> = (0..EFFECTS.len()).filter(|&i| (EFFECTS[i].on)(s)).collect();
            let first = if on.is_empty() { target } else { &pt.toned_view };
            p.tonemap.encode(encoder, f, hdr, first, on.is_empty());
            for (k, &i) in on.iter().enumerate() {
                let last = k + 1 == on.len();
                let (src, dst) =
                    if k % 2 == 0 { (&pt.from_toned, &pt.second_view) } else { (&pt.from_second, &pt.toned_view) };
                if EFFECTS[i].buffer_first {
                    // Its buffer first, right before it: the effect's span holds both.
                    p.distortion.encode(encoder, f, pt);
                }
                p.effects.encode(encoder, f, i, src, if last { target } else { dst }, last);
            }
        }
    }
    // The compose span ends after the chain (an empty pass holding the stamp).
    if end.is_some() {
        drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("post end"),
            color_attachments: &[super::targets::attachment(target, None)],
            depth_stencil_attachment: None,
            timestamp_writes: end,
            occlusion_query_set: None,
            multiview_mask: None,
        }));
    }
}

/// The chain's parameters for this frame.
pub fn params(s: &PostOptions, lut: Option<&Lut>, focus_fallback: f32) -> PostParams {
    let (lut_size, lut_min, lut_max) = match lut {
        Some(l) => (
            l.size,
            [l.domain_min[0], l.domain_min[1], l.domain_min[2], 0.0],
            [l.domain_max[0], l.domain_max[1], l.domain_max[2], 0.0],
        ),
        None => (0, [0.0; 4], [1.0, 1.0, 1.0, 0.0]),
    };
    PostParams {
        tonemap: s.tonemap as u32,
        auto_exposure: s.auto_exposure as u32,
        lut_size,
        pad0: 0,
        exposure: s.exposure,
        threshold: s.bloom_threshold,
        intensity: s.bloom_intensity,
        target_luminance: s.target_luminance,
        adapt_rate: adapt_rate(s.adaptation_speed),
        log_min: HIST_LOG_MIN,
        log_max: HIST_LOG_MAX,
        focus_fallback,
        lut_min,
        lut_max,
        fog_density: s.fog_density,
        fog_falloff: s.fog_height_falloff,
        // 0: auto (a fixed distance is > 0, `Settings::validate`).
        focus_distance: s.focus_distance.distance().unwrap_or(0.0),
        aperture: s.aperture,
        vignette: s.vignette,
        aa: s.aa as u32,
        pad2: 0,
        pad3: 0,
        effect: std::array::from_fn(|i| EFFECTS.get(i).map_or([0.0; 4], |e| (e.params)(s))),
    }
}

/// Depth of field's auto focus where the screen's centre pixel is background (sky): the framed
/// scene's view distance. The scene's bounds are the objects' bounding spheres (`bounds`: each
/// mesh's, model space) moved and scaled by their transforms; the focus is the view depth of
/// their box's centre, or the box's half-diagonal where that centre is not in front of the
/// camera (the camera inside the scene, or past its middle), kept within the camera's near and
/// far planes. An empty scene focuses at the far plane. O(objects), once a frame, on the CPU.
pub fn focus_fallback(scene: &crate::scene::Scene, bounds: &[(glam::DVec3, f64)]) -> f32 {
    let cam = &scene.camera;
    let (mut lo, mut hi) = (glam::DVec3::splat(f64::INFINITY), glam::DVec3::splat(f64::NEG_INFINITY));
    for o in &scene.objects {
        let Some(&(centre, radius)) = bounds.get(o.mesh) else { continue };
        let c = o.transform.transform_point3(centre);
        let scale = o.transform.x_axis.length().max(o.transform.y_axis.length()).max(o.transform.z_axis.length());
        let r = glam::DVec3::splat(radius * scale);
        lo = lo.min(c - r);
        hi = hi.max(c + r);
    }
    if !(lo.x <= hi.x) || !lo.is_finite() || !hi.is_finite() {
        return cam.far as f32;
    }
    let depth = (0.5 * (lo + hi) - cam.position).dot(cam.forward());
    let d = if depth > cam.near { depth } else { 0.5 * (hi - lo).length() };
    d.clamp(cam.near, cam.far) as f32
}

/// The fraction of the way auto-exposure moves per frame at `speed` (per second): the exact
/// step of `dL/dt = speed (L_frame - L)` over [`FRAME_DT`], in (0, 1) for every speed the knob
/// takes, so the adapted value approaches the frame's monotonically and never overshoots.
pub fn adapt_rate(speed: f32) -> f32 {
    // 1 - exp(-x) without the cancellation that rounds a slow speed's step to 0.
    -(-speed * FRAME_DT).exp_m1()
}

/// One full-screen draw of a post-chain pass into `view`: the frame's and the G-buffer's groups
/// with the post group `group`, timestamps as given.
pub fn post_draw(
    encoder: &mut wgpu::CommandEncoder,
    f: &FrameInputs<'_>,
    label: &str,
    pipeline: &crate::renderer::kit::RenderPipe,
    view: &wgpu::TextureView,
    group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[crate::renderer::targets::attachment(view, Some(wgpu::Color::BLACK))],
        depth_stencil_attachment: None,
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &f.frame.group, &[]);
    pass.set_bind_group(1, &f.targets.gbuffer_group, &[]);
    pass.set_bind_group(2, group, &[]);
    pass.draw(0..3, 0..1);
}

/// The grading LUT the post targets hold, by its `lut` setting (`None`: none uploaded), keyed
/// by the file's modification time too, so an edited file is read again.
#[derive(Default)]
pub struct LutCache {
    held: Option<((String, Option<std::time::SystemTime>), Lut)>,
}

impl LutCache {
    /// Writes the chain's parameters into `pt` (`focus_fallback`: [`focus_fallback`] of the
    /// frame), and the LUT `o` names when it is another one than the targets hold.
    pub fn upload(
        &mut self,
        queue: &wgpu::Queue,
        pt: &PostTargets,
        o: &PostOptions,
        focus_fallback: f32,
    ) -> anyhow::Result<()> {
        if let Some(name) = &o.lut {
            let key = (name.clone(), std::fs::metadata(name).and_then(|m| m.modified()).ok());
            if self.held.as_ref().is_none_or(|(k, _)| *k != key) {
                let lut = Lut::load(name).map_err(anyhow::Error::msg)?;
                let data: Vec<[f32; 4]> = lut.table.iter().map(|e| [e[0], e[1], e[2], 0.0]).collect();
                queue.write_buffer(&pt.lut, 0, bytemuck::cast_slice(&data));
                self.held = Some((key, lut));
            }
        }
        let lut = o.lut.as_ref().and(self.held.as_ref().map(|(_, l)| l));
        queue.write_buffer(&pt.params, 0, bytemuck::bytes_of(&params(o, lut, focus_fallback)));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the screen's centre is sky, auto focus falls back to the framed scene's distance:
    /// the view depth of its bounds' centre, their half-diagonal with the camera inside them,
    /// the far plane for an empty scene; always within the near and far planes.
    #[test]
    fn the_auto_focus_fallback_is_the_framed_scenes_distance() {
        use crate::scene::{Camera, Object, Scene};
        use glam::{DMat4, DVec3};
        let camera = Camera::looking_at(DVec3::ZERO, DVec3::NEG_Z);
        let mut sc = Scene::new("t", camera);
        assert_eq!(focus_fallback(&sc, &[]), camera.far as f32, "empty: the far plane");
        // A unit sphere (model space) scaled by 2, 30 units ahead and 5 to the side.
        let bounds = [(DVec3::ZERO, 1.0)];
        let at = |p: DVec3| Object {
            mesh: 0,
            material: 0,
            transform: DMat4::from_translation(p) * DMat4::from_scale(DVec3::splat(2.0)),
            layer: 0,
        };
        sc.objects = vec![at(DVec3::new(5.0, 0.0, -30.0))];
        assert!((focus_fallback(&sc, &bounds) - 30.0).abs() < 1e-4, "{}", focus_fallback(&sc, &bounds));
        // Two objects around the camera: the bounds' centre is not ahead, so their half-diagonal.
        sc.objects = vec![at(DVec3::new(0.0, 0.0, 10.0)), at(DVec3::new(0.0, 0.0, -10.0))];
        let half = 0.5 * DVec3::new(4.0, 4.0, 24.0).length();
        assert!((focus_fallback(&sc, &bounds) as f64 - half).abs() < 1e-4);
        // Far away: the far plane.
        sc.objects = vec![at(DVec3::new(0.0, 0.0, -1e6))];
        assert_eq!(focus_fallback(&sc, &bounds), camera.far as f32);
    }

    #[test]
    fn every_tonemap_maps_zero_to_zero_and_is_monotonic() {
        for t in Tonemap::ALL {
            assert_eq!(t.apply([0.0; 3]), [0.0; 3], "{t:?}");
            // Along grey and along the exposure of coloured light (x times a colour), every
            // channel is non-decreasing. AgX's only exception: at its white point (2^4.026,
            // where the log encoding clamps one channel before the others) its outset matrix's
            // negative terms let the clamped channel fall by 1.8e-6 (seen) while the other two
            // still rise: 1/1000 of an 8-bit step, allowed as 1e-5.
            let slack = if t == Tonemap::Agx { 1e-5 } else { 1e-12 };
            for colour in [[1.0, 1.0, 1.0], [1.0, 0.2, 0.05], [0.1, 0.9, 0.3], [0.02, 0.05, 1.0]] {
                let mut last = [0.0f64; 3];
                for i in 1..=40000 {
                    let x = (i as f64 / 2000.0 - 12.0).exp2();
                    let v = t.apply(colour.map(|c| c * x));
                    for c in 0..3 {
                        assert!(v[c] >= last[c] - slack, "{t:?} {colour:?} at {x}: channel {c} {} < {}", v[c], last[c]);
                    }
                    last = v;
                }
            }
        }
    }

    #[test]
    fn the_identity_lut_parses_back_and_bad_files_are_errors() {
        let id = Lut::identity(3);
        let mut text = String::from("TITLE \"id\"\n# comment\nLUT_3D_SIZE 3\n");
        for e in &id.table {
            text += &format!("{} {} {}\n", e[0], e[1], e[2]);
        }
        assert_eq!(Lut::parse(&text).unwrap(), id);
        let cut: String = text.lines().take(10).collect::<Vec<_>>().join("\n");
        assert!(Lut::parse(&cut).unwrap_err().contains("needs 27 entries"));
        assert!(Lut::parse("LUT_3D_SIZE 1\n").unwrap_err().contains("not in 2"));
        assert!(Lut::parse("LUT_3D_SIZE 99999999999\n").unwrap_err().contains("whole number"));
        assert!(Lut::parse("0 0 0\n").unwrap_err().contains("before LUT_3D_SIZE"));
        assert!(Lut::parse("LUT_1D_SIZE 4\n").unwrap_err().contains("1D"));
        assert!(Lut::parse("LUT_3D_SIZE 2\n0 0\n").unwrap_err().contains("three numbers"));
        assert!(Lut::parse("LUT_3D_SIZE 2\n0 0 nan\n").unwrap_err().contains("not finite"));
        assert!(Lut::parse("LUT_3D_SIZE 2\n0 0 x\n").unwrap_err().contains("not a number"));
        assert!(Lut::parse("FOO 2\n").unwrap_err().contains("unknown keyword"));
        // A byte-order mark, and Resolve's input range.
        let cube = |head: &str| {
            let mut t = format!("{head}LUT_3D_SIZE 2\n");
            for i in 0..8 {
                t += &format!("{} {} {}\n", i & 1, (i >> 1) & 1, i >> 2);
            }
            t
        };
        assert_eq!(Lut::parse(&cube("\u{feff}")).map(|l| l.size), Ok(2));
        let l = Lut::parse(&cube("LUT_3D_INPUT_RANGE 0 2\n")).unwrap();
        assert_eq!((l.domain_min, l.domain_max), ([0.0; 3], [2.0; 3]));
        assert!(Lut::parse(&cube("LUT_3D_INPUT_RANGE 0\n")).unwrap_err().contains("two numbers"));
        assert!(Lut::parse("").unwrap_err().contains("no LUT_3D_SIZE"));
        assert!(Lut::parse(
            "DOMAIN_MIN 1 1 1\nLUT_3D_SIZE 2\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n"
        )
        .unwrap_err()
        .contains("must exceed"));
        assert!(Lut::load("/no/such/file.cube").unwrap_err().contains("cannot read"));
        // Arbitrary bytes never panic.
        for seed in 0..200u32 {
            let junk: String = (0..64)
                .map(|i| char::from(b" 0123456789.-eLUT_3DSIZE\n#"[((seed * 31 + i * 7) % 26) as usize]))
                .collect();
            let _ = Lut::parse(&junk);
        }
    }

    #[test]
    fn adaptation_moves_part_of_the_way_and_never_overshoots() {
        for speed in [1e-6, 0.1, 2.0, 60.0, 1e4] {
            let r = adapt_rate(speed);
            assert!(r > 0.0 && r <= 1.0, "{speed}: {r}");
        }
    }
}

/// The post chain of a frame: which effects ran (the tonemap always runs in the chain) and,
/// with auto-exposure, the exposure state after the frame is read by `Last::exposure_state`.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct PostStats {
    pub bloom: bool,
    pub auto_exposure: bool,
    pub tonemap: crate::renderer::post::Tonemap,
    /// The effects after tone mapping that ran, by name, in the chain's order
    /// (`post::effects::EFFECTS`).
    pub effects: Vec<String>,
}

impl PostStats {
    /// Whether effect `name` ran.
    pub fn ran(&self, name: &str) -> bool {
        self.effects.iter().any(|e| e == name)
    }
}
