//! A frame to render, as data: the genus and quality, the sun, the camera (perspective or
//! orthographic), the weather, wind and haze, the engine's depth, and how many frames to
//! accumulate. What a scene turns into for the shaders (`Frame::uniforms`, the cloud block)
//! lives here with the model, so every host (the wgpu runtime, the package writer, the tests)
//! makes it the same way, from one set of defaults
//! ([`VIEW_DEFAULTS`](crate::view_defaults::VIEW_DEFAULTS)).

use glam::{Mat4, Vec2, Vec3};
use thiserror::Error;

use crate::engine_depth::SceneDepth;
use crate::limits::{self, Limit, Origin};
use crate::model::clouds::CloudVariant;
use crate::model::march::{CloudUniforms, CompositeParams};
use crate::model::sun::sun_direction;
use crate::view_defaults::VIEW_DEFAULTS;
use crate::wind::Drift;
use crate::{DataError, Features, Genus, PixelOutput, Quality, ScenePreset, analyse};

/// A frame that cannot be drawn, naming the `Frame` field and why.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FrameError {
    /// A number outside its range ([`crate::limits`]).
    #[error(transparent)]
    Value(#[from] DataError),
    #[error("{field}: {reason}")]
    Invalid { field: &'static str, reason: String },
    #[error("Frame::genus `{genus}`: {field}: {reason}")]
    Genus {
        genus: String,
        field: String,
        reason: String,
    },
}

/// What to render.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub genus: Genus,
    pub quality: Quality,
    pub features: Features,
    /// Sun elevation above the horizon and azimuth (degrees).
    pub sun_elevation_deg: f32,
    pub sun_azimuth_deg: f32,
    pub camera_altitude: f32,
    /// Camera pitch above the horizon, yaw, and vertical field of view (degrees).
    pub camera_pitch_deg: f32,
    pub camera_yaw_deg: f32,
    pub fov_deg: f32,
    /// Frames of temporal accumulation (at least 1). Upscaled, 16 frames shade every pixel
    /// once.
    pub frames: u32,
    /// Shade one pixel in sixteen per frame and reconstruct the rest from the history.
    pub upscale: bool,
    /// Keep the history of the previous `render` call (same size and mode) and reproject it,
    /// as a game loop does; otherwise each call starts afresh.
    pub continue_history: bool,
    /// Seed of the per-frame jitter sequence: same seed and frame, same pixels.
    pub seed: u32,
    /// Offset of the weather texture in tiles.
    pub weather_offset: Vec2,
    /// How far the wind has carried the clouds (see [`nimbus_clouds::wind`]).
    pub wind: Drift,
    /// With `continue_history`: read the history where the wind had the clouds a frame ago
    /// (the drift's change since the previous call), so drifting clouds do not smear. Off, the
    /// history is reprojected for the camera alone (for comparison).
    pub reproject_wind: bool,
    /// Haze density at sea level (1/m).
    pub haze_density: f32,
    /// Turbulent displacement of cloud bases (m).
    pub turbulence_displacement: f32,
    /// What each pixel holds: the composited image, or a linear or instrumented layer
    /// ([`PixelOutput::Samples`]: use one full-resolution frame, so no resolve averages them).
    pub output: PixelOutput,
    /// Verification mode: the clouds lit by a sun of irradiance 1 alone (no powder, ground
    /// bounce, sky light, per-sample sun filtering, haze, aerial perspective or background),
    /// the model an independent path tracer can reproduce; with `features.octaves = 1` and no
    /// `features.diffusion` it is pure single scattering, with more octaves or the diffusion
    /// the multiple-scattering approximation alone.
    pub verification: bool,
    /// What the composite adds around the clouds (sky, sun disc, ground, aerial perspective),
    /// each switchable; verification mode switches them all off.
    pub composite: CompositeParams,
    /// The opaque scene the clouds stand in, from an engine's depth buffer: its surfaces stop
    /// the march and the image becomes premultiplied over the engine's picture (the
    /// `scene-depth` key). `None`: Nimbus's sky and ground are the whole background.
    pub scene_depth: Option<SceneDepth>,
    /// An orthographic camera's view: the height (m) of what it sees, the width following the
    /// image's aspect; parallel rays along the camera's forward axis, each from its own point
    /// of the plane through the camera (the `orthographic` key). `None`: a perspective camera
    /// of `fov_deg`.
    pub orthographic: Option<f32>,
}

