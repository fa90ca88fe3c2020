"""Renders docs/images/isosurface_lox.png: the isosurface Pressure = 0.8 of the LOX post dataset
(../shared/data/volume) as `topotet simplify --isosurface` keeps it: embedded in the input (the
tets it crosses split, its triangles listed), then at 10% and 2% of the vertices. Its topology (Betti
numbers [8, 0, 0, 0]) and its vertices' value are kept at every level; the labels give the triangle
counts and the checker's verdict. Regenerate (docs/cli.md#isosurfaces):

    xvfb-run -a -s "-screen 0 1600x1000x24" pvbatch scripts/isosurface_image.py \\
        build/cli/topotet ../shared/data/volume/lox_post_tets.mesh.gz docs/images/isosurface_lox.png

(pvbatch needs an X server to render with Debian's ParaView: xvfb-run gives it one. Any topotet
build works; its outputs are read with ParaView's own readers.)
"""
import os
import re
import subprocess
import sys
import tempfile

from paraview.simple import (CreateView, Outline, Render, SaveScreenshot, Show, Text, Transform,
                             XMLPolyDataReader, XMLUnstructuredGridReader)

topotet, lox, image = sys.argv[1:4]
work = tempfile.mkdtemp(prefix="topotet_isosurface_")
LEVEL = "Pressure=0.8"


def simplify(ratio):
    """The output .vtu (and its _substructures.vtp) at `ratio`, and the report's topology verdict."""
    out = os.path.join(work, "lox_%g.vtu" % ratio)
    run = subprocess.run([topotet, "simplify", lox, "-o", out, "--ratio", str(ratio), "--isosurface", LEVEL,
                          "--threads", "2"], check=True, capture_output=True, text=True)
    verdict = re.search(r"^topology\s+(\w+)", run.stdout, re.M)
    return out, verdict.group(1) if verdict else "not checked"


view = CreateView("RenderView")
view.ViewSize = [1500, 520]
view.OrientationAxesVisibility = 0
view.Background = [1.0, 1.0, 1.0]
view.UseColorPaletteForBackground = 0

panels = [(1.0, "embedded in the input"), (0.1, "10% of the vertices"), (0.02, "2% of the vertices")]
width = None
for i, (ratio, title) in enumerate(panels):
    mesh, verdict = simplify(ratio)
    volume = XMLUnstructuredGridReader(FileName=[mesh])
    surfaces = XMLPolyDataReader(FileName=[mesh[:-4] + "_substructures.vtp"])
    surfaces.UpdatePipeline()
    volume.UpdatePipeline()
    if width is None:
        bounds = volume.GetDataInformation().GetBounds()
        width = 1.25 * (bounds[1] - bounds[0])
    triangles = surfaces.GetDataInformation().GetNumberOfCells()
    for source, representation in ((surfaces, "Surface With Edges"), (Outline(Input=volume), "Surface")):
        moved = Transform(Input=source)
        moved.Transform.Translate = [i * width, 0.0, 0.0]
        shown = Show(moved, view)
        shown.SetRepresentationType(representation)
        shown.ColorArrayName = [None, ""]  # one solid color
        shown.AmbientColor = shown.DiffuseColor = [0.85, 0.55, 0.3] if source is surfaces else [0.3, 0.3, 0.3]
        shown.EdgeColor = [0.45, 0.28, 0.15]
    label = Text(Text="%s: %d triangles, topology %s" % (title, triangles, verdict))
    shown = Show(label, view)
    shown.WindowLocation = "Any Location"
    shown.Position = [0.02 + i / 3.0, 0.92]
    shown.FontSize = 12
    shown.Color = [0.1, 0.1, 0.1]

# From above the panels' row (the dataset is flat in z), a little tilted, without perspective.
view.CameraParallelProjection = 1
view.CameraFocalPoint = [width, 0.0, 0.0]
view.CameraPosition = [width, -60.0, 100.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
Render(view)
view.ResetCamera()
view.CameraParallelScale = 0.45 * view.CameraParallelScale
Render(view)
SaveScreenshot(image, view, ImageResolution=[1500, 520], CompressionLevel="9")
print("wrote", image)
