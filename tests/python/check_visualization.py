"""Checks a run's visualization files (used by tests/cli/visualization.sh):
result.h5 has a block per body and each die's polyline at every recorded
step, the dies move, result.xdmf carries the step's time, stroke and loads
at full precision and equal to history.csv's, every dataset has units;
then that meshio reads the deformed points of the last step (without
meshio that check fails unless RPFEM_ALLOW_SKIP=1). Usage: check_visualization.py RUN_DIR N_BODIES N_DIES."""
import csv
import re
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

from checks import cannot_check, check, finish

run, n_bodies, n_dies = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])


with open(run + "/history.csv", newline="") as f:
    history = {int(float(r["step"])): r for r in csv.DictReader(f)}
load_cols = [c for c in next(iter(history.values())) if c.endswith(".Fx") or c.endswith(".Fy")]

with h5py.File(run + "/result.h5", "r") as h5:
    steps = sorted(int(k) for k in h5["steps"] if k.isdigit())
    check(len(steps) >= 3, "%d recorded steps" % len(steps))
    names = h5["mesh"].attrs["body_names"]
    names = (names.decode() if isinstance(names, bytes) else names).split(";")
    check(len(names) == n_bodies and sorted(h5["mesh/bodies"]) == sorted(names), "bodies in /mesh/bodies: %s" % names)
    body_ids = set(np.unique(h5["mesh/element_body"][:]).tolist())
    check(len(body_ids) == n_bodies, "element_body has %d values" % len(body_ids))
    first, last = "steps/%06d" % steps[0], "steps/%06d" % steps[-1]
    for s in (first, last):
        g = h5[s]
        # The bodies' views put together are the step's fields.
        x = np.concatenate([g["bodies"][b]["coordinates"][:] for b in names])
        rate = np.concatenate([g["bodies"][b]["strain_rate"][:] for b in names])
        check(np.array_equal(x, g["coordinates"][:]) and np.array_equal(rate, g["strain_rate"][:]),
              "%s: the bodies' coordinates and strain rates are the step's" % s)
        for b in names:
            body = g["bodies"][b]["body"][:]
            check(len(set(body.tolist())) == 1, "%s: body %s is one body id" % (s, b))
    die_names = sorted(h5[first]["dies"]) if "dies" in h5[first] else []
    check(len(die_names) == n_dies, "dies at step %d: %s" % (steps[0], die_names))
    for d in die_names:
        present = all("dies/" + d + "/coordinates" in h5["steps/%06d" % s] for s in steps)
        check(present, "die %s has a polyline at every recorded step" % d)
        a, b = h5[first]["dies"][d]["coordinates"][:], h5[last]["dies"][d]["coordinates"][:]
        check(a.shape == b.shape and np.abs(a - b).max() > 0, "die %s moves (%.6g mm)" % (d, np.abs(a - b).max()))
        conn = h5["dies"][d]["connectivity"][:]
        check(conn.shape == (len(a) - 1, 2), "die %s: %d segments" % (d, len(conn)))
    # Units on every dataset.
    missing = []
    h5.visititems(lambda n, o: missing.append(n) if isinstance(o, h5py.Dataset)
                  and o.attrs.get("units", "unknown") in ("unknown", b"unknown") else None)
    check(not missing, "every dataset has units%s" % (": missing " + ", ".join(missing[:5]) if missing else ""))
    check(h5[first]["strain_rate"].attrs["units"] in ("1/s", b"1/s"), "strain_rate in 1/s")
    x_last = h5[last]["coordinates"][:]
    x_first = h5[first]["coordinates"][:]
    h5_times = {s: float(h5["steps/%06d" % s].attrs["time"]) for s in steps}

# result.xdmf: per step the time (full precision, as result.h5), and the
# grid attributes stroke and loads equal to history.csv's.
root = ET.parse(run + "/result.xdmf").getroot()
collection = root.find("Domain/Grid")
grids = list(collection.findall("Grid"))
check(len(grids) == len(steps), "result.xdmf: %d step grids" % len(grids))
for s, g in zip(steps, grids):
    t = g.find("Time").get("Value")
    check(float(t) == h5_times[s], "step %d: time %s is result.h5's exactly" % (s, t))
    blocks = g.findall("Grid")
    kinds = [b.find("Topology").get("TopologyType") for b in blocks]
    check(kinds.count("Quadrilateral") == n_bodies and kinds.count("Polyline") == n_dies,
          "step %d: %d body blocks, %d die blocks" % (s, kinds.count("Quadrilateral"), kinds.count("Polyline")))
    values = {a.get("Name"): float(a.find("DataItem").text) for a in blocks[0].findall("Attribute")
              if a.get("Center") == "Grid"}
    row = history[s]
    for c in ["time", "stroke"] + load_cols:
        v, h = values.get(c), float(row[c])
        # history.csv has 10 significant digits
        check(v is not None and abs(v - h) <= 1e-9 * max(abs(h), 1e-300) + 1e-300,
              "step %d: %s %r = history.csv's %s" % (s, c, v, row[c]))
times = re.findall(r'<Time Value="([^"]+)"', open(run + "/result.xdmf").read())
check(any(len(t.replace("-", "").replace(".", "").lstrip("0")) > 10 for t in times[1:]),
      "times at full precision (%s)" % times[-1])

try:
    import meshio
except ImportError:
    meshio = None
    cannot_check("meshio (python3-meshio is not installed)")
if meshio:
    with meshio.xdmf.TimeSeriesReader(run + "/result_meshio.xdmf") as reader:
        points, cells = reader.read_points_cells()
        t, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    deformed = point_data["coordinates"]
    check(reader.num_steps == len(steps) and t == h5_times[steps[-1]], "meshio: %d steps, last at t = %r s"
          % (reader.num_steps, t))
    check(np.array_equal(deformed, x_last) and not np.array_equal(deformed, x_first),
          "meshio: the last step's points are result.h5's and differ from step 0's (by %.4g mm)"
          % np.abs(deformed - x_first).max())
    check(sorted(set(cell_data["body"][0].tolist())) == sorted(body_ids), "meshio: cell data body")
    check(len(cells[0].data) == len(cell_data["strain_rate"][0]), "meshio: strain_rate per cell")
finish()
