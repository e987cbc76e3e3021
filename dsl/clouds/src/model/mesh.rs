//! The cluster table of the `mesh` path ([`crate::Path::Mesh`]): the clouds around the camera as
//! a few thousand instanced clusters of soft puffs, fitted to the genus' own density by a pass of
//! their own, and drawn by the cloud pass from the table alone.
//!
//! The seeds' mesh clouds instance one hand-made cluster of spheres, 20–40 times, wherever an
//! artist puts them: a picture that cannot be the genus' weather. Here each cluster is a cell of
//! the sky around the camera, and each of its [`MESH_SUB`] × [`MESH_SUB`] × [`MESH_LAYERS`]
//! puffs is fitted to what its part of the volume holds: a soft puff (the kernel `(1 − r²)²`
//! inside an ellipsoid) with the same extinction integrated over its volume (its "mass"), the
//! same mean position and the same spread along each axis as the density the genus'
//! `#[shader_fn]`s give there ([`puff_fit`], from [`MESH_FIT`]² columns of [`MESH_FIT_STEPS`]
//! samples). A small cumulus in a puff's cell becomes a small dense puff where the cumulus is;
//! an evenly full cell's puff is widened to 1.5 of its spacing, where the kernels tile a deck
//! evenly within 2.3 %.
//!
//! The cells are polar around the camera's vertical, per altitude band (the 2D map's two
//! halves of the slab): [`MESH_SECTORS`] sectors of azimuth, and [`MESH_RINGS`] rings of
//! distance on the slice stack's scale ([`slice_offset`]: even near the camera, growing in
//! proportion to distance beyond [`super::slices::SLICE_NEAR`]), so a cell subtends about the
//! same angle wherever it lies (far out a ring is about three sectors deep at `low`'s 100 km
//! reach: 48 rings, as deep as wide, cost 30 % more a frame for no gain in the agreement
//! test); the innermost ring is one cluster. A puff's spreads are along its cell's radial and tangential directions and up. (A
//! grid of x and z rows was tried first: its cells along the view's axis are long and thin,
//! and their puffs drew streaks converging on the horizon.)
//!
//! The kernel has compact support and a closed form along any ray (its integral along a chord
//! is a polynomial, [`chord_integral`]), so the cloud pass draws the instances analytically,
//! per pixel, in place of rasterising spheres (which would need a geometry pass in the runtime
//! and in every engine package). A ray from the camera keeps its azimuth: in each band it
//! visits, ring by ring outwards over the rings its way through the band passes, the clusters
//! of its sector and of the neighbour on the side it passes nearer (the fit keeps every puff
//! within half a cell of its own, [`MESH_MARGIN`]); a cluster whose flag says its puffs lie
//! above, below or beside the ray is skipped, and a puff whose bounding sphere the ray misses
//! costs one read. Each puff seen is lit by the march's own source term ([`sample_source`]:
//! phase, octaves, sky, ground, powder) at the point its light comes from, with the optical
//! depth to the sun through its own kernel in closed form ([`puff_depth`]) and beyond it as the
//! bake marched it through the volume; the puffs are composited in distance bins
//! ([`distance_bin`]), and the visit ends once what was seen lets less through than the march's
//! least transmittance. No noise, no march, no secondary ray in the cloud pass.
//!
//! What it drops: every structure finer than a puff (about 3° across seen from the camera, a
//! few hundred metres overhead), two clouds in one puff's cell merge into one puff, and the
//! light inside a puff varies only through its own kernel; its use is a sky seen from afar, its
//! look the soft blobs of mesh clouds.
//!
//! Layout: a row per band and ring (lower band first, the innermost ring first), a cluster of
//! [`CLUSTER_TEXELS`] per sector along it. A cluster's first texel is its flag: how far its
//! puffs reach, down and up in local height (km) and round in azimuth (sectors from its
//! sector's middle; an empty cluster's reach nothing); then three texels per puff: (centre in km,
//! its kernel's widest reach in km, 0 when empty), (spread in km, radial, vertical and
//! tangential, peak extinction per km), (optical depth to the sun from where the sun's line
//! through its centre leaves its kernel, how evenly its cell is full, optical depths to the
//! ground and up from its kernel's lowest and highest points). Positions are in the camera's
//! local frame (`y` up, the planet curving away below it); kilometres keep them within the
//! bake's half floats.

use glam::{Vec2, Vec3, Vec4, ivec2};

use nimbus_dsl::prelude::*;

use super::bindings::{BAKE, CLOUDS};
use super::blob2d::{BLOB_BANDS, band_bounds, band_range, sun_depth_from};
use super::choices::{DIFFUSION, GROUND_BOUNCE, gate};
use super::march::{
    MarchResult, OctavePhases, altitude_along, octave_phases, sample_source, total_density,
};
use super::ray_light::{RayLight, early_termination, gathered_result};
use super::shell::ground_hit;
use super::slices::{curved_height, slice_coordinate, slice_offset, vertical_depth};
use crate::key::CloudKey;

