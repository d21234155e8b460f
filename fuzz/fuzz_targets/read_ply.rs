//! PLY bytes (ascii, binary LE/BE) through every reader entry point.
#![no_main]

mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    common::read_everything("input.ply", data);
});
