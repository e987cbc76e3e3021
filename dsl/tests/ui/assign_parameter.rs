use nimbus_dsl::prelude::*;

#[shader_fn]
fn clobber(x: f32) -> f32 {
    let y = x;
    y = 2.0;
    y
}

fn main() {}
