//! What the material ID costs: the same scene with its materials' own reflectance models (the
//! ID channel, a branch per pixel on it) against every object forced to `blinn-phong` (one
//! model: a WGSL constant, no channel), interleaved rounds at 1280x720, median GPU ms per pass.
//! Scenes: `materials` (9 lights) and `demo` (1024 lights) with its materials dealt the five
//! models in turn. `cargo run --release --example brdfbench [ROUNDS]`.

use lampshade::headless::render_image;
use lampshade::renderer::{BrdfOverride, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::scene::Brdf;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let gpu = match lampshade::Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("no GPU adapter: {e:#}");
            std::process::exit(1);
        }
    };
    let rounds = match std::env::args().nth(1).map(|s| s.parse::<usize>()) {
        None => 7,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("usage: brdfbench [ROUNDS]");
            std::process::exit(2);
        }
    };
    let (w, h) = (1280, 720);
    let materials = builtin::build("materials", BuiltinOptions::default()).unwrap();
    let mut demo = builtin::build("demo", BuiltinOptions::default()).unwrap();
    demo.name = "demo, five models".into();
    for (k, m) in demo.materials.iter_mut().enumerate() {
        m.brdf = Brdf::ALL[k % Brdf::ALL.len()];
    }
    let mut prepared = Vec::new();
    for scene in [&materials, &demo] {
        for force in [BrdfOverride::Scene, BrdfOverride::BlinnPhong] {
            let s = Settings { brdf: force, count_fragments: false, timestamps: true, ..Settings::default() };
            let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &s).unwrap();
            render_image(&gpu, &mut r, scene, &s, w, h).unwrap();
            prepared.push((scene, force, s, r, Vec::new()));
        }
    }
    for _ in 0..rounds {
        for (scene, _, s, r, times) in prepared.iter_mut() {
            let (_, st) = render_image(&gpu, r, scene, s, w, h).unwrap();
            let g = st.gpu_ms;
            times.push([g.gbuffer, g.lighting, g.compose, g.forward, g.total].map(|v| v.unwrap_or(0.0)));
        }
    }
    println!("| scene | models | G-buffer B/px | G-buffer ms | lighting ms | compose ms | forward ms | total ms |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    for (scene, force, _, r, times) in &prepared {
        let m = |i: usize| median(times.iter().map(|t| t[i]).collect());
        let models = match force {
            BrdfOverride::Scene => format!("own ({})", scene.brdfs(None).len()),
            other => format!("forced {}", other.name()),
        };
        println!(
            "| {} | {models} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            scene.name,
            r.layout().bytes_per_pixel(),
            m(0),
            m(1),
            m(2),
            m(3),
            m(4)
        );
    }
}
