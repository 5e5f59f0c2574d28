#!/usr/bin/python3
"""`rheo simulate` -> VTK series -> headless render (ctest vtk_render_e2e).

Runs block5 on the reference model and on the bit-true backend, reads the series with VTK's
own XML reader (python3-vtk9) and checks what a ParaView user sees: the object as 64
hexahedra with the point and cell fields named with their units and holding non-zero data,
the plate as its own part of mesh.pvd at the simulated height over the object's top, the edge
lattice with edge tensions in edges.pvd, fixed-point frames without the arrays the core does
not read back (and a note saying so). Then renders the peak-force frame with
scripts/render_vtk.py and checks the PNG is not empty. A missing vtk module is a failure,
not a skip: scripts/setup installs python3-vtk9.
"""

import argparse
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)
    return condition


try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    import numpy as np
except ImportError as e:
    sys.exit(f"FAIL: {sys.executable} cannot import vtk ({e}): install python3-vtk9 "
             "(scripts/setup) - this test needs it and does not skip")

VTK_QUAD, VTK_HEXAHEDRON = 9, 12
HEIGHT_M = 0.04  # block5: 40 mm cube


def simulate(rheo, out, *extra):
    command = [rheo, "simulate", "--scenario", "block5", "--quiet", "--no-plot", "--force",
               "--out", out, *extra]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"FAIL: {' '.join(command)} exited {run.returncode}:\n{run.stdout}{run.stderr}")
    return run.stdout


def read_pvd(path):
    """[(time, {name: file})] in time order."""
    frames = {}
    for ds in ElementTree.parse(path).getroot().iter("DataSet"):
        frames.setdefault(float(ds.get("timestep")), {})[ds.get("name")] = os.path.join(
            os.path.dirname(path), ds.get("file"))
    return sorted(frames.items())


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def arrays(grid):
    """{name: numpy array} of point and cell data."""
    out = {}
    for data in (grid.GetPointData(), grid.GetCellData()):
        for i in range(data.GetNumberOfArrays()):
            out[data.GetArrayName(i)] = vtk_to_numpy(data.GetArray(i))
    return out


def cell_types(grid):
    return {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}


def check_nonzero(fields, names, where):
    for name in names:
        if check(name in fields, f"{where}: no array {name} (has {sorted(fields)})"):
            a = fields[name].astype(float)
            check(np.all(np.isfinite(a)), f"{where}: {name} has non-finite values")
            check(np.abs(a).max() > 0.0, f"{where}: {name} is all zero")


def check_reference(out):
    pvd = os.path.join(out, "mesh.pvd")
    frames = read_pvd(pvd)
    check(len(frames) == 101, f"{pvd}: {len(frames)} time steps, expected 101")
    for t, parts in frames:
        check(set(parts) == {"object", "plate"}, f"{pvd}: t = {t}: parts {sorted(parts)}")
        for f in parts.values():
            check(os.path.isfile(f), f"{pvd}: {f} listed but missing")
    check(os.path.isfile(os.path.join(out, "edges.pvd")), "no edges.pvd")

    # The frame of the peak plate force (end of the push, t = 2 s).
    forces = [arrays(read_vtu(parts["plate"]))["plate_force_N"][0] for _, parts in frames]
    peak = int(np.argmax(forces))
    t, parts = frames[peak]
    check(abs(t - 2.0) < 1e-9, f"peak force frame at t = {t}, expected 2 s")
    obj = read_vtu(parts["object"])
    check(obj.GetNumberOfPoints() == 125, f"object: {obj.GetNumberOfPoints()} points")
    check(obj.GetNumberOfCells() == 64, f"object: {obj.GetNumberOfCells()} cells, expected 64")
    check(cell_types(obj) == {VTK_HEXAHEDRON}, f"object cell types {cell_types(obj)}")
    fields = arrays(obj)
    check_nonzero(fields, ["displacement_m", "velocity_m_s", "strain_m_per_m",
                           "strain_zz_m_per_m", "stress_Pa", "stress_zz_Pa",
                           "von_mises_stress_Pa"], f"{parts['object']}")
    check("residual_deformation_m" not in fields, "residual deformation under the plate")
    check(fields["strain_zz_m_per_m"].mean() < -0.1, "pushed 20 %, strain_zz not compressive")
    # The cells carry the plate load: mean vertical stress about force / top area.
    stress = -fields["stress_zz_Pa"].mean()
    expected = forces[peak] / HEIGHT_M**2
    check(0.8 * expected < stress < 1.2 * expected,
          f"mean stress_zz {-stress:.4g} Pa, force / area {-expected:.4g} Pa")

    plate = read_vtu(parts["plate"])
    check(plate.GetNumberOfCells() == 1 and cell_types(plate) == {VTK_QUAD}, "plate: not one quad")
    pb, ob = plate.GetBounds(), obj.GetBounds()
    plate_fields = arrays(plate)
    check(abs(pb[4] - (HEIGHT_M - plate_fields["plate_displacement_m"][0])) < 1e-7,
          f"plate at z = {pb[4]}, displacement {plate_fields['plate_displacement_m'][0]}")
    check(abs(pb[4] - 0.032) < 1e-7, f"plate at z = {pb[4]}, pushed 8 mm: expected 0.032")
    check(pb[0] < ob[0] and pb[1] > ob[1] and pb[2] < ob[2] and pb[3] > ob[3],
          f"plate {pb[:4]} does not span the object's top {ob[:4]}")
    check(ob[5] <= pb[4] + 1e-6, "object above the plate")

    edges = read_vtu(os.path.join(out, "vtk", os.path.basename(parts["object"]).replace(
        "frame", "edges")))
    check(edges.GetNumberOfCells() == 1036, f"edges: {edges.GetNumberOfCells()} cells")
    check_nonzero(arrays(edges), ["edge_tension_N", "edge_strain_m_per_m"], "edges")

    # After the release (t = 7 s) the plate is above the object: residual deformation.
    last = arrays(read_vtu(frames[-1][1]["object"]))
    check_nonzero(last, ["residual_deformation_m"], "last frame")
    return frames[peak][1], peak


