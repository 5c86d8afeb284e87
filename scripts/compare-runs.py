#!/usr/bin/env python3
"""Compares a run folder with an uninterrupted run's folder of the same seed.

    compare-runs.py REF GOT   -> prints "FILES CMP TIMING DIFF MODELS MODELS_CMP", writes GOT.cmp

FILES: the files of REF, checkpoint/ aside (the checkpoint's own record: resumes counted).
CMP: byte-identical in GOT. TIMING: equal once the wall-clock timings are removed (keys
seconds, wall_time, wall_time_s, tls_wall_time_s, sm4_seconds, sm5_seconds of a JSON; the
"Timing" table of report.md and report.html). DIFF: missing, extra or different files, listed in
GOT.cmp. MODELS: the model files of REF (rooms/*/ sm1.ply, sm2-5.json, dsm3.ply, models.glb,
model.json; floor/; export/), MODELS_CMP: those byte-identical in GOT.
"""
import filecmp
import json
import os
import re
import sys

TIMING = {"seconds", "wall_time", "wall_time_s", "tls_wall_time_s", "sm4_seconds", "sm5_seconds"}
MODEL = re.compile(r"(^|/)(sm1\.ply|sm[2-5]\.json|dsm3\.ply|models\.glb|model\.json)$|^(floor|export)/")


def drop(j):
    if isinstance(j, dict):
        return {k: drop(v) for k, v in j.items() if k not in TIMING}
    if isinstance(j, list):
        return [drop(x) for x in j]
    return j


def files(d):
    out = set()
    for root, _, names in os.walk(d):
        for n in names:
            rel = os.path.relpath(os.path.join(root, n), d)
            if not rel.startswith("checkpoint" + os.sep):
                out.add(rel)
    return out


def report_md(text):
    return re.sub(r"\n#+ Timing\n.*?(?=\n#|\Z)", "\n", text, flags=re.S)


def report_html(text):
    return re.sub(r"<h2>Timing</h2>.*?</table>", "", text, flags=re.S)


def main(ref, got):
    a, b = files(ref), files(got)
    bad = sorted("missing " + f for f in a - b) + sorted("extra " + f for f in b - a)
    same_bytes = loosened = models = models_cmp = 0
    for f in sorted(a):
        is_model = bool(MODEL.search(f))
        models += is_model
        if f not in b:
            continue
        pa, pb = os.path.join(ref, f), os.path.join(got, f)
        if filecmp.cmp(pa, pb, shallow=False):
            same_bytes += 1
            models_cmp += is_model
            continue
        ok = False
        if f.endswith(".json"):
            ok = drop(json.load(open(pa))) == drop(json.load(open(pb)))
        elif f == "report.md":
            ok = report_md(open(pa).read()) == report_md(open(pb).read())
        elif f == "report.html":
            ok = report_html(open(pa).read()) == report_html(open(pb).read())
        if ok:
            loosened += 1
        else:
            bad.append("differs " + f)
    print(f"{len(a)} {same_bytes} {loosened} {len(bad)} {models} {models_cmp}")
    with open(got.rstrip("/") + ".cmp", "w") as fh:
        fh.write("\n".join(bad) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
