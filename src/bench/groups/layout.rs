//! The `layout` group: the G-buffer layouts and normal encodings.

use super::sweep::Sweep;
use crate::bench::options::Config;
use crate::renderer::{LayoutChoice, Settings};

pub fn rows(s: &Sweep) -> Vec<Config> {
    let (o, q, base) = (s.o, s.o.quick, &s.base);
    // Seed 000's fp16 targets, the packed and fitted layouts, and the normal encodings with
    // everything else as `compact` stores it (compact itself is the `volume` row).
    let layouts: Vec<LayoutChoice> = if q {
        vec![LayoutChoice::Seed000, LayoutChoice::Oct8, LayoutChoice::Xyz8]
    } else {
        [LayoutChoice::Seed000, LayoutChoice::Packed, LayoutChoice::Fit]
            .into_iter()
            .chain(LayoutChoice::NORMAL_ENCODINGS)
            .collect()
    };
    let mut v = Vec::new();
    for layout in layouts {
        v.push(s.row("layout", format!("{layout:?}").to_lowercase(), Settings { layout, ..base.clone() }, o.lights));
    }
    v
}
