//! The MIT Push Dataset HDF5 importer (parse, clean, resample) must turn any bytes into a push or
//! an error.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::mit_push(data, "h5"));
