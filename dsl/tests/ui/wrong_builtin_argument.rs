// `max` of an f32 and a vec3: rustc rejects the call's argument type.
use nimbus_dsl::shader::{F32, Vec3};

fn widest(x: F32, v: Vec3) -> F32 {
    x.max(v)
}

fn main() {}
