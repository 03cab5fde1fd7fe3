//! The STL reader (binary and ASCII) and mesh builder on arbitrary bytes,
//! in memory.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raytrace::formats::stl;
use raytrace::shapes::MeshData;

fuzz_target!(|data: &[u8]| {
    if let Ok(soup) = stl::parse(data) {
        let mesh = MeshData::from_soup(soup);
        let _ = mesh.bounds();
        let _ = mesh.is_closed();
    }
});
