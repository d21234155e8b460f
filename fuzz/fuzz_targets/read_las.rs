//! LAS/LAZ bytes through every reader entry point.
#![no_main]

mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    // The LASzip VLR decides between LAS and LAZ decoding, so one name serves both.
    common::read_everything("input.las", data);
});
