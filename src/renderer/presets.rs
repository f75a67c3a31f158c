//! The seed presets: each seed's pipeline as the seed writes it, knob by knob, with the seed's
//! own line behind every setting. The defaults stay the best-measured settings; a preset shows
//! a seed. What a seed names that no knob can give yet is listed with the preset
//! ([`Preset::missing`]), so a user sees how far the preset is from the seed.
//!
//! A preset sets every pipeline knob: the default for the knobs its seed says nothing of, its
//! rows for the rest. The instruments ([`INSTRUMENTS`]: the debug view, the selected light, the
//! counters, the exposure) stay as the user has them. Later flags, keys and `set`s apply on top
//! (`--preset seed000 --culling tiled`: the preset first, then the culling mode).

use super::knobs;
use super::settings::Settings;
use serde::{Deserialize, Serialize};

/// A named pipeline: the defaults, or one seed's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// The defaults: the best-measured settings (deferred shading, volume culling, compact).
    Default,
    /// Seed 000: deferred shading, 1,024 point lights, two-pass stencil culling, four fp16 targets.
    Seed000,
    /// Seed 001: deferred spot lights culled with one INVERT stencil pass, Lambert normals.
    Seed001,
    /// Seed 002: NVIDIA's deferred shading talk: stencil REPLACE, material IDs, shadows, post.
    Seed002,
    /// Seed 003: the light pre-pass on a tile GPU, an 8-bit additive light buffer.
    Seed003,
    /// Seed 004: Unity's deferred lighting, a log-encoded light buffer.
    Seed004,
}

super::options::knob_names!(Preset => "preset");

/// The knobs a preset leaves as they are: what the user looks at and counts, not the pipeline.
pub const INSTRUMENTS: [&str; 5] = ["debug-view", "counts", "ideal", "timestamps", "exposure"];

/// The value `preset` reads when the settings are no preset's.
pub const CUSTOM: &str = "custom";

/// One setting of a preset and the seed's line that asks for it.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Row {
    pub knob: &'static str,
    pub value: &'static str,
    /// The seed's words, quoted as the seed writes them.
    pub seed: &'static str,
    /// The [`DEPARTURES`] the setting takes from its seed's words, by id.
    pub departs: &'static [&'static str],
}

/// Where the project does on purpose other than a seed line says, and the measured reason.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Departure {
    pub id: &'static str,
    pub seeds: &'static str,
    /// The seed's words, quoted as the seed writes them.
    pub line: &'static str,
    pub does: &'static str,
    /// The reason, with the oracle case, test or measurement behind it.
    pub why: &'static str,
}

