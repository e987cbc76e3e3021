//! Genus functions: the parts of the density a genus may write itself, as `#[shader_fn]`s in
//! its own crate, without forking the model.
//!
//! A genus names three functions ([`GenusFunctions`]):
//!
//! - `weather` ([`WeatherFn`]): the weather signal of each layer at a point of the ground plane
//!   (where cells, streaks or fronts are);
//! - `shape` ([`HeightFn`]): how the coverage threshold varies with height in each layer, which
//!   sets the silhouette (rounded tops, a tower's anvil);
//! - `profile` ([`HeightFn`]): how density varies with height in each layer.
//!
//! A fourth, the weather exponent's form, is not a file's choice: the model raises the weather
//! signal to each layer's `weather_exponent` after the weather function, and the key holds the
//! power only where an exponent is not 1 ([`GenusFunctions::for_layers`], which likewise picks
//! the reference profile's form without its exponential where no layer needs it).
//!
//! Each is a pair of twins made from one `#[shader_fn]` by [`height_fn!`](crate::height_fn)
//! or [`weather_fn!`](crate::weather_fn): the CPU twin runs in the stability catalogue and the
//! parity tests, the shader twin is recorded into the genus' shaders. The functions are part of
//! the shader key (a genus with its own profile gets its own shader, named after it), and a
//! TOML genus names them (`functions = { shape = "anvil_shape" }`): the built-ins below, or any a
//! program has [`register`]ed before it loads its files.

use std::fmt;
use std::sync::{Mutex, OnceLock};

use glam::{Vec2, Vec4};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::layer::CloudLayer;
use crate::model::genus_fns;
use crate::model::layers::{LayerGroup, LayerGroupShader};
use nimbus_dsl::shader;

/// A function of height in each of four layers: `(η, layers) → value per lane`, where `η` is
/// the height fraction in each layer (0 at its bottom, 1 at its top).
#[derive(Clone, Copy)]
pub struct HeightFn {
    /// The Rust name of the `#[shader_fn]` (and the tag in key names).
    pub name: &'static str,
    /// Its full path: two functions are the same only when their paths are.
    pub path: &'static str,
    /// What it is for, as `explain` and `list` print it.
    pub about: &'static str,
    pub cpu: fn(Vec4, LayerGroup) -> Vec4,
    pub shader: fn(shader::Vec4, LayerGroupShader) -> shader::Vec4,
}

/// The weather signal of four layers at a point, before the layers' weather exponents (which the
/// model applies): `(xz, uv, layers) → signal per lane`, with
/// `xz` the point's ground-plane position in metres (noise space: camera offset included) and
/// `uv` where it reads the weather tile (`xz · weather_repeat + weather_offset`, shifted where
/// the key breaks up the tile's repetition: `model::untiled_weather`). Read the weather texture
/// at `uv`; measure distances, and place noise computed in place, with `xz`.
#[derive(Clone, Copy)]
pub struct WeatherFn {
    pub name: &'static str,
    pub path: &'static str,
    pub about: &'static str,
    pub cpu: fn(Vec2, Vec2, LayerGroup) -> Vec4,
    pub shader: fn(shader::Vec2, shader::Vec2, LayerGroupShader) -> shader::Vec4,
}

/// Makes a [`HeightFn`] from a `#[shader_fn] fn f(eta: Vec4, layers: LayerGroup) -> Vec4`:
/// `height_fn!(f, "what it is for")`.
#[macro_export]
macro_rules! height_fn {
    ($f:ident, $about:expr) => {
        $crate::functions::HeightFn {
            name: ::core::stringify!($f),
            path: ::core::concat!(::core::module_path!(), "::", ::core::stringify!($f)),
            about: $about,
            cpu: $f,
            shader: |eta, layers| $f::shader(eta, layers),
        }
    };
}

