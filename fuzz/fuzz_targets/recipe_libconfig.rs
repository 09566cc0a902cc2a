//! Fuzz target: the libconfig recipe reader (the parser, the keywords of appendix A and
//! validation) must return Ok or Err on any text — no panic, no stack overflow however
//! deep the nesting — and a recipe it accepts must write back to libconfig and read
//! again as the same recipe.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use smartmesh::recipe::{ReadOptions, Recipe, RecipeFormat};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    // No preprocessor and no @include: the target reads no file and starts no process
    // (cpp and the include caps have their own tests in tests/recipe.rs).
    let options = ReadOptions::untrusted();
    let read = |text: &str, name: &str| {
        Recipe::from_str_with(text, RecipeFormat::Libconfig, Path::new(name), &options)
    };
    if let Ok(recipe) = read(text, "fuzz.cfg") {
        let written = recipe.to_libconfig();
        match read(&written, "written.cfg") {
            Ok(again) => assert_eq!(again, recipe, "{written}"),
            Err(e) => panic!("the written recipe does not read back: {e}\n{written}"),
        }
    }
});
