use nimbus_dsl::prelude::*;

#[shader_fn]
fn pair(x: f32) -> f32 {
    let (a, b) = (x, x);
    a + b
}

fn main() {}
