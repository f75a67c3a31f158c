//! What a run reports: the CSV, the markdown tables, the limit each configuration is held to and the Pareto front.

use super::*;
use crate::renderer::post::effects::EFFECTS;

/// The report's list of skipped configurations (empty when none was).
pub fn skipped_markdown(skipped: &[Skipped]) -> String {
    if skipped.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\n### Skipped ({})\n\nConfigurations this scene or adapter cannot take; the rest of the sweep ran without them.\n\n\
         | group | configuration | scene | reason |\n|---|---|---|---|\n",
        skipped.len()
    );
    for k in skipped {
        s += &format!(
            "| {} | {} | {} | {} |\n",
            k.group,
            k.label,
            k.scene,
            k.reason.replace('|', "/").replace('\n', " ")
        );
    }
    s
}

/// The groups whose rows are culling modes, and so get a `limit` row.
pub const LIMIT_GROUPS: [&str; 3] = ["culling", "lights", "radius"];

/// What a frame could cost if lighting did only the ideal work: G-buffer ms + compose ms + ideal
/// pairs x the cheapest lighting ms per evaluated pair any mode measured, all from the same run.
/// The shadow pass, when lights cast, is a fixed pass like the G-buffer: `gbuffer_ms` holds both.
/// A mode evaluates at least the ideal pairs (tested: ideal ≤ shaded in every mode), and no
/// mode of the run evaluated a pair more cheaply, so a mode reaching the limit would have to
/// shade only the ideal pairs at the best per-pair price seen. G-buffer and compose do the same
/// work in every mode, so their medians over the key's rows are used.
pub fn limit_ms(gbuffer_ms: f64, compose_ms: f64, ideal: u64, ms_per_pair: f64) -> f64 {
    gbuffer_ms + compose_ms + ideal as f64 * ms_per_pair
}

/// Lighting ms per evaluated pair of a row (`None` without a timed lighting pass or a count).
fn ms_per_pair(r: &Row) -> Option<f64> {
    (r.shaded_fragments > 0 && r.lighting_ms.is_finite() && r.lighting_ms > 0.0)
        .then(|| r.lighting_ms / r.shaded_fragments as f64)
}

/// Adds a `limit` row after the last row of each (group, scene, light count, size, radius) among
/// [`LIMIT_GROUPS`], and sets every such row's `limit_ratio`. The ms per pair is the cheapest
/// of every culling-mode row (any group of [`LIMIT_GROUPS`], any light count and radius) of the
/// same scene and size in the run; without any such row there is no limit.
pub fn add_limits(rows: &mut Vec<Row>) {
    type Key = (String, String, usize, u32, u32, u64);
    let key = |r: &Row| (r.group.clone(), r.scene.clone(), r.lights, r.width, r.height, r.radius_scale.to_bits());
    let modes: Vec<Row> =
        rows.iter().filter(|r| LIMIT_GROUPS.contains(&r.group.as_str()) && r.label != "limit").cloned().collect();
    let cheapest = |k: &Key| -> Option<f64> {
        modes
            .iter()
            .filter(|r| r.scene == k.1 && r.width == k.3 && r.height == k.4)
            .filter_map(ms_per_pair)
            .min_by(f64::total_cmp)
    };
    let mut keys: Vec<Key> = Vec::new();
    for r in modes.iter() {
        if !keys.contains(&key(r)) {
            keys.push(key(r));
        }
    }
    for k in keys {
        let Some(ms_per_pair) = cheapest(&k) else { continue };
        let mine: Vec<&Row> = rows.iter().filter(|r| key(r) == k).collect();
        let Some(first) = mine.first() else { continue };
        let gbuffer = median(mine.iter().map(|r| r.gbuffer_ms).filter(|v| v.is_finite()).collect());
        // NaN where nothing cast: no shadow pass ran.
        let shadows = median(mine.iter().map(|r| r.shadow.gpu_ms).filter(|v| v.is_finite()).collect());
        let compose = median(mine.iter().map(|r| r.compose_ms).filter(|v| v.is_finite()).collect());
        // Every mode counts the same ideal (tested); the largest guards against a row that did
        // not count it.
        let ideal = mine.iter().map(|r| r.ideal_fragments).max().unwrap_or(0);
        let lighting = ideal as f64 * ms_per_pair;
        let limit = limit_ms(gbuffer + if shadows.is_finite() { shadows } else { 0.0 }, compose, ideal, ms_per_pair);
        let row = Row {
            label: "limit".into(),
            culling: "limit".into(),
            volumes: "-".into(),
            gbuffer_ms: gbuffer,
            lighting_ms: lighting,
            compose_ms: compose,
            forward_ms: 0.0,
            total_ms: limit,
            lists_ms: f64::NAN,
            coverage_fragments: 0,
            shaded_fragments: ideal,
            ideal_fragments: ideal,
            efficiency: 1.0,
            flip_mean: f32::NAN,
            max_abs_light_error: f32::NAN,
            psnr_db: f64::NAN,
            pareto: false,
            limit_ratio: 1.0,
            total_se_ms: f64::NAN,
            regret: Default::default(),
            auto_chose: String::new(),
            draw_calls: 0,
            light_batches: 0,
            costliest: Vec::new(),
            ..(*first).clone()
        };
        for r in rows.iter_mut().filter(|r| key(r) == k) {
            r.limit_ratio = r.total_ms / limit;
        }
        let at = rows.iter().rposition(|r| key(r) == k).map_or(rows.len(), |i| i + 1);
        rows.insert(at, row);
    }
}