/// Rings of distance around the camera's vertical, per band.
pub const MESH_RINGS: u32 = 32;
/// Sectors of azimuth, per ring (the innermost ring is one cluster).
pub const MESH_SECTORS: u32 = 64;
/// Puffs across a cluster, radially and tangentially.
pub const MESH_SUB: u32 = 2;
/// Puffs up a cluster: layers within its band, each lit on its own (a cumulus' sunlit top and
/// shaded base are not one puff).
pub const MESH_LAYERS: u32 = 2;
/// Sample columns across a puff's cell, radially and tangentially, for its fit.
pub const MESH_FIT: u32 = 3;
/// Samples up each of a fit's columns (through the band).
pub const MESH_FIT_STEPS: u32 = 8;
/// How far (in cells) a cluster's puffs may reach beyond its cell: the fit keeps each puff's
/// drawn extent within it, so a ray sees every puff it passes in the clusters of its own cell
/// and of the neighbours it passes within this of.
pub const MESH_MARGIN: f32 = 0.5;

/// Puffs in a cluster.
pub const MESH_PUFFS: u32 = MESH_SUB * MESH_SUB * MESH_LAYERS;
/// Texels a puff takes in its cluster.
const PUFF_TEXELS: u32 = 3;
/// Texels a cluster takes in its row: the flag, then each puff's.
pub const CLUSTER_TEXELS: u32 = 1 + PUFF_TEXELS * MESH_PUFFS;
/// The table's width: every sector's cluster side by side.
const WIDTH: u32 = MESH_SECTORS * CLUSTER_TEXELS;
/// The table's height: a row per band and ring.
const HEIGHT: u32 = BLOB_BANDS * MESH_RINGS;

/// A puff's reach in spreads: its kernel, `(1 − r²)²` inside the ellipsoid of these many spreads
/// along each axis and nothing beyond, has a standard deviation of a third of its reach along
/// each axis, so the spreads the fit measures are the kernel's.
const PUFF_REACH: f32 = 3.0;
/// The kernel's integral over its unit ball (32π/105), times the reach cubed: a puff's mass
/// per unit peak extinction and cubic spread.
const KERNEL_VOLUME: f32 = 25.850_6;
/// The kernel's integral along a line through its centre (16/15 of the reach, in reaches).
const KERNEL_CHORD: f32 = 16.0 / 15.0;
/// The spread of the kernel's integral along a line, in half-chords: the standard deviation of
/// `(1 − u²)²` on [−1, 1] (1/√7).
const CHORD_SPREAD: f32 = 0.377_964_5;
/// A full turn (rad).
const TAU: f32 = core::f32::consts::TAU;
/// The spread of a box evenly full: its width over √12.
const EVEN_SPREAD: f32 = 0.288_675_1;
/// How much an evenly full cell's puff is widened (at the spread of an even box; less for a
/// compact cloud): kernels reaching 1.5 of their spacing (a spread of half of it, 1.73 times an
/// even box's) sum to a density even within 2.3 %, where at an even box's spread they would
/// leave stripes between them.
const TILING: f32 = 0.73;

/// The table's width and height in texels.
pub fn mesh_size() -> (u32, u32) {
    (WIDTH, HEIGHT)
}

/// What a puff's fit finds in its cell: the mass, mean and spread of the density there.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct PuffFit {
    /// Extinction integrated over the cell's volume (m²): what the puff holds.
    pub mass: f32,
    /// Mean position of the extinction: camera-relative x, altitude, camera-relative z (m).
    pub centre: Vec3,
    /// Standard deviation of the extinction's position (m) radially, in altitude and
    /// tangentially (along its cell's frame, [`cell_frame`]).
    pub spread: Vec3,
    /// Width of the fit's sample columns (m): the scale below which the puff knows nothing.
    pub footprint: f32,
    /// How evenly the cell is full across (1: a deck running on into its neighbours, 0: a
    /// compact cloud within it): the product of its radial and tangential fill.
    pub filled: f32,
}

/// Distance (m) from the camera's vertical of ring coordinate `k` (ring `k` spans `k` to
/// `k + 1`).
#[shader_fn]
pub fn ring_radius(k: f32) -> f32 {
    slice_offset(k / MESH_RINGS as f32)
}

/// Ring coordinate of the distance `r` (m) from the camera's vertical: the inverse of
/// [`ring_radius`].
#[shader_fn]
pub fn ring_coordinate(r: f32) -> f32 {
    slice_coordinate(r) * MESH_RINGS as f32
}

/// The radial direction (cos, sin of its azimuth in the x–z plane) of the cluster of `ring` and
/// `sector`: its sector's middle; the innermost ring, one cluster round the camera, keeps x and
/// z.
#[shader_fn]
pub fn cell_frame(ring: f32, sector: f32) -> Vec2 {
    let angle = (sector + 0.5) * (TAU / MESH_SECTORS as f32);
    select(vec2(angle.cos(), angle.sin()), vec2(1.0, 0.0), ring < 0.5)
}

/// The components of `v` along the radial direction `frame`, up, and tangentially.
#[shader_fn]
pub fn in_frame(v: Vec3, frame: Vec2) -> Vec3 {
    vec3(
        v.x * frame.x + v.z * frame.y,
        v.y,
        v.z * frame.x - v.x * frame.y,
    )
}

