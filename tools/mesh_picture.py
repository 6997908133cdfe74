#!/usr/bin/python3
"""mesh_picture.py - meshes written by `terrapatch export`, side by side in one PNG, each
coloured by a cell array (default max_error_m, on one shared scale) with its triangle edges,
rendered with VTK (the library ParaView is built on; Debian: python3-vtk9). Needs a display:
run it under xvfb-run where there is none.

  xvfb-run -a /usr/bin/python3 tools/mesh_picture.py -o OUT.png \\
      [--array max_error_m] [--range 0,5] [--zoom E,N,HALF_WIDTH_M] [--size 720] A.vtp B.vtp ...

Each panel is titled with its file name, triangle count and the array's range in it.
--zoom looks straight down at a square of 2*HALF_WIDTH_M around (E, N) (render CRS metres),
where the triangles can be told apart; without it the whole mesh is shown.
"""
import argparse
import os
import sys

import vtk


def read(path):
    r = vtk.vtkXMLPolyDataReader() if path.endswith(".vtp") else vtk.vtkPolyDataReader()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    if pd.GetNumberOfPoints() == 0:
        sys.exit(f"mesh_picture: {path}: no points (not a mesh terrapatch wrote?)")
    return pd


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("meshes", nargs="+")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--array", default="max_error_m")
    ap.add_argument("--range", help="LO,HI of the colour scale (default: over all meshes)")
    ap.add_argument("--zoom", help="E,N,HALF_WIDTH_M")
    ap.add_argument("--size", type=int, default=720, help="panel size in pixels")
    a = ap.parse_args()

    data = [read(p) for p in a.meshes]
    lo, hi = float("inf"), float("-inf")
    for p, pd in zip(a.meshes, data):
        arr = pd.GetCellData().GetArray(a.array)
        if arr is None:
            sys.exit(f"mesh_picture: {p}: no cell array '{a.array}'")
        r = arr.GetRange()
        lo, hi = min(lo, r[0]), max(hi, r[1])
    if a.range:
        lo, hi = (float(v) for v in a.range.split(","))
    hi = hi if hi > lo else lo + 1

    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (0) to red (the bound)
    lut.SetTableRange(lo, hi)
    lut.Build()

    n = len(data)
    win = vtk.vtkRenderWindow()
    win.SetSize(a.size * n, a.size + 60)
    win.SetOffScreenRendering(1)
    zoom = [float(v) for v in a.zoom.split(",")] if a.zoom else None
    for i, (path, pd) in enumerate(zip(a.meshes, data)):
        ren = vtk.vtkRenderer()
        ren.SetViewport(i / n, 0, (i + 1) / n, 1)
        ren.SetBackground(1, 1, 1)
        m = vtk.vtkPolyDataMapper()
        m.SetInputData(pd)
        m.SetScalarModeToUseCellFieldData()
        m.SelectColorArray(a.array)
        m.SetLookupTable(lut)
        m.SetScalarRange(lo, hi)
        m.ScalarVisibilityOn()
        act = vtk.vtkActor()
        act.SetMapper(m)
        act.GetProperty().EdgeVisibilityOn()
        act.GetProperty().SetEdgeColor(0.1, 0.1, 0.1)
        act.GetProperty().SetLineWidth(0.5)
        act.GetProperty().LightingOff()
        ren.AddActor(act)
        arr = pd.GetCellData().GetArray(a.array).GetRange()
        t = vtk.vtkTextActor()
        t.SetInput(f"{os.path.basename(path)}: {pd.GetNumberOfPolys():,} triangles, "
                   f"{a.array} {arr[0]:.2f}..{arr[1]:.2f}")
        t.GetTextProperty().SetColor(0, 0, 0)
        t.GetTextProperty().SetFontSize(16)
        t.GetTextProperty().SetBackgroundColor(1, 1, 1)
        t.GetTextProperty().SetBackgroundOpacity(0.85)
        t.SetPosition(8, 8)
        ren.AddActor2D(t)
        bar = vtk.vtkScalarBarActor()
        bar.SetLookupTable(lut)
        bar.SetTitle(a.array)
        bar.SetNumberOfLabels(5)
        bar.SetOrientationToHorizontal()
        bar.SetPosition(0.55, 0.9)
        bar.SetWidth(0.42)
        bar.SetHeight(0.09)
        bar.DrawBackgroundOn()
        bar.GetBackgroundProperty().SetColor(1, 1, 1)
        bar.GetBackgroundProperty().SetOpacity(0.85)
        bar.GetTitleTextProperty().SetColor(0, 0, 0)
        bar.GetLabelTextProperty().SetColor(0, 0, 0)
        ren.AddActor2D(bar)
        cam = ren.GetActiveCamera()
        b = pd.GetBounds()
        if zoom:
            e, nn, hw = zoom
            cam.SetFocalPoint(e, nn, b[4])
            cam.SetPosition(e, nn, b[5] + 10 * hw)
            cam.SetViewUp(0, 1, 0)
            cam.ParallelProjectionOn()
            cam.SetParallelScale(hw)
        else:
            cam.SetFocalPoint((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, b[4])
            cam.SetPosition((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, b[5] + 10 * (b[1] - b[0]))
            cam.SetViewUp(0, 1, 0)
            cam.ParallelProjectionOn()
            cam.SetParallelScale(max(b[1] - b[0], b[3] - b[2]) / 2 * 1.05)
        ren.ResetCameraClippingRange()
        win.AddRenderer(ren)
    win.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.Update()
    w = vtk.vtkPNGWriter()
    w.SetFileName(a.output)
    w.SetInputConnection(grab.GetOutputPort())
    w.Write()
    print(f"wrote {a.output}: {n} panels, {a.array} {lo:g}..{hi:g}")


if __name__ == "__main__":
    main()
