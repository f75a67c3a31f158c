//! The CPU's part of a frame at many lights, as `Renderer::render` runs it: records, plan
//! (with the clamps) and upload, medians over interleaved rounds of real frames;
//! `cargo run --release --example cpuplan [LIGHTS [ROUNDS]]` (default 16,384 lights, 9 rounds).
//! `cpuplan loop [LIGHTS]` repeats only the records and the plan (no GPU work), for a profiler.

use lampshade::headless::render_image;
use lampshade::renderer::plan::{FramePlan, PlanView};
use lampshade::renderer::records::FrameRecords;
use lampshade::renderer::volumes::Volumes;
use lampshade::renderer::{overlap, CullingMode, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let looped = args.get(1).map(String::as_str) == Some("loop");
    let rest = if looped { &args[2..] } else { &args[1..] };
    let number = |k: usize, default: usize| match rest.get(k).map(|s| s.parse::<usize>()) {
        None => default,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("usage: cpuplan [LIGHTS [ROUNDS]] | cpuplan loop [LIGHTS]");
            std::process::exit(2);
        }
    };
    let (lights, rounds) = (number(0, 16384), number(1, 9));
    let gpu = match lampshade::Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("no GPU adapter: {e:#}");
            std::process::exit(1);
        }
    };
    let scene = match builtin::build("demo", BuiltinOptions { lights: Some(lights), time: 0.0 }) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e:#}");
            std::process::exit(1);
        }
    };
    let (w, h) = (1280, 720);
    let all = [CullingMode::Volume, CullingMode::StencilReplace, CullingMode::Clustered, CullingMode::Auto];
    let only = std::env::var("CPUPLAN_MODE").ok();
    let modes: Vec<CullingMode> = all.into_iter().filter(|m| only.as_deref().is_none_or(|o| o == m.name())).collect();
    if looped {
        let volumes = Volumes::new(&gpu.device, (1, 12));
        for mode in modes {
            let settings = Settings { culling: mode, ..Settings::default() };
            let mut times = Vec::new();
            for _ in 0..200 {
                let t = std::time::Instant::now();
                let mut records = FrameRecords::new(&scene, &settings, (w, h), wgpu::TextureFormat::Rgba16Float);
                let view = PlanView {
                    proj: records.proj.as_mat4(),
                    near: scene.camera.near as f32,
                    far: scene.camera.far as f32,
                    size: (w, h),
                    mode,
                    depth_clamp: true,
                    forward_lights: settings.forward_lights,
                    light_batching: true,
                };
                let plan = FramePlan::new(&scene, &mut records, &[], &volumes, &view);
                let clamps = overlap::clamps(&plan.lights, (w, h), wgpu::TextureFormat::Rgba16Float);
                std::hint::black_box((&plan, &clamps));
                times.push(t.elapsed().as_secs_f64() * 1e3);
            }
            println!("{}: records + plan {:.2} ms", mode.name(), median(times));
        }
        return;
    }
    let mut prepared = Vec::new();
    for m in modes {
        let s = Settings { culling: m, count_fragments: false, timestamps: true, ..Settings::default() };
        let mut r = match Renderer::new(&gpu, OUTPUT_FORMAT, &s) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{e:#}");
                std::process::exit(1);
            }
        };
        if let Err(e) = render_image(&gpu, &mut r, &scene, &s, w, h) {
            eprintln!("{e:#}");
            std::process::exit(1);
        }
        prepared.push((m, s, r, Vec::new()));
    }
    for _ in 0..rounds {
        for (_, s, r, t) in prepared.iter_mut() {
            match render_image(&gpu, r, &scene, s, w, h) {
                Ok((_, st)) => {
                    t.push((st.cpu_ms, st.gpu_ms.lighting.unwrap_or(f64::NAN), st.gpu_ms.total.unwrap_or(f64::NAN)))
                }
                Err(e) => {
                    eprintln!("{e:#}");
                    std::process::exit(1);
                }
            }
        }
    }
    println!("demo, {} lights, {w}x{h}, {rounds} interleaved rounds, medians (ms)", scene.lights.len());
    println!("| mode | records | plan | upload | CPU total | GPU lighting | GPU total |");
    println!("|---|---|---|---|---|---|---|");
    for (m, _, _, t) in &prepared {
        let f = |g: fn(&lampshade::renderer::CpuMs) -> f64| median(t.iter().map(|x| g(&x.0)).collect());
        println!(
            "| {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} |",
            m.name(),
            f(|c| c.records),
            f(|c| c.plan),
            f(|c| c.upload),
            f(|c| c.records + c.plan + c.upload),
            median(t.iter().map(|x| x.1).collect()),
            median(t.iter().map(|x| x.2).collect())
        );
    }
}
