"""The compiled module against the CLI (run by tests/tools/python_test.cpp with MOPAD_BINARY,
MOPAD_SOURCE_DIR and MOPAD_WORK set):
- a TLS scan of office_5rooms as arrays equals `mopad scan`'s PLY and truth PLY;
- a 60 s closed-loop drive decided in Python from the robot's own LRF writes its commands and
  the true trajectory (the C++ test replays the commands and compares the bytes);
- the main job run from Python writes the run folder `mopad run` writes (the C++ test compares
  the files);
- the evaluator's summary on a run folder equals `mopad eval`'s."""
import json
import os
import subprocess

import numpy as np
import pytest

import mopad
import mopad.dataset

BIN = os.environ.get("MOPAD_BINARY")
SRC = os.environ.get("MOPAD_SOURCE_DIR")
WORK = os.environ.get("MOPAD_WORK")
pytestmark = pytest.mark.skipif(not (BIN and SRC and WORK), reason="run by tests/tools/python_test.cpp")

START = (12.275, 5.325, 0.0, 0.0)  # office_5rooms: the main job's start spot


@pytest.fixture(scope="module")
def office():
    d = os.path.join(WORK, "office")
    if not os.path.exists(os.path.join(d, "scene.truth.json")):
        mopad.generate_scene(os.path.join(SRC, "scenes", "office_5rooms.yaml"), d)
    return d


def test_a_scan_as_arrays_equals_mopad_scans_ply(office):
    world = mopad.World(office)
    s = mopad.scan(world, START, step_deg=0.5, seed=3, scan_id=2)
    ply = os.path.join(WORK, "scan.ply")
    truth = os.path.join(WORK, "scan.truth.ply")
    subprocess.run([BIN, "scan", office, "--pose", ",".join(map(str, START)), "--step-deg", "0.5",
                    "--seed", "3", "--scan-id", "2", "-o", ply, "--truth", truth],
                   check=True, capture_output=True)
    p = mopad.dataset.read_ply(ply)
    t = mopad.dataset.read_ply(truth)
    n = s["xyz"].shape[0]
    assert n == p["x"].shape[0] == t["x"].shape[0] > 10000
    assert np.array_equal(s["xyz"], np.stack([p["x"], p["y"], p["z"]], axis=1))
    assert np.array_equal(np.bincount(s["truth"]["label"], minlength=32),
                          np.bincount(t["scalar_label"], minlength=32))
    assert np.array_equal(s["truth"]["element"], t["scalar_element"])
    assert "truth" not in mopad.Robot(world, seed=1).scan(2.0)  # the robot side gets no truth


def test_a_closed_loop_drive_in_python_records_its_commands_and_trajectory(office):
    robot = mopad.Robot(mopad.World(office), seed=1)
    commands = []
    while robot.time() < 60.0:
        sweep = robot.top_sweep()
        ranges = sweep["ranges"]
        angles = sweep["angle_min"] + sweep["angle_increment"] * np.arange(ranges.shape[0])
        front = ranges[np.abs(angles) < 0.5]
        front = front[front > sweep["range_min"]]
        near = front.size > 0 and float(front.min()) < 1.2
        v, w = (0.0, 0.6) if near else (0.5, 0.0)
        commands.append((v, w))
        robot.step(v, w)
    with open(os.path.join(WORK, "commands.txt"), "w") as f:
        f.writelines(f"{v!r} {w!r}\n" for v, w in commands)
    with open(os.path.join(WORK, "python_trajectory.tum"), "w") as f:
        f.write(robot.true_trajectory_tum())
    odo = robot.odometry()
    assert len(commands) >= 2900
    assert abs(odo["x"]) + abs(odo["y"]) > 1.0  # it went somewhere


def test_the_main_job_in_python_writes_the_run_folder_of_mopad_run():
    spec = os.path.join(SRC, "scenes", "one_room.yaml")
    run = os.path.join(WORK, "run")  # eval/ names its run folder: both runs write here
    subprocess.run([BIN, "run", "-q", "--spec", spec, "--step-deg", "0.5", "-o", run],
                   check=True, capture_output=True)
    os.rename(run, os.path.join(WORK, "run_cli"))  # the C++ test compares the two folders
    lines = []
    summary = mopad.run(out=run, spec=spec, step_deg=0.5, log=lines.append)
    with open(os.path.join(run, "summary.json")) as f:
        assert summary == json.load(f)
    assert lines[0].startswith("scene: one_room, 1 rooms")
    assert summary["rooms"][0]["status"] == "scanned"
    assert mopad.run(resume=run) == summary  # a complete run: nothing to do
    with pytest.raises(mopad.InputError):
        mopad.run(out=os.path.join(WORK, "bad"), spec=spec, step_deg=50.0)


def test_an_exception_in_log_stops_the_run_in_order_and_resume_finishes_it():
    run = os.path.join(WORK, "stopped")
    spec = os.path.join(SRC, "scenes", "two_rooms_door.yaml")

    def interrupt(line):
        if line.startswith("room_1: scan 1,"):
            raise KeyboardInterrupt  # as Ctrl-C would: the run stops before its next room

    with pytest.raises(KeyboardInterrupt):
        mopad.run(out=run, spec=spec, step_deg=0.5, log=interrupt)
    with open(os.path.join(run, "checkpoint", "manifest.json")) as f:
        assert json.load(f)["state"] == "stopped"
    with open(os.path.join(run, "summary.json")) as f:
        assert len(json.load(f)["rooms"]) == 1
    summary = mopad.run(resume=run)  # replays room 1 (checked against its fingerprint), then 2
    assert len(summary["rooms"]) == 2
    with open(os.path.join(run, "checkpoint", "manifest.json")) as f:
        assert json.load(f)["state"] == "complete"


def test_the_evaluator_gives_mopad_evals_summary():
    run = os.path.join(WORK, "run")
    subprocess.run([BIN, "eval", run, "-o", os.path.join(WORK, "eval_cli")], check=True,
                   capture_output=True)
    summary = mopad.evaluate(run, out=os.path.join(WORK, "eval_py"))
    with open(os.path.join(WORK, "eval_cli", "evaluation.json")) as f:
        cli = json.load(f)
    assert summary == cli["summary"]
    assert summary["detection"]["wall"]["tp"] >= 4
