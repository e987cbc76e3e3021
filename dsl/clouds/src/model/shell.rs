//! Ray–shell intersection at planet scale, accurate in f32.
//!
//! The textbook quadratic forms `c = |o|² − r²` from two squares of ~4e13 m², whose f32 rounding
//! alone is ±4e6 m², and misplaces the shell by metres at the horizon. Here the camera is the
//! origin, the CPU supplies its altitude (small, so exact enough in f32), and both `c` and the
//! discriminant are formed as products of small differences (Haines et al., "Precision
//! Improvements for Ray/Sphere Intersection", Ray Tracing Gems ch. 7; altitude form):
//!
//! `c = (h_c − h_s)(2R + h_c + h_s)`, `Δ = (h_s − h_p)(2R + h_s + h_p)`,
//! with the closest-approach altitude `h_p = h_c·s − R·μ²/(1 + s)`, `s = √(1 − μ²)`.
//! The roots use `q = −b − sign(b)·√Δ`, `t = q` and `c / q`, so neither cancels.

use nimbus_dsl::prelude::*;

/// Mean Earth radius used for the cloud shells (m).
pub const EARTH_RADIUS: f32 = 6_360_000.0;

/// Distances along a ray to the sphere of altitude `shell_altitude`, from a camera at
/// `camera_altitude` whose ray makes cosine `mu` with the local up. Returns `(near, far)`,
/// sorted, possibly negative (behind the camera); `(-1, -1)` when the ray misses.
#[shader_fn]
pub fn ray_shell(camera_altitude: f32, mu: f32, shell_altitude: f32, radius: f32) -> Vec2 {
    let hc = camera_altitude;
    let hs = shell_altitude;
    let mu = mu.clamp(-1.0, 1.0);
    let s = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
    let hp = hc * s - radius * mu * mu / (1.0 + s);
    let disc = (hs - hp) * (2.0 * radius + hs + hp);
    let b = (radius + hc) * mu;
    let c = (hc - hs) * (2.0 * radius + hc + hs);
    if disc < 0.0 {
        return vec2(-1.0, -1.0);
    }
    let root = disc.sqrt();
    let q = -b - select(root, -root, b < 0.0);
    // q = 0 only when b = 0 and Δ = 0: a ray grazing the sphere at the camera itself.
    let q_safe = select(q, -1e-30, q == 0.0);
    let t0 = c / q_safe;
    let t1 = q;
    vec2(t0.min(t1), t0.max(t1))
}

/// Distance along a ray to the ground, or −1 when the ray never meets it. A camera standing on
/// the ground (altitude 0) and looking below the horizon meets it at distance 0: the shell's
/// near root is then exactly 0, which a "root > 0" test would miss, sending the ray under the
/// planet to clouds on the far side.
#[shader_fn]
pub fn ground_hit(camera_altitude: f32, mu: f32, radius: f32) -> f32 {
    let ground = ray_shell(camera_altitude, mu, 0.0, radius);
    select(-1.0, ground.x.max(0.0), ground.x >= 0.0 && mu < 0.0)
}
