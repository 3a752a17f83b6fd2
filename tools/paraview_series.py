"""A Lava series (`lava simulate --series DIR --every K`) rendered by ParaView, headless: the
last sample, the flow's particles as gaussian splats coloured by temperature (black body,
900 to 1500 K), the sparks as small dots. Makes docs/paraview-eruption.png (docs/flow.md,
"Study a run in ParaView"). Run by hand, not in CI (ParaView is 440 MB installed):

    apt-get install --no-install-recommends paraview python3-paraview
    build/lava simulate --scene scenes/eruption-explicit.toml --steps 8000 --backend cpu-simd \\
        --series /tmp/eruption --every 200
    xvfb-run -a pvpython tools/paraview_series.py /tmp/eruption.pvd docs/paraview-eruption.png
"""
import sys

from paraview import simple as pv

pvd, png = sys.argv[1], sys.argv[2]
reader = pv.PVDReader(FileName=pvd)
last = reader.TimestepValues[-1]
view = pv.CreateView("RenderView")
view.ViewSize = [1280, 720]
view.ViewTime = last
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.03, 0.03, 0.05]

# The flow: emitter 1 of the eruption (the sparks are emitter 0).
rock = pv.Threshold(Input=reader, Scalars=["POINTS", "emitter"], LowerThreshold=1,
                    UpperThreshold=1000)
shown = pv.Show(rock, view)
shown.SetRepresentationType("Point Gaussian")
shown.GaussianRadius = 0.05
shown.ShaderPreset = "Sphere"
shown.Ambient, shown.Diffuse = 0.6, 0.5  # the rock glows: its colour is its heat
pv.ColorBy(shown, ("POINTS", "temperature"))
heat = pv.GetColorTransferFunction("temperature")
heat.ApplyPreset("Black-Body Radiation", True)
heat.RescaleTransferFunction(900.0, 1500.0)
shown.SetScalarBarVisibility(view, True)
bar = pv.GetScalarBar(heat, view)
bar.Title = "temperature (K)"
bar.ComponentTitle = ""

sparks = pv.Threshold(Input=reader, Scalars=["POINTS", "emitter"], LowerThreshold=0,
                      UpperThreshold=0)
dots = pv.Show(sparks, view)
dots.SetRepresentationType("Points")
dots.PointSize = 1.5
dots.Opacity = 0.6
pv.ColorBy(dots, None)
dots.AmbientColor = dots.DiffuseColor = [1.0, 0.55, 0.15]

pv.Render(view)  # the first render places the camera; then ours
view.CameraPosition = [4.2, 2.2, 3.0]
view.CameraFocalPoint = [1.1, 0.25, 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = 30
pv.Render(view)
pv.SaveScreenshot(png, view, ImageResolution=[1280, 720])
print("%s: the sample at t = %g s of %d" % (png, last, len(reader.TimestepValues)))
