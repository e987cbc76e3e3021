//! Cascades in rotation, a band of rows at a time. With a sun, camera or wind that moves every
//! frame, the shadow atlas's out-of-date tiles are redrawn one after another, and each tile in
//! bands of rows over as many frames, so a frame's share of the atlas is bounded whatever the
//! preset: [`BAND_TEXELS`] texels (`low`'s 256-texel tile in two bands, `ultra`'s 1,024-texel
//! tile in 32), where a whole tile had cost a frame of `high` 410 ms and of `ultra` 1.5 s in
//! the browser benchmark.
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
    /// The tile drawn (`count` when none is out of date), the corner of its square in the
    /// atlas (texels, the shadow pass's frag-coord space), and the rows of it drawn this frame,
    /// into the back atlas: `height` rows from its row `top`.
    pub tile: u32,
    pub x: u32,
    pub y: u32,
    pub top: u32,
    pub height: u32,
    /// 1 when they are the tile's first band: take the copy of the block the tile's bands are
    /// drawn from (and the sun's lookup and the anchor it is kept with) before drawing them.
    pub first: u32,
    /// 1 when they are its last: copy the tile's square from the back atlas into the one the clouds
    /// read, and keep the copied block's transform for the tile (`redrawn_tiles`).
    pub last: u32,
}

/// Rows of a tile of `side` texels drawn per frame: [`BAND_TEXELS`] texels, at least one row,
/// at most the tile.
#[shader_fn]
pub fn band_rows(side: u32) -> u32 {
    let rows = BAND_TEXELS / select(side, 1u32, side == 0u32);
    select(select(rows, side, rows > side), 1u32, rows == 0u32)
}

/// Bands a tile of `side` texels is drawn in (the last may be shorter).
#[shader_fn]
pub fn tile_bands(side: u32) -> u32 {
    let rows = band_rows(side);
    let whole = side / rows;
    whole + select(0u32, 1u32, whole * rows < side)
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

/// This frame's band of the redraw of `count` tiles of `side` texels in rotation: the next band
/// of the tile in progress, or the first of the first out-of-date tile from where the rotation
/// stands.
#[shader_fn]
pub fn band_redraw(s: TileRedraw, count: u32, side: u32) -> BandDraw {
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
    let rows = band_rows(side);
    let top = s.band * rows;
    let height = select(rows, side - top, side - top < rows);
    let columns = atlas_columns(count);
    let x = (tile % columns) * side;
    let y = (tile / columns) * side;
    let done = s.band + 1u32 >= tile_bands(side);
    BandDraw {
        state: TileRedraw {
            stale,
            tile,
            band: select(s.band + 1u32, 0u32, done),
            next: select(s.next, (tile + 1u32) % count, done),
        },
        tile,
        x,
        y,
        top,
        height,
        first,
        last: select(0u32, 1u32, done),
    }
}
