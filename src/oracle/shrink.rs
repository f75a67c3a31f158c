//! Shrinking a failing case: Zeller's delta debugging ("Simplifying and Isolating
//! Failure-Inducing Input") over its lights, then its boxes: chunks of halving size are taken
//! out while the case still fails, down to single items, so what is left fails and loses that
//! failure when any one light or box is removed.

use super::case::Case;

/// Removes from `items` (through `set`) every chunk whose removal keeps `fails` true.
fn reduce<T: Clone>(
    best: &mut Case,
    get: fn(&Case) -> &Vec<T>,
    set: fn(&mut Case, Vec<T>),
    keep_one: bool,
    fails: &mut impl FnMut(&Case) -> bool,
) {
    let mut chunk = get(best).len().div_ceil(2).max(1);
    loop {
        let mut i = 0;
        while i < get(best).len() {
            let items = get(best);
            let end = (i + chunk).min(items.len());
            let mut rest: Vec<T> = items[..i].to_vec();
            rest.extend_from_slice(&items[end..]);
            if keep_one && rest.is_empty() {
                i = end;
                continue;
            }
            let mut candidate = best.clone();
            set(&mut candidate, rest);
            if fails(&candidate) {
                *best = candidate;
            } else {
                i = end;
            }
        }
        if chunk == 1 {
            break;
        }
        chunk = chunk.div_ceil(2);
    }
}

/// The smallest case found that still `fails`: lights first (at least one is kept), then
/// boxes. `fails(case)` must hold for `case` itself.
pub fn shrink(case: &Case, mut fails: impl FnMut(&Case) -> bool) -> Case {
    let mut best = case.clone();
    reduce(&mut best, |c| &c.lights, |c, v| c.lights = v, true, &mut fails);
    reduce(&mut best, |c| &c.boxes, |c, v| c.boxes = v, false, &mut fails);
    best.aims.push(format!("shrunk from {} lights and {} boxes", case.lights.len(), case.boxes.len()));
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::oracle::case::{generate, Limits};

    /// A failure that needs two given lights together and one box: shrinking keeps exactly
    /// those.
    #[test]
    fn shrinking_keeps_exactly_what_the_failure_needs() {
        let case = generate(7, 3, Limits { max_lights: 64, ..Limits::default() });
        let mut c = case.clone();
        while c.lights.len() < 40 {
            c.lights.extend(case.lights.iter().copied());
        }
        // Tell the lights apart by radius, and mark two and a box.
        for (i, l) in c.lights.iter_mut().enumerate() {
            match l {
                crate::scene::Light::Point(p) => p.radius = 1.0 + i as f32,
                crate::scene::Light::Spot(s) => s.radius = 1.0 + i as f32,
            }
        }
        let (a, b) = (c.lights[5].radius(), c.lights[31].radius());
        let marked = c.boxes[0].clone();
        let fails = |x: &Case| {
            let r: Vec<f32> = x.lights.iter().map(|l| l.radius()).collect();
            r.contains(&a) && r.contains(&b) && x.boxes.contains(&marked)
        };
        let s = shrink(&c, fails);
        assert_eq!(s.lights.iter().map(|l| l.radius()).collect::<Vec<_>>(), vec![a, b]);
        assert_eq!(s.boxes, vec![marked]);
    }
}
