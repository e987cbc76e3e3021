//! The named hard cases. Each builds its probes from one small genus and the high preset,
//! varied in exactly the way that makes it hard.

use glam::{Vec2, Vec3};

use nimbus_clouds::CloudKey;
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::shell::EARTH_RADIUS;
use nimbus_clouds::{Channel, CloudLayer, DensityProfileParams, Genus, Medium, PhaseSpec, Quality};

use super::case::{Case, CaseTextures, Pair, Probe};

/// One cumulus-like layer from 1500 to 3000 m, half the sky covered.
pub fn base_genus() -> Genus {
    Genus {
        name: "stability".into(),
        description: "One layer for the stability catalogue".into(),
        coverage: 0.5,
        medium: Medium::default(),
        phase: PhaseSpec::default(),
        functions: Default::default(),
        layers: vec![CloudLayer {
            altitude: 1500.0,
            height: 1500.0,
            shadow: true,
            ..CloudLayer::default()
        }],
    }
}

/// `base_genus` with its one layer changed by `f`.
fn with_layer(f: impl Fn(&mut CloudLayer)) -> Genus {
    let mut g = base_genus();
    f(&mut g.layers[0]);
    g
}

/// The uniforms of `quality` for `genus`, sun at `sun_elevation_deg` (azimuth 150°), camera at
/// `camera_altitude`; textures tiled every few kilometres so the small case textures give
/// structure at the probes' scale.
fn quality_uniforms(
    genus: &Genus,
    quality: Quality,
    sun_elevation_deg: f32,
    camera_altitude: f32,
) -> CloudUniforms {
    let (el, az) = (sun_elevation_deg.to_radians(), 150f32.to_radians());
    let sun = Vec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos());
    let mut u = CloudUniforms::for_genus(genus, quality, sun, camera_altitude);
    u.media.weather_repeat = Vec2::splat(1.0 / 4000.0);
    u.media.shape_repeat = Vec3::splat(1.0 / 1000.0);
    u.media.detail_repeat = Vec3::splat(1.0 / 200.0);
    u
}

/// The high preset's uniforms (see [`quality_uniforms`]).
fn uniforms(genus: &Genus, sun_elevation_deg: f32, camera_altitude: f32) -> CloudUniforms {
    quality_uniforms(genus, Quality::High, sun_elevation_deg, camera_altitude)
}

/// The reference preset's uniforms (whole-path stratified secondary marches, no shadow map in
/// the march).
fn reference_uniforms(
    genus: &Genus,
    sun_elevation_deg: f32,
    camera_altitude: f32,
) -> CloudUniforms {
    quality_uniforms(
        genus,
        Quality::Reference,
        sun_elevation_deg,
        camera_altitude,
    )
}

/// `high`'s key, integrating the air per ray: the probes of one case carry suns and camera
/// altitudes of their own, and one GPU dispatch runs them all, where one air table would serve
/// one sun at one altitude (the table's own hard cases are `tests/air_table.rs`'s).
fn key_of(genus: &Genus) -> CloudKey {
    let mut features = Quality::High.features();
    features.accurate_air_light = true;
    CloudVariant::new(genus, Quality::High, features).key
}

/// Unit direction with up-cosine `mu` at `azimuth` (radians).
fn direction(mu: f32, azimuth: f32) -> Vec3 {
    let mu = mu.clamp(-1.0, 1.0);
    let s = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
    Vec3::new(s * azimuth.cos(), mu, s * azimuth.sin())
}

/// Up-cosine of the ray from `camera` altitude that grazes the shell at `shell` altitude
/// (below the camera), in f64.
fn tangent_mu(camera: f32, shell: f32) -> f32 {
    let r = f64::from(EARTH_RADIUS);
    let ratio = (r + f64::from(shell)) / (r + f64::from(camera));
    -(1.0 - ratio * ratio).sqrt() as f32
}

