use nimbus_dsl::prelude::*;

#[shader_fn]
fn with_closure(x: f32) -> f32 {
    let double = |v: f32| v * 2.0;
    double(x)
}

fn main() {}
