#!/usr/bin/env python3
"""How far a flow's rock has run, sample by sample, from a `--series` run (docs/flow.md,
"The eruption on the implicit flow"): per sample its time, the rock alive, the share that
is crust, the front (the 99th percentile of the rock's distance from the vertical axis
through ORIGIN_X,ORIGIN_Z, so that a stray particle does not count), and the liquid's median
and 99th-percentile speed. Reads the collection with VTK's own XML reader (Debian's
python3-vtk9).

Usage: flow_front.py DIR.pvd [ORIGIN_X ORIGIN_Z]"""
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader


def sample(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    if data.GetNumberOfPoints() == 0:
        return None
    arrays = {"points": vtk_to_numpy(data.GetPoints().GetData())}
    point_data = data.GetPointData()
    for i in range(point_data.GetNumberOfArrays()):
        arrays[point_data.GetArrayName(i)] = vtk_to_numpy(point_data.GetArray(i))
    return arrays


def main():
    if len(sys.argv) not in (2, 4):
        sys.exit(__doc__)
    pvd = sys.argv[1]
    ox, oz = (float(sys.argv[2]), float(sys.argv[3])) if len(sys.argv) == 4 else (0.0, 0.0)
    folder = os.path.dirname(os.path.abspath(pvd))
    print(f"{'t (s)':>7} {'rock':>6} {'crust':>6} {'front (m)':>10} "
          f"{'median (m/s)':>13} {'p99 (m/s)':>10}")
    for entry in ET.parse(pvd).getroot().iter("DataSet"):
        arrays = sample(os.path.join(folder, entry.get("file")))
        t = float(entry.get("timestep"))
        if arrays is None or "temperature" not in arrays:
            print(f"{t:7.1f} {0:6d}")
            continue
        rock = arrays["temperature"] > 0.0  # the flow's particles alive carry a temperature
        n = int(rock.sum())
        if n == 0:
            print(f"{t:7.1f} {0:6d}")
            continue
        p = arrays["points"][rock]
        crust = arrays["crust"][rock] > 0
        radius = np.hypot(p[:, 0] - ox, p[:, 2] - oz)
        speed = arrays["speed"][rock][~crust]
        median = np.median(speed) if speed.size else 0.0
        fast = np.percentile(speed, 99) if speed.size else 0.0
        print(f"{t:7.1f} {n:6d} {100.0 * crust.mean():5.1f}% {np.percentile(radius, 99):10.3f} "
              f"{median:13.3f} {fast:10.3f}")


if __name__ == "__main__":
    main()