/// Up-cosines a fan of rays covers: straight down, grazing either side of the horizon, up.
const FAN: [f32; 13] = [
    -1.0, -0.3, -0.05, -0.01, -1e-3, -1e-6, 0.0, 1e-6, 1e-3, 0.01, 0.05, 0.3, 1.0,
];

/// Collects a case's probes.
struct Builder {
    key: CloudKey,
    textures: CaseTextures,
    probes: Vec<Probe>,
    chains: Vec<Vec<usize>>,
    pairs: Vec<Pair>,
}

impl Builder {
    fn new(genus: &Genus) -> Self {
        Builder {
            key: key_of(genus),
            textures: CaseTextures::Random(7),
            probes: Vec::new(),
            chains: Vec::new(),
            pairs: Vec::new(),
        }
    }

    /// The ray cut at an eighth, a quarter, half and all of the march's reach.
    fn chain(&mut self, u: CloudUniforms, direction: Vec3) {
        let jitter = (self.probes.len() as f32 * 0.618_034).fract();
        let chain = [0.125, 0.25, 0.5, 1.0]
            .map(|f| {
                let mut v = u;
                v.march.max_ray_distance *= f;
                self.probes.push(Probe {
                    uniforms: v,
                    direction: direction.normalize(),
                    jitter,
                });
                self.probes.len() - 1
            })
            .to_vec();
        self.chains.push(chain);
    }

    /// A fan of rays at two azimuths plus the rays towards and away from the sun, each a chain.
    fn fan(&mut self, u: CloudUniforms) {
        for az in [0.3f32, 2.5] {
            for mu in FAN {
                self.chain(u, direction(mu, az));
            }
        }
        let sun = u.light.sun_direction;
        self.chain(u, sun);
        self.chain(u, -sun);
    }

    /// Two probes of one ray under uniforms on either side of a threshold.
    fn pair(&mut self, a: CloudUniforms, b: CloudUniforms, direction: Vec3, rel: f32, abs: f32) {
        self.pair_of((a, direction), (b, direction), rel, abs);
    }

    /// Two probes, each with its own uniforms and direction, that must agree.
    fn pair_of(&mut self, a: (CloudUniforms, Vec3), b: (CloudUniforms, Vec3), rel: f32, abs: f32) {
        let jitter = 0.37;
        let mut push = |(u, d): (CloudUniforms, Vec3)| {
            self.probes.push(Probe {
                uniforms: u,
                direction: d.normalize(),
                jitter,
            });
            self.probes.len() - 1
        };
        let (a, b) = (push(a), push(b));
        self.pairs.push(Pair { a, b, rel, abs });
    }

    fn finish(self, name: &'static str, about: &'static str) -> Case {
        Case {
            name,
            about,
            key: self.key,
            textures: self.textures,
            probes: self.probes,
            chains: self.chains,
            pairs: self.pairs,
        }
    }
}

/// A thin version of the base layer: light crosses a hundred kilometres of it, so where a ray
/// stops marching shows in the pixel.
fn thin_genus() -> Genus {
    with_layer(|l| l.density_scale = 1e-4)
}

fn tangent_rays() -> Case {
    let g = thin_genus();
    let mut b = Builder::new(&g);
    for (camera, shell) in [(2250.0, 1500.0), (6000.0, 3000.0), (6000.0, 1500.0)] {
        let u = uniforms(&g, 30.0, camera);
        let mu = tangent_mu(camera, shell);
        for az in [0.3f32, 2.0, 4.0] {
            for d in [0.0, 1e-5, -1e-5, 1e-3, -1e-3] {
                b.chain(u, direction(mu + d, az));
            }
            // The same ray either side of the tangent. The chord a steeper ray cuts below the
            // shell grows as √Δμ (1e-8 in μ: a dip of ~3 mm, a chord of ~300 m), so the pair
            // sits a few f32 steps of μ apart.
            b.pair_of(
                (u, direction(mu - 1e-8, az)),
                (u, direction(mu + 1e-8, az)),
                0.02,
                1e-4,
            );
        }
    }
    b.finish(
        "tangent-rays",
        "rays grazing a layer's bottom or top shell from inside and from above",
    )
}

