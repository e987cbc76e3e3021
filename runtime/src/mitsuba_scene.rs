//! A Mitsuba 3 scene (XML) around an exported density grid, so that an independent renderer
//! draws the same clouds as Nimbus sees them: the grid in its box at its real place and size
//! (Mitsuba ignores the VOL header's bounding box, so the volume's `to_world` carries it), the
//! genus' phase function tabulated from the model's own `cloud_phase` CPU twin, the scene's sun
//! as a directional emitter, and the scene's camera.
//!
//! The scene takes parameters (`mitsuba.load_file(path, spp=…, sun=…, …)`) so one file gives
//! both renders an agreement check needs: `sun` (irradiance of the directional sun, default 1),
//! `sky` (radiance of a uniform background, default 0), `albedo` (default the genus'),
//! `max_depth` (default 2: single scattering; -1 for the full path tracer), `spp`, `width`,
//! `height`. With `sun=0 sky=1 albedo=0` the image is the clouds' transmittance.

use glam::Vec3;
use nimbus_clouds::model::march::cloud_phase;

use crate::density_export::DensityGrid;
use crate::error::RuntimeError;
use crate::render::{Frame, Renderer};
use nimbus_clouds::model::bindings::CloudTextures;

/// Entries of the coarsest tabulated phase function, evenly spaced in the cosine of the
/// scattering angle over [−1, 1] (Mitsuba's `tabphase` takes an even grid).
pub const PHASE_ENTRIES: usize = 1025;

/// Entries of the finest table written (each halving of the step doubles the XML).
pub const MAX_PHASE_ENTRIES: usize = 262_145;

/// How far from 1 the table's integral over the sphere may be. Mitsuba interpolates the table
/// linearly between entries and normalises it by that integral, so a table that misses 1 by x
/// renders every direction off by the factor 1/(1 + x): a forward peak narrower than one step
/// is a triangle far wider than the peak, and dims everything else (17× for 50 µm droplets on
/// 1,025 entries).
pub const PHASE_TABLE_TOLERANCE: f64 = 1e-3;

/// The integral over the sphere of a phase function tabulated at evenly spaced cosines from −1
/// to 1, interpolated linearly as Mitsuba does: 2π × the trapezoid rule in cos θ.
pub fn table_integral(values: &[f32]) -> f64 {
    if values.len() < 2 {
        return 0.0;
    }
    let step = 2.0 / (values.len() - 1) as f64;
    let inner: f64 = values
        .windows(2)
        .map(|w| f64::from(w[0] + w[1]) * 0.5)
        .sum();
    std::f64::consts::TAU * inner * step
}

/// The frame's phase function (the model's `cloud_phase`, first octave) at evenly spaced
/// cosines from −1 (back-scattering) to 1 (forward), in 1/sr: [`PHASE_ENTRIES`] entries, or as
/// many more (doubling the resolution) as the forward peak needs for the table to integrate to
/// 1 within [`PHASE_TABLE_TOLERANCE`]. A phase no table up to [`MAX_PHASE_ENTRIES`] represents
/// is refused, naming the genus, the phase and how far off Mitsuba would render it.
pub fn phase_table(frame: &Frame, textures: &CloudTextures) -> Result<Vec<f32>, RuntimeError> {
    let u = Renderer::uniforms(frame);
    let key = frame.variant().key;
    let _bound = textures.bind(u);
    let mut entries = PHASE_ENTRIES;
    loop {
        let values: Vec<f32> = (0..entries)
            .map(|i| {
                let cos_theta = (-1.0 + 2.0 * i as f64 / (entries - 1) as f64) as f32;
                cloud_phase(cos_theta, 1.0, key)
            })
            .collect();
        let integral = table_integral(&values);
        if (integral - 1.0).abs() <= PHASE_TABLE_TOLERANCE {
            return Ok(values);
        }
        if entries >= MAX_PHASE_ENTRIES {
            return Err(RuntimeError::PhaseTable {
                genus: frame.genus.name.clone(),
                phase: format!("{:?}", frame.genus.phase),
                entries,
                integral,
            });
        }
        entries = (entries - 1) * 2 + 1;
    }
}

