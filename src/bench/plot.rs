//! The bench's charts (plotters): time against error, the paths over the light count, scaling.

use super::*;

/// Seed 002's claim, plotted from the `path` group: GPU ms of each path against the (object,
/// light) pairs (left; forward multi-pass draws one per pair) and against the lit fragments
/// (right; deferred shades those), log-log, one series per path, the room ringed.
pub fn plot_paths(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let pts: Vec<&Row> = rows
        .iter()
        .filter(|r| r.group == "path" && r.path.error.is_empty() && r.total_ms.is_finite() && r.total_ms > 0.0)
        .collect();
    if pts.is_empty() {
        anyhow::bail!("no path row rendered");
    }
    let root = BitMapBackend::new(path, (1400, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, 2));
    let (t0, t1) = pts.iter().fold((f64::INFINITY, 0f64), |(a, b), r| (a.min(r.total_ms), b.max(r.total_ms)));
    let (t_lo, t_hi) = (t0 / 1.3, t1 * 1.3);
    let t_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
    let t_dec = crate::plot_layout::tick_decimals(&t_ticks);
    type Axis = fn(&Row) -> f64;
    let panels_spec: [(&str, &str, Axis); 2] = [
        ("GPU ms against (object, light) pairs", "(object, light) pairs", |r| r.path.object_light_pairs as f64),
        ("GPU ms against lit fragments (deferred)", "lit fragments", |r| r.path.lit_fragments as f64),
    ];
    for ((caption, x_desc, x), area) in panels_spec.into_iter().zip(panels.iter()) {
        let xs: Vec<f64> = pts.iter().map(|r| x(r)).filter(|v| *v > 0.0).collect();
        if xs.is_empty() {
            continue;
        }
        let (x_lo, x_hi) = xs.iter().fold((f64::INFINITY, 0f64), |(a, b), v| (a.min(*v), b.max(*v)));
        let (x_lo, x_hi) = (x_lo / 1.3, x_hi * 1.3);
        let x_ticks = crate::plot_layout::log_ticks(x_lo, x_hi);
        let x_dec = crate::plot_layout::tick_decimals(&x_ticks);
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 20))
            .margin(14)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (t_lo..t_hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("GPU ms per frame (median; room ringed)")
            .label_style(("sans-serif", 13))
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .draw()?;
        draw_ticks(&mut chart, area, (&x_ticks, x_dec), (&t_ticks, t_dec), (x_lo, x_hi), (t_lo, t_hi))?;
        for (i, p) in RenderPath::ALL.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let mut mine: Vec<(f64, f64, bool)> = pts
                .iter()
                .filter(|r| r.path.path == p.name() && x(r) > 0.0)
                .map(|r| (x(r), r.total_ms, r.scene == ROOM))
                .collect();
            if mine.is_empty() {
                continue;
            }
            mine.sort_by(|a, b| a.0.total_cmp(&b.0));
            let line: Vec<(f64, f64)> = mine.iter().filter(|m| !m.2).map(|m| (m.0, m.1)).collect();
            chart
                .draw_series(LineSeries::new(line, colour.stroke_width(2)))?
                .label(p.name())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            chart.draw_series(mine.iter().map(|&(x, y, room)| {
                if room {
                    Circle::new((x, y), 7, colour.stroke_width(2))
                } else {
                    Circle::new((x, y), 4, colour.filled())
                }
            }))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// Time (x) against FLIP error (y): one panel per group, one labelled point per configuration,
/// the default configuration (`culling` / `volume`) in grey in every panel for comparison, and
/// the Pareto front of the panel's scene, light count and size joined by a black line (points
/// on it ringed).
pub fn plot(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let pts: Vec<&Row> = rows
        .iter()
        .filter(|r| r.total_ms.is_finite() && r.total_ms > 0.0 && r.flip_mean.is_finite() && r.label != "limit")
        .collect();
    let mut groups: Vec<&str> = Vec::new();
    for r in &pts {
        if !groups.contains(&r.group.as_str()) {
            groups.push(&r.group);
        }
    }
    let cols = groups.len().clamp(1, 4);
    let rows_n = groups.len().div_ceil(cols).max(1);
    let root = BitMapBackend::new(path, (480 * cols as u32, 400 * rows_n as u32 + 50)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(50);
    title.titled("Speed against error, one panel per knob (lower left is better)", ("sans-serif", 26))?;
    let panels = body.split_evenly((rows_n, cols));
    let palette = PALETTE;
    let default = pts.iter().find(|r| r.group == "culling" && r.label == "volume").copied();
    let key = |r: &Row| (r.scene.clone(), r.lights, r.width, r.height);
    for (gi, (g, area)) in groups.iter().zip(panels.iter()).enumerate() {
        let color = palette[gi % palette.len()];
        let mut mine: Vec<&Row> = pts.iter().filter(|r| r.group == *g).copied().collect();
        if let Some(d) = default.filter(|_| *g != "culling") {
            mine.push(d);
        }
        let t_lo = mine.iter().map(|r| r.total_ms).fold(f64::INFINITY, f64::min) / 1.5;
        let t_hi = mine.iter().map(|r| r.total_ms).fold(0.0, f64::max) * 2.5;
        let e_hi = mine.iter().map(|r| r.flip_mean as f64).fold(1e-4, f64::max) * 1.25;
        // Ticks of our own: at least three per axis, labels distinct (plotters' log axis labels
        // only powers of ten, so a narrow range had one tick or none).
        let x_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
        let y_ticks = crate::plot_layout::linear_ticks(0.0, e_hi);
        let (x_dec, y_dec) = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&y_ticks));
        let mut chart = ChartBuilder::on(area)
            .caption(*g, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(64)
            .build_cartesian_2d((t_lo..t_hi).log_scale(), 0.0..e_hi)?;
        blank_mesh(&mut chart, ("GPU ms per frame (median)", "FLIP mean"), 13)?;
        let font: TextStyle = ("sans-serif", 13).into_font().into();
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let base = area.get_base_pixel();
        draw_ticks(&mut chart, area, (&x_ticks, x_dec), (&y_ticks, y_dec), (t_lo, t_hi), (0.0, e_hi))?;
        // The Pareto front of each scene/lights/size among this panel's points.
        let mut keys: Vec<_> = mine.iter().map(|r| key(r)).collect();
        keys.dedup();
        for k in keys {
            let mut front: Vec<(f64, f64)> =
                mine.iter().filter(|r| r.pareto && key(r) == k).map(|r| (r.total_ms, r.flip_mean as f64)).collect();
            front.sort_by(|a, b| a.0.total_cmp(&b.0));
            if front.len() > 1 {
                chart.draw_series(LineSeries::new(front, BLACK.stroke_width(1)))?;
            }
        }
        // Markers first, then each label where it covers no marker and no other label and
        // stays inside the plotting area (`plot_layout::place_labels`).
        mine.sort_by(|a, b| a.total_ms.total_cmp(&b.total_ms).then(b.flip_mean.total_cmp(&a.flip_mean)));
        let mut points = Vec::new();
        let mut sizes = Vec::new();
        let mut labels = Vec::new();
        for r in &mine {
            let is_default = default.is_some_and(|d| std::ptr::eq(d, *r)) && *g != "culling";
            let c = if is_default { RGBColor(160, 160, 160) } else { color };
            let p = (r.total_ms, r.flip_mean as f64);
            let label = if is_default {
                "default".to_string()
            } else if r.lights == default.map_or(0, |d| d.lights) {
                r.label.clone()
            } else {
                format!("{} ({} lights)", r.label, r.lights)
            };
            chart.draw_series(std::iter::once(Circle::new(p, 5, c.filled())))?;
            if r.pareto {
                chart.draw_series(std::iter::once(Circle::new(p, 8, BLACK.stroke_width(1))))?;
            }
            let (w, h) = area.estimate_text_size(&label, &font)?;
            points.push(chart.backend_coord(&p));
            sizes.push((w as i32, h as i32));
            labels.push((p, label, c));
        }
        let spots = crate::plot_layout::place_labels(&points, &sizes, 8, (xr.start, yr.start, xr.end, yr.end));
        let mut left_out = 0;
        for (((p, label, c), spot), (px, py)) in labels.into_iter().zip(spots).zip(points) {
            let Some((l, t, _, _)) = spot else {
                left_out += 1;
                continue;
            };
            chart.draw_series(std::iter::once(
                EmptyElement::at(p) + Text::new(label, (l - px, t - py), font.color(&c)),
            ))?;
        }
        if left_out > 0 {
            let (x0, y1) = (xr.start + 4, yr.end - 16);
            area.draw(&Text::new(
                format!("{left_out} label(s) left out: no free spot (see bench.md)"),
                (x0 - base.0, y1 - base.1),
                font.color(&BLACK),
            ))?;
        }
    }
    root.present()?;
    Ok(())
}

/// The axes' descriptions without plotters' own labels or grid: its log axis labels only its
/// powers of ten, so the charts blank them and draw their own ticks ([`draw_ticks`]).
pub(crate) fn blank_mesh<DB, X, Y>(
    chart: &mut plotters::chart::ChartContext<'_, DB, plotters::coord::cartesian::Cartesian2d<X, Y>>,
    (x_desc, y_desc): (&str, &str),
    size: u32,
) -> Result<()>
where
    DB: plotters::prelude::DrawingBackend,
    DB::ErrorType: 'static,
    X: plotters::coord::ranged1d::Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", size))
        .disable_mesh()
        .x_labels(0)
        .y_labels(0)
        .x_label_formatter(&|_| String::new())
        .y_label_formatter(&|_| String::new())
        .draw()
        .map_err(|e| anyhow::anyhow!("drawing the plot: {e}"))
}

