//! Why each light did or did not reach one pixel of the last frame: the per-pixel half of the
//! light ledger. RenderDoc and PIX give a pixel's history by draw; in a tiled or clustered
//! frame a light has no draw of its own, so this answers by light.
//!
//! Two halves, each answering one question:
//! - **the shading** (`explain.wgsl`, on the GPU): every light of the frame shades the pixel's
//!   G-buffer surface exactly as the light pass and the tiled/clustered loop do, whatever the
//!   culling decided (brute force at one pixel), and says what it added and which test zeroed
//!   it: the culling mask, the range, the spot cone, the surface facing away, the shadow, a
//!   dark cookie;
//! - **the culling** (here, on the CPU, from the frame's plan): whether the frame's culling
//!   admitted the light to the pixel: the pixel's tile or cluster list (read back from the
//!   GPU), or the light's bounding volume along the pixel's ray against the surface's depth as
//!   the method's depth and stencil tests take it (the volume's back face behind the surface;
//!   with the stencil methods, the surface inside the volume), a full-screen draw, or skipped
//!   off screen.
//!
//! Put together: each light is `lit` (admitted and adding light), `wasted` (admitted, adding
//! nothing: the false positives of the culling, with the test that zeroed it) or `culled`
//! (not admitted and adding nothing); a light the culling did not admit but that would have
//! added light is `missed`, which no culling mode may do ("culling may only skip work, never
//! light"). The sum of what the admitted lights add is held against the pixel's accumulated
//! light: the rest is what the G-buffer pass wrote before any light (ambient, sun, and in seed
//! 000's one target the emission).

pub mod brute;
pub mod cost;
pub mod waste;

use super::kit::bindings;
use super::kit::Shared;
use super::plan::Method;
use glam::Vec3;
use serde::Serialize;

/// Lights a workgroup of `cs_explain` shades.
pub(crate) const WORKGROUP: u32 = 64;
/// vec4s `cs_explain` writes a light.
pub(crate) const WORDS: usize = 4;

pub struct ExplainPass {
    pub(crate) pipeline: crate::renderer::kit::ComputePipe,
    pub(crate) bgl: wgpu::BindGroupLayout,
}

impl ExplainPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let (pipeline, bgl) = compute_pipeline(device, shared, "explain", "cs_explain");
        Self { pipeline, bgl }
    }
}

/// A compute pipeline over the frame, the G-buffer and the explanation's group
/// (`bindings::EXPLAIN`: parameters in, results out), and that group's layout.
pub(super) fn compute_pipeline(
    device: &wgpu::Device,
    shared: &Shared,
    label: &str,
    entry: &str,
) -> (crate::renderer::kit::ComputePipe, wgpu::BindGroupLayout) {
    let bgl = bindings::EXPLAIN.layout(device);
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(&shared.frame_bgl), Some(&shared.gbuffer_bgl), Some(&bgl)],
        immediate_size: 0,
    });
    (crate::renderer::kit::compute_pipe(device, label, Some(&layout), &shared.module, entry), bgl)
}

/// What the frame's culling did with a light at the pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Culling {
    /// Drawn full screen: every pixel evaluates it.
    FullScreen,
    /// In the pixel's tile or cluster list.
    InList,
    /// Not in the pixel's tile or cluster list.
    NotInList,
    /// The bounding volume's back face lies behind the surface (the volume method's depth
    /// test passes): evaluated.
    VolumeDepthPassed,
    /// The surface lies inside the bounding volume (the stencil methods' mark and test pass):
    /// evaluated.
    InsideVolume,
    /// The pixel's ray misses the bounding volume: never rasterised there.
    VolumeMissed,
    /// The surface lies behind the volume's back face: the depth test rejects it.
    BehindVolume,
    /// The surface lies in front of the volume (stencil methods): the stencil test rejects it.
    InFrontOfVolume,
    /// `auto` left the light undrawn (its volume is off screen).
    Skipped,
}

impl Culling {
    /// Whether the frame evaluated the light at the pixel.
    pub fn admitted(self) -> bool {
        matches!(self, Culling::FullScreen | Culling::InList | Culling::VolumeDepthPassed | Culling::InsideVolume)
    }