/// The fit of the puff `sub` (radial, tangential index within its cluster) of the cluster of
/// `ring` and `sector`, between altitudes `bounds` (its layer's): the mass, mean and spread of the
/// extinction that [`MESH_FIT`]² columns of [`MESH_FIT_STEPS`] samples find in its cell. Each
/// sample stands for its box (its density the mean over the box's width, its box's own spread
/// added), so a cell evenly full has the spread of the cell, and a small cloud in it the
/// cloud's. The spreads are then widened where the cell is full (puffs tile a deck evenly) and
/// kept within the cell grown by [`MESH_MARGIN`].
#[shader_fn]
pub fn puff_fit(ring: f32, sector: f32, sub: Vec2, bounds: Vec2, #[spec] key: CloudKey) -> PuffFit {
    let l = CLOUDS.get().light;
    let sigma_ratio = l.scattering_coefficient + l.absorption_coefficient;
    let fit = MESH_FIT as f32;
    let parts = MESH_SUB as f32;
    let inner = ring < 0.5;
    // The puff's cell: ring coordinates and azimuths (the innermost ring spans every azimuth).
    let sector_angle = select(TAU / MESH_SECTORS as f32, TAU, inner);
    let dk = 1.0 / (parts * fit);
    let dtheta = sector_angle / (parts * fit);
    let k0 = ring + sub.x / parts;
    let theta0 = select(sector * sector_angle, 0.0, inner) + sub.y * sector_angle / parts;
    let frame = cell_frame(ring, sector);
    // Positions relative to the cell's middle, along its frame, keep the variance's digits.
    let r_mid = ring_radius(k0 + 0.5 / parts);
    let theta_mid = theta0 + 0.5 * sector_angle / parts;
    let mid = select(
        vec2(theta_mid.cos(), theta_mid.sin()) * r_mid,
        Vec2::ZERO,
        inner,
    );
    let origin = vec3(mid.x, 0.5 * (bounds.x + bounds.y), mid.y);
    let dh = (bounds.y - bounds.x).max(1e-3) / MESH_FIT_STEPS as f32;
    let mut mass = 0.0f32;
    let mut first = Vec3::ZERO;
    let mut second = Vec3::ZERO;
    let mut widest = 0.0f32;
    for s in 0u32..(MESH_FIT * MESH_FIT) {
        let i = ((s as f32 + 0.5) / fit).floor();
        let j = s as f32 - i * fit;
        let r_lo = ring_radius(k0 + i * dk);
        let r_hi = ring_radius(k0 + (i + 1.0) * dk);
        let r = 0.5 * (r_lo + r_hi);
        let theta = theta0 + (j + 0.5) * dtheta;
        let point = vec2(theta.cos(), theta.sin()) * r;
        let size = vec2(r_hi - r_lo, r * dtheta);
        let footprint = size.x.max(size.y);
        widest = widest.max(footprint);
        let own = in_frame(
            vec3(size.x * size.x, dh * dh, size.y * size.y) * (1.0 / 12.0),
            vec2(1.0, 0.0),
        );
        for h_step in 0u32..MESH_FIT_STEPS {
            let h = bounds.x + (h_step as f32 + 0.5) * dh;
            let p = vec3(point.x, curved_height(h, r), point.y);
            let w = total_density(p, h, footprint, key) * sigma_ratio * (size.x * size.y * dh);
            let q = in_frame(vec3(point.x, h, point.y) - origin, frame);
            mass += w;
            first += q * w;
            second += (q * q + own) * w;
        }
    }
    let mean = first / mass.max(1e-20);
    let variance = second / mass.max(1e-20) - mean * mean;
    // The puff's whole cell: radially, in altitude, tangentially.
    let full = vec3(
        ring_radius(k0 + 1.0 / parts) - ring_radius(k0),
        bounds.y - bounds.x,
        select(r_mid * sector_angle / parts, ring_radius(1.0), inner),
    );
    let measured = vec3(
        variance.x.max(1.0).sqrt(),
        variance.y.max(1.0).sqrt(),
        variance.z.max(1.0).sqrt(),
    );
    // Puffs tile a deck: an evenly full cell's puff widened to meet its neighbours evenly, a
    // compact cloud's hardly.
    let fill = (measured / (full * EVEN_SPREAD).max(Vec3::splat(1.0))).min(Vec3::ONE);
    let widened = measured * (Vec3::ONE + fill * fill * TILING);
    let offset = frame.x * vec2(mean.x, mean.z) + frame.y * vec2(-mean.z, mean.x);
    let centre = origin + vec3(offset.x, mean.y, offset.y);
    // Within the cluster's cell grown by the margin: radially between the grown ring's edges,
    // tangentially within the grown sector's (the innermost ring: within its grown disc).
    let r_centre = vec2(centre.x, centre.z).length();
    let outer = ring_radius(ring + 1.0 + MESH_MARGIN);
    let radial_room = select(
        (r_centre - ring_radius(ring - MESH_MARGIN)).min(outer - r_centre),
        outer - r_centre,
        inner,
    );
    let across = in_frame(centre, frame).z;
    let tangential_room = select(
        r_centre * (0.5 + MESH_MARGIN) * sector_angle - across.abs(),
        outer - r_centre,
        inner,
    );
    let room = vec2(radial_room, tangential_room).max(Vec2::splat(PUFF_REACH)) * (1.0 / PUFF_REACH);
    // An empty cell keeps a puff the cell's size (it holds nothing; the size keeps the
    // divisions finite).
    let spread = select(
        full * EVEN_SPREAD,
        vec3(widened.x.min(room.x), widened.y, widened.z.min(room.y)),
        mass > 0.0,
    );
    PuffFit {
        mass,
        centre,
        spread,
        footprint: widest,
        filled: fill.x * fill.z,
    }
}