/// Makes a [`WeatherFn`] from a `#[shader_fn] fn f(xz: Vec2, uv: Vec2, layers: LayerGroup) ->
/// Vec4`:
/// `weather_fn!(f, "what it is for")`.
#[macro_export]
macro_rules! weather_fn {
    ($f:ident, $about:expr) => {
        $crate::functions::WeatherFn {
            name: ::core::stringify!($f),
            path: ::core::concat!(::core::module_path!(), "::", ::core::stringify!($f)),
            about: $about,
            cpu: $f,
            shader: |xz, uv, layers| $f::shader(xz, uv, layers),
        }
    };
}

/// What the two kinds of genus function have in common: identity by path, a name, a registry.
pub trait GenusFn: Copy + 'static {
    /// `height` or `weather`, as errors name the kind.
    const KIND: &'static str;
    fn name(&self) -> &'static str;
    fn path(&self) -> &'static str;
    fn about(&self) -> &'static str;
    /// The built-in functions of this kind.
    fn builtins() -> Vec<Self>;
    /// Functions of this kind a program registered.
    fn registered() -> &'static Mutex<Vec<Self>>;
}

macro_rules! genus_fn_impls {
    ($ty:ident, $kind:literal, $builtins:path) => {
        impl GenusFn for $ty {
            const KIND: &'static str = $kind;
            fn name(&self) -> &'static str {
                self.name
            }
            fn path(&self) -> &'static str {
                self.path
            }
            fn about(&self) -> &'static str {
                self.about
            }
            fn builtins() -> Vec<Self> {
                $builtins()
            }
            fn registered() -> &'static Mutex<Vec<Self>> {
                static REGISTERED: OnceLock<Mutex<Vec<$ty>>> = OnceLock::new();
                REGISTERED.get_or_init(|| Mutex::new(Vec::new()))
            }
        }

        impl PartialEq for $ty {
            fn eq(&self, other: &Self) -> bool {
                self.path == other.path
            }
        }

        impl Eq for $ty {}

        impl std::hash::Hash for $ty {
            fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
                self.path.hash(state);
            }
        }

        impl fmt::Debug for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.path)
            }
        }

        impl Serialize for $ty {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name)
            }
        }

        impl<'de> Deserialize<'de> for $ty {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let name = String::deserialize(d)?;
                lookup::<$ty>(&name).map_err(serde::de::Error::custom)
            }
        }
    };
}

genus_fn_impls!(HeightFn, "height", genus_fns::builtin_height_fns);
genus_fn_impls!(WeatherFn, "weather", genus_fns::builtin_weather_fns);

/// Every function of kind `F` a file may name: the built-ins, then the registered ones.
pub fn known<F: GenusFn>() -> Vec<F> {
    let mut all = F::builtins();
    if let Ok(reg) = F::registered().lock() {
        all.extend(reg.iter().copied());
    }
    all
}

/// The function of kind `F` called `name`.
pub fn lookup<F: GenusFn>(name: &str) -> Result<F, String> {
    let all = known::<F>();
    all.iter()
        .find(|f| f.name() == name)
        .copied()
        .ok_or_else(|| {
            let names: Vec<&str> = all.iter().map(|f| f.name()).collect();
            format!(
                "unknown {} function `{name}` (known: {})",
                F::KIND,
                names.join(", ")
            )
        })
}

/// Refused registrations.
#[derive(Clone, Debug, thiserror::Error, PartialEq, Eq)]
#[error("cannot register {kind} function `{name}` ({path}): `{other}` already has that name")]
pub struct RegisterError {
    pub kind: &'static str,
    pub name: &'static str,
    pub path: &'static str,
    pub other: &'static str,
}

/// Lets genus files name `f`. Registering the same function twice is harmless; another
/// function of the same name is refused (a file's name must mean one function).
pub fn register<F: GenusFn>(f: F) -> Result<(), RegisterError> {
    if let Some(other) = known::<F>().into_iter().find(|g| g.name() == f.name()) {
        if other.path() == f.path() {
            return Ok(());
        }
        return Err(RegisterError {
            kind: F::KIND,
            name: f.name(),
            path: f.path(),
            other: other.path(),
        });
    }
    if let Ok(mut reg) = F::registered().lock() {
        reg.push(f);
    }
    Ok(())
}