/// Fills every row's [`Units`]: per-pair costs from its own figures, ρ_fs and the fixed passes
/// against the calibration row of its scene and size (NaN without one).
pub fn add_units(rows: &mut [Row]) {
    let calibration: Vec<(String, u32, u32, f64)> = rows
        .iter()
        .filter(|r| r.group == CALIBRATION && r.lighting_ms.is_finite() && r.lighting_ms > 0.0)
        .map(|r| (r.scene.clone(), r.width, r.height, r.lighting_ms))
        .collect();
    let per = |ms: f64, n: u64| if n > 0 && ms.is_finite() { ms * 1e6 / n as f64 } else { f64::NAN };
    for r in rows.iter_mut() {
        let fs =
            calibration.iter().find(|c| c.0 == r.scene && c.1 == r.width && c.2 == r.height).map_or(f64::NAN, |c| c.3);
        r.units = Units {
            ns_per_pair: per(r.lighting_ms, r.shaded_fragments),
            ns_per_ideal: per(r.lighting_ms, r.ideal_fragments),
            rho_fs: r.lighting_ms / fs,
            gbuffer_fs: r.gbuffer_ms / fs,
            compose_fs: r.compose_ms / fs,
            culling_share: if r.lists_ms.is_finite() && r.lighting_ms > 0.0 {
                r.lists_ms / r.lighting_ms
            } else {
                f64::NAN
            },
        };
    }
}

/// Marks the rows no other row of the same scene, light count and size beats in both time and
/// error.
pub fn mark_pareto(rows: &mut [Row]) {
    let key = |r: &Row| (r.scene.clone(), r.lights, r.width, r.height);
    let snapshot: Vec<(_, f64, f32)> = rows.iter().map(|r| (key(r), r.total_ms, r.flip_mean)).collect();
    for (i, r) in rows.iter_mut().enumerate() {
        let (k, t, e) = &snapshot[i];
        r.pareto = !snapshot
            .iter()
            .enumerate()
            .any(|(j, (k2, t2, e2))| j != i && k2 == k && t2 <= t && e2 <= e && (t2 < t || e2 < e));
    }
}

