//! Layout for the bench's plots, kept apart from the drawing so it can be tested: axis ticks
//! whose labels are distinct and never fewer than three, and point labels placed where they
//! cover neither another label nor any marker and stay inside the plotting area.

/// Ticks for a logarithmic axis over `lo..=hi` (both > 0): the values m x 10^k inside the
/// range for the coarsest mantissa set that gives at least three (1; 1, 2, 5; 1, 1.5, 2, 3,
/// 5, 7; 1 ..= 9); a range too narrow for any gets linear ticks.
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return linear_ticks(lo, hi);
    }
    let sets: [&[f64]; 4] =
        [&[1.0], &[1.0, 2.0, 5.0], &[1.0, 1.5, 2.0, 3.0, 5.0, 7.0], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]];
    for set in sets {
        let mut ticks = Vec::new();
        let mut k = lo.log10().floor() as i32;
        while 10f64.powi(k) <= hi {
            for m in set {
                let v = m * 10f64.powi(k);
                if v >= lo && v <= hi {
                    ticks.push(v);
                }
            }
            k += 1;
        }
        if ticks.len() >= 3 {
            if ticks.len() <= 10 {
                return ticks;
            }
            // Too many: keep every n-th so at most ten remain.
            let n = ticks.len().div_ceil(10);
            return ticks.into_iter().step_by(n).collect();
        }
    }
    linear_ticks(lo, hi)
}

/// Three to nine ticks at a 1-2-5 step over `lo..=hi`.
pub fn linear_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return vec![lo];
    }
    let raw = (hi - lo) / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| (hi - lo) / s <= 8.0).unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    // Rounding may put the last multiple a hair outside the range.
    (first..=last).map(|i| i as f64 * step).filter(|v| *v >= lo && *v <= hi).collect()
}

/// The fewest decimals (0 ..= 8) that give every tick a different label which reads back as
/// its value (0.5 is "0.5", not "0"; float noise below 1e-9 relative is not a decimal).
pub fn tick_decimals(ticks: &[f64]) -> usize {
    (0..=8)
        .find(|&d| {
            let labels: Vec<String> = ticks.iter().map(|v| format!("{v:.d$}")).collect();
            let faithful = labels
                .iter()
                .zip(ticks)
                .all(|(l, v)| l.parse::<f64>().is_ok_and(|p| (p - v).abs() <= 1e-9 * v.abs().max(f64::MIN_POSITIVE)));
            faithful && labels.iter().enumerate().all(|(i, a)| labels[i + 1..].iter().all(|b| a != b))
        })
        .unwrap_or(8)
}

/// A pixel rectangle: left, top, right, bottom (exclusive).
pub type Rect = (i32, i32, i32, i32);

fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Places one label of size `sizes[i]` beside each marker `points[i]` (pixel centres, markers
/// of radius `marker`): tries right, left, above and below the marker, then further out
/// downwards and upwards, taking the first spot that covers no marker and no label placed
/// before it and lies inside `bounds`. Returns each label's rectangle, or `None` where no
/// spot within reach is free (the caller then leaves that label out rather than hide a marker).
pub fn place_labels(points: &[(i32, i32)], sizes: &[(i32, i32)], marker: i32, bounds: Rect) -> Vec<Option<Rect>> {
    let markers: Vec<Rect> =
        points.iter().map(|&(x, y)| (x - marker, y - marker, x + marker + 1, y + marker + 1)).collect();
    let mut placed: Vec<Rect> = Vec::new();
    let mut out = Vec::with_capacity(points.len());
    for (&(x, y), &(w, h)) in points.iter().zip(sizes) {
        let gap = marker + 3;
        let mut candidates: Vec<(i32, i32)> =
            vec![(x + gap, y - h / 2), (x - gap - w, y - h / 2), (x - w / 2, y - gap - h), (x - w / 2, y + gap)];
        for step in 1..=12 {
            let dy = step * (h + 1);
            candidates.extend([
                (x + gap, y - h / 2 + dy),
                (x + gap, y - h / 2 - dy),
                (x - gap - w, y - h / 2 + dy),
                (x - gap - w, y - h / 2 - dy),
            ]);
        }
        let spot = candidates.into_iter().map(|(l, t)| (l, t, l + w, t + h)).find(|&r| {
            r.0 >= bounds.0
                && r.1 >= bounds.1
                && r.2 <= bounds.2
                && r.3 <= bounds.3
                && !markers.iter().any(|&m| overlaps(r, m))
                && !placed.iter().any(|&p| overlaps(r, p))
        });
        if let Some(r) = spot {
            placed.push(r);
        }
        out.push(spot);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_axis_gets_at_least_three_distinct_tick_labels() {
        // Ranges the bench's panels had: a narrow one (no power of ten inside: one tick or none
        // before), a wide one, a tiny FLIP range (labels repeated at three decimals before).
        for (lo, hi, log) in [
            (20.0, 30.0, true),
            (24.5, 26.0, true),
            (8.0, 120.0, true),
            (0.5, 16000.0, true),
            (0.0, 0.006, false),
            (0.0, 0.00012, false),
            (0.0, 0.04, false),
            (0.004_87, 0.004_93, false),
            // The radius panel: factors 0.5 ..= 4, widened by 1.3 (0.5 was labelled "0").
            (0.5 / 1.3, 4.0 * 1.3, true),
        ] {
            let ticks = if log { log_ticks(lo, hi) } else { linear_ticks(lo, hi) };
            assert!(ticks.len() >= 3 && ticks.len() <= 10, "{lo}..{hi}: {ticks:?}");
            assert!(ticks.iter().all(|&t| t >= lo && t <= hi), "{lo}..{hi}: {ticks:?}");
            let d = tick_decimals(&ticks);
            let labels: Vec<String> = ticks.iter().map(|v| format!("{v:.d$}")).collect();
            let mut unique = labels.clone();
            unique.dedup();
            assert_eq!(unique.len(), labels.len(), "{lo}..{hi}: {labels:?}");
            for (l, v) in labels.iter().zip(&ticks) {
                let p: f64 = l.parse().unwrap_or(f64::NAN);
                assert!((p - v).abs() <= 1e-9 * v.abs().max(1e-300), "{lo}..{hi}: {v} labelled {l}");
            }
        }
        // The old formatting: three decimals on a narrow FLIP range repeats labels.
        let ticks = linear_ticks(0.004_87, 0.004_93);
        let old: Vec<String> = ticks.iter().map(|v| format!("{v:.3}")).collect();
        assert!(old.windows(2).any(|w| w[0] == w[1]), "{old:?}");
    }

    #[test]
    fn labels_cover_no_marker_no_label_and_stay_inside() {
        // The culling panel's crowd: six markers within 30 pixels, labels 100 pixels wide, one
        // marker at the right edge whose label used to run off the panel.
        let points = [(60, 100), (66, 100), (72, 101), (78, 100), (84, 99), (90, 100), (395, 100), (200, 20)];
        let sizes = [(100, 13); 8];
        let bounds = (0, 0, 400, 300);
        let placed = place_labels(&points, &sizes, 8, bounds);
        let rects: Vec<Rect> = placed.iter().map(|r| r.expect("every label finds a spot here")).collect();
        for (i, &r) in rects.iter().enumerate() {
            assert!(r.0 >= 0 && r.1 >= 0 && r.2 <= 400 && r.3 <= 300, "label {i} at {r:?} is cut off");
            for &(x, y) in &points {
                assert!(!overlaps(r, (x - 8, y - 8, x + 9, y + 9)), "label {i} at {r:?} covers the marker at {x},{y}");
            }
            for (j, &s) in rects.iter().enumerate() {
                assert!(i == j || !overlaps(r, s), "labels {i} and {j} overlap");
            }
        }
    }
}