impl Frame {
    /// A frame of `genus` at `quality` with the preset's toggles, seen as
    /// [`VIEW_DEFAULTS`] says (the defaults of a scene file too): from 2 m above the ground
    /// looking 12° up, sun 35° high.
    pub fn new(genus: Genus, quality: Quality, width: u32, height: u32) -> Frame {
        let d = VIEW_DEFAULTS;
        Frame {
            width,
            height,
            genus,
            quality,
            features: quality.features(),
            sun_elevation_deg: d.sun_elevation_deg,
            sun_azimuth_deg: d.sun_azimuth_deg,
            camera_altitude: d.camera_altitude,
            camera_pitch_deg: d.camera_pitch_deg,
            camera_yaw_deg: d.camera_yaw_deg,
            fov_deg: d.fov_deg,
            frames: 1,
            upscale: false,
            continue_history: false,
            seed: 0,
            weather_offset: Vec2::ZERO,
            wind: Drift::default(),
            reproject_wind: true,
            haze_density: d.haze_density,
            turbulence_displacement: d.turbulence_displacement,
            output: PixelOutput::Composite,
            verification: false,
            composite: CompositeParams::ALL,
            scene_depth: None,
            orthographic: None,
        }
    }

    /// The frame a scene describes, with the variant the scene derives (see
    /// [`nimbus_clouds::analyse`]): only the effects it can show. Its fixed sun and weather:
    /// for a moment of its timeline (clock, wind, weather states) see
    /// `nimbus_runtime::scene_time::frames_at`.
    pub fn from_scene(scene: &ScenePreset, genus: &Genus, width: u32, height: u32) -> Frame {
        let mut genus = genus.clone();
        if let Some(c) = scene.coverage {
            genus.coverage = c;
        }
        let features = analyse(scene, &genus).features;
        let mut f = Frame::new(genus, scene.quality, width, height);
        f.features = features;
        f.sun_elevation_deg = scene.sun_elevation_deg;
        f.sun_azimuth_deg = scene.sun_azimuth_deg;
        f.camera_altitude = scene.camera_altitude;
        f.camera_pitch_deg = scene.camera_pitch_deg;
        f.camera_yaw_deg = scene.camera_yaw_deg;
        f.fov_deg = scene.fov_deg;
        f.weather_offset = Vec2::from_array(scene.weather_offset);
        f.haze_density = scene.haze_density;
        f.turbulence_displacement = scene.turbulence_displacement;
        f
    }

    /// Checks every value against [`nimbus_clouds::limits`], the same ranges a scene file and
    /// the command line are held to; the error names the field (`Frame::fov_deg`).
    pub fn validate(&self) -> Result<(), FrameError> {
        let api = |l: &Limit| Origin::Api(format!("Frame::{}", l.field));
        let check = |l: &Limit, v: f64| l.check(v, api(l));
        for (field, side) in [("Frame::width", self.width), ("Frame::height", self.height)] {
            limits::IMAGE_SIDE.check(f64::from(side), Origin::Api(field.into()))?;
        }
        check(&limits::FRAMES, f64::from(self.frames))?;
        check(&limits::SUN_ELEVATION, f64::from(self.sun_elevation_deg))?;
        check(&limits::SUN_AZIMUTH, f64::from(self.sun_azimuth_deg))?;
        check(&limits::CAMERA_ALTITUDE, f64::from(self.camera_altitude))?;
        check(&limits::CAMERA_PITCH, f64::from(self.camera_pitch_deg))?;
        check(&limits::CAMERA_YAW, f64::from(self.camera_yaw_deg))?;
        check(&limits::FOV, f64::from(self.fov_deg))?;
        check(&limits::COVERAGE, f64::from(self.genus.coverage))?;
        check(&limits::HAZE_DENSITY, f64::from(self.haze_density))?;
        check(
            &limits::TURBULENCE_DISPLACEMENT,
            f64::from(self.turbulence_displacement),
        )?;
        for v in self.weather_offset.to_array() {
            check(&limits::WEATHER_OFFSET, f64::from(v))?;
        }
        check(&limits::OCTAVES, f64::from(self.features.octaves))?;
        if let Some(d) = &self.scene_depth {
            d.validate(self.width, self.height)?;
        }
        if let Some(h) = self.orthographic
            && !(h.is_finite() && h > 0.0)
        {
            return Err(FrameError::Invalid {
                field: "Frame::orthographic",
                reason: format!("the view's height must be a positive number of metres, got {h}"),
            });
        }
        if self.orthographic.is_some() && (self.upscale || self.frames > 1) {
            // The resolve reprojects directions from the camera, which parallel rays are not.
            return Err(FrameError::Invalid {
                field: "Frame::orthographic",
                reason: "an orthographic view is drawn one frame at a time (the temporal \
                         resolve reprojects rays from one point); set frames = 1, upscale off"
                    .into(),
            });
        }
        self.genus
            .validate()
            .map_err(|(field, reason)| FrameError::Genus {
                genus: self.genus.name.clone(),
                field,
                reason,
            })?;
        Ok(())
    }

