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

use glam::Vec4;

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

/// For four shells at once (altitudes `heights`), lane by lane: the nearer of [`ray_shell`]'s
/// two roots that lies beyond `t`, or 1e30 where neither does or the ray misses the shell. The
/// same arithmetic as `ray_shell` per lane (so the same roots, to the bit), without its early
/// return: the march asks this of every layer bottom and top where it enters a layer or jumps a
/// gap, and as a loop over the lanes, each a call with a branch, it was a vector indexed by a
/// counter (slow in SwiftShader); unrolled, eight such calls made SwiftShader's compile of the
/// cloud pass run past two minutes.
#[shader_fn]
pub fn shells_after(camera_altitude: f32, mu: f32, heights: Vec4, radius: f32, t: f32) -> Vec4 {
    let hc = camera_altitude;
    let mu = mu.clamp(-1.0, 1.0);
    let s = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
    let hp = hc * s - radius * mu * mu / (1.0 + s);
    let b = (radius + hc) * mu;
    let disc =
        (heights - Vec4::splat(hp)) * (Vec4::splat(2.0 * radius) + heights + Vec4::splat(hp));
    let c = (Vec4::splat(hc) - heights) * (Vec4::splat(2.0 * radius + hc) + heights);
    let root = disc.max(Vec4::ZERO).sqrt();
    let q = Vec4::splat(-b) - root * select(1.0, -1.0, b < 0.0);
    vec4(
        root_after(c.x, q.x, disc.x, t),
        root_after(c.y, q.y, disc.y, t),
        root_after(c.z, q.z, disc.z, t),
        root_after(c.w, q.w, disc.w, t),
    )
}

/// One lane of [`shells_after`]: the roots `c / q` and `q`, the nearer beyond `t` (1e30: none,
/// or `disc` < 0, a miss).
#[shader_fn]
pub fn root_after(c: f32, q: f32, disc: f32, t: f32) -> f32 {
    // q = 0 only when b = 0 and Δ = 0: a ray grazing the sphere at the camera itself.
    let t0 = c / select(q, -1e-30, q == 0.0);
    let near = t0.min(q);
    let far = t0.max(q);
    let first = select(select(1e30, far, far > t), near, near > t);
    select(first, 1e30, disc < 0.0)
}
