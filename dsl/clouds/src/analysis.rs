//! Which effects a scene can show: the minimal variant derived from a scene's content.
//!
//! Each rule is a small function of the scene that says whether an effect can make a visible
//! difference, and why. An effect is simulated only when the quality preset asks for it and
//! its rule allows it; the scene's `[features]` table then forces effects on or off over
//! both. Rules that are exact (the effect would contribute nothing) and rules that are
//! judgements (ground bounce seen from far above) are marked as such.

use super::features::{Features, Toggle};
use super::genus::Genus;
use super::path::Path;
use super::scene::ScenePreset;

/// Camera this far above the highest layer top sees no cloud base lit by the ground (m).
pub const GROUND_BOUNCE_VISIBLE_ABOVE: f32 = 1000.0;

/// What a scene contains, as far as the rules care.
#[derive(Clone, Copy, Debug)]
pub struct SceneContent<'a> {
    pub genus: &'a Genus,
    pub coverage: f32,
    pub sun_elevation_deg: f32,
    pub camera_altitude: f32,
    pub haze_density: f32,
    pub turbulence_displacement: f32,
}

impl<'a> SceneContent<'a> {
    pub fn of(scene: &ScenePreset, genus: &'a Genus) -> Self {
        SceneContent {
            genus,
            coverage: scene.coverage.unwrap_or(genus.coverage),
            sun_elevation_deg: scene.sun_elevation_deg,
            camera_altitude: scene.camera_altitude,
            haze_density: scene.haze_density,
            turbulence_displacement: scene.turbulence_displacement,
        }
    }
}

/// A rule's verdict: can the effect be seen, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    pub visible: bool,
    pub reason: String,
}

fn verdict(visible: bool, reason: impl Into<String>) -> Verdict {
    Verdict {
        visible,
        reason: reason.into(),
    }
}

/// Any cloud at all: coverage above 0 and an enabled layer with density.
pub fn clouds_present(c: &SceneContent) -> Verdict {
    let dense = c
        .genus
        .layers
        .iter()
        .filter(|l| l.is_enabled() && l.density_scale > 0.0)
        .count();
    if c.coverage <= 0.0 {
        return verdict(false, "coverage is 0: no clouds");
    }
    if dense == 0 {
        return verdict(false, "no layer has density");
    }
    verdict(true, format!("{dense} layer(s) with density"))
}

/// The sun gives direct light (its centre above the horizon).
pub fn sun_up(c: &SceneContent) -> Verdict {
    if c.sun_elevation_deg > 0.0 {
        verdict(true, format!("sun {}° up", c.sun_elevation_deg))
    } else {
        verdict(
            false,
            format!("sun {}° (below the horizon)", c.sun_elevation_deg),
        )
    }
}

fn shadow_top(c: &SceneContent) -> Option<f32> {
    c.genus
        .layers
        .iter()
        .filter(|l| l.is_enabled() && l.shadow && l.density_scale > 0.0)
        .map(|l| l.altitude + l.height)
        .reduce(f32::max)
}

/// Cloud shadows (beer shadow map, and the sky's light on the ground dimmed by the cloud
/// overhead): a shadow-casting layer. Exact: without one the map holds no optical depth and no
/// cloud stands over the ground. With the sun down the map casts nothing, but the cloud
/// overhead still dims the sky's light, so the effect stays (or the ground under an overcast
/// would brighten at the moment of sunset).
pub fn shadows(c: &SceneContent) -> Verdict {
    let clouds = clouds_present(c);
    if !clouds.visible {
        return clouds;
    }
    match shadow_top(c) {
        Some(_) if sun_up(c).visible => verdict(true, "a layer casts shadows and the sun is up"),
        Some(_) => verdict(
            true,
            "the sun is down, but a shadow-casting layer still dims the sky's light on the ground",
        ),
        None => verdict(false, "no layer casts shadows"),
    }
}

