//! The renderer's knobs as one table. Each row names a [`Settings`] field once and says what
//! values it takes; the rest is derived from the table:
//! - `Settings::validate` checks every row's range;
//! - `lampshade render --NAME VALUE` (the flags are built from the rows with `cli`);
//! - `set NAME VALUE` in viewer scripts and `UiState::set`;
//! - the viewer's sliders and choice boxes (their ranges and value names).
//!
//! A value's one name is its clap `ValueEnum` name, which is also its serde name in settings
//! files (see [`super::settings::name_of`]).

mod table;

pub use table::KNOBS;

use super::settings::{name_of, Settings};

/// The values a knob takes.
#[derive(Clone, Copy, Debug)]
pub enum Values {
    /// One of the names of a `ValueEnum`.
    Choice(fn() -> Vec<String>),
    /// A finite number between `min` and `max`, each end excluded when `open` says so; the
    /// viewer's slider spans `slider`, the part of the range a user moves through.
    Float { min: f64, max: f64, open: (bool, bool), slider: (f64, f64) },
    /// `auto` (the renderer picks the value each frame) or a number as `Float` takes it.
    FloatOrAuto { min: f64, max: f64, open: (bool, bool), slider: (f64, f64) },
    /// A whole number in `min ..= max`.
    Whole { min: u32, max: u32 },
    /// on / off (also true/false, 1/0, yes/no).
    Switch,
    /// A file (or a built-in name the row documents); `none` for no file.
    File,
}

impl Values {
    /// The range in words: `0 ..< 1`, `3 ..= 64`, `0 <.. 1000000` (`<` marks an excluded end).
    pub fn describe(&self) -> String {
        match *self {
            Values::Float { min, max, open, .. } => {
                format!("{min} {}..{} {max}", if open.0 { "<" } else { "" }, if open.1 { "<" } else { "=" })
            }
            Values::FloatOrAuto { min, max, open, slider } => {
                format!("auto or {}", Values::Float { min, max, open, slider }.describe())
            }
            Values::Whole { min, max } => format!("{min} ..= {max}"),
            Values::Choice(_) | Values::Switch | Values::File => String::new(),
        }
    }
}

/// One knob: its name (CLI flag, script `set` name; the settings file's key is the same name in
/// snake case), what it does, its values, and how to read and write it.
pub struct Knob {
    pub name: &'static str,
    /// The knob in a sentence ("light cut-off"), for messages.
    pub what: &'static str,
    pub help: &'static str,
    pub values: Values,
    /// `lampshade render` takes it as `--NAME VALUE`.
    pub cli: bool,
    pub get: fn(&Settings) -> String,
    /// Writes the parsed value; the range is checked by `Settings::validate` afterwards.
    put: fn(&mut Settings, &str) -> Result<(), String>,
}

fn names<T: clap::ValueEnum>() -> Vec<String> {
    T::value_variants().iter().map(name_of).collect()
}

fn choice<T: clap::ValueEnum>(what: &str, s: &str) -> Result<T, String> {
    super::settings::parse_name(what, s)
}

pub fn parse_switch(v: &str) -> Result<bool, String> {
    match v {
        "on" | "true" | "1" | "yes" => Ok(true),
        "off" | "false" | "0" | "no" => Ok(false),
        _ => Err(format!("'{v}' is not on/off")),
    }
}

pub fn switch_name(b: bool) -> String {
    if b { "on" } else { "off" }.into()
}

fn number(v: &str) -> Result<f64, String> {
    let x: f64 = v.trim().parse().map_err(|_| format!("'{v}' is not a number"))?;
    if !x.is_finite() {
        return Err(format!("'{v}' is not a finite number"));
    }
    Ok(x)
}

fn whole(v: &str) -> Result<u32, String> {
    v.trim().parse().map_err(|_| format!("'{v}' is not a whole number"))
}

/// The knob named `name`.
pub fn find(name: &str) -> Option<&'static Knob> {
    KNOBS.iter().find(|k| k.name == name)
}

/// The knob named `name`; an unknown name is an error listing the known ones.
pub fn knob(name: &str) -> Result<&'static Knob, String> {
    find(name).ok_or_else(|| {
        let all: Vec<&str> = KNOBS.iter().map(|k| k.name).collect();
        format!("unknown setting '{name}' (one of {})", all.join(", "))
    })
}

impl Knob {
    /// Writes `value` to `s` without checking the other rules (`Settings::set` does both).
    pub fn put(&self, s: &mut Settings, value: &str) -> Result<(), String> {
        (self.put)(s, value)
    }

    /// Whether `s`'s value of this knob lies in its range.
    pub fn check(&self, s: &Settings) -> Result<(), String> {
        let value = (self.get)(s);
        let bad = |why: String| Err(format!("{} {value} {why}", self.what));
        let values = match self.values {
            Values::FloatOrAuto { .. } if value == "auto" => return Ok(()),
            Values::FloatOrAuto { min, max, open, slider } => Values::Float { min, max, open, slider },
            v => v,
        };
        match values {
            Values::FloatOrAuto { .. } => {}
            Values::Float { min, max, open, .. } => {
                let x: f64 = value.parse().unwrap_or(f64::NAN);
                let above = if open.0 { x > min } else { x >= min };
                let below = if open.1 { x < max } else { x <= max };
                if !(x.is_finite() && above && below) {
                    return bad(format!("must be a finite number in {}", values.describe()));
                }
            }
            Values::Whole { min, max } => {
                let x: u32 = value.parse().unwrap_or(u32::MAX);
                if !(min..=max).contains(&x) {
                    return bad(format!("must be between {min} and {max}"));
                }
            }
            Values::Choice(_) | Values::Switch | Values::File => {}
        }
        Ok(())
    }

