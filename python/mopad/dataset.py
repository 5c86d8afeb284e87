"""Reader of `mopad dataset` folders (docs/dataset.md), with numpy only.

    import mopad.dataset
    ds = mopad.dataset.load("/tmp/ds")
    for ref in ds.scans:                  # one entry of dataset.json "scans" each
        scan = ds.read(ref)               # dict of numpy arrays, see Dataset.read
        walls = scan["xyz"][scan["semantic"] == ds.class_id("wall")]

Points are in the room's map frame (REP-105: x forward, z up, metres), as the robot registered
them; scan["X_MS"] is the scanner's pose in that frame and scan["X_WM"] maps the frame into the
truth's world frame (ds.truth, the scene's scene.truth.json).
"""
import json
import os

import numpy as np

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}


def read_ply(path):
    """The vertex element of a binary little-endian PLY as {property name: numpy array}."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        count, fields, fmt = None, [], None
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: header without end_header")
            words = line.decode("ascii", "replace").split()
            if not words or words[0] in ("comment", "obj_info"):
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                if words[1] != "vertex" or count is not None:
                    raise ValueError(f"{path}: element {words[1]}: only one vertex element is read")
                count = int(words[2])
            elif words[0] == "property":
                if words[1] == "list" or words[1] not in _PLY_TYPES:
                    raise ValueError(f"{path}: property {' '.join(words[1:])} not supported")
                fields.append((words[2], _PLY_TYPES[words[1]]))
            elif words[0] == "end_header":
                break
        if fmt != "binary_little_endian":
            raise ValueError(f"{path}: format {fmt}: binary_little_endian expected")
        data = np.fromfile(f, dtype=np.dtype(fields), count=count)
    if data.shape[0] != count:
        raise ValueError(f"{path}: {data.shape[0]} of {count} vertices (truncated)")
    return {name: data[name] for name, _ in fields}


class Dataset:
    """One `mopad dataset` folder: `index` (dataset.json), `scans` (its "scans" entries),
    `classes` ({semantic id: name}), `instances` ({instance id: dict with element, class,
    semantic}), `truth` (the truth JSON, loaded on first use)."""

    def __init__(self, root):
        self.root = root
        path = os.path.join(root, "dataset.json")
        with open(path, encoding="utf-8") as f:
            self.index = json.load(f)
        if self.index.get("format") != "mopad-dataset" or self.index.get("version") != 1:
            raise ValueError(f"{path}: not a mopad-dataset version 1")
        self.scans = self.index["scans"]
        self.classes = {c["id"]: c["name"] for c in self.index["semantic_classes"]}
        self.instances = {i["id"]: i for i in self.index["instances"]}
        self._rooms = {r["room"]: r for r in self.index["rooms"]}
        self._truth = None

    def class_id(self, name):
        """The semantic id of a class name ("wall", "component:socket_x2")."""
        for i, n in self.classes.items():
            if n == name:
                return i
        raise KeyError(name)

    @property
    def truth(self):
        if self._truth is None:
            with open(os.path.join(self.root, self.index["truth"]), encoding="utf-8") as f:
                self._truth = json.load(f)
        return self._truth

    def read(self, ref):
        """Scan `ref` (an entry of `scans`, or its position in it) as a dict: xyz (N, 3) float32,
        rgb (N, 3) uint8, intensity (N,) float32, semantic (N,) uint8, instance (N,) int32 (-1:
        none), sm1_label (N,) uint8 (the robot's: 0 none, 1 inlier, 2 outlier, 3 clutter),
        X_MS and X_WM (4, 4) float64, room, index."""
        if isinstance(ref, int):
            ref = self.scans[ref]
        v = read_ply(os.path.join(self.root, ref["file"]))
        if v["x"].shape[0] != ref["points"]:
            raise ValueError(f"{ref['file']}: {v['x'].shape[0]} points, dataset.json says {ref['points']}")
        out = {
            "xyz": np.stack([v["x"], v["y"], v["z"]], axis=1),
            "intensity": v["intensity"],
            "semantic": v["semantic"],
            "instance": v["instance"],
            "sm1_label": v["sm1_label"],
            "X_MS": np.array(ref["X_MS"], dtype=np.float64),
            "X_WM": np.array(self._rooms[ref["room"]]["X_WM"], dtype=np.float64),
            "room": ref["room"],
            "index": ref["index"],
        }
        if "red" in v:
            out["rgb"] = np.stack([v["red"], v["green"], v["blue"]], axis=1)
        return out


def load(root):
    """The dataset in folder `root`."""
    return Dataset(root)
