//! A scene file's bytes over the cumulus genus: if accepted, its derived keys generate and
//! naga validates them for every target.
#![no_main]
const GENUS: &str = include_str!("../../examples/genera/cumulus.toml");
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let genus = GENUS.replace("name = \"cumulus\"", "name = \"fuzzed\"");
    nimbus_testkit::fuzz::scene_codegen(data, &genus, &nimbus_codegen::Target::ALL);
});
