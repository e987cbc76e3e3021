//! Cascades in rotation, a band of rows at a time. With a sun, camera or wind that moves every
//! frame, the shadow atlas's out-of-date tiles are redrawn one after another, and each tile in
//! bands of rows over as many frames, so a frame's share of the atlas is bounded whatever the
//! preset: [`BAND_TEXELS`] texels (`low`'s 256-texel tile in two bands, `ultra`'s 1,024-texel
//! tile in 32), where a whole tile had cost a frame of `high` 410 ms and of `ultra` 1.5 s in
//! the browser benchmark. The air table, which follows the sun too, is drawn the same way, as
//! one tile (three bands).
//!
//! A tile in progress is drawn into a back atlas from a copy of the cloud block taken when its
//! first band is drawn, and reaches the atlas the clouds read, with the transform of that copy,
//! when its last band is drawn: no frame reads a tile half drawn, or one tile drawn for two suns
//! or around two places. This is the hosts' bookkeeping, written once: Nimbus's runtime calls
//! these functions, the JavaScript hosts their printed twins (`nimbus-sun.js`).

use nimbus_dsl::prelude::*;

use super::shadow::atlas_columns;

/// Texels of the shadow atlas one frame in rotation draws at most.
pub const BAND_TEXELS: u32 = 32_768;

/// Where the atlas's redraw in rotation stands between frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ShaderStruct)]
pub struct TileRedraw {
    /// Tiles out of date (bit `k`: tile `k`). A tile's bit is cleared when its first band is
    /// drawn, so a change after that marks it out of date again.
    pub stale: u32,
    /// The tile in progress and the band it draws next (`band` 0: none in progress).
    pub tile: u32,
    pub band: u32,
    /// The tile the rotation looks at first for the next one out of date.
    pub next: u32,
}

/// One frame of the redraw in rotation ([`band_redraw`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ShaderStruct)]
pub struct BandDraw {
    /// Where the redraw stands after this frame.
    pub state: TileRedraw,
    /// The tile drawn (`count` when none is out of date), its corner in the target (texels,
    /// the pass's frag-coord space), and the rows of it drawn this frame, into the back
    /// target: `height` rows from its row `top`.
    pub tile: u32,
    pub x: u32,
    pub y: u32,
    pub top: u32,
    pub height: u32,
    /// 1 when they are the tile's first band: take the copy of the block the tile's bands are
    /// drawn from (for a cascade, with the sun's lookup and the anchor it is kept with) before
    /// drawing them.
    pub first: u32,
    /// 1 when they are its last: copy the tile from the back target into the one the clouds
    /// read, and (cascades) keep the copied block's transform for it (`redrawn_tiles`).
    pub last: u32,
}

/// Rows of a target `width` texels wide drawn per frame: [`BAND_TEXELS`] texels, at least
/// one row, at most `height`.
#[shader_fn]
pub fn band_rows(width: u32, height: u32) -> u32 {
    let rows = BAND_TEXELS / select(width, 1u32, width == 0u32);
    select(select(rows, height, rows > height), 1u32, rows == 0u32)
}

/// Bands a tile of `width` × `height` texels is drawn in (the last may be shorter).
#[shader_fn]
pub fn bands_of(width: u32, height: u32) -> u32 {
    let rows = band_rows(width, height);
    let whole = height / rows;
    whole + select(0u32, 1u32, whole * rows < height)
}

/// Bands a square cascade tile of `side` texels is drawn in.
#[shader_fn]
pub fn tile_bands(side: u32) -> u32 {
    bands_of(side, side)
}

/// Every one of `count` tiles out of date (the sun, the camera's place or the clouds moved):
/// the tile in progress goes on, drawn from its copy, and is redrawn again in its turn.
#[shader_fn]
pub fn tiles_out_of_date(s: TileRedraw, count: u32) -> TileRedraw {
    TileRedraw {
        stale: (1u32 << count) - 1u32,
        tile: s.tile,
        band: s.band,
        next: s.next,
    }
}

/// This frame's band of the redraw in rotation of `count` tiles of `width` × `height` texels
/// (in the atlas's grid, [`atlas_columns`]): the next band of the tile in progress, or the
/// first of the first out-of-date tile from where the rotation stands. The shadow atlas's
/// cascades are square tiles; the air table is one tile.
#[shader_fn]
pub fn band_redraw(s: TileRedraw, count: u32, width: u32, height: u32) -> BandDraw {
    let mut tile = s.tile;
    let mut stale = s.stale;
    let mut first = 0u32;
    if s.band == 0u32 {
        let mut found = count;
        for i in 0u32..count {
            let k = (s.next + i) % count;
            if found == count && (stale & (1u32 << k)) != 0u32 {
                found = k;
            }
        }
        if found == count {
            return BandDraw {
                state: s,
                tile: count,
                x: 0u32,
                y: 0u32,
                top: 0u32,
                height: 0u32,
                first: 0u32,
                last: 0u32,
            };
        }
        tile = found;
        // Its bit is set: the difference clears it.
        stale -= 1u32 << found;
        first = 1u32;
    }
    let rows = band_rows(width, height);
    let top = s.band * rows;
    let columns = atlas_columns(count);
    let done = s.band + 1u32 >= bands_of(width, height);
    BandDraw {
        state: TileRedraw {
            stale,
            tile,
            band: select(s.band + 1u32, 0u32, done),
            next: select(s.next, (tile + 1u32) % count, done),
        },
        tile,
        x: (tile % columns) * width,
        y: (tile / columns) * height,
        top,
        height: select(rows, height - top, height - top < rows),
        first,
        last: select(0u32, 1u32, done),
    }
}
