//! The culling methods as one table, [`METHODS`], to be held against the seeds' tables: each
//! row is a method's draws (the marking draw, if any, and the shading draw, each as faces, depth
//! test and stencil), its pipelines' names, what a light drawn with it costs (draws per light,
//! the pixels it covers), and, by its place in the table, the order the light pass draws
//! batches in. Depth is written for standard depth (near = 0) and flipped under reversed Z
//! (`kit::z`).
//!
//! - seed 000 (Kayi, 1,024 point lights): [`STENCIL_TWO_PASS`];
//! - seed 001 (single-pass spot lights): [`STENCIL_INVERT`];
//! - seed 002 (the deferred shading talk): [`STENCIL_REPLACE`], and the
//!   [`VOLUME`] back-face test it compares them with;
//! - [`FULLSCREEN`]: no culling, the reference every method must match.
//!
//! Adding a drawn method is a row here and its `Method` and `CullingMode` values (the compiler
//! lists the matches that lack them).

use crate::renderer::kit::{face, stencil, DrawState, Faces, NO_STENCIL};
use crate::renderer::plan::Method;
use crate::renderer::settings::CullingMode;
use wgpu::{CompareFunction as Cmp, StencilOperation as Op};

/// A culling method's draws.
#[derive(Clone, Debug)]
pub struct StencilMethod {
    /// Drawn first with colour writes off, to mark the stencil.
    pub mark: Option<DrawState>,
    /// Drawn with the lighting shader.
    pub shade: DrawState,
    /// Replaces `shade`, with no mark drawn, for lights whose volume crosses the near plane:
    /// [`CROSSING_NEAR`] for every stencil method.
    pub shade_crossing_near: Option<DrawState>,
    /// The stencil reference: zero, or a value per batch of lights whose pixels never meet
    /// (1..=255, cleared every 255 batches; see `batches.rs`).
    pub reference: Reference,
    /// Whether the shading draw is the light's volume or a full-screen triangle.
    pub fullscreen: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    Zero,
    PerLight,
}

/// No culling: every light shades every pixel (the reference picture).
pub const FULLSCREEN: StencilMethod = StencilMethod {
    mark: None,
    shade: DrawState { faces: Faces::Both, depth: Cmp::Always, stencil: NO_STENCIL },
    shade_crossing_near: None,
    reference: Reference::Zero,
    fullscreen: true,
};

/// The stencil methods' draw for a light whose volume crosses the near plane: the plain volume's
/// (back faces, GreaterEqual, the volume bias), no mark before it.
///
/// Such a volume's faces are clipped: at the near plane, or with depth clamp (no near or far
/// clipping) at the side planes where they pass behind the eye (w <= 0). A vertex the clipper
/// makes on an edge from A to B carries rounding of order 2^-24 (|A| + |B|) in each clip
/// coordinate, and its depth z/w divides that by its own w, which goes to zero at the eye plane
/// (and is n at the near plane: with far vertices at distance D the depth error grows as D/n).
/// The depth interpolated across the clipped face inherits it, beyond what the volume bias
/// (`kit::VOLUME_BIAS_UNITS`) covers. The marks are where that lost light: a spot whose cone
/// passed behind the camera at a 170-degree field of view had its clipped front faces drawn
/// behind surfaces they lay in front of (some 480 float steps at a near plane of 2.8e-7), so
/// two-pass and INVERT marked those pixels outside. And where a front face lies wholly in front
/// of the near plane, depth clamp draws it at exactly the near depth, which a surface on the near
/// plane ties: INVERT's Less then inverts for it. The front faces' test only removes points in
/// front of the volume, so dropping it only adds work; the back faces' GreaterEqual is what
/// `auto` and `volume` draw these lights with. Their clipped depth has no derived bound either:
/// seed 004's rule (`NearLights::Fullscreen`) does not rest on it. Without depth clamp the plan
/// takes that rule whatever the setting: at w = n the error divides by the near distance itself,
/// and a spot of radius 103 at a near plane of 1.1e-5 (fov 170 degrees) had its clipped back
/// faces drawn in front of surfaces they lay behind. With depth clamp the near plane does not
/// clip; only edges passing behind the eye are clipped, at the side planes, where no case has
/// yet lost light. Seed 002 names no faces for its shading draw; the first design here shaded
/// such lights by their back faces with the depth test off after the mark.
pub const CROSSING_NEAR: DrawState = DrawState { faces: Faces::Back, depth: Cmp::GreaterEqual, stencil: NO_STENCIL };

