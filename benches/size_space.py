#!/usr/bin/env python3
"""`smartmesh size` on a mesh in space: whole-process time and peak memory.

A unit box with a spherical hole (radius 0.2) meshed by Gmsh (HXT) at a uniform size
H, the sphere a named surface; a recipe of one DISTANCE_TO_BORDER step on it (a wall
layer 0.005 across, 0.03 along, growing to 0.15 at 0.5 away). `size` is run on 1 and
2 threads (RAYON_NUM_THREADS) writing a `.solb`, timed with /usr/bin/time (wall, CPU,
peak resident memory); the two outputs must be the same bytes. `convert` of the mesh
to `.meshb` is timed beside it: the read and write alone. `--keep DIR` leaves the mesh
and the recipe in DIR (mesh.msh, wall.toml), for the split of `size`'s time by phase
(benches/adapt_space.rs with ADAPT_SPACE_ITERATIONS=0).

    cargo build --release
    python3 benches/size_space.py [--h 0.009] [--smartmesh target/release/smartmesh] [--keep DIR]
"""
import argparse, filecmp, os, subprocess, sys, tempfile

RECIPE = """[global]
h_max = 0.15

[regions]
sph = ["Sphere"]

[functions.perp]
kind = "distance"
size_at_source = 0.005
size_at_max_distance = 0.15
max_distance = 0.5
exponent = 1.0

[functions.par]
kind = "distance"
size_at_source = 0.03
size_at_max_distance = 0.15
max_distance = 0.5
exponent = 1.0

[[algorithms]]
type = "distance_to_border"
regions = ["sph"]
perpendicular = "perp"
parallel = "par"
"""


def make_mesh(h, path):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("box-sphere")
    box = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    ball = gmsh.model.occ.addSphere(0.5, 0.5, 0.5, 0.2)
    out, _ = gmsh.model.occ.cut([(3, box)], [(3, ball)])
    gmsh.model.occ.synchronize()
    faces = [f[1] for f in gmsh.model.getBoundary(out, oriented=False)]
    sphere = [f for f in faces if gmsh.model.getType(2, f) == "Sphere"]
    gmsh.model.addPhysicalGroup(2, sphere, 1, "Sphere")
    gmsh.model.addPhysicalGroup(2, [f for f in faces if f not in sphere], 2, "Box")
    gmsh.model.addPhysicalGroup(3, [out[0][1]], 3, "Fluid")
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(path)
    gmsh.finalize()


def timed(cmd, env=None):
    fmt = "%e %U %S %M"
    r = subprocess.run(["/usr/bin/time", "-f", fmt] + cmd, env=env,
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{r.stderr}")
    wall, user, sys_, rss = r.stderr.strip().splitlines()[-1].split()
    return float(wall), float(user) + float(sys_), int(rss) / 1024


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--h", type=float, default=0.009)
    ap.add_argument("--smartmesh", default="target/release/smartmesh")
    ap.add_argument("--keep", help="leave mesh.msh and wall.toml in this directory")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        d = a.keep or tmp
        os.makedirs(d, exist_ok=True)
        mesh, recipe = os.path.join(d, "mesh.msh"), os.path.join(d, "wall.toml")
        make_mesh(a.h, mesh)
        with open(recipe, "w") as f:
            f.write(RECIPE)
        info = subprocess.run([a.smartmesh, "info", mesh], capture_output=True, text=True).stdout
        print("\n".join(info.splitlines()[1:3]))
        outs = []
        for t in (1, 2):
            out = os.path.join(tmp, f"f{t}.solb")
            env = dict(os.environ, RAYON_NUM_THREADS=str(t))
            wall, cpu, rss = timed([a.smartmesh, "-q", "size", mesh, "--recipe", recipe, "-o", out], env)
            print(f"size, {t} thread(s): wall {wall:.2f} s, CPU {cpu:.2f} s, peak {rss:.0f} MiB")
            outs.append(out)
        print("same bytes on 1 and 2 threads:", filecmp.cmp(outs[0], outs[1], shallow=False))
        wall, cpu, rss = timed([a.smartmesh, "-q", "convert", mesh, os.path.join(tmp, "c.meshb")])
        print(f"convert to .meshb (read and write only): wall {wall:.2f} s, CPU {cpu:.2f} s, peak {rss:.0f} MiB")


if __name__ == "__main__":
    main()
