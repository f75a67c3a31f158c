//! Panels laid out over each other: the check a scripted run makes with `overlaps`, so the
//! window tests catch a region drawn over another (the pixel probe over the scene tab's
//! controls, in a window of the default size). Each region of the window reports the
//! rectangle it drew in ([`Region`]); regions that share a parent must not overlap, and a
//! region must lie inside its parent.

use super::common::Region;

/// What overlaps: sibling regions whose intersection is over a pixel in both directions
/// (touching edges and rounding do not count), and regions reaching over a pixel out of their
/// parent.
pub fn overlaps(regions: &[Region]) -> Vec<String> {
    let mut found = Vec::new();
    for (i, a) in regions.iter().enumerate() {
        for b in &regions[i + 1..] {
            let x = a.rect.intersect(b.rect);
            if a.parent == b.parent && x.width() > 1.0 && x.height() > 1.0 {
                found.push(format!("{} {:?} and {} {:?} overlap by {:?}", a.name, a.rect, b.name, b.rect, x.size()));
            }
        }
        if let Some(p) = a.parent.and_then(|p| regions.iter().find(|r| r.name == p)) {
            if !p.rect.expand(1.0).contains_rect(a.rect) {
                found.push(format!("{} {:?} reaches out of {} {:?}", a.name, a.rect, p.name, p.rect));
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{pos2, Rect};

    fn region(name: &'static str, parent: Option<&'static str>, x0: f32, y0: f32, x1: f32, y1: f32) -> Region {
        Region { name, parent, rect: Rect::from_min_max(pos2(x0, y0), pos2(x1, y1)) }
    }

    #[test]
    fn siblings_that_overlap_and_children_that_reach_out_are_found_and_touching_is_not() {
        let ok = [
            region("left", None, 0.0, 40.0, 270.0, 700.0),
            region("tabs", Some("left"), 0.0, 80.0, 270.0, 462.0),
            region("probe", Some("left"), 0.0, 462.0, 270.0, 700.0),
            region("viewport", None, 270.0, 40.0, 990.0, 570.0),
        ];
        assert!(overlaps(&ok).is_empty(), "{:?}", overlaps(&ok));
        // The scroll area running 43 px into the probe below it (as a panel laid over it did).
        let mut bad = ok.clone();
        bad[1].rect.max.y = 505.0;
        assert_eq!(overlaps(&bad).len(), 1, "{:?}", overlaps(&bad));
        let mut out = ok.clone();
        out[2].rect.max.y = 720.0;
        assert_eq!(overlaps(&out).len(), 1, "{:?}", overlaps(&out));
    }
}
