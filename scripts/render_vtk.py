#!/usr/bin/python3
"""Renders one frame of a `rheo simulate` VTK series (mesh.pvd) to a PNG, headless.

    scripts/render_vtk.py OUT/mesh.pvd --png frame.png [--frame -1] [--color stress_zz_Pa]

The object is drawn as shaded cells coloured by a point or cell array (default: stress_zz_Pa
if the frame has it, else strain_zz_m_per_m; vectors and tensors by their magnitude, or
NAME:COMPONENT), the plate as a translucent grey part. Needs the Debian package python3-vtk9
(scripts/setup installs it); /usr/bin/python3 is the interpreter that has it. Without an X
display the script runs itself again under xvfb-run, because Debian's VTK renders through
GLX only. Prints the time shown and the number of pixels that are not background.
"""

import argparse
import os
import shutil
import sys
import xml.etree.ElementTree as ElementTree

BACKGROUND = (1.0, 1.0, 1.0)


def ensure_display():
    """Re-executes under xvfb-run when there is no X display (offscreen GLX needs one)."""
    if os.environ.get("DISPLAY") or os.environ.get("RHEO_RENDER_UNDER_XVFB"):
        return
    xvfb_run = shutil.which("xvfb-run")
    if not xvfb_run:
        sys.exit("render_vtk: no X display and no xvfb-run (install xvfb and xauth: scripts/setup)")
    env = dict(os.environ, RHEO_RENDER_UNDER_XVFB="1")
    os.execve(xvfb_run, [xvfb_run, "-a", "-s", "-screen 0 1280x1024x24", sys.executable,
                         os.path.abspath(__file__)] + sys.argv[1:], env)


def import_vtk():
    try:
        import vtk  # noqa: F401 (Debian python3-vtk9)
    except ImportError:
        sys.exit(f"render_vtk: {sys.executable} has no vtk module: install python3-vtk9 "
                 "(scripts/setup) and run this with /usr/bin/python3")
    return vtk


def read_pvd(path):
    """{time: {part name: file path}} in time order."""
    root = ElementTree.parse(path).getroot()
    frames = {}
    base = os.path.dirname(os.path.abspath(path))
    for ds in root.iter("DataSet"):
        t = float(ds.get("timestep", "0"))
        name = ds.get("name") or ("object" if ds.get("part", "0") == "0" else "part" + ds.get("part"))
        frames.setdefault(t, {})[name] = os.path.join(base, ds.get("file"))
    return dict(sorted(frames.items()))


def read_vtu(vtk, path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfCells() == 0:
        sys.exit(f"render_vtk: {path}: no cells")
    return grid


def find_array(grid, name):
    """(array, is_cell_data) or (None, None)."""
    for data, is_cell in ((grid.GetCellData(), True), (grid.GetPointData(), False)):
        a = data.GetArray(name)
        if a is not None:
            return a, is_cell
    return None, None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pvd", help="mesh.pvd written by rheo simulate")
    parser.add_argument("--png", required=True, help="image to write")
    parser.add_argument("--frame", type=int, default=-1, help="frame index (default: last)")
    parser.add_argument("--color", help="array to colour by, NAME or NAME:COMPONENT")
    parser.add_argument("--size", default="800x600", help="image size WxH")
    args = parser.parse_args()
    ensure_display()
    vtk = import_vtk()

    frames = read_pvd(args.pvd)
    if not frames:
        sys.exit(f"render_vtk: {args.pvd}: no data sets")
    times = list(frames)
    t = times[args.frame]
    parts = frames[t]
    if "object" not in parts:
        sys.exit(f"render_vtk: {args.pvd}: no part 'object' at t = {t}")
    grid = read_vtu(vtk, parts["object"])

    color = args.color
    if not color:
        color = "stress_zz_Pa" if find_array(grid, "stress_zz_Pa")[0] else "strain_zz_m_per_m"
    name, _, component = color.partition(":")
    array, is_cell = find_array(grid, name)
    if array is None:
        sys.exit(f"render_vtk: {parts['object']}: no array {name}")
    component = int(component) if component else (-1 if array.GetNumberOfComponents() > 1 else 0)
    low, high = array.GetRange(component)
    if low == high:
        low, high = low - 1.0, high + 1.0

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(*BACKGROUND)

    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(grid)
    mapper = vtk.vtkDataSetMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    if is_cell:
        mapper.SetScalarModeToUseCellFieldData()
    else:
        mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(name)
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (low) to red (high)
    if component < 0:
        lut.SetVectorModeToMagnitude()
    else:
        lut.SetVectorModeToComponent()
        lut.SetVectorComponent(component)
    lut.Build()
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(low, high)
    mapper.ScalarVisibilityOn()
    obj = vtk.vtkActor()
    obj.SetMapper(mapper)
    obj.GetProperty().EdgeVisibilityOn()
    obj.GetProperty().SetEdgeColor(0.2, 0.2, 0.2)
    renderer.AddActor(obj)

    if "plate" in parts:
        plate_mapper = vtk.vtkDataSetMapper()
        plate_mapper.SetInputData(read_vtu(vtk, parts["plate"]))
        plate_mapper.ScalarVisibilityOff()
        plate = vtk.vtkActor()
        plate.SetMapper(plate_mapper)
        plate.GetProperty().SetColor(0.55, 0.55, 0.6)
        plate.GetProperty().SetOpacity(0.6)
        plate.GetProperty().SetLineWidth(4)
        renderer.AddActor(plate)

    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(color)
    bar.SetNumberOfLabels(5)
    bar.GetTitleTextProperty().SetColor(0, 0, 0)
    bar.GetLabelTextProperty().SetColor(0, 0, 0)
    bar.SetWidth(0.12)
    renderer.AddActor2D(bar)
    label = vtk.vtkTextActor()
    label.SetInput(f"t = {t:g} s")
    label.GetTextProperty().SetColor(0, 0, 0)
    label.GetTextProperty().SetFontSize(18)
    label.SetDisplayPosition(10, 10)
    renderer.AddActor2D(label)

    # An oblique view from the front, z up: shows the top (plate side) and two faces.
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(-0.6, -1.6, 0.9)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(0.9)

    width, height = (int(v) for v in args.size.lower().split("x"))
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(width, height)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(args.png)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()

    image = grab.GetOutput()
    pixels = image.GetPointData().GetScalars()
    background = tuple(round(255 * c) for c in BACKGROUND)
    count = pixels.GetNumberOfTuples()
    drawn = sum(1 for i in range(count) if tuple(int(v) for v in pixels.GetTuple(i))[:3] != background)
    print(f"render_vtk: {args.png}: t = {t:g} s, coloured by {color} "
          f"[{low:.4g}, {high:.4g}], {drawn} of {count} pixels not background")


if __name__ == "__main__":
    main()
