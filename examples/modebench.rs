//! GPU medians of a few culling modes on a built-in scene at 1280x720, timed in interleaved
//! rounds as the bench times them (uncounted frames; the pairs come from one counted frame
//! first): `cargo run --release --example modebench [LIGHTS [ROUNDS [MODE ...]]]`, default
//! 1,024 lights, 7 rounds, `clustered stencil-replace volume`. Unshadowed like the bench;
//! `MODEBENCH_SHADOWS=MODE` renders with `--shadows MODE` (`spots`, the default's sun and
//! spots, as the viewer draws `demo`); `MODEBENCH_SCENE=NAME` picks another built-in scene
//! (default `demo`).

use lampshade::headless::render_image;
use lampshade::renderer::{CullingMode, Renderer, Settings, ShadowMode, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn fail(msg: &str) -> ! {
    eprintln!("modebench: {msg}\nusage: modebench [LIGHTS [ROUNDS [MODE ...]]]");
    std::process::exit(2);
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let number = |k: usize, default: usize| match args.get(k).map(|s| s.parse::<usize>()) {
        None => default,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => fail(&format!("'{}' is not a positive count", args[k])),
    };
    let (lights, rounds) = (number(1, 1024), number(2, 7));
    let names: Vec<String> = if args.len() > 3 {
        args[3..].to_vec()
    } else {
        ["clustered", "stencil-replace", "volume"].map(String::from).to_vec()
    };
    let modes: Vec<CullingMode> = names.iter().map(|m| CullingMode::parse(m).unwrap_or_else(|e| fail(&e))).collect();
    let shadows = match std::env::var("MODEBENCH_SHADOWS") {
        Ok(v) => ShadowMode::parse(&v).unwrap_or_else(|e| fail(&format!("MODEBENCH_SHADOWS: {e}"))),
        Err(_) => ShadowMode::None,
    };
    let name = std::env::var("MODEBENCH_SCENE").unwrap_or_else(|_| "demo".into());
    let scene = builtin::build(&name, BuiltinOptions { lights: Some(lights), time: 0.0 }).unwrap_or_else(|e| fail(&e));
    let gpu = lampshade::Gpu::headless().unwrap_or_else(|e| fail(&format!("no GPU adapter: {e:#}")));
    let (w, h) = (1280, 720);
    let mut prepared = Vec::new();
    for m in modes {
        let s = Settings { culling: m, count_fragments: false, timestamps: true, shadows, ..Settings::default() };
        let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &s).unwrap_or_else(|e| fail(&format!("{e:#}")));
        let counted = Settings { count_fragments: true, ..s.clone() };
        let frame = |r: &mut Renderer, s: &Settings| {
            render_image(&gpu, r, &scene, s, w, h).unwrap_or_else(|e| fail(&format!("{e:#}"))).1
        };
        let pairs = frame(&mut r, &counted).shaded_fragments;
        frame(&mut r, &s);
        prepared.push((m, s, r, Vec::new(), pairs));
    }
    for _ in 0..rounds {
        for (_, s, r, times, _) in prepared.iter_mut() {
            let (_, st) = render_image(&gpu, r, &scene, s, w, h).unwrap_or_else(|e| fail(&format!("{e:#}")));
            times.push(st.gpu_ms);
        }
    }
    println!(
        "{name}, {} lights, 1280x720, shadows {}, {rounds} interleaved rounds, GPU ms medians",
        scene.lights.len(),
        shadows.name()
    );
    println!("| mode | G-buffer | lighting | compose | total | shaded pairs |");
    println!("|---|---|---|---|---|---|");
    for (m, _, _, t, pairs) in &prepared {
        let of = |f: fn(&lampshade::renderer::stats::GpuMs) -> Option<f64>| median(t.iter().filter_map(f).collect());
        println!(
            "| {} | {:.1} | {:.1} | {:.1} | {:.1} | {} |",
            m.name(),
            of(|g| g.gbuffer),
            of(|g| g.lighting),
            of(|g| g.compose),
            of(|g| g.total),
            pairs.map_or("-".to_string(), |p| p.to_string())
        );
    }
}
