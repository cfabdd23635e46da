"""Read the results of an rpfem run (`rpfem run CASE --out DIR`) in Python.

    import sys; sys.path.insert(0, "python")      # this folder of the source tree
    import rpfem_results
    run = rpfem_results.load_run("out/test1")
    run.history["stroke"], run.history["top_punch.Fy"]   # every step: mm, N
    run.history_frame()                                 # the same as a pandas DataFrame
    run.summary["status"]                               # summary.json as a dict
    last = run.steps[-1]                                # steps with fields on record
    m = run.mesh(last)                                  # deformed mesh at that step
    m.coordinates, m.connectivity, m.element_body, m.body_names
    run.field("strain_rate", last)                      # per element, 1/s
    run.dies(last)["top_punch"]                         # die profile, points x 2, mm

Units (docs/results-format.md): lengths mm, velocities mm/s, strain rates
1/s, stresses MPa, forces N (N/mm in plane strain), times s; every dataset
of result.h5 says its own in its attribute "units" (run.units(name, step)).
Needs numpy and h5py; pandas only for history_frame, meshio only for
Run.meshio. The files are opened for each call and closed again, so a
run that is still writing can be read.
"""
import csv
import json
import os
from collections import namedtuple

import numpy as np

# What Run.mesh returns: coordinates (nodes x 2, mm: r, z or x, y),
# connectivity (elements x 4, 0-based node ids, counter-clockwise),
# element_body (elements, body id of each element), body_names (by body id).
Mesh = namedtuple("Mesh", "coordinates connectivity element_body body_names")

# The fields of a recorded step directly under /steps/NNNNNN (others are
# under node/ or element/: contact_pressure, flow_stress, ...).
STEP_FIELDS = ("coordinates", "velocity", "velocity_xyz", "strain_rate", "strain", "mean_stress")

# History columns that count things (read as integers by history()).
COUNTS = ("step", "newton_iterations", "contact_passes", "solves", "cuts", "rigid_points")