/// The camera-relative local point (`y` up, the planet curving away) of a fit's centre
/// (x, altitude, z).
#[shader_fn]
pub fn local_point(centre: Vec3) -> Vec3 {
    vec3(
        centre.x,
        curved_height(centre.y, vec2(centre.x, centre.z).length()),
        centre.z,
    )
}

/// One texel of the table: a cluster's flag, or one of a puff's three texels.
#[shader_fn]
#[expect(
    clippy::if_same_then_else,
    reason = "the march down runs once for either of two key gates: one `if` per gate is how a \
              shader function branches on the key"
)]
pub fn mesh_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    let texel = vec2(frag_coord.x, frag_coord.y).floor();
    let rings = MESH_RINGS as f32;
    let band = ((texel.y + 0.5) / rings).floor();
    let ring = texel.y - band * rings;
    let sector = ((texel.x + 0.5) / CLUSTER_TEXELS as f32).floor();
    let within = texel.x - sector * CLUSTER_TEXELS as f32;
    if ring < 0.5 && sector > 0.5 {
        // The innermost ring is one cluster, its first sector's.
        return Vec4::ZERO;
    }
    let bounds = band_bounds(band, key);
    let parts = MESH_SUB as f32;
    let slot = ((within - 0.5) / PUFF_TEXELS as f32).floor();
    let part = within - 1.0 - slot * PUFF_TEXELS as f32;
    let is_flag = within < 0.5;
    // The flag fits every puff of the cluster; a puff's texels its own alone. One call of the
    // fit, in a loop: a browser's compiler took minutes over a march written out twice.
    // The flag: what the cluster's puffs reach, up (local y) and round (sectors from the
    // sector's middle), so a ray that passes above, below or beside them skips the cluster.
    let mut y_low = 1e4f32;
    let mut y_high = -1e4f32;
    let mut side_low = 1e4f32;
    let mut side_high = -1e4f32;
    let frame = cell_frame(ring, sector);
    let sector_angle = TAU / MESH_SECTORS as f32;
    let mut mass = 0.0f32;
    let mut centre = Vec3::ZERO;
    let mut spread = Vec3::ONE;
    let mut footprint = 1.0f32;
    let mut filled = 0.0f32;
    for p in 0u32..MESH_PUFFS {
        if is_flag || (p as f32 - slot).abs() < 0.5 {
            let layer = ((p as f32 + 0.5) / (parts * parts)).floor();
            let across = p as f32 - layer * parts * parts;
            let radial = ((across + 0.5) / parts).floor();
            let sub = vec2(radial, across - radial * parts);
            let height = (bounds.y - bounds.x) / MESH_LAYERS as f32;
            let lower = bounds.x + layer * height;
            let fit = puff_fit(ring, sector, sub, vec2(lower, lower + height), key);
            mass = fit.mass;
            centre = fit.centre;
            spread = fit.spread;
            footprint = fit.footprint;
            filled = fit.filled;
            if puff_peak(mass, spread) > 0.0 {
                let reach = spread * PUFF_REACH;
                let y = local_point(centre).y;
                y_low = y_low.min(y - reach.y);
                y_high = y_high.max(y + reach.y);
                let along = in_frame(centre, frame);
                let nearest = along.x - reach.x;
                // Its azimuth from the sector's middle, and its tangential reach as an angle
                // from its nearest point (every azimuth where it reaches round the vertical).
                let angle = along.z.atan2(along.x) / sector_angle;
                let half = select(
                    1e3,
                    reach.z / nearest.max(1e-3) / sector_angle,
                    nearest > reach.z,
                );
                side_low = side_low.min(angle - half);
                side_high = side_high.max(angle + half);
            }
        }
    }
    if is_flag {
        // The innermost ring's one cluster lies round the vertical: every azimuth.
        let all = ring < 0.5 && y_high > y_low;
        return vec4(
            y_low * 1e-3,
            y_high * 1e-3,
            select(side_low, -1e3, all),
            select(side_high, 1e3, all),
        );
    }
    let local = local_point(centre);
    let peak = puff_peak(mass, spread);
    if part < 0.5 {
        // Its centre, and how far its kernel reaches at most (nothing: an empty puff), so a
        // ray that passes wide of it reads nothing more.
        let widest = spread.x.max(spread.y).max(spread.z) * PUFF_REACH;
        return (local * 1e-3).extend(select(0.0, widest * 1e-3, peak > 0.0));
    }
    if part < 1.5 {
        return (spread * 1e-3).extend(peak * 1e3);
    }
    // Beyond the puff: the optical depth to the sun from where the sun's line through its
    // centre leaves its kernel, as the volume takes it from there (the cloud pass adds the
    // puff's own, from the point it lights to that edge, in closed form).
    let sun = CLOUDS.get().light.sun_direction;
    let frame = cell_frame(ring, sector);
    let reach = spread * PUFF_REACH;
    let exit = centre + sun * (1.0 / (in_frame(sun, frame) / reach).length());
    let tau_sun = sun_depth_from(
        exit.x,
        exit.z,
        vec2(exit.x, exit.z).length(),
        exit.y,
        footprint,
        key,
    );
    // Below and above the puff: from its kernel's lowest and highest points, down and up.
    let bottom = centre - vec3(0.0, reach.y, 0.0);
    let mut tau_ground = 0.0f32;
    if gate(key, GROUND_BOUNCE) {
        tau_ground = vertical_depth(local_point(bottom), bottom.y, -1.0, footprint, key);
    } else if gate(key, DIFFUSION) {
        tau_ground = vertical_depth(local_point(bottom), bottom.y, -1.0, footprint, key);
    }
    let mut tau_up = 0.0f32;
    if gate(key, DIFFUSION) {
        let top = centre + vec3(0.0, reach.y, 0.0);
        tau_up = vertical_depth(local_point(top), top.y, 1.0, footprint, key);
    }
    vec4(tau_sun, filled, tau_ground, tau_up)
}

