//! GPU lighting time and CPU planning time of the list modes (`clustered`, `zbin`, `tiled`) on
//! one scene, frame after frame on one renderer: `cargo run --release --example list_modes --
//! SCENE LIGHTS WxH [FRAMES]`. Prints, per mode, the medians of the frames after the first
//! two (pipelines compiled, buffers grown): the lighting span (`gpu_ms.lighting`) and the CPU's
//! plan (`cpu_ms.plan`), and the CPU's whole part (`cpu_ms`: records, plan, upload). Nothing counted, so the frame is the one a user gets. `tiled` is left
//! out past 65,536 lights (its compute pass keeps a bit for that many and walks every light
//! past them).

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
    println!("{name}, {} lights, {w}x{h}, medians of {} frames", scene.lights.len(), frames.saturating_sub(2));
    for mode in [CullingMode::Clustered, CullingMode::Zbin, CullingMode::Tiled] {
        if mode == CullingMode::Tiled && scene.lights.len() > 65_536 {
            continue;
        }
        let s = Settings {
            culling: mode,
            timestamps: true,
            count_fragments: false,
            count_ideal: false,
            ..Settings::default()
        };
        let run = Renderer::new(&gpu, OUTPUT_FORMAT, &s).and_then(|mut r| {
            let mut out = (Vec::new(), Vec::new(), Vec::new());
            for k in 0..frames {
                let (_, st) = lampshade::headless::render_image(&gpu, &mut r, &scene, &s, w, h)?;
                if k >= 2 {
                    out.0.push(st.gpu_ms.lighting.unwrap_or(f64::NAN));
                    out.1.push(st.cpu_ms.plan);
                    out.2.push(st.cpu_ms.total());
                }
            }
            Ok(out)
        });
        match run {
            Ok((gpu_ms, plan_ms, cpu_ms)) => println!(
                "{:10} lighting {:8.2} ms  plan (CPU) {:7.3} ms  records + plan + upload (CPU) {:7.3} ms",
                mode.name(),
                median(gpu_ms),
                median(plan_ms),
                median(cpu_ms)
            ),
            Err(e) => println!("{:10} {e:#}", mode.name()),
        }
    }
}
