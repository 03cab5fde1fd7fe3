//! The PLY reader and mesh builder on arbitrary bytes, in memory.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = raytrace::shapes::MeshData::from_bytes(data) {
        let _ = mesh.bounds();
        let _ = mesh.is_closed();
    }
});
