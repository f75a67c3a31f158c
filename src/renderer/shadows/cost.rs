//! What a frame's shadows ask for, from the scene and the options alone, before anything is
//! planned or drawn: how many lights cast, how many cube maps and shadow-map passes (a tile or
//! cube face each, the sun's cascades included) and how many casters and triangles each pass
//! may draw. `lampshade render` prints it before a frame whose shadow work is costly
//! ([`ShadowCost::costly`]) and shows the shadow passes' progress during it.
//!
//! These are the request's upper bounds: the plan (`shadows::plan`) then drops the lights off
//! screen and those past the atlas budget, and culls each pass's casters against its frustum.

use super::{casts_cube, kind_casts, sun_casts, ShadowMode, ShadowOptions};
use crate::scene::{Light, Scene};

/// Shadow-map triangles (passes x the casters' triangles, the upper bound) above which the
/// shadow work is costly: 2^24, about 2 s on lavapipe, which drew 10.2 million caster
/// triangles in 1.25 s (51 passes of 400 boxes of 4,800 triangles under `--preset seed002`,
/// 640x360, 2 cores); on a discrete GPU it is milliseconds, so the warning only says what the
/// frame asks for.
pub const COSTLY_TRIANGLES: u64 = 1 << 24;

/// Shadow-map passes past which a frame is said to be costly whatever its triangles: each pass
/// is a render pass with a draw per caster (64 casting point lights, an importer's light rig
/// for a file without lights, are 384).
pub const COSTLY_PASSES: u64 = 96;

/// The shadow work a frame asks for (see the module's notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadowCost {
    pub mode: ShadowMode,
    /// Casting lights by kind (their kind casts under the mode and their own flag is on).
    pub points: u64,
    pub spots: u64,
    /// Of those, the ones shadowed by a cube (six faces): the points and the wide spots.
    pub cubes: u64,
    /// The sun's cascades (0 when it does not cast).
    pub cascades: u64,
    /// Shadow-map passes: six a cube, one a narrow spot, one a cascade.
    pub passes: u64,
    /// Casters each pass may draw (every object), and their triangles.
    pub casters: u64,
    pub triangles: u64,
}

impl ShadowCost {
    /// The request of `scene` under `st`. O(lights + objects).
    pub fn of(scene: &Scene, st: &ShadowOptions) -> ShadowCost {
        let mut c = ShadowCost { mode: st.shadows, ..Default::default() };
        if st.shadows == ShadowMode::None {
            return c;
        }
        for l in scene.lights.iter().filter(|l| kind_casts(l, st.shadows) && l.cast_shadows()) {
            match l {
                Light::Point(_) => c.points += 1,
                Light::Spot(_) => c.spots += 1,
            }
            c.cubes += casts_cube(l) as u64;
        }
        c.cascades = if sun_casts(scene).is_some() { st.shadow_cascades as u64 } else { 0 };
        c.passes = 6 * c.cubes + (c.points + c.spots - c.cubes) + c.cascades;
        c.casters = scene.objects.len() as u64;
        c.triangles = scene
            .objects
            .iter()
            .filter_map(|o| scene.meshes.get(o.mesh))
            .map(|m| if m.indices.is_empty() { m.vertices.len() } else { m.indices.len() } as u64 / 3)
            .sum();
        c
    }

    /// Triangles the passes may draw in all: passes x the casters' triangles.
    pub fn work(&self) -> u64 {
        self.passes.saturating_mul(self.triangles)
    }

    /// Whether the work is over [`COSTLY_TRIANGLES`], or the passes over [`COSTLY_PASSES`].
    pub fn costly(&self) -> bool {
        self.work() > COSTLY_TRIANGLES || self.passes > COSTLY_PASSES
    }

    /// What `lampshade render` prints before a costly frame: the request and what it costs.
    pub fn warning(&self) -> String {
        let over = match self.work() > COSTLY_TRIANGLES {
            true => format!("over {COSTLY_TRIANGLES}, about 2 s on a CPU rasterizer"),
            false => format!("{} passes, over {COSTLY_PASSES}", self.passes),
        };
        format!(
            "note: {}: up to {} shadow-map triangles in all ({over}); \
             lights off screen or past the shadow budget (--shadow-budget) cast none, \
             --shadows none or spots turns them off",
            self.describe(),
            self.work(),
        )
    }