fn sun_case(name: &'static str, about: &'static str, elevation: f32) -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    b.fan(uniforms(&g, elevation, 2.0));
    b.fan(uniforms(&g, elevation, 2250.0));
    if elevation == 0.0 {
        for mu in [0.05f32, 0.3, 0.9, -0.2] {
            for camera in [2.0, 2250.0] {
                b.pair(
                    uniforms(&g, -0.01, camera),
                    uniforms(&g, 0.01, camera),
                    direction(mu, 2.6),
                    0.02,
                    1e-5,
                );
            }
        }
    }
    b.finish(name, about)
}

fn camera_case(name: &'static str, about: &'static str, altitudes: &[f32]) -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    for a in altitudes {
        b.fan(uniforms(&g, 30.0, *a));
    }
    b.finish(name, about)
}

fn camera_at_ground() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    b.fan(uniforms(&g, 30.0, 0.0));
    for mu in [-0.3f32, -1e-3, 1e-3, 0.05, 0.5] {
        b.pair(
            uniforms(&g, 30.0, 0.0),
            uniforms(&g, 30.0, 0.01),
            direction(mu, 1.1),
            0.05,
            1e-5,
        );
    }
    b.finish(
        "camera-at-ground",
        "camera at altitude 0: rays below the horizon hit the ground at distance 0",
    )
}

fn camera_on_layer_boundary() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    for boundary in [1500.0f32, 3000.0] {
        b.fan(uniforms(&g, 30.0, boundary));
        for mu in [-0.3f32, -0.01, -0.005, 0.005, 0.01, 0.3] {
            for az in [0.4f32, 3.3] {
                // Grazing rays meet their clouds 100–200 km away, after a gap whose far root
                // the two cameras compute in different ways (from inside the layer, from below
                // it): the last bits differ, the samples' phase with them, and over random
                // textures the far cloud's radiance by up to 19 % (since the noise is read at
                // the altitude, the far clouds' noise follows the planet's curve and these
                // rays cross more of its structure; 8 % before). A jump across the shell (the
                // bug this pair guards) is a factor, not per cent.
                let rel = if mu.abs() <= 0.01 { 0.25 } else { 0.05 };
                b.pair(
                    uniforms(&g, 30.0, boundary - 1e-3),
                    uniforms(&g, 30.0, boundary + 1e-3),
                    direction(mu, az),
                    rel,
                    1e-4,
                );
            }
        }
    }
    b.finish(
        "camera-on-layer-boundary",
        "camera exactly on, and a millimetre either side of, a layer's bottom and top",
    )
}

fn camera_in_orbit() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    let altitude = 400_000.0;
    let u = uniforms(&g, 30.0, altitude);
    let limb = tangent_mu(altitude, 0.0);
    for d in [-0.5f32, -0.05, -1e-3, -1e-5, 0.0, 1e-5, 1e-3, 0.05] {
        for az in [0.3f32, 2.5] {
            b.chain(u, direction(limb + d, az));
        }
    }
    b.chain(u, direction(-1.0, 0.0));
    b.chain(u, direction(1.0, 0.0));
    b.finish(
        "camera-in-orbit",
        "camera 400 km up looking at the limb: clouds and air seen edge-on from space",
    )
}

/// A genus as a case: fans of rays from below, inside and above its layers, under the sun at
/// 30°. How a genus of one's own, with its own functions, joins the catalogue's checks.
pub fn genus_case(name: &'static str, about: &'static str, genus: &Genus) -> Case {
    let (bottom, top) = genus.altitude_range().unwrap_or((0.0, 0.0));
    let mut b = Builder::new(genus);
    for camera in [2.0, 0.5 * (bottom + top), top + 2000.0] {
        b.fan(uniforms(genus, 30.0, camera));
    }
    b.finish(name, about)
}