/// Grid lines and labels at our own ticks (`plot_layout`): plotters' log axes label only
/// powers of ten, so both plots blank its labels and draw these. `x` and `y` are the ticks with
/// their decimals; the ranges are the plotted ones.
/// The plots' series colours, one per configuration or culling mode in order (both plots).
pub(crate) const PALETTE: [plotters::style::RGBColor; 8] = {
    use plotters::style::{RGBColor, BLUE, MAGENTA, RED};
    [
        RED,
        BLUE,
        RGBColor(0, 150, 0),
        MAGENTA,
        RGBColor(0, 150, 170),
        RGBColor(230, 120, 0),
        RGBColor(120, 70, 20),
        RGBColor(90, 90, 90),
    ]
};

pub(crate) fn draw_ticks<DB, X, Y>(
    chart: &mut plotters::chart::ChartContext<'_, DB, plotters::coord::cartesian::Cartesian2d<X, Y>>,
    area: &plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    (x_ticks, x_dec): (&[f64], usize),
    (y_ticks, y_dec): (&[f64], usize),
    (x_lo, x_hi): (f64, f64),
    (y_lo, y_hi): (f64, f64),
) -> Result<()>
where
    DB: plotters::prelude::DrawingBackend,
    DB::ErrorType: 'static,
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    use plotters::prelude::*;
    let font: TextStyle = ("sans-serif", 13).into_font().into();
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let base = area.get_base_pixel();
    let grid = RGBColor(225, 225, 225);
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("drawing the plot: {e}");
    for &v in x_ticks {
        chart.draw_series(LineSeries::new([(v, y_lo), (v, y_hi)], grid)).map_err(|e| err(&e))?;
        let text = format!("{v:.x_dec$}");
        let (w, _) = area.estimate_text_size(&text, &font).map_err(|e| err(&e))?;
        let (px, _) = chart.backend_coord(&(v, y_lo));
        area.draw(&Text::new(text, (px - w as i32 / 2 - base.0, yr.end + 4 - base.1), font.clone()))
            .map_err(|e| err(&e))?;
    }
    for &v in y_ticks {
        chart.draw_series(LineSeries::new([(x_lo, v), (x_hi, v)], grid)).map_err(|e| err(&e))?;
        let text = format!("{v:.y_dec$}");
        let (w, h) = area.estimate_text_size(&text, &font).map_err(|e| err(&e))?;
        let (_, py) = chart.backend_coord(&(x_lo, v));
        area.draw(&Text::new(text, (xr.start - 6 - w as i32 - base.0, py - h as i32 / 2 - base.1), font.clone()))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// Where each culling mode wins: total GPU ms (log) against the light count (log) and against
/// the light radius factor, one line per mode, the `limit` dashed in black, the fastest mode at
/// each point ringed. Rows of the `lights` and `radius` groups.
pub fn plot_scaling(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let root = BitMapBackend::new(path, (1200, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(50);
    title.titled("Where each culling mode wins (total GPU ms per frame, lower is better)", ("sans-serif", 24))?;
    let panels = body.split_evenly((1, 2));
    let palette = PALETTE;
    for (group, area) in ["lights", "radius"].into_iter().zip(panels.iter()) {
        let x = |r: &Row| if group == "radius" { r.radius_scale } else { r.lights as f64 };
        let mine: Vec<&Row> =
            rows.iter().filter(|r| r.group == group && r.total_ms.is_finite() && r.total_ms > 0.0).collect();
        if mine.is_empty() {
            area.titled(&format!("{group}: not run"), ("sans-serif", 18))?;
            continue;
        }
        let (x_lo, x_hi) = mine.iter().map(|r| x(r)).fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (t_lo, t_hi) =
            mine.iter().map(|r| r.total_ms).fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (x_lo, x_hi) = (x_lo / 1.3, x_hi * 1.3);
        let (t_lo, t_hi) = (t_lo / 1.3, t_hi * 1.3);
        let x_ticks = crate::plot_layout::log_ticks(x_lo, x_hi);
        let t_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
        let (x_dec, t_dec) = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&t_ticks));
        let caption = if group == "radius" {
            format!("over light radius ({} lights, radius x factor)", mine[0].lights)
        } else {
            "over light count (radius as the scene gives it)".to_string()
        };
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 18))
            .margin(14)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (t_lo..t_hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(if group == "radius" { "light radius factor" } else { "lights" })
            .y_desc("GPU ms per frame (median)")
            .label_style(("sans-serif", 13))
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .draw()?;
        draw_ticks(&mut chart, area, (&x_ticks, x_dec), (&t_ticks, t_dec), (x_lo, x_hi), (t_lo, t_hi))?;
        let mut modes: Vec<String> = Vec::new();
        for r in &mine {
            if !modes.contains(&r.culling) {
                modes.push(r.culling.clone());
            }
        }
        let wins = winners(rows, group);
        for (i, mode) in modes.iter().enumerate() {
            let mut line: Vec<(f64, f64)> =
                mine.iter().filter(|r| &r.culling == mode).map(|r| (x(r), r.total_ms)).collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            let is_limit = mode == "limit";
            let color = if is_limit { BLACK } else { palette[i % palette.len()] };
            let style = color.stroke_width(if is_limit { 1 } else { 2 });
            if is_limit {
                let dashes: Vec<[(f64, f64); 2]> = line.windows(2).flat_map(|w| log_dashes(w[0], w[1], 20)).collect();
                for d in dashes {
                    chart.draw_series(LineSeries::new(d, style))?;
                }
            } else {
                chart.draw_series(LineSeries::new(line.clone(), style))?;
            }
            chart
                .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))?
                .label(mode.as_str())
                .legend(move |(lx, ly)| Rectangle::new([(lx, ly - 4), (lx + 14, ly + 4)], color.filled()));
        }
        for (v, _, t) in &wins {
            chart.draw_series(std::iter::once(Circle::new((*v, *t), 9, BLACK.stroke_width(2))))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// The advisor's plot: frame time against light count (log-log), one colour per candidate, its
/// measured times as points joined by solid lines and its predicted line dashed; each
/// crossover marked with a vertical line, predicted dashed and measured solid.
pub fn plot_advice(a: &super::advise::Advice, path: &Path) -> Result<()> {
    use plotters::prelude::*;
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow::anyhow!("cannot load the plot font"))?;
    let root = BitMapBackend::new(path, (1000, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(50);
    title.titled(
        &format!("{} at {}x{}: predicted (dashed) and measured (solid) GPU ms per frame", a.scene, a.size.0, a.size.1),
        ("sans-serif", 20),
    )?;
    let counts: Vec<f64> = a.counts.iter().map(|&n| n as f64).collect();
    let (Some(&n_lo), Some(&n_hi)) = (counts.first(), counts.last()) else {
        root.present()?;
        return Ok(());
    };
    let (x_lo, x_hi) = (n_lo / 1.5, n_hi * 1.5);
    let times: Vec<f64> =
        a.predicted.iter().chain(&a.measured).flatten().copied().filter(|v| v.is_finite() && *v > 0.0).collect();
    let (t_lo, t_hi) = times.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
    let (t_lo, t_hi) = if t_lo.is_finite() { (t_lo / 1.5, t_hi * 1.5) } else { (1.0, 10.0) };
    let x_ticks = crate::plot_layout::log_ticks(x_lo, x_hi);
    let t_ticks = crate::plot_layout::log_ticks(t_lo, t_hi);
    let (x_dec, t_dec) = (crate::plot_layout::tick_decimals(&x_ticks), crate::plot_layout::tick_decimals(&t_ticks));
    let mut chart = ChartBuilder::on(&body)
        .margin(14)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d((x_lo..x_hi).log_scale(), (t_lo..t_hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("lights")
        .y_desc("GPU ms per frame (median)")
        .label_style(("sans-serif", 13))
        .disable_mesh()
        .x_labels(0)
        .y_labels(0)
        .x_label_formatter(&|_| String::new())
        .y_label_formatter(&|_| String::new())
        .draw()?;
    draw_ticks(&mut chart, &body, (&x_ticks, x_dec), (&t_ticks, t_dec), (x_lo, x_hi), (t_lo, t_hi))?;
    let dashed = |from: (f64, f64), to: (f64, f64)| log_dashes(from, to, 24);
    for (c, name) in a.candidates.iter().enumerate() {
        let color = PALETTE[c % PALETTE.len()];
        let measured: Vec<(f64, f64)> = counts
            .iter()
            .zip(&a.measured[c])
            .filter(|(_, t)| t.is_finite() && **t > 0.0)
            .map(|(&n, &t)| (n, t))
            .collect();
        chart.draw_series(LineSeries::new(measured.clone(), color.stroke_width(2)))?;
        chart
            .draw_series(measured.iter().map(|&p| Circle::new(p, 4, color.filled())))?
            .label(name.as_str())
            .legend(move |(lx, ly)| Rectangle::new([(lx, ly - 4), (lx + 14, ly + 4)], color.filled()));
        if let Some(f) = &a.fits[c] {
            let (p0, p1) = ((x_lo, f.predict(x_lo)), (x_hi, f.predict(x_hi)));
            if p0.1 > 0.0 && p1.1 > 0.0 {
                for d in dashed(p0, p1) {
                    chart.draw_series(LineSeries::new(d, color.stroke_width(1)))?;
                }
            }
        }
    }
    for (n, _, _) in &a.predicted_crossovers {
        for d in dashed((*n, t_lo), (*n, t_hi)) {
            chart.draw_series(LineSeries::new(d, BLACK.stroke_width(1)))?;
        }
    }
    for (n, _, _) in &a.measured_crossovers {
        chart.draw_series(LineSeries::new([(*n, t_lo), (*n, t_hi)], BLACK.stroke_width(2)))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()?;
    root.present()?;
    Ok(())
}

/// A dashed line from `from` to `to` on log-log axes: every other of `pieces` segments, equal in
/// length on the axes.
fn log_dashes(from: (f64, f64), to: (f64, f64), pieces: usize) -> Vec<[(f64, f64); 2]> {
    let at = |f: f64| (from.0 * (to.0 / from.0).powf(f), from.1 * (to.1 / from.1).powf(f));
    (0..pieces).step_by(2).map(|k| [at(k as f64 / pieces as f64), at((k + 1) as f64 / pieces as f64)]).collect()
}
