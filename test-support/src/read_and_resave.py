# For each .msh file given: the number of cells meshio reads (or its error message), and
# the elements of each Gmsh type that Gmsh reads before and after saving the file again
# in its own version; one JSON list on the last line. Used by the interop tests.
import sys, json, os, tempfile, gmsh, meshio
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
def counts():
    c = {}
    for d, t in gmsh.model.getEntities():
        types, etags, _ = gmsh.model.mesh.getElements(d, t)
        for ty, e in zip(types, etags):
            c[str(int(ty))] = c.get(str(int(ty)), 0) + len(e)
    return c
out = []
for path in sys.argv[1:]:
    try:
        m = meshio.read(path)
        mio = sum(len(b.data) for b in m.cells)
    except Exception as e:
        mio = str(e)
    version = float(open(path, "rb").read(40).split()[1])
    gmsh.clear()
    gmsh.open(path)
    before = counts()
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    again = os.path.join(tempfile.mkdtemp(), "again.msh")
    gmsh.write(again)
    gmsh.clear()
    gmsh.open(again)
    out.append({"meshio": mio, "before": before, "after": counts()})
print(json.dumps(out))
gmsh.finalize()
