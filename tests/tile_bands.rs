//! Cascades in rotation, a band at a time (`model::tile_bands`): the bookkeeping every host
//! runs. Each out-of-date tile is drawn in bands that cover its rows once, in order, a band a
//! frame and never more than `BAND_TEXELS` texels; the rotation takes the tiles in turn; a
//! change while a tile is drawn leaves that tile to finish from its copy and marks it out of
//! date again; the air table is one tile in bands; and the JavaScript twin the engine packages
//! run takes the same steps.

mod common;

use nimbus_clouds::Quality;
use nimbus_clouds::model::air_table::air_table_size;
use nimbus_clouds::model::sun::host_module;
use nimbus_clouds::model::tile_bands::{
    BAND_TEXELS, BandDraw, TileRedraw, band_redraw, bands_of, tile_bands, tiles_out_of_date,
};
use nimbus_codegen::print_js;
use serde_json::{Value, json};

/// Every frame's step from `s` until nothing is out of date (at most `limit` frames), for
/// `count` square tiles of `side` texels.
fn run(s: TileRedraw, count: u32, side: u32, limit: usize) -> Vec<BandDraw> {
    run_tiles(s, count, side, side, limit)
}

/// [`run`] for tiles of `width` × `height` texels.
fn run_tiles(
    mut s: TileRedraw,
    count: u32,
    width: u32,
    height: u32,
    limit: usize,
) -> Vec<BandDraw> {
    let mut steps = Vec::new();
    for _ in 0..limit {
        let step = band_redraw(s, count, width, height);
        s = step.state;
        if step.height == 0 {
            break;
        }
        steps.push(step);
    }
    steps
}

/// Sides the presets use and some they do not (a band that does not divide the tile).
const SIDES: [u32; 6] = [64, 256, 300, 512, 1024, 2048];

#[test]
fn every_tile_is_drawn_once_in_bands_that_cover_its_rows() {
    for count in 1..=4u32 {
        for side in SIDES {
            let bands = tile_bands(side);
            let start = tiles_out_of_date(TileRedraw::default(), count);
            let steps = run(start, count, side, 10_000);
            assert_eq!(
                steps.len() as u32,
                count * bands,
                "{count} tiles of {side}: a band a frame"
            );
            let columns = if count > 1 { 2 } else { 1 };
            for (k, tile) in steps.chunks(bands as usize).enumerate() {
                let k = k as u32;
                let mut row = 0;
                for (b, step) in tile.iter().enumerate() {
                    assert_eq!(step.tile, k, "tiles in turn");
                    assert_eq!(
                        (step.x, step.y),
                        ((k % columns) * side, (k / columns) * side)
                    );
                    assert_eq!(step.top, row, "{count}×{side}: band {b} of tile {k}");
                    assert!(step.height > 0 && step.height * side <= BAND_TEXELS.max(side));
                    assert_eq!(step.first, u32::from(b == 0));
                    assert_eq!(step.last, u32::from(b + 1 == bands as usize));
                    row += step.height;
                }
                assert_eq!(row, side, "{count}×{side}: tile {k}'s rows");
            }
            let end = steps.last().expect("steps").state;
            assert_eq!((end.stale, end.band), (0, 0), "{count}×{side}: all drawn");
        }
    }
    // The presets' own: a band a frame of at most BAND_TEXELS texels.
    for q in Quality::ALL {
        let s = q.settings();
        let rows = s.shadow_map_size / tile_bands(s.shadow_map_size);
        println!(
            "{}: {} tiles of {} texels, {} bands each ({} rows, {} texels a frame)",
            q.name(),
            s.shadow_cascade_count,
            s.shadow_map_size,
            tile_bands(s.shadow_map_size),
            rows,
            rows * s.shadow_map_size
        );
        assert!(rows * s.shadow_map_size <= BAND_TEXELS);
    }
}

/// The air table is one tile, wider than a band's texels allow in one row set: 128 rows of
/// its 256 a frame, three bands (its Rayleigh, Mie and optical-depth bands).
#[test]
fn the_air_table_is_one_tile_in_bands() {
    let (w, h) = air_table_size();
    let start = tiles_out_of_date(TileRedraw::default(), 1);
    let steps = run_tiles(start, 1, w, h, 100);
    let rows: Vec<(u32, u32, u32, u32)> = steps
        .iter()
        .map(|d| (d.top, d.height, d.first, d.last))
        .collect();
    println!("air table {w}×{h}: bands (top, rows, first, last) {rows:?}");
    assert_eq!(rows.iter().map(|r| r.1).sum::<u32>(), h);
    assert!(
        steps
            .iter()
            .all(|d| d.x == 0 && d.y == 0 && d.height * w <= BAND_TEXELS)
    );
    assert_eq!(rows.first().map(|r| r.2), Some(1));
    assert_eq!(rows.last().map(|r| r.3), Some(1));
    assert_eq!(steps.len() as u32, bands_of(w, h));
    assert!(
        steps.len() > 1,
        "the air table is drawn in more than one band"
    );
}