/// Sets `auto`'s [`Regret`] on its rows of the `culling` and `lights` groups: at each point
/// (group, scene, light count, size, radius factor), its total against the fastest row of
/// another plain culling mode (a row labelled with its mode, with or without ` xN`; not the
/// limit, not a variant such as `clustered gpu-lists`).
pub fn add_regret(rows: &mut [Row]) {
    let key = |r: &Row| (r.group.clone(), r.scene.clone(), r.lights, r.width, r.height, r.radius_scale.to_bits());
    // The label's count is the one asked; `lights` adds the scene's own (demo's four spots).
    let plain = |r: &Row| {
        r.label == r.culling
            || r.label.strip_prefix(&format!("{} x", r.culling)).is_some_and(|n| n.parse::<usize>().is_ok())
    };
    let candidates: Vec<Row> = rows
        .iter()
        .filter(|r| ["culling", "lights"].contains(&r.group.as_str()) && r.culling != "auto" && r.label != "limit")
        .filter(|r| plain(r) && r.total_ms.is_finite())
        .cloned()
        .collect();
    for r in rows.iter_mut().filter(|r| r.culling == "auto" && plain(r) && r.total_ms.is_finite()) {
        let best = candidates.iter().filter(|c| key(c) == key(r)).min_by(|a, b| a.total_ms.total_cmp(&b.total_ms));
        let Some(best) = best else { continue };
        // The configuration chosen: the list mode's own row, or auto's (its per-light plan).
        let own = candidates.iter().find(|c| key(c) == key(r) && c.culling == r.auto_chose);
        let (chosen, ms, se) = match own {
            Some(c) => (c.culling.clone(), c.total_ms, c.total_se_ms),
            None => ("auto".to_string(), r.total_ms, r.total_se_ms),
        };
        let noise = 2.0 * (se.powi(2) + best.total_se_ms.powi(2)).sqrt();
        r.regret = Regret {
            met: noise.is_finite().then_some(chosen == best.culling || ms - best.total_ms < noise),
            chosen,
            chosen_ms: ms,
            chosen_se_ms: se,
            best: best.culling.clone(),
            best_ms: best.total_ms,
            best_se_ms: best.total_se_ms,
            ratio: ms / best.total_ms,
        };
    }
}

/// `auto`'s regret per point, as a markdown section (empty without `auto` rows).
pub fn regret_markdown(rows: &[Row]) -> String {
    let mine: Vec<&Row> = rows.iter().filter(|r| r.regret.ratio.is_finite()).collect();
    if mine.is_empty() {
        return String::new();
    }
    let met = mine.iter().filter(|r| r.regret.met == Some(true)).count();
    let mut s = format!(
        "\n## `auto`'s regret\n\nThe measured total of the configuration `auto` chose (a list mode's own row, or \
         `auto`'s row where it kept its per-light plan) over the fastest mode's at the same point, medians of the \
         interleaved timed frames ± their standard error; met where the chosen is the fastest or the two differ by \
         less than two combined standard errors. `auto`'s own row is beside it. Met at {met} of {} points.\n\n\
         | group | scene | lights | size | auto ms | chose | chosen ms | best | best ms | regret | met |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
        mine.len()
    );
    for r in mine {
        let g = &r.regret;
        s += &format!(
            "| {} | {} | {} | {}x{} | {:.2} ± {:.2} | {} | {:.2} ± {:.2} | {} | {:.2} ± {:.2} | {:.3} | {} |\n",
            r.group,
            r.scene,
            r.lights,
            r.width,
            r.height,
            r.total_ms,
            r.total_se_ms,
            g.chosen,
            g.chosen_ms,
            g.chosen_se_ms,
            g.best,
            g.best_ms,
            g.best_se_ms,
            g.ratio,
            match g.met {
                Some(true) => "yes",
                Some(false) => "no",
                None => "-",
            }
        );
    }
    s
}

