//! A scene over time: the sun from its clock, the clouds' drift from its wind, and its weather
//! states, each taking over from the one before.
//!
//! Between two states of the same genus the coverage is interpolated (the variant, its key and
//! its pipeline stay the same: only uniforms change). Between two genera the pictures of both
//! are blended, weighted by the same smooth ramp. A state is reached at its time, smoothly
//! (`smoothstep` over the interval from the state before it, or from second 0 for the first).
//! Two states at the same time are a cut: the second takes over at once, as a scene that wants
//! one asks.

use serde::{Deserialize, Serialize};

use crate::clock::SunPosition;
use crate::scene::ScenePreset;
use crate::wind::Drift;

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

/// `smoothstep(0, 1, x)`: the ramp transitions follow, so they start and end without a kink.
fn ramp(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
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
        let (from, from_at, (to_at, to_layer)) = match next {
            None => return vec![resolved.last().map_or(own, |(_, l)| l.clone())],
            Some(0) => (own, 0.0, resolved[0].clone()),
            Some(i) => (
                resolved[i - 1].1.clone(),
                resolved[i - 1].0,
                resolved[i].clone(),
            ),
        };
        let span = to_at - from_at;
        let s = if span > 0.0 {
            ramp((seconds - from_at) / span)
        } else {
            1.0
        };
        if from.genus == to_layer.genus {
            // One genus: interpolate the coverage; the picture's one pipeline stays.
            return vec![Layer {
                genus: from.genus,
                coverage: from.coverage + (to_layer.coverage - from.coverage) * s as f32,
                weight: 1.0,
            }];
        }
        vec![
            Layer {
                weight: (1.0 - s) as f32,
                ..from
            },
            Layer {
                weight: s as f32,
                ..to_layer
            },
        ]
    }
}
