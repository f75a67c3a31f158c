//! The `stochastic` group's report: per layout, speed against error of the exact modes, the
//! stochastic estimators and the engines' caps on one chart (`stochastic.png`), and the table
//! the crossover is read from (`stochastic.md`).

use super::groups::STOCHASTIC_GROUP;
use super::Row;
use anyhow::Result;
use std::path::Path;

/// The FLIP mean under which an estimator's picture counts as reached.
pub const FLIP_TARGET: f32 = 0.05;

/// A row's layout (its label before ": ") and configuration.
fn split(r: &Row) -> (&str, &str) {
    r.label.split_once(": ").unwrap_or(("", &r.label))
}

/// A row's lighting time: the lighting span (list builds included), or a forward path's pass.
pub fn lighting_ms(r: &Row) -> f64 {
    if r.lighting_ms.is_finite() && r.lighting_ms > 0.0 {
        r.lighting_ms
    } else {
        r.forward_ms
    }
}

/// A row's lights per pixel: its frame's G-buffer points inside a light's shape, per pixel.
pub fn lights_per_pixel(r: &Row) -> f64 {
    r.ideal_fragments as f64 / (r.width as f64 * r.height as f64)
}

/// What kind of configuration a row is, by its label.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Family {
    Exact,
    Ris,
    StochasticCulling,
    Engine,
}

pub fn family(config: &str) -> Family {
    if config.contains(" RIS ") {
        Family::Ris
    } else if config.ends_with("stochastic culling") {
        Family::StochasticCulling
    } else if super::groups::STOCHASTIC_EXACT_MODES.iter().any(|m| m.name() == config) {
        Family::Exact
    } else {
        Family::Engine
    }
}

/// The group's rows by layout, in the order they ran.
fn layouts(rows: &[Row]) -> Vec<(&str, Vec<&Row>)> {
    let mut out: Vec<(&str, Vec<&Row>)> = Vec::new();
    for r in rows.iter().filter(|r| r.group == STOCHASTIC_GROUP) {
        let (layout, _) = split(r);
        match out.iter_mut().find(|(l, _)| *l == layout) {
            Some((_, v)) => v.push(r),
            None => out.push((layout, vec![r])),
        }
    }
    out
}

/// The markdown report: per layout, lights per pixel, the fastest exact mode, and for each RIS
/// mode the first K whose FLIP mean is at most [`FLIP_TARGET`] with its lighting time against
/// the fastest exact mode's; then every row.
pub fn stochastic_markdown(rows: &[Row]) -> String {
    let mut s = String::from("## The stochastic group\n\n");
    s += &format!(
        "Lighting ms (list builds included), FLIP mean against the reference, per layout. \"first K\" is the \
         fewest RIS samples whose FLIP mean is at most {FLIP_TARGET}; its time is against the fastest exact mode's.\n\n"
    );
    s += "| layout | lights/px | fastest exact (ms, FLIP) | clustered RIS: first K (ms, x exact) | zbin RIS: first K (ms, x exact) | best stochastic culling (ms, FLIP) |\n|---|---|---|---|---|---|\n";
    for (layout, v) in layouts(rows) {
        let lpp = v.iter().map(|r| lights_per_pixel(r)).fold(0.0, f64::max);
        let fastest = |f: Family| {
            v.iter()
                .filter(|r| family(split(r).1) == f && lighting_ms(r).is_finite())
                .min_by(|a, b| lighting_ms(a).total_cmp(&lighting_ms(b)))
                .copied()
        };
        let exact = fastest(Family::Exact);
        let exact_ms = exact.map_or(f64::NAN, lighting_ms);
        let first_k = |mode: &str| {
            v.iter()
                .filter(|r| split(r).1.starts_with(&format!("{mode} RIS")) && r.flip_mean <= FLIP_TARGET)
                .min_by_key(|r| split(r).1.rsplit('K').next().and_then(|k| k.parse::<u32>().ok()).unwrap_or(u32::MAX))
                .map_or("not reached".to_string(), |r| {
                    format!(
                        "{} ({:.2} ms, x{:.2})",
                        split(r).1.rsplit(' ').next().unwrap_or(""),
                        lighting_ms(r),
                        lighting_ms(r) / exact_ms
                    )
                })
        };
        let culled = fastest(Family::StochasticCulling)
            .map_or("-".into(), |r| format!("{} ({:.2} ms, {:.4})", split(r).1, lighting_ms(r), r.flip_mean));
        s += &format!(
            "| {layout} | {lpp:.2} | {} | {} | {} | {culled} |\n",
            exact.map_or("-".into(), |r| format!("{} ({:.2} ms, {:.4})", split(r).1, exact_ms, r.flip_mean)),
            first_k("clustered"),
            first_k("zbin"),
        );
    }
    s += "\n| layout | configuration | lighting ms | FLIP mean | ns/px | lights/px |\n|---|---|---|---|---|---|\n";
    for (layout, v) in layouts(rows) {
        for r in v {
            let ms = lighting_ms(r);
            s += &format!(
                "| {layout} | {} | {ms:.3} | {:.4} | {:.2} | {:.2} |\n",
                split(r).1,
                r.flip_mean,
                ms * 1e6 / (r.width as f64 * r.height as f64),
                lights_per_pixel(r)
            );
        }
    }
    s
}