/// Peak extinction (per m) of a puff of `mass` and `spread`; none where it would hold
/// less than a thousandth of optical depth through its centre (an empty cell).
#[shader_fn]
pub fn puff_peak(mass: f32, spread: Vec3) -> f32 {
    let peak = mass / (KERNEL_VOLUME * spread.x * spread.y * spread.z);
    let widest = spread.x.max(spread.y).max(spread.z);
    select(0.0, peak, peak * KERNEL_CHORD * PUFF_REACH * widest > 1e-3)
}

/// The table's texel `column` of the cluster of `sector` in `row` (band and ring).
#[shader_fn]
pub fn mesh_texel(sector: f32, column: f32, row: f32) -> Vec4 {
    // One texel as it is: a filtered read would blend a puff's neighbours in at no use, and
    // costs four.
    let x = sector * CLUSTER_TEXELS as f32 + column;
    BAKE.get().load(ivec2(x as i32, row as i32), 0)
}

/// The normal distribution's integral up to `s` spreads (a logistic: within 1 % of it).
#[shader_fn]
pub fn below_fraction(s: f32) -> f32 {
    1.0 / (1.0 + (-1.702 * s).exp())
}

/// The kernel's integral along a chord of half-length `half` (in reaches, `half² = 1 − d²` for a
/// line `d` from the centre), from its middle to `s` (within ±`half`): the integral of
/// `(half² − s²)²`.
#[shader_fn]
pub fn chord_integral(s: f32, half: f32) -> f32 {
    let a2 = half * half;
    let s2 = s * s;
    s * (a2 * a2 - (2.0 / 3.0) * a2 * s2 + 0.2 * s2 * s2)
}

/// Distance along a view ray of up-cosine `mu` at which it ends: the ground, or the march's
/// reach.
#[shader_fn]
pub fn ray_end(mu: f32) -> f32 {
    let u = CLOUDS.get();
    let ground = ground_hit(u.camera_altitude, mu, u.march.radius);
    select(u.march.max_ray_distance, ground, ground >= 0.0)
}

/// The kernel's optical depth per unit peak extinction from the point `q` (in reaches from
/// its centre) to its edge along the direction whose step is `e` reaches per metre: the
/// chord's integral from the point onwards, in metres.
#[shader_fn]
pub fn kernel_depth(q: Vec3, e: Vec3) -> f32 {
    let speed = e.length();
    let unit = e / speed;
    let along = q.dot(unit);
    let half = (1.0 - (q.dot(q) - along * along)).max(0.0).sqrt();
    (chord_integral(half, half) - chord_integral(along.clamp(-half, half), half)) / speed
}

/// A puff's own optical depth per unit peak extinction from the point `q` (in reaches) along
/// the direction of step `e` (reaches per metre) to its edge, for a puff `filled` (0–1) across.
/// A compact cloud's is its kernel's ([`kernel_depth`]), thinning to nothing at its silhouette;
/// a deck's puff runs on into its neighbours, which stand where its kernel thins: its depth is
/// the kernel's along its axis at the point's depth, the same across the puff, as through a
/// slab.
#[shader_fn]
pub fn puff_depth(q: Vec3, e: Vec3, filled: f32) -> f32 {
    let unit = e / e.length();
    mix(
        kernel_depth(q, e),
        kernel_depth(unit * q.dot(unit), e),
        filled.saturate(),
    )
}

/// The light and optical depth of one puff along a view ray, and where it comes from.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct PuffLight {
    /// Light the puff sends along the ray per unit of the light behind it, unattenuated by
    /// what lies in front.
    pub radiance: Vec3,
    /// The puff's optical depth along the ray (0: the ray misses it).
    pub tau: f32,
    /// Distance along the ray its light comes from (m).
    pub distance: f32,
}