#[test]
fn a_change_while_a_tile_is_drawn_lets_it_finish_and_marks_it_again() {
    let (count, side) = (3, 512);
    let bands = tile_bands(side);
    let mut s = tiles_out_of_date(TileRedraw::default(), count);
    // Tile 0 and half of tile 1 drawn.
    for _ in 0..bands + bands / 2 {
        s = band_redraw(s, count, side, side).state;
    }
    assert_eq!((s.tile, s.band), (1, bands / 2));
    assert_eq!(s.stale, 0b100, "tiles 0 and 1 taken, tile 2 waits");
    let unchanged = s;
    // The sun moves: every tile out of date again, tile 1 goes on from its copy.
    s = tiles_out_of_date(s, count);
    let steps = run(s, count, side, 10_000);
    let order: Vec<(u32, u32)> = steps
        .iter()
        .filter(|d| d.first == 1)
        .map(|d| (d.tile, d.top))
        .collect();
    assert_eq!(steps[0].tile, 1, "the tile in progress finishes first");
    assert_eq!(steps[0].first, 0, "from its copy");
    // Then 2, 0 and 1 again from where the rotation stands.
    assert_eq!(order, [(2, 0), (0, 0), (1, 0)]);
    assert_eq!(steps.len() as u32, bands / 2 + count * bands);
    // The control: without the change, tile 2 alone follows, tiles 0 and 1 are left as drawn.
    let control: Vec<(u32, u32)> = run(unchanged, count, side, 10_000)
        .iter()
        .filter(|d| d.first == 1)
        .map(|d| (d.tile, d.top))
        .collect();
    assert_eq!(control, [(2, 0)]);
}

#[test]
fn the_javascript_twin_takes_the_same_steps() {
    if !nimbus_testkit::skip::browser_tools_present(
        "the JavaScript twin test of the bands in rotation",
        nimbus_testkit::skip::node_missing(),
    ) {
        return;
    }
    let module = host_module().expect("records");
    let js = print_js(&module, &["tiles_out_of_date", "band_redraw"]).expect("prints");
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("sun.mjs"), &js).expect("write module");
    let cases: Vec<(u32, u32)> = (1..=4u32)
        .flat_map(|c| SIDES.iter().map(move |&s| (c, s)))
        .collect();
    std::fs::write(
        dir.path().join("run.mjs"),
        format!(
            "import {{ tiles_out_of_date, band_redraw }} from './sun.mjs';\n\
             const cases = {cases};\n\
             console.log(JSON.stringify(cases.map(([count, side]) => {{\n\
               let s = tiles_out_of_date({{ stale: 0, tile: 0, band: 0, next: 0 }}, count);\n\
               const steps = [];\n\
               for (let i = 0; i < 10000; i++) {{\n\
                 const d = band_redraw(s, count, side, side);\n\
                 s = d.state;\n\
                 if (d.height === 0) break;\n\
                 steps.push([d.tile, d.x, d.y, d.top, d.height, d.first, d.last, s.stale, s.tile, s.band, s.next]);\n\
               }}\n\
               return steps;\n\
             }})));\n",
            cases = json!(cases),
        ),
    )
    .expect("write runner");
    let results = common::run_node_json(&dir.path().join("run.mjs"), &js);
    let mut compared = 0;
    for ((count, side), got) in cases.iter().zip(results.as_array().expect("results")) {
        let start = tiles_out_of_date(TileRedraw::default(), *count);
        let want: Vec<Value> = run(start, *count, *side, 10_000)
            .iter()
            .map(|d| {
                let s = d.state;
                json!([
                    d.tile, d.x, d.y, d.top, d.height, d.first, d.last, s.stale, s.tile, s.band,
                    s.next
                ])
            })
            .collect();
        assert_eq!(got, &Value::Array(want), "{count} tiles of {side}");
        compared += got.as_array().map_or(0, Vec::len);
    }
    println!("JavaScript and CPU twins: the same {compared} steps");
    assert!(compared > 100);
}