/// Back faces at or behind the scene point: the point is in front of the volume's far side.
pub const VOLUME: StencilMethod = StencilMethod {
    mark: None,
    shade: CROSSING_NEAR,
    shade_crossing_near: None,
    reference: Reference::Zero,
    fullscreen: false,
};

/// Seed 000. Pass 1: front faces, no colour, Z LessEqual, Z-fail increments (saturating).
/// Pass 2: back faces, Z GreaterEqual, stencil Equal 0, every outcome writes zero (clearing the
/// mark for the next light).
pub const STENCIL_TWO_PASS: StencilMethod = StencilMethod {
    mark: Some(DrawState {
        faces: Faces::Front,
        depth: Cmp::LessEqual,
        stencil: stencil(face(Cmp::Always, Op::Keep, Op::IncrementClamp, Op::Keep), crate::renderer::kit::KEEP),
    }),
    shade: DrawState {
        faces: Faces::Back,
        depth: Cmp::GreaterEqual,
        stencil: stencil(
            face(Cmp::Equal, Op::Zero, Op::Zero, Op::Zero),
            face(Cmp::Equal, Op::Zero, Op::Zero, Op::Zero),
        ),
    },
    shade_crossing_near: Some(CROSSING_NEAR),
    reference: Reference::Zero,
    fullscreen: false,
};

/// Seed 001. Mark: both faces, Z Less, Z-fail inverts: a scene point inside the volume fails
/// only against the back face, an odd count, non-zero stencil. Shade: back faces, depth test
/// off, stencil NotEqual 0, pass op Zero clears for the next light.
pub const STENCIL_INVERT: StencilMethod = StencilMethod {
    mark: Some(DrawState {
        faces: Faces::Both,
        depth: Cmp::Less,
        stencil: stencil(
            face(Cmp::Always, Op::Keep, Op::Invert, Op::Keep),
            face(Cmp::Always, Op::Keep, Op::Invert, Op::Keep),
        ),
    }),
    shade: DrawState {
        faces: Faces::Back,
        depth: Cmp::Always,
        stencil: stencil(
            face(Cmp::NotEqual, Op::Keep, Op::Keep, Op::Zero),
            face(Cmp::NotEqual, Op::Keep, Op::Keep, Op::Zero),
        ),
    },
    shade_crossing_near: Some(CROSSING_NEAR),
    reference: Reference::Zero,
    fullscreen: false,
};

/// Seed 002 with REPLACE. Mark: back faces, Z Less, so Z fails (REPLACE X) exactly where the
/// scene point is at or in front of the far side. Shade: front faces, Z LessEqual, stencil
/// Equal X: the point is also at or behind the near side, i.e. inside. Where the volume crosses
/// the near plane (no front face where the camera is inside) the seed shades back faces with
/// the depth test off after the mark; here, as in every stencil method, they are drawn as plain
/// volumes, unmarked ([`CROSSING_NEAR`]). X = 1..255 differs per light
/// (per batch: a batch's lights never reach the same pixel), so the stencil is cleared only once
/// every 255 batches.
pub const STENCIL_REPLACE: StencilMethod = StencilMethod {
    mark: Some(DrawState {
        faces: Faces::Back,
        depth: Cmp::Less,
        stencil: stencil(
            face(Cmp::Always, Op::Keep, Op::Replace, Op::Keep),
            face(Cmp::Always, Op::Keep, Op::Replace, Op::Keep),
        ),
    }),
    shade: DrawState { faces: Faces::Front, depth: Cmp::LessEqual, stencil: EQUAL_REFERENCE },
    shade_crossing_near: Some(CROSSING_NEAR),
    reference: Reference::PerLight,
    fullscreen: false,
};

const EQUAL_REFERENCE: wgpu::StencilState =
    stencil(face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep), face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep));

/// What a light drawn with a method covers, for the cost estimates (`auto`'s frame rule, the
/// binned-bytes budget of the counting passes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Covers {
    /// Every pixel: one full-screen triangle per draw.
    Screen,
    /// The volume's footprint: the bounding mesh's triangles per draw.
    Volume,
    /// Nothing in the light pass (shaded by the tiled pass, or skipped).
    Nothing,
}