/// The base genus, deep (1 to 9 km) like a towering cloud, with the built-in genus functions
/// `functions` sets.
fn functions_genus(set: impl Fn(&mut nimbus_clouds::GenusFunctions)) -> Genus {
    let mut g = with_layer(|l| {
        l.altitude = 1000.0;
        l.height = 8000.0;
    });
    set(&mut g.functions);
    g
}

fn layer_case(name: &'static str, about: &'static str, genus: Genus, cameras: &[f32]) -> Case {
    let mut b = Builder::new(&genus);
    for c in cameras {
        b.fan(uniforms(&genus, 30.0, *c));
    }
    b.finish(name, about)
}

fn zero_height_layer() -> Case {
    let mut g = base_genus();
    g.layers.insert(
        0,
        CloudLayer {
            altitude: 2000.0,
            height: 0.0,
            ..CloudLayer::default()
        },
    );
    layer_case(
        "zero-height-layer",
        "a layer of height 0 packed beside a real one (its lane must add nothing, not 0/0)",
        g,
        &[2.0, 2000.0, 2250.0],
    )
}

fn density_pairs(name: &'static str, about: &'static str, scale: f32, reference: f32) -> Case {
    let g = with_layer(|l| l.density_scale = scale);
    let zero = with_layer(|l| l.density_scale = reference);
    let mut b = Builder::new(&g);
    b.textures = CaseTextures::RandomUnshadowed(7);
    b.fan(uniforms(&g, 30.0, 2.0));
    b.fan(uniforms(&g, 30.0, 2250.0));
    for mu in [0.05f32, 0.3, 1.0, -0.3] {
        for camera in [2.0f32, 2250.0, 6000.0] {
            b.pair(
                uniforms(&g, 30.0, camera),
                uniforms(&zero, 30.0, camera),
                direction(mu, 0.7),
                1e-3,
                1e-6,
            );
        }
    }
    b.finish(name, about)
}

fn coverage_case(name: &'static str, about: &'static str, coverage: f32) -> Case {
    let mut g = base_genus();
    g.coverage = coverage;
    let mut b = Builder::new(&g);
    if coverage >= 1.0 {
        b.textures = CaseTextures::Constant(1.0);
    } else {
        b.textures = CaseTextures::RandomUnshadowed(7);
    }
    b.fan(uniforms(&g, 30.0, 2.0));
    b.fan(uniforms(&g, 30.0, 2250.0));
    if coverage == 0.0 {
        let mut barely = g.clone();
        barely.coverage = 1e-6;
        for mu in [0.05f32, 0.3, 1.0] {
            b.pair(
                uniforms(&g, 30.0, 2.0),
                uniforms(&barely, 30.0, 2.0),
                direction(mu, 0.7),
                1e-3,
                1e-6,
            );
        }
    }
    b.finish(name, about)
}

fn phase_case(name: &'static str, about: &'static str, g: f32) -> Case {
    let mut genus = base_genus();
    genus.phase = PhaseSpec::HenyeyGreenstein { g };
    let mut b = Builder::new(&genus);
    for camera in [2.0f32, 2250.0, 6000.0] {
        let u = uniforms(&genus, 30.0, camera);
        b.fan(u);
        let sun = u.light.sun_direction;
        // Within a few peak widths (1 − |g| rad) of the sun and of the anti-sun.
        for d in [1e-4f32, 1e-3, 3e-3] {
            b.chain(u, sun + Vec3::new(d, 0.0, 0.0));
            b.chain(u, -sun + Vec3::new(0.0, 0.0, d));
        }
    }
    b.finish(name, about)
}

