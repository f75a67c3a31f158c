//! The culling oracle's long run: `cargo run --release --example oracle -- --cases N --seed S`.
//! Draws N cases from stream S (`lampshade::oracle::case::generate`), holds every culling mode
//! of the deferred path and the light pre-pass against brute force, shrinks each failure to the
//! fewest lights and boxes that still fail and writes it to `--out` (default
//! `tests/data/oracle/`, which the suite replays). Prints the totals as one JSON line at the
//! end (`--summary FILE` writes them too); exits 1 when any case failed.

use clap::Parser;
use lampshade::oracle::{self, case};

#[derive(Parser)]
struct Args {
    /// Cases to run.
    #[arg(long, default_value_t = 1000)]
    cases: u64,
    /// The generator's stream.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The first case's index (to resume a run).
    #[arg(long, default_value_t = 0)]
    first: u64,
    /// The most lights a case holds.
    #[arg(long, default_value_t = 256)]
    max_lights: usize,
    /// The fewest lights a case holds (the counts are log-distributed between the two). The
    /// family past the tiled pass's batch: `--min-lights 65537 --max-lights 130000`.
    #[arg(long, default_value_t = 1)]
    min_lights: usize,
    /// Only these culling modes (comma-separated; default every mode).
    #[arg(long, value_delimiter = ',')]
    modes: Vec<String>,
    /// Frame size, WxH.
    #[arg(long, default_value = "64x36")]
    size: String,
    /// Where shrunk failures are written.
    #[arg(long, default_value = "tests/data/oracle")]
    out: std::path::PathBuf,
    /// Also write the totals here (JSON).
    #[arg(long)]
    summary: Option<std::path::PathBuf>,
    /// Check these case files instead (each result printed as JSON).
    #[arg(long, num_args = 1..)]
    replay: Vec<std::path::PathBuf>,
}

#[derive(serde::Serialize, Default)]
struct Summary {
    seed: u64,
    first: u64,
    cases: u64,
    frames: u64,
    failed_cases: u64,
    missed_pixels: u64,
    extra_pixels: u64,
    saturated_pixels: u64,
    /// Frames a mode refused (a limit of the mode: none so far).
    refused_frames: u64,
    /// Frames whose path refused the case's settings before any culling (the light pre-pass
    /// with Rg11b10Ufloat accumulation).
    path_refused_frames: u64,
    written: Vec<String>,
    /// Cases per accumulation format.
    accumulation: std::collections::BTreeMap<String, u64>,
    seconds: f64,
}

/// A line above the progress bar (on stderr, also when the bar is hidden).
fn say(bar: &indicatif::ProgressBar, line: String) {
    bar.suspend(|| eprintln!("{line}"));
}

fn main() {
    let args = Args::parse();
    let Some((w, h)) = args.size.split_once('x').and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?))) else {
        eprintln!("--size takes WxH, e.g. 64x36 (got {:?})", args.size);
        std::process::exit(2);
    };
    let gpu = match lampshade::Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("no GPU adapter: {e:#}");
            std::process::exit(2);
        }
    };
    let mut runner = oracle::Runner::new(&gpu);
    if !args.replay.is_empty() {
        let mut failed = false;
        for p in &args.replay {
            let c: case::Case = match std::fs::read_to_string(p)
                .map_err(anyhow::Error::from)
                .and_then(|t| Ok(serde_json::from_str(&t)?))
            {
                Ok(c) => c,
                Err(e) => {
                    eprintln!("{}: {e:#}", p.display());
                    std::process::exit(2);
                }
            };
            match runner.check(&gpu, &c, &oracle::Scope::default()) {
                Ok(r) => {
                    failed |= r.failures().next().is_some();
                    println!("{}: {}", p.display(), serde_json::to_string(&r).unwrap_or_default());
                }
                Err(e) => {
                    eprintln!("{}: {e:#}", p.display());
                    failed = true;
                }
            }
        }
        std::process::exit(failed as i32);
    }
    let limits = case::Limits { width: w, height: h, max_lights: args.max_lights.max(1), min_lights: args.min_lights };
    let mut scope = oracle::Scope::default();
    if !args.modes.is_empty() {
        scope.modes.clear();
        for name in &args.modes {
            match lampshade::renderer::CullingMode::ALL.iter().find(|m| m.name() == *name) {
                Some(&m) => scope.modes.push(m),
                None => {
                    let names: Vec<String> = lampshade::renderer::CullingMode::ALL.iter().map(|m| m.name()).collect();
                    eprintln!("--modes: no culling mode {name:?} (one of {})", names.join(", "));
                    std::process::exit(2);
                }
            }
        }
    }
    let bar = indicatif::ProgressBar::new(args.cases);
    let start = std::time::Instant::now();
    let mut s = Summary { seed: args.seed, first: args.first, ..Default::default() };
    for index in args.first..args.first + args.cases {
        let c = case::generate(args.seed, index, limits);
        if index == args.first || index % case::SETTINGS_BLOCK == 0 {
            say(&bar, format!("case {index}: settings {:?}", c.settings));
        }
        *s.accumulation.entry(format!("{:?}", c.settings.accumulation)).or_default() += 1;
        match runner.check_and_shrink(&gpu, &c, &scope) {
            Ok((result, shrunk)) => {
                s.cases += 1;
                s.frames += result.modes.len() as u64;
                for m in &result.modes {
                    s.missed_pixels += m.missed as u64;
                    s.extra_pixels += m.extra as u64;
                    s.saturated_pixels += m.saturated as u64;
                    s.refused_frames += (m.refused.is_some() && !m.path_refused) as u64;
                    s.path_refused_frames += m.path_refused as u64;
                }
                if let Some(m) = result.modes.iter().find(|m| m.refused.is_some() && !m.path_refused) {
                    say(
                        &bar,
                        format!("case {index}: {} refused: {}", m.path, m.refused.as_deref().unwrap_or_default()),
                    );
                }
                if let Some(shrunk) = shrunk {
                    s.failed_cases += 1;
                    let failing: Vec<String> = result.failures().map(|m| format!("{}/{}", m.path, m.mode)).collect();
                    say(&bar, format!("case {index}: {} ({} lights)", failing.join(", "), c.lights.len()));
                    let path = args.out.join(format!("seed{}-case{index}.json", args.seed));
                    let written = std::fs::create_dir_all(&args.out)
                        .map_err(anyhow::Error::from)
                        .and_then(|_| Ok(std::fs::write(&path, serde_json::to_string_pretty(&shrunk)?)?));
                    match written {
                        Ok(()) => s.written.push(path.display().to_string()),
                        Err(e) => say(&bar, format!("writing {}: {e:#}", path.display())),
                    }
                }
            }
            Err(e) => say(&bar, format!("case {index}: {e:#}")),
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    s.seconds = start.elapsed().as_secs_f64();
    let line = serde_json::to_string(&s).unwrap_or_default();
    println!("{line}");
    if let Some(p) = &args.summary {
        if let Err(e) = std::fs::write(p, &line) {
            eprintln!("writing {}: {e}", p.display());
        }
    }
    std::process::exit(if s.failed_cases > 0 { 1 } else { 0 });
}
