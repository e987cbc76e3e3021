//! A scene file with a timeline (the first byte picks a second): taken at three times through the
//! scene loader every command uses; weights, sun and drift stay finite.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nimbus_cli::fuzz::timeline(data);
});
