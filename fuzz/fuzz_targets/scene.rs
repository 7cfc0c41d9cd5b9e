//! The scene parsers of both models on arbitrary text: a scene or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = fem::Scene::from_toml_str(text);
        let _ = spectral::Scene::from_toml_str(text);
    }
});
