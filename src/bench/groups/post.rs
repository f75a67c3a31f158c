//! The `post` group: the post chain, one effect at a time, then all of them.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::post::{Aa, Tonemap};
use crate::renderer::Settings;

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    // The post chain, one effect at a time, then all of them; the light error is of
    // the accumulation, before post, so it is the `volume` row's in every one of these.
    let mut p = vec![
        ("post off", base.clone()),
        ("bloom", Settings { bloom: true, ..base.clone() }),
        ("auto-exposure", Settings { auto_exposure: true, ..base.clone() }),
    ];
    let curves: &[Tonemap] = if q { &[Tonemap::Agx] } else { &Tonemap::ALL };
    p.extend(curves.iter().map(|&t| {
        let label: &'static str = match t {
            Tonemap::Aces => "tonemap aces (chain)",
            Tonemap::Reinhard => "tonemap reinhard",
            Tonemap::Agx => "tonemap agx",
            Tonemap::PbrNeutral => "tonemap pbr-neutral",
            Tonemap::None => "tonemap none",
        };
        // ACES alone is compose's own curve; the identity LUT takes it through the chain.
        let lut = (t == Tonemap::Aces).then(|| "identity".to_string());
        (label, Settings { tonemap: t, lut, ..base.clone() })
    }));
    p.push(("lut identity", Settings { lut: Some("identity".into()), tonemap: Tonemap::Agx, ..base.clone() }));
    // After tone mapping (AgX, so the chain runs for the curve alone in `tonemap agx`).
    let ldr = Settings { tonemap: Tonemap::Agx, ..base.clone() };
    p.push(("fog", Settings { fog: true, ..ldr.clone() }));
    p.push(("dof", Settings { dof: true, ..ldr.clone() }));
    p.push(("vignette", Settings { vignette: 0.5, ..ldr.clone() }));
    // Seed 002's distortion: its buffer's draws (the scene's distorting materials; none on
    // most scenes, `glass` has them) and the effect's pass.
    p.push(("distortion", Settings { distortion: true, ..ldr.clone() }));
    p.push(("aa edge", Settings { aa: Aa::Edge, ..ldr.clone() }));
    p.push(("aa fxaa", Settings { aa: Aa::Fxaa, ..ldr.clone() }));
    p.push((
        "all on",
        Settings {
            bloom: true,
            auto_exposure: true,
            lut: Some("identity".into()),
            fog: true,
            dof: true,
            vignette: 0.5,
            aa: Aa::Edge,
            ..ldr.clone()
        },
    ));
    p.into_iter().map(|(label, settings)| s.row("post", label.into(), settings, o.lights)).collect()
}
