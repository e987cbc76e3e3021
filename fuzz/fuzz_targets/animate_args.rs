//! `animate`'s arguments, one per line (the scene file of the examples first): parsed by the
//! command line's parser and planned, without a GPU or a write.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nimbus_cli::fuzz::animate_args(data);
});
