//! A scene over time: the sun from its clock, the clouds' drift from its wind, and its weather
//! states, each taking over from the one before.
//!
//! Between two states of the same genus every number of the scene is interpolated (the
//! variant, its key and its pipeline stay the same: only uniforms change). Between two genera
//! the pictures of both are blended, weighted by the same smooth ramp. Either way nothing
//! jumps: a state is reached at its time, smoothly (`smoothstep` over the interval).

use serde::{Deserialize, Serialize};

use crate::clock::SunPosition;
use crate::scene::ScenePreset;
use crate::wind::Drift;

/// One weather state: from `at` seconds on, the scene's genus and coverage become these.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeatherState {
    /// Seconds from the start of the timeline.
    pub at: f64,
    /// Genus of this state; the scene's when absent.
    pub genus: Option<String>,
    /// Coverage of this state; the genus' when absent.
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

    fn state_layer(&self, s: &WeatherState, genus_coverage: &dyn Fn(&str) -> f32) -> Layer {
        let genus = s.genus.clone().unwrap_or_else(|| self.genus.clone());
        let coverage = s
            .coverage
            .or(if s.genus.is_none() {
                self.coverage
            } else {
                None
            })
            .unwrap_or_else(|| genus_coverage(&genus));
        Layer {
            genus,
            coverage,
            weight: 1.0,
        }
    }

    fn weather_layers(&self, seconds: f64, genus_coverage: &dyn Fn(&str) -> f32) -> Vec<Layer> {
        let own = Layer {
            genus: self.genus.clone(),
            coverage: self.coverage.unwrap_or_else(|| genus_coverage(&self.genus)),
            weight: 1.0,
        };
        let layer = |s: &WeatherState| self.state_layer(s, genus_coverage);
        let states = &self.weather;
        // Before the first state the scene's own weather holds and leads into it from 0.
        let next = states.iter().position(|s| s.at > seconds);
        let (from, from_at, to) = match next {
            None => return vec![states.last().map_or(own, layer)],
            Some(0) => (own, 0.0, &states[0]),
            Some(i) => (layer(&states[i - 1]), states[i - 1].at, &states[i]),
        };
        let to_layer = layer(to);
        let span = to.at - from_at;
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