    /// A short word for the viewer.
    pub fn word(self) -> &'static str {
        match self {
            Culling::FullScreen => "full screen",
            Culling::InList => "in list",
            Culling::NotInList => "not in list",
            Culling::VolumeDepthPassed => "depth passed",
            Culling::InsideVolume => "stencil passed",
            Culling::VolumeMissed => "volume missed",
            Culling::BehindVolume => "depth failed",
            Culling::InFrontOfVolume => "stencil failed",
            Culling::Skipped => "skipped",
        }
    }
}

/// The first of the shader's tests that zeroes a light at the pixel, in the order a reader
/// checks them, or `Lit`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Shading {
    Lit,
    /// The light's culling mask leaves out the surface's layer (seed 004).
    Mask,
    /// The surface lies at or beyond the light's radius.
    Range,
    /// Outside a spot's cone.
    Cone,
    /// The surface faces away from the light (N.L <= 0).
    FacingAway,
    /// In the light's shadow (factor 0).
    Shadowed,
    /// The cookie is black there.
    CookieDark,
}

/// One light at the pixel.
#[derive(Clone, Debug, Serialize)]
pub struct LightWhy {
    pub index: usize,
    /// "point" or "spot".
    pub kind: &'static str,
    /// How the frame shades the light (its culling method).
    pub method: Method,
    pub culling: Culling,
    pub shading: Shading,
    /// What it adds at the pixel, linear, after its clamp: diffuse (before the albedo) and
    /// specular; `lit` is diffuse x albedo + specular, the colour it adds.
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub lit: Vec3,
    /// Shadow factor (1 lit .. 0 shadowed; 1 without a shadow map), and whether the light has
    /// one this frame (`shadow_tile`: lit / shadowed / no tile).
    pub shadow: f32,
    pub shadow_tile: bool,
    /// The cookie's luminance at the pixel (1 without a cookie).
    pub cookie: f32,
    /// Distance over the light's radius, spot attenuation, N.L.
    pub distance_over_radius: f32,
    pub spot: f32,
    pub n_dot_l: f32,
    /// Admitted and adding nothing: evaluated for nothing.
    pub wasted: bool,
    /// Not admitted but would have added light: light the culling dropped.
    pub missed: bool,
}

impl LightWhy {
    /// Whether the light adds anything at the pixel.
    pub fn contributes(&self) -> bool {
        self.diffuse.max_element() > 0.0 || self.specular.max_element() > 0.0
    }
}

/// The pixel's tile or cluster.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    pub index: usize,
    /// Lights in its list.
    pub lights: usize,
}

/// Why each light did or did not light pixel (`x`, `y`).
#[derive(Clone, Debug, Serialize)]
pub struct Explanation {
    pub x: u32,
    pub y: u32,
    /// False where no surface was drawn (background: nothing is lit).
    pub valid: bool,
    pub culling_mode: String,
    pub path: String,
    /// View-space position of the surface.
    pub position: Vec3,
    pub cell: Option<Cell>,
    /// The pixel's accumulated light as the targets hold it (decoded): diffuse and specular,
    /// or (seed 000's one target) the lit colour in `diffuse` and zero specular.
    pub accumulated_diffuse: Vec3,
    pub accumulated_specular: Vec3,
    /// The same for the sum of what the admitted lights add (`one_target`: their lit colours).
    pub lights_diffuse: Vec3,
    pub lights_specular: Vec3,
    /// Accumulated less the lights: what the G-buffer pass wrote before them (ambient, sun,
    /// seed 000's emission).
    pub rest_diffuse: Vec3,
    pub rest_specular: Vec3,
    /// The accumulation holds the lit colour in one target (seed 000).
    pub one_target: bool,
    /// The light pre-pass's light buffer (seed 003): `accumulated_diffuse` its RGB, the
    /// diffuse light with unit reflectance, `accumulated_specular` its A (the specular light's
    /// luminance, with unit reflectance) in every channel; the lights' sums likewise.
    pub prepass: bool,
    /// Every light whose screen bounds cover the pixel, or that the culling admitted, or that
    /// adds light; by contribution, largest first.
    pub lights: Vec<LightWhy>,
    /// Admitted, adding nothing (the culling's false positives at this pixel).
    pub wasted: usize,
    /// Adding light but not admitted: must be 0.
    pub missed: usize,
}

/// The luminance weights of the light pre-pass's mono specular (`LS_LUMINANCE`).
pub(crate) fn luminance() -> Vec3 {
    let [r, g, b] = crate::scene::LUMINANCE.map(|w| w as f32);
    Vec3::new(r, g, b)
}