/// Haze: a haze density above 0. Exact.
pub fn haze(c: &SceneContent) -> Verdict {
    if c.haze_density > 0.0 {
        verdict(true, format!("haze density {:e}", c.haze_density))
    } else {
        verdict(false, "haze density is 0")
    }
}

/// Light shafts (cloud shadows in the haze): haze to see them in, a sun, and a shadow-casting
/// layer between the sun and the camera (not all below it).
pub fn light_shafts(c: &SceneContent) -> Verdict {
    let h = haze(c);
    if !h.visible {
        return verdict(false, format!("{}: no air to show shafts in", h.reason));
    }
    let sun = sun_up(c);
    if !sun.visible {
        return verdict(false, format!("{}: no shafts without it", sun.reason));
    }
    let s = shadows(c);
    if !s.visible {
        return s;
    }
    match shadow_top(c) {
        Some(top) if c.camera_altitude > top => verdict(
            false,
            format!(
                "camera at {} m is above every shadow-casting layer (top {top} m)",
                c.camera_altitude
            ),
        ),
        _ => verdict(true, "shadow-casting clouds between the sun and the camera"),
    }
}

/// Shape detail: some layer erodes with the detail texture. Exact: an amount of 0 leaves the
/// density as it is.
pub fn shape_detail(c: &SceneContent) -> Verdict {
    let clouds = clouds_present(c);
    if !clouds.visible {
        return clouds;
    }
    let n = c
        .genus
        .layers
        .iter()
        .filter(|l| l.is_enabled() && l.shape_detail_amount > 0.0)
        .count();
    if n == 0 {
        verdict(false, "every layer's shape-detail amount is 0")
    } else {
        verdict(true, format!("{n} layer(s) with shape detail"))
    }
}

/// Turbulence: a displacement above 0. Exact.
pub fn turbulence(c: &SceneContent) -> Verdict {
    let clouds = clouds_present(c);
    if !clouds.visible {
        return clouds;
    }
    if c.turbulence_displacement > 0.0 {
        verdict(
            true,
            format!("turbulent displacement {} m", c.turbulence_displacement),
        )
    } else {
        verdict(false, "turbulent displacement is 0")
    }
}

/// The top of the highest enabled layer (m).
fn highest_top(c: &SceneContent) -> f32 {
    c.genus
        .layers
        .iter()
        .filter(|l| l.is_enabled())
        .map(|l| l.altitude + l.height)
        .fold(0.0f32, f32::max)
}

/// Ground bounce: light from the ground reaches cloud bases the camera can see. A judgement,
/// not exact: seen from far above, the bases it brightens are hidden by the clouds.
pub fn ground_bounce(c: &SceneContent) -> Verdict {
    let clouds = clouds_present(c);
    if !clouds.visible {
        return clouds;
    }
    let top = highest_top(c);
    if c.camera_altitude > top + GROUND_BOUNCE_VISIBLE_ABOVE {
        verdict(
            false,
            format!(
                "camera at {} m, far above every layer (top {top} m): bases out of sight",
                c.camera_altitude
            ),
        )
    } else {
        verdict(true, "cloud bases can be seen")
    }
}

/// Camera this far above the highest layer top (m) sees the weather tile repeat: the layer lies
/// open below it out to about 250 km (2.5 tiles of 100 km) and more, seen from above rather
/// than squeezed against the horizon as from below.
pub const UNTILED_WEATHER_ABOVE: f32 = 5000.0;

