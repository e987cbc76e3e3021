//! A frame budget (`[budget]` in a scene file): what the clouds may take of a frame on the
//! device the scene is for, and the path that fits it when the scene names none.
//!
//! What the volume costs depends on the device far more than anything Nimbus can know, so the
//! scene says it: `volume_ms`, the volume's frame at the scene's preset and size as measured
//! on the target device (`nimbus bench-frames` on it, or the engine's GPU timer). What each
//! baked path costs beside the volume is a ratio that depends much less on the device (it is
//! the same march, or none, over the same pixels): [`cost_ratio`], from `nimbus bench-frames`.
//! The choice ([`choose`]) is the most accurate path whose cost fits; the order of accuracy is
//! the accuracy study's (`nimbus tradeoff`).

use serde::{Deserialize, Serialize};

use crate::{Path, Quality};

/// `[budget]`: the clouds' share of a frame on the target device, and what the volume costs
/// there.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    /// Milliseconds of a frame the clouds may take.
    pub frame_ms: f32,
    /// Milliseconds the volume's frame takes at the scene's preset and size on the target
    /// device.
    pub volume_ms: f32,
}

/// The baked paths from the most accurate to the least (the accuracy study's FLIP against the
/// reference at `low` and `high`): the impostor is the volume's own pixel resampled, the slices
/// keep the density's altitude structure, the 2D map holds one bell per column, the mesh one
/// soft puff per cell.
pub const BY_ACCURACY: [Path; 4] = [Path::Impostor, Path::Slices, Path::Blob2d, Path::Mesh];

/// A baked path's full-resolution frame at `quality` as a fraction of the volume's, with its
/// bake cached (`nimbus bench-frames -r 640x360`, llvmpipe, the default scene, one run on
/// 2026-12-04 after the impostor's map took the whole picture: the
/// "×volume" column); `reference` takes `ultra`'s. The volume's is 1.
pub fn cost_ratio(path: Path, quality: Quality) -> f32 {
    use Quality::*;
    let column = match quality {
        Low => 0,
        Medium => 1,
        High => 2,
        Ultra | Reference => 3,
    };
    let row: [f32; 4] = match path {
        Path::Volume => return 1.0,
        Path::Slices => [0.29, 0.14, 0.21, 0.22],
        // Two reads a pixel: the map holds the whole picture.
        Path::Impostor => [0.03, 0.01, 0.01, 0.01],
        Path::Blob2d => [0.29, 0.14, 0.24, 0.23],
        // Its per-pixel search of the cluster table costs about what `low`'s march does, and
        // less than the others'.
        Path::Mesh => [0.96, 0.42, 0.42, 0.35],
    };
    row[column]
}

/// What moves a scene's clouds or sun from frame to frame, if anything: a baked path redraws
/// its bake whenever they move.
pub fn animated_by(scene: &crate::ScenePreset) -> Option<&'static str> {
    if scene.clock.is_some() {
        Some("its clock moves the sun")
    } else if scene.wind.is_some() {
        Some("its wind drifts the clouds")
    } else if !scene.weather.is_empty() {
        Some("its weather timeline changes the clouds")
    } else if scene.formation.is_some() {
        Some("its clouds form and dissolve")
    } else {
        None
    }
}

