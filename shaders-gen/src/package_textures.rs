//! The noise textures of an engine package, as files: 2D as PNG (RGBA8), 3D as raw R8 (the one
//! channel the shaders read: `NoiseKind::channels`) with a JSON descriptor. They are made by
//! the same compute kernels the runtime runs (on whatever adapter this machine has, lavapipe
//! included), so they are byte-identical to what `nimbus render` samples; with no adapter at
//! all, by the kernels' CPU twins, which agree within one 8-bit level (`tests/textures.rs`),
//! and the descriptor says so.

use std::io::Cursor;

use nimbus_runtime::Gpu;
use nimbus_runtime::render::TextureSizes;
use nimbus_runtime::textures::NoiseKind;

use crate::package_description::{TextureDescriptor, TextureDimension};

/// One texture file and its description.
#[derive(Clone)]
pub(crate) struct TextureFile {
    pub file: String,
    pub bytes: Vec<u8>,
    pub descriptor: TextureDescriptor,
}

/// What made the texels.
#[derive(Clone)]
pub(crate) struct Texels {
    pub files: Vec<TextureFile>,
    /// `gpu: <adapter>` or `cpu twins`.
    pub generated_by: String,
}

fn size_of(kind: NoiseKind, sizes: TextureSizes) -> u32 {
    match kind {
        NoiseKind::Weather => sizes.weather,
        NoiseKind::Shape => sizes.shape,
        NoiseKind::Detail => sizes.detail,
        NoiseKind::Turbulence => sizes.turbulence,
    }
}

fn is_3d(kind: NoiseKind) -> bool {
    matches!(kind, NoiseKind::Shape | NoiseKind::Detail)
}

/// Texture files made in this process, by the kinds and sizes asked for: the same request
/// gives the same bytes, and one process (the fuzz targets, a test) may ask many times.
type Made = Vec<(Vec<(NoiseKind, u32)>, Texels)>;
static MADE: std::sync::Mutex<Made> = std::sync::Mutex::new(Vec::new());

/// The files of `kinds` at `sizes` (made once per process).
pub(crate) fn texture_files(
    kinds: &[NoiseKind],
    sizes: TextureSizes,
) -> Result<Texels, Box<dyn std::error::Error>> {
    let key: Vec<(NoiseKind, u32)> = kinds.iter().map(|&k| (k, size_of(k, sizes))).collect();
    let cached = |made: &Made| made.iter().find(|(k, _)| *k == key).map(|(_, t)| t.clone());
    if let Some(t) = MADE.lock().ok().and_then(|m| cached(&m)) {
        return Ok(t);
    }
    let texels = make_texture_files(kinds, sizes)?;
    if let Ok(mut m) = MADE.lock() {
        m.push((key, texels.clone()));
    }
    Ok(texels)
}

/// The files of `kinds` at `sizes`, made now.
fn make_texture_files(
    kinds: &[NoiseKind],
    sizes: TextureSizes,
) -> Result<Texels, Box<dyn std::error::Error>> {
    let gpu = Gpu::new().ok();
    let generated_by = match &gpu {
        Some(g) => format!(
            "the runtime's compute kernels on {} (byte-identical to what `nimbus render` samples)",
            g.info().name
        ),
        None => "the kernels' CPU twins (no adapter here: within 1/255 of the GPU's texels)".into(),
    };
    let mut files = Vec::new();
    for &kind in kinds {
        let size = size_of(kind, sizes);
        let depth = if is_3d(kind) { size } else { 1 };
        let texels: Vec<u32> = match &gpu {
            Some(g) => g.noise_texels(kind, size)?,
            None => (0..depth)
                .flat_map(|z| (0..size).flat_map(move |y| (0..size).map(move |x| (x, y, z))))
                .map(|(x, y, z)| kind.cpu_texel(size, x, y, z))
                .collect(),
        };
        // pack4x8unorm puts R in the lowest byte: little-endian words are R, G, B, A bytes.
        let rgba: Vec<u8> = texels.iter().flat_map(|t| t.to_le_bytes()).collect();
        let one_channel = is_3d(kind) && kind.channels() == 1;
        let (file, bytes, layout) = if one_channel {
            // The cloud passes read the red channel alone: the file holds it, one byte a texel.
            (
                format!("textures/{}.r8", kind.name()),
                rgba.iter().step_by(4).copied().collect(),
                "raw R8, 1 byte per texel, x fastest, then y, then z; no header or padding; \
                 upload each byte widened through texel_halves, one half float a texel \
                 (r16float: the shaders read only the red channel)",
            )
        } else if is_3d(kind) {
            (
                format!("textures/{}.rgba8", kind.name()),
                rgba,
                "raw RGBA8, 4 bytes per texel (R, G, B, A), x fastest, then y, then z; no header \
                 or padding; upload each byte widened through texel_halves",
            )
        } else {
            let image = image::RgbaImage::from_raw(size, size, rgba)
                .ok_or("texel count does not match the texture size")?;
            let mut png = Vec::new();
            image.write_to(&mut Cursor::new(&mut png), image::ImageFormat::Png)?;
            (
                format!("textures/{}.png", kind.name()),
                png,
                "PNG, RGBA8, linear values (not sRGB: load without colour conversion or \
                 premultiplication); upload as half floats, each byte k the value k/255",
            )
        };
        let descriptor = TextureDescriptor {
            name: kind.resource(),
            file: file.clone(),
            dimension: if is_3d(kind) {
                TextureDimension::D3
            } else {
                TextureDimension::D2
            },
            size: if is_3d(kind) {
                vec![size, size, size]
            } else {
                vec![size, size]
            },
            format: if one_channel {
                "r16float"
            } else {
                "rgba16float"
            }
            .into(),
            file_format: if one_channel { "r8unorm" } else { "rgba8unorm" }.into(),
            layout: layout.into(),
            colour_space: "linear".into(),
            address_mode: "repeat".into(),
            filter: "linear".into(),
            mipmaps: false,
        };
        files.push(TextureFile {
            file,
            bytes,
            descriptor,
        });
    }
    Ok(Texels {
        files,
        generated_by,
    })
}