pub fn write_csv(rows: &[Row], path: &Path) -> Result<()> {
    let effects: String = EFFECTS.iter().map(|e| format!("{}_ms,", e.name)).collect();
    let mut out = format!(
        "group,label,scene,culling,layout,accumulation,reversed_z,depth_format,light_cutoff,sphere_subdivisions,cone_sides,volumes,\
         lights,radius_scale,width,height,gbuffer_ms,lighting_ms,compose_ms,forward_ms,bloom_ms,exposure_ms,tonemap_ms,{effects}total_ms,draw_calls,light_batches,\
         coverage_fragments,shaded_fragments,ideal_fragments,efficiency,gbuffer_bytes_per_pixel,flip_mean,max_abs_light_error,psnr_db,pareto,\
         reference,limit_ratio,path,passes,target_bytes_per_pixel,object_light_pairs,lit_fragments,error,\
         shadow_ms,shadow_bytes,shadow_casting,shadow_fallback_budget,shadow_fallback_off_screen,shadow_cube,shadow_cube_side,\
         lists_ms,ns_per_pair,ns_per_ideal,rho_fs,gbuffer_fs,compose_fs,culling_share,\
         cap_dropped_lights,cap_dropped_entries,cap_missed_pixels,cap_dropped_pairs,cap_entry_pairs,\
         total_se_ms,auto_chose,regret,regret_best,regret_met\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{}{:.3},{},{},{},{},{},{:.4},{},{:.6},{:.6},{:.2},{},{},{:.3},{},{},{},{},{},\"{}\",{:.3},{},{},{},{},{},{},{:.3},{:.4},{:.4},{:.3},{:.3},{:.3},{:.4},{},{},{},{},{},{:.3},{},{:.4},{},{}\n",
            r.group,
            r.label,
            r.scene,
            r.culling,
            r.layout,
            r.accumulation,
            r.reversed_z,
            r.depth_format,
            r.light_cutoff,
            r.sphere_subdivisions,
            r.cone_sides,
            r.volumes,
            r.lights,
            r.radius_scale,
            r.width,
            r.height,
            r.gbuffer_ms,
            r.lighting_ms,
            r.compose_ms,
            r.forward_ms,
            r.bloom_ms,
            r.exposure_ms,
            r.tonemap_ms,
            r.effects_ms.iter().map(|v| format!("{v:.3},")).collect::<String>(),
            r.total_ms,
            r.draw_calls,
            r.light_batches,
            r.coverage_fragments,
            r.shaded_fragments,
            r.ideal_fragments,
            r.efficiency,
            r.gbuffer_bytes_per_pixel,
            r.flip_mean,
            r.max_abs_light_error,
            r.psnr_db,
            r.pareto,
            r.reference,
            r.limit_ratio,
            r.path.path,
            r.path.passes,
            r.path.target_bytes_per_pixel,
            r.path.object_light_pairs,
            r.path.lit_fragments,
            r.path.error.replace('"', "'").replace(',', ";"),
            r.shadow.gpu_ms,
            r.shadow.bytes,
            r.shadow.casting,
            r.shadow.fallback_budget,
            r.shadow.fallback_off_screen,
            r.shadow.cube,
            r.shadow.cube_side,
            r.lists_ms,
            r.units.ns_per_pair,
            r.units.ns_per_ideal,
            r.units.rho_fs,
            r.units.gbuffer_fs,
            r.units.compose_fs,
            r.units.culling_share,
            r.caps.dropped_lights,
            r.caps.dropped_entries,
            r.caps.missed_pixels,
            r.caps.dropped_pairs,
            r.caps.entry_pairs,
            r.total_se_ms,
            r.auto_chose,
            r.regret.ratio,
            r.regret.best,
            r.regret.met.map_or(String::new(), |m| m.to_string())
        );
    }
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

