//! A genus file's bytes: parsed and validated, or refused; never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| nimbus_testkit::fuzz::genus_parser(data));
