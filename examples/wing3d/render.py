"""A ParaView picture of the adapted wing (pvpython, under xvfb-run where there is no
display): the wing's triangles with their edges, coloured by the smallest size the
field asks along it there (the middle of h1, h2, h3: the smallest is across the wall),
and the cut y = 0.75 of the tetrahedra near the wing with their edges, seen from above
the tip, downstream.

    xvfb-run -a pvpython examples/wing3d/render.py target/examples/wing3d/adapted.vtu OUT.png
"""
import sys

from paraview.simple import *  # noqa: F401,F403

WING = 1  # the physical tag of the surface Wing (geometry.py)

vtu, png = sys.argv[1], sys.argv[2]
reader = XMLUnstructuredGridReader(FileName=[vtu])
# The middle of the three sizes: on the wing, the smaller size along it (the smallest
# is the wall's, across it).
hmid = Calculator(Input=reader, ResultArrayName="h_mid")
hmid.Function = "h1 + h2 + h3 - max(max(h1, h2), h3) - min(min(h1, h2), h3)"
tris = ExtractCellsByType(Input=hmid)
tris.CellTypes = ["Triangle"]
wing = Threshold(Input=tris, Scalars=["CELLS", "gmsh:physical"])
wing.LowerThreshold, wing.UpperThreshold = WING - 0.5, WING + 0.5
tets = ExtractCellsByType(Input=hmid)
tets.CellTypes = ["Tetrahedron"]
cut = Slice(Input=tets)
cut.SliceType.Origin = [0.0, 0.75, 0.0]
cut.SliceType.Normal = [0.0, 1.0, 0.0]
# The cut within [-0.6, 2.2] x [-0.5, 0.5] in (x, z): four plane clips.
clip = cut
for origin, normal in (([-0.6, 0, 0], [1, 0, 0]), ([2.2, 0, 0], [-1, 0, 0]),
                       ([0, 0, -0.5], [0, 0, 1]), ([0, 0, 0.5], [0, 0, -1])):
    clip = Clip(Input=clip)
    clip.ClipType = "Plane"
    clip.ClipType.Origin = origin
    clip.ClipType.Normal = normal
    clip.Invert = 0

view = CreateView("RenderView")
view.ViewSize = [1400, 900]
view.UseColorPaletteForBackground = 0
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
lut = GetColorTransferFunction("h_mid")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.UseLogScale = 1
for src, opacity in ((wing, 1.0), (clip, 1.0)):
    d = Show(src, view)
    d.Representation = "Surface With Edges"
    d.EdgeColor = [0.15, 0.15, 0.15]
    ColorBy(d, ("POINTS", "h_mid"))
    d.LookupTable = lut
    d.Opacity = opacity
lut.AutomaticRescaleRangeMode = "Never"
lut.RescaleTransferFunction(0.005, 0.2)
bar = GetScalarBar(lut, view)
bar.Title = "size asked along the wing"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.Visibility = 1
cam = view.GetActiveCamera()
cam.SetFocalPoint(0.7, 0.9, -0.05)
cam.SetPosition(2.0, 2.5, 1.1)
cam.SetViewUp(0.0, 0.0, 1.0)
view.CameraParallelProjection = 0
Render(view)
SaveScreenshot(png, view, ImageResolution=[1400, 900])