pub fn markdown(run: &BenchRun, gpu_name: &str, o: &BenchOptions) -> String {
    let rows = &run.rows[..];
    let mut s = format!(
        "Scene `{}`, time {}, adapter {gpu_name}; GPU ms are medians of {} frames; error against the reference \
         (full-screen lights, Rgba32Float G-buffer and accumulation, blended surfaces depth peeled 16 layers deep), measured before post: the light error and PSNR \
         on the light accumulation, FLIP on the output only for frames without the post chain (`-` in the `post` rows). Ratio: lighting time over `fullscreen`'s in the \
         same run and size. * = on the Pareto front (time, FLIP) for its scene, light count and size. \
         Volumes: the bounding meshes the frame drew (only the kinds its lights need). \
         `limit` (groups culling, lights, radius): G-buffer ms + compose ms + ideal pairs x the cheapest \
         lighting ms per evaluated pair any culling mode measured at this scene and size in this run; `x limit` is each row's total over it.\n\n",
        o.scene, o.time, o.frames
    );
    let volume_refs: Vec<String> = rows
        .iter()
        .filter(|r| r.reference != "fullscreen" && r.label != "limit")
        .map(|r| format!("{} lights at {}x{}", r.lights, r.width, r.height))
        .fold(Vec::new(), |mut v, k| {
            if !v.contains(&k) {
                v.push(k);
            }
            v
        });
    if !volume_refs.is_empty() {
        s += &format!(
            "References drawn with plain volumes (a full-screen one would take minutes; volumes are tested equal to \
             full-screen within one 8-bit step): {}.\n\n",
            volume_refs.join(", ")
        );
    }
    // The post columns in the chain's order, as `effects_ms` holds them.
    let chain: Vec<&str> = ["bloom", "exposure", "tonemap"].into_iter().chain(EFFECTS.iter().map(|e| e.name)).collect();
    s += &format!(
        "| group | configuration | lights | size | G-buffer B/px | volumes | gbuffer ms | shadows ms | lighting ms | forward ms | post ms ({}) | total ms | x limit | lighting ratio | draw calls (batches) | coverage | shaded | ideal | efficiency | FLIP mean | max abs light error | PSNR dB |\n",
        chain.join("/")
    );
    s += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    let full: HashMap<(usize, u32, u32), f64> = rows
        .iter()
        .filter(|r| r.label == "fullscreen")
        .map(|r| ((r.lights, r.width, r.height), r.lighting_ms))
        .collect();
    for r in rows {
        let ratio = full
            .get(&(r.lights, r.width, r.height))
            .filter(|_| r.scene == o.scene)
            .filter(|_| r.label != "limit")
            .map_or("-".into(), |f| format!("{:.3}", r.lighting_ms / f));
        let x_limit = if r.limit_ratio.is_finite() { format!("{:.2}", r.limit_ratio) } else { "-".into() };
        let error = |v: f64, d: usize| if v.is_finite() { format!("{v:.d$}") } else { "-".into() };
        s += &format!(
            "| {} | {}{} | {} | {}x{} | {} | {} | {:.2} | {} | {:.2} | {:.2} | {} | {:.2} | {} | {} | {} ({}) | {} | {} | {} | {:.3} | {} | {} | {} |\n",
            r.group,
            r.label,
            if r.pareto { " *" } else { "" },
            r.lights,
            r.width,
            r.height,
            r.gbuffer_bytes_per_pixel,
            r.volumes,
            r.gbuffer_ms,
            if r.shadow.gpu_ms.is_finite() { format!("{:.2}", r.shadow.gpu_ms) } else { "-".into() },
            r.lighting_ms,
            r.forward_ms,
            if r.bloom_ms + r.exposure_ms + r.tonemap_ms > 0.0 {
                [r.bloom_ms, r.exposure_ms, r.tonemap_ms]
                    .iter()
                    .chain(&r.effects_ms)
                    .map(|v| format!("{v:.2}"))
                    .collect::<Vec<_>>()
                    .join("/")
            } else {
                "-".into()
            },
            r.total_ms,
            x_limit,
            ratio,
            r.draw_calls,
            r.light_batches,
            r.coverage_fragments,
            r.shaded_fragments,
            r.ideal_fragments,
            r.efficiency,
            error(r.flip_mean as f64, 5),
            error(r.max_abs_light_error as f64, 4),
            error(r.psnr_db, 1)
        );
    }
    s += &units_markdown(rows);
    s += &engines_markdown(rows);
    s += &paths_markdown(rows);
    s += &shadows_markdown(rows);
    s += &costliest_markdown(&run.rows);
    s += &ledger_markdown(&run.ledger);
    s += &super::split_markdown(&run.gbuffer_split);
    s += &regret_markdown(rows);
    s += &skipped_markdown(&run.skipped);
    s
}

/// The `engines` rows: each engine's caps against the same frame uncapped, in time and in
/// light lost, with the source of its figures.
pub fn engines_markdown(rows: &[Row]) -> String {
    let mine: Vec<&Row> = rows.iter().filter(|r| r.group == super::groups::ENGINES_GROUP).collect();
    if mine.is_empty() {
        return String::new();
    }
    let fmt = |v: f64, d: usize| if v.is_finite() { format!("{v:.d$}") } else { "-".into() };
    let mut s = String::from(
        "\n### The shortcuts engines ship\n\n\
         Each engine's caps over Lampshade's clustered deferred frame (or its forward path, for the \
         engines that shade forward), against the same frame uncapped. FLIP is against the \
         reference; missed pixels lack light beyond the accumulation's rounding against brute force \
         over every light (the G-buffer paths); dropped pairs are the light-pixel pairs the dropped \
         lights add, by brute force over them; entry pairs are those the per-cluster cap's dropped \
         entries reach (listed for the pixel's cell without the cap, not with it, the light's \
         shape holding the pixel's point).\n\n\
         | engine | lights | size | total ms | x uncapped | FLIP mean | missed pixels | dropped lights | dropped entries | dropped pairs | entry pairs | source |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in &mine {
        let forward = r.path.path == crate::renderer::RenderPath::Forward.name();
        let base = mine.iter().find(|b| {
            b.label == if forward { "forward uncapped" } else { "clustered uncapped" }
                && (b.scene.as_str(), b.lights, b.width, b.height) == (r.scene.as_str(), r.lights, r.width, r.height)
        });
        let ratio = base.map_or(f64::NAN, |b| r.total_ms / b.total_ms);
        s += &format!(
            "| {} | {} | {}x{} | {:.2} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.label,
            r.lights,
            r.width,
            r.height,
            r.total_ms,
            fmt(ratio, 2),
            fmt(r.flip_mean as f64, 5),
            fmt(r.caps.missed_pixels, 0),
            r.caps.dropped_lights,
            r.caps.dropped_entries,
            fmt(r.caps.dropped_pairs, 0),
            fmt(r.caps.entry_pairs, 0),
            r.caps.source
        );
    }
    s
}

