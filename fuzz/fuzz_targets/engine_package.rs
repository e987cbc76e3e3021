//! A scene file (the first byte picks the engine and the second): its engine package built in
//! memory, every pass validated by naga.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nimbus_cli::fuzz::engine_package(data);
});
