#!/usr/bin/env python3
"""OpenMoPAD from Python, notebook-free (docs/python.md): a scene, one TLS scan with its truth, a
robot brain of a few lines driving the simulated robot from its own LRF, and the figures.

    PYTHONPATH=build/python python3 examples/python_drive.py [SCENE] [SECONDS]

SCENE: a spec .yaml or a scene folder (default: scenes/office_5rooms.yaml, generated to
/tmp/mopad_python_office).
"""
import os
import sys

import numpy as np

import mopad

here = os.path.dirname(os.path.abspath(__file__))
scene = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "office_5rooms.yaml")
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 20.0
if scene.endswith(".yaml"):
    out = "/tmp/mopad_python_office"
    mopad.generate_scene(scene, out)
    scene = out
world = mopad.World(scene)
print(f"scene {world.source}: rooms {', '.join(world.rooms)}")

robot = mopad.Robot(world, seed=1)
x, y, yaw = robot.true_pose()
s = mopad.scan(world, (x, y, 0.0, np.degrees(yaw)), step_deg=0.5)
labels, counts = np.unique(s["truth"]["label"], return_counts=True)
print(f"scan at the start: {s['xyz'].shape[0]} points; by scene class {dict(zip(labels.tolist(), counts.tolist()))}")

# The brain sees the robot's sensors only: forward until something is near ahead, then turn.
while robot.time() < seconds:
    sweep = robot.top_sweep()
    r = sweep["ranges"]
    a = sweep["angle_min"] + sweep["angle_increment"] * np.arange(r.shape[0])
    ahead = r[(np.abs(a) < 0.5) & (r > sweep["range_min"])]
    near = ahead.size > 0 and ahead.min() < 1.2
    robot.step(0.0 if near else 0.5, 0.6 if near else 0.0)
odo = robot.odometry()
tx, ty, tyaw = robot.true_pose()
print(f"after {robot.time():.1f} s: odometry ({odo['x']:.2f}, {odo['y']:.2f}) m in odom; "
      f"true ({tx:.2f}, {ty:.2f}) m in the world")