    /// The viewer's slider span (`None` for other kinds).
    pub fn slider(&self) -> Option<std::ops::RangeInclusive<f32>> {
        match self.values {
            Values::Float { slider, .. } | Values::FloatOrAuto { slider, .. } => {
                Some(slider.0 as f32..=slider.1 as f32)
            }
            _ => None,
        }
    }

    /// The whole-number range, for drag values (`None` for other kinds).
    pub fn whole_range(&self) -> Option<std::ops::RangeInclusive<u32>> {
        match self.values {
            Values::Whole { min, max } => Some(min..=max),
            _ => None,
        }
    }

    /// The names a choice knob takes, `on`/`off` for a switch, none for numbers.
    pub fn names(&self) -> Vec<String> {
        match self.values {
            Values::Choice(f) => f(),
            Values::Switch => vec!["on".into(), "off".into()],
            Values::File => vec!["identity".into(), "none".into()],
            Values::FloatOrAuto { .. } => vec!["auto".into()],
            _ => Vec::new(),
        }
    }
}

impl Settings {
    /// Sets knob `name` to `value` (its one name, or a number), checked against the knob's range
    /// and every other rule of [`Settings::validate`]; on error `self` is unchanged.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), String> {
        let k = knob(name)?;
        let mut next = self.clone();
        (k.put)(&mut next, value)?;
        next.validate()?;
        *self = next;
        Ok(())
    }

    /// The value of knob `name` as `set` takes it.
    pub fn get(&self, name: &str) -> Result<String, String> {
        Ok((knob(name)?.get)(self))
    }
}

/// The `render` command's knob flags, built from [`KNOBS`]: `--NAME VALUE` for every row with
/// `cli`, in the table's order. Parsed into (name, value) pairs that [`Settings::set`] applies.
#[derive(Clone, Debug, Default)]
pub struct KnobArgs(pub Vec<(&'static str, String)>);

impl KnobArgs {
    /// Applies the flags given, in the table's order.
    pub fn apply(&self, settings: &mut Settings) -> Result<(), String> {
        for (name, value) in &self.0 {
            settings.set(name, value).map_err(|e| format!("--{name}: {e}"))?;
        }
        Ok(())
    }
}

impl clap::FromArgMatches for KnobArgs {
    fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut out = Vec::new();
        for k in KNOBS.iter().filter(|k| k.cli) {
            if let Some(v) = m.get_one::<String>(k.name) {
                out.push((k.name, v.clone()));
            }
        }
        Ok(Self(out))
    }

    fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl clap::Args for KnobArgs {
    fn augment_args(mut cmd: clap::Command) -> clap::Command {
        for k in KNOBS.iter().filter(|k| k.cli) {
            // Values are checked by `Settings::set` (with the table's message), so a choice's old
            // aliases (`d32s8`) parse too; the help lists the one names and the ranges.
            let values = match k.values {
                Values::Choice(_) | Values::Switch => format!("one of {}", k.names().join(", ")),
                Values::File => "a .cube file, identity or none".into(),
                _ => k.values.describe(),
            };
            let arg = clap::Arg::new(k.name).long(k.name).value_name("VALUE").help(format!("{} [{values}]", k.help));
            cmd = cmd.arg(arg);
        }
        cmd
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::settings::DepthFormat;

    #[test]
    fn every_knob_round_trips_its_default_and_rejects_nonsense() {
        let d = Settings::default();
        for k in KNOBS {
            let mut s = d.clone();
            let v = (k.get)(&d);
            s.set(k.name, &v).unwrap_or_else(|e| panic!("{}: {e}", k.name));
            assert_eq!(s, d, "{}", k.name);
            assert!(s.set(k.name, "nonsense").is_err(), "{} took 'nonsense'", k.name);
            assert_eq!(s, d, "{}: a rejected value changed the settings", k.name);
        }
        assert!(d.clone().set("no-such-knob", "1").unwrap_err().contains("unknown setting"));
    }

    #[test]
    fn ranges_come_from_the_table() {
        let mut s = Settings::default();
        assert!(s.set("light-cutoff", "1").is_err(), "the cut-off range is open at 1");
        s.set("light-cutoff", "0.5").unwrap();
        assert!(s.set("cone-sides", "2").unwrap_err().contains("cone sides 2 must be between 3 and 64"));
        assert!(s.set("sphere-subdivisions", "5").is_err());
        assert!(s.set("exposure", "0").is_err());
        s.set("exposure", "999999").unwrap();
        s.set("depth-format", "d24s8").unwrap();
        assert_eq!(s.depth_format, DepthFormat::Depth24PlusStencil8);
    }
}
