# SPDX-License-Identifier: MIT
"""Check a fesph ParaView time series the way ParaView 5.11 reads it (no X display needed).

Usage: $PREFIX/usr/bin/pvpython tools/check_series.py RUN_DIR [--expect-steps N]
           [--expect-cell-arrays a,b] [--expect-point-arrays c,d] [--expect-particle-arrays e,f]

RUN_DIR/elements.pvd is required; RUN_DIR/particles.pvd is checked when present. An array may
be given as name:components; known names default to their component count. Prints one line
per check and ends with "N passed, M failed"; the exit code is 0 only when nothing failed.
Install pvpython with tools/install_paraview.sh and call it by its full path without PYTHONPATH.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
from paraview import servermanager as sm
from paraview.simple import OpenDataFile
from vtkmodules.util.numpy_support import vtk_to_numpy

VTK_TETRA = 10

# What SeriesWriter writes by default, and how many components each array has.
ELEMENT_CELL_ARRAYS = ("stress,pressure,von_mises,plastic_strain,plastic_strain_rate,"
                       "temperature,damage,density,body,element_id")
ELEMENT_POINT_ARRAYS = "velocity,displacement,node_id"
COMPONENTS = {name: 1 for name in (ELEMENT_CELL_ARRAYS + "," + ELEMENT_POINT_ARRAYS).split(",")}
COMPONENTS.update(stress=6, velocity=3, displacement=3)


class Checks:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, what):
        ok = bool(ok)
        print(("PASS  " if ok else "FAIL  ") + what)
        if ok:
            self.passed += 1
        else:
            self.failed += 1
        return ok


def array_spec(text):
    """'a,b:3' -> [('a', default components or None), ('b', 3)]."""
    spec = []
    for item in filter(None, (s.strip() for s in text.split(","))):
        name, _, comps = item.partition(":")
        spec.append((name, int(comps) if comps else COMPONENTS.get(name)))
    return spec


def check_arrays(checks, label, data, spec):
    for name, comps in spec:
        array = data.GetAbstractArray(name)
        got = array.GetNumberOfComponents() if array is not None else None
        if comps is None:
            checks.check(array is not None, f"{label}: array '{name}' present")
        elif array is None:
            checks.check(False, f"{label}: array '{name}' present with {comps} components")
        else:
            checks.check(got == comps, f"{label}: array '{name}' present with {got} "
                         f"components (want {comps})")


def timestep_values(reader):
    values = reader.TimestepValues
    if values is None:
        return []
    # A single time step comes back as a plain float.
    return [float(v) for v in values] if hasattr(values, "__len__") else [float(values)]


def open_series(checks, pvd):
    """Reader and time list of a .pvd, after checking that every file it lists exists."""
    name = os.path.basename(pvd)
    try:
        files = [ds.get("file") for ds in ET.parse(pvd).getroot().iter("DataSet")]
    except ET.ParseError as err:
        checks.check(False, f"{name}: well-formed XML ({err})")
        return None, []
    folder = os.path.dirname(pvd)
    missing = [f for f in files if not os.path.isfile(os.path.join(folder, f))]
    checks.check(not missing, f"{name}: all {len(files)} listed files exist"
                 + (f" (missing: {', '.join(missing)})" if missing else ""))
    reader = OpenDataFile(pvd)
    if not checks.check(reader is not None, f"{name}: ParaView opens it"):
        return None, []
    times = timestep_values(reader)
    checks.check(len(times) == len(files),
                 f"{name}: {len(times)} time steps for {len(files)} listed files")
    checks.check(all(a < b for a, b in zip(times, times[1:])),
                 f"{name}: times strictly increasing {times}")
    return reader, times


def step_data(checks, label, reader, t):
    reader.UpdatePipeline(t)
    data = sm.Fetch(reader)
    tv = data.GetFieldData().GetArray("TimeValue")
    checks.check(tv is not None and tv.GetNumberOfTuples() == 1 and tv.GetValue(0) == t,
                 f"{label}: TimeValue field = {t}")
    return data


def check_elements(checks, pvd, expect_steps, cell_spec, point_spec):
    reader, times = open_series(checks, pvd)
    if reader is None:
        return
    if expect_steps is not None:
        checks.check(len(times) == expect_steps,
                     f"elements: {len(times)} time steps (want {expect_steps})")
    for t in times:
        label = f"elements t={t:g}"
        data = step_data(checks, label, reader, t)
        n = data.GetNumberOfCells()
        checks.check(n > 0, f"{label}: {n} cells > 0")
        types = vtk_to_numpy(data.GetCellTypesArray()) if n else np.empty(0)
        checks.check(np.all(types == VTK_TETRA), f"{label}: all cells are tets (type 10)")
        check_arrays(checks, label, data.GetCellData(), cell_spec)
        check_arrays(checks, label, data.GetPointData(), point_spec)


def check_particles(checks, pvd, point_spec):
    reader, times = open_series(checks, pvd)
    for t in times:
        label = f"particles t={t:g}"
        data = step_data(checks, label, reader, t)
        n = data.GetNumberOfPoints()
        if n == 0:
            print(f"info  {label}: no particles, arrays not checked")
            continue
        # One vertex cell per particle, or ParaView's Surface/Points views draw nothing.
        verts, cells = data.GetNumberOfVerts(), data.GetNumberOfCells()
        checks.check(verts == n and cells == n,
                     f"{label}: {n} particles, {verts} vertex cells of {cells} (want {n})")
        check_arrays(checks, label, data.GetPointData(), point_spec)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--expect-steps", type=int)
    parser.add_argument("--expect-cell-arrays", default=ELEMENT_CELL_ARRAYS)
    parser.add_argument("--expect-point-arrays", default=ELEMENT_POINT_ARRAYS)
    parser.add_argument("--expect-particle-arrays", default="")
    args = parser.parse_args()

    checks = Checks()
    elements = os.path.join(args.run_dir, "elements.pvd")
    if checks.check(os.path.isfile(elements), f"{elements} exists"):
        check_elements(checks, elements, args.expect_steps,
                       array_spec(args.expect_cell_arrays), array_spec(args.expect_point_arrays))
    particles = os.path.join(args.run_dir, "particles.pvd")
    if os.path.isfile(particles):
        check_particles(checks, particles, array_spec(args.expect_particle_arrays))

    print(f"{checks.passed} passed, {checks.failed} failed")
    sys.exit(0 if checks.failed == 0 else 1)


if __name__ == "__main__":
    main()
