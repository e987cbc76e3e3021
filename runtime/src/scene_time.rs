//! A scene at one time of its timeline: the frames to render and how to blend them
//! ([`nimbus_clouds::timeline`]). One frame while a weather state holds or changes within its
//! genus; two, weighted, while one genus gives way to another.

use nimbus_clouds::wind::Drift;
use nimbus_clouds::{Genus, ScenePreset};

use crate::error::RuntimeError;
use crate::render::{Frame, Image, Renderer};

/// The scene presets `scene` is at `seconds`, one per picture, each with the wind's drift and
/// its weight: the genus and coverage of the weather states, the sun by the clock (when the
/// scene has one).
pub fn scenes_at(
    scene: &ScenePreset,
    genus_coverage: &dyn Fn(&str) -> f32,
    seconds: f64,
) -> Vec<(ScenePreset, Drift, f32)> {
    let at = scene.at(seconds, genus_coverage);
    at.layers
        .into_iter()
        .map(|layer| {
            let mut s = scene.clone();
            s.genus = layer.genus;
            s.coverage = Some(layer.coverage.clamp(0.0, 1.0));
            if scene.clock.is_some() {
                s.sun_elevation_deg = at.sun.elevation_deg as f32;
                s.sun_azimuth_deg = at.sun.azimuth_deg.rem_euclid(360.0) as f32;
            }
            (s, at.drift, layer.weight)
        })
        .collect()
}

/// The frames of `scene` at `seconds`, each with its weight (they sum to 1), `width`×`height`.
/// `genus_of` finds a genus by name (a [`nimbus_clouds::CloudLibrary`]'s `genus`).
pub fn frames_at(
    scene: &ScenePreset,
    genus_of: &dyn Fn(&str) -> Option<Genus>,
    seconds: f64,
    width: u32,
    height: u32,
) -> Result<Vec<(Frame, f32)>, RuntimeError> {
    let coverage = |name: &str| genus_of(name).map_or(0.0, |g| g.coverage);
    let mut frames = Vec::new();
    for (s, drift, weight) in scenes_at(scene, &coverage, seconds) {
        let genus = genus_of(&s.genus).ok_or_else(|| RuntimeError::UnknownGenus {
            scene: scene.name.clone(),
            genus: s.genus.clone(),
        })?;
        let mut f = Frame::from_scene(&s, &genus, width, height);
        f.wind = drift;
        frames.push((f, weight));
    }
    Ok(frames)
}

impl Renderer<'_> {
    /// Renders weighted frames ([`frames_at`]) and blends their linear pixels.
    pub fn render_blend(&mut self, frames: &[(Frame, f32)]) -> Result<Image, RuntimeError> {
        let mut out: Option<Image> = None;
        for (frame, weight) in frames {
            if *weight <= 0.0 && frames.len() > 1 {
                continue;
            }
            let image = self.render(frame)?;
            match &mut out {
                None => {
                    out = Some(Image {
                        pixels: image.pixels.iter().map(|p| p.map(|c| c * weight)).collect(),
                        ..image
                    })
                }
                Some(o) => {
                    for (a, b) in o.pixels.iter_mut().zip(&image.pixels) {
                        for c in 0..4 {
                            a[c] += b[c] * weight;
                        }
                    }
                }
            }
        }
        out.ok_or_else(|| RuntimeError::Limit("no frame to render".into()))
    }
}
