#!/usr/bin/env pvpython
"""Renders an rpfem run (its result.xdmf) to PNG with ParaView.

    xvfb-run -a pvpython scripts/render.py RUN_DIR OUT.png [options]

Draws the bodies (quadrilaterals with their edges, coloured by a cell
field, strain_rate by default) and the rigid dies (black polylines) at the
last recorded step, with the step, time, stroke and the loads written
above. Options:
  --field NAME        cell field to colour by (strain_rate, strain, mean_stress, flow_stress, body)
  --step N            the recorded step N instead of the last
  --every             one PNG per recorded step: OUT_NNNNNN.png
  --over-time PLOT    also plot the stroke (mm, right axis) and every die
                      or platen load Fy (N) against time (s) to PLOT (PNG),
                      from the grid attributes (Plot Global Variables Over Time)
  --size W H          image size in pixels (default 1200 900)

Needs Debian's ParaView (pvpython); without a display, run it under
xvfb-run. Reads the file with ParaView's "Xdmf3 Reader (Top Level
Partition)" (Xdmf3ReaderT), which gives a named block per body and die.
"""
import argparse
import os
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction, GetScalarBar, PlotGlobalVariablesOverTime,
                             SaveScreenshot, Show, Text, Xdmf3ReaderT)


def globals_of(data):
    """The step's grid attributes (time, stroke, loads) of the first block."""
    block = data.GetBlock(0) if data.IsA("vtkMultiBlockDataSet") else data
    fd = block.GetFieldData()
    return {fd.GetArrayName(i): fd.GetArray(i).GetValue(0) for i in range(fd.GetNumberOfArrays())}


def caption(step, values):
    loads = ", ".join("%s %.4g kN" % (k[:-3], v / 1e3) for k, v in sorted(values.items()) if k.endswith(".Fy"))
    return "step %d   t = %.6g s   stroke = %.6g mm\n%s" % (step, values.get("time", 0), values.get("stroke", 0), loads)


def render(args):
    path = os.path.abspath(os.path.join(args.run, "result.xdmf"))
    if not os.path.exists(path):
        sys.exit("render.py: no result.xdmf in %s" % args.run)
    reader = Xdmf3ReaderT(FileName=[path])
    times = list(reader.TimestepValues)
    import h5py
    with h5py.File(os.path.join(args.run, "result.h5"), "r") as f:
        steps = [int(s) for s in f["steps/index"][:]]
    view = CreateView("RenderView")
    view.ViewSize = args.size
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.InteractionMode = "2D"
    shown = Show(reader, view)
    shown.Representation = "Surface With Edges"
    shown.EdgeColor = [0.25, 0.25, 0.25]
    shown.LineWidth = 3  # the dies' polylines (the bodies' edges keep 1)
    ColorBy(shown, ("CELLS", args.field))
    lut = GetColorTransferFunction(args.field)
    lut.NanColor = [0, 0, 0]
    shown.AmbientColor = shown.DiffuseColor = [0, 0, 0]  # the dies, which have no cell fields: black
    bar = GetScalarBar(lut, view)
    bar.Title = args.field
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    shown.SetScalarBarVisibility(view, True)
    text = Text()
    label = Show(text, view)
    label.Color = [0, 0, 0]
    label.FontSize = 14
    label.WindowLocation = "Upper Center"
    if args.every:
        todo = list(zip(steps, times))
        stem = os.path.splitext(args.out)[0]
        names = ["%s_%06d.png" % (stem, s) for s in steps]
    else:
        k = steps.index(args.step) if args.step is not None else len(steps) - 1
        todo, names = [(steps[k], times[k])], [args.out]
    # Frame the whole run: the bodies and dies at the first and last steps.
    bounds = [1e300, -1e300, 1e300, -1e300]
    for t in (times[0], times[-1]):
        reader.UpdatePipeline(t)
        b = reader.GetDataInformation().GetBounds()
        bounds = [min(bounds[0], b[0]), max(bounds[1], b[1]), min(bounds[2], b[2]), max(bounds[3], b[3])]
    cx, cy = 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3])
    view.CameraPosition, view.CameraFocalPoint, view.CameraViewUp = [cx, cy, 100.0], [cx, cy, 0.0], [0, 1, 0]
    view.CameraParallelProjection = 1
    aspect = args.size[0] / float(args.size[1])
    view.CameraParallelScale = 0.6 * max(bounds[3] - bounds[2], (bounds[1] - bounds[0]) / aspect)
    for (step, t), name in zip(todo, names):
        view.ViewTime = t
        reader.UpdatePipeline(t)
        text.Text = caption(step, globals_of(servermanager.Fetch(reader)))
        shown.RescaleTransferFunctionToDataRange(False, True)
        SaveScreenshot(name, view, ImageResolution=args.size)
        print(name)
    if args.over_time:
        plot_over_time(reader, args)


def plot_over_time(reader, args):
    """Stroke (right axis) and the loads Fy against time, from the field
    data ParaView makes of the grid attributes."""
    table = PlotGlobalVariablesOverTime(Input=reader)
    table.UpdatePipeline()
    data = servermanager.Fetch(table)
    columns = [data.GetColumnName(i) for i in range(data.GetNumberOfColumns())]
    loads = [c for c in columns if c.endswith(".Fy")]
    chart = CreateView("XYChartView")
    chart.ViewSize = args.size
    chart.LeftAxisTitle = "load Fy (N)"
    chart.BottomAxisTitle = "time (s)"
    chart.RightAxisTitle = "stroke (mm)"
    chart.ChartTitle = "rpfem: %s" % os.path.basename(os.path.abspath(args.run))
    series = Show(table, chart)
    series.UseIndexForXAxis = 0
    series.XArrayName = "Time"
    series.SeriesVisibility = ["stroke"] + loads
    series.SeriesPlotCorner = ["stroke", "1"]  # 1: bottom-right, the right axis
    series.SeriesLineThickness = [c for s in ["stroke"] + loads for c in (s, "2")]
    SaveScreenshot(args.over_time, chart, ImageResolution=args.size)
    print(args.over_time)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run")
    p.add_argument("out")
    p.add_argument("--field", default="strain_rate")
    p.add_argument("--step", type=int)
    p.add_argument("--every", action="store_true")
    p.add_argument("--over-time")
    p.add_argument("--size", type=int, nargs=2, default=[1200, 900])
    render(p.parse_args())


if __name__ == "__main__":
    main()
