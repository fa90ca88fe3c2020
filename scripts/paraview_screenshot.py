"""Renders docs/images/paraview_simplify.png: ParaView with the plugin's "Simplify
(topology-preserving)" applied to topotet's generated cube-sphere (two materials), the original on
the left, the simplified mesh on the right, both cut open to show the inner material, surfaces
with edges, colored by material. Regenerate (docs/paraview.md):

    xvfb-run -a -s "-screen 0 1600x1000x24" pvbatch scripts/paraview_screenshot.py \\
        build-paraview/lib/topotet/paraview/TopotetSimplify/TopotetSimplify.so \\
        build-paraview/cli/topotet docs/images/paraview_simplify.png

(pvbatch needs an X server to render with Debian's ParaView: xvfb-run gives it one.)
"""
import os
import subprocess
import sys
import tempfile

from paraview.simple import (Clip, ColorBy, CreateView, GetColorTransferFunction, LoadPlugin, Render,
                             SaveScreenshot, Show, Text, Transform, XMLUnstructuredGridReader, servermanager)

plugin, topotet, image = sys.argv[1:4]
work = tempfile.mkdtemp(prefix="topotet_screenshot_")
mesh = os.path.join(work, "cube_sphere.vtu")
subprocess.run([topotet, "generate", "cube-sphere", "--tets", "20000", "-o", mesh], check=True,
               stdout=subprocess.DEVNULL)

LoadPlugin(plugin, remote=False, ns=globals())
original = XMLUnstructuredGridReader(FileName=[mesh])
simplified = Simplifytopologypreserving(Input=original)  # noqa: F821 (defined by LoadPlugin)
simplified.TargetRatio = 0.2
simplified.UpdatePipeline()
result = servermanager.Fetch(simplified)
summary_counts = result.GetFieldData().GetAbstractArray("topotet_vertices")
verdict = result.GetFieldData().GetAbstractArray("topotet_topology").GetValue(0)

view = CreateView("RenderView")
view.ViewSize = [1000, 470]
view.OrientationAxesVisibility = 0
view.Background = [1.0, 1.0, 1.0]
view.UseColorPaletteForBackground = 0


def cut_open(source, shift):
    """The half behind the plane y = 0.5 (the cut shows the inner material), moved right by shift."""
    clip = Clip(Input=source, ClipType="Plane", Invert=0)
    clip.ClipType.Origin = [0.5, 0.5, 0.5]
    clip.ClipType.Normal = [0.0, 1.0, 0.0]
    moved = Transform(Input=clip)
    moved.Transform.Translate = [shift, 0.0, 0.0]
    shown = Show(moved, view)
    shown.SetRepresentationType("Surface With Edges")
    ColorBy(shown, ("CELLS", "material"))
    shown.EdgeColor = [0.15, 0.15, 0.15]
    return shown


cut_open(original, 0.0)
cut_open(simplified, 1.35)
lut = GetColorTransferFunction("material")
lut.InterpretValuesAsCategories = 1
lut.Annotations = ["1", "1", "2", "2"]
lut.IndexedColors = [0.55, 0.70, 0.85, 0.90, 0.55, 0.35]

for text, x in (("original: %d vertices" % summary_counts.GetValue(0), 0.07),
                ("Simplify (topology-preserving), 20%%: %d vertices, topology %s"
                 % (summary_counts.GetValue(1), verdict), 0.47)):
    label = Text(Text=text)
    shown = Show(label, view)
    shown.WindowLocation = "Any Location"
    shown.Position = [x, 0.92]
    shown.FontSize = 13
    shown.Color = [0.1, 0.1, 0.1]

view.CameraPosition = [1.17, -1.9, 1.6]
view.CameraFocalPoint = [1.17, 0.5, 0.45]
view.CameraViewUp = [0.0, 0.35, 1.0]
Render(view)
view.ResetCamera()
view.GetActiveCamera().Dolly(1.5)
Render(view)
SaveScreenshot(image, view, ImageResolution=[1000, 470], CompressionLevel="9")
print("%s: original %d -> %d vertices, topology %s" % (image, summary_counts.GetValue(0), summary_counts.GetValue(1), verdict))