/// Puff `p` of the cluster of `sector` in table row `row` (its radial direction `frame`) seen
/// along `direction` (up-cosine `mu`, ending at `end`): its optical depth in closed form, lit
/// at the point its light comes from by the march's source term.
#[shader_fn]
#[expect(
    clippy::too_many_arguments,
    reason = "a shader function takes what a ray knows as plain arguments"
)]
pub fn puff_light(
    sector: f32,
    row: f32,
    frame: Vec2,
    p: f32,
    direction: Vec3,
    end: f32,
    cos_theta: f32,
    phases: OctavePhases,
    #[spec] key: CloudKey,
) -> PuffLight {
    let u = CLOUDS.get();
    let l = u.light;
    let mu = direction.y;
    let column = 1.0 + PUFF_TEXELS as f32 * p;
    let bound = mesh_texel(sector, column, row);
    let centre = bound.xyz() * 1e3;
    let widest = bound.w * 1e3;
    let closest = centre.dot(direction);
    let mut radiance = Vec3::ZERO;
    let mut tau = 0.0f32;
    let mut distance = 0.0f32;
    // The bounding sphere first: one read for a puff the ray passes wide of.
    let near = (centre - direction * closest).length() < widest
        && closest + widest > 0.0
        && closest - widest < end;
    if widest > 0.0 && near {
        let shape = mesh_texel(sector, column + 1.0, row);
        let sigma = shape.xyz() * 1e3;
        let peak = shape.w * 1e-3;
        // In the puff's own units (its frame, its reach along each axis) the ray is a line
        // through a round kernel; `s` along it runs in those units from the point nearest
        // the centre.
        let reach = sigma * PUFF_REACH;
        let e = in_frame(direction, frame) / reach;
        let speed = e.length();
        let c = in_frame(centre, frame) / reach;
        let t_star = c.dot(e) / (speed * speed);
        let miss_squared = (c.dot(c) - t_star * t_star * speed * speed).max(0.0);
        let half = (1.0 - miss_squared).max(0.0).sqrt();
        // The part of the chord between the camera and the ray's end.
        let s_near = (-t_star * speed).clamp(-half, half);
        let s_far = ((end - t_star) * speed).clamp(-half, half);
        let whole = peak * (chord_integral(s_far, half) - chord_integral(s_near, half)) / speed;
        if miss_squared < 1.0 && whole > 1e-4 {
            tau = whole;
            let lit = mesh_texel(sector, column + 2.0, row);
            // Half the light the puff sends along the ray comes from before the depth where
            // its optical depth is −ln((1 + e^−τ)/2): the puff is lit as at that point (the
            // chord's profile taken as a logistic of its spread to find it).
            let f = (-(0.5 + 0.5 * (-tau).exp()).ln() / tau).clamp(1e-4, 0.5);
            let spread_along = CHORD_SPREAD * half.max(1e-3);
            let before = below_fraction(s_near / spread_along);
            let after = below_fraction(s_far / spread_along);
            let g = (before + f * (after - before)).clamp(1e-4, 1.0 - 1e-4);
            let s_lit = (spread_along * (g / (1.0 - g)).ln() / 1.702).clamp(s_near, s_far);
            distance = (t_star + s_lit / speed).clamp(0.0, end);
            let point = direction * distance;
            let q = in_frame(point - centre, frame) / reach;
            // The source term's extinction (its powder term darkens thin cloud): the puff's
            // peak. The kernel's own density at the point would call the seam between two
            // puffs of a deck thin cloud, where their sum is as dense as their centres.
            let sigma_t = peak.max(1e-9);
            // To the sun, up and down: the puff's own kernel from the point to its edge, in
            // closed form, and what the bake found beyond that edge.
            let tau_sun =
                peak * puff_depth(q, in_frame(l.sun_direction, frame) / reach, lit.y) + lit.x;
            let tau_up = peak * puff_depth(q, vec3(0.0, 1.0 / reach.y, 0.0), lit.y) + lit.w;
            let tau_ground = peak * puff_depth(q, vec3(0.0, -1.0 / reach.y, 0.0), lit.y) + lit.z;
            let h = altitude_along(u.camera_altitude, mu, distance, u.march.radius);
            let sigma_ratio = l.scattering_coefficient + l.absorption_coefficient;
            let source = sample_source(
                sigma_t / sigma_ratio,
                h,
                tau_sun,
                tau_up,
                tau_ground,
                cos_theta,
                phases,
                mu,
                key,
            );
            // The march's step integral, for a step holding the puff's whole optical depth at
            // the point's light per unit extinction.
            radiance = source * ((1.0 - (-tau).exp()) / sigma_t);
        }
    }
    PuffLight {
        radiance,
        tau,
        distance,
    }
}

/// The sector (whole) of the azimuth of the horizontal direction (`x`, `z`), the neighbouring
/// sector on the side it lies nearer, and the azimuth in sectors (0 to [`MESH_SECTORS`]).
#[shader_fn]
pub fn sectors_of(x: f32, z: f32) -> Vec3 {
    let count = MESH_SECTORS as f32;
    let turns = z.atan2(x) / TAU;
    let position = (turns - turns.floor()) * count;
    let own = position.floor().min(count - 1.0);
    let beside = own + select(1.0, -1.0, position - own < 0.5);
    vec3(own, beside - (beside / count).floor() * count, position)
}

/// Whether the flag `flag` of the cluster of `sector` lets a ray through: one at azimuth
/// `position` (in sectors) whose local height runs over `heights` at the cluster's distance.
#[shader_fn]
pub fn flag_passes(flag: Vec4, sector: f32, position: f32, heights: Vec2) -> bool {
    let count = MESH_SECTORS as f32;
    let offset = position - sector - 0.5;
    let wrapped = offset - count * (offset / count + 0.5).floor();
    flag.y > flag.x
        && heights.y >= flag.x * 1e3
        && heights.x <= flag.y * 1e3
        && wrapped >= flag.z
        && wrapped <= flag.w
}

