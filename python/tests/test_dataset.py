"""The Python loader against the run it came from (run by tests/tools/dataset_test.cpp with
MOPAD_RUN_DIR and MOPAD_DATASET_DIR set): every room's points, the robot's SM1 labels and the
truth labels read back equal the run's files and dataset.json's figures."""
import collections
import os

import numpy as np
import pytest

import mopad.dataset

RUN = os.environ.get("MOPAD_RUN_DIR")
DS = os.environ.get("MOPAD_DATASET_DIR")
pytestmark = pytest.mark.skipif(not RUN or not DS, reason="MOPAD_RUN_DIR, MOPAD_DATASET_DIR unset")


def test_points_and_sm1_labels_equal_the_runs_sm1_clouds():
    ds = mopad.dataset.load(DS)
    by_room = collections.defaultdict(list)
    for i, ref in enumerate(ds.scans):
        by_room[ref["room"]].append(ds.read(i))
    assert sorted(by_room) == sorted(r["room"] for r in ds.index["rooms"])
    for room, scans in by_room.items():
        sm1 = mopad.dataset.read_ply(os.path.join(RUN, "rooms", room, "sm1.ply"))
        n = sum(s["xyz"].shape[0] for s in scans)
        assert n == sm1["x"].shape[0]
        got = np.concatenate([s["sm1_label"] for s in scans])
        assert np.array_equal(np.bincount(got, minlength=4), np.bincount(sm1["scalar_label"], minlength=4))
        # Scan by scan, the points are the SM1 points of that scan, in order.
        for s in scans:
            mask = sm1["scalar_scan"] == s["index"]
            xyz = np.stack([sm1["x"][mask], sm1["y"][mask], sm1["z"][mask]], axis=1)
            assert np.array_equal(s["xyz"], xyz)


def test_truth_labels_agree_with_the_index_and_the_instance_table():
    ds = mopad.dataset.load(DS)
    total = collections.Counter()
    for i, ref in enumerate(ds.scans):
        s = ds.read(i)
        hist = collections.Counter({int(k): v for k, v in ref["semantic_histogram"].items()})
        got = collections.Counter(dict(zip(*np.unique(s["semantic"], return_counts=True))))
        assert {int(k): int(v) for k, v in got.items()} == dict(hist)
        total.update(hist)
        labelled = s["instance"] >= 0
        assert np.all((s["semantic"] == 0) == ~labelled)
        table = np.array([ds.instances[k]["semantic"] for k in sorted(ds.instances)])
        assert np.array_equal(s["semantic"][labelled], table[s["instance"][labelled]])
        assert s["X_MS"].shape == (4, 4) and np.allclose(s["X_MS"][3], [0, 0, 0, 1])
    # A room scan is mostly structure, and nearly every point meets a truth surface.
    n = sum(total.values())
    structure = sum(total[ds.class_id(c)] for c in ("wall", "floor", "ceiling"))
    assert structure > 0.5 * n
    assert total[0] < 0.01 * n
    assert ds.truth["rooms"]
