use nimbus_dsl::prelude::*;

#[shader_fn]
fn unbounded(x: f32) -> f32 {
    let mut y = x;
    while y > 1.0 {
        y = y * 0.5;
    }
    y
}

fn main() {}