/// Every deliberate departure from a seed line the presets keep (`docs/presets.md`).
pub const DEPARTURES: &[Departure] = &[
    Departure {
        id: "D1",
        seeds: "000, 001, 002",
        line: "Each light volume is rendered it two passes",
        does: "a light whose volume crosses the near plane is drawn by every stencil method as a plain volume (back faces, GreaterEqual), unmarked",
        why: "oracle stream 4: case 14373 (416 pixels missed by two-pass, 446 by INVERT: the clipped front face), 20938 (5), 15135 and 13145 (1 each); the plain volume shades the same fragments for those lights (`auto_shades_like_the_best_fixed_mode_with_the_camera_among_lights`); `tests/data/oracle/crossing-near-*.json`",
    },
    Departure {
        id: "D2",
        seeds: "001",
        line: "Then we render the light geometry with back face culling off and no pixel shader.",
        does: "the INVERT mark has a fragment stage (`fs_mark_both_faces`) that biases each face's depth, front nearer and back farther: one pipeline takes only one fixed-function bias",
        why: "`volume-rim-standard-depth.json` (lights behind a wall 1,700 away, near plane 0.05): unbiased, 71 pixels missed on the deferred path and 78 on the pre-pass; found by `lampshade check` on 2CylinderEngine",
    },
    Departure {
        id: "D3",
        seeds: "000, 001, 002",
        line: "Z function = Less/Equal",
        does: "every depth-tested volume draw is biased by 8 units of depth resolution and 1/16 of its slope (front faces nearer, back faces farther), derived from the volume fragment's rounding (`kit::VOLUME_BIAS_UNITS`)",
        why: "oracle stream 9, cases 0-99: unbiased, 4 cases (278 pixels) missed; biased, none",
    },
    Departure {
        id: "D4",
        seeds: "002",
        line: "Depth Func = ALWAY, Stencil Func = EQUAL,",
        does: "REPLACE's shading draw tests depth: front faces, LessEqual, stencil Equal X, after the back-face Less mark",
        why: "the mark alone sets exactly the pixels the plain volume's back faces pass, so shading with the depth test off shades the volume's set: 2,973,545 fragments against 1,190,990 on `demo` at 1280x720; held by `culling::stencil_modes_shade_exactly_the_points_inside_the_bounding_mesh`",
    },
    Departure {
        id: "D5",
        seeds: "004",
        line: "No real anti-aliasing support.",
        does: "`--msaa 4` multisamples the light pre-pass's pass 3 and its forward pass (passes 1 and 2 stay single-sample) after a depth-only draw primes the samples; the presets leave it off",
        why: "edge error against a 4x4-supersampled frame: `demo` 207.5 to 174.0, `street` 76.8 to 73.8 (`paths::` MSAA test; docs/measurements.md)",
    },
    Departure {
        id: "D6",
        seeds: "002",
        line: "Take advantage of early Z- and Stencil culling",
        does: "on the layouts that store a position (`seed000`, `seed002`) the G-buffer pass writes the stored position's depth (`frag_depth`), so neither it nor the z-only pass before it has early Z: the z-only pass saves the target writes of hidden surfaces, not their shading",
        why: "oracle stream 4, cases 8372 and 8851 (3 and 1 pixels missed on exactly those layouts: the rasteriser's plane lies far from the stored point on a grazing surface); `rim-position-layout-*.json`",
    },
    Departure {
        id: "D7",
        seeds: "002",
        line: "Stencil Z-FAIL = REPLACE (with value X)",
        does: "X is per batch of lights whose screen rectangles never meet, not per light; the stencil is cleared once every 255 batches",
        why: "on `demo` 390 draws in 195 batches instead of 2,056 draws, lighting 5-20% faster (`examples/batchbench`), the same sums bit for bit (`batching::`); also seed 002's own \"Avoid frequent stencil reference / op changes\"",
    },
    Departure {
        id: "D8",
        seeds: "000",
        line: "they are rendered as low-poly spheres",
        does: "the low-poly sphere circumscribes the light's sphere (scaled by 1/inradius, 0.2% margin)",
        why: "inscribed spheres miss light: 29 of 100 oracle cases fail (the oracle's deliberate-break table)",
    },
    Departure {
        id: "D9",
        seeds: "002",
        line: "Free bilinear filtering offsets extra per-pixel work",
        does: "the indirection cube is sampled nearest, and its two 16-bit coordinates are stored in the bytes of an Rgba8Unorm texel (Rg16Unorm needs a native-only feature)",
        why: "derived, not measured: filtering across cube faces blends two faces' coordinates along every edge; the nearest texel's error, at most 0.59 texels, is added to the slope bias (`shadows::indirection_error`)",
    },
    Departure {
        id: "D10",
        seeds: "002",
        line: "Render to shadow map at 2x pixels per clock",
        does: "shadow maps are written through a fragment shader (linear depth; distance for the cube array's faces), not depth only",
        why: "a design reason, not a measurement: linear depth keeps the biases in texels at every tile size, and the cube array needs a depth that is the same on every face",
    },
    Departure {
        id: "D11",
        seeds: "004",
        line: "Directional lights and Point/Spot lights that cross the near plane are rendered as fullscreen quads.",
        does: "on an adapter without depth clamp, lights crossing the far plane are drawn full-screen too",
        why: "oracle stream 4, cases 55695 (5 pixels) and 80311 (623 and 629 pixels in two-pass and INVERT): the clipped volume's faces miss its points",
    },
    Departure {
        id: "D12",
        seeds: "000",
        line: "RT2: RGB – world-space normal, Alpha – nothing",
        does: "`seed000` keeps the specular exponent in RT2's alpha (and the material ID in RT3's when the scene has several models)",
        why: "every material has an exponent and the channel costs no byte; not a measurement",
    },
    Departure {
        id: "D13",
        seeds: "004",
        line: "Lightmaps are also applied in the final pass.",
        does: "the light pass fades the sun by the crossfade weight at every pixel, and the final pass adds the bake, or the faded share of the sun back on surfaces without a lightmap",
        why: "the light buffer cannot tell lightmapped pixels; held by `presets::the_light_prepass_gives_surfaces_without_a_lightmap_their_whole_sun`",
    },
    Departure {
        id: "D14",
        seeds: "002",
        line: "Don't switch z-test direction mid-frame",
        does: "lights crossing the near plane are drawn as plain volumes, back faces with GreaterEqual (D1), between the REPLACE marks' Less and shading draws' LessEqual",
        why: "a volume that holds the camera has no front face to mark with; the back faces' GreaterEqual is the test that bounds it (the oracle cases of D1)",
    },
];

