use nimbus_dsl::prelude::*;

/// An ordinary Rust function: it has no shader twin.
fn helper(x: f32) -> f32 {
    x * 2.0
}

mod util {
    pub fn scaled(x: f32) -> f32 {
        x * 3.0
    }
}

#[shader_fn]
fn uses_helpers(x: f32) -> f32 {
    helper(x) + util::scaled(x)
}

fn main() {}
