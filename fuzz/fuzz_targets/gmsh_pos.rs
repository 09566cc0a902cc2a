//! Fuzz target: the reader of Gmsh's parsed post-processing views (`.pos`) must return
//! Ok or Err on any bytes, never panic, and hand over only what it promises: records
//! inside a view, 3 coordinates per node, a non-zero multiple of the values per node,
//! finite numbers.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::gmsh::pos::{read_bytes, Item};

fuzz_target!(|data: &[u8]| {
    let mut open = false;
    let _ = read_bytes(data, &mut |item| {
        match item {
            Item::View { .. } => {
                assert!(!open, "a view begun inside another");
                open = true;
            }
            Item::Record(r) => {
                assert!(open, "a record outside a view");
                assert_eq!(r.coords.len(), 3 * r.element.nodes());
                let per_step = r.element.nodes() * r.field.components();
                assert!(!r.values.is_empty() && r.values.len() % per_step == 0);
                assert!(r.coords.iter().chain(r.values).all(|x| x.is_finite()));
            }
            Item::EndView => {
                assert!(open, "a view ended that never began");
                open = false;
            }
        }
        Ok(())
    });
});