/// Something the seed names that no knob gives yet.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Missing {
    pub what: &'static str,
    pub seed: &'static str,
}

/// A [`Row`] as a constant expression (so a table of them is `'static`).
macro_rules! row {
    ($knob:expr, $value:expr, $seed:expr) => {
        Row { knob: $knob, value: $value, seed: $seed, departs: &[] }
    };
    ($knob:expr, $value:expr, $seed:expr; $($d:expr),+) => {
        Row { knob: $knob, value: $value, seed: $seed, departs: &[$($d),+] }
    };
}

/// A [`Missing`] as a constant expression.
macro_rules! missing {
    ($what:expr, $seed:expr) => {
        Missing { what: $what, seed: $seed }
    };
}

impl Preset {
    pub const ALL: [Preset; 6] =
        [Preset::Default, Preset::Seed000, Preset::Seed001, Preset::Seed002, Preset::Seed003, Preset::Seed004];

    /// The seeds' presets (all but `default`).
    pub const SEEDS: [Preset; 5] =
        [Preset::Seed000, Preset::Seed001, Preset::Seed002, Preset::Seed003, Preset::Seed004];

    /// The settings the preset changes from the defaults, each with its seed line.
    pub fn rows(self) -> &'static [Row] {
        match self {
            Preset::Default => &[],
            Preset::Seed000 => &[
                row!("path", "deferred", "All lighting function inputs are rendered into several buffers (in a single pass, using multiple render targets) which are then sampled by the light shader."),
                row!("layout", "seed000", "In the demo, I'm using four fp16 textures with this layout"; "D12"),
                row!("accumulation", "rgba16-float", "RT1: RGB – light accumulation, Alpha – nothing"),
                row!("ambient-in-gbuffer", "on", "RT1 starts off with light contribution from main ambient and directional sources (sun)."),
                row!("culling", "stencil-two-pass", "Each light volume is rendered it two passes"; "D1", "D3"),
                row!("light-batching", "off", "Each light volume is rendered it two passes"),
                row!("sphere-subdivisions", "1", "they are rendered as low-poly spheres"; "D8"),
                row!("reversed-z", "off", "Z function = Less/Equal"),
                row!("brdf", "phong", "Standard Phong function is used in the demo."),
                row!("shadows", "none", "It is also possible for each light to cast a shadow. I will explore this topic in the future articles."),
                row!("bloom", "on", "It can now be used in post-process effects (like bloom)."),
                row!("aa", "off", "No hardware antialiasing."),
            ],
            Preset::Seed001 => &[
                row!("path", "deferred", "reconstructs a view space position from the depth stored in the g-buffer"),
                row!("layout", "lambert8", "reconstructs the view space normal from two channels (using Lambert azimuthal equal-area projection"),
                row!("culling", "stencil-invert", "setting the stencil depthfail operation for both front and back faces to D3D11_STENCIL_OP_INVERT"; "D1", "D2", "D3"),
                row!("light-batching", "off", "The next stage is to render the cone again with the following depth stencil state."),
                row!("brdf", "blinn-phong", "calculates diffuse and specular light colour, taking into account distance and spotlight attenuation"),
                row!("shadows", "none", "calculates diffuse and specular light colour, taking into account distance and spotlight attenuation"),
            ],
            Preset::Seed002 => &[
                row!("path", "deferred", "For Each Light: framebuffer += brdf( G-buffer, light )"),
                row!("layout", "seed002", "Position.x Position.y Position.z Emissive"),
                row!("accumulation", "rgba16-float", "16-bit floating point enables HDR"),
                row!("culling", "stencil-replace", "Stencil Z-FAIL = REPLACE (with value X)"; "D1", "D3", "D4", "D7", "D14"),
                row!("brdf", "scene", "Store multiple BRDFs in light shader, choose per-pixel"),
                row!("material-branch", "branch", "Reasonably coherent dynamic branching"),
                row!("ambient-in-gbuffer", "off", "Keep MRT usage to 3 or fewer render targets … Directional Light = Quad"),
                row!("gbuffer-depth-prepass", "on", "Do an initial front-to-back-sorted z-only pass."; "D6"),
                row!("lightmaps", "off", "Keep MRT usage to 3 or fewer render targets"),
                row!("draw-order", "front-to-back", "Do an initial front-to-back-sorted z-only pass."),
                row!("anisotropy", "8", "Use aniso filtering during G-buffer pass (no level given)"),
                row!("shadows", "all", "Shadow maps work very well with deferred shading"),
                row!("shadow-cube", "indirect", "Unrolls a shadow cube map into a 2D depth texture … G16R16 cubemap efficiently maps XYZ->ST"; "D9"),
                row!("shadow-filter", "pcf2x2", "Enable bilinear filtering to get 4-sample PCF"),
                row!("shadow-format", "depth24", "Use D16 or D24X8 format for shadow maps"; "D10"),
                row!("bloom", "on", "Glow"),
                row!("auto-exposure", "on", "Auto-Exposure"),
                row!("distortion", "on", "Distortion"),
                row!("fog", "on", "Fog"),
                row!("aa", "edge", "\"Intelligent Blur\" : Only filter object edges"),
                row!("blended", "alpha", "Blend into final image, sort back-to-front as always"),
            ],
            Preset::Seed003 => &[
                row!("path", "light-prepass", "my 1st pass renders into an intermediate buffer (g-buffer) consisting of a 24-bit normal and a scaled 8-bit specular exponent"),
                row!("accumulation", "rgba8-unorm", "A second g-buffer containing a 24-bit diffuse color (rgb) and 8-bit specular value is updated by each light. … a glBlendFunc(GL_ONE, GL_ONE) call is used"),
                row!("culling", "volume", "The point lights are rendered using 3-d sphere geometry, taking advantage of the z-buffer"),
                row!("depth-format", "depth24-plus-stencil8", "Directional lights (representing the sun) are rendered as full screen quads with the 24-bit z-buffer and the 1st g-buffer as input textures."),
                row!("depth-read", "buffer", "Directional lights (representing the sun) are rendered as full screen quads with the 24-bit z-buffer and the 1st g-buffer as input textures."),
                row!("blended", "alpha", "These polygons must also be sorted from back to front"),
                row!("shadows", "none", "(no shadows are named)"),
                row!("lut", "identity", "a 5th pass is applied to perform color grading, depth of field, vignetting"),
                row!("dof", "on", "a 5th pass is applied to perform color grading, depth of field, vignetting"),
                row!("vignette", "0.3", "a 5th pass is applied to perform color grading, depth of field, vignetting (no strength given)"),
            ],
            Preset::Seed004 => &[
                row!("path", "light-prepass", "Base Pass … Lighting pass … Final pass: objects are rendered again."),
                row!("accumulation", "rgba8-log", "Lighting values are encoded using logarithmic encoding"),
                row!("culling", "volume", "Point and Spot lights that do not cross camera's near plane are rendered as 3D shapes, with Z buffer test against scene enabled."),
                row!("near-lights", "fullscreen", "Directional lights and Point/Spot lights that cross the near plane are rendered as fullscreen quads."; "D11"),
                row!("brdf", "scene", "Lighting model is fixed to Blinn-Phong. … Objects with shaders that can't handle Deferred Lighting are rendered after this process is done, using RenderTech-ForwardRendering path."),
                row!("shadows", "all", "All lights can have Shadows."),
                row!("lightmaps", "on", "Lightmaps are also applied in the final pass. Close to the camera, realtime lighting is used, and only baked indirect lighting is added."; "D13"),
                row!("aa", "off", "No real anti-aliasing support."),
                row!("depth-read", "buffer", "If platform & hardware supports reading Z buffer as a texture, then depth is not explicitly rendered."),
            ],
        }
    }

    /// What the seed names that no knob gives yet: the preset is that far from the seed.
    pub fn missing(self) -> &'static [Missing] {
        match self {
            Preset::Default => &[],
            Preset::Seed000 => &[],
            Preset::Seed001 => &[
                missing!("the normal's bit depth: the seed does not give it; the preset takes 8+8 bits", "reconstructs the view space normal from two channels"),
            ],
            Preset::Seed002 => &[
                missing!("the table has no specular exponent: the free channel carries it (packed with the material ID when the scene uses several models, 3% off at most)", "Normal.x Normal.y Normal.z Free"),
                missing!("emission is one channel, so it is stored as a multiple of the diffuse colour: exact only where the emission has the albedo's hue", "Emissive (single channel)"),
            ],
            Preset::Seed003 => &[
            ],
            Preset::Seed004 => &[],
        }
    }

    /// The seed's file in `shared/seeds/`, by number (`None` for the defaults).
    pub fn seed(self) -> Option<&'static str> {
        match self {
            Preset::Default => None,
            Preset::Seed000 => Some("000"),
            Preset::Seed001 => Some("001"),
            Preset::Seed002 => Some("002"),
            Preset::Seed003 => Some("003"),
            Preset::Seed004 => Some("004"),
        }
    }

    /// `keep`'s instruments on the defaults, with the preset's rows. Not validated here (the
    /// `preset` knob's own reading calls this inside validation); [`Preset::apply`] validates.
    pub fn settings(self, keep: &Settings) -> Settings {
        self.build(keep).0
    }

    /// [`Preset::settings`], checked: every row names a knob and a value it takes, and the
    /// result passes `Settings::validate`.
    pub fn apply(self, keep: &Settings) -> Result<Settings, String> {
        let (s, errors) = self.build(keep);
        if let Some(e) = errors.into_iter().next() {
            return Err(e);
        }
        s.validate().map_err(|e| format!("preset {}: {e}", self.name()))?;
        Ok(s)
    }

    /// The preset's settings and the rows that did not apply (an unknown knob or value).
    fn build(self, keep: &Settings) -> (Settings, Vec<String>) {
        let mut s = Settings::default();
        for name in INSTRUMENTS {
            if let (Some(k), Ok(v)) = (knobs::find(name), keep.get(name)) {
                // The value came from a knob of the same table: it parses.
                let _ = k.put(&mut s, &v);
            }
        }
        s.selected_light = keep.selected_light;
        let mut errors = Vec::new();
        for r in self.rows() {
            let put = knobs::knob(r.knob).and_then(|k| k.put(&mut s, r.value));
            if let Err(e) = put {
                errors.push(format!("preset {}: {}: {e}", self.name(), r.knob));
            }
        }
        (s, errors)
    }

    /// The preset `s` is, instruments aside.
    pub fn of(s: &Settings) -> Option<Preset> {
        Preset::ALL.into_iter().find(|p| p.settings(s) == *s)
    }

    /// The table of every preset as Markdown: what it sets, the seed's line behind each
    /// setting, and what the seed names that no knob gives yet (`lampshade presets`;
    /// `docs/presets.md` holds it).
    pub fn markdown() -> String {
        let mut out = String::new();
        for p in Preset::SEEDS {
            let seed = p.seed().unwrap_or_default();
            out.push_str(&format!("### `{}` (seed {seed})\n\n", p.name()));
            out.push_str(&format!("{}\n\n", super::settings::help_of(&p)));
            out.push_str("| knob | value | the seed's line | departs |\n|---|---|---|---|\n");
            for r in p.rows() {
                let departs: Vec<String> = r.departs.iter().map(|d| format!("[{d}](#departures)")).collect();
                out.push_str(&format!(
                    "| `{}` | `{}` | {} | {} |\n",
                    r.knob,
                    r.value,
                    r.seed.replace('|', "\\|"),
                    departs.join(", ")
                ));
            }
            if !p.missing().is_empty() {
                out.push_str("\nNot yet given by any knob:\n\n");
                for m in p.missing() {
                    out.push_str(&format!("- {} (\"{}\")\n", m.what, m.seed.replace('|', "\\|")));
                }
            }
            out.push('\n');
        }
        out.push_str("### Departures\n\n");
        out.push_str("| | seeds | the seed's line | what Lampshade does | why (measured) |\n|---|---|---|---|---|\n");
        for d in DEPARTURES {
            let cell = |s: &str| s.replace('|', "\\|");
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} |\n",
                d.id,
                d.seeds,
                cell(d.line),
                cell(d.does),
                cell(d.why)
            ));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_sets_valid_values_and_is_recognised() {
        for p in Preset::ALL {
            let s = p.apply(&Settings::default()).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(Preset::of(&s), Some(p), "{p:?} is not recognised from its own settings");
            // Every row changes its knob to the row's value (or keeps a default the seed names).
            for r in p.rows() {
                assert_eq!(s.get(r.knob).unwrap(), r.value, "{p:?}: {}", r.knob);
            }
        }
        // The seeds' presets differ from each other and from the defaults.
        let all: Vec<Settings> = Preset::ALL.iter().map(|p| p.settings(&Settings::default())).collect();
        for (i, a) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|b| b != a), "{:?} equals a later preset", Preset::ALL[i]);
        }
    }

    #[test]
    fn a_preset_keeps_the_instruments_and_a_changed_knob_makes_it_custom() {
        let mut mine = Settings { exposure: 2.5, count_ideal: true, ..Settings::default() };
        mine.set("debug-view", "stencil").unwrap();
        mine.set("preset", "seed000").unwrap();
        assert_eq!((mine.exposure, mine.count_ideal), (2.5, true));
        assert_eq!(mine.get("debug-view").unwrap(), "stencil");
        assert_eq!(mine.get("layout").unwrap(), "seed000");
        assert_eq!(mine.get("preset").unwrap(), "seed000");
        mine.set("culling", "tiled").unwrap();
        assert_eq!(mine.get("preset").unwrap(), CUSTOM);
        // `custom` leaves the knobs as they are; nonsense is an error that lists the presets.
        let before = mine.clone();
        mine.set("preset", CUSTOM).unwrap();
        assert_eq!(mine, before);
        let e = mine.set("preset", "seed005").unwrap_err();
        assert!(e.contains("seed000") && e.contains("seed004"), "{e}");
    }

    #[test]
    fn the_docs_hold_the_printed_tables() {
        let doc = include_str!("../../docs/presets.md");
        assert!(doc.ends_with(&Preset::markdown()), "docs/presets.md is not what `lampshade presets` prints");
    }

    #[test]
    fn every_row_quotes_its_seed() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/seeds");
        // The seeds sit beside the repository (CI's layout): without them no quote is checked,
        // which is a failure, not a pass.
        let dir = std::fs::read_dir(&root)
            .unwrap_or_else(|e| panic!("no seeds at {} ({e}): the quotes cannot be checked", root.display()));
        let texts: Vec<(String, String)> = dir
            .flatten()
            .map(|e| {
                (e.file_name().to_string_lossy().into_owned(), std::fs::read_to_string(e.path()).unwrap_or_default())
            })
            .collect();
        let norm = |s: &str| {
            s.replace(['’', '‘'], "'").replace(['“', '”'], "\"").split_whitespace().collect::<Vec<_>>().join(" ")
        };
        for p in Preset::SEEDS {
            let number = p.seed().unwrap();
            let text = &texts.iter().find(|(n, _)| n.starts_with(number)).expect("the seed's file").1;
            let text = norm(text);
            let quotes = p.rows().iter().map(|r| r.seed).chain(p.missing().iter().map(|m| m.seed));
            for r in p.rows() {
                for id in r.departs {
                    assert!(DEPARTURES.iter().any(|d| d.id == *id), "{p:?} {}: no departure {id}", r.knob);
                }
            }
            for q in quotes {
                // A quote may elide with " … " and end with a note in parentheses.
                let q = q.split(" (no ").next().unwrap_or(q);
                if q.starts_with('(') {
                    continue;
                }
                for part in q.split('…').map(str::trim).filter(|s| !s.is_empty()) {
                    for piece in part.split(" / ") {
                        let piece = norm(piece.trim_end_matches('.'));
                        assert!(text.contains(&piece), "seed {number} does not say \"{piece}\"");
                    }
                }
            }
        }
        // A departure's line stands in one of the seeds it names.
        for d in DEPARTURES {
            let line = norm(d.line.trim_end_matches('.'));
            let said = texts
                .iter()
                .filter(|(n, _)| d.seeds.split(", ").any(|k| n.starts_with(k)))
                .any(|(_, t)| norm(t).contains(&line));
            assert!(said, "departure {}: no seed of {} says \"{}\"", d.id, d.seeds, d.line);
        }
    }
}

/// `base` with engine `e`'s knobs applied (`caps::ENGINES`: each engine's caps as knob values).
pub fn engine_settings(e: &super::caps::Engine, base: &Settings) -> Result<Settings, String> {
    let mut s = base.clone();
    for (k, v) in e.knobs {
        s.set(k, v)?;
    }
    Ok(s)
}