fn profile_case() -> Case {
    let huge = |a: f32, b: f32| {
        with_layer(move |l| {
            l.density_profile = DensityProfileParams {
                a,
                b,
                c: 0.0,
                d: 0.0,
            };
        })
    };
    let g = huge(1.0, 80.0);
    let mut b = Builder::new(&g);
    for genus in [
        huge(1.0, 80.0),
        huge(1.0, -80.0),
        huge(1e-30, 80.0),
        huge(-1.0, 80.0),
    ] {
        b.fan(uniforms(&genus, 30.0, 2.0));
        b.fan(uniforms(&genus, 30.0, 2250.0));
    }
    b.finish(
        "overflowing-profile-exponent",
        "profile a·e^(b·η) at the largest accepted |b| = 80 (e^80 ≈ 5.5e34), and tiny or negative a",
    )
}

fn step_limits() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    let base = uniforms(&g, 30.0, 2250.0);
    let variants: [(u32, u32, u32, f32); 6] = [
        (0, 2, 3, 50.0),
        (1, 2, 3, 50.0),
        (2, 0, 0, 50.0),
        (500, 64, 32, 50.0),
        (20_000, 2, 3, 1.0),
        (500, 2, 3, 1e-3),
    ];
    for (iterations, sun, ground, min_step) in variants {
        let mut u = base;
        u.march.max_iterations = iterations;
        u.march.sun_steps = sun;
        u.march.ground_steps = ground;
        u.march.min_step = min_step;
        for mu in [-0.3f32, 0.0, 0.05, 1.0] {
            b.chain(u, direction(mu, 0.5));
        }
    }
    b.finish(
        "step-limits",
        "0, 1 and 20 000 primary steps, 0 and 64 secondary steps, a 1 mm minimum step",
    )
}

fn far_distances() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    for reach in [2e5f32, 1e6, 1e7] {
        for (camera, offset) in [(2.0f32, 0.0f32), (2250.0, 2e5), (6000.0, 1e7)] {
            let mut u = uniforms(&g, 30.0, camera);
            u.march.max_ray_distance = reach;
            u.camera_offset = Vec3::new(offset, 0.0, -offset);
            for mu in [-0.01f32, 0.0, 1e-3, 0.02] {
                b.chain(u, direction(mu, 1.3));
            }
        }
    }
    b.finish(
        "far-distances",
        "marches reaching 2e5, 1e6 and 1e7 m, noise looked up 1e7 m from the origin",
    )
}

/// One ray of `genus` as a case of its own (cut at four distances): what the property tests
/// draw at random.
pub fn single_ray_case(
    genus: &Genus,
    sun_elevation_deg: f32,
    camera_altitude: f32,
    direction: Vec3,
) -> Case {
    let mut b = Builder::new(genus);
    b.chain(
        uniforms(genus, sun_elevation_deg, camera_altitude),
        direction,
    );
    b.finish("random-ray", "a random ray of a random valid genus")
}

fn reference_case(name: &'static str, about: &'static str, genus: Genus, suns: &[f32]) -> Case {
    let mut b = Builder::new(&genus);
    b.key = CloudVariant::new(&genus, Quality::Reference, Quality::Reference.features()).key;
    for &sun in suns {
        for camera in [2.0f32, 2250.0, 6000.0] {
            b.fan(reference_uniforms(&genus, sun, camera));
        }
    }
    b.finish(name, about)
}

fn secondary_scale_near_one() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    let base = uniforms(&g, 30.0, 2250.0);
    let with = |scale: f32, full: u32| {
        let mut u = base;
        u.march.secondary_step_scale = scale;
        u.march.secondary_full_path = full;
        u.march.sun_steps = 8;
        u
    };
    for full in [0u32, 1] {
        for scale in [1.0f32, 1.000_05, 1.0002, 0.5] {
            b.fan(with(scale, full));
        }
        // Either side of the `|scale − 1| > 1e-4` switch between the two forms of the span: the
        // samples move by 0.02 %, the pixels by up to 0.3 %; a wrong form would move them by
        // far more.
        for mu in [-0.3f32, 0.05, 1.0] {
            b.pair(
                with(1.0, full),
                with(1.000_05, full),
                direction(mu, 0.9),
                5e-3,
                1e-5,
            );
        }
    }
    b.finish(
        "secondary-step-scale-near-one",
        "secondary steps growing ×1 (the span's n branch), ×1.00005 and ×1.0002 either side of the switch, and shrinking ×0.5",
    )
}

