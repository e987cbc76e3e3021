//! One cloud layer: a horizontal slab with its own shape and density parameters. Defaults are
//! those of @takram/three-clouds' `CloudLayer`.

use serde::{Deserialize, Serialize};

use crate::limits::format_value;

/// Channel of the local weather texture a layer reads its coverage from. Several layers may
/// share a channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Channel {
    #[default]
    R,
    G,
    B,
    A,
}

impl Channel {
    pub fn index(self) -> usize {
        match self {
            Channel::R => 0,
            Channel::G => 1,
            Channel::B => 2,
            Channel::A => 3,
        }
    }
}

/// `a·e^(b·η) + c·η + d` over the height fraction η ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DensityProfileParams {
    pub a: f32,
    pub b: f32,
    pub c: f32,
    pub d: f32,
}

impl Default for DensityProfileParams {
    fn default() -> Self {
        Self {
            a: 0.0,
            b: 0.0,
            c: 0.75,
            d: 0.25,
        }
    }
}

/// A cloud layer. Lengths in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CloudLayer {
    /// Weather-texture channel giving this layer's coverage signal.
    pub channel: Channel,
    /// Altitude of the layer's bottom above the ground (m).
    pub altitude: f32,
    /// Thickness of the layer (m); 0 disables it.
    pub height: f32,
    /// Overall density (extinction per metre at full density is this times the medium's
    /// coefficients).
    pub density_scale: f32,
    /// Influence of the shape (Perlin–Worley) texture, 0..1.
    pub shape_amount: f32,
    /// Influence of the shape-detail (Worley) texture, 0..1.
    pub shape_detail_amount: f32,
    /// Exponent on the weather signal: > 1 sharpens, < 1 flattens.
    pub weather_exponent: f32,
    /// Vertical bias of the rounded shape: 1 symmetric, towards 0 bottom-heavy.
    pub shape_altering_bias: f32,
    /// Softness of the coverage threshold: 1 ignores the weather, towards 0 a sharp step.
    pub coverage_filter_width: f32,
    pub density_profile: DensityProfileParams,
    /// Whether the layer casts shadows into the beer shadow map.
    pub shadow: bool,
}

impl Default for CloudLayer {
    fn default() -> Self {
        Self {
            channel: Channel::R,
            altitude: 0.0,
            height: 0.0,
            density_scale: 0.2,
            shape_amount: 1.0,
            shape_detail_amount: 1.0,
            weather_exponent: 1.0,
            shape_altering_bias: 0.35,
            coverage_filter_width: 0.6,
            density_profile: DensityProfileParams::default(),
            shadow: false,
        }
    }
}

/// Largest magnitude a density profile may reach in its layer: ample for any density (it is
/// bounded by `MAX_DENSITY`, 1e6 per metre, after scaling), and 340 times below f32's 3.4e38, so `a·e^(b·η)` is finite and
/// the shader never multiplies an infinite profile by a zero coverage (a NaN).
pub const MAX_PROFILE_VALUE: f64 = 1e36;

/// Largest |b| accepted in a density profile: e^(b·η) stays finite in f32 up to b ≈ 88.7.
pub const MAX_PROFILE_EXPONENT: f32 = 80.0;

fn check(ok: bool, field: &str, reason: String) -> Result<(), (String, String)> {
    if ok {
        Ok(())
    } else {
        Err((field.to_string(), reason))
    }
}

fn finite(v: f32, field: &str) -> Result<(), (String, String)> {
    check(
        v.is_finite(),
        field,
        format!("must be a finite number, got {v}"),
    )
}