/// The chart: a panel per layout, lighting ms (log) against FLIP mean, the exact modes, RIS,
/// stochastic culling and the engines' caps in their own colours, the panel's Pareto front
/// drawn through.
pub fn plot_stochastic(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let panels = layouts(rows);
    let cols = panels.len().clamp(1, 4);
    let rows_n = panels.len().div_ceil(cols).max(1);
    let root = BitMapBackend::new(path, (420 * cols as u32, 360 * rows_n as u32 + 80)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(80);
    title.titled(
        "Stochastic against exact: lighting ms against FLIP mean per layout (lower left is better)",
        ("sans-serif", 24),
    )?;
    let legend = [
        (Family::Exact, "exact modes", super::PALETTE[1]),
        (Family::Ris, "RIS, K from 1 to 16", super::PALETTE[0]),
        (Family::StochasticCulling, "stochastic culling", super::PALETTE[2]),
        (Family::Engine, "engine caps", super::PALETTE[5]),
    ];
    for (i, (_, name, c)) in legend.iter().enumerate() {
        let x = 20 + 260 * i as i32;
        title.draw(&Circle::new((x, 60), 6, c.filled()))?;
        title.draw(&Text::new(*name, (x + 12, 52), ("sans-serif", 16).into_font()))?;
    }
    let areas = body.split_evenly((rows_n, cols));
    for ((layout, v), area) in panels.iter().zip(areas.iter()) {
        let pts: Vec<(f64, f64, Family)> = v
            .iter()
            .filter(|r| lighting_ms(r).is_finite() && lighting_ms(r) > 0.0 && r.flip_mean.is_finite())
            .map(|r| (lighting_ms(r), r.flip_mean as f64, family(split(r).1)))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let lo = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min) / 1.5;
        let hi = pts.iter().map(|p| p.0).fold(0.0, f64::max) * 1.5;
        let e_hi = pts.iter().map(|p| p.1).fold(1e-3, f64::max) * 1.15;
        let lpp = v.iter().map(|r| lights_per_pixel(r)).fold(0.0, f64::max);
        let mut chart = ChartBuilder::on(area)
            .caption(format!("{layout} ({lpp:.2} lights/px)"), ("sans-serif", 17))
            .margin(10)
            .x_label_area_size(32)
            .y_label_area_size(52)
            .build_cartesian_2d((lo..hi).log_scale(), 0.0..e_hi)?;
        super::plot::blank_mesh(&mut chart, ("lighting ms", "FLIP mean"), 12)?;
        let x_ticks = crate::plot_layout::log_ticks(lo, hi);
        let y_ticks = crate::plot_layout::linear_ticks(0.0, e_hi);
        let decimals = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&y_ticks));
        super::plot::draw_ticks(
            &mut chart,
            area,
            (&x_ticks, decimals.0),
            (&y_ticks, decimals.1),
            (lo, hi),
            (0.0, e_hi),
        )?;
        // The FLIP target.
        chart.draw_series(LineSeries::new([(lo, FLIP_TARGET as f64), (hi, FLIP_TARGET as f64)], BLACK.mix(0.3)))?;
        let mut front: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| !pts.iter().any(|q| q.0 <= p.0 && q.1 <= p.1 && (q.0 < p.0 || q.1 < p.1)))
            .map(|p| (p.0, p.1))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(front, BLACK.stroke_width(1)))?;
        for (f, _, c) in legend {
            chart.draw_series(pts.iter().filter(|p| p.2 == f).map(|p| Circle::new((p.0, p.1), 4, c.filled())))?;
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(label: &str, lighting_ms: f64, flip_mean: f32) -> Row {
        Row {
            group: STOCHASTIC_GROUP.into(),
            label: label.into(),
            lighting_ms,
            flip_mean,
            width: 10,
            height: 10,
            ideal_fragments: 250,
            ..crate::bench::tests::blank_row()
        }
    }

    #[test]
    fn the_summary_names_the_fewest_samples_that_reach_the_target_against_the_fastest_exact_mode() {
        let rows = vec![
            row("wall: clustered", 10.0, 0.01),
            row("wall: zbin", 8.0, 0.01),
            row("wall: zbin stochastic culling", 6.0, 0.07),
            row("wall: clustered RIS K1", 4.0, 0.2),
            row("wall: clustered RIS K8", 16.0, 0.03),
            row("wall: clustered RIS K2", 12.0, 0.04),
            row("wall: zbin RIS K16", 30.0, 0.06),
            row("wall: bevy-default", 3.0, 0.5),
        ];
        let md = stochastic_markdown(&rows);
        let line = md.lines().find(|l| l.starts_with("| wall | 2.50 |")).expect("the layout's line");
        assert!(line.contains("zbin (8.00 ms, 0.0100)"), "{line}");
        assert!(line.contains("K2 (12.00 ms, x1.50)"), "{line}");
        assert!(line.contains("| not reached |"), "{line}");
        assert!(line.contains("zbin stochastic culling (6.00 ms, 0.0700)"), "{line}");
        assert_eq!(family("bevy-default"), Family::Engine);
        assert_eq!(family("tiled"), Family::Exact);
    }
}