    /// The cloud variant this frame renders.
    pub fn variant(&self) -> CloudVariant {
        let mut v = CloudVariant::new(&self.genus, self.quality, self.effective_features());
        v.key.output = self.output;
        v
    }

    /// The features rendered: the frame's, less every effect beyond the sun's scattering in
    /// verification mode.
    pub fn effective_features(&self) -> Features {
        let mut f = if self.verification {
            self.features.sun_scattering_only()
        } else {
            self.features
        };
        // The key reads the engine's depth exactly when the frame has a scene, and casts
        // parallel rays exactly when its camera is orthographic.
        f.scene_depth = self.scene_depth.is_some();
        f.orthographic = self.orthographic.is_some();
        f
    }

    /// The unit vector towards the sun (local frame, y up).
    pub fn sun_direction(&self) -> Vec3 {
        sun_direction(self.sun_elevation_deg, self.sun_azimuth_deg)
    }

    /// The camera's forward and up directions in the local frame (x east, y up, z south).
    pub fn camera_basis(&self) -> (Vec3, Vec3) {
        let (pitch, yaw) = (
            self.camera_pitch_deg.to_radians(),
            self.camera_yaw_deg.to_radians(),
        );
        let forward = Vec3::new(
            pitch.cos() * yaw.sin(),
            pitch.sin(),
            -pitch.cos() * yaw.cos(),
        );
        // The camera's up from its right (east at yaw 0, always horizontal), so a camera
        // looking straight up or down still has a basis (y-up would be parallel to forward).
        let right = Vec3::new(yaw.cos(), 0.0, yaw.sin());
        (forward, right.cross(forward))
    }

    /// View-projection without translation (the camera is the origin of the local frame).
    pub fn view_projection(&self) -> Mat4 {
        let (forward, up) = self.camera_basis();
        let view = Mat4::look_to_rh(Vec3::ZERO, forward, up);
        let aspect = self.width as f32 / self.height as f32;
        if let Some(h) = self.orthographic {
            // Depth 0 at the camera's plane: rays are unprojected at depths 0 and 1.
            let (x, y) = (0.5 * h * aspect, 0.5 * h);
            return Mat4::orthographic_rh(-x, x, -y, y, 0.0, 1e6) * view;
        }
        // Infinite far plane, reversed depth: the shader unprojects depth 1, the near plane,
        // where w is well conditioned at any field of view (unprojecting a far plane 1e6
        // times further than the near one loses w to cancellation and flips wide rays).
        Mat4::perspective_infinite_reverse_rh(self.fov_deg.to_radians(), aspect, 1.0) * view
    }

    /// What the frame writes into the cloud block (at frame index 0; the frame sequence fills
    /// the per-frame members): the genus at its quality lit by the frame's sun, seen by its
    /// camera, with its weather, wind, haze and composite.
    pub fn uniforms(&self) -> CloudUniforms {
        let mut u = CloudUniforms::for_genus(
            &self.genus,
            self.quality,
            self.sun_direction(),
            self.camera_altitude,
        );
        u.inverse_view_projection = self.view_projection().inverse();
        u.resolution = Vec2::new(self.width as f32, self.height as f32);
        u.media.weather_offset = self.weather_offset;
        u.media.wind_drift = self.wind.ground;
        u.media.wind_shear_drift = self.wind.per_metre;
        u.media.turbulence_displacement = self.turbulence_displacement;
        u.haze.density = self.haze_density;
        u.composite = self.composite;
        if self.verification {
            u = u.lit_by_sun_alone();
        }
        u
    }
}
