use nimbus_dsl::prelude::*;

#[shader_fn]
fn identity<T>(x: T) -> T {
    x
}

fn main() {}