fn secondary_span_overflow() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    for full in [0u32, 1] {
        let mut u = uniforms(&g, 30.0, 2250.0);
        u.march.sun_steps = 64;
        u.march.ground_steps = 64;
        u.march.secondary_step_scale = 4.0;
        u.march.secondary_full_path = full;
        b.fan(u);
    }
    b.finish(
        "secondary-span-overflow",
        "64 secondary steps growing ×4: the span 4⁶⁴ overflows f32 (the first step becomes 0, not NaN)",
    )
}

fn verification_mode() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    let features = nimbus_clouds::Features {
        octaves: 1,
        diffusion: false,
        ..Quality::Reference.features()
    }
    .sun_scattering_only();
    b.key = CloudVariant::new(&g, Quality::Reference, features).key;
    for camera in [2.0f32, 2250.0, 6000.0] {
        b.fan(reference_uniforms(&g, 30.0, camera).lit_by_sun_alone());
    }
    b.finish(
        "verification-mode",
        "single scattering of a sun of irradiance 1, no sky, background or aerial perspective",
    )
}

fn stacked_layers(name: &'static str, about: &'static str, altitudes: &[f32]) -> Case {
    let mut g = base_genus();
    g.layers = altitudes
        .iter()
        .enumerate()
        .map(|(i, &a)| CloudLayer {
            altitude: a,
            height: 400.0,
            shadow: true,
            channel: [Channel::R, Channel::G, Channel::B, Channel::A][i % 4],
            ..CloudLayer::default()
        })
        .collect();
    let top = altitudes.iter().fold(0.0f32, |m, a| m.max(*a)) + 400.0;
    layer_case(
        name,
        about,
        g,
        &[2.0, altitudes[altitudes.len() / 2] + 200.0, top + 3000.0],
    )
}

fn tiny_reach() -> Case {
    let g = base_genus();
    let mut b = Builder::new(&g);
    for reach in [1.0f32, 1e-3, 0.0] {
        for camera in [2.0f32, 2250.0] {
            let mut u = uniforms(&g, 30.0, camera);
            u.march.max_ray_distance = reach;
            for mu in [-0.3f32, 0.0, 0.05, 1.0] {
                b.chain(u, direction(mu, 0.5));
            }
        }
    }
    b.finish(
        "tiny-reach",
        "march reach 1 m, 1 mm and 0: the secondary marches' full path is capped by it too",
    )
}

