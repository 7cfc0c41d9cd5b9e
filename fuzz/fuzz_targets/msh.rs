//! The Gmsh MSH 4.1 reader on arbitrary bytes: it returns a mesh or an error, never panics.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = fem::gmsh::UnstructuredMesh::from_msh_bytes(data);
});
