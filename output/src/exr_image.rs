//! Linear images as OpenEXR (through the `exr` crate): named 32-bit float channels in one
//! layer, lossless (ZIP) compression, and a `software` attribute naming Nimbus so that a re-run
//! recognises its own file ([`crate::Signature::Exr`]).

use std::io::Cursor;

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, Text,
    WritableImage,
};

/// The `software` attribute of an EXR Nimbus writes starts with this.
pub(crate) const EXR_SOFTWARE: &str = "Nimbus";

/// One channel of a linear image: its EXR name (`R`, `clouds.R`, `depth.Z`, …) and its
/// values, row-major with the top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrChannel {
    pub name: String,
    pub values: Vec<f32>,
}

/// The EXR bytes of `channels`, each `width × height` values, signed as Nimbus's.
pub fn signed_exr(width: u32, height: u32, channels: &[ExrChannel]) -> Result<Vec<u8>, String> {
    let area = width as usize * height as usize;
    if let Some(c) = channels.iter().find(|c| c.values.len() != area) {
        return Err(format!(
            "channel `{}` has {} values for a {width}x{height} image",
            c.name,
            c.values.len()
        ));
    }
    let list = channels
        .iter()
        .map(|c| AnyChannel::new(c.name.as_str(), FlatSamples::F32(c.values.clone())))
        .collect();
    let mut attributes = LayerAttributes::named("nimbus");
    attributes.software_name = Some(Text::from(
        format!("{EXR_SOFTWARE} {}", env!("CARGO_PKG_VERSION")).as_str(),
    ));
    let layer = Layer::new(
        (width as usize, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(list),
    );
    let mut out = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut out)
        .map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

/// The `software` attribute of the EXR `bytes`, if they are an EXR that has one.
pub(crate) fn exr_software(bytes: &[u8]) -> Option<String> {
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).ok()?;
    meta.headers
        .iter()
        .find_map(|h| h.own_attributes.software_name.as_ref())
        .map(|t| t.to_string())
}