/// One culling method.
#[derive(Debug)]
pub struct MethodRow {
    pub method: Method,
    /// The culling mode that draws every light with it (`None`: `auto` only).
    pub mode: Option<CullingMode>,
    /// Its draws in the light pass; `None` when the light pass draws nothing for it.
    pub draws: Option<StencilMethod>,
    /// Pipeline labels: shade, mark, shade for volumes crossing the near plane.
    pub labels: [&'static str; 3],
    /// Draw calls per light, for `auto`'s cost estimate.
    pub draws_per_light: u32,
    pub covers: Covers,
}

impl MethodRow {
    /// The method marks the stencil before shading (batches of it are not merged across
    /// marks).
    pub fn marks(&self) -> bool {
        self.draws.as_ref().is_some_and(|d| d.mark.is_some())
    }
}

/// Every method, in the order the light pass draws its batches.
pub const METHODS: &[MethodRow] = &[
    MethodRow {
        method: Method::Fullscreen,
        mode: Some(CullingMode::Fullscreen),
        draws: Some(FULLSCREEN),
        labels: ["light fullscreen", "", ""],
        draws_per_light: 1,
        covers: Covers::Screen,
    },
    MethodRow {
        method: Method::Volume,
        mode: Some(CullingMode::Volume),
        draws: Some(VOLUME),
        labels: ["light volume", "", ""],
        draws_per_light: 1,
        covers: Covers::Volume,
    },
    MethodRow {
        method: Method::StencilTwoPass,
        mode: Some(CullingMode::StencilTwoPass),
        draws: Some(STENCIL_TWO_PASS),
        labels: ["two-pass shade", "two-pass mark", "two-pass shade (crossing near)"],
        draws_per_light: 2,
        covers: Covers::Volume,
    },
    MethodRow {
        method: Method::StencilInvert,
        mode: Some(CullingMode::StencilInvert),
        draws: Some(STENCIL_INVERT),
        labels: ["invert shade", "invert mark", "invert shade (crossing near)"],
        draws_per_light: 2,
        covers: Covers::Volume,
    },
    MethodRow {
        method: Method::StencilReplace,
        mode: Some(CullingMode::StencilReplace),
        draws: Some(STENCIL_REPLACE),
        labels: ["replace shade (front faces)", "replace mark", "replace shade (crossing near)"],
        draws_per_light: 2,
        covers: Covers::Volume,
    },
    // `auto` only: the volume lies outside the view frustum.
    MethodRow {
        method: Method::Skipped,
        mode: None,
        draws: None,
        labels: ["", "", ""],
        draws_per_light: 0,
        covers: Covers::Nothing,
    },
    // Shaded from their tiles' or clusters' lists by the tiled pass (`culling::tiled::pass`).
    MethodRow {
        method: Method::Tiled,
        mode: Some(CullingMode::Tiled),
        draws: None,
        labels: ["", "", ""],
        draws_per_light: 0,
        covers: Covers::Nothing,
    },
    MethodRow {
        method: Method::Clustered,
        mode: Some(CullingMode::Clustered),
        draws: None,
        labels: ["", "", ""],
        draws_per_light: 0,
        covers: Covers::Nothing,
    },
    MethodRow {
        method: Method::Zbin,
        mode: Some(CullingMode::Zbin),
        draws: None,
        labels: ["", "", ""],
        draws_per_light: 0,
        covers: Covers::Nothing,
    },
];

/// The row of method `m`.
pub fn row(m: Method) -> &'static MethodRow {
    // Every `Method` has a row (`every_method_has_one_row`).
    METHODS.iter().find(|r| r.method == m).unwrap_or(&METHODS[0])
}

/// `m`'s place in [`METHODS`]: the order its batches are drawn in.
pub fn order(m: Method) -> u8 {
    METHODS.iter().position(|r| r.method == m).unwrap_or(0) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_and_mode_has_one_row() {
        let all = [
            Method::Fullscreen,
            Method::Volume,
            Method::StencilTwoPass,
            Method::StencilInvert,
            Method::StencilReplace,
            Method::Tiled,
            Method::Clustered,
            Method::Zbin,
            Method::Skipped,
        ];
        for m in all {
            assert_eq!(METHODS.iter().filter(|r| r.method == m).count(), 1, "{m:?}");
            assert_eq!(row(m).method, m);
        }
        for mode in CullingMode::ALL {
            let rows = METHODS.iter().filter(|r| r.mode == Some(mode)).count();
            assert_eq!(rows, usize::from(mode != CullingMode::Auto), "{mode:?}");
        }
        // A method drawn in the light pass covers something and names its pipelines; the
        // stencil methods mark first and draw twice per light.
        for r in METHODS {
            assert_eq!(r.draws.is_some(), r.covers != Covers::Nothing, "{:?}", r.method);
            assert_eq!(r.draws.is_some(), !r.labels[0].is_empty(), "{:?}", r.method);
            assert_eq!(r.marks(), r.draws_per_light == 2, "{:?}", r.method);
            let near = r.draws.as_ref().is_some_and(|d| d.shade_crossing_near.is_some());
            assert_eq!(near, !r.labels[2].is_empty(), "{:?}", r.method);
        }
    }
}
