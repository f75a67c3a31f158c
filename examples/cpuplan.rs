//! The CPU's part of a frame at many lights, as `Renderer::render` runs it: records, plan
//! (with the clamps) and upload, medians over interleaved rounds of real frames;
//! `cargo run --release --example cpuplan [LIGHTS [ROUNDS]]` (default 16,384 lights, 9 rounds).
//! `cpuplan loop [LIGHTS]` repeats only the records and the plan (clamps and shadow plan
//! included, with the meshes' real bounds; no GPU work), for a profiler; `CPUPLAN_EVICT=MB`
//! writes that many MB before each looped frame, outside the timing, to time it on cold caches.
//! `CPUPLAN_MODE=clustered` and `CPUPLAN_BUILD=cpu|gpu` (who builds the clustered lists) pick
//! rows. The lights move (`demo` at a later time every frame, as the viewer's Space animates
//! them), so nothing cached from a frame before can stand in for this frame's work.

use lampshade::headless::render_image;
use lampshade::renderer::plan::{self, FramePlan, PlanView};
use lampshade::renderer::records::FrameRecords;
use lampshade::renderer::settings::ClusterBuilder;
use lampshade::renderer::volumes::Volumes;
use lampshade::renderer::{batches, shadows, tiles};
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
    // The animated lights: frame k shows `demo` at k x 0.25 s (built before the timing starts).
    let scene_at =
        |k: usize| match builtin::build("demo", BuiltinOptions { lights: Some(lights), time: k as f64 * 0.25 }) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e:#}");
                std::process::exit(1);
            }
        };
    let scene = scene_at(0);
    let (w, h) = (1280, 720);
    // The clustered lists built by the GPU (the default) and by the CPU.
    let (gpu_built, cpu_built) = (ClusterBuilder::Gpu, ClusterBuilder::Cpu);
    let all = [
        (CullingMode::Volume, gpu_built),
        (CullingMode::StencilReplace, gpu_built),
        (CullingMode::Clustered, gpu_built),
        (CullingMode::Clustered, cpu_built),
        (CullingMode::Auto, gpu_built),
        (CullingMode::Auto, cpu_built),
    ];
    let only = std::env::var("CPUPLAN_MODE").ok();
    let only_build = std::env::var("CPUPLAN_BUILD").ok();
    let modes: Vec<(CullingMode, ClusterBuilder)> = all
        .into_iter()
        .filter(|(m, b)| {
            only.as_deref().is_none_or(|o| o == m.name()) && only_build.as_deref().is_none_or(|o| o == b.name())
        })
        .collect();
    let label = |m: CullingMode, b: ClusterBuilder| match m {
        CullingMode::Clustered | CullingMode::Auto => format!("{} (lists: {})", m.name(), b.name()),
        _ => m.name(),
    };
    // `CPUPLAN_EVICT=MB`: before each looped frame, write that many MB (outside the timing), as a
    // real frame's rendering does to the caches (lavapipe runs on the same cores), so the loop
    // times cold data as real frames do.
    let evict_mb: usize = std::env::var("CPUPLAN_EVICT").ok().and_then(|v| v.parse().ok()).unwrap_or(0);
    let mut scratch = vec![0u8; evict_mb << 20];
    let mut evict = |frame: usize| {
        if !scratch.is_empty() {
            scratch.fill(frame as u8);
            std::hint::black_box(&scratch);
        }
    };
    if looped {
        let volumes = Volumes::new(&gpu.device, (1, 12));
        let scenes: Vec<_> = (0..8).map(scene_at).collect();
        // The meshes' bounds, as `Renderer` keeps them (the plans' object lists and the shadow
        // plan's casters read them).
        let bounds = lampshade::renderer::scene_gpu::mesh_bounds(&scene);
        for (mode, cluster_build) in modes {
            let settings = Settings { culling: mode, cluster_build, ..Settings::default() };
            // What `Renderer::render` hands the plan and the shadow plan.
            let plan_view = |scene: &lampshade::scene::Scene, records: &FrameRecords| PlanView {
                proj: records.proj.as_mat4(),
                near: scene.camera.near as f32,
                far: scene.camera.far as f32,
                size: (w, h),
                mode,
                depth_clamp: true,
                forward_lights: settings.forward_lights,
                light_batching: true,
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
            let shadow_options = settings.shadow_options();
            let shadow_inputs = |plans: &[plan::LightPlan], records: &FrameRecords| shadows::ShadowInputs {
                options: &shadow_options,
                bounds: &bounds,
                footprints: plans.iter().map(|l| (l.screen_share, l.screen_rect.is_some())).collect(),
                size: (w, h),
                proj: records.proj,
                max_texture: 8192,
                max_layers: 2048,
            };
            let mut times = Vec::new();
            let mut cpu = 0.0;
            for frame in 0..200 {
                let scene = &scenes[frame % scenes.len()];
                evict(frame);
                let c = lampshade::renderer::cputime::Clock::start();
                let t = std::time::Instant::now();
                let mut records =
                    FrameRecords::new(scene, &settings.options(), (w, h), wgpu::TextureFormat::Rgba16Float);
                let view = plan_view(scene, &records);
                let plan = FramePlan::new(scene, &mut records, &bounds, &volumes, &view);
                let clamps = overlap::clamps(&plan.lights, (w, h), wgpu::TextureFormat::Rgba16Float);
                let shadow_plan = shadows::plan(scene, &shadow_inputs(&plan.lights, &records));
                for ((l, c), &(first, count)) in records.lights.iter_mut().zip(&clamps.lights).zip(&shadow_plan.lights)
                {
                    l.clamp = *c;
                    l.shadow = [first, count, 0, 0];
                }
                std::hint::black_box((&plan, &records));
                times.push(t.elapsed().as_secs_f64() * 1e3);
                cpu += c.ms();
            }
            // CPU time over the threads that did the work (`cputime`), per frame: what the work
            // costs, apart from how a loaded machine schedules it.
            println!(
                "{}: records + plan (clamps and shadow plan included) {:.2} ms (median wall clock), {:.2} CPU ms per frame (all threads){}",
                label(mode, cluster_build),
                median(times),
                cpu / 200.0,
                if evict_mb > 0 { format!(", {evict_mb} MB written before each frame") } else { String::new() }
            );
            // Where it goes: the steps of `FramePlan::new` one by one (CPU time over all
            // threads, `cputime`), medians over 50 frames.
            use lampshade::renderer::cputime::Clock;
            let mut steps: Vec<(&str, Vec<f64>)> = Vec::new();
            let mut add = |name: &'static str, ms: f64| match steps.iter_mut().find(|(n, _)| *n == name) {
                Some((_, v)) => v.push(ms),
                None => steps.push((name, vec![ms])),
            };
            for frame in 0..50 {
                let scene = &scenes[frame % scenes.len()];
                evict(frame);
                let c = Clock::start();
                let mut records =
                    FrameRecords::new(scene, &settings.options(), (w, h), wgpu::TextureFormat::Rgba16Float);
                add("records", c.ms());
                let view = plan_view(scene, &records);
                let c = Clock::start();
                let radii = plan::SphereRadii::of(&volumes.sphere);
                let mut plans: Vec<_> = records
                    .lights
                    .iter()
                    .map(|l| {
                        plan::plan_sphere_ahead(l, radii, &volumes.sphere, &view)
                            .unwrap_or_else(|| plan::plan_light(l, &volumes, &view))
                    })
                    .collect();
                add("per-light plans (one thread)", c.ms());
                // The plans by kind: off screen, wholly on screen, partly (the silhouette
                // clipped to the screen), and the hull path.
                let mut kinds: [Vec<usize>; 4] = Default::default();
                for (i, l) in records.lights.iter().enumerate() {
                    let k = match plan::plan_sphere_ahead(l, radii, &volumes.sphere, &view) {
                        None => 3,
                        Some(p) => match p.screen_rect {
                            None => 0,
                            Some((lo, hi)) if lo.cmpge(-glam::Vec2::ONE).all() && hi.cmple(glam::Vec2::ONE).all() => 1,
                            Some(_) => 2,
                        },
                    };
                    kinds[k].push(i);
                }
                for (k, name) in
                    ["  off screen", "  wholly on screen", "  partly on screen", "  hull path"].into_iter().enumerate()
                {
                    let c = Clock::start();
                    for &i in &kinds[k] {
                        let l = &records.lights[i];
                        std::hint::black_box(
                            plan::plan_sphere_ahead(l, radii, &volumes.sphere, &view)
                                .unwrap_or_else(|| plan::plan_light(l, &volumes, &view)),
                        );
                    }
                    let ms = c.ms();
                    if frame == 0 {
                        println!("{name}: {} lights", kinds[k].len());
                    }
                    add(name, ms);
                }
                let c = Clock::start();
                let tiled = tiles::frame_rule(&mut plans, &view);
                add("frame rule", c.ms());
                if tiled == Some(plan::Method::Clustered) {
                    let c = Clock::start();
                    match cluster_build {
                        ClusterBuilder::Cpu => {
                            drop(std::hint::black_box(tiles::cluster_lists(&records.lights, &plans, &view)))
                        }
                        ClusterBuilder::Gpu => {
                            drop(std::hint::black_box(tiles::cluster_job(&records.lights, &plans, &view)))
                        }
                    }
                    add("cluster lists or spans", c.ms());
                }
                let c = Clock::start();
                std::hint::black_box(batches::LightBatches::new(&plans, &records.lights, &volumes, &view));
                add("batches", c.ms());
                let c = Clock::start();
                let clamps = overlap::clamps(&plans, (w, h), wgpu::TextureFormat::Rgba16Float);
                add("clamps", c.ms());
                // What `Renderer::render` does after the plan: the shadow plan, then the clamps
                // and shadow tiles into the records.
                let c = Clock::start();
                let shadow_plan = std::hint::black_box(shadows::plan(scene, &shadow_inputs(&plans, &records)));
                add("shadow plan", c.ms());
                let c = Clock::start();
                for ((l, c), &(first, count)) in records.lights.iter_mut().zip(&clamps.lights).zip(&shadow_plan.lights)
                {
                    l.clamp = *c;
                    l.shadow = [first, count, 0, 0];
                }
                std::hint::black_box(&records);
                add("clamps and shadow tiles into the records", c.ms());
                let c = Clock::start();
                std::hint::black_box(FramePlan::new(scene, &mut records, &bounds, &volumes, &view));
                add("FramePlan::new (all of it)", c.ms());
            }
            for (name, v) in steps {
                println!("  {name}: {:.3} ms", median(v));
            }
        }
        return;
    }
    let mut prepared = Vec::new();
    for (m, cluster_build) in modes {
        let s = Settings { culling: m, cluster_build, count_fragments: false, timestamps: true, ..Settings::default() };
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
        prepared.push((label(m, cluster_build), s, r, Vec::new()));
    }
    for round in 0..rounds {
        let scene = scene_at(round + 1);
        for (_, s, r, t) in prepared.iter_mut() {
            match render_image(&gpu, r, &scene, s, w, h) {
                Ok((_, st)) => t.push((
                    st.cpu_ms,
                    st.gpu_ms.lighting.unwrap_or(f64::NAN),
                    st.gpu_ms.total.unwrap_or(f64::NAN),
                    st.gpu_ms.lists.unwrap_or(0.0),
                )),
                Err(e) => {
                    eprintln!("{e:#}");
                    std::process::exit(1);
                }
            }
        }
    }
    println!("demo, {} lights (moving), {w}x{h}, {rounds} interleaved rounds, medians (ms)", scene.lights.len());
    let clock = if lampshade::renderer::cputime::measures_cpu() { "CPU time over all threads" } else { "wall clock" };
    println!("records, plan, upload: {clock}; wall clock: the three on the rendering thread");
    println!("| mode | records | plan | upload | CPU total | wall clock | GPU lists | GPU lighting | GPU total |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (m, _, _, t) in &prepared {
        let f = |g: fn(&lampshade::renderer::CpuMs) -> f64| median(t.iter().map(|x| g(&x.0)).collect());
        println!(
            "| {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} | {:.1} |",
            m,
            f(|c| c.records),
            f(|c| c.plan),
            f(|c| c.upload),
            f(|c| c.records + c.plan + c.upload),
            f(|c| c.wall),
            median(t.iter().map(|x| x.3).collect()),
            median(t.iter().map(|x| x.1).collect()),
            median(t.iter().map(|x| x.2).collect())
        );
    }
}
