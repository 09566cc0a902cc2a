"""The unit cube meshed by Gmsh (PyPI gmsh 4.15.2): the start of the example, and the
uniform meshes it is compared with.

    python3 geometry.py OUT.msh SIZE

Physical groups: the six faces Walls (1), the volume Cube (10).
"""

import sys

import gmsh

out, size = sys.argv[1], float(sys.argv[2])
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("cube")
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], 1, "Walls")
gmsh.model.addPhysicalGroup(3, [1], 10, "Cube")
gmsh.option.setNumber("Mesh.MeshSizeMax", size)
gmsh.option.setNumber("Mesh.MeshSizeMin", size)
gmsh.model.mesh.generate(3)
gmsh.write(out)
gmsh.finalize()