/// Every case, in a fixed order.
pub fn catalogue() -> Vec<Case> {
    use nimbus_clouds::model::genus_fns::{
        ANVIL_SHAPE, CELL_ROWS_WEATHER, CELLULAR_WEATHER, GRAIN_WEATHER, STREAK_WEATHER,
    };
    vec![
        genus_case(
            "anvil-shape",
            "a 8 km deep layer with the built-in anvil shape (and anvil-shaped profile)",
            &functions_genus(|f| {
                f.shape = ANVIL_SHAPE;
                f.profile = ANVIL_SHAPE;
            }),
        ),
        genus_case(
            "cellular-weather",
            "the deep layer under the cellular weather function",
            &functions_genus(|f| f.weather = CELLULAR_WEATHER),
        ),
        genus_case(
            "streak-weather",
            "the deep layer under the streak weather function",
            &functions_genus(|f| f.weather = STREAK_WEATHER),
        ),
        genus_case(
            "grain-weather",
            "the deep layer under the grain weather function (cellular noise evaluated in place)",
            &functions_genus(|f| f.weather = GRAIN_WEATHER),
        ),
        genus_case(
            "cell-rows-weather",
            "the deep layer under the cell-rows weather function",
            &functions_genus(|f| f.weather = CELL_ROWS_WEATHER),
        ),
        tangent_rays(),
        sun_case("sun-at-horizon", "sun at 0° (and ±0.01° either side)", 0.0),
        sun_case(
            "sun-just-below-horizon",
            "sun 0.5° below the horizon: clouds lit by the grazing sun, ground in the earth's shadow",
            -0.5,
        ),
        sun_case(
            "sun-far-below-horizon",
            "sun 30° below the horizon: no direct light anywhere",
            -30.0,
        ),
        camera_at_ground(),
        camera_case(
            "camera-inside-layer",
            "camera in the middle of the layer",
            &[2250.0],
        ),
        camera_on_layer_boundary(),
        camera_case(
            "camera-above-layers",
            "camera 5 km above the layer top",
            &[8000.0],
        ),
        camera_in_orbit(),
        zero_height_layer(),
        layer_case(
            "one-millimetre-layer",
            "a layer 1 mm thick, seen from below, from inside and from above",
            with_layer(|l| {
                l.altitude = 2000.0;
                l.height = 1e-3;
            }),
            &[2.0, 2000.0005, 5000.0],
        ),
        density_pairs(
            "density-scale-zero",
            "density scale 0 against 1e-12",
            0.0,
            1e-12,
        ),
        density_pairs(
            "density-scale-1e-8",
            "density scale 1e-8 against 0: far below every cut-off",
            1e-8,
            0.0,
        ),
        density_pairs(
            "density-scale-1e3",
            "density scale 1e3 against 1e3·(1 + 1e-6): optically thick within a millimetre",
            1e3,
            1e3 * (1.0 + 1e-6),
        ),
        coverage_case("coverage-zero", "coverage 0 (and 1e-6)", 0.0),
        coverage_case(
            "coverage-one",
            "coverage 1 with a full weather texture: overcast everywhere",
            1.0,
        ),
        layer_case(
            "narrow-coverage-filter",
            "coverage filter width 0.001, the smallest accepted: a near-step at cloud edges",
            with_layer(|l| l.coverage_filter_width = 1e-3),
            &[2.0, 2250.0],
        ),
        phase_case(
            "hg-g-0.999",
            "Henyey–Greenstein with g = 0.999: a forward peak 1e-3 rad wide",
            0.999,
        ),
        phase_case(
            "hg-g-minus-0.999",
            "Henyey–Greenstein with g = −0.999: the same peak backwards",
            -0.999,
        ),
        profile_case(),
        step_limits(),
        far_distances(),
        density_pairs(
            "denormal-density",
            "density scale 1e-39, a subnormal f32 (GPUs may flush it to 0), against 0",
            1e-39,
            0.0,
        ),
        reference_case(
            "reference-low-sun",
            "the reference preset's whole-path secondary marches with the sun 1° and 8° high: paths out of the layer tens of kilometres long",
            base_genus(),
            &[1.0, 8.0],
        ),
        reference_case(
            "reference-sun-below-horizon",
            "the reference preset with the sun 0.5° below the horizon: sun marches leave the layer through its bottom",
            base_genus(),
            &[-0.5],
        ),
        reference_case(
            "reference-optically-thick",
            "the reference preset in a layer of density scale 1e3: whole-path optical depths in the tens of thousands",
            with_layer(|l| l.density_scale = 1e3),
            &[30.0],
        ),
        secondary_scale_near_one(),
        secondary_span_overflow(),
        verification_mode(),
        stacked_layers(
            "eight-layers",
            "eight stacked layers in two lane groups, 100 m gaps between them",
            &[
                1000.0, 1500.0, 2000.0, 2500.0, 3000.0, 3500.0, 4000.0, 4500.0,
            ],
        ),
        stacked_layers(
            "coincident-layers",
            "two layers occupying the same altitudes (their densities add)",
            &[2000.0, 2000.0],
        ),
        tiny_reach(),
    ]
}
