use nimbus_dsl::prelude::*;

#[shader_fn]
fn nothing(x: f32) {
    let _y = x;
}

fn main() {}