/// (t_in, t_out) of the ray t x `dir` (t > 0, from the eye) through a convex volume given as
/// (point, outward normal) faces; `None` when it misses.
pub(crate) fn ray_interval(faces: &[(Vec3, Vec3)], dir: Vec3) -> Option<(f32, f32)> {
    let (mut t_in, mut t_out) = (0.0f32, f32::INFINITY);
    for &(a, n) in faces {
        if n == Vec3::ZERO {
            continue;
        }
        // Inside: (t dir - a) . n <= 0, i.e. t (dir . n) <= a . n.
        let (dn, an) = (dir.dot(n), a.dot(n));
        if dn.abs() < 1e-12 {
            if an < 0.0 {
                return None;
            }
        } else if dn > 0.0 {
            t_out = t_out.min(an / dn);
        } else {
            t_in = t_in.max(an / dn);
        }
    }
    (t_in <= t_out).then_some((t_in, t_out))
}

/// What the culling method `method` does at a surface `t_s` along the pixel's ray, for the
/// volume's interval `interval` along it; the stencil methods draw a volume crossing the near
/// plane (`crosses_near`) as a plain volume (`methods::CROSSING_NEAR`). A relative 1e-4 of slack at the faces: the rasteriser's depth and
/// the mesh's may differ by rounding there.
pub(crate) fn volume_culling(method: Method, interval: Option<(f32, f32)>, t_s: f32, crosses_near: bool) -> Culling {
    let Some((t_in, t_out)) = interval else { return Culling::VolumeMissed };
    let eps = 1e-4 * t_s.max(1e-6);
    if t_s > t_out + eps {
        return Culling::BehindVolume;
    }
    if method == Method::Volume || crosses_near {
        return Culling::VolumeDepthPassed;
    }
    if t_s + eps < t_in {
        return Culling::InFrontOfVolume;
    }
    Culling::InsideVolume
}

/// The first test that zeroes a light, in `shade_light_view`'s terms: the mask, then
/// distance / radius < 1, spot attenuation > 0, N.L > 0, shadow > 0, cookie > 0. A NaN fails
/// its test, as in the shader (`!(x > 0)`).
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub(crate) fn shading_of(reaches: bool, dr: f32, spot: f32, ndl: f32, shadow: f32, cookie: f32) -> Shading {
    if !reaches {
        Shading::Mask
    } else if !(dr < 1.0) {
        Shading::Range
    } else if !(spot > 0.0) {
        Shading::Cone
    } else if !(ndl > 0.0) {
        Shading::FacingAway
    } else if !(shadow > 0.0) {
        Shading::Shadowed
    } else if !(cookie > 0.0) {
        Shading::CookieDark
    } else {
        Shading::Lit
    }
}