impl CloudLayer {
    /// Checks every field; returns the field name (relative to the layer) and the reason.
    pub fn validate(&self) -> Result<(), (String, String)> {
        for (name, v) in [
            ("altitude", self.altitude),
            ("height", self.height),
            ("density_scale", self.density_scale),
            ("shape_amount", self.shape_amount),
            ("shape_detail_amount", self.shape_detail_amount),
            ("weather_exponent", self.weather_exponent),
            ("shape_altering_bias", self.shape_altering_bias),
            ("coverage_filter_width", self.coverage_filter_width),
            ("density_profile.a", self.density_profile.a),
            ("density_profile.b", self.density_profile.b),
            ("density_profile.c", self.density_profile.c),
            ("density_profile.d", self.density_profile.d),
        ] {
            finite(v, name)?;
        }
        check(
            self.altitude >= 0.0,
            "altitude",
            format!("must be ≥ 0 m, got {}", self.altitude),
        )?;
        check(
            self.altitude <= 100_000.0,
            "altitude",
            format!("must be ≤ 100 km, got {} m", self.altitude),
        )?;
        check(
            self.height >= 0.0,
            "height",
            format!("must be ≥ 0 m (0 disables the layer), got {}", self.height),
        )?;
        check(
            self.height <= 30_000.0,
            "height",
            format!("must be ≤ 30 km, got {} m", self.height),
        )?;
        check(
            self.density_scale >= 0.0,
            "density_scale",
            format!("must be ≥ 0, got {}", self.density_scale),
        )?;
        for (name, v) in [
            ("shape_amount", self.shape_amount),
            ("shape_detail_amount", self.shape_detail_amount),
        ] {
            check(
                (0.0..=1.0).contains(&v),
                name,
                format!("must be in [0, 1], got {v}"),
            )?;
        }
        check(
            self.weather_exponent > 0.0,
            "weather_exponent",
            format!("must be > 0, got {}", self.weather_exponent),
        )?;
        check(
            self.shape_altering_bias > 0.0,
            "shape_altering_bias",
            format!("must be > 0, got {}", self.shape_altering_bias),
        )?;
        check(
            (1e-3..=1.0).contains(&self.coverage_filter_width),
            "coverage_filter_width",
            format!(
                "must be in [0.001, 1] (it divides the coverage remap; 0 would divide by zero), got {}",
                self.coverage_filter_width
            ),
        )?;
        check(
            self.density_profile.b.abs() <= MAX_PROFILE_EXPONENT,
            "density_profile.b",
            format!(
                "|b| must be ≤ {MAX_PROFILE_EXPONENT} so e^(b·η) stays finite in f32, got {}",
                self.density_profile.b
            ),
        )?;
        // The profile's largest magnitude over the layer (η in 0..1) bounds every term the
        // shader computes; past f32's range it would be infinite, and 0·∞ a NaN.
        let p = self.density_profile;
        let terms = [
            (
                "density_profile.a",
                f64::from(p.a).abs() * f64::from(p.b).max(0.0).exp(),
                "lower |a| or b",
            ),
            ("density_profile.c", f64::from(p.c).abs(), "lower |c|"),
            ("density_profile.d", f64::from(p.d).abs(), "lower |d|"),
        ];
        let peak: f64 = terms.iter().map(|t| t.1).sum();
        // The field to blame is the term that carries the overflow, not always `a`.
        let (field, _, fix) = terms
            .into_iter()
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or(("density_profile.a", 0.0, "lower |a| or b"));
        check(
            peak <= MAX_PROFILE_VALUE,
            field,
            format!(
                "a·e^(b·η) + c·η + d reaches {peak:.3e} in the layer (a = {}, b = {}, c = {}, \
                 d = {}), beyond {MAX_PROFILE_VALUE:e}, where f32 arithmetic overflows; {fix}",
                format_value(f64::from(p.a)),
                format_value(f64::from(p.b)),
                format_value(f64::from(p.c)),
                format_value(f64::from(p.d))
            ),
        )?;
        Ok(())
    }

    /// Whether the layer contributes anything at all.
    pub fn is_enabled(&self) -> bool {
        self.height > 0.0 && self.density_scale > 0.0
    }
}
