//! Cells without a physical tag in a mesh that has physical groups.
//!
//! Gmsh saves only the elements of physical groups when a model has any (unless
//! `Mesh.SaveAll`), and meshio's 4.1 reader gives `gmsh:physical` only to the blocks of
//! entities with a group, so that a file mixing both cannot be read
//! ("Incompatible cell data 'gmsh:physical'"). A physical tag of 0 is no way out: MSH
//! 2.2 reads it as "no group".
//!
//! The policy: when some cell has a physical tag and others of dimension `d` have none
//! (tag 0), those are written in a physical group of their own, numbered one above
//! every physical tag of dimension `d` in the mesh (cells, `entities`, names) and named
//! [`UNTAGGED`]; the write report says so. smartmesh reads a group of that name back
//! as tag 0, without the name, so its own round trips keep the mesh as it was, while
//! Gmsh and meshio see an ordinary group. A mesh with no physical tag at all is written
//! as it is: Gmsh then keeps every element, and meshio reads no `gmsh:physical`.

use std::borrow::Cow;

use crate::{TaggedMesh, WriteReport};

/// The name of the physical group that holds the cells without a physical tag.
pub const UNTAGGED: &str = "smartmesh:untagged";

/// The mesh to write: `mesh` itself, or a copy whose cells without a physical tag are in
/// groups of their own (one per dimension, see the module header), as the report says.
pub(super) fn grouped<'a>(mesh: &'a TaggedMesh, report: &mut WriteReport) -> Cow<'a, TaggedMesh> {
    let mut untagged = [0usize; 4];
    let mut any_group =
        mesh.entities.iter().any(|(&(d, _), l)| d <= 3 && l.iter().any(|&p| p != 0));
    for b in &mesh.blocks {
        let zeros = b.physical.iter().filter(|&&p| p == 0).count();
        untagged[b.kind.dim() as usize] += zeros;
        any_group |= zeros < b.physical.len();
    }
    if !any_group || untagged.iter().all(|&n| n == 0) {
        return Cow::Borrowed(mesh);
    }
    // One above every physical tag of the dimension.
    let mut top = [0i64; 4];
    let mut see = |d: u8, p: i32| {
        if let Some(t) = top.get_mut(d as usize) {
            *t = (*t).max(p as i64);
        }
    };
    for b in &mesh.blocks {
        let d = b.kind.dim();
        b.physical.iter().for_each(|&p| see(d, p));
    }
    for (&(d, _), l) in &mesh.entities {
        l.iter().for_each(|&p| see(d, p));
    }
    for &(d, p) in mesh.tag_names.keys() {
        see(d, p);
    }
    let mut out = mesh.clone();
    for d in 0..4u8 {
        let n = untagged[d as usize];
        if n == 0 {
            continue;
        }
        let Ok(tag) = i32::try_from(top[d as usize] + 1) else {
            report.drop(format!("{n} {d}D cell(s) without a physical tag: no physical tag is free above the largest; written without a group (Gmsh does not keep them when it saves the file)"));
            continue;
        };
        for b in out.blocks.iter_mut().filter(|b| b.kind.dim() == d) {
            b.physical.iter_mut().filter(|p| **p == 0).for_each(|p| *p = tag);
        }
        out.tag_names.insert((d, tag), UNTAGGED.to_string());
        report.drop(format!(
            "{n} {d}D cell(s) without a physical tag written as physical group {tag} `{UNTAGGED}`: Gmsh keeps only the cells of physical groups, and meshio needs a group on every block; smartmesh reads them back as untagged (tag 0)"
        ));
    }
    Cow::Owned(out)
}

/// Undoes [`grouped`] on a mesh read: the cells of a group named [`UNTAGGED`] are
/// untagged again (tag 0), and the group is forgotten.
pub(super) fn ungroup(mesh: &mut TaggedMesh) {
    let groups: Vec<(u8, i32)> =
        mesh.tag_names.iter().filter(|(_, n)| n.as_str() == UNTAGGED).map(|(&k, _)| k).collect();
    for (d, tag) in groups {
        mesh.tag_names.remove(&(d, tag));
        for b in mesh.blocks.iter_mut().filter(|b| b.kind.dim() == d) {
            b.physical.iter_mut().filter(|p| **p == tag).for_each(|p| *p = 0);
        }
        for (_, l) in mesh.entities.range_mut((d, i32::MIN)..=(d, i32::MAX)) {
            l.retain(|&p| p != tag);
        }
    }
}
