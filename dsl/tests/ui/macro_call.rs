use nimbus_dsl::prelude::*;

#[shader_fn]
fn debug(x: f32) -> f32 {
    println!("{x}");
    x
}

fn main() {}