/// The explanation as a plain-text table: the pixel, its cell, the accumulated light against
/// the admitted lights' sum and the rest, then one row a light.
pub fn table(e: &Explanation) -> String {
    use std::fmt::Write;
    let v = |v: Vec3| format!("({:.4}, {:.4}, {:.4})", v.x, v.y, v.z);
    let mut s = String::new();
    let _ = writeln!(s, "pixel {},{} ({} path, {} culling):", e.x, e.y, e.path, e.culling_mode);
    if !e.valid {
        let _ = writeln!(s, "  background: no surface, no light");
        return s;
    }
    if let Some(c) = &e.cell {
        let _ = writeln!(s, "  cell {} holds {} lights", c.index, c.lights);
    }
    let (what, d) = match (e.one_target, e.prepass) {
        (true, _) => ("lit colour", ""),
        (false, true) => ("light buffer: diffuse", " specular (luminance)"),
        (false, false) => ("diffuse", " specular"),
    };
    let _ = writeln!(
        s,
        "  accumulated {what} {}{d} {}",
        v(e.accumulated_diffuse),
        if e.one_target { String::new() } else { v(e.accumulated_specular) }
    );
    let _ = writeln!(
        s,
        "  lights add  {what} {}{d} {}",
        v(e.lights_diffuse),
        if e.one_target { String::new() } else { v(e.lights_specular) }
    );
    let _ = writeln!(s, "  rest (ambient, sun{}) {}", if e.one_target { ", emission" } else { "" }, v(e.rest_diffuse));
    let _ = writeln!(s, "  {} lights listed, {} wasted, {} missed", e.lights.len(), e.wasted, e.missed);
    let _ = writeln!(
        s,
        "  {:>6} {:5} {:16} {:15} {:11} {:>28} {:>6} {:>6}",
        "light", "kind", "method", "culling", "shading", "adds (lit colour)", "d/r", "shadow"
    );
    for l in &e.lights {
        let flag = if l.missed {
            "  MISSED"
        } else if l.wasted {
            "  wasted"
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "  {:>6} {:5} {:16} {:15} {:11} {:>28} {:>6.3} {:>6.3}{flag}",
            l.index,
            l.kind,
            l.method.name(),
            l.culling.word(),
            format!("{:?}", l.shading).to_lowercase(),
            v(l.lit),
            l.distance_over_radius,
            l.shadow
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube around (0, 0, -5): the ray down -z enters at 4 and leaves at 6; each method's
    /// verdict for surfaces in front of, inside and behind it; a ray beside it misses.
    #[test]
    fn the_volume_tests_follow_each_methods_depth_and_stencil_rule() {
        let c = Vec3::new(0.0, 0.0, -5.0);
        let faces: Vec<(Vec3, Vec3)> =
            [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z].iter().map(|&n| (c + n, n)).collect();
        let hit = ray_interval(&faces, Vec3::NEG_Z).expect("the ray hits the cube");
        assert!((hit.0 - 4.0).abs() < 1e-6 && (hit.1 - 6.0).abs() < 1e-6, "{hit:?}");
        assert_eq!(ray_interval(&faces, Vec3::new(0.5, 0.0, -1.0).normalize()), None);
        // The eye inside: the interval starts at the eye.
        let around: Vec<(Vec3, Vec3)> = faces.iter().map(|&(a, n)| (a - c, n)).collect();
        assert_eq!(ray_interval(&around, Vec3::NEG_Z), Some((0.0, 1.0)));
        use Culling as C;
        for (t_s, volume, stencil) in [
            (3.0, C::VolumeDepthPassed, C::InFrontOfVolume),
            (5.0, C::VolumeDepthPassed, C::InsideVolume),
            (7.0, C::BehindVolume, C::BehindVolume),
        ] {
            assert_eq!(volume_culling(Method::Volume, Some(hit), t_s, false), volume, "volume at {t_s}");
            for m in [Method::StencilTwoPass, Method::StencilInvert, Method::StencilReplace] {
                assert_eq!(volume_culling(m, Some(hit), t_s, false), stencil, "{m:?} at {t_s}");
            }
            // Crossing the near plane, every method draws a plain volume.
            for m in [Method::Volume, Method::StencilTwoPass, Method::StencilInvert, Method::StencilReplace] {
                assert_eq!(volume_culling(m, Some(hit), t_s, true), volume, "{m:?} at {t_s}, crossing near");
            }
        }
        assert_eq!(volume_culling(Method::Volume, None, 5.0, false), C::VolumeMissed);
        assert_eq!(volume_culling(Method::Volume, None, 5.0, true), C::VolumeMissed);
        assert!(C::VolumeDepthPassed.admitted() && C::InsideVolume.admitted() && !C::BehindVolume.admitted());
    }

    /// Each test in turn zeroes the light; the first failing one is named; NaN fails.
    #[test]
    fn the_first_test_that_zeroes_a_light_is_named() {
        use Shading as S;
        assert_eq!(shading_of(true, 0.5, 1.0, 0.5, 1.0, 1.0), S::Lit);
        assert_eq!(shading_of(false, 2.0, 0.0, -1.0, 0.0, 0.0), S::Mask);
        assert_eq!(shading_of(true, 1.0, 0.0, -1.0, 0.0, 0.0), S::Range);
        assert_eq!(shading_of(true, 0.5, 0.0, -1.0, 0.0, 0.0), S::Cone);
        assert_eq!(shading_of(true, 0.5, 1.0, 0.0, 0.0, 0.0), S::FacingAway);
        assert_eq!(shading_of(true, 0.5, 1.0, 0.5, 0.0, 0.0), S::Shadowed);
        assert_eq!(shading_of(true, 0.5, 1.0, 0.5, 0.3, 0.0), S::CookieDark);
        assert_eq!(shading_of(true, f32::NAN, 1.0, 0.5, 1.0, 1.0), S::Range);
        assert_eq!(shading_of(true, 0.5, 1.0, f32::NAN, 1.0, 1.0), S::FacingAway);
    }
}
