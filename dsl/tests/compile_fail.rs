//! What must not compile: type errors a shader compiler would report (rustc reports them
//! instead) and Rust syntax `#[shader_fn]` cannot translate (the error points at that syntax).
//! The messages are pinned in tests/ui/*.stderr.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
