//! E57 bytes through every reader entry point.
#![no_main]

mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    common::read_everything("input.e57", data);
});
