#!/usr/bin/env python3
"""VTK itself reads the ParaView output of the `fem` command.

    check_fields.py OUT_DIR [--snapshots N] [--point X Y UX UY]

Opens OUT_DIR/fields.pvd (a ParaView collection: plain VTK has no reader for it, so it is
parsed as the XML it is), then every .vtu it lists with VTK's own vtkXMLUnstructuredGridReader,
and checks: times increase; the bulk holds quads (VTK type 9) and the crack lines (type 3); every
array of docs/outputs.md is there with one tuple per point or cell and its number of
components; vectors have z = 0. With --point, the bulk point at reference position (X, Y) of the
last snapshot has displacement (UX, UY) to the last bit (the arrays are binary float64 and the
numbers on the command line are written with Rust's round-trip formatting), and VTK's Warp By
Vector filter moves it to (X + UX, Y + UY). Exits 1 with the first problem found.
Run by `cargo test -p fem --test paraview` (vtk_reads_the_files).
"""

import argparse
import os
import sys
import xml.etree.ElementTree as ET

import vtk

BULK_POINT = {"displacement": 3, "velocity": 3}
BULK_CELL = {"sigma_xx": 1, "sigma_yy": 1, "sigma_xy": 1, "sigma_zz": 1, "von_mises": 1}
CRACK_POINT = {
    "displacement": 3,
    "velocity": 3,
    "gap": 1,
    "contact_penetration": 1,
    "contact_normal_traction": 1,
    "contact_tangential_traction": 1,
}
CRACK_CELL = {
    "face": 1,
    "facet_state": 1,
    "damage": 1,
    "normal_opening": 1,
    "tangential_opening": 1,
    "cohesive_normal_traction": 1,
    "cohesive_tangential_traction": 1,
}
EXPECTED = {
    "bulk": (vtk.VTK_QUAD, BULK_POINT, BULK_CELL),
    "crack": (vtk.VTK_LINE, CRACK_POINT, CRACK_CELL),
}


class Errors:
    """Collects VTK's own error messages (a reader that fails only prints them)."""

    def __init__(self):
        self.messages = []

    def __call__(self, caller, event):
        self.messages.append(f"{caller.GetClassName()}: {event}")


def fail(message):
    print(f"vtk check FAILED: {message}")
    sys.exit(1)


def read(path):
    if not os.path.isfile(path):
        fail(f"{path}: listed in fields.pvd but missing")
    reader = vtk.vtkXMLUnstructuredGridReader()
    errors = Errors()
    reader.AddObserver("ErrorEvent", errors)
    reader.SetFileName(path)
    reader.Update()
    if errors.messages:
        fail(f"{path}: {errors.messages}")
    return reader.GetOutput()


def check_arrays(path, data, expected, count, where):
    for name, components in expected.items():
        array = data.GetArray(name)
        if array is None:
            fail(f"{path}: no {where} array {name}")
        if array.GetNumberOfComponents() != components:
            fail(f"{path}: {name} has {array.GetNumberOfComponents()} components, not {components}")
        if array.GetNumberOfTuples() != count:
            fail(f"{path}: {name} has {array.GetNumberOfTuples()} tuples for {count} {where}s")
        if components == 3 and any(array.GetComponent(k, 2) != 0.0 for k in range(count)):
            fail(f"{path}: {name} has a non-zero z component")


def check_piece(path, part):
    grid = read(path)
    cell_type, point_arrays, cell_arrays = EXPECTED[part]
    points, cells = grid.GetNumberOfPoints(), grid.GetNumberOfCells()
    if points == 0 or cells == 0:
        fail(f"{path}: {points} points, {cells} cells")
    types = {grid.GetCellType(k) for k in range(cells)}
    if types != {cell_type}:
        fail(f"{path}: cell types {types}, expected {{{cell_type}}}")
    check_arrays(path, grid.GetPointData(), point_arrays, points, "point")
    check_arrays(path, grid.GetCellData(), cell_arrays, cells, "cell")
    return grid


def check_point(grid, x, y, ux, uy):
    for k in range(grid.GetNumberOfPoints()):
        px, py, _ = grid.GetPoint(k)
        if px == x and py == y:
            break
    else:
        fail(f"no point at ({x!r}, {y!r})")
    u = grid.GetPointData().GetArray("displacement").GetTuple3(k)
    if (u[0], u[1], u[2]) != (ux, uy, 0.0):
        fail(f"displacement at ({x!r}, {y!r}) is {u!r}, expected ({ux!r}, {uy!r}, 0)")
    warp = vtk.vtkWarpVector()
    warp.SetInputData(grid)
    warp.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "displacement")
    warp.Update()
    wx, wy, _ = warp.GetOutput().GetPoint(k)
    # the filter adds in float64: X + u rounded once, the same sum Python makes
    if (wx, wy) != (x + ux, y + uy):
        fail(f"Warp By Vector moved ({x!r}, {y!r}) to ({wx!r}, {wy!r}), not ({x + ux!r}, {y + uy!r})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--snapshots", type=int)
    parser.add_argument("--point", type=float, nargs=4, metavar=("X", "Y", "UX", "UY"))
    args = parser.parse_args()
    pvd = os.path.join(args.out_dir, "fields.pvd")
    root = ET.parse(pvd).getroot()
    if root.get("type") != "Collection":
        fail(f"{pvd}: VTKFile type {root.get('type')!r}, not 'Collection'")
    snapshots = {}
    for entry in root.iter("DataSet"):
        t = float(entry.get("timestep"))
        part = {"0": "bulk", "1": "crack"}.get(entry.get("part"))
        if part is None or os.path.basename(entry.get("file")).split("_")[0] != part:
            fail(f"{pvd}: part {entry.get('part')!r} with file {entry.get('file')!r}")
        snapshots.setdefault(t, {})[part] = os.path.join(args.out_dir, entry.get("file"))
    times = list(snapshots)
    if args.snapshots is not None and len(times) != args.snapshots:
        fail(f"{pvd}: {len(times)} snapshots, expected {args.snapshots}")
    if any(b <= a for a, b in zip(times, times[1:])):
        fail(f"{pvd}: times do not increase: {times}")
    last = None
    for t in times:
        for part, path in sorted(snapshots[t].items()):
            grid = check_piece(path, part)
            if part == "bulk":
                last = grid
    if args.point is not None:
        check_point(last, *args.point)
    print(f"vtk check: {len(times)} snapshots of {sorted(snapshots[times[-1]])} read by VTK {vtk.vtkVersion.GetVTKVersion()}, ok")


if __name__ == "__main__":
    main()