/// The untiled weather: the camera is high above the clouds, where one view holds several
/// weather tiles side by side and the tile's repetition shows as rows and columns of the same
/// cloud fields. A judgement; from the ground the tiles beyond the first lie within a few
/// degrees of the horizon, behind the air.
pub fn untiled_weather(c: &SceneContent) -> Verdict {
    let clouds = clouds_present(c);
    if !clouds.visible {
        return clouds;
    }
    let top = highest_top(c);
    let above = c.camera_altitude - top;
    if above < UNTILED_WEATHER_ABOVE {
        return verdict(
            false,
            format!(
                "camera at {} m, not {UNTILED_WEATHER_ABOVE} m above the clouds (top {top} m): \
                 the weather tile's repetition lies at the horizon",
                c.camera_altitude
            ),
        );
    }
    // How far the camera sees the layer's top: to where its line of sight grazes it.
    let r = f64::from(crate::model::shell::EARTH_RADIUS);
    let reach = ((r + f64::from(c.camera_altitude)).powi(2) - (r + f64::from(top)).powi(2))
        .max(0.0)
        .sqrt();
    verdict(
        true,
        format!(
            "camera {above} m above the clouds sees them out to {:.0} km, {:.0} weather tiles: \
             the tile would repeat in rows and columns",
            reach / 1000.0,
            reach / 100_000.0
        ),
    )
}

/// Lowest base of a layer the flat 2D layer may stand for (m): cirrus and cirrostratus.
pub const FLAT_LAYER_MIN_ALTITUDE: f32 = 6000.0;
/// Thickest layer it may stand for (m): a sheet no pixel resolves the depth of from below.
pub const FLAT_LAYER_MAX_THICKNESS: f32 = 1200.0;
/// How far below the layer the camera must be (m): from near or inside it the layer has depth.
pub const FLAT_LAYER_CAMERA_BELOW: f32 = 2000.0;

/// The flat high layer (an approximation the analysis chooses, not an effect): every layer
/// with density is thin (≤ [`FLAT_LAYER_MAX_THICKNESS`]) and high (base ≥
/// [`FLAT_LAYER_MIN_ALTITUDE`]), and the camera is at least [`FLAT_LAYER_CAMERA_BELOW`] below
/// them. A judgement: the accuracy study measures what it costs in error.
pub fn flat_high_layer(c: &SceneContent) -> Verdict {
    let clouds = clouds_present(c);
    if !clouds.visible {
        return verdict(false, format!("{}: nothing to draw", clouds.reason));
    }
    let layers: Vec<_> = c
        .genus
        .layers
        .iter()
        .filter(|l| l.is_enabled() && l.density_scale > 0.0)
        .collect();
    if let Some(l) = layers.iter().find(|l| l.altitude < FLAT_LAYER_MIN_ALTITUDE) {
        return verdict(
            false,
            format!(
                "a layer at {} m is not a high layer (below {FLAT_LAYER_MIN_ALTITUDE} m): the \
                 volume is marched",
                l.altitude
            ),
        );
    }
    if let Some(l) = layers.iter().find(|l| l.height > FLAT_LAYER_MAX_THICKNESS) {
        return verdict(
            false,
            format!(
                "a layer {} m thick has depth to show (over {FLAT_LAYER_MAX_THICKNESS} m): the \
                 volume is marched",
                l.height
            ),
        );
    }
    let base = layers
        .iter()
        .map(|l| l.altitude)
        .fold(f32::INFINITY, f32::min);
    if c.camera_altitude > base - FLAT_LAYER_CAMERA_BELOW {
        return verdict(
            false,
            format!(
                "camera at {} m is near the layer (base {base} m; flat needs {FLAT_LAYER_CAMERA_BELOW} \
                 m below it): the volume is marched",
                c.camera_altitude
            ),
        );
    }
    let thickest = layers.iter().map(|l| l.height).fold(0.0f32, f32::max);
    verdict(
        true,
        format!(
            "{} thin high layer(s) (base ≥ {base} m, ≤ {thickest} m thick) seen from {} m: drawn \
             as a 2D layer, {} density reads per pixel instead of a march",
            layers.len(),
            c.camera_altitude,
            crate::model::flat_layer::FLAT_SAMPLES
        ),
    )
}

/// The rule of a toggle, or `None` when only the quality preset decides it (the effect
/// table's `rule` column).
pub fn rule(t: Toggle) -> Option<fn(&SceneContent) -> Verdict> {
    t.rule()
}