/// The culling-mode rows in units that survive a change of hardware, and the fixed passes
/// against the calibration pass.
pub fn units_markdown(rows: &[Row]) -> String {
    let fmt = |v: f64, d: usize| if v.is_finite() { format!("{v:.d$}") } else { "-".into() };
    let mut s = String::new();
    let cal: Vec<&Row> = rows.iter().filter(|r| r.group == CALIBRATION).collect();
    if !cal.is_empty() {
        s += "\n### Fixed passes in full-screen passes\n\n\
              Calibration: one point light reaching every pixel, shaded `fullscreen` over the scene's G-buffer \
              (the scene's lights left out), timed in the same rounds; its lighting ms is the unit (fs). \
              G-buffer and compose: the median over the rows of the same scene and size.\n\n\
              | scene | size | calibration ms | G-buffer ms | G-buffer fs | compose ms | compose fs |\n\
              |---|---|---|---|---|---|---|\n";
        for c in cal {
            let same: Vec<&Row> = rows
                .iter()
                .filter(|r| r.scene == c.scene && r.width == c.width && r.height == c.height && r.label != "limit")
                .filter(|r| r.path.path == RenderPath::Deferred.name() && r.path.error.is_empty())
                .collect();
            let gbuffer = median(same.iter().map(|r| r.gbuffer_ms).filter(|v| v.is_finite()).collect());
            let compose = median(same.iter().map(|r| r.compose_ms).filter(|v| v.is_finite()).collect());
            let scene = Path::new(&c.scene).file_stem().map_or(c.scene.clone(), |f| f.to_string_lossy().into());
            s += &format!(
                "| {scene} | {}x{} | {:.3} | {} | {} | {} | {} |\n",
                c.width,
                c.height,
                c.lighting_ms,
                fmt(gbuffer, 2),
                fmt(gbuffer / c.lighting_ms, 2),
                fmt(compose, 2),
                fmt(compose / c.lighting_ms, 2)
            );
        }
    }
    let modes: Vec<&Row> = rows.iter().filter(|r| LIMIT_GROUPS.contains(&r.group.as_str())).collect();
    if modes.is_empty() {
        return s;
    }
    s += "\n### Lighting in units that survive a change of hardware\n\n\
          ns/pair: lighting ns per evaluated light–pixel pair (the mode's shaded fragments, or its list entries walked \
          per pixel); ns/ideal: per pair inside the lights' true shapes; ρ_fs: lighting ms in calibration passes; \
          culling share: GPU list building or marking over lighting (`-` for the drawn modes, which mark in the draws \
          that shade, and for lists built on the CPU); x limit: total over the `limit` row.\n\n\
          | group | configuration | lights | size | lighting ms | lists ms | ns/pair | ns/ideal | ρ_fs | culling share | x limit |\n\
          |---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in modes {
        s += &format!(
            "| {} | {} | {} | {}x{} | {:.2} | {} | {} | {} | {} | {} | {} |\n",
            r.group,
            r.label,
            r.lights,
            r.width,
            r.height,
            r.lighting_ms,
            fmt(r.lists_ms, 2),
            fmt(r.units.ns_per_pair, 3),
            fmt(r.units.ns_per_ideal, 3),
            fmt(r.units.rho_fs, 1),
            if r.units.culling_share.is_finite() {
                format!("{:.0}%", r.units.culling_share * 100.0)
            } else {
                "-".into()
            },
            fmt(r.limit_ratio, 2)
        );
    }
    s
}

