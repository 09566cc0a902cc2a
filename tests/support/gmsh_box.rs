//! The unit cube meshed by Gmsh with named surfaces, curve, point and volume, the
//! input of the tests of `adapt` and `remesh` in space, and the signed volume of a
//! tetrahedron they check the results with.

/// The unit cube meshed by Gmsh with physical surfaces Left (x = 0, 1), Right (x = 1,
/// 2), Walls (the others, 3), the volume Solid (10), the curve Rim (the four edges of
/// the face x = 0, 20) and the point Origin (30).
pub(crate) const GMSH_BOX: &str = r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("box")
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
gmsh.model.occ.synchronize()
left, right, walls = [], [], []
for d, t in gmsh.model.getEntities(2):
    x = gmsh.model.occ.getCenterOfMass(d, t)[0]
    (left if x < 1e-9 else right if x > 1 - 1e-9 else walls).append(t)
gmsh.model.addPhysicalGroup(2, left, 1, "Left")
gmsh.model.addPhysicalGroup(2, right, 2, "Right")
gmsh.model.addPhysicalGroup(2, walls, 3, "Walls")
gmsh.model.addPhysicalGroup(3, [1], 10, "Solid")
rim = [t for d, t in gmsh.model.getBoundary([(2, left[0])], oriented=False)]
gmsh.model.addPhysicalGroup(1, rim, 20, "Rim")
origin = [t for d, t in gmsh.model.getEntities(0)
          if max(abs(c) for c in gmsh.model.getValue(0, t, [])) < 1e-9]
gmsh.model.addPhysicalGroup(0, origin, 30, "Origin")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
gmsh.model.mesh.generate(3)
gmsh.write(sys.argv[1])
gmsh.finalize()
"#;

/// Six times the signed volume of a tetrahedron.
pub(crate) fn volume6(p: [[f64; 3]; 4]) -> f64 {
    let d = |i: usize| [p[i][0] - p[0][0], p[i][1] - p[0][1], p[i][2] - p[0][2]];
    let (a, b, c) = (d(1), d(2), d(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}
