// A vec3 plus a u32 is a type error in the shader twin (and in WGSL).
use nimbus_dsl::shader::{U32, Vec3};

fn add(v: Vec3, n: U32) -> Vec3 {
    v + n
}

fn main() {}
