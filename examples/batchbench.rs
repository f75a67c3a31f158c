//! Batched against unbatched light draws on `demo` at 1280x720, interleaved rounds (as the
//! bench times them, uncounted): `cargo run --release --example batchbench [LIGHTS [ROUNDS]]`;
//! `batchbench cpu` times `FramePlan::new` (which builds the batches) at 16,384 lights.

use lampshade::headless::render_image;
use lampshade::renderer::{CullingMode, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};

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
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).map(String::as_str) == Some("cpu") {
        cpu(&gpu);
        return;
    }
    let number = |k: usize, default: usize| match args.get(k).map(|s| s.parse::<usize>()) {
        None => default,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("usage: batchbench [LIGHTS [ROUNDS]] | batchbench cpu");
            std::process::exit(2);
        }
    };
    let (lights, rounds) = (number(1, 1024), number(2, 7));
    let (w, h) = (1280, 720);
    let scene = builtin::build("demo", BuiltinOptions { lights: Some(lights), time: 0.0 }).unwrap();
    let modes = [
        CullingMode::Volume,
        CullingMode::StencilTwoPass,
        CullingMode::StencilInvert,
        CullingMode::StencilReplace,
        CullingMode::Auto,
    ];
    let mut prepared = Vec::new();
    for m in modes {
        for b in [false, true] {
            let s = Settings {
                culling: m,
                light_batching: b,
                count_fragments: false,
                timestamps: true,
                ..Settings::default()
            };
            let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &s).unwrap();
            render_image(&gpu, &mut r, &scene, &s, w, h).unwrap();
            prepared.push((m, b, s, r, Vec::new()));
        }
    }
    for _ in 0..rounds {
        for (_, _, s, r, t) in prepared.iter_mut() {
            let (_, st) = render_image(&gpu, r, &scene, s, w, h).unwrap();
            t.push(st);
        }
    }
    println!("demo {} lights 1280x720, {rounds} interleaved rounds, medians", scene.lights.len());
    println!("| mode | batching | lighting ms | total ms | draw calls | batches | lighting on/off |");
    let mut off_light = 0.0;
    for (m, b, _, _, t) in &prepared {
        let l = median(t.iter().filter_map(|s| s.gpu_ms.lighting).collect());
        let tot = median(t.iter().filter_map(|s| s.gpu_ms.total).collect());
        let last = t.last().unwrap();
        let ratio = if *b {
            format!("{:.3}", l / off_light)
        } else {
            off_light = l;
            "-".into()
        };
        println!(
            "| {} | {} | {:.1} | {:.1} | {} | {} | {} |",
            m.name(),
            if *b { "on" } else { "off" },
            l,
            tot,
            last.draw_calls,
            last.light_batches,
            ratio
        );
    }
}

/// CPU time of `FramePlan::new` (which builds the batches) at 16,384 lights, batching off and on.
fn cpu(gpu: &lampshade::Gpu) {
    use lampshade::renderer::plan::{FramePlan, PlanView};
    use lampshade::renderer::records::FrameRecords;
    use lampshade::renderer::volumes::Volumes;
    let scene = builtin::build("demo", BuiltinOptions { lights: Some(16384), time: 0.0 }).unwrap();
    let volumes = Volumes::new(&gpu.device, (1, 12));
    for mode in [CullingMode::Volume, CullingMode::StencilTwoPass, CullingMode::Auto] {
        for light_batching in [false, true] {
            let settings = Settings { culling: mode, ..Settings::default() };
            let mut times = Vec::new();
            let mut batches = 0;
            for _ in 0..9 {
                let mut records =
                    FrameRecords::new(&scene, &settings.options(), (1280, 720), wgpu::TextureFormat::Rgba16Float);
                let view = PlanView {
                    proj: records.proj.as_mat4(),
                    near: scene.camera.near as f32,
                    far: scene.camera.far as f32,
                    size: (1280, 720),
                    mode,
                    depth_clamp: true,
                    forward_lights: settings.forward_lights,
                    light_batching,
                    cluster_build: settings.cluster_build,
                    grid: Default::default(),
                    costs: Default::default(),
                    object_cap: (0, Default::default()),
                    loop_limit: None,
                    near_fullscreen: false,
                    front_to_back: false,
                    sort_blended: true,
                    prepass_models: None,
                };
                let t = std::time::Instant::now();
                let plan = FramePlan::new(&scene, &mut records, &[], &volumes, &view);
                times.push(t.elapsed().as_secs_f64() * 1e3);
                batches = plan.batches.batches.len();
            }
            println!(
                "{} batching {light_batching}: FramePlan::new {:.2} ms, {batches} batches",
                mode.name(),
                median(times)
            );
        }
    }
}
