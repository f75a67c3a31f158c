//! The lighting model again, on the CPU in f64: checks the GPU shader's arithmetic at sampled
//! pixels, from the same G-buffer inputs the shader read (see `Last::probe`). It mirrors
//! `shade_light` and `fs_ambient` in the WGSL line for line; lights come from the scene in f64.
//! Each reflectance model (`Brdf`, the pixel's material ID) has its twin here: `brdf_light`,
//! `ambient_diffuse`, `ambient_specular`.

// `!(a < b)` is the WGSL's NaN-safe test, mirrored as it is written there.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::renderer::PixelProbe;
pub use crate::scene::occluders::Occluders;
use crate::scene::{Brdf, Light, Scene};
use glam::DVec3;

/// The surface a probe decoded, in f64: what the models read.
struct Surface {
    brdf: Brdf,
    albedo: DVec3,
    normal: DVec3,
    view: DVec3,
    spec_level: f64,
    spec_exp: f64,
    /// How close the toon model's steps came to flipping: the least distance of 3 N.L to a
    /// whole number and of the lobe to 0.5 over the terms evaluated (infinite for the others).
    toon_margin: std::cell::Cell<f64>,
}

/// The twin of `brdf_light` (WGSL): one light of colour `color` and attenuation `att` from
/// direction `l` with N.L = `ndl`; (diffuse before albedo, specular).
fn brdf_light(s: &Surface, l: DVec3, ndl: f64, color: DVec3, att: f64) -> (DVec3, DVec3) {
    if ndl <= 0.0 || s.brdf == Brdf::Unlit {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    if s.brdf == Brdf::Lambert {
        return (color * (att * ndl), DVec3::ZERO);
    }
    if s.brdf == Brdf::Phong {
        // R = reflect(-L, N) = 2 (N.L) N - L.
        let r = s.normal * (2.0 * s.normal.dot(l)) - l;
        let lobe = r.dot(s.view).max(0.0).powf(s.spec_exp);
        return (color * (att * ndl), color * (att * (lobe * s.spec_level)));
    }
    let h = safe_normalize(l + s.view, s.normal);
    let lobe = s.normal.dot(h).max(0.0).powf(s.spec_exp);
    match s.brdf {
        Brdf::Metal => (DVec3::ZERO, color * (att * ndl * lobe * s.spec_level) * s.albedo),
        Brdf::Toon => {
            let band = ((ndl * 3.0) - (ndl * 3.0).round()).abs();
            s.toon_margin.set(s.toon_margin.get().min(band).min((lobe - 0.5).abs()));
            (color * (att * (ndl * 3.0).ceil() / 3.0), color * (att * if lobe >= 0.5 { s.spec_level } else { 0.0 }))
        }
        _ => (color * (att * ndl), color * (att * ndl * lobe * s.spec_level)),
    }
}

/// The twin of `ls_cookie`: the factor on `light`'s colour at the point `v` from it (view
/// space; `rot` turns world into view), bilinear and clamp-to-edge as the shader filters.
/// 1 without a cookie.
pub fn cookie(scene: &Scene, light: &Light, v: DVec3, rot: glam::DMat3) -> DVec3 {
    let Some(image) = light.cookie().and_then(|c| scene.cookies.get(c as usize)) else {
        return DVec3::ONE;
    };
    match light {
        Light::Spot(s) => {
            let dir = (rot * s.direction.as_dvec3()).normalize();
            let up = rot * crate::scene::cookie::spot_up(s.direction.as_dvec3());
            match crate::scene::cookie::spot_uv(v, dir, up, (s.outer_angle as f64).tan()) {
                Some(uv) => image.sample(0, uv),
                None => DVec3::ZERO,
            }
        }
        Light::Point(_) => {
            let (face, uv) = crate::scene::cookie::cube_face_uv(rot.transpose() * v);
            image.sample(face, uv)
        }
    }
}

/// The twin of `ambient_diffuse`: ambient, none for a metal, 1 for unlit.
fn ambient_diffuse(s: &Surface, ambient: DVec3) -> DVec3 {
    match s.brdf {
        Brdf::Metal => DVec3::ZERO,
        Brdf::Unlit => DVec3::ONE,
        _ => ambient,
    }
}

/// The twin of `ambient_specular`: the normalised lobe integrates to f0 = level x 8 / (n + 8);
/// tinted for a metal, none for lambert and unlit.
fn ambient_specular(s: &Surface, ambient: DVec3) -> DVec3 {
    let a = ambient * (s.spec_level * 8.0 / (s.spec_exp + 8.0));
    match s.brdf {
        Brdf::Lambert | Brdf::Unlit => DVec3::ZERO,
        Brdf::Metal => a * s.albedo,
        _ => a,
    }
}

fn safe_normalize(v: DVec3, fallback: DVec3) -> DVec3 {
    let l2 = v.length_squared();
    if !(l2 > 1e-20) || l2 > 1e30 {
        fallback
    } else {
        v / l2.sqrt()
    }
}

/// Where a light reaches a view-space point `pos` of normal `n`: its world position, the unit
/// direction to it (view space; `n` at the light itself), its attenuation (the windowed falloff
/// (1 - (d/r)²)², times the spot's smoothstep cone) and its colour times intensity.
struct Reach {
    lp: DVec3,
    l: DVec3,
    att: f64,
    color: DVec3,
}

/// [`Reach`] of `light` at `pos`, or `None` beyond its radius.
/// `rot` is the camera's rotation (world to view).
fn reach(light: &Light, cam: &crate::scene::Camera, rot: glam::DMat3, pos: DVec3, n: DVec3) -> Option<Reach> {
    let (lp, radius, color, spot) = match light {
        Light::Point(l) => (l.position, l.radius as f64, (l.color * l.intensity).as_dvec3(), None),
        Light::Spot(s) => (
            s.position,
            s.radius as f64,
            (s.color * s.intensity).as_dvec3(),
            Some(((rot * s.direction.as_dvec3()).normalize(), s.outer_angle as f64, s.inner_angle as f64)),
        ),
    };
    let to_light = cam.to_view(lp) - pos;
    let d = to_light.length();
    if !(d < radius) {
        return None;
    }
    let l = if d > 1e-6 * radius { to_light / d } else { n };
    let x = d / radius;
    let w = (1.0 - x * x).clamp(0.0, 1.0);
    let mut att = w * w;
    if let Some((dir, outer, inner)) = spot {
        let (co, ci) = (outer.cos(), inner.cos());
        let c = (-l).dot(dir);
        att *= if ci - co < 1e-6 { f64::from(u8::from(c >= co)) } else { smoothstep(co, ci, c) };
    }
    Some(Reach { lp, l, att, color })
}

fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// What ambient + sun and each light may add to a channel at most: the renderer's fp16 clamp
/// (`overlap::clamps`), or none.
#[derive(Clone, Debug, PartialEq)]
pub struct Clamps {
    pub ambient: f64,
    /// One per scene light, in scene order.
    pub lights: Vec<f64>,
}

impl Clamps {
    /// No clamp: the lighting model's own values.
    pub fn none(lights: usize) -> Self {
        Self { ambient: f64::INFINITY, lights: vec![f64::INFINITY; lights] }
    }

    /// The clamps the renderer's last frame applied (`Last::light_clamps`).
    pub fn of(renderer: &crate::renderer::Renderer) -> Self {
        let (ambient, lights) = renderer.last_frame().light_clamps();
        Self { ambient: ambient as f64, lights: lights.into_iter().map(f64::from).collect() }
    }
}

/// Diffuse and specular light (before albedo) at a probed pixel: ambient + sun + every light,
/// each term clamped as the shader clamps it (`clamp.ambient`, `clamp.lights[i]`; a light
/// without an entry is not clamped).
pub fn shade(scene: &Scene, p: &PixelProbe, clamp: &Clamps) -> (DVec3, DVec3) {
    let (d, s, _) = shade_with_margin(scene, p, clamp);
    (d, s)
}

/// [`shade`], and how close a `toon` pixel came to one of its steps (see `Surface::toon_margin`;
/// infinite for the other models): within f32 rounding of a step the GPU may take the other
/// side, so a comparison skips such pixels.
pub fn shade_with_margin(scene: &Scene, p: &PixelProbe, clamp: &Clamps) -> (DVec3, DVec3, f64) {
    if !p.valid {
        return (DVec3::ZERO, DVec3::ZERO, f64::INFINITY);
    }
    let cam = &scene.camera;
    let rot = cam.rotation();
    let n = p.normal.as_dvec3();
    let pos = p.position.as_dvec3();
    let s = Surface {
        brdf: p.brdf,
        albedo: p.albedo.as_dvec3(),
        normal: n,
        view: safe_normalize(-pos, DVec3::Z),
        spec_level: p.specular_level as f64,
        spec_exp: p.specular_exponent as f64,
        toon_margin: std::cell::Cell::new(f64::INFINITY),
    };
    let ambient = scene.ambient.as_dvec3();
    let mut diffuse = ambient_diffuse(&s, ambient);
    let mut specular = ambient_specular(&s, ambient);
    if let Some(sun) = scene.sun {
        let l = (rot * (-sun.direction.as_dvec3())).normalize();
        let c = (sun.color * sun.intensity).as_dvec3();
        let (d, sp) = brdf_light(&s, l, n.dot(l).max(0.0), c, 1.0);
        diffuse += d;
        specular += sp;
    }
    // `ambient_limit`: an unlit surface's 1 is never clamped below 1.
    let ambient_limit = if s.brdf == Brdf::Unlit { clamp.ambient.max(1.0) } else { clamp.ambient };
    diffuse = diffuse.min(DVec3::splat(ambient_limit));
    specular = specular.min(DVec3::splat(ambient_limit));
    for (i, light) in scene.lights.iter().enumerate() {
        // Seed 004's culling mask (`ls_light_reaches`).
        if light.mask() & (1u32 << (p.layer & 31)) == 0 {
            continue;
        }
        let limit = DVec3::splat(clamp.lights.get(i).copied().unwrap_or(f64::INFINITY));
        let Some(Reach { lp, l, att, color }) = reach(light, cam, rot, pos, n) else { continue };
        let ndl = n.dot(l).max(0.0);
        if att <= 0.0 || ndl <= 0.0 {
            continue;
        }
        let color = color * cookie(scene, light, pos - cam.to_view(lp), rot);
        let (d, sp) = brdf_light(&s, l, ndl, color, att);
        diffuse += d.min(limit);
        specular += sp.min(limit);
    }
    (diffuse, specular, s.toon_margin.get())
}

/// The light pre-pass's (`--path light-prepass`) lit colour at a probed pixel, enclosed: the
/// f64 twin of its three passes (`fs_light` under `LS_PREPASS`, `prepass_light`,
/// `prepass_shade`) evaluated on the probe's exact surface, with every term widened to what
/// the pre-pass's stored inputs can make of it. Returns (lo, hi), linear, before exposure.
///
/// Derivation. The pre-pass differs from deferred shading of the same surface in three ways:
/// 1. Its normal is stored in 8 bits per component: the normal it shades with is within
///    `normal_error` (radians; `asin(sqrt(3) / 255)` = 0.389 degrees,
///    `gbuffer::prepass_layout`) of the true one. By the triangle inequality on the sphere the
///    angle to L (and to H, which does not depend on N) moves by at most that much: N.L lies
///    in [cos(min(t_l + e, 90 deg)), cos(max(t_l - e, 0))], N.H likewise.
/// 2. Its exponent is stored as log2(n) / 11 in 8 bits: the one it shades with lies in
///    [n / `exp_ratio`, n x `exp_ratio`] (ratio 2^(11/510)), clamped to [1, 2048]. The lobe
///    cos^n falls as n grows, the unit level (n + 8) / 8 rises: each factor's range is taken at
///    the matching end.
/// 3. Its specular is one number, the luminance M of the sum of every light's specular with
///    unit reflectance, coloured in pass 3 by the diffuse light's chromaticity D / lum(D). With
///    D's channels in [Dlo, Dhi], D_c / lum(D) = D_c / (w_c D_c + sum_(k != c) w_k D_k) rises with
///    D_c and falls with the others: its range is [Dlo_c / (w_c Dlo_c + sum w_k Dhi_k),
///    Dhi_c / (w_c Dhi_c + sum w_k Dlo_k)]; the GPU takes white where lum(D) <= 1e-6.
///
/// Every factor is non-negative and each product and sum is monotone in its factors, so the
/// products of the ends enclose the pre-pass's value (the per-light clamps are monotone too).
/// The sun goes through the light buffer as a light (seeds 003/004: directional lights are
/// full-screen quads in the lighting pass): the same three widenings, with attenuation 1 and
/// the ambient clamp. Ambient and emission are evaluated in pass 3 from the material itself,
/// as deferred evaluates them from its G-buffer (exactly, with the `reference` layout), so
/// they add no width. What remains is f32 arithmetic and the HDR target's fp16 rounding,
/// which the caller allows for.
pub fn prepass_enclosure(
    scene: &Scene,
    p: &PixelProbe,
    clamp: &Clamps,
    normal_error: f64,
    exp_ratio: f64,
) -> (DVec3, DVec3) {
    const LUM: DVec3 = DVec3::from_array(crate::scene::LUMINANCE);
    if !p.valid {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    let cam = &scene.camera;
    let rot = cam.rotation();
    let n = p.normal.as_dvec3();
    let pos = p.position.as_dvec3();
    let view = safe_normalize(-pos, DVec3::Z);
    let s = Surface {
        brdf: p.brdf,
        albedo: p.albedo.as_dvec3(),
        normal: n,
        view,
        spec_level: p.specular_level as f64,
        spec_exp: p.specular_exponent as f64,
        toon_margin: std::cell::Cell::new(f64::INFINITY),
    };
    // Ambient: pass 3, from the material (the same values deferred computes).
    let ambient = scene.ambient.as_dvec3();
    let ambient_limit = if s.brdf == Brdf::Unlit { clamp.ambient.max(1.0) } else { clamp.ambient };
    let amb_d = ambient_diffuse(&s, ambient).min(DVec3::splat(ambient_limit));
    let amb_s = ambient_specular(&s, ambient).min(DVec3::splat(ambient_limit));
    // Pass 2: every light, Blinn-Phong with unit reflectance, on the stored normal/exponent.
    let e = normal_error;
    let exp_lo = (s.spec_exp / exp_ratio).clamp(1.0, 2048.0);
    let exp_hi = (s.spec_exp * exp_ratio).clamp(1.0, 2048.0);
    let angle = |v: DVec3| n.dot(v).clamp(-1.0, 1.0).acos();
    let cos_range = |t: f64| {
        let half_pi = std::f64::consts::FRAC_PI_2;
        ((t + e).min(half_pi).cos().max(0.0), (t - e).max(0.0).min(half_pi).cos().max(0.0))
    };
    let (mut d_lo, mut d_hi, mut m_lo, mut m_hi) = (DVec3::ZERO, DVec3::ZERO, 0.0, 0.0);
    // The sun first (the pass that starts the buffer; the thin buffer's one model is
    // Blinn-Phong, so its clamp is the ambient one), then every light.
    let sun = scene.sun.map(|sun| {
        let l = (rot * (-sun.direction.as_dvec3())).normalize();
        (l, 1.0, (sun.color * sun.intensity).as_dvec3(), DVec3::splat(clamp.ambient))
    });
    let lights = scene.lights.iter().enumerate().filter_map(|(i, light)| {
        let limit = DVec3::splat(clamp.lights.get(i).copied().unwrap_or(f64::INFINITY));
        reach(light, cam, rot, pos, n).map(|Reach { l, att, color, .. }| (l, att, color, limit))
    });
    for (l, att, color, limit) in sun.into_iter().chain(lights) {
        if att <= 0.0 {
            continue;
        }
        let (ndl_lo, ndl_hi) = cos_range(angle(l));
        let (nh_lo, nh_hi) = cos_range(angle(safe_normalize(l + view, n)));
        let (lobe_lo, lobe_hi) = (nh_lo.powf(exp_hi), nh_hi.powf(exp_lo));
        let (lev_lo, lev_hi) = ((exp_lo + 8.0) / 8.0, (exp_hi + 8.0) / 8.0);
        d_lo += (color * (att * ndl_lo)).min(limit);
        d_hi += (color * (att * ndl_hi)).min(limit);
        m_lo += (color * (att * ndl_lo * lobe_lo * lev_lo)).min(limit).dot(LUM);
        m_hi += (color * (att * ndl_hi * lobe_hi * lev_hi)).min(limit).dot(LUM);
    }
    // Pass 3 reads the buffer through `finite` (fp16's largest value; deferred's compose does
    // the same), then colours the specular with the diffuse light's chromaticity.
    let top = crate::renderer::records::FP16_MAX as f64;
    (d_lo, d_hi, m_lo, m_hi) = (d_lo.min(DVec3::splat(top)), d_hi.min(DVec3::splat(top)), m_lo.min(top), m_hi.min(top));
    let mut chroma_lo = DVec3::ZERO;
    let mut chroma_hi = DVec3::ZERO;
    for c in 0..3 {
        let others = |v: DVec3| (0..3).filter(|&k| k != c).map(|k| LUM[k] * v[k]).sum::<f64>();
        let den_lo = LUM[c] * d_lo[c] + others(d_hi);
        let den_hi = LUM[c] * d_hi[c] + others(d_lo);
        chroma_lo[c] = if den_lo > 0.0 { d_lo[c] / den_lo } else { 0.0 };
        chroma_hi[c] = if den_hi > 0.0 { d_hi[c] / den_hi } else { 1.0 / LUM[c] };
    }
    if d_lo.dot(LUM) <= 1e-6 {
        // The GPU's white where lum(D) is (near) zero.
        chroma_lo = chroma_lo.min(DVec3::ONE);
        chroma_hi = chroma_hi.max(DVec3::ONE);
    }
    let f0 = s.spec_level * 8.0 / (s.spec_exp + 8.0);
    let (mut spec_lo, mut spec_hi) = (chroma_lo * (m_lo * f0), chroma_hi * (m_hi * f0));
    match s.brdf {
        Brdf::Lambert => (spec_lo, spec_hi) = (DVec3::ZERO, DVec3::ZERO),
        Brdf::Unlit => (d_lo, d_hi, spec_lo, spec_hi) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO),
        Brdf::Metal => {
            (d_lo, d_hi) = (DVec3::ZERO, DVec3::ZERO);
            (spec_lo, spec_hi) = (spec_lo * s.albedo, spec_hi * s.albedo);
        }
        _ => {}
    }
    let emissive = p.emissive.as_dvec3();
    // `prepass_shade` writes at most fp16's largest value.
    let lit = |d: DVec3, sp: DVec3| ((d + amb_d) * s.albedo + sp + amb_s + emissive).min(DVec3::splat(top));
    (lit(d_lo, spec_lo), lit(d_hi, spec_hi))
}