/// One effect's decision.
#[derive(Clone, Debug, PartialEq)]
pub struct Decision {
    pub toggle: Toggle,
    pub included: bool,
    pub reason: String,
}

/// The derived variant of a scene and the reasons.
#[derive(Clone, Debug, PartialEq)]
pub struct Analysis {
    pub features: Features,
    pub decisions: Vec<Decision>,
    /// Layers in use, and the lane groups they need (1 group = up to 4 layers).
    pub layers: usize,
    pub layer_groups: usize,
    /// The path the clouds are drawn by, and why.
    pub path: PathDecision,
}

/// The path a scene's clouds are drawn by, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct PathDecision {
    pub path: Path,
    pub reason: String,
}

/// Derives the minimal features for `scene` seen with `genus`.
pub fn analyse(scene: &ScenePreset, genus: &Genus) -> Analysis {
    let content = SceneContent::of(scene, genus);
    let preset = scene.quality.features();
    let mut features = preset;
    let mut decisions = Vec::new();
    for &t in Toggle::ALL {
        let forced = scene.features.get(t);
        let (included, reason) = match (forced, t.get(&preset), rule(t)) {
            (Some(on), _, _) => (on, format!("forced {} by the scene", on_off(on))),
            (None, false, Some(r)) if t.chosen_in(scene.quality) => {
                let v = r(&content);
                (v.visible, v.reason)
            }
            (None, false, _) => (
                false,
                format!("off in the `{}` preset", scene.quality.name()),
            ),
            (None, true, None) => (
                true,
                format!(
                    "on in the `{}` preset (no scene rule)",
                    scene.quality.name()
                ),
            ),
            (None, true, Some(r)) => {
                let v = r(&content);
                (v.visible, v.reason)
            }
        };
        t.set(&mut features, included);
        decisions.push(Decision {
            toggle: t,
            included,
            reason,
        });
    }
    if let Some(o) = scene.features.octaves {
        features.octaves = o;
    }
    let path = path_choice(scene, &features);
    features.path = path.path;
    if path.path != Path::Volume && features.flat_high_layer {
        // The flat layer is the volume's shortcut; a baked path draws the layer from its own
        // tables.
        features.flat_high_layer = false;
        if let Some(d) = decisions
            .iter_mut()
            .find(|d| d.toggle == Toggle::FlatHighLayer)
        {
            d.included = false;
            d.reason = format!(
                "the `{}` path draws the high layer from its bake",
                path.path
            );
        }
    }
    let layers = genus.layers.iter().filter(|l| l.is_enabled()).count();
    Analysis {
        features,
        decisions,
        layers,
        layer_groups: genus.layer_groups(),
        path,
    }
}

/// The path a scene draws its clouds by, and why: the scene's `path`, else the one its
/// `[budget]` fits ([`crate::budget::choose`]), unless its camera needs the volume.
fn path_choice(scene: &ScenePreset, features: &Features) -> PathDecision {
    let (wanted, reason) = match (scene.features.path, scene.budget) {
        (Some(wanted), _) => (
            wanted,
            format!(
                "chosen by the scene (`path = \"{wanted}\"`): {}",
                wanted.doc()
            ),
        ),
        (None, Some(budget)) => {
            crate::budget::choose(budget, scene.quality, crate::budget::animated_by(scene))
        }
        (None, None) => (
            Path::Volume,
            "the default: the scene names no path and no budget".into(),
        ),
    };
    if wanted != Path::Volume && features.orthographic {
        return PathDecision {
            path: Path::Volume,
            reason: format!(
                "`{wanted}` ({reason}); but an orthographic camera shades each pixel from its \
                 own origin, which a bake around one camera cannot serve"
            ),
        };
    }
    PathDecision {
        path: wanted,
        reason,
    }
}

fn on_off(on: bool) -> &'static str {
    if on { "on" } else { "off" }
}