/// The `shadows` group's table: the shadow pass's GPU ms (outside `total ms`), the
/// bytes of the atlas and the cube array, who casts, and the error against the finest shadows.
pub fn shadows_markdown(rows: &[Row]) -> String {
    let shadows: Vec<&Row> = rows.iter().filter(|r| r.group == "shadows").collect();
    if shadows.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n### Shadows\n\n\
         Shadow ms: the shadow pass (atlas and cube array; `-` where nothing cast), part of `total ms`. \
         Bytes: the atlas, the cube array and the indirection cube as allocated; cube side: the cube array's face \
         or the indirection cube's. Casting: lights with shadows (the sun counted); budget, \
         off screen: lights that fell back to unshadowed for the budget or for being off screen. FLIP mean against the finest shadows (64 MiB, poisson16, \
         4 cascades) of the same casters (`cube` rows: every light, cubes unrolled).\n\n\
         | configuration | lights | shadow ms | total ms | bytes | casting | budget | off screen | cube side | FLIP mean |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in shadows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {:.5} |\n",
            r.label,
            r.lights,
            if r.shadow.gpu_ms.is_finite() { format!("{:.2}", r.shadow.gpu_ms) } else { "-".into() },
            r.total_ms,
            r.shadow.bytes,
            r.shadow.casting,
            r.shadow.fallback_budget,
            r.shadow.fallback_off_screen,
            if r.shadow.cube_side > 0 { r.shadow.cube_side.to_string() } else { "-".into() },
            r.flip_mean
        );
    }
    s
}

/// The `path` group's table: per scene and light count, each path's intermediate
/// bytes per pixel, passes, draw calls, GPU ms and error; a path that failed says why.
pub fn paths_markdown(rows: &[Row]) -> String {
    let paths: Vec<&Row> = rows.iter().filter(|r| r.group == "path").collect();
    if paths.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n### Rendering paths\n\n\
         Bytes/pixel: every intermediate target, samples included. Passes: up to the compose or tonemap. \
         Draw calls: every draw up to the compose or tonemap (deferred: one per object into the G-buffer, its light draws, \
         the compose; light pre-pass: pass 1's and pass 3's object draws, its light draws and the tonemap; forward: every \
         pass's draws and the tonemap). \
         Pairs: entries of the forward object light lists, the (object, light) draws of multi-pass. \
         Lit: the deferred light pass's shaded fragments for that scene and count. \
         Shaded: fragments the path's shading passes shaded (deferred: light fragments). Error: FLIP mean against the reference.\n\n\
         | scene | lights | path | bytes/pixel | passes | draw calls | pairs | lit | shaded | GPU ms | FLIP mean |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in paths {
        let scene = std::path::Path::new(&r.scene).file_stem().map_or(r.scene.clone(), |f| f.to_string_lossy().into());
        if !r.path.error.is_empty() {
            s += &format!("| {scene} | {} | {} | error: {} | | | | | | | |\n", r.lights, r.path.path, r.path.error);
            continue;
        }
        s += &format!(
            "| {scene} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.5} |\n",
            r.lights,
            r.path.path,
            r.path.target_bytes_per_pixel,
            r.path.passes,
            r.path.draw_calls,
            r.path.object_light_pairs,
            r.path.lit_fragments,
            r.shaded_fragments,
            r.total_ms,
            r.flip_mean
        );
    }
    s
}

/// For each x (light count in `lights`, radius factor in `radius`), the culling mode with the
/// lowest total time: where each mode wins.
pub fn winners(rows: &[Row], group: &str) -> Vec<(f64, String, f64)> {
    let x = |r: &Row| if group == "radius" { r.radius_scale } else { r.lights as f64 };
    let mut xs: Vec<f64> = rows.iter().filter(|r| r.group == group).map(x).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    xs.into_iter()
        .filter_map(|v| {
            rows.iter()
                .filter(|r| r.group == group && x(r) == v && r.label != "limit" && r.total_ms.is_finite())
                .min_by(|a, b| a.total_ms.total_cmp(&b.total_ms))
                .map(|r| (v, r.culling.clone(), r.total_ms))
        })
        .collect()
}
