//! GPU lighting time and CPU planning time of the list modes (`clustered`, `zbin`, `tiled`) on
//! one scene, frame after frame on one renderer: `cargo run --release --example list_modes --
//! SCENE LIGHTS WxH [FRAMES]`. Prints, per mode, the medians of the frames after the first
//! two (pipelines compiled, buffers grown): the lighting span (`gpu_ms.lighting`) and the CPU's
//! plan (`cpu_ms.plan`), the CPU's whole part (`cpu_ms`: records, plan, upload), and the CPU
//! time of the whole `render_image` call (this thread and its helpers: validation, the pass
//! set, the stats, the picture's readback; not the driver's threads). The scene does not move,
//! so from the second frame on a frame reuses the first one's CPU part (`FrameStats::cpu_reused`);
//! `LIST_MODES_ANIMATE=1` hands each frame a new light list (the same lights), so every frame
//! computes its part as a moving scene's would. Nothing counted, so the frame is the one a user gets.
//! `LIST_MODES_IDEAL=1` also prints the frame's ideal pairs (the pixel-light pairs whose light
//! reaches the pixel, counted in one more frame) and each mode's lighting ns per ideal pair.

use lampshade::renderer::{CullingMode, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{build, BuiltinOptions};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: list_modes SCENE LIGHTS WxH [FRAMES]";
    let (Some(name), Some(lights), Some(size)) = (args.first(), args.get(1), args.get(2)) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let parsed = (
        lights.parse::<usize>().ok(),
        size.split_once('x').and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?))),
        args.get(3).map_or(Some(7), |f| f.parse::<usize>().ok()),
    );
    let (Some(n), Some((w, h)), Some(frames)) = parsed else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let scene = match build(name, BuiltinOptions { lights: Some(n), ..Default::default() }) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let gpu = match lampshade::Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("no GPU adapter: {e:#}");
            std::process::exit(2);
        }
    };
    let animate = std::env::var("LIST_MODES_ANIMATE").is_ok_and(|v| v == "1");
    let mut scene = scene;
    println!("{name}, {} lights, {w}x{h}, medians of {} frames", scene.lights.len(), frames.saturating_sub(2));
    // The ideal pairs, from one counted frame (clustered: the per-light ideal counts of a list
    // mode's frame), when asked.
    let mut ideal = None;
    if std::env::var("LIST_MODES_IDEAL").is_ok_and(|v| v == "1") {
        let s = Settings { culling: CullingMode::Clustered, count_ideal: true, ..Settings::default() };
        let counted = Renderer::new(&gpu, OUTPUT_FORMAT, &s)
            .and_then(|mut r| lampshade::headless::render_image(&gpu, &mut r, &scene, &s, w, h));
        match counted {
            Ok((_, st)) => ideal = st.ideal_fragments,
            Err(e) => eprintln!("the counted frame: {e:#}"),
        }
        println!("ideal pairs {}", ideal.map_or("-".into(), |i| i.to_string()));
    }
    for mode in [CullingMode::Clustered, CullingMode::Zbin, CullingMode::Tiled] {
        let s = Settings {
            culling: mode,
            timestamps: true,
            count_fragments: false,
            count_ideal: false,
            ..Settings::default()
        };
        let run = Renderer::new(&gpu, OUTPUT_FORMAT, &s).and_then(|mut r| {
            let mut out = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for k in 0..frames {
                if animate {
                    // Another list of the same lights: nothing to reuse.
                    scene.set_lights(scene.lights.to_vec());
                }
                let clock = lampshade::renderer::cputime::Clock::start();
                let (_, st) = lampshade::headless::render_image(&gpu, &mut r, &scene, &s, w, h)?;
                let call = clock.ms();
                if k >= 2 {
                    out.0.push(st.gpu_ms.lighting.unwrap_or(f64::NAN));
                    out.1.push(st.cpu_ms.plan);
                    out.2.push(st.cpu_ms.total());
                    out.4.push(st.cpu_ms.records);
                    out.5.push(st.cpu_ms.upload);
                    out.3.push(call);
                }
            }
            Ok(out)
        });
        match run {
            Ok((gpu_ms, plan_ms, cpu_ms, call_ms, records_ms, upload_ms)) => println!(
                "{:10} lighting {:8.2} ms{}  plan (CPU) {:7.3} ms  records + plan + upload (CPU) {:7.3} ms \
                 ({:.3} + {:.3} + {:.3})  the frame call (CPU) {:7.3} ms",
                mode.name(),
                median(gpu_ms.clone()),
                ideal.map_or(String::new(), |i| format!(" ({:.3} ns per ideal pair)", median(gpu_ms) * 1e6 / i as f64)),
                median(plan_ms.clone()),
                median(cpu_ms),
                median(records_ms),
                median(plan_ms),
                median(upload_ms),
                median(call_ms)
            ),
            Err(e) => println!("{:10} {e:#}", mode.name()),
        }
    }
}
