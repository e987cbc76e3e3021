//! A genus file's bytes: if accepted, every preset's keys generate and naga validates them
//! (WGSL, and each backend's translation).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nimbus_testkit::fuzz::genus_codegen(data, &nimbus_codegen::Target::ALL);
});