    /// The request in a line: "shadows (all) on 64 point lights: 64 cube maps, 387
    /// shadow-map passes (3 sun cascades) of up to 1605 casters (19440 triangles) each".
    pub fn describe(&self) -> String {
        let mut on = Vec::new();
        if self.points > 0 {
            on.push(format!("{} point light{}", self.points, plural(self.points)));
        }
        if self.spots > 0 {
            on.push(format!("{} spot{}", self.spots, plural(self.spots)));
        }
        if self.cascades > 0 {
            on.push("the sun".to_string());
        }
        if on.is_empty() {
            on.push("nothing".to_string());
        }
        let cascades = if self.cascades > 0 { format!(" ({} sun cascades)", self.cascades) } else { String::new() };
        format!(
            "shadows ({}) on {}: {} cube map{}, {} shadow-map pass{}{} of up to {} caster{} ({} triangles) each",
            crate::renderer::options::name_of(&self.mode),
            on.join(", "),
            self.cubes,
            plural(self.cubes),
            self.passes,
            if self.passes == 1 { "" } else { "es" },
            cascades,
            self.casters,
            plural(self.casters),
            self.triangles
        )
    }
}

fn plural(n: u64) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::Settings;
    use crate::scene::builtin::{build, BuiltinOptions};

    /// The request's counts are the scene's: `street`'s 64 point lights under `--shadows all`
    /// ask for 64 cube maps, 6 x 64 passes plus the sun's cascades, each of up to every object;
    /// `shadows` (a sun, one narrow spot, one point) for one cube map and 6 + 1 + 3 passes;
    /// `spots` leaves the points out; and the line names those counts.
    #[test]
    fn the_shadow_warning_counts_the_scenes_lights_and_passes() {
        let all = Settings { shadows: ShadowMode::All, ..Settings::default() }.shadow_options();
        let street = build("street", BuiltinOptions::default()).unwrap();
        assert_eq!(street.lights.len(), 64);
        assert!(street.lights.iter().all(|l| matches!(l, Light::Point(_)) && l.cast_shadows()));
        let c = ShadowCost::of(&street, &all);
        let cascades = if sun_casts(&street).is_some() { all.shadow_cascades as u64 } else { 0 };
        assert_eq!((c.points, c.spots, c.cubes, c.cascades), (64, 0, 64, cascades));
        assert_eq!(c.passes, 384 + cascades);
        assert_eq!(c.casters, street.objects.len() as u64);
        let text = c.warning();
        for part in [
            "shadows (all) on 64 point lights".to_string(),
            "64 cube maps".to_string(),
            format!("{} shadow-map passes", 384 + cascades),
            format!("of up to {} casters", street.objects.len()),
            format!("up to {} shadow-map triangles", c.passes * c.triangles),
        ] {
            assert!(text.contains(&part), "'{part}' not in: {text}");
        }
        // 384 cube faces and the cascades: costly by their passes, whatever the triangles
        // (an importer's rig of 64 point lights under `--preset seed002`).
        assert!(c.costly(), "64 casting point lights: {} passes", c.passes);

        let sc = build("shadows", BuiltinOptions::default()).unwrap();
        let c = ShadowCost::of(&sc, &all);
        assert_eq!((c.points, c.spots, c.cubes, c.cascades), (1, 1, 1, 3), "{}", c.describe());
        assert_eq!(c.passes, 6 + 1 + 3);
        assert!(
            c.describe().starts_with(
                "shadows (all) on 1 point light, 1 spot, the sun: 1 cube map, 10 shadow-map passes (3 sun cascades)"
            ),
            "{}",
            c.describe()
        );
        assert!(!c.costly(), "the shadows scene is cheap: {}", c.work());
        let spots = Settings { shadows: ShadowMode::Spots, ..Settings::default() }.shadow_options();
        assert_eq!(ShadowCost::of(&sc, &spots).passes, 1 + 3);
        let none = Settings { shadows: ShadowMode::None, ..Settings::default() }.shadow_options();
        assert_eq!(ShadowCost::of(&sc, &none).passes, 0);
    }
}