def check_fixed_point(out, stdout):
    # The fixed-point backends read the edges' Voigt lengths back at every frame, so their
    # frames carry edge tensions and stresses like the reference's (3-D block: no VTK note).
    frames = read_pvd(os.path.join(out, "mesh.pvd"))
    fields = arrays(read_vtu(frames[-1][1]["object"]))
    check_nonzero(fields, ["displacement_m", "velocity_m_s", "strain_zz_m_per_m", "stress_Pa",
                           "stress_zz_Pa", "von_mises_stress_Pa"], "bittrue")
    edges = arrays(read_vtu(frames[-1][1]["object"].replace("frame_", "edges_")))
    check_nonzero(edges, ["edge_tension_N", "edge_strain_m_per_m"], "bittrue edges")
    note = [line for line in stdout.splitlines() if "VTK note" in line]
    check(not note, f"a VTK note on absent arrays in:\n{stdout}")


def check_render(render, pvd, frame, png):
    run = subprocess.run([sys.executable, render, pvd, "--png", png, "--frame", str(frame)],
                         capture_output=True, text=True)
    print(run.stdout + run.stderr, end="")
    if not check(run.returncode == 0, f"render_vtk.py exited {run.returncode}"):
        return
    reader = vtk.vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3]
    drawn = np.any(pixels != 255, axis=1)
    colours = len({tuple(p) for p in pixels[drawn]})
    print(f"{png}: {w}x{h}, {drawn.sum()} pixels not background, {colours} colours")
    check(drawn.sum() > 0.1 * w * h, f"{png}: only {drawn.sum()} pixels drawn")
    check(colours > 20, f"{png}: {colours} colours: the field is not shown")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--rheo", required=True)
    parser.add_argument("--render", required=True, help="scripts/render_vtk.py")
    parser.add_argument("--work", required=True, help="directory for the runs and the PNG")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    ref_out = os.path.join(args.work, "block5_ref")
    bittrue_out = os.path.join(args.work, "block5_bittrue")
    for d in (ref_out, bittrue_out):
        shutil.rmtree(d, ignore_errors=True)

    simulate(args.rheo, ref_out)
    _, peak = check_reference(ref_out)
    # 2,500 steps: the push and part of the hold, enough for velocities (bit-true is slower).
    check_fixed_point(bittrue_out, simulate(args.rheo, bittrue_out, "--backend", "bittrue",
                                            "--steps", "2500"))
    check_render(args.render, os.path.join(ref_out, "mesh.pvd"), peak,
                 os.path.join(args.work, "block5_peak_stress_zz.png"))
    if failures:
        sys.exit(f"{len(failures)} check(s) failed")
    print("vtk_render_e2e: all checks passed")


if __name__ == "__main__":
    main()
