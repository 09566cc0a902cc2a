//! Triangle's regional attributes are reals, and its own sample `la.poly` has attributes
//! (0.05, 0.2, ...) without an area column, which Triangle then reads as area bounds:
//! the mesher meshes it, keeps each region's attribute as the cell field
//! `triangle:attribute1` and bounds each region's triangles by it.

use smartmesh_test_support::formats as common;

use smartmesh::formats::{read_path, CellKind};
use smartmesh::mesher::{triangulate, MeshOptions};
use smartmesh_test_support::measure::signed_area;

#[test]
fn la_poly_meshes_with_its_attributes_as_a_field_and_area_bounds() {
    smartmesh_test_support::require_public_fixtures!();
    let input = read_path(&common::public_fixture("triangle/la.poly"), None).unwrap();
    let regions = input.regions.clone();
    assert_eq!(regions.len(), 6);
    assert_eq!(regions[0].attribute, 0.05);
    let out = triangulate(&input, &MeshOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let field = &out.cell_data["triangle:attribute1"];
    assert_eq!(field.len(), out.num_cells());
    let mut offset = 0;
    let mut seen = std::collections::BTreeSet::new();
    for b in &out.blocks {
        for (i, (cell, &tag)) in b.cells().zip(&b.physical).enumerate() {
            let a = field.values[offset + i];
            if b.kind != CellKind::Triangle {
                assert_eq!(a, 0.0);
                continue;
            }
            // Not all attributes are integers: none is a tag.
            assert_eq!(tag, 0);
            // 0 where no seed reaches (Triangle -pA leaves a part of la.poly so too).
            assert!(a == 0.0 || regions.iter().any(|r| r.attribute == a), "attribute {a}");
            if a == 0.0 {
                continue;
            }
            seen.insert(a.to_bits());
            let p = |k: usize| {
                let q = out.points[cell[k] as usize];
                [q[0], q[1]]
            };
            let area = signed_area(p(0), p(1), p(2));
            // The missing area column makes the attribute the bound, as in Triangle.
            assert!(area <= a * (1.0 + 1e-9), "a triangle of area {area} in region {a}");
        }
        offset += b.len();
    }
    // Every seeded layer of the cross-section is meshed with its own attribute.
    assert_eq!(seen.len(), 5, "0.05, 0.2, 0.4, 0.8 and 3");
}
