//! A scene over time: the sun from its clock, the clouds' drift from its wind, and its weather
//! states, each taking over from the one before.
//!
//! Between two states of the same genus the coverage is interpolated (the variant, its key and
//! its pipeline stay the same: only uniforms change). Between two genera the pictures of both
//! are blended, weighted by the same smooth ramp. A state is reached at its time, smoothly
//! (`smoothstep` over the interval from the state before it, or from second 0 for the first).
//! Two states at the same time are a cut: the second takes over at once, as a scene that wants
//! one asks.

use nimbus_dsl::prelude::*;
use nimbus_dsl::{DslError, ModuleBuilder, loc};
use serde::{Deserialize, Serialize};

use crate::clock::SunPosition;
use crate::scene::ScenePreset;
use crate::wind::{Drift, wind_drift, wind_velocity, wind_velocity_at};

/// One weather state: by `at` seconds the weather has become this. What it does not name it
/// keeps from the state before it (the scene itself before the first).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeatherState {
    /// Seconds from the start of the timeline.
    pub at: f64,
    /// Genus of this state; the previous state's when absent.
    pub genus: Option<String>,
    /// Coverage of this state; when absent the previous state's, or the genus' own where the
    /// genus changes.
    pub coverage: Option<f32>,
    /// Seconds before `at` the transition into this state starts; from the state before it
    /// (second 0 for the first) when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub over: Option<f64>,
}

/// What one picture of the scene at a time is made of: a genus and its coverage, and the
/// weight of its picture (1 when one state holds).
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    pub genus: String,
    pub coverage: f32,
    pub weight: f32,
}

/// The scene at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneAt {
    pub sun: SunPosition,
    pub drift: Drift,
    /// One layer, or two whose weights sum to 1 (a change of genus under way).
    pub layers: Vec<Layer>,
}

/// `smoothstep(0, 1, progress)`: the ramp transitions follow, so they start and end without a
/// kink (`progress` is the fraction of the transition's interval gone by, clamped to 0..1).
#[shader_fn]
pub fn weather_ramp(progress: f32) -> f32 {
    smoothstep(0.0, 1.0, progress)
}

/// How far through the transition into a weather state reached at `to_at` (s) the timeline is
/// at `seconds`: the transition starts at `from_at`, the time of the state before (0 for the
/// first), or `over` seconds before `to_at` when `over` ≥ 0 and that is later. 0 before it
/// starts (the ramp clamps), 1 once reached, and 1 for a cut (no time between the two).
#[shader_fn]
pub fn weather_progress(seconds: f32, from_at: f32, to_at: f32, over: f32) -> f32 {
    let start = select(from_at, from_at.max(to_at - over), over >= 0.0);
    let span = to_at - start;
    select(1.0, (seconds - start) / span.max(1e-6), span > 0.0)
}

/// The coverage `progress` of the way through a transition from `from` to `to` within one
/// genus: what `media.coverage` holds while the weather changes.
#[shader_fn]
pub fn weather_coverage(from: f32, to: f32, progress: f32) -> f32 {
    from + (to - from) * weather_ramp(progress)
}

/// A module holding what a host computes as the scene runs — the wind's velocity
/// ([`wind_velocity`], [`wind_velocity_at`] and its [`TOP_ALTITUDE`](crate::wind::TOP_ALTITUDE)),
/// the drift it makes ([`wind_drift`]), the weather's ramp ([`weather_progress`],
/// [`weather_coverage`]) and the altitude the temporal resolve moves with
/// the wind ([`crate::model::resolve::facing_altitude`]) — for printing their JavaScript twins
/// (`nimbus-wind.js` in engine packages with a JavaScript host).
pub fn host_module() -> Result<nimbus_dsl::ir::Module, DslError> {
    use crate::model::resolve::facing_altitude;
    use nimbus_dsl::host_fn;
    ModuleBuilder::build(
        "host",
        "Host functions: the wind's velocity, the weather's ramp, and the altitude the \
         reprojection moves with the wind.",
        loc!(),
        |m| {
            m.host(host_fn!(wind_velocity), loc!());
            m.host(host_fn!(wind_velocity_at), loc!());
            m.host(host_fn!(weather_coverage), loc!());
            m.host(host_fn!(weather_progress), loc!());
            m.host(host_fn!(wind_drift), loc!());
            m.host(host_fn!(facing_altitude), loc!());
        },
    )
}

impl ScenePreset {
    /// The scene `seconds` after the start of its timeline; `genus_coverage` gives a genus'
    /// own coverage (for a state or scene that names none).
    pub fn at(&self, seconds: f64, genus_coverage: &dyn Fn(&str) -> f32) -> SceneAt {
        let sun = match &self.clock {
            Some(c) => c.sun_at(seconds),
            None => SunPosition {
                elevation_deg: f64::from(self.sun_elevation_deg),
                azimuth_deg: f64::from(self.sun_azimuth_deg),
            },
        };
        let drift = self.wind.map(|w| w.drift(seconds)).unwrap_or_default();
        SceneAt {
            sun,
            drift,
            layers: self.weather_layers(seconds, genus_coverage),
        }
    }

    fn weather_layers(&self, seconds: f64, genus_coverage: &dyn Fn(&str) -> f32) -> Vec<Layer> {
        let own = Layer {
            genus: self.genus.clone(),
            coverage: self.coverage.unwrap_or_else(|| genus_coverage(&self.genus)),
            weight: 1.0,
        };
        // Each state keeps what it does not name from the state before it: its genus, and its
        // coverage while the genus stays (a new genus brings its own).
        let mut resolved: Vec<(f64, Layer)> = Vec::with_capacity(self.weather.len());
        let mut previous = own.clone();
        for state in &self.weather {
            let genus = state
                .genus
                .clone()
                .unwrap_or_else(|| previous.genus.clone());
            let coverage = state.coverage.unwrap_or_else(|| {
                if genus == previous.genus {
                    previous.coverage
                } else {
                    genus_coverage(&genus)
                }
            });
            previous = Layer {
                genus,
                coverage,
                weight: 1.0,
            };
            resolved.push((state.at, previous.clone()));
        }
        // Before the first state the scene's own weather holds and leads into it from 0.
        let next = resolved.iter().position(|(at, _)| *at > seconds);
        let (from, from_at, (to_at, to_layer), over) = match next {
            None => return vec![resolved.last().map_or(own, |(_, l)| l.clone())],
            Some(0) => (own, 0.0, resolved[0].clone(), self.weather[0].over),
            Some(i) => (
                resolved[i - 1].1.clone(),
                resolved[i - 1].0,
                resolved[i].clone(),
                self.weather[i].over,
            ),
        };
        // The same function a JavaScript host's timeline calls (`nimbus-wind.js`).
        let progress = weather_progress(
            seconds as f32,
            from_at as f32,
            to_at as f32,
            over.map_or(-1.0, |o| o as f32),
        );
        if from.genus == to_layer.genus {
            // One genus: interpolate the coverage; the picture's one pipeline stays.
            return vec![Layer {
                genus: from.genus,
                coverage: weather_coverage(from.coverage, to_layer.coverage, progress),
                weight: 1.0,
            }];
        }
        let s = weather_ramp(progress);
        vec![
            Layer {
                weight: 1.0 - s,
                ..from
            },
            Layer {
                weight: s,
                ..to_layer
            },
        ]
    }
}
