"""pvpython check of a run's result.xdmf (used by tests/cli/visualization.sh):
ParaView's three XDMF readers read it; the top-level-partition and XDMF 2
readers give N_BODIES blocks of quadrilaterals and N_DIES of lines at every
step, the dies move, and the stroke comes out of Plot Global Variables Over
Time with a value per step. Usage: pvpython pv_blocks.py RESULT_XDMF N_BODIES N_DIES"""
import sys

from paraview import servermanager
from paraview.simple import OpenDataFile, PlotGlobalVariablesOverTime, XDMFReader, Xdmf3ReaderT

from checks import check, finish

path, n_bodies, n_dies = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])


def leaves(d):
    if d.IsA("vtkMultiBlockDataSet") or d.IsA("vtkMultiPieceDataSet"):
        out = []
        for i in range(d.GetNumberOfBlocks() if d.IsA("vtkMultiBlockDataSet") else d.GetNumberOfPieces()):
            b = d.GetBlock(i) if d.IsA("vtkMultiBlockDataSet") else d.GetPiece(i)
            out += leaves(b) if b is not None else []
        return out
    return [d]


def kinds(reader, t):
    reader.UpdatePipeline(t)
    blocks = leaves(servermanager.Fetch(reader))
    quads = [b for b in blocks if b.GetNumberOfCells() and b.GetCellType(0) == 9]
    lines = [b for b in blocks if b.GetNumberOfCells() and b.GetCellType(0) in (3, 4)]
    return quads, lines


for name, reader in (("Xdmf3ReaderT", Xdmf3ReaderT(FileName=[path])), ("XDMFReader", XDMFReader(FileNames=[path])),
                     ("default reader", OpenDataFile(path))):
    times = list(reader.TimestepValues)
    check(len(times) >= 3, "%s: %d time steps" % (name, len(times)))
    q0, l0 = kinds(reader, times[0])
    q1, l1 = kinds(reader, times[-1])
    check(len(q0) == len(q1) == n_bodies, "%s: %d body blocks" % (name, len(q1)))
    check(len(l0) == len(l1) == n_dies, "%s: %d die blocks" % (name, len(l1)))
    if len(l0) == len(l1) == n_dies:
        moved = [abs(a.GetBounds()[2] - b.GetBounds()[2]) for a, b in zip(l0, l1)]
        check(min(moved) > 0, "%s: the dies move (%s mm)" % (name, ", ".join("%.4g" % m for m in moved)))
    if name == "Xdmf3ReaderT":
        table = PlotGlobalVariablesOverTime(Input=reader)
        table.UpdatePipeline()
        data = servermanager.Fetch(table)
        stroke = data.GetColumnByName("stroke")
        check(stroke is not None and stroke.GetNumberOfTuples() == len(times),
              "Plot Global Variables Over Time: stroke at %d steps" % (stroke.GetNumberOfTuples() if stroke else 0))
finish()