/// The path for `budget` at `quality` in a scene that `animated` says moves (or not), and why.
pub fn choose(budget: Budget, quality: Quality, animated: Option<&str>) -> (Path, String) {
    let Budget {
        frame_ms,
        volume_ms,
    } = budget;
    if volume_ms <= frame_ms {
        return (
            Path::Volume,
            format!("the budget: the volume's {volume_ms} ms fits the frame's {frame_ms} ms"),
        );
    }
    if let Some(why) = animated {
        return (
            Path::Volume,
            format!(
                "the budget asks for {:.1}× less than the volume's {volume_ms} ms, but the scene \
                 moves every frame ({why}) and a baked path would redraw its bake each frame, \
                 which costs several volume frames (`nimbus bench-frames`, last column): \
                 upscaling or a lower preset is the saving here",
                volume_ms / frame_ms
            ),
        );
    }
    let cost = |p: Path| cost_ratio(p, quality) * volume_ms;
    if let Some(&p) = BY_ACCURACY.iter().find(|&&p| cost(p) <= frame_ms) {
        return (
            p,
            format!(
                "the budget: the volume's {volume_ms} ms exceeds the frame's {frame_ms} ms; \
                 `{p}` costs about {:.2}× the volume at `{}` ({:.1} ms), the most accurate \
                 path that fits (by accuracy: {})",
                cost(p) / volume_ms,
                quality.name(),
                cost(p),
                names()
            ),
        );
    }
    let cheapest = BY_ACCURACY
        .iter()
        .copied()
        .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
        .unwrap_or(Path::Blob2d);
    (
        cheapest,
        format!(
            "the budget: no path fits the frame's {frame_ms} ms at `{}` (the volume {volume_ms} \
             ms); `{cheapest}` is the cheapest ({:.1} ms): upscaling (a quarter to a fifth of a \
             full-resolution frame) or a smaller image is needed as well",
            quality.name(),
            cost(cheapest)
        ),
    )
}

/// The baked paths in order of accuracy, for messages.
fn names() -> String {
    BY_ACCURACY
        .iter()
        .map(|p| format!("`{p}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn budget(frame_ms: f32, volume_ms: f32) -> Budget {
        Budget {
            frame_ms,
            volume_ms,
        }
    }

    #[test]
    fn the_volume_stays_when_it_fits_or_the_scene_moves() {
        let (p, why) = choose(budget(16.0, 12.0), Quality::High, None);
        assert_eq!(p, Path::Volume, "{why}");
        let (p, why) = choose(budget(4.0, 40.0), Quality::Low, Some("its wind"));
        assert_eq!(p, Path::Volume, "{why}");
        assert!(why.contains("its wind"), "{why}");
    }

    #[test]
    fn the_most_accurate_path_that_fits_is_chosen() {
        // 0.2 of the volume: the impostor fits at `low` (0.03), nothing more accurate exists.
        let (p, why) = choose(budget(8.0, 40.0), Quality::Low, None);
        assert_eq!(p, Path::Impostor, "{why}");
        // Each path at its own cost exactly: the first in accuracy order that fits.
        for q in [Quality::Low, Quality::Medium, Quality::High, Quality::Ultra] {
            for (i, &want) in BY_ACCURACY.iter().enumerate() {
                let ratio = cost_ratio(want, q);
                let fits_earlier = BY_ACCURACY[..i].iter().any(|&e| cost_ratio(e, q) <= ratio);
                let (p, why) = choose(budget(ratio * 100.0, 100.0), q, None);
                if fits_earlier {
                    assert_ne!(p, want, "{why}");
                } else {
                    assert_eq!(p, want, "{q:?}: {why}");
                }
            }
        }
    }

    #[test]
    fn an_impossible_budget_gets_the_cheapest_path_and_says_so() {
        let cheapest = BY_ACCURACY
            .iter()
            .map(|&p| cost_ratio(p, Quality::Medium))
            .fold(f32::INFINITY, f32::min);
        // Half of what the cheapest path costs.
        let (p, why) = choose(budget(cheapest * 50.0, 100.0), Quality::Medium, None);
        assert_eq!(cost_ratio(p, Quality::Medium), cheapest, "{why}");
        assert!(why.contains("no path fits"), "{why}");
    }

    #[test]
    fn every_baked_path_has_a_cost_and_a_place_in_the_accuracy_order() {
        for p in Path::ALL {
            let cost = cost_ratio(p, Quality::Low);
            assert!(cost > 0.0 && cost.is_finite(), "{p}: cost {cost}");
            if p.bakes() {
                assert!(BY_ACCURACY.contains(&p), "{p} is not in the accuracy order");
            }
        }
    }
}