/// The clouds along `direction` drawn from the cluster table (the march's result, for
/// [`super::march::composite`]). In each band the ray's horizontal way keeps its azimuth: it
/// visits, ring by ring from the camera outwards (those its way through the band passes, and
/// half a ring either side), the clusters of its sector and of the neighbour on the side it
/// passes nearer. Each visited cluster's puffs are drawn in closed form, put in distance bins,
/// and the bins composited front to back.
#[shader_fn]
pub fn mesh_clouds(direction: Vec3, #[spec] key: CloudKey) -> MarchResult {
    let u = CLOUDS.get();
    let m = u.march;
    let mu = direction.y;
    let cos_theta = direction.dot(u.light.sun_direction);
    let phases = octave_phases(cos_theta, key);
    let end = ray_end(mu);
    let lower = band_range(mu, band_bounds(0.0, key));
    let upper = band_range(mu, band_bounds(1.0, key));
    let across = vec2(direction.x, direction.z).length();
    let sectors = sectors_of(direction.x, direction.z);
    let rings = MESH_RINGS as f32;
    // Per distance bin (the nearer four, the farther four): the puffs' optical depths, their
    // opacities, their light (red, green, blue) and their opacity-weighted distances.
    let mut tau_near = Vec4::ZERO;
    let mut tau_far = Vec4::ZERO;
    let mut opacity_near = Vec4::ZERO;
    let mut opacity_far = Vec4::ZERO;
    let mut red_near = Vec4::ZERO;
    let mut red_far = Vec4::ZERO;
    let mut green_near = Vec4::ZERO;
    let mut green_far = Vec4::ZERO;
    let mut blue_near = Vec4::ZERO;
    let mut blue_far = Vec4::ZERO;
    let mut depth_near = Vec4::ZERO;
    let mut depth_far = Vec4::ZERO;
    let mut samples = 0.0f32;
    // Nearer band first, as the 2D map's samples: with the rings outwards, what is visited
    // first lies in front, and once the puffs visited hold enough optical depth that what is
    // left would pass less than the march's least transmittance, the rest is not visited (as
    // the march ends a ray; the bins order what was).
    let lower_near = select(1e30, lower.x, lower.y > lower.x);
    let upper_near = select(1e30, upper.x, upper.y > upper.x);
    let first_band = select(1.0, 0.0, lower_near <= upper_near);
    let enough = -m.min_transmittance.max(1e-6).ln();
    let mut seen = 0.0f32;
    for b in 0u32..BLOB_BANDS {
        let band = (first_band - b as f32).abs();
        let range = select(upper, lower, band < 0.5);
        if range.y > range.x && seen < enough {
            // The band's stretch of the ray, in ring coordinates, grown by the margin.
            let first = (ring_coordinate(across * range.x) - MESH_MARGIN)
                .floor()
                .max(0.0);
            let last = (ring_coordinate(across * range.y.min(end)) + MESH_MARGIN)
                .floor()
                .min(rings - 1.0);
            let row_base = band * rings;
            let reach = range.y.min(end);
            // Only the rings the band's stretch passes: a loop of the whole grid with a test in
            // it ran every ring's work masked off in a CPU rasteriser's SIMD lanes.
            for k in (first as u32)..((last + 1.0) as u32) {
                let ring = k as f32;
                if seen >= enough {
                    break;
                }
                {
                    for n in 0u32..2u32 {
                        // The innermost ring is one cluster (its first sector's).
                        let sector =
                            select(select(sectors.y, sectors.x, n == 0u32), 0.0, k == 0u32);
                        let row = row_base + ring;
                        // The ray's height over the ring, grown by the margin, within the band.
                        let t_in = (ring_radius(ring - MESH_MARGIN).max(0.0) / across)
                            .clamp(range.x, reach);
                        let t_out =
                            (ring_radius(ring + 1.0 + MESH_MARGIN) / across).clamp(range.x, reach);
                        let heights = vec2(
                            (direction.y * t_in).min(direction.y * t_out),
                            (direction.y * t_in).max(direction.y * t_out),
                        );
                        let visit = (k > 0u32 || n == 0u32)
                            && seen < enough
                            && flag_passes(
                                mesh_texel(sector, 0.0, row),
                                sector,
                                sectors.z,
                                heights,
                            );
                        if visit {
                            let frame = cell_frame(ring, sector);
                            for p in 0u32..MESH_PUFFS {
                                let puff = puff_light(
                                    sector, row, frame, p as f32, direction, end, cos_theta,
                                    phases, key,
                                );
                                if puff.tau > 0.0 {
                                    samples += 1.0;
                                    seen += puff.tau;
                                    let opacity = 1.0 - (-puff.tau).exp();
                                    let bin = distance_bin(puff.distance);
                                    let near = one_hot(bin);
                                    let far = one_hot(bin - 4.0);
                                    tau_near += near * puff.tau;
                                    tau_far += far * puff.tau;
                                    opacity_near += near * opacity;
                                    opacity_far += far * opacity;
                                    red_near += near * puff.radiance.x;
                                    red_far += far * puff.radiance.x;
                                    green_near += near * puff.radiance.y;
                                    green_far += far * puff.radiance.y;
                                    blue_near += near * puff.radiance.z;
                                    blue_far += far * puff.radiance.z;
                                    depth_near += near * (opacity * puff.distance);
                                    depth_far += far * (opacity * puff.distance);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    // The bins front to back. Within a bin the puffs are taken as mixed: their light per unit
    // opacity, times the opacity of their summed optical depth (two puffs behind one another
    // block no more than their sum lets through).
    let mut radiance = Vec3::ZERO;
    let mut transmittance = 1.0f32;
    let mut depth_sum = 0.0f32;
    let mut weight_sum = 0.0f32;
    for k in 0u32..DISTANCE_BINS {
        let kf = k as f32;
        let near = one_hot(kf);
        let far = one_hot(kf - 4.0);
        let tau = tau_near.dot(near) + tau_far.dot(far);
        let opacities = opacity_near.dot(near) + opacity_far.dot(far);
        let light = vec3(
            red_near.dot(near) + red_far.dot(far),
            green_near.dot(near) + green_far.dot(far),
            blue_near.dot(near) + blue_far.dot(far),
        );
        let depth = depth_near.dot(near) + depth_far.dot(far);
        let opacity = 1.0 - (-tau).exp();
        let share = opacity / opacities.max(1e-6);
        radiance += light * (share * transmittance);
        depth_sum += depth * (share * transmittance);
        weight_sum += opacity * transmittance;
        transmittance *= 1.0 - opacity;
    }
    // As the march ends a ray: the rest is more of the same cloud.
    let gathered = early_termination(RayLight {
        radiance,
        transmittance,
        depth_sum,
        weight_sum,
    });
    gathered_result(gathered, samples)
}

/// Distance bins of a ray's puffs: composited front to back between bins, mixed within one.
const DISTANCE_BINS: u32 = 8;
/// The far end of the nearest distance bin (m); each further bin ends twice as far, the last
/// holds everything beyond.
const NEAREST_BIN: f32 = 250.0;

/// The bin (0 to [`DISTANCE_BINS`] − 1, fractions between) of distance `t` along a ray: a bin
/// per doubling, so a puff twice as far as another is drawn behind it. A puff between two bins'
/// centres is shared between them ([`one_hot`]): a puff whose distance crossed a bin's edge
/// would otherwise jump from behind its neighbour to in front of it, and draw the edge.
#[shader_fn]
pub fn distance_bin(t: f32) -> f32 {
    ((t.max(1.0) / NEAREST_BIN).log2() + 1.0).clamp(0.0, (DISTANCE_BINS - 1u32) as f32)
}

/// 1 in the lane of `bin` (0–3), 0 in the others (and in all four outside 0–3); a fraction
/// shared between the two lanes either side.
#[shader_fn]
pub fn one_hot(bin: f32) -> Vec4 {
    let lanes = vec4(0.0, 1.0, 2.0, 3.0);
    let distance = (Vec4::splat(bin) - lanes).max(lanes - Vec4::splat(bin));
    (Vec4::ONE - distance).max(Vec4::ZERO)
}

/// The optical depth of the puffs above the ground point (`x`, `z`) (camera-relative): each
/// puff's column through it, in the clusters whose cells grown by the margin hold the point
/// (two rings at most, in its sector and the neighbour it lies nearer).
#[shader_fn]
pub fn mesh_overhead(x: f32, z: f32) -> f32 {
    let ground = vec3(x, 0.0, z);
    let k = ring_coordinate(vec2(x, z).length());
    let first = (k - MESH_MARGIN).floor().max(0.0);
    let last = (k + MESH_MARGIN).floor().min((MESH_RINGS - 1u32) as f32);
    let sectors = sectors_of(x, z);
    let mut tau = 0.0f32;
    for band in 0u32..BLOB_BANDS {
        for c in 0u32..4u32 {
            let ring = first + select(0.0, 1.0, c >= 2u32);
            let own = c == 0u32 || c == 2u32;
            let sector = select(select(sectors.y, sectors.x, own), 0.0, ring < 0.5);
            let row = band as f32 * MESH_RINGS as f32 + ring;
            let visit = ring <= last && (ring > 0.5 || own);
            let flag = mesh_texel(sector, 0.0, row);
            if visit && flag_passes(flag, sector, sectors.z, vec2(flag.x, flag.y) * 1e3) {
                let frame = cell_frame(ring, sector);
                for p in 0u32..MESH_PUFFS {
                    let column = 1.0 + PUFF_TEXELS as f32 * p as f32;
                    let bound = mesh_texel(sector, column, row);
                    let centre = bound.xyz() * 1e3;
                    let beside = vec2(x - centre.x, z - centre.z).length();
                    if bound.w > 0.0 && beside < bound.w * 1e3 {
                        let shape = mesh_texel(sector, column + 1.0, row);
                        let reach = shape.xyz() * (1e3 * PUFF_REACH);
                        let d = in_frame(ground - centre, frame) / reach;
                        let half_squared = (1.0 - d.x * d.x - d.z * d.z).max(0.0);
                        // The kernel's chord through the point: 16/15 of its half-length to the
                        // fifth power, in reaches.
                        tau += shape.w
                            * 1e-3
                            * KERNEL_CHORD
                            * reach.y
                            * half_squared
                            * half_squared
                            * half_squared.sqrt();
                    }
                }
            }
        }
    }
    tau
}