def read_history(path):
    """history.csv as a NumPy structured array, a float64 field per column
    (units: docs/results-format.md; loads `<group>.Fx`, `<group>.Fy` in N).
    A cell that is not a number (a row cut short by a killed run) is NaN."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return np.zeros(0, dtype=[])
    header, body = rows[0], [r for r in rows[1:] if r]

    def number(row, i):
        try:
            return float(row[i])
        except (IndexError, ValueError):
            return float("nan")
    table = np.zeros(len(body), dtype=[(name, "f8") for name in header])
    for k, row in enumerate(body):
        table[k] = tuple(number(row, i) for i in range(len(header)))
    return table


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


class Run:
    """One run's folder. Attributes: folder, history (read_history of
    history.csv; None without one), summary (summary.json as a dict; the
    copy in result.h5 when summary.json is missing; {} without either),
    steps (the step numbers with fields in result.h5, ascending; [] without
    one)."""

    def __init__(self, folder):
        self.folder = folder
        self.h5_path = os.path.join(folder, "result.h5")
        hist = os.path.join(folder, "history.csv")
        self.history = read_history(hist) if os.path.exists(hist) else None
        self.summary = {}
        self.steps = []
        self.has_result = False  # result.h5 is there and opens
        path = os.path.join(folder, "summary.json")
        if os.path.exists(path):
            with open(path) as f:
                self.summary = json.load(f)
        try:
            f = self._open()
        except OSError:  # missing, or not (yet) an HDF5 file
            return
        with f:
            self.has_result = True
            if "steps" in f:
                self.steps = sorted(int(k) for k in f["steps"] if k.isdigit())
            if not self.summary and "metadata" in f and "json" in f["metadata"].attrs:
                self.summary = json.loads(_text(f["metadata"].attrs["json"]))

    def _open(self):
        import h5py
        return h5py.File(self.h5_path, "r")

    @staticmethod
    def _group(step):
        return "steps/%06d" % step

    def history_frame(self):
        """The history as a pandas DataFrame (pandas needed), counts as
        integers."""
        import pandas as pd
        frame = pd.DataFrame(self.history)
        for c in COUNTS:
            if c in frame and frame[c].notna().all():
                frame[c] = frame[c].astype(int)
        return frame

    def time(self, step):
        """The step's time, s (full precision)."""
        with self._open() as f:
            return float(f[self._group(step)].attrs["time"])

    def stroke(self, step):
        """The step's stroke, mm (the reference motion's travel)."""
        with self._open() as f:
            return float(f[self._group(step)].attrs["stroke"])

    def mesh_group(self, step):
        """The step's mesh group in result.h5: "/mesh", or "/meshes/NNNNNN"
        from a remesh at step NNNNNN on."""
        with self._open() as f:
            return _text(f[self._group(step)].attrs.get("mesh", "/mesh"))

    @staticmethod
    def _mesh(m, x=None):
        names = _text(m.attrs.get("body_names", "")).split(";")
        x = m["initial_coordinates"][:] if x is None else x
        return Mesh(x, m["connectivity"][:].astype(int), m["element_body"][:].astype(int), names)

    def mesh(self, step, deformed=True):
        """The mesh of a recorded step (a Mesh): its coordinates at that
        step (mm; the mesh's initial ones if not deformed)."""
        with self._open() as f:
            g = f[self._group(step)]
            m = f[_text(g.attrs.get("mesh", "/mesh"))]
            return self._mesh(m, g["coordinates"][:] if deformed else None)

    def initial_mesh(self):
        """The run's first mesh at the start (a Mesh, coordinates in mm),
        whether or not a step is on record."""
        with self._open() as f:
            return self._mesh(f["mesh"])

    def _path(self, g, name):
        for p in (name, "node/" + name, "element/" + name):
            if p in g:
                return p
        raise KeyError("step %s has no field '%s' (fields: %s)" % (g.name, name, ", ".join(self.fields_of(g))))

    @staticmethod
    def fields_of(g):
        out = [k for k in STEP_FIELDS if k in g]
        for sub in ("node", "element"):
            if sub in g:
                out += sorted(g[sub])
        return out

    def fields(self, step):
        """The names of the step's fields (for field())."""
        with self._open() as f:
            return self.fields_of(f[self._group(step)])

    def field(self, name, step, body=None):
        """A field at a recorded step: per node (coordinates mm, velocity
        mm/s, contact_pressure MPa, ...) or per element (strain_rate 1/s,
        strain, mean_stress MPa, flow_stress MPa, ...); `name` as listed by
        fields(). With `body` (a name), that body's nodes or elements only."""
        with self._open() as f:
            g = f[self._group(step)]
            if body is not None:
                g = g["bodies"][body]
            return g[self._path(g, name)][:]

    def units(self, name, step):
        """The units of a field of a step (its dataset's attribute)."""
        with self._open() as f:
            g = f[self._group(step)]
            return _text(g[self._path(g, name)].attrs["units"])

    def dies(self, step):
        """Each rigid die's profile at the step: {name: points x 2 (mm)},
        a polyline in the profile's walking order; {} without dies."""
        with self._open() as f:
            g = f[self._group(step)]
            return {k: g["dies"][k]["coordinates"][:] for k in g["dies"]} if "dies" in g else {}

    def history_row(self, step):
        """The history row of a step (a structured record), None if absent."""
        if self.history is None:
            return None
        rows = self.history[self.history["step"] == step]
        return rows[0] if len(rows) else None

    def meshio(self, step):
        """The step as a meshio.Mesh (meshio needed): the deformed points
        (z = 0), the quadrilaterals, point data velocity (mm/s) and the node
        fields, cell data the element fields and the body id."""
        import meshio
        m = self.mesh(step)
        points = np.column_stack([m.coordinates, np.zeros(len(m.coordinates))])
        point_data, cell_data = {}, {"body": [m.element_body]}
        with self._open() as f:
            g = f[self._group(step)]
            for name in self.fields_of(g):
                data = g[self._path(g, name)][:]
                if name in ("coordinates", "velocity_xyz"):
                    continue
                if len(data) == len(points):
                    point_data[name] = data
                else:
                    cell_data[name] = [data]
        return meshio.Mesh(points, [("quad", m.connectivity)], point_data=point_data, cell_data=cell_data)


def load_run(folder):
    """The run written to `folder` (a Run)."""
    return Run(folder)