/// `"x, y, z"` as Mitsuba reads a vector.
fn xyz(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

/// Escapes text for an XML attribute value.
fn attribute(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The scene's XML, with `volume` the grid file's path as the scene should name it (relative
/// paths resolve against the XML's folder). The first line marks the file as Nimbus's.
///
/// Mitsuba's tabulated phase function takes its values from cos θ = −1 to 1 with θ the
/// scattering angle (forward scattering at cos θ = 1), the convention of the model.
pub fn mitsuba_scene_xml(frame: &Frame, grid: &DensityGrid, volume: &str, phase: &[f32]) -> String {
    let (forward, up) = frame.camera_basis();
    let eye = Vec3::new(0.0, frame.camera_altitude, 0.0);
    let sun = Renderer::uniforms(frame).light.sun_direction;
    let r = grid.region;
    let extent = r.max - r.min;
    let centre = (r.min + r.max) * 0.5;
    let inside = eye.cmpgt(r.min).all() && eye.cmplt(r.max).all();
    let values: Vec<String> = phase.iter().map(|v| format!("{v:e}")).collect();
    let mut x = String::new();
    let mut line = |s: &str| {
        x.push_str(s);
        x.push('\n');
    };
    line(&format!(
        "<!-- {} {}: {} as a Mitsuba 3 scene; see `nimbus export-density --help`. -->",
        nimbus_output::TEXT_MARKER,
        env!("CARGO_PKG_VERSION"),
        attribute(&frame.variant().name()),
    ));
    line(r#"<scene version="3.0.0">"#);
    line(r#"    <default name="spp" value="256"/>"#);
    line(&format!(
        r#"    <default name="width" value="{}"/>"#,
        frame.width
    ));
    line(&format!(
        r#"    <default name="height" value="{}"/>"#,
        frame.height
    ));
    line(r#"    <default name="max_depth" value="2"/>"#);
    line(r#"    <default name="sun" value="1"/>"#);
    line(r#"    <default name="sky" value="0"/>"#);
    line(&format!(
        r#"    <default name="albedo" value="{}"/>"#,
        grid.albedo
    ));
    line(r#"    <integrator type="volpath">"#);
    line(r#"        <integer name="max_depth" value="$max_depth"/>"#);
    // No Russian roulette: in cloud that does not absorb it keeps a path with probability 0.95
    // per bounce, so the light a thick deck transmits, whose paths take a thousand bounces and
    // more, comes from a few survivors of enormous weight, and a render's mean sits low (the
    // deck from below of the agreement suite read 7 % dark with it from the 1,000th bounce).
    // Paths still end: every one leaves the grid's box.
    line(r#"        <integer name="rr_depth" value="1000000000"/>"#);
    line(r#"    </integrator>"#);
    // The medium first: a camera inside the grid's box names it, and a reference must follow
    // what it names.
    line(r#"    <medium type="heterogeneous" id="clouds">"#);
    line(r#"        <float name="albedo" value="$albedo"/>"#);
    line(r#"        <float name="scale" value="1"/>"#);
    line(r#"        <volume name="sigma_t" type="gridvolume">"#);
    line(&format!(
        r#"            <string name="filename" value="{}"/>"#,
        attribute(volume)
    ));
    line(r#"            <string name="filter_type" value="trilinear"/>"#);
    line(r#"            <transform name="to_world">"#);
    line(&format!(
        r#"                <scale value="{}"/>"#,
        xyz(extent)
    ));
    line(&format!(
        r#"                <translate value="{}"/>"#,
        xyz(r.min)
    ));
    line(r#"            </transform>"#);
    line(r#"        </volume>"#);
    line(r#"        <phase type="tabphase">"#);
    line(&format!(
        r#"            <string name="values" value="{}"/>"#,
        values.join(", ")
    ));
    line(r#"        </phase>"#);
    line(r#"    </medium>"#);
    line(r#"    <sensor type="perspective">"#);
    if inside {
        // A camera inside the box starts its rays in the medium (the cube's interior); without
        // this, Mitsuba starts them in vacuum and the clouds around the camera are not there.
        line(r#"        <ref name="medium" id="clouds"/>"#);
    }
    line(r#"        <string name="fov_axis" value="y"/>"#);
    line(&format!(
        r#"        <float name="fov" value="{}"/>"#,
        frame.fov_deg
    ));
    line(r#"        <float name="near_clip" value="1"/>"#);
    line(r#"        <float name="far_clip" value="1e7"/>"#);
    line(r#"        <transform name="to_world">"#);
    line(&format!(
        r#"            <lookat origin="{}" target="{}" up="{}"/>"#,
        xyz(eye),
        xyz(eye + forward),
        xyz(up)
    ));
    line(r#"        </transform>"#);
    line(
        r#"        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>"#,
    );
    line(r#"        <film type="hdrfilm">"#);
    line(r#"            <integer name="width" value="$width"/>"#);
    line(r#"            <integer name="height" value="$height"/>"#);
    line(r#"            <string name="pixel_format" value="rgb"/>"#);
    line(r#"            <rfilter type="box"/>"#);
    line(r#"        </film>"#);
    line(r#"    </sensor>"#);
    line(r#"    <emitter type="directional">"#);
    line(&format!(
        r#"        <vector name="direction" value="{}"/>"#,
        xyz(-sun)
    ));
    line(r#"        <rgb name="irradiance" value="$sun"/>"#);
    line(r#"    </emitter>"#);
    line(r#"    <emitter type="constant"><rgb name="radiance" value="$sky"/></emitter>"#);
    line(r#"    <shape type="cube">"#);
    line(r#"        <transform name="to_world">"#);
    line(&format!(
        r#"            <scale value="{}"/>"#,
        xyz(extent * 0.5)
    ));
    line(&format!(
        r#"            <translate value="{}"/>"#,
        xyz(centre)
    ));
    line(r#"        </transform>"#);
    line(r#"        <bsdf type="null"/>"#);
    line(r#"        <ref name="interior" id="clouds"/>"#);
    line(r#"    </shape>"#);
    line(r#"</scene>"#);
    x
}