/// The functions a genus' density is made of. Unset ones are the built-in defaults, which
/// give the reference library's model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GenusFunctions {
    pub weather: WeatherFn,
    pub shape: HeightFn,
    pub profile: HeightFn,
    /// The weather exponent's form, applied to the weather function's signal: not a file's
    /// choice, but the cheapest exact one for the genus' layers ([`GenusFunctions::for_layers`]).
    #[serde(skip, default = "unit_exponent")]
    pub exponent: HeightFn,
}

fn unit_exponent() -> HeightFn {
    genus_fns::UNIT_EXPONENT
}

impl Default for GenusFunctions {
    fn default() -> Self {
        GenusFunctions {
            weather: genus_fns::TEXTURE_WEATHER,
            shape: genus_fns::ROUNDED_SHAPE,
            profile: genus_fns::LINEAR_PROFILE,
            exponent: genus_fns::UNIT_EXPONENT,
        }
    }
}

impl GenusFunctions {
    pub fn is_default(&self) -> bool {
        *self == GenusFunctions::default()
    }

    /// `(slot, name)` of each function that is not the default, for key names and reports.
    pub fn custom(&self) -> Vec<(&'static str, &'static str)> {
        let d = GenusFunctions::default();
        let mut out = Vec::new();
        if self.weather != d.weather {
            out.push(("weather", self.weather.name));
        }
        if self.shape != d.shape {
            out.push(("shape", self.shape.name));
        }
        if self.profile != d.profile {
            out.push(("profile", self.profile.name));
        }
        if self.exponent != d.exponent {
            out.push(("exponent", self.exponent.name));
        }
        out
    }

    /// These functions for a genus of `layers`, each in the cheapest form that computes the
    /// same numbers. The weather exponent has two forms (the power, or none where every
    /// layer's is 1); the reference library's profile has two: `a·e^(b·η) + c·η + d` needs the
    /// exponential only where some layer has both `a` and `b` non-zero, and `a + c·η + d` is
    /// the same sum for every other layer (`a·e^0 = a`, `0·e^(bη) = 0`), so either name gives
    /// the form the layers need. A key holds what this returns, so a genus whose exponential
    /// term matters gets a shader of its own (named `exponential_profile`) and no other pays
    /// for it.
    pub fn for_layers(self, layers: &[CloudLayer]) -> GenusFunctions {
        let reference = [genus_fns::LINEAR_PROFILE, genus_fns::EXPONENTIAL_PROFILE];
        let constant_term = layers
            .iter()
            .all(|l| l.density_profile.a == 0.0 || l.density_profile.b == 0.0);
        let profile = if reference.contains(&self.profile) {
            reference[usize::from(!constant_term)]
        } else {
            self.profile
        };
        // Likewise the weather exponent: `x¹ = x`, so only a layer whose exponent is not 1
        // needs the power.
        let unit = layers.iter().all(|l| l.weather_exponent == 1.0);
        let exponent = if unit {
            genus_fns::UNIT_EXPONENT
        } else {
            genus_fns::WEATHER_EXPONENT
        };
        GenusFunctions {
            profile,
            exponent,
            ..self
        }
    }

    /// Every slot with its function's name, path and purpose.
    pub fn slots(&self) -> [(&'static str, &'static str, &'static str, &'static str); 4] {
        [
            (
                "weather",
                self.weather.name,
                self.weather.path,
                self.weather.about,
            ),
            ("shape", self.shape.name, self.shape.path, self.shape.about),
            (
                "profile",
                self.profile.name,
                self.profile.path,
                self.profile.about,
            ),
            (
                "exponent",
                self.exponent.name,
                self.exponent.path,
                self.exponent.about,
            ),
        ]
    }
}
